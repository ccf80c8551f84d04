//! `pelt sweep`'s table of knobs: one entry per knob, written in one place (what the scene
//! must hold, how a value parses, the values swept by default, how a value applies, the
//! scene's own value). Ranges come from the homes the scene file and the flags use
//! (`pelt_scene::flags`, `reflection_limits`, `ShadowMaps`, `pelt_fur::manifest::SHELLS`).

use pelt_bake::options::Quantize;
use pelt_fur::HeightBits;
use pelt_scene::Mode;
use pelt_scene::flags;
use pelt_scene::knobs::ShellCount;
use pelt_scene::scene::{
    FurBlend, FurCoverage, FurLighting, ShadowMaps, Technique, reflection_limits as limits,
};

use super::knob::{Knob, KnobError, Need, Value};

/// A power of two from `lo` to `hi`.
fn pow2(s: &str, lo: u32, hi: u32) -> Option<Value> {
    let v: u32 = s.parse().ok()?;
    ((lo..=hi).contains(&v) && v.is_power_of_two()).then_some(Value::Count(v))
}

/// A count in `range`, the range the scene file and the flags accept
/// (`pelt_scene::flags`, one home for each).
fn within(s: &str, range: std::ops::RangeInclusive<u32>) -> Option<Value> {
    flags::count(s, range).ok().map(Value::Count)
}

fn switch(s: &str) -> Option<Value> {
    flags::switch(s).ok().map(Value::Switch)
}

fn counts(v: &[u32]) -> Vec<Value> {
    v.iter().map(|&n| Value::Count(n)).collect()
}

fn on_off(_: (u32, u32)) -> Vec<Value> {
    vec![Value::Switch(true), Value::Switch(false)]
}

/// The count a [`Value::Count`] holds (other values are never made for a count knob).
fn count(v: Value) -> Option<u32> {
    match v {
        Value::Count(n) => Some(n),
        _ => None,
    }
}

/// The switch a [`Value::Switch`] holds.
fn on(v: Value) -> Option<bool> {
    match v {
        Value::Switch(b) => Some(b),
        _ => None,
    }
}

/// Every knob, in report order.
pub const KNOBS: &[Knob] = &[
    Knob {
        name: "shells",
        needs: &[Need::Fur],
        // `auto`: the manifest's shells-by-screen-size rule (no count forced), beside fixed
        // counts.
        parse: |s| {
            if s == "auto" {
                Some(Value::Auto)
            } else {
                within(s, pelt_fur::manifest::SHELLS)
            }
        },
        sweep: |_| {
            let mut v = vec![Value::Auto];
            v.extend(counts(&[4, 8, 16, 32, 64]));
            v
        },
        set: |s, v| {
            s.knobs.shells = match v {
                Value::Auto => Some(ShellCount::BySize),
                v => count(v).map(ShellCount::Fixed),
            }
        },
        own: |o| {
            let look = &o.fur?.look;
            Some(match o.settings?.shells {
                Some(n) => Value::Count(n),
                None if look.shell_rule.is_some() => Value::Auto,
                None => Value::Count(look.shells),
            })
        },
    },
    Knob {
        name: "fins",
        needs: &[Need::Fur],
        parse: switch,
        sweep: on_off,
        set: |s, v| s.knobs.fins = on(v),
        own: |o| {
            let fins = o.settings?.fins_with(o.scene.fur_coverage);
            Some(Value::Switch(
                fins && o.fur.is_some_and(|f| !f.fins.is_empty()),
            ))
        },
    },
    Knob {
        name: "fur-blend",
        needs: &[Need::Fur],
        parse: |s| s.parse().ok().map(Value::Blend),
        sweep: |_| {
            vec![
                Value::Blend(FurBlend::Stipple),
                Value::Blend(FurBlend::Wboit),
            ]
        },
        set: |s, v| {
            if let Value::Blend(b) = v {
                s.knobs.fur_blend = Some(b);
            }
        },
        own: |o| Some(Value::Blend(o.scene.fur_blend)),
    },
    Knob {
        name: "fur-coverage",
        needs: &[Need::Fur],
        parse: |s| s.parse().ok().map(Value::Coverage),
        sweep: |_| {
            [FurCoverage::Analytic, FurCoverage::Binary]
                .map(Value::Coverage)
                .into()
        },
        set: |s, v| {
            if let Value::Coverage(c) = v {
                s.knobs.fur_coverage = Some(c);
            }
        },
        own: |o| Some(Value::Coverage(o.scene.fur_coverage)),
    },
    Knob {
        name: "fur-lighting",
        needs: &[Need::Fur],
        parse: |s| s.parse().ok().map(Value::Lighting),
        sweep: |_| {
            [FurLighting::KajiyaKay, FurLighting::Revie]
                .map(Value::Lighting)
                .into()
        },
        set: |s, v| {
            if let Value::Lighting(l) = v {
                s.knobs.fur_lighting = Some(l);
            }
        },
        own: |o| Some(Value::Lighting(o.scene.fur_lighting)),
    },
    Knob {
        name: "mode",
        needs: &[Need::Fur],
        parse: |s| {
            s.parse()
                .ok()
                .filter(|m| matches!(m, Mode::Inferred | Mode::Deferred | Mode::Forward))
                .map(Value::Mode)
        },
        sweep: |_| {
            [Mode::Inferred, Mode::Deferred, Mode::Forward]
                .map(Value::Mode)
                .into()
        },
        set: |s, v| {
            if let Value::Mode(m) = v {
                s.mode = Some(m);
            }
        },
        own: |_| Some(Value::Mode(Mode::Inferred)),
    },
    Knob {
        name: "texture-size",
        needs: &[Need::Fur],
        parse: |s| pow2(s, 16, 4096),
        sweep: |_| counts(&[64, 128, 256, 512, 1024]),
        set: |s, v| s.texture_size = count(v),
        own: |o| Some(Value::Count(o.fur?.model.size)),
    },
    Knob {
        name: "height-bits",
        needs: &[Need::Fur],
        parse: |s| match s {
            "8" => Some(Value::Bits(HeightBits::Eight)),
            "16" => Some(Value::Bits(HeightBits::Sixteen)),
            _ => None,
        },
        sweep: |_| {
            [HeightBits::Eight, HeightBits::Sixteen]
                .map(Value::Bits)
                .into()
        },
        set: |s, v| {
            if let Value::Bits(b) = v {
                s.height_bits = Some(b);
            }
        },
        own: |o| Some(Value::Bits(o.fur?.model.height_bits)),
    },
    Knob {
        name: "quantize",
        needs: &[Need::Fur],
        parse: |s| s.parse().ok().map(Value::Quantize),
        sweep: |_| {
            [Quantize::U8, Quantize::U16, Quantize::Float]
                .map(Value::Quantize)
                .into()
        },
        set: |s, v| {
            if let Value::Quantize(q) = v {
                s.quantize = Some(q);
            }
        },
        // The comb's storage is not kept in the baked data.
        own: |_| None,
    },
    Knob {
        name: "lbuffer-scale",
        needs: &[],
        parse: |s| flags::lbuffer_scale(s).ok().map(Value::Scale),
        sweep: |_| [0.25, 0.5, 0.625, 0.75, 1.0].map(Value::Scale).into(),
        set: |s, v| {
            if let Value::Scale(x) = v {
                s.knobs.lbuffer_scale = Some(x);
            }
        },
        own: |o| Some(Value::Scale(o.scene.lbuffer_scale)),
    },
    Knob {
        name: "dsf",
        needs: &[],
        parse: switch,
        sweep: on_off,
        set: |s, v| s.knobs.dsf = on(v),
        own: |o| Some(Value::Switch(o.scene.dsf)),
    },
    Knob {
        name: "size",
        needs: &[],
        // The sweep's sizes stay where its references (strands, ray tracer) finish.
        parse: |s| {
            flags::size(s)
                .ok()
                .filter(|&(w, h)| (8..=4096).contains(&w) && (8..=4096).contains(&h))
                .map(|(w, h)| Value::Size(w, h))
        },
        sweep: |(w, h)| {
            [0.25f32, 0.5, 0.75, 1.0]
                .map(|s| {
                    let f = |v: u32| ((v as f32 * s).round() as u32).max(8);
                    Value::Size(f(w), f(h))
                })
                .into()
        },
        set: |s, v| {
            if let Value::Size(w, h) = v {
                s.knobs.size = Some((w, h));
            }
        },
        own: |o| Some(Value::Size(o.scene.output.width, o.scene.output.height)),
    },
    Knob {
        name: "reflections",
        needs: &[Need::Optics],
        parse: |s| s.parse().ok().map(Value::Technique),
        sweep: |_| {
            [Technique::DistanceMaps, Technique::Envmap, Technique::Off]
                .map(Value::Technique)
                .into()
        },
        set: |s, v| {
            if let Value::Technique(t) = v {
                s.knobs.reflections.technique = Some(t);
            }
        },
        own: |o| Some(Value::Technique(o.scene.reflections.technique)),
    },
    Knob {
        name: "linear-steps",
        needs: &[Need::Optics],
        parse: |s| within(s, limits::LINEAR_STEPS),
        sweep: |_| counts(&[4, 8, 16, 32, 64]),
        set: |s, v| s.knobs.reflections.linear_steps = count(v),
        own: |o| Some(Value::Count(o.scene.reflections.linear_steps)),
    },
    Knob {
        name: "secant-steps",
        needs: &[Need::Optics],
        parse: |s| within(s, limits::SECANT_STEPS),
        sweep: |_| counts(&[0, 1, 2, 6, 12]),
        set: |s, v| s.knobs.reflections.secant_steps = count(v),
        own: |o| Some(Value::Count(o.scene.reflections.secant_steps)),
    },
    Knob {
        name: "layers",
        needs: &[Need::Optics],
        parse: |s| within(s, limits::LAYERS),
        sweep: |_| counts(&[3, 4, 5]),
        set: |s, v| s.knobs.reflections.layers = count(v),
        own: |o| Some(Value::Count(o.scene.reflections.layers)),
    },
    Knob {
        name: "cube-size",
        needs: &[Need::Optics],
        parse: |s| pow2(s, 8, 2048),
        sweep: |_| counts(&[64, 128, 256, 512]),
        set: |s, v| s.knobs.reflections.cube_size = count(v),
        own: |o| Some(Value::Count(o.scene.reflections.cube_size)),
    },
    Knob {
        name: "max-depth",
        needs: &[Need::Optics],
        parse: |s| within(s, limits::MAX_DEPTH),
        sweep: |_| counts(&[1, 2, 4, 8]),
        set: |s, v| s.knobs.reflections.max_depth = count(v),
        own: |o| Some(Value::Count(o.scene.reflections.max_depth)),
    },
    Knob {
        name: "min-max",
        needs: &[Need::Optics],
        parse: switch,
        sweep: on_off,
        set: |s, v| s.knobs.reflections.min_max = on(v),
        own: |o| Some(Value::Switch(o.scene.reflections.min_max)),
    },
    Knob {
        name: "shadow-size",
        needs: &[Need::CastingLight],
        parse: |s| flags::shadow_size(s).ok().map(Value::Count),
        sweep: |_| counts(&[128, 256, 512, 1024, 2048]),
        set: |s, v| s.knobs.shadow_size = count(v),
        own: |o| Some(Value::Count(o.scene.shadow_maps.size)),
    },
    Knob {
        name: "pcf",
        needs: &[Need::CastingLight],
        parse: |s| within(s, ShadowMaps::PCF),
        sweep: |_| counts(&[1, 2, 3, 4]),
        set: |s, v| s.knobs.pcf = count(v),
        own: |o| Some(Value::Count(o.scene.shadow_maps.pcf)),
    },
    Knob {
        name: "opacity-layers",
        needs: &[Need::CastingLight, Need::Fur],
        parse: |s| within(s, ShadowMaps::OPACITY_LAYERS),
        sweep: |_| counts(&[0, 1, 2, 3]),
        set: |s, v| s.knobs.opacity_layers = count(v),
        own: |o| Some(Value::Count(o.scene.shadow_maps.opacity_layers)),
    },
];

/// Every knob's name, comma separated.
fn names() -> String {
    KNOBS.iter().map(|k| k.name).collect::<Vec<_>>().join(", ")
}

/// The lookups by name, in this table.
impl Knob {
    /// The knob called `name`.
    pub fn named(name: &str) -> Result<&'static Knob, KnobError> {
        KNOBS
            .iter()
            .find(|k| k.name == name)
            .ok_or_else(|| KnobError::Unknown {
                name: name.into(),
                known: names(),
            })
    }

    /// Parses `NAME=V1,V2,...`.
    pub fn parse_list(arg: &str) -> Result<(&'static Knob, Vec<Value>), KnobError> {
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
}
