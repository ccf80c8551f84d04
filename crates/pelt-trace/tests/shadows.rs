//! Shadow rays: a light with `"shadows": true` adds nothing where a surface stands between
//! it and the point lit; without the flag the image is exactly what it was.

use std::f32::consts::FRAC_1_SQRT_2;

use pelt_scene::Scene;
use pelt_scene::asset::{MeshData, builtin};
use pelt_trace::{Traced, trace_scene};

/// A floor, a sphere above it and one light straight above the sphere, seen from above.
fn stage(shadows: bool, light_y: f32) -> Scene {
    let json = format!(
        r#"{{
        "output": {{"width": 48, "height": 48}},
        "camera": {{"position": [0, 6, 0.01], "target": [0, 0, 0], "fovYDeg": 40, "near": 0.1, "far": 20}},
        "ambient": [0.05, 0.05, 0.05],
        "objects": [
            {{"asset": "builtin:quad", "transform": {{"rotation": [-0.7071068, 0, 0, 0.7071068], "scale": [4, 4, 1]}}}},
            {{"asset": "builtin:sphere", "transform": {{"translation": [0, 1, 0]}}}}
        ],
        "lights": [{{"position": [0, {light_y}, 0], "intensity": 3, "radius": 10, "shadows": {shadows}}}]
    }}"#
    );
    serde_json::from_str(&json).expect("the stage parses")
}

fn trace(scene: &Scene) -> Traced {
    let meshes: Vec<MeshData> = ["quad", "sphere"]
        .iter()
        .map(|n| builtin(n).expect("built-in mesh"))
        .collect();
    trace_scene(scene, &meshes, &[0, 1]).expect("traced")
}

fn luma(t: &Traced, x: u32, y: u32) -> u32 {
    let i = ((y * t.width + x) * 4) as usize;
    t.rgba[i..i + 3].iter().map(|&c| u32::from(c)).sum()
}

#[test]
fn a_shadow_casting_light_leaves_the_floor_under_the_sphere_in_shadow() {
    let lit = trace(&stage(false, 2.0));
    let shadowed = trace(&stage(true, 2.0));
    // Seen from above, the sphere covers about 7 pixels about the centre and its shadow
    // (from a light 1 above its centre) about 13. A floor pixel far outside both is lit
    // alike with and without shadows.
    let (edge, corner) = ((24, 2), (2, 2));
    assert_eq!(
        luma(&lit, corner.0, corner.1),
        luma(&shadowed, corner.0, corner.1)
    );
    // The floor just outside the sphere's silhouette but inside its shadow: lit without
    // shadows, exactly the ambient term (the scene without its light) with them.
    let mut dark = stage(true, 2.0);
    dark.lights.clear();
    let ambient = trace(&dark);
    let (x, y) = (24, 14);
    assert_eq!(luma(&shadowed, x, y), luma(&ambient, x, y));
    assert!(
        luma(&lit, x, y) > 2 * luma(&ambient, x, y),
        "lit {} vs ambient {}",
        luma(&lit, x, y),
        luma(&ambient, x, y)
    );
    // The sphere's top sees the light: the same with and without shadows.
    assert_eq!(luma(&lit, 24, 24), luma(&shadowed, 24, 24));
    assert!(luma(&lit, edge.0, edge.1) > 0);
}

#[test]
fn without_an_occluder_shadow_rays_change_nothing_and_the_flag_defaults_off() {
    // The floor alone: every point the light reaches sees it, so the images are equal.
    let sphere_only = |shadows| {
        let mut s = stage(shadows, 2.0);
        s.objects.truncate(1);
        s
    };
    assert_eq!(trace(&sphere_only(false)), trace(&sphere_only(true)));
    let parsed: Scene =
        serde_json::from_str(r#"{"lights": [{"position": [0, 1, 0], "radius": 2}]}"#)
            .expect("parses");
    assert!(!parsed.lights[0].shadows);
    let bad = serde_json::from_str::<Scene>(
        r#"{"lights": [{"position": [0, 1, 0], "radius": 2, "shadows": 1}]}"#,
    );
    assert!(bad.is_err());
}

/// The stage under a directional light travelling along `direction` (no falloff).
fn sun_stage(shadows: bool, direction: [f32; 3]) -> Scene {
    let mut s = stage(shadows, 2.0);
    let json = format!(
        r#"{{"kind": "directional", "direction": {direction:?}, "intensity": 1.2, "shadows": {shadows}}}"#
    );
    s.lights = vec![serde_json::from_str(&json).expect("a sun")];
    s
}

#[test]
fn a_directional_light_casts_a_parallel_shadow_of_the_spheres_size_and_lights_without_falloff() {
    let lit = trace(&sun_stage(false, [0.0, -1.0, 0.0]));
    let shadowed = trace(&sun_stage(true, [0.0, -1.0, 0.0]));
    let mut dark = sun_stage(true, [0.0, -1.0, 0.0]);
    dark.lights.clear();
    let ambient = trace(&dark);
    // Straight down, parallel rays: the shadow is the sphere's own disc, so the floor just
    // outside the silhouette (about 7 pixels from the centre) is lit, and a point light's
    // wider shadow (about 13) is not cast.
    assert_eq!(luma(&shadowed, 24, 14), luma(&lit, 24, 14));
    assert_eq!(luma(&shadowed, 2, 2), luma(&lit, 2, 2));
    // No falloff: the floor is lit alike at its centre and corner (a point light's is not).
    assert!(luma(&lit, 2, 2).abs_diff(luma(&lit, 24, 12)) <= 3);
    // Slanted (45° toward −x): the shadow leaves the sphere's silhouette toward −x; a floor
    // point there gets the ambient term only, its mirror image on +x stays lit.
    let d = [-FRAC_1_SQRT_2, -FRAC_1_SQRT_2, 0.0];
    let (lit, shadowed) = (trace(&sun_stage(false, d)), trace(&sun_stage(true, d)));
    let (x, y) = (13, 24);
    assert_eq!(luma(&shadowed, x, y), luma(&ambient, x, y));
    assert!(luma(&lit, x, y) > 2 * luma(&ambient, x, y));
    assert_eq!(luma(&shadowed, 48 - x, y), luma(&lit, 48 - x, y));
}
