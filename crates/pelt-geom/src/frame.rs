//! The tangent frame a comb is expressed in, as every consumer rebuilds it from the vertex
//! data: N unit, T = normalize(T − N (N·T)) (Gram-Schmidt; glTF only promises T roughly
//! orthogonal), B = cross(N, T) · w with w = ±1 (glTF 2.0 §3.7.2.1). f64 throughout. This is
//! the one rule (Revie Listing 2.7): the bake expresses combs in it, `pelt inspect` and the
//! preview decode them with it, and `comb_object` in shaders/fur_common.wgsl implements the
//! same steps and fallback on the GPU (checked against this module by the preview's tests).

use crate::normals::normalize_f64;
use glam::{DVec3, Vec3, Vec4};

/// Below this length (relative) a tangent has no direction left once projected.
pub const DEGENERATE_TANGENT: f64 = 1e-6;

/// An orthonormal frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Tangent.
    pub t: DVec3,
    /// Bitangent = cross(n, t) · w.
    pub b: DVec3,
    /// Normal.
    pub n: DVec3,
    /// Handedness, exactly ±1.
    pub w: f64,
}

/// A deterministic unit vector perpendicular to unit `n`: the coordinate axis least aligned
/// with `n` (first of x, y, z on ties), projected and normalized.
#[inline]
pub fn perpendicular(n: DVec3) -> DVec3 {
    let a = n.abs();
    let e = if a.x <= a.y && a.x <= a.z {
        DVec3::X
    } else if a.y <= a.z {
        DVec3::Y
    } else {
        DVec3::Z
    };
    (e - n * n.dot(e)).normalize()
}

/// The sign glTF's w stands for: -1 for negative w, +1 otherwise (0 included).
#[inline]
pub fn handedness(w: f32) -> f64 {
    if w < 0.0 { -1.0 } else { 1.0 }
}

impl Frame {
    /// Builds the frame from a normal (any length but zero) and a tangent. Returns the frame and
    /// whether the tangent was degenerate (zero, or along N) and replaced by [`perpendicular`].
    #[inline]
    pub fn new(normal: Vec3, tangent: Vec4) -> (Frame, bool) {
        let n = normalize_f64(normal).unwrap_or(DVec3::Z);
        let t = tangent.truncate().as_dvec3();
        let scale = t.abs().max_element();
        let projected = if scale > 0.0 && scale.is_finite() {
            let ts = t / scale;
            let p = ts - n * n.dot(ts);
            (p.length() > DEGENERATE_TANGENT * ts.length()).then(|| p.normalize())
        } else {
            None
        };
        let degenerate = projected.is_none();
        let t = projected.unwrap_or_else(|| perpendicular(n));
        let w = handedness(tangent.w);
        (
            Frame {
                t,
                b: n.cross(t) * w,
                n,
                w,
            },
            degenerate,
        )
    }

    /// The object-space unit direction of a tangent-space comb (the decoding every renderer
    /// does); the tangent where the comb has no direction (below 1e-6).
    #[inline]
    pub fn comb_direction(&self, c: DVec3) -> DVec3 {
        let d = self.to_object(c);
        let len = d.length();
        if len > 1e-6 { d / len } else { self.t }
    }

    /// Tangent-space coordinates of an object-space vector.
    #[inline]
    pub fn to_tangent(&self, v: DVec3) -> DVec3 {
        DVec3::new(v.dot(self.t), v.dot(self.b), v.dot(self.n))
    }

    /// Object-space vector from tangent-space coordinates (the decoding the renderer does).
    #[inline]
    pub fn to_object(&self, c: DVec3) -> DVec3 {
        self.t * c.x + self.b * c.y + self.n * c.z
    }

    /// The tangent as glTF stores it (xyz unit, w = ±1).
    #[inline]
    pub fn tangent4(&self) -> [f32; 4] {
        [
            self.t.x as f32,
            self.t.y as f32,
            self.t.z as f32,
            self.w as f32,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_orthonormal_and_handed() {
        for w in [1.0f32, -1.0] {
            let (f, bad) = Frame::new(Vec3::new(0.0, 0.0, 2.0), Vec4::new(1.0, 0.0, 0.3, w));
            assert!(!bad);
            assert!((f.t - DVec3::X).length() < 1e-15);
            assert!((f.b - DVec3::Y * f64::from(w)).length() < 1e-15);
            let v = DVec3::new(0.3, -0.4, 0.5);
            assert!((f.to_object(f.to_tangent(v)) - v).length() < 1e-15);
        }
    }

    #[test]
    fn tangent_along_normal_falls_back_to_a_perpendicular() {
        let (f, bad) = Frame::new(Vec3::Y, Vec4::new(0.0, 5.0, 0.0, 1.0));
        assert!(bad);
        assert!(f.t.dot(f.n).abs() < 1e-15 && (f.t.length() - 1.0).abs() < 1e-15);
        let (_, bad) = Frame::new(Vec3::Y, Vec4::ZERO);
        assert!(bad);
    }
}
