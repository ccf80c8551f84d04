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

use glam::{Vec2, Vec3};
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
    pub corners: Vec<[f32; 4]>,
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
    let pos = |c: usize| V3::new(positions[indices[c] as usize].to_array());
    let nrm = |c: usize| V3::new(normals[indices[c] as usize].to_array());

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
    for (c, &w) in wid.iter().enumerate() {
        if !faces[c / 3].degenerate {
            fan[fill[w as usize] as usize] = c as u32;
            fill[w as usize] += 1;
        }
    }
    drop(fill);
    let fan_of = |w: u32| &fan[fan_start[w as usize] as usize..fan_start[w as usize + 1] as usize];

    // Neighbour across each edge (edge e runs from corner e to corner e+1).
    let mut neighbours = vec![NONE; 3 * nf];
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

    // The 4-rule groups, a depth-first walk around each vertex as in the reference (the order
    // matters where a face without usable UVs takes the orientation of the first group that
    // reaches it).
    let mut assigned = vec![NONE; 3 * nf];
    let mut group_rep = Vec::<u32>::new();
    let mut group_orient = Vec::<bool>::new();
    let mut group_start = vec![0u32];
    let mut group_faces = Vec::<u32>::with_capacity(3 * nf);
    let mut stack = Vec::<u32>::new();
    for f in 0..nf {
        if faces[f].degenerate || faces[f].any {
            continue;
        }
        for k in 0..3 {
            if assigned[3 * f + k] != NONE {
                continue;
            }
            let gid = group_rep.len() as u32;
            let rep = wid[3 * f + k];
            let orient = faces[f].orient;
            group_rep.push(rep);
            group_orient.push(orient);
            group_faces.push(f as u32);
            assigned[3 * f + k] = gid;
            stack.push(neighbours[3 * f + k]);
            stack.push(neighbours[3 * f + (k + 2) % 3]);
            while let Some(t) = stack.pop() {
                if t == NONE {
                    continue;
                }
                let t = t as usize;
                let Some(i) = (0..3).find(|&i| wid[3 * t + i] == rep) else {
                    continue;
                };
                if assigned[3 * t + i] != NONE {
                    continue;
                }
                if faces[t].any && assigned[3 * t..3 * t + 3].iter().all(|&a| a == NONE) {
                    faces[t].orient = orient;
                }
                if faces[t].orient != orient {
                    continue;
                }
                group_faces.push(t as u32);
                assigned[3 * t + i] = gid;
                stack.push(neighbours[3 * t + i]);
                stack.push(neighbours[3 * t + (i + 2) % 3]);
            }
            group_start.push(group_faces.len() as u32);
        }
    }

    // Evaluate every group (in parallel blocks) and scatter to corners.
    const BLOCK: usize = 2048;
    let groups = group_rep.len();
    let results: Vec<Vec<(u32, V3, bool)>> = (0..groups.div_ceil(BLOCK))
        .into_par_iter()
        .map(|b| {
            let mut out = Vec::new();
            let mut scratch = GroupScratch::default();
            for g in b * BLOCK..groups.min((b + 1) * BLOCK) {
                let members = &group_faces[group_start[g] as usize..group_start[g + 1] as usize];
                let rep = group_rep[g];
                let corner_of = |f: u32| {
                    let f = f as usize;
                    3 * f + (0..3).find(|&i| wid[3 * f + i] == rep).unwrap_or(0)
                };
                // Every member shares the welded vertex, hence the normal.
                let n = nrm(corner_of(members[0]));
                evaluate_group(members, &faces, n, &corner_of, &pos, &mut scratch);
                for (&a, &s) in members.iter().zip(&scratch.result) {
                    out.push((corner_of(a) as u32, s, group_orient[g]));
                }
            }
            out
        })
        .collect();

    let mut space: Vec<Option<(V3, bool)>> = vec![None; 3 * nf];
    for &(c, s, o) in results.iter().flatten() {
        space[c as usize] = Some((s, o));
    }

    // Degenerate triangles copy the space of the first proper corner at the same welded vertex.
    for f in (0..nf).filter(|&f| faces[f].degenerate) {
        for k in 0..3 {
            let c = 3 * f + k;
            if let Some(&src) = fan_of(wid[c]).first() {
                space[c] = space[src as usize];
            }
        }
    }

    let default_corners = space.iter().filter(|s| s.is_none()).count();
    let corners = space
        .iter()
        .map(|s| match s {
            Some((s, o)) => [s.x, s.y, s.z, if *o { 1.0 } else { -1.0 }],
            None => [1.0, 0.0, 0.0, -1.0],
        })
        .collect();
    Tangents {
        corners,
        stats: TangentStats {
            degenerate_triangles: faces.iter().filter(|f| f.degenerate).count(),
            degenerate_uv_triangles: faces.iter().filter(|f| !f.degenerate && f.any).count(),
            default_corners,
        },
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
    /// Memberships of the sub-groups (over `sorted`), one after another.
    masks: Vec<bool>,
    /// Membership being built.
    member: Vec<bool>,
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
    let k = members.len();
    for &a in members {
        let ia = sc.sorted.binary_search(&a).unwrap_or(0);
        let (sa, ta) = sc.projected[ia];
        let any_a = faces[a as usize].any;
        sc.member.clear();
        sc.member
            .extend(sc.sorted.iter().zip(&sc.projected).map(|(&bf, &(sb, tb))| {
                let meets =
                    sa.dot(sb) > ANGULAR_THRESHOLD_COS && ta.dot(tb) > ANGULAR_THRESHOLD_COS;
                any_a || faces[bf as usize].any || a == bf || meets
            }));
        let found = sc
            .subgroups
            .iter()
            .find(|(off, _)| sc.masks[*off..*off + k] == sc.member[..]);
        let s = match found {
            Some((_, s)) => *s,
            None => {
                let sub = sc
                    .sorted
                    .iter()
                    .zip(&sc.member)
                    .filter(|(_, m)| **m)
                    .map(|(&f, _)| f);
                let s = evaluate(sub, faces, n, corner_of, pos);
                sc.subgroups.push((sc.masks.len(), s));
                sc.masks.extend_from_slice(&sc.member);
                s
            }
        };
        sc.result.push(s);
    }
}

/// Angle-weighted average of the projected tangents of a sub-group (faces in ascending order).
fn evaluate(
    sub: impl Iterator<Item = u32>,
    faces: &[Face],
    n: V3,
    corner_of: &impl Fn(u32) -> usize,
    pos: &impl Fn(usize) -> V3,
) -> V3 {
    let mut res = V3::ZERO;
    for f in sub {
        let face = &faces[f as usize];
        if face.any {
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
        res = res.plus(face.s.project_normalized(n).scale(angle));
    }
    res.normalized_or_zero()
}
