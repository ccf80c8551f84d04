//! Shadow rays for the strand reference: each explicit strand (`pelt render --mode strands`,
//! [`pelt_scene::strands`]) sampled at its segments' ends, a ray from each sample toward each
//! light that casts shadows, through every other strand (capsules of the strand's radius
//! about its segments, in a BVH of their boxes) and the scene's triangles ([`World::sees`]).
//! What reaches the light is one bit per sample and light, which the strands' fragments blend
//! linearly along each segment. The strands follow the shells' path (Revie Listing 2.1) as
//! strands.wgsl builds them, bent by the frame's wind as they are drawn
//! ([`pelt_scene::wind::bend`], the CPU twin of `wind_comb`), so a blown strand is shadowed
//! where it is blown to.

use glam::{Mat4, Vec3};
use glam34::Vec3A;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::builder::build_bvh2;
use obvhs::ray::Ray;
use rayon::prelude::*;

use pelt_scene::light::Source;
use pelt_scene::shading::Emitter;
use pelt_scene::vertex::StrandRoot;
use pelt_scene::wind::{self, WindOn};

use crate::World;

/// Segments per strand (strands.wgsl's `SEGMENTS`); samples are their ends.
pub const SEGMENTS: usize = 4;
/// Most lights a strand's bits hold (5 bits each in 64).
pub const MAX_LIGHTS: usize = 12;

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

/// A strand's sample points in world space, root to tip, and its world radius.
fn samples(set: &StrandSet<'_>, on: &WindOn, s: &StrandRoot) -> ([Vec3; SEGMENTS + 1], f32) {
    let points = set.points(on, s);
    let m = set.model;
    let scale = (m.x_axis.truncate().length()
        + m.y_axis.truncate().length()
        + m.z_axis.truncate().length())
        / 3.0;
    (points, s.comb[3] * scale)
}

/// A capsule: a segment and its radius, and which strand it belongs to.
#[derive(Debug, Clone, Copy)]
struct Capsule {
    a: Vec3,
    b: Vec3,
    r: f32,
    strand: u32,
}

fn a3(v: Vec3) -> Vec3A {
    Vec3A::new(v.x, v.y, v.z)
}

impl obvhs::Boundable for Capsule {
    fn aabb(&self) -> Aabb {
        let r = Vec3::splat(self.r);
        Aabb::new(a3(self.a.min(self.b) - r), a3(self.a.max(self.b) + r))
    }
}

/// Where the ray `o + d t` (unit `d`) first meets capsule `c` (Quílez's capsule test), if it
/// does at `t > 0`.
fn capsule_hit(o: Vec3, d: Vec3, c: &Capsule) -> Option<f32> {
    let ba = c.b - c.a;
    let oa = o - c.a;
    let baba = ba.dot(ba);
    let bard = ba.dot(d);
    let baoa = ba.dot(oa);
    let rdoa = d.dot(oa);
    let oaoa = oa.dot(oa);
    let qa = baba - bard * bard;
    let qb = baba * rdoa - baoa * bard;
    let qc = baba * oaoa - baoa * baoa - c.r * c.r * baba;
    let h = qb * qb - qa * qc;
    if h >= 0.0 && qa > 1e-12 * baba {
        let t = (-qb - h.sqrt()) / qa;
        let y = baoa + t * bard;
        if y > 0.0 && y < baba && t > 0.0 {
            return Some(t);
        }
    }
    // The round ends.
    [c.a, c.b]
        .iter()
        .filter_map(|&centre| {
            let oc = o - centre;
            let hb = d.dot(oc);
            let hc = oc.dot(oc) - c.r * c.r;
            let h = hb * hb - hc;
            let t = -hb - h.max(0.0).sqrt();
            (h >= 0.0 && t > 0.0).then_some(t)
        })
        .reduce(f32::min)
}

/// Every strand of `sets` as capsules in a BVH.
struct Occluders {
    capsules: Vec<Capsule>,
    bvh: Bvh2,
}

impl Occluders {
    fn new(sets: &[StrandSet<'_>]) -> Occluders {
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
                        });
                    }
                }
                strand += 1;
            }
        }
        if capsules.is_empty() {
            return Occluders {
                capsules,
                bvh: Bvh2::default(),
            };
        }
        let bvh = build_bvh2(
            &capsules,
            obvhs::BvhBuildParams::medium_build(),
            &mut std::time::Duration::default(),
        );
        let capsules = bvh
            .primitive_indices
            .iter()
            .map(|&i| capsules[i as usize])
            .collect();
        Occluders { capsules, bvh }
    }

    /// Whether the ray `o + d t` meets a capsule of any strand but `own` before `tmax`.
    fn blocked(&self, o: Vec3, d: Vec3, tmax: f32, own: u32) -> bool {
        if self.capsules.is_empty() {
            return false;
        }
        // +0 for −0 (see World::hit).
        let d = d + Vec3::ZERO;
        let ray = Ray::new(a3(o), a3(d), 0.0, tmax);
        !self.bvh.ray_traverse_miss(ray, |r, id| {
            let c = &self.capsules[id];
            match capsule_hit(o, d, c) {
                Some(t) if c.strand != own && t < r.tmax => t,
                _ => f32::INFINITY,
            }
        })
    }
}

/// Whether world point `p` on strand `own` (surface normal `n` at its root) sees `light`.
fn sees(world: &World, occ: &Occluders, p: Vec3, n: Vec3, light: &Emitter, own: u32) -> bool {
    if !world.sees_above(p, n, light) {
        return false;
    }
    let (d, dist) = match light.source() {
        Source::At(position) => {
            let to = position - p;
            (to.normalize_or_zero(), to.length())
        }
        Source::Along(direction) => (-direction, f32::INFINITY),
    };
    !occ.blocked(p, d, dist, own)
}

/// For each set, each strand's bits: bit `5 l + k` is set where sample `k` (height
/// `k / 4` of the strand's) sees light `l` of `lights` (at most [`MAX_LIGHTS`]). Rows run in
/// parallel; the bits are the same at any thread count.
pub fn shadow_bits(
    world: &World,
    sets: &[StrandSet<'_>],
    lights: &[Emitter],
) -> Vec<Vec<[u32; 2]>> {
    let lights = &lights[..lights.len().min(MAX_LIGHTS)];
    let occ = Occluders::new(sets);
    let mut first = 0u32;
    sets.iter()
        .map(|set| {
            let base = first;
            first += set.roots.len() as u32;
            let normal_model = set.model.inverse().transpose();
            let on = set.wind_on();
            set.roots
                .par_iter()
                .enumerate()
                .map(|(i, s)| {
                    let (p, _) = samples(set, &on, s);
                    let n = normal_model
                        .transform_vector3(Vec3::from_slice(&s.normal[..3]))
                        .normalize_or_zero();
                    let mut bits = 0u64;
                    for (l, light) in lights.iter().enumerate() {
                        for (k, &q) in p.iter().enumerate() {
                            if sees(world, &occ, q, n, light, base + i as u32) {
                                bits |= 1 << (5 * l + k);
                            }
                        }
                    }
                    [bits as u32, (bits >> 32) as u32]
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strand(x: f32, z: f32, radius: f32) -> StrandRoot {
        StrandRoot {
            root: [x, 0.0, z, 1.0],
            normal: [0.0, 1.0, 0.0, 1.0],
            comb: [0.0, 0.0, 0.0, radius],
            lean: [0.0; 4],
            albedo: [1.0; 4],
        }
    }

    #[test]
    fn a_capsule_is_hit_from_outside_and_missed_beside() {
        let c = Capsule {
            a: Vec3::ZERO,
            b: Vec3::Y,
            r: 0.1,
            strand: 0,
        };
        let t = capsule_hit(Vec3::new(-1.0, 0.5, 0.0), Vec3::X, &c).expect("hits the side");
        assert!((t - 0.9).abs() < 1e-5, "{t}");
        let cap = capsule_hit(Vec3::new(0.0, 2.0, 0.0), -Vec3::Y, &c).expect("hits the cap");
        assert!((cap - 0.9).abs() < 1e-5, "{cap}");
        assert!(capsule_hit(Vec3::new(-1.0, 0.5, 0.2), Vec3::X, &c).is_none());
        assert!(
            capsule_hit(Vec3::new(1.0, 0.5, 0.0), Vec3::X, &c).is_none(),
            "behind"
        );
    }

    /// A light low on the +x side: a strand standing in front of another toward it hides
    /// the other's samples at the heights the ray passes through it, and nothing else; a strand
    /// with nothing toward the light sees it everywhere.
    #[test]
    fn a_strand_shadows_the_samples_behind_it_and_no_others() {
        let world = World::empty();
        let roots = [
            strand(0.0, 0.0, 0.05),
            strand(0.5, 0.0, 0.05),
            strand(0.0, 3.0, 0.05),
        ];
        let set = StrandSet {
            model: Mat4::IDENTITY,
            length: 1.0,
            roots: &roots,
            wind: ([0.0; 4], [0.0; 4]),
        };
        let light = Emitter::Directional {
            direction: Vec3::new(-1.0, 0.0, 0.0),
        };
        let bits = shadow_bits(&world, &[set], &[light]);
        let all = (1u32 << 5) - 1;
        assert_eq!(bits[0][0][0], 0, "behind strand 1 at every height");
        assert_eq!(bits[0][1][0], all, "strand 1 sees the light");
        assert_eq!(bits[0][2][0], all, "strand 2 has nothing toward the light");
        let tilted = Emitter::Directional {
            direction: Vec3::new(-1.0, -1.0, 0.0).normalize(),
        };
        // Toward the light up 45°: from height y, the ray meets x = 0.5 at height y + 0.5,
        // inside strand 1 only for y ≤ 0.5.
        let bits = shadow_bits(&world, &[set], &[tilted]);
        assert_eq!(
            bits[0][0][0], 0b11000,
            "only samples above 0.5 see past strand 1"
        );
    }

    /// A steady wind along +z bends each strand as a comb along +z of the wind's strength
    /// does (strands.wgsl's path), so a strand blown behind another toward a light from +z
    /// is shadowed where it stood in the open at rest.
    #[test]
    fn the_wind_bends_the_strands_the_rays_start_from() {
        let world = World::empty();
        fn blown(roots: &[StrandRoot], strength: f32) -> StrandSet<'_> {
            StrandSet {
                model: Mat4::from_scale(Vec3::splat(2.0)),
                length: 1.0,
                roots,
                wind: ([0.0, 0.0, strength, 0.0], [0.0; 4]),
            }
        }
        let one = [strand(0.0, 0.0, 0.05)];
        let combed = [StrandRoot {
            comb: [0.0, 0.0, 0.8, 0.05],
            ..one[0]
        }];
        let (p, _) = samples(&blown(&one, 0.8), &blown(&one, 0.8).wind_on(), &one[0]);
        let still = blown(&combed, 0.0);
        let (q, _) = samples(&still, &still.wind_on(), &combed[0]);
        for k in 0..=SEGMENTS {
            assert!(
                (p[k] - q[k]).length() < 1e-5,
                "sample {k}: {} vs {}",
                p[k],
                q[k]
            );
        }
        assert!(
            p[SEGMENTS].z > 0.5,
            "the tip is blown along +z: {}",
            p[SEGMENTS]
        );
        // Light low from +x; a strand combed toward −z between the first and the light. A
        // strong wind along +z blows both out along +z, the first lower and farther, into the
        // other's shadow: the bits are those of the strands combed by the wind, not those of
        // the strands at rest.
        let light = Emitter::Directional {
            direction: Vec3::new(-1.0, 0.0, 0.0),
        };
        let back = |r: StrandRoot, dz: f32| StrandRoot {
            comb: [0.0, 0.0, r.comb[2] + dz, r.comb[3]],
            ..r
        };
        let roots = [strand(0.0, 0.0, 0.2), back(strand(0.5, 0.0, 0.2), -0.8)];
        let windy = shadow_bits(&world, &[blown(&roots, 3.0)], &[light]);
        let combed = roots.map(|r| back(r, 3.0));
        let as_combed = shadow_bits(&world, &[blown(&combed, 0.0)], &[light]);
        let still = shadow_bits(&world, &[blown(&roots, 0.0)], &[light]);
        assert_eq!(
            windy, as_combed,
            "the wind bends the strands as a comb does"
        );
        assert_ne!(windy, still, "blown strands are not shadowed as still ones");
    }
}
