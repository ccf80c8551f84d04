//! `pelt render-bench --experiment reflections`: mirrors and glass from distance maps
//! (GPU Gems 3 ch. 17) against the CPU ray tracer, as tables: Figure 17-6's linear/secant
//! steps, min-max acceleration on and off, cube size, layers, bounces, and the
//! environment-map baseline; with `--pictures`, the images and FLIP heat maps.

use anyhow::Context as _;
use pelt_measure::reflections::{self, Reference, Run};
use pelt_preview::Preview;
use pelt_preview::knobs::{self, Knobs};
use pelt_preview::scene::{Reflections, Technique};

use crate::RenderBenchArgs;

/// A pass's time, or a dash when the frame did not run it.
fn ms(v: Option<f64>) -> String {
    v.map_or_else(|| "—".to_owned(), |v| format!("{v:.1}"))
}

fn row(what: &str, r: &Run, shade_base: f64) {
    println!(
        "| {what} | {:.4} | {:.4} | {:.1} | {} | {} | {:.1} | {:.1} |",
        r.error,
        r.error_reflective,
        r.frame_ms,
        ms(r.maps_ms),
        ms(r.minmax_ms),
        r.shade_ms,
        (r.shade_ms - shade_base).max(0.0)
    );
}

fn header(title: &str) {
    println!("\n{title}\n");
    println!(
        "| setting | FLIP whole | FLIP mirror/glass pixels | frame ms | distance maps ms | min-max ms | shading pass ms | reflection shading ms |"
    );
    println!("|---|---|---|---|---|---|---|---|");
}

/// Runs the experiment.
pub fn run(preview: &mut Preview, args: &RenderBenchArgs) -> anyhow::Result<()> {
    let input = knobs::load(&args.scene, &Knobs::default(), (640, 360))
        .with_context(|| format!("loading {}", args.scene.display()))?;
    let (scene, meshes, of) = (&input.scene, &input.meshes, &input.mesh_of);
    let base = scene.reflections;
    let reference: Reference = reflections::reference(scene, meshes, of, base.max_depth)?;
    let frames = (args.warmup, args.frames);
    let (w, h) = (scene.output.width, scene.output.height);
    println!(
        "reflections: {} at {w}×{h}, {} mode; ray tracer {:.0} ms on {} threads",
        args.scene.display(),
        args.mode,
        reference.ms,
        rayon::current_num_threads()
    );
    let shade_base = reflections::shade_without(preview, scene, meshes, of, args.mode, frames)?;
    let mut measure = |k: Reflections| -> anyhow::Result<Run> {
        if k.max_depth == reference.max_depth {
            return Ok(reflections::run(
                preview, scene, meshes, of, args.mode, k, &reference, frames,
            )?);
        }
        let r = reflections::reference(scene, meshes, of, k.max_depth)?;
        Ok(reflections::run(
            preview, scene, meshes, of, args.mode, k, &r, frames,
        )?)
    };
    header("Defaults and the baseline");
    let default = measure(base)?;
    row("distance maps, scene's knobs", &default, shade_base);
    let env = measure(Reflections {
        technique: Technique::Envmap,
        ..base
    })?;
    row("environment map (baseline)", &env, shade_base);
    let off = measure(Reflections {
        technique: Technique::Off,
        ..base
    })?;
    row("off (opaque)", &off, shade_base);
    header("Figure 17-6: linear / secant steps");
    for (l, s) in [(15, 1), (15, 10), (80, 1), (80, 10)] {
        let r = measure(Reflections {
            linear_steps: l,
            secant_steps: s,
            ..base
        })?;
        row(&format!("{l} / {s}"), &r, shade_base);
    }
    header("Min-max acceleration (Figure 17-4) against linear steps");
    for steps in [8, 16, 32, 64] {
        for min_max in [false, true] {
            let r = measure(Reflections {
                linear_steps: steps,
                min_max,
                ..base
            })?;
            let what = format!(
                "{steps} steps, min-max {}",
                if min_max { "on" } else { "off" }
            );
            row(&what, &r, shade_base);
        }
    }
    header("Cube size");
    for cube_size in [64, 128, 256, 512] {
        let r = measure(Reflections { cube_size, ..base })?;
        row(&format!("{cube_size}²"), &r, shade_base);
    }
    header("Layers (2 + depth-peeled layers of the rest)");
    for layers in [3, 4, 5] {
        let r = measure(Reflections { layers, ..base })?;
        row(&format!("{layers}"), &r, shade_base);
    }
    header("Most bounces");
    for max_depth in [1, 2, 4, 8] {
        let r = measure(Reflections { max_depth, ..base })?;
        row(&format!("{max_depth}"), &r, shade_base);
    }
    if let Some(dir) = &args.pictures {
        std::fs::create_dir_all(dir)?;
        let save = |name: &str, i: &pelt_preview::Image| i.save(&dir.join(name));
        save("raytrace.png", &reference.image)?;
        save("distance-maps.png", &default.image)?;
        save("distance-maps-flip.png", &default.flip.heat_map())?;
        save("envmap.png", &env.image)?;
        save("envmap-flip.png", &env.flip.heat_map())?;
        println!("\npictures in {}", dir.display());
    }
    Ok(())
}
