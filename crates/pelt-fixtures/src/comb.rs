//! The known comb the shapes are painted with ([`comb_field`]) and how a direction and
//! length become the stored colour ([`paint`]): below the shapes, the edge cases and the crate
//! root, which all paint with them.

use glam::Vec3;

/// The known comb: object-space direction (unit, not yet tangential) and length at a point with
/// normal `n`. A downward "gravity" comb swirled around the Y axis, length varying along X.
pub fn comb_field(p: Vec3, n: Vec3) -> (Vec3, f32) {
    let swirl = Vec3::Y.cross(n);
    let d = (Vec3::new(-0.35, -1.0, 0.15) + swirl * 0.6).normalize_or(Vec3::X);
    let len = 0.4 + 0.6 * (0.5 + 0.5 * (3.0 * p.x).sin());
    (d, len)
}

/// A direction and length as the color a painter stores: RGB = d·0.5 + 0.5, A = length.
pub fn paint(d: Vec3, len: f32) -> [f32; 4] {
    let c = d * 0.5 + Vec3::splat(0.5);
    [c.x, c.y, c.z, len]
}
