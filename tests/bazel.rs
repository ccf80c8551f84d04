//! pelt's Bazel rules (`bazel/`) on the example workspace (`examples/bazel/`), offline:
//! every action runs in the Linux sandbox, where an action sees only its declared inputs (so a
//! remote executor would have all it needs); outputs are byte-identical to direct `pelt` runs;
//! a bake missing a declared `.bin` fails there; an undeclared-but-unused input (pruned by the
//! depfile) re-runs nothing; and against a loopback Remote Execution API cache (BuildGrid), a
//! clean rebuild is all remote cache hits and changing one `.bin` re-runs only its bake.
//!
//! Without `bazel` (Debian `bazel-bootstrap`) the test is skipped, unless `PELT_REQUIRE_BAZEL`
//! is set; the cache half needs BuildGrid's `bgd` (`PELT_BGD`, else `PATH`), required likewise
//! by `PELT_REQUIRE_BUILDGRID`. CI sets both and installs both.

mod common;

use std::collections::BTreeMap;
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output};
use std::time::{Duration, Instant};

use common::*;

/// The bake actions of the example: three `pelt_bake` and one `pelt_textures`.
const PELT_ACTIONS: usize = 4;

/// A Bazel client on one workspace with its own output root (removed at the end).
struct Bazel {
    workspace: PathBuf,
    user_root: PathBuf,
}

impl Bazel {
    fn new(workspace: PathBuf) -> Bazel {
        // Short: the server's socket path lies under it.
        let user_root = std::env::temp_dir().join(format!("pelt-bazel-{}", std::process::id()));
        Bazel {
            workspace,
            user_root,
        }
    }

    fn run(&self, args: &[&str]) -> Output {
        Command::new("bazel")
            .arg(format!("--output_user_root={}", self.user_root.display()))
            .arg("--max_idle_secs=300")
            .args(args)
            .current_dir(&self.workspace)
            .env("PELT", env!("CARGO_BIN_EXE_pelt"))
            .output()
            .expect("run bazel")
    }

    /// `bazel build //... FLAGS` in the sandbox; the counts of its processes by kind
    /// ("linux-sandbox", "remote cache hit", "internal"). Fails the test if the build fails.
    fn build(&self, target: &str, flags: &[&str]) -> BTreeMap<String, usize> {
        let mut args = vec!["build", target, "--spawn_strategy=linux-sandbox"];
        args.extend_from_slice(flags);
        let out = self.run(&args);
        let log = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "bazel build {flags:?} failed:\n{log}");
        processes(&log)
    }
}

impl Drop for Bazel {
    fn drop(&mut self) {
        let _ = self.run(&["clean", "--expunge"]);
        let _ = self.run(&["shutdown"]);
        let _ = Command::new("chmod")
            .args(["-R", "u+w"])
            .arg(&self.user_root)
            .status();
        let _ = std::fs::remove_dir_all(&self.user_root);
    }
}

/// Counts from Bazel's summary line, "INFO: 8 processes: 4 internal, 4 linux-sandbox."
fn processes(log: &str) -> BTreeMap<String, usize> {
    let line = log
        .lines()
        .rfind(|l| l.starts_with("INFO: ") && l.contains(" process"))
        .unwrap_or_else(|| panic!("no process summary in:\n{log}"));
    let list = line.split_once(": ").and_then(|(_, r)| r.split_once(": "));
    let mut counts = BTreeMap::new();
    for part in list
        .map_or("", |(_, kinds)| kinds)
        .trim_end_matches('.')
        .split(", ")
    {
        if let Some((n, kind)) = part.split_once(' ') {
            counts.insert(kind.to_owned(), n.parse().expect("count"));
        }
    }
    counts
}

fn count(c: &BTreeMap<String, usize>, kind: &str) -> usize {
    c.get(kind).copied().unwrap_or(0)
}

/// Copies `bazel/` and `examples/bazel/` into `dir`, keeping their relative places (the
/// example's WORKSPACE finds the rules at `../../bazel`).
fn copy_example(dir: &Path) -> PathBuf {
    copy_into(&root().join("bazel"), dir);
    copy_into(&root().join("examples/bazel"), &dir.join("examples"))
}

/// Flips the lowest bit of the first NORMAL component in `NAME.gltf`'s `.bin`: new content,
/// still a valid file.
fn change_bin(ws: &Path, name: &str) {
    let gltf: serde_json::Value = serde_json::from_slice(
        &std::fs::read(ws.join(format!("assets/{name}.gltf"))).expect("read .gltf"),
    )
    .expect("JSON");
    let a = gltf["meshes"][0]["primitives"][0]["attributes"]["NORMAL"]
        .as_u64()
        .expect("NORMAL") as usize;
    let acc = &gltf["accessors"][a];
    let view = &gltf["bufferViews"][acc["bufferView"].as_u64().expect("view") as usize];
    let at = view["byteOffset"].as_u64().unwrap_or(0) + acc["byteOffset"].as_u64().unwrap_or(0);
    let bin = ws.join(format!("assets/{name}.bin"));
    let mut bytes = std::fs::read(&bin).expect("read .bin");
    bytes[at as usize] ^= 1;
    std::fs::write(&bin, bytes).expect("write .bin");
}

/// What `pelt` writes run directly in the workspace with the example's flags.
fn direct_outputs(ws: &Path, dir: &Path) {
    let pelt = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_pelt"))
            .args(args)
            .current_dir(ws)
            .output()
            .expect("run pelt");
        assert!(out.status.success(), "{args:?}: {out:?}");
    };
    let d = |f: &str| dir.join(f).display().to_string();
    pelt(&["bake", "-q", "assets/cube.gltf", "-o", &d("cube.glb")]);
    pelt(&[
        "bake",
        "-q",
        "assets/torus.gltf",
        "--quantize",
        "u16",
        "--compress",
        "-o",
        &d("torus.glb"),
    ]);
    pelt(&[
        "bake",
        "-q",
        "assets/textured.obj",
        "--config",
        "fur.json",
        "-o",
        &d("textured.glb"),
    ]);
    pelt(&[
        "textures",
        "-q",
        "--config",
        "fur.json",
        "-o",
        &d("fur_textures"),
    ]);
}

fn assert_same_outputs(ws: &Path, direct: &Path) {
    let bin = ws.join("bazel-bin");
    for f in ["cube.glb", "torus.glb", "textured.glb"] {
        let a = std::fs::read(bin.join(f)).expect("bazel output");
        let b = std::fs::read(direct.join(f)).expect("direct output");
        assert!(a == b, "{f}: Bazel's output differs from pelt's own");
    }
    let listed = files_under(&direct.join("fur_textures"));
    assert_eq!(files_under(&bin.join("fur_textures")), listed);
    assert!(listed.len() > 3, "fur textures: {listed:?}");
    for f in listed {
        let a = std::fs::read(bin.join("fur_textures").join(&f)).expect("bazel texture");
        let b = std::fs::read(direct.join("fur_textures").join(&f)).expect("direct texture");
        assert!(a == b, "fur_textures/{}: differs", f.display());
    }
}

#[test]
fn bazel_rules_build_in_the_sandbox_and_hit_a_remote_cache() {
    if !program_available(
        "bazel",
        "PELT_REQUIRE_BAZEL",
        "apt-get install bazel-bootstrap",
    ) {
        return;
    }
    let dir = scratch("bazel");
    let ws = copy_example(&dir);
    let bazel = Bazel::new(ws.clone());

    // Sandboxed: each action sees its declared inputs only.
    let first = bazel.build("//...", &[]);
    assert_eq!(count(&first, "linux-sandbox"), PELT_ACTIONS, "{first:?}");
    let direct = dir.join("direct");
    direct_outputs(&ws, &direct);
    assert_same_outputs(&ws, &direct);

    // Negative control: the same bake without its .bin declared fails in the sandbox.
    let build = ws.join("BUILD.bazel");
    let text = std::fs::read_to_string(&build).expect("BUILD");
    let undeclared = "\npelt_bake(name = \"undeclared\", src = \"assets/cube.gltf\")\n";
    std::fs::write(&build, text.clone() + undeclared).expect("BUILD");
    let out = bazel.run(&["build", "//:undeclared", "--spawn_strategy=linux-sandbox"]);
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "an undeclared .bin was readable");
    assert!(
        log.contains("cube.bin"),
        "the failure names no .bin:\n{log}"
    );
    std::fs::write(&build, text).expect("BUILD");

    // The bake reads two of the three declared textures: changing the third re-runs nothing,
    // changing one it reads re-runs that bake alone.
    std::fs::write(ws.join("assets/tex/spare.png"), b"not read").expect("write");
    assert_eq!(count(&bazel.build("//...", &[]), "linux-sandbox"), 0);
    let albedo = ws.join("assets/tex/albedo.png");
    let png = std::fs::read(&albedo).expect("read");
    std::fs::write(&albedo, [png.as_slice(), b"trailing"].concat()).expect("write");
    assert_eq!(count(&bazel.build("//...", &[]), "linux-sandbox"), 1);

    remote_cache(&bazel, &ws);
}

/// A BuildGrid cache on a free loopback port, stopped when dropped.
struct Cache(Child);

impl Drop for Cache {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn start_cache(bgd: &Path, dir: &Path) -> (Cache, u16) {
    let port = TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("free port")
        .port();
    let config = dir.join("cache.yml");
    let yaml = std::fs::read_to_string(root().join("examples/bazel/buildgrid-cache.yml"))
        .expect("cache config")
        .replace("127.0.0.1:50051", &format!("127.0.0.1:{port}"));
    std::fs::write(&config, yaml).expect("write config");
    let log = std::fs::File::create(dir.join("bgd.log")).expect("log");
    let child = Command::new(bgd)
        .args(["server", "start"])
        .arg(&config)
        .stdout(log.try_clone().expect("log"))
        .stderr(log)
        .spawn()
        .expect("start bgd");
    let cache = Cache(child);
    let start = Instant::now();
    while TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "BuildGrid did not listen on {port}"
        );
        std::thread::sleep(Duration::from_millis(200));
    }
    (cache, port)
}

fn remote_cache(bazel: &Bazel, ws: &Path) {
    let bgd = std::env::var_os("PELT_BGD").map(PathBuf::from).or_else(|| {
        Command::new("bgd")
            .arg("--help")
            .output()
            .is_ok()
            .then(|| PathBuf::from("bgd"))
    });
    let hint = "python3 -m venv V && V/bin/pip install buildgrid==0.4.4; PELT_BGD=V/bin/bgd";
    if !tool_available(bgd.is_some(), "PELT_REQUIRE_BUILDGRID", "BuildGrid", hint) {
        return;
    }
    let (_cache, port) = start_cache(&bgd.expect("bgd"), ws.parent().expect("dir"));
    let remote = format!("--remote_cache=grpc://127.0.0.1:{port}");
    // Populate the cache, then build again from nothing: every bake is a cache hit.
    bazel.run(&["clean"]);
    let populated = bazel.build("//...", &[&remote]);
    assert_eq!(
        count(&populated, "linux-sandbox"),
        PELT_ACTIONS,
        "{populated:?}"
    );
    bazel.run(&["clean"]);
    let rebuilt = bazel.build("//...", &[&remote]);
    assert_eq!(
        count(&rebuilt, "remote cache hit"),
        PELT_ACTIONS,
        "{rebuilt:?}"
    );
    assert_eq!(count(&rebuilt, "linux-sandbox"), 0, "{rebuilt:?}");
    // One changed .bin: its bake alone runs.
    change_bin(ws, "cube");
    let one = bazel.build("//...", &[&remote]);
    assert_eq!(count(&one, "linux-sandbox"), 1, "{one:?}");
    assert_eq!(count(&one, "remote cache hit"), 0, "{one:?}");
}
