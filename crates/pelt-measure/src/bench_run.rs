//! `pelt render-bench` as one library call: which experiments ([`Experiment`]), their
//! settings ([`Settings`], clap's `Args` with the `cli` feature) and [`run`], which times
//! them on a [`Preview`] and hands each experiment's Markdown to the caller as it finishes
//! (the tables of [`crate::render_bench`]).

use std::path::{Path, PathBuf};

use pelt_preview::{Backend, Mode, Preview, RenderError};

use crate::render_bench::{self, BenchError, Frames, Timed};

/// The experiments of `pelt render-bench`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Experiment {
    /// 101 objects, 81 lights: inferred against forward.
    Objects,
    /// 122 lights: 800×450 L-buffer with DSF against 1280×720 without.
    Lbuffer,
    /// The fur demo: shells 4 to 64, fins on and off, stipple against WBOIT, forward.
    Fur,
    /// Mirrors and glass against the ray tracer: Figure 17-6's linear/secant steps,
    /// min-max on and off, cube size, layers, bounces, the environment-map baseline.
    Reflections,
    /// All of them.
    All,
}

/// What `pelt render-bench` runs, and how.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct Settings {
    /// Which experiment: objects (a), lbuffer (b), fur (shells, fins, blend) or all.
    #[cfg_attr(feature = "cli", arg(long, value_enum, default_value_t = Experiment::All))]
    pub experiment: Experiment,
    /// wgpu back end: auto, vulkan or gl.
    #[cfg_attr(feature = "cli", arg(long, default_value = "auto"))]
    pub backend: Backend,
    /// Timed frames per configuration.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 15))]
    pub frames: usize,
    /// Untimed frames first.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 3))]
    pub warmup: usize,
    /// The object every grid cell holds.
    #[cfg_attr(feature = "cli", arg(long, default_value = "builtin:sphere"))]
    pub asset: String,
    /// The reflections experiment's scene.
    #[cfg_attr(
        feature = "cli",
        arg(long, default_value = "fixtures/scenes/mirrors.json")
    )]
    pub scene: PathBuf,
    /// The reflections experiment's mode (forward: the same lighting as the ray tracer, so
    /// the error is the reflections' alone).
    #[cfg_attr(feature = "cli", arg(long, default_value = "forward"))]
    pub mode: Mode,
    /// After each experiment's table, each row's profile: per pass, the device's time, the
    /// CPU's encode time, draws, pipeline and bind-group changes, triangles, vertex bytes, and
    /// the fragment-shader invocations and samples written the GPU counts.
    #[cfg_attr(feature = "cli", arg(long))]
    pub profile: bool,
    /// Write the reflections experiment's pictures here: ours, the ray tracer's, the
    /// environment map's and FLIP heat maps.
    #[cfg_attr(feature = "cli", arg(long, value_name = "DIR"))]
    pub pictures: Option<PathBuf>,
    /// Print nothing but the tables and errors (no line as each experiment starts).
    #[cfg_attr(feature = "cli", arg(short, long))]
    pub quiet: bool,
}

/// Runs the experiments `s` chooses on `preview`, giving `emit` each one's Markdown (and,
/// with `s.profile`, each row's profile) as it finishes; the reflections experiment's
/// pictures go to `s.pictures`.
pub fn run(
    preview: &mut Preview,
    s: &Settings,
    emit: &mut dyn FnMut(&str),
    status: &mut dyn FnMut(&str),
) -> Result<(), BenchError> {
    use Experiment::{All, Fur, Lbuffer, Objects, Reflections};
    let frames = Frames {
        warmup: s.warmup,
        timed: s.frames,
    };
    let e = s.experiment;
    let each = format!("{} untimed and {} timed frames each", s.warmup, s.frames);
    if matches!(e, Reflections | All) {
        status(&format!(
            "render-bench: reflections ({}): the ray tracer, then every configuration, {each}",
            s.scene.display()
        ));
        let r = render_bench::reflection_tables(preview, &s.scene, s.mode, frames)?;
        emit(&format!("{}\n", r.intro));
        r.tables.iter().for_each(|t| emit(&t.markdown()));
        if let Some(dir) = &s.pictures {
            std::fs::create_dir_all(dir).map_err(|source| BenchError::Io {
                path: dir.clone(),
                source,
            })?;
            for (name, image) in &r.pictures {
                image.save(&dir.join(name)).map_err(RenderError::Frame)?;
            }
            emit(&format!("\npictures in {}\n", dir.display()));
        }
    }
    let mut timed = |t: Timed| {
        emit(&t.table.markdown());
        if s.profile {
            emit(&t.profiles_markdown());
        }
    };
    if matches!(e, Fur | All) {
        status(&format!(
            "render-bench: the fur demo at 1280×720, every configuration, {each}"
        ));
        timed(render_bench::fur(preview, frames)?);
    }
    if matches!(e, Objects | Lbuffer | All) {
        let which = (matches!(e, Objects | All), matches!(e, Lbuffer | All));
        status(&format!(
            "render-bench: the inferred-lighting paper's experiments at 1280×720, {each}"
        ));
        timed(render_bench::paper(
            preview,
            Path::new(&s.asset),
            which,
            frames,
        )?);
    }
    Ok(())
}
