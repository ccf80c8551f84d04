//! What the plugin shares with its shaders and with pelt: the fur uniform's layout against
//! its WGSL struct (parsed by the naga Bevy composes with), and the document pelt's reader
//! makes of the files Bevy's loader hands the extension handler.

use std::path::Path;

use bevy::reflect::structs::Struct;
use bevy::render::render_resource::ShaderType;
use bevy_pelt::material::FurUniform;

/// The `struct NAME { … }` block of `src`, parsed alone.
fn wgsl_struct(src: &str, name: &str) -> Result<(u32, Vec<String>), String> {
    let start = src.find(&format!("struct {name} {{")).ok_or("no struct")?;
    let end = start + src[start..].find("\n}").ok_or("unclosed")? + 2;
    let module = naga::front::wgsl::parse_str(&src[start..end]).map_err(|e| e.to_string())?;
    let ty = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .ok_or("not parsed")?
        .1;
    match &ty.inner {
        naga::TypeInner::Struct { members, span } => Ok((
            *span,
            members
                .iter()
                .map(|m| m.name.clone().unwrap_or_default())
                .collect(),
        )),
        _ => Err("not a struct".into()),
    }
}

fn rust_fields() -> Vec<String> {
    let u = FurUniform::default();
    (0..u.field_len())
        .filter_map(|i| u.name_at(i).map(str::to_owned))
        .collect()
}

#[test]
fn the_fur_uniform_matches_its_wgsl_struct() {
    let src = include_str!("../shaders/fur_shell.wgsl");
    let (size, names) = wgsl_struct(src, "FurUniform").expect("FurUniform in fur_shell.wgsl");
    assert_eq!(u64::from(size), FurUniform::min_size().get());
    assert_eq!(names, rust_fields());
    // Negative control: the struct with a member dropped no longer matches.
    let dropped = src.replacen("    gust: vec4<f32>,\n", "", 1);
    let (size, names) = wgsl_struct(&dropped, "FurUniform").expect("still parses");
    assert!(u64::from(size) != FurUniform::min_size().get() && names != rust_fields());
}

fn fixture(rel: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(rel)
}

#[test]
fn the_document_is_read_from_a_glb_or_from_gltf_json_and_bevys_buffers() {
    let glb = fixture("creature.glb");
    let bytes = std::fs::read(&glb).expect("fixture");
    let doc = bevy_pelt::extension::document(&glb, bytes, &[]).expect("a GLB");
    assert!(!doc.primitives().is_empty());
    // A .gltf: its JSON, with the buffers as Bevy loaded them (here: decoded by pelt itself).
    let gltf = fixture("edge/fan.gltf");
    let own = pelt_io::Document::load(&gltf).expect("fixture");
    let buffers: Vec<Vec<u8>> = own.buffers.iter().map(|b| b.to_vec()).collect();
    let doc = bevy_pelt::extension::document(&gltf, std::fs::read(&gltf).expect("read"), &buffers)
        .expect("a .gltf");
    assert_eq!(doc.primitives(), own.primitives());
    // Neither: an error naming the file.
    let e = bevy_pelt::extension::document(Path::new("junk.glb"), b"not glTF".to_vec(), &[])
        .expect_err("an error");
    assert!(e.contains("junk.glb"), "{e}");
}
