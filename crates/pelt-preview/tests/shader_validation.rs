//! Every WGSL file in the top-level `shaders/` folder is composed from its imports (naga_oil)
//! and validates with naga, no GPU needed (as re_renderer's tests/shader_validation.rs does);
//! every file there is one the renderer compiles; the uniform structs have the sizes the Rust side declares; and every
//! pipeline's vertex-buffer layout and bind-group slots match its entry points' inputs and
//! `@group` bindings.

use std::path::Path;

use pelt_preview::features::opacity::FurRead;
use pelt_preview::features::reflect::{FaceUniforms, ReflectUniforms};
use pelt_preview::features::registry;
use pelt_preview::features::shadows::{LightMap, ShadowFace, ShadowRead};
use pelt_preview::renderer::{PipelineDesc, PipelineSpec};
use pelt_preview::shaders::{FILES, ShaderDesc, compose_str, decorated};
use pelt_preview::uniforms::{
    FinInstance, FrameUniforms, FurVertex, LightUniforms, MaterialUniforms, ObjectUniforms, Vertex,
};

/// `s` composed from its imports by naga_oil, and naga's validation of the result.
fn composed(s: ShaderDesc) -> (naga::Module, naga::valid::ModuleInfo) {
    let module = s.compose().unwrap_or_else(|e| panic!("{e}"));
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{}: {e:?}", s.module_name()));
    (module, info)
}

/// The type named `name` in `m` (the module's own, or a shared module's, decorated).
fn type_named(m: &naga::Module, name: &str) -> Option<naga::Handle<naga::Type>> {
    m.types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .map(|(h, _)| h)
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
        wgpu::VertexFormat::Uint32x2 => {
            *ty == TypeInner::Vector {
                size: VectorSize::Bi,
                scalar: Scalar::U32,
            }
        }
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
    // Each file is a registered shader's, or a shared module another file imports.
    let shared = |text: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix("#define_import_path "))
            .map(|p| p.trim().to_owned())
    };
    for (name, text) in FILES {
        let on_disk = std::fs::read_to_string(dir.join(name)).expect("read");
        assert_eq!(on_disk, text, "{name}: compiled text is the file");
        let registered = registry::shaders().iter().any(|s| s.file == name);
        let imported = shared(text).is_some_and(|path| {
            FILES
                .iter()
                .any(|(_, t)| t.contains(&format!("#import {path}::")))
        });
        assert!(
            registered || imported,
            "{name} is a registered shader's file or a shared module some file imports"
        );
    }
    // Each module as composed, with the entry points its pipelines use.
    for s in registry::shaders() {
        let (m, _) = composed(s);
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
        let (m, info) = composed(s);
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
    let (m, info) = composed(s);
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
    let (m, info) = composed(shader);
    let e = check_groups(&m, &info, ["vs_fullscreen", "fs_cube"], &spec).expect_err("missing");
    assert!(e.contains("@group(1)"), "{e}");
}

#[test]
fn uniform_structs_match_the_rust_side() {
    // The shared structs as a shader importing them sees them.
    let m = compose_str(
        "uniforms.wgsl",
        "#import pelt::common::{Frame, Object, Light, MaterialParams, VERTEX_FLOATS, FUR_FLOATS}
fn f(a: Frame, b: Object, c: Light, d: MaterialParams) -> u32 {
    return VERTEX_FLOATS + FUR_FLOATS;
}",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(m.to_ctx()).expect("layout");
    let size_of_struct = |name: &str| -> u32 {
        let h = type_named(&m, &decorated("pelt::common", name))
            .unwrap_or_else(|| panic!("struct {name} in common.wgsl"));
        layouter[h].size
    };
    assert_eq!(size_of_struct("Frame") as usize, size_of::<FrameUniforms>());
    assert_eq!(
        size_of_struct("Object") as usize,
        size_of::<ObjectUniforms>()
    );
    assert_eq!(size_of_struct("Light") as usize, size_of::<LightUniforms>());
    // The lighting inputs' read settings (lighting_inputs.wgsl), as the lighting passes see
    // them: the shadow maps' and the fur opacity layers'.
    let inputs = compose_str(
        "lighting_read.wgsl",
        "#import pelt::lighting_inputs::{ShadowRead, LightMap, FurRead}
fn f(a: ShadowRead, b: LightMap, c: FurRead) -> f32 {
    return b.texel.x + f32(a.pcf.x) + c.layers.x;
}",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let mut laid = naga::proc::Layouter::default();
    laid.update(inputs.to_ctx()).expect("layout");
    for (name, size) in [
        ("ShadowRead", size_of::<ShadowRead>()),
        ("LightMap", size_of::<LightMap>()),
        ("FurRead", size_of::<FurRead>()),
    ] {
        let h = type_named(&inputs, &decorated("pelt::lighting_inputs", name))
            .unwrap_or_else(|| panic!("struct {name} in lighting_inputs.wgsl"));
        assert_eq!(laid[h].size as usize, size, "{name}");
    }
    assert_eq!(
        size_of_struct("MaterialParams") as usize,
        size_of::<MaterialUniforms>()
    );
    // VertexIn, FurIn, FinIn: the Rust vertices pack the same attributes without padding.
    assert_eq!(size_of::<Vertex>(), 3 * 4 + 3 * 4 + 4 * 4 + 4 + 2 * 4);
    assert_eq!(size_of::<FurVertex>(), 4 * 4 + 2 * 4 + 4 * 4 + 4 * 4);
    // The compute passes' view of the same records, in 32-bit words.
    let words = |name: &str| -> usize {
        let name = &decorated("pelt::common", name);
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
        (
            shader_of("shadows", "shadow_map.wgsl"),
            "ShadowFace",
            size_of::<ShadowFace>(),
        ),
    ] {
        let (m, _) = composed(shader);
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(m.to_ctx()).expect("layout");
        let h =
            type_named(&m, name).unwrap_or_else(|| panic!("struct {name} in {}", shader.file()));
        assert_eq!(layouter[h].size as usize, size, "{name}");
    }
}

/// A broken shader is caught (the checker itself can fail).
#[test]
#[should_panic(expected = "broken.wgsl")]
fn a_broken_shader_fails_validation() {
    let broken = "#import pelt::common::{Frame}\nfn f(a: Frame) -> f32 { return vec2<f32>(1.0); }";
    compose_str("broken.wgsl", broken).unwrap_or_else(|e| panic!("{e}"));
}

/// The named slots are where the shaders and pipelines put their groups: the shared frame and
/// object bindings (object_bindings.wgsl) at `slot::FRAME` and `slot::OBJECT` in every module
/// that uses them, and each pipeline's frame, object and material layouts at those slots.
#[test]
fn named_slots_match_the_shaders_groups() {
    use pelt_preview::draw::slot;
    use pelt_preview::layout;
    let frame = decorated("pelt::object_bindings", "frame");
    let object = decorated("pelt::object_bindings", "object");
    let mut seen = 0;
    for PipelineDesc { shader: s, spec } in every_pipeline() {
        let (m, _) = composed(s);
        for (_, g) in m.global_variables.iter() {
            let (Some(name), Some(rb)) = (&g.name, &g.binding) else {
                continue;
            };
            let want = match name {
                n if *n == frame => slot::FRAME,
                n if *n == object => slot::OBJECT,
                _ => continue,
            };
            seen += 1;
            assert_eq!(rb.group, want, "{}: {name}", s.module_name());
        }
        let at = |l: &layout::LayoutDesc| spec.groups.iter().position(|g| g == l);
        for (l, want) in [(layout::FRAME, slot::FRAME), (layout::OBJECT, slot::OBJECT)] {
            if let Some(i) = at(&l) {
                assert_eq!(i as u32, want, "{}: {}", s.module_name(), l.label);
            }
        }
        if let Some(i) = at(&pelt_preview::gpu_material::LAYOUT) {
            let lit = [slot::MATERIAL, slot::GBUFFER_MATERIAL];
            assert!(
                lit.contains(&(i as u32)),
                "{}: material at {i}",
                s.module_name()
            );
        }
    }
    assert!(seen >= 20, "{seen} shared bindings checked");
}
