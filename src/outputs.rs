//! Output paths checked before the work starts: a missing folder is created (as `pelt bake`
//! creates its output folders), and a path that cannot be written (a folder where a file
//! goes, a file where a folder goes, no permission) fails at once, naming the path, instead
//! of after minutes of rendering.

use std::fs::OpenOptions;
use std::path::Path;

use anyhow::{Context as _, bail};

/// Makes sure `file` can be written: its folder exists (created if missing) and takes a new
/// file. "-" (standard output) always can. Nothing is left in the folder by the check.
pub fn file(file: &Path) -> anyhow::Result<()> {
    if file.as_os_str() == "-" {
        return Ok(());
    }
    if file.is_dir() {
        bail!("{}: is a folder, not a file to write", file.display());
    }
    let folder = match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    self::folder(folder).with_context(|| format!("{}: cannot be written", file.display()))
}

/// Makes sure `dir` is a folder that takes new files, creating it (and its parents) if
/// missing.
pub fn folder(dir: &Path) -> anyhow::Result<()> {
    if dir.exists() && !dir.is_dir() {
        bail!("{} is a file, not a folder", dir.display());
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create the folder {}", dir.display()))?;
    let probe = dir.join(format!(".pelt-write-check-{}", std::process::id()));
    OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .with_context(|| format!("cannot write into the folder {}", dir.display()))?;
    std::fs::remove_file(&probe).with_context(|| format!("cannot remove {}", probe.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_folders_are_created_and_impossible_paths_refused() {
        let dir = std::env::temp_dir().join(format!("pelt-outputs-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let nested = dir.join("a/b/out.png");
        file(&nested).unwrap();
        assert!(dir.join("a/b").is_dir());
        assert_eq!(std::fs::read_dir(dir.join("a/b")).unwrap().count(), 0);
        // A file where a folder must go, and a folder where the file goes: refused, named.
        std::fs::write(dir.join("f"), b"x").unwrap();
        let e = format!("{:#}", file(&dir.join("f/out.png")).unwrap_err());
        assert!(e.contains("f/out.png") && e.contains("is a file"), "{e}");
        let e = format!("{:#}", file(&dir.join("a")).unwrap_err());
        assert!(e.contains("is a folder"), "{e}");
        file(Path::new("-")).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
