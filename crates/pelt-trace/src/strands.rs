//! Shadow rays for the strand reference: each explicit strand (`pelt render --mode strands`,
//! [`pelt_scene::strands`]) sampled at its segments' ends, a ray from each sample toward each
//! light that casts shadows, through every other strand (capsules of the strand's radius
//! about its segments, in a BVH of their boxes) and the scene's triangles ([`World::sees`]).
//! What reaches the light is one bit per sample and light, which the strands' fragments blend
//! linearly along each segment. The strands are built as [`crate::strand_set`] builds them,
//! bent by the frame's wind as they are drawn, so a blown strand is shadowed where it is
//! blown to.

use glam::Vec3;
use rayon::prelude::*;

use crate::World;
use crate::capsules::Capsules;
pub use crate::strand_set::{SEGMENTS, StrandSet, capsules_of, samples};
use pelt_scene::light::Source;
use pelt_scene::shading::Emitter;

/// Most lights a strand's bits hold (5 bits each in 64).
pub const MAX_LIGHTS: usize = 12;

/// Whether world point `p` on strand `own` (surface normal `n` at its root) sees `light`.
fn sees(world: &World, occ: &Capsules, p: Vec3, n: Vec3, light: &Emitter, own: u32) -> bool {
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
    let occ = Capsules::new(capsules_of(sets));
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
    use glam::Mat4;
    use pelt_scene::vertex::StrandRoot;

    fn strand(x: f32, z: f32, radius: f32) -> StrandRoot {
        StrandRoot {
            root: [x, 0.0, z, 1.0],
            normal: [0.0, 1.0, 0.0, 1.0],
            comb: [0.0, 0.0, 0.0, radius],
            lean: [0.0; 4],
            albedo: [1.0; 4],
        }
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
