//! The demo's painted creature: the fixture generator's creature (a painted comb field,
//! `pelt_fixtures::shapes::creature`) baked with the demo's fur (Revie §2.4.1's comb bake, the
//! seeded strand model's textures). `pelt demo` renders it, `pelt render-bench --experiment
//! fur` times it, and the sweep measures its scene, so all three draw one asset.

use std::path::Path;

use pelt_bake::BakeOptions;
use pelt_bake::fur::{FurAssets, bake_with_fur};
use pelt_fixtures::build::{BuildOptions, ColorEncoding, document};
use pelt_fur::{FurConfig, FurError, StrandParams};
use pelt_io::IoError;

/// Why the demo creature could not be made.
#[derive(Debug, thiserror::Error)]
pub enum DemoCreatureError {
    /// The fur textures could not be generated.
    #[error("generating the demo creature's fur textures: {0}")]
    Textures(#[source] FurError),
    /// The bake or the write failed.
    #[error("baking the demo creature: {0}")]
    Bake(#[source] IoError),
}

/// The demo's fur: `fixtures/fur.json`'s strands and colours, with fur long enough to read at
/// a glance (the creature is about 4 units long).
pub fn demo_fur() -> FurConfig {
    FurConfig {
        length: 0.09,
        uv_scale: 6.0,
        base_color: [0.08, 0.05, 0.03],
        tip_color: [0.62, 0.47, 0.31],
        textures: StrandParams {
            seed: 7,
            size: 512,
            strands: 12000,
            radius: 0.0025,
            radius_jitter: 0.3,
            height_min: 0.4,
            height_max: 1.0,
            tilt: 1.5,
            ..StrandParams::default()
        },
        ..FurConfig::default()
    }
}

/// Bakes the fixture creature with [`demo_fur`] into `path` (a `.glb`, written atomically).
pub fn bake_creature(path: &Path) -> Result<(), DemoCreatureError> {
    let mut doc = document(
        &pelt_fixtures::shapes::creature(64, 128),
        BuildOptions {
            colors: ColorEncoding::U8x4,
            ..BuildOptions::default()
        },
    );
    let assets = FurAssets::new(demo_fur()).map_err(DemoCreatureError::Textures)?;
    bake_with_fur(&mut doc, &BakeOptions::default(), &assets).map_err(DemoCreatureError::Bake)?;
    pelt_io::glb::write_glb(&doc, path).map_err(DemoCreatureError::Bake)?;
    Ok(())
}
