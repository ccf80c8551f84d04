//! Coverage-preserving mip chains.
//!
//! A box-filtered mip chain keeps the mean of a texture but not its distribution: thin strands
//! averaged with bare ground come out as low heights (or low alpha), so a shell that tests
//! `height > s` (Revie §2.4.4) or an alpha test shows fewer and fewer strands the further away
//! the fur is, and fur thins out into its skin. Castaño's alpha-test mipmaps rescale alpha to
//! keep the coverage at one threshold; shells test every threshold between 0 and 1, so pelt
//! keeps the whole distribution instead:
//!
//! 1. Level L is first box-filtered from level L − 1 (which orders its texels spatially).
//! 2. Its texels are ranked by that filtered value (ties by position: deterministic).
//! 3. Level 0's values, sorted, are cut into as many equal runs as level L has texels (each
//!    run 4^L texels long); the texel of rank k gets the mean of run k.
//!
//! Then for every threshold t the fraction of texels above t differs from level 0's by at most
//! one texel of level L (the run that straddles t), and the mean is kept exactly (up to
//! rounding), down to the 1 × 1 level. For the fin texture the distribution is matched per row
//! band (a row of level L against the rows of level 0 it covers), so the height profile is
//! kept too.

use rayon::prelude::*;

/// How texels are grouped when matching distributions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Groups {
    /// The whole image is one distribution (dots, heightfield).
    Whole,
    /// Each row of a level matches the rows of level 0 it covers (fin texture).
    Rows,
}

/// Sizes of mip level `level` of a `w` × `h` image.
pub fn level_size(w: usize, h: usize, level: usize) -> (usize, usize) {
    ((w >> level).max(1), (h >> level).max(1))
}

/// Number of levels below level 0 (down to 1 × 1).
pub fn level_count(w: usize, h: usize) -> usize {
    w.max(h).trailing_zeros() as usize
}

/// A sorted distribution: (value, count) with values ascending.
type Distribution = Vec<(u16, u64)>;

fn distribution(values: impl Iterator<Item = u16>, scratch: &mut [u32]) -> Distribution {
    let mut touched = Vec::new();
    for v in values {
        if scratch[v as usize] == 0 {
            touched.push(v);
        }
        scratch[v as usize] += 1;
    }
    touched.sort_unstable();
    touched
        .into_iter()
        .map(|v| {
            let c = std::mem::take(&mut scratch[v as usize]);
            (v, u64::from(c))
        })
        .collect()
}

fn merge(parts: &[Distribution]) -> Distribution {
    let mut all: Vec<(u16, u64)> = parts.iter().flatten().copied().collect();
    all.sort_unstable_by_key(|e| e.0);
    let mut out: Distribution = Vec::with_capacity(all.len());
    for (v, c) in all {
        match out.last_mut() {
            Some(last) if last.0 == v => last.1 += c,
            _ => out.push((v, c)),
        }
    }
    out
}

/// Stable LSD radix sort of (key, index) pairs packed as `key << 32 | index`, by key.
fn radix_sort(pairs: &mut Vec<u64>) {
    let mut tmp = vec![0u64; pairs.len()];
    for shift in [32u32, 40, 48, 56] {
        let mut counts = [0usize; 256];
        for &p in pairs.iter() {
            counts[((p >> shift) & 0xFF) as usize] += 1;
        }
        if counts.contains(&pairs.len()) {
            continue; // every key has the same digit here
        }
        let mut at = 0;
        for c in &mut counts {
            let n = *c;
            *c = at;
            at += n;
        }
        for &p in pairs.iter() {
            let d = ((p >> shift) & 0xFF) as usize;
            tmp[counts[d]] = p;
            counts[d] += 1;
        }
        std::mem::swap(pairs, &mut tmp);
    }
}

/// Box filter of `prev` (pw × ph) into level size (w, h), as the sum scaled to four children
/// (so keys from different child counts compare), in [0, 4 · 65535].
fn box_keys(prev: &[u16], pw: usize, ph: usize, w: usize, h: usize) -> Vec<u32> {
    let fx = pw / w;
    let fy = ph / h;
    let scale = 4 / (fx * fy) as u32;
    let mut keys = vec![0u32; w * h];
    keys.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, k) in row.iter_mut().enumerate() {
            let mut sum = 0u32;
            for dy in 0..fy {
                for dx in 0..fx {
                    sum += u32::from(prev[(y * fy + dy) * pw + x * fx + dx]);
                }
            }
            *k = sum * scale;
        }
    });
    keys
}

/// Levels 1 to 1 × 1 of a `w` × `h` chain: `make(keys, lw, lh)` turns the box-filter
/// keys of each level (from [`box_keys`] over the level above) into the level's values.
fn chain(
    level0: &[u16],
    w: usize,
    h: usize,
    mut make: impl FnMut(Vec<u32>, usize, usize) -> Vec<u16>,
) -> Vec<Vec<u16>> {
    let mut levels: Vec<Vec<u16>> = Vec::new();
    for level in 1..=level_count(w, h) {
        let (pw, ph) = level_size(w, h, level - 1);
        let (lw, lh) = level_size(w, h, level);
        let prev: &[u16] = levels.last().map_or(level0, Vec::as_slice);
        let keys = box_keys(prev, pw, ph, lw, lh);
        levels.push(make(keys, lw, lh));
    }
    levels
}

/// The mip chain of `level0` (w × h, both powers of two), levels 1 to 1 × 1.
pub fn coverage_chain(level0: &[u16], w: usize, h: usize, groups: Groups) -> Vec<Vec<u16>> {
    let mut scratch = vec![0u32; 1 << 16];
    let base: Vec<Distribution> = match groups {
        Groups::Whole => vec![distribution(level0.iter().copied(), &mut scratch)],
        Groups::Rows => level0
            .chunks(w)
            .map(|row| distribution(row.iter().copied(), &mut scratch))
            .collect(),
    };
    chain(level0, w, h, |keys, lw, lh| {
        let group_rows = match groups {
            Groups::Whole => lh,
            Groups::Rows => 1,
        };
        let mut pairs: Vec<u64> = keys
            .iter()
            .enumerate()
            .map(|(i, &k)| {
                let g = (i / (lw * group_rows)) as u64;
                ((g << 18 | u64::from(k)) << 32) | i as u64
            })
            .collect();
        radix_sort(&mut pairs);
        let mut out = vec![0u16; lw * lh];
        let per_group = lw * group_rows;
        for (g, ranked) in pairs.chunks(per_group).enumerate() {
            let merged;
            let dist: &Distribution = match groups {
                Groups::Whole => &base[0],
                Groups::Rows => {
                    let s = h / lh;
                    merged = merge(&base[g * s..(g + 1) * s]);
                    &merged
                }
            };
            let total: u64 = dist.iter().map(|e| e.1).sum();
            let run = total / ranked.len() as u64;
            let mut entry = 0;
            let mut left = dist.first().map_or(0, |e| e.1);
            for &p in ranked {
                let mut need = run;
                let mut sum = 0u64;
                while need > 0 {
                    while left == 0 {
                        entry += 1;
                        left = dist[entry].1;
                    }
                    let take = need.min(left);
                    sum += take * u64::from(dist[entry].0);
                    left -= take;
                    need -= take;
                }
                out[(p & 0xFFFF_FFFF) as usize] = ((sum + run / 2) / run) as u16;
            }
        }
        out
    })
}

/// Plain 2 × 2 box-filtered chain (what a GPU's mip generation does), for comparison.
pub fn box_chain(level0: &[u16], w: usize, h: usize) -> Vec<Vec<u16>> {
    chain(level0, w, h, |keys, _, _| {
        keys.into_iter().map(|k| ((k + 2) / 4) as u16).collect()
    })
}

/// Alpha-weighted 2 × 2 average of RGB for each level of a chain whose alphas are `alphas`
/// (level 0 first, then the levels of the chain).
pub fn rgb_chain(rgb0: &[[u8; 3]], alphas: &[&[u16]], w: usize, h: usize) -> Vec<Vec<[u8; 3]>> {
    let mut levels: Vec<Vec<[u8; 3]>> = Vec::new();
    for level in 1..alphas.len() {
        let (pw, ph) = level_size(w, h, level - 1);
        let (lw, lh) = level_size(w, h, level);
        let (fx, fy) = (pw / lw, ph / lh);
        let prev: &[[u8; 3]] = levels.last().map_or(rgb0, Vec::as_slice);
        let a = alphas[level - 1];
        let mut out = vec![[0u8; 3]; lw * lh];
        for (i, px) in out.iter_mut().enumerate() {
            let (x, y) = (i % lw, i / lw);
            let mut sum = [0u64; 3];
            let mut weight = 0u64;
            for dy in 0..fy {
                for dx in 0..fx {
                    let j = (y * fy + dy) * pw + x * fx + dx;
                    let wgt = u64::from(a[j]);
                    weight += wgt;
                    for c in 0..3 {
                        sum[c] += wgt * u64::from(prev[j][c]);
                    }
                }
            }
            if weight > 0 {
                *px = sum.map(|s| ((s + weight / 2) / weight) as u8);
            }
        }
        levels.push(out);
    }
    levels
}

#[cfg(test)]
mod tests {
    use super::*;

    fn above(values: &[u16], t: u16) -> f64 {
        values.iter().filter(|&&v| v > t).count() as f64 / values.len() as f64
    }

    #[test]
    fn sparse_dots_keep_their_coverage_where_a_box_filter_loses_it() {
        // One full texel in every 4 × 4 block: coverage 1/16 at every threshold below 65535.
        let n = 64;
        let img: Vec<u16> = (0..n * n)
            .map(|i| {
                if (i % n) % 4 == 0 && (i / n) % 4 == 0 {
                    65535
                } else {
                    0
                }
            })
            .collect();
        let chain = coverage_chain(&img, n, n, Groups::Whole);
        assert_eq!(chain.len(), 6);
        for (l, level) in chain.iter().enumerate().take(4) {
            for t in [0u16, 30000, 65000] {
                assert!(
                    (above(level, t) - 1.0 / 16.0).abs() < 1e-9,
                    "level {} t {t}: {}",
                    l + 1,
                    above(level, t)
                );
            }
        }
        let mean = |v: &[u16]| v.iter().map(|&x| f64::from(x)).sum::<f64>() / v.len() as f64;
        for level in &chain {
            assert!((mean(level) - 65535.0 / 16.0).abs() < 1.0);
        }
        // The box filter keeps the mean but at level 2 no texel passes t = 30000.
        let boxed = box_chain(&img, n, n);
        assert_eq!(above(&boxed[1], 30000), 0.0);
    }

    #[test]
    fn radix_sort_is_stable_by_key() {
        let mut v: Vec<u64> = [(5u64, 0u64), (1, 1), (5, 2), (0, 3), (1, 4), (300_000, 5)]
            .iter()
            .map(|&(k, i)| k << 32 | i)
            .collect();
        radix_sort(&mut v);
        let got: Vec<(u64, u64)> = v.iter().map(|p| (p >> 32, p & 0xFFFF_FFFF)).collect();
        assert_eq!(got, [(0, 3), (1, 1), (1, 4), (5, 0), (5, 2), (300_000, 5)]);
    }

    #[test]
    fn rows_keep_their_own_profile() {
        // Top half fully covered, bottom half bare: every level keeps the split per row.
        let (w, h) = (32, 8);
        let img: Vec<u16> = (0..w * h)
            .map(|i| if i / w < 4 { 65535 } else { 0 })
            .collect();
        let chain = coverage_chain(&img, w, h, Groups::Rows);
        let (lw, lh) = level_size(w, h, 1);
        assert_eq!(chain[0].len(), lw * lh);
        assert!(chain[0][..lw * 2].iter().all(|&v| v == 65535));
        assert!(chain[0][lw * 2..].iter().all(|&v| v == 0));
    }
}
