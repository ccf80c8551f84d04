//! Cube maps rendered as six faces of a 2D array (distance maps of mirrors and glass, GPU
//! Gems 3 §17.2.1; shadow cubes of point lights): one convention for the faces' views, which
//! common.wgsl's `face_uv` inverts when a shader reads them.

use glam::{Mat4, Vec3};

/// The six faces' view matrices about the origin: row 0 maps a direction to the face's
/// s coordinate, row 1 to −t, row 2 to −(major axis) (GPUs' cube-map convention, which
/// reflect.wgsl's `face_uv` inverts).
pub fn face_view(face: u32) -> Mat4 {
    let (s, t, m) = match face {
        0 => (Vec3::NEG_Z, Vec3::NEG_Y, Vec3::X),
        1 => (Vec3::Z, Vec3::NEG_Y, Vec3::NEG_X),
        2 => (Vec3::X, Vec3::Z, Vec3::Y),
        3 => (Vec3::X, Vec3::NEG_Z, Vec3::NEG_Y),
        4 => (Vec3::X, Vec3::NEG_Y, Vec3::Z),
        _ => (Vec3::NEG_X, Vec3::NEG_Y, Vec3::NEG_Z),
    };
    Mat4::from_cols(
        s.extend(0.0),
        (-t).extend(0.0),
        (-m).extend(0.0),
        glam::Vec4::W,
    )
    .transpose()
}
