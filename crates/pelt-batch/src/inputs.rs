//! Which files a command line names, and where each one's output goes.
//!
//! An argument is a file (taken as given, whatever its extension, so a typo fails loudly), a
//! folder (searched recursively for `.gltf`, `.glb` and `.obj`, skipping hidden entries and the
//! output folder), or a glob pattern (`scans/**/*.gltf`, for shells that do not expand `**`).
//! Discovery is sorted, so the plan is the same on every run and machine.
//!
//! One file in and an output ending in `.glb` writes that file. Otherwise the output is a
//! folder: a file named directly lands as `OUT/stem.glb`; a file found under a folder or a
//! pattern's fixed prefix keeps its relative path (`OUT/sub/dir/stem.glb`), so equal names in
//! different folders do not collide. Two inputs mapped to one output, or an output that would
//! overwrite an input, are usage errors found before anything is read.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Extensions searched for in folders and kept from glob matches (case-insensitive).
pub const EXTENSIONS: [&str; 3] = ["gltf", "glb", "obj"];

/// One input and its output.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Job {
    /// The file to bake.
    pub input: PathBuf,
    /// The `.glb` to write.
    pub output: PathBuf,
}

/// A command line that cannot be laid out (a usage error: nothing is read or written).
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// A malformed glob pattern.
    #[error("pattern {pattern:?} is not a valid glob: {message}")]
    BadPattern {
        /// The pattern.
        pattern: String,
        /// Why.
        message: String,
    },
    /// A pattern or folder that names no input.
    #[error("{0} names no .gltf, .glb or .obj file")]
    Nothing(String),
    /// A folder that cannot be listed.
    #[error("cannot list {}: {source}", path.display())]
    List {
        /// The folder.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// One input, a file output that is not `.glb`.
    #[error("output {} must end in .glb (pelt writes self-contained binary glTF)", .0.display())]
    NotGlb(PathBuf),
    /// Several inputs, a file output.
    #[error("output {} must be a folder when baking several inputs", .0.display())]
    NotFolder(PathBuf),
    /// Two inputs, one output.
    #[error("{} and {} would both be written to {}", first.display(), second.display(), output.display())]
    Collision {
        /// The first input.
        first: PathBuf,
        /// The second input.
        second: PathBuf,
        /// Their output.
        output: PathBuf,
    },
    /// An output that is one of the inputs.
    #[error("{} would be overwritten by its own output", .0.display())]
    Overwrite(PathBuf),
}

/// Lays out the jobs of `args` with output `output` (a `.glb` for one file, else a folder).
pub fn plan(args: &[PathBuf], output: &Path) -> Result<Vec<Job>, PlanError> {
    let skip_dir = output.canonicalize().ok().filter(|p| p.is_dir());
    // (input, output path relative to the output folder, named directly)
    let mut found: Vec<(PathBuf, PathBuf, bool)> = Vec::new();
    for arg in args {
        let text = arg.to_string_lossy();
        if arg.is_dir() {
            let mut files = Vec::new();
            walk(arg, skip_dir.as_deref(), &mut files)?;
            if files.is_empty() {
                return Err(PlanError::Nothing(format!("folder {}", arg.display())));
            }
            for f in files {
                let rel = f.strip_prefix(arg).unwrap_or(&f).to_owned();
                found.push((f, rel, false));
            }
        } else if is_pattern(&text) && !arg.exists() {
            let base = literal_prefix(&text);
            let matches = glob::glob(&text).map_err(|e| PlanError::BadPattern {
                pattern: text.clone().into_owned(),
                message: e.to_string(),
            })?;
            let before = found.len();
            for m in matches.flatten() {
                if m.is_file() && has_extension(&m) && !hidden_under(&m, &base) {
                    if skip_dir
                        .as_ref()
                        .is_some_and(|d| m.canonicalize().is_ok_and(|c| c.starts_with(d)))
                    {
                        continue;
                    }
                    let rel = m.strip_prefix(&base).unwrap_or(&m).to_owned();
                    found.push((m, rel, false));
                }
            }
            if found.len() == before {
                return Err(PlanError::Nothing(format!("pattern {text:?}")));
            }
        } else {
            let name = arg.file_name().map(PathBuf::from).unwrap_or_default();
            found.push((arg.clone(), name, true));
        }
    }
    // The same file named twice (by a folder and a pattern, say) is baked once.
    let mut seen_inputs = std::collections::BTreeSet::new();
    found.retain(|(input, _, _)| seen_inputs.insert(input.clone()));

    let folder_like = output.is_dir() || output.as_os_str().to_string_lossy().ends_with('/');
    let jobs: Vec<Job> = if found.len() == 1 && found[0].2 && !folder_like {
        if !has_named_extension(output, "glb") {
            return Err(PlanError::NotGlb(output.to_owned()));
        }
        vec![Job {
            input: found[0].0.clone(),
            output: output.to_owned(),
        }]
    } else {
        if output.exists() && !output.is_dir() {
            return Err(PlanError::NotFolder(output.to_owned()));
        }
        found
            .into_iter()
            .map(|(input, rel, _)| Job {
                output: output.join(rel.with_extension("glb")),
                input,
            })
            .collect()
    };
    let mut by_output: BTreeMap<&Path, &Path> = BTreeMap::new();
    for j in &jobs {
        if let Some(first) = by_output.insert(&j.output, &j.input) {
            return Err(PlanError::Collision {
                first: first.to_owned(),
                second: j.input.clone(),
                output: j.output.clone(),
            });
        }
    }
    let inputs: std::collections::BTreeSet<PathBuf> = jobs
        .iter()
        .filter_map(|j| j.input.canonicalize().ok())
        .collect();
    for j in &jobs {
        if j.output.canonicalize().is_ok_and(|o| inputs.contains(&o)) {
            return Err(PlanError::Overwrite(j.output.clone()));
        }
    }
    Ok(jobs)
}

/// Supported inputs under `dir`, sorted, skipping hidden entries, symlinked folders and
/// `skip` (the output folder, when it lies below `dir`).
fn walk(dir: &Path, skip: Option<&Path>, out: &mut Vec<PathBuf>) -> Result<(), PlanError> {
    let list_err = |source| PlanError::List {
        path: dir.to_owned(),
        source,
    };
    let mut entries: Vec<std::fs::DirEntry> = std::fs::read_dir(dir)
        .map_err(list_err)?
        .collect::<Result<_, _>>()
        .map_err(list_err)?;
    entries.sort_by_key(std::fs::DirEntry::file_name);
    for e in entries {
        if e.file_name().to_string_lossy().starts_with('.') {
            continue;
        }
        let path = e.path();
        let kind = e.file_type().map_err(list_err)?;
        if kind.is_dir() {
            if !skip.is_some_and(|s| path.canonicalize().is_ok_and(|c| c == s)) {
                walk(&path, skip, out)?;
            }
        } else if has_extension(&path) && path.is_file() {
            out.push(path);
        }
    }
    Ok(())
}

fn is_pattern(s: &str) -> bool {
    s.contains(['*', '?', '['])
}

/// The pattern's leading components without wildcards (`scans/2024` of `scans/2024/**/*.glb`).
fn literal_prefix(pattern: &str) -> PathBuf {
    let mut base = PathBuf::new();
    for c in Path::new(pattern).components() {
        if is_pattern(&c.as_os_str().to_string_lossy()) {
            break;
        }
        base.push(c);
    }
    base
}

/// Whether a glob match passes through a hidden entry below the pattern's prefix.
fn hidden_under(path: &Path, base: &Path) -> bool {
    path.strip_prefix(base)
        .unwrap_or(path)
        .components()
        .any(|c| c.as_os_str().to_string_lossy().starts_with('.'))
}

fn has_extension(p: &Path) -> bool {
    EXTENSIONS.iter().any(|e| has_named_extension(p, e))
}

fn has_named_extension(p: &Path, ext: &str) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tree(name: &str, files: &[&str]) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("pelt-batch-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        for f in files {
            let p = dir.join(f);
            std::fs::create_dir_all(p.parent().expect("parent")).expect("mkdir");
            std::fs::write(&p, b"x").expect("write");
        }
        dir
    }

    #[test]
    fn folders_are_searched_recursively_in_order_keeping_relative_paths() {
        let d = tree(
            "walk",
            &[
                "b.glb",
                "a/x.gltf",
                "a/x.bin",
                "c/.hidden.glb",
                ".git/y.glb",
                "a/z.OBJ",
                "n.txt",
            ],
        );
        let out = d.join("out");
        let jobs = plan(std::slice::from_ref(&d), &out).expect("plan");
        let got: Vec<_> = jobs
            .iter()
            .map(|j| j.output.strip_prefix(&out).expect("under out").to_owned())
            .collect();
        assert_eq!(
            got,
            vec![PathBuf::from("a/x.glb"), "a/z.glb".into(), "b.glb".into()]
        );
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn globs_keep_paths_below_their_fixed_prefix() {
        let d = tree("glob", &["s/one/a.gltf", "s/two/a.gltf", "s/two/b.bin"]);
        let pattern = d.join("s/**/*.gltf");
        let out = d.join("out");
        let jobs = plan(&[pattern], &out).expect("plan");
        assert_eq!(jobs.len(), 2);
        assert_eq!(jobs[0].output, out.join("one/a.glb"));
        assert_eq!(jobs[1].output, out.join("two/a.glb"));
        let e = plan(&[d.join("s/**/*.none")], &out).expect_err("no match");
        assert!(e.to_string().contains("names no .gltf"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn collisions_and_self_overwrites_are_usage_errors() {
        let d = tree("collide", &["one/a.gltf", "two/a.gltf", "in/c.glb"]);
        let out = d.join("out");
        let e = plan(&[d.join("one/a.gltf"), d.join("two/a.gltf")], &out).expect_err("collision");
        assert!(e.to_string().contains("would both be written to"), "{e}");
        let e = plan(&[d.join("in")], &d.join("in")).expect_err("overwrite");
        assert!(
            e.to_string().contains("overwritten by its own output"),
            "{e}"
        );
        let e = plan(&[d.join("in/c.glb")], &d.join("c.gltf")).expect_err("not glb");
        assert!(e.to_string().contains("must end in .glb"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn the_output_folder_is_not_searched() {
        let d = tree("skipout", &["a.glb", "out/a.glb"]);
        let jobs = plan(std::slice::from_ref(&d), &d.join("out")).expect("plan");
        assert_eq!(jobs.len(), 1);
        assert_eq!(jobs[0].input, d.join("a.glb"));
        let _ = std::fs::remove_dir_all(&d);
    }
}
