//! The state features keep per scene, made when a scene is prepared and followed on a knob
//! change by looping over the registry: the strand reference's traced shadows refuse a change
//! of lights (the CPU meshes they were traced through are gone) and follow the wind.

mod common;

use glam::Vec3;
use pelt_preview::Mode;
use pelt_preview::scene::FurBlend;

#[test]
fn the_strands_traced_shadows_follow_the_wind_and_refuse_new_lights() {
    let mut p = common::preview();
    let meshes = vec![common::furry_sphere()];
    let mut s = common::scene(4, false, FurBlend::Stipple);
    s.output.width = 48;
    s.output.height = 36;
    s.lights[0].shadows = true;
    let mut sv = p
        .prepare_loaded(&s, &meshes, &[0], Mode::Strands)
        .expect("prepare");
    // The same scene, and a new time in the wind: followed.
    p.update(&mut sv, &s, Mode::Strands)
        .expect("the same scene");
    s.time = 0.5;
    p.update(&mut sv, &s, Mode::Strands).expect("a new time");
    // A light moved: the bits would have to be traced through meshes no longer held.
    s.lights[0].emitter = pelt_scene::shading::Emitter::Point {
        position: Vec3::new(-2.5, 2.5, 3.0),
        radius: 12.0,
    };
    let e = p
        .update(&mut sv, &s, Mode::Strands)
        .expect_err("stale shadows");
    assert!(e.to_string().contains("prepare the scene again"), "{e}");
    // Negative control: outside strands mode no feature traces shadows, so nothing refuses.
    let mut sv = p
        .prepare_loaded(&s, &meshes, &[0], Mode::Forward)
        .expect("prepare");
    s.lights[0].emitter = pelt_scene::shading::Emitter::Point {
        position: Vec3::new(2.5, 2.5, 3.0),
        radius: 12.0,
    };
    p.update(&mut sv, &s, Mode::Forward)
        .expect("forward follows");
}

/// The shadow maps' layers outlive the frame, and the opacity maps draw into them after the
/// shadow pass: a frame that changes neither draws the same image from the kept layers, and a
/// change of the fur alone (its shell count) has both drawn again, so the image equals that
/// of the changed scene prepared afresh. Negative control: the change shows in the image.
#[test]
fn the_shadow_layers_are_kept_until_the_fur_drawn_into_them_changes() {
    let mut p = common::preview();
    let meshes = vec![common::furry_sphere()];
    let lit = |shells| {
        let mut s = common::scene(shells, false, FurBlend::Stipple);
        s.output.width = 64;
        s.output.height = 48;
        s.lights[0].shadows = true;
        s.shadow_maps.opacity_layers = 3;
        s
    };
    let (eight, four) = (lit(8), lit(4));
    let mut sv = p
        .prepare_loaded(&eight, &meshes, &[0], Mode::Forward)
        .expect("prepare");
    let first = p.render(&sv).expect("first frame");
    let kept = p.render(&sv).expect("a frame from the kept layers");
    assert!(
        first.rgba == kept.rgba,
        "the kept layers draw the same image"
    );
    p.update(&mut sv, &four, Mode::Forward)
        .expect("fewer shells");
    let followed = p.render(&sv).expect("after the change");
    let fresh = p
        .prepare_loaded(&four, &meshes, &[0], Mode::Forward)
        .expect("prepared afresh");
    let afresh = p.render(&fresh).expect("a fresh frame");
    assert!(followed.rgba != first.rgba, "the shell count shows");
    assert!(
        followed.rgba == afresh.rgba,
        "the layers were drawn again for the changed fur"
    );
}
