//! A fuzz harness that runs on the stable toolchain (no libFuzzer, no nightly): seeded
//! mutations ([`pelt_fixtures::mutate`]: bit flips, byte stamps, truncations, splices, JSON
//! and OBJ number edits, NaN and huge words in GLB binary chunks) of the fixture corpus go
//! through the whole bake: load, bake, fur embedding, GLB writing, and loading and baking the
//! output again. A case fails when it
//!
//! - panics (caught with `catch_unwind`),
//! - returns an error that does not name the file,
//! - holds more memory at once than [`memory_limit`] allows for its size (the process must
//!   use [`pelt_alloc::Counting`] as its global allocator), or
//! - bakes, but its output does not load and bake again.
//!
//! Cases are a function of (seed, index), so a failure is reproduced from those two numbers;
//! failing inputs are also written out, to become fixtures under `fixtures/fuzz/`.

use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::time::Instant;

use pelt_bake::BakeOptions;
use pelt_bake::fur::{FurAssets, combed, embed};
use pelt_bake::options::{Quantize, TangentGenerator, TangentMode};
use pelt_io::IoError;

/// The seed files: every fixture under `root/fixtures` small enough to bake quickly in a
/// debug build (the edge cases, the bad corpus, fuzz finds, sphere and torus), sorted.
pub fn corpus(root: &Path) -> std::io::Result<Vec<(PathBuf, Vec<u8>)>> {
    let mut files = Vec::new();
    for dir in [
        "fixtures/edge",
        "fixtures/bad",
        "fixtures/fuzz",
        "fixtures/compressed",
    ] {
        let Ok(entries) = std::fs::read_dir(root.join(dir)) else {
            continue;
        };
        for e in entries {
            let p = e?.path();
            let ext = p
                .extension()
                .map(|e| e.to_string_lossy().to_ascii_lowercase());
            if matches!(ext.as_deref(), Some("gltf" | "glb" | "obj")) {
                files.push(p);
            }
        }
    }
    files.push(root.join("fixtures/sphere.glb"));
    files.push(root.join("fixtures/torus.glb"));
    files.sort();
    files
        .into_iter()
        .map(|p| std::fs::read(&p).map(|b| (p, b)))
        .collect()
}

/// The most bytes a case may hold at once: 16 times its size plus what every case needs
/// (tables, thread stacks' bookkeeping, the fur textures it embeds) plus 4 MiB.
pub fn memory_limit(input_bytes: usize, fixed: usize) -> usize {
    16 * input_bytes + fixed + (4 << 20)
}

/// How a case ended.
#[derive(Debug)]
pub enum Verdict {
    /// Baked, and the output loads and bakes again.
    Baked,
    /// A clean error naming the file.
    Refused(IoError),
    /// A defect: what went wrong.
    Defect(String),
}

/// Why a case stopped before its output baked again.
#[derive(Debug, thiserror::Error)]
enum CaseError {
    /// The input was refused: loading, baking, embedding fur or writing it failed.
    #[error(transparent)]
    Refused(#[from] IoError),
    /// The output was written but does not load: a defect.
    #[error("DEFECT: the output does not load: {0}")]
    OutputLoad(#[source] IoError),
    /// The output loads but does not bake again: a defect.
    #[error("DEFECT: the output does not bake again: {0}")]
    OutputBake(#[source] IoError),
}

/// Runs one input through the whole bake. `path` names it in errors and anchors the relative
/// URIs of a `.gltf`; `fur` is embedded when given.
pub fn exercise(
    path: &Path,
    bytes: Vec<u8>,
    quantize: Quantize,
    fur: Option<&FurAssets>,
) -> Verdict {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let result = std::panic::catch_unwind(AssertUnwindSafe(|| -> Result<(), CaseError> {
        let mut doc = pelt_io::load_bytes(path, bytes)?;
        let opts = BakeOptions {
            quantize,
            ..BakeOptions::default()
        };
        let report = pelt_bake::bake_document(&mut doc, &opts)?;
        if let Some(fur) = fur {
            embed(&mut doc, fur, &combed(&report))?;
        }
        let out = pelt_io::glb::to_vec(&doc)?;
        // The output must stand on its own: load and bake it again.
        let again = Path::new("output.glb");
        let mut back = pelt_io::Document::from_bytes(again, out).map_err(CaseError::OutputLoad)?;
        // The second bake regenerates MikkTSpace tangents, so every input exercises both
        // generators (the first used the default: gradient unless a normal map asks).
        let again_opts = BakeOptions {
            tangents: TangentMode::Regenerate,
            tangent_generator: TangentGenerator::Mikktspace,
            ..opts
        };
        pelt_bake::bake_document(&mut back, &again_opts).map_err(CaseError::OutputBake)?;
        Ok(())
    }));
    match result {
        Ok(Ok(())) => Verdict::Baked,
        Ok(Err(CaseError::Refused(e))) if e.to_string().contains(&name) => Verdict::Refused(e),
        Ok(Err(CaseError::Refused(e))) => {
            Verdict::Defect(format!("the error does not name {name}: {e}"))
        }
        Ok(Err(defect)) => Verdict::Defect(defect.to_string()),
        Err(panic) => {
            let msg = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
                .unwrap_or_else(|| "(no message)".to_owned());
            Verdict::Defect(format!("panic: {msg}"))
        }
    }
}

/// Small fur textures (64² texels) for the cases that embed fur.
pub fn small_fur() -> Option<FurAssets> {
    let mut config = pelt_fur::manifest::FurConfig::default();
    config.textures.size = 64;
    config.textures.strands = 200;
    FurAssets::new(config).ok()
}

/// One defect.
#[derive(Debug)]
pub struct Finding {
    /// Case index.
    pub case: u64,
    /// The seed file it was made from.
    pub from: PathBuf,
    /// What went wrong.
    pub what: String,
    /// Where its bytes were written, if they could be.
    pub saved: Option<PathBuf>,
}

/// Totals of a run.
#[derive(Debug, Default)]
pub struct Summary {
    /// Cases run.
    pub cases: u64,
    /// Cases that baked.
    pub baked: u64,
    /// Cases refused with a named error.
    pub refused: u64,
    /// The largest ratio of peak memory (less the fur allowance) to input size, over inputs of
    /// at least 64 KiB (below that the fixed allowance dominates).
    pub worst_ratio: f64,
    /// The slowest case, in milliseconds.
    pub slowest_ms: f64,
    /// Defects.
    pub findings: Vec<Finding>,
    /// Wall time.
    pub seconds: f64,
}

impl std::fmt::Display for Finding {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "case {} (from {}): {}",
            self.case,
            self.from.display(),
            self.what
        )?;
        if let Some(p) = &self.saved {
            write!(f, " [saved as {}]", p.display())?;
        }
        Ok(())
    }
}

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} cases in {:.1} s ({:.0}/s): {} baked, {} refused, {} defects; worst memory \
             {:.1}× the input; slowest case {:.0} ms",
            self.cases,
            self.seconds,
            self.cases as f64 / self.seconds.max(1e-9),
            self.baked,
            self.refused,
            self.findings.len(),
            self.worst_ratio,
            self.slowest_ms
        )
    }
}

/// Runs cases `0..cases` of `seed` (stopping early after `budget` seconds, if given), writing
/// failing inputs into `crash_dir`. `trace` prints each case before it runs (to find one that
/// aborts the process).
pub fn run(
    seeds: &[(PathBuf, Vec<u8>)],
    seed: u64,
    cases: u64,
    budget: Option<f64>,
    crash_dir: &Path,
    trace: bool,
) -> Summary {
    // Valid seeds weigh 8 times a bad one: most bad files fail at once, and mutations of
    // valid files reach deeper code.
    let named: Vec<(String, Vec<u8>)> = seeds
        .iter()
        .flat_map(|(p, b)| {
            let bad = p.components().any(|c| c.as_os_str() == "bad");
            let copies = if bad { 1 } else { 8 };
            std::iter::repeat_n((p.to_string_lossy().into_owned(), b.clone()), copies)
        })
        .collect();
    let fur = small_fur();
    let fur_bytes: usize = fur
        .as_ref()
        .map_or(0, |f| f.pngs.iter().map(Vec::len).sum());
    let previous_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let start = Instant::now();
    let mut s = Summary::default();
    for case in 0..cases {
        if budget.is_some_and(|b| start.elapsed().as_secs_f64() > b) {
            break;
        }
        let (from, kind, bytes) = pelt_fixtures::mutate::case(&named, seed, case);
        let from = PathBuf::from(from);
        if trace {
            eprintln!("case {case}: {kind:?} of {}", from.display());
        }
        let quantize = [Quantize::Float, Quantize::U16, Quantize::U8][(case % 3) as usize];
        let with_fur = fur.as_ref().filter(|_| case % 4 == 0);
        let size = bytes.len();
        let kept = bytes.clone();
        let base = pelt_alloc::reset_peak();
        let t = Instant::now();
        let verdict = exercise(&from, bytes, quantize, with_fur);
        let took = t.elapsed().as_secs_f64() * 1e3;
        let peak = pelt_alloc::peak().saturating_sub(base);
        s.slowest_ms = s.slowest_ms.max(took);
        s.cases += 1;
        let fixed = if with_fur.is_some() { 2 * fur_bytes } else { 0 };
        if size >= 64 << 10 {
            s.worst_ratio = s
                .worst_ratio
                .max(peak.saturating_sub(fixed) as f64 / size as f64);
        }
        let mut what = match verdict {
            Verdict::Baked => {
                s.baked += 1;
                None
            }
            Verdict::Refused(_) => {
                s.refused += 1;
                None
            }
            Verdict::Defect(d) => Some(d),
        };
        if what.is_none() && peak > memory_limit(size, fixed) {
            what = Some(format!(
                "held {peak} bytes at once for a {size}-byte input (limit {})",
                memory_limit(size, fixed)
            ));
        }
        if let Some(what) = what {
            let ext = from
                .extension()
                .map_or("bin".into(), |e| e.to_string_lossy());
            let saved = crash_dir.join(format!("case-{seed}-{case}.{ext}"));
            let saved = std::fs::create_dir_all(crash_dir)
                .and_then(|()| std::fs::write(&saved, &kept))
                .ok()
                .map(|()| saved);
            s.findings.push(Finding {
                case,
                from,
                what,
                saved,
            });
        }
    }
    std::panic::set_hook(previous_hook);
    s.seconds = start.elapsed().as_secs_f64();
    s
}
