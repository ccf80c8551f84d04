//! A light, kind by kind: where its light comes from ([`Emitter`]: a point light, a sun), how
//! far and how strongly it reaches a point (the CPU twin of `light_reach` in
//! shaders/common.wgsl), where a shadow ray goes to meet it, its screen bounds, and its two
//! written forms: the scene file's and glTF's `KHR_lights_punctual`. Everything that depends on
//! a light's kind outside the shaders and the shadow maps' fitting asks it here.

use glam::{Mat4, Vec3, Vec4};
use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::checked::{NonNegative, Positive};

/// Where a light's light comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Emitter {
    /// A point light at `position` whose light falls to zero at `radius`.
    Point {
        /// Position.
        position: Vec3,
        /// Radius where its light reaches zero.
        radius: f32,
    },
    /// A directional light (a sun): its light travels along the unit `direction` everywhere,
    /// with no falloff.
    Directional {
        /// Unit direction the light travels in (from the light toward the scene).
        direction: Vec3,
    },
    /// A spot light: a point light at `position` reaching `radius` whose light is confined to
    /// a cone about the unit `direction`: full within `inner`, none beyond `outer` (half-angles
    /// in radians, 0 ≤ inner ≤ outer ≤ π/2), smooth between them as glTF's
    /// `KHR_lights_punctual` spot lights.
    Spot {
        /// Position.
        position: Vec3,
        /// Unit direction its cone points in.
        direction: Vec3,
        /// Radius where its light reaches zero.
        radius: f32,
        /// The cone's half-angle of full light (radians).
        inner: f32,
        /// The cone's half-angle past which no light reaches (radians).
        outer: f32,
    },
}

/// Where a light's rays start: at a point (a point light), or infinitely far, travelling along
/// a unit direction (a sun).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Source {
    /// From this point.
    At(Vec3),
    /// Along this unit direction (from the light toward the scene).
    Along(Vec3),
}

impl Emitter {
    /// Where its rays start (what a shadow ray aims at).
    pub fn source(&self) -> Source {
        match *self {
            Emitter::Point { position, .. } | Emitter::Spot { position, .. } => {
                Source::At(position)
            }
            Emitter::Directional { direction } => Source::Along(direction),
        }
    }

    /// Its kind as the scene file names it.
    pub fn kind(&self) -> LightKind {
        match self {
            Emitter::Point { .. } => LightKind::Point,
            Emitter::Directional { .. } => LightKind::Directional,
            Emitter::Spot { .. } => LightKind::Spot,
        }
    }

    /// Whether it reaches everywhere from one direction (the shaders' SUNS variant).
    pub fn is_directional(&self) -> bool {
        matches!(self.source(), Source::Along(_))
    }

    /// Whether a shader's loop over lights that holds it needs the full `light_reach` (its
    /// branch on the kind, the SUNS variant): every kind but a plain point light, whose reach
    /// is `bare_reach` (common.wgsl).
    pub fn needs_suns(&self) -> bool {
        !matches!(self, Emitter::Point { .. })
    }

    /// The sphere (centre, radius) outside which it lights nothing; `None`: it reaches
    /// everywhere.
    pub fn bounds(&self) -> Option<(Vec3, f32)> {
        match *self {
            Emitter::Point { position, radius }
            | Emitter::Spot {
                position, radius, ..
            } => Some((position, radius)),
            Emitter::Directional { .. } => None,
        }
    }

    /// `cone` of the shaders' `Light` in the space `to_space` maps world space to: a spot
    /// light's unit direction times 1 / (cos inner − cos outer) and −cos outer times the
    /// same, so that clamp(dot(xyz, −l) + w, 0, 1) is its smooth falloff; (0, 0, 0, 1), no
    /// cone, for the other kinds.
    pub fn cone(&self, to_space: Mat4) -> Vec4 {
        match *self {
            Emitter::Spot {
                direction,
                inner,
                outer,
                ..
            } => {
                let scale = 1.0 / (inner.cos() - outer.cos()).max(1e-3);
                let d = to_space.transform_vector3(direction).normalize() * scale;
                d.extend(-outer.cos() * scale)
            }
            Emitter::Point { .. } | Emitter::Directional { .. } => Vec4::W,
        }
    }

    /// `position_radius` of the shaders' `Light` (common.wgsl) in the space `to_space` maps
    /// world space to (a rigid transform): a point light's position and radius, a sun's unit
    /// direction toward it and 0.
    pub fn packed(&self, to_space: Mat4) -> Vec4 {
        match *self {
            Emitter::Point { position, radius }
            | Emitter::Spot {
                position, radius, ..
            } => to_space.transform_point3(position).extend(radius),
            Emitter::Directional { direction } => to_space
                .transform_vector3(-direction)
                .normalize()
                .extend(0.0),
        }
    }

    /// This light moved by `m` (an object's transform): its position carried, its direction
    /// turned, its radius scaled by the largest of the transform's axis scales.
    pub fn moved(&self, m: Mat4) -> Emitter {
        match *self {
            Emitter::Point { position, radius } => Emitter::Point {
                position: m.transform_point3(position),
                radius: radius * axis_scale(m),
            },
            Emitter::Directional { direction } => Emitter::Directional {
                direction: m.transform_vector3(direction).normalize_or(direction),
            },
            Emitter::Spot {
                position,
                direction,
                radius,
                inner,
                outer,
            } => Emitter::Spot {
                position: m.transform_point3(position),
                direction: m.transform_vector3(direction).normalize_or(direction),
                radius: radius * axis_scale(m),
                inner,
                outer,
            },
        }
    }

    /// A point or spot light's position.
    pub fn position(&self) -> Option<Vec3> {
        match self.source() {
            Source::At(position) => Some(position),
            Source::Along(_) => None,
        }
    }

    /// A point or spot light's radius.
    pub fn radius(&self) -> Option<f32> {
        self.bounds().map(|(_, radius)| radius)
    }

    /// The unit direction from `p` toward the light, its falloff at `p` and the distance a
    /// shadow ray travels to reach it (infinite for a directional light); `None` where a point
    /// or spot light does not reach (`light_reach` in common.wgsl): beyond its radius, or
    /// outside a spot light's cone.
    pub fn reach(&self, p: Vec3) -> Option<(Vec3, f32, f32)> {
        let Some((position, radius)) = self.bounds() else {
            return Some((-self.travel(), 1.0, f32::INFINITY));
        };
        let to_light = position - p;
        let dist = to_light.length();
        if dist >= radius {
            return None;
        }
        let x = dist / radius;
        let window = (1.0 - x * x * x * x).clamp(0.0, 1.0);
        let l = to_light / dist.max(1e-6);
        let cone = self.cone(Mat4::IDENTITY);
        let a = (cone.truncate().dot(-l) + cone.w).clamp(0.0, 1.0);
        if a <= 0.0 {
            return None;
        }
        let atten = window * window / (1.0 + dist * dist) * (a * a);
        Some((l, atten, dist))
    }

    /// The way its light travels: a sun's direction, a spot light's axis; zero for a point
    /// light (its light travels every way).
    pub fn travel(&self) -> Vec3 {
        match *self {
            Emitter::Directional { direction } | Emitter::Spot { direction, .. } => direction,
            Emitter::Point { .. } => Vec3::ZERO,
        }
    }
}

/// A light of the scene file: a point light (`"position"` and `"radius"`) or, with
/// `"kind": "directional"`, a sun (`"direction"`, the way its light travels).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "LightFile", into = "LightFile")]
pub struct Light {
    /// Where its light comes from (a point light's position and radius are finite, its radius
    /// above 0; a directional light's direction is finite and of unit length).
    pub emitter: Emitter,
    /// Linear RGB colour (finite, at least 0).
    pub color: [f32; 3],
    /// Intensity multiplier.
    pub intensity: NonNegative,
    /// Whether the light casts shadows: surfaces it cannot see directly get none of its light
    /// (the ray tracer traces a shadow ray toward it).
    pub shadows: bool,
}

impl Light {
    /// A white point light of `intensity` at `position` reaching `radius`, casting no
    /// shadows.
    pub fn point(position: [f32; 3], radius: f32, intensity: f32) -> Light {
        Light {
            emitter: Emitter::Point {
                position: Vec3::from(position),
                radius,
            },
            color: [1.0; 3],
            intensity: NonNegative(intensity),
            shadows: false,
        }
    }

    /// This light with `color`.
    pub fn with_color(self, color: [f32; 3]) -> Light {
        Light { color, ..self }
    }
}

/// Light kinds as written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LightKind {
    /// A point light (the default).
    #[default]
    Point,
    /// A directional light.
    Directional,
    /// A spot light.
    Spot,
}

impl LightKind {
    /// Every kind, in the order `--explain` lists them.
    pub const ALL: [LightKind; 3] = [LightKind::Point, LightKind::Directional, LightKind::Spot];
}

/// A light as written (checked into a [`Light`]; a mistake is reported at the light's place
/// in the file).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LightFile {
    #[serde(default, skip_serializing_if = "is_point")]
    kind: LightKind,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    position: Option<[f32; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    direction: Option<[f32; 3]>,
    #[serde(default = "white")]
    color: [f32; 3],
    #[serde(default = "one")]
    intensity: NonNegative,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    radius: Option<Positive>,
    #[serde(default, skip_serializing_if = "is_false")]
    shadows: bool,
    #[serde(default, rename = "innerDeg", skip_serializing_if = "Option::is_none")]
    inner_deg: Option<f32>,
    #[serde(default, rename = "outerDeg", skip_serializing_if = "Option::is_none")]
    outer_deg: Option<f32>,
}

fn is_point(k: &LightKind) -> bool {
    *k == LightKind::Point
}

impl TryFrom<LightFile> for Light {
    type Error = String;

    fn try_from(f: LightFile) -> Result<Light, String> {
        if !f.color.iter().all(|c| c.is_finite() && *c >= 0.0) {
            return Err(format!(
                "color: components must be finite and at least 0, got {:?}",
                f.color
            ));
        }
        let emitter = emitter_of(&f)?;
        Ok(Light {
            emitter,
            color: f.color,
            intensity: f.intensity,
            shadows: f.shadows,
        })
    }
}

/// The emitter a light as written describes, each kind with exactly its own fields.
fn emitter_of(f: &LightFile) -> Result<Emitter, String> {
    let position = || -> Result<Vec3, String> {
        let p = f
            .position
            .ok_or(format!("a {} light needs a position", f.kind.name()))?;
        let v = Vec3::from(p);
        v.is_finite()
            .then_some(v)
            .ok_or(format!("position: must be finite, got {p:?}"))
    };
    let radius = || {
        f.radius
            .map(|r| r.0)
            .ok_or(format!("a {} light needs a radius", f.kind.name()))
    };
    let direction = || -> Result<Vec3, String> {
        let d = f
            .direction
            .ok_or(format!("a {} light needs a direction", f.kind.name()))?;
        let v = Vec3::from(d);
        if !v.is_finite() || v.length() < 1e-6 {
            return Err(format!("direction: must be finite and not zero, got {d:?}"));
        }
        Ok(v.normalize())
    };
    let only = |field: &str, kinds: &str| format!("{field}: only {kinds} has one");
    if f.kind != LightKind::Spot && (f.inner_deg.is_some() || f.outer_deg.is_some()) {
        let field = if f.inner_deg.is_some() {
            "innerDeg"
        } else {
            "outerDeg"
        };
        return Err(only(field, "a spot light (\"kind\": \"spot\")"));
    }
    match f.kind {
        LightKind::Point => {
            if f.direction.is_some() {
                return Err(only(
                    "direction",
                    "a directional light or a spot light (\"kind\": \"directional\" or \"spot\")",
                ));
            }
            Ok(Emitter::Point {
                position: position()?,
                radius: radius()?,
            })
        }
        LightKind::Directional => {
            if f.position.is_some() || f.radius.is_some() {
                return Err(
                    "a directional light has no position or radius (it reaches everywhere)".into(),
                );
            }
            Ok(Emitter::Directional {
                direction: direction()?,
            })
        }
        LightKind::Spot => {
            let (inner, outer) = cone_of(f.inner_deg, f.outer_deg)?;
            Ok(Emitter::Spot {
                position: position()?,
                direction: direction()?,
                radius: radius()?,
                inner,
                outer,
            })
        }
    }
}

/// A spot light's cone from its half-angles in degrees (glTF's defaults: 0 and 45), checked:
/// 0 ≤ inner ≤ outer ≤ 90, outer above 0. In radians.
fn cone_of(inner_deg: Option<f32>, outer_deg: Option<f32>) -> Result<(f32, f32), String> {
    let inner = inner_deg.unwrap_or(0.0);
    let outer = outer_deg.unwrap_or(45.0);
    if !(outer.is_finite() && outer > 0.0 && outer <= 90.0) {
        return Err(format!(
            "outerDeg: must be above 0 and at most 90, got {outer}"
        ));
    }
    if !(inner.is_finite() && (0.0..=outer).contains(&inner)) {
        return Err(format!(
            "innerDeg: must be from 0 to outerDeg ({outer}), got {inner}"
        ));
    }
    Ok((inner.to_radians(), outer.to_radians()))
}

impl LightKind {
    /// Its name in the scene file.
    pub fn name(self) -> &'static str {
        match self {
            LightKind::Point => "point",
            LightKind::Directional => "directional",
            LightKind::Spot => "spot",
        }
    }
}

impl From<Light> for LightFile {
    fn from(l: Light) -> LightFile {
        let e = l.emitter;
        let (inner_deg, outer_deg) = match e {
            Emitter::Spot { inner, outer, .. } => {
                (Some(inner.to_degrees()), Some(outer.to_degrees()))
            }
            Emitter::Point { .. } | Emitter::Directional { .. } => (None, None),
        };
        LightFile {
            kind: e.kind(),
            position: e.position().map(Into::into),
            direction: (e.travel() != Vec3::ZERO).then(|| e.travel().into()),
            color: l.color,
            intensity: l.intensity,
            radius: e.radius().map(Positive),
            shadows: l.shadows,
            inner_deg,
            outer_deg,
        }
    }
}

fn is_false(b: &bool) -> bool {
    !*b
}

fn white() -> [f32; 3] {
    [1.0; 3]
}

fn one() -> NonNegative {
    NonNegative(1.0)
}

/// The largest length `m` gives a unit axis.
fn axis_scale(m: Mat4) -> f32 {
    let s = [m.x_axis, m.y_axis, m.z_axis].map(|a| a.truncate().length());
    s[0].max(s[1]).max(s[2])
}

/// The glTF extension whose lights an asset brings into its scene.
pub const KHR_LIGHTS_PUNCTUAL: &str = "KHR_lights_punctual";

/// A light of glTF's `KHR_lights_punctual` (`def`, one of the extension's `lights`) where a
/// node of world matrix `world` places it: at the node's origin, shining down its −z axis.
/// The extension's units are pelt's intensity: candela for point and spot lights (pelt's
/// falloff, 1/(1 + d²) windowed to zero at the radius, is the extension's 1/d² away from the
/// light), lux for a sun. Without a `range` a light reaches where its brightest channel falls
/// to 1/256. glTF lights cast no shadows (the extension has no such switch, and three.js
/// and Bevy read them so). A spot light's cone angles are the extension's (radians, 0 and π/4
/// by default).
pub fn from_khr(def: &Value, world: Mat4) -> Result<Light, String> {
    let floats = |key: &str, n: usize| -> Result<Option<Vec<f32>>, String> {
        let Some(v) = def.get(key) else {
            return Ok(None);
        };
        let a: Option<Vec<f32>> = v.as_array().and_then(|a| {
            a.iter()
                .map(|x| x.as_f64().map(|f| f as f32).filter(|f| f.is_finite()))
                .collect()
        });
        match a {
            Some(a) if a.len() == n => Ok(Some(a)),
            _ => Err(format!("{key}: must be {n} finite numbers, got {v}")),
        }
    };
    let number = |key: &str| -> Result<Option<f32>, String> {
        match def.get(key) {
            None => Ok(None),
            Some(v) => match v.as_f64().map(|f| f as f32) {
                Some(f) if f.is_finite() && f >= 0.0 => Ok(Some(f)),
                _ => Err(format!(
                    "{key}: must be a finite number of at least 0, got {v}"
                )),
            },
        }
    };
    let color: [f32; 3] = match floats("color", 3)? {
        Some(c) if c.iter().all(|&c| c >= 0.0) => [c[0], c[1], c[2]],
        Some(c) => return Err(format!("color: components must be at least 0, got {c:?}")),
        None => [1.0; 3],
    };
    let intensity = number("intensity")?.unwrap_or(1.0);
    let brightest = color.iter().fold(0.0_f32, |a, &c| a.max(c)) * intensity;
    let radius = match number("range")? {
        Some(r) if r > 0.0 => r,
        Some(r) => return Err(format!("range: must be above 0, got {r}")),
        None => (256.0 * brightest - 1.0).max(0.0).sqrt().max(1e-3),
    };
    let position = world.transform_point3(Vec3::ZERO);
    if !position.is_finite() {
        return Err(format!("its node places it at {position}"));
    }
    let down = world.transform_vector3(Vec3::NEG_Z);
    let emitter = match def.get("type").and_then(Value::as_str) {
        Some("point") => Emitter::Point { position, radius },
        Some("directional") => Emitter::Directional {
            direction: direction_of(down)?,
        },
        Some("spot") => {
            let spot = def.get("spot").unwrap_or(&Value::Null);
            let angle = |key: &str| match spot.get(key) {
                None => Ok(None),
                Some(v) => v
                    .as_f64()
                    .map(|a| (a as f32).to_degrees())
                    .filter(|a| a.is_finite())
                    .map(Some)
                    .ok_or(format!("spot.{key}: must be a number, got {v}")),
            };
            let (inner, outer) = cone_of(angle("innerConeAngle")?, angle("outerConeAngle")?)
                .map_err(|e| format!("spot: {e} (in degrees)"))?;
            Emitter::Spot {
                position,
                direction: direction_of(down)?,
                radius,
                inner,
                outer,
            }
        }
        _ => {
            return Err(format!(
                "type: must be \"directional\", \"point\" or \"spot\", got {}",
                def.get("type").unwrap_or(&Value::Null)
            ));
        }
    };
    Ok(Light {
        emitter,
        color,
        intensity: NonNegative(intensity),
        shadows: false,
    })
}

/// A node's −z axis as a light's unit direction; a node that scales it to nothing has none.
fn direction_of(down: Vec3) -> Result<Vec3, String> {
    if !down.is_finite() || down.length() < 1e-12 {
        return Err(format!("its node's matrix leaves it no direction ({down})"));
    }
    Ok(down.normalize())
}
