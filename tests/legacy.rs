//! Files baked by earlier pelt versions (`fixtures/legacy/`) still read: their topology is
//! found and they render as a fresh bake of the same input does.

mod common;

use common::*;
use serde_json::json;

#[test]
fn an_extras_form_bake_reads_and_renders_as_a_fresh_bake() {
    let dir = scratch("legacy-extras");
    let legacy = fixture("legacy/sphere-extras.glb");
    let o = pelt_ok(&["inspect", legacy.to_str().unwrap_or_default()]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("1 normal groups") && text.contains("3312 fin edges"),
        "{text}"
    );
    let fresh = bake(
        &fixture("sphere.glb"),
        &dir,
        &["--config", "fixtures/legacy/fur-small.json"],
    );
    let scene = |asset: &std::path::Path, material: serde_json::Value| {
        json!({
            "output": { "width": 160, "height": 90 },
            "camera": { "position": [0.0, 1.4, 3.6], "target": [0.0, 0.5, 0.0], "fovYDeg": 40 },
            "objects": [{ "asset": asset, "material": material }],
            "lights": [{ "position": [2.0, 2.5, 3.0], "color": [1, 1, 1], "intensity": 6, "radius": 10 }]
        })
    };
    let fur = json!({ "kind": "fur", "length": 0.15 });
    let forward = ["--mode", "forward"];
    let old = render_in(&dir, "legacy", &scene(&legacy, fur.clone()), &forward);
    let new = render_in(&dir, "fresh", &scene(&fresh, fur), &forward);
    let f = flip_of(&old, &new);
    println!("extras-form bake against a fresh bake: FLIP {f:.4}");
    assert!(f <= 0.01, "FLIP {f}");
    // Control: the same file drawn without its fur is another picture.
    let bare = render_in(
        &dir,
        "bare",
        &scene(&legacy, json!({ "kind": "opaque" })),
        &forward,
    );
    let g = flip_of(&old, &bare);
    assert!(g > 0.05, "the control passes: FLIP {g}");
}
