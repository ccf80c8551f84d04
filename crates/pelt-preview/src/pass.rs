//! A pass's identity: the name `--explain`, the profile and the errors give it. Each feature
//! declares the ids of the passes it builds or draws on request (`features::geometry::PASS`,
//! …) next to them; the core only carries them. Which passes a frame runs, and in what order,
//! is decided from the registry ([`crate::feature::planned`]).

use std::fmt;

/// A pass, by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Pass(&'static str);

impl Pass {
    /// The pass called `name` (short, lower case, hyphenated: `shadow-maps`).
    pub const fn new(name: &'static str) -> Pass {
        Pass(name)
    }

    /// Its name.
    pub const fn name(self) -> &'static str {
        self.0
    }
}

impl fmt::Display for Pass {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
}
