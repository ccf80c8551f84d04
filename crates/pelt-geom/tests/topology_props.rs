//! Property tests of normal groups and their IDs on random meshes: grids whose every corner has
//! its own vertex (so only welding connects faces), a random normal per corner from a small
//! palette (so groups of every size form), random diagonals, and duplicated faces (so
//! non-manifold edges occur). Checked against a brute-force oracle.

use std::collections::BTreeSet;

use glam::Vec3;
use pelt_geom::group_ids;
use pelt_geom::topology::{CornerNormals, TopologyOptions, build};
use proptest::prelude::*;

struct Case {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    indices: Vec<u32>,
}

fn case(w: u32, h: u32, picks: &[u8], flips: &[bool], dups: &[usize]) -> Case {
    let palette = [Vec3::Z, Vec3::new(0.0, 0.6, 0.8), Vec3::new(0.6, 0.0, 0.8)];
    let grid = |x: u32, y: u32| Vec3::new(x as f32, y as f32, ((x * 7 + y * 3) % 5) as f32 * 0.1);
    let mut c = Case {
        positions: vec![],
        normals: vec![],
        indices: vec![],
    };
    let mut tris: Vec<[(u32, u32); 3]> = vec![];
    for y in 0..h {
        for x in 0..w {
            let q = [(x, y), (x + 1, y), (x + 1, y + 1), (x, y + 1)];
            if flips[(y * w + x) as usize % flips.len()] {
                tris.extend([[q[0], q[1], q[2]], [q[0], q[2], q[3]]]);
            } else {
                tris.extend([[q[0], q[1], q[3]], [q[1], q[2], q[3]]]);
            }
        }
    }
    for &d in dups {
        tris.push(tris[d % tris.len()]);
    }
    for t in &tris {
        for &(x, y) in t {
            let k = c.positions.len();
            c.positions.push(grid(x, y));
            c.normals
                .push(palette[picks[k % picks.len()] as usize % palette.len()]);
            c.indices.push(k as u32);
        }
    }
    c
}

/// Components of the dual graph, by brute force: faces joined where they share two positions
/// (an edge) with equal corner normals at both.
fn oracle(c: &Case) -> Vec<usize> {
    let nf = c.indices.len() / 3;
    let key = |i: usize| {
        c.positions[c.indices[i] as usize]
            .to_array()
            .map(f32::to_bits)
    };
    let mut label: Vec<usize> = (0..nf).collect();
    loop {
        let mut changed = false;
        for f in 0..nf {
            for g in 0..nf {
                if f == g {
                    continue;
                }
                // Corner pairs at shared positions, and whether their normals agree.
                let mut shared = vec![];
                for i in 3 * f..3 * f + 3 {
                    for j in 3 * g..3 * g + 3 {
                        if key(i) == key(j) {
                            shared.push(c.normals[i] == c.normals[j]);
                        }
                    }
                }
                // Joined across any shared edge (two shared positions) agreeing at both ends.
                let agree = (0..shared.len())
                    .any(|a| (a + 1..shared.len()).any(|b| shared[a] && shared[b]));
                if agree && label[g] > label[f] {
                    label[g] = label[f];
                    changed = true;
                }
            }
        }
        if !changed {
            return label;
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn groups_match_the_oracle_and_neighbouring_groups_never_share_an_id(
        w in 1u32..9, h in 1u32..7,
        picks in prop::collection::vec(0u8..3, 1..40),
        flips in prop::collection::vec(any::<bool>(), 1..20),
        dups in prop::collection::vec(0usize..200, 0..4),
    ) {
        let c = case(w, h, &picks, &flips, &dups);
        let t = build(&c.positions, &c.indices, CornerNormals::Corner(&c.normals), &TopologyOptions::default());
        // Same partition as the oracle.
        let o = oracle(&c);
        let nf = c.indices.len() / 3;
        for f in 0..nf {
            for g in 0..nf {
                prop_assert_eq!(t.face_group[f] == t.face_group[g], o[f] == o[g], "faces {} {}", f, g);
            }
        }
        // IDs: all distinct up to 255 groups; neighbours (sharing a position) always differ.
        let ids = group_ids::assign(&t);
        prop_assert_eq!(ids.uncolorable_groups, 0);
        prop_assert_eq!(ids.shared_id_pairs, 0);
        prop_assert!(ids.id.iter().all(|&i| i != 0));
        if t.groups <= 255 {
            let distinct: BTreeSet<u8> = ids.id.iter().copied().collect();
            prop_assert_eq!(distinct.len(), t.groups);
        }
        let key = |i: usize| c.positions[c.indices[i] as usize].to_array().map(f32::to_bits);
        for i in 0..c.indices.len() {
            for j in 0..c.indices.len() {
                let (f, g) = (t.face_group[i / 3], t.face_group[j / 3]);
                if key(i) == key(j) && f != g {
                    prop_assert_ne!(ids.id[f as usize], ids.id[g as usize]);
                }
            }
        }
    }

    #[test]
    fn beyond_255_groups_neighbours_still_get_different_ids(
        w in 16u32..28, h in 12u32..20, seed in any::<u64>(),
    ) {
        // Every corner its own normal: every face its own group, hundreds of them.
        let n = (w * h * 6) as usize;
        let picks: Vec<u8> = (0..n).map(|k| ((seed >> (k % 61)) as u8).wrapping_add(k as u8) % 3).collect();
        let mut c = case(w, h, &picks, &[true, false, false], &[]);
        for (k, nrm) in c.normals.iter_mut().enumerate() {
            *nrm = Vec3::new((k % 97) as f32, (k / 97) as f32, 100.0).normalize();
        }
        let t = build(&c.positions, &c.indices, CornerNormals::Corner(&c.normals), &TopologyOptions::default());
        prop_assert_eq!(t.groups, c.indices.len() / 3);
        let ids = group_ids::assign(&t);
        prop_assert!(ids.neighbour_pairs > 0);
        prop_assert_eq!(ids.shared_id_pairs, 0);
        prop_assert_eq!(ids.ids_used, 255);
        let (pairs, _, _) = group_ids::neighbour_pairs(&t);
        for (a, b) in pairs {
            prop_assert_ne!(ids.id[a as usize], ids.id[b as usize]);
        }
    }
}
