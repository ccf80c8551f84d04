//! Draws a pelt scene file headless to a PNG, as `pelt render` does:
//!
//! `cargo run --release --example render -- SCENE.json -o OUT.png --size WxH [--shells N|auto]
//! [--animation NAME --time T]`
//!
//! A bad scene file, a missing asset or animation, or fur that cannot be read exits 1 naming
//! the place, and writes no PNG.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use bevy::app::ScheduleRunnerPlugin;
use bevy::asset::{AssetPlugin, LoadState, RenderAssetUsages, UnapprovedPathMode};
use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::render::render_resource::TextureFormat;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;
use bevy_pelt::scene::{self, PeltScene, SceneOptions, Spawner};
use bevy_pelt::{
    FurAttached, FurControl, FurSettings, PeltFur, PeltFurError, PeltFurPlugin,
    PeltSurfaceMaterial, SkyMaterial,
};

const USAGE: &str = "usage: render SCENE.json -o OUT.png [--size WxH] [--shells N|auto] [--animation NAME --time T]";

/// The command line.
#[derive(Clone, Debug, Resource)]
struct Args {
    scene: PathBuf,
    out: PathBuf,
    size: Option<UVec2>,
    shells: Option<Shells>,
    animation: Option<String>,
    time: f32,
    control: Option<FurControl>,
}

#[derive(Clone, Copy, Debug)]
enum Shells {
    Auto,
    Fixed(u32),
}

fn parse() -> Result<Args, String> {
    let mut it = std::env::args().skip(1);
    let (mut scene, mut out, mut size, mut shells, mut animation, mut time) =
        (None, None, None, None, None, None);
    let mut control = None;
    while let Some(a) = it.next() {
        let mut value = |name: &str| it.next().ok_or(format!("{name} needs a value\n{USAGE}"));
        match a.as_str() {
            "-o" | "--output" => out = Some(PathBuf::from(value("-o")?)),
            "--size" => {
                let v = value("--size")?;
                let (w, h) = v
                    .split_once('x')
                    .ok_or(format!("--size: {v}: expected WxH"))?;
                let (w, h) = (w.parse::<u32>(), h.parse::<u32>());
                match (w, h) {
                    (Ok(w), Ok(h)) if (1..=8192).contains(&w) && (1..=8192).contains(&h) => {
                        size = Some(UVec2::new(w, h))
                    }
                    _ => return Err(format!("--size: {v}: width and height must be 1 to 8192")),
                }
            }
            "--shells" => {
                let v = value("--shells")?;
                shells = Some(match v.as_str() {
                    "auto" => Shells::Auto,
                    n => match n.parse::<u32>() {
                        Ok(n) if (1..=1024).contains(&n) => Shells::Fixed(n),
                        _ => return Err(format!("--shells: {v}: expected 1 to 1024 or auto")),
                    },
                });
            }
            "--animation" => animation = Some(value("--animation")?),
            // The tests' negative controls.
            "--control" => match value("--control")?.as_str() {
                "opaque-shells" => control = Some(FurControl::OpaqueShells),
                c => return Err(format!("--control: {c}: known: opaque-shells")),
            },
            "--time" => {
                let v = value("--time")?;
                time = Some(
                    v.parse::<f32>()
                        .ok()
                        .filter(|t| t.is_finite() && *t >= 0.0)
                        .ok_or(format!("--time: {v}: expected seconds, at least 0"))?,
                );
            }
            "-h" | "--help" => return Err(USAGE.into()),
            s if s.starts_with('-') => return Err(format!("unknown flag {s}\n{USAGE}")),
            s if scene.is_none() => scene = Some(PathBuf::from(s)),
            s => return Err(format!("unexpected argument {s}\n{USAGE}")),
        }
    }
    Ok(Args {
        scene: scene.ok_or(USAGE)?,
        out: out.ok_or(format!("-o OUT.png is required\n{USAGE}"))?,
        size,
        shells,
        animation,
        time: time.unwrap_or(0.0),
        control,
    })
}

/// What the app reports back after it stops (`App::run` takes the app's world with it).
#[derive(Resource, Clone, Default)]
struct Report(std::sync::Arc<std::sync::Mutex<Option<Result<(), String>>>>);

/// Progress toward the picture.
#[derive(Resource, Default)]
struct Capture {
    ready_frames: u32,
    frames: u32,
    requested: bool,
    result: Option<Result<(), String>>,
    target: Handle<Image>,
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

fn run() -> Result<(), String> {
    let args = parse()?;
    let mut file = pelt_scene::scene::Scene::load(&args.scene).map_err(|e| e.to_string())?;
    if matches!(args.shells, Some(Shells::Auto)) {
        for o in &mut file.objects {
            if let pelt_scene::scene::Material::Fur(f) = &mut o.material {
                f.shells = None;
            }
        }
    }
    scene::check_assets(&file).map_err(|e| format!("{}: {e}", args.scene.display()))?;
    let size = args
        .size
        .unwrap_or(UVec2::new(file.output.width, file.output.height));
    let forced = match args.shells {
        Some(Shells::Fixed(n)) => Some(n),
        _ => None,
    };
    let report = Report::default();
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                ..default()
            })
            .set(AssetPlugin {
                file_path: scene::asset_root(),
                unapproved_path_mode: UnapprovedPathMode::Allow,
                ..default()
            })
            .set(RenderPlugin {
                synchronous_pipeline_compilation: true,
                ..default()
            })
            .disable::<WinitPlugin>(),
    )
    .add_plugins((
        ScheduleRunnerPlugin::run_loop(Duration::ZERO),
        PeltFurPlugin,
    ))
    .insert_resource(FurSettings {
        shells: forced,
        control: args.control,
    })
    .insert_resource(SceneFile(file, size))
    .insert_resource(args.clone())
    .init_resource::<Capture>()
    .insert_resource(report.clone())
    .add_systems(Startup, setup)
    .add_systems(Update, (scene::surfaces, scene::pose, progress).chain());
    let exit = app.run();
    let result = report
        .0
        .lock()
        .map_err(|_| "the app's report was poisoned")?
        .take();
    result.unwrap_or_else(|| {
        Err(format!(
            "the app stopped ({exit:?}) before the picture was taken"
        ))
    })
}

#[derive(Resource)]
struct SceneFile(pelt_scene::scene::Scene, UVec2);

fn setup(
    mut commands: Commands,
    file: Res<SceneFile>,
    args: Res<Args>,
    assets: Res<AssetServer>,
    mut images: ResMut<Assets<Image>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut surfaces: ResMut<Assets<PeltSurfaceMaterial>>,
    mut skies: ResMut<Assets<SkyMaterial>>,
    mut capture: ResMut<Capture>,
) {
    let size = file.1;
    let mut image = Image::new_target_texture(size.x, size.y, TextureFormat::Rgba8UnormSrgb, None);
    image.asset_usage = RenderAssetUsages::default();
    let target = images.add(image);
    capture.target = target.clone();
    let options = SceneOptions {
        animation: args.animation.clone(),
        time: args.time,
    };
    let mut s = Spawner {
        commands: &mut commands,
        assets: &assets,
        meshes: &mut meshes,
        surfaces: &mut surfaces,
        skies: &mut skies,
    };
    let built = scene::spawn(
        &mut s,
        &file.0,
        size,
        RenderTarget::Image(target.into()),
        options,
    );
    commands.insert_resource(built);
}

/// Waits for every asset, fur and pose, lets three frames draw, then takes the picture.
fn progress(
    mut commands: Commands,
    mut capture: ResMut<Capture>,
    scene: Res<PeltScene>,
    assets: Res<AssetServer>,
    children: Query<&Children>,
    waiting: Query<Entity, (With<PeltFur>, Without<FurAttached>)>,
    broken: Query<&PeltFurError>,
    args: Res<Args>,
    mut exit: MessageWriter<AppExit>,
    report: Res<Report>,
) {
    if let Some(r) = capture.result.clone() {
        if let Ok(mut slot) = report.0.lock() {
            *slot = Some(r);
        }
        exit.write(AppExit::Success);
        return;
    }
    capture.frames += 1;
    let fail = |capture: &mut Capture, e: String| capture.result = Some(Err(e));
    if let Some(e) = scene.errors.first() {
        return fail(&mut capture, format!("{}: {e}", args.scene.display()));
    }
    if let Some(e) = broken.iter().next() {
        return fail(&mut capture, e.0.clone());
    }
    let mut ready = true;
    for o in &scene.objects {
        match assets.get_load_state(&o.gltf) {
            Some(LoadState::Failed(e)) => {
                return fail(
                    &mut capture,
                    format!("{}: {}: {e}", args.scene.display(), o.place),
                );
            }
            Some(LoadState::Loaded) => {}
            _ => ready = false,
        }
        ready &=
            assets.is_loaded_with_dependencies(&o.gltf) && o.posed && children.get(o.root).is_ok();
    }
    ready &= waiting.is_empty();
    if capture.frames > 3000 {
        return fail(
            &mut capture,
            "the scene did not finish loading in 3000 frames".into(),
        );
    }
    if !ready || capture.requested {
        return;
    }
    capture.ready_frames += 1;
    if capture.ready_frames < 4 {
        return;
    }
    capture.requested = true;
    let out = args.out.clone();
    commands
        .spawn(Screenshot::image(capture.target.clone()))
        .observe(
            move |shot: On<ScreenshotCaptured>, mut capture: ResMut<Capture>| {
                capture.result = Some(write_png(&shot.image, &out));
            },
        );
}

/// The picture as an RGBA PNG, written whole or not at all.
fn write_png(image: &Image, out: &std::path::Path) -> Result<(), String> {
    let (w, h) = (image.width(), image.height());
    let data = image.data.as_ref().ok_or("the screenshot has no pixels")?;
    // Opaque RGBA, as pelt writes (the target's alpha is the blend's, not coverage).
    let rgba: Vec<u8> = data
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header().map_err(|e| e.to_string())?;
        writer.write_image_data(&rgba).map_err(|e| e.to_string())?;
    }
    let tmp = out.with_extension("png.partial");
    std::fs::write(&tmp, &bytes).map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, out).map_err(|e| format!("{}: {e}", out.display()))
}
