//! What the keys and the mouse of `pelt view` do, apart from the window: a key names an
//! [`Action`], applying an action changes the [`Settings`] (mode and knobs), and mouse motion
//! turns into orbit, pan and zoom amounts.

use pelt_preview::Mode;
use pelt_preview::knobs::spec::{self, KnobSpec};
use pelt_preview::knobs::{Knobs, ShellCount};
use pelt_preview::plan::DebugView;
use pelt_preview::scene::FurBlend;

/// Radians of orbit per pixel dragged.
pub const ORBIT_PER_PIXEL: f32 = 0.008;
/// Wheel steps per pixel of a touchpad's pixel delta.
pub const ZOOM_PER_PIXEL: f32 = 1.0 / 40.0;

/// What a key does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Next mode: inferred, deferred, forward.
    CycleMode,
    /// Next debug view: normal groups, the decoded comb, then back to inferred lighting.
    CycleDebug,
    /// L-buffer scale down (`[`) or up (`]`) by 0.125.
    LbufferScale(i8),
    /// DSF on/off.
    ToggleDsf,
    /// Shells halved (`-`) or doubled (`=`).
    Shells(i8),
    /// Fins on/off.
    ToggleFins,
    /// Stipple ⇄ WBOIT.
    ToggleBlend,
    /// Frame the asset.
    Frame,
    /// Write a screenshot.
    Screenshot,
    /// Reload the input (and the shaders).
    Reload,
    /// Re-measure the pass costs.
    Measure,
    /// Show or hide the text overlay.
    ToggleOverlay,
    /// Print the controls.
    Help,
    /// Close the window.
    Quit,
    /// Play or pause the animation.
    PlayPause,
    /// Step the animation a frame back (`,`) or forward (`.`).
    Step(i8),
    /// The next animation clip.
    NextClip,
}

impl Action {
    /// The knob the action turns (its spec: name, range, the scene's own value), if any.
    pub fn knob(self) -> Option<&'static KnobSpec> {
        Some(match self {
            Action::CycleMode => &spec::MODE,
            Action::LbufferScale(_) => &spec::LBUFFER_SCALE,
            Action::ToggleDsf => &spec::DSF,
            Action::Shells(_) => &spec::SHELLS,
            Action::ToggleFins => &spec::FINS,
            Action::ToggleBlend => &spec::FUR_BLEND,
            _ => return None,
        })
    }
}

/// The action of a key, by its character (lower case) or name.
pub fn action(key: &str) -> Option<Action> {
    Some(match key {
        "m" => Action::CycleMode,
        "g" => Action::CycleDebug,
        "[" => Action::LbufferScale(-1),
        "]" => Action::LbufferScale(1),
        "d" => Action::ToggleDsf,
        "-" => Action::Shells(-1),
        "=" | "+" => Action::Shells(1),
        "i" => Action::ToggleFins,
        "b" => Action::ToggleBlend,
        "f" => Action::Frame,
        "p" => Action::Screenshot,
        "r" => Action::Reload,
        "t" => Action::Measure,
        "o" => Action::ToggleOverlay,
        "h" | "?" => Action::Help,
        "q" | "Escape" => Action::Quit,
        "Space" => Action::PlayPause,
        "," => Action::Step(-1),
        "." => Action::Step(1),
        "c" => Action::NextClip,
        _ => return None,
    })
}

/// The controls, for `H` and `--help`.
pub const HELP: &str = "\
pelt view controls:
  left drag        orbit            right drag / shift+left drag   pan
  wheel            zoom             F   frame the asset
  M  mode (inferred, deferred, forward)      [ ]  L-buffer scale -/+ 0.125
  G  debug view (normal groups, comb, off)
  D  DSF on/off    - =  shells halve/double  I  fins on/off   B  stipple/WBOIT
  P  screenshot    R  reload input and shaders   T  measure pass costs   O  overlay on/off
  Space  play/pause animation or wind   , .  step a frame back/forward   C  next clip
  H  this help     Q / Esc  quit
Drop a .glb, .gltf, .obj or .json on the window to open it; the open file reloads when it
changes on disk.";

/// The mode and the knobs the keys turn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Lighting mode.
    pub mode: Mode,
    /// Overrides of the scene.
    pub knobs: Knobs,
}

impl Settings {
    /// Applies a knob action; `base` holds the scene's own values for the knobs not
    /// overridden yet (L-buffer scale, DSF, shells, fins, blend). Returns whether anything
    /// changed.
    pub fn apply(&mut self, a: Action, base: &Knobs) -> bool {
        let before = *self;
        let k = &mut self.knobs;
        match a {
            Action::CycleMode => {
                self.mode = match self.mode {
                    Mode::Inferred => Mode::Deferred,
                    Mode::Deferred => Mode::Forward,
                    Mode::Forward | Mode::Strands | Mode::Debug(_) => Mode::Inferred,
                };
            }
            Action::CycleDebug => {
                self.mode = match self.mode {
                    Mode::Debug(DebugView::Groups) => Mode::Debug(DebugView::Comb),
                    Mode::Debug(DebugView::Comb) => Mode::Inferred,
                    _ => Mode::Debug(DebugView::Groups),
                };
            }
            Action::LbufferScale(d) => {
                let s = k.lbuffer_scale.or(base.lbuffer_scale).unwrap_or(0.625);
                k.lbuffer_scale = Some((s + 0.125 * f32::from(d)).clamp(0.125, 1.0));
            }
            Action::ToggleDsf => k.dsf = Some(!k.dsf.or(base.dsf).unwrap_or(true)),
            Action::Shells(d) => {
                let s = match k.shells.or(base.shells) {
                    Some(ShellCount::Fixed(n)) => n,
                    _ => 16,
                };
                k.shells = Some(ShellCount::Fixed(
                    if d > 0 { s * 2 } else { s / 2 }.clamp(1, 256),
                ));
            }
            Action::ToggleFins => k.fins = Some(!k.fins.or(base.fins).unwrap_or(true)),
            Action::ToggleBlend => {
                k.fur_blend = Some(match k.fur_blend.or(base.fur_blend) {
                    Some(FurBlend::Wboit) => FurBlend::Stipple,
                    _ => FurBlend::Wboit,
                });
            }
            _ => return false,
        }
        *self != before
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_map_to_actions_and_unknown_keys_to_none() {
        assert_eq!(action("m"), Some(Action::CycleMode));
        assert_eq!(action("["), Some(Action::LbufferScale(-1)));
        assert_eq!(action("Escape"), Some(Action::Quit));
        assert_eq!(action("z"), None);
        assert_eq!(action("Space"), Some(Action::PlayPause));
        assert_eq!(action(","), Some(Action::Step(-1)));
        assert_eq!(action("c"), Some(Action::NextClip));
        assert_eq!(action("g"), Some(Action::CycleDebug));
    }

    #[test]
    fn knob_actions_change_the_settings_within_range() {
        let base = Knobs {
            lbuffer_scale: Some(0.625),
            dsf: Some(true),
            shells: Some(ShellCount::Fixed(16)),
            fins: Some(true),
            fur_blend: Some(FurBlend::Stipple),
            size: None,
            reflections: Default::default(),
            ..Knobs::default()
        };
        let mut s = Settings {
            mode: Mode::Inferred,
            knobs: Knobs::default(),
        };
        assert!(s.apply(Action::CycleMode, &base));
        assert_eq!(s.mode, Mode::Deferred);
        s.apply(Action::CycleMode, &base);
        s.apply(Action::CycleMode, &base);
        assert_eq!(s.mode, Mode::Inferred);
        s.apply(Action::CycleDebug, &base);
        assert_eq!(s.mode, Mode::Debug(DebugView::Groups));
        s.apply(Action::CycleDebug, &base);
        assert_eq!(s.mode, Mode::Debug(DebugView::Comb));
        s.apply(Action::CycleDebug, &base);
        assert_eq!(s.mode, Mode::Inferred);
        s.apply(Action::LbufferScale(1), &base);
        assert_eq!(s.knobs.lbuffer_scale, Some(0.75));
        for _ in 0..20 {
            s.apply(Action::LbufferScale(-1), &base);
        }
        assert_eq!(s.knobs.lbuffer_scale, Some(0.125));
        s.apply(Action::Shells(1), &base);
        assert_eq!(s.knobs.shells, Some(ShellCount::Fixed(32)));
        for _ in 0..10 {
            s.apply(Action::Shells(1), &base);
        }
        assert_eq!(s.knobs.shells, Some(ShellCount::Fixed(256)));
        s.apply(Action::ToggleDsf, &base);
        s.apply(Action::ToggleFins, &base);
        s.apply(Action::ToggleBlend, &base);
        assert_eq!(
            (s.knobs.dsf, s.knobs.fins, s.knobs.fur_blend),
            (Some(false), Some(false), Some(FurBlend::Wboit))
        );
        assert!(!s.apply(Action::Screenshot, &base), "not a knob");
    }

    /// Whether `a`, applied to no overrides, changes just the override `knob` sets: setting
    /// the knob over the action's result leaves what setting it alone does.
    fn turns(a: Action, knob: &KnobSpec) -> bool {
        let Some(set) = knob.set else { return false };
        let v = knob
            .range
            .every()
            .and_then(|v| v.first().copied())
            .unwrap_or_else(|| knob.parse("1").expect("1 is a scale and a count"));
        let mut s = Settings {
            mode: Mode::Inferred,
            knobs: Knobs::default(),
        };
        s.apply(a, &Knobs::default());
        let mut alone = Knobs::default();
        set(&mut s.knobs, v);
        set(&mut alone, v);
        s.knobs == alone
    }

    #[test]
    fn every_knob_key_turns_the_knob_its_spec_names() {
        let keys = "m[]d-=ib";
        let knobs: Vec<&KnobSpec> = keys
            .chars()
            .filter_map(|c| action(&c.to_string()).and_then(Action::knob))
            .collect();
        assert_eq!(knobs.len(), keys.len(), "a knob key without a knob");
        for c in keys.chars() {
            let a = action(&c.to_string()).expect("a key");
            let k = a.knob().expect("a knob");
            assert!(spec::ALL.contains(&k), "{} is not a knob spec", k.name);
            if a != Action::CycleMode {
                assert!(turns(a, k), "{c} does not turn {}", k.name);
            }
        }
        // Negative control: a key does not turn another knob.
        assert!(!turns(Action::ToggleDsf, &spec::FINS));
        assert!(!turns(Action::Shells(1), &spec::LBUFFER_SCALE));
    }
}
