//! The content key an output records, for `--incremental`.
//!
//! The key is BLAKE3 over pelt's version, the flags and config that shape the output (the
//! caller's salt), and the name, length and bytes of every file the input's bake read: the
//! asset, its external buffers and images. An `--incremental` bake writes the key into the
//! output's root `extras.pelt.source` with the files read (relative to the input's folder, so
//! no absolute path enters the output); a plain bake writes no record and spends no time
//! hashing. That is enough to recompute the key without parsing the input: an unchanged
//! input is skipped after hashing its files, a changed one (or a changed flag, config or pelt
//! version) is baked again.

use std::io::Read as _;
use std::path::{Path, PathBuf};

use serde_json::{Value, json};

/// Format version of the record; part of every key.
pub const RECORD_VERSION: u32 = 1;

/// What an output records about how it was made.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Record {
    /// Hex BLAKE3 key.
    pub key: String,
    /// Files read besides the input, relative to the input's folder, `/`-separated.
    pub reads: Vec<String>,
}

/// The files read besides `input` (from [`pelt_io::Document::files_read`]), relative to the
/// input's folder. Files outside it (never produced by the loader) are left out.
pub fn relative_reads(input: &Path, files_read: &[PathBuf]) -> Vec<String> {
    let dir = input.parent().unwrap_or(Path::new(""));
    files_read
        .iter()
        .filter(|p| p.as_path() != input)
        .filter_map(|p| p.strip_prefix(dir).ok())
        .map(|p| {
            p.components()
                .map(|c| c.as_os_str().to_string_lossy())
                .collect::<Vec<_>>()
                .join("/")
        })
        .collect()
}

/// The files a record names, as paths beside `input`.
pub fn read_paths(input: &Path, reads: &[String]) -> Vec<PathBuf> {
    let dir = input.parent().unwrap_or(Path::new(""));
    reads.iter().map(|r| dir.join(r)).collect()
}

/// Computes the key of `input` plus `reads` under `salt`.
pub fn compute(input: &Path, reads: &[String], salt: &[u8]) -> std::io::Result<String> {
    let mut h = blake3::Hasher::new();
    h.update(b"pelt bake key\0");
    h.update(&RECORD_VERSION.to_le_bytes());
    h.update(&(salt.len() as u64).to_le_bytes());
    h.update(salt);
    let files = std::iter::once((String::new(), input.to_owned()))
        .chain(reads.iter().cloned().zip(read_paths(input, reads)));
    for (name, path) in files {
        let file = std::fs::File::open(&path)?;
        let len = file.metadata()?.len();
        h.update(&(name.len() as u64).to_le_bytes());
        h.update(name.as_bytes());
        h.update(&len.to_le_bytes());
        // Hash exactly the length recorded: a file growing meanwhile cannot shift the framing.
        let mut taken = file.take(len);
        let read = std::io::copy(&mut taken, &mut h)?;
        if read != len {
            return Err(std::io::Error::other(format!(
                "{} changed while it was hashed",
                path.display()
            )));
        }
    }
    Ok(h.finalize().to_hex().to_string())
}

/// Writes `record` into the document's root `extras.pelt.source`. Returns false (and writes
/// nothing) when the root `extras` or `extras.pelt` exists but is not an object.
pub fn set_record(doc: &mut pelt_io::Document, record: &Record) -> bool {
    let extras = doc
        .json
        .entry("extras")
        .or_insert_with(|| Value::Object(Default::default()));
    let Some(extras) = extras.as_object_mut() else {
        return false;
    };
    let pelt = extras
        .entry("pelt")
        .or_insert_with(|| Value::Object(Default::default()));
    let Some(pelt) = pelt.as_object_mut() else {
        return false;
    };
    pelt.insert(
        "source".into(),
        json!({"key": record.key, "reads": record.reads}),
    );
    true
}

/// The record of an existing `.glb`, read from its JSON chunk alone (the BIN chunk is not
/// read); None when the file is missing, not a GLB, or has no record.
pub fn read_record(output: &Path) -> Option<Record> {
    let mut file = std::fs::File::open(output).ok()?;
    let size = file.metadata().ok()?.len();
    let mut head = [0u8; 20];
    file.read_exact(&mut head).ok()?;
    let word = |o: usize| u32::from_le_bytes([head[o], head[o + 1], head[o + 2], head[o + 3]]);
    if &head[..4] != b"glTF" || u64::from(word(8)) != size || word(16) != 0x4E4F_534A {
        return None;
    }
    let json_len = u64::from(word(12));
    if 20 + json_len > size {
        return None;
    }
    let mut json = vec![0u8; json_len as usize];
    file.read_exact(&mut json).ok()?;
    let root: Value = serde_json::from_slice(&json).ok()?;
    let source = root.get("extras")?.get("pelt")?.get("source")?;
    Some(Record {
        key: source.get("key")?.as_str()?.to_owned(),
        reads: source
            .get("reads")?
            .as_array()?
            .iter()
            .map(|r| r.as_str().map(str::to_owned))
            .collect::<Option<_>>()?,
    })
}
