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
    /// Always generate tangents (with [`TangentGenerator`]'s rule).
    Regenerate,
}

/// Which generator makes the tangents a bake generates.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum TangentGenerator {
    /// MikkTSpace where the primitive's material has a normal texture (a normal map needs the
    /// frame glTF names), the gradient frame elsewhere (the comb decodes the same in any
    /// stored frame). [`crate::primitive::bake_primitive`] alone knows no material: it treats
    /// the primitive as having none; [`crate::asset`] resolves this per primitive.
    #[default]
    Auto,
    /// MikkTSpace everywhere (bit-identical to the reference).
    Mikktspace,
    /// The per-vertex UV-gradient frame everywhere (`pelt_geom::gradient`).
    Gradient,
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

/// How the output is packed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Compression {
    /// Plain: float attributes, uncompressed bufferViews.
    #[default]
    None,
    /// `EXT_meshopt_compression`: quantized attributes and compressed streams
    /// ([`pelt_io::pack`]); a float comb is stored as normalized u8.
    Meshopt,
}

impl serde::Serialize for Compression {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for Compression {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse()
            .map_err(|e| serde::de::Error::custom(format!("compress: {e}")))
    }
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

/// A name that is not one of an option's values.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{value:?} is not one of {}", allowed.join(", "))]
pub struct NameError {
    /// The name given.
    pub value: String,
    /// The names allowed.
    pub allowed: &'static [&'static str],
}

/// One home for an option's names: the CLI's values, the report's words, scene and config
/// files all parse and print them here.
macro_rules! named {
    ($t:ty { $($v:ident => $n:literal),+ $(,)? }) => {
        impl $t {
            /// Every value's name, in declaration order.
            pub const NAMES: &'static [&'static str] = &[$($n),+];

            /// This value's name.
            pub fn name(self) -> &'static str {
                match self {
                    $(Self::$v => $n),+
                }
            }
        }

        impl FromStr for $t {
            type Err = NameError;
            fn from_str(s: &str) -> Result<Self, NameError> {
                match s {
                    $($n => Ok(Self::$v),)+
                    _ => Err(NameError { value: s.to_owned(), allowed: Self::NAMES }),
                }
            }
        }

        impl fmt::Display for $t {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

named!(TangentMode { Keep => "keep", Regenerate => "regenerate" });
named!(TangentGenerator { Auto => "auto", Mikktspace => "mikktspace", Gradient => "gradient" });
named!(ColorSpace { Linear => "linear", Srgb => "srgb" });
named!(Quantize { Float => "float", U16 => "u16", U8 => "u8" });
named!(Compression { None => "none", Meshopt => "meshopt" });
named!(TopologyMode { Full => "full", Groups => "groups", Off => "off" });

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

/// Where the comb comes from.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub enum CombSource {
    /// COLOR_0, as painted (primitives without it get normal groups only).
    #[default]
    Painted,
    /// Generated along an axis for every triangle primitive (COLOR_0 is not read).
    Generate(GeneratedComb),
}

/// A generated comb: the axis projected on the surface and smoothed (see
/// `pelt_geom::flow`), at one length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeneratedComb {
    /// Object-space direction the fur flows toward (glTF axes: +Y up, +Z front).
    pub axis: [f32; 3],
    /// Comb length (the painted alpha): 0 to 1 of the fur's length.
    pub length: f32,
    /// Smoothing steps over the welded mesh.
    pub smoothing: u32,
    /// Scale the length by a channel of one of the primitive's material textures.
    pub length_texture: Option<LengthTexture>,
}

/// A comb length read from a texture: `length × channel` at each vertex's UV.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LengthTexture {
    /// Which of the material's textures.
    pub slot: pelt_io::picture::Slot,
    /// Channel 0-3 (r, g, b, a), its stored 8-bit value over 255.
    pub channel: u8,
}

impl GeneratedComb {
    /// Default axis: toward the back (−Z in glTF axes), so fur lies from head to tail.
    pub const DEFAULT_AXIS: [f32; 3] = [0.0, 0.0, -1.0];
    /// Default smoothing steps.
    pub const DEFAULT_SMOOTHING: u32 = 8;
}

impl Default for GeneratedComb {
    fn default() -> Self {
        GeneratedComb {
            axis: Self::DEFAULT_AXIS,
            length: 1.0,
            smoothing: Self::DEFAULT_SMOOTHING,
            length_texture: None,
        }
    }
}

/// Error parsing a [`CombSource`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "invalid comb {0:?}: expected painted, generate, or generate:AXIS with AXIS one of x, y, z \
     (optionally negated, e.g. -z) or three numbers (e.g. 0,-0.5,-1)"
)]
pub struct CombSourceError(String);

/// Parses an axis: `x`, `-y`, `+z`, or three comma-separated numbers (not all zero).
pub fn parse_axis(s: &str) -> Option<[f32; 3]> {
    let t = s.trim();
    let (sign, name) = match t.strip_prefix('-') {
        Some(n) => (-1.0, n),
        None => (1.0, t.strip_prefix('+').unwrap_or(t)),
    };
    let named = match name.to_ascii_lowercase().as_str() {
        "x" => Some([sign, 0.0, 0.0]),
        "y" => Some([0.0, sign, 0.0]),
        "z" => Some([0.0, 0.0, sign]),
        _ => None,
    };
    if named.is_some() {
        return named;
    }
    let v: Vec<f32> = t
        .split(',')
        .map(|x| x.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .ok()?;
    let v: [f32; 3] = v.try_into().ok()?;
    let len = v.iter().map(|x| x * x).sum::<f32>().sqrt();
    (len.is_finite() && len > 0.0).then(|| v.map(|x| x / len))
}

impl FromStr for CombSource {
    type Err = CombSourceError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let err = || CombSourceError(s.to_owned());
        match s.split_once(':') {
            None if s == "painted" => Ok(CombSource::Painted),
            None if s == "generate" => Ok(CombSource::Generate(GeneratedComb::default())),
            Some(("generate", axis)) => Ok(CombSource::Generate(GeneratedComb {
                axis: parse_axis(axis).ok_or_else(err)?,
                ..GeneratedComb::default()
            })),
            _ => Err(err()),
        }
    }
}

impl fmt::Display for CombSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CombSource::Painted => write!(f, "painted"),
            CombSource::Generate(g) => {
                let [x, y, z] = g.axis;
                write!(f, "generate:{x},{y},{z}")
            }
        }
    }
}

/// Default crease angle (degrees) of the smooth normals made for meshes without NORMAL.
pub const DEFAULT_CREASE_ANGLE_DEG: f32 = 60.0;

/// Everything a bake can be told.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BakeOptions {
    /// Keep or regenerate tangents.
    pub tangents: TangentMode,
    /// Which generator makes generated tangents.
    pub tangent_generator: TangentGenerator,
    /// How COLOR_0 holds the direction.
    pub color_space: ColorSpace,
    /// Axis remap applied to the decoded direction (for Z-up sources).
    pub axes: AxisMap,
    /// Storage of `_FUR_COMB`.
    pub quantize: Quantize,
    /// How the output is packed.
    pub compress: Compression,
    /// Welding and the normal-group rule.
    pub topology: TopologyOptions,
    /// How much topology to write.
    pub topology_mode: TopologyMode,
    /// Where the comb comes from.
    pub comb: CombSource,
    /// Crease angle (radians) of the smooth normals made for meshes without NORMAL: faces
    /// whose normals differ by more stay apart (0 gives flat normals, as glTF clients would).
    pub crease_angle: f32,
}

impl Default for BakeOptions {
    fn default() -> Self {
        BakeOptions {
            tangents: TangentMode::default(),
            tangent_generator: TangentGenerator::default(),
            color_space: ColorSpace::default(),
            axes: AxisMap::default(),
            quantize: Quantize::default(),
            compress: Compression::default(),
            topology: TopologyOptions::default(),
            topology_mode: TopologyMode::default(),
            comb: CombSource::default(),
            crease_angle: DEFAULT_CREASE_ANGLE_DEG.to_radians(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn option_names_round_trip_and_a_bad_one_lists_the_rest() {
        for n in Quantize::NAMES {
            assert_eq!(n.parse::<Quantize>().expect("a listed name").name(), *n);
        }
        assert_eq!(TopologyMode::Groups.to_string(), "groups");
        assert_eq!("srgb".parse::<ColorSpace>(), Ok(ColorSpace::Srgb));
        let e = "mikk".parse::<TangentGenerator>().unwrap_err().to_string();
        assert_eq!(e, "\"mikk\" is not one of auto, mikktspace, gradient");
    }

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

    #[test]
    fn comb_sources_parse() {
        assert_eq!("painted".parse(), Ok(CombSource::Painted));
        let CombSource::Generate(g) = "generate".parse().unwrap() else {
            panic!("generate")
        };
        assert_eq!(g.axis, [0.0, 0.0, -1.0]);
        let CombSource::Generate(g) = "generate:+y".parse().unwrap() else {
            panic!("generate:+y")
        };
        assert_eq!(g.axis, [0.0, 1.0, 0.0]);
        let CombSource::Generate(g) = "generate:0,-3,4".parse().unwrap() else {
            panic!("numbers")
        };
        assert_eq!(g.axis, [0.0, -0.6, 0.8]);
        assert_eq!(
            "generate:0,-3,4".parse::<CombSource>().unwrap().to_string(),
            "generate:0,-0.6,0.8"
        );
        for bad in [
            "generate:",
            "generate:w",
            "generate:0,0,0",
            "generate:1,2",
            "paint",
            "",
        ] {
            assert!(bad.parse::<CombSource>().is_err(), "{bad}");
        }
    }
}
