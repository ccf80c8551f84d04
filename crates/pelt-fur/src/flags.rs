//! The strand model's parameters as `pelt textures` flags: with the `cli` feature,
//! [`StrandFlags`] is clap's `Args`; each flag overrides one [`StrandParams`] field (a
//! config's `fur.textures` value or the default), and [`StrandFlags::apply`] sets them.

use crate::params::{HeightBits, StrandParams};

/// Overrides of the strand model; `None` keeps the config's value.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct StrandFlags {
    /// Seed of the strand generator.
    #[cfg_attr(feature = "cli", arg(long))]
    pub seed: Option<u64>,
    /// Texture side in texels (a power of two, 4 to 16384).
    #[cfg_attr(feature = "cli", arg(long))]
    pub size: Option<u32>,
    /// Fin texture height in texels (a power of two up to --size; default size/4).
    #[cfg_attr(feature = "cli", arg(long))]
    pub fin_height: Option<u32>,
    /// Strands per tile.
    #[cfg_attr(feature = "cli", arg(long))]
    pub strands: Option<u32>,
    /// Mean strand radius in tile widths.
    #[cfg_attr(feature = "cli", arg(long))]
    pub radius: Option<f64>,
    /// Radius jitter in [0, 1).
    #[cfg_attr(feature = "cli", arg(long))]
    pub radius_jitter: Option<f64>,
    /// Shortest strand, as a fraction of the fur length.
    #[cfg_attr(feature = "cli", arg(long))]
    pub height_min: Option<f64>,
    /// Longest strand, as a fraction of the fur length.
    #[cfg_attr(feature = "cli", arg(long))]
    pub height_max: Option<f64>,
    /// Height distribution exponent: 1 uniform, above 1 more short strands.
    #[cfg_attr(feature = "cli", arg(long))]
    pub height_bias: Option<f64>,
    /// Lean: tips displaced by up to this many radii per unit height.
    #[cfg_attr(feature = "cli", arg(long))]
    pub tilt: Option<f64>,
    /// Number of clump centres.
    #[cfg_attr(feature = "cli", arg(long))]
    pub clumps: Option<u32>,
    /// Fraction of strands in clumps (0 to 1).
    #[cfg_attr(feature = "cli", arg(long))]
    pub clumping: Option<f64>,
    /// Clump spread (standard deviation, tile widths).
    #[cfg_attr(feature = "cli", arg(long))]
    pub clump_radius: Option<f64>,
    /// Thickness of the slab the fin texture shows, in tile widths.
    #[cfg_attr(feature = "cli", arg(long))]
    pub fin_depth: Option<f64>,
    /// Heightfield bits: 16 or 8.
    #[cfg_attr(feature = "cli", arg(long, value_parser = parse_bits))]
    pub height_bits: Option<HeightBits>,
    /// Skip the mip chains.
    #[cfg_attr(feature = "cli", arg(long))]
    pub no_mips: bool,
}

impl StrandFlags {
    /// Sets the fields these flags give (the ranges are [`crate::FurConfig::validate`]'s).
    pub fn apply(&self, t: &mut StrandParams) {
        macro_rules! set {
            ($($field:ident),*) => { $( if let Some(v) = self.$field { t.$field = v; } )* };
        }
        set!(
            seed,
            size,
            fin_height,
            strands,
            radius,
            radius_jitter,
            height_min,
            height_max,
            height_bias,
            tilt,
            clumps,
            clumping,
            clump_radius,
            fin_depth,
            height_bits
        );
        if self.no_mips {
            t.mips = false;
        }
    }
}

/// `8` or `16`. A clap value parser: its error is clap's message, so a `String`.
#[cfg(feature = "cli")]
fn parse_bits(s: &str) -> Result<HeightBits, String> {
    s.parse::<u8>()
        .ok()
        .and_then(|bits| HeightBits::try_from(bits).ok())
        .ok_or_else(|| format!("{s:?} is not 8 or 16"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_set_what_they_give_and_keep_the_rest() {
        let base = StrandParams::default();
        let mut t = base.clone();
        StrandFlags::default().apply(&mut t);
        assert_eq!(t, base);
        let flags = StrandFlags {
            seed: Some(base.seed + 1),
            tilt: Some(3.0),
            height_bits: Some(HeightBits::Eight),
            no_mips: true,
            ..Default::default()
        };
        flags.apply(&mut t);
        assert_eq!(
            (t.seed, t.tilt, t.height_bits, t.mips),
            (base.seed + 1, 3.0, HeightBits::Eight, false)
        );
        assert_eq!((t.size, t.strands), (base.size, base.strands));
    }

    #[cfg(feature = "cli")]
    #[test]
    fn the_flags_parse() {
        use clap::Parser as _;
        #[derive(clap::Parser)]
        struct Cli {
            #[command(flatten)]
            flags: StrandFlags,
        }
        let parse = |a: &[&str]| Cli::try_parse_from([&["pelt"], a].concat()).map(|c| c.flags);
        let f = parse(&["--height-bits", "8", "--clumps", "400"]).expect("valid");
        assert_eq!(
            (f.height_bits, f.clumps),
            (Some(HeightBits::Eight), Some(400))
        );
        assert!(parse(&["--height-bits", "12"]).is_err());
        assert!(parse(&["--strands", "-3"]).is_err());
    }
}
