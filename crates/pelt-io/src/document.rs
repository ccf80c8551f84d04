//! A glTF 2.0 asset in memory: the JSON root kept whole (so extensions, extras, node hierarchy,
//! materials and key order survive the bake) and the bytes of every buffer and URI image.
//!
//! Loading checks what the file claims against what it holds before any use: GLB header and
//! chunk lengths against the file size, `byteLength` against the bytes actually read. URIs must
//! stay inside the asset's folder: `..`, absolute paths and schemes (`file:`, `http:`) are
//! refused.

use std::path::{Component, Path, PathBuf};

use base64::Engine as _;
use serde_json::{Map, Value};

use crate::error::{IoError, Result};

const GLB_MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// Geometry extensions whose data pelt cannot decode.
const UNSUPPORTED_EXTENSIONS: &[&str] = &["KHR_draco_mesh_compression"];

/// The meshopt compression extensions (decoded by [`crate::meshopt`]).
pub const MESHOPT_EXTENSIONS: [&str; 2] = ["EXT_meshopt_compression", "KHR_meshopt_compression"];

/// Whether buffer JSON `b` is a meshopt fallback buffer (`extensions.*.fallback: true`).
pub(crate) fn is_fallback(b: &Value) -> bool {
    MESHOPT_EXTENSIONS.iter().any(|e| {
        b.get("extensions")
            .and_then(|x| x.get(e))
            .and_then(|x| x.get("fallback"))
            .and_then(Value::as_bool)
            == Some(true)
    })
}

/// One primitive: `meshes[mesh].primitives[primitive]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct PrimitiveRef {
    /// Mesh index.
    pub mesh: usize,
    /// Primitive index within the mesh.
    pub primitive: usize,
}

/// An image given by URI, loaded so that the output can embed it.
#[derive(Debug, Clone)]
pub struct UriImage {
    /// Image bytes.
    pub bytes: Vec<u8>,
    /// MIME type (from the data URI, the `mimeType` property, the file extension or the bytes).
    pub mime: String,
}

/// The bytes of one buffer. A GLB's BIN chunk stays inside the bytes read from the file (no
/// copy); [`Buffer`] derefs to exactly the buffer's `byteLength` bytes.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Buffer {
    data: FileBytes,
    start: usize,
    len: usize,
}

/// A file's bytes: read into memory, or (large files) mapped read-only from the page cache.
/// A mapped file becomes an owned copy the first time its bytes are borrowed mutably.
#[derive(Debug)]
pub enum FileBytes {
    /// Bytes in memory.
    Owned(Vec<u8>),
    /// A read-only private map of the whole file.
    Mapped(memmap2::Mmap),
}

impl Default for FileBytes {
    fn default() -> Self {
        FileBytes::Owned(Vec::new())
    }
}

impl Clone for FileBytes {
    fn clone(&self) -> Self {
        FileBytes::Owned(self.to_vec())
    }
}

impl PartialEq for FileBytes {
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}

impl Eq for FileBytes {}

impl std::ops::Deref for FileBytes {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        match self {
            FileBytes::Owned(v) => v,
            FileBytes::Mapped(m) => m,
        }
    }
}

impl std::ops::DerefMut for FileBytes {
    fn deref_mut(&mut self) -> &mut [u8] {
        if let FileBytes::Mapped(m) = self {
            *self = FileBytes::Owned(m.to_vec());
        }
        match self {
            FileBytes::Owned(v) => v,
            FileBytes::Mapped(_) => unreachable!("made owned above"),
        }
    }
}

impl Buffer {
    /// The buffer `data[start..start + len]` (clamped to `data`).
    pub fn new(data: Vec<u8>, start: usize, len: usize) -> Buffer {
        Buffer::of(FileBytes::Owned(data), start, len)
    }

    /// [`Buffer::new`] over a file's bytes.
    pub fn of(data: FileBytes, start: usize, len: usize) -> Buffer {
        let start = start.min(data.len());
        let len = len.min(data.len() - start);
        Buffer { data, start, len }
    }
}

impl From<Vec<u8>> for Buffer {
    fn from(data: Vec<u8>) -> Buffer {
        let len = data.len();
        Buffer {
            data: FileBytes::Owned(data),
            start: 0,
            len,
        }
    }
}

impl std::ops::Deref for Buffer {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        &self.data[self.start..self.start + self.len]
    }
}

impl std::ops::DerefMut for Buffer {
    fn deref_mut(&mut self) -> &mut [u8] {
        &mut self.data[self.start..self.start + self.len]
    }
}

/// The bytes of a bufferView an edit added: plain bytes, or 32-bit words already in
/// little-endian order (records built as words are stored without a byte copy).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ViewData {
    /// Bytes.
    Bytes(Vec<u8>),
    /// Little-endian 32-bit words.
    Words(Vec<u32>),
    /// Bytes written through a meshopt filter ([`crate::pack`]): what a reader decodes, and
    /// the filtered bytes the compressed stream holds.
    Filtered(Box<Filtered>),
}

/// A bufferView's data as a meshopt filter stores it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Filtered {
    /// What the filter's decoder gives back: the view's data for every reader.
    pub data: Vec<u8>,
    /// The filter's output, which the vertex codec compresses.
    pub encoded: Vec<u8>,
    /// The filter.
    pub filter: crate::pack_codec::Filter,
    /// Bytes per element.
    pub stride: usize,
}

impl ViewData {
    /// The bytes.
    pub fn bytes(&self) -> &[u8] {
        match self {
            ViewData::Bytes(b) => b,
            ViewData::Words(w) => bytemuck::cast_slice(w),
            ViewData::Filtered(f) => &f.data,
        }
    }
}

impl From<Vec<u8>> for ViewData {
    fn from(b: Vec<u8>) -> Self {
        ViewData::Bytes(b)
    }
}

/// A loaded glTF asset.
#[derive(Debug, Clone)]
pub struct Document {
    /// The file it came from (used in every error message).
    pub path: PathBuf,
    /// The JSON root object.
    pub json: Map<String, Value>,
    /// The bytes of each buffer, exactly `byteLength` long.
    pub buffers: Vec<Buffer>,
    /// For each image: its bytes when it was given by URI (None when it lives in a bufferView).
    pub uri_images: Vec<Option<UriImage>>,
    /// Every file read to build this document (the asset, external buffers, images).
    pub files_read: Vec<PathBuf>,
    /// Data of bufferViews added by edits, in order after the original ones.
    pub(crate) new_views: Vec<ViewData>,
    /// Number of bufferViews in the source.
    pub(crate) source_views: usize,
    /// Accessors an edit stopped using (candidates for [`Document::prune_detached`]).
    pub(crate) detached: Vec<usize>,
    /// BufferViews an edit stopped using (fin records replaced by a new bake).
    pub(crate) detached_views: Vec<usize>,
    /// Each bufferView's compressed stream ([`Document::pack_meshopt`]), for the writer.
    pub(crate) packed: Option<Vec<Option<crate::pack_codec::Packed>>>,
    /// What loading read past or repaired (an OBJ's missing `.mtl`, text that was not UTF-8),
    /// each naming the file and the place; a bake reports them.
    pub warnings: Vec<String>,
}

impl Document {
    /// Loads a `.gltf` or `.glb` file (detected by its magic bytes).
    pub fn load(path: &Path) -> Result<Document> {
        let bytes = read_file(path).map_err(|source| IoError::Fs {
            path: path.to_owned(),
            action: "read",
            source,
        })?;
        Self::from_file_bytes(path, bytes)
    }

    /// Parses a glTF or GLB held in memory; `path` names it in errors and anchors relative URIs.
    pub fn from_bytes(path: &Path, bytes: Vec<u8>) -> Result<Document> {
        Self::from_file_bytes(path, FileBytes::Owned(bytes))
    }

    /// [`Document::from_bytes`] over bytes read or mapped from a file.
    pub fn from_file_bytes(path: &Path, bytes: FileBytes) -> Result<Document> {
        let is_glb = bytes.starts_with(GLB_MAGIC);
        let has_glb_ext = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
        if has_glb_ext && !is_glb {
            return Err(IoError::invalid(
                path,
                "GLB header",
                "bad magic: expected \"glTF\"",
            ));
        }
        let (json, bin) = if is_glb {
            let (json_range, bin_range) = split_glb(path, &bytes)?;
            let json = parse_json(path, &bytes[json_range])?;
            // The BIN chunk stays where it was read: no copy of the (large) binary data.
            let bin = bin_range.map(|r| Buffer::of(bytes, r.start, r.len()));
            (json, bin)
        } else {
            let json = parse_json(path, &bytes)?;
            (json, None)
        };
        let mut doc = Document {
            path: path.to_owned(),
            json,
            buffers: Vec::new(),
            uri_images: Vec::new(),
            files_read: vec![path.to_owned()],
            new_views: Vec::new(),
            packed: None,
            source_views: 0,
            detached: Vec::new(),
            detached_views: Vec::new(),
            warnings: Vec::new(),
        };
        doc.check_asset()?;
        doc.load_buffers(bin)?;
        doc.load_images()?;
        doc.decode_meshopt()?;
        doc.source_views = doc.array("bufferViews").len();
        Ok(doc)
    }

    /// Builds a document from JSON and buffers made in memory (OBJ import, fixtures).
    pub fn from_parts(path: &Path, json: Map<String, Value>, buffers: Vec<Vec<u8>>) -> Document {
        let source_views = json
            .get("bufferViews")
            .and_then(Value::as_array)
            .map_or(0, Vec::len);
        let images = json
            .get("images")
            .and_then(Value::as_array)
            .map_or(0, Vec::len);
        Document {
            path: path.to_owned(),
            json,
            buffers: buffers.into_iter().map(Buffer::from).collect(),
            uri_images: vec![None; images],
            files_read: vec![path.to_owned()],
            new_views: Vec::new(),
            packed: None,
            source_views,
            detached: Vec::new(),
            detached_views: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// The top-level array `name` (empty when absent or not an array).
    pub fn array(&self, name: &str) -> &[Value] {
        self.json
            .get(name)
            .and_then(Value::as_array)
            .map_or(&[], Vec::as_slice)
    }

    /// Every primitive of every mesh, in order.
    pub fn primitives(&self) -> Vec<PrimitiveRef> {
        self.array("meshes")
            .iter()
            .enumerate()
            .flat_map(|(mesh, m)| {
                let n = m
                    .get("primitives")
                    .and_then(Value::as_array)
                    .map_or(0, Vec::len);
                (0..n).map(move |primitive| PrimitiveRef { mesh, primitive })
            })
            .collect()
    }

    /// The primitive's JSON object.
    pub fn primitive(&self, r: PrimitiveRef) -> Result<&Map<String, Value>> {
        self.array("meshes")
            .get(r.mesh)
            .and_then(|m| m.get("primitives"))
            .and_then(Value::as_array)
            .and_then(|p| p.get(r.primitive))
            .and_then(Value::as_object)
            .ok_or_else(|| self.invalid(self.place(r), "primitive is not a JSON object"))
    }

    /// The primitive's JSON object, for editing.
    pub(crate) fn primitive_mut(&mut self, r: PrimitiveRef) -> Option<&mut Map<String, Value>> {
        self.json
            .get_mut("meshes")?
            .as_array_mut()?
            .get_mut(r.mesh)?
            .get_mut("primitives")?
            .as_array_mut()?
            .get_mut(r.primitive)?
            .as_object_mut()
    }

    /// The mesh's name, if it has one.
    pub fn mesh_name(&self, mesh: usize) -> Option<&str> {
        self.array("meshes").get(mesh)?.get("name")?.as_str()
    }

    /// A human-readable place: `meshes[0] "Body" primitives[1]`.
    pub fn place(&self, r: PrimitiveRef) -> String {
        match self.mesh_name(r.mesh) {
            Some(name) => format!("meshes[{}] {:?} primitives[{}]", r.mesh, name, r.primitive),
            None => format!("meshes[{}] primitives[{}]", r.mesh, r.primitive),
        }
    }

    /// The primitive's mode (4 = TRIANGLES when absent).
    pub fn mode(&self, r: PrimitiveRef) -> Result<u64> {
        match self.primitive(r)?.get("mode") {
            None => Ok(4),
            Some(v) => v.as_u64().filter(|&m| m <= 6).ok_or_else(|| {
                self.invalid(
                    format!("{} mode", self.place(r)),
                    format!("invalid mode {v}"),
                )
            }),
        }
    }

    /// The accessor index of attribute `name`, if the primitive has it.
    pub fn attribute(&self, r: PrimitiveRef, name: &str) -> Result<Option<usize>> {
        let prim = self.primitive(r)?;
        let Some(v) = prim.get("attributes").and_then(|a| a.get(name)) else {
            return Ok(None);
        };
        v.as_u64().map(|i| Some(i as usize)).ok_or_else(|| {
            self.invalid(
                format!("{} attributes.{name}", self.place(r)),
                "not an accessor index",
            )
        })
    }

    /// An [`IoError::Invalid`] for this document.
    pub fn invalid(&self, place: impl Into<String>, message: impl Into<String>) -> IoError {
        IoError::invalid(&self.path, place, message)
    }

    /// Total bytes held (buffers and URI images): the yardstick for accessors without data.
    pub fn real_bytes(&self) -> u64 {
        let b: usize = self.buffers.iter().map(|b| b.len()).sum();
        let i: usize = self
            .uri_images
            .iter()
            .flatten()
            .map(|i| i.bytes.len())
            .sum();
        (b + i) as u64
    }

    fn check_asset(&self) -> Result<()> {
        let version = self
            .json
            .get("asset")
            .and_then(|a| a.get("version"))
            .and_then(Value::as_str);
        match version {
            Some(v) if v.split('.').next() == Some("2") => {}
            Some(v) => {
                return Err(self.invalid("asset.version", format!("glTF {v} is not glTF 2.x")));
            }
            None => return Err(self.invalid("asset.version", "missing (not a glTF 2.0 file?)")),
        }
        for key in ["extensionsUsed", "extensionsRequired"] {
            for ext in self.array(key).iter().filter_map(Value::as_str) {
                if UNSUPPORTED_EXTENSIONS.contains(&ext) {
                    return Err(self.invalid(
                        key,
                        format!(
                            "{ext} is not supported: decompress the asset first \
                             (e.g. `gltf-transform copy` without compression)"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    fn load_buffers(&mut self, mut bin: Option<Buffer>) -> Result<()> {
        let specs: Vec<(Option<String>, Option<u64>, bool)> = self
            .array("buffers")
            .iter()
            .map(|b| {
                (
                    b.get("uri").and_then(Value::as_str).map(str::to_owned),
                    b.get("byteLength").and_then(Value::as_u64),
                    is_fallback(b),
                )
            })
            .collect();
        for (i, (uri, len, fallback)) in specs.into_iter().enumerate() {
            let place = format!("buffers[{i}]");
            let len =
                len.ok_or_else(|| self.invalid(&place, "byteLength is missing or not an integer"))?;
            // A meshopt fallback buffer holds nothing: its views are decoded instead.
            if fallback && uri.is_none() {
                self.buffers.push(Buffer::from(Vec::new()));
                continue;
            }
            let mut data = match uri {
                None if i == 0 => bin.take().ok_or_else(|| {
                    self.invalid(&place, "has no uri, and the file has no GLB BIN chunk")
                })?,
                None => return Err(self.invalid(&place, "has no uri (only buffer 0 of a GLB may)")),
                Some(uri) => Buffer::from(self.resolve_uri(&uri, &place)?.0),
            };
            if (data.len() as u64) < len {
                return Err(self.invalid(
                    &place,
                    format!(
                        "byteLength is {len}, but only {} bytes are there",
                        data.len()
                    ),
                ));
            }
            data.len = len as usize;
            self.buffers.push(data);
        }
        Ok(())
    }

    fn load_images(&mut self) -> Result<()> {
        let specs: Vec<(Option<String>, Option<String>)> = self
            .array("images")
            .iter()
            .map(|im| {
                (
                    im.get("uri").and_then(Value::as_str).map(str::to_owned),
                    im.get("mimeType")
                        .and_then(Value::as_str)
                        .map(str::to_owned),
                )
            })
            .collect();
        for (i, (uri, mime)) in specs.into_iter().enumerate() {
            let loaded = match uri {
                None => None,
                Some(uri) => {
                    let (bytes, uri_mime) = self.resolve_uri(&uri, &format!("images[{i}]"))?;
                    let mime = mime
                        .or(uri_mime)
                        .or_else(|| mime_from_name(&uri))
                        .or_else(|| mime_from_bytes(&bytes))
                        .ok_or_else(|| {
                            self.invalid(format!("images[{i}]"), "unknown image type (no mimeType)")
                        })?;
                    Some(UriImage { bytes, mime })
                }
            };
            self.uri_images.push(loaded);
        }
        Ok(())
    }

    /// Reads a URI: a base64 data URI, or a relative file inside the asset's folder.
    fn resolve_uri(&mut self, uri: &str, place: &str) -> Result<(Vec<u8>, Option<String>)> {
        if let Some(rest) = uri.strip_prefix("data:") {
            let (header, payload) = rest
                .split_once(',')
                .ok_or_else(|| self.invalid(place, "malformed data URI (no comma)"))?;
            let Some(mime) = header.strip_suffix(";base64") else {
                return Err(self.invalid(place, "data URI is not base64"));
            };
            let bytes = base64::engine::general_purpose::STANDARD
                .decode(payload.trim_end())
                .map_err(|e| self.invalid(place, format!("malformed base64 in data URI: {e}")))?;
            let mime = (!mime.is_empty()).then(|| mime.to_owned());
            return Ok((bytes, mime));
        }
        let rel = safe_relative_path(uri)
            .map_err(|why| self.invalid(place, format!("uri {uri:?} {why}")))?;
        let full = self.path.parent().unwrap_or(Path::new("")).join(rel);
        let bytes = std::fs::read(&full).map_err(|e| {
            self.invalid(
                place,
                format!("cannot read uri {uri:?} ({}): {e}", full.display()),
            )
        })?;
        self.files_read.push(full);
        Ok((bytes, None))
    }
}

/// Files at least this large are mapped instead of read (see [`read_file`]).
const MAP_FROM: u64 = 256 << 10;

/// Files at least this large are read by several threads where they cannot be mapped.
const PARALLEL_FROM: u64 = 16 << 20;

/// Reads a whole file. Large files are mapped read-only (`PELT_MMAP=0` reads them instead):
/// their pages are already in the page cache, so the map costs neither a copy nor fresh
/// memory the kernel must fault in and zero (57 MB of each on the 1.3 M-triangle benchmark).
/// As with any mapped input, truncating the file while pelt reads it kills the process
/// (SIGBUS); a file changed in place mid-bake is read torn either way. Where the map fails,
/// large files are read by several threads, each into its own part of the buffer.
fn read_file(path: &Path) -> std::io::Result<FileBytes> {
    let file = std::fs::File::open(path)?;
    #[cfg(unix)]
    {
        let len = file.metadata()?.len();
        let map_ok = std::env::var_os("PELT_MMAP").is_none_or(|v| v != "0");
        if len >= MAP_FROM
            && map_ok
            && let Some(map) = map_file(&file, len)
        {
            return Ok(FileBytes::Mapped(map));
        }
        // Asked only for large files: on Linux the answer costs a few reads of cgroup files.
        if len >= PARALLEL_FROM {
            let threads = std::thread::available_parallelism().map_or(1, |n| n.get().min(4));
            if threads >= 2 {
                return read_parallel(&file, len, threads).map(FileBytes::Owned);
            }
        }
    }
    let mut bytes = Vec::new();
    std::io::Read::read_to_end(&mut &file, &mut bytes)?;
    Ok(FileBytes::Owned(bytes))
}

/// A read-only, populated map of a regular file of `len` bytes (None where mapping fails).
#[cfg(unix)]
#[expect(
    unsafe_code,
    reason = "memmap2::Mmap::map is unsafe because another process may change the file; \
              see read_file for what that means here"
)]
fn map_file(file: &std::fs::File, len: u64) -> Option<memmap2::Mmap> {
    if !file.metadata().ok()?.is_file() {
        return None;
    }
    // SAFETY: the map is read-only and private; pelt never writes through it (a mutable
    // borrow copies it first). Concurrent truncation by another process is the documented
    // hazard of mapping, accepted for inputs (see read_file).
    let map = unsafe { memmap2::MmapOptions::new().populate().map(file) }.ok()?;
    (map.len() as u64 == len).then_some(map)
}

/// `len` bytes of `file` (its real length, from the file system) read by `threads` threads.
#[cfg(unix)]
fn read_parallel(file: &std::fs::File, len: u64, threads: usize) -> std::io::Result<Vec<u8>> {
    use std::os::unix::fs::FileExt;
    let mut bytes = vec![0u8; len as usize];
    let part = (len as usize).div_ceil(threads);
    std::thread::scope(|scope| {
        let jobs: Vec<_> = bytes
            .chunks_mut(part)
            .enumerate()
            .map(|(i, chunk)| scope.spawn(move || file.read_exact_at(chunk, (i * part) as u64)))
            .collect();
        jobs.into_iter().try_for_each(|j| {
            j.join()
                .unwrap_or_else(|_| Err(std::io::Error::other("reader thread panicked")))
        })
    })?;
    // A file that grew while being read would be truncated here; report it as changed.
    if file.metadata()?.len() != len {
        return Err(std::io::Error::other("the file changed while it was read"));
    }
    Ok(bytes)
}

/// Checks a GLB's header and chunks; returns the JSON chunk's and the BIN chunk's byte ranges.
fn split_glb(
    path: &Path,
    b: &[u8],
) -> Result<(std::ops::Range<usize>, Option<std::ops::Range<usize>>)> {
    let bad = |place: &str, msg: String| IoError::invalid(path, place, msg);
    let u32_at = |o: usize| {
        b.get(o..o + 4)
            .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
    };
    let (Some(version), Some(length)) = (u32_at(4), u32_at(8)) else {
        return Err(bad(
            "GLB header",
            format!("truncated: the file has only {} bytes", b.len()),
        ));
    };
    if version != 2 {
        return Err(bad("GLB header", format!("version {version}, expected 2")));
    }
    if length as usize != b.len() {
        return Err(bad(
            "GLB header",
            format!("declares {length} bytes, but the file has {}", b.len()),
        ));
    }
    let mut chunks = Vec::new();
    let mut at = 12usize;
    while at < b.len() {
        let (Some(len), Some(kind)) = (u32_at(at), u32_at(at + 4)) else {
            return Err(bad(
                &format!("GLB chunk at byte {at}"),
                "truncated chunk header".into(),
            ));
        };
        let start = at + 8;
        let end = start
            .checked_add(len as usize)
            .filter(|&e| e <= b.len())
            .ok_or_else(|| {
                bad(
                    &format!("GLB chunk {} at byte {at}", chunks.len()),
                    format!("declares {len} bytes, but only {} remain", b.len() - start),
                )
            })?;
        chunks.push((kind, start..end));
        at = end;
    }
    let mut it = chunks.into_iter();
    let json = match it.next() {
        Some((CHUNK_JSON, r)) => r,
        Some((kind, _)) => {
            return Err(bad(
                "GLB chunk 0",
                format!("type 0x{kind:08X}, expected JSON"),
            ));
        }
        None => return Err(bad("GLB", "no JSON chunk".into())),
    };
    let bin = match it.next() {
        Some((CHUNK_BIN, r)) => Some(r),
        Some((kind, _)) => {
            return Err(bad(
                "GLB chunk 1",
                format!("type 0x{kind:08X}, expected BIN"),
            ));
        }
        None => None,
    };
    Ok((json, bin))
}

fn parse_json(path: &Path, bytes: &[u8]) -> Result<Map<String, Value>> {
    match serde_json::from_slice::<Value>(bytes) {
        Ok(Value::Object(m)) => Ok(m),
        Ok(_) => Err(IoError::invalid(path, "JSON", "the root is not an object")),
        Err(e) => {
            let at = format!(" at line {} column {}", e.line(), e.column());
            let message = e.to_string();
            Err(IoError::invalid(
                path,
                format!("JSON line {} column {}", e.line(), e.column()),
                message.strip_suffix(&at).unwrap_or(&message),
            ))
        }
    }
}

/// A URI as a relative path that cannot leave the asset's folder.
pub fn safe_relative_path(uri: &str) -> std::result::Result<PathBuf, &'static str> {
    let decoded = percent_decode(uri).ok_or("has malformed percent-encoding")?;
    if decoded.contains(':') {
        return Err("has a scheme or drive letter; only relative paths are allowed");
    }
    if decoded.starts_with('/') || decoded.starts_with('\\') {
        return Err("is an absolute path; only relative paths are allowed");
    }
    let path = PathBuf::from(decoded.replace('\\', "/"));
    for c in path.components() {
        match c {
            Component::Normal(_) | Component::CurDir => {}
            _ => return Err("leaves the asset's folder"),
        }
    }
    if path.as_os_str().is_empty() {
        return Err("is empty");
    }
    Ok(path)
}

fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

fn mime_from_name(uri: &str) -> Option<String> {
    let ext = uri.rsplit('.').next()?.to_ascii_lowercase();
    let m = match ext.as_str() {
        "png" => "image/png",
        "jpg" | "jpeg" => "image/jpeg",
        "webp" => "image/webp",
        "ktx2" => "image/ktx2",
        _ => return None,
    };
    Some(m.to_owned())
}

pub(crate) fn mime_from_bytes(b: &[u8]) -> Option<String> {
    let m = if b.starts_with(b"\x89PNG") {
        "image/png"
    } else if b.starts_with(&[0xFF, 0xD8, 0xFF]) {
        "image/jpeg"
    } else if b.len() > 12 && &b[0..4] == b"RIFF" && &b[8..12] == b"WEBP" {
        "image/webp"
    } else if b.starts_with(b"\xABKTX 20") {
        "image/ktx2"
    } else {
        return None;
    };
    Some(m.to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uris_may_not_escape_the_folder() {
        assert!(safe_relative_path("a/b.bin").is_ok());
        assert!(safe_relative_path("./b%20c.bin").is_ok());
        for bad in [
            "../x.bin",
            "a/../../x",
            "/etc/passwd",
            "file:///etc/passwd",
            "C:\\x",
            "%2e%2e/x",
            "a\\..\\..\\x",
            "",
        ] {
            assert!(safe_relative_path(bad).is_err(), "{bad} was accepted");
        }
    }

    #[test]
    fn glb_lengths_are_checked() {
        let p = Path::new("t.glb");
        let mut b = b"glTF".to_vec();
        b.extend(2u32.to_le_bytes());
        b.extend(100u32.to_le_bytes());
        let e = Document::from_bytes(p, b).unwrap_err().to_string();
        assert!(e.contains("declares 100 bytes, but the file has 12"), "{e}");
    }
}
