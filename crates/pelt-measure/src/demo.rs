//! `pelt demo`: the main job end to end on bundled data. The Khronos Fox (bundled from
//! fixtures/fox, CC0 mesh, CC BY 4.0 rig and animations): baked with a generated comb (no one
//! painted it) and fur whose colour comes from its base colour texture, `fox.glb`; rendered
//! furred and textured mid-walk, `demo.png`, and over its walk cycle, `fox-walk.png` (skinned
//! on the GPU, [`pelt_preview::animate`]), under a key light that casts shadows (the Fox
//! stands in its contact shadow, redrawn for each pose) and in a light gusting wind. Then the demo creature ([`crate::demo_creature`]),
//! baked with fur textures exactly as `pelt bake --config` would, read back and rendered as
//! deferred fur (Revie) under the procedural sky: `creature.png`, a turntable contact sheet
//! of `frames` views around it, `turntable.png`, and the creature beside a mirror
//! (fixtures/scenes/creature-mirror.json, GPU Gems 3 ch. 17), `mirror.png`; and the
//! creature's scene as a scene file, `scene.json` (what `pelt sweep` measures), and the Fox's,
//! `fox.json` (shadows, wind and springs: `pelt render fox.json --animation Walk --time 0.35`
//! draws `demo.png`).

use std::path::{Path, PathBuf};

use glam::Vec3;
use pelt_bake::BakeOptions;
use pelt_bake::fur::{FurAssets, bake_with_fur};
use pelt_bake::options::{CombSource, GeneratedComb};
use pelt_fur::{FurConfig, FurError};
use pelt_io::IoError;
use pelt_preview::animate::{AnimateError, Clip, spread};
use pelt_preview::asset::{self, AssetError, MeshData, PoseAt};
use pelt_preview::knobs::Knobs;
use pelt_preview::procedural::fur_scene;
use pelt_preview::scene::{FurBlend, Material, Spring};
use pelt_preview::wind::Wind;
use pelt_preview::{FrameError, Image, Mode, Preview, RenderError, Scene, SceneError};

use crate::demo_creature::{DemoCreatureError, bake_creature, demo_fur};

/// The bundled Fox (fixtures/fox/Fox.glb, unchanged; licences in fixtures/fox/README.md).
const FOX: &[u8] = include_bytes!("../../../fixtures/fox/Fox.glb");

/// fixtures/scenes/creature-mirror.json: the creature beside a mirror (layered distance maps,
/// GPU Gems 3 ch. 17).
const MIRROR_SCENE: &str = include_str!("../../../fixtures/scenes/creature-mirror.json");

/// The Fox's walk: 0 to 0.708 s.
const WALK: (f32, f32) = (0.0, 0.708);

/// Where in the walk the still is drawn (s).
const MID_WALK: f32 = 0.35;

/// What can stop the demo.
#[derive(Debug, thiserror::Error)]
pub enum DemoError {
    /// The output folder could not be made.
    #[error("creating {}: {source}", path.display())]
    Folder {
        /// The folder.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The creature could not be made.
    #[error(transparent)]
    Creature(#[from] DemoCreatureError),
    /// The Fox's fur textures could not be generated.
    #[error("generating the Fox's fur textures: {0}")]
    Textures(#[source] FurError),
    /// The Fox could not be read, baked or written, or the scene file written.
    #[error(transparent)]
    Io(#[from] IoError),
    /// An asset could not be loaded back.
    #[error(transparent)]
    Asset(#[from] AssetError),
    /// The bundled mirror scene does not parse.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// Rendering failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The scene could not be written as JSON.
    #[error("writing the demo's scene file: {0}")]
    Json(#[source] serde_json::Error),
    /// Animating the Fox failed.
    #[error(transparent)]
    Animate(#[from] AnimateError),
}

impl From<FrameError> for DemoError {
    fn from(e: FrameError) -> Self {
        DemoError::Render(RenderError::Frame(e))
    }
}

/// The demo's choices.
#[derive(Debug, Clone)]
pub struct DemoOptions {
    /// The output folder (created).
    pub output: PathBuf,
    /// The stills' size (the contact sheets' frames are a quarter of it).
    pub size: (u32, u32),
    /// Frames of the turntable and of the walk (4 per row).
    pub frames: u32,
    /// Shells (by screen size, at most the bake's, when `None`).
    pub shells: Option<u32>,
    /// How fur is composited.
    pub fur_blend: FurBlend,
}

/// The files the demo wrote, in the order written.
#[derive(Debug, Clone, Default)]
pub struct DemoOutputs {
    /// Each file and what it holds.
    pub files: Vec<(PathBuf, String)>,
}

/// The Fox's fur: the demo's strands, length scaled to its size (about 150 units nose to
/// tail), coloured by the Fox's base colour texture (orange back, white chest and tail tip),
/// darker at the roots.
pub fn fox_fur() -> FurConfig {
    FurConfig {
        length: 3.0,
        base_color: [0.35, 0.33, 0.32],
        tip_color: [1.0, 1.0, 1.0],
        color_from_texture: true,
        ..demo_fur()
    }
}

/// Bakes the bundled Fox with a generated comb (toward its tail) and the fox fur into `path`.
pub fn bake_fox(path: &Path) -> Result<(), DemoError> {
    let mut doc = pelt_io::Document::from_bytes(Path::new("Fox.glb"), FOX.to_vec())?;
    let opts = BakeOptions {
        comb: CombSource::Generate(GeneratedComb::default()),
        ..BakeOptions::default()
    };
    let assets = FurAssets::new(fox_fur()).map_err(DemoError::Textures)?;
    bake_with_fur(&mut doc, &opts, &assets)?;
    pelt_io::glb::write_glb(&doc, path)?;
    Ok(())
}

/// The fur scene of `mesh` (at `asset`) at `(w, h)`, seen from `yaw` degrees.
fn scene_of(o: &DemoOptions, asset: &Path, mesh: &MeshData, (w, h): (u32, u32), yaw: f32) -> Scene {
    let (lo, hi) = mesh.bounds();
    let mut s = fur_scene(asset, lo, hi, w, h, yaw);
    s.fur_blend = o.fur_blend;
    let k = Knobs {
        shells: o.shells.map(pelt_scene::knobs::ShellCount::Fixed),
        ..Knobs::default()
    };
    k.apply(&mut s);
    s
}

/// The Fox's scene (framed on `mid`, three-quarter view from the front left): the fur scene
/// with its key light casting shadows, so the Fox stands on the floor in its contact shadow,
/// a light wind in its fur, and springs in it (about 6 Hz, a third of critical damping), so
/// the fur lags as the Fox walks.
fn fox_scene(o: &DemoOptions, asset: &Path, mid: &MeshData, size: (u32, u32)) -> Scene {
    let mut s = scene_of(o, asset, mid, size, 35.0);
    s.lights[0].shadows = true;
    // A light breeze from the Fox's left, gusting; the still is drawn mid-walk, at 0.35 s.
    s.wind = Some(Wind {
        direction: Vec3::new(1.0, 0.0, 0.4).normalize(),
        strength: 0.5,
        gust_hz: 0.8,
        turbulence: 0.5,
    });
    s.time = MID_WALK;
    if let Some(Material::Fur(f)) = s.objects.first_mut().map(|o| &mut o.material) {
        f.spring = Some(Spring {
            stiffness: 1500.0,
            damping: 25.0,
        });
    }
    s
}

/// The Fox furred mid-walk, and its walk cycle as a contact sheet (three-quarter view from
/// the front left).
fn fox_renders(
    preview: &mut Preview,
    o: &DemoOptions,
    asset: &Path,
) -> Result<(Image, Image, Scene), DemoError> {
    let walk = |time: f32| PoseAt {
        animation: "Walk".to_owned(),
        time,
    };
    let mid = asset::load_at(asset, Some(&walk(MID_WALK)))?;
    let quad = asset::quad();
    let (w, h) = o.size;
    let scene = fox_scene(o, asset, &mid, (w, h));
    let d = preview.prepare_loaded(
        &scene,
        &[mid.clone(), quad.clone()],
        &[0, 1],
        Mode::Inferred,
    )?;
    let still = preview.render(&d)?;
    let poses = spread("Walk", WALK, o.frames);
    let first = asset::load_at(asset, Some(&poses[0]))?;
    // Framed on the mid-walk pose, as the still.
    let tile = ((w / 4).max(1), (h / 4).max(1));
    let clip = Clip {
        scene: &fox_scene(o, asset, &mid, tile),
        meshes: &[first, quad],
        mesh_of: &[0, 1],
        doc: &pelt_io::load(asset)?,
        path: asset,
        mode: Mode::Inferred,
    };
    let tiles = clip.frames(preview, &poses)?;
    Ok((still, Image::contact_sheet(&tiles, 4), scene))
}

/// The creature (baked at `asset`) beside a mirror, rendered at `size`.
fn mirror_scene(
    preview: &mut Preview,
    asset: &Path,
    (w, h): (u32, u32),
) -> Result<Image, DemoError> {
    let mut scene = Scene::parse(Path::new("creature-mirror.json"), MIRROR_SCENE)?;
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
fn write_scene(scene: &Scene, path: &Path) -> Result<(), DemoError> {
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
    let json = serde_json::to_string_pretty(&s).map_err(DemoError::Json)?;
    pelt_io::glb::write_atomic(path, json.as_bytes())?;
    Ok(())
}

/// Runs the demo into `o.output`.
pub fn run(preview: &mut Preview, o: &DemoOptions) -> Result<DemoOutputs, DemoError> {
    let dir = &o.output;
    std::fs::create_dir_all(dir).map_err(|source| DemoError::Folder {
        path: dir.clone(),
        source,
    })?;
    let mut out = DemoOutputs::default();
    let mut wrote = |name: &str, what: String| {
        out.files.push((dir.join(name), what));
        dir.join(name)
    };
    let (w, h) = o.size;
    let fox = wrote("fox.glb", "the Fox, generated comb".into());
    bake_fox(&fox)?;
    let (still, walk, fox_scene) = fox_renders(preview, o, &fox)?;
    still.save(&wrote(
        "demo.png",
        format!("furred and textured mid-walk, {w}×{h}"),
    ))?;
    walk.save(&wrote(
        "fox-walk.png",
        format!("{} frames of its walk", o.frames),
    ))?;
    write_scene(
        &fox_scene,
        &wrote(
            "fox.json",
            format!(
                "the Fox's scene (pelt render fox.json --animation Walk --time {MID_WALK} draws demo.png)"
            ),
        ),
    )?;
    let asset = wrote("creature.glb", "baked fixture creature".into());
    bake_creature(&asset)?;
    let meshes = vec![asset::load(&asset)?, asset::quad()];
    let at = |size, yaw| scene_of(o, &asset, &meshes[0], size, yaw);
    let d = preview.prepare_loaded(&at((w, h), 0.0), &meshes, &[0, 1], Mode::Inferred)?;
    preview
        .render(&d)?
        .save(&wrote("creature.png", format!("{w}×{h}")))?;
    write_scene(
        &at((w, h), 0.0),
        &wrote("scene.json", "the creature's scene".into()),
    )?;
    let tile = ((w / 4).max(1), (h / 4).max(1));
    let mut tiles = Vec::new();
    for k in 0..o.frames {
        let yaw = 360.0 * k as f32 / o.frames as f32;
        let d = preview.prepare_loaded(&at(tile, yaw), &meshes, &[0, 1], Mode::Inferred)?;
        tiles.push(preview.render(&d)?);
    }
    let turntable = wrote("turntable.png", format!("{} views", o.frames));
    Image::contact_sheet(&tiles, 4).save(&turntable)?;
    let mirror = wrote("mirror.png", "beside a mirror".into());
    mirror_scene(preview, &asset, (w, h))?.save(&mirror)?;
    Ok(out)
}
