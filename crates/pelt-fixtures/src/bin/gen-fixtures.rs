//! Writes pelt's fixtures: `gen-fixtures OUT_DIR [--big]`.
//!
//! OUT_DIR gets sphere.glb, torus.glb, creature.glb, edge/*.gltf and the bad-input corpus
//! bad/* with its expected.json (the files committed under `fixtures/`); `--big` adds creature-1m3.glb, the ~1.3 M-triangle benchmark mesh with
//! tangents (about 58 MB, not committed).

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let big = args.iter().any(|a| a == "--big");
    let Some(out) = args
        .iter()
        .find(|a| !a.starts_with("--"))
        .map(PathBuf::from)
    else {
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

fn run(out: &std::path::Path, big: bool) -> Result<(), pelt_io::IoError> {
    pelt_fixtures::write_all(out)?;
    let bad = out.join("bad");
    pelt_fixtures::bad::write(&bad).map_err(|source| pelt_io::IoError::Fs {
        path: bad,
        action: "write",
        source,
    })?;
    if big {
        pelt_fixtures::write_big(&out.join("creature-1m3.glb"))?;
    }
    Ok(())
}
