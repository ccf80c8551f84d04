//! `pelt demo`: the main job end to end on bundled data. The Khronos Fox (bundled from
//! fixtures/fox, CC0 mesh, CC BY 4.0 rig and animations): baked with a generated comb (no one
//! painted it) and fur whose colour comes from its base colour texture, `fox.glb`; rendered
//! furred and textured mid-walk, `demo.png`, and over its walk cycle, `fox-walk.png`. Then the
//! fixture creature (a painted comb on a blobby body, `pelt-fixtures`), baked with fur textures
//! exactly as `pelt bake --config` would, read back and rendered as deferred fur (Revie) under
//! the procedural sky: `creature.png`, a turntable contact sheet of `--frames` views around
//! it, `turntable.png`, and the creature beside a mirror (fixtures/scenes/
//! creature-mirror.json, GPU Gems 3 ch. 17), `mirror.png`; and the creature's scene as a
//! scene file, `scene.json` (what `pelt sweep` measures in docs/sweep.md).

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context as _;
use pelt_bake::BakeOptions;
use pelt_bake::fur::{FurAssets, bake_with_fur};
use pelt_fur::FurConfig;
use pelt_measure::demo_creature::{bake_creature, demo_fur};
use pelt_preview::knobs::Knobs;
use pelt_preview::procedural::fur_scene;
use pelt_preview::{Image, Mode, Preview};

use crate::DemoArgs;

/// The bundled Fox (fixtures/fox/Fox.glb, unchanged; licences in fixtures/fox/README.md).
const FOX: &[u8] = include_bytes!("../fixtures/fox/Fox.glb");

/// The Fox's fur: the demo's strands, length scaled to its size (about 150 units nose to
/// tail), coloured by the Fox's base colour texture (orange back, white chest and tail tip),
/// darker at the roots.
fn fox_fur() -> FurConfig {
    FurConfig {
        length: 3.0,
        base_color: [0.35, 0.33, 0.32],
        tip_color: [1.0, 1.0, 1.0],
        color_from_texture: true,
        ..demo_fur()
    }
}

/// Bakes the bundled Fox with a generated comb (toward its tail) and the fox fur into `path`.
fn bake_fox(path: &Path) -> anyhow::Result<()> {
    let mut doc = pelt_io::Document::from_bytes(Path::new("Fox.glb"), FOX.to_vec())?;
    let opts = BakeOptions {
        comb: "generate".parse()?,
        ..BakeOptions::default()
    };
    let assets = FurAssets::new(fox_fur()).context("generating the fox's fur textures")?;
    bake_with_fur(&mut doc, &opts, &assets).context("baking the Fox")?;
    pelt_io::glb::write_glb(&doc, path)?;
    Ok(())
}

/// The Fox furred at `time` s of its walk, and the walk cycle as a contact sheet.
fn fox_renders(
    preview: &mut Preview,
    asset: &Path,
    (w, h): (u32, u32),
    frames: u32,
    shells: Option<u32>,
) -> anyhow::Result<(Image, Image)> {
    use pelt_preview::asset::{PoseAt, load_at};
    let walk = |time: f32| PoseAt {
        animation: "Walk".to_owned(),
        time,
    };
    let mid = load_at(asset, Some(&walk(0.35)))?;
    let (lo, hi) = mid.bounds();
    let quad = pelt_preview::asset::builtin("quad").context("built-in quad")?;
    // Three-quarter view from the front left.
    let scene_at = |w, h| {
        let mut s = fur_scene(asset, lo, hi, w, h, 35.0);
        Knobs {
            shells,
            ..Knobs::default()
        }
        .apply(&mut s);
        s
    };
    let d = preview.prepare_loaded(
        &scene_at(w, h),
        &[mid, quad.clone()],
        &[0, 1],
        Mode::Inferred,
    )?;
    let still = preview.render(&d)?;
    let (tw, th) = ((w / 4).max(1), (h / 4).max(1));
    // Prepared once; each frame of the walk is skinned on the GPU.
    let first = load_at(asset, Some(&walk(0.0)))?;
    let d = preview.prepare_loaded(&scene_at(tw, th), &[first, quad], &[0, 1], Mode::Inferred)?;
    let mut tiles = Vec::new();
    for k in 0..frames {
        // Walk: 0 to 0.708 s; frames evenly over one cycle.
        let t = 0.708 * k as f32 / frames as f32;
        preview.pose(&d, "Walk", t, asset)?;
        tiles.push(preview.render(&d)?);
    }
    Ok((still, Image::contact_sheet(&tiles, 4)))
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
        Knobs {
            shells: args.shells,
            ..Knobs::default()
        }
        .apply(&mut s);
        s
    };
    let (w, h) = args.size;
    let t0 = std::time::Instant::now();
    let fox = args.output.join("fox.glb");
    bake_fox(&fox)?;
    let (still, walk) = fox_renders(&mut preview, &fox, (w, h), args.frames, args.shells)?;
    let demo = args.output.join("demo.png");
    still.save(&demo)?;
    walk.save(&args.output.join("fox-walk.png"))?;
    let d = preview.prepare_loaded(&scene_at(w, h, 0.0), &meshes, &[0, 1], Mode::Inferred)?;
    let image = preview.render(&d)?;
    let creature = args.output.join("creature.png");
    image.save(&creature)?;
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
            "wrote {} (the Fox, generated comb), {} (furred and textured mid-walk, {w}×{h}), fox-walk.png ({} frames of its walk), {} (baked fixture creature), {}, {} ({} views), {} (beside a mirror) in {:.1} s",
            fox.display(),
            demo.display(),
            args.frames,
            asset.display(),
            creature.display(),
            turntable.display(),
            args.frames,
            mirror.display(),
            t0.elapsed().as_secs_f64()
        );
    }
    Ok(ExitCode::SUCCESS)
}
