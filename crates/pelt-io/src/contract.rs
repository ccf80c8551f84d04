//! The baked format's contract in one place: the names of the attributes pelt writes, how
//! `_FUR_COMB` is stored and decoded, and where the fin records and the tangent frame are
//! defined. The bake writes through it, and `pelt inspect` and the preview read through it;
//! `docs/format.md` describes the same rules for other readers.
//!
//! - `_FUR_COMB`: VEC4, float or normalized byte/short: xyz the comb in the tangent frame
//!   ([`pelt_geom::frame::Frame`]), w the fur length. Normalized unsigned storage maps each
//!   direction component x to (x + 1) / 2 (Revie §2.4.1); [`decode_comb`] undoes it. Signed
//!   normalized storage (what quantizing tools such as glTF-Transform write) holds x as is.
//! - `_NORMAL_GROUP`: SCALAR unsigned short, one 8-bit normal-group ID per vertex.
//! - fin records: [`crate::topology`] ([`crate::topology::FIN_RECORD_SIZE`] bytes each).

use glam::{Vec3, Vec4};

use crate::accessor::{self, ComponentType};
use crate::document::{Document, PrimitiveRef};
use crate::error::Result;

/// The tangent-space comb and fur length.
pub const COMB_ATTRIBUTE: &str = "_FUR_COMB";

/// The normal-group IDs.
pub use crate::topology::NORMAL_GROUP_ATTRIBUTE;

/// A stored `_FUR_COMB` value to direction and length: normalized integers (already divided
/// by 65535 or 255, as a GPU does for normalized formats) have their direction mapped back
/// from [0, 1] to [−1, 1]; floats are as stored.
pub fn decode_comb(c: [f32; 4], normalized: bool) -> [f32; 4] {
    if normalized {
        [c[0] * 2.0 - 1.0, c[1] * 2.0 - 1.0, c[2] * 2.0 - 1.0, c[3]]
    } else {
        c
    }
}

/// The primitive's `_FUR_COMB`, decoded, checked to be VEC4 with `n` values (None when the
/// primitive has none).
pub fn read_comb(doc: &Document, r: PrimitiveRef, n: usize) -> Result<Option<Vec<Vec4>>> {
    let Some(i) = doc.attribute(r, COMB_ATTRIBUTE)? else {
        return Ok(None);
    };
    let place = format!("{} attribute {COMB_ATTRIBUTE}", doc.place(r));
    let e = accessor::read(doc, i, &place)?;
    if e.components != 4 || e.count != n {
        return Err(doc.invalid(
            place,
            format!(
                "must be VEC4 with one value per vertex ({n}), found {} × {}",
                e.ty, e.count
            ),
        ));
    }
    // Signed normalized values are already in [−1, 1]; only unsigned ones are biased.
    let normalized = e.normalized && matches!(e.component, ComponentType::U8 | ComponentType::U16);
    Ok(Some(
        e.to_f32::<4>()
            .into_iter()
            .map(|c| Vec4::from(decode_comb(c, normalized)))
            .collect(),
    ))
}

/// The object-space unit direction of comb `c` at a vertex with normal `n` and tangent `t`
/// (the frame rebuilt by [`pelt_geom::frame::Frame`], f64 inside).
pub fn comb_object(n: Vec3, t: Vec4, c: Vec3) -> Vec3 {
    let (frame, _) = pelt_geom::frame::Frame::new(n, t);
    frame.comb_direction(c.as_dvec3()).as_vec3()
}
