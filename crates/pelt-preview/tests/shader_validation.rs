//! Every WGSL file in the top-level `shaders/` folder parses and validates with naga, no GPU
//! needed (as re_renderer's tests/shader_validation.rs does); every file there is one the
//! renderer compiles; and the uniform structs have the sizes the Rust side declares.

use std::path::Path;

use pelt_preview::shaders::{COMMON, Shader};
use pelt_preview::uniforms::{FrameUniforms, LightUniforms, ObjectUniforms, Vertex};

fn validate(name: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    module
}

#[test]
fn every_shader_file_validates_and_is_compiled_by_the_renderer() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shaders");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .expect("shaders/ exists")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".wgsl"))
        .collect();
    files.sort();
    let mut known: Vec<String> = Shader::ALL.iter().map(|s| s.file().to_owned()).collect();
    known.push("common.wgsl".to_owned());
    known.sort();
    assert_eq!(
        files, known,
        "every file in shaders/ is a pass shader or the prelude"
    );
    // The prelude alone, then each pass as compiled.
    validate("common.wgsl", COMMON);
    for s in Shader::ALL {
        let source = s.source();
        let on_disk = std::fs::read_to_string(dir.join(s.file())).expect("read");
        assert!(
            source.ends_with(&on_disk),
            "{}: compiled source is the file",
            s.file()
        );
        let m = validate(s.file(), &source);
        let entries: Vec<&str> = m.entry_points.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(entries, vec!["vs_main", "fs_main"], "{}", s.file());
    }
}

#[test]
fn uniform_structs_match_the_rust_side() {
    let m = validate("common.wgsl", COMMON);
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(m.to_ctx()).expect("layout");
    let size_of_struct = |name: &str| -> u32 {
        let (h, _) = m
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("struct {name} in common.wgsl"));
        layouter[h].size
    };
    assert_eq!(size_of_struct("Frame") as usize, size_of::<FrameUniforms>());
    assert_eq!(
        size_of_struct("Object") as usize,
        size_of::<ObjectUniforms>()
    );
    assert_eq!(size_of_struct("Light") as usize, size_of::<LightUniforms>());
    // VertexIn: the Rust vertex packs the same four attributes without padding.
    assert_eq!(size_of::<Vertex>(), 3 * 4 + 3 * 4 + 4 * 4 + 4);
}

/// A broken shader is caught (the checker itself can fail).
#[test]
#[should_panic(expected = "broken.wgsl")]
fn a_broken_shader_fails_validation() {
    validate(
        "broken.wgsl",
        &format!("{COMMON}\nfn f() -> f32 {{ return vec2<f32>(1.0); }}"),
    );
}
