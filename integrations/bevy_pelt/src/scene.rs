//! A pelt scene file (crates/pelt-scene, `pelt render SCENE`) built in Bevy: its camera,
//! ambient and lights as Bevy's (in the units docs/bevy.md gives), its glTF objects through
//! Bevy's loader with [`crate::PeltFurPlugin`] drawing their fur, its built-in shapes, pelt's
//! opaque surface on every object without fur and pelt's procedural sky. Mirrors, glass and
//! fur springs are not drawn (they are drawn opaque, and springs left still, with a warning).

use bevy::animation::{
    AnimationPlayer,
    graph::{AnimationGraph, AnimationGraphHandle},
};
use bevy::camera::{Exposure, RenderTarget};
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::gltf::{Gltf, GltfAssetLabel};
use bevy::light::{
    DirectionalLightShadowMap, NotShadowCaster, NotShadowReceiver, PointLightShadowMap,
    ShadowFilteringMethod,
};
use bevy::prelude::*;
use bevy::render::view::Msaa;
use pelt_scene::scene::{Material as SceneMaterial, Scene};
use pelt_scene::shading::Emitter;

use crate::extension::PeltFur;
use crate::material::{PeltSurface, PeltSurfaceMaterial, SkyMaterial};
use crate::settings::FurWind;

/// pelt_scene::shading::BACKGROUND: the linear colour behind a scene without a sky.
pub const BACKGROUND: [f32; 3] = [0.02, 0.022, 0.028];

/// A pelt light's intensity as a Bevy point light's lumens (Bevy lights a Lambertian surface
/// by lumens / 4π / π; pelt by its intensity).
pub const POINT_LUMENS_PER_INTENSITY: f32 = 4.0 * std::f32::consts::PI * std::f32::consts::PI;

/// A pelt directional light's intensity as a Bevy directional light's lux.
pub const SUN_LUX_PER_INTENSITY: f32 = std::f32::consts::PI;

/// How a scene is drawn.
#[derive(Clone, Debug, Default)]
pub struct SceneOptions {
    /// The animation every animated object plays (None: the bind pose, as pelt).
    pub animation: Option<String>,
    /// The time of the animation and of the wind, in seconds.
    pub time: f32,
}

/// One glTF object of the scene.
#[derive(Clone, Debug)]
pub struct SceneObject {
    /// `objects[i]: ASSET`, for messages.
    pub place: String,
    /// The glTF.
    pub gltf: Handle<Gltf>,
    /// The entity its scene is spawned under.
    pub root: Entity,
    /// Whether its fur is drawn (`"material": {"kind": "fur"}`).
    pub fur: bool,
    /// Whether its animation is posed (or none was asked for).
    pub posed: bool,
}

/// What the scene became: its camera and glTF objects, and what went wrong.
#[derive(Resource, Clone, Debug, Default)]
pub struct PeltScene {
    /// The camera.
    pub camera: Option<Entity>,
    /// The glTF objects.
    pub objects: Vec<SceneObject>,
    /// The options it is drawn with.
    pub options: SceneOptions,
    /// Errors (an asset that failed to load, a missing animation), each naming the place.
    pub errors: Vec<String>,
}

fn linear(c: [f32; 3]) -> Color {
    Color::linear_rgb(c[0], c[1], c[2])
}

/// pelt's opaque surface over `m`.
pub fn surface(m: StandardMaterial) -> PeltSurfaceMaterial {
    PeltSurfaceMaterial {
        base: m,
        extension: PeltSurface {},
    }
}

fn builtin(name: &str) -> Option<(Mesh, bool)> {
    match name {
        "builtin:quad" => Some((Rectangle::new(1.0, 1.0).into(), true)),
        "builtin:cube" => Some((Cuboid::new(1.0, 1.0, 1.0).into(), false)),
        "builtin:sphere" => Some((Sphere::new(0.5).mesh().uv(48, 24), false)),
        _ => None,
    }
}

/// Everything spawning needs from the world.
pub struct Spawner<'a, 'w, 's> {
    /// Commands.
    pub commands: &'a mut Commands<'w, 's>,
    /// The asset server (its root: the scene file's folder).
    pub assets: &'a AssetServer,
    /// Meshes.
    pub meshes: &'a mut Assets<Mesh>,
    /// pelt's surfaces.
    pub surfaces: &'a mut Assets<PeltSurfaceMaterial>,
    /// The sky.
    pub skies: &'a mut Assets<SkyMaterial>,
}

/// Spawns `scene` drawn to `target` at `size`; its glTF assets are loaded by their paths as
/// `Scene::load` resolved them, so the asset server's root must be the working directory
/// ([`asset_root`]).
pub fn spawn(
    s: &mut Spawner,
    scene: &Scene,
    size: UVec2,
    target: RenderTarget,
    options: SceneOptions,
) -> PeltScene {
    let mut out = PeltScene {
        options: options.clone(),
        ..default()
    };
    out.camera = Some(spawn_camera(s, scene, size, target));
    let c = &scene.camera;
    let shadow_size = scene.shadow_maps.size;
    for (i, l) in scene.lights.iter().enumerate() {
        spawn_light(s.commands, l, i, Vec3::from(c.target), shadow_size);
    }
    s.commands.insert_resource(PointLightShadowMap {
        size: shadow_size as usize,
    });
    s.commands.insert_resource(DirectionalLightShadowMap {
        size: shadow_size as usize,
    });
    let wind = scene.wind.map_or_else(FurWind::default, |w| FurWind {
        direction: Vec3::from(w.direction.to_array()),
        strength: w.strength,
        gust_hz: w.gust_hz,
        turbulence: w.turbulence,
        time: None,
    });
    s.commands.insert_resource(FurWind {
        time: Some(options.time),
        ..wind
    });
    for (i, o) in scene.objects.iter().enumerate() {
        spawn_object(s, &mut out, i, o);
    }
    out
}

/// The scene's camera as pelt's (no tonemapping, exposure 1, no MSAA, its shadow filter and
/// ambient), and its sky.
fn spawn_camera(s: &mut Spawner, scene: &Scene, size: UVec2, target: RenderTarget) -> Entity {
    let c = &scene.camera;
    let eye = Vec3::from(c.position);
    let camera = s
        .commands
        .spawn((
            Camera3d::default(),
            Camera {
                clear_color: ClearColorConfig::Custom(linear(BACKGROUND)),
                ..default()
            },
            target,
            Projection::Perspective(PerspectiveProjection {
                fov: c.fov_y_deg.to_radians(),
                near: c.near,
                far: c.far,
                aspect_ratio: size.x as f32 / size.y as f32,
                ..default()
            }),
            Transform::from_translation(eye).looking_at(Vec3::from(c.target), Vec3::from(c.up)),
            Tonemapping::None,
            DebandDither::Disabled,
            Msaa::Off,
            Exposure {
                ev100: -(1.2f32).log2(),
            },
            // pelt's shadow filter: `pcf` 2 is a bilinear 2×2 comparison, which the hardware
            // does; wider kernels map to Bevy's Gaussian.
            if scene.shadow_maps.pcf <= 2 {
                ShadowFilteringMethod::Hardware2x2
            } else {
                ShadowFilteringMethod::Gaussian
            },
            AmbientLight {
                color: linear(scene.ambient),
                brightness: 1.0,
                ..default()
            },
        ))
        .id();
    match scene.sky {
        pelt_scene::scene::Sky::Procedural => {
            let sphere = s.meshes.add(Sphere::new(c.far * 0.9).mesh().uv(64, 32));
            s.commands.spawn((
                Mesh3d(sphere),
                MeshMaterial3d(s.skies.add(SkyMaterial {})),
                Transform::from_translation(eye),
                NotShadowCaster,
                NotShadowReceiver,
            ));
        }
        pelt_scene::scene::Sky::Cubemap(_) => {
            warn!("sky: cube-map skies are not drawn by bevy_pelt (the background colour is)");
        }
        pelt_scene::scene::Sky::None => {}
    }
    camera
}

/// One light; a point light's depth bias is a texel of its shadow cube at the camera's target
/// (pelt biases by a texel wherever the lookup is; Bevy by a constant distance).
fn spawn_light(
    commands: &mut Commands,
    l: &pelt_scene::scene::Light,
    i: usize,
    target: Vec3,
    shadow_size: u32,
) {
    let color = linear(l.color);
    let name = Name::new(format!("lights[{i}]"));
    match l.emitter {
        Emitter::Point { position, radius } => {
            let p = Vec3::from(position.to_array());
            let texel = 2.0 * p.distance(target) / shadow_size.max(1) as f32;
            commands.spawn((
                PointLight {
                    color,
                    intensity: l.intensity.0 * POINT_LUMENS_PER_INTENSITY,
                    range: radius,
                    radius: 0.0,
                    shadow_maps_enabled: l.shadows,
                    shadow_depth_bias: texel.max(PointLight::DEFAULT_SHADOW_DEPTH_BIAS),
                    ..default()
                },
                Transform::from_translation(p),
                name,
            ));
        }
        Emitter::Directional { direction } => {
            let d = Vec3::from(direction.to_array());
            commands.spawn((
                DirectionalLight {
                    color,
                    illuminance: l.intensity.0 * SUN_LUX_PER_INTENSITY,
                    shadow_maps_enabled: l.shadows,
                    ..default()
                },
                Transform::default().looking_to(d, up_for(d)),
                name,
            ));
        }
        Emitter::Spot {
            position,
            direction,
            radius,
            inner,
            outer,
        } => {
            // Bevy's spot light spreads its lumens as a point light's does (its cone masks
            // them), and takes an outer angle below a right angle.
            let p = Vec3::from(position.to_array());
            let d = Vec3::from(direction.to_array());
            let texel = 2.0 * p.distance(target) / shadow_size.max(1) as f32;
            let outer = outer.min(std::f32::consts::FRAC_PI_2 - 1e-3);
            commands.spawn((
                SpotLight {
                    color,
                    intensity: l.intensity.0 * POINT_LUMENS_PER_INTENSITY,
                    range: radius,
                    radius: 0.0,
                    shadow_maps_enabled: l.shadows,
                    shadow_depth_bias: texel.max(SpotLight::DEFAULT_SHADOW_DEPTH_BIAS),
                    inner_angle: inner.min(outer),
                    outer_angle: outer,
                    ..default()
                },
                Transform::from_translation(p).looking_to(d, up_for(d)),
                name,
            ));
        }
    }
}

/// An up vector for a light looking along `d`: +y, or +z where it looks nearly straight
/// up or down.
fn up_for(d: Vec3) -> Vec3 {
    if d.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y }
}

fn spawn_object(s: &mut Spawner, out: &mut PeltScene, i: usize, o: &pelt_scene::scene::Object) {
    let t = &o.transform;
    let transform = Transform {
        translation: Vec3::from(t.translation),
        rotation: Quat::from_array(t.rotation).normalize(),
        scale: Vec3::from(t.scale),
    };
    let asset = o.asset.to_string_lossy().into_owned();
    let place = format!("objects[{i}]: {asset}");
    if let Some((mesh, quad)) = builtin(&asset) {
        let m = StandardMaterial {
            base_color: linear(o.color),
            metallic: 0.0,
            perceptual_roughness: 0.5,
            double_sided: quad,
            cull_mode: if quad {
                None
            } else {
                Some(bevy::render::render_resource::Face::Back)
            },
            ..default()
        };
        s.commands.spawn((
            Mesh3d(s.meshes.add(mesh)),
            MeshMaterial3d(s.surfaces.add(surface(m))),
            transform,
            Name::new(place),
        ));
        return;
    }
    let fur = matches!(o.material, SceneMaterial::Fur(_));
    if !fur && !matches!(o.material, SceneMaterial::Opaque) {
        warn!("{place}: this material kind is drawn opaque by bevy_pelt");
    }
    if let SceneMaterial::Fur(f) = &o.material
        && f.spring.is_some()
    {
        warn!("{place}: fur springs are not drawn by bevy_pelt (the fur is still)");
    }
    let gltf: Handle<Gltf> = s.assets.load(asset.clone());
    let scene = s.assets.load(GltfAssetLabel::Scene(0).from_asset(asset));
    let (shells, length, fins) = match &o.material {
        SceneMaterial::Fur(f) => (f.shells, f.length, f.fins),
        _ => (None, None, None),
    };
    let object = PeltObject {
        tint: Vec3::from(o.color),
        fur,
        shells,
        length,
        fins,
    };
    let root = s
        .commands
        .spawn((
            WorldAssetRoot(scene),
            transform,
            Name::new(place.clone()),
            object,
        ))
        .id();
    let posed = out.options.animation.is_none();
    out.objects.push(SceneObject {
        place,
        gltf,
        root,
        fur,
        posed,
    });
}

/// On a scene object's root (or any ancestor of a fur mesh): its tint, whether its fur is
/// drawn, and the scene file's overrides of the fur's manifest.
#[derive(Component, Clone, Copy, Debug)]
pub struct PeltObject {
    /// Linear colour multiplied into its base colour.
    pub tint: Vec3,
    /// Whether its fur is drawn.
    pub fur: bool,
    /// A shell count (forces the count: no rule).
    pub shells: Option<u32>,
    /// A fur length in mesh units.
    pub length: Option<f32>,
    /// Fins on or off (None: by the coverage).
    pub fins: Option<bool>,
}

/// Gives every mesh of a scene object without fur pelt's surface (the object's tint
/// multiplied in), and takes the fur off objects whose material is not fur.
pub fn surfaces(
    mut commands: Commands,
    meshes: Query<(Entity, &MeshMaterial3d<StandardMaterial>, Has<PeltFur>)>,
    parents: Query<&ChildOf>,
    objects: Query<&PeltObject>,
    standard: Res<Assets<StandardMaterial>>,
    mut surfaces: ResMut<Assets<PeltSurfaceMaterial>>,
) {
    // Only meshes that still have Bevy's material: each is replaced once.
    for (e, material, has_fur) in &meshes {
        let Some(object) = parents.iter_ancestors(e).find_map(|a| objects.get(a).ok()) else {
            continue;
        };
        if has_fur && object.fur {
            continue;
        }
        let Some(m) = standard.get(&material.0) else {
            continue;
        };
        let mut m = m.clone();
        m.base_color = (m.base_color.to_linear().to_vec3() * object.tint)
            .extend(m.base_color.alpha())
            .into_linear_color();
        commands
            .entity(e)
            .remove::<MeshMaterial3d<StandardMaterial>>()
            .remove::<PeltFur>()
            .insert(MeshMaterial3d(surfaces.add(surface(m))));
    }
}

trait IntoLinear {
    fn into_linear_color(self) -> Color;
}

impl IntoLinear for Vec4 {
    fn into_linear_color(self) -> Color {
        Color::LinearRgba(LinearRgba::new(self.x, self.y, self.z, self.w))
    }
}

/// Poses each object's animation at the scene's time once its glTF and players are there;
/// a clip the file lacks is an error naming the object and the clips it has.
pub fn pose(
    mut commands: Commands,
    mut scene: ResMut<PeltScene>,
    gltfs: Res<Assets<Gltf>>,
    children: Query<&Children>,
    mut players: Query<&mut AnimationPlayer>,
    mut graphs: ResMut<Assets<AnimationGraph>>,
    clips: Res<Assets<AnimationClip>>,
) {
    let Some(name) = scene.options.animation.clone() else {
        return;
    };
    let time = scene.options.time;
    let mut errors = Vec::new();
    for o in scene.objects.iter_mut().filter(|o| !o.posed) {
        let Some(g) = gltfs.get(&o.gltf) else {
            continue;
        };
        let found: Vec<Entity> = children
            .iter_descendants(o.root)
            .filter(|e| players.contains(*e))
            .collect();
        if found.is_empty() {
            if g.animations.is_empty() {
                o.posed = true;
            }
            continue;
        }
        let Some(clip) = g.named_animations.get(name.as_str()) else {
            let mut have: Vec<&str> = g.named_animations.keys().map(|k| k.as_ref()).collect();
            have.sort_unstable();
            errors.push(format!(
                "{}: no animation \"{name}\" (has {})",
                o.place,
                if have.is_empty() {
                    "none".into()
                } else {
                    have.join(", ")
                }
            ));
            o.posed = true;
            continue;
        };
        let duration = clips.get(clip).map_or(0.0, |c| c.duration());
        let (graph, node) = AnimationGraph::from_clip(clip.clone());
        let graph = graphs.add(graph);
        for e in found {
            if let Ok(mut p) = players.get_mut(e) {
                p.play(node).seek_to(time.min(duration)).pause();
            }
            commands
                .entity(e)
                .insert(AnimationGraphHandle(graph.clone()));
        }
        o.posed = true;
    }
    scene.errors.extend(errors);
}

/// Whether every asset of `scene` (as `Scene::load` resolved them, against the working
/// directory) is a file the scene can load, or why not (checked before Bevy starts, so that a
/// bad scene writes nothing).
pub fn check_assets(scene: &Scene) -> Result<(), String> {
    for (i, o) in scene.objects.iter().enumerate() {
        let a = o.asset.to_string_lossy();
        if a.starts_with("builtin:") {
            if builtin(&a).is_none() {
                return Err(format!(
                    "objects[{i}].asset: {a}: unknown built-in shape (known: builtin:cube, builtin:sphere, builtin:quad)"
                ));
            }
            continue;
        }
        if !o.asset.is_file() {
            return Err(format!(
                "objects[{i}].asset: {}: no such file",
                o.asset.display()
            ));
        }
    }
    Ok(())
}

/// The asset root a scene loaded by `Scene::load` needs: the working directory, absolute
/// (Bevy resolves a relative root against the executable's folder).
pub fn asset_root() -> String {
    std::env::current_dir()
        .map(|d| d.to_string_lossy().into_owned())
        .unwrap_or_else(|_| ".".into())
}
