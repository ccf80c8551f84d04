//! The CPU half of the debug views. `debug-groups` draws each normal group (Kircher &
//! Lawrance §3.1: the faces whose normals are continuous, the low byte of the DSF ID) in one
//! flat colour, and neighbouring groups must never share a colour: a hash of the ID cannot
//! promise that, so the groups are coloured as a graph. Two groups are neighbours where a
//! triangle joins them or where their vertices meet at one position (a hard edge splits its
//! vertices, so the triangles either side reference different copies at the same place).
//! Groups are coloured greedily, most neighbours first (Welsh & Powell), which needs at most
//! one class more than the largest number of neighbours. `debug-comb` needs nothing here:
//! the shader decodes the comb as the fur passes do.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use crate::vertex::Vertex;

/// The colour class of each vertex's normal group: neighbouring groups get different
/// classes, and class 0 goes to the group with the most neighbours. Deterministic: the same
/// mesh gives the same classes. `indices` index `vertices` (an index out of range is
/// ignored: the mesh loader has already checked them).
pub fn group_classes(vertices: &[Vertex], indices: &[u32]) -> Vec<u32> {
    let neighbours = group_graph(vertices, indices);
    let classes = colour(&neighbours);
    vertices.iter().map(|v| classes[&v.group]).collect()
}

/// Each group's neighbours (every group of the mesh is a key).
fn group_graph(vertices: &[Vertex], indices: &[u32]) -> BTreeMap<u32, BTreeSet<u32>> {
    let mut graph: BTreeMap<u32, BTreeSet<u32>> = BTreeMap::new();
    let mut join = |a: u32, b: u32| {
        if a != b {
            graph.entry(a).or_default().insert(b);
            graph.entry(b).or_default().insert(a);
        }
    };
    for tri in indices.chunks_exact(3) {
        let g: Vec<u32> = tri
            .iter()
            .filter_map(|&i| vertices.get(i as usize).map(|v| v.group))
            .collect();
        for (k, &a) in g.iter().enumerate() {
            for &b in &g[k + 1..] {
                join(a, b);
            }
        }
    }
    // Groups whose vertices meet at one position (`+ 0.0` folds -0 into 0).
    let mut by_position: HashMap<[u32; 3], BTreeSet<u32>> = HashMap::new();
    for v in vertices {
        let key = v.position.map(|c| (c + 0.0).to_bits());
        by_position.entry(key).or_default().insert(v.group);
    }
    for set in by_position.values().filter(|s| s.len() > 1) {
        let g: Vec<u32> = set.iter().copied().collect();
        for (k, &a) in g.iter().enumerate() {
            for &b in &g[k + 1..] {
                join(a, b);
            }
        }
    }
    for v in vertices {
        graph.entry(v.group).or_default();
    }
    graph
}

/// Greedy colouring, groups with the most neighbours first (ties by ID).
fn colour(graph: &BTreeMap<u32, BTreeSet<u32>>) -> HashMap<u32, u32> {
    let mut order: Vec<(&u32, &BTreeSet<u32>)> = graph.iter().collect();
    order.sort_by(|a, b| b.1.len().cmp(&a.1.len()).then(a.0.cmp(b.0)));
    let mut class: HashMap<u32, u32> = HashMap::with_capacity(graph.len());
    for (&g, near) in order {
        let taken: BTreeSet<u32> = near.iter().filter_map(|n| class.get(n).copied()).collect();
        let free = (0..).find(|c| !taken.contains(c)).unwrap_or(0);
        class.insert(g, free);
    }
    class
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vertex(position: [f32; 3], group: u32) -> Vertex {
        Vertex {
            position,
            normal: [0.0, 0.0, 1.0],
            albedo: [1.0; 4],
            group,
            uv: [0.0; 2],
        }
    }

    /// A strip of `n` quads along x, quad k in group `ids[k]`, each with its own vertices
    /// (split at every edge, as hard edges are).
    fn strip(ids: &[u32]) -> (Vec<Vertex>, Vec<u32>) {
        let (mut v, mut i) = (Vec::new(), Vec::new());
        for (k, &g) in ids.iter().enumerate() {
            let x = k as f32;
            let base = v.len() as u32;
            for p in [
                [x, 0.0, 0.0],
                [x + 1.0, 0.0, 0.0],
                [x + 1.0, 1.0, 0.0],
                [x, 1.0, 0.0],
            ] {
                v.push(vertex(p, g));
            }
            i.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
        (v, i)
    }

    #[test]
    fn split_neighbours_get_different_classes() {
        // Groups 0 and 13 side by side: a hue hash of the ID may put them close; classes
        // never do. A path of groups needs two classes.
        let (v, i) = strip(&[0, 13, 26, 39]);
        let c = group_classes(&v, &i);
        for k in 0..3 {
            assert_ne!(
                c[k * 4],
                c[(k + 1) * 4],
                "quads {k} and {} share a class",
                k + 1
            );
        }
        assert!(c.iter().all(|&x| x < 2), "{c:?}");
        // The same group at both ends closes a cycle of three: three classes.
        let (v, i) = strip(&[0, 13, 26, 0]);
        let c = group_classes(&v, &i);
        let distinct: BTreeSet<u32> = c.iter().copied().collect();
        assert_eq!(distinct.len(), 3, "{c:?}");
    }

    #[test]
    fn a_hub_with_many_neighbours_uses_few_classes() {
        // A fan of 8 triangles around a centre, all split: every group touches the centre,
        // so all 8 are pairwise neighbours (they meet at one point) and need 8 classes.
        let mut v = Vec::new();
        let mut i = Vec::new();
        for k in 0..8u32 {
            let a = k as f32 * std::f32::consts::TAU / 8.0;
            let b = (k + 1) as f32 * std::f32::consts::TAU / 8.0;
            let base = v.len() as u32;
            v.push(vertex([0.0, 0.0, 0.0], 100 + k));
            v.push(vertex([a.cos(), a.sin(), 0.0], 100 + k));
            v.push(vertex([b.cos(), b.sin(), 0.0], 100 + k));
            i.extend([base, base + 1, base + 2]);
        }
        let c = group_classes(&v, &i);
        let distinct: BTreeSet<u32> = c.iter().copied().collect();
        assert_eq!(distinct.len(), 8, "{c:?}");
    }

    #[test]
    fn one_group_is_class_zero_and_output_is_per_vertex() {
        let (v, i) = strip(&[5, 5, 5]);
        assert_eq!(group_classes(&v, &i), vec![0; 12]);
    }
}
