//! The strands seen from above: per texel, which of a 4×4 grid of subsamples some strand
//! covers (the anti-aliased dot texture) and the height of the tallest strand over the texel
//! centre (the heightfield Revie's shells compare against, §2.4.4). The tile is a torus: a
//! strand near a border is drawn on both sides, so the textures tile with no seam.
//!
//! Seen from above, a strand covers the capsule its cross-sections sweep (the disc at the
//! root moved along its lean up to its height). The heightfield holds, per texel centre, the
//! greatest height z ≤ h at which the strand's cross-section still covers it; for an upright
//! strand that is h over the whole disc. Shell s shows a texel where the heightfield exceeds
//! s, so the set a shell shows is exactly the set of texels some strand reaches above s.

use rayon::prelude::*;

use crate::strands::Strand;

/// Subsamples per texel side (4 × 4 = 16 per texel).
pub const SUB: usize = 4;
/// Half a texel diagonal: beyond this distance from the centre no subsample can be covered.
const HALF_DIAGONAL: f64 = std::f64::consts::FRAC_1_SQRT_2 + 1e-9;
/// Rows per parallel band.
const BAND: usize = 16;

/// The top view of a tile.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TopView {
    /// Side in texels.
    pub size: usize,
    /// Per texel (row-major, row 0 first): bit `4·sy + sx` set when subsample (sx, sy) is
    /// covered by some strand.
    pub mask: Vec<u16>,
    /// Per texel: the tallest strand over the centre, as round(height · 65535) (at least 1
    /// where covered), 0 where bare.
    pub height: Vec<u16>,
}

/// A strand in texel units, with its segment (root to the centre of its top cross-section).
#[derive(Clone, Copy)]
struct Footprint {
    cx: f64,
    cy: f64,
    r: f64,
    /// Lean per unit height, in texels.
    tx: f64,
    ty: f64,
    h: f64,
    /// Segment end offset: (tx, ty) · h.
    ex: f64,
    ey: f64,
}

impl Footprint {
    fn new(s: &Strand, n: f64) -> Self {
        Footprint {
            cx: s.x * n,
            cy: s.y * n,
            r: s.r * n,
            tx: s.tx * n,
            ty: s.ty * n,
            h: s.h,
            ex: s.tx * n * s.h,
            ey: s.ty * n * s.h,
        }
    }

    /// Squared distance from (qx, qy) (relative to the root) to the segment.
    #[inline]
    fn dist2(&self, qx: f64, qy: f64) -> f64 {
        let e2 = self.ex * self.ex + self.ey * self.ey;
        let t = if e2 > 0.0 {
            ((qx * self.ex + qy * self.ey) / e2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let dx = qx - t * self.ex;
        let dy = qy - t * self.ey;
        dx * dx + dy * dy
    }

    /// The greatest height z in [0, h] whose cross-section covers (qx, qy), given that some
    /// does.
    #[inline]
    fn top(&self, qx: f64, qy: f64) -> f64 {
        let a = self.tx * self.tx + self.ty * self.ty;
        if a <= 1e-18 {
            return self.h;
        }
        let b = qx * self.tx + qy * self.ty;
        let c = qx * qx + qy * qy - self.r * self.r;
        let disc = (b * b - a * c).max(0.0);
        ((b + disc.sqrt()) / a).clamp(0.0, self.h)
    }

    /// Extent in texels (x0, x1, y0, y1), padded by one texel for the subsamples.
    fn bounds(&self) -> (f64, f64, f64, f64) {
        (
            self.cx + self.ex.min(0.0) - self.r - 1.0,
            self.cx + self.ex.max(0.0) + self.r + 1.0,
            self.cy + self.ey.min(0.0) - self.r - 1.0,
            self.cy + self.ey.max(0.0) + self.r + 1.0,
        )
    }
}

/// The wrapped copies (offsets −n, 0, +n) of the span [lo, hi] that meet [0, n).
fn wraps(lo: f64, hi: f64, n: f64) -> impl Iterator<Item = f64> {
    [-n, 0.0, n]
        .into_iter()
        .filter(move |o| hi + o >= 0.0 && lo + o < n)
}

/// Height in [0, 1] as a 16-bit code, at least 1 (0 means bare).
fn height_code(z: f64) -> u16 {
    ((z * 65535.0).round() as u16).max(1)
}

/// Renders the top view of `strands` on a `size`² tile.
pub fn top_view(strands: &[Strand], size: usize) -> TopView {
    let n = size as f64;
    let prints: Vec<Footprint> = strands.iter().map(|s| Footprint::new(s, n)).collect();
    let band = BAND.min(size);
    let bands = size.div_ceil(band);
    // Which (strand, y offset) pairs touch each band; strand order is kept.
    let mut lists: Vec<Vec<(u32, f64)>> = vec![Vec::new(); bands];
    for (i, f) in prints.iter().enumerate() {
        let (_, _, y0, y1) = f.bounds();
        for oy in wraps(y0, y1, n) {
            let b0 = ((y0 + oy).max(0.0) as usize) / band;
            let b1 = (((y1 + oy).min(n - 1.0)) as usize) / band;
            for list in &mut lists[b0..=b1.min(bands - 1)] {
                list.push((i as u32, oy));
            }
        }
    }
    let mut mask = vec![0u16; size * size];
    let mut height = vec![0u16; size * size];
    mask.par_chunks_mut(band * size)
        .zip(height.par_chunks_mut(band * size))
        .zip(lists.par_iter())
        .enumerate()
        .for_each(|(b, ((mask, height), list))| {
            let row0 = b * band;
            let rows = mask.len() / size;
            for &(i, oy) in list {
                let f = prints[i as usize];
                let (x0, x1, y0, y1) = f.bounds();
                let r0 = ((y0 + oy).floor().max(row0 as f64) as usize).max(row0);
                let r1 = ((y1 + oy).ceil() as isize).min((row0 + rows) as isize - 1);
                if r1 < r0 as isize {
                    continue;
                }
                for ox in wraps(x0, x1, n) {
                    let c0 = (x0 + ox).floor().max(0.0) as usize;
                    let c1 = ((x1 + ox).ceil() as isize).min(size as isize - 1);
                    if c1 < c0 as isize {
                        continue;
                    }
                    for row in r0..=r1 as usize {
                        let qy = row as f64 + 0.5 - (f.cy + oy);
                        for col in c0..=c1 as usize {
                            let qx = col as f64 + 0.5 - (f.cx + ox);
                            let d = f.dist2(qx, qy).sqrt() - f.r;
                            if d >= HALF_DIAGONAL {
                                continue;
                            }
                            let at = (row - row0) * size + col;
                            let bits = if d <= -HALF_DIAGONAL {
                                u16::MAX
                            } else {
                                subsample_mask(&f, qx, qy)
                            };
                            mask[at] |= bits;
                            if d <= 0.0 {
                                let code = height_code(f.top(qx, qy));
                                if code > height[at] {
                                    height[at] = code;
                                }
                            }
                        }
                    }
                }
            }
        });
    TopView { size, mask, height }
}

/// Subsample offsets from the texel centre.
const OFFSETS: [f64; SUB] = [-0.375, -0.125, 0.125, 0.375];

fn subsample_mask(f: &Footprint, qx: f64, qy: f64) -> u16 {
    let r2 = f.r * f.r;
    let mut bits = 0u16;
    for (sy, oy) in OFFSETS.iter().enumerate() {
        for (sx, ox) in OFFSETS.iter().enumerate() {
            if f.dist2(qx + ox, qy + oy) <= r2 {
                bits |= 1 << (sy * SUB + sx);
            }
        }
    }
    bits
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strand(x: f64, y: f64, r: f64, h: f64) -> Strand {
        Strand {
            x,
            y,
            r,
            h,
            tx: 0.0,
            ty: 0.0,
            tint: 0.5,
        }
    }

    #[test]
    fn one_upright_strand_covers_its_disc_at_its_height() {
        let v = top_view(&[strand(0.5, 0.5, 4.0 / 64.0, 0.75)], 64);
        let covered = v.mask.iter().map(|m| m.count_ones()).sum::<u32>() as f64 / 16.0;
        let area = std::f64::consts::PI * 16.0;
        assert!((covered - area).abs() < 0.01 * area, "{covered} vs {area}");
        assert_eq!(v.height[32 * 64 + 32], height_code(0.75));
        assert_eq!(v.height[0], 0);
        let centres = v.height.iter().filter(|&&h| h > 0).count() as f64;
        assert!((centres - area).abs() < 0.1 * area);
    }

    #[test]
    fn a_strand_on_the_corner_shows_in_all_four_corners() {
        let v = top_view(&[strand(0.0, 0.0, 2.0 / 32.0, 1.0)], 32);
        for at in [0, 31, 31 * 32, 32 * 32 - 1] {
            assert_eq!(v.mask[at], u16::MAX, "texel {at}");
            assert_eq!(v.height[at], 65535);
        }
        assert_eq!(v.mask[16 * 32 + 16], 0);
    }

    #[test]
    fn a_leaning_strand_is_tallest_at_its_tip() {
        let mut s = strand(0.25, 0.5, 2.0 / 64.0, 1.0);
        s.tx = 20.0 / 64.0; // tip 20 texels to the right
        let v = top_view(&[s], 64);
        let row = 32 * 64;
        let root = v.height[row + 16];
        let tip = v.height[row + 16 + 20];
        assert!(root > 0 && tip > root, "{root} {tip}");
        assert!(tip > 60000 && root < 8000, "{root} {tip}");
    }
}
