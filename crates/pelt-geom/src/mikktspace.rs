//! MikkTSpace tangents (Mikkelsen 2008/2011, the generator glTF 2.0 names for meshes without
//! TANGENT), reimplemented for speed and checked bit for bit against `bevy_mikktspace`, a
//! faithful port of the reference C code (see `tests/mikktspace_oracle.rs`).
//!
//! The steps are the reference's: per-triangle first-order derivatives (eqs. 18-19 of the
//! thesis) and orientation; welding of identical (position, normal, UV) corners; triangle
//! neighbours across welded edges of opposite direction; the "4-rule" groups of faces around
//! each vertex with one orientation; sub-groups by the angular threshold (180 degrees, as in
//! the reference default); angle-weighted averaging; degenerate triangles copying the space of
//! a proper triangle at the same welded vertex.
//!
//! What differs is only how: hash welding instead of a k-d split, vertex fans instead of a
//! global edge sort, and rayon over faces and groups. The result is identical except in one
//! place: where three or more faces share one edge (non-manifold), the reference pairs faces in
//! the order its (off-by-one) quicksort leaves them for the largest vertex id; pelt pairs them in
//! face order everywhere. Triangles only (glTF primitives are triangles).

use std::collections::HashMap;

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use crate::fastmath::{V3, not_zero};
use crate::weld::{key_bits, weld};

const NONE: u32 = u32::MAX;

/// cos of the reference's default angular threshold (180 degrees): sub-groups split only
/// where projected derivatives point exactly opposite.
const ANGULAR_THRESHOLD_COS: f32 = -1.0;

/// Tangents per corner and what the generator met on the way.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Tangents {
    /// One tangent per corner (`indices.len()`): xyz as generated, w = +1 or -1. xyz is unit
    /// except where the reference yields zero (a face whose UV derivative lies along the normal);
    /// callers decide the fallback there.
    pub corners: Vec<Vec4>,
    /// What happened, for the report.
    pub stats: TangentStats,
}

/// Counts of the special cases, for the report.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TangentStats {
    /// Triangles with two coincident corners; their corners copy a neighbour's tangent space.
    pub degenerate_triangles: usize,
    /// Proper triangles with zero UV area or zero derivatives; they take their neighbours'.
    pub degenerate_uv_triangles: usize,
    /// Corners no group reached; they get the reference default (1, 0, 0, -1).
    pub default_corners: usize,
}

#[derive(Clone, Copy)]
struct Face {
    s: V3,
    t: V3,
    orient: bool,
    any: bool,
    degenerate: bool,
}

/// Generates MikkTSpace tangents for an indexed triangle list. `positions`, `normals` (unit) and
/// `uvs` are per vertex; `indices.len()` must be a multiple of three with every index in range.
pub fn generate(positions: &[Vec3], normals: &[Vec3], uvs: &[Vec2], indices: &[u32]) -> Tangents {
    let nf = indices.len() / 3;

    // Welded id per corner: identical position, normal and UV.
    let (vertex_weld, welded) = weld(positions.len(), |v| {
        let (p, n, t) = (positions[v], normals[v], uvs[v]);
        [p.x, p.y, p.z, n.x, n.y, n.z, t.x, t.y].map(key_bits)
    });
    let wid: Vec<u32> = indices
        .par_iter()
        .map(|&v| vertex_weld[v as usize])
        .collect();

    let mut faces: Vec<Face> = (0..nf)
        .into_par_iter()
        .with_min_len(4096)
        .map(|f| {
            let p = [0, 1, 2].map(|k| positions[indices[3 * f + k] as usize].to_array());
            let tx = [0, 1, 2].map(|k| uvs[indices[3 * f + k] as usize].to_array());
            face_info(p, tx)
        })
        .collect();

    // Fans: the proper-face corners of each welded vertex, in corner order.
    let (fan_start, fan, fan_pos) = fans(&wid, &faces, welded);

    // Neighbour across each edge (edge e runs from corner e to corner e+1).
    let neighbours = edge_neighbours(&faces, &wid, &fan_start, &fan);

    // The 4-rule groups: around each welded vertex, the faces connected across shared edges
    // with one orientation. Each corner's tangent space is written at its place in `fan`
    // (w = ±1; w = 0 while no group has reached it).
    let mut fan_space = vec![[0.0f32; 4]; fan.len()];
    let ctx = Context {
        wid: &wid,
        fan: &fan,
        fan_start: &fan_start,
        neighbours: &neighbours,
        positions,
        normals,
        indices,
    };

    // A face without usable UVs takes the orientation of the first group that reaches it, so
    // around vertices with such faces the walk must follow the reference's global order:
    // seeds in corner order, one at a time. Everywhere else groups are connected components,
    // independent of order, and vertices are done in parallel.
    let ordered: Vec<bool> = (0..welded)
        .into_par_iter()
        .with_min_len(4096)
        .map(|w| {
            ctx.fan_of(w as u32)
                .iter()
                .any(|&c| faces[c as usize / 3].any)
        })
        .collect();
    if ordered.iter().any(|&o| o) {
        ordered_groups(&ctx, &mut faces, &ordered, &fan_pos, &mut fan_space);
    }
    unordered_groups(&ctx, &faces, &ordered, &fan_start, &mut fan_space);

    // What the gather below needs of the faces; the rest is freed first, so the per-corner
    // result does not add to the walk's peak memory.
    let degenerate: Vec<bool> = faces.par_iter().map(|f| f.degenerate).collect();
    let degenerate_triangles = degenerate.iter().filter(|&&d| d).count();
    let degenerate_uv_triangles = faces.iter().filter(|f| !f.degenerate && f.any).count();
    drop((faces, neighbours, fan));

    // Each corner's space: its own, or for a degenerate triangle the space of the first proper
    // corner at the same welded vertex; corners no group reached get the reference default.
    let (corners, default_corners) = gather(&degenerate, &wid, &fan_start, &fan_pos, &fan_space);
    Tangents {
        corners,
        stats: TangentStats {
            degenerate_triangles,
            degenerate_uv_triangles,
            default_corners,
        },
    }
}

/// The fans step: the proper-face corners of each welded vertex, in corner order (`fan`,
/// vertex `w`'s from `fan_start[w]`), and each proper corner's place in `fan` (where its
/// tangent space will be written; `NONE` for a degenerate face's).
fn fans(wid: &[u32], faces: &[Face], welded: usize) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
    let nf = faces.len();
    let mut fan_start = vec![0u32; welded + 1];
    for (c, &w) in wid.iter().enumerate() {
        if !faces[c / 3].degenerate {
            fan_start[w as usize + 1] += 1;
        }
    }
    for i in 0..welded {
        fan_start[i + 1] += fan_start[i];
    }
    let mut fill = fan_start.clone();
    let mut fan = vec![0u32; fan_start[welded] as usize];
    // Each proper corner's position in `fan` (where its tangent space will be written).
    let mut fan_pos = vec![NONE; 3 * nf];
    for (c, &w) in wid.iter().enumerate() {
        if !faces[c / 3].degenerate {
            fan[fill[w as usize] as usize] = c as u32;
            fan_pos[c] = fill[w as usize];
            fill[w as usize] += 1;
        }
    }
    drop(fill);
    (fan_start, fan, fan_pos)
}

/// The neighbours step: for each edge of each proper face (edge e runs from corner e to
/// corner e+1), the face across it that pairs with it in its edge group, or `NONE`.
fn edge_neighbours(faces: &[Face], wid: &[u32], fan_start: &[u32], fan: &[u32]) -> Vec<u32> {
    let fan_of = |w: u32| &fan[fan_start[w as usize] as usize..fan_start[w as usize + 1] as usize];
    let mut neighbours = vec![NONE; 3 * faces.len()];
    neighbours
        .par_chunks_mut(3)
        .enumerate()
        .with_min_len(2048)
        .for_each_init(Vec::new, |entries: &mut Vec<(u32, bool)>, (f, out)| {
            if faces[f].degenerate {
                return;
            }
            for (e, slot) in out.iter_mut().enumerate() {
                let a = wid[3 * f + e];
                let b = wid[3 * f + (e + 1) % 3];
                entries.clear();
                let mut me = 0;
                for &c in fan_of(a) {
                    let (g, j) = (c as usize / 3, c as usize % 3);
                    if wid[3 * g + (j + 1) % 3] == b {
                        if g == f {
                            me = entries.len();
                        }
                        entries.push((g as u32, true));
                    } else if wid[3 * g + (j + 2) % 3] == b {
                        entries.push((g as u32, false));
                    }
                }
                *slot = pair_in_edge_group(entries, me);
            }
        });
    neighbours
}

/// The 4-rule groups around every vertex whose walk needs no global order, in parallel over
/// blocks of welded vertices: each group's tangent space written at its corners' places in
/// `fan_space` (w = ±1 by the group's orientation).
fn unordered_groups(
    ctx: &Context,
    faces: &[Face],
    ordered: &[bool],
    fan_start: &[u32],
    fan_space: &mut [[f32; 4]],
) {
    let welded = ordered.len();
    let faces_ref = faces;
    let mut blocks = Vec::new();
    let mut rest = fan_space;
    for w0 in (0..welded).step_by(4096) {
        let w1 = welded.min(w0 + 4096);
        let len = (fan_start[w1] - fan_start[w0]) as usize;
        let (run, tail) = rest.split_at_mut(len);
        blocks.push((w0..w1, run));
        rest = tail;
    }
    blocks.into_par_iter().for_each(|(range, run)| {
        let mut scratch = GroupScratch::default();
        let mut walk = Walk::default();
        let base = fan_start[range.start] as usize;
        for w in range.filter(|&w| !ordered[w]) {
            let at = fan_start[w] as usize - base;
            walk.groups(ctx, faces_ref, w as u32);
            for g in 0..walk.count() {
                let (members, places, orient) = walk.group(g);
                ctx.evaluate(w as u32, members, faces_ref, &mut scratch);
                let sign = if orient { 1.0 } else { -1.0 };
                for (&q, s) in places.iter().zip(&scratch.result) {
                    run[at + q as usize] = [s.x, s.y, s.z, sign];
                }
            }
        }
    });
}

/// The gather step: each corner's tangent space, its own, or for a degenerate triangle the
/// space of the first proper corner at the same welded vertex; corners no group reached get
/// the reference default (1, 0, 0, -1), and are counted.
fn gather(
    degenerate: &[bool],
    wid: &[u32],
    fan_start: &[u32],
    fan_pos: &[u32],
    fan_space: &[[f32; 4]],
) -> (Vec<Vec4>, usize) {
    let nf = degenerate.len();
    let source = |c: usize| -> Option<[f32; 4]> {
        let q = if degenerate[c / 3] {
            let w = wid[c] as usize;
            (fan_start[w] < fan_start[w + 1]).then_some(fan_start[w])?
        } else {
            fan_pos[c]
        };
        let s = fan_space[q as usize];
        (s[3] != 0.0).then_some(s)
    };
    let corners: Vec<Vec4> = (0..3 * nf)
        .into_par_iter()
        .with_min_len(4096)
        .map(|c| Vec4::from(source(c).unwrap_or([1.0, 0.0, 0.0, -1.0])))
        .collect();
    // Proper corners and fan entries correspond one to one; degenerate corners are few.
    let unreached = fan_space.par_iter().filter(|s| s[3] == 0.0).count();
    let degenerate_unreached = (0..nf)
        .filter(|&f| degenerate[f])
        .flat_map(|f| 3 * f..3 * f + 3)
        .filter(|&c| source(c).is_none())
        .count();
    let default_corners = unreached + degenerate_unreached;
    (corners, default_corners)
}

/// What the group walk and evaluation read.
struct Context<'a> {
    wid: &'a [u32],
    fan: &'a [u32],
    fan_start: &'a [u32],
    neighbours: &'a [u32],
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    indices: &'a [u32],
}

impl Context<'_> {
    /// The proper-face corners at welded vertex `w`, ascending.
    fn fan_of(&self, w: u32) -> &[u32] {
        &self.fan[self.fan_start[w as usize] as usize..self.fan_start[w as usize + 1] as usize]
    }

    /// The corner of face `f` at welded vertex `rep` (its first, as the reference finds it).
    fn corner_of(&self, rep: u32, f: u32) -> usize {
        let f = f as usize;
        3 * f + (0..3).find(|&i| self.wid[3 * f + i] == rep).unwrap_or(0)
    }

    fn pos(&self, c: usize) -> V3 {
        V3::new(self.positions[self.indices[c] as usize].to_array())
    }

    /// Tangent spaces of the members of one group around `rep`, into `scratch.result`.
    fn evaluate(&self, rep: u32, members: &[u32], faces: &[Face], scratch: &mut GroupScratch) {
        let corner_of = |f: u32| self.corner_of(rep, f);
        // Every member shares the welded vertex, hence the normal.
        let n = V3::new(self.normals[self.indices[corner_of(members[0])] as usize].to_array());
        evaluate_group(members, faces, n, &corner_of, &|c| self.pos(c), scratch);
    }
}

/// The groups around one welded vertex (reused between vertices).
#[derive(Default)]
struct Walk {
    /// Group index per fan entry of the vertex (NONE: not reached yet).
    assigned: Vec<u32>,
    /// Members (faces) of each group, one group after another.
    members: Vec<u32>,
    /// Each member's place in the vertex's fan.
    places: Vec<u32>,
    /// (start in `members`, orientation) per group.
    starts: Vec<(usize, bool)>,
    stack: Vec<u32>,
}

impl Walk {
    fn count(&self) -> usize {
        self.starts.len()
    }

    /// Group `g`: its member faces, their places in the fan, its orientation.
    fn group(&self, g: usize) -> (&[u32], &[u32], bool) {
        let (a, orient) = self.starts[g];
        let b = self.starts.get(g + 1).map_or(self.members.len(), |s| s.0);
        (&self.members[a..b], &self.places[a..b], orient)
    }

    /// The groups around welded vertex `w` whose faces all have usable UVs: the connected
    /// components, across shared edges, of the faces with one orientation.
    fn groups(&mut self, ctx: &Context, faces: &[Face], w: u32) {
        let fan_w = ctx.fan_of(w);
        self.assigned.clear();
        self.assigned.resize(fan_w.len(), NONE);
        self.members.clear();
        self.places.clear();
        self.starts.clear();
        for (p, &c) in fan_w.iter().enumerate() {
            if self.assigned[p] != NONE {
                continue;
            }
            let (f, k) = (c as usize / 3, c as usize % 3);
            let orient = faces[f].orient;
            let g = self.starts.len() as u32;
            self.starts.push((self.members.len(), orient));
            self.members.push(f as u32);
            self.places.push(p as u32);
            self.assigned[p] = g;
            self.stack.clear();
            self.stack.push(ctx.neighbours[3 * f + k]);
            self.stack.push(ctx.neighbours[3 * f + (k + 2) % 3]);
            while let Some(t) = self.stack.pop() {
                if t == NONE {
                    continue;
                }
                let t = t as usize;
                let Some(i) = (0..3).find(|&i| ctx.wid[3 * t + i] == w) else {
                    continue;
                };
                let Ok(q) = fan_w.binary_search(&((3 * t + i) as u32)) else {
                    continue;
                };
                if self.assigned[q] != NONE || faces[t].orient != orient {
                    continue;
                }
                self.members.push(t as u32);
                self.places.push(q as u32);
                self.assigned[q] = g;
                self.stack.push(ctx.neighbours[3 * t + i]);
                self.stack.push(ctx.neighbours[3 * t + (i + 2) % 3]);
            }
        }
    }
}

/// The groups around the `ordered` vertices, walked as the reference does: seeds in corner
/// order, depth first, a face without usable UVs taking the orientation of the first group that
/// reaches it. Writes their tangent spaces into `fan_space`.
fn ordered_groups(
    ctx: &Context,
    faces: &mut [Face],
    ordered: &[bool],
    fan_pos: &[u32],
    fan_space: &mut [[f32; 4]],
) {
    // Seeds: the corners at ordered vertices, in corner order, of faces with usable UVs.
    let mut seeds: Vec<u32> = ordered
        .iter()
        .enumerate()
        .filter(|&(_, &o)| o)
        .flat_map(|(w, _)| ctx.fan_of(w as u32).iter().copied())
        .collect();
    seeds.sort_unstable();
    // Group per corner; every corner met lies at an ordered vertex.
    let mut assigned: HashMap<u32, u32> = HashMap::new();
    let is_assigned = |a: &HashMap<u32, u32>, c: usize| a.contains_key(&(c as u32));
    let mut groups: Vec<(u32, bool, Vec<u32>)> = Vec::new();
    let mut stack = Vec::<u32>::new();
    for c in seeds {
        let (f, k) = (c as usize / 3, c as usize % 3);
        if faces[f].any || is_assigned(&assigned, 3 * f + k) {
            continue;
        }
        let rep = ctx.wid[3 * f + k];
        let gid = groups.len() as u32;
        let orient = faces[f].orient;
        let mut members = vec![f as u32];
        assigned.insert(c, gid);
        stack.push(ctx.neighbours[3 * f + k]);
        stack.push(ctx.neighbours[3 * f + (k + 2) % 3]);
        while let Some(t) = stack.pop() {
            if t == NONE {
                continue;
            }
            let t = t as usize;
            let Some(i) = (0..3).find(|&i| ctx.wid[3 * t + i] == rep) else {
                continue;
            };
            if is_assigned(&assigned, 3 * t + i) {
                continue;
            }
            if faces[t].any && (0..3).all(|j| !is_assigned(&assigned, 3 * t + j)) {
                faces[t].orient = orient;
            }
            if faces[t].orient != orient {
                continue;
            }
            members.push(t as u32);
            assigned.insert((3 * t + i) as u32, gid);
            stack.push(ctx.neighbours[3 * t + i]);
            stack.push(ctx.neighbours[3 * t + (i + 2) % 3]);
        }
        groups.push((rep, orient, members));
    }
    let faces = &*faces;
    let results: Vec<Vec<(u32, [f32; 4])>> = groups
        .par_chunks(256)
        .map(|chunk| {
            let mut scratch = GroupScratch::default();
            let mut out = Vec::new();
            for (rep, orient, members) in chunk {
                ctx.evaluate(*rep, members, faces, &mut scratch);
                let sign = if *orient { 1.0 } else { -1.0 };
                for (&f, s) in members.iter().zip(&scratch.result) {
                    out.push((fan_pos[ctx.corner_of(*rep, f)], [s.x, s.y, s.z, sign]));
                }
            }
            out
        })
        .collect();
    for (q, s) in results.into_iter().flatten() {
        fan_space[q as usize] = s;
    }
}

/// First-order tangent and bitangent of one triangle (thesis eqs. 18-19), in the reference's
/// order of operations.
fn face_info(p: [[f32; 3]; 3], tx: [[f32; 2]; 3]) -> Face {
    if p[0] == p[1] || p[1] == p[2] || p[2] == p[0] {
        return Face {
            s: V3::ZERO,
            t: V3::ZERO,
            orient: false,
            any: false,
            degenerate: true,
        };
    }
    let v = p.map(V3::new);
    let d_tx = [1, 2].map(|t| [0, 1].map(|i| tx[t][i] - tx[0][i]));
    let d_v = [v[1].minus(v[0]), v[2].minus(v[0])];
    let signed_area = d_tx[0][0] * d_tx[1][1] - d_tx[0][1] * d_tx[1][0];
    let area = signed_area.abs();
    let s = d_v[0].scale(d_tx[1][1]).minus(d_v[1].scale(d_tx[0][1]));
    let t = d_v[0].scale(-d_tx[1][0]).plus(d_v[1].scale(d_tx[0][0]));
    let orient = signed_area > 0.0;
    let mut face = Face {
        s: V3::ZERO,
        t: V3::ZERO,
        orient,
        any: true,
        degenerate: false,
    };
    if not_zero(area) {
        let sign = if orient { 1.0 } else { -1.0 };
        face.s = s.normalized_or_zero().scale(sign);
        face.t = t.normalized_or_zero().scale(sign);
        if not_zero(s.length() / area) && not_zero(t.length() / area) {
            face.any = false;
        }
    }
    face
}

/// Neighbour of entry `me` among all faces sharing one welded edge, given as (face, runs a→b)
/// in face order. The reference pairs greedily in that order: each unpaired entry takes the
/// first later unpaired entry running the other way.
fn pair_in_edge_group(entries: &[(u32, bool)], me: usize) -> u32 {
    if let [(f0, d0), (f1, d1)] = entries {
        return if d0 == d1 {
            NONE
        } else if me == 0 {
            *f1
        } else {
            *f0
        };
    }
    let mut partner = vec![NONE; entries.len()];
    for i in 0..entries.len() {
        if partner[i] != NONE {
            continue;
        }
        if let Some(j) =
            (i + 1..entries.len()).find(|&j| partner[j] == NONE && entries[j].1 != entries[i].1)
        {
            partner[i] = j as u32;
            partner[j] = i as u32;
        }
    }
    match partner.get(me) {
        Some(&p) if p != NONE => entries[p as usize].0,
        _ => NONE,
    }
}

/// Reused buffers for [`evaluate_group`].
#[derive(Default)]
struct GroupScratch {
    /// Members in ascending face order.
    sorted: Vec<u32>,
    /// Projected (s, t) per sorted member.
    projected: Vec<(V3, V3)>,
    /// Each distinct sub-group: where its membership starts in `masks`, and its tangent.
    subgroups: Vec<(usize, V3)>,
    /// Memberships of the sub-groups (bit j = sorted member j), `words` u64 each, in a row.
    masks: Vec<u64>,
    /// Membership being built.
    member: Vec<u64>,
    /// Result per member, in the group's order.
    result: Vec<V3>,
}

/// The tangent of every member of a group: each member's sub-group holds the members whose
/// projected derivatives agree with its own within the angular threshold; equal sub-groups are
/// evaluated once, summing in ascending face order as the reference does.
fn evaluate_group(
    members: &[u32],
    faces: &[Face],
    n: V3,
    corner_of: &impl Fn(u32) -> usize,
    pos: &impl Fn(usize) -> V3,
    sc: &mut GroupScratch,
) {
    sc.sorted.clear();
    sc.sorted.extend_from_slice(members);
    sc.sorted.sort_unstable();
    sc.projected.clear();
    sc.projected.extend(sc.sorted.iter().map(|&f| {
        let face = &faces[f as usize];
        (face.s.project_normalized(n), face.t.project_normalized(n))
    }));
    sc.subgroups.clear();
    sc.masks.clear();
    sc.result.clear();
    let words = members.len().div_ceil(64);
    // Common case: every pair agrees (or involves a face without usable UVs), so every
    // member's sub-group is the whole group and one evaluation serves all.
    let agree = |i: usize, j: usize| {
        let (fi, fj) = (sc.sorted[i] as usize, sc.sorted[j] as usize);
        let ((si, ti), (sj, tj)) = (sc.projected[i], sc.projected[j]);
        faces[fi].any
            || faces[fj].any
            || (si.dot(sj) > ANGULAR_THRESHOLD_COS && ti.dot(tj) > ANGULAR_THRESHOLD_COS)
    };
    let k = members.len();
    if (0..k).all(|i| (i + 1..k).all(|j| agree(i, j))) {
        sc.member.clear();
        sc.member.resize(words, u64::MAX);
        let s = evaluate(sc, faces, n, corner_of, pos);
        sc.result.resize(k, s);
        return;
    }
    for &a in members {
        let ia = sc.sorted.binary_search(&a).unwrap_or(0);
        let (sa, ta) = sc.projected[ia];
        let any_a = faces[a as usize].any;
        sc.member.clear();
        sc.member.resize(words, 0);
        for (j, (&bf, &(sb, tb))) in sc.sorted.iter().zip(&sc.projected).enumerate() {
            let meets = sa.dot(sb) > ANGULAR_THRESHOLD_COS && ta.dot(tb) > ANGULAR_THRESHOLD_COS;
            if any_a || faces[bf as usize].any || a == bf || meets {
                sc.member[j / 64] |= 1 << (j % 64);
            }
        }
        let found = sc
            .subgroups
            .iter()
            .find(|(off, _)| sc.masks[*off..*off + words] == sc.member[..]);
        let s = match found {
            Some((_, s)) => *s,
            None => {
                let s = evaluate(sc, faces, n, corner_of, pos);
                sc.subgroups.push((sc.masks.len(), s));
                sc.masks.extend_from_slice(&sc.member);
                s
            }
        };
        sc.result.push(s);
    }
}

/// Angle-weighted average of the projected tangents of the sub-group `sc.member` (summed in
/// ascending face order).
fn evaluate(
    sc: &GroupScratch,
    faces: &[Face],
    n: V3,
    corner_of: &impl Fn(u32) -> usize,
    pos: &impl Fn(usize) -> V3,
) -> V3 {
    let mut res = V3::ZERO;
    for (j, (&f, &(s, _))) in sc.sorted.iter().zip(&sc.projected).enumerate() {
        if sc.member[j / 64] & (1 << (j % 64)) == 0 || faces[f as usize].any {
            continue;
        }
        let c = corner_of(f);
        let base = c - c % 3;
        let i = c % 3;
        let p = [(i + 1) % 3, i, (i + 2) % 3].map(|k| pos(base + k));
        let v0 = p[0].minus(p[1]).project_normalized(n);
        let v1 = p[2].minus(p[1]).project_normalized(n);
        let cos = v0.dot(v1).clamp(-1.0, 1.0);
        let angle = f64::from(cos).acos() as f32;
        res = res.plus(s.scale(angle));
    }
    res.normalized_or_zero()
}
