//! The bake's choices as `pelt bake` flags: with the `cli` feature, [`Flags`] is clap's
//! `Args` (each flag's name, values and help written here once, next to the options they
//! set), and [`Flags::options`] merges them with a bake config into [`BakeOptions`] (a flag
//! wins over the config's `comb.source` and `normals.creaseAngle`).

use crate::config::BakeConfig;
use crate::options::{
    AxisMap, BakeOptions, ColorSpace, CombSource, Compression, DEFAULT_CREASE_ANGLE_DEG, Quantize,
    TangentGenerator, TangentMode, TopologyMode, TopologyOptions,
};

/// The bake's flags (everything but inputs, outputs and the batch's own).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct Flags {
    /// Keep TANGENT where present, or always generate tangents.
    #[cfg_attr(feature = "cli", arg(long, default_value = "keep", value_parser = parse::named::<TangentMode>(TangentMode::NAMES)))]
    pub tangents: TangentMode,
    /// Which generator makes generated tangents: auto = MikkTSpace where the primitive's
    /// material has a normal texture, the one-pass UV-gradient frame elsewhere (the comb
    /// decodes the same in any stored frame; several times faster); mikktspace everywhere;
    /// gradient everywhere.
    #[cfg_attr(feature = "cli", arg(long, default_value = "auto", value_parser = parse::named::<TangentGenerator>(TangentGenerator::NAMES)))]
    pub tangent_generator: TangentGenerator,
    /// How COLOR_0 holds the painted direction: linear (glTF's definition) or srgb (8-bit
    /// sRGB paint that an exporter linearized, as Blender does with byte colors).
    #[cfg_attr(feature = "cli", arg(long, default_value = "linear", value_parser = parse::named::<ColorSpace>(ColorSpace::NAMES)))]
    pub comb_color_space: ColorSpace,
    /// Remap the comb's axes, e.g. x,z,-y for a comb painted in a Z-up tool.
    #[cfg_attr(feature = "cli", arg(long, default_value = "x,y,z"))]
    pub comb_axes: AxisMap,
    /// Storage of _FUR_COMB: float, or normalized u16 / u8.
    #[cfg_attr(feature = "cli", arg(long, default_value = "float", value_parser = parse::named::<Quantize>(Quantize::NAMES)))]
    pub quantize: Quantize,
    /// Pack the output for shipping: `--compress` (or `--compress meshopt`) quantizes
    /// positions, normals, tangents, UVs and colours and compresses every vertex, index and
    /// fin-record stream with EXT_meshopt_compression (a float comb is stored as u8);
    /// `none` writes plain data. Overrides the config's `compress`.
    #[cfg_attr(feature = "cli", arg(long, value_name = "FORMAT", num_args = 0..=1, default_missing_value = "meshopt", value_parser = parse::named::<Compression>(Compression::NAMES)))]
    pub compress: Option<Compression>,
    /// Topology to write: full (_NORMAL_GROUP and fin edges), groups (_NORMAL_GROUP only) or
    /// off (the comb bake alone, for engines that use neither).
    #[cfg_attr(feature = "cli", arg(long, default_value = "full", value_parser = parse::named::<TopologyMode>(TopologyMode::NAMES)))]
    pub topology: TopologyMode,
    /// Weld positions closer than this (in the mesh's units) for topology, for exports whose
    /// seams do not meet exactly. 0 welds bit-equal positions only.
    #[cfg_attr(feature = "cli", arg(long, value_name = "DIST", default_value_t = 0.0, value_parser = parse::non_negative))]
    pub weld_epsilon: f32,
    /// Normals at a shared edge that differ by at most this angle (degrees) keep the two faces
    /// in one normal group; larger differences are creases.
    #[cfg_attr(feature = "cli", arg(long, value_name = "DEG", default_value_t = pelt_geom::topology::DEFAULT_NORMAL_TOLERANCE_DEG, value_parser = parse::degrees))]
    pub normal_tolerance: f32,
    /// Where the comb comes from: painted (COLOR_0; primitives without it get normal groups
    /// only) or generate[:AXIS], fur flowing along an object-space axis projected on the
    /// surface (x, y, z with an optional sign, or three numbers; default -z, toward the back
    /// in glTF axes). Overrides the config's comb.source.
    #[cfg_attr(feature = "cli", arg(long, value_name = "SOURCE"))]
    pub comb: Option<CombSource>,
    /// Crease angle (degrees) of the smooth normals made for meshes without NORMAL: faces
    /// whose normals differ by more keep a hard edge; 0 gives flat normals, as glTF clients
    /// assume (default 60, or the config's normals.creaseAngle).
    #[cfg_attr(feature = "cli", arg(long, value_name = "DEG", value_parser = parse::degrees))]
    pub crease_angle: Option<f32>,
}

impl Default for Flags {
    fn default() -> Self {
        Flags {
            tangents: TangentMode::default(),
            tangent_generator: TangentGenerator::default(),
            comb_color_space: ColorSpace::default(),
            comb_axes: AxisMap::default(),
            quantize: Quantize::default(),
            compress: None,
            topology: TopologyMode::default(),
            weld_epsilon: 0.0,
            normal_tolerance: pelt_geom::topology::DEFAULT_NORMAL_TOLERANCE_DEG,
            comb: None,
            crease_angle: None,
        }
    }
}

/// A config's `comb` section that cannot be combined with the flags.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("comb.source: {0}")]
pub struct CombConfigError(#[source] crate::config::CombSectionError);

impl Flags {
    /// The bake options: these flags, with the config's comb and normals where no flag
    /// overrides them.
    pub fn options(&self, config: Option<&BakeConfig>) -> Result<BakeOptions, CombConfigError> {
        let comb_config = config.and_then(|c| c.comb.clone()).unwrap_or_default();
        let comb = comb_config.source(self.comb).map_err(CombConfigError)?;
        let crease_deg = self.crease_angle.unwrap_or_else(|| {
            config
                .and_then(|c| c.normals.as_ref())
                .map_or(DEFAULT_CREASE_ANGLE_DEG, |n| n.crease_angle)
        });
        Ok(BakeOptions {
            tangents: self.tangents,
            tangent_generator: self.tangent_generator,
            color_space: self.comb_color_space,
            axes: self.comb_axes,
            quantize: self.quantize,
            compress: self
                .compress
                .or_else(|| config.and_then(|c| c.compress))
                .unwrap_or_default(),
            topology_mode: self.topology,
            topology: TopologyOptions {
                weld_epsilon: self.weld_epsilon,
                normal_tolerance: self.normal_tolerance.to_radians(),
            },
            comb,
            crease_angle: crease_deg.to_radians(),
        })
    }
}

/// The flags' value parsers: the ranges and names the bake accepts.
#[cfg(feature = "cli")]
mod parse {
    use crate::options::NameError;

    /// A parser for an option named in `names` (the option's `NAMES`, one home for them).
    pub fn named<T>(
        names: &'static [&'static str],
    ) -> impl clap::builder::TypedValueParser<Value = T>
    where
        T: std::str::FromStr<Err = NameError> + Clone + Send + Sync + 'static,
    {
        use clap::builder::TypedValueParser as _;
        clap::builder::PossibleValuesParser::new(names).try_map(|s| s.parse::<T>())
    }

    /// A finite number ≥ 0.
    pub fn non_negative(s: &str) -> Result<f32, String> {
        match s.parse::<f32>() {
            Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
            _ => Err(format!("{s:?} is not a finite number >= 0")),
        }
    }

    /// An angle in degrees, 0 to 180.
    pub fn degrees(s: &str) -> Result<f32, String> {
        match s.parse::<f32>() {
            Ok(v) if (0.0..=180.0).contains(&v) => Ok(v),
            _ => Err(format!("{s:?} is not an angle from 0 to 180 degrees")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{CombConfig, NormalsConfig};

    #[test]
    fn flags_win_over_the_config_and_the_config_over_the_defaults() {
        let config = BakeConfig {
            comb: Some(CombConfig {
                source: "generate:x".into(),
                ..Default::default()
            }),
            normals: Some(NormalsConfig { crease_angle: 30.0 }),
            ..Default::default()
        };
        let plain = Flags::default().options(None).expect("defaults");
        assert_eq!(plain, BakeOptions::default());
        let from_config = Flags::default().options(Some(&config)).expect("config");
        assert!(matches!(from_config.comb, CombSource::Generate(g) if g.axis == [1.0, 0.0, 0.0]));
        assert!((from_config.crease_angle - 30f32.to_radians()).abs() < 1e-6);
        let flags = Flags {
            comb: Some(CombSource::Painted),
            crease_angle: Some(0.0),
            normal_tolerance: 90.0,
            ..Flags::default()
        };
        let o = flags.options(Some(&config)).expect("flags");
        assert_eq!((o.comb, o.crease_angle), (CombSource::Painted, 0.0));
        assert!((o.topology.normal_tolerance - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
        let bad = BakeConfig {
            comb: Some(CombConfig {
                source: "sideways".into(),
                ..Default::default()
            }),
            ..Default::default()
        };
        let e = Flags::default()
            .options(Some(&bad))
            .expect_err("bad source");
        assert!(e.to_string().starts_with("comb.source: "), "{e}");
    }

    #[cfg(feature = "cli")]
    #[test]
    fn the_flags_parse_the_option_names_and_ranges() {
        use clap::Parser as _;
        #[derive(clap::Parser)]
        struct Cli {
            #[command(flatten)]
            flags: Flags,
        }
        let parse = |a: &[&str]| Cli::try_parse_from([&["pelt"], a].concat()).map(|c| c.flags);
        assert_eq!(parse(&[]).expect("no flags"), Flags::default());
        let f = parse(&[
            "--quantize",
            "u8",
            "--comb-axes",
            "x,z,-y",
            "--crease-angle",
            "0",
        ])
        .expect("valid");
        assert_eq!((f.quantize, f.crease_angle), (Quantize::U8, Some(0.0)));
        for bad in [
            ["--quantize", "u4"],
            ["--crease-angle", "181"],
            ["--weld-epsilon", "-1"],
            ["--comb", "sideways"],
        ] {
            assert!(parse(&bad).is_err(), "{bad:?}");
        }
    }
}
