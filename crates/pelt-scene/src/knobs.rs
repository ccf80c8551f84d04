//! The renderer's knobs as overrides of a scene (the flags of `pelt render` and the keys of
//! `pelt view`): output size, L-buffer scale, DSF, shells, fins and fur blend; and how an
//! input (a scene file or one asset framed by the default scene) becomes a scene.

use std::path::Path;

use crate::asset::{self, AssetError, MeshData};
use crate::scene::{
    FurBlend, FurCoverage, FurLighting, Material, Reflections, Scene, SceneError, Technique,
};

/// Overrides; `None` keeps the scene's value.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Knobs {
    /// Output size.
    pub size: Option<(u32, u32)>,
    /// L-buffer scale (0.1 to 1).
    pub lbuffer_scale: Option<f32>,
    /// Discontinuity sensitive filtering.
    pub dsf: Option<bool>,
    /// Shells per fur object.
    pub shells: Option<u32>,
    /// Silhouette fins.
    pub fins: Option<bool>,
    /// How fur is composited.
    pub fur_blend: Option<FurBlend>,
    /// How much of the skin a shell hides.
    pub fur_coverage: Option<FurCoverage>,
    /// How the deferred paths light fur.
    pub fur_lighting: Option<FurLighting>,
    /// Mirrors and glass.
    pub reflections: ReflectionKnobs,
}

/// Overrides of the scene's `reflections` block; `None` keeps the scene's value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ReflectionKnobs {
    /// The technique.
    pub technique: Option<Technique>,
    /// Linear search steps.
    pub linear_steps: Option<u32>,
    /// Secant steps.
    pub secant_steps: Option<u32>,
    /// Distance-map layers.
    pub layers: Option<u32>,
    /// Cube face size.
    pub cube_size: Option<u32>,
    /// Most bounces.
    pub max_depth: Option<u32>,
    /// Min-max acceleration.
    pub min_max: Option<bool>,
}

impl ReflectionKnobs {
    /// Applies the overrides to `r`.
    pub fn apply(&self, r: &mut Reflections) {
        let set = |v: &mut u32, o: Option<u32>| {
            if let Some(o) = o {
                *v = o;
            }
        };
        if let Some(t) = self.technique {
            r.technique = t;
        }
        set(&mut r.linear_steps, self.linear_steps);
        set(&mut r.secant_steps, self.secant_steps);
        set(&mut r.layers, self.layers);
        set(&mut r.cube_size, self.cube_size);
        set(&mut r.max_depth, self.max_depth);
        if let Some(m) = self.min_max {
            r.min_max = m;
        }
    }
}

impl Knobs {
    /// Applies the overrides to `scene`.
    pub fn apply(&self, scene: &mut Scene) {
        if let Some((w, h)) = self.size {
            scene.output.width = w;
            scene.output.height = h;
        }
        if let Some(s) = self.lbuffer_scale {
            scene.lbuffer_scale = s;
        }
        if let Some(d) = self.dsf {
            scene.dsf = d;
        }
        if let Some(b) = self.fur_blend {
            scene.fur_blend = b;
        }
        if let Some(c) = self.fur_coverage {
            scene.fur_coverage = c;
        }
        if let Some(l) = self.fur_lighting {
            scene.fur_lighting = l;
        }
        self.reflections.apply(&mut scene.reflections);
        for o in &mut scene.objects {
            if let Material::Fur(f) = &mut o.material {
                if self.shells.is_some() {
                    f.shells = self.shells;
                }
                if let Some(on) = self.fins {
                    f.fins = Some(on);
                }
            }
        }
    }
}

/// Why an input could not become a scene.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// The scene file is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The asset could not be loaded.
    #[error(transparent)]
    Asset(#[from] AssetError),
    /// A scene object's asset could not be loaded.
    #[error(transparent)]
    Object(#[from] asset::ObjectAssetError),
}

/// A loaded input: the scene, its meshes and each object's mesh index.
#[derive(Debug, Clone)]
pub struct Input {
    /// The scene (overrides applied).
    pub scene: Scene,
    /// Its meshes.
    pub meshes: Vec<MeshData>,
    /// Object i's mesh is `meshes[mesh_of[i]]`.
    pub mesh_of: Vec<usize>,
}

/// Whether `path` names a scene file (`.json`) rather than an asset.
pub fn is_scene(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// Loads `path`: a scene file with its assets, or one asset in the default scene
/// ([`crate::framing::asset_scene`]) at `default_size` unless `knobs.size` says otherwise.
pub fn load(path: &Path, knobs: &Knobs, default_size: (u32, u32)) -> Result<Input, InputError> {
    load_at(path, knobs, default_size, None)
}

/// [`load`] with animated assets posed at `pose`.
pub fn load_at(
    path: &Path,
    knobs: &Knobs,
    default_size: (u32, u32),
    pose: Option<&asset::PoseAt>,
) -> Result<Input, InputError> {
    let (mut scene, meshes, mesh_of) = if is_scene(path) {
        let scene = Scene::load(path)?;
        let (meshes, of) = asset::load_scene_at(&scene, pose)?;
        (scene, meshes, of)
    } else {
        let mesh = asset::load_at(path, pose)?;
        let (w, h) = knobs.size.unwrap_or(default_size);
        let scene = crate::framing::asset_scene(path, &mesh, w, h);
        (scene, vec![mesh], vec![0])
    };
    knobs.apply(&mut scene);
    Ok(Input {
        scene,
        meshes,
        mesh_of,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{FurSettings, Object};

    #[test]
    fn overrides_reach_every_fur_object_and_leave_the_rest() {
        let mut s = Scene::default();
        for m in [Material::Fur(FurSettings::default()), Material::Opaque] {
            s.objects.push(Object {
                asset: "a.glb".into(),
                transform: Default::default(),
                material: m,
                color: [1.0; 3],
            });
        }
        let before = s.clone();
        Knobs::default().apply(&mut s);
        assert_eq!(s, before, "no overrides, no change");
        Knobs {
            size: Some((64, 32)),
            lbuffer_scale: Some(0.5),
            dsf: Some(false),
            shells: Some(7),
            fins: Some(false),
            fur_blend: Some(FurBlend::Wboit),
            fur_coverage: Some(FurCoverage::Binary),
            fur_lighting: Some(FurLighting::Revie),
            reflections: ReflectionKnobs {
                technique: Some(Technique::Envmap),
                linear_steps: Some(80),
                min_max: Some(false),
                ..Default::default()
            },
        }
        .apply(&mut s);
        assert_eq!(
            (
                s.reflections.technique,
                s.reflections.linear_steps,
                s.reflections.min_max,
                s.reflections.secant_steps
            ),
            (
                Technique::Envmap,
                80,
                false,
                Reflections::default().secant_steps
            )
        );
        assert_eq!((s.output.width, s.output.height), (64, 32));
        assert_eq!(
            (s.lbuffer_scale, s.dsf, s.fur_blend),
            (0.5, false, FurBlend::Wboit)
        );
        assert_eq!(
            (s.fur_coverage, s.fur_lighting),
            (FurCoverage::Binary, FurLighting::Revie)
        );
        let Material::Fur(f) = s.objects[0].material else {
            panic!("fur")
        };
        assert_eq!((f.shells, f.fins), (Some(7), Some(false)));
        assert_eq!(s.objects[1].material, Material::Opaque);
    }

    #[test]
    fn an_asset_gets_the_default_scene_and_a_missing_one_is_named() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        let i = load(&root.join("torus.glb"), &Knobs::default(), (120, 80)).expect("torus");
        assert_eq!((i.scene.output.width, i.scene.output.height), (120, 80));
        assert_eq!((i.meshes.len(), i.mesh_of.clone()), (1, vec![0]));
        let e = load(&root.join("no-such.glb"), &Knobs::default(), (8, 8)).expect_err("missing");
        assert!(e.to_string().contains("no-such.glb"), "{e}");
    }
}
