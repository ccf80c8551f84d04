//! The bad-input corpus (`fixtures/bad/`, made by `pelt_fixtures::bad`) and the fuzz finds
//! (`fixtures/fuzz/`): every bad file fails with an error naming the file and the place its
//! `expected.json` gives, a non-zero exit, no output and no panic, holding at most a small
//! multiple of its real size in memory (measured by the counting allocator this test binary
//! runs on).

mod common;

#[global_allocator]
static GLOBAL: pelt_alloc::Counting = pelt_alloc::Counting;

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use common::*;
use serde_json::Value;

/// Memory is measured process-wide: tests of this binary take turns.
static SERIAL: Mutex<()> = Mutex::new(());

/// The corpus files of `dir` (inputs only) with their expectations.
fn corpus(dir: &str) -> Vec<(PathBuf, Value)> {
    let dir = fixture(dir);
    let expected: serde_json::Map<String, Value> =
        serde_json::from_slice(&std::fs::read(dir.join("expected.json")).expect("expected.json"))
            .expect("expected.json parses");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("corpus folder")
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.extension()
                .is_some_and(|e| e == "gltf" || e == "glb" || e == "obj")
        })
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let name = p
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned();
            let e = expected
                .get(&name)
                .unwrap_or_else(|| panic!("{name} has no entry in expected.json"))
                .clone();
            (p, e)
        })
        .collect()
}

#[test]
fn generator_reproduces_the_committed_corpus() {
    let _turn = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let dir = scratch("bad-gen");
    let n = pelt_fixtures::bad::write(&dir).expect("generate");
    assert!(n >= 60, "only {n} bad files");
    let names = |d: &Path| {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .expect("dir")
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    let made = names(&dir);
    assert_eq!(made, names(&fixture("bad")), "run `just fixtures`");
    for name in made {
        assert!(
            std::fs::read(dir.join(&name)).ok() == std::fs::read(fixture("bad").join(&name)).ok(),
            "fixtures/bad/{name} differs from the generator's output: run `just fixtures`"
        );
    }
}

/// Runs the file through the fuzz harness's whole bake in this process; returns how it ended
/// and the peak bytes held.
fn bake_in_process(path: &Path) -> (pelt_fuzz::Verdict, usize) {
    let bytes = std::fs::read(path).expect("read");
    let base = pelt_alloc::reset_peak();
    let verdict = pelt_fuzz::exercise(path, bytes, pelt_bake::options::Quantize::Float, None);
    (verdict, pelt_alloc::peak().saturating_sub(base))
}

#[test]
fn every_bad_file_fails_naming_file_and_place_within_bounded_memory() {
    let _turn = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut checked = 0;
    let mut wrong = Vec::new();
    let mut worst = (0usize, String::new());
    for dir in ["bad", "fuzz"] {
        for (path, expect) in corpus(dir) {
            let name = path
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned();
            // The real size: the file plus the external buffer some cases name.
            let real = std::fs::metadata(&path).map_or(0, |m| m.len() as usize) + 208;
            let (verdict, peak) = bake_in_process(&path);
            let err = match verdict {
                pelt_fuzz::Verdict::Baked => None,
                pelt_fuzz::Verdict::Refused(e) => Some(e.to_string()),
                pelt_fuzz::Verdict::Defect(d) => {
                    wrong.push(format!("{name}: {d}"));
                    Some(d)
                }
            };
            // A refused file: 4 × the input plus 256 KiB for what every load sets up, so a
            // 4 GiB claim, a 2^40 count or a huge index cannot get past. A file that bakes:
            // the fuzz harness's bound for a whole bake.
            let limit = if err.is_some() {
                4 * real + (256 << 10)
            } else {
                pelt_fuzz::memory_limit(real, 0)
            };
            if peak > limit {
                wrong.push(format!("{name}: held {peak} bytes at once (limit {limit})"));
            }
            if peak > worst.0 {
                worst = (peak, name.clone());
            }
            if expect.get("bakes").and_then(Value::as_bool) == Some(true) {
                if let Some(e) = err {
                    wrong.push(format!("{name} should bake: {e}"));
                }
            } else {
                let place = expect["place"].as_str().unwrap_or_default();
                let message = expect["message"].as_str().unwrap_or_default();
                match err {
                    None => wrong.push(format!("{name} was accepted")),
                    Some(e) if !(e.contains(&name) && e.contains(place) && e.contains(message)) => {
                        wrong.push(format!(
                            "{name}: expected {place:?} and {message:?} in: {e}"
                        ));
                    }
                    Some(_) => {}
                }
            }
            checked += 1;
        }
    }
    eprintln!(
        "{checked} files; the largest peak: {} bytes ({})",
        worst.0, worst.1
    );
    assert!(
        wrong.is_empty(),
        "{} files:\n{}",
        wrong.len(),
        wrong.join("\n")
    );
    assert!(checked >= 63, "only {checked} files checked");
}

#[test]
fn the_cli_refuses_every_bad_file_with_no_output() {
    let _turn = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let files = corpus("bad");
    // One batch over the folder: every file fails, nothing is written, the report has all.
    let out = scratch("bad-batch");
    let report = out.join("report.json");
    let baked = out.join("baked");
    let r = pelt(
        &[
            "bake",
            "fixtures/bad",
            "-o",
            baked.to_str().unwrap_or_default(),
            "--report",
            report.to_str().unwrap_or_default(),
        ],
        &[],
    );
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        stderr.contains(&format!("{n} of {n} inputs failed", n = files.len())),
        "{stderr}"
    );
    let written = files_under(&baked);
    assert!(
        written.is_empty(),
        "files written for bad inputs: {written:?}"
    );
    let rep: Value =
        serde_json::from_slice(&std::fs::read(&report).expect("report")).expect("json");
    let inputs = rep["inputs"].as_array().expect("inputs");
    assert_eq!(inputs.len(), files.len());
    assert!(
        inputs
            .iter()
            .all(|i| i["status"] == "failed" && i["error"].is_string())
    );
    assert_eq!(rep["summary"]["failed"], files.len());

    // And one file at a time: exit 1, the file and the place on stderr, no output.
    let chunks: Vec<&[(PathBuf, Value)]> = files.chunks(files.len().div_ceil(2)).collect();
    std::thread::scope(|s| {
        for chunk in chunks {
            let out = &out;
            s.spawn(move || {
                for (path, expect) in chunk {
                    let name = path.file_name().unwrap_or_default().to_string_lossy();
                    let target = out.join(format!("{name}.glb"));
                    let r = pelt(
                        &[
                            "bake",
                            path.to_str().unwrap_or_default(),
                            "-o",
                            target.to_str().unwrap_or_default(),
                        ],
                        &[],
                    );
                    let err = String::from_utf8_lossy(&r.stderr);
                    assert_eq!(r.status.code(), Some(1), "{name}: {err}");
                    assert!(
                        err.contains(&*name)
                            && err.contains(expect["place"].as_str().unwrap_or("?")),
                        "{name}: {err}"
                    );
                    assert!(!err.contains("panicked"), "{name}: {err}");
                    assert!(!target.exists(), "{name}: output written");
                }
            });
        }
    });
}
