//! The strands seen from the side: the fin texture. Silhouette fins (Lengyel et al.; Frantzen's
//! fin cards) show a slab of the fur edge-on, so the fin texture is the side view of the
//! strands whose roots lie in a slab `fin_depth` tile widths thick, rendered from the same
//! strands (same positions, radii, heights, lean) as the dots and heightfield. Columns span
//! the tile's width (wrapping, so fins tile along an edge); rows span the fur's height, root at
//! the bottom row, height 1 at the top.
//!
//! Channels: A = coverage from a 4 × 4 subsample grid per texel. RGB describe the strand that
//! covers most of the texel (ties go to the one nearest the viewer): R = height along that
//! strand (0 at the root, 1 at its tip, for a root-to-tip colour ramp), G = the strand's random
//! tint, B = across the strand (0 at its left edge, 0.5 on its axis, 1 at its right edge, for
//! cylindrical shading).

use rayon::prelude::*;

use crate::raster::SUB;
use crate::strands::Strand;

/// The side view.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FinView {
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// Per texel (row 0 = the top row, height 1): covered subsamples, bit `4·sz + sx` with
    /// sz counted from the bottom of the texel.
    pub mask: Vec<u16>,
    /// Per texel: R, G, B as described in the module documentation (0 where bare).
    pub rgb: Vec<[u8; 3]>,
}

const OFFSETS: [f64; SUB] = [0.125, 0.375, 0.625, 0.875];

/// Renders the side view of the strands whose root y is below `depth`, `width` × `height`
/// texels. `width` is the tile's size in texels (the unit of x).
pub fn side_view(strands: &[Strand], depth: f64, width: usize, height: usize) -> FinView {
    let slab: Vec<&Strand> = strands.iter().filter(|s| s.y < depth).collect();
    let n = width as f64;
    let rows = height as f64;
    let mut mask = vec![0u16; width * height];
    let mut rgb = vec![[0u8; 3]; width * height];
    mask.par_chunks_mut(width)
        .zip(rgb.par_chunks_mut(width))
        .enumerate()
        .for_each(|(image_row, (mask, rgb))| {
            let k = height - 1 - image_row; // rows counted from the bottom
            let z_lo = k as f64 / rows;
            let z_mid = (k as f64 + 0.5) / rows;
            // Per texel, the best strand so far: (covered subsamples, root y, slab index).
            let mut best: Vec<(u32, f64, usize)> = vec![(0, 0.0, usize::MAX); width];
            for (si, s) in slab.iter().enumerate() {
                if s.h < z_lo {
                    continue;
                }
                let (cx, r, tx) = (s.x * n, s.r * n, s.tx * n);
                // The axis moves by tx / rows within the row.
                let a_lo = cx + tx * z_lo;
                let a_hi = cx + tx * (z_lo + 1.0 / rows);
                let lo = a_lo.min(a_hi) - r - 1.0;
                let hi = a_lo.max(a_hi) + r + 1.0;
                let drift = (tx / rows).abs() * 0.5;
                let full_row = s.h >= z_lo + 1.0 / rows;
                for ox in [-n, 0.0, n] {
                    if hi + ox < 0.0 || lo + ox >= n {
                        continue;
                    }
                    let c0 = (lo + ox).floor().max(0.0) as usize;
                    let c1 = ((hi + ox).ceil() as isize).min(width as isize - 1);
                    if c1 < c0 as isize {
                        continue;
                    }
                    for col in c0..=c1 as usize {
                        let axis_mid = cx + ox + tx * z_mid;
                        let d = (col as f64 + 0.5 - axis_mid).abs();
                        if d >= r + 0.5 + drift {
                            continue;
                        }
                        let bits = if full_row && d <= r - 0.5 - drift {
                            u16::MAX
                        } else {
                            let mut bits = 0u16;
                            for (sz, oz) in OFFSETS.iter().enumerate() {
                                let z = (k as f64 + oz) / rows;
                                if z > s.h {
                                    continue;
                                }
                                let axis = cx + ox + tx * z;
                                for (sx, oxs) in OFFSETS.iter().enumerate() {
                                    if (col as f64 + oxs - axis).abs() <= r {
                                        bits |= 1 << (sz * SUB + sx);
                                    }
                                }
                            }
                            bits
                        };
                        if bits == 0 {
                            continue;
                        }
                        mask[col] |= bits;
                        let count = bits.count_ones();
                        let b = &mut best[col];
                        if count > b.0 || (count == b.0 && s.y < b.1) {
                            *b = (count, s.y, si);
                            let along = (z_mid / s.h).clamp(0.0, 1.0);
                            let across = ((col as f64 + 0.5 - axis_mid) / r).clamp(-1.0, 1.0);
                            rgb[col] = [unorm8(along), unorm8(s.tint), unorm8(0.5 + 0.5 * across)];
                        }
                    }
                }
            }
        });
    FinView {
        width,
        height,
        mask,
        rgb,
    }
}

fn unorm8(v: f64) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_upright_strand_is_a_band_up_to_its_height() {
        let s = Strand {
            x: 0.5,
            y: 0.0,
            r: 3.0 / 64.0,
            h: 0.5,
            tx: 0.0,
            ty: 0.0,
            tint: 0.25,
        };
        let v = side_view(&[s], 0.1, 64, 16);
        // Rows 8..16 (the bottom half) are covered across 6 texels, the top half is bare.
        for row in 0..16 {
            let covered: u32 = v.mask[row * 64..(row + 1) * 64]
                .iter()
                .map(|m| m.count_ones())
                .sum();
            let want = if row >= 8 { 6 * 16 } else { 0 };
            assert_eq!(covered, want, "row {row}");
        }
        let bottom = v.rgb[15 * 64 + 32];
        assert_eq!(bottom[1], 64);
        assert!(bottom[0] < 20, "{bottom:?}");
        // A strand outside the slab is not drawn.
        let v2 = side_view(&[Strand { y: 0.5, ..s }], 0.1, 64, 16);
        assert!(v2.mask.iter().all(|&m| m == 0));
    }
}
