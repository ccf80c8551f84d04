//! The quality knobs `pelt sweep` turns, one entry each in [`KNOBS`](super::table::KNOBS): its name (the flag of
//! `pelt render` or `pelt bake`), what the scene must hold for it to change anything, how a
//! value is parsed, the values swept when none are given, how a value is applied to a
//! setting (the scene's overrides, the mode or a re-bake) and the scene's own value. The
//! range in words, the default, the reference each is measured against and whether it
//! re-bakes are declared by the renderer feature that reads the knob
//! (`pelt_preview::feature::KnobDesc`) and read here; a test checks the two tables name the
//! same knobs.

use std::fmt;

use pelt_bake::options::Quantize;
use pelt_fur::HeightBits;
use pelt_preview::feature::KnobDesc;
use pelt_preview::features::registry;
use pelt_scene::Mode;
use pelt_scene::fur::FurData;
use pelt_scene::knobs::Knobs;
use pelt_scene::scene::{FurBlend, FurCoverage, FurLighting, FurSettings, Scene, Technique};

/// What a knob is measured against (declared with the knob by the feature that reads it).
pub use pelt_preview::feature::Reference as Truth;

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

/// What the scene itself sets, for telling which swept value is its own.
#[derive(Debug, Clone, Copy)]
pub struct Own<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The first fur asset's baked data.
    pub fur: Option<&'a FurData>,
    /// The first fur material's settings.
    pub settings: Option<FurSettings>,
}

/// A knob: one entry of [`KNOBS`](super::table::KNOBS).
#[derive(Debug, Clone, Copy)]
pub struct Knob {
    /// Its name (the `pelt render` or `pelt bake` flag without dashes).
    pub name: &'static str,
    /// What the scene must hold (all of it) for the knob to change anything.
    pub needs: &'static [Need],
    /// One value from its text (None: not allowed).
    pub(super) parse: fn(&str) -> Option<Value>,
    /// The values swept when none are given, around the defaults, for a scene drawn at
    /// (width, height).
    pub(super) sweep: fn((u32, u32)) -> Vec<Value>,
    /// Applies one of its own values.
    pub(super) set: fn(&mut Setting, Value),
    /// The scene's own value (None where it cannot be told).
    pub(super) own: fn(&Own<'_>) -> Option<Value>,
}

impl PartialEq for Knob {
    fn eq(&self, other: &Knob) -> bool {
        self.name == other.name
    }
}

impl Eq for Knob {}
/// One value of a knob.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A count or size.
    Count(u32),
    /// A scale.
    Scale(f32),
    /// On or off.
    Switch(bool),
    /// A mode.
    Mode(Mode),
    /// A fur blend.
    Blend(FurBlend),
    /// A fur coverage model.
    Coverage(FurCoverage),
    /// A fur lighting model.
    Lighting(FurLighting),
    /// Heightfield bits.
    Bits(HeightBits),
    /// Comb quantization.
    Quantize(Quantize),
    /// Output width and height.
    Size(u32, u32),
    /// Reflection technique.
    Technique(Technique),
    /// The shells-by-screen-size rule of the fur's manifest (`pelt_fur::shells`).
    Auto,
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Count(n) => write!(f, "{n}"),
            Value::Scale(s) => write!(f, "{s}"),
            Value::Switch(b) => f.write_str(if *b { "on" } else { "off" }),
            Value::Mode(m) => write!(f, "{m}"),
            Value::Blend(FurBlend::Stipple) => f.write_str("stipple"),
            Value::Blend(FurBlend::Wboit) => f.write_str("wboit"),
            Value::Coverage(FurCoverage::Analytic) => f.write_str("analytic"),
            Value::Coverage(FurCoverage::Binary) => f.write_str("binary"),
            Value::Lighting(FurLighting::KajiyaKay) => f.write_str("kajiya-kay"),
            Value::Lighting(FurLighting::Revie) => f.write_str("revie"),
            Value::Bits(HeightBits::Eight) => f.write_str("8"),
            Value::Bits(HeightBits::Sixteen) => f.write_str("16"),
            Value::Quantize(Quantize::U8) => f.write_str("u8"),
            Value::Quantize(Quantize::U16) => f.write_str("u16"),
            Value::Quantize(Quantize::Float) => f.write_str("float"),
            Value::Size(w, h) => write!(f, "{w}x{h}"),
            Value::Technique(t) => write!(f, "{t}"),
            Value::Auto => f.write_str("auto"),
        }
    }
}

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
        allowed: &'static str,
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

/// A knob without a registered descriptor (the registry test rules it out).
const UNREGISTERED: KnobDesc = KnobDesc::new("?", "?", "?", Truth::Strands);

impl Knob {
    /// Its descriptor, as the feature that reads it registered it
    /// (`pelt_preview::features::registry`): range, default, reference.
    pub fn desc(&self) -> &'static KnobDesc {
        registry::knob(self.name).unwrap_or(&UNREGISTERED)
    }

    /// What values it allows, in words.
    pub fn allowed(&self) -> &'static str {
        self.desc().range
    }

    /// Parses one value.
    pub fn value(&self, s: &str) -> Result<Value, KnobError> {
        (self.parse)(s).ok_or_else(|| KnobError::Value {
            knob: self.name,
            value: s.into(),
            allowed: self.allowed(),
        })
    }

    /// The reference the knob is measured against.
    pub fn truth(&self) -> Truth {
        self.desc().reference
    }

    /// Whether a value is applied by baking the asset again.
    pub fn rebakes(&self) -> bool {
        self.desc().rebakes
    }

    /// The values swept when none are given, around the defaults (`size` is the scene's
    /// output size; sizes are derived from it).
    pub fn defaults(&self, size: (u32, u32)) -> Vec<Value> {
        (self.sweep)(size)
    }

    /// The scene's own value of the knob (None where it cannot be told).
    pub fn own(&self, scene: &Own<'_>) -> Option<Value> {
        (self.own)(scene)
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
        (knob.set)(&mut self, value);
        self
    }
}

#[cfg(test)]
mod tests {
    use super::super::table::KNOBS;
    use super::*;
    use pelt_scene::scene::{ShadowMaps, reflection_limits as limits};

    fn knob(name: &str) -> &'static Knob {
        Knob::named(name).expect("a knob")
    }

    #[test]
    fn every_knob_is_declared_by_the_feature_that_reads_it() {
        for k in KNOBS {
            assert!(
                registry::knob(k.name).is_some(),
                "{} has no descriptor",
                k.name
            );
            let n = KNOBS.iter().filter(|x| x.name == k.name).count();
            assert_eq!(n, 1, "{} is in the table {n} times", k.name);
        }
        for (f, d) in registry::knobs() {
            assert!(
                Knob::named(d.name).is_ok(),
                "{f} declares {}, which the sweep cannot turn",
                d.name
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
                Truth::Strands => assert!(needs(Need::Fur), "{}", k.name),
                Truth::RayTracer => assert!(
                    needs(Need::Optics) || needs(Need::CastingLight),
                    "{}",
                    k.name
                ),
                Truth::Deferred => assert!(k.needs.is_empty(), "{}", k.name),
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
                k.name
            );
            assert!(k.value(&r.end().to_string()).is_ok(), "{}", k.name);
            assert!(k.value(&(r.end() + 1).to_string()).is_err(), "{}", k.name);
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
            assert_eq!(Knob::named(k.name), Ok(k));
            for v in k.defaults((640, 360)) {
                assert_eq!(k.value(&v.to_string()), Ok(v), "{}={v}", k.name);
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
            assert!(settings.len() >= 2, "{} sweeps {}", k.name, settings.len());
            for (i, s) in settings.iter().enumerate() {
                assert_ne!(*s, Setting::default(), "{} value {i} sets nothing", k.name);
                assert!(!settings[..i].contains(s), "{} value {i} repeats", k.name);
                assert_eq!(s.rebakes(), k.rebakes(), "{}", k.name);
            }
        }
    }

    #[test]
    fn a_setting_sets_what_its_knob_names() {
        let s = Setting::default()
            .with(knob("shells"), Value::Count(8))
            .with(knob("quantize"), Value::Quantize(Quantize::U8))
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
