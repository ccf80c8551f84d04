//! `pelt bake` as a build step: folders and globs, one failure never stopping the others,
//! progress and summary, atomic outputs under SIGKILL, byte-identical outputs at any `--jobs`,
//! depfiles and `--incremental`.

mod common;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use common::*;
use serde_json::Value;

fn s(p: &Path) -> &str {
    p.to_str().unwrap_or_default()
}

/// A tree of inputs: two folders with a file of the same name, a nested OBJ, a stray .bin.
fn input_tree(name: &str) -> PathBuf {
    let dir = scratch(name);
    let copy = |from: &str, to: &str| {
        let t = dir.join(to);
        std::fs::create_dir_all(t.parent().expect("parent")).expect("mkdir");
        std::fs::copy(fixture(from), t).expect("copy");
    };
    copy("edge/flat-cube.gltf", "in/a/cube.gltf");
    copy("edge/hard-torus.gltf", "in/b/cube.gltf");
    copy("sphere.glb", "in/sphere.glb");
    copy("edge/painted.obj", "in/deep/er/painted.obj");
    std::fs::write(dir.join("in/a/notes.txt"), "not an asset").expect("write");
    dir
}

#[test]
fn folders_and_globs_bake_recursively_keeping_relative_paths() {
    let dir = input_tree("walk");
    let out = dir.join("out");
    let r = pelt(&["bake", s(&dir.join("in")), "-o", s(&out)], &[]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(r.status.success(), "{err}");
    assert_eq!(
        files_under(&out),
        vec![
            PathBuf::from("a/cube.glb"),
            "b/cube.glb".into(),
            "deep/er/painted.glb".into(),
            "sphere.glb".into()
        ]
    );
    // Plain lines when stderr is not a terminal, then the summary.
    assert!(
        err.contains("[1/4] baked ") && err.contains("[4/4] "),
        "{err}"
    );
    assert!(
        err.contains("pelt: 4 inputs: 4 baked, 0 up to date, 0 failed"),
        "{err}"
    );

    let out2 = dir.join("out2");
    let pattern = format!("{}/in/**/*.gltf", dir.display());
    let r = pelt(&["bake", &pattern, "-o", s(&out2), "-q"], &[]);
    assert!(r.status.success());
    assert!(
        r.stderr.is_empty(),
        "--quiet printed: {}",
        String::from_utf8_lossy(&r.stderr)
    );
    assert_eq!(
        files_under(&out2),
        vec![PathBuf::from("a/cube.glb"), "b/cube.glb".into()]
    );
    let r = pelt(
        &[
            "bake",
            &format!("{}/in/**/*.fbx", dir.display()),
            "-o",
            s(&out2),
        ],
        &[],
    );
    assert_eq!(r.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&r.stderr).contains("names no .gltf"));
}

#[test]
fn a_terminal_gets_a_progress_bar_instead_of_lines() {
    // `script` (util-linux, in every Debian) gives pelt a pseudo-terminal as stderr.
    let dir = scratch("tty");
    let cmd = format!(
        "{} bake fixtures/edge fixtures/bad/nan-position.glb -o {}",
        env!("CARGO_BIN_EXE_pelt"),
        dir.join("out").display()
    );
    let r = std::process::Command::new("script")
        .args(["-qec", &cmd, "/dev/null"])
        .current_dir(root())
        .output()
        .expect("run script(1)");
    let text = String::from_utf8_lossy(&r.stdout);
    assert!(
        !text.contains("[1/15] "),
        "plain lines on a terminal: {text}"
    );
    // The bar is redrawn at a limited rate: some position "k/15" with its filled cells.
    assert!(
        text.contains("/15 ") && text.contains('█'),
        "no bar: {text}"
    );
    // Failures and warnings scroll above the bar, naming their file; the summary follows.
    assert!(
        text.contains("FAILED fixtures/bad/nan-position.glb"),
        "{text}"
    );
    assert!(
        text.contains("warning: fixtures/edge/modes.gltf: meshes[0]"),
        "{text}"
    );
    assert!(
        text.contains("pelt: 15 inputs: 14 baked, 0 up to date, 1 failed"),
        "{text}"
    );
}

#[test]
fn one_failing_file_never_stops_the_others_and_every_file_is_reported() {
    let dir = input_tree("fail");
    for bad in ["glb-truncated-bin.glb", "nan-position.glb"] {
        std::fs::copy(fixture("bad").join(bad), dir.join("in").join(bad)).expect("copy");
    }
    // A stale output of a failing input from an earlier run must not survive.
    let out = dir.join("out");
    std::fs::create_dir_all(&out).expect("mkdir");
    std::fs::write(out.join("nan-position.glb"), b"stale").expect("write");
    let report = dir.join("report.json");
    let r = pelt(
        &[
            "bake",
            s(&dir.join("in")),
            "-o",
            s(&out),
            "--report",
            s(&report),
            "--jobs",
            "2",
        ],
        &[],
    );
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert_eq!(files_under(&out).len(), 4, "{:?}", files_under(&out));
    assert!(!out.join("nan-position.glb").exists(), "stale output kept");
    let tail = err
        .split("pelt: 2 of 6 inputs failed:")
        .nth(1)
        .expect("failure list");
    assert!(tail.contains("glb-truncated-bin.glb: GLB header"), "{tail}");
    assert!(tail.contains("nan-position.glb: meshes[0]"), "{tail}");
    let rep: Value =
        serde_json::from_slice(&std::fs::read(&report).expect("report")).expect("json");
    let inputs = rep["inputs"].as_array().expect("inputs");
    assert_eq!(inputs.len(), 6);
    let failed: Vec<&str> = inputs
        .iter()
        .filter(|i| i["status"] == "failed")
        .filter_map(|i| i["input"].as_str())
        .collect();
    assert_eq!(failed.len(), 2, "{failed:?}");
    assert!(
        inputs
            .iter()
            .filter(|i| i["status"] == "ok")
            .all(|i| i["output_bytes"].as_u64() > Some(0))
    );
    assert_eq!(rep["summary"]["baked"], 4);

    // --quiet: the failures alone.
    let r = pelt(&["bake", s(&dir.join("in")), "-o", s(&out), "-q"], &[]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1));
    assert!(
        !err.contains("baked") && err.contains("2 of 6 inputs failed"),
        "{err}"
    );
}

#[test]
fn outputs_are_byte_identical_across_runs_and_job_counts() {
    let dir = scratch("jobs");
    let mut runs = Vec::new();
    let started = Instant::now();
    for (i, jobs) in ["1", "2", "8", "2"].iter().enumerate() {
        if i == 3 {
            // A later run, over a second after the first: no clock reaches the outputs.
            std::thread::sleep(Duration::from_millis(1100).saturating_sub(started.elapsed()));
        }
        let out = dir.join(format!("run{i}"));
        let r = pelt(
            &[
                "bake",
                "fixtures/edge",
                "fixtures/creature.glb",
                "fixtures/torus.glb",
                "-o",
                s(&out),
                "--jobs",
                jobs,
                "--tangents",
                "regenerate",
                "--config",
                "fixtures/fur.json",
                "-q",
            ],
            &[],
        );
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let files = files_under(&out);
        let bytes: Vec<Vec<u8>> = files
            .iter()
            .map(|f| std::fs::read(out.join(f)).expect("read"))
            .collect();
        runs.push((files, bytes));
    }
    assert_eq!(runs[0].0.len(), 16);
    for (files, bytes) in &runs[1..] {
        assert_eq!(files, &runs[0].0);
        for (k, b) in bytes.iter().enumerate() {
            assert!(
                *b == runs[0].1[k],
                "{} differs between --jobs values or runs",
                files[k].display()
            );
        }
    }
    // No absolute path inside any output.
    for b in &runs[0].1 {
        let text = String::from_utf8_lossy(b);
        assert!(
            !text.contains(s(&root())) && !text.contains(s(&dir)),
            "absolute path in an output"
        );
    }
}

/// A .gltf with an external buffer and an image whose name needs escaping, and its files.
fn external_asset(dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir.join("tex")).expect("mkdir");
    let mut json = with_external_buffer("edge/flat-cube.gltf", dir, "cube.bin");
    std::fs::write(dir.join("tex/fur dots.png"), tiny_png()).expect("write");
    json["images"] = serde_json::json!([{"uri": "tex/fur%20dots.png"}]);
    let path = dir.join("cube.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&json).expect("json")).expect("write");
    path
}

fn tiny_png() -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, 1, 1);
        enc.set_color(png::ColorType::Rgba);
        let mut w = enc.write_header().expect("png header");
        w.write_image_data(&[255, 0, 0, 255]).expect("png data");
    }
    out
}

#[test]
fn the_depfile_lists_every_file_read() {
    let dir = scratch("dep");
    let input = external_asset(&dir.join("in"));
    let out = dir.join("out/cube.glb");
    let dep = dir.join("cube.d");
    let r = pelt(
        &[
            "bake",
            s(&input),
            "-o",
            s(&out),
            "--config",
            "fixtures/fur.json",
            "--depfile",
            s(&dep),
            "-q",
        ],
        &[],
    );
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let text = std::fs::read_to_string(&dep).expect("depfile");
    let d = dir.join("in");
    let expect = format!(
        "{}: \\\n  {} \\\n  {} \\\n  {} \\\n  fixtures/fur.json\n",
        out.display(),
        input.display(),
        d.join("cube.bin").display(),
        d.join("tex/fur\\ dots.png").display(),
    );
    assert_eq!(text, expect);
    // The image was embedded: the output stands alone.
    let doc = pelt_io::Document::load(&out).expect("load output");
    assert!(doc.json["images"][0].get("uri").is_none());
}

/// Modification time of a file.
fn mtime(p: &Path) -> std::time::SystemTime {
    std::fs::metadata(p)
        .and_then(|m| m.modified())
        .expect("mtime")
}

#[test]
fn incremental_skips_only_what_is_up_to_date() {
    let dir = scratch("incr");
    let input = external_asset(&dir.join("in"));
    std::fs::copy(fixture("sphere.glb"), dir.join("in/sphere.glb")).expect("copy");
    let out = dir.join("out");
    let in_dir = dir.join("in");
    let run = |extra: &[&str]| {
        let mut args = vec!["bake", s(&in_dir), "-o", s(&out), "--incremental"];
        args.extend_from_slice(extra);
        let r = pelt(&args, &[]);
        let err = String::from_utf8_lossy(&r.stderr).into_owned();
        assert!(r.status.success(), "{err}");
        err
    };
    // A plain bake records no key (it spends no time hashing), so the first --incremental
    // run bakes everything.
    let plain = pelt(&["bake", s(&in_dir), "-o", s(&out), "-q"], &[]);
    assert!(plain.status.success());
    let doc = pelt_io::Document::load(&out.join("sphere.glb")).expect("load");
    assert!(
        doc.json.get("extras").is_none(),
        "a plain bake wrote a record"
    );
    let first = run(&[]);
    assert!(first.contains("2 baked, 0 up to date"), "{first}");
    let cube = out.join("cube.glb");
    let sphere = out.join("sphere.glb");
    let (t_cube, t_sphere) = (mtime(&cube), mtime(&sphere));
    let again = run(&[]);
    assert!(again.contains("0 baked, 2 up to date"), "{again}");
    assert_eq!(
        (mtime(&cube), mtime(&sphere)),
        (t_cube, t_sphere),
        "an up-to-date output was rewritten"
    );

    // A changed external buffer (one position nudged) rebakes that input alone.
    let bin = dir.join("in/cube.bin");
    let mut b = std::fs::read(&bin).expect("read");
    let v = f32::from_le_bytes([b[0], b[1], b[2], b[3]]) + 0.25;
    b[..4].copy_from_slice(&v.to_le_bytes());
    std::fs::write(&bin, b).expect("write");
    let changed = run(&[]);
    assert!(changed.contains("1 baked, 1 up to date"), "{changed}");
    assert!(
        changed.contains(&format!("up to date: {}", sphere.display())),
        "{changed}"
    );

    // A changed flag or config rebakes everything; the report says which were skipped.
    let flag = run(&["--quantize", "u16"]);
    assert!(flag.contains("2 baked, 0 up to date"), "{flag}");
    let config = run(&["--quantize", "u16", "--config", "fixtures/fur.json"]);
    assert!(config.contains("2 baked, 0 up to date"), "{config}");
    let report = dir.join("r.json");
    run(&[
        "--quantize",
        "u16",
        "--config",
        "fixtures/fur.json",
        "--report",
        s(&report),
    ]);
    let rep: Value =
        serde_json::from_slice(&std::fs::read(&report).expect("report")).expect("json");
    assert!(
        rep["inputs"]
            .as_array()
            .expect("inputs")
            .iter()
            .all(|i| i["status"] == "up to date")
    );
    // The output records the key and its reads relative to the input's folder.
    let doc = pelt_io::Document::load(&cube).expect("load");
    let source = &doc.json["extras"]["pelt"]["source"];
    assert_eq!(
        source["reads"],
        serde_json::json!(["cube.bin", "tex/fur dots.png"])
    );
    assert_eq!(source["key"].as_str().map(str::len), Some(64));
    let _ = input;
}

#[test]
fn a_killed_batch_leaves_no_partial_file_under_any_output_name() {
    let dir = scratch("kill");
    // Inputs big enough that a write takes a few milliseconds: 8 copies of a 100k-triangle
    // creature (about 5 MB out each).
    let shape = pelt_fixtures::shapes::creature(160, 320);
    let doc = pelt_fixtures::build::document(&shape, pelt_fixtures::build::BuildOptions::default());
    let inputs = dir.join("in");
    std::fs::create_dir_all(&inputs).expect("mkdir");
    for i in 0..8 {
        write_input(&doc, &inputs.join(format!("c{i}.glb")));
    }
    // The reference output of one copy (all copies bake to the same bytes).
    let reference = dir.join("reference.glb");
    pelt_ok(&["bake", s(&inputs.join("c0.glb")), "-o", s(&reference), "-q"]);
    let reference = std::fs::read(&reference).expect("reference");

    let out = dir.join("out");
    let mut mid_write_kills = 0;
    // Up to MID_WRITE rounds kill the moment a temporary file shows up (a write under way),
    // until two kills have landed during a write (a kill can land just after the rename, on a
    // loaded machine); the last round kills after two outputs are complete.
    const MID_WRITE: usize = 16;
    let rounds = (0..MID_WRITE).chain([MID_WRITE]);
    for round in rounds {
        if round < MID_WRITE && mid_write_kills >= 2 {
            continue;
        }
        let _ = std::fs::remove_dir_all(&out);
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_pelt"))
            .args(["bake", s(&inputs), "-o", s(&out), "--jobs", "2", "-q"])
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("spawn pelt");
        let deadline = Instant::now() + Duration::from_secs(120);
        while Instant::now() < deadline && child.try_wait().ok().flatten().is_none() {
            let names: Vec<String> = std::fs::read_dir(&out)
                .map(|d| {
                    d.flatten()
                        .map(|e| e.file_name().to_string_lossy().into_owned())
                        .collect()
                })
                .unwrap_or_default();
            let writing = names.iter().any(|n| n.contains(".pelt-tmp-"));
            let done = names.iter().filter(|n| !n.starts_with('.')).count();
            if (round < MID_WRITE && writing) || (round == MID_WRITE && done >= 2) {
                break;
            }
        }
        child.kill().expect("SIGKILL"); // SIGKILL on Unix: no cleanup runs
        let _ = child.wait();
        let mut finished = 0;
        for f in files_under(&out) {
            let name = f.to_string_lossy();
            if name.starts_with('.') {
                assert!(
                    name.contains(".pelt-tmp-"),
                    "round {round}: unexpected {name}"
                );
                mid_write_kills += 1;
                continue;
            }
            let bytes = std::fs::read(out.join(&f)).expect("read");
            assert!(
                bytes == reference,
                "round {round}: {name} is not a complete output"
            );
            finished += 1;
        }
        assert!(
            finished < 8,
            "round {round}: the batch finished before the kill"
        );
    }
    eprintln!("kills that left a temporary file (a write under way): {mid_write_kills}");
    assert!(
        mid_write_kills > 0,
        "no kill landed during a write: the test proved nothing"
    );
    // The next run sweeps what the killed ones left and finishes the job.
    let r = pelt(&["bake", s(&inputs), "-o", s(&out), "-q"], &[]);
    assert!(r.status.success());
    let after = files_under(&out);
    assert_eq!(after.len(), 8, "{after:?}");
    assert!(after.iter().all(|f| !f.to_string_lossy().starts_with('.')));
}
