//! The converged fur reference: a scene prepared in [`Mode::Strands`] (explicit strands
//! from the strand model, Kajiya-Kay per light: `pelt_preview::features::strands`) rendered
//! again and again at `k`× the output resolution (a stratified k × k grid of samples per
//! output pixel in one frame: the strands cost geometry, not fill, on a CPU rasterizer), the
//! grid jittered within its cell from frame to frame, every sample averaged in linear
//! light. Frames alternate between two halves; at every doubling of the frame count the two
//! half means are compared with FLIP, and accumulation stops once they differ by at most the
//! target (0.005 by default): the figure is reported with the image, so a user can see how
//! converged the reference is.

use std::time::Instant;

use pelt_preview::view::View;
use pelt_preview::{Image, Mode, Preview, RenderError, SceneView};
use pelt_scene::asset::MeshData;
use pelt_scene::scene::Scene;
use pelt_scene::shading::{linear_of_srgb8, srgb8};

use crate::Flip;

/// How far to accumulate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Stop once the two halves differ by at most this FLIP mean.
    pub target: f32,
    /// Samples per pixel before the first check.
    pub min_samples: u32,
    /// Give up (not converged) after this many samples per pixel.
    pub max_samples: u32,
    /// Samples per pixel side in one frame (None: chosen from the output size and the
    /// strands drawn, [`Options::grid_for`]).
    pub supersample: Option<u32>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            target: 0.005,
            min_samples: 16,
            max_samples: 4096,
            supersample: None,
        }
    }
}

/// Fine pixels a frame may hold per strand drawn: a frame's geometry (about 1.3 µs a strand
/// on llvmpipe) and its fill (about 0.6 µs a fine pixel where fur covers it) then cost about
/// alike, so a sample costs at most about twice its fill, and the larger grid stratifies
/// better (docs/reference.md has the measurements).
pub const FINE_PIXELS_PER_STRAND: u64 = 4;

/// The largest grid side: 256 samples per pixel a frame.
pub const MAX_GRID: u32 = 16;

/// The largest frame side a grid may make.
pub const MAX_FRAME_SIDE: u32 = 4096;

impl Options {
    /// The grid side `k` for an output of `size` before the strands are known: the most, up
    /// to 4, that keeps the frame within 2048 pixels a side.
    pub fn grid(&self, (w, h): (u32, u32)) -> u32 {
        self.supersample
            .unwrap_or_else(|| (2048 / w.max(h).max(1)).clamp(1, 4))
            .max(1)
    }

    /// The grid side `k` for an output of `size` drawing `strands` strands a frame: at least
    /// [`Options::grid`], and as large as [`FINE_PIXELS_PER_STRAND`] fine pixels per strand
    /// asks (at most [`MAX_GRID`], the frame at most [`MAX_FRAME_SIDE`] a side), so a frame's
    /// fill keeps pace with its geometry. Deterministic: the same scene always gets the
    /// same grid.
    pub fn grid_for(&self, size: (u32, u32), strands: u64) -> u32 {
        let base = self.grid(size);
        if self.supersample.is_some() {
            return base;
        }
        let (w, h) = (u64::from(size.0.max(1)), u64::from(size.1.max(1)));
        let wanted = (strands.saturating_mul(FINE_PIXELS_PER_STRAND) / (w * h)).isqrt();
        let fits = MAX_FRAME_SIDE / size.0.max(size.1).max(1);
        let k = u32::try_from(wanted)
            .unwrap_or(u32::MAX)
            .min(MAX_GRID)
            .min(fits);
        base.max(k)
    }
}

/// A converged (or not) strand reference.
#[derive(Debug, Clone)]
pub struct Reference {
    /// The mean of every sample, sRGB.
    pub image: Image,
    /// The mean in linear light, RGB per pixel.
    pub linear: Vec<[f32; 3]>,
    /// Samples taken per pixel (frames × k²).
    pub samples: u32,
    /// Frames rendered.
    pub frames: u32,
    /// Samples per pixel side in one frame.
    pub grid: u32,
    /// FLIP mean between the two half-sample images at the end.
    pub half_vs_half: f32,
    /// Whether `half_vs_half` reached the target.
    pub converged: bool,
    /// (samples per pixel, half-vs-half FLIP) at every check.
    pub history: Vec<(u32, f32)>,
    /// Wall time per sample per pixel (a frame's render and readback over k²),
    /// milliseconds.
    pub ms_per_sample: f64,
    /// Wall time per frame, milliseconds.
    pub ms_per_frame: f64,
    /// Strands drawn (every fur object's).
    pub strands: u64,
}

impl Reference {
    /// The reference if it converged to `target`, else why not (nothing should be written).
    pub fn converged(self, target: f32) -> Result<Reference, NotConverged> {
        if self.converged {
            return Ok(self);
        }
        Err(NotConverged {
            samples: self.samples,
            half_vs_half: self.half_vs_half,
            target,
        })
    }
}

/// `4 096 strands, 64 samples per pixel in 4 frames of 4×4, half-vs-half FLIP 0.0040, 95 ms
/// per frame`.
impl std::fmt::Display for Reference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} strands, {} samples per pixel in {} frames of {}×{}, half-vs-half FLIP {:.4}, {:.0} ms per frame",
            self.strands,
            self.samples,
            self.frames,
            self.grid,
            self.grid,
            self.half_vs_half,
            self.ms_per_frame
        )
    }
}

/// The strand reference stopped short of its target.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error(
    "the strand reference did not converge: after {samples} samples the two halves differ by FLIP {half_vs_half:.4} (target {target}); raise --max-samples or --target-flip; nothing written"
)]
pub struct NotConverged {
    /// Samples per pixel taken.
    pub samples: u32,
    /// The two halves' FLIP mean at the end.
    pub half_vs_half: f32,
    /// The target.
    pub target: f32,
}

/// Sample `i`'s offset within the pixel (the R2 sequence; one home with the viewer's
/// progressive refinement).
pub use pelt_preview::progressive::jitter;

/// sRGB 8-bit to linear, per value ([`pelt_scene::shading::linear_of_srgb8`] tabulated).
fn srgb_to_linear_table() -> [f32; 256] {
    std::array::from_fn(|i| linear_of_srgb8(i as u8))
}

/// An image of `sum / n` (linear RGB sums).
fn mean_image(w: u32, h: u32, sum: &[[f64; 3]], n: u32) -> (Image, Vec<[f32; 3]>) {
    let n = f64::from(n.max(1));
    let linear: Vec<[f32; 3]> = sum.iter().map(|s| s.map(|v| (v / n) as f32)).collect();
    let rgba = linear
        .iter()
        .flat_map(|p| [p[0], p[1], p[2]].map(srgb8).into_iter().chain([255]))
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

/// Prepares `scene` in strands mode at k× its output size and accumulates it until
/// converged ([`accumulate`]).
pub fn reference(
    preview: &mut Preview,
    scene: &Scene,
    meshes: &[MeshData],
    mesh_of: &[usize],
    opts: Options,
) -> Result<Reference, RenderError> {
    reference_with(preview, (scene, meshes, mesh_of), opts, &mut |_| {})
}

/// Where the strand reference stands: told once when it is prepared (`frames` 0) and after
/// every frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// Frames drawn so far.
    pub frames: u32,
    /// The most frames it will draw (`max_samples`); it stops sooner once converged.
    pub max_frames: u32,
    /// Samples per pixel so far.
    pub samples: u32,
    /// The two halves' FLIP at the last check (None before the first).
    pub half_vs_half: Option<f32>,
    /// The FLIP it stops at.
    pub target: f32,
    /// Strands drawn each frame.
    pub strands: u64,
    /// Seconds since it started preparing.
    pub elapsed: f64,
}

/// [`reference`], telling `progress` where it stands (for a progress bar).
pub fn reference_with(
    preview: &mut Preview,
    (scene, meshes, mesh_of): (&Scene, &[MeshData], &[usize]),
    opts: Options,
    progress: &mut dyn FnMut(&Step),
) -> Result<Reference, RenderError> {
    let started = Instant::now();
    let size = (scene.output.width, scene.output.height);
    let at = |k: u32| {
        let mut fine = scene.clone();
        fine.output.width = size.0 * k;
        fine.output.height = size.1 * k;
        fine
    };
    let first = opts.grid(size);
    let mut sv = preview.prepare_loaded(&at(first), meshes, mesh_of, Mode::Strands)?;
    let k = opts.grid_for(size, strands_of(&sv));
    if k != first {
        preview.update(&mut sv, &at(k), Mode::Strands)?;
    }
    accumulate(preview, &mut sv, k, opts, &mut |s: &Step| {
        progress(&Step {
            elapsed: started.elapsed().as_secs_f64(),
            ..*s
        });
    })
}

/// The strands `sv` draws a frame (every fur object's).
fn strands_of(sv: &SceneView) -> u64 {
    sv.owned
        .get::<pelt_preview::features::strands::SceneStrands>()
        .map_or(&[][..], |s| &s.0)
        .iter()
        .flatten()
        .map(|s| u64::from(s.count))
        .sum()
}

/// Adds frame `img` (k× the output size) into `sum`: each output pixel takes its k × k
/// block.
fn add_blocks(sum: &mut [[f64; 3]], img: &Image, k: u32, table: &[f32; 256]) {
    let w = img.width / k;
    for y in 0..img.height {
        let row = (y / k * w) as usize;
        for x in 0..img.width {
            let p = img.pixel(x, y);
            let acc = &mut sum[row + (x / k) as usize];
            for c in 0..3 {
                acc[c] += f64::from(table[p[c] as usize]);
            }
        }
    }
}

/// Accumulates jittered frames of `sv` (prepared in strands mode at `k`× the output size)
/// until the two halves differ by at most `opts.target`, or `opts.max_samples` samples per
/// pixel.
pub fn accumulate(
    preview: &Preview,
    sv: &mut SceneView,
    k: u32,
    opts: Options,
    progress: &mut dyn FnMut(&Step),
) -> Result<Reference, RenderError> {
    let k = k.max(1);
    let (w, h) = (sv.plan.output.0 / k, sv.plan.output.1 / k);
    let base: View = sv.plan.view;
    let table = srgb_to_linear_table();
    let px = (w * h) as usize;
    let mut halves = [vec![[0.0f64; 3]; px], vec![[0.0f64; 3]; px]];
    let mut history = Vec::new();
    let per_frame = k * k;
    // Frames come in pairs (one per half); checks at every doubling.
    let mut next_check = (opts.min_samples.div_ceil(per_frame))
        .max(2)
        .next_power_of_two();
    // An even count, so the halves end alike; the last frame is a check too.
    let max_frames = opts
        .max_samples
        .div_ceil(per_frame)
        .max(next_check)
        .next_multiple_of(2);
    let started = Instant::now();
    let mut n = 0;
    let mut last = f32::INFINITY;
    let strands = strands_of(sv);
    let mut step = Step {
        frames: 0,
        max_frames,
        samples: 0,
        half_vs_half: None,
        target: opts.target,
        strands,
        elapsed: 0.0,
    };
    progress(&step);
    while n < max_frames {
        preview.jitter(sv, &base, jitter(n));
        let img = preview.render(sv)?;
        add_blocks(&mut halves[(n % 2) as usize], &img, k, &table);
        n += 1;
        let check = n == next_check || n == max_frames;
        if check {
            let (a, _) = mean_image(w, h, &halves[0], n / 2 * per_frame);
            let (b, _) = mean_image(w, h, &halves[1], n / 2 * per_frame);
            last = Flip::new(&a, &b).map_or(f32::INFINITY, |f| f.mean());
            history.push((n * per_frame, last));
            step.half_vs_half = Some(last);
        }
        step.frames = n;
        step.samples = n * per_frame;
        step.elapsed = started.elapsed().as_secs_f64();
        progress(&step);
        if check {
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
    let samples = n * per_frame;
    let (image, linear) = mean_image(w, h, &total, samples);
    Ok(Reference {
        image,
        linear,
        samples,
        frames: n,
        grid: k,
        half_vs_half: last,
        converged: last <= opts.target,
        history,
        ms_per_sample: elapsed / f64::from(samples.max(1)),
        ms_per_frame: elapsed / f64::from(n.max(1)),
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
    fn the_grid_grows_with_the_strands_within_its_bounds() {
        let o = Options::default();
        // Few strands: the frame-size rule alone (4 up to 512 pixels a side).
        assert_eq!(o.grid_for((160, 90), 6_000), 4);
        assert_eq!(o.grid_for((1280, 720), 6_000), 1);
        // The fixture sphere's 432,000 strands: 4 fine pixels each over 160×90 is 10 a side.
        assert_eq!(o.grid_for((160, 90), 432_000), 10);
        assert_eq!(o.grid_for((1280, 720), 432_000), 1);
        assert_eq!(o.grid_for((1280, 720), 2_000_000), 2);
        // At most 16 a side, and a frame at most 4096 pixels a side.
        assert_eq!(o.grid_for((160, 90), 100_000_000), MAX_GRID);
        assert_eq!(o.grid_for((1000, 10), 100_000_000), 4);
        // A grid asked for is kept.
        let fixed = Options {
            supersample: Some(2),
            ..o
        };
        assert_eq!(fixed.grid_for((160, 90), 432_000), 2);
    }

    #[test]
    fn srgb_round_trips() {
        let t = srgb_to_linear_table();
        for (i, &v) in t.iter().enumerate() {
            assert_eq!(srgb8(v) as usize, i);
        }
    }
}
