//! Disjoint sets over `0..n` (union-find with path halving). The root of every set is its
//! smallest member, so the partition and its representatives do not depend on the order in
//! which joins arrive: [`AtomicUnionFind`] takes joins from many threads at once and ends in
//! the same sets as the sequential [`UnionFind`].

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

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
    pub fn labels(mut self) -> (Vec<u32>, usize) {
        let n = self.0.len();
        // The root is the smallest member, so it is labelled before any other member.
        let roots: Vec<u32> = (0..n as u32).map(|x| self.find(x)).collect();
        first_seen_labels(&roots)
    }
}

/// Dense labels for elements given their representatives (`rep[i] <= i`, and a
/// representative is its own): numbered in order of the representatives; and the count.
pub(crate) fn first_seen_labels(rep: &[u32]) -> (Vec<u32>, usize) {
    let mut label = vec![0u32; rep.len()];
    let mut count = 0u32;
    for (i, &r) in rep.iter().enumerate() {
        label[i] = if r as usize == i {
            count += 1;
            count - 1
        } else {
            label[r as usize]
        };
    }
    (label, count as usize)
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
