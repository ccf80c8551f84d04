//! Compressed input: bufferViews compressed with `EXT_meshopt_compression` or
//! `KHR_meshopt_compression` (what `gltfpack -c`/`-cc` writes) are decoded when the file is
//! loaded, with meshoptimizer's own decoder (the `meshopt` crate) and its filters
//! (octahedral, quaternion, exponential, colour), into buffers of their own. The views then
//! read plain data like any other, the extension is dropped from the document and the
//! fallback buffers (declared without data) are left empty; the writer never refers to them.
//!
//! Every field is checked before anything is allocated: the compressed range lies inside a
//! buffer that holds data, the stride and count suit the mode, and the decoded size is the
//! view's `byteLength` and at most [`MAX_DECODED`] bytes. A decoder error names the view.

use serde_json::Value;

use crate::document::{Buffer, Document};
use crate::error::Result;

// The extensions' names are the document's (it recognises their fallback buffers on
// loading); their old path here keeps working.
pub use crate::document::MESHOPT_EXTENSIONS as EXTENSIONS;

/// Most bytes one bufferView may decode to.
pub const MAX_DECODED: u64 = 1 << 30;

/// One compressed view's parameters.
struct Compressed {
    buffer: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: String,
    filter: String,
}

/// The mode, stride and filter rules of the extension.
fn check_params(c: &Compressed, khr: bool) -> std::result::Result<(), String> {
    match c.mode.as_str() {
        "ATTRIBUTES" if c.stride == 0 || c.stride > 256 || !c.stride.is_multiple_of(4) => {
            return Err(format!(
                "ATTRIBUTES stride {} is not a multiple of 4 up to 256",
                c.stride
            ));
        }
        "TRIANGLES" | "INDICES" if c.stride != 2 && c.stride != 4 => {
            return Err(format!("{} stride {} is neither 2 nor 4", c.mode, c.stride));
        }
        "TRIANGLES" if !c.count.is_multiple_of(3) => {
            return Err(format!(
                "TRIANGLES count {} is not a multiple of 3",
                c.count
            ));
        }
        "ATTRIBUTES" | "TRIANGLES" | "INDICES" => {}
        other => return Err(format!("unknown mode {other:?}")),
    }
    let filter_ok = match c.filter.as_str() {
        "NONE" => true,
        "OCTAHEDRAL" | "COLOR" => c.stride == 4 || c.stride == 8,
        "QUATERNION" => c.stride == 8,
        "EXPONENTIAL" => c.stride.is_multiple_of(4),
        _ => false,
    };
    if !filter_ok || (c.filter != "NONE" && c.mode != "ATTRIBUTES") || (c.filter == "COLOR" && !khr)
    {
        return Err(format!(
            "filter {:?} does not suit mode {} with stride {}",
            c.filter, c.mode, c.stride
        ));
    }
    Ok(())
}

/// Decodes one view's data; a nonzero code is the decoder's error.
#[expect(
    unsafe_code,
    reason = "meshoptimizer's decoders are C; each call is given a destination of exactly count × stride bytes and the source slice, and the decoders are safe for untrusted input (they only write inside the destination)"
)]
fn decode(c: &Compressed, src: &[u8]) -> std::result::Result<Vec<u8>, i32> {
    use meshopt::ffi;
    let mut out = vec![0u8; c.count * c.stride];
    let (dst, n, stride) = (out.as_mut_ptr().cast(), c.count, c.stride);
    let code = unsafe {
        match c.mode.as_str() {
            "ATTRIBUTES" => {
                ffi::meshopt_decodeVertexBuffer(dst, n, stride, src.as_ptr(), src.len())
            }
            "TRIANGLES" => ffi::meshopt_decodeIndexBuffer(dst, n, stride, src.as_ptr(), src.len()),
            _ => ffi::meshopt_decodeIndexSequence(dst, n, stride, src.as_ptr(), src.len()),
        }
    };
    if code != 0 {
        return Err(code);
    }
    unsafe {
        match c.filter.as_str() {
            "OCTAHEDRAL" => ffi::meshopt_decodeFilterOct(dst, n, stride),
            "QUATERNION" => ffi::meshopt_decodeFilterQuat(dst, n, stride),
            "EXPONENTIAL" => ffi::meshopt_decodeFilterExp(dst, n, stride),
            "COLOR" => ffi::meshopt_decodeFilterColor(dst, n, stride),
            _ => {}
        }
    }
    Ok(out)
}

/// Decodes every job's view, in parallel: views cannot be split (their blocks decode in
/// sequence), so each worker takes the largest view not yet started (longest first: the
/// cores finish close together). The results are in `jobs`' order.
fn decode_all(
    buffers: &[Buffer],
    jobs: &[(usize, &'static str, Compressed)],
) -> Vec<std::result::Result<Vec<u8>, i32>> {
    use std::sync::OnceLock;
    use std::sync::atomic::{AtomicUsize, Ordering};
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by_key(|&k| std::cmp::Reverse(jobs[k].2.count * jobs[k].2.stride));
    let next = AtomicUsize::new(0);
    let results: Vec<OnceLock<std::result::Result<Vec<u8>, i32>>> =
        jobs.iter().map(|_| OnceLock::new()).collect();
    let work = || {
        while let Some(&k) = order.get(next.fetch_add(1, Ordering::Relaxed)) {
            let c = &jobs[k].2;
            let _ = results[k].set(decode(c, &buffers[c.buffer][c.offset..c.offset + c.length]));
        }
    };
    // One puller per thread: a thread busy elsewhere (another file of a batch) leaves the
    // views to the others.
    let pullers = rayon::current_num_threads().min(jobs.len());
    rayon::scope(|s| {
        for _ in 1..pullers {
            s.spawn(|_| work());
        }
        work();
    });
    results
        .into_iter()
        .map(|r| r.into_inner().unwrap_or(Err(-1)))
        .collect()
}

impl Document {
    /// Decodes every meshopt-compressed bufferView (see the module documentation).
    pub(crate) fn decode_meshopt(&mut self) -> Result<()> {
        let used: Vec<&str> = self
            .array("extensionsUsed")
            .iter()
            .filter_map(Value::as_str)
            .filter(|e| EXTENSIONS.contains(e))
            .collect();
        if used.is_empty() {
            return Ok(());
        }
        let mut jobs = Vec::new();
        for v in 0..self.array("bufferViews").len() {
            if let Some(job) = self.compressed_view(v)? {
                jobs.push(job);
            }
        }
        let decoded = decode_all(&self.buffers, &jobs);
        for ((v, ext, c), data) in jobs.into_iter().zip(decoded) {
            let place = format!("bufferViews[{v}].extensions.{ext}");
            let data = data.map_err(|code| {
                self.invalid(
                    &place,
                    format!("the compressed data cannot be decoded (meshopt error {code})"),
                )
            })?;
            self.install(v, ext, c.count * c.stride, data);
        }
        self.drop_meshopt_declarations();
        Ok(())
    }

    /// View `v`'s compression parameters, checked (None: it is not compressed).
    fn compressed_view(&self, v: usize) -> Result<Option<(usize, &'static str, Compressed)>> {
        let view = &self.array("bufferViews")[v];
        let Some((ext, spec)) = EXTENSIONS
            .iter()
            .find_map(|e| Some((*e, view.get("extensions")?.get(e)?)))
        else {
            return Ok(None);
        };
        let place = format!("bufferViews[{v}].extensions.{ext}");
        let num = |k: &str| spec.get(k).and_then(Value::as_u64);
        let text = |k: &str, d: &str| spec.get(k).and_then(Value::as_str).unwrap_or(d).to_owned();
        let missing = |k: &str| self.invalid(&place, format!("{k} is missing or not an integer"));
        let c = Compressed {
            buffer: num("buffer").ok_or_else(|| missing("buffer"))? as usize,
            offset: num("byteOffset").unwrap_or(0) as usize,
            length: num("byteLength").ok_or_else(|| missing("byteLength"))? as usize,
            stride: num("byteStride").ok_or_else(|| missing("byteStride"))? as usize,
            count: num("count").ok_or_else(|| missing("count"))? as usize,
            mode: text("mode", ""),
            filter: text("filter", "NONE"),
        };
        check_params(&c, ext.starts_with("KHR")).map_err(|m| self.invalid(&place, m))?;
        let decoded = (c.count as u64).saturating_mul(c.stride as u64);
        let view_len = view.get("byteLength").and_then(Value::as_u64);
        if decoded > MAX_DECODED || view_len != Some(decoded) {
            return Err(self.invalid(
                &place,
                format!(
                    "count × byteStride = {decoded} bytes, but the view's byteLength is {}{}",
                    view_len.map_or("missing".to_owned(), |l| l.to_string()),
                    if decoded > MAX_DECODED {
                        " (and more than pelt decodes)"
                    } else {
                        ""
                    }
                ),
            ));
        }
        let inside = self.buffers.get(c.buffer).is_some_and(|b| {
            c.offset
                .checked_add(c.length)
                .is_some_and(|end| end <= b.len())
        });
        if !inside {
            return Err(self.invalid(
                &place,
                format!(
                    "bytes {}..{} are not in buffers[{}] (a fallback buffer holds none)",
                    c.offset,
                    c.offset.saturating_add(c.length),
                    c.buffer
                ),
            ));
        }
        Ok(Some((v, ext, c)))
    }

    /// View `v` reads `data` (a buffer of its own) from now on, without extension `ext`.
    fn install(&mut self, v: usize, ext: &str, len: usize, data: Vec<u8>) {
        let index = self.buffers.len();
        self.buffers.push(Buffer::from(data));
        if let Some(b) = self.json.get_mut("buffers").and_then(Value::as_array_mut) {
            b.push(serde_json::json!({ "byteLength": len }));
        }
        let Some(view) = self
            .json
            .get_mut("bufferViews")
            .and_then(|x| x.get_mut(v))
            .and_then(Value::as_object_mut)
        else {
            return;
        };
        view.insert("buffer".into(), Value::from(index));
        view.remove("byteOffset");
        if let Some(exts) = view.get_mut("extensions").and_then(Value::as_object_mut) {
            exts.remove(ext);
            if exts.is_empty() {
                view.remove("extensions");
            }
        }
    }

    /// The data is plain now: the extension is no longer used or required, and the fallback
    /// buffers' markers go with it.
    fn drop_meshopt_declarations(&mut self) {
        for key in ["extensionsUsed", "extensionsRequired"] {
            if let Some(list) = self.json.get_mut(key).and_then(Value::as_array_mut) {
                list.retain(|e| !e.as_str().is_some_and(|e| EXTENSIONS.contains(&e)));
                if list.is_empty() {
                    self.json.remove(key);
                }
            }
        }
        let buffers = self.json.get_mut("buffers").and_then(Value::as_array_mut);
        for b in buffers.into_iter().flatten() {
            if let Some(exts) = b.get_mut("extensions").and_then(Value::as_object_mut) {
                for e in EXTENSIONS {
                    exts.remove(e);
                }
                if exts.is_empty()
                    && let Some(o) = b.as_object_mut()
                {
                    o.remove("extensions");
                }
            }
        }
    }
}
