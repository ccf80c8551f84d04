//! Make-syntax dependency files (`--depfile`): one rule per output listing every file it was
//! made from (the input, its external buffers and images, the bake config), as Make, Ninja
//! (`deps = gcc`) and Bazel's or Buck2's depfile support read them. Paths are written as the
//! command line gave them (relative stays relative) with spaces, `#` and `$` escaped.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One rule per job: its output depends on every file its bake read, then `also` (the
/// config, read by every job).
pub fn rules(
    jobs: &[crate::Job],
    outcomes: &[crate::Outcome],
    also: &[PathBuf],
) -> Vec<(PathBuf, Vec<PathBuf>)> {
    jobs.iter()
        .zip(outcomes)
        .map(|(j, o)| {
            let mut deps = o.reads.clone();
            deps.extend(also.iter().cloned());
            (j.output.clone(), deps)
        })
        .collect()
}

/// `target: dep dep …` rules, one per output, deps deduplicated in first-read order.
pub fn render(rules: &[(PathBuf, Vec<PathBuf>)]) -> String {
    let mut out = String::new();
    for (target, deps) in rules {
        out.push_str(&escape(target));
        out.push(':');
        let mut seen = std::collections::HashSet::new();
        for d in deps.iter().filter(|d| seen.insert(*d)) {
            let _ = write!(out, " \\\n  {}", escape(d));
        }
        out.push('\n');
    }
    out
}

/// A path as a Make word: backslash before spaces and `#`, `$$` for `$`.
pub fn escape(p: &Path) -> String {
    let s = p.to_string_lossy();
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            ' ' | '#' => {
                out.push('\\');
                out.push(c);
            }
            '$' => out.push_str("$$"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_list_each_dep_once_with_make_escapes() {
        let text = render(&[(
            PathBuf::from("out/a b.glb"),
            vec![
                PathBuf::from("in/a b.gltf"),
                PathBuf::from("in/a$1.bin"),
                PathBuf::from("in/a b.gltf"),
                PathBuf::from("in/#x.png"),
            ],
        )]);
        assert_eq!(
            text,
            "out/a\\ b.glb: \\\n  in/a\\ b.gltf \\\n  in/a$$1.bin \\\n  in/\\#x.png\n"
        );
    }
}
