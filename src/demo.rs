//! `pelt demo`: the main job end to end on bundled data. Generates the fixture creature (a
//! painted comb on a blobby body, `pelt-fixtures`), bakes it with fur textures exactly as
//! `pelt bake --config` would, writes the `.glb`, reads it back and renders it as deferred fur
//! (Revie) under the procedural sky: `demo.png`, a turntable contact sheet of `--frames` views
//! around it, `turntable.png`, and the creature beside a mirror (fixtures/scenes/
//! creature-mirror.json, GPU Gems 3 ch. 17), `mirror.png`; and the demo's scene as a scene
//! file, `scene.json` (what `pelt sweep` measures in the README).

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context as _;
use pelt_bake::BakeOptions;
use pelt_bake::fur::{FurAssets, bake_with_fur};
use pelt_fur::{FurConfig, StrandParams};
use pelt_preview::procedural::fur_scene;
use pelt_preview::{Image, Mode, Preview};

use crate::DemoArgs;

/// The demo's fur: `fixtures/fur.json`'s strands and colours, with fur long enough to read at
/// a glance (the creature is about 4 units long).
pub fn demo_fur() -> FurConfig {
    FurConfig {
        length: 0.09,
        shells: 16,
        uv_scale: 6.0,
        base_color: [0.08, 0.05, 0.03],
        tip_color: [0.62, 0.47, 0.31],
        materials: None,
        textures: StrandParams {
            seed: 7,
            size: 512,
            strands: 12000,
            radius: 0.0025,
            radius_jitter: 0.3,
            height_min: 0.4,
            height_max: 1.0,
            tilt: 1.5,
            ..StrandParams::default()
        },
    }
}

/// Bakes the fixture creature with the demo's fur into `path`.
pub fn bake_creature(path: &Path) -> anyhow::Result<()> {
    use pelt_fixtures::build::{BuildOptions, ColorEncoding, document};
    let mut doc = document(
        &pelt_fixtures::shapes::creature(64, 128),
        BuildOptions {
            colors: ColorEncoding::U8x4,
            ..BuildOptions::default()
        },
    );
    let assets = FurAssets::new(demo_fur()).context("generating the fur textures")?;
    bake_with_fur(&mut doc, &BakeOptions::default(), &assets).context("baking the creature")?;
    pelt_io::glb::write_glb(&doc, path)?;
    Ok(())
}

/// Copies `tile` into `sheet` at (x, y).
fn paste(sheet: &mut Image, tile: &Image, x: u32, y: u32) {
    for row in 0..tile.height {
        let src = (row * tile.width * 4) as usize;
        let dst = (((y + row) * sheet.width + x) * 4) as usize;
        let n = (tile.width * 4) as usize;
        sheet.rgba[dst..dst + n].copy_from_slice(&tile.rgba[src..src + n]);
    }
}

/// fixtures/scenes/creature-mirror.json: the creature beside a mirror (layered distance maps,
/// GPU Gems 3 ch. 17).
const MIRROR_SCENE: &str = include_str!("../fixtures/scenes/creature-mirror.json");

/// The creature (baked at `asset`) beside a mirror, rendered at `size`.
fn mirror_scene(preview: &mut Preview, asset: &Path, (w, h): (u32, u32)) -> anyhow::Result<Image> {
    let mut scene = pelt_preview::Scene::parse(Path::new("creature-mirror.json"), MIRROR_SCENE)?;
    scene.output.width = w;
    scene.output.height = h;
    for o in &mut scene.objects {
        if o.asset.ends_with("creature.glb") {
            o.asset = asset.to_owned();
        }
    }
    let d = preview.prepare(&scene, Mode::Inferred)?;
    Ok(preview.render(&d)?)
}

/// Writes the demo's scene as a scene file beside the creature (its asset named relative to
/// it, so the folder can move), for `pelt render` and `pelt sweep`.
fn write_scene(scene: &pelt_preview::Scene, path: &Path) -> anyhow::Result<()> {
    let mut s = scene.clone();
    for o in &mut s.objects {
        if let Some(name) = o
            .asset
            .file_name()
            .filter(|_| o.asset.extension().is_some())
        {
            o.asset = name.into();
        }
    }
    let json = serde_json::to_string_pretty(&s)?;
    pelt_io::glb::write_atomic(path, json.as_bytes())
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}

/// Runs `pelt demo`.
pub fn run(args: &DemoArgs) -> anyhow::Result<ExitCode> {
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("creating {}", args.output.display()))?;
    let asset = args.output.join("creature.glb");
    bake_creature(&asset)?;
    let mesh = pelt_preview::asset::load(&asset)?;
    let quad = pelt_preview::asset::builtin("quad").context("built-in quad")?;
    let (lo, hi) = mesh.bounds();
    let meshes = vec![mesh, quad];
    let mut preview = Preview::new(args.backend)?;
    if !args.quiet {
        eprintln!("adapter: {}", preview.adapter());
    }
    let scene_at = |w, h, yaw| {
        let mut s = fur_scene(&asset, lo, hi, w, h, yaw);
        s.fur_blend = args.fur_blend;
        crate::render::override_fur(&mut s, args.shells, None);
        s
    };
    let (w, h) = args.size;
    let t0 = std::time::Instant::now();
    let d = preview.prepare_loaded(&scene_at(w, h, 0.0), &meshes, &[0, 1], Mode::Inferred)?;
    let image = preview.render(&d)?;
    let demo = args.output.join("demo.png");
    image.save(&demo)?;
    write_scene(&scene_at(w, h, 0.0), &args.output.join("scene.json"))?;
    let (tw, th) = ((w / 4).max(1), (h / 4).max(1));
    let cols = args.frames.min(4);
    let rows = args.frames.div_ceil(4);
    let mut sheet = Image {
        width: tw * cols,
        height: th * rows,
        rgba: vec![0; (tw * cols * th * rows * 4) as usize],
    };
    for k in 0..args.frames {
        let yaw = 360.0 * k as f32 / args.frames as f32;
        let d = preview.prepare_loaded(&scene_at(tw, th, yaw), &meshes, &[0, 1], Mode::Inferred)?;
        let tile = preview.render(&d)?;
        paste(&mut sheet, &tile, (k % 4) * tw, (k / 4) * th);
    }
    let turntable = args.output.join("turntable.png");
    sheet.save(&turntable)?;
    let mirror = args.output.join("mirror.png");
    mirror_scene(&mut preview, &asset, (w, h))?.save(&mirror)?;
    if !args.quiet {
        eprintln!(
            "wrote {} (baked fixture creature), {} ({w}×{h}), {} ({} views), {} (beside a mirror) in {:.1} s",
            asset.display(),
            demo.display(),
            turntable.display(),
            args.frames,
            mirror.display(),
            t0.elapsed().as_secs_f64()
        );
    }
    Ok(ExitCode::SUCCESS)
}
