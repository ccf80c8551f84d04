//! Draws a pelt scene file headless to a PNG, as `pelt render` does:
//!
//! `cargo run --release --example render -- SCENE.json -o OUT.png --size WxH [--shells N|auto]
//! [--animation NAME --time T]`
//!
//! A bad scene file, a missing asset or animation, or fur that cannot be read exits 1 naming
//! the place, and writes no PNG.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use bevy::app::ScheduleRunnerPlugin;
use bevy::asset::{AssetPlugin, LoadState, RenderAssetUsages, UnapprovedPathMode};
use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::render::pipelined_rendering::PipelinedRenderingPlugin;
use bevy::render::render_resource::PollType;
use bevy::render::render_resource::TextureFormat;
use bevy::render::renderer::RenderDevice;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::render::{Render, RenderApp, RenderPlugin, RenderSystems};
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;
use bevy_pelt::scene::{self, PeltScene, SceneOptions, Spawner};
use bevy_pelt::{
    FurAttached, FurControl, FurSettings, PeltFur, PeltFurData, PeltFurError, PeltFurPlugin,
    PeltSurfaceMaterial, SkyMaterial,
};

const USAGE: &str = "usage: render SCENE.json -o OUT.png [--size WxH] [--shells N|auto] [--fins on|off] [--animation NAME] [--time T] [--report] [--bench N]";

/// The command line.
#[derive(Clone, Debug, Resource)]
struct Args {
    scene: PathBuf,
    out: PathBuf,
    size: Option<UVec2>,
    shells: Option<Shells>,
    animation: Option<String>,
    time: f32,
    control: Option<Control>,
    report: bool,
    bench: Option<u32>,
    fins: Option<bool>,
}

/// The tests' negative controls.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Control {
    Fur(FurControl),
    NoWind,
    NoShadows,
}

#[derive(Clone, Copy, Debug)]
enum Shells {
    Auto,
    Fixed(u32),
}

fn parse_size(v: &str) -> Result<UVec2, String> {
    let (w, h) = v
        .split_once('x')
        .ok_or(format!("--size: {v}: expected WxH"))?;
    match (w.parse::<u32>(), h.parse::<u32>()) {
        (Ok(w), Ok(h)) if (1..=8192).contains(&w) && (1..=8192).contains(&h) => {
            Ok(UVec2::new(w, h))
        }
        _ => Err(format!("--size: {v}: width and height must be 1 to 8192")),
    }
}

fn parse_shells(v: &str) -> Result<Shells, String> {
    match v {
        "auto" => Ok(Shells::Auto),
        n => match n.parse::<u32>() {
            Ok(n) if (1..=1024).contains(&n) => Ok(Shells::Fixed(n)),
            _ => Err(format!("--shells: {v}: expected 1 to 1024 or auto")),
        },
    }
}

fn parse_control(v: &str) -> Result<Control, String> {
    Ok(match v {
        "opaque-shells" => Control::Fur(FurControl::OpaqueShells),
        "no-fur-shadow" => Control::Fur(FurControl::NoFurShadow),
        "no-texture" => Control::Fur(FurControl::NoTexture),
        "no-wind" => Control::NoWind,
        "no-shadows" => Control::NoShadows,
        c => {
            return Err(format!(
                "--control: {c}: known: opaque-shells, no-fur-shadow, no-texture, no-wind, no-shadows"
            ));
        }
    })
}

fn parse_switch(flag: &str, v: &str) -> Result<bool, String> {
    match v {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("{flag}: {v}: expected on or off")),
    }
}

/// A number of `flag` that `ok` accepts, or an error saying what it expects.
fn parse_number<T: std::str::FromStr>(
    flag: &str,
    v: &str,
    ok: impl Fn(&T) -> bool,
    expected: &str,
) -> Result<T, String> {
    v.parse::<T>()
        .ok()
        .filter(|x| ok(x))
        .ok_or(format!("{flag}: {v}: expected {expected}"))
}

fn parse() -> Result<Args, String> {
    let mut it = std::env::args().skip(1);
    let mut a = Args {
        scene: PathBuf::new(),
        out: PathBuf::new(),
        size: None,
        shells: None,
        animation: None,
        time: 0.0,
        control: None,
        report: false,
        bench: None,
        fins: None,
    };
    let (mut scene, mut out) = (None, None);
    while let Some(flag) = it.next() {
        let mut value = |name: &str| it.next().ok_or(format!("{name} needs a value\n{USAGE}"));
        match flag.as_str() {
            "-o" | "--output" => out = Some(PathBuf::from(value("-o")?)),
            "--size" => a.size = Some(parse_size(&value("--size")?)?),
            "--shells" => a.shells = Some(parse_shells(&value("--shells")?)?),
            "--animation" => a.animation = Some(value("--animation")?),
            "--time" => {
                a.time = parse_number(
                    "--time",
                    &value("--time")?,
                    |t: &f32| t.is_finite() && *t >= 0.0,
                    "seconds, at least 0",
                )?
            }
            "--fins" => a.fins = Some(parse_switch("--fins", &value("--fins")?)?),
            "--report" => a.report = true,
            "--bench" => {
                a.bench = Some(parse_number(
                    "--bench",
                    &value("--bench")?,
                    |n: &u32| (1..=10_000).contains(n),
                    "1 to 10000 frames",
                )?)
            }
            // The tests' negative controls.
            "--control" => a.control = Some(parse_control(&value("--control")?)?),
            s if s.starts_with('-') => return Err(format!("unknown flag {s}\n{USAGE}")),
            s if scene.is_none() => scene = Some(PathBuf::from(s)),
            s => return Err(format!("unexpected argument {s}\n{USAGE}")),
        }
    }
    a.scene = scene.ok_or(USAGE)?;
    a.out = out.ok_or(format!("-o OUT.png is required\n{USAGE}"))?;
    Ok(a)
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
    /// `--bench`: when the last frame began, and each frame's time.
    last: Option<Instant>,
    times: Vec<f64>,
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

/// The scene file as the flags change it (a control's edits, `--shells auto` releasing the
/// objects' counts), its assets checked.
fn load(args: &Args) -> Result<pelt_scene::scene::Scene, String> {
    let mut file = pelt_scene::scene::Scene::load(&args.scene).map_err(|e| e.to_string())?;
    match args.control {
        Some(Control::NoWind) => file.wind = None,
        Some(Control::NoShadows) => file.lights.iter_mut().for_each(|l| l.shadows = false),
        _ => {}
    }
    if matches!(args.shells, Some(Shells::Auto)) {
        for o in &mut file.objects {
            if let pelt_scene::scene::Material::Fur(f) = &mut o.material {
                f.shells = None;
            }
        }
    }
    scene::check_assets(&file).map_err(|e| format!("{}: {e}", args.scene.display()))?;
    Ok(file)
}

fn run() -> Result<(), String> {
    let args = parse()?;
    let file = load(&args)?;
    let size = args
        .size
        .unwrap_or(UVec2::new(file.output.width, file.output.height));
    let forced = match args.shells {
        Some(Shells::Fixed(n)) => Some(n),
        _ => None,
    };
    let binary = file.fur_coverage == pelt_scene::scene::FurCoverage::Binary;
    let report = Report::default();
    let mut app = App::new();
    let plugins = DefaultPlugins
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
        .disable::<WinitPlugin>();
    // `--bench`: each frame drawn to the end before the next (no pipelined rendering, and the
    // render world waits for the device), so that a frame's time is its whole cost.
    if args.bench.is_some() {
        app.add_plugins(plugins.disable::<PipelinedRenderingPlugin>());
        app.sub_app_mut(RenderApp)
            .add_systems(Render, wait_for_device.in_set(RenderSystems::Cleanup));
    } else {
        app.add_plugins(plugins);
    }
    app.add_plugins((
        ScheduleRunnerPlugin::run_loop(Duration::ZERO),
        PeltFurPlugin,
    ))
    .insert_resource(FurSettings {
        shells: forced,
        fins: args.fins,
        binary_coverage: binary,
        control: match args.control {
            Some(Control::Fur(c)) => Some(c),
            _ => None,
        },
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

/// Blocks until the device has finished the frame's work (`--bench`).
fn wait_for_device(device: Res<RenderDevice>) {
    if let Err(e) = device.poll(PollType::wait_indefinitely()) {
        error!("waiting for the device: {e}");
    }
}

/// Waits for every asset, fur and pose, lets three frames draw (and `--bench` frames more,
/// timed), then takes the picture.
fn progress(
    mut commands: Commands,
    mut capture: ResMut<Capture>,
    scene: Res<PeltScene>,
    assets: Res<AssetServer>,
    children: Query<&Children>,
    waiting: Query<Entity, (With<PeltFur>, Without<FurAttached>)>,
    broken: Query<&PeltFurError>,
    furs: Query<&FurAttached>,
    data: Res<Assets<PeltFurData>>,
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
    if let Some(n) = args.bench {
        let now = Instant::now();
        if let Some(last) = capture.last {
            capture.times.push((now - last).as_secs_f64() * 1e3);
        }
        capture.last = Some(now);
        if capture.times.len() < n as usize {
            return;
        }
    }
    capture.requested = true;
    print_json(&args, &capture.times, &furs, &data);
    let out = args.out.clone();
    commands
        .spawn(Screenshot::image(capture.target.clone()))
        .observe(
            move |shot: On<ScreenshotCaptured>, mut capture: ResMut<Capture>| {
                capture.result = Some(write_png(&shot.image, &out));
            },
        );
}

/// `--report` (the shells each fur primitive draws) and `--bench` (frame times), as one JSON
/// object on stdout.
fn print_json(args: &Args, times: &[f64], furs: &Query<&FurAttached>, data: &Assets<PeltFurData>) {
    if !args.report && args.bench.is_none() {
        return;
    }
    let mut out = serde_json::Map::new();
    if args.report {
        let mut fur: Vec<serde_json::Value> = furs
            .iter()
            .map(|f| {
                let place = data.get(&f.data).map_or("", |d| d.place.as_str());
                serde_json::json!({ "place": place, "shells": f.drawn, "max": f.max, "byScreenSize": f.rule.is_some() })
            })
            .collect();
        fur.sort_by_key(|v| v["place"].to_string());
        out.insert("fur".into(), fur.into());
    }
    if args.bench.is_some() {
        let mut sorted = times.to_vec();
        sorted.sort_by(f64::total_cmp);
        let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0.0);
        out.insert("frames".into(), times.to_vec().into());
        out.insert("medianMs".into(), median.into());
    }
    println!("{}", serde_json::Value::Object(out));
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
