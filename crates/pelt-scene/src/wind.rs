//! Wind (Frantzen's "uniform vector for further dynamic displacement"): the scene file's
//! `"wind": {"direction": [x, y, z], "strength": s, "gustHz": f, "turbulence": t}` and its
//! per-frame constants. The field bends every strand's comb along the surface by the wind's
//! vector at its root (shaders/fur_common.wgsl, `wind_comb`), in the shells, the fins and the
//! strand reference alike; it gusts as 1 + ½ sin(2π f T) and varies by ±t with a value noise
//! that scrolls along the wind, so it is a function of the position and the scene's time T
//! (`pelt render --time T`), nothing else. [`bend`] is the CPU twin of `wind_comb`, for
//! the strand reference's shadow rays (`pelt_trace::strands`).

use glam::{IVec3, Mat3, Vec3};
use serde::{Deserialize, Serialize};

use crate::checked::NonNegative;

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

/// A hash of lattice point `c` to −1..1: fur_common.wgsl's `lattice`, bit for bit.
pub fn lattice(c: IVec3) -> f32 {
    let [x, y, z] = c.to_array().map(i32::cast_unsigned);
    let mut h =
        x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841) ^ z.wrapping_mul(0xcb1a_b31f);
    h = (h ^ (h >> 16)).wrapping_mul(0x7feb_352d);
    h = (h ^ (h >> 15)).wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    (h >> 8) as f32 / 8_388_607.5 - 1.0
}

/// Value noise at `x` (lattice spacing 1): fur_common.wgsl's `value_noise`, −1..1.
pub fn value_noise(x: Vec3) -> f32 {
    let i = x.floor().as_ivec3();
    let f = x - x.floor();
    let u = f * f * (Vec3::splat(3.0) - 2.0 * f);
    let at = |dx, dy, dz| lattice(i + IVec3::new(dx, dy, dz));
    let mix = |a: f32, b: f32, t: f32| a * (1.0 - t) + b * t;
    let x00 = mix(at(0, 0, 0), at(1, 0, 0), u.x);
    let x10 = mix(at(0, 1, 0), at(1, 1, 0), u.x);
    let x01 = mix(at(0, 0, 1), at(1, 0, 1), u.x);
    let x11 = mix(at(0, 1, 1), at(1, 1, 1), u.x);
    mix(mix(x00, x10, u.y), mix(x01, x11, u.y), u.z)
}

/// One object's fur under the wind: what `wind_comb` reads besides the strand.
#[derive(Debug, Clone, Copy)]
pub struct WindOn {
    /// The wind's constants ([`constants`]).
    pub wind: ([f32; 4], [f32; 4]),
    /// World to object for a vector (the inverse of the model's 3×3).
    pub to_object: Mat3,
    /// The object's fur length (asset units): the noise's cells are 16 of them.
    pub fur_length: f32,
}

impl WindOn {
    /// The wind `wind` on an object placed by `model` with fur `fur_length` long.
    pub fn new(wind: ([f32; 4], [f32; 4]), model: glam::Mat4, fur_length: f32) -> WindOn {
        WindOn {
            wind,
            to_object: Mat3::from_mat4(model).inverse(),
            fur_length,
        }
    }
}

/// The object-space comb `comb` of a strand rooted at object-space `root` with normal `n`,
/// bent by the wind there: fur_common.wgsl's `wind_comb` on the CPU.
pub fn bend(comb: Vec3, n: Vec3, root: Vec3, on: &WindOn) -> Vec3 {
    let (w, gust) = on.wind;
    let v = Vec3::new(w[0], w[1], w[2]);
    if v == Vec3::ZERO {
        return comb;
    }
    let t = w[3];
    let dir = (on.to_object * v).normalize();
    let cell = on.fur_length.max(1e-6) * 16.0;
    let gusting = 1.0 + 0.5 * (std::f32::consts::TAU * gust[0] * t).sin();
    let stir = 1.0 + gust[1] * value_noise(root / cell - dir * t);
    let v = dir * (v.length() * gusting * stir);
    let nn = n.normalize();
    let vn = v.dot(nn);
    comb + v + nn * (vn.max(-0.8) - vn)
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

    #[test]
    fn the_noise_is_smooth_bounded_and_hits_its_lattice_values() {
        use glam::{IVec3, Vec3};
        for (i, c) in [IVec3::ZERO, IVec3::new(-3, 7, 2), IVec3::new(100, -50, 9)]
            .into_iter()
            .enumerate()
        {
            let at = super::value_noise(c.as_vec3());
            assert_eq!(at, super::lattice(c), "lattice point {i}");
        }
        let mut prev = super::value_noise(Vec3::new(0.1, 0.2, 0.3));
        let mut seen = (f32::MAX, f32::MIN);
        for k in 1..2000 {
            let x = Vec3::new(0.1 + k as f32 * 0.01, 0.2, 0.3 + k as f32 * 0.003);
            let v = super::value_noise(x);
            assert!((-1.0..=1.0).contains(&v), "{v} at {x}");
            assert!((v - prev).abs() < 0.06, "a jump of {} at {x}", v - prev);
            seen = (seen.0.min(v), seen.1.max(v));
            prev = v;
        }
        assert!(seen.1 - seen.0 > 0.8, "the noise varies: {seen:?}");
        // Integer mixing of the WGSL: the same value for the same point, and a different
        // one for its neighbour.
        assert_ne!(super::lattice(IVec3::ZERO), super::lattice(IVec3::X));
    }

    #[test]
    fn the_bend_adds_the_wind_in_object_space_and_never_presses_fur_into_the_skin() {
        use glam::{Mat4, Quat, Vec3};
        let steady = |v: Vec3, t: f32| ((v.extend(t)).into(), [0.0; 4]);
        let model = Mat4::from_rotation_translation(Quat::from_rotation_y(1.0), Vec3::X);
        let on = super::WindOn::new(steady(Vec3::new(0.3, 0.0, 0.0), 2.0), model, 0.1);
        let n = Vec3::Y;
        let comb = Vec3::new(0.0, 0.0, 0.2);
        let bent = super::bend(comb, n, Vec3::ZERO, &on);
        let along = Mat4::from_quat(Quat::from_rotation_y(1.0))
            .inverse()
            .transform_vector3(Vec3::new(0.3, 0.0, 0.0));
        assert!(
            (bent - (comb + along)).length() < 1e-6,
            "{bent} vs {}",
            comb + along
        );
        let none = super::WindOn::new(([0.0; 4], [0.0; 4]), model, 0.1);
        assert_eq!(super::bend(comb, n, Vec3::ZERO, &none), comb);
        // Straight into the surface: held to 0.8 of the normal.
        let down = super::WindOn::new(steady(Vec3::new(0.0, -5.0, 0.0), 0.0), Mat4::IDENTITY, 0.1);
        let pressed = super::bend(Vec3::ZERO, n, Vec3::ZERO, &down);
        assert!(
            (pressed - Vec3::new(0.0, -0.8, 0.0)).length() < 1e-6,
            "{pressed}"
        );
        // Gusts and turbulence change it over time.
        let gusty = super::WindOn {
            wind: ([1.0, 0.0, 0.0, 0.3], [2.0, 0.5, 0.0, 0.0]),
            ..on
        };
        let later = super::WindOn {
            wind: ([1.0, 0.0, 0.0, 0.55], [2.0, 0.5, 0.0, 0.0]),
            ..on
        };
        let p = Vec3::new(0.2, 0.1, 0.0);
        assert_ne!(
            super::bend(comb, n, p, &gusty),
            super::bend(comb, n, p, &later)
        );
    }
}
