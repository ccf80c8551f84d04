//! Spot lights as the scene file and glTF's `KHR_lights_punctual` write them, and their cone
//! on the CPU (`Emitter::reach`, the twin of common.wgsl's `point_reach`): full light within
//! the inner half-angle, none past the outer, the extension's smooth falloff between.

use std::path::Path;

use glam::{Mat4, Quat, Vec3};
use pelt_scene::light::{Emitter, LightKind, from_khr};
use pelt_scene::scene::Scene;
use serde_json::json;

fn parse(lights: &str) -> Result<Scene, String> {
    Scene::parse(
        Path::new("scene.json"),
        &format!("{{\"lights\": [\n{lights}]}}"),
    )
    .map_err(|e| e.to_string())
}

#[test]
fn a_spot_light_reads_from_the_scene_file_and_writes_back_as_it_was_read() {
    let s = parse(
        r#"{"kind": "spot", "position": [0, 4, 0], "direction": [0, -2, 0], "innerDeg": 20, "outerDeg": 30, "radius": 10, "shadows": true}"#,
    )
    .expect("a spot light");
    let Emitter::Spot {
        position,
        direction,
        radius,
        inner,
        outer,
    } = s.lights[0].emitter
    else {
        panic!("{:?}", s.lights[0]);
    };
    assert_eq!(
        (position, direction, radius),
        (Vec3::new(0.0, 4.0, 0.0), Vec3::NEG_Y, 10.0)
    );
    assert!((inner.to_degrees() - 20.0).abs() < 1e-4 && (outer.to_degrees() - 30.0).abs() < 1e-4);
    assert_eq!(s.lights[0].emitter.kind(), LightKind::Spot);
    let text = serde_json::to_string(&s.lights[0]).expect("writes");
    assert!(
        text.contains("\"kind\":\"spot\"") && text.contains("innerDeg"),
        "{text}"
    );
    let again: pelt_scene::scene::Light = serde_json::from_str(&text).expect("reads back");
    assert_eq!(again, s.lights[0]);
    // glTF's defaults: inner 0, outer 45.
    let d =
        parse(r#"{"kind": "spot", "position": [0, 1, 0], "direction": [1, 0, 0], "radius": 3}"#)
            .expect("defaults");
    let Emitter::Spot { inner, outer, .. } = d.lights[0].emitter else {
        panic!("{:?}", d.lights[0]);
    };
    assert_eq!((inner, outer), (0.0, 45.0_f32.to_radians()));
}

#[test]
fn a_bad_spot_light_is_an_error_at_its_place() {
    for (light, says) in [
        (
            r#"{"kind": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "radius": 3, "innerDeg": 40, "outerDeg": 30}"#,
            "innerDeg",
        ),
        (
            r#"{"kind": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "radius": 3, "outerDeg": 95}"#,
            "outerDeg",
        ),
        (
            r#"{"kind": "spot", "position": [0, 1, 0], "direction": [0, 0, 0], "radius": 3}"#,
            "direction",
        ),
        (
            r#"{"kind": "spot", "position": [0, 1, 0], "radius": 3}"#,
            "needs a direction",
        ),
        (
            r#"{"kind": "spot", "direction": [0, -1, 0], "radius": 3}"#,
            "needs a position",
        ),
        (
            r#"{"kind": "spot", "position": [0, 1, 0], "direction": [0, -1, 0]}"#,
            "needs a radius",
        ),
        (
            r#"{"position": [0, 1, 0], "radius": 3, "outerDeg": 30}"#,
            "only a spot light",
        ),
        (
            r#"{"kind": "directional", "direction": [0, -1, 0], "innerDeg": 3}"#,
            "only a spot light",
        ),
    ] {
        let e = parse(light).expect_err(says);
        assert!(
            e.contains("scene.json") && e.contains("lights[0]") && e.contains(says),
            "{e}"
        );
    }
}

/// The cone on the CPU: the KHR_lights_punctual falloff, clamp((cos θ − cos outer) /
/// (cos inner − cos outer), 0, 1)², times the point light's; nothing past the outer angle.
#[test]
fn the_cone_is_full_within_inner_smooth_between_and_dark_past_outer() {
    let (inner, outer) = (20.0_f32.to_radians(), 30.0_f32.to_radians());
    let spot = Emitter::Spot {
        position: Vec3::ZERO,
        direction: Vec3::NEG_Y,
        radius: 100.0,
        inner,
        outer,
    };
    let point = Emitter::Point {
        position: Vec3::ZERO,
        radius: 100.0,
    };
    let at = |deg: f32| {
        let a = deg.to_radians();
        Vec3::new(a.sin(), -a.cos(), 0.0) * 2.0
    };
    let falloff = |deg: f32| {
        let p = at(deg);
        let s = spot.reach(p).map_or(0.0, |r| r.1);
        s / point.reach(p).expect("in reach").1
    };
    assert!((falloff(0.0) - 1.0).abs() < 1e-6 && (falloff(19.0) - 1.0).abs() < 1e-6);
    let t = (25.0_f32.to_radians().cos() - outer.cos()) / (inner.cos() - outer.cos());
    assert!(
        (falloff(25.0) - t * t).abs() < 1e-5,
        "{} vs {}",
        falloff(25.0),
        t * t
    );
    assert!(falloff(25.0) > 0.1 && falloff(25.0) < 0.9);
    assert!(spot.reach(at(31.0)).is_none() && spot.reach(at(90.0)).is_none());
    // The negative control: a point light there reaches past the cone.
    assert!(point.reach(at(31.0)).is_some());
    // The shaders get the same cone: clamp(dot(cone.xyz, −l) + cone.w, 0, 1).
    let c = spot.cone(Mat4::IDENTITY);
    let l = -at(25.0).normalize();
    assert!(((c.truncate().dot(-l) + c.w) - t).abs() < 1e-5);
    assert_eq!(point.cone(Mat4::IDENTITY), glam::Vec4::W);
}

#[test]
fn khr_lights_punctual_spot_lights_read_their_cone_and_the_nodes_axis() {
    // A quarter turn about x turns the node's −z axis down.
    let world = Mat4::from_rotation_translation(
        Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2),
        Vec3::new(1.0, 3.0, 0.0),
    );
    let def = json!({"type": "spot", "intensity": 5, "range": 8,
        "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}});
    let l = from_khr(&def, world).expect("a spot light");
    let Emitter::Spot {
        position,
        direction,
        radius,
        inner,
        outer,
    } = l.emitter
    else {
        panic!("{l:?}");
    };
    assert!(position.abs_diff_eq(Vec3::new(1.0, 3.0, 0.0), 1e-6));
    assert!(direction.abs_diff_eq(Vec3::NEG_Y, 1e-6), "{direction}");
    assert_eq!(radius, 8.0);
    assert!((inner - 0.2).abs() < 1e-6 && (outer - 0.5).abs() < 1e-6);
    assert_eq!((l.intensity.0, l.shadows), (5.0, false));
    // The extension's defaults: inner 0, outer π/4.
    let d = from_khr(&json!({"type": "spot"}), Mat4::IDENTITY).expect("defaults");
    let Emitter::Spot { inner, outer, .. } = d.emitter else {
        panic!("{d:?}");
    };
    assert!(inner == 0.0 && (outer - std::f32::consts::FRAC_PI_4).abs() < 1e-6);
    // A cone wider than a right angle, or an inner past the outer, is refused.
    for bad in [
        json!({"type": "spot", "spot": {"outerConeAngle": 2.0}}),
        json!({"type": "spot", "spot": {"innerConeAngle": 0.6, "outerConeAngle": 0.5}}),
        json!({"type": "spot", "spot": {"innerConeAngle": "wide"}}),
    ] {
        let e = from_khr(&bad, Mat4::IDENTITY).expect_err("a bad cone");
        assert!(e.starts_with("spot"), "{e}");
    }
}
