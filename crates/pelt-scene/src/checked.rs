//! The scene file's checked numbers: `f32` newtypes whose deserializing fails, at its place
//! in the file, when the value is out of range ([`Unit`], [`Ior`], [`NonNegative`],
//! [`Positive`]). Below the scene file and the wind, which both read them.

use serde::{Deserialize, Serialize};

/// A checked `f32` newtype: deserializing one that fails `$ok` is an error at its place in
/// the file, with `$what` as the message.
macro_rules! checked_f32 {
    ($(#[$doc:meta])* $name:ident, |$v:ident| $ok:expr, $what:literal) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
        #[serde(try_from = "f32", into = "f32")]
        pub struct $name(pub f32);

        impl TryFrom<f32> for $name {
            type Error = String;
            fn try_from($v: f32) -> Result<Self, String> {
                if $ok {
                    Ok($name($v))
                } else {
                    Err(format!(concat!("must be ", $what, ", got {}"), $v))
                }
            }
        }

        impl From<$name> for f32 {
            fn from(x: $name) -> f32 {
                x.0
            }
        }
    };
}

checked_f32!(
    /// A number in (0, 1].
    Unit,
    |v| v > 0.0 && v <= 1.0,
    "above 0 and at most 1"
);
checked_f32!(
    /// An index of refraction in [1, 3].
    Ior,
    |v| (1.0..=3.0).contains(&v),
    "from 1 to 3"
);
checked_f32!(
    /// A finite number ≥ 0.
    NonNegative,
    |v| v.is_finite() && v >= 0.0,
    "a finite number of at least 0"
);
checked_f32!(
    /// A finite number > 0.
    Positive,
    |v| v.is_finite() && v > 0.0,
    "a finite number above 0"
);
