//! The triangle mesh pelt bakes: one glTF primitive (or one OBJ model) as indexed triangles,
//! with optional normals, UVs, tangents and a color set, plus its validation. NaN or Inf in any
//! attribute is an error naming the attribute and the vertex, never something to carry along.

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

/// Errors found in mesh data. The IO layer adds the file, mesh and primitive to each.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeomError {
    /// A component of an attribute is NaN or infinite.
    #[error("attribute {attribute}: vertex {vertex} has a non-finite value ({value})")]
    NonFinite {
        /// Attribute name as in glTF (`POSITION`, `NORMAL`, …).
        attribute: String,
        /// Vertex index.
        vertex: usize,
        /// The offending value, as text.
        value: String,
    },
    /// An index points past the vertex count.
    #[error("index {position} is {index}, but the primitive has only {vertex_count} vertices")]
    IndexOutOfRange {
        /// Position within the index list.
        position: usize,
        /// The index value.
        index: u32,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// The index count is not a multiple of three.
    #[error("{count} indices is not a whole number of triangles")]
    PartialTriangle {
        /// Number of indices.
        count: usize,
    },
    /// An attribute's length differs from the vertex count.
    #[error("attribute {attribute} has {len} elements, POSITION has {vertex_count}")]
    LengthMismatch {
        /// Attribute name.
        attribute: String,
        /// Its element count.
        len: usize,
        /// Vertex count.
        vertex_count: usize,
    },
}

/// An indexed triangle mesh. Attributes are per vertex; `indices` holds three per triangle.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Vertex normals, if the source has them.
    pub normals: Option<Vec<Vec3>>,
    /// First UV set, if the source has one.
    pub uvs: Option<Vec<Vec2>>,
    /// Tangents (xyz, w = handedness), if the source has them.
    pub tangents: Option<Vec<Vec4>>,
    /// First color set as RGBA (VEC3 sources get A = 1).
    pub colors: Option<Vec<Vec4>>,
    /// Triangle corner indices.
    pub indices: Vec<u32>,
}

impl Mesh {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Checks attribute lengths, index ranges and that every component is finite. The checks
    /// run side by side; the error reported is the first in the order POSITION, NORMAL,
    /// TEXCOORD_0, TANGENT, COLOR_0, indices, whatever finished first.
    pub fn validate(&self) -> Result<(), GeomError> {
        let n = self.positions.len();
        let checks: [&(dyn Fn() -> Result<(), GeomError> + Sync); 6] = [
            &|| check_finite("POSITION", self.positions.iter().map(Vec3::to_array)),
            &|| check_optional("NORMAL", self.normals.as_deref(), n, Vec3::to_array),
            &|| check_optional("TEXCOORD_0", self.uvs.as_deref(), n, Vec2::to_array),
            &|| check_optional("TANGENT", self.tangents.as_deref(), n, Vec4::to_array),
            &|| check_optional("COLOR_0", self.colors.as_deref(), n, Vec4::to_array),
            &|| check_indices(&self.indices, n),
        ];
        let results: Vec<Result<(), GeomError>> = checks.par_iter().map(|check| check()).collect();
        results.into_iter().collect()
    }
}

/// An optional attribute: its length against the vertex count, then [`check_finite`].
fn check_optional<T, const N: usize>(
    attribute: &str,
    values: Option<&[T]>,
    vertex_count: usize,
    components: fn(&T) -> [f32; N],
) -> Result<(), GeomError> {
    let Some(v) = values else { return Ok(()) };
    check_len(attribute, v.len(), vertex_count)?;
    check_finite(attribute, v.iter().map(components))
}

/// Fails on the first element with a NaN or infinite component. The common all-finite case
/// is settled by a branch-free scan; the first bad element is then found in order.
pub fn check_finite<const N: usize>(
    attribute: &str,
    values: impl Iterator<Item = [f32; N]> + Clone,
) -> Result<(), GeomError> {
    let all_finite = values
        .clone()
        .fold(true, |ok, v| v.iter().fold(ok, |ok, c| ok & c.is_finite()));
    if all_finite {
        return Ok(());
    }
    for (vertex, v) in values.enumerate() {
        if let Some(bad) = v.iter().find(|c| !c.is_finite()) {
            return Err(GeomError::NonFinite {
                attribute: attribute.to_owned(),
                vertex,
                value: format!("{bad}"),
            });
        }
    }
    Ok(())
}

/// Fails when an index is out of range or the count is not a multiple of three.
pub fn check_indices(indices: &[u32], vertex_count: usize) -> Result<(), GeomError> {
    if !indices.len().is_multiple_of(3) {
        return Err(GeomError::PartialTriangle {
            count: indices.len(),
        });
    }
    // Branch-free maximum first; the offending position only when there is one.
    let max = indices.iter().fold(0u32, |m, &i| m.max(i));
    if (max as usize) < vertex_count {
        return Ok(());
    }
    if let Some((position, &index)) = indices
        .iter()
        .enumerate()
        .find(|&(_, &i)| i as usize >= vertex_count)
    {
        return Err(GeomError::IndexOutOfRange {
            position,
            index,
            vertex_count,
        });
    }
    Ok(())
}

fn check_len(attribute: &str, len: usize, vertex_count: usize) -> Result<(), GeomError> {
    if len == vertex_count {
        Ok(())
    } else {
        Err(GeomError::LengthMismatch {
            attribute: attribute.to_owned(),
            len,
            vertex_count,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri() -> Mesh {
        Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            indices: vec![0, 1, 2],
            ..Mesh::default()
        }
    }

    #[test]
    fn nan_names_attribute_and_vertex() {
        let mut m = tri();
        m.normals = Some(vec![Vec3::Z, Vec3::new(0.0, f32::NAN, 1.0), Vec3::Z]);
        let err = m.validate().unwrap_err();
        assert_eq!(
            err,
            GeomError::NonFinite {
                attribute: "NORMAL".into(),
                vertex: 1,
                value: "NaN".into()
            }
        );
    }

    #[test]
    fn index_out_of_range_is_reported() {
        let mut m = tri();
        m.indices = vec![0, 1, 3];
        assert!(matches!(
            m.validate(),
            Err(GeomError::IndexOutOfRange {
                position: 2,
                index: 3,
                ..
            })
        ));
        m.indices = vec![0, 1];
        assert!(matches!(
            m.validate(),
            Err(GeomError::PartialTriangle { count: 2 })
        ));
    }

    #[test]
    fn with_several_faults_the_first_in_attribute_order_is_reported() {
        // The checks run side by side; the report must not depend on which finished first.
        let mut m = tri();
        m.indices = vec![0, 1, 7];
        m.colors = Some(vec![Vec4::ONE; 2]);
        m.tangents = Some(vec![Vec4::new(f32::INFINITY, 0.0, 0.0, 1.0); 3]);
        m.normals = Some(vec![Vec3::Z, Vec3::Z, Vec3::new(f32::NAN, 0.0, 1.0)]);
        for _ in 0..20 {
            assert_eq!(
                m.validate(),
                Err(GeomError::NonFinite {
                    attribute: "NORMAL".into(),
                    vertex: 2,
                    value: "NaN".into()
                })
            );
        }
        m.normals = None;
        assert!(matches!(
            m.validate(),
            Err(GeomError::NonFinite { attribute, .. }) if attribute == "TANGENT"
        ));
        m.tangents = None;
        assert!(matches!(
            m.validate(),
            Err(GeomError::LengthMismatch { attribute, .. }) if attribute == "COLOR_0"
        ));
        m.colors = None;
        assert!(matches!(
            m.validate(),
            Err(GeomError::IndexOutOfRange { index: 7, .. })
        ));
    }

    #[test]
    fn valid_mesh_passes() {
        assert_eq!(tri().validate(), Ok(()));
    }
}
