//! `pelt sweep`: every quality knob's time against its error. The scene is rendered at each
//! value of each knob (one knob at a time around the defaults, or every combination), in one
//! renderer: a knob that lives in the renderer changes the plan and the uniforms of one
//! prepared scene and uploads no asset; a knob that lives in the asset (texture size,
//! heightfield bits, comb quantization) bakes the asset again. Each setting is timed (median
//! of N frames after warm-up: GPU timestamps where the back end's are real time, wall time
//! otherwise) and measured with FLIP against its knob's reference: the converged strand
//! reference for the fur's knobs, a full-resolution deferred frame for the lighting knobs,
//! the CPU ray tracer for the distance-map knobs. [`report`] writes the tables, [`plot`] the
//! pictures.

pub mod knob;
pub mod plot;
pub mod rebake;
pub mod report;
pub mod table;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use pelt_preview::frame::PassClock;
use pelt_preview::{Image, Mode, Preview, RenderError, SceneView};
use pelt_scene::asset::MeshData;
use pelt_scene::knobs::{self, InputError, Knobs};
use pelt_scene::scene::{Material, Scene};

use crate::Flip;
use crate::reflections::MeasureError;
use knob::{Knob, KnobError, Need, Own, Setting, Truth, Value};
use table::KNOBS;

/// What to sweep and how.
#[derive(Debug, Clone)]
pub struct Options {
    /// Knobs with their values; empty: every knob that applies, at its default values.
    pub knobs: Vec<(&'static Knob, Vec<Value>)>,
    /// Every combination instead of one knob at a time.
    pub grid: bool,
    /// Timed frames per setting.
    pub frames: usize,
    /// Untimed frames before them.
    pub warmup: usize,
    /// How far the strand reference converges.
    pub reference: crate::strands::Options,
    /// Where images, re-baked assets and reports go.
    pub out: PathBuf,
}

/// Most settings a grid may have.
pub const MAX_SETTINGS: usize = 512;

/// A drawing error on the in-memory bitmap the pictures are drawn on.
pub type PlotError = plotters::drawing::DrawingAreaErrorKind<
    <plotters::prelude::BitMapBackend<'static> as plotters::prelude::DrawingBackend>::ErrorType,
>;

/// Why a PNG the sweep wrote (a heat map) could not be read back.
#[derive(Debug, thiserror::Error)]
pub enum ReadBackError {
    /// The file could not be opened.
    #[error(transparent)]
    Open(#[from] std::io::Error),
    /// The PNG decoder refused it.
    #[error(transparent)]
    Png(#[from] png::DecodingError),
    /// It is not the 8-bit RGBA the sweep writes.
    #[error("not an 8-bit RGBA PNG")]
    NotRgba8,
}

/// Why a sweep stopped.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// A knob or value is not allowed (usage).
    #[error(transparent)]
    Knob(#[from] KnobError),
    /// The grid is too large (usage).
    #[error(
        "--grid would render {0} settings (at most {MAX_SETTINGS}): give fewer knobs or values"
    )]
    TooMany(usize),
    /// The input could not be loaded.
    #[error(transparent)]
    Input(#[from] InputError),
    /// Rendering failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The ray-traced reference failed.
    #[error(transparent)]
    Measure(#[from] MeasureError),
    /// An asset could not be baked again.
    #[error(transparent)]
    Rebake(#[from] rebake::RebakeError),
    /// The strand reference did not converge.
    #[error(transparent)]
    NotConverged(#[from] crate::strands::NotConverged),
    /// A picture (`sweep.png`, `contact.png`) could not be drawn.
    #[error("{what}: {source}")]
    Plot {
        /// The picture.
        what: &'static str,
        /// plotters' error.
        #[source]
        source: PlotError,
    },
    /// A heat map this sweep wrote could not be read back for the contact sheet.
    #[error("{}: {source}", path.display())]
    ReadBack {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: ReadBackError,
    },
    /// An output could not be written (or a re-baked asset read back, or a frame compared).
    #[error("{path}: {source}")]
    Write {
        /// The file.
        path: String,
        /// Why, as the writer, loader or comparison said.
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
}

/// One measured setting.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The knob's name (a grid's knobs joined by `+`).
    pub knob: String,
    /// Its value (a grid's values joined by `+`).
    pub value: String,
    /// Median frame time, milliseconds.
    pub ms: f64,
    /// FLIP mean against the reference.
    pub error: f32,
    /// The reference.
    pub truth: Truth,
    /// Whether every value is the scene's default.
    pub default: bool,
    /// On its knob's Pareto front (no other setting of the knob is both faster and closer).
    pub pareto: bool,
    /// The image, relative to the output folder.
    pub image: String,
    /// The FLIP heat map, relative to the output folder.
    pub heat: String,
    /// Bytes uploaded to the GPU to switch to this setting.
    pub upload_bytes: u64,
    /// Against the strand reference: the fur's mean luminance over the reference's
    /// ([`crate::luminance`]).
    pub fur_luminance: Option<f32>,
}

/// A reference as the reports give it.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceInfo {
    /// Which.
    pub truth: Truth,
    /// Samples accumulated (1 for a single frame or the ray tracer).
    pub samples: u32,
    /// Half-vs-half FLIP of the strand reference.
    pub half_vs_half_flip: Option<f32>,
    /// Its time, milliseconds (every sample).
    pub ms: f64,
    /// Time per sample per pixel, milliseconds.
    pub ms_per_sample: f64,
    /// Frames rendered (each k × k samples per pixel).
    pub frames: u32,
    /// Samples per pixel side in a frame.
    pub grid: u32,
    /// Time per frame, milliseconds.
    pub ms_per_frame: f64,
    /// Its image, relative to the output folder.
    pub image: String,
    /// Strands drawn (the strand reference).
    pub strands: u64,
}

/// A finished sweep.
#[derive(Debug, Clone)]
pub struct Sweep {
    /// Every setting.
    pub rows: Vec<Row>,
    /// The references used.
    pub references: Vec<ReferenceInfo>,
    /// The adapter.
    pub adapter: String,
    /// How the frames were timed.
    pub clock: &'static str,
    /// Output size of the scene.
    pub size: (u32, u32),
    /// The whole sweep's wall time, milliseconds.
    pub total_ms: f64,
    /// Frames timed per setting, after warm-up.
    pub frames: usize,
}

impl Sweep {
    /// The setting with the least error among those measured against the strand reference
    /// whose time is at most `fraction` of the strand reference's.
    pub fn best_under(&self, fraction: f64) -> Option<&Row> {
        let r = self.references.iter().find(|r| r.truth == Truth::Strands)?;
        self.rows
            .iter()
            .filter(|row| row.truth == Truth::Strands && row.ms <= r.ms * fraction)
            .min_by(|a, b| a.error.total_cmp(&b.error))
    }
}

/// Marks each row on its knob's Pareto front.
pub fn mark_pareto(rows: &mut [Row]) {
    let on: Vec<bool> = rows
        .iter()
        .map(|r| {
            !rows.iter().any(|o| {
                o.knob == r.knob
                    && o.ms <= r.ms
                    && o.error <= r.error
                    && (o.ms < r.ms || o.error < r.error)
            })
        })
        .collect();
    for (r, p) in rows.iter_mut().zip(on) {
        r.pareto = p;
    }
}

/// What the loaded scene has, for deciding which knobs apply.
struct Contents {
    fur: bool,
    optics: bool,
    /// A light casts shadows.
    shadows: bool,
    /// Fur meshes and their asset files (None: built in, cannot be re-baked).
    fur_assets: Vec<(usize, Option<PathBuf>)>,
}

fn contents(scene: &Scene, meshes: &[MeshData], of: &[usize]) -> Contents {
    let mut c = Contents {
        fur: false,
        optics: false,
        shadows: scene.lights.iter().any(|l| l.shadows),
        fur_assets: Vec::new(),
    };
    for (i, o) in scene.objects.iter().enumerate() {
        match o.material {
            Material::Fur(_) if meshes[of[i]].fur.is_some() => {
                c.fur = true;
                if !c.fur_assets.iter().any(|(m, _)| *m == of[i]) {
                    let builtin = o
                        .asset
                        .to_string_lossy()
                        .starts_with(pelt_scene::asset::BUILTIN);
                    c.fur_assets
                        .push((of[i], (!builtin).then(|| o.asset.clone())));
                }
            }
            Material::Mirror { .. } | Material::Glass { .. } => c.optics = true,
            _ => {}
        }
    }
    c
}

/// Checks that `knob` has something to change in the scene.
fn applies(knob: &Knob, c: &Contents) -> Result<(), KnobError> {
    let missing = knob.needs.iter().find(|n| match n {
        Need::Fur => !c.fur,
        Need::Optics => !c.optics,
        Need::CastingLight => !c.shadows,
    });
    let why = match missing {
        Some(n) => Some(n.missing()),
        None if knob.rebakes() && c.fur_assets.iter().any(|(_, p)| p.is_none()) => {
            Some("a fur object's asset is built in and cannot be baked again")
        }
        None => None,
    };
    match why {
        Some(why) => Err(KnobError::NotApplicable {
            knob: knob.name(),
            why,
        }),
        None => Ok(()),
    }
}

/// The settings to render: (knob label, value label, setting, truth, every value default).
type Planned = (String, String, Setting, Truth, bool);

fn plan(
    opts: &Options,
    scene: &Scene,
    meshes: &[MeshData],
    c: &Contents,
) -> Result<Vec<Planned>, SweepError> {
    let size = (scene.output.width, scene.output.height);
    let lists: Vec<(&Knob, Vec<Value>)> = if opts.knobs.is_empty() {
        KNOBS
            .iter()
            .filter(|k| applies(k, c).is_ok())
            .map(|k| (k, k.defaults(size)))
            .collect()
    } else {
        for (k, _) in &opts.knobs {
            applies(k, c)?;
        }
        opts.knobs.clone()
    };
    let own = Own::of(scene, meshes);
    let default = |k: &Knob, v: &Value| k.own(&own) == Some(*v);
    if !opts.grid {
        let mut out = Vec::new();
        for (k, values) in &lists {
            for v in values {
                let s = Setting::default().with(k, *v);
                out.push((
                    k.name().to_string(),
                    v.to_string(),
                    s,
                    k.truth(),
                    default(k, v),
                ));
            }
        }
        return Ok(out);
    }
    let total: usize = lists.iter().map(|(_, v)| v.len()).product();
    if total > MAX_SETTINGS {
        return Err(SweepError::TooMany(total));
    }
    let truth = lists
        .iter()
        .map(|(k, _)| k.truth())
        .min_by_key(|t| match t {
            Truth::Strands => 0,
            Truth::RayTracer => 1,
            Truth::Deferred => 2,
        })
        .unwrap_or(Truth::Deferred);
    let name = lists
        .iter()
        .map(|(k, _)| k.name())
        .collect::<Vec<_>>()
        .join("+");
    let mut out = Vec::with_capacity(total);
    for i in 0..total {
        let (mut rest, mut s, mut labels, mut all_default) =
            (i, Setting::default(), Vec::new(), true);
        for (k, values) in &lists {
            let v = values[rest % values.len()];
            rest /= values.len();
            s = s.with(k, v);
            labels.push(v.to_string());
            all_default &= default(k, &v);
        }
        out.push((name.clone(), labels.join("+"), s, truth, all_default));
    }
    Ok(out)
}

fn write_png(dir: &Path, rel: &str, image: &Image) -> Result<(), SweepError> {
    let path = dir.join(rel);
    image.save(&path).map_err(|e| SweepError::Write {
        path: path.display().to_string(),
        source: Box::new(e),
    })
}

/// A file name for a setting's label.
fn file_stem(knob: &str, value: &str) -> String {
    format!("{knob}={value}")
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "=.+-_".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The references the settings need, computed once.
struct References {
    images: HashMap<Truth, Image>,
    info: Vec<ReferenceInfo>,
    /// The fur's pixels of the strand reference.
    fur: Option<crate::luminance::FurMask>,
}

/// What a sweep tells its caller as it goes (for progress on long runs).
#[derive(Debug, Clone, Copy)]
pub enum Event<'a> {
    /// A reference starts.
    Reference(Truth),
    /// The strand reference's progress.
    Strands(&'a crate::strands::Step),
    /// Setting `.1` of `.2` is measured.
    Row(&'a Row, usize, usize),
}

fn references(
    preview: &mut Preview,
    loaded: (&Scene, &[MeshData], &[usize]),
    planned: &[Planned],
    opts: &Options,
    progress: &mut dyn FnMut(Event<'_>),
) -> Result<References, SweepError> {
    let (scene, meshes, of) = loaded;
    let mut truths: Vec<Truth> = planned.iter().map(|p| p.3).collect();
    truths.sort();
    truths.dedup();
    let mut out = References {
        images: HashMap::new(),
        info: Vec::new(),
        fur: None,
    };
    for t in truths {
        progress(Event::Reference(t));
        let started = Instant::now();
        let (image, samples, half, per_sample, strands, frames) = match t {
            Truth::Strands => {
                let r = crate::strands::reference_with(
                    preview,
                    (scene, meshes, of),
                    opts.reference,
                    &mut |s| progress(Event::Strands(s)),
                )?
                .converged(opts.reference.target)?;
                let bare = crate::luminance::bare(preview, scene, meshes, of)?;
                out.fur = Some(crate::luminance::mask(&r.image, &bare));
                (
                    r.image,
                    r.samples,
                    Some(r.half_vs_half),
                    r.ms_per_sample,
                    r.strands,
                    (r.frames, r.grid, r.ms_per_frame),
                )
            }
            Truth::Deferred => {
                let sv = preview.prepare_loaded(scene, meshes, of, Mode::Deferred)?;
                let started = Instant::now();
                let image = preview.render(&sv)?;
                let ms = started.elapsed().as_secs_f64() * 1e3;
                (image, 1, None, ms, 0, (1, 1, ms))
            }
            Truth::RayTracer => {
                let depth = planned
                    .iter()
                    .filter_map(|p| p.2.knobs.reflections.max_depth)
                    .chain([scene.reflections.max_depth])
                    .max()
                    .unwrap_or(scene.reflections.max_depth);
                let r = crate::reflections::reference(scene, meshes, of, depth)?;
                let ms = r.ms;
                (r.image, 1, None, ms, 0, (1, 1, ms))
            }
        };
        let rel = format!("reference-{}.png", t.name());
        write_png(&opts.out, &rel, &image)?;
        out.info.push(ReferenceInfo {
            truth: t,
            samples,
            half_vs_half_flip: half,
            ms: started.elapsed().as_secs_f64() * 1e3,
            ms_per_sample: per_sample,
            frames: frames.0,
            grid: frames.1,
            ms_per_frame: frames.2,
            image: rel,
            strands,
        });
        out.images.insert(t, image);
    }
    Ok(out)
}

/// `image` scaled to `w × h` (bilinear on the sRGB bytes; an identity when the size agrees).
pub fn resize(image: &Image, w: u32, h: u32) -> Image {
    if (image.width, image.height) == (w, h) {
        return image.clone();
    }
    let mut rgba = Vec::with_capacity((w * h * 4) as usize);
    let (sx, sy) = (
        image.width as f32 / w as f32,
        image.height as f32 / h as f32,
    );
    for y in 0..h {
        for x in 0..w {
            let fx = ((x as f32 + 0.5) * sx - 0.5).clamp(0.0, (image.width - 1) as f32);
            let fy = ((y as f32 + 0.5) * sy - 0.5).clamp(0.0, (image.height - 1) as f32);
            let (x0, y0) = (fx as u32, fy as u32);
            let (x1, y1) = (
                (x0 + 1).min(image.width - 1),
                (y0 + 1).min(image.height - 1),
            );
            let (tx, ty) = (fx - x0 as f32, fy - y0 as f32);
            let p = |x, y| image.pixel(x, y).map(f32::from);
            let (a, b, c, d) = (p(x0, y0), p(x1, y0), p(x0, y1), p(x1, y1));
            for k in 0..4 {
                let top = a[k] + (b[k] - a[k]) * tx;
                let bottom = c[k] + (d[k] - c[k]) * tx;
                rgba.push((top + (bottom - top) * ty).round() as u8);
            }
        }
    }
    Image {
        width: w,
        height: h,
        rgba,
    }
}

/// Loaded meshes with the fur assets baked again for one re-bake setting.
fn rebaked_meshes(
    meshes: &[MeshData],
    c: &Contents,
    s: &Setting,
    dir: &Path,
    label: &str,
) -> Result<Vec<MeshData>, SweepError> {
    let mut out = meshes.to_vec();
    for (k, path) in &c.fur_assets {
        let Some(path) = path else { continue };
        let stem = path
            .file_stem()
            .map_or("asset".into(), |s| s.to_string_lossy().into_owned());
        let dst = dir.join(format!("{stem}-{label}.glb"));
        rebake::rebake(path, &dst, s)?;
        out[*k] = pelt_scene::asset::load(&dst).map_err(|e| SweepError::Write {
            path: dst.display().to_string(),
            source: Box::new(e),
        })?;
    }
    Ok(out)
}

/// Times `sv` and renders it once.
fn measure(
    preview: &Preview,
    sv: &SceneView,
    opts: &Options,
) -> Result<(f64, Image, PassClock), SweepError> {
    let t = preview.time(sv, opts.warmup, opts.frames)?;
    let ms = match t.clock {
        PassClock::Gpu => t.passes.iter().map(|(_, ms)| ms).sum(),
        PassClock::Wall => t.frame_ms,
    };
    Ok((ms, preview.render(sv)?, t.clock))
}

/// Runs the sweep of `input` (a scene file or an asset) with `base` overrides applied first.
/// `progress` hears of each reference as it starts, the strand reference's steps and each row
/// as it is measured.
pub fn run(
    preview: &mut Preview,
    input: &Path,
    base: &Knobs,
    default_size: (u32, u32),
    opts: &Options,
    progress: &mut dyn FnMut(Event<'_>),
) -> Result<Sweep, SweepError> {
    let started = Instant::now();
    let loaded = knobs::load(input, base, default_size)?;
    let (scene, meshes, of) = (&loaded.scene, &loaded.meshes, &loaded.mesh_of);
    let c = contents(scene, meshes, of);
    let planned = plan(opts, scene, meshes, &c)?;
    for sub in ["images", "heat", "assets"] {
        std::fs::create_dir_all(opts.out.join(sub)).map_err(|e| SweepError::Write {
            path: opts.out.join(sub).display().to_string(),
            source: Box::new(e),
        })?;
    }
    let refs = references(preview, (scene, meshes, of), &planned, opts, progress)?;
    let settings = planned.len();
    let mut sv = preview.prepare_loaded(scene, meshes, of, Mode::Inferred)?;
    let mut rows = Vec::with_capacity(planned.len());
    let mut clock = "wall";
    for (knob, value, setting, truth, default) in planned {
        preview.take_uploaded();
        let mut s = scene.clone();
        setting.knobs.apply(&mut s);
        let mode = setting.mode.unwrap_or(Mode::Inferred);
        let stem = file_stem(&knob, &value);
        let (ms, image, c_used) = if setting.rebakes() {
            let m = rebaked_meshes(meshes, &c, &setting, &opts.out.join("assets"), &stem)?;
            preview.take_uploaded();
            let svr = preview.prepare_loaded(&s, &m, of, mode)?;
            measure(preview, &svr, opts)?
        } else {
            preview.update(&mut sv, &s, mode)?;
            measure(preview, &sv, opts)?
        };
        clock = if c_used == PassClock::Gpu {
            "gpu"
        } else {
            "wall"
        };
        let upload_bytes = preview.take_uploaded();
        let reference = &refs.images[&truth];
        let test = resize(&image, reference.width, reference.height);
        let flip = Flip::new(reference, &test).map_err(|e| SweepError::Write {
            path: stem.clone(),
            source: Box::new(e),
        })?;
        let row = Row {
            image: format!("images/{stem}.png"),
            heat: format!("heat/{stem}.png"),
            knob,
            value,
            ms,
            error: flip.mean(),
            truth,
            default,
            pareto: false,
            upload_bytes,
            fur_luminance: match (truth, &refs.fur) {
                (Truth::Strands, Some(m)) => m.ratio(&test),
                _ => None,
            },
        };
        write_png(&opts.out, &row.image, &image)?;
        write_png(&opts.out, &row.heat, &flip.heat_map())?;
        progress(Event::Row(&row, rows.len() + 1, settings));
        rows.push(row);
    }
    mark_pareto(&mut rows);
    Ok(Sweep {
        rows,
        references: refs.info,
        adapter: preview.adapter(),
        clock,
        size: (scene.output.width, scene.output.height),
        total_ms: started.elapsed().as_secs_f64() * 1e3,
        frames: opts.frames,
    })
}
