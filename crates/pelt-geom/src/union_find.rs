//! Disjoint sets over `0..n` (union-find with path halving). The root of every set is its
//! smallest member, so the partition and its representatives do not depend on the order in
//! which joins arrive: [`AtomicUnionFind`] takes joins from many threads at once and ends in
//! the same sets as the sequential [`UnionFind`].

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use rayon::prelude::*;

/// Disjoint sets over `0..n`.
#[derive(Debug, Clone)]
pub struct UnionFind(Vec<u32>);

impl UnionFind {
    /// `n` singleton sets.
    pub fn new(n: usize) -> Self {
        UnionFind((0..n as u32).collect())
    }

    /// The root (smallest member) of `x`'s set.
    #[inline]
    pub fn find(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let p = self.0[x as usize];
            self.0[x as usize] = self.0[p as usize];
            x = p;
        }
        x
    }

    /// Joins the sets of `a` and `b`.
    #[inline]
    pub fn join(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        self.0[hi as usize] = lo;
    }

    /// Dense labels numbered in order of each set's smallest member (its first element), and
    /// the number of sets.
    pub fn labels(self) -> (Vec<u32>, usize) {
        // Every join is done: a find that does not halve paths can run in parallel.
        let parent = &self.0;
        let root = |mut x: u32| {
            while parent[x as usize] != x {
                x = parent[x as usize];
            }
            x
        };
        let roots: Vec<u32> = (0..parent.len() as u32)
            .into_par_iter()
            .with_min_len(crate::task_len(parent.len(), LABEL_CHUNK))
            .map(root)
            .collect();
        // The root is the smallest member, so it is labelled before any other member.
        first_seen_labels(roots)
    }
}

/// Elements per parallel task when labelling.
const LABEL_CHUNK: usize = 1 << 16;

/// Dense labels for elements given their representatives (`rep[i] <= i`, and a
/// representative is its own): numbered in order of the representatives; and the count.
/// Computed in place over `rep`, in parallel: each representative's rank among the
/// representatives (a prefix count by chunks), then every element takes its
/// representative's rank.
pub(crate) fn first_seen_labels(mut rep: Vec<u32>) -> (Vec<u32>, usize) {
    let n = rep.len();
    let chunk = crate::task_len(n, LABEL_CHUNK);
    let is_rep = |i: usize, r: u32| r as usize == i;
    let counts: Vec<u32> = rep
        .par_chunks(chunk)
        .enumerate()
        .map(|(k, ch)| {
            let base = k * chunk;
            ch.iter()
                .enumerate()
                .filter(|&(j, &r)| is_rep(base + j, r))
                .count() as u32
        })
        .collect();
    let offsets: Vec<u32> = counts
        .iter()
        .scan(0u32, |acc, &c| {
            let o = *acc;
            *acc += c;
            Some(o)
        })
        .collect();
    let total = counts.iter().sum::<u32>() as usize;
    // rank[i] for representatives i (other entries unused).
    let mut rank = vec![0u32; n];
    rank.par_chunks_mut(chunk)
        .zip(rep.par_chunks(chunk))
        .enumerate()
        .for_each(|(k, (out, ch))| {
            let (base, mut next) = (k * chunk, offsets[k]);
            for (j, &r) in ch.iter().enumerate() {
                if is_rep(base + j, r) {
                    out[j] = next;
                    next += 1;
                }
            }
        });
    rep.par_iter_mut()
        .with_min_len(chunk)
        .for_each(|r| *r = rank[*r as usize]);
    (rep, total)
}

/// [`UnionFind`] that many threads can join into at once (lock-free). Parents only ever point
/// to smaller members and a root is linked by compare-and-swap only while it is still a root,
/// so no cycle can form and no join is lost, whatever the interleaving.
#[derive(Debug)]
pub struct AtomicUnionFind(Vec<AtomicU32>);

impl AtomicUnionFind {
    /// `n` singleton sets.
    pub fn new(n: usize) -> Self {
        AtomicUnionFind((0..n as u32).map(AtomicU32::new).collect())
    }

    /// The current root of `x`'s set (path halving as it goes).
    #[inline]
    pub fn find(&self, mut x: u32) -> u32 {
        loop {
            let p = self.0[x as usize].load(Relaxed);
            if p == x {
                return x;
            }
            let gp = self.0[p as usize].load(Relaxed);
            if gp != p {
                // x is not a root, so only halving ever rewrites its parent; any ancestor is a
                // correct parent, so a plain store is enough (a racing halving may be undone,
                // never a link).
                self.0[x as usize].store(gp, Relaxed);
            }
            x = gp;
        }
    }

    /// Joins the sets of `a` and `b`.
    #[inline]
    pub fn join(&self, mut a: u32, mut b: u32) {
        loop {
            a = self.find(a);
            b = self.find(b);
            if a == b {
                return;
            }
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            if self.0[hi as usize]
                .compare_exchange(hi, lo, Relaxed, Relaxed)
                .is_ok()
            {
                return;
            }
            // `hi` stopped being a root meanwhile: look again from where it went.
        }
    }

    /// The sequential sets, once every join is done.
    pub fn into_sequential(self) -> UnionFind {
        UnionFind(self.0.into_iter().map(AtomicU32::into_inner).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_follow_first_members_whatever_the_join_order() {
        let joins = [(5u32, 2u32), (7, 5), (1, 3), (6, 0)];
        let mut a = UnionFind::new(8);
        let mut b = UnionFind::new(8);
        for &(x, y) in &joins {
            a.join(x, y);
        }
        for &(x, y) in joins.iter().rev() {
            b.join(y, x);
        }
        let expected = (vec![0, 1, 2, 1, 3, 2, 0, 2], 4);
        assert_eq!(a.labels(), expected);
        assert_eq!(b.labels(), expected);
    }

    #[test]
    fn parallel_labels_match_a_sequential_count_across_chunks() {
        // Representatives spread over several label chunks, some pointing back many chunks.
        let n = 5 * LABEL_CHUNK + 123;
        let rep: Vec<u32> = (0..n as u32)
            .map(|i| match i % 7 {
                0 | 3 => i,
                1 => i - 1,
                _ => (i.wrapping_mul(2_654_435_761) % (i + 1)) / 7 * 7,
            })
            .collect();
        let mut expected = vec![0u32; n];
        let mut count = 0;
        for (i, &r) in rep.iter().enumerate() {
            expected[i] = if r as usize == i {
                count += 1;
                count - 1
            } else {
                expected[r as usize]
            };
        }
        assert_eq!(first_seen_labels(rep), (expected, count as usize));
    }

    #[test]
    fn parallel_joins_end_in_the_sequential_sets() {
        use rayon::prelude::*;
        // A scrambled chain of joins over many sets, applied from several threads.
        let n = 200_000u32;
        let joins: Vec<(u32, u32)> = (0..n)
            .map(|i| (i.wrapping_mul(7919) % n, (i.wrapping_mul(104_729) + 13) % n))
            .filter(|(a, b)| a % 3 == b % 3)
            .collect();
        let atomic = AtomicUnionFind::new(n as usize);
        joins.par_iter().for_each(|&(a, b)| atomic.join(a, b));
        let mut seq = UnionFind::new(n as usize);
        for &(a, b) in &joins {
            seq.join(a, b);
        }
        assert_eq!(atomic.into_sequential().labels(), seq.labels());
    }
}
