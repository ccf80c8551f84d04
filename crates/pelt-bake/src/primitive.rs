//! Baking one primitive: unit normals (flat where missing or zero), tangents (kept, MikkTSpace,
//! or the one-pass UV-gradient frame where no normal map needs MikkTSpace), topology (normal
//! groups and their IDs, Kircher & Lawrance §3.1), vertex splits where corners of one vertex
//! disagree (mirrored-UV seams, flat normals, different group IDs), then the comb and group ID
//! of every output vertex (made beside the topology where normals and tangents are per vertex;
//! see `vertex_pass`), and the fin edges of the furry part. Only the work the primitive needs
//! is done: with usable NORMAL, per-vertex tangents (kept, or the gradient frame) and one
//! normal group nothing is done per corner and no vertex is split.
//!
//! [`group_primitive`] is the part of this a primitive without a painted comb gets: normal
//! groups and their IDs only, so the renderer's filter keeps its creases too.

use std::borrow::Cow;
use std::time::Instant;

use glam::{Vec2, Vec3, Vec4};
use pelt_geom::Mesh;
use pelt_geom::fins::{self, FinEdge};
use pelt_geom::flow::comb_flow;
use pelt_geom::group_ids::{self, GroupIds};
use pelt_geom::normals::{UNIT_TOLERANCE, corner_normals, face_normal, normalize_f64};
use pelt_geom::smooth::smooth_corner_normals;
use pelt_geom::topology::{self, CornerNormals, Topology};
use pelt_geom::weld::{key_bits, weld};
use pelt_geom::{gradient, mikktspace};
use rayon::prelude::*;
use serde::Serialize;

use crate::comb;
use crate::frame::Frame;
use crate::options::{
    BakeOptions, CombSource, GeneratedComb, TangentGenerator, TangentMode, TopologyMode,
};
use crate::vertex_pass::{self, CHUNK, Writes};

/// Where the output tangents came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TangentSource {
    /// The file's TANGENT was kept.
    Kept,
    /// MikkTSpace generated them.
    Mikktspace,
    /// The per-vertex UV-gradient frame (`pelt_geom::gradient`; no normal map needs them).
    Gradient,
}

impl TangentSource {
    /// The name the report and `extras.pelt.tangents` use.
    pub fn name(self) -> &'static str {
        match self {
            TangentSource::Kept => "kept",
            TangentSource::Mikktspace => "mikktspace",
            TangentSource::Gradient => "gradient",
        }
    }
}

/// Topology counts for the report.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct TopologyStats {
    /// Distinct positions after welding.
    pub welded_positions: usize,
    /// Normal groups (connected components of the face dual graph).
    pub normal_groups: usize,
    /// Distinct group IDs written.
    pub ids_used: usize,
    /// Vertices added so that every face sees its own group ID (some may also have been split
    /// for normals or tangents).
    pub group_split_vertices: usize,
    /// Pairs of groups sharing an edge or a vertex.
    pub neighbour_group_pairs: usize,
    /// Neighbouring pairs that share an ID (0 unless the IDs could not separate them).
    pub shared_id_pairs: usize,
    /// Groups left sharing an ID with a neighbour.
    pub uncolorable_groups: usize,
    /// Most groups meeting at one position.
    pub most_groups_at_a_vertex: usize,
    /// Neighbouring pairs the paper's random 8-bit IDs would have given the same ID (one
    /// seeded draw).
    pub random_id_collisions: usize,
    /// Unique welded edges of proper triangles.
    pub edges: usize,
    /// Edges with one face.
    pub boundary_edges: usize,
    /// Edges with three or more faces.
    pub nonmanifold_edges: usize,
    /// Fin edges written.
    pub fin_edges: usize,
    /// Edges left out of the fins: no vertex beside them has fur.
    pub bare_edges: usize,
}

impl TopologyStats {
    fn new(t: &Topology, ids: &GroupIds) -> Self {
        TopologyStats {
            welded_positions: t.positions,
            normal_groups: t.groups,
            ids_used: ids.ids_used,
            neighbour_group_pairs: ids.neighbour_pairs,
            shared_id_pairs: ids.shared_id_pairs,
            uncolorable_groups: ids.uncolorable_groups,
            most_groups_at_a_vertex: ids.most_groups_at_a_vertex,
            random_id_collisions: ids.random_collisions,
            edges: t.edges.len(),
            boundary_edges: t.boundary_edges(),
            nonmanifold_edges: t.nonmanifold_edges(),
            ..TopologyStats::default()
        }
    }

    fn warnings(&self, out: &mut Vec<String>) {
        if self.nonmanifold_edges > 0 {
            out.push(format!(
                "{} of {} edges are shared by three or more triangles (non-manifold): a fin \
                 along such an edge stands between its two lowest triangles only, and a \
                 repeated triangle draws its shells twice (denser fur there)",
                self.nonmanifold_edges, self.edges
            ));
        }
        if self.shared_id_pairs > 0 {
            out.push(format!(
                "{} normal groups: {} neighbouring pairs share an ID ({} groups left without a free ID; up to {} groups meet at one vertex, 255 IDs exist)",
                self.normal_groups,
                self.shared_id_pairs,
                self.uncolorable_groups,
                self.most_groups_at_a_vertex
            ));
        }
    }
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
    /// Triangles with zero area (or collapsed by `--weld-epsilon`).
    pub degenerate_triangles: usize,
    /// Triangles with zero UV area or derivatives (MikkTSpace's fallback applies).
    pub degenerate_uv_triangles: usize,
    /// The source had no NORMAL: flat normals were generated (`--crease-angle 0`).
    pub flat_normals: bool,
    /// The source had no NORMAL: smooth normals were generated (crease angle above 0).
    pub smooth_normals: bool,
    /// The comb was generated along an axis (`--comb generate`), not read from COLOR_0.
    pub generated_comb: bool,
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
    /// Topology.
    #[serde(flatten)]
    pub topology: TopologyStats,
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
    /// `_NORMAL_GROUP`: the group ID of every output vertex (0 for a vertex no face uses);
    /// empty with `--topology off`.
    pub normal_group: Vec<u16>,
    /// Fin edges, referring to output vertices (None unless `--topology full`).
    pub fins: Option<Vec<FinEdge>>,
    /// Counts.
    pub stats: PrimitiveStats,
    /// Things the user should know.
    pub warnings: Vec<String>,
    /// Time spent on topology (groups, IDs, fins), in milliseconds.
    pub topology_ms: f64,
}

/// The comb's fallbacks, said aloud: combs along the normal (or straight into the surface),
/// which nothing is left of on the surface and which point along the tangent instead; fur of
/// length 0 everywhere (every comb grey, or alpha 0); and fur without TEXCOORD_0, which the
/// shells' strand textures and the strand reference are laid out by.
fn comb_warnings(stats: &PrimitiveStats, comb: &[[f32; 4]], has_uvs: bool, out: &mut Vec<String>) {
    let n = comb.len();
    if stats.parallel_combs > 0 {
        out.push(format!(
            "{} of {n} vertices' combs lie along the normal or point straight into the surface \
             (within {:.2}°): no direction is left on the surface, so the fur there is combed \
             along the tangent (+U) instead",
            stats.parallel_combs,
            comb::PARALLEL_TOLERANCE.to_degrees()
        ));
    }
    let furred = comb.iter().filter(|c| c[3] > 0.0).count();
    if n > 0 && furred == 0 {
        let why = if stats.gray_combs == n {
            "every comb is grey (no direction painted)".to_owned()
        } else if stats.gray_combs == 0 {
            "every comb has alpha 0".to_owned()
        } else {
            format!(
                "{} combs are grey and the rest have alpha 0",
                stats.gray_combs
            )
        };
        out.push(format!(
            "no fur: {why}, so the fur length is 0 at every vertex"
        ));
    } else if !has_uvs && furred > 0 {
        out.push(
            "no TEXCOORD_0: the fur's strand textures are laid out by it, so shells draw \
             untextured fur and the strand reference grows no strands on this primitive"
                .to_owned(),
        );
    }
}

/// Per-vertex or per-corner data; per-vertex data is borrowed from the mesh when usable as is.
enum Attr<'a, T: Clone> {
    Vertex(Cow<'a, [T]>),
    Corner(Vec<T>),
}

impl<T: Copy> Attr<'_, T> {
    #[inline]
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

/// Bakes one primitive. The mesh must have passed [`Mesh::validate`] and carry COLOR_0 unless
/// the comb is generated.
pub fn bake_primitive(mesh: &Mesh, opts: &BakeOptions) -> BakedPrimitive {
    bake_primitive_with(mesh, opts, None)
}

/// [`bake_primitive`] with a generated comb's length scaled per vertex by `lengths` (a texture
/// channel sampled at each vertex; see [`crate::options::LengthTexture`]).
pub fn bake_primitive_with(
    mesh: &Mesh,
    opts: &BakeOptions,
    lengths: Option<&[f32]>,
) -> BakedPrimitive {
    let mut stats = PrimitiveStats {
        vertices_in: mesh.vertex_count(),
        triangles: mesh.triangle_count(),
        ..PrimitiveStats::default()
    };
    let mut warnings = Vec::new();
    let idx = &mesh.indices;

    // Normals: per vertex when the file's are usable, per corner otherwise.
    let (normals, rewrite_normals) = source_normals(mesh, opts, &mut stats, &mut warnings);

    // Tangents: kept (per vertex), MikkTSpace (per corner) or the gradient frame (per vertex).
    let (keep, kept, source) = tangent_source(mesh, opts, &mut warnings);
    stats.tangents = Some(source);

    // MikkTSpace first: its working memory is freed before the topology's is taken.
    let mikktspace = (source == TangentSource::Mikktspace).then(|| {
        if mesh.uvs.is_none() {
            warnings.push("no TEXCOORD_0: tangents follow MikkTSpace's fallback frame".to_owned());
        }
        generate_tangents(mesh, &normals, &mut stats)
    });

    // Kept tangents whose w is not exactly ±1 are rewritten with its sign.
    if let Some(ts) = kept {
        stats.tangent_w_fixed = ts
            .par_iter()
            .with_min_len(CHUNK)
            .filter(|t| t.w != 1.0 && t.w != -1.0)
            .count();
    }
    // Generated tangents are written as their frame's (projected, unit, w = ±1).
    let generated = source != TangentSource::Kept;
    let write = Writes {
        normals: rewrite_normals,
        tangents: generated || stats.tangent_w_fixed > 0,
    };
    // TANGENT as written: the frame's where generated or unusable, else the kept xyz with
    // w made exactly ±1.
    let tangent_out = |frame: &Frame, degenerate: bool, t: Vec4| {
        if degenerate || generated {
            frame.tangent4()
        } else {
            [t.x, t.y, t.z, crate::frame::handedness(t.w) as f32]
        }
    };
    // The comb of a source vertex in a frame: painted, or generated along `flow`.
    let generate = match opts.comb {
        CombSource::Generate(g) => Some(g),
        CombSource::Painted => None,
    };
    stats.generated_comb = generate.is_some();
    let colors = mesh.colors.as_deref().unwrap_or_default();
    let comb_at = |v: usize, frame: &Frame, flow: Option<&[Vec3]>| {
        let (d, len) = match (flow, generate) {
            (Some(dirs), Some(g)) => (
                dirs[v].as_dvec3(),
                f64::from(g.length) * lengths.map_or(1.0, |l| f64::from(l[v])),
            ),
            _ => comb::decode_color(
                colors.get(v).copied().unwrap_or(Vec4::ONE),
                opts.color_space,
                &opts.axes,
            ),
        };
        comb::bake(d, len, frame)
    };

    // Topology over the normals as written: groups, their IDs. Beside it, none of which needs
    // the groups: the gradient frame (one sequential pass), a generated comb's flow, and, where
    // every vertex's normal and tangent are its own, the per-vertex pass over the source
    // vertices (split vertices copy their source's results). The topology, the longer, starts
    // at once on this thread; another takes the rest when it wakes.
    let ((mut topo, mut topology_ms), side) = rayon::join(
        || primitive_topology(mesh, &normals, opts),
        || {
            beside_topology(
                mesh,
                source,
                generate,
                kept,
                &normals,
                &comb_at,
                &tangent_out,
                write,
            )
        },
    );
    let (gradient, flow, early) = side;
    let tangents = framing_tangents(mesh, kept, mikktspace, gradient, &mut stats, &mut warnings);

    match &topo {
        Some((t, ids)) => {
            stats.degenerate_triangles = t.degenerate_faces();
            stats.topology = TopologyStats::new(t, ids);
        }
        None => stats.degenerate_triangles = degenerate_triangles(mesh),
    }
    let groups = topo.as_ref().map_or(0, |(t, _)| t.groups);
    let corner_id = |c: usize| {
        topo.as_ref()
            .map_or(0, |(t, ids)| ids.id[t.face_group[c / 3] as usize])
    };

    // Output vertices: one per distinct (source vertex, normal, tangent, group ID).
    // With per-corner data, each output vertex reads it at the first corner that uses it.
    let (remap, first_corner) =
        output_vertices(mesh, &normals, &tangents, groups, &corner_id, &mut stats);
    let out_count = remap.as_ref().map_or(mesh.vertex_count(), |(m, _)| m.len());
    let map = remap.as_ref().map(|(m, _)| m.as_slice());
    stats.vertices_out = out_count;
    stats.split_vertices = out_count - mesh.vertex_count();

    // The (normal, tangent) an output vertex is framed by.
    let inputs = |o: usize| framed_by(mesh, &normals, &tangents, map, first_corner.as_deref(), o);

    // The per-vertex pass over the output vertices: copied from the source vertices' where it
    // ran beside the topology, else run now.
    let out = match (early, map) {
        (Some(src), Some(m)) => src.gather(m),
        (Some(src), None) => src,
        (None, _) => vertex_pass::run(
            out_count,
            &inputs,
            &|v, f| comb_at(v, f, flow.as_deref()),
            &tangent_out,
            write,
        ),
    };
    let counts = out.counts();
    stats.degenerate_tangents = counts.degenerate_tangents;
    stats.gray_combs = counts.gray;
    stats.parallel_combs = counts.parallel;
    let (comb, out_normals, mut out_tangents) = (out.comb, out.normals, out.tangents);
    comb_warnings(&stats, &comb, mesh.uvs.is_some(), &mut warnings);

    // The group ID of every output vertex: its first corner's face's.
    let normal_group: Vec<u16> = match &topo {
        None => Vec::new(),
        Some(_) => output_groups(out_count, first_corner.as_deref(), groups, &corner_id),
    };

    // Kept tangents that were unusable are replaced: only then is TANGENT rewritten.
    if out_tangents.is_none() && stats.degenerate_tangents > 0 {
        out_tangents = Some(replaced_tangents(out_count, &inputs, &tangent_out));
    }
    if stats.degenerate_tangents > 0 && keep {
        warnings.push(format!(
            "{} kept tangents were zero or along the normal and were replaced",
            stats.degenerate_tangents
        ));
    }
    // Fin edges over the output vertices, where there is fur.
    let t_fins = Instant::now();
    let fins = match &mut topo {
        Some((t, _)) if opts.topology_mode == TopologyMode::Full => {
            let out_indices = remap.as_ref().map_or(idx.as_slice(), |(_, i)| i.as_slice());
            Some(fin_edges(t, out_indices, &comb, &mut stats))
        }
        _ => None,
    };
    topology_ms += ms(t_fins);
    stats.topology.warnings(&mut warnings);
    BakedPrimitive {
        remap,
        normals: out_normals,
        tangents: out_tangents,
        comb,
        normal_group,
        fins,
        stats,
        warnings,
        topology_ms,
    }
}

/// A primitive without a painted comb: normal groups and their IDs only.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupedPrimitive {
    /// When vertices were split: (output vertex → source vertex, new indices).
    pub remap: Option<(Vec<u32>, Vec<u32>)>,
    /// `_NORMAL_GROUP` per output vertex.
    pub normal_group: Vec<u16>,
    /// Topology counts.
    pub stats: TopologyStats,
    /// Triangles with zero area.
    pub degenerate_triangles: usize,
    /// Things the user should know.
    pub warnings: Vec<String>,
    /// Time spent, in milliseconds.
    pub topology_ms: f64,
}

/// Normal groups of a primitive without a comb, from its own NORMAL (which must be present:
/// without it glTF clients shade flat, and every face would be a group of its own).
pub fn group_primitive(mesh: &Mesh, opts: &BakeOptions) -> Option<GroupedPrimitive> {
    let t0 = Instant::now();
    let ns = mesh.normals.as_ref()?;
    let idx = &mesh.indices;
    let topo = topology::build(
        &mesh.positions,
        idx,
        CornerNormals::Vertex(ns),
        &opts.topology,
    );
    let ids = group_ids::assign(&topo);
    let mut stats = TopologyStats::new(&topo, &ids);
    let corner_id = |c: usize| ids.id[topo.face_group[c / 3] as usize];
    let (remap, first_corner) = if topo.groups > 1 {
        let normals = Attr::Vertex(Cow::Borrowed(ns.as_slice()));
        let split = split_vertices(mesh, &normals, None, &corner_id);
        stats.group_split_vertices = split.for_ids;
        (split.remap, Some(split.first_corner))
    } else {
        (None, None)
    };
    let out_count = remap.as_ref().map_or(mesh.vertex_count(), |(m, _)| m.len());
    let normal_group: Vec<u16> = match &first_corner {
        Some(f) => f
            .par_iter()
            .with_min_len(CHUNK)
            .map(|&c| {
                if c == u32::MAX {
                    0
                } else {
                    u16::from(corner_id(c as usize))
                }
            })
            .collect(),
        None => vec![ids.id.first().map_or(0, |&i| u16::from(i)); out_count],
    };
    let mut warnings = Vec::new();
    stats.warnings(&mut warnings);
    Some(GroupedPrimitive {
        remap,
        normal_group,
        degenerate_triangles: topo.degenerate_faces(),
        stats,
        warnings,
        topology_ms: ms(t0),
    })
}

/// The normals step: per vertex when the file's are usable (borrowed when already unit), per
/// corner (flat, or smooth with a crease angle) otherwise; with whether NORMAL is rewritten.
fn source_normals<'a>(
    mesh: &'a Mesh,
    opts: &BakeOptions,
    stats: &mut PrimitiveStats,
    warnings: &mut Vec<String>,
) -> (Attr<'a, Vec3>, bool) {
    let idx = &mesh.indices;
    match &mesh.normals {
        Some(ns) => {
            let (zero, renormalized) = ns
                .par_iter()
                .with_min_len(CHUNK)
                .map(|&n| match normalize_f64(n) {
                    None => (1, 0),
                    Some(_) => (
                        0,
                        usize::from((n.as_dvec3().length() - 1.0).abs() > UNIT_TOLERANCE),
                    ),
                })
                .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
            stats.zero_normals = zero;
            stats.renormalized_normals = renormalized;
            if zero > 0 {
                (
                    Attr::Corner(corner_normals(&mesh.positions, Some(ns), idx).0),
                    true,
                )
            } else if renormalized > 0 {
                let unit = ns
                    .par_iter()
                    .with_min_len(CHUNK)
                    .map(|&n| normalize_f64(n).map_or(Vec3::Z, |u| u.as_vec3()))
                    .collect();
                (Attr::Vertex(Cow::Owned(unit)), true)
            } else {
                (Attr::Vertex(Cow::Borrowed(ns.as_slice())), false)
            }
        }
        None if opts.crease_angle <= 0.0 => {
            stats.flat_normals = true;
            warnings.push("no NORMAL: flat normals generated and written".to_owned());
            (
                Attr::Corner(corner_normals(&mesh.positions, None, idx).0),
                true,
            )
        }
        None => {
            stats.smooth_normals = true;
            warnings.push(format!(
                "no NORMAL: smooth normals generated (angle-weighted, crease angle {:.0}°) and \
                 written; glTF clients would shade it flat (--crease-angle 0 does that)",
                opts.crease_angle.to_degrees()
            ));
            (
                Attr::Corner(smooth_corner_normals(
                    &mesh.positions,
                    idx,
                    opts.crease_angle,
                )),
                true,
            )
        }
    }
}

/// The tangents' source: the file's, kept (`keep`; then they are borrowed), or generated by
/// MikkTSpace or the gradient frame.
fn tangent_source<'a>(
    mesh: &'a Mesh,
    opts: &BakeOptions,
    warnings: &mut Vec<String>,
) -> (bool, Option<&'a [Vec4]>, TangentSource) {
    let keep =
        opts.tangents == TangentMode::Keep && mesh.tangents.is_some() && mesh.normals.is_some();
    if mesh.tangents.is_some() && mesh.normals.is_none() {
        warnings.push(
            "TANGENT ignored: without NORMAL glTF clients must ignore it; regenerated".to_owned(),
        );
    }
    let kept = mesh.tangents.as_deref().filter(|_| keep);
    let source = match kept {
        Some(_) => TangentSource::Kept,
        None if opts.tangent_generator == TangentGenerator::Mikktspace => TangentSource::Mikktspace,
        None => TangentSource::Gradient,
    };
    (keep, kept, source)
}

/// The tangents the output is framed by: the kept ones, MikkTSpace's per corner, or the
/// gradient frame's (made beside the topology when the source is the gradient).
fn framing_tangents<'a>(
    mesh: &Mesh,
    kept: Option<&'a [Vec4]>,
    mikktspace: Option<Vec<Vec4>>,
    gradient: Option<gradient::GradientTangents>,
    stats: &mut PrimitiveStats,
    warnings: &mut Vec<String>,
) -> Attr<'a, Vec4> {
    match (kept, mikktspace) {
        (Some(ts), _) => Attr::Vertex(Cow::Borrowed(ts)),
        (None, Some(corners)) => Attr::Corner(corners),
        (None, None) => {
            if mesh.uvs.is_none() {
                warnings.push(
                    "no TEXCOORD_0: tangents are perpendiculars of the normal (no UV gradient)"
                        .to_owned(),
                );
            }
            // Made beside the topology (the source is Gradient here).
            let g = gradient.unwrap_or_else(|| {
                gradient::generate(&mesh.positions, mesh.uvs.as_deref(), &mesh.indices)
            });
            stats.degenerate_uv_triangles = g.degenerate_uv_triangles;
            Attr::Vertex(Cow::Owned(g.vertices))
        }
    }
}

/// The group ID of every output vertex: its first corner's face's (0 for a vertex no face
/// uses); with a single group, every vertex's without a first corner too.
fn output_groups(
    out_count: usize,
    first_corner: Option<&[u32]>,
    groups: usize,
    corner_id: &(impl Fn(usize) -> u8 + Sync),
) -> Vec<u16> {
    let only_id = (groups == 1).then(|| u16::from(corner_id(0)));
    (0..out_count)
        .into_par_iter()
        .with_min_len(CHUNK)
        .map(|o| match (first_corner, only_id) {
            (Some(f), _) if f[o] != u32::MAX => u16::from(corner_id(f[o] as usize)),
            (None, Some(id)) => id,
            _ => 0,
        })
        .collect()
}

/// The fins step: the topology's edges kept as fins where there is fur (a comb longer than
/// 0 on the edge), over the output vertices' `out_indices`.
fn fin_edges(
    t: &mut Topology,
    out_indices: &[u32],
    comb: &[[f32; 4]],
    stats: &mut PrimitiveStats,
) -> Vec<FinEdge> {
    let lengths: Vec<f32> = comb.par_iter().with_min_len(CHUNK).map(|c| c[3]).collect();
    let fur = if lengths.par_iter().all(|&l| l > 0.0) {
        fins::Fur::Everywhere
    } else {
        fins::Fur::Lengths(&lengths)
    };
    let edges = t.take_edges();
    let all = edges.len();
    let fins = fins::build(edges, out_indices, fur);
    stats.topology.fin_edges = fins.len();
    stats.topology.bare_edges = all - fins.len();
    fins
}

/// The topology step over the normals as written (none with `--topology off`): the groups
/// and their IDs, with the milliseconds it took.
fn primitive_topology(
    mesh: &Mesh,
    normals: &Attr<Vec3>,
    opts: &BakeOptions,
) -> (Option<(Topology, GroupIds)>, f64) {
    let t_topology = Instant::now();
    let topo = (opts.topology_mode != TopologyMode::Off).then(|| {
        let t = topology::build(
            &mesh.positions,
            &mesh.indices,
            corner_normals_of(normals),
            &opts.topology,
        );
        let ids = group_ids::assign(&t);
        (t, ids)
    });
    (topo, ms(t_topology))
}

/// Split vertices: output vertex → source vertex, and the new indices.
type Remap = (Vec<u32>, Vec<u32>);

/// The output vertices step: split where a source vertex's corners differ in normal, tangent
/// or group ID (none when every one is per vertex and there is one group); the remap and
/// each output vertex's first corner.
fn output_vertices(
    mesh: &Mesh,
    normals: &Attr<Vec3>,
    tangents: &Attr<Vec4>,
    groups: usize,
    corner_id: &(impl Fn(usize) -> u8 + Sync),
    stats: &mut PrimitiveStats,
) -> (Option<Remap>, Option<Vec<u32>>) {
    let per_corner = normals.is_corner() || tangents.is_corner() || groups > 1;
    if !per_corner {
        return (None, None);
    }
    let split = split_vertices(mesh, normals, Some(tangents), corner_id);
    stats.topology.group_split_vertices = split.for_ids;
    (split.remap, Some(split.first_corner))
}

/// TANGENT rewritten for every output vertex, when kept tangents were unusable: each framed
/// again from its (normal, tangent) and written as `tangent_out` writes it.
fn replaced_tangents(
    out_count: usize,
    inputs: &(impl Fn(usize) -> (usize, Vec3, Vec4) + Sync),
    tangent_out: &(impl Fn(&Frame, bool, Vec4) -> [f32; 4] + Sync),
) -> Vec<[f32; 4]> {
    (0..out_count)
        .into_par_iter()
        .with_min_len(CHUNK)
        .map(|o| {
            let (_, n, t) = inputs(o);
            let (frame, degenerate) = Frame::new(n, t);
            tangent_out(&frame, degenerate, t)
        })
        .collect()
}

/// The source vertex, normal and tangent output vertex `o` is framed by: its first corner's
/// where data is per corner, else its source vertex's (a vertex no triangle uses: the stored
/// normal, or +Z, and any tangent).
fn framed_by(
    mesh: &Mesh,
    normals: &Attr<Vec3>,
    tangents: &Attr<Vec4>,
    map: Option<&[u32]>,
    first_corner: Option<&[u32]>,
    o: usize,
) -> (usize, Vec3, Vec4) {
    let v = map.map_or(o, |m| m[o] as usize);
    let c = first_corner.map_or(u32::MAX, |f| f[o]);
    if c != u32::MAX {
        return (v, normals.at(v, c as usize), tangents.at(v, c as usize));
    }
    // Per-vertex data, or a vertex no triangle uses: stored normal (or +Z), any tangent.
    let n = match normals {
        Attr::Vertex(ns) => ns[v],
        Attr::Corner(_) => mesh
            .normals
            .as_ref()
            .and_then(|ns| normalize_f64(ns[v]))
            .map_or(Vec3::Z, |d| d.as_vec3()),
    };
    let t = match tangents {
        Attr::Vertex(ts) => ts[v],
        Attr::Corner(_) => Vec4::new(1.0, 0.0, 0.0, 1.0),
    };
    (v, n, t)
}

/// The work beside the topology, none of which needs the groups: the gradient frame (when it
/// is the tangents' source), a generated comb's flow, and, where every vertex's normal and
/// tangent are its own, the per-vertex pass over the source vertices.
#[expect(
    clippy::too_many_arguments,
    reason = "the bake's inputs and its two closures, passed as they are to the vertex pass"
)]
fn beside_topology(
    mesh: &Mesh,
    source: TangentSource,
    generate: Option<GeneratedComb>,
    kept: Option<&[Vec4]>,
    normals: &Attr<Vec3>,
    comb_at: &(impl Fn(usize, &Frame, Option<&[Vec3]>) -> ([f32; 4], comb::CombCase) + Sync),
    tangent_out: &(impl Fn(&Frame, bool, Vec4) -> [f32; 4] + Sync),
    write: Writes,
) -> (
    Option<gradient::GradientTangents>,
    Option<Vec<Vec3>>,
    Option<vertex_pass::VertexOut>,
) {
    let idx = &mesh.indices;
    let gradient = (source == TangentSource::Gradient)
        .then(|| gradient::generate(&mesh.positions, mesh.uvs.as_deref(), idx));
    let flow = generate.map(|g| comb_flow(&mesh.positions, idx, Vec3::from(g.axis), g.smoothing));
    let vertex_tangents = kept.or(gradient.as_ref().map(|g| g.vertices.as_slice()));
    let early = match (normals, vertex_tangents) {
        (Attr::Vertex(ns), Some(ts)) => Some(vertex_pass::run(
            mesh.vertex_count(),
            &|v| (v, ns[v], ts[v]),
            &|v, f| comb_at(v, f, flow.as_deref()),
            tangent_out,
            write,
        )),
        _ => None,
    };
    (gradient, flow, early)
}

/// The normals topology compares, borrowed from the bake's.
fn corner_normals_of<'a>(normals: &'a Attr<'_, Vec3>) -> CornerNormals<'a> {
    match normals {
        Attr::Vertex(v) => CornerNormals::Vertex(v),
        Attr::Corner(c) => CornerNormals::Corner(c),
    }
}

/// Triangles with zero area (when topology, which counts them too, is off).
fn degenerate_triangles(mesh: &Mesh) -> usize {
    mesh.indices
        .par_chunks_exact(3)
        .with_min_len(CHUNK)
        .filter(|t| {
            let p = |k: usize| mesh.positions[t[k] as usize];
            face_normal(p(0), p(1), p(2)).is_none()
        })
        .count()
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
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
    result.corners
}

/// The vertex split: the new vertex table (when any vertex was split), the first corner of
/// every output vertex (`u32::MAX` for a vertex no triangle uses), and how many (vertex, group
/// ID) pairs needed a vertex of their own.
struct Split {
    remap: Option<(Vec<u32>, Vec<u32>)>,
    first_corner: Vec<u32>,
    for_ids: usize,
}

/// Splits vertices whose corners disagree (normal, tangent or group ID). Each vertex keeps its
/// slot with the values of its first corner; corners that differ from it get new vertices
/// appended after the originals (one per distinct (vertex, normal, tangent, ID)). The remap is
/// (output vertex → source vertex, new indices), or None when the corners of every vertex
/// agree.
fn split_vertices(
    mesh: &Mesh,
    normals: &Attr<Vec3>,
    tangents: Option<&Attr<Vec4>>,
    corner_id: &(impl Fn(usize) -> u8 + Sync),
) -> Split {
    let idx = &mesh.indices;
    let nv = mesh.vertex_count();
    let key = |c: usize| {
        let v = idx[c] as usize;
        let n = normals.at(v, c);
        let t = tangents.map_or(Vec4::ZERO, |t| t.at(v, c));
        let b = [n.x, n.y, n.z, t.x, t.y, t.z, t.w].map(key_bits);
        [
            b[0],
            b[1],
            b[2],
            b[3],
            b[4],
            b[5],
            b[6],
            u32::from(corner_id(c)),
        ]
    };
    let mut first_corner = vec![u32::MAX; nv];
    for (c, &v) in idx.iter().enumerate() {
        let f = &mut first_corner[v as usize];
        if *f == u32::MAX {
            *f = c as u32;
        }
    }
    let differing: Vec<usize> = (0..idx.len())
        .into_par_iter()
        .with_min_len(CHUNK)
        .filter(|&c| {
            let f = first_corner[idx[c] as usize] as usize;
            f != c && key(f) != key(c)
        })
        .collect();
    if differing.is_empty() {
        return Split {
            remap: None,
            first_corner,
            for_ids: 0,
        };
    }
    // (vertex, ID) pairs beyond each vertex's first: the duplication group IDs alone need.
    let other_id: Vec<usize> = differing
        .par_iter()
        .with_min_len(CHUNK)
        .copied()
        .filter(|&c| corner_id(c) != corner_id(first_corner[idx[c] as usize] as usize))
        .collect();
    let for_ids = weld(other_id.len(), |k| {
        let c = other_id[k];
        [idx[c], u32::from(corner_id(c))]
    })
    .1;
    let (ids, count) = weld(differing.len(), |k| {
        let c = differing[k];
        let q = key(c);
        [idx[c], q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7]]
    });
    let mut map: Vec<u32> = (0..nv as u32).collect();
    map.resize(nv + count, 0);
    first_corner.resize(nv + count, u32::MAX);
    let mut indices = idx.clone();
    for (&c, &id) in differing.iter().zip(&ids) {
        let o = nv + id as usize;
        map[o] = idx[c];
        indices[c] = o as u32;
        // `differing` ascends, so the first corner seen for a new vertex is its first.
        if first_corner[o] == u32::MAX {
            first_corner[o] = c as u32;
        }
    }
    Split {
        remap: Some((map, indices)),
        first_corner,
        for_ids,
    }
}
