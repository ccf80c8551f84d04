//! Pixel tests of materials (glTF 2.0 §3.9; Frantzen's textured, normal-mapped,
//! roughness-mapped objects): a quad whose base colour texture is red on the left and blue on
//! the right shows both halves in the deferred and forward renders (and they agree); a normal
//! map tilted toward one side brightens the quad under a light on that side and darkens it
//! under a light on the other; a roughness map dims the highlight where it is rough. Negative
//! controls: the untextured quad has equal halves, and flat normals light both sides alike.

use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;
use pelt_io::picture::{Rgba8, WrappingMode};
use pelt_preview::asset::{MeshData, builtin};
use pelt_preview::scene::{Camera, Light, Material, Object, Size, Transform};
use pelt_preview::{Image, Mode, Scene};
use pelt_scene::material::{self, Texture};

mod common;

use common::{assert_flip, out_dir, preview};

/// A `w` × `h` image coloured `a` where `first(x, y)` holds, `b` elsewhere (RGBA).
fn two_tone(w: u32, h: u32, a: [u8; 4], b: [u8; 4], first: impl Fn(u32, u32) -> bool) -> Rgba8 {
    let pixels = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .flat_map(|(x, y)| if first(x, y) { a } else { b })
        .collect();
    Rgba8 {
        width: w,
        height: h,
        pixels,
    }
}

/// An image whose left half is `left` and right half `right`.
fn halves(w: u32, h: u32, left: [u8; 4], right: [u8; 4]) -> Rgba8 {
    two_tone(w, h, left, right, |x, _| x < w / 2)
}

fn texture(image: Rgba8) -> Option<Texture> {
    Some(Texture {
        image: Arc::new(image),
        wrap: [WrappingMode::ClampToEdge; 2],
    })
}

/// The built-in quad (XY plane, facing +Z) with UVs 0..1 (v down), one material.
fn quad(m: material::Material) -> MeshData {
    let mut q = builtin("quad").expect("quad");
    for v in &mut q.vertices {
        v.uv = [v.position[0] + 0.5, 0.5 - v.position[1]];
    }
    q.materials = vec![m];
    q
}

fn scene(light_at: Vec3) -> Scene {
    lit_scene(light_at, 3.0)
}

fn lit_scene(light_at: Vec3, intensity: f32) -> Scene {
    Scene {
        output: Size {
            width: 128,
            height: 96,
        },
        camera: Camera {
            position: [0.0, 0.0, 2.2],
            target: [0.0; 3],
            near: 0.5,
            far: 10.0,
            ..Camera::default()
        },
        ambient: [0.05; 3],
        objects: vec![Object {
            asset: PathBuf::from("quad"),
            transform: Transform {
                scale: [2.0, 2.0, 1.0],
                ..Transform::default()
            },
            material: Material::Opaque,
            color: [1.0; 3],
        }],
        lights: vec![Light::point(light_at.into(), 8.0, intensity)],
        ..Scene::default()
    }
}

fn draw(p: &mut pelt_preview::Preview, s: &Scene, mesh: &MeshData, mode: Mode) -> Image {
    let d = p
        .prepare_loaded(s, std::slice::from_ref(mesh), &[0], mode)
        .expect("prepare");
    p.render(&d).expect("render")
}

/// Mean RGB over the block of `i` from (x0, y0) to (x1, y1), in fractions of the image.
fn mean(i: &Image, x0: f32, x1: f32, y0: f32, y1: f32) -> Vec3 {
    let (w, h) = (i.width as f32, i.height as f32);
    let mut sum = Vec3::ZERO;
    let mut n = 0.0;
    for y in (y0 * h) as u32..(y1 * h) as u32 {
        for x in (x0 * w) as u32..(x1 * w) as u32 {
            let p = i.pixel(x, y);
            sum += Vec3::new(f32::from(p[0]), f32::from(p[1]), f32::from(p[2]));
            n += 1.0;
        }
    }
    sum / n
}

fn save(i: &Image, name: &str) {
    i.save(&out_dir().join(format!("{name}.png")))
        .expect("write");
}

#[test]
fn a_base_colour_texture_shows_in_deferred_and_forward_alike() {
    let mut p = preview();
    let s = scene(Vec3::new(0.0, 0.0, 1.5));
    let textured = quad(material::Material {
        base_color: texture(halves(16, 16, [230, 40, 40, 255], [40, 40, 230, 255])),
        ..material::Material::default()
    });
    let deferred = draw(&mut p, &s, &textured, Mode::Deferred);
    let forward = draw(&mut p, &s, &textured, Mode::Forward);
    save(&deferred, "material-base-colour");
    assert_flip("material-base-colour", &forward, &deferred, 0.02);
    for (name, i) in [("deferred", &deferred), ("forward", &forward)] {
        let left = mean(i, 0.3, 0.45, 0.3, 0.7);
        let right = mean(i, 0.55, 0.7, 0.3, 0.7);
        assert!(left.x > 2.0 * left.z && left.x > 60.0, "{name} left {left}");
        assert!(
            right.z > 2.0 * right.x && right.z > 60.0,
            "{name} right {right}"
        );
    }
    // Negative control: without the texture both halves are the same colour.
    let plain = draw(
        &mut p,
        &s,
        &quad(material::Material::default()),
        Mode::Deferred,
    );
    let (left, right) = (
        mean(&plain, 0.3, 0.45, 0.3, 0.7),
        mean(&plain, 0.55, 0.7, 0.3, 0.7),
    );
    assert!(
        (left - right).abs().max_element() < 3.0,
        "{left} vs {right}"
    );
}

#[test]
fn a_normal_map_turns_the_surface_toward_the_light() {
    let mut p = preview();
    // Every texel's normal leans 45° toward +U (+X on the quad): (0.707, 0, 0.707) encoded.
    let tilted = [218, 128, 218, 255];
    let mapped = quad(material::Material {
        normal: texture(halves(8, 8, tilted, tilted)),
        ..material::Material::default()
    });
    let flat = quad(material::Material::default());
    // Lights low on either side, so the tilt changes N·L a lot.
    let right = scene(Vec3::new(1.6, 0.0, 0.4));
    let left = scene(Vec3::new(-1.6, 0.0, 0.4));
    for mode in [Mode::Deferred, Mode::Forward] {
        let centre = |s: &Scene, m: &MeshData, p: &mut pelt_preview::Preview| {
            let i = draw(p, s, m, mode);
            mean(&i, 0.4, 0.6, 0.4, 0.6).length()
        };
        let (flat_r, flat_l) = (centre(&right, &flat, &mut p), centre(&left, &flat, &mut p));
        let (map_r, map_l) = (
            centre(&right, &mapped, &mut p),
            centre(&left, &mapped, &mut p),
        );
        // Control: flat normals see both lights alike.
        assert!(
            (flat_r - flat_l).abs() < 0.05 * flat_r,
            "{mode:?} flat {flat_r} {flat_l}"
        );
        assert!(
            map_r > 1.3 * flat_r,
            "{mode:?}: toward the light {map_r} vs flat {flat_r}"
        );
        assert!(
            map_l < 0.7 * flat_l,
            "{mode:?}: away from it {map_l} vs flat {flat_l}"
        );
    }
    save(
        &draw(&mut p, &right, &mapped, Mode::Deferred),
        "material-normal-map",
    );
}

#[test]
fn a_roughness_map_dims_the_highlight_where_it_is_rough() {
    let mut p = preview();
    // Left half smooth (G = 0), right half rough (G = 255); metallic 0 (B = 0).
    let mr = halves(16, 16, [0, 0, 0, 255], [0, 255, 0, 255]);
    let mesh = quad(material::Material {
        metallic_roughness: texture(mr),
        metallic: 0.0,
        roughness: 1.0,
        ..material::Material::default()
    });
    // The light straight in front: the highlight covers the centre; lit from the side of
    // the camera so both halves get the same diffuse light.
    let s = lit_scene(Vec3::new(0.0, 0.0, 1.2), 0.8);
    for mode in [Mode::Deferred, Mode::Forward] {
        let i = draw(&mut p, &s, &mesh, mode);
        let smooth = mean(&i, 0.42, 0.48, 0.4, 0.6);
        let rough = mean(&i, 0.52, 0.58, 0.4, 0.6);
        assert!(
            smooth.x > rough.x + 10.0,
            "{mode:?}: smooth {smooth} rough {rough}"
        );
        if mode == Mode::Deferred {
            save(&i, "material-roughness");
        }
    }
}

/// An image whose top half is `top` and bottom half `bottom`.
fn rows(w: u32, h: u32, top: [u8; 4], bottom: [u8; 4]) -> Rgba8 {
    two_tone(w, h, top, bottom, |_, y| y < h / 2)
}

#[test]
fn fur_takes_its_colour_from_the_base_colour_texture_when_the_config_says_so() {
    let mut p = preview();
    let mut sphere = common::furry_sphere();
    sphere.materials[0].base_color = texture(rows(8, 8, [230, 40, 40, 255], [40, 40, 230, 255]));
    let s = common::scene(16, true, pelt_preview::scene::FurBlend::Stipple);
    // (red − blue) / (red + blue) over bands across the sphere's upper and lower parts (it
    // fills about y = 0.08..0.7 of the image).
    let bands = |i: &Image| {
        let hue = |c: Vec3| (c.x - c.z) / (c.x + c.z + 1.0);
        (
            hue(mean(i, 0.4, 0.6, 0.2, 0.3)),
            hue(mean(i, 0.4, 0.6, 0.5, 0.6)),
        )
    };
    let mut run = |from_texture: bool, name: &str| {
        let mut m = sphere.clone();
        m.fur.as_mut().expect("fur").look.color_from_texture = from_texture;
        let i = draw(&mut p, &s, &m, Mode::Inferred);
        save(&i, name);
        bands(&i)
    };
    let (up, down) = run(true, "material-fur-from-texture");
    assert!(
        up > 0.2 && down < -0.2,
        "the red and blue halves show through the fur: {up} {down}"
    );
    // Negative control: the fur's own colours, the same hue above and below.
    let (up, down) = run(false, "material-fur-own-colour");
    assert!((up - down).abs() < 0.1, "one fur colour: {up} {down}");
}

/// Whether `sv`'s frame draws with a pipeline specialized for untextured materials.
fn draws_untextured(sv: &pelt_preview::SceneView) -> bool {
    let frame = sv.own_frame().expect("frame");
    let recipes =
        pelt_preview::frame::recipes(&frame, pelt_preview::frame::Maps::IfStale).expect("recipes");
    recipes.iter().flat_map(|r| r.keys()).any(|k| {
        k.desc
            .spec
            .constants
            .contains(&(pelt_preview::gpu_material::TEXTURED, 0.0))
    })
}

#[test]
fn an_untextured_material_skips_the_fetches_and_draws_as_the_neutral_texels_do() {
    let mut p = preview();
    let s = scene(Vec3::new(0.3, 0.2, 1.5));
    let white = |v: u8| texture(halves(2, 2, [v, v, v, 255], [v, v, v, 255]));
    // The textured pipeline sampling white texels (the neutral values) ...
    let sampled = quad(material::Material {
        base_color: white(255),
        metallic_roughness: white(255),
        ..material::Material::default()
    });
    let plain = quad(material::Material::default());
    for mode in [Mode::Inferred, Mode::Deferred, Mode::Forward] {
        let a = p
            .prepare_loaded(&s, std::slice::from_ref(&plain), &[0], mode)
            .expect("prepare");
        assert!(draws_untextured(&a), "{mode}: the untextured pipeline");
        let b = p
            .prepare_loaded(&s, std::slice::from_ref(&sampled), &[0], mode)
            .expect("prepare");
        assert!(!draws_untextured(&b), "{mode}: the textured pipeline");
        let (a, b) = (p.render(&a).expect("plain"), p.render(&b).expect("sampled"));
        // ... and the untextured one reading those values without a fetch: the same bytes.
        assert!(
            a.rgba == b.rgba,
            "{mode}: untextured and white-textured differ"
        );
        // Negative control: a texel one step off white is another image.
        let grey = quad(material::Material {
            base_color: white(250),
            ..material::Material::default()
        });
        let c = draw(&mut p, &s, &grey, mode);
        assert!(
            a.rgba != c.rgba,
            "{mode}: the comparison cannot tell textures apart"
        );
    }
}

/// How far the centre of `i` (where the quad is) is from its corner (background), in RGB.
fn centre_contrast(i: &Image) -> f32 {
    (mean(i, 0.4, 0.6, 0.4, 0.6) - mean(i, 0.0, 0.1, 0.0, 0.1)).length()
}

#[test]
fn a_single_sided_material_hides_its_back_and_a_mirrored_object_keeps_its_front() {
    let mut p = preview();
    let single = quad(material::Material::default());
    let double = quad(material::Material {
        double_sided: true,
        ..material::Material::default()
    });
    // Seen from behind, lit from behind.
    let mut behind = scene(Vec3::new(0.3, 0.2, -1.5));
    behind.camera.position = [0.0, 0.0, -2.2];
    // Seen from the front through a mirroring transform (x scaled by -2): its triangles turn
    // clockwise on screen, and are still its front.
    let mut mirrored = scene(Vec3::new(0.3, 0.2, 1.5));
    mirrored.objects[0].transform.scale = [-2.0, 2.0, 1.0];
    for mode in [Mode::Inferred, Mode::Deferred, Mode::Forward] {
        let back = draw(&mut p, &behind, &single, mode);
        let both = draw(&mut p, &behind, &double, mode);
        let front = draw(&mut p, &mirrored, &single, mode);
        save(&back, &format!("single-sided-back-{mode}"));
        save(&front, &format!("single-sided-mirrored-{mode}"));
        assert!(
            centre_contrast(&back) < 1.0,
            "{mode}: the back of a single-sided quad is culled ({})",
            centre_contrast(&back)
        );
        // Negative control: the same view of a double-sided quad shows it.
        assert!(
            centre_contrast(&both) > 20.0,
            "{mode}: a double-sided quad shows its back ({})",
            centre_contrast(&both)
        );
        assert!(
            centre_contrast(&front) > 20.0,
            "{mode}: a mirrored single-sided quad shows its front ({})",
            centre_contrast(&front)
        );
        // Mirrored in x, the symmetric quad is the same picture, lit from its front.
        let plain = draw(&mut p, &scene(Vec3::new(0.3, 0.2, 1.5)), &single, mode);
        let d = (mean(&front, 0.3, 0.7, 0.3, 0.7) - mean(&plain, 0.3, 0.7, 0.3, 0.7)).length();
        assert!(d < 2.0, "{mode}: mirrored and plain quads differ by {d}");
    }
}
