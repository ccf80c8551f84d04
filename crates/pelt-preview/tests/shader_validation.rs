//! Every WGSL file in the top-level `shaders/` folder parses and validates with naga, no GPU
//! needed (as re_renderer's tests/shader_validation.rs does); every file there is one the
//! renderer compiles; the uniform structs have the sizes the Rust side declares; and every
//! pipeline's vertex-buffer layout and bind-group slots match its entry points' inputs and
//! `@group` bindings.

use std::path::Path;

use pelt_preview::features::reflect::{FaceUniforms, ReflectUniforms};
use pelt_preview::features::registry;
use pelt_preview::renderer::{PipelineDesc, PipelineSpec};
use pelt_preview::shaders::{COMMON, FILES, ShaderDesc};
use pelt_preview::uniforms::{
    FinInstance, FrameUniforms, FurVertex, LightUniforms, MaterialUniforms, ObjectUniforms, Vertex,
};

fn validate_info(name: &str, source: &str) -> (naga::Module, naga::valid::ModuleInfo) {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    (module, info)
}

fn validate(name: &str, source: &str) -> naga::Module {
    validate_info(name, source).0
}

/// Every pipeline of every registered feature, compute pipelines as specs of their groups.
fn every_pipeline() -> Vec<PipelineDesc> {
    let compute = registry::FEATURES.iter().flat_map(|f| {
        f.compute.iter().map(|c| PipelineDesc {
            shader: c.shader,
            spec: PipelineSpec {
                groups: c.groups.to_vec(),
                ..PipelineSpec::default()
            },
        })
    });
    registry::pipelines().into_iter().chain(compute).collect()
}

fn shader_of(f: &str, file: &str) -> ShaderDesc {
    registry::FEATURES
        .iter()
        .find(|x| x.name == f)
        .map(|x| (x.pipelines)())
        .unwrap_or_default()
        .into_iter()
        .map(|p| p.shader)
        .find(|s| s.file() == file)
        .unwrap_or_else(|| panic!("feature {f} declares {file}"))
}

/// Whether a vertex format feeds a WGSL input of type `ty`.
fn fits(format: wgpu::VertexFormat, ty: &naga::TypeInner) -> bool {
    use naga::{Scalar, TypeInner, VectorSize};
    let f32v = |n| TypeInner::Vector {
        size: n,
        scalar: Scalar::F32,
    };
    match format {
        wgpu::VertexFormat::Float32 => *ty == TypeInner::Scalar(Scalar::F32),
        wgpu::VertexFormat::Float32x2 => *ty == f32v(VectorSize::Bi),
        wgpu::VertexFormat::Float32x3 => *ty == f32v(VectorSize::Tri),
        wgpu::VertexFormat::Float32x4 => *ty == f32v(VectorSize::Quad),
        wgpu::VertexFormat::Uint32 => *ty == TypeInner::Scalar(Scalar::U32),
        _ => false,
    }
}

/// The vertex entry point's `@location` inputs against `spec`'s vertex buffers: the same
/// locations, each fed a format of its type.
fn check_vertex(m: &naga::Module, vs: &str, spec: &PipelineSpec) -> Result<(), String> {
    let ep = m
        .entry_points
        .iter()
        .find(|e| e.name == vs)
        .ok_or(format!("no entry point {vs}"))?;
    let mut inputs = Vec::new();
    let mut add = |binding: &Option<naga::Binding>, ty: naga::Handle<naga::Type>| {
        if let Some(naga::Binding::Location { location, .. }) = binding {
            inputs.push((*location, m.types[ty].inner.clone()));
        }
    };
    for a in &ep.function.arguments {
        match &m.types[a.ty].inner {
            naga::TypeInner::Struct { members, .. } if a.binding.is_none() => {
                for mb in members {
                    add(&mb.binding, mb.ty);
                }
            }
            _ => add(&a.binding, a.ty),
        }
    }
    let attrs: Vec<&wgpu::VertexAttribute> = spec
        .vertex_buffers
        .iter()
        .flat_map(|b| b.attributes.iter())
        .collect();
    if attrs.len() != inputs.len() {
        return Err(format!(
            "{} attributes for {} inputs",
            attrs.len(),
            inputs.len()
        ));
    }
    for (loc, ty) in &inputs {
        let a = attrs
            .iter()
            .find(|a| a.shader_location == *loc)
            .ok_or(format!("no attribute at location {loc}"))?;
        if !fits(a.format, ty) {
            return Err(format!(
                "location {loc}: {:?} does not feed {ty:?}",
                a.format
            ));
        }
    }
    Ok(())
}

/// Every global an entry point of `eps` uses, against the layout `spec` puts at its group.
fn check_groups(
    m: &naga::Module,
    info: &naga::valid::ModuleInfo,
    eps: [&str; 2],
    spec: &PipelineSpec,
) -> Result<(), String> {
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(m.to_ctx()).map_err(|e| e.to_string())?;
    for (i, ep) in m.entry_points.iter().enumerate() {
        if !eps.contains(&ep.name.as_str()) {
            continue;
        }
        let used = info.get_entry_point(i);
        for (h, g) in m.global_variables.iter() {
            let Some(rb) = &g.binding else { continue };
            if used[h].is_empty() {
                continue;
            }
            let name = g.name.clone().unwrap_or_default();
            let id = spec.groups.get(rb.group as usize).ok_or(format!(
                "{}: {name} at @group({}) but the pipeline has {} groups",
                ep.name,
                rb.group,
                spec.groups.len()
            ))?;
            let entry = id
                .entries
                .iter()
                .copied()
                .find(|e| e.binding == rb.binding)
                .ok_or(format!(
                    "{name}: {} has no binding {}",
                    id.label, rb.binding
                ))?;
            let ok = match (&m.types[g.ty].inner, entry.ty) {
                (
                    _,
                    wgpu::BindingType::Buffer {
                        ty,
                        min_binding_size,
                        ..
                    },
                ) => match ty {
                    wgpu::BufferBindingType::Uniform => {
                        let size = u64::from(layouter[g.ty].size);
                        g.space == naga::AddressSpace::Uniform
                            && min_binding_size.map(|n| n.get()) == Some(size)
                    }
                    wgpu::BufferBindingType::Storage { read_only } => matches!(
                        g.space,
                        naga::AddressSpace::Storage { access }
                            if access.contains(naga::StorageAccess::STORE) != read_only
                    ),
                },
                (naga::TypeInner::Sampler { .. }, wgpu::BindingType::Sampler(_)) => true,
                (
                    naga::TypeInner::Image {
                        dim,
                        arrayed,
                        class,
                    },
                    wgpu::BindingType::Texture {
                        sample_type,
                        view_dimension,
                        ..
                    },
                ) => {
                    let dim_ok = match (dim, arrayed) {
                        (naga::ImageDimension::D2, false) => {
                            view_dimension == wgpu::TextureViewDimension::D2
                        }
                        (naga::ImageDimension::D2, true) => {
                            view_dimension == wgpu::TextureViewDimension::D2Array
                        }
                        (naga::ImageDimension::Cube, false) => {
                            view_dimension == wgpu::TextureViewDimension::Cube
                        }
                        _ => false,
                    };
                    let kind_ok = match (class, sample_type) {
                        (
                            naga::ImageClass::Sampled { kind, .. },
                            wgpu::TextureSampleType::Float { .. },
                        ) => *kind == naga::ScalarKind::Float,
                        (naga::ImageClass::Sampled { kind, .. }, wgpu::TextureSampleType::Uint) => {
                            *kind == naga::ScalarKind::Uint
                        }
                        _ => false,
                    };
                    dim_ok && kind_ok
                }
                _ => false,
            };
            if !ok {
                return Err(format!(
                    "{}: {name} at @group({}) @binding({}) does not match {}",
                    ep.name, rb.group, rb.binding, id.label
                ));
            }
        }
    }
    Ok(())
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
            registry::shaders().iter().any(|s| s.parts.contains(&name)),
            "{name} is part of some registered feature's shader"
        );
    }
    // The prelude alone, then each module as compiled, with the entry points its pipelines use.
    validate("common.wgsl", COMMON);
    for s in registry::shaders() {
        let source = s.source();
        let m = validate(&s.module_name(), &source);
        let entries: Vec<&str> = m.entry_points.iter().map(|e| e.name.as_str()).collect();
        let (vs, fs) = s.entry_points();
        assert!(
            entries.contains(&vs) && entries.contains(&fs),
            "{}: {vs}/{fs} in {entries:?}",
            s.module_name()
        );
    }
}

#[test]
fn every_pipeline_layout_matches_its_entry_points() {
    let all = every_pipeline();
    // Every feature's pipelines, each variant (blends, lightings, coverage codes) once.
    assert!(all.len() >= 30, "{} pipelines registered", all.len());
    for PipelineDesc { shader: s, spec } in all {
        let (m, info) = validate_info(&s.module_name(), &s.source());
        let (vs, fs) = s.entry_points();
        if !s.is_compute() {
            check_vertex(&m, vs, &spec)
                .unwrap_or_else(|e| panic!("{} vertex buffers: {e}", s.module_name()));
        }
        check_groups(&m, &info, [vs, fs], &spec)
            .unwrap_or_else(|e| panic!("{} bind groups: {e}", s.module_name()));
        // Every override constant the pipeline sets exists in the module.
        for (name, _) in &spec.constants {
            assert!(
                m.overrides
                    .iter()
                    .any(|(_, o)| o.name.as_deref() == Some(name)),
                "{}: no override {name}",
                s.module_name()
            );
        }
    }
}

/// The layout checks can fail: a G-buffer pipeline fed the fur vertex buffer, or with its
/// groups swapped, is caught.
#[test]
fn a_mismatched_layout_is_caught() {
    let PipelineDesc { shader: s, spec } = pelt_preview::features::geometry::pipeline();
    let (m, info) = validate_info(&s.module_name(), &s.source());
    let (vs, fs) = s.entry_points();
    let mut wrong = spec.clone();
    wrong.vertex_buffers = vec![pelt_preview::features::fur_vertex_layout()];
    assert!(check_vertex(&m, vs, &wrong).is_err());
    let mut wrong = spec;
    wrong.groups.reverse();
    let e = check_groups(&m, &info, [vs, fs], &wrong).expect_err("swapped groups");
    assert!(e.contains("does not match"), "{e}");
    let PipelineDesc { shader, mut spec } = pelt_preview::features::sky::pipeline(true);
    spec.groups = vec![pelt_preview::layout::FRAME];
    let (m, info) = validate_info("sky", &shader.source());
    let e = check_groups(&m, &info, ["vs_fullscreen", "fs_cube"], &spec).expect_err("missing");
    assert!(e.contains("@group(1)"), "{e}");
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
    assert_eq!(
        size_of_struct("MaterialParams") as usize,
        size_of::<MaterialUniforms>()
    );
    // VertexIn, FurIn, FinIn: the Rust vertices pack the same attributes without padding.
    assert_eq!(size_of::<Vertex>(), 3 * 4 + 3 * 4 + 4 * 4 + 4 + 2 * 4);
    assert_eq!(size_of::<FurVertex>(), 4 * 4 + 2 * 4 + 4 * 4);
    // The compute passes' view of the same records, in 32-bit words.
    let words = |name: &str| -> usize {
        let (_, c) = m
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("const {name} in common.wgsl"));
        match m.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => v as usize,
            ref e => panic!("{name} is {e:?}"),
        }
    };
    assert_eq!(words("VERTEX_FLOATS") * 4, size_of::<Vertex>());
    assert_eq!(words("FUR_FLOATS") * 4, size_of::<FurVertex>());
    assert_eq!(
        size_of::<FinInstance>(),
        4 * 12 + 2 * 16 + 2 * 12 + 8 + 4 + 12
    );
    // The distance maps' own uniforms (keep in sync with distance_map.wgsl and reflect.wgsl).
    for (shader, name, size) in [
        (
            shader_of("reflect", "distance_map.wgsl"),
            "Face",
            size_of::<FaceUniforms>(),
        ),
        (
            shader_of("reflect", "reflect.wgsl"),
            "Reflect",
            size_of::<ReflectUniforms>(),
        ),
    ] {
        let m = validate(shader.file(), &shader.source());
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(m.to_ctx()).expect("layout");
        let (h, _) = m
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("struct {name} in {}", shader.file()));
        assert_eq!(layouter[h].size as usize, size, "{name}");
    }
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
