//! The strand model as a medium: how much of a view ray the strands hide, where a pixel holds
//! many strands and the shells cannot resolve them one by one.
//!
//! A strand of radius r seen at an angle ψ from its direction hides a band 2r·sin ψ wide
//! along its length, and its round tip a disc of area π r². With ρ(z) strands per unit area
//! taller than height z, a ray crossing the layer between heights z₀ and z₁ at |cos θ| = μ
//! from the normal meets (Beer–Lambert) an optical depth
//!
//! Δτ = [ Σ_{h>z} 2r · sin ψ · ℓ(z₀, z₁)  +  Σ_{z₀<h≤z₁} π r² ] / (area · μ),
//!
//! ℓ being the length of strand between the two heights. On the tile both sums are
//! proportional to the tips' area π r² (radius and height are independent), so one quantity,
//! the **top-view area fraction of strands taller than z**, `T(z) = Σ_{h>z} π r² / area`,
//! carries both: the tips give T(z₀) − T(z₁), the sides κ·T(z)·sin ψ·ℓ with κ = Σ 2r / Σ π r²
//! (per tile width). [`Density`] stores T at [`BINS`] heights per texel, splatted from the
//! same strands the heightfield is rendered from, with box-filtered mips: T is an area
//! fraction, so the mean over a footprint is exactly the footprint's T, at every level. The
//! shells (shaders/shells.wgsl) sample it at the pixel's footprint and turn Δτ into the
//! opacity 1 − e^(−Δτ) of the layer each shell stands for.

use crate::mips::level_size;
use crate::params::StrandParams;
use crate::strands::Strand;

/// Heights at which T is stored: z_k = k / BINS, k = 0..BINS (T(1) = 0: no strand is taller
/// than the fur length).
pub const BINS: usize = 8;

/// The strand model's medium statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct Density {
    /// Side of level 0 in texels (a power of two).
    pub side: u32,
    /// Levels, level 0 first, down to 1 × 1: per texel, T(z_k) for k = 0..BINS.
    pub levels: Vec<Vec<[f32; BINS]>>,
    /// κ = Σ 2r / Σ π r², per tile width: side area per unit length over tip area.
    pub kappa: f64,
    /// Mean strand diameter, tile widths: below it a pixel resolves single strands.
    pub diameter: f64,
}

/// The side of the density texture for `strands` strands per tile: about one strand per
/// texel (a finer level would only be used where the shells resolve strands from the
/// heightfield), between 4 and `max`.
pub fn side_for(strands: u32, max: u32) -> u32 {
    let s = f64::from(strands).sqrt().ceil() as u32;
    s.next_power_of_two().clamp(4, max.max(4))
}

/// Most strands the statistics are gathered from; a larger model is sampled evenly (every
/// k-th strand, weighted k): its strands are independent draws, so the estimate is unbiased.
pub const MAX_SAMPLED: u32 = 1 << 20;

/// The medium statistics of the model `p` (assumed valid), at level-0 side `side`. Each
/// strand's tip area π r² is splatted bilinearly (wrapping) around its root into every bin
/// below its height. One thread, strand order: the same result at any thread count.
pub fn density(p: &StrandParams, side: u32) -> Density {
    let centres = crate::strands::centres(p);
    let stride = p.strands.div_ceil(MAX_SAMPLED).max(1);
    let sampled = (0..p.strands)
        .step_by(stride as usize)
        .map(|i| crate::strands::nth(p, &centres, i));
    splat(sampled, f64::from(stride), side)
}

/// [`density`] of the given strands, each counted `weight` times.
fn splat(strands: impl Iterator<Item = Strand>, weight: f64, side: u32) -> Density {
    let n = side as usize;
    let texel_area = 1.0 / (n * n) as f64;
    let mut level0 = vec![[0.0f64; BINS]; n * n];
    let (mut sum_2r, mut sum_area, mut count) = (0.0, 0.0, 0.0);
    for s in strands {
        let a = std::f64::consts::PI * s.r * s.r * weight;
        sum_2r += 2.0 * s.r * weight;
        sum_area += a;
        count += weight;
        let bins = ((s.h * BINS as f64).ceil() as usize).min(BINS);
        let fx = s.x * n as f64 - 0.5;
        let fy = s.y * n as f64 - 0.5;
        let (x0, y0) = (fx.floor(), fy.floor());
        let (wx, wy) = (fx - x0, fy - y0);
        let x0 = x0 as i64;
        let y0 = y0 as i64;
        for (dy, wy) in [(0, 1.0 - wy), (1, wy)] {
            for (dx, wx) in [(0, 1.0 - wx), (1, wx)] {
                let x = (x0 + dx).rem_euclid(n as i64) as usize;
                let y = (y0 + dy).rem_euclid(n as i64) as usize;
                let v = a * wx * wy / texel_area;
                for t in &mut level0[y * n + x][..bins] {
                    *t += v;
                }
            }
        }
    }
    let mut levels = vec![level0];
    for l in 1..=crate::mips::level_count(n, n) {
        let (pw, _) = level_size(n, n, l - 1);
        let (w, h) = level_size(n, n, l);
        let prev = &levels[l - 1];
        let next: Vec<[f64; BINS]> = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let mut t = [0.0; BINS];
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let c = &prev[(2 * y + dy) * pw + 2 * x + dx];
                    for k in 0..BINS {
                        t[k] += c[k] / 4.0;
                    }
                }
                t
            })
            .collect();
        levels.push(next);
    }
    Density {
        side,
        levels: levels
            .into_iter()
            .map(|l| l.into_iter().map(|t| t.map(|v| v as f32)).collect())
            .collect(),
        kappa: if sum_area > 0.0 {
            sum_2r / sum_area
        } else {
            0.0
        },
        diameter: if count > 0.0 { sum_2r / count } else { 0.0 },
    }
}

/// T at height `z` from the stored bins (linear between them, 0 at z = 1), as the shells
/// read it.
pub fn t_at(bins: &[f32; BINS], z: f64) -> f64 {
    let x = z.clamp(0.0, 1.0) * BINS as f64;
    let k = (x.floor() as usize).min(BINS - 1);
    let f = x - k as f64;
    let lo = f64::from(bins[k]);
    let hi = if k + 1 < BINS {
        f64::from(bins[k + 1])
    } else {
        0.0
    };
    lo + (hi - lo) * f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strands::generate;

    #[test]
    fn the_whole_tile_holds_every_strands_tip_area() {
        let p = StrandParams {
            strands: 4000,
            ..StrandParams::default()
        };
        let strands = generate(&p);
        let d = density(&p, 64);
        let last = d.levels.last().expect("a 1 × 1 level");
        assert_eq!(last.len(), 1);
        let area: f64 = strands
            .iter()
            .map(|s| std::f64::consts::PI * s.r * s.r)
            .sum();
        assert!((f64::from(last[0][0]) - area).abs() < 1e-4 * area);
        // Bin k holds the strands taller than k / BINS.
        for (k, got) in last[0].iter().enumerate() {
            let z = k as f64 / BINS as f64;
            let want: f64 = strands
                .iter()
                .filter(|s| s.h > z)
                .map(|s| std::f64::consts::PI * s.r * s.r)
                .sum();
            assert!(
                (f64::from(*got) - want).abs() < 1e-4 * area,
                "bin {k}: {} vs {want}",
                last[0][k]
            );
        }
        // Every level keeps the mean.
        for l in &d.levels {
            let mean: f64 = l.iter().map(|t| f64::from(t[0])).sum::<f64>() / l.len() as f64;
            assert!((mean - area).abs() < 1e-4 * area, "{mean} vs {area}");
        }
        let kappa_want = strands.iter().map(|s| 2.0 * s.r).sum::<f64>() / area;
        assert!((d.kappa - kappa_want).abs() < 1e-9 * kappa_want);
    }

    #[test]
    fn a_huge_model_is_sampled_without_bias() {
        let p = StrandParams {
            strands: 3 * MAX_SAMPLED,
            radius: 0.0002,
            ..StrandParams::default()
        };
        let d = density(&p, 16);
        // E[π r²] N with r = r̄ (1 + j (2u − 1)): π r̄² (1 + j²/3) N.
        let want =
            std::f64::consts::PI * p.radius * p.radius * (1.0 + 0.09 / 3.0) * f64::from(p.strands);
        let got = f64::from(d.levels.last().expect("levels")[0][0]);
        assert!((got - want).abs() < 0.01 * want, "{got} vs {want}");
        assert!(
            (d.diameter - 2.0 * p.radius).abs() < 0.01 * p.radius,
            "{} vs {}",
            d.diameter,
            2.0 * p.radius
        );
    }

    #[test]
    fn bins_interpolate_and_vanish_at_the_top() {
        let bins = [1.0, 1.0, 1.0, 1.0, 0.8, 0.6, 0.4, 0.2];
        assert_eq!(t_at(&bins, 0.0), 1.0);
        assert!((t_at(&bins, 0.5625) - 0.7).abs() < 1e-6);
        assert!((t_at(&bins, 0.9375) - 0.1).abs() < 1e-6);
        assert_eq!(t_at(&bins, 1.0), 0.0);
        assert_eq!(t_at(&bins, 7.0), 0.0);
    }

    #[test]
    fn side_is_about_one_strand_per_texel() {
        assert_eq!(side_for(12_000, 1024), 128);
        assert_eq!(side_for(1, 1024), 4);
        assert_eq!(side_for(50_000_000, 512), 512);
    }
}
