//! Pixel tests of the debug views. `debug-groups`: three quads side by side in normal groups
//! 0, 12 and 24 (IDs that a palette indexed by the ID modulo 12 would paint alike) show the
//! middle quad in another colour than its neighbours; the negative control, one group across
//! all three, shows one colour. `debug-comb`: on the baked furry sphere, the pixels under
//! vertices that face the camera hold the comb decoded on the CPU (pelt-geom's tangent frame,
//! the bake's own), direction as colour and length as brightness; the negative control (the
//! tangent-space comb taken as the direction, no decode) misses them by far more.

use std::path::PathBuf;

use glam::{DVec3, Mat4, Vec3, Vec4};
use pelt_geom::frame::Frame;
use pelt_preview::asset::MeshData;
use pelt_preview::plan::DebugView;
use pelt_preview::scene::{Camera, Material, Object, Size, Transform};
use pelt_preview::uniforms::Vertex;
use pelt_preview::{Image, Mode, Scene};

mod common;

use common::{furry_sphere, out_dir, preview, scene};

/// Three unit quads along x, quad k in group `ids[k]`, each with its own four vertices (a
/// hard edge between each pair).
fn strip(ids: [u32; 3]) -> MeshData {
    let (mut v, mut i) = (Vec::new(), Vec::new());
    for (k, g) in ids.into_iter().enumerate() {
        let x = k as f32 - 1.5;
        let base = v.len() as u32;
        for p in [
            [x, -0.5, 0.0],
            [x + 1.0, -0.5, 0.0],
            [x + 1.0, 0.5, 0.0],
            [x, 0.5, 0.0],
        ] {
            v.push(Vertex {
                position: p,
                normal: [0.0, 0.0, 1.0],
                albedo: [1.0; 4],
                group: g,
                uv: [0.0; 2],
            });
        }
        i.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    MeshData::untextured(v, i)
}

fn strip_scene() -> Scene {
    Scene {
        output: Size {
            width: 192,
            height: 96,
        },
        camera: Camera {
            position: [0.0, 0.0, 2.0],
            target: [0.0; 3],
            near: 0.5,
            far: 10.0,
            ..Camera::default()
        },
        objects: vec![Object {
            asset: PathBuf::from("strip"),
            transform: Transform::default(),
            material: Material::Opaque,
            color: [1.0; 3],
        }],
        ..Scene::default()
    }
}

fn draw(s: &Scene, mesh: &MeshData, mode: Mode, name: &str) -> Image {
    let mut p = preview();
    let d = p
        .prepare_loaded(s, std::slice::from_ref(mesh), &[0], mode)
        .expect("prepare");
    let image = p.render(&d).expect("render");
    image
        .save(&out_dir().join(format!("{name}.png")))
        .expect("write");
    image
}

/// The 8-bit colour at (`x`, `y`), fractions of the image.
fn at(i: &Image, x: f32, y: f32) -> Vec3 {
    let p = i.pixel((x * i.width as f32) as u32, (y * i.height as f32) as u32);
    Vec3::new(f32::from(p[0]), f32::from(p[1]), f32::from(p[2]))
}

/// The colours of the left, middle and right quads' centres.
fn quads(i: &Image) -> [Vec3; 3] {
    // The strip spans x in [-1.5, 1.5] at z = 0; seen from z = 2 with the default field of
    // view it fills most of the image's width, quad centres at x = -1, 0, 1.
    [0.25, 0.5, 0.75].map(|x| at(i, x, 0.5))
}

#[test]
fn neighbouring_normal_groups_differ_even_where_their_ids_match_modulo_a_palette() {
    let groups = Mode::Debug(DebugView::Groups);
    let [l, m, r] = quads(&draw(
        &strip_scene(),
        &strip([0, 12, 24]),
        groups,
        "debug-groups",
    ));
    eprintln!("left {l}, middle {m}, right {r}");
    for c in [l, m, r] {
        assert!(c.max_element() > 60.0, "a quad is unlit black: {c}");
    }
    assert!(
        (m - l).length() > 60.0 && (m - r).length() > 60.0,
        "the middle group looks like a neighbour: {l} {m} {r}"
    );
    // Negative control: one group across the strip is one colour.
    let [a, b, c] = quads(&draw(
        &strip_scene(),
        &strip([5, 5, 5]),
        groups,
        "debug-groups-one",
    ));
    assert!(
        (a - b).length() < 12.0 && (b - c).length() < 12.0,
        "one group drew in several colours: {a} {b} {c}"
    );
}

fn srgb_to_linear(c: f32) -> f32 {
    let c = c / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Mean distance (linear RGB) between the pixels under the sphere's camera-facing vertices
/// and the colour `expect` gives each vertex.
fn comb_error(image: &Image, s: &Scene, mesh: &MeshData, expect: impl Fn(usize) -> Vec3) -> f32 {
    let eye = Vec3::from(s.camera.position);
    let view = Mat4::look_at_rh(eye, Vec3::from(s.camera.target), Vec3::from(s.camera.up));
    let aspect = image.width as f32 / image.height as f32;
    let proj = Mat4::perspective_rh(s.camera.fov_y_deg.to_radians(), aspect, 0.5, 20.0);
    let (mut sum, mut n) = (0.0, 0);
    for (k, v) in mesh.vertices.iter().enumerate() {
        let p = Vec3::from(v.position);
        let normal = Vec3::from(v.normal).normalize();
        let to_eye = (eye - p).normalize();
        if normal.dot(to_eye) < 0.8 {
            continue;
        }
        let clip = proj * view * Vec4::from((p, 1.0));
        let ndc = clip.truncate() / clip.w;
        let x = (ndc.x * 0.5 + 0.5) * image.width as f32;
        let y = (0.5 - ndc.y * 0.5) * image.height as f32;
        let px = image.pixel(x as u32, y as u32);
        let got = Vec3::new(
            srgb_to_linear(f32::from(px[0])),
            srgb_to_linear(f32::from(px[1])),
            srgb_to_linear(f32::from(px[2])),
        );
        sum += (got - expect(k)).length();
        n += 1;
    }
    assert!(n > 20, "only {n} vertices face the camera");
    sum / n as f32
}

#[test]
fn the_comb_view_shows_the_comb_decoded_as_the_bake_encoded_it() {
    let mesh = furry_sphere();
    let mut s = scene(16, true, Default::default());
    s.objects[0].asset = PathBuf::from("sphere");
    s.objects[0].material = Material::Opaque;
    let image = draw(&s, &mesh, Mode::Debug(DebugView::Comb), "debug-comb");
    let fur = mesh.fur.as_ref().expect("baked fur");
    let colour =
        |dir: DVec3, length: f32| (dir.normalize().as_vec3() * 0.5 + 0.5) * length.clamp(0.0, 1.0);
    let decoded = |k: usize| {
        let (v, f) = (&mesh.vertices[k], &fur.vertices[k]);
        let (frame, _) = Frame::new(Vec3::from(v.normal), Vec4::from(f.tangent));
        let c = DVec3::new(f.comb[0].into(), f.comb[1].into(), f.comb[2].into());
        colour(frame.comb_direction(c), f.comb[3])
    };
    let raw = |k: usize| {
        let c = fur.vertices[k].comb;
        colour(DVec3::new(c[0].into(), c[1].into(), c[2].into()), c[3])
    };
    let (good, bad) = (
        comb_error(&image, &s, &mesh, decoded),
        comb_error(&image, &s, &mesh, raw),
    );
    eprintln!("comb view against the decoded comb {good:.4}, against the raw comb {bad:.4}");
    assert!(
        good < 0.06,
        "the comb view misses the decoded comb by {good}"
    );
    assert!(
        bad > 3.0 * good,
        "the test cannot tell decoded from raw: {good} vs {bad}"
    );
}
