//! A fur object's explicit strands as the ray tracer builds them ([`StrandSet`]): the strand
//! reference's strands ([`pelt_scene::strands`]) along the shells' path (Revie Listing 2.1) as
//! strands.wgsl builds them, bent by the frame's wind ([`pelt_scene::wind::bend`], the CPU twin
//! of `wind_comb`), their sample points (the segments' ends) and their capsules
//! ([`capsules_of`]), which the strands' shadow rays ([`crate::strands`]) and the traced fur
//! ([`crate::fur`]) both meet.

use glam::{Mat4, Vec3};

use pelt_scene::vertex::StrandRoot;
use pelt_scene::wind::{self, WindOn};

use crate::capsules::Capsule;

/// Segments per strand (strands.wgsl's `SEGMENTS`); samples are their ends.
pub const SEGMENTS: usize = 4;

/// One fur object's strands as drawn: object to world, fur length (asset units), roots.
#[derive(Debug, Clone, Copy)]
pub struct StrandSet<'a> {
    /// Object to world.
    pub model: Mat4,
    /// The fur length in the asset's units (the planned fur's).
    pub length: f32,
    /// The planted strands.
    pub roots: &'a [StrandRoot],
    /// The frame's wind constants (`pelt_scene::wind::constants`; all zero: none).
    pub wind: ([f32; 4], [f32; 4]),
}

impl StrandSet<'_> {
    /// The wind on these strands (what [`StrandSet::points`] bends them by).
    pub fn wind_on(&self) -> WindOn {
        WindOn::new(self.wind, self.model, self.length)
    }

    /// `N` points of strand `s` in world space, evenly spaced from root to tip, as
    /// strands.wgsl draws it: its comb bent by the wind `on` ([`StrandSet::wind_on`]).
    pub fn points<const N: usize>(&self, on: &WindOn, s: &StrandRoot) -> [Vec3; N] {
        let root = Vec3::from_slice(&s.root[..3]);
        let n = Vec3::from_slice(&s.normal[..3]);
        let comb = wind::bend(Vec3::from_slice(&s.comb[..3]), n, root, on);
        let lean = Vec3::from_slice(&s.lean[..3]);
        let reach = self.length * s.normal[3];
        let last = N.saturating_sub(1).max(1) as f32;
        std::array::from_fn(|k| {
            let z = s.root[3] * k as f32 / last;
            let dir = (n.normalize_or_zero() + comb * z).normalize_or_zero();
            self.model
                .transform_point3(root + lean * z + dir * (z * reach))
        })
    }
}

/// A strand's sample points in world space, root to tip (its segments' ends), and its
/// world radius.
pub fn samples(set: &StrandSet<'_>, on: &WindOn, s: &StrandRoot) -> ([Vec3; SEGMENTS + 1], f32) {
    let points = set.points(on, s);
    let m = set.model;
    let scale = (m.x_axis.truncate().length()
        + m.y_axis.truncate().length()
        + m.z_axis.truncate().length())
        / 3.0;
    (points, s.comb[3] * scale)
}

/// Every strand of `sets` as capsules: strands numbered from 0 through the sets in order,
/// each capsule's id its segment (strand × [`SEGMENTS`] + k). A segment of no length or a
/// strand of no radius has none.
pub fn capsules_of(sets: &[StrandSet<'_>]) -> Vec<Capsule> {
    let mut capsules = Vec::new();
    let mut strand = 0u32;
    for set in sets {
        let on = set.wind_on();
        for s in set.roots {
            let (p, r) = samples(set, &on, s);
            for k in 0..SEGMENTS {
                if p[k] != p[k + 1] && r > 0.0 {
                    capsules.push(Capsule {
                        a: p[k],
                        b: p[k + 1],
                        r,
                        strand,
                        id: strand * SEGMENTS as u32 + k as u32,
                    });
                }
            }
            strand += 1;
        }
    }
    capsules
}
