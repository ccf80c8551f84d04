//! Polling files for changes (the open input, a scene's assets, the shader folder): by
//! modification time and length, so a re-bake or an editor's save is seen within one poll.
//! Polling needs no platform watcher and costs a few `stat` calls per half second.

use std::path::PathBuf;
use std::time::SystemTime;

/// What a file looked like.
type Stamp = Option<(SystemTime, u64)>;

fn stamp(p: &PathBuf) -> Stamp {
    let m = std::fs::metadata(p).ok()?;
    Some((m.modified().ok()?, m.len()))
}

/// Files and how they looked when last seen.
#[derive(Debug, Default, Clone)]
pub struct Watch {
    files: Vec<(PathBuf, Stamp)>,
}

impl Watch {
    /// Watches `files` as they are now.
    pub fn new(files: impl IntoIterator<Item = PathBuf>) -> Watch {
        Watch {
            files: files
                .into_iter()
                .map(|p| {
                    let s = stamp(&p);
                    (p, s)
                })
                .collect(),
        }
    }

    /// Whether any file changed (appeared, vanished, or has a new time or length) since the
    /// last call; remembers the new state.
    pub fn changed(&mut self) -> bool {
        let mut any = false;
        for (p, s) in &mut self.files {
            let now = stamp(p);
            if now != *s {
                *s = now;
                any = true;
            }
        }
        any
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rewritten_file_is_seen_once() {
        let dir = std::env::temp_dir().join(format!("pelt-watch-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let f = dir.join("a.glb");
        std::fs::write(&f, b"one").expect("write");
        let mut w = Watch::new([f.clone()]);
        assert!(!w.changed());
        std::fs::write(&f, b"three").expect("write");
        assert!(w.changed());
        assert!(!w.changed(), "seen once");
        std::fs::remove_file(&f).expect("remove");
        assert!(w.changed(), "a vanished file is a change");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
