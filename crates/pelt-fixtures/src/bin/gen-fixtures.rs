//! Writes pelt's fixtures: `gen-fixtures OUT_DIR [--big] [--creature RINGSxSEGMENTS]...`.
//!
//! OUT_DIR gets sphere.glb, torus.glb, creature.glb, edge/*.gltf and the bad-input corpus
//! bad/* with its expected.json (the files committed under `fixtures/`). `--big` adds the
//! ~1.3 M-triangle benchmark meshes (not committed): creature-1m3.glb with tangents, one
//! bufferView per attribute as Blender's exporter writes (about 58 MB), and
//! creature-1m3-notan.glb without tangents, interleaved. `--creature 50x100` adds the same pair
//! at another size (creature-TRIANGLES.glb and creature-TRIANGLES-notan.glb), for the
//! scaling benchmark.

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = || {
        eprintln!("usage: gen-fixtures OUT_DIR [--big] [--creature RINGSxSEGMENTS]...");
        ExitCode::from(2)
    };
    let (mut out, mut big, mut sizes) = (None, false, Vec::new());
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--big" => big = true,
            "--creature" => {
                let parsed = it.next().and_then(|v| {
                    let (r, s) = v.split_once('x')?;
                    let (r, s) = (r.parse::<u32>().ok()?, s.parse::<u32>().ok()?);
                    (3..=4096).contains(&r).then_some(())?;
                    (3..=4096).contains(&s).then_some((r, s))
                });
                match parsed {
                    Some(rs) => sizes.push(rs),
                    None => return usage(),
                }
            }
            _ if a.starts_with("--") || out.is_some() => return usage(),
            _ => out = Some(PathBuf::from(a)),
        }
    }
    let Some(out) = out else { return usage() };
    match run(&out, big, &sizes) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("gen-fixtures: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(out: &std::path::Path, big: bool, sizes: &[(u32, u32)]) -> Result<(), pelt_io::IoError> {
    pelt_fixtures::write_all(out)?;
    let bad = out.join("bad");
    pelt_fixtures::bad::write(&bad).map_err(|source| pelt_io::IoError::Fs {
        path: bad,
        action: "write",
        source,
    })?;
    if big {
        pelt_fixtures::write_big(out)?;
    }
    for &(rings, segments) in sizes {
        pelt_fixtures::write_creature(out, rings, segments)?;
    }
    Ok(())
}
