//! `pelt sweep`'s table of knobs: one entry per knob spec (`pelt_scene::knobs::spec`, where
//! each knob's name, range, parse, default, reference, own value and setter are declared),
//! with what the sweep adds: what the scene must hold, the values swept by default, a
//! narrower range where the sweep's references stop, and how the mode and the re-bakes apply.

use pelt_fur::HeightBits;
use pelt_scene::knobs::spec::{self, Range};

use super::knob::{Knob, KnobError, Need, Value};

fn counts(v: &[u32]) -> Vec<Value> {
    v.iter().map(|&n| Value::Count(n)).collect()
}

/// The sweep's sizes: where its references (strands, ray tracer) finish.
const SWEPT_SIZE: Range = Range::Size(8..=4096);
/// The sweep's cube-map sizes.
const SWEPT_CUBE_SIZE: Range = Range::PowerOfTwo(8..=2048);

/// Every knob, in report order.
pub const KNOBS: &[Knob] = &[
    Knob::of(
        &spec::SHELLS,
        &[Need::Fur],
        // `auto`: the manifest's shells-by-screen-size rule (no count forced), beside fixed
        // counts.
        Some(|_| {
            let mut v = vec![Value::Auto];
            v.extend(counts(&[4, 8, 16, 32, 64]));
            v
        }),
    ),
    Knob::of(&spec::FINS, &[Need::Fur], None),
    Knob::of(&spec::FUR_BLEND, &[Need::Fur], None),
    Knob::of(&spec::FUR_COVERAGE, &[Need::Fur], None),
    Knob::of(&spec::FUR_LIGHTING, &[Need::Fur], None),
    Knob {
        set: Some(|s, v| s.mode = v.word()),
        ..Knob::of(&spec::MODE, &[Need::Fur], None)
    },
    Knob {
        set: Some(|s, v| s.texture_size = v.count()),
        ..Knob::of(
            &spec::TEXTURE_SIZE,
            &[Need::Fur],
            Some(|_| counts(&[64, 128, 256, 512, 1024])),
        )
    },
    Knob {
        set: Some(|s, v| {
            s.height_bits = match v {
                Value::Word("8") => Some(HeightBits::Eight),
                Value::Word("16") => Some(HeightBits::Sixteen),
                _ => None,
            }
        }),
        ..Knob::of(&spec::HEIGHT_BITS, &[Need::Fur], None)
    },
    Knob {
        set: Some(|s, v| s.quantize = v.word()),
        ..Knob::of(&spec::QUANTIZE, &[Need::Fur], None)
    },
    Knob::of(
        &spec::LBUFFER_SCALE,
        &[],
        Some(|_| [0.25, 0.5, 0.625, 0.75, 1.0].map(Value::Scale).into()),
    ),
    Knob::of(&spec::DSF, &[], None),
    Knob {
        within: Some(&SWEPT_SIZE),
        ..Knob::of(
            &spec::SIZE,
            &[],
            Some(|(w, h)| {
                [0.25f32, 0.5, 0.75, 1.0]
                    .map(|s| {
                        let f = |v: u32| ((v as f32 * s).round() as u32).max(8);
                        Value::Size(f(w), f(h))
                    })
                    .into()
            }),
        )
    },
    Knob::of(&spec::REFLECTIONS, &[Need::Optics], None),
    Knob::of(
        &spec::LINEAR_STEPS,
        &[Need::Optics],
        Some(|_| counts(&[4, 8, 16, 32, 64])),
    ),
    Knob::of(
        &spec::SECANT_STEPS,
        &[Need::Optics],
        Some(|_| counts(&[0, 1, 2, 6, 12])),
    ),
    Knob::of(&spec::LAYERS, &[Need::Optics], Some(|_| counts(&[3, 4, 5]))),
    Knob {
        within: Some(&SWEPT_CUBE_SIZE),
        ..Knob::of(
            &spec::CUBE_SIZE,
            &[Need::Optics],
            Some(|_| counts(&[64, 128, 256, 512])),
        )
    },
    Knob::of(
        &spec::MAX_DEPTH,
        &[Need::Optics],
        Some(|_| counts(&[1, 2, 4, 8])),
    ),
    Knob::of(&spec::MIN_MAX, &[Need::Optics], None),
    Knob::of(&spec::SILHOUETTES, &[Need::Optics], None),
    Knob::of(
        &spec::SHADOW_SIZE,
        &[Need::CastingLight],
        Some(|_| counts(&[128, 256, 512, 1024, 2048])),
    ),
    Knob::of(
        &spec::PCF,
        &[Need::CastingLight],
        Some(|_| counts(&[1, 2, 3, 4])),
    ),
    Knob::of(
        &spec::OPACITY_LAYERS,
        &[Need::CastingLight, Need::Fur],
        Some(|_| counts(&[0, 1, 2, 3])),
    ),
];

/// Every knob's name, comma separated.
fn names() -> String {
    KNOBS.iter().map(Knob::name).collect::<Vec<_>>().join(", ")
}

/// The lookups by name, in this table.
impl Knob {
    /// The knob called `name`.
    pub fn named(name: &str) -> Result<&'static Knob, KnobError> {
        KNOBS
            .iter()
            .find(|k| k.name() == name)
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
