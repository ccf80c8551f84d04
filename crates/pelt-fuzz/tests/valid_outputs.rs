//! Never an invalid output, under mutation: seeded mutations of the valid fixtures (JSON
//! numbers, bit flips, splices, truncations) go through the bake; every one that bakes is
//! written (so CI's written-output check sees it too) and handed to the Khronos validator,
//! which must find no error; every other one is written compressed, and each reads back.
//! Skipped without the validator unless PELT_REQUIRE_VALIDATOR is set.

use std::path::Path;
use std::process::Command;

/// How many mutants are tried; about one in eight bakes.
const CASES: u64 = 600;

#[test]
fn every_mutant_that_bakes_is_a_valid_gltf() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let seeds: Vec<(String, Vec<u8>)> = pelt_fuzz::corpus(&root)
        .expect("corpus")
        .into_iter()
        // Valid seeds only; not yet the compressed ones, whose animations reach sampler
        // formats the whole-document check does not cover yet.
        .filter(|(p, _)| {
            !p.components()
                .any(|c| c.as_os_str() == "bad" || c.as_os_str() == "compressed")
        })
        .map(|(p, b)| (p.to_string_lossy().into_owned(), b))
        .collect();
    let dir = root.join("target/fuzz-valid");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("mkdir");
    let mut written = Vec::new();
    for case in 0..CASES {
        let (from, _, bytes) = pelt_fixtures::mutate::case(&seeds, 0x7A11D, case);
        let Ok(mut doc) = pelt_io::load_bytes(Path::new(from), bytes) else {
            continue;
        };
        // Every other case is written compressed (`--compress meshopt`).
        let opts = pelt_bake::BakeOptions {
            compress: if case % 2 == 1 {
                pelt_bake::options::Compression::Meshopt
            } else {
                pelt_bake::options::Compression::None
            },
            ..pelt_bake::BakeOptions::default()
        };
        let Ok(mut report) = pelt_bake::bake_document(&mut doc, &opts) else {
            continue;
        };
        pelt_bake::pack_output(&mut doc, &opts, &mut report).expect("pack a baked document");
        let out = dir.join(format!("case-{case}.glb"));
        pelt_io::glb::write_glb(&doc, &out).expect("write");
        read_back(&out);
        written.push(out);
    }
    assert!(written.len() >= 40, "only {} mutants baked", written.len());
    let packed = written
        .iter()
        .filter(|p| {
            std::fs::read(p).is_ok_and(|b| b.windows(23).any(|w| w == b"EXT_meshopt_compression"))
        })
        .count();
    assert!(packed >= 15, "only {packed} compressed outputs");
    let validator = root.join("tools/validator/node_modules/gltf-validator");
    if !validator.exists() {
        assert!(
            std::env::var_os("PELT_REQUIRE_VALIDATOR").is_none(),
            "PELT_REQUIRE_VALIDATOR is set but the validator is missing"
        );
        eprintln!("skipped: npm ci --prefix tools/validator");
        return;
    }
    let o = Command::new("node")
        .arg(root.join("tools/validator/validate.mjs"))
        .arg("--errors-only")
        .args(&written)
        .output()
        .expect("run node");
    let text = String::from_utf8_lossy(&o.stdout);
    eprintln!(
        "{} mutants baked; {}",
        written.len(),
        text.lines().last().unwrap_or("")
    );
    assert!(o.status.success(), "{text}");
}

/// What pelt's readers do with an output: every primitive's triangles and fins read back.
fn read_back(path: &Path) {
    let doc = pelt_io::load(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    for r in doc.primitives() {
        if doc.mode(r).is_ok_and(|m| m == 4) {
            pelt_io::mesh::read_primitive(&doc, r)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        }
        doc.read_fins(r)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
}
