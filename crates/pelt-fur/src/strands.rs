//! The strand model: seeded strand roots on the tileable unit square, each a (possibly leaning)
//! cylinder of its own radius and height. Every texture pelt makes (dots, heightfield, fin
//! texture) is a view of this one set, so they agree with each other, as Lengyel et al.'s shell
//! and fin textures do when both are rendered from one geometric hair model.

use rayon::prelude::*;

use crate::params::StrandParams;
use crate::rng::SplitMix64;

/// One strand. Positions are in tile widths on the unit torus; heights are fractions of the
/// fur length. At height z the strand's horizontal cross-section is the disc of radius `r`
/// centred at (x + z·tx, y + z·ty), for 0 ≤ z ≤ h.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strand {
    /// Root, x (in [0, 1)).
    pub x: f64,
    /// Root, y (in [0, 1)).
    pub y: f64,
    /// Radius.
    pub r: f64,
    /// Height.
    pub h: f64,
    /// Lean in x per unit height.
    pub tx: f64,
    /// Lean in y per unit height.
    pub ty: f64,
    /// A per-strand random value in [0, 1) (the fin texture's tint channel).
    pub tint: f64,
}

/// Stream index of clump centre `c` (strand streams use the indices from 0 up).
fn clump_stream(c: u32) -> u64 {
    u64::MAX - u64::from(c)
}

/// The clump centres of `p` (empty without clumping).
pub fn centres(p: &StrandParams) -> Vec<(f64, f64)> {
    (0..p.clumps)
        .map(|c| {
            let mut s = SplitMix64::stream(p.seed, clump_stream(c));
            (s.unit(), s.unit())
        })
        .collect()
}

/// Generates the strands of `p` (assumed valid). Strand `i` depends only on the seed, `i`
/// and the parameters, so the result is the same at any thread count.
pub fn generate(p: &StrandParams) -> Vec<Strand> {
    let centres = centres(p);
    (0..p.strands)
        .into_par_iter()
        .map(|i| nth(p, &centres, i))
        .collect()
}

/// Strand `i` of `p`, given the model's clump [`centres`].
pub fn nth(p: &StrandParams, centres: &[(f64, f64)], i: u32) -> Strand {
    let span = p.height_max - p.height_min;
    let mut s = SplitMix64::stream(p.seed, u64::from(i));
    // A fixed number of draws per strand, whatever the options, so that turning
    // clumping or tilt on leaves radii and heights where they were.
    let member = s.unit();
    let clump = if centres.is_empty() {
        s.next_u64();
        0
    } else {
        s.below(p.clumps)
    };
    let (u, v) = (s.unit(), s.unit());
    let ur = s.unit();
    let uh = s.unit();
    let (ut, ua) = (s.unit(), s.unit());
    let tint = s.unit();
    let (x, y) = if member < p.clumping && !centres.is_empty() {
        // Box-Muller on (u, v): a normal offset around the clump centre.
        let rr = (-2.0 * (1.0 - u).ln()).sqrt() * p.clump_radius;
        let a = std::f64::consts::TAU * v;
        let (cx, cy) = centres[clump as usize];
        (wrap_unit(cx + rr * a.cos()), wrap_unit(cy + rr * a.sin()))
    } else {
        (u, v)
    };
    let r = p.radius * (1.0 + p.radius_jitter * (2.0 * ur - 1.0));
    let h = p.height_min + span * uh.powf(p.height_bias);
    let lean = p.tilt * p.radius * ut;
    let a = std::f64::consts::TAU * ua;
    Strand {
        x,
        y,
        r,
        h,
        tx: lean * a.cos(),
        ty: lean * a.sin(),
        tint,
    }
}

/// `v` wrapped into [0, 1).
pub fn wrap_unit(v: f64) -> f64 {
    let w = v - v.floor();
    if w >= 1.0 { 0.0 } else { w }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strands_depend_on_seed_and_index_only() {
        let p = StrandParams {
            strands: 1000,
            ..StrandParams::default()
        };
        let a = generate(&p);
        let more = generate(&StrandParams {
            strands: 2000,
            ..p.clone()
        });
        assert_eq!(a[..], more[..1000]);
        let other = generate(&StrandParams {
            seed: 2,
            ..p.clone()
        });
        assert_ne!(a, other);
        let tilted = generate(&StrandParams { tilt: 2.0, ..p });
        assert!(a.iter().zip(&tilted).all(|(s, t)| s.h == t.h && s.x == t.x));
        assert!(tilted.iter().any(|t| t.tx != 0.0));
    }

    #[test]
    fn strands_respect_their_ranges() {
        let p = StrandParams {
            strands: 5000,
            tilt: 3.0,
            clumps: 10,
            clumping: 0.5,
            ..StrandParams::default()
        };
        for s in generate(&p) {
            assert!((0.0..1.0).contains(&s.x) && (0.0..1.0).contains(&s.y));
            assert!(s.r >= p.radius * 0.7 - 1e-12 && s.r <= p.radius * 1.3 + 1e-12);
            assert!(s.h >= p.height_min && s.h <= p.height_max);
            assert!(s.tx.hypot(s.ty) <= p.tilt * p.radius + 1e-12);
        }
    }
}
