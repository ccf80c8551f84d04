//! `pelt render` end to end: an asset with the default scene, a scene file, modes, sizes,
//! `--explain` without a GPU, deterministic PNGs, a baked asset with normal groups, and the
//! errors (bad scene: exit 2 naming file, line and field; missing asset: exit 1 naming the
//! object; nothing written either way). The back end follows `PELT_BACKEND` (CI runs both).

mod common;

use std::path::Path;

use common::*;

fn backend() -> String {
    std::env::var("PELT_BACKEND").unwrap_or_else(|_| "auto".into())
}

fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).expect("png written");
    let d = png::Decoder::new(std::io::Cursor::new(bytes));
    let r = d.read_info().expect("valid png");
    (r.info().width, r.info().height)
}

fn render(args: &[&str]) -> std::process::Output {
    let b = backend();
    let mut all: Vec<&str> = vec!["render", "--backend", &b];
    all.extend_from_slice(args);
    pelt(&all, &[])
}

fn render_ok(args: &[&str]) -> std::process::Output {
    let out = render(args);
    assert!(
        out.status.success(),
        "pelt render {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

#[test]
fn an_asset_renders_with_the_default_scene_and_names_the_adapter() {
    let dir = scratch("render-asset");
    let out = dir.join("torus.png");
    let o = render_ok(&[
        fixture("torus.glb").to_str().expect("utf8"),
        "-o",
        out.to_str().expect("utf8"),
    ]);
    assert_eq!(png_size(&out), (640, 360));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("adapter: "), "{err}");
    // The asset is in the picture: pixels differ from the background in the middle.
    let bytes = std::fs::read(&out).expect("read");
    let mut r = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .expect("png");
    let mut buf = vec![0; r.output_buffer_size().expect("size")];
    r.next_frame(&mut buf).expect("frame");
    let centre = ((180 * 640 + 320) * 4) as usize;
    let corner = 0usize;
    assert_ne!(
        buf[centre..centre + 3],
        buf[corner..corner + 3],
        "the torus covers the centre"
    );
}

#[test]
fn a_scene_renders_in_every_mode_deterministically() {
    let dir = scratch("render-scene");
    let scene = fixture("scenes/showcase.json");
    let s = scene.to_str().expect("utf8");
    let mut last = Vec::new();
    for mode in ["inferred", "deferred", "forward"] {
        let to = |out: &Path| {
            let o = out.to_str().expect("utf8");
            render_ok(&[s, "--mode", mode, "--size", "160x90", "-q", "-o", o]);
        };
        let out = dir.join(format!("{mode}.png"));
        to(&out);
        assert_eq!(png_size(&out), (160, 90), "{mode}");
        let again = dir.join(format!("{mode}-again.png"));
        to(&again);
        let a = std::fs::read(&out).expect("read");
        assert_eq!(
            a,
            std::fs::read(&again).expect("read"),
            "{mode}: byte-identical"
        );
        assert_ne!(a, last, "{mode} differs from the previous mode");
        last = a;
    }
}

#[test]
fn explain_lists_the_passes_without_opening_a_device() {
    let scene = fixture("scenes/showcase.json");
    let o = pelt(&["render", scene.to_str().expect("utf8"), "--explain"], &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // Opening a device prints the adapter; explaining alone does not open one.
    assert!(!String::from_utf8_lossy(&o.stderr).contains("adapter:"));
    let text = String::from_utf8_lossy(&o.stdout);
    for want in [
        "mode inferred",
        "L-buffer 400×225",
        "geometry",
        "light",
        "material",
        "3 alpha",
    ] {
        assert!(text.contains(want), "{want:?} in {text}");
    }
    let fwd = pelt(
        &[
            "render",
            scene.to_str().expect("utf8"),
            "--explain",
            "--mode",
            "forward",
        ],
        &[],
    );
    let text = String::from_utf8_lossy(&fwd.stdout);
    assert!(
        text.contains("forward") && !text.contains("geometry"),
        "{text}"
    );
    // Distance maps appear only for scenes with mirrors or glass, with their cost drivers.
    assert!(!text.contains("distance-maps"), "{text}");
    let mirrors = fixture("scenes/mirrors.json");
    let m = pelt(
        &[
            "render",
            mirrors.to_str().expect("utf8"),
            "--explain",
            "--cube-size",
            "128",
            "--layers",
            "4",
        ],
        &[],
    );
    let text = String::from_utf8_lossy(&m.stdout);
    for want in [
        "distance-maps",
        "3 maps × 6 faces × 4 layers",
        "128² texels = 72 face renders",
        "min-max",
        "silhouettes on",
        "3 mirror/glass objects by ray tracing their distance maps",
    ] {
        assert!(text.contains(want), "{want:?} in {text}");
    }
    let off = pelt(
        &[
            "render",
            mirrors.to_str().expect("utf8"),
            "--explain",
            "--reflections",
            "off",
        ],
        &[],
    );
    assert!(!String::from_utf8_lossy(&off.stdout).contains("distance-maps"));
}

#[test]
fn mirrors_render_on_the_gpu_and_in_the_ray_tracer_deterministically() {
    let dir = scratch("render-mirrors");
    let scene = fixture("scenes/mirrors.json");
    let s = scene.to_str().expect("utf8");
    let traced = |threads: &str, name: &str| {
        let out = dir.join(name);
        let r = pelt(
            &[
                "render",
                s,
                "--mode",
                "raytrace",
                "--size",
                "160x90",
                "-q",
                "-o",
                out.to_str().expect("utf8"),
            ],
            &[("RAYON_NUM_THREADS", threads)],
        );
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        std::fs::read(&out).expect("png")
    };
    let one = traced("1", "rt1.png");
    assert_eq!(one, traced("2", "rt2.png"), "the same at any thread count");
    assert_eq!(png_size(&dir.join("rt1.png")), (160, 90));
    for technique in ["distance-maps", "envmap", "off"] {
        let out = dir.join(format!("{technique}.png"));
        render_ok(&[
            s,
            "--size",
            "160x90",
            "--cube-size",
            "64",
            "--reflections",
            technique,
            "-q",
            "-o",
            out.to_str().expect("utf8"),
        ]);
        assert_eq!(png_size(&out), (160, 90));
    }
    let maps = std::fs::read(dir.join("distance-maps.png")).expect("png");
    assert_ne!(maps, std::fs::read(dir.join("off.png")).expect("png"));
}

#[test]
fn a_baked_asset_with_normal_groups_renders() {
    let dir = scratch("render-baked");
    let baked = bake(&fixture("creature.glb"), &dir, &[]);
    let out = dir.join("creature.png");
    render_ok(&[
        baked.to_str().expect("utf8"),
        "--size",
        "128x96",
        "-q",
        "-o",
        out.to_str().expect("utf8"),
    ]);
    assert_eq!(png_size(&out), (128, 96));
}

#[test]
fn bad_scenes_and_missing_assets_fail_cleanly_without_output() {
    let dir = scratch("render-errors");
    let out = dir.join("never.png");
    let o = out.to_str().expect("utf8");
    // A scene error: exit 2, file:line:column and the field path.
    let bad = dir.join("bad.json");
    std::fs::write(
        &bad,
        "{\n  \"objects\": [{\"asset\": \"builtin:cube\", \"colr\": [1, 0, 0]}]\n}\n",
    )
    .expect("write");
    let r = render(&[bad.to_str().expect("utf8"), "-o", o]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{err}");
    assert!(
        err.contains("bad.json:2:") && err.contains("objects[0]") && err.contains("colr"),
        "{err}"
    );
    // A missing asset: exit 1, naming the object and the path.
    let missing = dir.join("missing.json");
    std::fs::write(
        &missing,
        r#"{"objects": [{"asset": "builtin:cube"}, {"asset": "nowhere.glb"}]}"#,
    )
    .expect("write");
    let r = render(&[missing.to_str().expect("utf8"), "-o", o]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("objects[1]") && err.contains("nowhere.glb"),
        "{err}"
    );
    // An asset that is not glTF.
    let junk = dir.join("junk.glb");
    std::fs::write(&junk, b"not a gltf file").expect("write");
    let r = render(&[junk.to_str().expect("utf8"), "-o", o]);
    assert_eq!(
        r.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    assert!(String::from_utf8_lossy(&r.stderr).contains("junk.glb"));
    // Flags out of range and unknown back ends are usage errors.
    for args in [
        ["--size", "0x10"],
        ["--lbuffer-scale", "2"],
        ["--backend", "metal"],
        ["--mode", "raytraced"],
        ["--linear-steps", "0"],
        ["--cube-size", "100"],
        ["--layers", "9"],
        ["--max-depth", "0"],
        ["--reflections", "mirrors"],
        ["--min-max", "maybe"],
        ["--silhouettes", "maybe"],
    ] {
        let mut a = vec![
            fixture("torus.glb").to_str().expect("utf8").to_owned(),
            "-o".into(),
            o.to_owned(),
        ];
        a.extend(args.iter().map(|s| s.to_string()));
        let r = pelt(
            &[
                &["render"],
                &a.iter().map(String::as_str).collect::<Vec<_>>()[..],
            ]
            .concat(),
            &[],
        );
        assert_eq!(
            r.status.code(),
            Some(2),
            "{args:?}: {}",
            String::from_utf8_lossy(&r.stderr)
        );
    }
    // Bad reflection values in a scene: exit 2 naming the field.
    for (i, (json, field)) in [
        (r#"{"reflections": {"linearSteps": -1}}"#, "reflections.linearSteps"),
        (r#"{"reflections": {"cubeSize": 100}}"#, "reflections.cubeSize"),
        (
            r#"{"objects": [{"asset": "builtin:sphere", "material": {"kind": "glass", "ior": 0}}]}"#,
            "objects[0].material.ior",
        ),
        (
            r#"{"objects": [{"asset": "builtin:sphere", "material": {"kind": "mirror", "f0": 0.9, "n": 0.2}}]}"#,
            "objects[0].material",
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let path = dir.join(format!("reflect{i}.json"));
        std::fs::write(&path, json).expect("write");
        let r = render(&[path.to_str().expect("utf8"), "-o", o]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{json}: {err}");
        assert!(err.contains(field), "{field} in {err}");
    }
    assert!(!out.exists(), "nothing written");
    assert_eq!(
        std::fs::read_dir(&dir).expect("dir").count(),
        7,
        "only the test's own inputs"
    );
}

#[test]
fn demo_bakes_the_creature_and_renders_fur_and_a_turntable() {
    let dir = scratch("demo");
    let b = backend();
    let out = pelt(
        &[
            "demo",
            "-o",
            dir.to_str().expect("utf8"),
            "--backend",
            &b,
            "--size",
            "320x180",
            "--frames",
            "6",
            "--shells",
            "8",
        ],
        &[],
    );
    assert!(
        out.status.success(),
        "pelt demo: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The Fox: baked with a generated comb, furred and textured mid-walk (demo.png) and over
    // its walk cycle.
    assert_eq!(png_size(&dir.join("demo.png")), (320, 180));
    assert_eq!(png_size(&dir.join("fox-walk.png")), (320, 90));
    // Its fur is orange (the base colour texture's; crates/pelt-preview/tests/fur.rs checks
    // that fur follows the texture, with a negative control).
    let demo = load_png(&dir.join("demo.png"));
    let orange = demo
        .rgba
        .chunks_exact(4)
        .filter(|p| {
            let [r, g, b] = [p[0], p[1], p[2]].map(f32::from);
            r > 70.0 && r > 1.6 * b && g < 0.85 * r
        })
        .count();
    assert!(orange > 1500, "{orange} orange pixels");
    // The creature, and six 80×45 views of it, four to a row.
    assert_eq!(png_size(&dir.join("creature.png")), (320, 180));
    assert_eq!(png_size(&dir.join("turntable.png")), (320, 90));
    // The creature beside a mirror (fixtures/scenes/creature-mirror.json).
    assert_eq!(png_size(&dir.join("mirror.png")), (320, 180));
    // The Fox's scene file draws demo.png again, byte for byte (shadows, wind and springs
    // at the walk's 0.35 s); another time draws otherwise.
    let fox_json = dir.join("fox.json");
    let again = |time: &str, name: &str| {
        let png = dir.join(name);
        render_ok(&[
            fox_json.to_str().expect("utf8"),
            "--animation",
            "Walk",
            "--time",
            time,
            "-o",
            png.to_str().expect("utf8"),
        ]);
        load_png(&png)
    };
    assert!(
        again("0.35", "again.png") == demo,
        "fox.json at 0.35 s is not demo.png"
    );
    assert!(
        again("0.1", "early.png") != demo,
        "0.1 s draws demo.png too"
    );
    let fox = pelt_preview::asset::load(&dir.join("fox.glb")).expect("baked fox loads");
    let fur = fox.fur.expect("the fox has fur");
    assert_eq!(fur.source, pelt_preview::fur::TextureSource::Baked);
    // The baked creature carries the fur the renderer read.
    let glb = dir.join("creature.glb");
    let m = pelt_preview::asset::load(&glb).expect("baked creature loads");
    let fur = m.fur.expect("fur");
    assert_eq!(fur.source, pelt_preview::fur::TextureSource::Baked);
    assert!(!fur.fins.is_empty());
    // A plain render of the baked asset draws it as fur (the default scene notices).
    let png = dir.join("asset.png");
    let o = render_ok(&[
        glb.to_str().expect("utf8"),
        "-o",
        png.to_str().expect("utf8"),
        "--size",
        "160x90",
        "--explain",
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    // Analytic coverage (the default) holds the silhouette in the shells: no fins unless
    // asked. The shells follow the fur's size on screen, at most the manifest's 16: a few
    // at 160×90.
    assert!(
        text.contains("fur: base + 3 shells (by screen size, at most 16), "),
        "{text}"
    );
    assert!(text.contains("obliterate"), "{text}");
}

/// The Fox baked with a generated comb (once per test).
fn baked_fox(dir: &Path) -> std::path::PathBuf {
    bake(&fixture("fox/Fox.glb"), dir, &["--comb", "generate"])
}

#[test]
fn the_bind_pose_renders_like_the_static_mesh() {
    // `pelt pose` without a clip skins the Fox at its nodes' rest transforms, which is its
    // bind pose: rendered, it must match the asset drawn as a static mesh.
    let dir = scratch("bind-pose");
    let fox = baked_fox(&dir);
    let rest = dir.join("rest.glb");
    pelt_ok(&[
        "pose",
        fox.to_str().expect("utf8"),
        "-o",
        rest.to_str().expect("utf8"),
    ]);
    let png = |asset: &Path, name: &str| {
        let out = dir.join(name);
        render_ok(&[
            asset.to_str().expect("utf8"),
            "-o",
            out.to_str().expect("utf8"),
            "--size",
            "160x90",
        ]);
        load_png(&out)
    };
    let (a, c) = (png(&fox, "static.png"), png(&rest, "rest.png"));
    let f = pelt_measure::flip::Flip::new(&a, &c)
        .expect("same size")
        .mean();
    eprintln!("bind pose against static: FLIP {f}");
    assert!(f <= 0.005, "bind pose against static: FLIP {f}");
    let walk = dir.join("walk.png");
    render_ok(&[
        fox.to_str().expect("utf8"),
        "-o",
        walk.to_str().expect("utf8"),
        "--size",
        "160x90",
        "--animation",
        "Walk",
        "--time",
        "0.35",
    ]);
    let f = pelt_measure::flip::Flip::new(&a, &load_png(&walk))
        .expect("size")
        .mean();
    // Negative control: mid-walk fails the same threshold (measured 0.009 at 160×90 on
    // llvmpipe; the Fox covers a small part of the frame).
    assert!(
        f > 0.005,
        "mid-walk should fail the bind-pose threshold: FLIP {f}"
    );
}

#[test]
fn animation_contact_sheet_and_unknown_clip() {
    let dir = scratch("anim-sheet");
    let fox = baked_fox(&dir);
    let sheet = dir.join("sheet.png");
    render_ok(&[
        fox.to_str().expect("utf8"),
        "-o",
        sheet.to_str().expect("utf8"),
        "--size",
        "160x90",
        "--animation",
        "Run",
        "--frames",
        "6",
    ]);
    // Six 80×45 tiles, four to a row.
    assert_eq!(png_size(&sheet), (320, 90));
    let bad = dir.join("bad.png");
    let o = render(&[
        fox.to_str().expect("utf8"),
        "-o",
        bad.to_str().expect("utf8"),
        "--animation",
        "Trot",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains(r#"no animation named "Trot": the file has "Survey", "Walk", "Run""#),
        "{err}"
    );
    assert!(!bad.exists());
}

#[test]
fn fur_renders_the_same_from_either_tangent_generator() {
    // The comb is stored in the frame the bake writes and decoded with the frame the renderer
    // reads, so the gradient frame (the default without a normal map) and MikkTSpace give the
    // same fur, fins included.
    let dir = scratch("tangent-generators");
    let creature = fixture("creature.glb");
    let png = |name: &str, bake_args: &[&str]| {
        let sub = dir.join(name);
        let baked = bake(&creature, &sub, bake_args);
        let out = dir.join(format!("{name}.png"));
        render_ok(&[
            baked.to_str().expect("utf8"),
            "-o",
            out.to_str().expect("utf8"),
            "--size",
            "192x108",
        ]);
        load_png(&out)
    };
    let gradient = png("gradient", &[]);
    let mikk = png("mikktspace", &["--tangent-generator", "mikktspace"]);
    let f = pelt_measure::flip::Flip::new(&gradient, &mikk)
        .expect("same size")
        .mean();
    eprintln!("gradient frame against MikkTSpace: FLIP {f}");
    assert!(f <= 0.001, "gradient frame against MikkTSpace: FLIP {f}");
    // Negative control: the comb's axes swapped (another fur direction) fails the threshold.
    let swapped = png("swapped", &["--comb-axes", "z,x,y"]);
    let f = pelt_measure::flip::Flip::new(&gradient, &swapped)
        .expect("same size")
        .mean();
    eprintln!("gradient frame against a swapped comb: FLIP {f}");
    assert!(
        f > 0.001,
        "a swapped comb should fail the threshold: FLIP {f}"
    );
}
