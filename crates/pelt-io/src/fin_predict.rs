//! Fin records derived from the index list, for compressed output: a bake's fins are, on most
//! meshes, nearly all the edges of the triangle list, so a compressed file stores only how
//! they differ from the edges a reader can list itself (`extras.pelt.fins.fromIndices`,
//! `docs/format.md`). The prediction is defined by vertex indices alone, so that any reader
//! can compute it exactly:
//!
//! 1. every triangle with three different vertex indices contributes its three corners; corner
//!    `c` starts the edge {`indices[c]`, `indices[next(c)]`} (unordered);
//! 2. the corners of one edge, in ascending order, give one record: the first two (the second
//!    is `0xFFFFFFFF` when the edge has one);
//! 3. records are sorted by (first corner, second corner).
//!
//! The stored fins are then (prediction − removed) + added, in the same order. The writer
//! states every record with its lower face first, so that a manifold edge matches its
//! prediction; welded seams, degenerate faces and edges without fur are the exceptions.

use pelt_geom::fins::FinEdge;
use pelt_geom::topology::NO_CORNER;

/// A record's sort key.
fn key(e: &FinEdge) -> (u32, u32) {
    (e.corner, e.second_corner)
}

/// The record with its lower face's corner first (a boundary record as it is).
pub fn lower_first(e: FinEdge) -> FinEdge {
    if e.second_corner != NO_CORNER && e.second_corner < e.corner {
        FinEdge {
            corner: e.second_corner,
            second_corner: e.corner,
        }
    } else {
        e
    }
}

/// The edges of triangle list `indices` as fin records (module documentation, steps 1-3).
/// The corners are bucketed by their edge's lower vertex (a counting sort), so the cost is
/// linear in the corners; records come out in first-corner order without a sort.
pub fn predict(indices: &[u32]) -> Vec<FinEdge> {
    let proper = |f: usize| {
        let t = &indices[3 * f..3 * f + 3];
        t[0] != t[1] && t[1] != t[2] && t[0] != t[2]
    };
    let corners = indices.len() / 3 * 3;
    let low = |c: usize| indices[c].min(indices[c / 3 * 3 + (c + 1) % 3]) as usize;
    let high = |c: usize| indices[c].max(indices[c / 3 * 3 + (c + 1) % 3]);
    let vertices = indices.iter().max().map_or(0, |&m| m as usize + 1);
    let mut start = vec![0u32; vertices + 1];
    for c in (0..corners).filter(|&c| proper(c / 3)) {
        start[low(c) + 1] += 1;
    }
    for v in 0..vertices {
        start[v + 1] += start[v];
    }
    // Each bucket: (other end, corner), corners ascending as they are placed.
    let mut fill = start.clone();
    let mut sides = vec![(0u32, 0u32); start[vertices] as usize];
    for c in (0..corners).filter(|&c| proper(c / 3)) {
        let at = &mut fill[low(c)];
        sides[*at as usize] = (high(c), c as u32);
        *at += 1;
    }
    // Per edge, the record sits at its first corner.
    let mut second = vec![NO_RECORD; corners];
    for v in 0..vertices {
        let bucket = &mut sides[start[v] as usize..start[v + 1] as usize];
        bucket.sort_unstable();
        for g in bucket.chunk_by(|x, y| x.0 == y.0) {
            second[g[0].1 as usize] = g.get(1).map_or(NO_CORNER, |s| s.1);
        }
    }
    by_first_corner(&second)
}

/// In a table of second corners indexed by first corner: no record starts at this corner (an
/// index list is at most 2^28 elements, so this is never a corner).
pub(crate) const NO_RECORD: u32 = u32::MAX - 1;

/// The records of a table of second corners indexed by first corner, in first-corner order.
pub(crate) fn by_first_corner(second: &[u32]) -> Vec<FinEdge> {
    second
        .iter()
        .enumerate()
        .filter(|&(_, &s)| s != NO_RECORD)
        .map(|(c, &s)| FinEdge {
            corner: c as u32,
            second_corner: s,
        })
        .collect()
}

/// What turns sorted `predicted` into sorted `truth`: (added, removed), both sorted.
pub fn diff(truth: &[FinEdge], predicted: &[FinEdge]) -> (Vec<FinEdge>, Vec<FinEdge>) {
    let (mut added, mut removed) = (Vec::new(), Vec::new());
    let (mut i, mut j) = (0, 0);
    while i < truth.len() || j < predicted.len() {
        match (truth.get(i), predicted.get(j)) {
            (Some(t), Some(p)) if key(t) == key(p) => {
                i += 1;
                j += 1;
            }
            (Some(t), Some(p)) if key(t) < key(p) => {
                added.push(*t);
                i += 1;
            }
            (Some(t), None) => {
                added.push(*t);
                i += 1;
            }
            (_, Some(p)) => {
                removed.push(*p);
                j += 1;
            }
            (None, None) => break,
        }
    }
    (added, removed)
}

/// (`predicted` − `removed`) + `added`, sorted; None when a removed record is not predicted.
pub fn apply(
    predicted: &[FinEdge],
    added: &[FinEdge],
    removed: &[FinEdge],
) -> Option<Vec<FinEdge>> {
    let mut removed_sorted = removed.to_vec();
    removed_sorted.sort_unstable_by_key(key);
    let mut kept = Vec::with_capacity(predicted.len() + added.len());
    let mut r = removed_sorted.iter().peekable();
    for p in predicted {
        if r.peek().is_some_and(|x| key(x) == key(p)) {
            r.next();
        } else {
            kept.push(*p);
        }
    }
    if r.next().is_some() {
        return None;
    }
    let mut added_sorted = added.to_vec();
    added_sorted.sort_unstable_by_key(key);
    // Two sorted lists merged.
    let mut out = Vec::with_capacity(kept.len() + added_sorted.len());
    let (mut i, mut j) = (0, 0);
    while i < kept.len() || j < added_sorted.len() {
        let take_kept =
            j == added_sorted.len() || (i < kept.len() && key(&kept[i]) <= key(&added_sorted[j]));
        if take_kept {
            out.push(kept[i]);
            i += 1;
        } else {
            out.push(added_sorted[j]);
            j += 1;
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn e(corner: u32, second_corner: u32) -> FinEdge {
        FinEdge {
            corner,
            second_corner,
        }
    }

    #[test]
    fn a_quad_predicts_its_five_edges() {
        // (0 1 2) and (2 1 3) share edge 1-2: corner 1 starts it in face 0, corner 3 in face 1.
        let p = predict(&[0, 1, 2, 2, 1, 3]);
        assert_eq!(
            p,
            [
                e(0, NO_CORNER),
                e(1, 3),
                e(2, NO_CORNER),
                e(4, NO_CORNER),
                e(5, NO_CORNER)
            ]
        );
        // A triangle that repeats a vertex has no edges.
        assert_eq!(predict(&[0, 0, 1]), []);
    }

    #[test]
    fn diff_and_apply_give_the_truth_back() {
        let predicted = predict(&[0, 1, 2, 2, 1, 3, 4, 5, 6]);
        // Two boundary edges welded into one (a seam), one edge without fur dropped.
        let mut truth: Vec<FinEdge> = predicted
            .iter()
            .copied()
            .filter(|x| ![e(0, NO_CORNER), e(6, NO_CORNER), e(7, NO_CORNER)].contains(x))
            .collect();
        truth.push(lower_first(e(7, 0)));
        truth.sort_unstable_by_key(key);
        let (added, removed) = diff(&truth, &predicted);
        assert_eq!(added, [e(0, 7)]);
        assert_eq!(removed, [e(0, NO_CORNER), e(6, NO_CORNER), e(7, NO_CORNER)]);
        assert_eq!(apply(&predicted, &added, &removed), Some(truth));
        assert_eq!(apply(&predicted, &[], &[e(99, 1)]), None, "not predicted");
    }
}
