//! The renderer core's contracts, on a real adapter (`PELT_BACKEND=gl|vulkan`): GPU assets are
//! uploaded once and frames after the first write only uniforms; camera and knob moves build
//! no pipeline; a planned pass missing a target or resource is an error; pipeline keys carry
//! the output format; cube and array targets render one layer at a time, with mip chains.

mod common;

use pelt_preview::asset::MeshData;
use pelt_preview::features::mips::mip_chain;
use pelt_preview::frame::read_back_layer;
use pelt_preview::orbit::Orbit;
use pelt_preview::scene::FurBlend;
use pelt_preview::targets::{LayeredTarget, full_chain};
use pelt_preview::{Mode, ViewOutput};

use common::{furry_sphere, preview, scene};

/// Most bytes a frame after the first may upload: its uniforms (the forward light array, and
/// within 4 KiB the frame constants, a few objects and lights, the shell table), never a mesh
/// or texture.
const UNIFORM_BYTES: u64 = (pelt_preview::uniforms::MAX_FORWARD_LIGHTS
    * size_of::<pelt_preview::uniforms::LightUniforms>()
    + 4 * 1024) as u64;

/// Bytes of a mesh's vertex and index buffers.
fn mesh_bytes(m: &MeshData) -> u64 {
    (size_of_val(m.vertices.as_slice()) + size_of_val(m.indices.as_slice())) as u64
}

#[test]
fn camera_and_knob_moves_build_no_pipeline_after_the_first_frame_and_upload_only_uniforms() {
    let mut p = preview();
    let meshes = vec![furry_sphere()];
    let mut s = scene(16, true, FurBlend::Stipple);
    p.take_uploaded();
    let mut sv = p
        .prepare_loaded(&s, &meshes, &[0], Mode::Inferred)
        .expect("prepare");
    p.render(&sv).expect("frame 0");
    let first = p.take_uploaded();
    eprintln!("frame 0 uploaded {first} bytes");
    assert!(first > mesh_bytes(&meshes[0]), "frame 0 uploads the mesh");
    let built = p.renderer.pipelines_built();
    assert!(built > 0);
    let mut orbit = Orbit::new(&s.camera);
    for k in 1..10 {
        orbit.rotate(0.3, 0.04);
        s.camera = orbit.camera();
        match k % 3 {
            0 => s.lbuffer_scale = [0.5, 0.75, 1.0][k % 2],
            1 => common::set_shells(&mut s, [4, 24][k % 2]),
            _ => s.dsf = !s.dsf,
        }
        p.update(&mut sv, &s, Mode::Inferred).expect("update");
        p.render(&sv).expect("frame");
        assert_eq!(
            p.renderer.pipelines_built(),
            built,
            "frame {k} built a pipeline"
        );
        let up = p.take_uploaded();
        eprintln!("frame {k} uploaded {up} bytes");
        assert!(
            up > 0 && up <= UNIFORM_BYTES,
            "frame {k}: {up} bytes (a moved camera writes its uniforms, nothing more)"
        );
    }
    // A still camera writes nothing at all.
    p.update(&mut sv, &s, Mode::Inferred).expect("update");
    p.render(&sv).expect("still frame");
    assert_eq!(p.take_uploaded(), 0, "nothing changed, nothing written");
    // The counter sees new pipelines: another mode needs its own.
    p.update(&mut sv, &s, Mode::Forward).expect("forward");
    p.render(&sv).expect("forward frame");
    assert!(
        p.renderer.pipelines_built() > built,
        "forward compiles its pipelines"
    );
}

#[test]
fn a_scene_prepared_again_reuses_its_gpu_assets_and_a_changed_mesh_uploads() {
    let mut p = preview();
    let mut meshes = vec![furry_sphere()];
    let s = scene(8, true, FurBlend::Stipple);
    let first = p
        .prepare_loaded(&s, &meshes, &[0], Mode::Inferred)
        .expect("prepare");
    let cold = p.take_uploaded();
    let again = p
        .prepare_loaded(&s, &meshes, &[0], Mode::Inferred)
        .expect("again");
    let warm = p.take_uploaded();
    eprintln!("first prepare {cold} bytes, second {warm}");
    assert!(cold > mesh_bytes(&meshes[0]));
    assert!(
        warm <= UNIFORM_BYTES,
        "the cache keeps the mesh and textures: {warm}"
    );
    // Same bytes, same GPU buffers.
    let a = first.meshes[0].as_ref().expect("uploaded");
    let b = again.meshes[0].as_ref().expect("uploaded");
    assert!(std::sync::Arc::ptr_eq(a, b));
    // Negative control: one vertex moved is another asset.
    meshes[0].vertices[0].position[0] += 1e-3;
    p.prepare_loaded(&s, &meshes, &[0], Mode::Inferred)
        .expect("changed");
    assert!(p.take_uploaded() > mesh_bytes(&meshes[0]));
    // Assets no scene holds are dropped.
    drop((first, again));
    assert!(p.assets.sweep() >= 1);
}

#[test]
fn a_planned_pass_missing_its_target_or_mesh_is_an_error() {
    let mut p = preview();
    let meshes = vec![furry_sphere()];
    let s = scene(8, true, FurBlend::Stipple);
    let mut sv = p
        .prepare_loaded(&s, &meshes, &[0], Mode::Inferred)
        .expect("prepare");
    p.render(&sv).expect("whole, it renders");
    sv.targets.gbuffer = None;
    let e = p.render(&sv).expect_err("no G-buffer").to_string();
    assert!(e.contains("geometry pass needs a G-buffer"), "{e}");
    let mut sv = p
        .prepare_loaded(&s, &meshes, &[0], Mode::Inferred)
        .expect("prepare");
    sv.meshes[0] = None;
    let e = p.render(&sv).expect_err("no mesh").to_string();
    assert!(e.contains("the mesh of objects[0]"), "{e}");
    let mut sv = p
        .prepare_loaded(&s, &meshes, &[0], Mode::Inferred)
        .expect("prepare");
    sv.targets.composition = None;
    let e = p.render(&sv).expect_err("no composition").to_string();
    assert!(e.contains("obliterate pass needs"), "{e}");
}

#[test]
fn pipeline_keys_carry_the_output_format() {
    let mut p = preview();
    let meshes = vec![furry_sphere()];
    let s = scene(8, true, FurBlend::Stipple);
    let rgba = p
        .prepare_loaded(&s, &meshes, &[0], Mode::Inferred)
        .expect("rgba");
    let a = p.render(&rgba).expect("rgba frame");
    let built = p.renderer.pipelines_built();
    let bgra = p
        .prepare_view(
            &s,
            &meshes,
            &[0],
            Mode::Inferred,
            ViewOutput {
                format: wgpu::TextureFormat::Bgra8UnormSrgb,
                own_color: true,
            },
        )
        .expect("bgra");
    let mut b = p.render(&bgra).expect("bgra frame");
    let more = p.renderer.pipelines_built() - built;
    // The material pass's pipelines (base, sky, shells, fins) are built again for the new
    // format; the G-buffer, light and obliteration passes' are shared.
    assert!((1..built).contains(&more), "{more} new of {built}");
    for px in b.rgba.chunks_exact_mut(4) {
        px.swap(0, 2);
    }
    assert_eq!(a, b, "the same image in either channel order");
}

/// Clears layer `layer` (mip 0) of `t` to `rgb` through its own view.
fn clear_layer(p: &pelt_preview::Preview, t: &LayeredTarget, layer: u32, rgb: [f64; 3]) {
    let r = &p.renderer;
    let view = t.layer(layer, 0);
    let mut enc = r
        .gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("clear layer"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: &view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color {
                    r: rgb[0],
                    g: rgb[1],
                    b: rgb[2],
                    a: 1.0,
                }),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    r.gpu.queue.submit([enc.finish()]);
}

#[test]
fn cube_faces_and_array_layers_render_one_at_a_time_and_mips_average_them() {
    let p = preview();
    let r = &p.renderer;
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let cube = LayeredTarget::new(r, "cube", (16, 16), 6, full_chain((16, 16)), format);
    assert_eq!(cube.mips, 5);
    for face in 0..6 {
        let f = f64::from(face);
        clear_layer(&p, &cube, face, [f / 5.0, 1.0 - f / 5.0, 0.5]);
    }
    // Face 4: a one-texel checker of 0 and 255.
    let checker: Vec<u8> = (0..16 * 16)
        .flat_map(|i| {
            let v = if (i % 16 + i / 16) % 2 == 0 { 255 } else { 0 };
            [v, v, v, 255]
        })
        .collect();
    r.gpu.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture: &cube.texture,
            mip_level: 0,
            origin: wgpu::Origin3d { x: 0, y: 0, z: 4 },
            aspect: wgpu::TextureAspect::All,
        },
        &checker,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(64),
            rows_per_image: Some(16),
        },
        wgpu::Extent3d {
            width: 16,
            height: 16,
            depth_or_array_layers: 1,
        },
    );
    mip_chain(r, &cube).expect("mips");
    let read = |layer, mip| {
        read_back_layer(r, &cube.texture, layer, mip, cube.mip_size(mip)).expect("read")
    };
    for face in [0u32, 2, 5] {
        let want = [
            (f64::from(face) / 5.0 * 255.0).round() as u8,
            ((1.0 - f64::from(face) / 5.0) * 255.0).round() as u8,
            128,
        ];
        for mip in [0, 2, 4] {
            let px = read(face, mip).pixel(0, 0);
            for c in 0..3 {
                assert!(
                    px[c].abs_diff(want[c]) <= 1,
                    "face {face} mip {mip}: {px:?}, want {want:?}"
                );
            }
        }
    }
    // The checker averages to grey at mip 1 already, and stays there down to 1×1.
    for mip in 1..5 {
        let img = read(4, mip);
        assert!(
            img.rgba.chunks_exact(4).all(|p| p[0].abs_diff(128) <= 1),
            "mip {mip} of the checker: {:?}",
            img.pixel(0, 0)
        );
    }
    assert_eq!(read(4, 0).pixel(0, 0)[0], 255, "mip 0 is untouched");
    // A 2D array: three layers, each its own.
    let array = LayeredTarget::new(r, "array", (8, 4), 3, 1, format);
    for layer in 0..3 {
        clear_layer(&p, &array, layer, [f64::from(layer) / 2.0, 0.0, 1.0]);
    }
    for layer in 0..3 {
        let px = read_back_layer(r, &array.texture, layer, 0, (8, 4))
            .expect("read")
            .pixel(7, 3);
        assert_eq!(
            px[0],
            (f64::from(layer) / 2.0 * 255.0).round() as u8,
            "layer {layer}"
        );
    }
}

#[test]
fn several_views_in_one_frame_each_equal_their_own_render() {
    let mut p = preview();
    let meshes = vec![furry_sphere()];
    let s = scene(8, true, FurBlend::Stipple);
    let mut cameras = vec![s.camera];
    for deg in [90.0_f32, 200.0] {
        let mut o = Orbit::new(&s.camera);
        o.rotate(deg.to_radians(), 0.3);
        cameras.push(o.camera());
    }
    for mode in [Mode::Inferred, Mode::Forward] {
        let mut sv = p.prepare_loaded(&s, &meshes, &[0], mode).expect("prepare");
        for c in &cameras[1..] {
            p.add_view(&mut sv, c).expect("add view");
        }
        let frame = p.render_views(&sv).expect("three views, one frame");
        assert_eq!(frame.len(), 3);
        for (v, c) in cameras.iter().enumerate() {
            let alone = {
                let mut one = s.clone();
                one.camera = *c;
                let sv1 = p
                    .prepare_loaded(&one, &meshes, &[0], mode)
                    .expect("prepare");
                p.render(&sv1).expect("render")
            };
            assert!(
                frame[v] == alone,
                "{mode} view {v} differs from its own render"
            );
        }
        assert!(
            frame[0] != frame[1] && frame[1] != frame[2],
            "the views differ"
        );
    }
}

#[test]
fn shaders_reload_from_a_folder_and_a_broken_set_keeps_the_last_good_pipelines() {
    let dir = std::env::temp_dir().join(format!("pelt-shaders-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    for (name, text) in pelt_preview::shaders::FILES {
        std::fs::write(dir.join(name), text).expect("write");
    }
    let mut p = preview();
    let meshes = vec![furry_sphere()];
    let mut s = scene(8, true, FurBlend::Stipple);
    s.sky = pelt_preview::scene::Sky::Procedural;
    let sv = p
        .prepare_loaded(&s, &meshes, &[0], Mode::Inferred)
        .expect("prepare");
    let before = p.render(&sv).expect("render");
    // A broken file: naga's error names the module and the line; nothing changes.
    let sky = dir.join("sky.wgsl");
    let good = std::fs::read_to_string(&sky).expect("read");
    std::fs::write(&sky, good.replace("fn ndc_of(", "fn ndc_of(((")).expect("write");
    let e = p
        .renderer
        .load_shaders(&dir)
        .expect_err("broken sky")
        .to_string();
    assert!(e.contains("sky.wgsl") && e.contains("ndc_of((("), "{e}");
    assert_eq!(
        p.render(&sv).expect("render"),
        before,
        "the last good pipelines draw"
    );
    // A valid edit takes effect on the next frame: a red zenith (the procedural sky is in
    // common.wgsl).
    std::fs::write(&sky, &good).expect("write");
    let common = dir.join("common.wgsl");
    let shared = std::fs::read_to_string(&common).expect("read");
    std::fs::write(
        &common,
        shared.replace(
            "let zenith = vec3<f32>(0.10, 0.22, 0.55);",
            "let zenith = vec3<f32>(0.90, 0.02, 0.02);",
        ),
    )
    .expect("write");
    let built = p.renderer.pipelines_built();
    p.renderer.load_shaders(&dir).expect("valid set");
    let after = p.render(&sv).expect("render");
    assert!(
        p.renderer.pipelines_built() > built,
        "pipelines rebuilt from the new source"
    );
    // The top-left corner is sky (the sphere covers the top centre).
    let corner = |i: &pelt_preview::Image| i.pixel(2, 0);
    let (b, a) = (corner(&before), corner(&after));
    if !(a[0] > b[0] + 40 && a[2] < b[2]) {
        let out = common::out_dir();
        before.save(&out.join("reload-before.png")).expect("write");
        after.save(&out.join("reload-actual.png")).expect("write");
        panic!("the sky did not turn red: {b:?} -> {a:?}; images in target/render-tests/");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_profile_counts_what_each_pass_draws() {
    let mut p = preview();
    let meshes = vec![furry_sphere()];
    let shells = 8;
    let s = scene(shells, false, FurBlend::Stipple);
    let sv = p
        .prepare_loaded(&s, &meshes, &[0], Mode::Inferred)
        .expect("prepare");
    let t = p.time(&sv, 0, 2).expect("profile");
    let of = |name: &str| {
        t.profile
            .iter()
            .find(|x| x.pass == name)
            .unwrap_or_else(|| panic!("no {name} pass in {:?}", t.profile))
    };
    let tris = meshes[0].indices.len() as u64 / 3;
    let g = of("geometry").counts;
    let stride = size_of::<pelt_preview::uniforms::Vertex>() as u64;
    // The sphere, and its stippled outer shell (Revie's G-buffer fur), each drawn once.
    assert_eq!(
        (g.draws, g.pipelines, g.triangles),
        (2, 2, 2 * tris),
        "{g:?}"
    );
    assert_eq!(g.vertices, 6 * tris, "{g:?}");
    assert!(g.vertex_bytes >= g.vertices * stride, "{g:?}");
    let all: u64 = t.profile.iter().map(|x| x.counts.triangles).sum();
    assert!(
        all >= (2 + u64::from(shells)) * tris,
        "geometry, material and {shells} shells draw the sphere: {all} triangles"
    );
    // Each frame's encoding and its submit lie inside the frame's wall time, so their
    // medians are within the frames' median too.
    assert!(
        t.frame_ms.is_finite()
            && t.encode_ms > 0.0
            && t.frame_ms >= t.encode_ms
            && t.submit_ms > 0.0
            && t.submit_ms <= t.frame_ms,
        "{t:?}"
    );
    let table = t.profile_table();
    assert!(
        table.contains("| geometry |") && table.contains("| submit (CPU) |"),
        "{table}"
    );
}

#[test]
fn a_pass_sets_a_pipeline_or_bind_group_once_until_it_changes() {
    use pelt_preview::features::geometry::PASS;
    use pelt_preview::recipe::{Recipe, Step};
    let p = preview();
    let device = &p.renderer.gpu.device;
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[],
    });
    let group = || {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
            entries: &[],
        })
    };
    let (a, b) = (group(), group());
    let mut r = Recipe::new(PASS, vec![], None);
    let geometry = pelt_preview::features::geometry::pipeline();
    for _ in 0..3 {
        r.pipeline(geometry.clone());
        r.bind(0, &a, None);
        r.push(Step::Draw(0..3, 0..2));
    }
    let c = r.counts();
    assert_eq!((c.pipelines, c.binds, c.draws), (1, 1, 3), "{c:?}");
    assert_eq!((c.triangles, c.vertices), (6, 18), "{c:?}");
    // Another group, another offset or another slot is a change.
    r.bind(0, &b, None);
    r.bind(0, &b, Some(256));
    r.bind(1, &b, Some(256));
    r.bind(0, &a, None);
    assert_eq!(r.counts().binds, 5);
    // Varying a pipeline nothing has drawn with yet replaces it (neither set nor compiled);
    // after a draw it is a new pipeline.
    let mut r = Recipe::new(PASS, vec![], None);
    r.pipeline(geometry.clone());
    r.specialize(pelt_preview::gpu_material::TEXTURED, Some(0.0));
    r.sides(Some(wgpu::Face::Back), wgpu::FrontFace::Ccw);
    r.push(Step::Draw(0..3, 0..1));
    assert_eq!(r.keys().count(), 1);
    let k = r.keys().next().expect("a key");
    assert_eq!(k.desc.spec.cull, Some(wgpu::Face::Back));
    assert_eq!(
        k.desc.constant(pelt_preview::gpu_material::TEXTURED),
        Some(0.0)
    );
    r.sides(None, wgpu::FrontFace::Cw);
    r.push(Step::Draw(0..3, 0..1));
    assert_eq!(r.keys().count(), 2);
    assert_eq!(r.counts().pipelines, 2);
}
