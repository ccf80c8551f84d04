//! The comb bake of Revie, "Implementing Fur Using Deferred Shading", §2.4.1 and Listing 2.7:
//! the painted RGB (a direction in the mesh's local space, [-1, 1] stored as [0, 1]) is
//! Gram-Schmidt-orthonormalized against the vertex normal and expressed in the tangent frame,
//! so the comb follows the surface when the mesh deforms. A (fur length) is carried through.
//!
//! Output `_FUR_COMB` = (x, y, z, length): (x, y, z) the unit tangent-space direction (z ≈ 0),
//! length in [0, 1]. Defined results where the listing would divide by zero:
//! - near gray (|RGB·2−1| ≤ [`GRAY_EPSILON`]): no direction was painted; length 0, direction
//!   (1, 0, 0);
//! - within [`PARALLEL_TOLERANCE`] radians of the normal: nothing is left after Gram-Schmidt;
//!   the comb falls back to the tangent direction (1, 0, 0), length kept.
//!
//! Quantized encodings use the paper's mapping: direction components (x + 1) / 2 and length
//! as is, as normalized unsigned integers.

use glam::{DVec3, Vec4};

use crate::frame::Frame;
use crate::options::{AxisMap, ColorSpace};

/// Decoded directions shorter than this carry no direction (8-bit mid-gray 127 or 128 decodes
/// to |d| = 0.0068 and must count as gray).
pub const GRAY_EPSILON: f64 = 0.01;

/// A comb within this angle (radians) of the normal has no usable tangential part.
pub const PARALLEL_TOLERANCE: f64 = 1e-3;

/// What happened to one vertex's comb.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CombCase {
    /// Regular: projected and expressed in tangent space.
    Combed,
    /// Near gray: length set to 0.
    Gray,
    /// Along the normal: tangent direction used.
    ParallelToNormal,
}

/// sRGB encoding (linear → sRGB), per IEC 61966-2-1.
pub fn linear_to_srgb(c: f64) -> f64 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Decodes COLOR_0 into (object-space direction, not normalized; length). RGBA is clamped to
/// [0, 1] first, as glTF requires of COLOR_0; a subnormal alpha is length 0.
pub fn decode_color(c: Vec4, space: ColorSpace, axes: &AxisMap) -> (DVec3, f64) {
    let ch = |v: f32| {
        let v = f64::from(v).clamp(0.0, 1.0);
        match space {
            ColorSpace::Linear => v,
            ColorSpace::Srgb => linear_to_srgb(v),
        }
    };
    let d = [
        ch(c.x) * 2.0 - 1.0,
        ch(c.y) * 2.0 - 1.0,
        ch(c.z) * 2.0 - 1.0,
    ];
    let d = if axes.is_identity() { d } else { axes.apply(d) };
    // A subnormal length is 0: GPUs flush subnormals, so it would draw as none anyway, and
    // the bake says so ("no fur") rather than counting it as fur.
    let length = if c.w.abs() < f32::MIN_POSITIVE {
        0.0
    } else {
        f64::from(c.w).clamp(0.0, 1.0)
    };
    (DVec3::from_array(d), length)
}

/// Listing 2.7 for one vertex: direction `d` (object space, any length) and `length`.
#[inline]
pub fn bake(d: DVec3, length: f64, frame: &Frame) -> ([f32; 4], CombCase) {
    let mag = d.length();
    if mag.is_nan() || mag <= GRAY_EPSILON {
        return ([1.0, 0.0, 0.0, 0.0], CombCase::Gray);
    }
    let u = d / mag;
    // Gram-Schmidt against the unit normal; what is left has length sin(angle to N).
    let tangential = u - frame.n * u.dot(frame.n);
    let s = tangential.length();
    if s < PARALLEL_TOLERANCE.sin() {
        return ([1.0, 0.0, 0.0, length as f32], CombCase::ParallelToNormal);
    }
    let c = frame.to_tangent(tangential / s);
    (
        [c.x as f32, c.y as f32, c.z as f32, length as f32],
        CombCase::Combed,
    )
}

/// Maps [-1, 1] → [0, 1] (the paper's color mapping).
#[inline]
fn unit(v: f32) -> f32 {
    ((v + 1.0) * 0.5).clamp(0.0, 1.0)
}

/// The paper's [0, 1] mapping scaled to `max` and rounded: direction (x + 1) / 2, length as is.
fn quantize(c: [f32; 4], max: f32) -> [f32; 4] {
    let q = |v: f32| (v * max).round();
    [
        q(unit(c[0])),
        q(unit(c[1])),
        q(unit(c[2])),
        q(c[3].clamp(0.0, 1.0)),
    ]
}

/// `_FUR_COMB` as normalized unsigned shorts.
pub fn encode_u16(c: [f32; 4]) -> [u16; 4] {
    quantize(c, 65535.0).map(|v| v as u16)
}

/// `_FUR_COMB` as normalized unsigned bytes.
pub fn encode_u8(c: [f32; 4]) -> [u8; 4] {
    quantize(c, 255.0).map(|v| v as u8)
}

/// Decodes a normalized-integer `_FUR_COMB` (components already divided by 65535 or 255, as a
/// GPU does for normalized formats) back to direction and length.
pub fn decode_unorm(c: [f32; 4]) -> [f32; 4] {
    pelt_io::contract::decode_comb(c, true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn frame() -> Frame {
        Frame::new(Vec3::Z, Vec4::new(1.0, 0.0, 0.0, 1.0)).0
    }

    #[test]
    fn listing_2_7_on_a_simple_case() {
        // Paint (1, 0, 1)/√2 over normal +Z: the tangential part is +X = tangent direction.
        let (c, case) = bake(DVec3::new(1.0, 0.0, 1.0), 0.5, &frame());
        assert_eq!(case, CombCase::Combed);
        assert!((c[0] - 1.0).abs() < 1e-7 && c[1].abs() < 1e-7 && c[2].abs() < 1e-7);
        assert_eq!(c[3], 0.5);
    }

    #[test]
    fn gray_and_parallel_cases() {
        let (d, l) = decode_color(
            Vec4::new(0.5, 0.5, 0.5, 1.0),
            ColorSpace::Linear,
            &AxisMap::default(),
        );
        assert_eq!(bake(d, l, &frame()), ([1.0, 0.0, 0.0, 0.0], CombCase::Gray));
        let eight_bit_gray = Vec4::new(128.0 / 255.0, 127.0 / 255.0, 128.0 / 255.0, 1.0);
        let (d, l) = decode_color(eight_bit_gray, ColorSpace::Linear, &AxisMap::default());
        assert_eq!(bake(d, l, &frame()).1, CombCase::Gray);
        let (c, case) = bake(DVec3::Z * 0.7, 0.25, &frame());
        assert_eq!(
            (c, case),
            ([1.0, 0.0, 0.0, 0.25], CombCase::ParallelToNormal)
        );
    }

    #[test]
    fn srgb_decoding_recovers_the_painted_value() {
        // A painted 8-bit value 200/255, linearized by an exporter.
        let painted = 200.0 / 255.0;
        let lin = ((painted + 0.055) / 1.055_f64).powf(2.4) as f32;
        let (d, _) = decode_color(
            Vec4::new(lin, lin, lin, 1.0),
            ColorSpace::Srgb,
            &AxisMap::default(),
        );
        assert!((d.x - (painted * 2.0 - 1.0)).abs() < 1e-6);
    }

    #[test]
    fn quantization_round_trips_exact_points() {
        assert_eq!(encode_u16([-1.0, 0.0, 1.0, 1.0]), [0, 32768, 65535, 65535]);
        assert_eq!(encode_u8([-1.0, 1.0, 0.0, 0.5]), [0, 255, 128, 128]);
        let d = decode_unorm([0.0, 1.0, 0.5, 1.0]);
        assert_eq!(d, [-1.0, 1.0, 0.0, 1.0]);
    }
}
