//! What the strand model should give, analytically: the expected coverage of a shell at height
//! h, of the dot texture and of a fin-texture row, for the density, radius and height
//! distribution of [`StrandParams`]. The tests compare measured textures against these.
//!
//! With N strands placed independently and uniformly on the unit torus, a point is bare with
//! probability (1 − E[a])^N, where a is the area one strand covers. Seen from above, a strand
//! reaches above height h over the capsule swept by its cross-sections between h and its
//! height h_i: area π r² + 2 r |t| (h_i − h) when h_i > h, and 0 otherwise (r its radius, t its
//! lean per unit height). Radius, height and lean are independent, so
//! E[a(h)] = π E[r²] P(h_i > h) + 2 E[r] E[|t|] E[(h_i − h)⁺], with r = r̄(1 + j(2u − 1)):
//! E[r] = r̄, E[r²] = r̄²(1 + j²/3); |t| = tilt·r̄·u: E[|t|] = tilt·r̄/2; and h_i = min + (max −
//! min)·u^b: P(h_i > h) = 1 − x^(1/b) with x = (h − min)/(max − min).
//!
//! Clumped strands are not independent, so these hold only with `clumping` = 0.

use crate::params::StrandParams;

fn span(p: &StrandParams) -> f64 {
    p.height_max - p.height_min
}

/// P(h_i > h): the fraction of strands taller than `h`.
pub fn taller(p: &StrandParams, h: f64) -> f64 {
    let x = (h - p.height_min) / span(p);
    if x < 0.0 {
        1.0
    } else if x >= 1.0 {
        0.0
    } else {
        1.0 - x.powf(1.0 / p.height_bias)
    }
}

/// E[(h_i − h)⁺].
pub fn excess(p: &StrandParams, h: f64) -> f64 {
    let x = (h - p.height_min) / span(p);
    let k = 1.0 / p.height_bias;
    if x < 0.0 {
        p.height_min + span(p) / (p.height_bias + 1.0) - h
    } else if x >= 1.0 {
        0.0
    } else {
        // ∫_x^1 (1 − y^k) dy, in units of the span.
        span(p) * ((1.0 - x) - (1.0 - x.powf(k + 1.0)) / (k + 1.0))
    }
}

/// E[a(h)]: the expected area one strand covers above height `h` (tile widths²).
pub fn strand_area(p: &StrandParams, h: f64) -> f64 {
    let r2 = p.radius * p.radius * (1.0 + p.radius_jitter * p.radius_jitter / 3.0);
    let lean = p.tilt * p.radius / 2.0;
    std::f64::consts::PI * r2 * taller(p, h) + 2.0 * p.radius * lean * excess(p, h)
}

/// Expected fraction of the tile where the heightfield exceeds `h` (what shell h shows).
pub fn shell_coverage(p: &StrandParams, h: f64) -> f64 {
    1.0 - (1.0 - strand_area(p, h)).powf(f64::from(p.strands))
}

/// Expected mean alpha of the dot texture (the whole strands seen from above).
pub fn dot_coverage(p: &StrandParams) -> f64 {
    shell_coverage(p, 0.0)
}

/// Expected coverage of the fin texture at height `h`: a strand is in the slab with
/// probability `fin_depth`, and then covers a band 2r wide if it is taller than h.
pub fn fin_coverage(p: &StrandParams, h: f64) -> f64 {
    1.0 - (1.0 - p.fin_depth * 2.0 * p.radius * taller(p, h)).powf(f64::from(p.strands))
}

/// Inverse of [`fin_coverage`] and [`shell_coverage`] for upright strands: the fraction of
/// strands taller than h implied by a measured coverage, given the area one strand covers.
pub fn implied_taller(coverage: f64, strands: f64, area_per_strand: f64) -> f64 {
    (1.0 - (1.0 - coverage).powf(1.0 / strands)) / area_per_strand
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distribution_edges() {
        let p = StrandParams {
            height_min: 0.2,
            height_max: 0.8,
            height_bias: 2.0,
            ..StrandParams::default()
        };
        assert_eq!(taller(&p, 0.1), 1.0);
        assert_eq!(taller(&p, 0.8), 0.0);
        // u^2 > x ⇔ u > √x: at x = 1/4, 1/2 of strands.
        assert!((taller(&p, 0.2 + 0.6 * 0.25) - 0.5).abs() < 1e-12);
        // E[h] = min + span / (b + 1) = 0.2 + 0.6 / 3.
        assert!((excess(&p, 0.0) - 0.4).abs() < 1e-12);
        // Continuous at height_min.
        assert!((excess(&p, 0.2 - 1e-9) - excess(&p, 0.2 + 1e-9)).abs() < 1e-6);
        // Numerical integral of P(h_i > y) from 0.5 to 1.
        let steps = 100_000;
        let num: f64 = (0..steps)
            .map(|i| taller(&p, 0.5 + (i as f64 + 0.5) * 0.5 / steps as f64) * 0.5 / steps as f64)
            .sum();
        assert!(
            (excess(&p, 0.5) - num).abs() < 1e-6,
            "{} {num}",
            excess(&p, 0.5)
        );
    }
}
