//! The values each quality knob takes, as data ([`Range`]): what its flag parses, what the
//! scene file checks and the words both write, with the bounds themselves (the scene's
//! limits are these). A leaf of the crate: the scene file, the flags and the knob specs
//! ([`super::spec`]) all read it, and it reads none of them.

use std::fmt;
use std::ops::RangeInclusive;

use crate::flags;

pub use crate::flags::MAX_SIDE;
/// The L-buffer's scale of the output.
pub const LBUFFER_SCALE_BOUNDS: RangeInclusive<f32> = 0.1..=1.0;
/// A shadow map's side.
pub const SHADOW_SIZE_BOUNDS: RangeInclusive<u32> = 16..=4096;
/// The PCF square's side.
pub const PCF_BOUNDS: RangeInclusive<u32> = 1..=8;
/// Deep opacity layers.
pub const OPACITY_LAYERS_BOUNDS: RangeInclusive<u32> = 0..=3;
/// The distance maps' linear search steps.
pub const LINEAR_STEPS_BOUNDS: RangeInclusive<u32> = 1..=1024;
/// Their secant steps.
pub const SECANT_STEPS_BOUNDS: RangeInclusive<u32> = 0..=64;
/// Their layers.
pub const LAYERS_BOUNDS: RangeInclusive<u32> = 3..=8;
/// Their cube's side.
pub const CUBE_SIZE_BOUNDS: RangeInclusive<u32> = 8..=65536;
/// Their reflections' depth.
pub const MAX_DEPTH_BOUNDS: RangeInclusive<u32> = 1..=16;

/// `--size`: each side 1 to [`MAX_SIDE`].
pub const SIZE: Range = Range::Size(1..=MAX_SIDE);
/// `--lbuffer-scale`.
pub const LBUFFER_SCALE: Range = Range::Scale(LBUFFER_SCALE_BOUNDS);
/// `--shells`: auto or the fur manifest's counts.
pub const SHELLS: Range = Range::AutoOrCount(pelt_fur::manifest::SHELLS);
/// `--shadow-size`.
pub const SHADOW_SIZE: Range = Range::PowerOfTwo(SHADOW_SIZE_BOUNDS);
/// `--pcf`.
pub const PCF: Range = Range::Count(PCF_BOUNDS);
/// `--opacity-layers`.
pub const OPACITY_LAYERS: Range = Range::Count(OPACITY_LAYERS_BOUNDS);
/// `--linear-steps`.
pub const LINEAR_STEPS: Range = Range::Count(LINEAR_STEPS_BOUNDS);
/// `--secant-steps`.
pub const SECANT_STEPS: Range = Range::Count(SECANT_STEPS_BOUNDS);
/// `--layers`.
pub const LAYERS: Range = Range::Count(LAYERS_BOUNDS);
/// `--cube-size`.
pub const CUBE_SIZE: Range = Range::PowerOfTwo(CUBE_SIZE_BOUNDS);
/// `--max-depth`.
pub const MAX_DEPTH: Range = Range::Count(MAX_DEPTH_BOUNDS);
/// Every on-or-off knob (`--dsf`, `--fins`, `--min-max`).
pub const SWITCH: Range = Range::Switch;

/// What a knob's error is measured against.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Reference {
    /// The converged strand reference (fur).
    Strands,
    /// Full-resolution deferred at the reference size (lighting).
    Deferred,
    /// The CPU ray tracer (mirrors and glass).
    RayTracer,
}

impl Reference {
    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Reference::Strands => "strands",
            Reference::Deferred => "deferred",
            Reference::RayTracer => "raytrace",
        }
    }
}

/// The values a knob takes, as data: what its flag parses, what the scene file checks and
/// the words both write.
#[derive(Debug, Clone, PartialEq)]
pub enum Range {
    /// A whole number in the range.
    Count(RangeInclusive<u32>),
    /// A power of two in the range.
    PowerOfTwo(RangeInclusive<u32>),
    /// A number in the range.
    Scale(RangeInclusive<f32>),
    /// On or off.
    Switch,
    /// `auto` (the fur manifest's shells-by-screen-size rule) or a count in the range.
    AutoOrCount(RangeInclusive<u32>),
    /// `WxH`, each side in the range.
    Size(RangeInclusive<u32>),
    /// One of these words.
    Words(&'static [&'static str]),
}

/// One value of a knob.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A count or size.
    Count(u32),
    /// A scale.
    Scale(f32),
    /// On or off.
    Switch(bool),
    /// Width and height.
    Size(u32, u32),
    /// The shells-by-screen-size rule of the fur's manifest (`pelt_fur::shells`).
    Auto,
    /// One of the knob's words (a mode, a fur blend, a reflection technique, ...).
    Word(&'static str),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Count(n) => write!(f, "{n}"),
            Value::Scale(s) => write!(f, "{s}"),
            Value::Switch(b) => f.write_str(if *b { "on" } else { "off" }),
            Value::Size(w, h) => write!(f, "{w}x{h}"),
            Value::Auto => f.write_str("auto"),
            Value::Word(w) => f.write_str(w),
        }
    }
}

impl Value {
    /// The count a [`Value::Count`] holds.
    pub fn count(self) -> Option<u32> {
        match self {
            Value::Count(n) => Some(n),
            _ => None,
        }
    }

    /// The switch a [`Value::Switch`] holds.
    pub fn on(self) -> Option<bool> {
        match self {
            Value::Switch(b) => Some(b),
            _ => None,
        }
    }

    /// What a [`Value::Word`] names, parsed (`FurBlend`, `Technique`, `Mode`, ...).
    pub fn word<T: std::str::FromStr>(self) -> Option<T> {
        match self {
            Value::Word(w) => w.parse().ok(),
            _ => None,
        }
    }
}

/// `a`, `a or b`, `a, b or c`.
fn either(words: &[&str]) -> String {
    match words {
        [] => String::new(),
        [one] => (*one).to_owned(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

impl Range {
    /// The values in words (`1 to 8`, `a power of two from 16 to 4096`, `on or off`).
    pub fn words(&self) -> String {
        match self {
            Range::Count(r) => format!("{} to {}", r.start(), r.end()),
            Range::PowerOfTwo(r) => format!("a power of two from {} to {}", r.start(), r.end()),
            Range::Scale(r) => format!("{} to {}", r.start(), r.end()),
            Range::Switch => "on or off".into(),
            Range::AutoOrCount(r) => {
                format!("auto (by screen size) or {} to {}", r.start(), r.end())
            }
            Range::Size(r) => format!("WxH, each {} to {}", r.start(), r.end()),
            Range::Words(w) => either(w),
        }
    }

    /// One value from its text, as a flag gives it; the error says what was given and what
    /// is allowed.
    pub fn parse(&self, s: &str) -> Result<Value, String> {
        match self {
            Range::Count(r) => flags::count(s, r.clone()).map(Value::Count),
            Range::PowerOfTwo(r) => flags::power_of_two(s, r.clone()).map(Value::Count),
            Range::Scale(r) => flags::scale(s, r.clone()).map(Value::Scale),
            Range::Switch => flags::switch(s).map(Value::Switch),
            Range::AutoOrCount(_) if s == "auto" => Ok(Value::Auto),
            Range::AutoOrCount(r) => flags::count(s, r.clone())
                .map(Value::Count)
                .map_err(|e| format!("{e}, or auto")),
            Range::Size(r) => flags::sides(s, r.clone()).map(|(w, h)| Value::Size(w, h)),
            Range::Words(w) => w
                .iter()
                .find(|&&w| w == s)
                .map(|&w| Value::Word(w))
                .ok_or_else(|| format!("{s:?} is not {}", either(w))),
        }
    }

    /// Whether `v` is in the range, as the scene file checks it: the error is `must be ...,
    /// got V` (the scene file's error names the file and the field).
    pub fn check(&self, v: Value) -> Result<(), String> {
        let ok = match (self, v) {
            (Range::Count(r) | Range::AutoOrCount(r), Value::Count(n)) => r.contains(&n),
            (Range::AutoOrCount(_), Value::Auto) => true,
            (Range::PowerOfTwo(r), Value::Count(n)) => r.contains(&n) && n.is_power_of_two(),
            (Range::Scale(r), Value::Scale(x)) => r.contains(&x),
            (Range::Switch, Value::Switch(_)) => true,
            (Range::Size(r), Value::Size(w, h)) => r.contains(&w) && r.contains(&h),
            (Range::Words(w), Value::Word(x)) => w.contains(&x),
            _ => false,
        };
        if ok {
            return Ok(());
        }
        Err(match self {
            Range::Count(r) | Range::AutoOrCount(r) => {
                format!("must be {} to {}, got {v}", r.start(), r.end())
            }
            Range::Scale(r) => format!("must be from {} to {}, got {v}", r.start(), r.end()),
            _ => format!("must be {}, got {v}", self.words()),
        })
    }

    /// Every value, in order, where the range is a list (a switch: on, off; words).
    pub fn every(&self) -> Option<Vec<Value>> {
        match self {
            Range::Switch => Some(vec![Value::Switch(true), Value::Switch(false)]),
            Range::Words(w) => Some(w.iter().map(|&w| Value::Word(w)).collect()),
            _ => None,
        }
    }
}

impl Range {
    /// A count (a [`Range::Count`] or [`Range::PowerOfTwo`] knob's flag).
    pub fn count(&self, s: &str) -> Result<u32, String> {
        self.parse(s)
            .and_then(|v| v.count().ok_or_else(|| format!("{s:?} is not a count")))
    }

    /// A switch's flag.
    pub fn switch(&self, s: &str) -> Result<bool, String> {
        self.parse(s)
            .and_then(|v| v.on().ok_or_else(|| format!("{s:?} is not on or off")))
    }

    /// A scale's flag.
    pub fn scale(&self, s: &str) -> Result<f32, String> {
        match self.parse(s)? {
            Value::Scale(x) => Ok(x),
            _ => Err(format!("{s:?} is not a scale")),
        }
    }

    /// A size's flag.
    pub fn size(&self, s: &str) -> Result<(u32, u32), String> {
        match self.parse(s)? {
            Value::Size(w, h) => Ok((w, h)),
            _ => Err(format!("{s:?} is not WxH")),
        }
    }

    /// A scene file's count, checked: `must be ..., got V`.
    pub fn check_count(&self, v: u32) -> Result<(), String> {
        self.check(Value::Count(v))
    }
}
