//! Specular paths, exactly as the GPU's Listing 17-5 loop (shaders/reflect.wgsl) follows
//! them, with every next hit found by tracing the real triangles:
//!
//! - a mirror reflects, weighting the path by Schlick's Fresnel with its F0 (§17.3, F0 from
//!   n and k for metals);
//! - glass refracts with weight 1 − F (and its tint when the ray enters), or reflects totally
//!   when no refracted direction exists; it flips its normal and inverts its index when the
//!   ray leaves it (Listing 17-5); its F is the exact dielectric Fresnel, which vanishes at
//!   IOR 1 as Schlick's does not;
//! - at the surface the camera sees, glass both reflects (F) and refracts (1 − F): two paths;
//! - a diffuse hit ends the path with its local lighting seen from the ray (a shadow-casting
//!   light only where a shadow ray reaches it: [`World::sees`]);
//! - a ray that leaves the scene ends in the sky;
//! - a path still on a specular surface after `max_depth` bounces ends in the sky in the
//!   direction of its mirror reflection.

use glam::Vec3;

use pelt_scene::plan::Optics;
use pelt_scene::shading::{self, dielectric_f0, fresnel, fresnel_dielectric};

use crate::world::{Hit, World};

/// Traces paths through a [`World`].
#[derive(Debug, Clone, Copy)]
pub struct Tracer<'w> {
    /// The scene.
    pub world: &'w World,
    /// Most specular bounces on a path.
    pub max_depth: u32,
}

/// A specular surface's state on a path: F0, Listing 17-5's `n` (negative: reflector;
/// positive: the IOR of a refractor), and the glass tint.
#[derive(Debug, Clone, Copy)]
struct Surface {
    f0: Vec3,
    n: f32,
    tint: Vec3,
}

impl Surface {
    fn of(o: Optics) -> Option<Surface> {
        match o {
            Optics::Diffuse => None,
            Optics::Mirror { f0 } => Some(Surface {
                f0,
                n: -1.0,
                tint: Vec3::ONE,
            }),
            Optics::Glass { ior, tint } => Some(Surface {
                f0: Vec3::splat(dielectric_f0(ior)),
                n: ior,
                tint,
            }),
        }
    }
}

/// Mirror direction of `v` about `n`.
pub fn reflect(v: Vec3, n: Vec3) -> Vec3 {
    v - 2.0 * v.dot(n) * n
}

/// Refraction of unit `v` through unit `n` (facing against `v`) with `eta` = n₁/n₂; None on
/// total internal reflection (GLSL/WGSL `refract`).
pub fn refract(v: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let c = n.dot(v);
    let k = 1.0 - eta * eta * (1.0 - c * c);
    (k >= 0.0).then(|| eta * v - (eta * c + k.sqrt()) * n)
}

impl Tracer<'_> {
    /// The colour seen along a camera ray, and the optics of its first hit.
    pub fn camera_ray(&self, eye: Vec3, d: Vec3, tmin: f32, tmax: f32) -> (Vec3, Option<Optics>) {
        let Some(h) = self.world.hit(eye, d, tmin, tmax) else {
            return (self.world.sky.radiance(d), None);
        };
        let c = match Surface::of(h.optics) {
            None => self.diffuse(&h, d),
            Some(s) if s.n > 0.0 => {
                self.path(h.p, d, h.n, s, true) + self.path(h.p, d, h.n, s, false)
            }
            Some(s) => self.path(h.p, d, h.n, s, false),
        };
        (c, Some(h.optics))
    }

    /// The local lighting of a diffuse hit seen along `d`, its normal facing the ray as the
    /// rasterizer's two-sided faces do; a shadow-casting light adds nothing where a shadow
    /// ray toward it meets a surface first.
    fn diffuse(&self, h: &Hit, d: Vec3) -> Vec3 {
        let w = self.world;
        if let Some(s) = &h.strand {
            return crate::fur::strand_radiance(s, h.p, -d, w.ambient, &w.lights, |l| {
                !l.shadows || w.strand_sees(h.p, &l.emitter, s.strand)
            });
        }
        if h.skin {
            // The shells' base mesh: fur at its root, lit about the strand's direction there
            // (the normal: strand_tangent at height 0).
            let root = crate::fur::StrandHit {
                tangent: h.n,
                albedo: h.albedo,
                strand: u32::MAX,
                normal: h.n,
            };
            let g = h.g.normalize_or_zero();
            return crate::fur::strand_radiance(&root, h.p, -d, w.ambient, &w.lights, |l| {
                !l.shadows || w.sees(h.p, g, &l.emitter)
            });
        }
        let n = if h.g.dot(d) < 0.0 { h.n } else { -h.n };
        shading::shade_seen(h.albedo, h.p, n, -d, w.ambient, &w.lights, |l| {
            !l.shadows || w.sees(h.p, h.g.normalize_or_zero(), &l.emitter)
        })
    }

    /// Listing 17-5 from a point `x` of surface `s` (unit normal `n`) reached along `v`;
    /// `reflect_first` takes glass's Fresnel-reflected branch at the first event.
    fn path(
        &self,
        mut x: Vec3,
        mut v: Vec3,
        mut n: Vec3,
        mut s: Surface,
        reflect_first: bool,
    ) -> Vec3 {
        let w = self.world;
        let mut throughput = Vec3::ONE;
        for depth in 0..self.max_depth {
            let r = if s.n <= 0.0 {
                throughput *= fresnel(s.f0, n.dot(v));
                reflect(v, n)
            } else {
                let entering = v.dot(n) <= 0.0;
                let (nn, eta) = if entering { (n, 1.0 / s.n) } else { (-n, s.n) };
                let f = fresnel_dielectric(-v.dot(nn), eta);
                match refract(v, nn, eta) {
                    Some(_) if reflect_first && depth == 0 => {
                        throughput *= f;
                        reflect(v, nn)
                    }
                    Some(t) => {
                        let tint = if entering { s.tint } else { Vec3::ONE };
                        throughput *= (1.0 - f) * tint;
                        t.normalize()
                    }
                    // Total internal reflection (F = 1).
                    None => reflect(v, nn),
                }
            };
            let Some(h) = w.hit(x, r, w.epsilon, f32::INFINITY) else {
                return throughput * w.sky.radiance(r);
            };
            match Surface::of(h.optics) {
                None => return throughput * self.diffuse(&h, r),
                Some(next) => s = next,
            }
            x = h.p;
            v = r;
            n = h.n;
        }
        throughput * w.sky.radiance(reflect(v, n).normalize_or_zero())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refraction_bends_toward_the_normal_and_reflects_totally_past_the_critical_angle() {
        let n = Vec3::Y;
        let v = Vec3::new(1.0, -1.0, 0.0).normalize();
        let t = refract(v, n, 1.0 / 1.5).expect("refracts");
        // Snell: sin θt = sin θi / 1.5.
        assert!((t.x - v.x / 1.5).abs() < 1e-6, "{t}");
        assert!((t.length() - 1.0).abs() < 1e-6);
        // From inside glass at 45°: beyond the critical angle (41.8°).
        assert!(refract(v, n, 1.5).is_none());
        assert_eq!(refract(v, n, 1.0), Some(v));
        assert_eq!(reflect(v, n), Vec3::new(v.x, -v.y, 0.0));
    }
}
