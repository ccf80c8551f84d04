//! The ray tracer's fur (`--mode raytrace`): fur objects traced as the strand reference's
//! strands, for camera rays, reflections and shadow rays. On the baked fixture creature in
//! front of a planar mirror (fixtures/scenes/creature-mirror.json's stage) at test size, the
//! fur differs from the same creature with its fur length near zero both where it is seen
//! directly and where the mirror shows it (the old truth, the base mesh in the fur's mean
//! colour, is the negative control: it barely differs); without a mirror, the traced fur
//! agrees with the converged strand reference within twice the reference's own noise; and
//! the preview's mirror shows the creature's fur (its shells in the distance maps) as bright
//! as the ray tracer's, where the skin alone is far darker. A failed
//! comparison leaves `-reference.png`, `-actual.png` and `-diff.png` in
//! `target/render-tests/`.

mod common;

use std::path::{Path, PathBuf};

use common::{preview, save_failure};
use pelt_bake::BakeOptions;
use pelt_bake::fur::{FurAssets, bake_with_fur};
use pelt_fur::FurConfig;
use pelt_measure::Flip;
use pelt_measure::strands::{self, Options};
use pelt_preview::knobs::{self, Knobs};
use pelt_preview::scene::{FurSettings, Material};
use pelt_preview::{Image, Scene};
use pelt_scene::plan::{MeshInfo, ScenePlan};
use pelt_trace::{SkyModel, World};

const SIZE: (u32, u32) = (160, 90);

struct Loaded {
    scene: Scene,
    meshes: Vec<pelt_preview::asset::MeshData>,
    of: Vec<usize>,
}

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// fixtures/scenes/creature-mirror.json with the fixture creature (baked as it loads) in
/// place of the demo's, at `size`; `mirror`: keep the mirror and its frame.
fn creature_stage(name: &str, size: (u32, u32), mirror: bool) -> Loaded {
    let text = std::fs::read_to_string(fixtures().join("scenes/creature-mirror.json"))
        .expect("creature-mirror.json");
    let mut json: serde_json::Value = serde_json::from_str(&text).expect("json");
    // One folder per stage: the tests run in parallel and each bakes its own creature.
    let dir = common::out_dir().join(format!("fur-trace-{name}"));
    std::fs::create_dir_all(&dir).expect("scratch");
    let creature = baked_creature(&dir);
    json["objects"][0]["asset"] = creature.to_str().expect("utf8").into();
    if !mirror {
        json["objects"].as_array_mut().expect("objects").truncate(2);
    }
    let path = dir.join("stage.json");
    std::fs::write(&path, json.to_string()).expect("write");
    let k = Knobs {
        size: Some(size),
        ..Knobs::default()
    };
    let i = knobs::load(&path, &k, size).expect("the stage");
    Loaded {
        scene: i.scene,
        meshes: i.meshes,
        of: i.mesh_of,
    }
}

/// fixtures/creature.glb baked with the default generated fur, as `pelt bake` bakes it,
/// written into `dir`.
fn baked_creature(dir: &Path) -> PathBuf {
    let mut doc = pelt_io::load(&fixtures().join("creature.glb")).expect("the creature");
    let assets = FurAssets::new(FurConfig::default()).expect("fur textures");
    bake_with_fur(&mut doc, &BakeOptions::default(), &assets).expect("bake");
    let out = dir.join("creature.glb");
    pelt_io::glb::write_glb(&doc, &out).expect("write");
    out
}

/// `scene` with its fur object's fur `length` long.
fn with_fur_length(scene: &Scene, length: f32) -> Scene {
    let mut s = scene.clone();
    s.objects[0].material = Material::Fur(FurSettings {
        length: Some(length),
        ..FurSettings::default()
    });
    s
}

fn image(t: pelt_trace::Traced) -> (Image, Vec<bool>) {
    (
        Image {
            width: t.width,
            height: t.height,
            rgba: t.rgba,
        },
        t.reflective,
    )
}

fn traced(l: &Loaded, scene: &Scene) -> (Image, Vec<bool>) {
    image(pelt_trace::trace_scene(scene, &l.meshes, &l.of).expect("ray tracer"))
}

/// The old truth: fur objects as their base mesh in the fur's mean colour.
fn traced_bald(l: &Loaded, scene: &Scene) -> Image {
    let infos: Vec<MeshInfo> = l.meshes.iter().map(MeshInfo::of).collect();
    let plan = ScenePlan::new(scene, &infos, &l.of, pelt_scene::Mode::Forward);
    let world = World::new(&plan, &l.meshes, SkyModel::Procedural);
    let view = pelt_scene::view::View::new(scene);
    let size = (scene.output.width, scene.output.height);
    image(pelt_trace::render(&world, &plan, &view, size)).0
}

/// Pixels that differ by more than 2 levels in any channel.
fn differ(a: &Image, b: &Image) -> Vec<bool> {
    a.rgba
        .chunks_exact(4)
        .zip(b.rgba.chunks_exact(4))
        .map(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 2))
        .collect()
}

#[test]
fn the_ray_tracer_draws_fur_seen_directly_and_in_a_mirror() {
    let l = creature_stage("bald", SIZE, true);
    let (fur, mirror) = traced(&l, &l.scene);
    let short = with_fur_length(&l.scene, 1e-4);
    let (bald, _) = traced(&l, &short);
    // Where the creature is: the pixels that change when it goes.
    let mut empty = l.scene.clone();
    empty.objects[0].transform.scale = [1e-6; 3];
    let (gone, _) = traced(&l, &empty);
    let creature = differ(&fur, &gone);
    let direct: Vec<bool> = creature
        .iter()
        .zip(&mirror)
        .map(|(&c, &m)| c && !m)
        .collect();
    let reflected: Vec<bool> = creature
        .iter()
        .zip(&mirror)
        .map(|(&c, &m)| c && m)
        .collect();
    let count = |m: &[bool]| m.iter().filter(|&&b| b).count();
    assert!(
        count(&direct) > 500 && count(&reflected) > 100,
        "the creature is seen directly ({}) and in the mirror ({})",
        count(&direct),
        count(&reflected)
    );
    let f = Flip::new(&bald, &fur).expect("same size");
    let (seen, in_mirror) = (f.masked_mean(&direct), f.masked_mean(&reflected));
    eprintln!("fur vs fur length 1e-4: FLIP {seen:.4} seen directly, {in_mirror:.4} in the mirror");
    if seen < 0.05 || in_mirror < 0.05 {
        save_failure("fur-trace-bald", &bald, &fur);
    }
    assert!(seen >= 0.05, "seen directly: {seen}");
    assert!(in_mirror >= 0.05, "in the mirror: {in_mirror}");
    // The negative control: the old truth, bald in the fur's mean colour, is nearly the
    // same with its fur or without.
    let old = traced_bald(&l, &l.scene);
    let old_short = traced_bald(&l, &short);
    let g = Flip::new(&old_short, &old).expect("same size");
    let old_mirror = g.masked_mean(&reflected);
    eprintln!("the old truth: FLIP {old_mirror:.4} in the mirror");
    assert!(old_mirror < 0.05, "the old truth drew no fur: {old_mirror}");
}

/// Without a mirror, the traced fur (32×32 rays per pixel) against the converged strand
/// reference (the GPU's strands): within twice the reference's own noise, its two halves'
/// FLIP against each other (about 0.008), and far closer than the old truth (the base mesh in
/// the fur's mean colour, the negative control).
#[test]
fn the_ray_tracers_fur_is_close_to_the_strand_reference() {
    let size = (128, 72);
    let l = creature_stage("strands", size, false);
    let converged = |scene: &Scene| {
        image(
            pelt_trace::trace_scene_sampled(scene, &l.meshes, &l.of, Some(32), &|_| {})
                .expect("ray tracer"),
        )
        .0
    };
    let fur = converged(&l.scene);
    let mut p = preview();
    let opts = Options {
        target: 0.02,
        ..Options::default()
    };
    let reference =
        strands::reference(&mut p, &l.scene, &l.meshes, &l.of, opts).expect("the strand reference");
    eprintln!("reference: {reference}");
    let mut empty = l.scene.clone();
    empty.objects[0].transform.scale = [1e-6; 3];
    let gone = converged(&empty);
    let creature = differ(&fur, &gone);
    let over = Flip::new(&reference.image, &fur)
        .expect("same size")
        .masked_mean(&creature);
    let old = Flip::new(&reference.image, &traced_bald(&l, &l.scene))
        .expect("same size")
        .masked_mean(&creature);
    eprintln!(
        "against the strand reference over the creature: traced fur FLIP {over:.4}, the old truth {old:.4}; the reference's half-vs-half {:.4}",
        reference.half_vs_half
    );
    let within = 2.0 * reference.half_vs_half;
    if over > within {
        save_failure("fur-trace-vs-strands", &reference.image, &fur);
    }
    assert!(
        over <= within,
        "traced fur against the strands: {over:.4} > twice the reference's half-vs-half {within:.4}"
    );
    assert!(
        old >= 2.0 * over,
        "the old truth is not as close: {old} vs {over}"
    );
}

/// The preview's fur in the mirror (the shells drawn into the distance maps) against the
/// fur-tracing ray tracer, in the default (inferred) and forward modes, over the pixels where
/// both show the creature in the mirror: the reflected fur's brightness and FLIP. The
/// negative control: the creature with its fur length near zero, bald in the mirror as the
/// maps drew every fur object before, is far darker there.
#[test]
fn the_preview_shows_fur_in_the_mirror_as_the_ray_tracer_does() {
    let l = creature_stage("preview", (320, 180), true);
    let (fur, mirror) = traced(&l, &l.scene);
    let mut empty = l.scene.clone();
    empty.objects[0].transform.scale = [1e-6; 3];
    let (gone, _) = traced(&l, &empty);
    let reflected: Vec<bool> = differ(&fur, &gone)
        .iter()
        .zip(&mirror)
        .map(|(&c, &m)| c && m)
        .collect();
    let count = |m: &[bool]| m.iter().filter(|&&b| b).count();
    assert!(count(&reflected) > 400, "the mirror shows the creature");
    let mut p = preview();
    let mut render = |scene: &Scene, mode| {
        let view = p
            .prepare_loaded(scene, &l.meshes, &l.of, mode)
            .expect("prepare");
        p.render(&view).expect("render")
    };
    let forward = pelt_preview::Mode::Forward;
    let preview_gone = render(&empty, forward);
    let bald = render(&with_fur_length(&l.scene, 1e-4), forward);
    let truth = pelt_measure::luminance::mean_luminance(&fur, &reflected);
    let mut shown = Vec::new();
    for (name, mode) in [
        ("inferred", pelt_preview::Mode::Inferred),
        ("forward", forward),
    ] {
        let ours = render(&l.scene, mode);
        // Where the preview's mirror shows the creature too.
        let both: Vec<bool> = differ(&ours, &preview_gone)
            .iter()
            .zip(&reflected)
            .map(|(&c, &r)| c && r)
            .collect();
        let f = Flip::new(&fur, &ours).expect("same size");
        let ratio = pelt_measure::luminance::mean_luminance(&ours, &both)
            / pelt_measure::luminance::mean_luminance(&fur, &both);
        eprintln!(
            "{name}: reflected fur FLIP {:.4} over the {} pixels both show it, {:.4} over all {} the ray tracer's mirror shows it; brightness {ratio:.3}× the ray tracer's",
            f.masked_mean(&both),
            count(&both),
            f.masked_mean(&reflected),
            count(&reflected),
        );
        if !(0.9..=1.1).contains(&ratio) {
            save_failure(&format!("fur-mirror-{name}"), &fur, &ours);
        }
        assert!(
            count(&both) * 2 > count(&reflected),
            "{name}: the preview's mirror shows the creature"
        );
        assert!(
            (0.9..=1.1).contains(&ratio),
            "{name}: reflected fur {ratio:.3}× as bright as the ray tracer's"
        );
        shown.push(both);
    }
    let dark = pelt_measure::luminance::mean_luminance(&bald, &shown[1])
        / pelt_measure::luminance::mean_luminance(&fur, &shown[1]);
    eprintln!("bald in the mirror: {dark:.3}× the ray tracer's brightness (truth {truth:.3})");
    assert!(dark < 0.9, "the bald creature in the mirror: {dark:.3}×");
}
