//! Helpers for pelt's CLI tests: run the binary, scratch folders, read baked outputs back.

#![allow(
    dead_code,
    reason = "each test binary uses a different subset of these helpers"
)]

pub mod extension_schema;
pub mod runtime;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{DVec3, Vec3, Vec4};
use pelt_io::{Document, accessor};

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A fixture path.
pub fn fixture(rel: &str) -> PathBuf {
    root().join("fixtures").join(rel)
}

/// A fresh, empty scratch folder under the target directory.
pub fn scratch(name: &str) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir = root().join("target").join("test-scratch").join(format!(
        "{name}-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch folder");
    dir
}

/// Copies `src` (a file or a folder, recursively) into folder `parent` (created), under its
/// own name; returns the copy's path.
pub fn copy_into(src: &Path, parent: &Path) -> PathBuf {
    std::fs::create_dir_all(parent).expect("create folder");
    let status = Command::new("cp")
        .arg("-r")
        .arg(src)
        .arg(parent)
        .status()
        .expect("run cp");
    assert!(
        status.success(),
        "cp -r {} {}",
        src.display(),
        parent.display()
    );
    parent.join(src.file_name().expect("a named source"))
}

/// Every file under `dir`, relative to it, sorted (none when it does not exist).
pub fn files_under(dir: &Path) -> Vec<PathBuf> {
    fn go(base: &Path, dir: &Path, out: &mut Vec<PathBuf>) {
        if let Ok(entries) = std::fs::read_dir(dir) {
            for e in entries.flatten() {
                let p = e.path();
                if p.is_dir() {
                    go(base, &p, out);
                } else {
                    out.push(p.strip_prefix(base).unwrap_or(&p).to_owned());
                }
            }
        }
    }
    let mut v = Vec::new();
    go(dir, dir, &mut v);
    v.sort();
    v
}

/// Runs `pelt ARGS` with optional environment.
pub fn pelt(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_pelt"));
    c.args(args).current_dir(root());
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run pelt")
}

/// Runs pelt and asserts success.
pub fn pelt_ok(args: &[&str]) -> Output {
    let out = pelt(args, &[]);
    assert!(
        out.status.success(),
        "pelt {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Bakes `input` to `dir/name.glb` with extra args; returns the output path.
pub fn bake(input: &Path, dir: &Path, extra: &[&str]) -> PathBuf {
    let out = dir.join(format!(
        "{}.glb",
        input.file_stem().unwrap_or_default().to_string_lossy()
    ));
    let mut args = vec![
        "bake",
        "-q",
        input.to_str().unwrap_or_default(),
        "-o",
        out.to_str().unwrap_or_default(),
    ];
    args.extend_from_slice(extra);
    pelt_ok(&args);
    out
}

/// One baked primitive read back.
pub struct Baked {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub tangents: Vec<Vec4>,
    pub colors: Vec<Vec4>,
    pub comb: Vec<[f32; 4]>,
    pub comb_normalized: bool,
    pub indices: Vec<u32>,
}

/// Reads primitive (mesh, prim) of a baked file.
pub fn read_baked(path: &Path, mesh: usize, prim: usize) -> Baked {
    let doc = Document::load(path).expect("load output");
    let r = pelt_io::PrimitiveRef {
        mesh,
        primitive: prim,
    };
    let m = pelt_io::mesh::read_primitive(&doc, r).expect("read primitive");
    let ci = doc
        .attribute(r, "_FUR_COMB")
        .expect("attr")
        .expect("_FUR_COMB present");
    let e = accessor::read(&doc, ci, "_FUR_COMB").expect("read comb");
    Baked {
        positions: m.mesh.positions.clone(),
        normals: m.mesh.normals.clone().expect("NORMAL present"),
        tangents: m.mesh.tangents.clone().expect("TANGENT present"),
        // Empty for a primitive without COLOR_0 (a generated comb).
        colors: m.mesh.colors.clone().unwrap_or_default(),
        comb: e.to_f32::<4>(),
        comb_normalized: e.normalized,
        indices: m.mesh.indices,
    }
}

impl Baked {
    /// Object-space comb direction of vertex `v`, decoded as docs/bake.md documents.
    pub fn object_comb(&self, v: usize) -> DVec3 {
        let mut c = self.comb[v];
        if self.comb_normalized {
            c = pelt_bake::comb::decode_unorm(c);
        }
        let (frame, _) = pelt_bake::frame::Frame::new(self.normals[v], self.tangents[v]);
        frame.to_object(DVec3::new(
            f64::from(c[0]),
            f64::from(c[1]),
            f64::from(c[2]),
        ))
    }

    /// The input comb of vertex `v` after Gram-Schmidt against the normal (the expected result).
    pub fn expected_comb(&self, v: usize) -> Option<DVec3> {
        let c = self.colors[v];
        let d = DVec3::new(f64::from(c.x), f64::from(c.y), f64::from(c.z)) * 2.0 - DVec3::ONE;
        let n = self.normals[v].as_dvec3().normalize();
        let g = d - n * n.dot(d);
        (d.length() > pelt_bake::comb::GRAY_EPSILON && g.length() > 1e-3 * d.length())
            .then(|| g.normalize())
    }
}

/// Angle between two directions, radians.
pub fn angle(a: DVec3, b: DVec3) -> f64 {
    a.normalize().dot(b.normalize()).clamp(-1.0, 1.0).acos()
}

/// A fixture `.gltf`'s JSON with its embedded buffer moved out: writes the buffer to
/// `dir/bin_name`, points `buffers[0].uri` at it and returns the JSON (for the caller to
/// adjust and write).
pub fn with_external_buffer(fixture_rel: &str, dir: &Path, bin_name: &str) -> serde_json::Value {
    use base64::Engine as _;
    let mut json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(fixture(fixture_rel)).expect("read fixture"))
            .expect("fixture JSON");
    let uri = json["buffers"][0]["uri"]
        .as_str()
        .expect("data URI")
        .to_owned();
    let payload = uri.split_once(',').expect("data URI payload").1;
    let bin = base64::engine::general_purpose::STANDARD
        .decode(payload)
        .expect("base64");
    std::fs::write(dir.join(bin_name), bin).expect("write .bin");
    json["buffers"][0]["uri"] = bin_name.into();
    json
}

/// Whether a tool a test needs is here. When it is not, the test is skipped with `hint` (how
/// to install it), unless `require_env` is set (CI sets it), which turns the absence into a
/// failure.
pub fn tool_available(found: bool, require_env: &str, what: &str, hint: &str) -> bool {
    if !found {
        assert!(
            std::env::var_os(require_env).is_none(),
            "{require_env} is set but {what} is missing ({hint})"
        );
        eprintln!("skipped: {what} not found ({hint})");
    }
    found
}

/// Whether `program` runs here (`program --version`); [`tool_available`] decides whether
/// its absence skips or fails.
pub fn program_available(program: &str, require_env: &str, hint: &str) -> bool {
    let found = Command::new(program).arg("--version").output().is_ok();
    tool_available(found, require_env, program, hint)
}

/// An RGBA PNG written by pelt, read back.
pub fn load_png(path: &Path) -> pelt_preview::Image {
    let bytes = std::fs::read(path).expect("png written");
    let mut r = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .expect("valid png");
    let mut rgba = vec![0; r.output_buffer_size().expect("size")];
    let info = r.next_frame(&mut rgba).expect("frame");
    assert_eq!(info.color_type, png::ColorType::Rgba);
    pelt_preview::Image {
        width: info.width,
        height: info.height,
        rgba,
    }
}

/// Runs the Khronos glTF-Validator on `files` and fails on any error or warning (skipped where
/// the validator is not installed, unless PELT_REQUIRE_VALIDATOR is set, as CI does).
pub fn validate_clean(files: &[&Path]) {
    let script = root().join("tools/validator/validate.mjs");
    let installed = root()
        .join("tools/validator/node_modules/gltf-validator")
        .exists();
    if !tool_available(
        installed,
        "PELT_REQUIRE_VALIDATOR",
        "the glTF validator",
        "npm ci --prefix tools/validator",
    ) {
        return;
    }
    let o = Command::new("node")
        .arg(script)
        .args(files)
        .output()
        .expect("run node");
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{text}");
    assert_eq!(
        text.matches(": 0 errors, 0 warnings").count(),
        files.len(),
        "{text}"
    );
}

/// Writes a test *input* (not a pelt output): the bytes pelt-io lays out, without the
/// `PELT_WRITTEN_LOG` entry an output gets, since some inputs are broken on purpose.
pub fn write_input(doc: &Document, path: &Path) {
    let bytes = pelt_io::glb::to_vec(doc).expect("lay out the input");
    std::fs::write(path, bytes).expect("write the input");
}

/// Runs `pelt bake ARGS --report -` (which must succeed) and returns the report's first input.
pub fn bake_report(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["bake"];
    all.extend_from_slice(args);
    all.extend(["--report", "-"]);
    let o = pelt_ok(&all);
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("report");
    report["inputs"][0].clone()
}

/// Mean FLIP between two images of one size.
pub fn flip_of(a: &pelt_preview::Image, b: &pelt_preview::Image) -> f32 {
    pelt_measure::flip::Flip::new(a, b)
        .expect("same size")
        .mean()
}

/// Pixels where `forward` draws lit fur (mean 8-bit channel over 40) and `test` draws them
/// near black (under 35 % of forward's).
pub fn near_black_where_lit(forward: &pelt_preview::Image, test: &pelt_preview::Image) -> usize {
    let mean = |p: &[u8]| (u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2])) as f32 / 3.0;
    forward
        .rgba
        .chunks_exact(4)
        .zip(test.rgba.chunks_exact(4))
        .filter(|(f, t)| mean(f) > 40.0 && mean(t) < 0.35 * mean(f))
        .count()
}

/// Writes `scene` to `dir/name.json`, renders it with `args` (`--mode M`…) to
/// `dir/name<-each argument>.png` and returns the image.
pub fn render_in(
    dir: &Path,
    name: &str,
    scene: &serde_json::Value,
    args: &[&str],
) -> pelt_preview::Image {
    let scene_path = dir.join(format!("{name}.json"));
    std::fs::write(&scene_path, scene.to_string()).expect("scene");
    let tag: String = args.iter().map(|a| format!("-{a}")).collect();
    let png = dir.join(format!("{name}{tag}.png"));
    let mut all = vec![
        "render",
        "-q",
        scene_path.to_str().unwrap_or_default(),
        "-o",
        png.to_str().unwrap_or_default(),
    ];
    all.extend_from_slice(args);
    pelt_ok(&all);
    load_png(&png)
}

/// Renders `scene` forward to `dir/name.png` (not quiet): (image, stderr).
pub fn render_warned(
    dir: &Path,
    name: &str,
    scene: &serde_json::Value,
) -> (pelt_preview::Image, String) {
    let s = dir.join(format!("{name}.json"));
    std::fs::write(&s, scene.to_string()).expect("scene");
    let png = dir.join(format!("{name}.png"));
    let o = pelt(
        &[
            "render",
            s.to_str().unwrap_or_default(),
            "-o",
            png.to_str().unwrap_or_default(),
            "--mode",
            "forward",
        ],
        &[],
    );
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{name}: {err}");
    (load_png(&png), err)
}
