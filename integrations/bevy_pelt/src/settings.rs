//! The plugin's resources: how many shells to draw ([`FurSettings`]) and the wind the fur
//! bends in ([`FurWind`], pelt's scene `wind`: crates/pelt-scene/src/wind.rs).

use bevy::prelude::*;

/// Negative controls for the tests: a picture drawn wrong on purpose, which a comparison
/// against pelt must reject.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Reflect)]
pub enum FurControl {
    /// Every shell opaque (no coverage from the strand model).
    OpaqueShells,
    /// The shells cast no shadows (the fur casts as its base mesh).
    NoFurShadow,
    /// The fur ignores the base colour texture (`colorFromTexture` off).
    NoTexture,
}

/// How the fur is drawn.
#[derive(Resource, Clone, Debug, Default, Reflect)]
#[reflect(Resource)]
pub struct FurSettings {
    /// A shell count for every fur primitive (None: by screen size, the manifest's
    /// `shellRule`, at most its `shells`; or its `shells` where it has no rule).
    pub shells: Option<u32>,
    /// Silhouette fins on or off for every fur primitive (None: a scene object's `fins`, else
    /// on with the binary coverage and off with the analytic one, as pelt).
    pub fins: Option<bool>,
    /// The scene's `furCoverage` is `binary` (the fins then reach up to where the faces
    /// turn from the eye by FIN_SILHOUETTE; the shells here always take the analytic one).
    pub binary_coverage: bool,
    /// A negative control (tests only).
    pub control: Option<FurControl>,
}

/// The wind (pelt's scene `wind`): every fur material bends by it.
#[derive(Resource, Clone, Debug, Default, Reflect)]
#[reflect(Resource)]
pub struct FurWind {
    /// The world direction the wind blows toward (any length; zero: no wind).
    pub direction: Vec3,
    /// Its strength (how far it bends a strand, in comb units).
    pub strength: f32,
    /// Gusts per second.
    pub gust_hz: f32,
    /// Turbulence, 0 to 1.
    pub turbulence: f32,
    /// The time the gusts and turbulence are evaluated at (None: the app's `Time`).
    pub time: Option<f32>,
}

impl FurWind {
    /// The shader's wind and gust vectors at `now` seconds (the app's clock).
    /// (pelt_scene::wind::constants: all zero without wind).
    pub fn vectors(&self, now: f32) -> (Vec4, Vec4) {
        let d = self.direction.normalize_or_zero();
        let wind = (d != Vec3::ZERO).then(|| pelt_scene::wind::Wind {
            direction: glam30::Vec3::from_array(d.to_array()),
            strength: self.strength,
            gust_hz: self.gust_hz,
            turbulence: self.turbulence,
        });
        let (w, g) = pelt_scene::wind::constants(wind.as_ref(), self.time.unwrap_or(now));
        (Vec4::from_array(w), Vec4::from_array(g))
    }
}
