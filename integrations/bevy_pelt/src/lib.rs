//! bevy_pelt: pelt's baked fur (the `PELT_fur` glTF extension, docs/extension/PELT_fur) drawn
//! in Bevy as pelt's forward mode draws it (Revie, "Implementing Fur Using Deferred Shading",
//! §2.3–2.4: shells along the comb, Kajiya-Kay lighting), with Bevy's glTF loader, lights,
//! shadow maps, skinning and animation.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_pelt::PeltFurPlugin;
//!
//! App::new()
//!     .add_plugins((DefaultPlugins, PeltFurPlugin))
//!     .add_systems(Startup, |mut commands: Commands, assets: Res<AssetServer>| {
//!         commands.spawn(WorldAssetRoot(assets.load("fox.glb#Scene0")));
//!     })
//!     .run();
//! ```
//!
//! Modules: [`extension`] reads the extension as Bevy loads a glTF; [`attach`] draws the fur
//! of the entities it tagged; [`rule`] sets the shells by screen size and the wind each frame;
//! [`material`] holds the materials and [`shaders`] the WGSL (pelt's own shared modules and
//! the plumbing to Bevy's); [`scene`] builds a pelt scene file in Bevy.

pub mod attach;
pub mod extension;
pub mod fins;
pub mod material;
pub mod rule;
pub mod scene;
pub mod settings;
pub mod shaders;

use bevy::gltf::extensions::GltfExtensionHandlers;
use bevy::pbr::MaterialPlugin;
use bevy::prelude::*;

pub use attach::{FurAttached, FurShell};
pub use extension::{PeltFur, PeltFurData, PeltFurError};
pub use material::{FurMaterial, PeltSurfaceMaterial, SkyMaterial};
pub use settings::{FurControl, FurSettings, FurWind};

/// Draws the fur of every glTF the app loads after it is added (add it after Bevy's
/// `DefaultPlugins`, or after its `GltfPlugin`).
#[derive(Default)]
pub struct PeltFurPlugin;

impl Plugin for PeltFurPlugin {
    fn build(&self, app: &mut App) {
        shaders::register(app);
        app.init_asset::<PeltFurData>()
            .register_type::<PeltFur>()
            .register_type::<Handle<PeltFurData>>()
            .register_type::<PeltFurError>()
            .init_resource::<FurSettings>()
            .init_resource::<FurWind>()
            .add_plugins((
                MaterialPlugin::<FurMaterial>::default(),
                MaterialPlugin::<fins::FinMaterial>::default(),
                MaterialPlugin::<PeltSurfaceMaterial>::default(),
                MaterialPlugin::<SkyMaterial>::default(),
            ))
            .add_systems(
                Update,
                (attach::attach_fur, rule::apply_rule, rule::apply_wind).chain(),
            );
        match app.world().get_resource::<GltfExtensionHandlers>() {
            Some(handlers) => handlers
                .0
                .write_blocking()
                .push(Box::new(extension::FurExtensionHandler::default())),
            None => error!("bevy_pelt: PeltFurPlugin needs Bevy's GltfPlugin added before it"),
        }
    }
}
