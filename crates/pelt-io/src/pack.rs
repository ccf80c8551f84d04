//! Compressed output with `EXT_meshopt_compression` (what `pelt bake --compress meshopt`
//! writes), in three steps over the finished document:
//!
//! 1. order ([`crate::pack_order`]): triangles in vertex-cache order, vertices in first-use
//!    order, fin records following them;
//! 2. quantize ([`crate::pack_quantize`]): positions, normals, tangents, texture coordinates
//!    and float colours to small integers through the extension's filters
//!    (`KHR_mesh_quantization` where a normal or tangent becomes bytes);
//! 3. plan (here): each bufferView the codecs can take (vertex data with a stride that is a
//!    multiple of 4 up to 256, triangle index lists, fin records) gets its compressed stream;
//!    images and anything the codecs do not shrink stay as they are.
//!
//! The writer ([`crate::glb`]) puts the streams in the BIN chunk and points each compressed
//! view at a fallback buffer that holds no data, as the extension describes. The document
//! keeps the data a reader decodes, so a check or a read of the document before writing sees
//! what the file holds. The same document gives the same bytes at any thread count.

use std::collections::HashMap;

use serde::Serialize;
use serde_json::Value;

use crate::accessor::{self, ComponentType, view_bytes};
use crate::document::{Document, ViewData};
use crate::error::Result;
// The stream type is the codecs' (the document holds it); its old path here keeps working.
pub use crate::pack_codec::Packed;
use crate::pack_codec::{Filter, encode_triangles, encode_vertices};

/// The extension compressed output uses.
pub const EXTENSION: &str = "EXT_meshopt_compression";

/// What compressing did, for the bake report.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct PackReport {
    /// The extension written.
    pub extension: &'static str,
    /// Primitives put in vertex-cache order.
    pub primitives_reordered: usize,
    /// Primitives left in their order (accessors shared with another primitive), whose
    /// indices only took the codec's rotations.
    pub primitives_kept_in_order: usize,
    /// Accessors quantized.
    pub accessors_quantized: usize,
    /// BufferViews written compressed.
    pub views_compressed: usize,
    /// BufferViews written as they are (images, data the codecs do not shrink).
    pub views_plain: usize,
    /// Bytes of the compressed views as a reader decodes them.
    pub decoded_bytes: u64,
    /// Bytes of their streams.
    pub compressed_bytes: u64,
}

/// How each accessor is used, to tell index lists and shared data apart.
#[derive(Default)]
struct Uses {
    /// References to each accessor, from anywhere.
    refs: Vec<u32>,
    /// Accessors that are the `indices` of a TRIANGLES primitive.
    triangle_indices: Vec<bool>,
    /// Accessors used as `indices` of any other primitive.
    other_indices: Vec<bool>,
}

impl Document {
    /// Compresses the document for output (see the module documentation). Call it last:
    /// the plan names bufferViews by index, and an edit after it is refused by the writer.
    pub fn pack_meshopt(&mut self) -> Result<PackReport> {
        let mut report = PackReport {
            extension: EXTENSION,
            ..PackReport::default()
        };
        let uses = self.accessor_uses();
        for r in self.primitives() {
            if self.mode(r)? != 4 {
                continue;
            }
            let prim = self.primitive(r)?;
            let mine = |v: &Value| v.as_u64().is_some_and(|a| uses.refs[a as usize] == 1);
            let own = prim.get("indices").is_some_and(mine)
                && prim
                    .get("attributes")
                    .and_then(Value::as_object)
                    .is_some_and(|a| a.values().all(mine))
                && prim.get("targets").is_none();
            if self.order_for_codec(r, own)? {
                report.primitives_reordered += 1;
            } else {
                report.primitives_kept_in_order += 1;
            }
        }
        let mut done = HashMap::new();
        let mut quantization = false;
        for r in self.primitives() {
            if self.mode(r)? == 4 {
                quantization |= self.quantize_for_codec(r, &mut done)?;
            }
        }
        report.accessors_quantized = done.len();
        if quantization {
            self.require_extension("KHR_mesh_quantization");
        }
        self.prune_detached();
        let plan = self.plan_views()?;
        for p in &plan {
            match p {
                Some(p) => {
                    report.views_compressed += 1;
                    report.decoded_bytes += (p.count * p.stride) as u64;
                    report.compressed_bytes += p.stream.len() as u64;
                }
                None => report.views_plain += 1,
            }
        }
        if report.views_compressed > 0 {
            self.require_extension(EXTENSION);
        }
        self.packed = Some(plan);
        Ok(report)
    }

    /// Adds `name` to `extensionsUsed` and `extensionsRequired` (once).
    pub(crate) fn require_extension(&mut self, name: &str) {
        for key in ["extensionsUsed", "extensionsRequired"] {
            let list = self
                .json
                .entry(key)
                .or_insert_with(|| Value::Array(Vec::new()));
            if let Some(l) = list.as_array_mut()
                && !l.iter().any(|e| e.as_str() == Some(name))
            {
                l.push(Value::from(name));
            }
        }
    }

    fn accessor_uses(&mut self) -> Uses {
        let n = self.array("accessors").len();
        let mut uses = Uses {
            refs: vec![0; n],
            triangle_indices: vec![false; n],
            other_indices: vec![false; n],
        };
        crate::prune::for_each_accessor_ref(&mut self.json, &mut |v| {
            if let Some(i) = v.as_u64().filter(|&i| (i as usize) < n) {
                uses.refs[i as usize] += 1;
            }
        });
        for r in self.primitives() {
            let Ok(prim) = self.primitive(r) else {
                continue;
            };
            let Some(i) = prim.get("indices").and_then(Value::as_u64) else {
                continue;
            };
            let Some(i) = (i as usize).lt(&n).then_some(i as usize) else {
                continue;
            };
            if prim.get("mode").and_then(Value::as_u64).unwrap_or(4) == 4 {
                uses.triangle_indices[i] = true;
            } else {
                uses.other_indices[i] = true;
            }
        }
        uses
    }

    /// Each bufferView's compressed stream, or None where it stays plain; views encode in
    /// parallel, one task each.
    fn plan_views(&mut self) -> Result<Vec<Option<Packed>>> {
        use rayon::prelude::*;
        let uses = self.accessor_uses();
        let jobs: Vec<Option<Job>> = (0..self.array("bufferViews").len())
            .map(|v| self.job(v, &uses))
            .collect::<Result<_>>()?;
        let doc = &*self;
        Ok(jobs
            .into_par_iter()
            .enumerate()
            .map(|(v, job)| job.and_then(|j| j.run(doc, v)))
            .collect())
    }

    /// What view `v` holds, as far as the codecs care.
    fn job(&self, v: usize, uses: &Uses) -> Result<Option<Job>> {
        let place = format!("bufferViews[{v}]");
        let (bytes, stride) = view_bytes(self, v, &place)?;
        if bytes.is_empty() || self.view_holds_image(v) {
            return Ok(None);
        }
        if v >= self.source_views
            && let ViewData::Filtered(f) = &self.new_views[v - self.source_views]
        {
            return Ok(Some(Job::Attributes {
                stride: f.stride,
                filter: Some(f.filter),
            }));
        }
        let on_view: Vec<(usize, &Value)> = self
            .array("accessors")
            .iter()
            .enumerate()
            .filter(|(_, a)| a.get("bufferView").and_then(Value::as_u64) == Some(v as u64))
            .collect();
        if let [(a, acc)] = on_view[..]
            && uses.triangle_indices[a]
            && !uses.other_indices[a]
            && acc.get("byteOffset").and_then(Value::as_u64).unwrap_or(0) == 0
        {
            let e = accessor::read_any(self, a, &place)?;
            if e.bytes.len() == bytes.len()
                && matches!(e.component, ComponentType::U16 | ComponentType::U32)
                && e.count.is_multiple_of(3)
            {
                return Ok(Some(Job::Triangles {
                    size: e.component.size(),
                }));
            }
        }
        let sizes: Vec<usize> = on_view
            .iter()
            .filter_map(|(a, _)| accessor::read_any(self, *a, &place).ok())
            .map(|e| e.element_size())
            .collect();
        let stride = match (stride, &sizes[..]) {
            (Some(s), _) => s,
            (None, [s, rest @ ..]) if rest.iter().all(|x| x == s) => *s,
            _ => return Ok(None),
        };
        let fits = stride > 0
            && stride <= 256
            && stride.is_multiple_of(4)
            && bytes.len().is_multiple_of(stride);
        Ok(fits.then_some(Job::Attributes {
            stride,
            filter: None,
        }))
    }

    fn view_holds_image(&self, v: usize) -> bool {
        self.array("images")
            .iter()
            .any(|i| i.get("bufferView").and_then(Value::as_u64) == Some(v as u64))
    }
}

/// How one view would be compressed.
enum Job {
    Attributes {
        stride: usize,
        filter: Option<Filter>,
    },
    Triangles {
        size: usize,
    },
}

impl Job {
    /// The stream, when the codec takes the data and makes it smaller.
    fn run(self, doc: &Document, v: usize) -> Option<Packed> {
        let (bytes, _) = view_bytes(doc, v, "").ok()?;
        let packed = match self {
            Job::Attributes { stride, filter } => {
                let source = match (&filter, v.checked_sub(doc.source_views)) {
                    (Some(_), Some(k)) => match &doc.new_views[k] {
                        ViewData::Filtered(f) => &f.encoded[..],
                        _ => bytes,
                    },
                    _ => bytes,
                };
                Packed {
                    mode: "ATTRIBUTES",
                    filter,
                    stride,
                    count: bytes.len() / stride,
                    stream: encode_vertices(source, stride),
                }
            }
            Job::Triangles { size } => {
                let indices: Vec<u32> = bytes
                    .chunks_exact(size)
                    .map(|c| match c {
                        [a, b] => u32::from(u16::from_le_bytes([*a, *b])),
                        _ => u32::from_le_bytes([c[0], c[1], c[2], c[3]]),
                    })
                    .collect();
                let vertices = indices.iter().max().map_or(0, |&m| m as usize + 1);
                let (stream, decoded) = encode_triangles(&indices, vertices)?;
                // Only a stream that decodes to exactly these indices will do.
                if decoded != indices {
                    return None;
                }
                Packed {
                    mode: "TRIANGLES",
                    filter: None,
                    stride: size,
                    count: indices.len(),
                    stream,
                }
            }
        };
        (packed.stream.len() < bytes.len()).then_some(packed)
    }
}
