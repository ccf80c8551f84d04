//! Every WGSL file in the top-level `shaders/` folder parses and validates with naga, no GPU
//! needed (as re_renderer's tests/shader_validation.rs does); every file there is one the
//! renderer compiles; and the uniform structs have the sizes the Rust side declares.

use std::path::Path;

use pelt_preview::shaders::{COMMON, FILES, Shader};
use pelt_preview::uniforms::{
    FinInstance, FrameUniforms, FurVertex, LightUniforms, ObjectUniforms, Vertex,
};

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
    // Every file on disk is compiled in, byte for byte, and used by some module.
    let mut known: Vec<String> = FILES.iter().map(|(n, _)| (*n).to_owned()).collect();
    known.sort();
    assert_eq!(
        files, known,
        "every file in shaders/ is compiled into the renderer"
    );
    for (name, text) in FILES {
        let on_disk = std::fs::read_to_string(dir.join(name)).expect("read");
        assert_eq!(on_disk, text, "{name}: compiled text is the file");
        assert!(
            Shader::ALL.iter().any(|s| s.parts().contains(&name)),
            "{name} is part of some module"
        );
    }
    // The prelude alone, then each module as compiled, with the entry points its pipelines use.
    validate("common.wgsl", COMMON);
    for s in Shader::ALL {
        let source = s.source();
        let m = validate(&s.module_name(), &source);
        let entries: Vec<&str> = m.entry_points.iter().map(|e| e.name.as_str()).collect();
        for wboit in [false, true] {
            let (vs, fs) = s.entry_points(wboit);
            assert!(
                entries.contains(&vs) && entries.contains(&fs),
                "{}: {vs}/{fs} in {entries:?}",
                s.module_name()
            );
        }
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
    // VertexIn, FurIn, FinIn: the Rust vertices pack the same attributes without padding.
    assert_eq!(size_of::<Vertex>(), 3 * 4 + 3 * 4 + 4 * 4 + 4);
    assert_eq!(size_of::<FurVertex>(), 4 * 4 + 2 * 4 + 4 * 4);
    assert_eq!(size_of::<FinInstance>(), 4 * 12 + 2 * 16 + 2 * 12 + 8 + 4);
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
