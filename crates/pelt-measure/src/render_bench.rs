//! `pelt render-bench`'s experiments as tables, timed on this machine's adapter: the
//! inferred-lighting paper's two (Kircher & Lawrance §6: (a) 101 objects and 81 lights,
//! inferred against forward; (b) 122 lights, an 800×450 L-buffer with DSF against 1280×720
//! without), the fur demo against its knobs (Revie's shells and fins, stipple against
//! WBOIT, the forward Kajiya-Kay reference), and mirrors and glass against the ray tracer
//! (GPU Gems 3 ch. 17; [`reflection_tables`]).

use std::path::{Path, PathBuf};

use pelt_preview::asset::AssetError;
use pelt_preview::knobs::{self, InputError, Knobs};
use pelt_preview::procedural::{fur_scene, paper_lbuffer_scale, paper_objects_and_lights};
use pelt_preview::scene::{FurBlend, Reflections, Technique};
use pelt_preview::{Image, Mode, Preview, RenderError, Scene, Timings};

use crate::demo_creature::{DemoCreatureError, bake_creature};
use crate::reflections::{self, MeasureError, Reference, Run};
use crate::table::Table;

/// What can stop a benchmark.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// Rendering failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// An asset could not be loaded.
    #[error(transparent)]
    Asset(#[from] AssetError),
    /// The scene could not be loaded.
    #[error(transparent)]
    Input(#[from] InputError),
    /// The demo creature could not be made.
    #[error(transparent)]
    Creature(#[from] DemoCreatureError),
    /// The reflections experiment failed.
    #[error(transparent)]
    Measure(#[from] MeasureError),
    /// A scratch folder could not be made.
    #[error("{}: {source}", path.display())]
    Io {
        /// The folder.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
}

/// Untimed and timed frames per configuration.
#[derive(Debug, Clone, Copy)]
pub struct Frames {
    /// Untimed frames first.
    pub warmup: usize,
    /// Timed frames.
    pub timed: usize,
}

/// An experiment's table and, for each of its rows, the profile of its frame (per pass: the
/// device's time, the CPU's encode time, draws and state changes).
pub struct Timed {
    /// One row per configuration.
    pub table: Table,
    /// Each row's configuration and its frame's profile.
    pub profiles: Vec<(String, Timings)>,
}

impl Timed {
    /// Every profile as a titled Markdown table.
    pub fn profiles_markdown(&self) -> String {
        self.profiles
            .iter()
            .map(|(what, t)| format!("\n{what}: {t}\n\n{}", t.profile_table()))
            .collect()
    }
}

/// The paper's experiment (a) (`objects`) and (b) (`lbuffer`) with `asset` in every cell.
pub fn paper(
    preview: &mut Preview,
    asset: &Path,
    (objects, lbuffer): (bool, bool),
    frames: Frames,
) -> Result<Timed, BenchError> {
    let a = paper_objects_and_lights(asset);
    let b = paper_lbuffer_scale(asset);
    let b_full = Scene {
        lbuffer_scale: 1.0,
        dsf: false,
        ..b.clone()
    };
    let (ea, eb) = (
        "(a) 101 objects, 81 lights, 1280×720",
        "(b) 122 lights, 1280×720",
    );
    let mut runs = Vec::new();
    if objects {
        runs.push((
            ea,
            a.clone(),
            Mode::Inferred,
            "inferred, L-buffer 800×450, DSF",
        ));
        runs.push((ea, a, Mode::Forward, "forward"));
    }
    if lbuffer {
        runs.push((eb, b, Mode::Inferred, "L-buffer 800×450 with DSF"));
        runs.push((eb, b_full, Mode::Inferred, "L-buffer 1280×720 without DSF"));
    }
    let columns = ["experiment", "configuration", "frame ms (median)", "passes"];
    let mut table = Table::new(None, &columns);
    let mut profiles = Vec::new();
    for (name, scene, mode, what) in runs {
        let d = preview.prepare(&scene, mode)?;
        let t = preview.time(&d, frames.warmup, frames.timed)?;
        table.push(vec![
            name.into(),
            what.into(),
            format!("{:.1}", t.frame_ms),
            t.passes_line(1),
        ]);
        profiles.push((format!("{name}, {what}"), t));
    }
    Ok(Timed { table, profiles })
}

/// The fur experiment: the demo scene (the demo creature, 1280×720) against shell count,
/// fins on and off, stipple against WBOIT, and the forward Kajiya-Kay reference.
pub fn fur(preview: &mut Preview, frames: Frames) -> Result<Timed, BenchError> {
    let dir = std::env::temp_dir().join(format!("pelt-render-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|source| BenchError::Io {
        path: dir.clone(),
        source,
    })?;
    let asset = dir.join("creature.glb");
    bake_creature(&asset)?;
    let mesh = pelt_preview::asset::load(&asset);
    let _ = std::fs::remove_dir_all(&dir);
    let mesh = mesh?;
    let (lo, hi) = mesh.bounds();
    let meshes = vec![mesh, pelt_preview::asset::quad()];
    let at = |shells: u32, fins: bool, blend: FurBlend| {
        let mut s = fur_scene(&asset, lo, hi, 1280, 720, 0.0);
        s.fur_blend = blend;
        let k = Knobs {
            shells: Some(knobs::ShellCount::Fixed(shells)),
            fins: Some(fins),
            ..Knobs::default()
        };
        k.apply(&mut s);
        s
    };
    let mut runs: Vec<(String, Scene, Mode)> = [4, 8, 16, 32, 64]
        .map(|n| {
            let what = format!("{n} shells, fins, stipple");
            (what, at(n, true, FurBlend::Stipple), Mode::Inferred)
        })
        .into();
    for (what, shells, fins, blend, mode) in [
        (
            "16 shells, no fins, stipple",
            16,
            false,
            FurBlend::Stipple,
            Mode::Inferred,
        ),
        (
            "16 shells, fins, WBOIT",
            16,
            true,
            FurBlend::Wboit,
            Mode::Inferred,
        ),
        (
            "64 shells, fins, WBOIT",
            64,
            true,
            FurBlend::Wboit,
            Mode::Inferred,
        ),
        (
            "16 shells, fins, forward Kajiya-Kay",
            16,
            true,
            FurBlend::Stipple,
            Mode::Forward,
        ),
    ] {
        runs.push((what.into(), at(shells, fins, blend), mode));
    }
    let mut table = Table::new(None, &["fur demo, 1280×720", "frame ms (median)", "passes"]);
    let mut profiles = Vec::new();
    for (what, scene, mode) in runs {
        let d = preview.prepare_loaded(&scene, &meshes, &[0, 1], mode)?;
        let t = preview.time(&d, frames.warmup, frames.timed)?;
        table.push(vec![
            what.clone(),
            format!("{:.1}", t.frame_ms),
            t.passes_line(1),
        ]);
        profiles.push((format!("fur demo, {what}"), t));
    }
    Ok(Timed { table, profiles })
}

/// The reflections experiment's tables, its opening line and its pictures.
pub struct ReflectionTables {
    /// The scene, its size and mode, and the ray tracer's time.
    pub intro: String,
    /// Defaults and the baseline; Figure 17-6's linear/secant steps; min-max acceleration;
    /// cube size; layers; bounces.
    pub tables: Vec<Table>,
    /// File name and image: the ray tracer's, the distance maps', the environment map's,
    /// and the FLIP heat maps.
    pub pictures: Vec<(&'static str, Image)>,
}

/// A pass's time, or a dash when the frame did not run it.
fn ms(v: Option<f64>) -> String {
    v.map_or_else(|| "—".to_owned(), |v| format!("{v:.1}"))
}

fn section(title: &str) -> Table {
    let columns = [
        "setting",
        "FLIP whole",
        "FLIP mirror/glass pixels",
        "frame ms",
        "distance maps ms",
        "min-max ms",
        "shading pass ms",
        "reflection shading ms",
    ];
    Table::new(Some(title.to_owned()), &columns)
}

fn row(what: String, r: &Run, shade_base: f64) -> Vec<String> {
    vec![
        what,
        format!("{:.4}", r.error),
        format!("{:.4}", r.error_reflective),
        format!("{:.1}", r.frame_ms),
        ms(r.maps_ms),
        ms(r.minmax_ms),
        format!("{:.1}", r.shade_ms),
        format!("{:.1}", (r.shade_ms - shade_base).max(0.0)),
    ]
}

/// Mirrors and glass from distance maps (GPU Gems 3 ch. 17) in the scene at `path`, drawn
/// in `mode`, against the CPU ray tracer: Figure 17-6's linear/secant steps, min-max
/// acceleration on and off, cube size, layers, bounces, and the environment-map baseline.
pub fn reflection_tables(
    preview: &mut Preview,
    path: &Path,
    mode: Mode,
    frames: Frames,
) -> Result<ReflectionTables, BenchError> {
    let input = knobs::load(path, &Knobs::default(), (640, 360))?;
    let (scene, meshes, of) = (&input.scene, &input.meshes, &input.mesh_of);
    let base = scene.reflections;
    let reference: Reference = reflections::reference(scene, meshes, of, base.max_depth)?;
    let fr = (frames.warmup, frames.timed);
    let intro = format!(
        "reflections: {} at {}×{}, {mode} mode; ray tracer {:.0} ms on {} threads",
        path.display(),
        scene.output.width,
        scene.output.height,
        reference.ms,
        rayon::current_num_threads()
    );
    let shade_base = reflections::shade_without(preview, scene, meshes, of, mode, fr)?;
    let mut measure = |k: Reflections| -> Result<Run, BenchError> {
        let own;
        let r = if k.max_depth == reference.max_depth {
            &reference
        } else {
            own = reflections::reference(scene, meshes, of, k.max_depth)?;
            &own
        };
        Ok(reflections::run(
            preview, scene, meshes, of, mode, k, r, fr,
        )?)
    };
    let mut tables = Vec::new();
    let mut t = section("Defaults and the baseline");
    let default = measure(base)?;
    t.push(row(
        "distance maps, scene's knobs".into(),
        &default,
        shade_base,
    ));
    let envmap = |technique| Reflections { technique, ..base };
    let env = measure(envmap(Technique::Envmap))?;
    t.push(row("environment map (baseline)".into(), &env, shade_base));
    let off = measure(envmap(Technique::Off))?;
    t.push(row("off (opaque)".into(), &off, shade_base));
    tables.push(t);
    tables.extend(knob_tables(base, shade_base, &mut measure)?);
    let pictures = vec![
        ("distance-maps-flip.png", default.flip.heat_map()),
        ("envmap-flip.png", env.flip.heat_map()),
        ("raytrace.png", reference.image),
        ("distance-maps.png", default.image),
        ("envmap.png", env.image),
    ];
    Ok(ReflectionTables {
        intro,
        tables,
        pictures,
    })
}

/// The tables that vary one knob of the scene's reflections `base` at a time: Figure 17-6's
/// linear and secant steps, min-max acceleration against linear steps, cube size, layers and
/// bounces. `measure` renders and measures a setting.
fn knob_tables(
    base: Reflections,
    shade_base: f64,
    measure: &mut impl FnMut(Reflections) -> Result<Run, BenchError>,
) -> Result<Vec<Table>, BenchError> {
    let mut tables = Vec::new();
    let mut t = section("Figure 17-6: linear / secant steps");
    for (l, s) in [(15, 1), (15, 10), (80, 1), (80, 10)] {
        let k = Reflections {
            linear_steps: l,
            secant_steps: s,
            ..base
        };
        t.push(row(format!("{l} / {s}"), &measure(k)?, shade_base));
    }
    tables.push(t);
    let mut t = section("Min-max acceleration (Figure 17-4) against linear steps");
    for linear_steps in [8, 16, 32, 64] {
        for min_max in [false, true] {
            let k = Reflections {
                linear_steps,
                min_max,
                ..base
            };
            let on = if min_max { "on" } else { "off" };
            let what = format!("{linear_steps} steps, min-max {on}");
            t.push(row(what, &measure(k)?, shade_base));
        }
    }
    tables.push(t);
    let mut t = section("Cube size");
    for cube_size in [64, 128, 256, 512] {
        let k = Reflections { cube_size, ..base };
        t.push(row(format!("{cube_size}²"), &measure(k)?, shade_base));
    }
    tables.push(t);
    let mut t = section("Layers (2 + depth-peeled layers of the rest)");
    for layers in [3, 4, 5] {
        let k = Reflections { layers, ..base };
        t.push(row(format!("{layers}"), &measure(k)?, shade_base));
    }
    tables.push(t);
    let mut t = section("Most bounces");
    for max_depth in [1, 2, 4, 8] {
        let k = Reflections { max_depth, ..base };
        t.push(row(format!("{max_depth}"), &measure(k)?, shade_base));
    }
    tables.push(t);
    Ok(tables)
}
