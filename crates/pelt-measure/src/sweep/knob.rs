//! The quality knobs `pelt sweep` turns: their names (the flags of `pelt render` and `pelt
//! bake`), how each value is parsed, the values swept when none are given, and how a value is
//! applied to a scene, a mode or a re-bake. The range in words, the default, the reference
//! each is measured against and whether it re-bakes are declared by the renderer feature
//! that reads the knob (`pelt_preview::feature::KnobDesc`) and read here.

use std::fmt;

use pelt_bake::options::Quantize;
use pelt_fur::HeightBits;
use pelt_preview::feature::KnobDesc;
use pelt_preview::features::registry;
use pelt_scene::Mode;
use pelt_scene::flags;
use pelt_scene::knobs::Knobs;
use pelt_scene::scene::{
    FurBlend, FurCoverage, FurLighting, ShadowMaps, Technique, reflection_limits as limits,
};

/// A knob.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Knob {
    /// Shells per fur object.
    Shells,
    /// Silhouette fins.
    Fins,
    /// Fur compositing.
    FurBlend,
    /// How much of the skin a shell hides.
    Coverage,
    /// How the deferred paths light fur.
    FurLighting,
    /// The renderer's mode (inferred, deferred, forward).
    Mode,
    /// Fur texture size (re-bake).
    TextureSize,
    /// Heightfield bits (re-bake).
    HeightBits,
    /// `_FUR_COMB` quantization (re-bake).
    Quantize,
    /// L-buffer scale.
    LbufferScale,
    /// Discontinuity sensitive filtering.
    Dsf,
    /// Output size.
    Size,
    /// Mirror and glass technique.
    Reflections,
    /// Distance-map linear steps.
    LinearSteps,
    /// Secant steps.
    SecantSteps,
    /// Distance-map layers.
    Layers,
    /// Cube face size.
    CubeSize,
    /// Most bounces.
    MaxDepth,
    /// Min-max acceleration.
    MinMax,
    /// Shadow cube face size.
    ShadowSize,
    /// Shadow filtering (PCF side).
    Pcf,
    /// Deep opacity map layers (fur self-shadowing).
    OpacityLayers,
}

/// What a knob is measured against (declared with the knob by the feature that reads it).
pub use pelt_preview::feature::Reference as Truth;

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
        }
    }
}

/// A knob name or value that is not allowed (a usage error).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KnobError {
    /// No such knob.
    #[error("unknown knob {name:?} (knobs: {})", Knob::ALL.map(Knob::name).join(", "))]
    Unknown {
        /// What was given.
        name: String,
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

fn count(s: &str, lo: u32, hi: u32, pow2: bool) -> Option<Value> {
    let v: u32 = s.parse().ok()?;
    ((lo..=hi).contains(&v) && (!pow2 || v.is_power_of_two())).then_some(Value::Count(v))
}

/// A count in `range`, the range the scene file and the flags accept
/// (`pelt_scene::flags`, one home for each).
fn within(s: &str, range: std::ops::RangeInclusive<u32>) -> Option<Value> {
    flags::count(s, range).ok().map(Value::Count)
}

fn switch(s: &str) -> Option<Value> {
    flags::switch(s).ok().map(Value::Switch)
}

/// A knob without a registered descriptor (the registry test rules it out).
const UNREGISTERED: KnobDesc = KnobDesc::new("?", "?", "?", Truth::Strands);

impl Knob {
    /// Every knob, in report order.
    pub const ALL: [Knob; 22] = [
        Knob::Shells,
        Knob::Fins,
        Knob::FurBlend,
        Knob::Coverage,
        Knob::FurLighting,
        Knob::Mode,
        Knob::TextureSize,
        Knob::HeightBits,
        Knob::Quantize,
        Knob::LbufferScale,
        Knob::Dsf,
        Knob::Size,
        Knob::Reflections,
        Knob::LinearSteps,
        Knob::SecantSteps,
        Knob::Layers,
        Knob::CubeSize,
        Knob::MaxDepth,
        Knob::MinMax,
        Knob::ShadowSize,
        Knob::Pcf,
        Knob::OpacityLayers,
    ];

    /// The knob's name (the `pelt render` or `pelt bake` flag without dashes).
    pub fn name(self) -> &'static str {
        match self {
            Knob::Shells => "shells",
            Knob::Fins => "fins",
            Knob::FurBlend => "fur-blend",
            Knob::Coverage => "fur-coverage",
            Knob::FurLighting => "fur-lighting",
            Knob::Mode => "mode",
            Knob::TextureSize => "texture-size",
            Knob::HeightBits => "height-bits",
            Knob::Quantize => "quantize",
            Knob::LbufferScale => "lbuffer-scale",
            Knob::Dsf => "dsf",
            Knob::Size => "size",
            Knob::Reflections => "reflections",
            Knob::LinearSteps => "linear-steps",
            Knob::SecantSteps => "secant-steps",
            Knob::Layers => "layers",
            Knob::CubeSize => "cube-size",
            Knob::MaxDepth => "max-depth",
            Knob::MinMax => "min-max",
            Knob::ShadowSize => "shadow-size",
            Knob::Pcf => "pcf",
            Knob::OpacityLayers => "opacity-layers",
        }
    }

    /// The knob called `name`.
    pub fn named(name: &str) -> Result<Knob, KnobError> {
        Knob::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| KnobError::Unknown { name: name.into() })
    }

    /// Its descriptor, as the feature that reads it registered it
    /// (`pelt_preview::features::registry`): range, default, reference.
    pub fn desc(self) -> &'static KnobDesc {
        registry::knob(self.name()).unwrap_or(&UNREGISTERED)
    }

    /// What values it allows, in words.
    pub fn allowed(self) -> &'static str {
        self.desc().range
    }

    /// Parses one value.
    pub fn value(self, s: &str) -> Result<Value, KnobError> {
        let v = match self {
            Knob::Shells => within(s, pelt_fur::manifest::SHELLS),
            Knob::Fins | Knob::Dsf | Knob::MinMax => switch(s),
            Knob::FurBlend => s.parse().ok().map(Value::Blend),
            Knob::Coverage => s.parse().ok().map(Value::Coverage),
            Knob::FurLighting => s.parse().ok().map(Value::Lighting),
            Knob::Mode => s
                .parse()
                .ok()
                .filter(|m| matches!(m, Mode::Inferred | Mode::Deferred | Mode::Forward))
                .map(Value::Mode),
            Knob::TextureSize => count(s, 16, 4096, true),
            Knob::HeightBits => match s {
                "8" => Some(Value::Bits(HeightBits::Eight)),
                "16" => Some(Value::Bits(HeightBits::Sixteen)),
                _ => None,
            },
            Knob::Quantize => s.parse().ok().map(Value::Quantize),
            Knob::LbufferScale => flags::lbuffer_scale(s).ok().map(Value::Scale),
            // The sweep's sizes stay where its references (strands, ray tracer) finish.
            Knob::Size => flags::size(s)
                .ok()
                .filter(|&(w, h)| (8..=4096).contains(&w) && (8..=4096).contains(&h))
                .map(|(w, h)| Value::Size(w, h)),
            Knob::Reflections => s.parse().ok().map(Value::Technique),
            Knob::LinearSteps => within(s, limits::LINEAR_STEPS),
            Knob::SecantSteps => within(s, limits::SECANT_STEPS),
            Knob::Layers => within(s, limits::LAYERS),
            Knob::CubeSize => count(s, 8, 2048, true),
            Knob::MaxDepth => within(s, limits::MAX_DEPTH),
            Knob::ShadowSize => flags::shadow_size(s).ok().map(Value::Count),
            Knob::Pcf => within(s, ShadowMaps::PCF),
            Knob::OpacityLayers => within(s, ShadowMaps::OPACITY_LAYERS),
        };
        v.ok_or_else(|| KnobError::Value {
            knob: self.name(),
            value: s.into(),
            allowed: self.allowed(),
        })
    }

    /// Parses `NAME=V1,V2,...`.
    pub fn parse_list(arg: &str) -> Result<(Knob, Vec<Value>), KnobError> {
        let (name, values) = arg
            .split_once('=')
            .ok_or_else(|| KnobError::Syntax { given: arg.into() })?;
        let knob = Knob::named(name.trim())?;
        let values = values
            .split(',')
            .map(|v| knob.value(v.trim()))
            .collect::<Result<Vec<_>, _>>()?;
        if values.is_empty() {
            return Err(KnobError::Syntax { given: arg.into() });
        }
        Ok((knob, values))
    }

    /// The reference the knob is measured against.
    pub fn truth(self) -> Truth {
        self.desc().reference
    }

    /// Whether a value is applied by baking the asset again.
    pub fn rebakes(self) -> bool {
        self.desc().rebakes
    }

    /// The values swept when none are given, around the defaults (`size` is the scene's
    /// output size; sizes are derived from it).
    pub fn defaults(self, (w, h): (u32, u32)) -> Vec<Value> {
        let c = |v: &[u32]| v.iter().map(|&n| Value::Count(n)).collect();
        let onoff = vec![Value::Switch(true), Value::Switch(false)];
        match self {
            Knob::Shells => c(&[4, 8, 16, 32, 64]),
            Knob::Fins | Knob::Dsf | Knob::MinMax => onoff,
            Knob::FurBlend => vec![
                Value::Blend(FurBlend::Stipple),
                Value::Blend(FurBlend::Wboit),
            ],
            Knob::Coverage => vec![
                Value::Coverage(FurCoverage::Analytic),
                Value::Coverage(FurCoverage::Binary),
            ],
            Knob::FurLighting => vec![
                Value::Lighting(FurLighting::KajiyaKay),
                Value::Lighting(FurLighting::Revie),
            ],
            Knob::Mode => [Mode::Inferred, Mode::Deferred, Mode::Forward]
                .map(Value::Mode)
                .into(),
            Knob::TextureSize => c(&[64, 128, 256, 512, 1024]),
            Knob::HeightBits => vec![
                Value::Bits(HeightBits::Eight),
                Value::Bits(HeightBits::Sixteen),
            ],
            Knob::Quantize => [Quantize::U8, Quantize::U16, Quantize::Float]
                .map(Value::Quantize)
                .into(),
            Knob::LbufferScale => [0.25, 0.5, 0.625, 0.75, 1.0].map(Value::Scale).into(),
            Knob::Size => [0.25f32, 0.5, 0.75, 1.0]
                .map(|s| {
                    let f = |v: u32| ((v as f32 * s).round() as u32).max(8);
                    Value::Size(f(w), f(h))
                })
                .into(),
            Knob::Reflections => [Technique::DistanceMaps, Technique::Envmap, Technique::Off]
                .map(Value::Technique)
                .into(),
            Knob::LinearSteps => c(&[4, 8, 16, 32, 64]),
            Knob::SecantSteps => c(&[0, 1, 2, 6, 12]),
            Knob::Layers => c(&[3, 4, 5]),
            Knob::CubeSize => c(&[64, 128, 256, 512]),
            Knob::MaxDepth => c(&[1, 2, 4, 8]),
            Knob::ShadowSize => c(&[128, 256, 512, 1024, 2048]),
            Knob::Pcf => c(&[1, 2, 3, 4]),
            Knob::OpacityLayers => c(&[0, 1, 2, 3]),
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
    pub fn with(mut self, knob: Knob, value: Value) -> Setting {
        let k = &mut self.knobs;
        let r = &mut k.reflections;
        match (knob, value) {
            (Knob::Shells, Value::Count(n)) => k.shells = Some(n),
            (Knob::Fins, Value::Switch(b)) => k.fins = Some(b),
            (Knob::FurBlend, Value::Blend(b)) => k.fur_blend = Some(b),
            (Knob::Coverage, Value::Coverage(c)) => k.fur_coverage = Some(c),
            (Knob::FurLighting, Value::Lighting(l)) => k.fur_lighting = Some(l),
            (Knob::Mode, Value::Mode(m)) => self.mode = Some(m),
            (Knob::TextureSize, Value::Count(n)) => self.texture_size = Some(n),
            (Knob::HeightBits, Value::Bits(b)) => self.height_bits = Some(b),
            (Knob::Quantize, Value::Quantize(q)) => self.quantize = Some(q),
            (Knob::LbufferScale, Value::Scale(s)) => k.lbuffer_scale = Some(s),
            (Knob::Dsf, Value::Switch(b)) => k.dsf = Some(b),
            (Knob::Size, Value::Size(w, h)) => k.size = Some((w, h)),
            (Knob::Reflections, Value::Technique(t)) => r.technique = Some(t),
            (Knob::LinearSteps, Value::Count(n)) => r.linear_steps = Some(n),
            (Knob::SecantSteps, Value::Count(n)) => r.secant_steps = Some(n),
            (Knob::Layers, Value::Count(n)) => r.layers = Some(n),
            (Knob::CubeSize, Value::Count(n)) => r.cube_size = Some(n),
            (Knob::MaxDepth, Value::Count(n)) => r.max_depth = Some(n),
            (Knob::MinMax, Value::Switch(b)) => r.min_max = Some(b),
            (Knob::ShadowSize, Value::Count(n)) => k.shadow_size = Some(n),
            (Knob::Pcf, Value::Count(n)) => k.pcf = Some(n),
            (Knob::OpacityLayers, Value::Count(n)) => k.opacity_layers = Some(n),
            // Values come from the knob's own parser; any other pair cannot be made.
            _ => {}
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_knob_is_declared_by_the_feature_that_reads_it() {
        for k in Knob::ALL {
            assert!(
                registry::knob(k.name()).is_some(),
                "{} has no descriptor",
                k.name()
            );
        }
        for (f, d) in registry::knobs() {
            assert!(
                Knob::named(d.name).is_ok(),
                "{f} declares {}, which the sweep cannot turn",
                d.name
            );
        }
        let truths = [
            (Knob::Shells, Truth::Strands),
            (Knob::Quantize, Truth::Strands),
            (Knob::Dsf, Truth::Deferred),
            (Knob::Size, Truth::Deferred),
            (Knob::MinMax, Truth::RayTracer),
            (Knob::Pcf, Truth::RayTracer),
            (Knob::ShadowSize, Truth::RayTracer),
            (Knob::OpacityLayers, Truth::Strands),
        ];
        for (k, t) in truths {
            assert_eq!(k.truth(), t, "{}", k.name());
        }
        assert!(Knob::HeightBits.rebakes() && !Knob::Fins.rebakes());
    }

    #[test]
    fn the_ranges_in_words_are_the_scene_files_ranges() {
        for (k, r) in [
            (Knob::Shells, pelt_fur::manifest::SHELLS),
            (Knob::LinearSteps, limits::LINEAR_STEPS),
            (Knob::SecantSteps, limits::SECANT_STEPS),
            (Knob::Layers, limits::LAYERS),
            (Knob::MaxDepth, limits::MAX_DEPTH),
            (Knob::Pcf, ShadowMaps::PCF),
            (Knob::OpacityLayers, ShadowMaps::OPACITY_LAYERS),
        ] {
            assert_eq!(
                k.allowed(),
                format!("{} to {}", r.start(), r.end()),
                "{k:?}"
            );
            assert!(k.value(&r.end().to_string()).is_ok(), "{k:?}");
            assert!(k.value(&(r.end() + 1).to_string()).is_err(), "{k:?}");
        }
        let l = pelt_scene::scene::LBUFFER_SCALE;
        assert_eq!(
            Knob::LbufferScale.allowed(),
            format!("{} to {}", l.start(), l.end())
        );
    }

    #[test]
    fn names_round_trip_and_bad_ones_name_the_range() {
        for k in Knob::ALL {
            assert_eq!(Knob::named(k.name()), Ok(k));
            for v in k.defaults((640, 360)) {
                assert_eq!(k.value(&v.to_string()), Ok(v), "{}={v}", k.name());
            }
        }
        let e = Knob::parse_list("shells=4,300").expect_err("300 shells");
        assert_eq!(
            e.to_string(),
            "knob shells: \"300\" is not allowed (1 to 256)"
        );
        let e = Knob::parse_list("shell=4").expect_err("unknown");
        assert!(e.to_string().contains("unknown knob \"shell\""), "{e}");
        assert!(Knob::parse_list("shells").is_err());
        assert!(Knob::parse_list("texture-size=100").is_err());
        assert!(Knob::parse_list("mode=strands").is_err());
    }

    #[test]
    fn a_setting_sets_what_its_knob_names() {
        let s = Setting::default()
            .with(Knob::Shells, Value::Count(8))
            .with(Knob::Quantize, Value::Quantize(Quantize::U8))
            .with(Knob::LinearSteps, Value::Count(7));
        assert_eq!(s.knobs.shells, Some(8));
        assert_eq!(s.quantize, Some(Quantize::U8));
        assert_eq!(s.knobs.reflections.linear_steps, Some(7));
        assert!(s.rebakes());
        assert!(
            !Setting::default()
                .with(Knob::Fins, Value::Switch(false))
                .rebakes()
        );
    }
}
