//! Exact welding: vertices whose keys are bit-for-bit equal (after mapping -0.0 to +0.0, so
//! equality is IEEE `==` for finite values) share one id. Ids are dense and numbered in order of
//! first appearance, so the result does not depend on hashing, sorting or thread count.
//!
//! [`weld_positions`] adds welding within a distance, for exports whose seams do not meet
//! exactly: positions closer than epsilon join, transitively.

use glam::Vec3;
use rayon::prelude::*;

use crate::union_find::{UnionFind, first_seen_labels};

/// The f32 bit pattern used as a weld key: `-0.0` becomes `+0.0`.
#[inline]
pub fn key_bits(x: f32) -> u32 {
    if x == 0.0 { 0 } else { x.to_bits() }
}

/// Welds `n` vertices by the key `key(i)`. Returns the id of every vertex and the number of ids.
///
/// Parallel and deterministic: keys are hashed (in parallel), (hash, index) pairs sorted (in
/// parallel), and each run of equal hashes split by exact key comparison, so a hash collision
/// can never weld different keys. The representative of each key is its first vertex; ids are
/// numbered in the order representatives appear.
pub fn weld<const N: usize>(n: usize, key: impl Fn(usize) -> [u32; N] + Sync) -> (Vec<u32>, usize) {
    weld_by(n, key, hash_key)
}

/// Below this many vertices [`weld`] runs on one thread with a hash table: there the parallel
/// sort's hand-offs between threads cost more than they save, and a table needs no sort and
/// no labelling pass.
const TABLE_BELOW: usize = 1 << 16;

/// [`weld`] with the hash as a parameter (tests force collisions with it).
fn weld_by<const N: usize>(
    n: usize,
    key: impl Fn(usize) -> [u32; N] + Sync,
    hash: impl Fn(&[u32; N]) -> u64 + Sync,
) -> (Vec<u32>, usize) {
    if n < TABLE_BELOW {
        return weld_table(n, &key, &hash);
    }
    let order: Vec<(u64, u32)> = (0..n)
        .into_par_iter()
        .with_min_len(4096)
        .map(|i| (hash(&key(i)), i as u32))
        .collect();
    let order = sort_hashed(order);

    // First vertex with the same key, for every vertex.
    let mut rep = vec![0u32; n];
    let mut distinct: Vec<([u32; N], u32)> = Vec::new();
    for run in order.chunk_by(|a, b| a.0 == b.0) {
        if let [(_, i)] = run {
            rep[*i as usize] = *i;
            continue;
        }
        // Equal hashes: indices ascend, so the first of each distinct key is its representative.
        distinct.clear();
        for &(_, i) in run {
            let k = key(i as usize);
            rep[i as usize] = match distinct.iter().find(|(d, _)| *d == k) {
                Some(&(_, r)) => r,
                None => {
                    distinct.push((k, i));
                    i
                }
            };
        }
    }
    drop(order);

    first_seen_labels(rep)
}

/// [`weld`] on one thread: an open-addressing table (linear probing) from each distinct key to
/// its id, ids given in order of first appearance as the vertices are visited in order; keys
/// are compared exactly, so colliding hashes only cost probes.
fn weld_table<const N: usize>(
    n: usize,
    key: &impl Fn(usize) -> [u32; N],
    hash: &impl Fn(&[u32; N]) -> u64,
) -> (Vec<u32>, usize) {
    const EMPTY: u32 = u32::MAX;
    let mask = (2 * n).next_power_of_two().max(16) - 1;
    let mut slots = vec![EMPTY; mask + 1];
    // The first vertex of every id.
    let mut first: Vec<u32> = Vec::new();
    let ids = (0..n)
        .map(|v| {
            let k = key(v);
            let mut s = hash(&k) as usize & mask;
            loop {
                match slots[s] {
                    EMPTY => {
                        let id = first.len() as u32;
                        slots[s] = id;
                        first.push(v as u32);
                        return id;
                    }
                    id if key(first[id as usize] as usize) == k => return id,
                    _ => s = (s + 1) & mask,
                }
            }
        })
        .collect();
    (ids, first.len())
}

/// Welds positions: bit-equal ones when `epsilon` is 0 (or not positive), otherwise every pair
/// within `epsilon` (Euclidean distance, in f64) joins, and joins chain (a run of points each
/// within epsilon of the next becomes one position). Ids are numbered in order of first
/// appearance, as in [`weld`].
pub fn weld_positions(positions: &[Vec3], epsilon: f32) -> (Vec<u32>, usize) {
    let within = epsilon.is_finite() && epsilon > 0.0;
    if !within {
        return weld(positions.len(), |v| positions[v].to_array().map(key_bits));
    }
    let eps = f64::from(epsilon);
    // A grid of cells of size epsilon: points within epsilon lie in the same or adjacent cells.
    let limit = (1i64 << 52) as f64;
    let cell = |p: Vec3| -> [i64; 3] {
        (p.as_dvec3() / eps)
            .floor()
            .to_array()
            .map(|c| c.clamp(-limit, limit) as i64)
    };
    let mut order: Vec<([i64; 3], u32)> = positions
        .par_iter()
        .enumerate()
        .with_min_len(4096)
        .map(|(v, &p)| (cell(p), v as u32))
        .collect();
    order.par_sort_unstable();
    let joins: Vec<(u32, u32)> = order
        .par_iter()
        .with_min_len(1024)
        .flat_map_iter(|&(c, v)| {
            let p = positions[v as usize].as_dvec3();
            let order = &order;
            (0..27).flat_map(move |k| {
                let n = [c[0] + k / 9 - 1, c[1] + (k / 3) % 3 - 1, c[2] + k % 3 - 1];
                let lo = order.partition_point(|e| e.0 < n);
                order[lo..]
                    .iter()
                    .take_while(move |e| e.0 == n)
                    .filter(move |e| {
                        e.1 > v && positions[e.1 as usize].as_dvec3().distance(p) <= eps
                    })
                    .map(move |e| (v, e.1))
            })
        })
        .collect();
    let mut sets = UnionFind::new(positions.len());
    for (a, b) in joins {
        sets.join(a, b);
    }
    sets.labels()
}

/// Sorts (hash, index) pairs. Large inputs go through one counting-sort pass on the top 16 bits
/// of the hash (hashes are uniform, so buckets are small), then each bucket is sorted in
/// parallel; the result is the same total order as a comparison sort.
fn sort_hashed(mut order: Vec<(u64, u32)>) -> Vec<(u64, u32)> {
    const BITS: u32 = 16;
    if order.len() < 1 << BITS {
        order.par_sort_unstable();
        return order;
    }
    let bucket = |h: u64| (h >> (64 - BITS)) as usize;
    let mut start = vec![0usize; (1 << BITS) + 1];
    for &(h, _) in &order {
        start[bucket(h) + 1] += 1;
    }
    for b in 0..1 << BITS {
        start[b + 1] += start[b];
    }
    let mut fill = start.clone();
    let mut sorted = vec![(0u64, 0u32); order.len()];
    for &e in &order {
        let slot = &mut fill[bucket(e.0)];
        sorted[*slot] = e;
        *slot += 1;
    }
    drop(order);
    let mut parts = Vec::with_capacity(1 << BITS);
    let mut rest = sorted.as_mut_slice();
    for b in 0..1 << BITS {
        let (part, tail) = rest.split_at_mut(start[b + 1] - start[b]);
        parts.push(part);
        rest = tail;
    }
    parts
        .into_par_iter()
        .with_min_len(256)
        .for_each(|p| p.sort_unstable());
    sorted
}

/// A 64-bit hash of a key (multiply-xorshift per word, murmur3's finalizer at the end).
#[inline]
fn hash_key<const N: usize>(k: &[u32; N]) -> u64 {
    let mut h = 0x9E37_79B9_7F4A_7C15u64;
    for &w in k {
        h = (h ^ u64::from(w)).wrapping_mul(0xFF51_AFD7_ED55_8CCD);
        h ^= h >> 32;
    }
    h ^= h >> 33;
    h = h.wrapping_mul(0xC4CE_B9FE_1A85_EC53);
    h ^ (h >> 33)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_keys_share_ids_in_first_seen_order() {
        let keys = [[3u32], [1], [3], [2], [1]];
        let (ids, n) = weld(keys.len(), |i| keys[i]);
        assert_eq!(ids, vec![0, 1, 0, 2, 1]);
        assert_eq!(n, 3);
    }

    #[test]
    fn hash_collisions_never_weld_different_keys() {
        // Many keys, few distinct: runs of equal hashes hold equal keys only; and ids follow
        // first appearance whatever the sort did.
        let keys: Vec<[u32; 2]> = (0..10_000u32).map(|i| [i % 7, (i * 31) % 5]).collect();
        let (ids, n) = weld(keys.len(), |i| keys[i]);
        assert_eq!(n, 35);
        // Every hash equal: exact comparison alone must give the same ids.
        assert_eq!(weld_by(keys.len(), |i| keys[i], |_| 7), (ids.clone(), n));
        let mut first = std::collections::HashMap::new();
        let mut next = 0;
        for (i, k) in keys.iter().enumerate() {
            let id = *first.entry(*k).or_insert_with(|| {
                next += 1;
                next - 1
            });
            assert_eq!(ids[i], id, "vertex {i}");
        }
    }

    #[test]
    fn table_and_sort_give_the_same_ids() {
        // Above TABLE_BELOW the parallel sort welds, below it the table: same ids, also when
        // every hash collides.
        let keys: Vec<[u32; 2]> = (0..(TABLE_BELOW as u32 + 5000))
            .map(|i| [i % 9173, (i * 7) % 11])
            .collect();
        let (big, n) = weld(keys.len(), |i| keys[i]);
        let (small, m) = weld_table(keys.len(), &|i| keys[i], &hash_key);
        assert_eq!((small, m), (big.clone(), n));
        let few = 3000;
        assert_eq!(
            weld_table(few, &|i| keys[i], &|_| 7),
            weld_table(few, &|i| keys[i], &hash_key)
        );
        assert_eq!(
            weld_table(few, &|i| keys[i], &hash_key),
            (big[..few].to_vec(), n.min(few))
        );
    }

    #[test]
    fn epsilon_welds_near_points_across_cell_borders_and_chains() {
        let p = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.001, 0.0, 0.0),
            // Within 0.01 of vertex 1, but in another grid cell.
            Vec3::new(0.998, 0.0, 0.004),
            Vec3::new(0.0, 0.0, 0.0),
            // A chain: each within epsilon of the next.
            Vec3::new(0.0, 5.0, 0.0),
            Vec3::new(0.0, 5.009, 0.0),
            Vec3::new(0.0, 5.018, 0.0),
            Vec3::new(0.0, 0.02, 0.0),
        ];
        assert_eq!(weld_positions(&p, 0.0), (vec![0, 1, 2, 0, 3, 4, 5, 6], 7));
        assert_eq!(weld_positions(&p, 0.01), (vec![0, 1, 1, 0, 2, 2, 2, 3], 4));
    }

    #[test]
    fn bucketed_sort_equals_a_comparison_sort() {
        let v: Vec<(u64, u32)> = (0..200_000u64)
            .map(|i| (hash_key(&[(i % 70_000) as u32]), i as u32))
            .collect();
        let mut expected = v.clone();
        expected.sort_unstable();
        assert_eq!(sort_hashed(v), expected);
    }

    #[test]
    fn negative_zero_welds_with_zero() {
        assert_eq!(key_bits(-0.0), key_bits(0.0));
        assert_ne!(key_bits(1.0), key_bits(-1.0));
    }
}
