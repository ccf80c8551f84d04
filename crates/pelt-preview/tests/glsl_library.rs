//! The GLSL library of `integrations/three` is the naga translation of the WGSL in `shaders/`
//! as it is now: regenerated here and compared byte for byte with the committed file, so the
//! WebGL formulas cannot drift from the WGSL ones. `PELT_UPDATE_GLSL=1` rewrites the file.

use std::path::PathBuf;

fn committed() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../integrations/three/src/generated/pelt-glsl.js")
}

#[test]
fn the_three_runtime_glsl_is_generated_from_the_current_wgsl() {
    let module = pelt_preview::glsl::library_module().expect("the library translates");
    for function in [
        "vec3 comb_object(",
        "vec3 wind_comb(",
        "vec3 shell_offset(",
        "vec3 strand_tangent(",
        "float layer_opacity(",
        "float t_at(",
        "float fin_visibility(",
        "vec4 light_reach(",
        "vec4 strand_light(",
        "vec3 procedural(",
    ] {
        assert!(module.contains(function), "{function} missing");
    }
    let path = committed();
    if std::env::var_os("PELT_UPDATE_GLSL").is_some() {
        std::fs::write(&path, &module).expect("write the generated GLSL");
        return;
    }
    let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        on_disk == module,
        "{} is not the GLSL of the current shaders/: run \
         PELT_UPDATE_GLSL=1 cargo test -p pelt-preview --test glsl_library",
        path.display()
    );
}
