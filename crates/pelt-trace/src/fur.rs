//! Fur as the ray tracer sees it: each fur object's explicit strands (the strand reference's,
//! [`pelt_scene::strands`], bent by the wind as strands.wgsl draws them) as capsules that
//! camera rays, reflections, refractions and shadow rays all meet, lit as strands.wgsl lights
//! them: Kajiya-Kay per light about the strand's direction (Revie Listing 2.4, after
//! Heidrich & Seidel), the albedo the shells use at that height, and a shadow ray toward each
//! shadow-casting light through the other strands and the scene.

use glam::Vec3;

use pelt_scene::shading::{Light, SPECULAR_POWER, SPECULAR_STRENGTH};
use pelt_scene::vertex::StrandRoot;
use pelt_scene::wind::WindOn;

use crate::capsules::{Capsule, Capsules, axis_at};
use crate::strand_set::{SEGMENTS, StrandSet, capsules_of};

/// A fur object's strands as traced: where they are (a [`StrandSet`]) and how they look.
#[derive(Debug, Clone, Copy)]
pub struct FurSet<'a> {
    /// The strands.
    pub strands: StrandSet<'a>,
    /// The object's colour (the strands' albedo is multiplied by it, as its tint).
    pub tint: Vec3,
    /// The fur's colour at the root.
    pub base: Vec3,
    /// The fur's colour at the tip.
    pub tip: Vec3,
}

/// What one strand segment shows: its heights and world directions at its ends, its albedo
/// (times its object's tint) and its fur set (the root and tip colours).
#[derive(Debug, Clone, Copy)]
struct SegmentLook {
    z: [f32; 2],
    t: [Vec3; 2],
    albedo: Vec3,
    set: u32,
}

/// A strand's point met by a ray: its unit direction, its albedo there, its strand and the
/// outward normal of its capsule.
#[derive(Debug, Clone, Copy)]
pub struct StrandHit {
    /// Unit direction of the strand (root to tip) there.
    pub tangent: Vec3,
    /// Its albedo there.
    pub albedo: Vec3,
    /// Which strand.
    pub strand: u32,
    /// The capsule's outward unit normal there.
    pub normal: Vec3,
}

/// Every fur object's strands, traced.
#[derive(Debug, Default)]
pub struct TracedFur {
    capsules: Capsules,
    looks: Vec<SegmentLook>,
    /// Each set's (root, tip) colours.
    colors: Vec<(Vec3, Vec3)>,
}

/// P'(z) of the shells' path (`strand_velocity` in fur_common.wgsl) for unit-less normal `n`
/// and comb `comb`.
fn velocity(n: Vec3, comb: Vec3, z: f32) -> Vec3 {
    let m = n.normalize_or_zero() + comb * z;
    let len = m.length();
    if len <= 1e-6 {
        return if comb.length() > 1e-6 {
            comb
        } else {
            n.normalize_or_zero()
        };
    }
    let d = m / len;
    let dd = (comb - d * d.dot(comb)) / len;
    d + dd * z
}

/// Strand `s` of `set`'s segment looks (in the set's wind `on`): heights and world directions
/// at each end (strands.wgsl's `strand_direction`).
fn looks_of(set: &FurSet<'_>, on: &WindOn, index: u32, s: &StrandRoot, out: &mut Vec<SegmentLook>) {
    let st = &set.strands;
    let n = Vec3::from_slice(&s.normal[..3]);
    let comb = pelt_scene::wind::bend(
        Vec3::from_slice(&s.comb[..3]),
        n,
        Vec3::from_slice(&s.root[..3]),
        on,
    );
    let lean = Vec3::from_slice(&s.lean[..3]);
    let k = st.length * s.normal[3];
    let dir = |z: f32| -> Vec3 {
        let d = st.model.transform_vector3(lean + velocity(n, comb, z) * k);
        if d.length() > 1e-12 {
            d.normalize()
        } else {
            Vec3::X
        }
    };
    let albedo = Vec3::from_slice(&s.albedo[..3]) * set.tint;
    for seg in 0..SEGMENTS {
        let z0 = s.root[3] * seg as f32 / SEGMENTS as f32;
        let z1 = s.root[3] * (seg + 1) as f32 / SEGMENTS as f32;
        out.push(SegmentLook {
            z: [z0, z1],
            t: [dir(z0), dir(z1)],
            albedo,
            set: index,
        });
    }
}

impl TracedFur {
    /// The strands of `sets`, numbered as [`capsules_of`] numbers them.
    pub fn new(sets: &[FurSet<'_>]) -> TracedFur {
        let strand_sets: Vec<StrandSet<'_>> = sets.iter().map(|f| f.strands).collect();
        let capsules: Vec<Capsule> = capsules_of(&strand_sets);
        let mut looks = Vec::new();
        for (i, set) in sets.iter().enumerate() {
            let on = set.strands.wind_on();
            for s in set.strands.roots {
                looks_of(set, &on, i as u32, s, &mut looks);
            }
        }
        TracedFur {
            capsules: Capsules::new(capsules),
            looks,
            colors: sets.iter().map(|s| (s.base, s.tip)).collect(),
        }
    }

    /// Whether there are no strands.
    pub fn is_empty(&self) -> bool {
        self.capsules.is_empty()
    }

    /// The strand point the ray `o + d t` meets first with `t` in `(tmin, tmax)`, and `t`.
    pub fn hit(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<(StrandHit, f32)> {
        let (c, t) = self.capsules.first(o, d, tmin, tmax)?;
        let look = &self.looks[c.id as usize];
        let (along, normal) = axis_at(c, o + d * t);
        let blend = look.t[0].lerp(look.t[1], along);
        let tangent = if blend.length() > 1e-6 {
            blend.normalize()
        } else {
            look.t[0]
        };
        let height = look.z[0] + (look.z[1] - look.z[0]) * along;
        let (base, tip) = self.colors[look.set as usize];
        Some((
            StrandHit {
                tangent,
                albedo: look.albedo * base.lerp(tip, height),
                strand: c.strand,
                normal,
            },
            t,
        ))
    }

    /// Whether the ray `o + d t` meets a strand other than `own` before `tmax` (`u32::MAX`:
    /// from no strand).
    pub fn blocked(&self, o: Vec3, d: Vec3, tmax: f32, own: u32) -> bool {
        self.capsules.blocked(o, d, tmax, own)
    }
}

/// The radiance a strand point `h` at `p` sends toward unit `v` (from `p` toward the viewer)
/// under `ambient` and `lights` (fur_light_forward.wgsl's `fur_lighting` and strands.wgsl's
/// sum): ambient plus each light's Kajiya-Kay diffuse times the albedo, plus its specular
/// times the specular strength; a light only where `sees(light)`.
pub fn strand_radiance(
    h: &StrandHit,
    p: Vec3,
    v: Vec3,
    ambient: Vec3,
    lights: &[Light],
    sees: impl Fn(&Light) -> bool,
) -> Vec3 {
    let t = h.tangent;
    let vt = v.dot(t);
    let sin_v = (1.0 - vt * vt).max(0.0).sqrt();
    let mut diffuse = ambient;
    let mut specular = Vec3::ZERO;
    for light in lights {
        let Some((l, atten, _)) = light.emitter.reach(p) else {
            continue;
        };
        if atten <= 0.0 || !sees(light) {
            continue;
        }
        let lt = l.dot(t);
        let sin_l = (1.0 - lt * lt).max(0.0).sqrt();
        diffuse += light.color * (sin_l * atten);
        let spec = (sin_l * sin_v - lt * vt).max(0.0).powf(SPECULAR_POWER) * atten;
        specular += light.color * spec;
    }
    h.albedo * diffuse + SPECULAR_STRENGTH * specular
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    fn strand(x: f32) -> StrandRoot {
        StrandRoot {
            root: [x, 0.0, 0.0, 1.0],
            normal: [0.0, 1.0, 0.0, 1.0],
            comb: [0.0, 0.0, 0.0, 0.05],
            lean: [0.0; 4],
            albedo: [1.0, 0.5, 1.0, 1.0],
        }
    }

    /// An upright strand seen from the side: it is met at its side, its direction is up,
    /// and its colour runs from the fur's base colour at the root to its tip colour, times
    /// the strand's albedo and the object's tint.
    #[test]
    fn a_strand_is_met_upright_with_the_colour_of_its_height() {
        let roots = [strand(0.0)];
        let set = FurSet {
            strands: StrandSet {
                model: Mat4::IDENTITY,
                length: 1.0,
                roots: &roots,
                wind: ([0.0; 4], [0.0; 4]),
            },
            tint: Vec3::new(1.0, 1.0, 0.5),
            base: Vec3::new(1.0, 0.0, 0.0),
            tip: Vec3::new(0.0, 0.0, 1.0),
        };
        let fur = TracedFur::new(&[set]);
        let at = |y: f32| fur.hit(Vec3::new(0.0, y, 5.0), -Vec3::Z, 0.0, f32::INFINITY);
        let (low, t) = at(0.1).expect("the root end");
        assert!((t - 4.95).abs() < 1e-4, "{t}");
        assert!(low.tangent.abs_diff_eq(Vec3::Y, 1e-5), "{}", low.tangent);
        assert!(low.normal.abs_diff_eq(Vec3::Z, 1e-4), "{}", low.normal);
        assert!(
            low.albedo.abs_diff_eq(Vec3::new(0.9, 0.0, 0.05), 1e-4),
            "{}",
            low.albedo
        );
        let (high, _) = at(0.9).expect("the tip end");
        assert!(
            high.albedo.abs_diff_eq(Vec3::new(0.1, 0.0, 0.45), 1e-4),
            "{}",
            high.albedo
        );
        assert!(at(1.2).is_none(), "above the tip");
        assert!(
            fur.hit(Vec3::new(0.2, 0.5, 5.0), -Vec3::Z, 0.0, f32::INFINITY)
                .is_none(),
            "beside it"
        );
    }

    /// Kajiya-Kay: a light across the strand lights it fully, a light along it not at all
    /// (the negative control); a light not seen adds nothing.
    #[test]
    fn a_strand_is_lit_across_and_not_along() {
        let h = StrandHit {
            tangent: Vec3::Y,
            albedo: Vec3::ONE,
            strand: 0,
            normal: Vec3::Z,
        };
        let sun = |d: Vec3| Light {
            emitter: pelt_scene::shading::Emitter::Directional { direction: d },
            color: Vec3::ONE,
            shadows: false,
        };
        let v = Vec3::Z;
        let across = strand_radiance(&h, Vec3::ZERO, v, Vec3::ZERO, &[sun(-Vec3::X)], |_| true);
        let along = strand_radiance(&h, Vec3::ZERO, v, Vec3::ZERO, &[sun(-Vec3::Y)], |_| true);
        let hidden = strand_radiance(&h, Vec3::ZERO, v, Vec3::ZERO, &[sun(-Vec3::X)], |_| false);
        assert!(across.x > 0.99, "{across}");
        assert!(along.x < 1e-6, "{along}");
        assert_eq!(hidden, Vec3::ZERO);
    }
}
