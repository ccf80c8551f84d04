//! The `.glb` writer (glTF 2.0 §4.4): one JSON chunk and one BIN chunk holding every buffer,
//! the views added by edits and every URI image, so the output stands alone. Views keep their
//! order and are 4-byte aligned. The output goes to a temporary file in the target folder and
//! is renamed into place, so a killed run never leaves a partial file under the output name.
//! No timestamps or paths are written: the same document gives the same bytes.

use std::io::Write;
use std::path::{Path, PathBuf};

use serde_json::{Map, Value, json};

use crate::document::Document;
use crate::error::{IoError, Result};

/// What was written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WriteStats {
    /// Bytes of the whole file.
    pub file_bytes: u64,
    /// Bytes of the BIN chunk.
    pub bin_bytes: u64,
}

/// A run of BIN bytes, borrowed from the document.
struct Piece<'a>(&'a [u8]);

impl Piece<'_> {
    fn bytes(&self) -> &[u8] {
        self.0
    }
}

/// The GLB layout: final JSON text, BIN pieces at their offsets, BIN length.
type Layout<'a> = (Vec<u8>, Vec<(u64, Piece<'a>)>, u64);

/// The BIN chunk as it is laid out: each piece at its offset, 4-byte aligned, in order.
#[derive(Default)]
struct Bin<'a> {
    pieces: Vec<(u64, Piece<'a>)>,
    len: u64,
}

impl<'a> Bin<'a> {
    /// Places `bytes` after what is placed, at a multiple of 4; returns its offset.
    fn place(&mut self, bytes: &'a [u8]) -> u64 {
        let off = self.len.next_multiple_of(4);
        self.len = off + bytes.len() as u64;
        self.pieces.push((off, Piece(bytes)));
        off
    }
}

/// Lays the document out as GLB: the final JSON and the BIN pieces in order (with padding).
fn layout(doc: &Document) -> Result<Layout<'_>> {
    let mut json = doc.json.clone();
    let mut bin = Bin::default();
    let mut views: Vec<Value> = json
        .get("bufferViews")
        .and_then(Value::as_array)
        .cloned()
        .unwrap_or_default();
    let fallback = place_views(doc, &mut views, &mut bin)?;
    let mut images: Vec<Value> = json
        .get("images")
        .and_then(Value::as_array)
        .cloned()
        .unwrap_or_default();
    embed_uri_images(doc, &mut images, &mut views, &mut bin)?;
    let bin_len = bin.len;

    if !views.is_empty() {
        json.insert("bufferViews".into(), Value::Array(views));
    }
    if !images.is_empty() {
        json.insert("images".into(), Value::Array(images));
    }
    set_buffers(&mut json, bin_len, fallback);

    let text = serde_json::to_vec(&Value::Object(json))
        .map_err(|e| doc.invalid("JSON", format!("cannot serialize: {e}")))?;
    Ok((text, bin.pieces, bin_len))
}

/// Placing the bufferViews in the BIN chunk, in order: each view's bytes in buffer 0, or a
/// compressed view's stream, the view itself then reading from the fallback buffer (buffer 1,
/// which holds no bytes). Returns the fallback buffer's length (0: none).
fn place_views<'a>(doc: &'a Document, views: &mut [Value], bin: &mut Bin<'a>) -> Result<u64> {
    let packed = match &doc.packed {
        Some(p) if p.len() != views.len() => {
            return Err(doc.invalid(
                "bufferViews",
                "the document changed after it was compressed (internal)",
            ));
        }
        Some(p) => &p[..],
        None => &[],
    };
    let mut fallback = 0u64;
    for (i, v) in views.iter_mut().enumerate() {
        let vplace = format!("bufferViews[{i}]");
        let obj = v
            .as_object_mut()
            .ok_or_else(|| doc.invalid(&vplace, "not an object"))?;
        if let Some(Some(p)) = packed.get(i) {
            let off = bin.place(&p.stream);
            let at = fallback.next_multiple_of(4);
            fallback = at + (p.count * p.stride) as u64;
            obj.insert("buffer".into(), json!(1));
            obj.insert("byteOffset".into(), json!(at));
            let exts = obj.entry("extensions").or_insert_with(|| json!({}));
            if let Some(e) = exts.as_object_mut() {
                e.insert(crate::pack::EXTENSION.into(), compressed_view(p, off));
            }
            continue;
        }
        let (data, _) = crate::accessor::view_bytes(doc, i, "output")?;
        let off = bin.place(data);
        obj.insert("buffer".into(), json!(0));
        if off == 0 {
            obj.remove("byteOffset");
        } else {
            obj.insert("byteOffset".into(), json!(off));
        }
    }
    Ok(fallback)
}

/// Embedding the images read from URIs: each one's bytes placed in the BIN chunk behind a
/// new bufferView (appended to `views`), the image naming that view and its MIME type.
fn embed_uri_images<'a>(
    doc: &'a Document,
    images: &mut [Value],
    views: &mut Vec<Value>,
    bin: &mut Bin<'a>,
) -> Result<()> {
    for (i, img) in images.iter_mut().enumerate() {
        let Some(Some(uri)) = doc.uri_images.get(i) else {
            continue;
        };
        let obj = img
            .as_object_mut()
            .ok_or_else(|| doc.invalid(format!("images[{i}]"), "not an object"))?;
        let off = bin.place(&uri.bytes);
        let mut view = Map::new();
        view.insert("buffer".into(), json!(0));
        if off != 0 {
            view.insert("byteOffset".into(), json!(off));
        }
        view.insert("byteLength".into(), json!(uri.bytes.len()));
        obj.remove("uri");
        obj.insert("bufferView".into(), json!(views.len()));
        obj.insert("mimeType".into(), json!(uri.mime));
        views.push(Value::Object(view));
    }
    Ok(())
}

/// The `buffers` entry: buffer 0 the BIN chunk (`bin_len` bytes, the first buffer's other
/// properties kept, its URI dropped), buffer 1 the compressed views' fallback when there is
/// one; none when the BIN chunk is empty.
fn set_buffers(json: &mut Map<String, Value>, bin_len: u64, fallback: u64) {
    if bin_len > 0 {
        let mut buffer = json
            .get("buffers")
            .and_then(Value::as_array)
            .and_then(|b| b.first())
            .and_then(Value::as_object)
            .cloned()
            .unwrap_or_default();
        buffer.remove("uri");
        buffer.insert("byteLength".into(), json!(bin_len));
        let mut buffers = vec![Value::Object(buffer)];
        if fallback > 0 {
            buffers.push(json!({
                "byteLength": fallback,
                "extensions": { crate::pack::EXTENSION: { "fallback": true } }
            }));
        }
        json.insert("buffers".into(), Value::Array(buffers));
    } else {
        json.remove("buffers");
    }
}

/// The `EXT_meshopt_compression` object of a view whose stream starts at BIN offset `off`.
fn compressed_view(p: &crate::pack::Packed, off: u64) -> Value {
    let mut e = Map::new();
    e.insert("buffer".into(), json!(0));
    e.insert("byteOffset".into(), json!(off));
    e.insert("byteLength".into(), json!(p.stream.len()));
    e.insert("byteStride".into(), json!(p.stride));
    e.insert("mode".into(), json!(p.mode));
    if let Some(f) = p.filter {
        e.insert("filter".into(), json!(f.name()));
    }
    e.insert("count".into(), json!(p.count));
    Value::Object(e)
}

/// Writes the document as a `.gltf` whose single buffer is a base64 data URI (for small,
/// readable fixtures), atomically.
pub fn write_gltf_embedded(doc: &Document, out: &Path) -> Result<()> {
    use base64::Engine as _;
    let (json, pieces, bin_len) = layout(doc)?;
    let mut root: Map<String, Value> =
        serde_json::from_slice(&json).map_err(|e| doc.invalid("JSON", e.to_string()))?;
    if bin_len > 0 {
        let mut bin = vec![0u8; bin_len as usize];
        for (off, p) in &pieces {
            bin[*off as usize..*off as usize + p.bytes().len()].copy_from_slice(p.bytes());
        }
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&bin)
        );
        if let Some(b) = root
            .get_mut("buffers")
            .and_then(|b| b.get_mut(0))
            .and_then(Value::as_object_mut)
        {
            b.insert("uri".into(), json!(uri));
        }
    }
    let mut text = serde_json::to_vec_pretty(&Value::Object(root))
        .map_err(|e| doc.invalid("JSON", e.to_string()))?;
    text.push(b'\n');
    write_atomic(out, &text)
}

/// Writes `bytes` to `out` through a temporary file and a rename.
pub fn write_atomic(out: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = temp_path(out);
    let r = std::fs::write(&tmp, bytes).and_then(|()| replace(&tmp, out));
    r.map_err(|source| {
        let _ = std::fs::remove_file(&tmp);
        IoError::Fs {
            path: out.to_owned(),
            action: "write",
            source,
        }
    })
}

/// Writes the document as a self-contained `.glb` at `out`, atomically.
pub fn write_glb(doc: &Document, out: &Path) -> Result<WriteStats> {
    let plan = plan(doc)?;
    let tmp = temp_path(out);
    let result = (|| -> std::io::Result<()> {
        let file = std::fs::File::create(&tmp)?;
        // Small pieces (headers, JSON, padding) are gathered; large views go straight out.
        let mut w = std::io::BufWriter::with_capacity(64 << 10, file);
        plan.write(&mut w)?;
        let file = w
            .into_inner()
            .map_err(std::io::IntoInnerError::into_error)?;
        drop(file);
        replace(&tmp, out)
    })();
    if let Err(source) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(IoError::Fs {
            path: out.to_owned(),
            action: "write",
            source,
        });
    }
    log_written(out);
    Ok(plan.stats())
}

/// A test hook: with `PELT_WRITTEN_LOG` set, the path of every `.glb` written is appended to
/// that file (one absolute path per line), so that a test run can hand every output any test
/// wrote to the Khronos validator (`tools/validate-written.sh`).
fn log_written(out: &Path) {
    use std::io::Write as _;
    let Some(log) = std::env::var_os("PELT_WRITTEN_LOG") else {
        return;
    };
    let path = std::path::absolute(out).unwrap_or_else(|_| out.to_owned());
    let line = format!("{}\n", path.display());
    // One short write with O_APPEND: lines from parallel writers do not interleave.
    if let Ok(mut f) = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(log)
    {
        let _ = f.write_all(line.as_bytes());
    }
}

/// The document as self-contained `.glb` bytes in memory.
pub fn to_vec(doc: &Document) -> Result<Vec<u8>> {
    let plan = plan(doc)?;
    let mut out = Vec::with_capacity(plan.total as usize);
    plan.write(&mut out)
        .map_err(|e| doc.invalid("output", e.to_string()))?;
    Ok(out)
}

/// A laid-out GLB, ready to stream.
struct Plan<'a> {
    json: Vec<u8>,
    pieces: Vec<(u64, Piece<'a>)>,
    bin_len: u64,
    total: u64,
}

fn plan(doc: &Document) -> Result<Plan<'_>> {
    let (json, pieces, bin_len) = layout(doc)?;
    let json_padded = json.len().next_multiple_of(4) as u64;
    let bin_padded = bin_len.next_multiple_of(4);
    let total = 12 + 8 + json_padded + if bin_len > 0 { 8 + bin_padded } else { 0 };
    if total > u64::from(u32::MAX) {
        return Err(doc.invalid(
            "output",
            format!("{total} bytes exceed the 4 GiB GLB limit"),
        ));
    }
    Ok(Plan {
        json,
        pieces,
        bin_len,
        total,
    })
}

impl Plan<'_> {
    fn stats(&self) -> WriteStats {
        WriteStats {
            file_bytes: self.total,
            bin_bytes: self.bin_len.next_multiple_of(4),
        }
    }

    fn write(&self, w: &mut impl Write) -> std::io::Result<()> {
        let json_padded = self.json.len().next_multiple_of(4);
        let bin_padded = self.bin_len.next_multiple_of(4);
        w.write_all(b"glTF")?;
        w.write_all(&2u32.to_le_bytes())?;
        w.write_all(&(self.total as u32).to_le_bytes())?;
        w.write_all(&(json_padded as u32).to_le_bytes())?;
        w.write_all(&0x4E4F_534Au32.to_le_bytes())?;
        w.write_all(&self.json)?;
        w.write_all(&b"   "[..(json_padded - self.json.len())])?;
        if self.bin_len > 0 {
            w.write_all(&(bin_padded as u32).to_le_bytes())?;
            w.write_all(&0x004E_4942u32.to_le_bytes())?;
            let mut at = 0u64;
            for (off, p) in &self.pieces {
                let pad = (off - at) as usize;
                w.write_all(&[0u8; 4][..pad])?;
                w.write_all(p.bytes())?;
                at = off + p.bytes().len() as u64;
            }
            w.write_all(&[0u8; 4][..(bin_padded - at) as usize])?;
        }
        Ok(())
    }
}

/// Moves the finished temporary file `tmp` to `out`. An old file at `out` is removed first
/// rather than renamed over: on ext4, renaming over an existing file makes the kernel allocate
/// and start writing the new file's blocks inside the `rename` call (the `auto_da_alloc`
/// heuristic for programs that skip `fsync`), which made writing the 86 MB benchmark output
/// take 80 to 370 ms instead of about 30 ms. The output name is absent for the moment between
/// the two calls, never partial.
fn replace(tmp: &Path, out: &Path) -> std::io::Result<()> {
    match std::fs::symlink_metadata(out) {
        Ok(m) if m.is_file() => std::fs::remove_file(out)?,
        _ => {}
    }
    std::fs::rename(tmp, out)
}

/// `dir/.name.pelt-tmp-PID`: in the target folder so the final rename stays on one filesystem.
fn temp_path(out: &Path) -> PathBuf {
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    out.with_file_name(format!(".{name}.pelt-tmp-{}", std::process::id()))
}
