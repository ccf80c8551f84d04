//! The edits a bake makes to a [`Document`]: append accessors (each with its own bufferView,
//! 4-byte aligned elements as glTF requires for vertex attributes), point a primitive's
//! attribute at one, and re-index a primitive whose vertices were split (every attribute and
//! morph target gathered through the same vertex map, min/max recomputed where present).
//! Edits only append: the accessors a primitive stops using are recorded as detached, and
//! [`crate::prune`] removes those nothing else refers to once the bake is done.

use serde_json::{Map, Value, json};

use crate::accessor::{self, ComponentType, Elements};
use crate::document::{Document, PrimitiveRef, ViewData};
use crate::error::Result;

/// bufferView target for vertex attributes.
pub const ARRAY_BUFFER: u32 = 34962;
/// bufferView target for indices.
pub const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// [`NewAccessor::target`] for a bufferView that is neither vertex nor index data.
pub const NO_TARGET: u32 = 0;

/// Data for a new accessor: packed little-endian elements and how to describe them.
#[derive(Debug, Clone, PartialEq)]
pub struct NewAccessor {
    /// Component type.
    pub component: ComponentType,
    /// Components per element (1-4).
    pub components: usize,
    /// Normalized integers.
    pub normalized: bool,
    /// Packed elements (float data is kept as the words it was computed in: no copy).
    pub bytes: ViewData,
    /// Write `min` and `max` (required for POSITION).
    pub min_max: bool,
    /// bufferView target.
    pub target: u32,
}

/// Little-endian bytes of plain numbers (a copy on little-endian targets).
fn le_bytes<T: bytemuck::Pod, const S: usize>(v: &[T], to_le: impl Fn(&T) -> [u8; S]) -> Vec<u8> {
    if cfg!(target_endian = "little") {
        bytemuck::cast_slice(v).to_vec()
    } else {
        v.iter().flat_map(to_le).collect()
    }
}

impl NewAccessor {
    /// A vertex attribute of `components`-vectors.
    fn vectors(
        component: ComponentType,
        components: usize,
        normalized: bool,
        bytes: impl Into<ViewData>,
    ) -> Self {
        Self {
            component,
            components,
            normalized,
            bytes: bytes.into(),
            min_max: false,
            target: ARRAY_BUFFER,
        }
    }

    /// Float vectors, taking ownership: on little-endian targets the vector becomes the
    /// bufferView's data as it is (no copy, no fresh memory).
    pub fn f32_owned<const N: usize>(v: Vec<[f32; N]>) -> Self {
        let words: Vec<u32> = if cfg!(target_endian = "little") {
            bytemuck::allocation::cast_vec::<[f32; N], [u32; N]>(v).into_flattened()
        } else {
            v.as_flattened()
                .iter()
                .map(|x| x.to_bits().to_le())
                .collect()
        };
        Self::vectors(ComponentType::F32, N, false, ViewData::Words(words))
    }

    /// Float vectors.
    pub fn f32<const N: usize>(v: &[[f32; N]]) -> Self {
        let bytes = le_bytes(v.as_flattened(), |x| x.to_le_bytes());
        Self::vectors(ComponentType::F32, N, false, bytes)
    }

    /// Normalized unsigned short vectors.
    pub fn u16_norm<const N: usize>(v: &[[u16; N]]) -> Self {
        let bytes = le_bytes(v.as_flattened(), |x| x.to_le_bytes());
        Self::vectors(ComponentType::U16, N, true, bytes)
    }

    /// Unsigned short vectors, not normalized (integer values such as IDs).
    pub fn u16<const N: usize>(v: &[[u16; N]]) -> Self {
        let bytes = le_bytes(v.as_flattened(), |x| x.to_le_bytes());
        Self::vectors(ComponentType::U16, N, false, bytes)
    }

    /// Normalized unsigned byte vectors.
    pub fn u8_norm<const N: usize>(v: &[[u8; N]]) -> Self {
        Self::vectors(ComponentType::U8, N, true, v.as_flattened().to_vec())
    }

    /// Records an extension reads (fin records: VEC2 UNSIGNED_INT), as little-endian words,
    /// in a bufferView without a target (neither vertex nor index data).
    pub fn records(words: ViewData, components: usize) -> Self {
        Self {
            component: ComponentType::U32,
            components,
            normalized: false,
            bytes: words,
            min_max: false,
            target: NO_TARGET,
        }
    }

    /// Triangle indices: unsigned short when every vertex fits below 65535, else unsigned int.
    pub fn indices(v: &[u32], vertex_count: usize) -> Self {
        let (component, bytes) = if vertex_count <= 65535 {
            let short: Vec<u16> = v.iter().map(|&i| i as u16).collect();
            (ComponentType::U16, le_bytes(&short, |x| x.to_le_bytes()))
        } else {
            (ComponentType::U32, le_bytes(v, |x| x.to_le_bytes()))
        };
        Self {
            component,
            components: 1,
            normalized: false,
            bytes: ViewData::Bytes(bytes),
            min_max: false,
            target: ELEMENT_ARRAY_BUFFER,
        }
    }

    /// Elements of an existing accessor gathered through `map` (new element `i` = old `map[i]`).
    /// A leading run where `map[i] == i` (vertices kept in place by a split) is one copy.
    pub fn gathered(e: &Elements, map: &[u32], min_max: bool) -> Self {
        let size = e.element_size();
        let mut bytes = Vec::with_capacity(map.len() * size);
        let kept = map
            .iter()
            .enumerate()
            .take_while(|&(i, &m)| m as usize == i)
            .count();
        bytes.extend_from_slice(&e.bytes[..kept * size]);
        for &m in &map[kept..] {
            let s = m as usize * size;
            bytes.extend_from_slice(&e.bytes[s..s + size]);
        }
        Self {
            component: e.component,
            components: e.components,
            normalized: e.normalized,
            bytes: ViewData::Bytes(bytes),
            min_max,
            target: ARRAY_BUFFER,
        }
    }

    /// Bytes per element.
    pub fn element_size(&self) -> usize {
        self.components * self.component.size()
    }

    /// Bytes from one element to the next in the data as given (filtered data is laid out
    /// with its filter's stride already).
    fn given_stride(&self) -> usize {
        match &self.bytes {
            ViewData::Filtered(f) => f.stride,
            _ => self.element_size(),
        }
    }

    fn count(&self) -> usize {
        self.bytes.bytes().len() / self.given_stride()
    }

    /// Per-component (min, max) in the accessor's own type, as JSON numbers.
    fn bounds(&self) -> (Vec<Value>, Vec<Value>) {
        let n = self.components;
        let mut lo = vec![f64::INFINITY; n];
        let mut hi = vec![f64::NEG_INFINITY; n];
        if self.component == ComponentType::F32 {
            let mut lo32 = vec![f32::INFINITY; n];
            let mut hi32 = vec![f32::NEG_INFINITY; n];
            for e in self.bytes.bytes().chunks_exact(4 * n) {
                for k in 0..n {
                    let v =
                        f32::from_le_bytes([e[4 * k], e[4 * k + 1], e[4 * k + 2], e[4 * k + 3]]);
                    lo32[k] = lo32[k].min(v);
                    hi32[k] = hi32[k].max(v);
                }
            }
            lo = lo32.into_iter().map(f64::from).collect();
            hi = hi32.into_iter().map(f64::from).collect();
        } else {
            for i in 0..self.count() * n {
                let k = i % n;
                let v = accessor::raw(self.component, self.bytes.bytes(), i);
                lo[k] = lo[k].min(v);
                hi[k] = hi[k].max(v);
            }
        }
        let num = |v: f64| {
            if self.component == ComponentType::F32 {
                json!(v)
            } else {
                json!(v as i64)
            }
        };
        (
            lo.into_iter().map(num).collect(),
            hi.into_iter().map(num).collect(),
        )
    }
}

impl Document {
    /// Appends an accessor (and its bufferView); returns the accessor index.
    pub fn push_accessor(&mut self, a: NewAccessor) -> usize {
        let size = a.element_size();
        let given = a.given_stride();
        let count = a.count();
        let stride = if a.target == ARRAY_BUFFER {
            given.next_multiple_of(4)
        } else {
            given
        };
        let bounds = (a.min_max && count > 0).then(|| a.bounds());
        let data = if stride == given {
            a.bytes
        } else {
            let mut d = vec![0u8; count * stride];
            let src = a.bytes.bytes();
            for (dst, src) in d.chunks_exact_mut(stride).zip(src.chunks_exact(given)) {
                dst[..given].copy_from_slice(src);
            }
            ViewData::Bytes(d)
        };
        let mut view = Map::new();
        view.insert("buffer".into(), json!(0));
        view.insert("byteLength".into(), json!(data.bytes().len()));
        if stride != size {
            view.insert("byteStride".into(), json!(stride));
        }
        if a.target != NO_TARGET {
            view.insert("target".into(), json!(a.target));
        }
        let view_index = self.source_views + self.new_views.len();
        push_to(&mut self.json, "bufferViews", Value::Object(view));
        self.new_views.push(data);

        let mut acc = Map::new();
        acc.insert("bufferView".into(), json!(view_index));
        acc.insert("componentType".into(), json!(a.component.gl()));
        if a.normalized {
            acc.insert("normalized".into(), json!(true));
        }
        acc.insert("count".into(), json!(count));
        acc.insert("type".into(), json!(accessor::type_of(a.components)));
        if let Some((lo, hi)) = bounds {
            acc.insert("min".into(), Value::Array(lo));
            acc.insert("max".into(), Value::Array(hi));
        }
        push_to(&mut self.json, "accessors", Value::Object(acc))
    }

    /// Appends a raw bufferView (4-byte aligned at write time); returns its index.
    pub fn push_view(&mut self, data: impl Into<ViewData>, target: Option<u32>) -> usize {
        let bytes = data.into();
        let mut view = Map::new();
        view.insert("buffer".into(), json!(0));
        view.insert("byteLength".into(), json!(bytes.bytes().len()));
        if let Some(t) = target {
            view.insert("target".into(), json!(t));
        }
        let index = self.source_views + self.new_views.len();
        push_to(&mut self.json, "bufferViews", Value::Object(view));
        self.new_views.push(bytes);
        index
    }

    /// Appends an accessor given as JSON (for layouts [`NewAccessor`] does not cover, such as
    /// sparse ones); returns its index.
    pub fn push_accessor_json(&mut self, accessor: Value) -> usize {
        push_to(&mut self.json, "accessors", accessor)
    }

    /// Points attribute `name` of the primitive at accessor `index`.
    pub fn set_attribute(&mut self, r: PrimitiveRef, name: &str, index: usize) -> Result<()> {
        let place = self.place(r);
        let prim = self.primitive_checked(r)?;
        let attrs = prim
            .entry("attributes")
            .or_insert_with(|| Value::Object(Map::new()));
        match attrs.as_object_mut() {
            Some(a) => {
                let old = a.insert(name.to_owned(), json!(index));
                if let Some(old) = old.as_ref().and_then(Value::as_u64) {
                    self.detached.push(old as usize);
                }
                Ok(())
            }
            None => Err(self.invalid(place, "attributes is not an object")),
        }
    }

    /// Removes attribute `name` of the primitive (its accessor becomes a candidate for
    /// [`Document::prune_detached`]); returns the accessor it named.
    pub fn remove_attribute(&mut self, r: PrimitiveRef, name: &str) -> Result<Option<usize>> {
        let place = self.place(r);
        let prim = self.primitive_checked(r)?;
        let old = match prim.get_mut("attributes").and_then(Value::as_object_mut) {
            Some(a) => a.shift_remove(name),
            None => return Err(self.invalid(place, "attributes is not an object")),
        };
        let old = old.as_ref().and_then(Value::as_u64).map(|i| i as usize);
        self.detached.extend(old);
        Ok(old)
    }

    /// Marks accessors as no longer used by an edit (skins, animations, morph targets an edit
    /// removed): [`Document::prune_detached`] drops those nothing refers to any more.
    pub fn detach_accessors(&mut self, indices: impl IntoIterator<Item = usize>) {
        self.detached.extend(indices);
    }

    /// Re-indexes a primitive after a vertex split: new vertex i copies old vertex `map[i]` in
    /// every attribute and morph target, and `indices` (into the new vertices) replace the old.
    /// Attributes named in `replaced` are dropped, not gathered: the caller sets them anew.
    pub fn remap_primitive(
        &mut self,
        r: PrimitiveRef,
        map: &[u32],
        indices: &[u32],
        replaced: &[&str],
    ) -> Result<()> {
        let place = self.place(r);
        let prim = self.primitive(r)?.clone();
        let mut attrs = prim
            .get("attributes")
            .and_then(Value::as_object)
            .cloned()
            .unwrap_or_default();
        attrs.retain(|name, _| !replaced.contains(&name.as_str()));
        for (name, v) in attrs.iter_mut() {
            let old = v.as_u64().ok_or_else(|| {
                self.invalid(
                    format!("{place} attributes.{name}"),
                    "not an accessor index",
                )
            })? as usize;
            *v = json!(self.regather(old, map, &format!("{place} attributes.{name}"))?);
        }
        let mut targets = prim
            .get("targets")
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default();
        for (t, target) in targets.iter_mut().enumerate() {
            if let Some(obj) = target.as_object_mut() {
                for (name, v) in obj.iter_mut() {
                    let tp = format!("{place} targets[{t}].{name}");
                    let old = v
                        .as_u64()
                        .ok_or_else(|| self.invalid(&tp, "not an accessor index"))?
                        as usize;
                    *v = json!(self.regather(old, map, &tp)?);
                }
            }
        }
        let idx = self.push_accessor(NewAccessor::indices(indices, map.len()));
        // Everything the primitive used before is now detached from it.
        let old_targets = prim.get("targets").and_then(Value::as_array);
        let old = prim
            .get("attributes")
            .and_then(Value::as_object)
            .into_iter()
            .chain(
                old_targets
                    .into_iter()
                    .flatten()
                    .filter_map(Value::as_object),
            )
            .flat_map(|o| o.values())
            .chain(prim.get("indices"));
        self.detached
            .extend(old.filter_map(Value::as_u64).map(|a| a as usize));
        let prim = self.primitive_checked(r)?;
        prim.insert("attributes".into(), Value::Object(attrs));
        if !targets.is_empty() {
            prim.insert("targets".into(), Value::Array(targets));
        }
        prim.insert("indices".into(), json!(idx));
        Ok(())
    }

    pub(crate) fn primitive_checked(&mut self, r: PrimitiveRef) -> Result<&mut Map<String, Value>> {
        let err = self.invalid(self.place(r), "primitive is not a JSON object");
        self.primitive_mut(r).ok_or(err)
    }

    fn regather(&mut self, old: usize, map: &[u32], place: &str) -> Result<usize> {
        let e = accessor::read(self, old, place)?;
        if let Some(&bad) = map.iter().find(|&&m| m as usize >= e.count) {
            return Err(self.invalid(
                format!("{place} (accessor {old})"),
                format!("has {} elements, vertex {bad} is referenced", e.count),
            ));
        }
        let had_bounds = self
            .array("accessors")
            .get(old)
            .is_some_and(|a| a.get("min").is_some() || a.get("max").is_some());
        Ok(self.push_accessor(NewAccessor::gathered(&e, map, had_bounds)))
    }
}

pub(crate) fn push_to(json: &mut Map<String, Value>, key: &str, v: Value) -> usize {
    let arr = json.entry(key).or_insert_with(|| Value::Array(Vec::new()));
    if !arr.is_array() {
        *arr = Value::Array(Vec::new());
    }
    match arr.as_array_mut() {
        Some(a) => {
            a.push(v);
            a.len() - 1
        }
        None => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn owned_floats_store_the_same_bytes_as_copied_ones() {
        let v = vec![[1.0f32, -2.5, 3.25e-9, f32::MAX], [0.0, -0.0, 7.0, 1e20]];
        let copied = NewAccessor::f32(&v);
        let owned = NewAccessor::f32_owned(v.clone());
        assert!(matches!(owned.bytes, ViewData::Words(_)));
        assert_eq!(copied.bytes.bytes(), owned.bytes.bytes());
        assert_eq!(owned.count(), 2);
        assert_eq!(copied.bounds(), owned.bounds());
        assert_eq!(owned.bytes.bytes()[..4], 1.0f32.to_le_bytes());
    }
}
