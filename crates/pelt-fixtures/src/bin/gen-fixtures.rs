//! Writes pelt's fixtures: `gen-fixtures OUT_DIR [--big]`.
//!
//! OUT_DIR gets sphere.glb, torus.glb, creature.glb and edge/*.gltf (the files committed under
//! `fixtures/`); `--big` adds creature-1m3.glb, the ~1.3 M-triangle benchmark mesh with
//! tangents (about 58 MB, not committed).

use std::path::PathBuf;
use std::process::ExitCode;

use pelt_fixtures::build::{BuildOptions, ColorEncoding, document};
use pelt_fixtures::{edge, shapes};
use pelt_io::glb::{write_glb, write_gltf_embedded};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let big = args.iter().any(|a| a == "--big");
    let Some(out) = args.iter().find(|a| !a.starts_with("--")).map(PathBuf::from) else {
        eprintln!("usage: gen-fixtures OUT_DIR [--big]");
        return ExitCode::from(2);
    };
    match run(&out, big) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("gen-fixtures: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(out: &std::path::Path, big: bool) -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all(out.join("edge"))?;
    let u8x4 = BuildOptions { colors: ColorEncoding::U8x4, ..BuildOptions::default() };
    for (name, shape, opts) in [
        ("sphere", shapes::sphere(24, 48), BuildOptions::default()),
        ("torus", shapes::torus(24, 48), BuildOptions { tangents: true, ..BuildOptions::default() }),
        ("creature", shapes::creature(64, 128), u8x4),
    ] {
        write_glb(&document(&shape, opts), &out.join(format!("{name}.glb")))?;
    }
    for (name, doc) in edge::all() {
        write_gltf_embedded(&doc, &out.join("edge").join(format!("{name}.gltf")))?;
    }
    if big {
        let shape = shapes::creature(570, 1140);
        let opts = BuildOptions { tangents: true, ..BuildOptions::default() };
        write_glb(&document(&shape, opts), &out.join("creature-1m3.glb"))?;
    }
    Ok(())
}
