//! Baking one primitive: unit normals (flat where missing or zero), tangents (kept, or
//! MikkTSpace), vertex splits where corners of one vertex disagree (mirrored-UV seams, flat
//! normals), then the comb of every output vertex. Only the work the primitive needs is done:
//! with usable NORMAL and TANGENT nothing is done per corner and no vertex is split.

use glam::{Vec2, Vec3, Vec4};
use pelt_geom::Mesh;
use pelt_geom::mikktspace;
use pelt_geom::normals::{UNIT_TOLERANCE, corner_normals, face_normal, normalize_f64};
use pelt_geom::weld::{key_bits, weld};
use rayon::prelude::*;
use serde::Serialize;

use crate::comb::{self, CombCase};
use crate::frame::Frame;
use crate::options::{BakeOptions, TangentMode};

/// Where the output tangents came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TangentSource {
    /// The file's TANGENT was kept.
    Kept,
    /// MikkTSpace generated them.
    Generated,
}

/// Counts for the report; every special case is counted.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct PrimitiveStats {
    /// Vertices in the source primitive.
    pub vertices_in: usize,
    /// Vertices written.
    pub vertices_out: usize,
    /// Triangles.
    pub triangles: usize,
    /// Vertices added by splitting (mirrored UV seams, flat normals).
    pub split_vertices: usize,
    /// Triangles with zero area.
    pub degenerate_triangles: usize,
    /// Triangles with zero UV area or derivatives (MikkTSpace's fallback applies).
    pub degenerate_uv_triangles: usize,
    /// The source had no NORMAL: flat normals were generated.
    pub flat_normals: bool,
    /// Vertices whose normal was zero and was replaced by flat normals.
    pub zero_normals: usize,
    /// Vertices whose normal was not unit length and was renormalized.
    pub renormalized_normals: usize,
    /// Tangent source.
    pub tangents: Option<TangentSource>,
    /// Vertices whose tangent was zero or along the normal and was replaced by a perpendicular.
    pub degenerate_tangents: usize,
    /// Kept tangents whose w was not exactly ±1 (written as its sign).
    pub tangent_w_fixed: usize,
    /// Corners MikkTSpace could not reach (reference default (1, 0, 0, -1)).
    pub default_tangent_corners: usize,
    /// Combs near gray: length 0.
    pub gray_combs: usize,
    /// Combs along the normal: tangent direction used.
    pub parallel_combs: usize,
}

/// What the bake writes back for one primitive. Per-vertex arrays are indexed by output vertex.
#[derive(Debug, Clone, PartialEq)]
pub struct BakedPrimitive {
    /// When vertices were split: (output vertex → source vertex, new indices).
    pub remap: Option<(Vec<u32>, Vec<u32>)>,
    /// New NORMAL, when the source's had to be generated or repaired.
    pub normals: Option<Vec<[f32; 3]>>,
    /// New TANGENT, when generated or repaired.
    pub tangents: Option<Vec<[f32; 4]>>,
    /// `_FUR_COMB` (float; quantized by the writer if asked).
    pub comb: Vec<[f32; 4]>,
    /// Counts.
    pub stats: PrimitiveStats,
    /// Things the user should know.
    pub warnings: Vec<String>,
}

/// One output vertex: normal, tangent, tangent was degenerate, comb, comb case.
type VertexOut = (Vec3, [f32; 4], bool, [f32; 4], CombCase);

/// Per-vertex or per-corner data.
enum Attr<T> {
    Vertex(Vec<T>),
    Corner(Vec<T>),
}

impl<T: Copy> Attr<T> {
    fn at(&self, vertex: usize, corner: usize) -> T {
        match self {
            Attr::Vertex(v) => v[vertex],
            Attr::Corner(c) => c[corner],
        }
    }
    fn is_corner(&self) -> bool {
        matches!(self, Attr::Corner(_))
    }
}

/// Bakes one primitive. The mesh must have passed [`Mesh::validate`] and carry COLOR_0.
pub fn bake_primitive(mesh: &Mesh, opts: &BakeOptions) -> BakedPrimitive {
    let mut stats = PrimitiveStats {
        vertices_in: mesh.vertex_count(),
        triangles: mesh.triangle_count(),
        ..PrimitiveStats::default()
    };
    let mut warnings = Vec::new();
    let idx = &mesh.indices;

    stats.degenerate_triangles = idx
        .par_chunks_exact(3)
        .with_min_len(4096)
        .filter(|t| {
            let p = |k: usize| mesh.positions[t[k] as usize];
            face_normal(p(0), p(1), p(2)).is_none()
        })
        .count();

    // Normals: per vertex when the file's are usable, per corner (flat) otherwise.
    let (normals, rewrite_normals) = match &mesh.normals {
        Some(ns) => {
            let unit: Vec<Option<(Vec3, bool)>> = ns
                .par_iter()
                .with_min_len(4096)
                .map(|&n| {
                    normalize_f64(n).map(|u| {
                        (
                            u.as_vec3(),
                            (n.as_dvec3().length() - 1.0).abs() > UNIT_TOLERANCE,
                        )
                    })
                })
                .collect();
            stats.renormalized_normals = unit.iter().flatten().filter(|u| u.1).count();
            stats.zero_normals = unit.iter().filter(|u| u.is_none()).count();
            if stats.zero_normals == 0 {
                let v: Vec<Vec3> = unit.into_iter().flatten().map(|u| u.0).collect();
                (Attr::Vertex(v), stats.renormalized_normals > 0)
            } else {
                (
                    Attr::Corner(corner_normals(&mesh.positions, Some(ns), idx).0),
                    true,
                )
            }
        }
        None => {
            stats.flat_normals = true;
            warnings.push("no NORMAL: flat normals generated and written".to_owned());
            (
                Attr::Corner(corner_normals(&mesh.positions, None, idx).0),
                true,
            )
        }
    };

    // Tangents: kept (per vertex) or MikkTSpace (per corner).
    let keep =
        opts.tangents == TangentMode::Keep && mesh.tangents.is_some() && mesh.normals.is_some();
    if mesh.tangents.is_some() && mesh.normals.is_none() {
        warnings.push(
            "TANGENT ignored: without NORMAL glTF clients must ignore it; regenerated".to_owned(),
        );
    }
    let tangents: Attr<Vec4> = if keep {
        stats.tangents = Some(TangentSource::Kept);
        let ts = mesh.tangents.as_deref().unwrap_or_default();
        stats.tangent_w_fixed = ts.iter().filter(|t| t.w != 1.0 && t.w != -1.0).count();
        Attr::Vertex(ts.to_vec())
    } else {
        stats.tangents = Some(TangentSource::Generated);
        if mesh.uvs.is_none() {
            warnings.push("no TEXCOORD_0: tangents follow MikkTSpace's fallback frame".to_owned());
        }
        Attr::Corner(generate_tangents(mesh, &normals, &mut stats))
    };

    // Output vertices: one per distinct (source vertex, normal, tangent).
    let remap = if normals.is_corner() || tangents.is_corner() {
        split_vertices(mesh, &normals, &tangents)
    } else {
        None
    };
    let out_count = remap.as_ref().map_or(mesh.vertex_count(), |(m, _)| m.len());
    // Each output vertex's source vertex and one corner using it (for per-corner data).
    let first_corner = first_corners(remap.as_ref().map_or(idx, |(_, i)| i), out_count);
    let source = |o: usize| remap.as_ref().map_or(o, |(m, _)| m[o] as usize);
    stats.vertices_out = out_count;
    stats.split_vertices = out_count - mesh.vertex_count();

    let colors = mesh.colors.as_deref().unwrap_or_default();
    let per_vertex: Vec<VertexOut> = (0..out_count)
        .into_par_iter()
        .with_min_len(2048)
        .map(|o| {
            let v = source(o);
            let c = first_corner[o];
            let (n, t) = if c == u32::MAX {
                // Unreferenced vertex: stored normal (or +Z), any tangent.
                let n = match &normals {
                    Attr::Vertex(ns) => ns[v],
                    Attr::Corner(_) => mesh
                        .normals
                        .as_ref()
                        .and_then(|ns| normalize_f64(ns[v]))
                        .map_or(Vec3::Z, |d| d.as_vec3()),
                };
                let t = match &tangents {
                    Attr::Vertex(ts) => ts[v],
                    Attr::Corner(_) => Vec4::new(1.0, 0.0, 0.0, 1.0),
                };
                (n, t)
            } else {
                (normals.at(v, c as usize), tangents.at(v, c as usize))
            };
            let (frame, degenerate) = Frame::new(n, t);
            let (d, len) = comb::decode_color(
                colors.get(v).copied().unwrap_or(Vec4::ONE),
                opts.color_space,
                &opts.axes,
            );
            let (combed, case) = comb::bake(d, len, &frame);
            (n, frame.tangent4(), degenerate, combed, case)
        })
        .collect();

    stats.degenerate_tangents = per_vertex.iter().filter(|p| p.2).count();
    stats.gray_combs = per_vertex.iter().filter(|p| p.4 == CombCase::Gray).count();
    stats.parallel_combs = per_vertex
        .iter()
        .filter(|p| p.4 == CombCase::ParallelToNormal)
        .count();

    let out_normals = rewrite_normals.then(|| per_vertex.iter().map(|p| p.0.to_array()).collect());
    let out_tangents = match &tangents {
        Attr::Corner(_) => Some(per_vertex.iter().map(|p| p.1).collect()),
        Attr::Vertex(ts) if stats.degenerate_tangents > 0 || stats.tangent_w_fixed > 0 => Some(
            per_vertex
                .iter()
                .zip(ts)
                .map(|(p, t)| {
                    if p.2 {
                        p.1
                    } else {
                        [t.x, t.y, t.z, crate::frame::handedness(t.w) as f32]
                    }
                })
                .collect(),
        ),
        Attr::Vertex(_) => None,
    };
    if stats.degenerate_tangents > 0 && keep {
        warnings.push(format!(
            "{} kept tangents were zero or along the normal and were replaced",
            stats.degenerate_tangents
        ));
    }
    let comb = per_vertex.iter().map(|p| p.3).collect();
    BakedPrimitive {
        remap,
        normals: out_normals,
        tangents: out_tangents,
        comb,
        stats,
        warnings,
    }
}

/// MikkTSpace over the mesh, per corner; corners whose tangent comes out zero keep it (the
/// frame replaces it by a perpendicular and counts it).
fn generate_tangents(mesh: &Mesh, normals: &Attr<Vec3>, stats: &mut PrimitiveStats) -> Vec<Vec4> {
    let zero_uvs;
    let uvs: &[Vec2] = match &mesh.uvs {
        Some(u) => u,
        None => {
            zero_uvs = vec![Vec2::ZERO; mesh.vertex_count()];
            &zero_uvs
        }
    };
    let result = match normals {
        Attr::Vertex(ns) => mikktspace::generate(&mesh.positions, ns, uvs, &mesh.indices),
        Attr::Corner(cn) => {
            // A vertex table with one entry per distinct (vertex, normal).
            let idx = &mesh.indices;
            let (ids, count) = weld(idx.len(), |c| {
                let n = cn[c];
                [idx[c], key_bits(n.x), key_bits(n.y), key_bits(n.z)]
            });
            let mut p = vec![Vec3::ZERO; count];
            let mut n = vec![Vec3::Z; count];
            let mut t = vec![Vec2::ZERO; count];
            for (c, &id) in ids.iter().enumerate() {
                let v = idx[c] as usize;
                p[id as usize] = mesh.positions[v];
                n[id as usize] = cn[c];
                t[id as usize] = uvs[v];
            }
            mikktspace::generate(&p, &n, &t, &ids)
        }
    };
    stats.degenerate_uv_triangles = result.stats.degenerate_uv_triangles;
    stats.default_tangent_corners = result.stats.default_corners;
    result.corners.into_iter().map(Vec4::from).collect()
}

/// Splits vertices whose corners disagree. Each vertex keeps its slot with the values of its
/// first corner; corners that differ from it get new vertices appended after the originals (one
/// per distinct (vertex, normal, tangent)). Returns (output vertex → source vertex, new
/// indices), or None when the corners of every vertex agree.
fn split_vertices(
    mesh: &Mesh,
    normals: &Attr<Vec3>,
    tangents: &Attr<Vec4>,
) -> Option<(Vec<u32>, Vec<u32>)> {
    let idx = &mesh.indices;
    let nv = mesh.vertex_count();
    let key = |c: usize| {
        let v = idx[c] as usize;
        let n = normals.at(v, c);
        let t = tangents.at(v, c);
        [n.x, n.y, n.z, t.x, t.y, t.z, t.w].map(key_bits)
    };
    let mut first = vec![u32::MAX; nv];
    let mut differing = Vec::new();
    for (c, &v) in idx.iter().enumerate() {
        let f = &mut first[v as usize];
        if *f == u32::MAX {
            *f = c as u32;
        } else if key(*f as usize) != key(c) {
            differing.push(c);
        }
    }
    if differing.is_empty() {
        return None;
    }
    let (ids, count) = weld(differing.len(), |k| {
        let c = differing[k];
        let q = key(c);
        [idx[c], q[0], q[1], q[2], q[3], q[4], q[5], q[6]]
    });
    let mut map: Vec<u32> = (0..nv as u32).collect();
    map.resize(nv + count, 0);
    let mut indices = idx.clone();
    for (&c, &id) in differing.iter().zip(&ids) {
        let o = nv + id as usize;
        map[o] = idx[c];
        indices[c] = o as u32;
    }
    Some((map, indices))
}

/// For each output vertex, the first corner that uses it (u32::MAX when none).
fn first_corners(idx: &[u32], out_count: usize) -> Vec<u32> {
    let mut first = vec![u32::MAX; out_count];
    for (c, &v) in idx.iter().enumerate() {
        let f = &mut first[v as usize];
        if *f == u32::MAX {
            *f = c as u32;
        }
    }
    first
}
