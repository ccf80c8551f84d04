//! Temporary files left by killed runs. Outputs are written as `.NAME.pelt-tmp-PID` in the
//! output's folder and renamed into place, so a killed run never leaves a partial file under
//! an output name, but it can leave its temporary file. Before writing, a batch removes those
//! whose process is gone (Linux: no `/proc/PID`); files of live processes are left alone.

use std::path::Path;

/// Removes stale temporaries in `dir`; returns how many.
pub fn sweep(dir: &Path) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let mut removed = 0;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(pid) = temp_pid(&name) else {
            continue;
        };
        if !alive(pid) && std::fs::remove_file(e.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// The PID of a temporary file's name (`.a.glb.pelt-tmp-1234` → 1234).
pub fn temp_pid(name: &str) -> Option<u32> {
    if !name.starts_with('.') {
        return None;
    }
    name.rsplit_once(".pelt-tmp-")?.1.parse().ok()
}

fn alive(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    let proc = Path::new("/proc");
    // Without /proc there is no safe way to tell: keep the file.
    !proc.is_dir() || proc.join(pid.to_string()).exists()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_temporaries_of_dead_processes_are_removed() {
        assert_eq!(temp_pid(".a b.glb.pelt-tmp-42"), Some(42));
        assert_eq!(temp_pid("a.glb.pelt-tmp-42"), None);
        assert_eq!(temp_pid(".a.glb"), None);
        let dir = std::env::temp_dir().join(format!("pelt-sweep-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("mkdir");
        // PIDs above the kernel's limit (4194304) are never alive.
        let dead = dir.join(".x.glb.pelt-tmp-999999999");
        let live = dir.join(format!(".y.glb.pelt-tmp-{}", std::process::id()));
        let other = dir.join("x.glb");
        for p in [&dead, &live, &other] {
            std::fs::write(p, b"x").expect("write");
        }
        assert_eq!(sweep(&dir), 1);
        assert!(!dead.exists() && live.exists() && other.exists());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
