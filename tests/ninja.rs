//! `pelt bake --depfile` under a real build tool: ninja over a folder of inputs whose buffers
//! live in external `.bin` files. Touching one input's `.bin` rebuilds exactly that output; a
//! run with nothing changed does nothing.
//!
//! Without `ninja` (Debian `ninja-build`) the test is skipped with a message, unless
//! `PELT_REQUIRE_NINJA` is set (CI sets it and installs ninja).

mod common;

use std::path::Path;
use std::process::Command;
use std::time::{Duration, SystemTime};

use common::*;

/// The three inputs: fixture glTFs with their embedded buffer moved out to `NAME.bin`.
const INPUTS: [(&str, &str); 3] = [
    ("cube", "edge/flat-cube.gltf"),
    ("torus", "edge/hard-torus.gltf"),
    ("grid", "edge/sparse-color.gltf"),
];

/// Writes `dir/NAME.gltf` with its buffer in `dir/NAME.bin`.
fn external(dir: &Path, name: &str, fixture_rel: &str) {
    let json = with_external_buffer(fixture_rel, dir, &format!("{name}.bin"));
    std::fs::write(
        dir.join(format!("{name}.gltf")),
        serde_json::to_vec_pretty(&json).expect("JSON"),
    )
    .expect("write .gltf");
}

/// `ninja -C dir`: its standard output (the test fails on a non-zero exit).
fn ninja(dir: &Path) -> String {
    let out = Command::new("ninja")
        .arg("-C")
        .arg(dir)
        .output()
        .expect("run ninja");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "ninja failed:\n{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

/// The outputs ninja says it built, from its `[k/n] bake OUTPUT` lines.
fn built(log: &str) -> Vec<String> {
    log.lines()
        .filter_map(|l| l.split_once("] bake ").map(|(_, o)| o.trim().to_owned()))
        .collect()
}

fn mtime(p: &Path) -> SystemTime {
    std::fs::metadata(p)
        .and_then(|m| m.modified())
        .expect("mtime")
}

#[test]
fn ninja_rebuilds_exactly_the_output_whose_bin_changed() {
    if !program_available("ninja", "PELT_REQUIRE_NINJA", "apt-get install ninja-build") {
        return;
    }
    let dir = scratch("ninja");
    std::fs::create_dir_all(dir.join("in")).expect("mkdir");
    let mut rules = format!(
        "rule bake\n  command = {} bake -q $in -o $out --depfile $out.d\n  depfile = $out.d\n  \
         deps = gcc\n  description = bake $out\n",
        env!("CARGO_BIN_EXE_pelt")
    );
    for (name, rel) in INPUTS {
        external(&dir.join("in"), name, rel);
        rules += &format!("build out/{name}.glb: bake in/{name}.gltf\n");
    }
    std::fs::write(dir.join("build.ninja"), rules).expect("write build.ninja");

    // First run: everything.
    let mut first = built(&ninja(&dir));
    first.sort();
    assert_eq!(first, ["out/cube.glb", "out/grid.glb", "out/torus.glb"]);
    for (name, _) in INPUTS {
        let out = dir.join(format!("out/{name}.glb"));
        assert!(
            pelt_io::Document::load(&out).is_ok(),
            "{} unreadable",
            out.display()
        );
    }
    // Nothing changed: nothing to do.
    let again = ninja(&dir);
    assert!(
        again.contains("no work to do"),
        "second run did work:\n{again}"
    );

    // Touch one input's .bin (the .gltf is untouched): only its output is rebuilt, which
    // ninja can only know from the depfile.
    let before: Vec<SystemTime> = INPUTS
        .iter()
        .map(|(n, _)| mtime(&dir.join(format!("out/{n}.glb"))))
        .collect();
    let bin = std::fs::File::options()
        .write(true)
        .open(dir.join("in/torus.bin"))
        .expect("open .bin");
    // Strictly newer than the outputs (ninja compares nanosecond mtimes), not in the future.
    std::thread::sleep(Duration::from_millis(20));
    bin.set_modified(SystemTime::now()).expect("touch");
    drop(bin);
    assert_eq!(built(&ninja(&dir)), ["out/torus.glb"]);
    for ((name, _), old) in INPUTS.iter().zip(before) {
        let now = mtime(&dir.join(format!("out/{name}.glb")));
        assert_eq!(
            now != old,
            *name == "torus",
            "{name}: rebuilt = {}",
            now != old
        );
    }
    let last = ninja(&dir);
    assert!(
        last.contains("no work to do"),
        "run after the rebuild did work:\n{last}"
    );
}
