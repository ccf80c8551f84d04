//! Linear blend skinning (glTF 2.0 §3.7.3.3) and morph targets (§3.7.2.2) on the CPU: each
//! vertex is moved by the weighted sum of its joints' matrices. Positions take the matrix,
//! tangents its upper 3×3 (then renormalized, w kept), normals its cofactor matrix (the
//! inverse transpose up to scale, defined even where the blend is singular; its sign follows
//! the determinant so mirrored joints keep normals outward). The preview's skinning pass
//! (`shaders/skin.wgsl`) does the same arithmetic.

use glam::{Mat3, Mat4, Vec3, Vec4};

/// One joint set (JOINTS_n with WEIGHTS_n) per vertex.
#[derive(Debug, Clone, Default)]
pub struct Influences {
    /// Joint indices, four per vertex per set.
    pub joints: Vec<Vec<[u16; 4]>>,
    /// Weights matching `joints`.
    pub weights: Vec<Vec<[f32; 4]>>,
}

/// What skinning found in the weights.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct WeightStats {
    /// Vertices whose weights did not sum to 1 (within 1e-3) and were normalized.
    pub normalized: usize,
    /// Vertices with no weight at all (left where the mesh node puts them).
    pub unweighted: usize,
}

/// A vertex's joint that does not exist: (vertex, set, joint index).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BadJoint {
    /// Vertex.
    pub vertex: usize,
    /// JOINTS_n set.
    pub set: usize,
    /// The joint index named.
    pub joint: u16,
}

impl Influences {
    /// The first joint index (with any weight) beyond `joints` joints.
    pub fn bad_joint(&self, joints: usize) -> Option<BadJoint> {
        self.joints.iter().enumerate().find_map(|(set, js)| {
            js.iter().enumerate().find_map(|(vertex, j)| {
                j.iter()
                    .find(|&&j| usize::from(j) >= joints)
                    .map(|&joint| BadJoint { vertex, set, joint })
            })
        })
    }

    /// The blend matrix of vertex `v` (None when it has no weight), and whether its weights
    /// had to be normalized.
    pub fn blend(&self, v: usize, mats: &[Mat4]) -> (Option<Mat4>, bool) {
        let mut sum = 0.0f32;
        let mut m = Mat4::ZERO;
        for (js, ws) in self.joints.iter().zip(&self.weights) {
            for (&j, &w) in js[v].iter().zip(&ws[v]) {
                if w != 0.0 {
                    sum += w;
                    m += mats[usize::from(j)] * w;
                }
            }
        }
        if sum <= 0.0 || !sum.is_finite() {
            return (None, false);
        }
        let off = (sum - 1.0).abs() > 1e-3;
        (Some(if off { m * (1.0 / sum) } else { m }), off)
    }
}

/// A vertex moved by matrix `m`: position, unit normal, tangent (xyz unit, w kept).
pub fn transform(m: &Mat4, p: Vec3, n: Vec3, t: Vec4) -> (Vec3, Vec3, Vec4) {
    let m3 = Mat3::from_mat4(*m);
    let cof = Mat3::from_cols(
        m3.y_axis.cross(m3.z_axis),
        m3.z_axis.cross(m3.x_axis),
        m3.x_axis.cross(m3.y_axis),
    );
    let sign = if m3.determinant() < 0.0 { -1.0 } else { 1.0 };
    let n2 = (cof * n * sign).normalize_or(n);
    let t2 = (m3 * t.truncate()).normalize_or(t.truncate());
    (m.transform_point3(p), n2, t2.extend(t.w))
}

/// Morph targets added to a vertex table: `base += Σ w_k · target_k` for every target with a
/// non-zero weight (targets without the attribute add nothing).
pub fn morph(base: &mut [Vec3], targets: &[Option<Vec<Vec3>>], weights: &[f32]) {
    for (t, &w) in targets.iter().zip(weights) {
        if let (Some(t), true) = (t, w != 0.0) {
            for (b, d) in base.iter_mut().zip(t) {
                *b += *d * w;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_stay_perpendicular_under_non_uniform_scale_and_mirroring() {
        for m in [
            Mat4::from_scale(Vec3::new(3.0, 1.0, 0.5)),
            Mat4::from_scale(Vec3::new(-1.0, 2.0, 1.0)),
            Mat4::from_rotation_z(0.7) * Mat4::from_scale(Vec3::new(1.0, 4.0, 1.0)),
        ] {
            // A surface spanned by two tangents and its normal.
            let (a, b) = (Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 1.0));
            let n = a.cross(b).normalize();
            let (_, n2, t2) = transform(&m, Vec3::ZERO, n, a.normalize().extend(-1.0));
            let (a2, b2) = (m.transform_vector3(a), m.transform_vector3(b));
            assert!(
                n2.dot(a2).abs() < 1e-5 && n2.dot(b2).abs() < 1e-5,
                "{m}: {n2}"
            );
            assert!((n2.length() - 1.0).abs() < 1e-6);
            // Outward stays outward: the same side as the transformed cross product would be
            // for a proper rotation, flipped with the winding for a mirror.
            let side = a2.cross(b2).dot(n2) * m.determinant().signum();
            assert!(side > 0.0, "{m}");
            assert_eq!(t2.w, -1.0);
        }
    }

    #[test]
    fn weights_that_do_not_sum_to_one_are_normalized_and_counted() {
        let mats = [
            Mat4::from_translation(Vec3::X),
            Mat4::from_translation(Vec3::Y),
        ];
        let inf = Influences {
            joints: vec![vec![[0, 1, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0]]],
            weights: vec![vec![[0.5, 0.5, 0.0, 0.0], [1.0, 1.0, 0.0, 0.0], [0.0; 4]]],
        };
        let (m, off) = inf.blend(0, &mats);
        assert!(!off);
        assert!(
            m.unwrap()
                .transform_point3(Vec3::ZERO)
                .abs_diff_eq(Vec3::new(0.5, 0.5, 0.0), 1e-6)
        );
        let (m, off) = inf.blend(1, &mats);
        assert!(off);
        assert!(
            m.unwrap()
                .transform_point3(Vec3::ZERO)
                .abs_diff_eq(Vec3::new(0.5, 0.5, 0.0), 1e-6)
        );
        assert_eq!(inf.blend(2, &mats), (None, false));
        assert_eq!(inf.bad_joint(2), None);
        assert_eq!(
            inf.bad_joint(1),
            Some(BadJoint {
                vertex: 0,
                set: 0,
                joint: 1
            })
        );
    }
}
