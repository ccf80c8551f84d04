//! The comb's fallbacks are said aloud: a bake whose combs all lie along the normal or point
//! into the surface, whose combs are all grey or have alpha 0, or whose fur has no TEXCOORD_0
//! gets a warning naming the case and the count; a regular comb on the same grid gets none
//! (the negative control).

use glam::{Vec2, Vec3, Vec4};
use pelt_bake::options::BakeOptions;
use pelt_bake::primitive::bake_primitive;
use pelt_geom::Mesh;

/// A flat 4×4-vertex grid facing +Z, every vertex painted `color`, with or without UVs.
fn grid(color: Vec4, uvs: bool) -> Mesh {
    let mut m = Mesh::default();
    for y in 0..4 {
        for x in 0..4 {
            m.positions.push(Vec3::new(x as f32, y as f32, 0.0));
            m.normals.get_or_insert_with(Vec::new).push(Vec3::Z);
            m.colors.get_or_insert_with(Vec::new).push(color);
            if uvs {
                m.uvs
                    .get_or_insert_with(Vec::new)
                    .push(Vec2::new(x as f32 / 3.0, y as f32 / 3.0));
            }
        }
    }
    for y in 0..3u32 {
        for x in 0..3u32 {
            let a = y * 4 + x;
            m.indices.extend([a, a + 1, a + 4, a + 1, a + 5, a + 4]);
        }
    }
    m
}

fn warnings(color: Vec4, uvs: bool) -> Vec<String> {
    bake_primitive(&grid(color, uvs), &BakeOptions::default()).warnings
}

#[test]
fn a_regular_comb_bakes_without_a_word() {
    // Combed along +X, leaning out: the control every case below differs from by one thing.
    assert_eq!(
        warnings(Vec4::new(1.0, 0.5, 0.75, 1.0), true),
        Vec::<String>::new()
    );
}

#[test]
fn combs_along_the_normal_or_into_the_surface_are_named_with_their_count() {
    for (case, color) in [
        ("along the normal", Vec4::new(0.5, 0.5, 1.0, 1.0)),
        ("into the surface", Vec4::new(0.5, 0.5, 0.0, 1.0)),
    ] {
        let w = warnings(color, true);
        assert_eq!(w.len(), 1, "{case}: {w:?}");
        assert!(
            w[0].starts_with(
                "16 of 16 vertices' combs lie along the normal or point straight into the surface"
            ) && w[0].contains("combed along the tangent (+U) instead"),
            "{case}: {w:?}"
        );
    }
}

#[test]
fn fur_of_length_zero_everywhere_is_named_by_its_cause() {
    let grey = warnings(Vec4::new(0.5, 0.5, 0.5, 1.0), true);
    assert_eq!(
        grey,
        [
            "no fur: every comb is grey (no direction painted), so the fur length is 0 at every vertex"
        ]
    );
    let alpha = warnings(Vec4::new(1.0, 0.5, 0.75, 0.0), true);
    assert_eq!(
        alpha,
        ["no fur: every comb has alpha 0, so the fur length is 0 at every vertex"]
    );
}

#[test]
fn fur_without_texcoord_0_is_named() {
    let w = warnings(Vec4::new(1.0, 0.5, 0.75, 1.0), false);
    assert!(
        w.iter()
            .any(|w| w.starts_with("no TEXCOORD_0: the fur's strand textures are laid out by it")),
        "{w:?}"
    );
}
