//! 8-bit IDs for normal groups, as the inferred-lighting filter reads them (Kircher & Lawrance
//! §3.1: object ID << 8 | normal-group ID, compared in the DSF).
//!
//! The paper gives each group a random 8-bit ID and accepts the rare collision. pelt assigns
//! them deterministically, and better:
//! - ID 0 is reserved (the renderer's "no group"), so 255 IDs are available;
//! - with at most 255 groups, group `g` (numbered by first face) gets ID `g + 1`: all distinct;
//! - beyond that, neighbouring groups (sharing an edge or a vertex) get different IDs where
//!   possible: a greedy coloring of the group adjacency graph, largest degree first
//!   (Welsh–Powell order), each group taking the least-used ID its neighbours leave free, so
//!   use spreads over all 255 IDs. Where a group's neighbours already hold every ID, it takes
//!   the ID fewest of them hold, and the assignment reports how many groups that happened to
//!   and how many neighbouring pairs share an ID as a result.
//!
//! For comparison it also counts the neighbouring pairs that the paper's random assignment
//! (one seeded draw) would have given the same ID.
//!
//! Where more than 255 groups meet at one position (a mesh collapsed to a point, a fan of
//! hundreds of creased faces) no assignment separates them all, and listing every pair would
//! take memory growing with the square of the count: there each group is paired with its
//! [`CROWDED_WINDOW`] successors only.

use rayon::prelude::*;

use crate::topology::Topology;

/// IDs available to groups (1..=255; 0 means "no group").
pub const IDS: usize = 255;

/// Where more than [`IDS`] groups meet at one position, each is paired with this many of its
/// successors (by group number, wrapping) instead of with all of them.
pub const CROWDED_WINDOW: usize = 8;

/// Seed of the random assignment the report compares against.
pub const RANDOM_SEED: u64 = 0x7065_6c74; // "pelt"

/// The IDs of a mesh's normal groups, with what the report needs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GroupIds {
    /// ID per group (1..=255).
    pub id: Vec<u8>,
    /// Distinct IDs used.
    pub ids_used: usize,
    /// Pairs of groups sharing an edge or a vertex.
    pub neighbour_pairs: usize,
    /// Neighbouring pairs that ended up with the same ID (0 unless coloring failed).
    pub shared_id_pairs: usize,
    /// Groups for which no free ID was left.
    pub uncolorable_groups: usize,
    /// Most groups meeting at one position: above 255, no assignment can separate them all.
    pub most_groups_at_a_vertex: usize,
    /// Neighbouring pairs one seeded random 8-bit assignment (the paper's) gives the same ID.
    pub random_collisions: usize,
}

/// splitmix64: a well-mixed 64-bit hash.
fn splitmix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// The paper's random 8-bit ID of group `g`.
pub fn random_id(g: u32) -> u8 {
    (splitmix(u64::from(g) ^ RANDOM_SEED) & 0xFF) as u8
}

/// Neighbouring group pairs (lower group first), sorted and unique (at crowded positions only
/// the [`CROWDED_WINDOW`] pairs of each group), the most groups met at one position, and the
/// groups of each crowded position (more than [`IDS`] groups), sorted.
pub fn neighbour_pairs(t: &Topology) -> (Vec<(u32, u32)>, usize, Vec<Vec<u32>>) {
    if t.groups < 2 {
        return (Vec::new(), usize::from(t.groups > 0), Vec::new());
    }
    let parts: Vec<Part> = (0..t.positions.div_ceil(4096))
        .into_par_iter()
        .map(|task| {
            let mut pairs = Vec::new();
            let mut most = 0;
            let mut crowded = Vec::new();
            let mut here: Vec<u32> = Vec::new();
            for p in task * 4096..((task + 1) * 4096).min(t.positions) {
                here.clear();
                here.extend(t.faces_at(p as u32).map(|f| t.face_group[f as usize]));
                here.sort_unstable();
                here.dedup();
                most = most.max(here.len());
                if here.len() <= IDS {
                    for (i, &a) in here.iter().enumerate() {
                        pairs.extend(here[i + 1..].iter().map(|&b| (a, b)));
                    }
                } else {
                    // More groups than IDs meet here: no assignment separates them all, and
                    // all pairs would grow with the square of the count (a mesh collapsed to
                    // a point has every group at one position). Each group is paired with
                    // its CROWDED_WINDOW successors, which keeps the pairs linear.
                    pairs.extend(window_pairs(&here));
                    crowded.push(here.clone());
                }
            }
            (pairs, most, crowded)
        })
        .collect();
    let most = parts.iter().map(|p| p.1).max().unwrap_or(0);
    let mut pairs = Vec::new();
    let mut crowded = Vec::new();
    for (p, _, c) in parts {
        pairs.extend(p);
        crowded.extend(c);
    }
    pairs.par_sort_unstable();
    pairs.dedup();
    (pairs, most, crowded)
}

/// One task's share of [`neighbour_pairs`]: pairs, most groups at a position, crowded sets.
type Part = (Vec<(u32, u32)>, usize, Vec<Vec<u32>>);

/// Each group of a crowded position paired with its [`CROWDED_WINDOW`] successors (wrapping).
fn window_pairs(groups: &[u32]) -> impl Iterator<Item = (u32, u32)> + '_ {
    let k = groups.len();
    groups.iter().enumerate().flat_map(move |(i, &a)| {
        (1..=CROWDED_WINDOW.min(k.saturating_sub(1) / 2)).map(move |d| {
            let b = groups[(i + d) % k];
            (a.min(b), a.max(b))
        })
    })
}

/// Assigns the IDs of `t`'s groups.
pub fn assign(t: &Topology) -> GroupIds {
    let (pairs, most, crowded) = neighbour_pairs(t);
    let n = t.groups;
    let id: Vec<u8> = if n <= IDS {
        (0..n).map(|g| (g + 1) as u8).collect()
    } else {
        color(n, &pairs)
    };
    let same = |f: &dyn Fn(u32) -> u8| pairs.iter().filter(|&&(a, b)| f(a) == f(b)).count();
    let mut shared_id_pairs = same(&|g| id[g as usize]);
    let mut random_collisions = same(&|g| random_id(g));
    let mut neighbour_total = pairs.len();
    let mut seen = [false; 256];
    for &i in &id {
        seen[i as usize] = true;
    }
    // Counted from the result, not assumed: a group is uncolorable when a neighbour shares its ID.
    let mut uncolorable = vec![false; n];
    for &(a, b) in &pairs {
        if id[a as usize] == id[b as usize] {
            uncolorable[a.max(b) as usize] = true;
        }
    }
    // Crowded positions: every pair there is a neighbouring pair, but only the window pairs
    // are listed. Count the rest from how many groups hold each ID (linear in the groups).
    for set in &crowded {
        let k = set.len();
        let window: Vec<(u32, u32)> = window_pairs(set).collect();
        neighbour_total += k * (k - 1) / 2 - window.len();
        shared_id_pairs += unlisted_same(set, &window, |g| id[g as usize]);
        random_collisions += unlisted_same(set, &window, random_id);
        let mut first = [true; 256];
        for &g in set {
            let i = id[g as usize] as usize;
            if !std::mem::take(&mut first[i]) {
                uncolorable[g as usize] = true;
            }
        }
    }
    GroupIds {
        ids_used: seen.iter().filter(|&&s| s).count(),
        neighbour_pairs: neighbour_total,
        shared_id_pairs,
        uncolorable_groups: uncolorable.iter().filter(|&&u| u).count(),
        most_groups_at_a_vertex: most,
        random_collisions,
        id,
    }
}

/// Pairs of a crowded position's groups that `f` gives the same ID and that its window pairs
/// do not list: all such pairs, from how many groups hold each ID, less the listed ones.
fn unlisted_same(set: &[u32], window: &[(u32, u32)], f: impl Fn(u32) -> u8) -> usize {
    let mut holders = [0usize; 256];
    for &g in set {
        holders[f(g) as usize] += 1;
    }
    let all: usize = holders.iter().map(|&h| h * h.saturating_sub(1) / 2).sum();
    all - window.iter().filter(|&&(a, b)| f(a) == f(b)).count()
}

/// Greedy coloring with IDs 1..=255 (see the module documentation).
fn color(n: usize, pairs: &[(u32, u32)]) -> Vec<u8> {
    // Adjacency lists (CSR).
    let mut start = vec![0u32; n + 1];
    for &(a, b) in pairs {
        start[a as usize + 1] += 1;
        start[b as usize + 1] += 1;
    }
    for g in 0..n {
        start[g + 1] += start[g];
    }
    let mut fill = start.clone();
    let mut adj = vec![0u32; 2 * pairs.len()];
    for &(a, b) in pairs {
        for (x, y) in [(a, b), (b, a)] {
            adj[fill[x as usize] as usize] = y;
            fill[x as usize] += 1;
        }
    }
    let degree = |g: usize| start[g + 1] - start[g];
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_by_key(|&g| (std::cmp::Reverse(degree(g as usize)), g));

    let mut id = vec![0u8; n];
    let mut uses = [0usize; IDS + 1];
    let mut held = [0u32; IDS + 1];
    for g in order {
        let neighbours = &adj[start[g as usize] as usize..start[g as usize + 1] as usize];
        held.fill(0);
        for &h in neighbours {
            held[id[h as usize] as usize] += 1;
        }
        // Free IDs first, then the fewest holders; among those the least used, then the lowest.
        let best = (1..=IDS)
            .min_by_key(|&i| (held[i], uses[i], i))
            .unwrap_or(1);
        id[g as usize] = best as u8;
        uses[best] += 1;
    }
    id
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::topology::{CornerNormals, TopologyOptions, build};
    use glam::Vec3;

    /// A fan of `k` triangles around the origin, each with its own normal: `k` groups that all
    /// meet at the center.
    fn fan(k: usize) -> Topology {
        let mut p = vec![Vec3::ZERO];
        let mut i = vec![];
        for j in 0..k {
            let a = j as f32 / k as f32 * std::f32::consts::TAU;
            p.push(Vec3::new(a.cos(), a.sin(), 0.0));
            i.extend([0, 1 + j as u32, 1 + ((j + 1) % k) as u32]);
        }
        // Per-corner normals that differ per face.
        let normals: Vec<Vec3> = (0..i.len())
            .map(|c| {
                let a = (c / 3) as f32 * 0.02;
                Vec3::new(a.cos(), a.sin(), 1.0)
            })
            .collect();
        build(
            &p,
            &i,
            CornerNormals::Corner(&normals),
            &TopologyOptions::default(),
        )
    }

    #[test]
    fn few_groups_get_distinct_ids() {
        let t = fan(40);
        assert_eq!(t.groups, 40);
        let ids = assign(&t);
        assert_eq!(ids.ids_used, 40);
        assert_eq!(ids.id, (1..=40).collect::<Vec<u8>>());
        // Every pair meets at the center.
        assert_eq!(ids.neighbour_pairs, 40 * 39 / 2);
        assert_eq!(ids.shared_id_pairs, 0);
        assert_eq!(ids.most_groups_at_a_vertex, 40);
        // The random assignment collides on at least one of 780 pairs for this seed, as the
        // birthday bound predicts (expected 780 / 256 ≈ 3).
        assert!(ids.random_collisions > 0);
    }

    #[test]
    fn too_many_groups_at_one_vertex_is_reported() {
        let t = fan(300);
        let ids = assign(&t);
        assert_eq!(ids.most_groups_at_a_vertex, 300);
        assert_eq!(ids.ids_used, 255);
        assert!(ids.uncolorable_groups >= 300 - 255);
        // Fewest holders: 45 IDs are held twice, so 45 pairs share one.
        assert_eq!(ids.shared_id_pairs, 45);
    }

    #[test]
    fn crowded_positions_list_linear_pairs_but_count_all() {
        let t = fan(3000);
        let (pairs, most, crowded) = neighbour_pairs(&t);
        assert_eq!(most, 3000);
        assert_eq!(crowded.len(), 1);
        // All pairs would be 4.5 million; the window lists at most 8 per group (plus the
        // ring's edge pairs, which the center already covers).
        assert!(
            pairs.len() <= 8 * 3000 + 3000,
            "{} pairs listed",
            pairs.len()
        );
        let ids = assign(&t);
        assert_eq!(ids.neighbour_pairs, 3000 * 2999 / 2);
        // 3000 groups over 255 IDs: 195 IDs held 12 times, 60 held 11 times.
        let expect = 195 * (12 * 11 / 2) + 60 * (11 * 10 / 2);
        assert!(
            ids.shared_id_pairs >= expect,
            "{} < {expect}",
            ids.shared_id_pairs
        );
        assert_eq!(ids.uncolorable_groups, 3000 - 255);
    }
}
