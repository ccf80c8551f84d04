//! The scene as the ray tracer sees it: every drawn triangle in world space with its vertex
//! normals and colours and its object's optics, a BVH over them (`obvhs`: PLOC build,
//! compressed wide BVH8 traversal), the lights, the ambient term and the sky. Intersection is
//! a two-sided Möller–Trumbore test (the BVH crate's own culls back faces, and refraction
//! leaves glass through its back faces).

use glam::{Mat4, Vec3};
use glam34::Vec3A;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;

use pelt_scene::asset::MeshData;
use pelt_scene::light::Source;
use pelt_scene::plan::{Optics, ScenePlan};
use pelt_scene::shading::{self, Emitter, Light, linear_of_srgb8};
use pelt_scene::sky::CubeImages;
use pelt_scene::vertex::StrandRoot;

use crate::fur::{FurSet, StrandHit, TracedFur};
use crate::strand_set::StrandSet;

/// One triangle: world positions, unit vertex normals, linear vertex colours, its object.
#[derive(Debug, Clone, Copy)]
pub struct Tri {
    /// Corners.
    pub p: [Vec3; 3],
    /// Vertex normals (world, unit).
    pub n: [Vec3; 3],
    /// Vertex colours (linear, times the object's colour).
    pub albedo: [Vec3; 3],
    /// Index into [`World::optics`].
    pub object: u32,
}

/// What lies beyond the scene.
#[derive(Debug, Clone)]
pub enum SkyModel {
    /// The flat background colour.
    Background,
    /// The procedural sky.
    Procedural,
    /// A cube map: six faces of linear RGB, `size`² each.
    Cube {
        /// Face side.
        size: u32,
        /// +X −X +Y −Y +Z −Z, rows top to bottom.
        faces: Vec<Vec<Vec3>>,
    },
}

impl SkyModel {
    /// The cube map of `images`.
    pub fn cube(images: &CubeImages) -> SkyModel {
        SkyModel::Cube {
            size: images.size,
            faces: images
                .faces
                .iter()
                .map(|f| {
                    f.chunks_exact(4)
                        .map(|p| {
                            Vec3::new(
                                linear_of_srgb8(p[0]),
                                linear_of_srgb8(p[1]),
                                linear_of_srgb8(p[2]),
                            )
                        })
                        .collect()
                })
                .collect(),
        }
    }

    /// The radiance arriving from unit direction `d`.
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        match self {
            SkyModel::Background => Vec3::from(shading::BACKGROUND),
            SkyModel::Procedural => shading::procedural_sky(d),
            SkyModel::Cube { size, faces } => {
                let (face, u, v) = cube_face_uv(d);
                bilinear(&faces[face], *size, u, v)
            }
        }
    }
}

/// The cube face (+X −X +Y −Y +Z −Z) and its texture coordinates (0..1, v down) of
/// direction `d`, by the cube-map convention GPUs sample with.
pub fn cube_face_uv(d: Vec3) -> (usize, f32, f32) {
    let a = d.abs();
    let (face, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
        if d.x > 0.0 {
            (0, -d.z, -d.y, a.x)
        } else {
            (1, d.z, -d.y, a.x)
        }
    } else if a.y >= a.z {
        if d.y > 0.0 {
            (2, d.x, d.z, a.y)
        } else {
            (3, d.x, -d.z, a.y)
        }
    } else if d.z > 0.0 {
        (4, d.x, -d.y, a.z)
    } else {
        (5, -d.x, -d.y, a.z)
    };
    let ma = ma.max(1e-20);
    (face, (sc / ma + 1.0) / 2.0, (tc / ma + 1.0) / 2.0)
}

fn bilinear(face: &[Vec3], size: u32, u: f32, v: f32) -> Vec3 {
    let s = size as f32;
    let x = (u * s - 0.5).clamp(0.0, s - 1.0);
    let y = (v * s - 0.5).clamp(0.0, s - 1.0);
    let (x0, y0) = (x.floor() as usize, y.floor() as usize);
    let (x1, y1) = (
        (x0 + 1).min(size as usize - 1),
        (y0 + 1).min(size as usize - 1),
    );
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    let at = |x: usize, y: usize| face[y * size as usize + x];
    let top = at(x0, y0).lerp(at(x1, y0), fx);
    let bottom = at(x0, y1).lerp(at(x1, y1), fx);
    top.lerp(bottom, fy)
}

/// The traced scene.
#[derive(Debug)]
pub struct World {
    /// Triangles, in BVH primitive order.
    pub tris: Vec<Tri>,
    /// Each object's optics, by [`Tri::object`].
    pub optics: Vec<Optics>,
    /// Each object's base mesh is a traced fur object's skin, by [`Tri::object`]: lit as the
    /// shells' base mesh is, as fur at the root ([`Hit::skin`]).
    pub skins: Vec<bool>,
    /// Lights (every light of the scene).
    pub lights: Vec<Light>,
    /// Ambient light.
    pub ambient: Vec3,
    /// The sky.
    pub sky: SkyModel,
    /// Ray offset off a surface (a small fraction of the scene's size).
    pub epsilon: f32,
    bvh: CwBvh,
    fur: TracedFur,
}

/// A ray's first hit.
#[derive(Debug, Clone, Copy)]
pub struct Hit {
    /// The point.
    pub p: Vec3,
    /// The interpolated unit normal, as the mesh orients it (outward).
    pub n: Vec3,
    /// The geometric normal of the triangle's winding (unnormalized).
    pub g: Vec3,
    /// The interpolated colour.
    pub albedo: Vec3,
    /// The hit object's optics.
    pub optics: Optics,
    /// The strand met, where the ray met a traced strand ([`World::with_fur`]) rather than a
    /// triangle.
    pub strand: Option<StrandHit>,
    /// Whether the triangle met is a traced fur object's skin (its albedo the fur's root
    /// colour's).
    pub skin: bool,
}

fn a(v: Vec3) -> Vec3A {
    Vec3A::new(v.x, v.y, v.z)
}

impl World {
    /// The world of `plan` (its objects, lights and ambient) over `meshes`, under `sky`, a
    /// fur object drawn as its base mesh in the fur's mean colour (the old truth, bald).
    pub fn new(plan: &ScenePlan, meshes: &[MeshData], sky: SkyModel) -> World {
        Self::build(plan, meshes, sky, &[])
    }

    /// [`World::new`] with each fur object's strands traced: `strands[m]` the strands planted
    /// on mesh `m` (`pelt_scene::strands::plant`; `None`: a fur object of that mesh keeps its
    /// base mesh in the fur's mean colour), in the plan's wind, over its base mesh in the
    /// object's own colour (as the strand reference draws it).
    pub fn with_fur(
        plan: &ScenePlan,
        meshes: &[MeshData],
        sky: SkyModel,
        strands: &[Option<Vec<StrandRoot>>],
    ) -> World {
        Self::build(plan, meshes, sky, strands)
    }

    fn build(
        plan: &ScenePlan,
        meshes: &[MeshData],
        sky: SkyModel,
        strands: &[Option<Vec<StrandRoot>>],
    ) -> World {
        let mut sets = Vec::new();
        let mut tris = Vec::new();
        let mut optics = Vec::new();
        let mut skins = Vec::new();
        for (o, _) in &plan.objects {
            if o.pattern != 0 {
                continue; // alpha: not traced
            }
            let mesh = &meshes[o.mesh];
            let normal_model = o.model.inverse().transpose();
            let planted = strands.get(o.mesh).and_then(Option::as_ref);
            let color = match (o.fur, planted) {
                (Some(f), Some(roots)) => {
                    sets.push(FurSet {
                        strands: StrandSet {
                            model: o.model,
                            length: f.length,
                            roots,
                            wind: plan.wind,
                        },
                        tint: o.color,
                        base: f.base_color,
                        tip: f.tip_color,
                    });
                    o.color * f.base_color
                }
                (Some(f), None) => (f.base_color + f.tip_color) / 2.0,
                (None, _) => o.color,
            };
            let id = optics.len() as u32;
            optics.push(o.optics);
            skins.push(o.fur.is_some() && planted.is_some());
            push_mesh(&mut tris, mesh, o.model, normal_model, color, id);
        }
        let (centre, radius) = plan.extent;
        let _ = centre;
        let shapes: Vec<Triangle> = tris
            .iter()
            .map(|t| Triangle {
                v0: a(t.p[0]),
                v1: a(t.p[1]),
                v2: a(t.p[2]),
            })
            .collect();
        let bvh = build_cwbvh_from_tris(
            &shapes,
            obvhs::BvhBuildParams::medium_build(),
            &mut std::time::Duration::default(),
        );
        // Reorder the triangles into the BVH's primitive order.
        let tris = bvh
            .primitive_indices
            .iter()
            .map(|&i| tris[i as usize])
            .collect();
        World {
            tris,
            optics,
            skins,
            lights: plan.lights.clone(),
            ambient: plan.ambient,
            sky,
            epsilon: radius.max(1e-3) * 1e-4,
            bvh,
            fur: TracedFur::new(&sets),
        }
    }

    /// A world with nothing in it (no triangles, lights or ambient light).
    pub fn empty() -> World {
        World {
            tris: Vec::new(),
            optics: Vec::new(),
            skins: Vec::new(),
            lights: Vec::new(),
            ambient: Vec3::ZERO,
            sky: SkyModel::Background,
            epsilon: 1e-4,
            bvh: CwBvh::default(),
            fur: TracedFur::default(),
        }
    }

    /// Whether the point `p` of a surface with geometric normal `g` sees `light`: the shadow
    /// ray leaves `p` offset along `g` toward the light's side (so it cannot hit its own
    /// triangle) and must reach a point light, or leave the scene toward a directional one,
    /// before meeting any traced surface (mirrors and glass included, as their meshes cast in
    /// a shadow map).
    pub fn sees(&self, p: Vec3, g: Vec3, light: &Emitter) -> bool {
        let toward = match light.source() {
            Source::At(position) => position - p,
            Source::Along(direction) => -direction,
        };
        let side = if g.dot(toward) >= 0.0 { g } else { -g };
        self.sees_from(p, side, light)
    }

    /// [`World::sees`] for a point on the side of its surface that `n` points to (a strand's
    /// sample, on or above the surface it grows from): the ray leaves `p` offset along `n`
    /// whichever side the light is on, so the surface hides a light behind it (inside a
    /// closed mesh, or under a plane) from the strand's root as from its tip.
    pub fn sees_above(&self, p: Vec3, n: Vec3, light: &Emitter) -> bool {
        self.sees_from(p, n, light)
    }

    /// Whether the shadow ray from `p`, offset by epsilon along `side`, reaches `light`.
    fn sees_from(&self, p: Vec3, side: Vec3, light: &Emitter) -> bool {
        self.reaches(p + side * self.epsilon, light, u32::MAX)
    }

    /// Whether it traces fur objects' strands ([`World::with_fur`]).
    pub fn traces_fur(&self) -> bool {
        !self.fur.is_empty()
    }

    /// Whether a point on traced strand `own` sees `light`: the shadow ray leaves `p` offset
    /// toward the light and meets no triangle and no other strand.
    pub fn strand_sees(&self, p: Vec3, light: &Emitter, own: u32) -> bool {
        let toward = match light.source() {
            Source::At(position) => (position - p).normalize_or_zero(),
            Source::Along(direction) => -direction,
        };
        self.reaches(p + toward * self.epsilon, light, own)
    }

    /// Whether the ray from `o` toward `light` meets no triangle and no traced strand but
    /// `own` on its way.
    fn reaches(&self, o: Vec3, light: &Emitter, own: u32) -> bool {
        let (d, tmax) = match light.source() {
            Source::At(position) => {
                let to = position - o;
                let dist = to.length();
                if dist <= self.epsilon {
                    return true;
                }
                (to / dist, dist - self.epsilon)
            }
            Source::Along(direction) => (-direction, f32::INFINITY),
        };
        self.hit_triangle(o, d, 0.0, tmax).is_none() && !self.fur.blocked(o, d, tmax, own)
    }

    /// The first hit of the ray `o + d t` (unit `d`) with `t` in `(tmin, tmax)`: a triangle
    /// or a traced strand.
    pub fn hit(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<Hit> {
        let tri = self.hit_triangle(o, d, tmin, tmax);
        let near = tri.map_or(tmax, |(_, t)| t);
        match self.fur.hit(o, d, tmin, near) {
            Some((s, t)) => Some(Hit {
                p: o + d * t,
                n: s.normal,
                g: s.normal,
                albedo: s.albedo,
                optics: Optics::Diffuse,
                strand: Some(s),
                skin: false,
            }),
            None => tri.map(|(h, _)| h),
        }
    }

    /// The first triangle the ray `o + d t` (unit `d`) meets with `t` in `(tmin, tmax)`, and
    /// that `t`.
    fn hit_triangle(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<(Hit, f32)> {
        if self.tris.is_empty() {
            return None;
        }
        // A negative zero component becomes +0: under obvhs 0.4 a ray with a −0 component
        // (its inverse is −1/ε there, by `signum`) missed a sphere it passes through; with +0
        // it hits (tests/shadows.rs, the directional light along (−1, −1, 0)).
        let d = d + Vec3::ZERO;
        let ray = Ray::new(a(o), a(d), tmin, tmax);
        let mut rh = RayHit::none();
        let mut best = (0usize, 0.0f32, 0.0f32);
        let found = self.bvh.ray_traverse(ray, &mut rh, |r, id| {
            let t = &self.tris[id];
            match intersect(t, o, d) {
                Some((tt, u, v)) if tt > r.tmin && tt < r.tmax => {
                    best = (id, u, v);
                    tt
                }
                _ => f32::INFINITY,
            }
        });
        if !found {
            return None;
        }
        // The closure's last accepted candidate is the closest (tmax shrinks as it goes).
        let (id, u, v) = best;
        let t = &self.tris[id];
        let w = 1.0 - u - v;
        let n = (t.n[0] * w + t.n[1] * u + t.n[2] * v).normalize_or_zero();
        let g = (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]);
        let hit = Hit {
            p: o + d * rh.t,
            n: if n == Vec3::ZERO {
                g.normalize_or_zero()
            } else {
                n
            },
            g,
            albedo: t.albedo[0] * w + t.albedo[1] * u + t.albedo[2] * v,
            optics: self.optics[t.object as usize],
            strand: None,
            skin: self.skins[t.object as usize],
        };
        Some((hit, rh.t))
    }
}

fn push_mesh(
    tris: &mut Vec<Tri>,
    mesh: &MeshData,
    model: Mat4,
    normal_model: Mat4,
    color: Vec3,
    id: u32,
) {
    let vert = |i: u32| {
        let v = &mesh.vertices[i as usize];
        (
            model.transform_point3(Vec3::from(v.position)),
            normal_model
                .transform_vector3(Vec3::from(v.normal))
                .normalize_or_zero(),
            Vec3::new(v.albedo[0], v.albedo[1], v.albedo[2]) * color,
        )
    };
    for c in mesh.indices.chunks_exact(3) {
        let (p0, n0, a0) = vert(c[0]);
        let (p1, n1, a1) = vert(c[1]);
        let (p2, n2, a2) = vert(c[2]);
        tris.push(Tri {
            p: [p0, p1, p2],
            n: [n0, n1, n2],
            albedo: [a0, a1, a2],
            object: id,
        });
    }
}

/// Two-sided Möller–Trumbore: (t, u, v) of the ray `o + d t` through `tri`.
fn intersect(tri: &Tri, o: Vec3, d: Vec3) -> Option<(f32, f32, f32)> {
    let e1 = tri.p[1] - tri.p[0];
    let e2 = tri.p[2] - tri.p[0];
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - tri.p[0];
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some((e2.dot(q) * inv, u, v))
}
