//! Quantized attributes for compressed output, stored through the filters
//! `EXT_meshopt_compression` defines so that the vertex codec sees small integers:
//!
//! | attribute | stored as | filter | bound |
//! |---|---|---|---|
//! | POSITION (float VEC3) | float VEC3 | exponential, [`POSITION_BITS`]-bit mantissa shared per axis | half a step of 2^(e − bits + 1) where 2^e bounds the axis |
//! | NORMAL (float VEC3) | normalized BYTE VEC3, stride 4 (`KHR_mesh_quantization`) | octahedral, [`DIRECTION_BITS`] bits | ≈ 1° |
//! | TANGENT (float VEC4) | normalized BYTE VEC4 (`KHR_mesh_quantization`), w exact | octahedral, [`DIRECTION_BITS`] bits | ≈ 1° |
//! | TEXCOORD_n (float VEC2) | float VEC2 | exponential, [`TEXCOORD_BITS`] bits shared per axis | as POSITION |
//! | COLOR_n (float) | normalized UNSIGNED_BYTE | none | 1/510 |
//!
//! Everything else (the comb, which the bake stores as normalized integers, normal-group
//! IDs, joints, weights, morph targets, animation data) is compressed losslessly. The view's
//! data is what the filter's decoder gives back, so the document holds what a reader reads.

use std::collections::HashMap;

use serde_json::Value;

use crate::accessor::{self, ComponentType};
use crate::document::{Document, Filtered, PrimitiveRef, ViewData};
use crate::edit::{ARRAY_BUFFER, NewAccessor};
use crate::error::Result;
use crate::pack_codec::{Filter, encode_exponential, encode_octahedral, unfilter};

/// Mantissa bits of quantized positions.
pub const POSITION_BITS: i32 = 14;
/// Mantissa bits of quantized texture coordinates.
pub const TEXCOORD_BITS: i32 = 12;
/// Bits of the octahedral coordinates of normals and tangents.
pub const DIRECTION_BITS: i32 = 8;

/// An attribute's quantized form, or None to keep it as it is.
fn quantized(name: &str, e: &accessor::Elements) -> Option<NewAccessor> {
    if e.component != ComponentType::F32 {
        return None;
    }
    let filtered = |component, components, normalized, stride, filter, encoded: Vec<u8>| {
        let data = unfilter(filter, &encoded, stride);
        NewAccessor {
            component,
            components,
            normalized,
            bytes: ViewData::Filtered(Box::new(Filtered {
                data,
                encoded,
                filter,
                stride,
            })),
            min_max: name == "POSITION",
            target: ARRAY_BUFFER,
        }
    };
    let octahedral = |w: bool| {
        let v: Vec<[f32; 4]> = if w {
            e.to_f32::<4>()
        } else {
            e.to_f32::<3>()
                .into_iter()
                .map(|[x, y, z]| [x, y, z, 0.0])
                .collect()
        };
        encode_octahedral(&v, 4, DIRECTION_BITS)
    };
    let exponential = |bits| {
        let n = e.components;
        let floats: Vec<f32> = (0..e.count * n).map(|i| e.component_f32(i)).collect();
        encode_exponential(&floats, 4 * n, bits)
    };
    Some(match (name, e.components) {
        ("POSITION", 3) => filtered(
            ComponentType::F32,
            3,
            false,
            12,
            Filter::Exponential,
            exponential(POSITION_BITS),
        ),
        ("NORMAL", 3) => filtered(
            ComponentType::I8,
            3,
            true,
            4,
            Filter::Octahedral,
            octahedral(false),
        ),
        ("TANGENT", 4) => filtered(
            ComponentType::I8,
            4,
            true,
            4,
            Filter::Octahedral,
            octahedral(true),
        ),
        (t, 2) if t.starts_with("TEXCOORD_") => filtered(
            ComponentType::F32,
            2,
            false,
            8,
            Filter::Exponential,
            exponential(TEXCOORD_BITS),
        ),
        (c, 3 | 4) if c.starts_with("COLOR_") => {
            let v: Vec<[u8; 1]> = (0..e.count * e.components)
                .map(|i| [(e.component_f32(i).clamp(0.0, 1.0) * 255.0).round() as u8])
                .collect();
            let mut a = NewAccessor::u8_norm(&v);
            a.components = e.components;
            a
        }
        _ => return None,
    })
}

impl Document {
    /// Replaces primitive `r`'s float attributes by their quantized forms (the table in the
    /// module documentation); `done` maps accessors already quantized to their replacements,
    /// so a shared accessor is quantized once. Returns whether `KHR_mesh_quantization` is now
    /// needed (a normal or tangent is stored as bytes).
    pub(crate) fn quantize_for_codec(
        &mut self,
        r: PrimitiveRef,
        done: &mut HashMap<usize, usize>,
    ) -> Result<bool> {
        let place = self.place(r);
        let attrs: Vec<(String, usize)> = self
            .primitive(r)?
            .get("attributes")
            .and_then(Value::as_object)
            .into_iter()
            .flatten()
            .filter_map(|(k, v)| Some((k.clone(), v.as_u64()? as usize)))
            .collect();
        let mut needs_extension = false;
        for (name, old) in attrs {
            let new = match done.get(&old) {
                Some(&new) => Some(new),
                None => {
                    let e = accessor::read(self, old, &format!("{place} attributes.{name}"))?;
                    let q = quantized(&name, &e).map(|a| self.push_accessor(a));
                    if let Some(new) = q {
                        done.insert(old, new);
                    }
                    q
                }
            };
            if let Some(new) = new {
                self.set_attribute(r, &name, new)?;
                needs_extension |= name == "NORMAL" || name == "TANGENT";
            }
        }
        Ok(needs_extension)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edit::NewAccessor;
    use serde_json::json;
    use std::path::Path;

    fn doc_with(attr: &str, a: NewAccessor) -> (Document, PrimitiveRef) {
        let Value::Object(json) = json!({"asset": {"version": "2.0"},
            "meshes": [{"primitives": [{"attributes": {}}]}]})
        else {
            unreachable!("object literal")
        };
        let mut d = Document::from_parts(Path::new("q.gltf"), json, vec![]);
        let r = PrimitiveRef {
            mesh: 0,
            primitive: 0,
        };
        let i = d.push_accessor(a);
        d.set_attribute(r, attr, i).expect("set");
        (d, r)
    }

    fn read_back(d: &Document, r: PrimitiveRef, attr: &str) -> Vec<[f32; 4]> {
        let i = d.attribute(r, attr).expect("attr").expect("present");
        let e = accessor::read(d, i, attr).expect("reads");
        (0..e.count)
            .map(|k| {
                let mut v = [0.0; 4];
                for (c, x) in v.iter_mut().enumerate().take(e.components) {
                    *x = e.component_f32(k * e.components + c);
                }
                v
            })
            .collect()
    }

    #[test]
    fn positions_stay_float_within_the_stated_step() {
        let p: Vec<[f32; 3]> = (0..100)
            .map(|i| [i as f32 * 0.013 - 0.5, (i as f32).sin(), 2.0])
            .collect();
        let (mut d, r) = doc_with("POSITION", NewAccessor::f32(&p));
        assert!(!d.quantize_for_codec(r, &mut HashMap::new()).expect("q"));
        let back = read_back(&d, r, "POSITION");
        // |x| < 2^1 per axis (z = 2 needs 2^2): a step of 2^(e − (bits − 1)).
        for (a, b) in p.iter().zip(&back) {
            for k in 0..3 {
                let e = if k == 2 { 2 } else { 1 };
                let step = 2f32.powi(e - (POSITION_BITS - 1));
                assert!((a[k] - b[k]).abs() <= step / 2.0, "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn tangents_become_bytes_with_exact_handedness() {
        let t = vec![[0.6f32, 0.8, 0.0, -1.0], [0.0, 0.0, 1.0, 1.0]];
        let (mut d, r) = doc_with("TANGENT", NewAccessor::f32(&t));
        assert!(d.quantize_for_codec(r, &mut HashMap::new()).expect("q"));
        for (a, b) in t.iter().zip(read_back(&d, r, "TANGENT")) {
            assert_eq!(a[3], b[3]);
            let dot: f32 = (0..3).map(|k| a[k] * b[k]).sum();
            assert!(
                dot > 0.9995_f32.min(1.0_f32.to_radians().cos()),
                "{a:?} {b:?}"
            );
        }
    }
}
