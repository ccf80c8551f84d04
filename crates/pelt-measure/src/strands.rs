//! The converged fur reference: a scene prepared in [`Mode::Strands`] (explicit strands
//! from the strand model, Kajiya-Kay per light: `pelt_preview::features::strands`) rendered
//! again and again with the projection jittered within the pixel, the samples averaged in
//! linear light. Samples alternate between two halves; at every doubling of the count the two
//! half-sample means are compared with FLIP, and accumulation stops once they differ by at
//! most the target (0.005 by default): the figure is reported with the image, so a user can
//! see how converged the reference is.

use std::time::Instant;

use pelt_preview::view::View;
use pelt_preview::{Image, Mode, Preview, RenderError, SceneView};
use pelt_scene::asset::MeshData;
use pelt_scene::scene::Scene;

use crate::Flip;

/// How far to accumulate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Stop once the two halves differ by at most this FLIP mean.
    pub target: f32,
    /// Samples before the first check (a power of two, at least 2).
    pub min_samples: u32,
    /// Give up (not converged) after this many.
    pub max_samples: u32,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            target: 0.005,
            min_samples: 16,
            max_samples: 4096,
        }
    }
}

/// A converged (or not) strand reference.
#[derive(Debug, Clone)]
pub struct Reference {
    /// The mean of every sample, sRGB.
    pub image: Image,
    /// The mean in linear light, RGB per pixel.
    pub linear: Vec<[f32; 3]>,
    /// Samples taken.
    pub samples: u32,
    /// FLIP mean between the two half-sample images at the end.
    pub half_vs_half: f32,
    /// Whether `half_vs_half` reached the target.
    pub converged: bool,
    /// (samples, half-vs-half FLIP) at every check.
    pub history: Vec<(u32, f32)>,
    /// Wall time per sample (render and readback), milliseconds.
    pub ms_per_sample: f64,
    /// Strands drawn (every fur object's).
    pub strands: u64,
}

/// The R2 sequence (Roberts 2018) in [-0.5, 0.5)²: sample `i`'s offset within the pixel.
/// Its even and odd terms are each low-discrepancy, so both halves cover the pixel.
pub fn jitter(i: u32) -> (f32, f32) {
    const A1: f64 = 0.754_877_666_246_692_7;
    const A2: f64 = 0.569_840_290_998_053_3;
    let n = f64::from(i);
    let f = |a: f64| ((0.5 + n * a).fract() - 0.5) as f32;
    (f(A1), f(A2))
}

/// sRGB 8-bit to linear, per value.
fn srgb_to_linear_table() -> [f32; 256] {
    std::array::from_fn(|i| {
        let c = i as f32 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    })
}

/// Linear to sRGB 8-bit.
fn linear_to_srgb8(v: f32) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let s = if v <= 0.003_130_8 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5).floor() as u8
}

/// An image of `sum / n` (linear RGB sums).
fn mean_image(w: u32, h: u32, sum: &[[f64; 3]], n: u32) -> (Image, Vec<[f32; 3]>) {
    let n = f64::from(n.max(1));
    let linear: Vec<[f32; 3]> = sum.iter().map(|s| s.map(|v| (v / n) as f32)).collect();
    let rgba = linear
        .iter()
        .flat_map(|p| {
            [p[0], p[1], p[2]]
                .map(linear_to_srgb8)
                .into_iter()
                .chain([255])
        })
        .collect();
    (
        Image {
            width: w,
            height: h,
            rgba,
        },
        linear,
    )
}

/// Prepares `scene` in strands mode and accumulates it until converged ([`accumulate`]).
pub fn reference(
    preview: &mut Preview,
    scene: &Scene,
    meshes: &[MeshData],
    mesh_of: &[usize],
    opts: Options,
) -> Result<Reference, RenderError> {
    let mut sv = preview.prepare_loaded(scene, meshes, mesh_of, Mode::Strands)?;
    accumulate(preview, &mut sv, opts)
}

/// Accumulates jittered samples of `sv` (prepared in strands mode) until the two halves
/// differ by at most `opts.target`, or `opts.max_samples`.
pub fn accumulate(
    preview: &Preview,
    sv: &mut SceneView,
    opts: Options,
) -> Result<Reference, RenderError> {
    let (w, h) = sv.plan.output;
    let base: View = sv.plan.view;
    let table = srgb_to_linear_table();
    let px = (w * h) as usize;
    let mut halves = [vec![[0.0f64; 3]; px], vec![[0.0f64; 3]; px]];
    let mut history = Vec::new();
    let mut next_check = opts.min_samples.max(2).next_power_of_two();
    let max = opts.max_samples.max(next_check);
    let started = Instant::now();
    let mut n = 0;
    let mut last = f32::INFINITY;
    while n < max {
        preview.jitter(sv, &base, jitter(n));
        let img = preview.render(sv)?;
        let half = &mut halves[(n % 2) as usize];
        for (acc, p) in half.iter_mut().zip(img.rgba.chunks_exact(4)) {
            for c in 0..3 {
                acc[c] += f64::from(table[p[c] as usize]);
            }
        }
        n += 1;
        if n == next_check {
            let (a, _) = mean_image(w, h, &halves[0], n / 2);
            let (b, _) = mean_image(w, h, &halves[1], n / 2);
            last = Flip::new(&a, &b).map_or(f32::INFINITY, |f| f.mean());
            history.push((n, last));
            if last <= opts.target {
                break;
            }
            next_check *= 2;
        }
    }
    let elapsed = started.elapsed().as_secs_f64() * 1000.0;
    preview.jitter(sv, &base, (0.0, 0.0));
    let total: Vec<[f64; 3]> = halves[0]
        .iter()
        .zip(&halves[1])
        .map(|(a, b)| [a[0] + b[0], a[1] + b[1], a[2] + b[2]])
        .collect();
    let (image, linear) = mean_image(w, h, &total, n);
    let strands = sv
        .strands
        .iter()
        .flatten()
        .map(|s| u64::from(s.count))
        .sum();
    Ok(Reference {
        image,
        linear,
        samples: n,
        half_vs_half: last,
        converged: last <= opts.target,
        history,
        ms_per_sample: elapsed / f64::from(n.max(1)),
        strands,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jitter_halves_each_cover_the_pixel() {
        for half in 0..2 {
            let mut quadrants = [0; 4];
            for i in (half..64).step_by(2) {
                let (x, y) = jitter(i);
                assert!((-0.5..0.5).contains(&x) && (-0.5..0.5).contains(&y));
                quadrants[usize::from(x >= 0.0) + 2 * usize::from(y >= 0.0)] += 1;
            }
            assert!(quadrants.iter().all(|&q| q >= 5), "{quadrants:?}");
        }
    }

    #[test]
    fn srgb_round_trips() {
        let t = srgb_to_linear_table();
        for (i, &v) in t.iter().enumerate() {
            assert_eq!(linear_to_srgb8(v) as usize, i);
        }
    }
}
