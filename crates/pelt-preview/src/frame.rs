//! Running a frame: the passes in order as recipes, their pipelines compiled, encoded,
//! submitted, the image read back ([`crate::readback`]); and timing whole frames (wall clock,
//! after warm-up) and single passes (GPU timestamps where the back end's are real time, Vulkan; wall time per separately submitted pass elsewhere, as on GL
//! llvmpipe whose timestamps are wrong).

use std::time::Instant;

use crate::draw::MissingInput;
use crate::feature::{DrawsInto, Frame, Output, planned};
use crate::features;
use crate::pass::Pass;
use crate::recipe::{Counts, Queries, Recipe};
use crate::renderer::Renderer;
use crate::targets::Target;
use crate::work::{self, Work};

pub use crate::readback::{FrameError, Image, read_back, read_back_layer, read_buffer, wait};
use crate::readback::{encoder, map_read, query_buffers};

/// Whether a frame renders the distance maps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Maps {
    /// Only when they are stale (the first frame, or the scene or its knobs changed): they
    /// depend on the scene, not on the camera.
    IfStale,
    /// Every frame (what a scene whose objects move would pay; the timing default).
    Always,
    /// Not in this frame (another view of the same frame renders them).
    Never,
}

/// The frame's passes as recipes: each pass of the frame's feature table that its plan
/// wants, in the registry's order ([`planned`]), built by the feature that registered it.
pub fn recipes<'a>(outer: &Frame<'a>, maps: Maps) -> Result<Vec<Recipe<'a>>, MissingInput> {
    let mut out = Vec::new();
    // Every pass before the resolve draws into the scene colour where the plan has one.
    let inner = &features::resolve::inner(outer)?;
    for b in planned(inner.features, inner.plan) {
        let skip = b.cached.is_some_and(|c| match maps {
            Maps::IfStale => (c.fresh)(inner),
            Maps::Always => false,
            Maps::Never => true,
        });
        if skip {
            continue;
        }
        let f = match b.into {
            DrawsInto::Scene => inner,
            DrawsInto::Output => outer,
        };
        b.build.run(f, &mut out)?;
    }
    Ok(out)
}

/// Records that the submitted frame `f` drew (or kept) the planned passes whose output
/// outlives it.
fn mark_drawn(f: &Frame<'_>) {
    for c in planned(f.features, f.plan).iter().filter_map(|b| b.cached) {
        (c.drawn)(f);
    }
}

/// Builds the frame's recipes and compiles the pipelines they use that are not cached yet.
fn prepared<'a>(r: &Renderer, f: &Frame<'a>, maps: Maps) -> Result<Vec<Recipe<'a>>, FrameError> {
    let recipes = recipes(f, maps)?;
    r.prepare(recipes.iter().flat_map(Recipe::keys))?;
    Ok(recipes)
}

/// Encodes and submits one whole frame.
fn submit_frame(r: &Renderer, recipes: &[Recipe<'_>]) -> Result<(), FrameError> {
    let mut enc = encoder(r);
    for p in recipes {
        p.encode(r, &mut enc, Queries::default())?;
    }
    r.gpu.queue.submit([enc.finish()]);
    Ok(())
}

/// Renders several views in one frame: every view's passes in one submission, then each
/// view's image read back (each frame must draw into its targets' own colour target).
pub fn render_many(r: &Renderer, frames: &[Frame<'_>]) -> Result<Vec<Image>, FrameError> {
    let scope = r.gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let mut all = Vec::new();
    for (i, f) in frames.iter().enumerate() {
        // The views share the scene's maps: the first renders them if they are stale.
        let maps = if i == 0 { Maps::IfStale } else { Maps::Never };
        all.extend(prepared(r, f, maps)?);
    }
    submit_frame(r, &all)?;
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(FrameError::Device(e.to_string()));
    }
    if let Some(f) = frames.first() {
        mark_drawn(f);
    }
    frames
        .iter()
        .map(|f| {
            let target = f.targets.color.as_ref().ok_or_else(|| MissingInput {
                pass: "output",
                what: "a colour target of the view's own".into(),
            })?;
            read_back(r, &target.texture, f.plan.output)
        })
        .collect()
}

/// Renders one frame of `f` and submits it (into a window's surface, or the view's own
/// target), with device errors checked.
pub fn draw(r: &Renderer, f: &Frame<'_>) -> Result<(), FrameError> {
    let scope = r.gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let recipes = prepared(r, f, Maps::IfStale)?;
    submit_frame(r, &recipes)?;
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(FrameError::Device(e.to_string()));
    }
    mark_drawn(f);
    if let Some(e) = r.gpu.take_error() {
        return Err(FrameError::Device(e));
    }
    Ok(())
}

/// Renders one frame into `target` (the view's own colour target) and reads it back.
pub fn render(r: &Renderer, f: &Frame<'_>, target: &Target) -> Result<Image, FrameError> {
    draw(r, f)?;
    read_back(r, &target.texture, f.plan.output)
}

/// How pass times were measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PassClock {
    /// GPU timestamp queries (Vulkan).
    Gpu,
    /// Wall time around each pass submitted and waited for on its own.
    Wall,
}

/// One pass of the profile: its time on the device, the CPU's time to encode it, and what it
/// asks of the GPU.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PassProfile {
    /// The pass.
    pub pass: &'static str,
    /// Its time ([`Timings::clock`]), median.
    pub ms: f64,
    /// The CPU's time to encode it into the frame's command buffer, median.
    pub encode_ms: f64,
    /// Draws, state changes, triangles and vertex bytes.
    #[serde(flatten)]
    pub counts: Counts,
    /// Fragment-shader invocations and samples written, counted by the GPU in one frame
    /// (where it counts them; [`crate::work`]).
    #[serde(flatten)]
    pub work: Work,
}

/// Medians over timed frames, in milliseconds: where a frame's time goes.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Timings {
    /// Whole frames: encode, submit, wait.
    pub frame_ms: f64,
    /// The CPU's part of a frame: encoding every pass and finishing the command buffer.
    pub encode_ms: f64,
    /// The CPU's time in `queue.submit` (validation and hand-off to the driver).
    pub submit_ms: f64,
    /// Each pass (a pass of several recipes, as a distance map's faces, summed).
    #[serde(skip)]
    pub passes: Vec<(Pass, f64)>,
    /// Each pass with its encode time and counts.
    pub profile: Vec<PassProfile>,
    /// How the pass times were taken.
    pub clock: PassClock,
    /// Frames timed (after warm-up).
    pub frames: usize,
}

impl Timings {
    /// Each pass as `name ms`, to `digits` decimals, comma-separated.
    pub fn passes_line(&self, digits: usize) -> String {
        let passes: Vec<String> = self
            .passes
            .iter()
            .map(|(p, ms)| format!("{} {ms:.digits$}", p.name()))
            .collect();
        passes.join(", ")
    }

    /// The profile as a Markdown table: a row per pass (device time, CPU encode time, draws,
    /// pipeline and bind-group changes, triangles, vertex bytes, fragment-shader invocations
    /// and samples written, "–" where the device does not count them) and the frame's CPU
    /// rows.
    pub fn profile_table(&self) -> String {
        let mut t = String::from(
            "| pass | ms | encode ms | draws | pipelines | binds | buffers | triangles | vertex bytes | fragments | samples |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
        );
        let counted = |v: Option<u64>| v.map_or_else(|| "–".to_string(), |v| v.to_string());
        let mut total = Counts::default();
        let mut all = Work::default();
        for p in &self.profile {
            let c = &p.counts;
            total += *c;
            all += p.work;
            t += &format!(
                "| {} | {:.2} | {:.3} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                p.pass,
                p.ms,
                p.encode_ms,
                c.draws,
                c.pipelines,
                c.binds,
                c.buffers,
                c.triangles,
                c.vertex_bytes,
                counted(p.work.fragments),
                counted(p.work.samples)
            );
        }
        let c = total;
        t += &format!(
            "| all passes | {:.2} | {:.3} | {} | {} | {} | {} | {} | {} | {} | {} |\n| submit (CPU) | | {:.3} | | | | | | | | |\n| frame (wall) | {:.2} | | | | | | | | | |\n",
            self.profile.iter().map(|p| p.ms).sum::<f64>(),
            self.encode_ms,
            c.draws,
            c.pipelines,
            c.binds,
            c.buffers,
            c.triangles,
            c.vertex_bytes,
            counted(all.fragments),
            counted(all.samples),
            self.submit_ms,
            self.frame_ms
        );
        t
    }
}

/// `frame 3.20 ms (median of 15; CPU: encode 0.40 ms, submit 0.10 ms); passes (GPU
/// timestamps): geometry 1.10 ms, …`.
impl std::fmt::Display for Timings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let passes: Vec<String> = self
            .passes
            .iter()
            .map(|(p, ms)| format!("{} {ms:.2} ms", p.name()))
            .collect();
        write!(
            f,
            "frame {:.2} ms (median of {}; CPU: encode {:.2} ms, submit {:.2} ms); passes ({}): {}",
            self.frame_ms,
            self.frames,
            self.encode_ms,
            self.submit_ms,
            match self.clock {
                PassClock::Gpu => "GPU timestamps",
                PassClock::Wall => "wall time, each pass submitted alone",
            },
            passes.join(", ")
        )
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() { 0.0 } else { v[v.len() / 2] }
}

/// Times `frames` frames after `warmup` untimed ones (the distance maps are rendered in each).
pub fn time(
    r: &Renderer,
    f: &Frame<'_>,
    warmup: usize,
    frames: usize,
) -> Result<Timings, FrameError> {
    let device = &r.gpu.device;
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    // Every timed frame renders the distance maps, as a scene whose objects move would.
    let recipes = prepared(r, f, Maps::Always)?;
    for _ in 0..warmup {
        submit_frame(r, &recipes)?;
        wait(r)?;
    }
    let mut whole = Vec::with_capacity(frames);
    let mut cpu = CpuTimes::new(recipes.len(), frames);
    for _ in 0..frames {
        let t = Instant::now();
        cpu.submit_frame(r, &recipes)?;
        wait(r)?;
        whole.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let (per, clock) = if r.gpu.timestamps {
        (gpu_pass_times(r, &recipes, frames)?, PassClock::Gpu)
    } else {
        (wall_pass_times(r, &recipes, frames)?, PassClock::Wall)
    };
    let counted = work::count(r, &recipes)?;
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(FrameError::Device(e.to_string()));
    }
    // A pass of many recipes (a distance map's faces) is their sum.
    let mut profile: Vec<(Pass, PassProfile)> = Vec::new();
    for (((recipe, ms), encode_ms), counted) in recipes
        .iter()
        .zip(per.into_iter().map(median))
        .zip(cpu.encode.into_iter().map(median))
        .zip(counted)
    {
        let pass = recipe.pass;
        let at = match profile.iter().position(|(p, _)| *p == pass) {
            Some(i) => i,
            None => {
                profile.push((
                    pass,
                    PassProfile {
                        pass: pass.name(),
                        ms: 0.0,
                        encode_ms: 0.0,
                        counts: Counts::default(),
                        work: Work::default(),
                    },
                ));
                profile.len() - 1
            }
        };
        let p = &mut profile[at].1;
        p.ms += ms;
        p.encode_ms += encode_ms;
        p.counts += recipe.counts();
        p.work += counted.unwrap_or_default();
    }
    Ok(Timings {
        frame_ms: median(whole),
        encode_ms: median(cpu.frame_encode),
        submit_ms: median(cpu.submit),
        passes: profile.iter().map(|(p, x)| (*p, x.ms)).collect(),
        profile: profile.into_iter().map(|(_, x)| x).collect(),
        clock,
        frames,
    })
}

/// The CPU's side of timed frames: each recipe's encode time, the whole frame's encode time
/// (with the command buffer finished) and the submit call.
struct CpuTimes {
    encode: Vec<Vec<f64>>,
    frame_encode: Vec<f64>,
    submit: Vec<f64>,
}

impl CpuTimes {
    fn new(recipes: usize, frames: usize) -> CpuTimes {
        CpuTimes {
            encode: vec![Vec::with_capacity(frames); recipes],
            frame_encode: Vec::with_capacity(frames),
            submit: Vec::with_capacity(frames),
        }
    }

    /// [`submit_frame`], timed.
    fn submit_frame(&mut self, r: &Renderer, recipes: &[Recipe<'_>]) -> Result<(), FrameError> {
        let ms = |t: Instant| t.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        let mut enc = encoder(r);
        for (p, times) in recipes.iter().zip(&mut self.encode) {
            let t = Instant::now();
            p.encode(r, &mut enc, Queries::default())?;
            times.push(ms(t));
        }
        let buffer = enc.finish();
        self.frame_encode.push(ms(start));
        let t = Instant::now();
        r.gpu.queue.submit([buffer]);
        self.submit.push(ms(t));
        Ok(())
    }
}

/// Each pass's time in each of `frames` frames from GPU timestamps (Vulkan).
fn gpu_pass_times(
    r: &Renderer,
    recipes: &[Recipe<'_>],
    frames: usize,
) -> Result<Vec<Vec<f64>>, FrameError> {
    let device = &r.gpu.device;
    let n = recipes.len() as u32 * 2;
    let set = device.create_query_set(&wgpu::QuerySetDescriptor {
        label: Some("pass times"),
        ty: wgpu::QueryType::Timestamp,
        count: n,
    });
    let bytes = u64::from(n) * 8;
    let (resolve, read) = query_buffers(r, "timestamps", bytes);
    let period = f64::from(r.gpu.queue.get_timestamp_period());
    let mut per: Vec<Vec<f64>> = vec![Vec::with_capacity(frames); recipes.len()];
    for _ in 0..frames {
        let mut enc = encoder(r);
        for (i, p) in recipes.iter().enumerate() {
            let timestamps = Some(wgpu::RenderPassTimestampWrites {
                query_set: &set,
                beginning_of_pass_write_index: Some(2 * i as u32),
                end_of_pass_write_index: Some(2 * i as u32 + 1),
            });
            let q = Queries {
                timestamps,
                ..Queries::default()
            };
            p.encode(r, &mut enc, q)?;
        }
        enc.resolve_query_set(&set, 0..n, &resolve, 0);
        enc.copy_buffer_to_buffer(&resolve, 0, &read, 0, bytes);
        r.gpu.queue.submit([enc.finish()]);
        {
            let m = map_read(r, &read)?;
            let t: &[u64] = bytemuck::cast_slice(&m);
            for (i, v) in per.iter_mut().enumerate() {
                v.push(t[2 * i + 1].saturating_sub(t[2 * i]) as f64 * period / 1e6);
            }
        }
        read.unmap();
    }
    Ok(per)
}

/// Each pass's time in each of `frames` frames as wall time, each pass submitted and
/// waited for alone (GL, whose timestamps are wrong on llvmpipe).
fn wall_pass_times(
    r: &Renderer,
    recipes: &[Recipe<'_>],
    frames: usize,
) -> Result<Vec<Vec<f64>>, FrameError> {
    let mut per: Vec<Vec<f64>> = vec![Vec::with_capacity(frames); recipes.len()];
    for _ in 0..frames {
        for (i, p) in recipes.iter().enumerate() {
            let t = Instant::now();
            let mut enc = encoder(r);
            p.encode(r, &mut enc, Queries::default())?;
            r.gpu.queue.submit([enc.finish()]);
            wait(r)?;
            per[i].push(t.elapsed().as_secs_f64() * 1e3);
        }
    }
    Ok(per)
}

/// Draws the overlay's text over `output` (the window's surface) and submits it.
pub fn overlay(
    r: &Renderer,
    ov: &features::overlay::Overlay,
    output: Output<'_>,
) -> Result<(), FrameError> {
    let Some(recipe) = ov.pass(output) else {
        return Ok(());
    };
    r.prepare(recipe.keys())?;
    submit_frame(r, std::slice::from_ref(&recipe))
}

/// Scales `source`'s frame up into `output` (the window's surface) and submits it.
pub fn upscale(
    r: &Renderer,
    up: &features::upscale::Upscale,
    output: Output<'_>,
) -> Result<(), FrameError> {
    let recipe = up.pass(output);
    r.prepare(recipe.keys())?;
    submit_frame(r, std::slice::from_ref(&recipe))
}
