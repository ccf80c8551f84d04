//! The strand model's parameters, their defaults and their checks.
//!
//! Lengths on the tile are in tile widths (the tile is the unit square the textures cover, so
//! the same seed and parameters describe the same strands at every `size`); heights are
//! fractions of the fur length (0 = root, 1 = the longest fur the shells reach).

use serde::{Deserialize, Serialize};

use crate::error::ParamError;

/// Largest texture side pelt generates.
pub const MAX_SIZE: u32 = 16384;
/// Most strands in one tile.
pub const MAX_STRANDS: u32 = 50_000_000;

/// Bits per heightfield texel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(try_from = "u8", into = "u8")]
pub enum HeightBits {
    /// 8-bit gray PNG.
    Eight,
    /// 16-bit gray PNG (default).
    #[default]
    Sixteen,
}

impl TryFrom<u8> for HeightBits {
    type Error = String;
    fn try_from(v: u8) -> Result<Self, String> {
        match v {
            8 => Ok(HeightBits::Eight),
            16 => Ok(HeightBits::Sixteen),
            _ => Err(format!("heightBits must be 8 or 16, not {v}")),
        }
    }
}

impl From<HeightBits> for u8 {
    fn from(b: HeightBits) -> u8 {
        match b {
            HeightBits::Eight => 8,
            HeightBits::Sixteen => 16,
        }
    }
}

/// Everything that decides the strands and the textures made from them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct StrandParams {
    /// Seed of the strand generator.
    pub seed: u64,
    /// Side of the dot texture and heightfield in texels (a power of two, 4 to 16384); also the
    /// fin texture's width.
    pub size: u32,
    /// Height of the fin texture in texels (a power of two, at most `size`); 0 = `size / 4`.
    pub fin_height: u32,
    /// Strands per tile.
    pub strands: u32,
    /// Mean strand radius, in tile widths.
    pub radius: f64,
    /// Radius jitter in [0, 1): each radius is uniform in `radius · (1 ± jitter)`.
    pub radius_jitter: f64,
    /// Shortest strand (fraction of the fur length, 0 to 1).
    pub height_min: f64,
    /// Longest strand (fraction of the fur length, `height_min` to 1).
    pub height_max: f64,
    /// Height distribution: height = min + (max − min) · u^bias, u uniform in [0, 1). 1 is
    /// uniform, above 1 favours short strands, below 1 long ones.
    pub height_bias: f64,
    /// Lean: each strand's tip is displaced, in a random direction, by up to `tilt` mean
    /// radii per unit of height (uniformly between 0 and `tilt`). 0 = upright strands.
    pub tilt: f64,
    /// Number of clump centres (0 = no clumping).
    pub clumps: u32,
    /// Fraction of strands that belong to a clump (0 to 1).
    pub clumping: f64,
    /// Spread of a clump: standard deviation of a clumped root around its centre, in tile
    /// widths.
    pub clump_radius: f64,
    /// Thickness of the slab of strands the fin texture shows, in tile widths.
    pub fin_depth: f64,
    /// Bits per heightfield texel (16 or 8).
    pub height_bits: HeightBits,
    /// Generate the coverage-preserving mip chains.
    pub mips: bool,
}

impl Default for StrandParams {
    fn default() -> Self {
        StrandParams {
            seed: 1,
            size: 1024,
            fin_height: 0,
            strands: 12_000,
            radius: 0.0025,
            radius_jitter: 0.3,
            height_min: 0.4,
            height_max: 1.0,
            height_bias: 1.0,
            tilt: 0.0,
            clumps: 0,
            clumping: 0.0,
            clump_radius: 0.01,
            fin_depth: 0.02,
            height_bits: HeightBits::Sixteen,
            mips: true,
        }
    }
}

/// A [`ParamError`] for `field`.
fn bad(field: &str, why: String) -> Result<(), ParamError> {
    Err(ParamError {
        field: field.to_owned(),
        why,
    })
}

impl StrandParams {
    /// The fin texture's height in texels (`fin_height`, or `size / 4` when 0).
    pub fn fin_rows(&self) -> u32 {
        if self.fin_height == 0 {
            (self.size / 4).max(1)
        } else {
            self.fin_height
        }
    }

    /// Checks every parameter; the error names the first bad one.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.check_layout()?;
        self.check_finite()?;
        self.check_strand_shape()?;
        self.check_clumps()?;
        if !(self.fin_depth > 0.0 && self.fin_depth <= 1.0) {
            return bad(
                "finDepth",
                format!("must be above 0 and at most 1, got {}", self.fin_depth),
            );
        }
        Ok(())
    }

    /// The texture's layout: its size, the fin texture's rows, and the strand count.
    fn check_layout(&self) -> Result<(), ParamError> {
        if !self.size.is_power_of_two() || !(4..=MAX_SIZE).contains(&self.size) {
            return bad(
                "size",
                format!(
                    "must be a power of two from 4 to {MAX_SIZE} (textures tile and mip down to 1 texel), got {}",
                    self.size
                ),
            );
        }
        let fin = self.fin_rows();
        if !fin.is_power_of_two() || fin > self.size {
            return bad(
                "finHeight",
                format!(
                    "must be a power of two no larger than size ({}), got {fin}",
                    self.size
                ),
            );
        }
        if self.strands == 0 || self.strands > MAX_STRANDS {
            return bad(
                "strands",
                format!("must be 1 to {MAX_STRANDS}, got {}", self.strands),
            );
        }
        Ok(())
    }

    /// Every real-valued parameter is a finite number.
    fn check_finite(&self) -> Result<(), ParamError> {
        let finite = [
            ("radius", self.radius),
            ("radiusJitter", self.radius_jitter),
            ("heightMin", self.height_min),
            ("heightMax", self.height_max),
            ("heightBias", self.height_bias),
            ("tilt", self.tilt),
            ("clumping", self.clumping),
            ("clumpRadius", self.clump_radius),
            ("finDepth", self.fin_depth),
        ];
        if let Some((field, v)) = finite.iter().find(|(_, v)| !v.is_finite()) {
            return bad(field, format!("must be a finite number, got {v}"));
        }
        Ok(())
    }

    /// One strand's shape: radius, heights, tilt, and the footprint they make together.
    fn check_strand_shape(&self) -> Result<(), ParamError> {
        if !(self.radius > 0.0 && self.radius <= 0.1) {
            return bad(
                "radius",
                format!(
                    "must be above 0 and at most 0.1 tile widths, got {}",
                    self.radius
                ),
            );
        }
        if !(0.0..1.0).contains(&self.radius_jitter) {
            return bad(
                "radiusJitter",
                format!("must be in [0, 1), got {}", self.radius_jitter),
            );
        }
        if !(0.0..=1.0).contains(&self.height_min) || !(0.0..=1.0).contains(&self.height_max) {
            return bad(
                "heightMin",
                format!(
                    "heightMin and heightMax must be in [0, 1], got {} and {}",
                    self.height_min, self.height_max
                ),
            );
        }
        if self.height_max <= self.height_min {
            return bad(
                "heightMax",
                format!(
                    "must be above heightMin ({}), got {}",
                    self.height_min, self.height_max
                ),
            );
        }
        if !(self.height_bias > 0.0 && self.height_bias <= 100.0) {
            return bad(
                "heightBias",
                format!("must be above 0 and at most 100, got {}", self.height_bias),
            );
        }
        if !(0.0..=100.0).contains(&self.tilt) {
            return bad("tilt", format!("must be in [0, 100], got {}", self.tilt));
        }
        // The lean of the longest strand must stay well inside the tile, or a strand would
        // overlap its own wrapped copy.
        let lean = self.tilt * self.radius * self.height_max + 2.0 * self.radius * 2.0;
        if lean > 0.25 {
            return bad(
                "tilt",
                format!(
                    "a strand's footprint ({lean:.3} tile widths with this radius and tilt) must stay under 1/4 of the tile"
                ),
            );
        }
        Ok(())
    }

    /// The clumps: how strongly strands gather, how many clumps, and their radius.
    fn check_clumps(&self) -> Result<(), ParamError> {
        if !(0.0..=1.0).contains(&self.clumping) {
            return bad(
                "clumping",
                format!("must be in [0, 1], got {}", self.clumping),
            );
        }
        if self.clumping > 0.0 && self.clumps == 0 {
            return bad(
                "clumps",
                "must be at least 1 when clumping is above 0".into(),
            );
        }
        if self.clumps > self.strands {
            return bad(
                "clumps",
                format!(
                    "must be at most strands ({}), got {}",
                    self.strands, self.clumps
                ),
            );
        }
        if !(self.clump_radius > 0.0 && self.clump_radius <= 0.25) {
            return bad(
                "clumpRadius",
                format!(
                    "must be above 0 and at most 0.25, got {}",
                    self.clump_radius
                ),
            );
        }
        Ok(())
    }
}
