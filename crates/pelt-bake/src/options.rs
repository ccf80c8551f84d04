//! Bake options and their parsing (the CLI maps its flags onto these).

use std::fmt;
use std::str::FromStr;

pub use pelt_geom::topology::TopologyOptions;

/// What to do with tangents.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum TangentMode {
    /// Keep TANGENT when the primitive has it (and NORMAL); generate it otherwise.
    #[default]
    Keep,
    /// Always generate MikkTSpace tangents.
    Regenerate,
}

/// How COLOR_0's RGB holds the painted direction.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum ColorSpace {
    /// The stored (linear, as glTF defines COLOR_0) value is the painted value.
    #[default]
    Linear,
    /// The direction was painted as 8-bit sRGB and the exporter linearized it (Blender's byte
    /// colors): re-encode with the sRGB transfer function before decoding the direction.
    Srgb,
}

/// Storage of `_FUR_COMB`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Quantize {
    /// VEC4 float.
    #[default]
    Float,
    /// VEC4 unsigned short, normalized.
    U16,
    /// VEC4 unsigned byte, normalized.
    U8,
}

/// How much topology a bake writes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum TopologyMode {
    /// `_NORMAL_GROUP` and fin edges.
    #[default]
    Full,
    /// `_NORMAL_GROUP` only (no fins).
    Groups,
    /// Neither (the comb bake alone).
    Off,
}

/// A remapping of the comb's axes: output axis i = sign_i · input axis src_i.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisMap {
    /// (source axis 0-2, sign) for x, y, z.
    pub axes: [(usize, f64); 3],
}

impl Default for AxisMap {
    fn default() -> Self {
        AxisMap {
            axes: [(0, 1.0), (1, 1.0), (2, 1.0)],
        }
    }
}

impl AxisMap {
    /// Applies the map.
    pub fn apply(&self, v: [f64; 3]) -> [f64; 3] {
        self.axes.map(|(src, sign)| sign * v[src])
    }

    /// True for x,y,z.
    pub fn is_identity(&self) -> bool {
        *self == AxisMap::default()
    }
}

/// Error parsing an [`AxisMap`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "invalid axis map {0:?}: expected three of x, y, z, each once, optionally negated (e.g. x,z,-y)"
)]
pub struct AxisMapError(String);

impl FromStr for AxisMap {
    type Err = AxisMapError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let err = || AxisMapError(s.to_owned());
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        if parts.len() != 3 {
            return Err(err());
        }
        let mut axes = [(0, 1.0); 3];
        let mut seen = [false; 3];
        for (i, p) in parts.iter().enumerate() {
            let (sign, name) = match p.strip_prefix('-') {
                Some(n) => (-1.0, n),
                None => (1.0, p.strip_prefix('+').unwrap_or(p)),
            };
            let src = match name.to_ascii_lowercase().as_str() {
                "x" => 0,
                "y" => 1,
                "z" => 2,
                _ => return Err(err()),
            };
            if seen[src] {
                return Err(err());
            }
            seen[src] = true;
            axes[i] = (src, sign);
        }
        Ok(AxisMap { axes })
    }
}

impl fmt::Display for AxisMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names = ["x", "y", "z"];
        let parts: Vec<String> = self
            .axes
            .iter()
            .map(|&(s, sign)| format!("{}{}", if sign < 0.0 { "-" } else { "" }, names[s]))
            .collect();
        write!(f, "{}", parts.join(","))
    }
}

/// Everything a bake can be told.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BakeOptions {
    /// Keep or regenerate tangents.
    pub tangents: TangentMode,
    /// How COLOR_0 holds the direction.
    pub color_space: ColorSpace,
    /// Axis remap applied to the decoded direction (for Z-up sources).
    pub axes: AxisMap,
    /// Storage of `_FUR_COMB`.
    pub quantize: Quantize,
    /// Welding and the normal-group rule.
    pub topology: TopologyOptions,
    /// How much topology to write.
    pub topology_mode: TopologyMode,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_maps_parse_and_apply() {
        let m: AxisMap = "x,z,-y".parse().unwrap();
        assert_eq!(m.apply([1.0, 2.0, 3.0]), [1.0, 3.0, -2.0]);
        assert_eq!(m.to_string(), "x,z,-y");
        assert!("x,y".parse::<AxisMap>().is_err());
        assert!("x,x,z".parse::<AxisMap>().is_err());
        assert!("x,y,w".parse::<AxisMap>().is_err());
        assert!(AxisMap::default().is_identity());
    }
}
