//! Accessor reads (glTF 2.0 §3.6): every component type, `normalized` integers, interleaved
//! strides, accessors without a bufferView and sparse substitution. Every range is checked in
//! u64 against the buffer's real bytes before anything is allocated.

use rayon::prelude::*;
use std::borrow::Cow;

use serde_json::Value;

use crate::document::Document;
use crate::error::Result;

/// glTF component types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ComponentType {
    /// 5120
    I8,
    /// 5121
    U8,
    /// 5122
    I16,
    /// 5123
    U16,
    /// 5125
    U32,
    /// 5126
    F32,
}

impl ComponentType {
    /// From the glTF enum value.
    pub fn from_gl(v: u64) -> Option<Self> {
        Some(match v {
            5120 => Self::I8,
            5121 => Self::U8,
            5122 => Self::I16,
            5123 => Self::U16,
            5125 => Self::U32,
            5126 => Self::F32,
            _ => return None,
        })
    }

    /// The glTF enum value.
    pub fn gl(self) -> u32 {
        match self {
            Self::I8 => 5120,
            Self::U8 => 5121,
            Self::I16 => 5122,
            Self::U16 => 5123,
            Self::U32 => 5125,
            Self::F32 => 5126,
        }
    }

    /// Bytes per component.
    pub fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::U32 | Self::F32 => 4,
        }
    }

    /// Name for reports: `float`, `unsigned byte`, …
    pub fn name(self) -> &'static str {
        match self {
            Self::I8 => "byte",
            Self::U8 => "unsigned byte",
            Self::I16 => "short",
            Self::U16 => "unsigned short",
            Self::U32 => "unsigned int",
            Self::F32 => "float",
        }
    }
}

/// Components per element for a glTF `type`.
pub fn components_of(ty: &str) -> Option<usize> {
    Some(match ty {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" => 4,
        "MAT2" => 4,
        "MAT3" => 9,
        "MAT4" => 16,
        _ => return None,
    })
}

/// The glTF `type` for a component count of a vector.
pub fn type_of(components: usize) -> &'static str {
    match components {
        1 => "SCALAR",
        2 => "VEC2",
        3 => "VEC3",
        _ => "VEC4",
    }
}

/// An accessor's elements, tightly packed, sparse values applied. The bytes are borrowed from
/// the document when they already lie there packed.
#[derive(Debug, Clone, PartialEq)]
pub struct Elements<'d> {
    /// Component type.
    pub component: ComponentType,
    /// Components per element.
    pub components: usize,
    /// The `type` string.
    pub ty: String,
    /// Whether integers are normalized.
    pub normalized: bool,
    /// Element count.
    pub count: usize,
    /// `count * components * component.size()` bytes.
    pub bytes: Cow<'d, [u8]>,
}

impl Elements<'_> {
    /// Bytes per element.
    pub fn element_size(&self) -> usize {
        self.components * self.component.size()
    }

    /// Component `i` (flat index) as f32, applying glTF's normalization rules.
    #[inline]
    pub fn component_f32(&self, i: usize) -> f32 {
        decode(self.component, self.normalized, &self.bytes, i)
    }

    /// Elements as `[f32; N]` (N must equal the component count).
    pub fn to_f32<const N: usize>(&self) -> Vec<[f32; N]> {
        self.to_vec::<N, [f32; N]>()
    }

    /// Elements as `T` made from `[f32; N]` (N must equal the component count), decoded in
    /// parallel straight into their final vector.
    pub fn to_vec<const N: usize, T: From<[f32; N]> + Send>(&self) -> Vec<T> {
        debug_assert_eq!(N, self.components);
        let layout = Layout {
            stride: self.element_size(),
            count: self.count,
        };
        decode_vec::<N, T>(self.component, self.normalized, &self.bytes, layout)
    }
}

/// Where elements lie in a byte slice: element `k` starts at `k * stride`.
#[derive(Clone, Copy)]
struct Layout {
    stride: usize,
    count: usize,
}

/// Decodes `layout.count` elements of `N` components of type `c` from `b`, in parallel.
fn decode_vec<const N: usize, T: From<[f32; N]> + Send>(
    c: ComponentType,
    n: bool,
    b: &[u8],
    layout: Layout,
) -> Vec<T> {
    match c {
        ComponentType::F32 => map_elements::<N, 4, T>(b, layout, f32::from_le_bytes),
        ComponentType::U8 => {
            map_elements::<N, 1, T>(b, layout, |x| normalize(c, n, f64::from(x[0])))
        }
        ComponentType::I8 => {
            map_elements::<N, 1, T>(b, layout, |x| normalize(c, n, f64::from(x[0] as i8)))
        }
        ComponentType::U16 => map_elements::<N, 2, T>(b, layout, |x| {
            normalize(c, n, f64::from(u16::from_le_bytes(x)))
        }),
        ComponentType::I16 => map_elements::<N, 2, T>(b, layout, |x| {
            normalize(c, n, f64::from(i16::from_le_bytes(x)))
        }),
        ComponentType::U32 => map_elements::<N, 4, T>(b, layout, |x| {
            normalize(c, n, f64::from(u32::from_le_bytes(x)))
        }),
    }
}

/// Elements per parallel task when decoding.
const DECODE_CHUNK: usize = 16384;

/// Decodes elements of `N` components of `S` bytes each with `f`, in parallel: packed ones as
/// exact chunks, interleaved ones (a bufferView's byteStride) straight from the view, without
/// gathering them into a packed copy first.
#[inline]
fn map_elements<const N: usize, const S: usize, T: From<[f32; N]> + Send>(
    b: &[u8],
    layout: Layout,
    f: impl Fn([u8; S]) -> f32 + Sync,
) -> Vec<T> {
    let element = |e: &[u8]| {
        T::from(std::array::from_fn(|k| {
            f(std::array::from_fn(|j| e[k * S + j]))
        }))
    };
    let min = pelt_geom::task_len(layout.count, DECODE_CHUNK);
    if layout.stride == N * S {
        return b[..layout.count * N * S]
            .par_chunks_exact(N * S)
            .with_min_len(min)
            .map(element)
            .collect();
    }
    (0..layout.count)
        .into_par_iter()
        .with_min_len(min)
        .map(|k| element(&b[k * layout.stride..k * layout.stride + N * S]))
        .collect()
}

/// Component `i` of packed little-endian `b` as its raw value (integers not normalized).
#[inline]
pub fn raw(c: ComponentType, b: &[u8], i: usize) -> f64 {
    match c {
        ComponentType::F32 => f64::from(f32::from_le_bytes([
            b[4 * i],
            b[4 * i + 1],
            b[4 * i + 2],
            b[4 * i + 3],
        ])),
        ComponentType::U8 => f64::from(b[i]),
        ComponentType::I8 => f64::from(b[i] as i8),
        ComponentType::U16 => f64::from(u16::from_le_bytes([b[2 * i], b[2 * i + 1]])),
        ComponentType::I16 => f64::from(i16::from_le_bytes([b[2 * i], b[2 * i + 1]])),
        ComponentType::U32 => f64::from(u32::from_le_bytes([
            b[4 * i],
            b[4 * i + 1],
            b[4 * i + 2],
            b[4 * i + 3],
        ])),
    }
}

/// Component `i` as f32 with glTF's normalization rules (§3.11) where `normalized`.
#[inline]
fn decode(c: ComponentType, normalized: bool, b: &[u8], i: usize) -> f32 {
    normalize(c, normalized, raw(c, b, i))
}

/// A raw component value as f32, with glTF's normalization rules where `normalized`.
#[inline]
fn normalize(c: ComponentType, normalized: bool, v: f64) -> f32 {
    if !normalized {
        return v as f32;
    }
    match c {
        ComponentType::U8 => (v / 255.0) as f32,
        ComponentType::I8 => (v / 127.0).max(-1.0) as f32,
        ComponentType::U16 => (v / 65535.0) as f32,
        ComponentType::I16 => (v / 32767.0).max(-1.0) as f32,
        ComponentType::U32 | ComponentType::F32 => v as f32,
    }
}

/// A checked view of `bufferViews[index]` (a source view, or one added by an edit):
/// (the view's bytes, byteStride).
pub(crate) fn view_bytes<'d>(
    doc: &'d Document,
    index: usize,
    place: &str,
) -> Result<(&'d [u8], Option<usize>)> {
    let views = doc.array("bufferViews");
    if index >= doc.source_views && index < views.len() {
        // A view added by an edit: its bytes live in the document, already checked.
        let stride = views[index]
            .get("byteStride")
            .and_then(Value::as_u64)
            .map(|s| s as usize);
        return Ok((doc.new_views[index - doc.source_views].bytes(), stride));
    }
    let v = views.get(index).ok_or_else(|| {
        doc.invalid(
            place,
            format!(
                "bufferView {index} does not exist ({} defined)",
                views.len()
            ),
        )
    })?;
    let vplace = format!("{place} bufferViews[{index}]");
    let buffer =
        uint(v, "buffer").ok_or_else(|| doc.invalid(&vplace, "buffer is missing"))? as usize;
    let data = doc
        .buffers
        .get(buffer)
        .ok_or_else(|| doc.invalid(&vplace, format!("buffer {buffer} does not exist")))?;
    let offset = opt_uint(doc, v, "byteOffset", &vplace)?.unwrap_or(0);
    let length =
        uint(v, "byteLength").ok_or_else(|| doc.invalid(&vplace, "byteLength is missing"))?;
    let end = offset
        .checked_add(length)
        .filter(|&e| e <= data.len() as u64)
        .ok_or_else(|| {
            doc.invalid(
                &vplace,
                format!(
                    "bytes {offset}..{offset}+{length} exceed buffer {buffer} ({} bytes)",
                    data.len()
                ),
            )
        })?;
    let stride = match v.get("byteStride") {
        None => None,
        Some(s) => Some(
            s.as_u64()
                .filter(|&s| (4..=252).contains(&s))
                .ok_or_else(|| doc.invalid(&vplace, format!("byteStride {s} is outside 4..=252")))?
                as usize,
        ),
    };
    Ok((&data[offset as usize..end as usize], stride))
}

fn uint(v: &Value, key: &str) -> Option<u64> {
    v.get(key).and_then(Value::as_u64)
}

/// An optional non-negative integer property: absent is None, present but not such an
/// integer (`-1`, `1.5`, `"3"`, `null`) is an error, never a silent default.
fn opt_uint(doc: &Document, v: &Value, key: &str, place: &str) -> Result<Option<u64>> {
    match v.get(key) {
        None => Ok(None),
        Some(x) => x
            .as_u64()
            .map(Some)
            .ok_or_else(|| doc.invalid(place, format!("{key} {x} is not a non-negative integer"))),
    }
}

/// Checks that `count` elements of `elem` bytes, `stride` apart from `offset`, lie inside the
/// `len` bytes of their bufferView.
fn check_span(
    doc: &Document,
    place: &str,
    len: usize,
    offset: u64,
    stride: usize,
    count: u64,
    elem: usize,
) -> Result<()> {
    let need = (count - 1)
        .checked_mul(stride as u64)
        .and_then(|x| x.checked_add(offset))
        .and_then(|x| x.checked_add(elem as u64));
    match need {
        Some(n) if n <= len as u64 => Ok(()),
        _ => Err(doc.invalid(
            place,
            format!(
                "{count} elements of {elem} bytes (stride {stride}, offset {offset}) need more \
                 than the {len} bytes of its bufferView"
            ),
        )),
    }
}

/// `count` packed elements of `elem` bytes from `offset` in `bytes`, checked to lie inside.
fn packed<'d>(
    doc: &Document,
    place: &str,
    bytes: &'d [u8],
    offset: u64,
    count: u64,
    elem: usize,
) -> Result<&'d [u8]> {
    check_span(doc, place, bytes.len(), offset, elem, count, elem)?;
    let offset = offset as usize;
    Ok(&bytes[offset..offset + count as usize * elem])
}

/// Reads accessor `index` into packed elements. `place` prefixes errors (e.g. the attribute).
pub fn read<'d>(doc: &'d Document, index: usize, place: &str) -> Result<Elements<'d>> {
    finish(doc, locate(doc, index, place)?)
}

/// [`read`] that also takes float `MAT4` accessors (inverse bind matrices); used to check an
/// accessor's bounds before the `gltf` crate's readers walk it.
pub fn read_any<'d>(doc: &'d Document, index: usize, place: &str) -> Result<Elements<'d>> {
    finish(doc, locate_with(doc, index, place, true)?)
}

/// An accessor checked against its bufferView, not yet copied or decoded ([`locate`]).
pub struct Located<'d> {
    place: String,
    /// Component type.
    pub component: ComponentType,
    /// Components per element.
    pub components: usize,
    /// The `type` string.
    pub ty: String,
    /// Whether integers are normalized.
    pub normalized: bool,
    /// Element count.
    pub count: usize,
    /// Bytes per element.
    elem: usize,
    /// `byteOffset` within the bufferView.
    offset: usize,
    /// The bufferView's bytes and the element stride (every element checked to lie inside);
    /// None without a bufferView (zeros, then sparse).
    data: Option<(&'d [u8], usize)>,
    sparse: Option<&'d Value>,
}

/// Checks accessor `index` against its bufferView without copying or decoding it, so a caller
/// can look at its type first and then [`Located::decode`] it. `place` prefixes errors.
pub fn locate<'d>(doc: &'d Document, index: usize, place: &str) -> Result<Located<'d>> {
    locate_with(doc, index, place, false)
}

fn locate_with<'d>(
    doc: &'d Document,
    index: usize,
    place: &str,
    float_mat4: bool,
) -> Result<Located<'d>> {
    let accessors = doc.array("accessors");
    let place = format!("{place} (accessor {index})");
    let a = accessors.get(index).ok_or_else(|| {
        doc.invalid(
            &place,
            format!(
                "accessor {index} does not exist ({} defined)",
                accessors.len()
            ),
        )
    })?;
    let component = uint(a, "componentType")
        .and_then(ComponentType::from_gl)
        .ok_or_else(|| doc.invalid(&place, "componentType is missing or invalid"))?;
    let ty = a
        .get("type")
        .and_then(Value::as_str)
        .unwrap_or("")
        .to_owned();
    let components =
        components_of(&ty).ok_or_else(|| doc.invalid(&place, format!("type {ty:?} is invalid")))?;
    if ty.starts_with("MAT") && !(float_mat4 && ty == "MAT4" && component == ComponentType::F32) {
        return Err(doc.invalid(
            &place,
            format!("matrix accessors ({ty}) are not vertex data pelt reads"),
        ));
    }
    let normalized = a
        .get("normalized")
        .and_then(Value::as_bool)
        .unwrap_or(false);
    let count = uint(a, "count")
        .filter(|&c| c >= 1)
        .ok_or_else(|| doc.invalid(&place, "count is missing or zero"))?;
    let elem = components * component.size();
    let offset = opt_uint(doc, a, "byteOffset", &place)?.unwrap_or(0);
    if !offset.is_multiple_of(component.size() as u64) {
        return Err(doc.invalid(
            &place,
            format!("byteOffset {offset} is not a multiple of the component size"),
        ));
    }
    let data = match opt_uint(doc, a, "bufferView", &place)? {
        Some(v) => {
            let (data, stride) = view_bytes(doc, v as usize, &place)?;
            let stride = stride.unwrap_or(elem);
            if stride < elem {
                return Err(doc.invalid(
                    &place,
                    format!("byteStride {stride} is smaller than an element ({elem} bytes)"),
                ));
            }
            check_span(doc, &place, data.len(), offset, stride, count, elem)?;
            Some((data, stride))
        }
        None => {
            // No data: zeros (then sparse). Bounded by the asset's real size so a lying count
            // cannot make us allocate without limit.
            let want = count.saturating_mul(elem as u64);
            let limit = 64 * doc.real_bytes() + (1 << 20);
            if want > limit {
                return Err(doc.invalid(&place, format!("count {count} without a bufferView would need {want} bytes; the asset holds {}", doc.real_bytes())));
            }
            None
        }
    };
    Ok(Located {
        place,
        component,
        components,
        ty,
        normalized,
        // Both fit: the span check or the size limit above bounds them.
        count: count as usize,
        elem,
        offset: offset as usize,
        data,
        sparse: a.get("sparse"),
    })
}

/// The located accessor as packed elements: borrowed when packed in its view, copied out when
/// interleaved, zeros without a view; sparse values applied.
fn finish<'d>(doc: &Document, l: Located<'d>) -> Result<Elements<'d>> {
    let (count, elem, offset) = (l.count, l.elem, l.offset);
    let mut bytes = match l.data {
        Some((data, stride)) if stride == elem => {
            Cow::Borrowed(&data[offset..offset + count * elem])
        }
        Some((data, stride)) => {
            let mut out = Vec::with_capacity(count * elem);
            for e in 0..count {
                let s = offset + e * stride;
                out.extend_from_slice(&data[s..s + elem]);
            }
            Cow::Owned(out)
        }
        None => Cow::Owned(vec![0u8; count * elem]),
    };
    if let Some(sparse) = l.sparse {
        apply_sparse(doc, &l.place, sparse, count as u64, elem, bytes.to_mut())?;
    }
    Ok(Elements {
        component: l.component,
        components: l.components,
        ty: l.ty,
        normalized: l.normalized,
        count,
        bytes,
    })
}

fn apply_sparse(
    doc: &Document,
    place: &str,
    sparse: &Value,
    count: u64,
    elem: usize,
    out: &mut [u8],
) -> Result<()> {
    let sp = format!("{place} sparse");
    let n = uint(sparse, "count")
        .filter(|&n| n >= 1 && n <= count)
        .ok_or_else(|| {
            doc.invalid(
                &sp,
                format!("sparse count is missing or outside 1..={count}"),
            )
        })?;
    let idx = sparse
        .get("indices")
        .ok_or_else(|| doc.invalid(&sp, "indices missing"))?;
    let val = sparse
        .get("values")
        .ok_or_else(|| doc.invalid(&sp, "values missing"))?;
    let ict = uint(idx, "componentType")
        .and_then(ComponentType::from_gl)
        .filter(|c| {
            matches!(
                c,
                ComponentType::U8 | ComponentType::U16 | ComponentType::U32
            )
        })
        .ok_or_else(|| {
            doc.invalid(
                &sp,
                "indices componentType must be an unsigned integer type",
            )
        })?;
    let iview =
        uint(idx, "bufferView").ok_or_else(|| doc.invalid(&sp, "indices bufferView missing"))?;
    let vview =
        uint(val, "bufferView").ok_or_else(|| doc.invalid(&sp, "values bufferView missing"))?;
    let (ib, _) = view_bytes(doc, iview as usize, &format!("{sp} indices"))?;
    let ibytes = packed(
        doc,
        &format!("{sp} indices"),
        ib,
        opt_uint(doc, idx, "byteOffset", &sp)?.unwrap_or(0),
        n,
        ict.size(),
    )?;
    let (vb, _) = view_bytes(doc, vview as usize, &format!("{sp} values"))?;
    let vbytes = packed(
        doc,
        &format!("{sp} values"),
        vb,
        opt_uint(doc, val, "byteOffset", &sp)?.unwrap_or(0),
        n,
        elem,
    )?;
    let mut last: Option<u64> = None;
    for k in 0..n as usize {
        let i = u64::from(read_index(ict, ibytes, k));
        if i >= count || last.is_some_and(|l| i <= l) {
            return Err(doc.invalid(
                &sp,
                format!("index {k} is {i}: sparse indices must increase and stay below {count}"),
            ));
        }
        last = Some(i);
        let i = i as usize;
        out[i * elem..(i + 1) * elem].copy_from_slice(&vbytes[k * elem..(k + 1) * elem]);
    }
    Ok(())
}

#[inline]
fn read_index(c: ComponentType, b: &[u8], k: usize) -> u32 {
    match c {
        ComponentType::U8 => u32::from(b[k]),
        ComponentType::U16 => u32::from(u16::from_le_bytes([b[2 * k], b[2 * k + 1]])),
        _ => u32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]]),
    }
}

/// Reads a float vector attribute with `N` components (any component type, normalized or not).
pub fn read_vec<const N: usize>(
    doc: &Document,
    index: usize,
    place: &str,
) -> Result<Vec<[f32; N]>> {
    read_vec_as::<N, [f32; N]>(doc, index, place)
}

/// Reads a float vector attribute with `N` components as `T` (see [`read_vec`]).
pub fn read_vec_as<const N: usize, T: From<[f32; N]> + Send>(
    doc: &Document,
    index: usize,
    place: &str,
) -> Result<Vec<T>> {
    let located = locate(doc, index, place)?;
    if located.components != N {
        return Err(doc.invalid(
            format!("{place} (accessor {index})"),
            format!("type is {}, expected {}", located.ty, type_of(N)),
        ));
    }
    located.decode::<N, T>(doc)
}

impl Located<'_> {
    /// The elements as `T` made from `[f32; N]` (N must equal [`Located::components`]),
    /// decoded in parallel: interleaved ones straight out of the bufferView, the rest through
    /// [`Elements`] (packed views are borrowed; sparse values applied).
    pub fn decode<const N: usize, T: From<[f32; N]> + Send>(
        self,
        doc: &Document,
    ) -> Result<Vec<T>> {
        debug_assert_eq!(N, self.components);
        if let Located {
            data: Some((data, stride)),
            sparse: None,
            ..
        } = self
            && stride != self.elem
        {
            let layout = Layout {
                stride,
                count: self.count,
            };
            return Ok(decode_vec::<N, T>(
                self.component,
                self.normalized,
                &data[self.offset..],
                layout,
            ));
        }
        Ok(finish(doc, self)?.to_vec::<N, T>())
    }
}

/// Reads an index accessor (SCALAR unsigned byte, short or int, not normalized).
pub fn read_indices(doc: &Document, index: usize, place: &str) -> Result<Vec<u32>> {
    let e = read(doc, index, place)?;
    let ok = e.components == 1
        && !e.normalized
        && matches!(
            e.component,
            ComponentType::U8 | ComponentType::U16 | ComponentType::U32
        );
    if !ok {
        return Err(doc.invalid(
            format!("{place} (accessor {index})"),
            format!(
                "indices must be SCALAR unsigned integers, found {} {}",
                e.ty,
                e.component.name()
            ),
        ));
    }
    let b = &*e.bytes;
    Ok(match e.component {
        ComponentType::U8 => b
            .par_iter()
            .with_min_len(pelt_geom::task_len(e.count, DECODE_CHUNK))
            .map(|&i| u32::from(i))
            .collect(),
        ComponentType::U16 => b
            .par_chunks_exact(2)
            .with_min_len(pelt_geom::task_len(e.count, DECODE_CHUNK))
            .map(|i| u32::from(u16::from_le_bytes([i[0], i[1]])))
            .collect(),
        _ => b
            .par_chunks_exact(4)
            .with_min_len(pelt_geom::task_len(e.count, DECODE_CHUNK))
            .map(|i| u32::from_le_bytes([i[0], i[1], i[2], i[3]]))
            .collect(),
    })
}
