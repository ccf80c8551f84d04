//! The quality knobs `pelt sweep` turns, one entry each in [`KNOBS`](super::table::KNOBS):
//! its spec (`pelt_scene::knobs::spec`: its name, the flag of `pelt render` or `pelt bake`,
//! its range, how a value parses, its default, its reference, whether it re-bakes, the
//! scene's own value and how a value applies to the scene's overrides), what the scene must
//! hold for it to change anything, and the sweep's own part: the values swept when none are
//! given, a narrower range where the sweep's references stop, and how a value that is no
//! scene override applies (the mode, a re-bake). The renderer feature that reads the knob
//! names the same spec (`pelt_preview::feature::KnobDesc`); a test checks the two tables name
//! the same knobs.

use pelt_bake::options::Quantize;
use pelt_fur::HeightBits;
use pelt_scene::Mode;
use pelt_scene::knobs::Knobs;
use pelt_scene::knobs::spec::{KnobSpec, Range};

/// What the scene itself sets, for telling which swept value is its own.
pub use pelt_scene::knobs::spec::Own;
/// What a knob is measured against (declared with the knob's spec).
pub use pelt_scene::knobs::spec::Reference as Truth;
/// One value of a knob.
pub use pelt_scene::knobs::spec::Value;

/// What a scene must hold for a knob to change anything.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Need {
    /// A fur object with a baked comb.
    Fur,
    /// A mirror or glass object.
    Optics,
    /// A light that casts shadows.
    CastingLight,
}

impl Need {
    /// Why a scene without it has nothing for the knob to change.
    pub fn missing(self) -> &'static str {
        match self {
            Need::Fur => "the scene has no fur object with a baked comb",
            Need::Optics => "the scene has no mirror or glass object",
            Need::CastingLight => "the scene has no light that casts shadows",
        }
    }
}

/// The values a knob sweeps for a scene drawn at (width, height).
pub type Sweep = fn((u32, u32)) -> Vec<Value>;

/// A knob: one entry of [`KNOBS`](super::table::KNOBS).
#[derive(Debug, Clone, Copy)]
pub struct Knob {
    /// What it is: name, range, parse, default, reference, own value, setter.
    pub spec: &'static KnobSpec,
    /// What the scene must hold (all of it) for the knob to change anything.
    pub needs: &'static [Need],
    /// The values the sweep takes where fewer than the spec's (None: the spec's).
    pub(super) within: Option<&'static Range>,
    /// The values swept when none are given, around the defaults, for a scene drawn at
    /// (width, height) (None: every value of a switch or a list of words).
    pub(super) sweep: Option<Sweep>,
    /// Applies a value that is no scene override (the mode, a re-bake; None: the spec's
    /// setter).
    pub(super) set: Option<fn(&mut Setting, Value)>,
}

impl Knob {
    /// A knob the sweep turns through its spec alone, sweeping `sweep`.
    pub(super) const fn of(
        spec: &'static KnobSpec,
        needs: &'static [Need],
        sweep: Option<Sweep>,
    ) -> Knob {
        Knob {
            spec,
            needs,
            within: None,
            sweep,
            set: None,
        }
    }
}

impl PartialEq for Knob {
    fn eq(&self, other: &Knob) -> bool {
        self.spec == other.spec
    }
}

impl Eq for Knob {}

/// A knob name or value that is not allowed (a usage error).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KnobError {
    /// No such knob.
    #[error("unknown knob {name:?} (knobs: {known})")]
    Unknown {
        /// What was given.
        name: String,
        /// Every knob's name, comma separated.
        known: String,
    },
    /// Not `NAME=V1,V2,...`.
    #[error("--knob {given:?}: expected NAME=V1,V2,... (for example shells=4,16,64)")]
    Syntax {
        /// What was given.
        given: String,
    },
    /// A value out of range.
    #[error("knob {knob}: {value:?} is not allowed ({allowed})")]
    Value {
        /// The knob.
        knob: &'static str,
        /// The value.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    /// The knob has nothing to change in this scene.
    #[error("knob {knob}: {why}")]
    NotApplicable {
        /// The knob.
        knob: &'static str,
        /// Why.
        why: &'static str,
    },
}

impl Knob {
    /// Its name (the flag without dashes).
    pub fn name(&self) -> &'static str {
        self.spec.name
    }

    /// The values it takes in a sweep.
    fn range(&self) -> &'static Range {
        self.within.unwrap_or(&self.spec.range)
    }

    /// What values it allows, in words.
    pub fn allowed(&self) -> String {
        self.range().words()
    }

    /// Parses one value.
    pub fn value(&self, s: &str) -> Result<Value, KnobError> {
        self.range().parse(s).map_err(|_| KnobError::Value {
            knob: self.name(),
            value: s.into(),
            allowed: self.allowed(),
        })
    }

    /// The reference the knob is measured against.
    pub fn truth(&self) -> Truth {
        self.spec.reference
    }

    /// Whether a value is applied by baking the asset again.
    pub fn rebakes(&self) -> bool {
        self.spec.rebakes
    }

    /// The values swept when none are given, around the defaults (`size` is the scene's
    /// output size; sizes are derived from it).
    pub fn defaults(&self, size: (u32, u32)) -> Vec<Value> {
        match self.sweep {
            Some(sweep) => sweep(size),
            None => self.range().every().unwrap_or_default(),
        }
    }

    /// The scene's own value of the knob (None where it cannot be told).
    pub fn own(&self, scene: &Own<'_>) -> Option<Value> {
        (self.spec.own)(scene)
    }

    /// Applies one of its values to `s`.
    fn apply(&self, s: &mut Setting, v: Value) {
        match (self.set, self.spec.set) {
            (Some(set), _) => set(s, v),
            (None, Some(set)) => set(&mut s.knobs, v),
            (None, None) => {}
        }
    }
}

/// What a setting changes: the renderer's knobs, the mode, and how the fur assets are baked.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Setting {
    /// Scene overrides.
    pub knobs: Knobs,
    /// The mode (None: inferred, the renderer's default).
    pub mode: Option<Mode>,
    /// Re-bake: fur texture size.
    pub texture_size: Option<u32>,
    /// Re-bake: heightfield bits.
    pub height_bits: Option<HeightBits>,
    /// Re-bake: comb quantization.
    pub quantize: Option<Quantize>,
}

impl Setting {
    /// Whether the fur assets must be baked again.
    pub fn rebakes(&self) -> bool {
        self.texture_size.is_some() || self.height_bits.is_some() || self.quantize.is_some()
    }

    /// `self` with `knob` at `value` (a value of that knob, as [`Knob::value`] makes).
    pub fn with(mut self, knob: &Knob, value: Value) -> Setting {
        knob.apply(&mut self, value);
        self
    }
}

#[cfg(test)]
mod tests {
    use super::super::table::KNOBS;
    use super::*;
    use pelt_preview::features::registry;
    use pelt_scene::knobs::spec;
    use pelt_scene::scene::{ShadowMaps, reflection_limits as limits};

    fn knob(name: &str) -> &'static Knob {
        Knob::named(name).expect("a knob")
    }

    #[test]
    fn every_knob_is_declared_by_the_feature_that_reads_it() {
        for k in KNOBS {
            assert!(
                registry::knob(k.name()).is_some_and(|d| d.spec == k.spec),
                "{} has no descriptor",
                k.name()
            );
            let n = KNOBS.iter().filter(|x| x.name() == k.name()).count();
            assert_eq!(n, 1, "{} is in the table {n} times", k.name());
            let setters = usize::from(k.set.is_some()) + usize::from(k.spec.set.is_some());
            assert_eq!(setters, 1, "{} is set {setters} ways", k.name());
        }
        for (f, d) in registry::knobs() {
            assert!(
                Knob::named(d.name()).is_ok(),
                "{f} declares {}, which the sweep cannot turn",
                d.name()
            );
        }
        for s in spec::ALL {
            assert!(
                Knob::named(s.name).is_ok(),
                "the sweep cannot turn {}",
                s.name
            );
        }
        let truths = [
            ("shells", Truth::Strands),
            ("quantize", Truth::Strands),
            ("dsf", Truth::Deferred),
            ("size", Truth::Deferred),
            ("min-max", Truth::RayTracer),
            ("pcf", Truth::RayTracer),
            ("shadow-size", Truth::RayTracer),
            ("opacity-layers", Truth::Strands),
        ];
        for (k, t) in truths {
            assert_eq!(knob(k).truth(), t, "{k}");
        }
        assert!(knob("height-bits").rebakes() && !knob("fins").rebakes());
    }

    #[test]
    fn a_knob_needs_what_its_reference_draws() {
        for k in KNOBS {
            let needs = |n: Need| k.needs.contains(&n);
            match k.truth() {
                Truth::Strands => assert!(needs(Need::Fur), "{}", k.name()),
                Truth::RayTracer => assert!(
                    needs(Need::Optics) || needs(Need::CastingLight),
                    "{}",
                    k.name()
                ),
                Truth::Deferred => assert!(k.needs.is_empty(), "{}", k.name()),
            }
        }
    }

    #[test]
    fn the_ranges_in_words_are_the_scene_files_ranges() {
        let shells = knob("shells");
        let r = pelt_fur::manifest::SHELLS;
        assert_eq!(
            shells.allowed(),
            format!("auto (by screen size) or {} to {}", r.start(), r.end())
        );
        assert!(shells.value("auto").is_ok() && shells.value(&r.end().to_string()).is_ok());
        assert!(shells.value(&(r.end() + 1).to_string()).is_err());
        for (k, r) in [
            ("linear-steps", limits::LINEAR_STEPS),
            ("secant-steps", limits::SECANT_STEPS),
            ("layers", limits::LAYERS),
            ("max-depth", limits::MAX_DEPTH),
            ("pcf", ShadowMaps::PCF),
            ("opacity-layers", ShadowMaps::OPACITY_LAYERS),
        ] {
            let k = knob(k);
            assert_eq!(
                k.allowed(),
                format!("{} to {}", r.start(), r.end()),
                "{}",
                k.name()
            );
            assert!(k.value(&r.end().to_string()).is_ok(), "{}", k.name());
            assert!(k.value(&(r.end() + 1).to_string()).is_err(), "{}", k.name());
        }
        let l = pelt_scene::scene::LBUFFER_SCALE;
        assert_eq!(
            knob("lbuffer-scale").allowed(),
            format!("{} to {}", l.start(), l.end())
        );
    }

    #[test]
    fn names_round_trip_and_bad_ones_name_the_range() {
        for k in KNOBS {
            assert_eq!(Knob::named(k.name()), Ok(k));
            for v in k.defaults((640, 360)) {
                assert_eq!(k.value(&v.to_string()), Ok(v), "{}={v}", k.name());
            }
        }
        let e = Knob::parse_list("shells=4,300").expect_err("300 shells");
        assert_eq!(
            e.to_string(),
            "knob shells: \"300\" is not allowed (auto (by screen size) or 1 to 256)"
        );
        let e = Knob::parse_list("shell=4").expect_err("unknown");
        assert!(e.to_string().contains("unknown knob \"shell\""), "{e}");
        assert!(e.to_string().contains("opacity-layers"), "{e}");
        assert!(Knob::parse_list("shells").is_err());
        assert!(Knob::parse_list("texture-size=100").is_err());
        assert!(Knob::parse_list("mode=strands").is_err());
    }

    #[test]
    fn every_swept_value_changes_the_setting_and_distinct_values_differ() {
        for k in KNOBS {
            let settings: Vec<Setting> = k
                .defaults((640, 360))
                .into_iter()
                .map(|v| Setting::default().with(k, v))
                .collect();
            assert!(
                settings.len() >= 2,
                "{} sweeps {}",
                k.name(),
                settings.len()
            );
            for (i, s) in settings.iter().enumerate() {
                assert_ne!(
                    *s,
                    Setting::default(),
                    "{} value {i} sets nothing",
                    k.name()
                );
                assert!(!settings[..i].contains(s), "{} value {i} repeats", k.name());
                assert_eq!(s.rebakes(), k.rebakes(), "{}", k.name());
            }
        }
    }

    #[test]
    fn a_setting_sets_what_its_knob_names() {
        let s = Setting::default()
            .with(knob("shells"), Value::Count(8))
            .with(knob("quantize"), Value::Word("u8"))
            .with(knob("linear-steps"), Value::Count(7));
        assert_eq!(
            s.knobs.shells,
            Some(pelt_scene::knobs::ShellCount::Fixed(8))
        );
        assert_eq!(s.quantize, Some(Quantize::U8));
        assert_eq!(s.knobs.reflections.linear_steps, Some(7));
        assert!(s.rebakes());
        assert!(
            !Setting::default()
                .with(knob("fins"), Value::Switch(false))
                .rebakes()
        );
    }
}
