//! Property tests of the bake at the extremes (comb within 1e-7 rad of the normal, coordinates
//! from 1e-20 to 1e20, subnormals, frames with w = -1): never NaN or Inf, and the comb decoded
//! back to object space equals the Gram-Schmidt'd input wherever it has a tangential part.

use glam::{DVec3, Vec2, Vec3, Vec4};
use pelt_bake::comb::{self, CombCase, GRAY_EPSILON};
use pelt_bake::frame::Frame;
use pelt_bake::options::{BakeOptions, TangentMode};
use pelt_bake::primitive::bake_primitive;
use pelt_geom::Mesh;
use proptest::prelude::*;

fn unit() -> impl Strategy<Value = DVec3> {
    (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0)
        .prop_filter("not zero", |(x, y, z)| x * x + y * y + z * z > 1e-3)
        .prop_map(|(x, y, z)| DVec3::new(x, y, z).normalize())
}

/// A bumpy 3×3 grid of quads scaled by `scale`, with colors from `dirs`.
fn grid(scale: f32, dirs: &[DVec3], normals: bool, tangents: Option<f32>) -> Mesh {
    let mut m = Mesh::default();
    for y in 0..4 {
        for x in 0..4 {
            let z = ((x * 7 + y * 3) % 5) as f32 * 0.1;
            m.positions
                .push(Vec3::new(x as f32 * scale, y as f32 * scale, z * scale));
            m.uvs
                .get_or_insert_with(Vec::new)
                .push(Vec2::new(x as f32 / 3.0, y as f32 / 3.0));
            let d = dirs[(x + 4 * y) % dirs.len()];
            let c = d * 0.5 + DVec3::splat(0.5);
            m.colors
                .get_or_insert_with(Vec::new)
                .push(Vec4::new(c.x as f32, c.y as f32, c.z as f32, 0.75));
            if normals {
                m.normals
                    .get_or_insert_with(Vec::new)
                    .push(Vec3::new(-z * 0.2, 0.1, 1.0).normalize());
            }
            if let Some(w) = tangents {
                m.tangents
                    .get_or_insert_with(Vec::new)
                    .push(Vec4::new(1.0, 0.0, 0.0, w));
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

/// Checks a baked primitive: everything finite, and decode(comb) = GS(input) per vertex.
fn check(mesh: &Mesh, opts: &BakeOptions) -> Result<(), TestCaseError> {
    let b = bake_primitive(mesh, opts);
    let map: Vec<usize> = match &b.remap {
        Some((m, _)) => m.iter().map(|&v| v as usize).collect(),
        None => (0..b.comb.len()).collect(),
    };
    for (o, &v) in map.iter().enumerate() {
        let normal = match &b.normals {
            Some(n) => Vec3::from(n[o]),
            None => mesh.normals.as_ref().map_or(Vec3::Z, |n| n[v]),
        };
        let tangent = match &b.tangents {
            Some(t) => Vec4::from(t[o]),
            None => mesh.tangents.as_ref().map_or(Vec4::X, |t| t[v]),
        };
        let c = b.comb[o];
        prop_assert!(c.iter().all(|x| x.is_finite()), "vertex {o}: {c:?}");
        prop_assert!(normal.is_finite() && tangent.is_finite());
        prop_assert!(tangent.w == 1.0 || tangent.w == -1.0);
        let (frame, _) = Frame::new(normal, tangent);
        let col = mesh.colors.as_ref().map_or(Vec4::ONE, |cs| cs[v]);
        let (d, _) = comb::decode_color(col, opts.color_space, &opts.axes);
        let g = d - frame.n * frame.n.dot(d);
        if d.length() > GRAY_EPSILON && g.length() > 1e-2 * d.length() {
            let back = frame.to_object(DVec3::new(
                f64::from(c[0]),
                f64::from(c[1]),
                f64::from(c[2]),
            ));
            let err = back.normalize().dot(g.normalize()).clamp(-1.0, 1.0).acos();
            prop_assert!(err < 1e-5, "vertex {o}: {err} rad");
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn comb_within_1e_7_rad_of_the_normal_falls_back(n in unit(), p in unit(), a in 0.0f64..1e-7, len in 0.0f64..1.0, w in prop::bool::ANY) {
        let t = (p - n * n.dot(p)).try_normalize().unwrap_or_else(|| pelt_bake::frame::perpendicular(n));
        let tangent = Vec4::new(t.x as f32, t.y as f32, t.z as f32, if w { 1.0 } else { -1.0 });
        let (frame, _) = Frame::new(n.as_vec3(), tangent);
        let d = frame.n * a.cos() + frame.t * a.sin();
        let (c, case) = comb::bake(d, len, &frame);
        prop_assert_eq!(case, CombCase::ParallelToNormal);
        prop_assert_eq!(c, [1.0, 0.0, 0.0, len as f32]);
    }

    #[test]
    fn regular_combs_round_trip_in_any_frame(n in unit(), t in unit(), d in unit(), w in prop::bool::ANY) {
        let tangent = Vec4::new(t.x as f32, t.y as f32, t.z as f32, if w { 1.0 } else { -1.0 });
        let (frame, _) = Frame::new(n.as_vec3(), tangent);
        let g = d - frame.n * frame.n.dot(d);
        prop_assume!(g.length() > 1e-2);
        let (c, case) = comb::bake(d, 1.0, &frame);
        prop_assert_eq!(case, CombCase::Combed);
        prop_assert!(c[2].abs() < 1e-6);
        let back = frame.to_object(DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2])));
        prop_assert!(back.normalize().dot(g.normalize()) > 1.0 - 1e-12);
    }

    #[test]
    fn any_scale_from_1e_20_to_1e20_bakes_cleanly(exp in -20.0f32..20.0, dirs in prop::collection::vec(unit(), 1..8), normals in prop::bool::ANY) {
        let mesh = grid(10f32.powf(exp), &dirs, normals, None);
        check(&mesh, &BakeOptions::default())?;
    }

    #[test]
    fn subnormal_coordinates_bake_cleanly(mant in 1.0f32..8.0, dirs in prop::collection::vec(unit(), 1..8), normals in prop::bool::ANY) {
        let scale = mant * 1e-42; // below f32::MIN_POSITIVE (1.18e-38): subnormal
        prop_assume!(scale > 0.0 && !scale.is_normal());
        let mesh = grid(scale, &dirs, normals, None);
        check(&mesh, &BakeOptions::default())?;
    }

    #[test]
    fn kept_frames_with_w_minus_1_round_trip(dirs in prop::collection::vec(unit(), 1..8), w in prop::bool::ANY) {
        let mesh = grid(1.0, &dirs, true, Some(if w { 1.0 } else { -1.0 }));
        check(&mesh, &BakeOptions { tangents: TangentMode::Keep, ..BakeOptions::default() })?;
    }
}

#[test]
fn w_minus_1_mirrors_the_bitangent_coordinate() {
    let d = DVec3::new(0.0, 1.0, 0.0);
    let (plus, _) = Frame::new(Vec3::Z, Vec4::new(1.0, 0.0, 0.0, 1.0));
    let (minus, _) = Frame::new(Vec3::Z, Vec4::new(1.0, 0.0, 0.0, -1.0));
    let (a, _) = comb::bake(d, 1.0, &plus);
    let (b, _) = comb::bake(d, 1.0, &minus);
    assert_eq!(a[1], 1.0);
    assert_eq!(b[1], -1.0);
}
