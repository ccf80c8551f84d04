//! Pixel tests of deferred fur (Revie §2.3–2.4), fins and weighted blended OIT, on a real
//! wgpu adapter (`PELT_BACKEND=gl|vulkan`, as tests/render.rs). The asset is the fixture
//! sphere (radius 1, the known painted comb) baked in-process exactly as `pelt bake --config`
//! would, with 256² fur textures. Images are at most 192 × 144.

mod common;

use std::path::PathBuf;

use glam::Vec3;
use pelt_preview::asset::{MeshData, builtin};
use pelt_preview::scene::{FurBlend, FurCoverage, FurSettings, Material, Object, Sky, Transform};
use pelt_preview::wind::Wind;
use pelt_preview::{Image, Mode, Preview, Scene};

use common::{assert_flip, flip_mean, furry_sphere, light, out_dir, preview, scene, write_failure};

struct Fixture {
    preview: Preview,
    meshes: Vec<MeshData>,
}

impl Fixture {
    fn new() -> Fixture {
        Fixture {
            preview: preview(),
            meshes: vec![
                furry_sphere(),
                builtin("cube").expect("cube"),
                builtin("quad").expect("quad"),
            ],
        }
    }

    /// Renders `scene`, whose objects name their mesh by index through `mesh_of`.
    fn render_with(&mut self, scene: &Scene, mesh_of: &[usize], mode: Mode) -> Image {
        let d = self
            .preview
            .prepare_loaded(scene, &self.meshes, mesh_of, mode)
            .expect("prepare");
        self.preview.render(&d).expect("render")
    }

    fn render(&mut self, scene: &Scene, mode: Mode) -> Image {
        self.render_with(scene, &vec![0; scene.objects.len()], mode)
    }
}

fn is_background(p: [u8; 4], bg: [u8; 4]) -> bool {
    p.iter().zip(bg).all(|(a, b)| a.abs_diff(b) <= 1)
}

#[test]
fn flip_against_64_shells_falls_monotonically_through_4_8_16_32() {
    let mut f = Fixture::new();
    let reference = f.render(&scene(64, true, FurBlend::Stipple), Mode::Inferred);
    let mut errors = Vec::new();
    for n in [4, 8, 16, 32] {
        let img = f.render(&scene(n, true, FurBlend::Stipple), Mode::Inferred);
        let (e, err) = flip_mean(&reference, &img);
        eprintln!("shells {n:>2}: FLIP mean against 64 shells {e:.5}");
        if let Some(&(_, prev)) = errors.last()
            && e >= prev
        {
            write_failure(&format!("shells-{n}"), &reference, &img, &err);
            panic!("{n} shells: FLIP {e:.5} is not below the previous {prev:.5}");
        }
        errors.push((n, e));
    }
    // Coarse shells are visibly wrong, so the measure can fail: 4 shells sit well above the
    // measure's floor (32 shells). With coverage from the strands' optical depth 4 shells are
    // within about 0.016 of 64 here; the old binary shells were above 0.02.
    assert!(
        errors[0].1 > 2.0 * errors[3].1,
        "4 shells differ from 64 far more than 32 do: {errors:?}"
    );
}

/// Pixels outside the bare sphere's silhouette and inside the fur's reach that show fur.
fn silhouette_coverage(f: &mut Fixture, fins: bool, coverage: FurCoverage) -> f64 {
    // Lit by a bright ambient term alone, so a pixel differs from the background wherever fur
    // covers any of it, however the lights would reach it.
    let lit = |mut s: Scene| {
        s.ambient = [1.0; 3];
        s.lights.clear();
        s
    };
    let mut bare = lit(scene(16, false, FurBlend::Stipple));
    bare.objects[0].material = Material::Opaque;
    let base = f.render(&bare, Mode::Inferred);
    let mut furred = lit(scene(16, fins, FurBlend::Stipple));
    furred.fur_coverage = coverage;
    let fur = f.render(&furred, Mode::Inferred);
    let bg = fur.pixel(0, 0);
    let (w, h) = (fur.width, fur.height);
    let inside = |x: u32, y: u32| !is_background(base.pixel(x, y), bg);
    // The band: outside the base silhouette, within 4 pixels of it (the fur reaches about
    // 0.18 / 4.2 of the focal length, ~6 pixels here).
    let (mut band, mut covered) = (0u32, 0u32);
    for y in 4..h - 4 {
        for x in 4..w - 4 {
            if inside(x, y) {
                continue;
            }
            let near = (-4i32..=4).any(|dy| {
                (-4i32..=4).any(|dx| inside((x as i32 + dx) as u32, (y as i32 + dy) as u32))
            });
            if near {
                band += 1;
                covered += u32::from(!is_background(fur.pixel(x, y), bg));
            }
        }
    }
    assert!(band > 200, "a silhouette band exists ({band} pixels)");
    f64::from(covered) / f64::from(band)
}

#[test]
fn fins_cover_more_of_the_silhouette_band() {
    // With the binary heightfield the shells lose the strands seen side-on at the silhouette,
    // which the fins stand for.
    let mut f = Fixture::new();
    let without = silhouette_coverage(&mut f, false, FurCoverage::Binary);
    let with = silhouette_coverage(&mut f, true, FurCoverage::Binary);
    // Analytic coverage takes the grazing path's optical depth into the shells themselves
    // (and plans no fins by default): alone they cover the band at least as the binary
    // shells do with their fins.
    let analytic = silhouette_coverage(&mut f, false, FurCoverage::Analytic);
    eprintln!(
        "silhouette band coverage: binary without fins {without:.3}, with fins {with:.3}; analytic without fins {analytic:.3}"
    );
    assert!(
        with > without + 0.02,
        "fins add coverage: {with:.3} against {without:.3}"
    );
    assert!(
        analytic >= with,
        "analytic shells cover the band: {analytic:.3} against binary with fins {with:.3}"
    );
}

/// Mean over the 2×2 cells of `region` of (3a − b − c − d) / 4, a = the top-left pixel: what
/// a 1-in-4 stipple pattern leaves. Natural texture averages out; a stipple residue does not.
fn stipple_energy(img: &Image, region: &dyn Fn(u32, u32) -> bool) -> f64 {
    let lum = |x: u32, y: u32| {
        let p = img.pixel(x, y);
        (0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])) / 255.0
    };
    let (mut sum, mut n) = (0.0, 0u32);
    for y in (0..img.height - 1).step_by(2) {
        for x in (0..img.width - 1).step_by(2) {
            if region(x, y) {
                let a = lum(x, y);
                sum += (3.0 * a - lum(x + 1, y) - lum(x, y + 1) - lum(x + 1, y + 1)) / 4.0;
                n += 1;
            }
        }
    }
    assert!(n > 100, "region has {n} cells");
    sum / f64::from(n)
}

#[test]
fn no_stipple_residue_after_obliteration() {
    let mut f = Fixture::new();
    // L-buffer at full resolution and plain bilinear (no DSF): the outer shell's stippled
    // texels fall on exact output pixels, and only the obliteration keeps the ground and the
    // fur from reading them. A grey ground behind, so shell texels over it would show.
    let mut s = scene(16, true, FurBlend::Stipple);
    s.lbuffer_scale = 1.0;
    s.dsf = false;
    s.objects.push(Object {
        asset: PathBuf::from("quad"),
        transform: Transform {
            translation: [0.0, 0.0, -1.6],
            scale: [8.0, 8.0, 1.0],
            ..Transform::default()
        },
        material: Material::Opaque,
        color: [0.5; 3],
    });
    let d = f
        .preview
        .prepare_loaded(&s, &f.meshes, &[0, 2], Mode::Inferred)
        .expect("prepare");
    let img = f.preview.render(&d).expect("render");
    // The buffers themselves: the G-buffer holds the outer shell's stippled texels, the
    // composition copy every material reads holds none.
    let shell_id = d.plan.objects[0].fur.expect("fur").shell_id;
    let shell_texels = |t: &wgpu::Texture| {
        let raw = pelt_preview::frame::read_back(
            &f.preview.renderer,
            t,
            d.plan.lbuffer.expect("L-buffer"),
        )
        .expect("read back");
        raw.rgba
            .chunks_exact(4)
            .filter(|p| u32::from(u16::from_le_bytes([p[2], p[3]])) >> 8 == shell_id)
            .count()
    };
    let before = shell_texels(&d.targets.gbuffer.as_ref().expect("G-buffer").dsf.texture);
    let after = shell_texels(
        &d.targets
            .composition
            .as_ref()
            .expect("composition")
            .dsf
            .texture,
    );
    eprintln!("outer-shell texels: {before} in the G-buffer, {after} after obliteration");
    assert!(
        before > 500,
        "the outer shell is stippled into the G-buffer ({before})"
    );
    assert_eq!(after, 0, "obliteration leaves no outer-shell texel");
    // The fur's fringe: the ring from inside the sphere's silhouette (radius 47 pixels here)
    // to past the fur's tips (56), where the shells thin out over the ground.
    let region = |x: u32, y: u32| {
        let (cx, cy) = (f64::from(x) - 96.0, f64::from(y) - 72.0);
        (38.0..64.0).contains(&(cx * cx + cy * cy).sqrt())
    };
    let e = stipple_energy(&img, &region);
    // The threshold: a residue of one 8-bit step (1/255) on every top-left pixel gives
    // 3/4 · 1/255 ≈ 0.0029; half a step is allowed.
    let threshold = 0.5 * 0.75 / 255.0;
    eprintln!("stipple energy {e:.6} (threshold {threshold:.6})");
    if e.abs() > threshold {
        img.save(&out_dir().join("stipple-actual.png"))
            .expect("write");
        panic!("stipple residue {e:.6} > {threshold:.6}; image in target/render-tests/");
    }
    // The detector sees a residue of 2/255 on the top-left pixels.
    let mut marked = img.clone();
    for y in (0..marked.height).step_by(2) {
        for x in (0..marked.width).step_by(2) {
            let i = ((y * marked.width + x) * 4) as usize;
            for c in 0..3 {
                marked.rgba[i + c] = marked.rgba[i + c].saturating_add(2);
            }
        }
    }
    let m = stipple_energy(&marked, &region);
    assert!(
        m.abs() > 2.0 * threshold,
        "a 2/255 stipple is detected: {m:.6}"
    );
}

#[test]
fn an_occluder_in_front_of_the_fur_is_not_sampled_into_the_strands() {
    let mut f = Fixture::new();
    // A thin bar in front of the sphere, lit by a strong light that reaches the bar but not
    // the fur (its sphere of influence ends 0.25 in front of the fur's tips).
    let with_light = |on: bool| {
        let mut s = scene(16, true, FurBlend::Stipple);
        s.objects.push(Object {
            asset: PathBuf::from("cube"),
            transform: Transform {
                translation: [0.1, 0.0, 1.8],
                scale: [0.12, 2.4, 0.05],
                ..Transform::default()
            },
            material: Material::Opaque,
            color: [0.9; 3],
        });
        if on {
            s.lights
                .push(light(Vec3::new(0.1, 0.0, 2.3), Vec3::ONE, 40.0, 0.9));
        }
        s
    };
    let dark = f.render_with(&with_light(false), &[0, 1], Mode::Inferred);
    let lit = f.render_with(&with_light(true), &[0, 1], Mode::Inferred);
    // The bar's own pixels, from a render of the bar alone on the background.
    let mut bar_only = with_light(false);
    bar_only.objects.remove(0);
    let bar = f.render_with(&bar_only, &[1], Mode::Inferred);
    let bg = bar.pixel(0, 0);
    let (mut bar_gain, mut bar_n, mut worst) = (0.0, 0u32, 0u8);
    for y in 0..lit.height {
        for x in 0..lit.width {
            let (a, b) = (lit.pixel(x, y), dark.pixel(x, y));
            let d = (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0);
            if is_background(bar.pixel(x, y), bg) {
                worst = worst.max(d);
            } else {
                bar_gain += f64::from(d);
                bar_n += 1;
            }
        }
    }
    let bar_gain = bar_gain / f64::from(bar_n.max(1));
    eprintln!(
        "occluder: the bar brightens by {bar_gain:.1}/255 on average; fur and background change by at most {worst}/255"
    );
    assert!(bar_gain > 40.0, "the light reaches the bar ({bar_gain:.1})");
    if worst > 3 {
        lit.save(&out_dir().join("occluder-actual.png"))
            .expect("write");
        dark.save(&out_dir().join("occluder-reference.png"))
            .expect("write");
        panic!("the bar's light leaks into the fur: {worst}/255; images in target/render-tests/");
    }
}

#[test]
fn deferred_fur_against_the_forward_kajiya_kay_reference() {
    let mut f = Fixture::new();
    let s = scene(16, true, FurBlend::Stipple);
    let forward = f.render(&s, Mode::Forward);
    let deferred = f.render(&s, Mode::Deferred);
    let inferred = f.render(&s, Mode::Inferred);
    let (d, _) = flip_mean(&forward, &deferred);
    let (i, _) = flip_mean(&forward, &inferred);
    let (di, _) = flip_mean(&deferred, &inferred);
    eprintln!(
        "fur FLIP mean: deferred (full-res L-buffer) vs forward Kajiya-Kay {d:.4}; inferred vs forward {i:.4}; inferred vs deferred {di:.4}"
    );
    // Reported, not a quality bar: the grain normal and rim bend approximate Kajiya-Kay
    // (Revie §2.3.3: "does not perfectly emulate the results of the forward-shading
    // solution"). The bounds only say both images are the same fur.
    assert!(d > 0.0 && d < 0.35, "deferred vs forward {d}");
    assert!(
        di < d,
        "the L-buffer scale costs less than the shading model"
    );
}

#[test]
fn wboit_matches_ordered_blending_without_saturating() {
    let mut f = Fixture::new();
    let stipple = f.render(&scene(16, true, FurBlend::Stipple), Mode::Inferred);
    let wboit = f.render(&scene(64, true, FurBlend::Wboit), Mode::Inferred);
    let wboit16 = f.render(&scene(16, true, FurBlend::Wboit), Mode::Inferred);
    // Saturated accumulation shows as black pixels; none in the fur.
    let black = wboit
        .rgba
        .chunks_exact(4)
        .filter(|p| p[0] < 3 && p[1] < 3 && p[2] < 3)
        .count();
    assert_eq!(black, 0, "no black (saturated) pixels with 64 shells");
    let e = assert_flip("wboit-vs-stipple", &stipple, &wboit16, 0.12);
    eprintln!("WBOIT against ordered blending, 16 shells: FLIP {e:.4}");
    assert_ne!(stipple, wboit16, "the blend modes differ");
}

#[test]
fn fur_renders_are_deterministic_and_the_sky_fills_the_background() {
    let mut f = Fixture::new();
    let mut s = scene(8, true, FurBlend::Stipple);
    s.sky = Sky::Procedural;
    let a = f.render(&s, Mode::Inferred);
    let b = f.render(&s, Mode::Inferred);
    assert_eq!(a.png(), b.png(), "byte-identical");
    // The sky: brighter and bluer at the top than the flat background, darker below.
    let (top, bottom) = (a.pixel(5, 2), a.pixel(5, a.height - 3));
    assert!(top[2] > 120 && top[2] > top[0], "sky at the top {top:?}");
    assert!(bottom[2] < top[2], "below the horizon {bottom:?}");
}

/// Writes a `size`² PNG of one colour.
fn face_png(path: &std::path::Path, size: (u32, u32), rgb: [u8; 3]) {
    let mut bytes = Vec::new();
    {
        let mut e = png::Encoder::new(&mut bytes, size.0, size.1);
        e.set_color(png::ColorType::Rgb);
        e.set_depth(png::BitDepth::Eight);
        let data: Vec<u8> = (0..size.0 * size.1).flat_map(|_| rgb).collect();
        e.write_header()
            .expect("header")
            .write_image_data(&data)
            .expect("data");
    }
    std::fs::write(path, bytes).expect("write face");
}

#[test]
fn a_cube_map_sky_shows_its_faces_and_a_bad_face_is_named() {
    let dir = out_dir().join("cube-sky");
    std::fs::create_dir_all(&dir).expect("dir");
    // +X red, −X green, +Y blue, −Y yellow, +Z magenta, −Z cyan.
    let colours = [
        [255, 0, 0],
        [0, 255, 0],
        [0, 0, 255],
        [255, 255, 0],
        [255, 0, 255],
        [0, 255, 255],
    ];
    let faces: [PathBuf; 6] = std::array::from_fn(|i| dir.join(format!("face{i}.png")));
    for (f, c) in faces.iter().zip(colours) {
        face_png(f, (8, 8), c);
    }
    let mut f = Fixture::new();
    // Looking down −Z with nothing in view: the −Z face (cyan) fills the image.
    let mut s = scene(4, false, FurBlend::Stipple);
    s.objects.clear();
    s.camera.position = [0.0, 0.0, 0.0];
    s.camera.target = [0.0, 0.0, -1.0];
    s.sky = Sky::Cubemap(faces.clone());
    let img = f.render_with(&s, &[], Mode::Inferred);
    let c = img.pixel(img.width / 2, img.height / 2);
    assert!(
        c[0] < 10 && c[1] > 245 && c[2] > 245,
        "−Z face is cyan: {c:?}"
    );
    // Looking up: the +Y face (blue).
    s.camera.target = [0.0, 1.0, -0.001];
    s.camera.up = [0.0, 0.0, -1.0];
    let img = f.render_with(&s, &[], Mode::Inferred);
    let c = img.pixel(img.width / 2, img.height / 2);
    assert!(
        c[0] < 10 && c[1] < 10 && c[2] > 245,
        "+Y face is blue: {c:?}"
    );
    // A face of another size is refused, naming it; nothing is drawn.
    face_png(&faces[2], (8, 4), [0, 0, 255]);
    let err = f
        .preview
        .prepare_loaded(&s, &f.meshes, &[], Mode::Inferred)
        .expect_err("a non-square face");
    let msg = err.to_string();
    assert!(
        msg.contains("sky.faces[2]") && msg.contains("square"),
        "{msg}"
    );
}

/// Runs `strand_tangent` and `shell_offset` of shaders/fur_common.wgsl (the functions the
/// shells, fins and strands call) on the GPU for each (normal, comb, height) and returns
/// (tangent, offset) per input.
fn gpu_path(p: &Preview, inputs: &[([f32; 3], [f32; 3], f32)]) -> Vec<([f32; 3], [f32; 3])> {
    use wgpu::util::DeviceExt;
    let source = r"#import pelt::fur_common::{shell_offset, strand_tangent}
@group(0) @binding(0) var<storage, read> inputs: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> outputs: array<vec4<f32>>;
@compute @workgroup_size(1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = inputs[2u * id.x].xyz;
    let c = inputs[2u * id.x + 1u].xyz;
    let z = inputs[2u * id.x + 1u].w;
    outputs[2u * id.x] = vec4<f32>(strand_tangent(n, c, z), 0.0);
    outputs[2u * id.x + 1u] = vec4<f32>(shell_offset(n, c, z, 1.0, 1.0), 0.0);
}
";
    let composed =
        pelt_preview::shaders::compose_str("strand path test", source).expect("composes");
    let device = &p.renderer.gpu.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("strand path test"),
        source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(composed)),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("strand path test"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let data: Vec<[f32; 4]> = inputs
        .iter()
        .flat_map(|&(n, c, z)| [[n[0], n[1], n[2], 0.0], [c[0], c[1], c[2], z]])
        .collect();
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("inputs"),
        contents: bytemuck::cast_slice(&data),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("outputs"),
        size: (data.len() * 16) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("strand path test"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(inputs.len() as u32, 1, 1);
    }
    p.renderer.gpu.queue.submit([enc.finish()]);
    let bytes = pelt_preview::frame::read_buffer(&p.renderer, &output).expect("read back");
    let out: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    out.chunks_exact(2)
        .map(|o| ([o[0][0], o[0][1], o[0][2]], [o[1][0], o[1][1], o[1][2]]))
        .collect()
}

#[test]
fn the_shaders_strand_tangent_is_the_cpu_paths_derivative_at_each_height() {
    // The Kajiya-Kay tangent every shell, fin and strand fragment is lit about is
    // `strand_tangent` at its height; it must equal pelt_fur::path's derivative, and the
    // shells' offset the path itself, for combs along the normal, in the tangent plane,
    // between, longer than the fur and absent.
    let p = preview();
    let normals = [[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [-0.48, 0.6, 0.64]];
    let combs = [
        [1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.6, 0.8, 0.0],
        [0.3, -0.2, 0.1],
        [2.0, 1.0, 0.0],
        [0.0, 0.0, 0.0],
    ];
    let heights = [0.0, 0.03, 0.25, 0.5, 0.75, 0.97, 1.0];
    let mut inputs = Vec::new();
    for n in normals {
        for c in combs {
            for z in heights {
                inputs.push((n, c, z));
            }
        }
    }
    let got = gpu_path(&p, &inputs);
    let f64v = |v: [f32; 3]| v.map(f64::from);
    let mut worst_angle = 0.0f64;
    let mut worst_offset = 0.0f64;
    for (&(n, c, z), (t, o)) in inputs.iter().zip(&got) {
        let want_t = pelt_fur::path::tangent(f64v(n), f64v(c), f64::from(z));
        let want_o = pelt_fur::path::point(f64v(n), f64v(c), f64::from(z));
        let t = f64v(*t);
        let cos = (t[0] * want_t[0] + t[1] * want_t[1] + t[2] * want_t[2]).clamp(-1.0, 1.0);
        let angle = cos.acos().to_degrees();
        let offset = (0..3)
            .map(|k| (o[k] as f64 - want_o[k]).abs())
            .fold(0.0, f64::max);
        assert!(
            angle < 0.05 && offset < 1e-5,
            "n {n:?} comb {c:?} z {z}: tangent {t:?} against {want_t:?} ({angle:.4}°), offset {o:?} against {want_o:?}"
        );
        worst_angle = worst_angle.max(angle);
        worst_offset = worst_offset.max(offset);
    }
    eprintln!(
        "{} heights: tangents within {worst_angle:.5}°, offsets within {worst_offset:.2e}",
        inputs.len()
    );
    // The check can fail: the old tangent, n + c·max(z, 0.5), is far from the path's.
    let old = {
        let (n, c, z) = ([0.0f64, 0.0, 1.0], [1.0f64, 0.0, 0.0], 1.0f64);
        let m = [n[0] + c[0] * z.max(0.5), n[1], n[2] + c[2] * z.max(0.5)];
        let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
        let t = pelt_fur::path::tangent(n, c, z);
        ((m[0] * t[0] + m[1] * t[1] + m[2] * t[2]) / l)
            .acos()
            .to_degrees()
    };
    assert!(old > 20.0, "{old}");
}

/// Fur receives shadows in every mode: a plate between the key light and the upper half of
/// the furry sphere darkens the fur it shades (forward: each strand's own lookup; inferred
/// and deferred: the shadowed L-buffer), and the lower half, which the key light still sees,
/// keeps its light.
#[test]
fn fur_receives_shadows_in_every_mode() {
    let mut f = Fixture::new();
    let mut off = scene(16, true, FurBlend::Stipple);
    // A plate between the key light (2.5, 2.5, 3) and the sphere's upper half.
    off.objects.push(Object {
        asset: PathBuf::from("cube"),
        transform: Transform {
            translation: [1.25, 1.6, 1.5],
            scale: [1.2, 0.05, 1.2],
            ..Transform::default()
        },
        material: Material::Opaque,
        color: [0.5; 3],
    });
    let mut on = off.clone();
    on.lights[0].shadows = true;
    // The plate's shadow alone: the fur's own (deep opacity maps) is tested with the strands'
    // shadow rays (crates/pelt-measure/tests/strands.rs).
    on.shadow_maps.opacity_layers = 0;
    // The same key light as a sun from where the point light stands (its intensity at the
    // sphere): its orthographic map shadows the fur alike. Its rays are parallel, so the plate
    // is twice as wide to cast the shadow the point light's diverging rays cast.
    let sun = |mut s: Scene| {
        let toward = Vec3::new(2.5, 2.5, 3.0);
        let sun = pelt_preview::scene::Light {
            emitter: pelt_scene::shading::Emitter::Directional {
                direction: -toward.normalize(),
            },
            color: [1.0, 0.95, 0.85],
            intensity: pelt_preview::scene::NonNegative(14.0 / (1.0 + toward.length_squared())),
            shadows: s.lights[0].shadows,
        };
        s.lights[0] = sun;
        s.objects[1].transform.scale = [2.4, 0.05, 2.4];
        s
    };
    let of = [0, 1];
    let luma = |img: &Image, rows: std::ops::Range<u32>| -> f64 {
        let mut sum = 0.0;
        for y in rows {
            for x in 60..132 {
                let i = ((y * img.width + x) * 4) as usize;
                sum += img.rgba[i..i + 3]
                    .iter()
                    .map(|&c| f64::from(c))
                    .sum::<f64>();
            }
        }
        sum
    };
    let cases = [Mode::Forward, Mode::Inferred, Mode::Deferred]
        .into_iter()
        .flat_map(|m| [(m, false), (m, true)]);
    for (mode, directional) in cases {
        let (off, on) = if directional {
            (sun(off.clone()), sun(on.clone()))
        } else {
            (off.clone(), on.clone())
        };
        let mode_name = format!("{mode}{}", if directional { " (directional)" } else { "" });
        let a = f.render_with(&off, &of, mode);
        let b = f.render_with(&on, &of, mode);
        let (top_a, top_b) = (luma(&a, 30..60), luma(&b, 30..60));
        let (low_a, low_b) = (luma(&a, 100..120), luma(&b, 100..120));
        eprintln!(
            "{mode_name}: upper fur {top_b:.0} of {top_a:.0} unshadowed; lower {low_b:.0} of {low_a:.0}"
        );
        if top_b > 0.9 * top_a || std::env::var_os("PELT_SAVE").is_some() {
            write_failure(
                &format!("fur-shadow-{mode}-{directional}"),
                &a,
                &b,
                &flip_mean(&a, &b).1,
            );
        }
        assert!(
            top_b <= 0.9 * top_a,
            "{mode_name}: the plate's shadow darkens the upper fur"
        );
        assert!(
            low_b >= 0.97 * low_a,
            "{mode_name}: the lower fur keeps the key light"
        );
    }
}

/// Wind (Frantzen's displacement vector): none, and a wind of no strength, draw the same
/// bytes; a wind toward +x moves the fur's coverage toward +x and one toward −x toward −x,
/// in the shells with fins (forward and inferred) and in the strand reference alike; it gusts
/// with the scene's time (two times differ) and one time drawn twice is the same image.
#[test]
fn wind_bends_the_fur_along_it_in_shells_fins_and_strands_and_none_is_still() {
    let mut f = Fixture::new();
    let mut base = scene(16, true, FurBlend::Stipple);
    base.objects[0].material = Material::Fur(FurSettings {
        shells: Some(16),
        fins: Some(true),
        length: Some(0.3),
        ..FurSettings::default()
    });
    let windy = |x: f32, strength: f32, time: f32| {
        let mut s = base.clone();
        s.wind = Some(Wind {
            direction: Vec3::new(x, 0.0, 0.0),
            strength,
            gust_hz: 0.5,
            turbulence: 0.3,
        });
        s.time = time;
        s
    };
    // The mean column of the pixels that are not background.
    let centroid = |img: &Image| -> f64 {
        let bg: [u8; 4] = img.rgba[..4].try_into().expect("a pixel");
        let (mut sum, mut n) = (0.0, 0.0);
        for (i, p) in img.rgba.chunks(4).enumerate() {
            if !is_background(p.try_into().expect("a pixel"), bg) {
                sum += (i as u32 % img.width) as f64;
                n += 1.0;
            }
        }
        sum / n
    };
    for mode in [Mode::Forward, Mode::Inferred, Mode::Strands] {
        let still = f.render(&base, mode);
        assert_eq!(
            still.rgba,
            f.render(&windy(1.0, 0.0, 0.7), mode).rgba,
            "{mode}: a wind of no strength moved something"
        );
        let east = f.render(&windy(1.0, 2.0, 0.0), mode);
        let west = f.render(&windy(-1.0, 2.0, 0.0), mode);
        let (c, e, w) = (centroid(&still), centroid(&east), centroid(&west));
        eprintln!("{mode}: coverage centre at column {c:.2}; blown east {e:.2}, west {w:.2}");
        if e < c + 1.0 || w > c - 1.0 || std::env::var_os("PELT_SAVE").is_some() {
            write_failure(
                &format!("wind-{mode}"),
                &west,
                &east,
                &flip_mean(&west, &east).1,
            );
        }
        assert!(
            e > c + 1.0,
            "{mode}: east wind moved the fur to {e} from {c}"
        );
        assert!(
            w < c - 1.0,
            "{mode}: west wind moved the fur to {w} from {c}"
        );
        if mode != Mode::Strands {
            assert_eq!(east.rgba, f.render(&windy(1.0, 2.0, 0.0), mode).rgba);
            assert_ne!(east.rgba, f.render(&windy(1.0, 2.0, 0.5), mode).rgba);
        }
    }
}

/// The furry sphere (16 shells, 0.3 long) over a wide floor at height `floor`, under a light
/// overhead; the scene's objects are drawn with meshes `[0, 1]`.
fn furry_sphere_over_floor(floor: f32) -> Scene {
    let mut s = scene(16, false, FurBlend::Stipple);
    s.camera.far = 30.0;
    s.objects[0].material = Material::Fur(FurSettings {
        shells: Some(16),
        fins: Some(false),
        length: Some(0.3),
        ..FurSettings::default()
    });
    s.objects.push(Object {
        asset: PathBuf::from("cube"),
        transform: Transform {
            translation: [0.0, floor, 0.0],
            scale: [8.0, 0.05, 8.0],
            ..Transform::default()
        },
        material: Material::Opaque,
        color: [0.8; 3],
    });
    s.lights = vec![light(Vec3::new(0.0, 6.0, 0.0), Vec3::ONE, 40.0, 20.0)];
    s
}

/// Pixels `test` darkens by a tenth or more against `reference`, and the share of them
/// between a tenth and nine tenths of the unshadowed floor's light `lit` (soft).
fn shadow_band(reference: &Image, test: &Image, lit: &Image) -> (usize, f64) {
    let luma = |img: &Image, i: usize| -> f64 {
        img.rgba[4 * i..4 * i + 3]
            .iter()
            .map(|&c| f64::from(pelt_scene::shading::linear_of_srgb8(c)))
            .sum()
    };
    let (mut darker, mut soft) = (0usize, 0usize);
    for i in 0..(lit.width * lit.height) as usize {
        let (r, t, l) = (luma(reference, i), luma(test, i), luma(lit, i));
        if t < 0.9 * r {
            darker += 1;
            if t > 0.1 * l && t < 0.9 * l {
                soft += 1;
            }
        }
    }
    (darker, soft as f64 / darker.max(1) as f64)
}

/// What scene `s` (meshes `[0, 1]`, its light not yet casting) shows of the fur's shadow in
/// `mode`: the band the fur's coverage adds to the base mesh's shadow and its soft share,
/// and the base mesh's own shadow and its soft share (writes `NAME-{lit,coverage,base}.png`).
fn fur_shadow_bands(f: &mut Fixture, s: &Scene, mode: Mode, name: &str) -> [(usize, f64); 2] {
    let of = [0, 1];
    let unshadowed = f.render_with(s, &of, mode);
    let mut lit = s.clone();
    lit.lights[0].shadows = true;
    let dom = f.render_with(&lit, &of, mode);
    lit.shadow_maps.opacity_layers = 0;
    let base = f.render_with(&lit, &of, mode);
    for (part, img) in [("lit", &unshadowed), ("coverage", &dom), ("base", &base)] {
        img.save(&out_dir().join(format!("{name}-{part}.png")))
            .expect("write");
    }
    let fur = shadow_band(&base, &dom, &unshadowed);
    let mesh = shadow_band(&unshadowed, &base, &unshadowed);
    eprintln!(
        "{name}: the fur's band: {} pixels, {:.0} % soft; the base mesh's shadow: {} pixels, {:.0} % soft",
        fur.0,
        100.0 * fur.1,
        mesh.0,
        100.0 * mesh.1
    );
    [fur, mesh]
}

/// Fur casts by its coverage (deep opacity maps): under a shadow-casting light overhead, the
/// furry sphere's shadow on a floor gains a band around the base mesh's shadow, soft (most of
/// its pixels between the floor's lit and shadowed levels); the base mesh's own shadow, the
/// negative control, has a hard edge.
#[test]
fn fur_casts_a_soft_shadow_by_its_coverage() {
    let mut f = Fixture::new();
    let mut s = furry_sphere_over_floor(-1.35);
    s.camera.position = [0.0, 7.0, 6.0];
    s.camera.target = [0.0, -1.3, 0.0];
    let [(fur_px, fur_soft), (mesh_px, mesh_soft)] =
        fur_shadow_bands(&mut f, &s, Mode::Forward, "fur-casts");
    assert!(mesh_px > 200, "the base mesh casts: {mesh_px} pixels");
    assert!(
        fur_px > 100,
        "the fur casts by its coverage: {fur_px} pixels"
    );
    assert!(fur_soft >= 0.6, "the fur's shadow is soft: {fur_soft:.2}");
    assert!(
        mesh_soft <= 0.3,
        "control: the base mesh's edge is hard: {mesh_soft:.2}"
    );
}

/// Fur off screen casts by its coverage too: the camera looks down at the floor beside the
/// sphere, which is behind it, so the view draws no fur; the edge of the sphere's shadow in
/// view still gains the fur's band, soft at its outer edge (the opacity maps draw every fur
/// object that casts, `Plan::fur_casters`), in forward and inferred modes alike. Without
/// them the band is empty: the fur casts as its base mesh alone.
#[test]
fn fur_off_screen_casts_by_its_coverage() {
    let mut f = Fixture::new();
    let mut s = furry_sphere_over_floor(-3.0);
    s.camera.position = [1.6, -1.7, 0.0];
    s.camera.target = [1.6, -3.0, 0.0];
    s.camera.up = [0.0, 0.0, -1.0];
    s.camera.fov_y_deg = 70.0;
    let of = [0, 1];
    for mode in [Mode::Forward, Mode::Inferred] {
        let mut lit = s.clone();
        lit.lights[0].shadows = true;
        let plan = pelt_scene::Plan::new(&lit, &f.meshes, &of, mode).expect("plan");
        assert_eq!((plan.shown, plan.fur.len()), (1, 0), "only the floor shows");
        assert_eq!(plan.fur_casters.len(), 1, "the sphere's fur casts");
        let e = pelt_preview::explain(&plan);
        assert!(e.contains("(1 fur object(s) off screen cast too)"), "{e}");
        lit.shadow_maps.opacity_layers = 0;
        let plain = pelt_scene::Plan::new(&lit, &f.meshes, &of, mode).expect("plan");
        assert_eq!(
            (plain.objects.len(), plain.fur_casters.len()),
            (1, 0),
            "without opacity layers nothing off screen is kept"
        );
        let name = format!("fur-off-screen-casts-{mode}");
        let [(fur_px, fur_soft), (mesh_px, mesh_soft)] = fur_shadow_bands(&mut f, &s, mode, &name);
        assert!(
            mesh_px > 200,
            "{mode}: the base mesh casts: {mesh_px} pixels"
        );
        assert!(
            fur_px > 100,
            "{mode}: the off-screen fur casts by its coverage: {fur_px} pixels"
        );
        // Seen from just above the floor, most of the band is the fur's dense inner part;
        // its outer part is soft where the base mesh's edge is hard.
        assert!(
            fur_soft >= 0.2 && fur_soft >= 5.0 * mesh_soft,
            "{mode}: the fur's shadow is soft ({fur_soft:.2}), the mesh's hard ({mesh_soft:.2})"
        );
    }
}
