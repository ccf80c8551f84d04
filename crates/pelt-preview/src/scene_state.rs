//! What a feature keeps per scene: state that outlives frames but not the scene (the shadow
//! maps, the strand reference's traced shadows, the distance maps), declared in the
//! feature's descriptor as how it is made for a prepared scene and how it follows a knob
//! change (refitted where it still fits, made again where it does not, dropped where the
//! scene no longer needs it). `Preview::prepare_view` and `Preview::update` loop over the
//! registry; the state is kept in the scene view's [`Owned`] and read only by its feature.

use crate::assets::{AssetCache, GpuSky};
use crate::owned::Owned;
use crate::plan::ScenePlan;
use crate::renderer::Renderer;
use crate::scene::Scene;
use pelt_scene::asset::MeshData;

/// What a scene gives the features that keep state for it.
#[derive(Debug, Clone, Copy)]
pub struct SceneInputs<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// Its camera-independent plan.
    pub plan: &'a ScenePlan,
    /// Its cube-map sky, when it has one.
    pub sky: Option<&'a GpuSky>,
}

/// What a newly prepared scene gives besides: its CPU meshes (by mesh index) and the cache
/// of GPU assets shared with other scenes.
pub struct Prepared<'a> {
    /// The meshes, as loaded.
    pub meshes: &'a [MeshData],
    /// The shared GPU assets.
    pub assets: &'a mut AssetCache,
}

/// A feature's per-scene state, as registered.
#[derive(Debug, Clone, Copy)]
pub struct SceneState {
    /// Makes it for a newly prepared scene (none where the scene needs none).
    pub make:
        fn(&Renderer, &SceneInputs<'_>, &mut Prepared<'_>, &mut Owned) -> Result<(), StateError>,
    /// Follows a knob change (no asset is read): refits it, makes it again where it no
    /// longer fits, drops it where the scene no longer needs it.
    pub follow: fn(&Renderer, &SceneInputs<'_>, &mut Owned) -> Result<(), StateError>,
}

/// State a feature cannot make or follow for a scene, with its feature's own error.
#[derive(Debug, thiserror::Error)]
#[error(transparent)]
pub struct StateError(#[from] pub Box<dyn std::error::Error + Send + Sync>);

impl StateError {
    /// `e` as a state error.
    pub fn of(e: impl std::error::Error + Send + Sync + 'static) -> StateError {
        StateError(Box::new(e))
    }
}
