//! Wind (Frantzen's "uniform vector for further dynamic displacement"): the scene file's
//! `"wind": {"direction": [x, y, z], "strength": s, "gustHz": f, "turbulence": t}` and its
//! per-frame constants. The field bends every strand's comb along the surface by the wind's
//! vector at its root (shaders/fur_common.wgsl, `wind_comb`), in the shells, the fins and the
//! strand reference alike; it gusts as 1 + ½ sin(2π f T) and varies by ±t with a value noise
//! that scrolls along the wind, so it is a function of the position and the scene's time T
//! (`pelt render --time T`), nothing else.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::scene::NonNegative;

/// The scene's wind.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "WindFile", into = "WindFile")]
pub struct Wind {
    /// Unit world direction it blows toward.
    pub direction: Vec3,
    /// How far it bends a strand, in comb units: 1 bends it as a comb of length 1 along the
    /// surface does (about 45° at the tip).
    pub strength: f32,
    /// Gusts per second (0: steady).
    pub gust_hz: f32,
    /// The noise's share of the strength, 0 to 1.
    pub turbulence: f32,
}

/// The wind as written.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "camelCase")]
struct WindFile {
    direction: [f32; 3],
    strength: NonNegative,
    #[serde(default = "zero")]
    gust_hz: NonNegative,
    #[serde(default = "zero")]
    turbulence: NonNegative,
}

fn zero() -> NonNegative {
    NonNegative(0.0)
}

impl TryFrom<WindFile> for Wind {
    type Error = String;

    fn try_from(f: WindFile) -> Result<Wind, String> {
        let d = Vec3::from(f.direction);
        if !d.is_finite() || d.length() < 1e-6 {
            return Err(format!(
                "direction: must be finite and not zero, got {:?}",
                f.direction
            ));
        }
        if f.turbulence.0 > 1.0 {
            return Err(format!(
                "turbulence: must be from 0 to 1, got {}",
                f.turbulence.0
            ));
        }
        Ok(Wind {
            direction: d.normalize(),
            strength: f.strength.0,
            gust_hz: f.gust_hz.0,
            turbulence: f.turbulence.0,
        })
    }
}

impl From<Wind> for WindFile {
    fn from(w: Wind) -> WindFile {
        WindFile {
            direction: w.direction.into(),
            strength: NonNegative(w.strength),
            gust_hz: NonNegative(w.gust_hz),
            turbulence: NonNegative(w.turbulence),
        }
    }
}

/// The wind's per-frame constants at scene time `time` (s): xyz its world direction × its
/// strength, w the time; and x the gust frequency, y the turbulence. No wind (or none of
/// strength) is all zero, which the shaders take as "leave the comb as it is".
pub fn constants(wind: Option<&Wind>, time: f32) -> ([f32; 4], [f32; 4]) {
    match wind {
        Some(w) if w.strength > 0.0 => (
            (w.direction * w.strength).extend(time).into(),
            [w.gust_hz, w.turbulence, 0.0, 0.0],
        ),
        _ => ([0.0; 4], [0.0; 4]),
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::Scene;

    fn parse(text: &str) -> Result<Scene, String> {
        Scene::parse(Path::new("scene.json"), text).map_err(|e| e.to_string())
    }

    #[test]
    fn wind_reads_with_defaults_and_bad_fields_name_their_place() {
        let s = parse(r#"{"wind": {"direction": [3, 0, 4], "strength": 0.5}}"#).expect("wind");
        let w = s.wind.expect("a wind");
        assert_eq!(w.direction, glam::Vec3::new(0.6, 0.0, 0.8));
        assert_eq!((w.strength, w.gust_hz, w.turbulence), (0.5, 0.0, 0.0));
        assert_eq!(parse("{}").expect("no wind").wind, None);
        for (text, says) in [
            (
                "{\n\"wind\": {\"direction\": [0, 0, 0], \"strength\": 1}}",
                "wind: direction: must be finite and not zero",
            ),
            (
                "{\n\"wind\": {\"direction\": [1, 0, 0], \"strength\": -1}}",
                "wind.strength",
            ),
            (
                "{\n\"wind\": {\"direction\": [1, 0, 0], \"strength\": 1, \"gustHz\": -2}}",
                "wind.gustHz",
            ),
            (
                "{\n\"wind\": {\"direction\": [1, 0, 0], \"strength\": 1, \"turbulence\": 2}}",
                "turbulence: must be from 0 to 1",
            ),
            (
                "{\n\"wind\": {\"direction\": [1, 0, 0], \"strength\": 1, \"gust\": 2}}",
                "unknown field",
            ),
        ] {
            let e = parse(text).expect_err(text);
            assert!(e.starts_with("scene.json:2:"), "{e}");
            assert!(e.contains(says), "{e}");
        }
    }

    #[test]
    fn no_wind_or_none_of_strength_is_all_zero() {
        let w = super::Wind {
            direction: glam::Vec3::X,
            strength: 0.0,
            gust_hz: 1.0,
            turbulence: 0.5,
        };
        assert_eq!(super::constants(Some(&w), 3.0), ([0.0; 4], [0.0; 4]));
        assert_eq!(super::constants(None, 3.0), ([0.0; 4], [0.0; 4]));
        let blowing = super::Wind { strength: 2.0, ..w };
        assert_eq!(
            super::constants(Some(&blowing), 3.0),
            ([2.0, 0.0, 0.0, 3.0], [1.0, 0.5, 0.0, 0.0])
        );
    }
}
