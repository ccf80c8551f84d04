//! The fuzz budget CI runs: PELT_FUZZ_CASES cases (default 20 000) of PELT_FUZZ_SEED (default
//! fixed, so CI is repeatable) over the fixture corpus. Longer runs: `cargo run --release -p
//! pelt-fuzz -- --seconds 600 --seed $RANDOM`.

#[global_allocator]
static GLOBAL: pelt_alloc::Counting = pelt_alloc::Counting;

use std::path::Path;

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

#[test]
fn mutated_corpus_never_panics_names_the_file_and_stays_within_memory() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let seeds = pelt_fuzz::corpus(&root).expect("read the fixture corpus");
    assert!(seeds.len() >= 70, "only {} seed files", seeds.len());
    let cases = env_u64("PELT_FUZZ_CASES", 20_000);
    let seed = env_u64("PELT_FUZZ_SEED", 0x5EED_F00D);
    let crash_dir = root.join("target/fuzz-crashes");
    let s = pelt_fuzz::run(&seeds, seed, cases, None, &crash_dir, false);
    eprintln!("fuzz: seed {seed}: {s}");
    assert_eq!(s.cases, cases);
    // A harness whose mutations never get past the parsers would test nothing.
    assert!(
        s.baked * 20 >= cases,
        "only {} of {cases} cases baked",
        s.baked
    );
    assert!(
        s.refused * 4 >= cases,
        "only {} of {cases} cases were refused",
        s.refused
    );
    let report: Vec<String> = s
        .findings
        .iter()
        .take(20)
        .map(ToString::to_string)
        .collect();
    assert!(
        s.findings.is_empty(),
        "{} defects (copy each saved input into fixtures/fuzz/ and fix it):\n{}",
        s.findings.len(),
        report.join("\n")
    );
}
