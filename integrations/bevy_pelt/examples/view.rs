//! Opens a window on a pelt scene file or a `.glb` (framed as `pelt view` frames it) with its
//! fur drawn by bevy_pelt: drag to orbit, scroll to zoom; an asset's clip plays if named.
//!
//! `cargo run --release --example view -- SCENE.json|ASSET.glb [--shells N|auto]
//! [--animation NAME] [--frames N]` (`--frames`: close after N frames, exit 1 if the fur is
//! not drawn by then).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use bevy::asset::{AssetPlugin, UnapprovedPathMode};
use bevy::camera::RenderTarget;
use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll};
use bevy::prelude::*;
use bevy::window::WindowRef;
use bevy_pelt::scene::{self, PeltScene, SceneOptions, Spawner};
use bevy_pelt::{
    FurAttached, FurSettings, FurWind, PeltFurError, PeltFurPlugin, PeltSurfaceMaterial,
    SkyMaterial,
};

const USAGE: &str =
    "usage: view SCENE.json|ASSET.glb [--shells N|auto] [--animation NAME] [--frames N]";

#[derive(Resource, Clone)]
struct Args {
    path: PathBuf,
    shells: Option<u32>,
    auto: bool,
    animation: Option<String>,
    frames: Option<u32>,
}

fn parse() -> Result<Args, String> {
    let mut it = std::env::args().skip(1);
    let mut a = Args {
        path: PathBuf::new(),
        shells: None,
        auto: false,
        animation: None,
        frames: None,
    };
    let mut path = None;
    while let Some(s) = it.next() {
        let mut value = |n: &str| it.next().ok_or(format!("{n} needs a value\n{USAGE}"));
        match s.as_str() {
            "--shells" => match value("--shells")?.as_str() {
                "auto" => a.auto = true,
                v => {
                    a.shells = Some(
                        v.parse()
                            .ok()
                            .filter(|n| (1..=1024).contains(n))
                            .ok_or(format!("--shells: {v}: expected 1 to 1024 or auto"))?,
                    )
                }
            },
            "--animation" => a.animation = Some(value("--animation")?),
            "--frames" => {
                let v = value("--frames")?;
                a.frames = Some(
                    v.parse()
                        .map_err(|_| format!("--frames: {v}: expected a count"))?,
                );
            }
            f if f.starts_with('-') => return Err(format!("unknown flag {f}\n{USAGE}")),
            p if path.is_none() => path = Some(PathBuf::from(p)),
            p => return Err(format!("unexpected argument {p}\n{USAGE}")),
        }
    }
    a.path = path.ok_or(USAGE)?;
    Ok(a)
}

/// The scene to show: the file, or the default scene framing an asset.
fn scene_of(path: &Path) -> Result<pelt_scene::scene::Scene, String> {
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        return pelt_scene::scene::Scene::load(path).map_err(|e| e.to_string());
    }
    let mesh = pelt_scene::asset::load(path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(pelt_scene::framing::asset_scene(path, &mesh, 1280, 720))
}

fn main() -> ExitCode {
    if std::env::args().skip(1).any(|a| a == "-h" || a == "--help") {
        println!("{USAGE}");
        return ExitCode::SUCCESS;
    }
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

#[derive(Resource)]
struct SceneFile(pelt_scene::scene::Scene);

/// The outcome, shared with `run` (`App::run` takes the app's world with it), and the frames
/// drawn.
#[derive(Resource, Clone, Default)]
struct Outcome(
    std::sync::Arc<std::sync::Mutex<Option<Result<(), String>>>>,
    u32,
);

impl Outcome {
    fn set(&self, r: Result<(), String>) {
        if let Ok(mut slot) = self.0.lock() {
            *slot = Some(r);
        }
    }
}

fn run() -> Result<(), String> {
    let args = parse()?;
    let mut file = scene_of(&args.path)?;
    if args.auto {
        for o in &mut file.objects {
            if let pelt_scene::scene::Material::Fur(f) = &mut o.material {
                f.shells = None;
            }
        }
    }
    scene::check_assets(&file).map_err(|e| format!("{}: {e}", args.path.display()))?;
    let title = format!("bevy_pelt: {}", args.path.display());
    let size = UVec2::new(file.output.width, file.output.height);
    let binary = file.fur_coverage == pelt_scene::scene::FurCoverage::Binary;
    let outcome = Outcome::default();
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: Some(Window {
                    title,
                    resolution: (size.x, size.y).into(),
                    ..default()
                }),
                ..default()
            })
            .set(AssetPlugin {
                file_path: scene::asset_root(),
                unapproved_path_mode: UnapprovedPathMode::Allow,
                ..default()
            }),
    )
    .add_plugins(PeltFurPlugin)
    .insert_resource(FurSettings {
        shells: args.shells,
        fins: None,
        binary_coverage: binary,
        control: None,
    })
    .insert_resource(SceneFile(file))
    .insert_resource(args.clone())
    .insert_resource(outcome.clone())
    .add_systems(Startup, setup)
    .add_systems(
        Update,
        (scene::surfaces, scene::pose, play, orbit, count_frames).chain(),
    );
    app.run();
    let result = outcome
        .0
        .lock()
        .map_err(|_| "the app's outcome was poisoned")?
        .take();
    result.unwrap_or(Ok(()))
}

fn setup(
    mut commands: Commands,
    file: Res<SceneFile>,
    args: Res<Args>,
    assets: Res<AssetServer>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut surfaces: ResMut<Assets<PeltSurfaceMaterial>>,
    mut skies: ResMut<Assets<SkyMaterial>>,
    windows: Query<&Window>,
) {
    let size = windows
        .iter()
        .next()
        .map_or(UVec2::new(1280, 720), |w| w.physical_size());
    let options = SceneOptions {
        animation: args.animation.clone(),
        time: 0.0,
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
        RenderTarget::Window(WindowRef::Primary),
        options,
    );
    let c = &file.0.camera;
    let eye = Vec3::from(c.position);
    let target = Vec3::from(c.target);
    commands.insert_resource(Orbit {
        target,
        offset: eye - target,
    });
    commands.insert_resource(built);
}

/// The camera's orbit about its target.
#[derive(Resource)]
struct Orbit {
    target: Vec3,
    offset: Vec3,
}

fn orbit(
    mut o: ResMut<Orbit>,
    buttons: Res<ButtonInput<MouseButton>>,
    motion: Res<AccumulatedMouseMotion>,
    scroll: Res<AccumulatedMouseScroll>,
    scene: Res<PeltScene>,
    mut cameras: Query<&mut Transform, With<Camera3d>>,
) {
    if buttons.pressed(MouseButton::Left) && motion.delta != Vec2::ZERO {
        let yaw = Quat::from_rotation_y(-motion.delta.x * 0.005);
        let right = o.offset.cross(Vec3::Y).normalize_or_zero();
        let pitch = Quat::from_axis_angle(right, -motion.delta.y * 0.005);
        let next = pitch * (yaw * o.offset);
        if next.normalize_or_zero().y.abs() < 0.98 {
            o.offset = next;
        } else {
            o.offset = yaw * o.offset;
        }
    }
    if scroll.delta.y != 0.0 {
        o.offset *= (1.0 - scroll.delta.y * 0.1).clamp(0.5, 1.5);
    }
    if let Some(mut t) = scene.camera.and_then(|c| cameras.get_mut(c).ok()) {
        *t = Transform::from_translation(o.target + o.offset).looking_at(o.target, Vec3::Y);
    }
}

/// The wind follows the app's clock; a named clip plays in a loop.
fn play(
    mut wind: ResMut<FurWind>,
    mut players: Query<&mut AnimationPlayer, Added<AnimationGraphHandle>>,
) {
    if wind.time.is_some() {
        wind.time = None;
    }
    for mut p in &mut players {
        let nodes: Vec<_> = p.playing_animations().map(|(n, _)| *n).collect();
        for n in nodes {
            if let Some(a) = p.animation_mut(n) {
                a.resume().repeat();
            }
        }
    }
}

fn count_frames(
    mut outcome: ResMut<Outcome>,
    args: Res<Args>,
    scene: Res<PeltScene>,
    furs: Query<(), With<FurAttached>>,
    broken: Query<&PeltFurError>,
    mut exit: MessageWriter<AppExit>,
) {
    outcome.1 += 1;
    if let Some(e) = scene
        .errors
        .first()
        .cloned()
        .or_else(|| broken.iter().next().map(|b| b.0.clone()))
    {
        outcome.set(Err(e));
        exit.write(AppExit::from_code(1));
        return;
    }
    let Some(n) = args.frames else { return };
    if outcome.1 >= n {
        let wants_fur = scene.objects.iter().any(|o| o.fur);
        outcome.set(if wants_fur && furs.is_empty() {
            Err(format!("no fur drawn after {n} frames"))
        } else {
            Ok(())
        });
        exit.write(AppExit::Success);
    }
}
