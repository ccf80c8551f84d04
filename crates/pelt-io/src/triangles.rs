//! Triangle topologies: what glTF's `TRIANGLES` (4), `TRIANGLE_STRIP` (5) and `TRIANGLE_FAN`
//! (6) modes mean as a triangle list (glTF 2.0 §3.7.2.1, "Topology types"), and writing a
//! converted list back into a primitive.
//!
//! Strip triangle i is (v[i], v[i+1+i%2], v[i+2-i%2]), which keeps every triangle's winding the
//! first one's; fan triangle i is (v[i+1], v[i+2], v[0]). Triangles that repeat a vertex (the
//! degenerate triangles that join strips) are dropped from strips and fans alike.

use serde_json::json;

use crate::document::{Document, PrimitiveRef};
use crate::edit::NewAccessor;
use crate::error::Result;

/// `TRIANGLES`.
pub const TRIANGLES: u64 = 4;
/// `TRIANGLE_STRIP`.
pub const TRIANGLE_STRIP: u64 = 5;
/// `TRIANGLE_FAN`.
pub const TRIANGLE_FAN: u64 = 6;

/// Whether `mode` draws triangles (a list, a strip or a fan).
pub fn is_triangles(mode: u64) -> bool {
    matches!(mode, TRIANGLES | TRIANGLE_STRIP | TRIANGLE_FAN)
}

/// glTF's name of a primitive mode.
pub fn mode_name(mode: u64) -> &'static str {
    match mode {
        0 => "POINTS",
        1 => "LINES",
        2 => "LINE_LOOP",
        3 => "LINE_STRIP",
        TRIANGLES => "TRIANGLES",
        TRIANGLE_STRIP => "TRIANGLE_STRIP",
        _ => "TRIANGLE_FAN",
    }
}

/// The triangle list that `indices` drawn in `mode` describe, and how many degenerate
/// triangles were dropped. A list (mode 4) is returned as it is.
pub fn triangle_list(mode: u64, indices: Vec<u32>) -> (Vec<u32>, usize) {
    let tri = |i: usize| -> [u32; 3] {
        match mode {
            TRIANGLE_STRIP => [indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]],
            _ => [indices[i + 1], indices[i + 2], indices[0]],
        }
    };
    if !matches!(mode, TRIANGLE_STRIP | TRIANGLE_FAN) {
        return (indices, 0);
    }
    let count = indices.len().saturating_sub(2);
    let mut list = Vec::with_capacity(count * 3);
    let mut dropped = 0;
    for i in 0..count {
        let [a, b, c] = tri(i);
        if a == b || b == c || a == c {
            dropped += 1;
        } else {
            list.extend([a, b, c]);
        }
    }
    (list, dropped)
}

impl Document {
    /// Makes a strip or fan primitive a list: `list` (into its `vertex_count` vertices)
    /// becomes its indices and its mode `TRIANGLES`. The old index accessor is detached.
    pub fn set_triangle_list(
        &mut self,
        r: PrimitiveRef,
        list: &[u32],
        vertex_count: usize,
    ) -> Result<()> {
        let a = self.push_accessor(NewAccessor::indices(list, vertex_count));
        let prim = self.primitive_checked(r)?;
        let old = prim.insert("indices".into(), json!(a));
        prim.insert("mode".into(), json!(TRIANGLES));
        self.detach_accessors(old.and_then(|o| o.as_u64()).map(|o| o as usize));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Twice the signed area's z of triangle (a, b, c) over points on a line of quads.
    fn winding(points: &[[f32; 2]], t: &[u32]) -> f32 {
        let p = |i: u32| points[i as usize];
        let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    }

    #[test]
    fn strips_keep_their_winding_and_lose_degenerates() {
        // Bottom row 0 2 4 6, top row 1 3 5 7 (x = i / 2, y = i % 2).
        let points: Vec<[f32; 2]> = (0..8).map(|i| [(i / 2) as f32, (i % 2) as f32]).collect();
        let (list, dropped) = triangle_list(TRIANGLE_STRIP, (0..8).collect());
        assert_eq!(dropped, 0);
        assert_eq!(&list[..9], &[0, 1, 2, 1, 3, 2, 2, 3, 4]);
        let first = winding(&points, &list[..3]);
        for t in list.chunks(3) {
            assert_eq!(winding(&points, t).signum(), first.signum(), "{t:?}");
        }
        // Two strips joined by repeating 3 and 4: the four joining triangles go.
        let (joined, dropped) = triangle_list(TRIANGLE_STRIP, vec![0, 1, 2, 3, 3, 4, 4, 5, 6, 7]);
        assert_eq!(dropped, 4);
        assert_eq!(joined.len(), 3 * 4);
        for t in joined.chunks(3) {
            assert_eq!(winding(&points, t).signum(), first.signum(), "{t:?}");
        }
    }

    #[test]
    fn fans_turn_around_their_first_vertex() {
        let (list, dropped) = triangle_list(TRIANGLE_FAN, vec![0, 1, 2, 3, 3]);
        assert_eq!(dropped, 1);
        assert_eq!(list, vec![1, 2, 0, 2, 3, 0]);
        let (short, _) = triangle_list(TRIANGLE_FAN, vec![0, 1]);
        assert!(short.is_empty());
    }

    #[test]
    fn lists_are_left_alone() {
        let (list, dropped) = triangle_list(TRIANGLES, vec![0, 0, 1]);
        assert_eq!((list, dropped), (vec![0, 0, 1], 0));
    }
}
