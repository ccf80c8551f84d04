//! The scene file (JSON): objects (a baked asset, a transform, a material), point and
//! directional lights,
//! ambient light, camera, output size, L-buffer scale and DSF switch — everything the inferred
//! lighting renderer (Kircher & Lawrance) is run on — and the `reflections` block, the knobs
//! of mirrors and glass (GPU Gems 3 ch. 17). Every error names the file, the line and
//! column, and the field's path (`objects[3].material.opacity`); unknown keys are errors.
//! Asset paths are relative to the scene file's folder.

use std::fmt;
use std::path::{Path, PathBuf};

use glam::{Mat4, Quat, Vec3};

// The checked numbers moved below this module (the wind reads them too); their old paths here
// keep working.
pub use crate::checked::{Ior, NonNegative, Positive, Unit};
pub use crate::light::{Light, LightKind};
use crate::wind::Wind;
pub use pelt_anim::spring::Spring;
use serde::{Deserialize, Serialize};

/// The prefix of built-in shape names: an object's asset named so is a built-in shape, not a
/// file beside the scene.
pub const BUILTIN: &str = "builtin:";

/// A material.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "MaterialSpec", into = "MaterialSpec")]
pub enum Material {
    /// Opaque, lit through the L-buffer.
    Opaque,
    /// Stippled alpha (up to three layers over opaque).
    Alpha {
        /// Opacity in (0, 1].
        opacity: Unit,
    },
    /// Deferred fur (Revie), from the asset's baked comb and fur manifest.
    Fur(FurSettings),
    /// Mirror (layered distance maps, GPU Gems 3 ch. 17).
    Mirror {
        /// Fresnel reflectance at normal incidence per channel (§17.3), written as `f0` or
        /// derived from a refraction index `n` and extinction coefficient `k`.
        f0: [f32; 3],
        /// Its distance map's reference point (world); the centre of its bounds when absent.
        reference: Option<[f32; 3]>,
    },
    /// Glass with an index of refraction.
    Glass {
        /// Index of refraction (1 to 3).
        ior: Ior,
        /// Colour multiplied into light each time it enters the glass (default white).
        tint: [f32; 3],
        /// Its distance map's reference point (world); the centre of its bounds when absent.
        reference: Option<[f32; 3]>,
    },
}

/// A silvered mirror's reflectance at normal incidence when a scene gives none (silver,
/// n ≈ 0.15, k ≈ 3.6).
pub const DEFAULT_MIRROR_F0: [f32; 3] = [0.95, 0.95, 0.95];

/// Fresnel reflectance at normal incidence from a refraction index and an extinction
/// coefficient (GPU Gems 3 §17.3, after Lazányi & Szirmay-Kalos): ((n−1)² + k²) / ((n+1)² + k²).
pub fn fresnel_f0(n: f32, k: f32) -> f32 {
    ((n - 1.0) * (n - 1.0) + k * k) / ((n + 1.0) * (n + 1.0) + k * k)
}

/// A number or an RGB triple, as written for `f0`, `n`, `k` and `tint`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Rgb {
    /// The same value in each channel.
    Grey(f32),
    /// One value per channel.
    Rgb([f32; 3]),
}

impl Rgb {
    /// Per channel.
    pub fn channels(self) -> [f32; 3] {
        match self {
            Rgb::Grey(v) => [v; 3],
            Rgb::Rgb(c) => c,
        }
    }
}

/// A fur material's overrides of the asset's manifest.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FurSettings {
    /// Shell count (the manifest's when absent; 1 to 256).
    pub shells: Option<u32>,
    /// Silhouette fins. When absent they follow the coverage model
    /// ([`FurSettings::fins_with`]).
    pub fins: Option<bool>,
    /// Fur length in mesh units (the manifest's when absent).
    pub length: Option<f32>,
    /// Secondary motion: a damped spring per vertex that the skinned motion drags, so the fur
    /// lags and settles (crate::springs). None: the fur follows the skin rigidly.
    pub spring: Option<Spring>,
}

impl FurSettings {
    /// Whether fins are drawn under `coverage`: as set, else on with the binary heightfield
    /// (the shells lose the silhouette's side-on strands, which the fins stand for) and off
    /// with analytic coverage, whose shells already hold the optical depth of the grazing
    /// path (fins there add fur the strands do not have: docs/fur.md).
    pub fn fins_with(&self, coverage: FurCoverage) -> bool {
        self.fins.unwrap_or(coverage == FurCoverage::Binary)
    }
}

/// The most shells a fur material draws (`pelt_fur::manifest::SHELLS`'s end).
pub const MAX_SHELLS: u32 = *pelt_fur::manifest::SHELLS.end();

/// The L-buffer scales a scene and every flag accept.
pub const LBUFFER_SCALE: std::ops::RangeInclusive<f32> = crate::knobs::range::LBUFFER_SCALE_BOUNDS;

/// How the fur's shells and fins are composited.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum FurBlend {
    /// Revie: alpha blended "over", inner shells first (the order one instanced draw gives).
    #[default]
    Stipple,
    /// Weighted blended order-independent transparency (McGuire & Bavoil; Frantzen).
    Wboit,
}

impl std::str::FromStr for FurBlend {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "stipple" => Ok(FurBlend::Stipple),
            "wboit" => Ok(FurBlend::Wboit),
            _ => Err(format!(
                "unknown fur blend {s:?} (expected stipple or wboit)"
            )),
        }
    }
}

/// How much of the skin a shell hides (see `pelt_fur::density`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FurCoverage {
    /// Each shell's opacity is the strand model's optical depth over the layer it stands
    /// for (tips and sides, slanted by the view), where a pixel holds many strands; the
    /// binary heightfield where it resolves them.
    #[default]
    Analytic,
    /// The binary heightfield alone, faded over the top of each strand (Revie §2.4.4 as
    /// written): what a shell shows is the strands' top-view area.
    Binary,
}

impl std::str::FromStr for FurCoverage {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "analytic" => Ok(FurCoverage::Analytic),
            "binary" => Ok(FurCoverage::Binary),
            _ => Err(format!(
                "unknown fur coverage {s:?} (expected analytic or binary)"
            )),
        }
    }
}

/// How the deferred and inferred paths light fur from the L-buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FurLighting {
    /// The strand tangent in the G-buffer, Kajiya-Kay per light in the L-buffer (as the
    /// forward shells and the strand reference are lit), root and tip mixed by height.
    #[default]
    KajiyaKay,
    /// Revie §2.4: grain normals at the root, rim-bent normals on the stippled outer shell,
    /// Blinn-Phong in the L-buffer, the brighter of root and tip.
    Revie,
}

impl std::str::FromStr for FurLighting {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "kajiya-kay" => Ok(FurLighting::KajiyaKay),
            "revie" => Ok(FurLighting::Revie),
            _ => Err(format!(
                "unknown fur lighting {s:?} (expected kajiya-kay or revie)"
            )),
        }
    }
}

/// The background.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Sky {
    /// A flat colour.
    #[default]
    None,
    /// A gradient sky with a sun glow.
    Procedural,
    /// A cube map from six images: +X, −X, +Y, −Y, +Z, −Z.
    Cubemap([PathBuf; 6]),
}

/// Sky kinds as written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum SkyKind {
    /// [`Sky::None`].
    None,
    /// [`Sky::Procedural`].
    Procedural,
    /// [`Sky::Cubemap`].
    Cubemap,
}

/// The sky as written: `{"kind": "procedural"}` or `{"kind": "cubemap", "faces": [six PNG
/// paths: +X, −X, +Y, −Y, +Z, −Z]}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SkySpec {
    /// The kind.
    pub kind: SkyKind,
    /// Cube faces (cubemap only), relative to the scene file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub faces: Option<[PathBuf; 6]>,
}

impl TryFrom<SkySpec> for Sky {
    type Error = String;
    fn try_from(s: SkySpec) -> Result<Self, String> {
        match (s.kind, s.faces) {
            (SkyKind::Cubemap, Some(f)) => Ok(Sky::Cubemap(f)),
            (SkyKind::Cubemap, None) => Err("a cubemap sky needs six faces".into()),
            (_, Some(_)) => Err("faces is only for a cubemap sky".into()),
            (SkyKind::None, None) => Ok(Sky::None),
            (SkyKind::Procedural, None) => Ok(Sky::Procedural),
        }
    }
}

impl From<Sky> for SkySpec {
    fn from(s: Sky) -> SkySpec {
        match s {
            Sky::None => SkySpec {
                kind: SkyKind::None,
                faces: None,
            },
            Sky::Procedural => SkySpec {
                kind: SkyKind::Procedural,
                faces: None,
            },
            Sky::Cubemap(f) => SkySpec {
                kind: SkyKind::Cubemap,
                faces: Some(f),
            },
        }
    }
}

/// Material kinds as written in a scene file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum MaterialKind {
    /// [`Material::Opaque`].
    Opaque,
    /// [`Material::Alpha`].
    Alpha,
    /// [`Material::Fur`].
    Fur,
    /// [`Material::Mirror`].
    Mirror,
    /// [`Material::Glass`].
    Glass,
}

/// A material as written: `{"kind": "alpha", "opacity": 0.5}`. (A plain struct rather than a
/// tagged enum, so that errors inside it keep their field path.)
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// The kind.
    pub kind: MaterialKind,
    /// Opacity (alpha only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub opacity: Option<Unit>,
    /// Index of refraction (glass only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ior: Option<Ior>,
    /// Shell count (fur only; 1 to 256).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shells: Option<u32>,
    /// Silhouette fins (fur only; default: on with binary coverage, off with analytic).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fins: Option<bool>,
    /// Fur length in mesh units (fur only; default: the asset's manifest).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length: Option<f32>,
    /// Secondary motion (fur only): `{"stiffness": k, "damping": d}`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spring: Option<SpringSpec>,
    /// Reflectance at normal incidence, 0 to 1 (mirror only; not with `n`/`k`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub f0: Option<Rgb>,
    /// Refraction index of a metal, above 0 (mirror only, with optional `k`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub n: Option<Rgb>,
    /// Extinction coefficient of a metal, at least 0 (mirror only, with `n`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k: Option<Rgb>,
    /// Colour of the glass, 0 to 1 (glass only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tint: Option<Rgb>,
    /// The distance map's reference point in world space (mirror and glass; default: the
    /// centre of the object's bounds).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference: Option<[f32; 3]>,
}

/// A fur spring as written: stiffness k in 1/s² (ω₀², above 0) and damping d in 1/s (above
/// 0: an undamped spring would swing forever and has no steady state on a looping clip).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    /// Stiffness in 1/s².
    pub stiffness: f32,
    /// Damping in 1/s.
    pub damping: f32,
}

impl TryFrom<SpringSpec> for Spring {
    type Error = String;
    fn try_from(s: SpringSpec) -> Result<Self, String> {
        if !(s.stiffness.is_finite() && s.stiffness > 0.0) {
            return Err(format!(
                "spring stiffness must be finite and above 0 (1/s²), got {}",
                s.stiffness
            ));
        }
        if !(s.damping.is_finite() && s.damping > 0.0) {
            return Err(format!(
                "spring damping must be finite and above 0 (1/s), got {}",
                s.damping
            ));
        }
        Ok(Spring {
            stiffness: s.stiffness,
            damping: s.damping,
        })
    }
}

/// A mirror's F0 from `f0`, or `n` and `k`.
fn mirror_f0(m: &MaterialSpec) -> Result<[f32; 3], String> {
    match (m.f0, m.n, m.k) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
            Err("give a mirror either f0 or n and k, not both".into())
        }
        (Some(f0), None, None) => {
            let c = f0.channels();
            if c.iter().all(|v| (0.0..=1.0).contains(v)) {
                Ok(c)
            } else {
                Err(format!("f0 components must be from 0 to 1, got {c:?}"))
            }
        }
        (None, None, Some(_)) => Err("k needs n (the metal's refraction index)".into()),
        (None, Some(n), k) => {
            let (n, k) = (n.channels(), k.map_or([0.0; 3], Rgb::channels));
            if !n.iter().all(|v| v.is_finite() && *v > 0.0) {
                return Err(format!(
                    "n components must be finite and above 0, got {n:?}"
                ));
            }
            if !k.iter().all(|v| v.is_finite() && *v >= 0.0) {
                return Err(format!(
                    "k components must be finite and at least 0, got {k:?}"
                ));
            }
            Ok([0, 1, 2].map(|i| fresnel_f0(n[i], k[i])))
        }
        (None, None, None) => Ok(DEFAULT_MIRROR_F0),
    }
}

impl TryFrom<MaterialSpec> for Material {
    type Error = String;
    fn try_from(m: MaterialSpec) -> Result<Self, String> {
        m.check_properties()?;
        match m.kind {
            MaterialKind::Fur => m.fur(),
            MaterialKind::Alpha => {
                if m.ior.is_some() {
                    return m.extra("ior");
                }
                m.opacity
                    .map(|opacity| Material::Alpha { opacity })
                    .ok_or_else(|| "an alpha material needs an opacity".to_owned())
            }
            MaterialKind::Glass => m.glass(),
            kind => {
                if m.opacity.is_some() {
                    return m.extra("opacity");
                }
                if m.ior.is_some() {
                    return m.extra("ior");
                }
                Ok(match kind {
                    MaterialKind::Mirror => Material::Mirror {
                        f0: mirror_f0(&m)?,
                        reference: m.reference,
                    },
                    _ => Material::Opaque,
                })
            }
        }
    }
}

impl MaterialSpec {
    /// The error for a property `what` that this spec's kind does not have.
    fn extra<T>(&self, what: &str) -> Result<T, String> {
        Err(format!(
            "{what} is not a property of {:?} materials",
            self.kind
        ))
    }

    /// The properties of one kind that a spec of another gives (the mirror's f0, n and k, the
    /// glass's tint, a mirror's or glass's reference, the fur's shells, fins, length and
    /// spring), and a reference that is not finite: errors, in that order.
    fn check_properties(&self) -> Result<(), String> {
        if self.kind != MaterialKind::Mirror {
            if self.f0.is_some() {
                return self.extra("f0");
            }
            if self.n.is_some() {
                return self.extra("n");
            }
            if self.k.is_some() {
                return self.extra("k");
            }
        }
        if self.kind != MaterialKind::Glass && self.tint.is_some() {
            return self.extra("tint");
        }
        if !matches!(self.kind, MaterialKind::Mirror | MaterialKind::Glass)
            && self.reference.is_some()
        {
            return self.extra("reference");
        }
        if let Some(r) = self.reference
            && !r.iter().all(|v| v.is_finite())
        {
            return Err(format!("reference must be finite, got {r:?}"));
        }
        if self.kind != MaterialKind::Fur {
            if self.shells.is_some() {
                return self.extra("shells");
            }
            if self.fins.is_some() {
                return self.extra("fins");
            }
            if self.length.is_some() {
                return self.extra("length");
            }
            if self.spring.is_some() {
                return self.extra("spring");
            }
        }
        Ok(())
    }

    /// A fur material: no opacity or ior; shells within their knob's range, a finite length
    /// of at least 0, and a valid spring.
    fn fur(&self) -> Result<Material, String> {
        if self.opacity.is_some() {
            return self.extra("opacity");
        }
        if self.ior.is_some() {
            return self.extra("ior");
        }
        if let Some(n) = self.shells {
            crate::knobs::range::SHELLS
                .check_count(n)
                .map_err(|m| format!("shells {m}"))?;
        }
        if let Some(l) = self.length
            && !(l.is_finite() && l >= 0.0)
        {
            return Err(format!("length must be finite and at least 0, got {l}"));
        }
        Ok(Material::Fur(FurSettings {
            shells: self.shells,
            fins: self.fins,
            length: self.length,
            spring: self.spring.map(TryFrom::try_from).transpose()?,
        }))
    }

    /// A glass material: no opacity; its tint's components from 0 to 1 (white by default),
    /// its ior 1.5 by default.
    fn glass(&self) -> Result<Material, String> {
        if self.opacity.is_some() {
            return self.extra("opacity");
        }
        let tint = self.tint.map_or([1.0; 3], Rgb::channels);
        if !tint.iter().all(|v| (0.0..=1.0).contains(v)) {
            return Err(format!("tint components must be from 0 to 1, got {tint:?}"));
        }
        Ok(Material::Glass {
            ior: self.ior.unwrap_or(Ior(1.5)),
            tint,
            reference: self.reference,
        })
    }
}

impl From<Material> for MaterialSpec {
    fn from(m: Material) -> MaterialSpec {
        let mut spec = MaterialSpec {
            kind: MaterialKind::Opaque,
            opacity: None,
            ior: None,
            shells: None,
            fins: None,
            length: None,
            spring: None,
            f0: None,
            n: None,
            k: None,
            tint: None,
            reference: None,
        };
        match m {
            Material::Opaque => {}
            Material::Alpha { opacity } => {
                spec.kind = MaterialKind::Alpha;
                spec.opacity = Some(opacity);
            }
            Material::Fur(f) => {
                spec.kind = MaterialKind::Fur;
                spec.shells = f.shells;
                spec.fins = f.fins;
                spec.length = f.length;
                spec.spring = f.spring.filter(|s| !s.rigid()).map(|s| SpringSpec {
                    stiffness: s.stiffness,
                    damping: s.damping,
                });
            }
            Material::Mirror { f0, reference } => {
                spec.kind = MaterialKind::Mirror;
                spec.f0 = (f0 != DEFAULT_MIRROR_F0).then_some(Rgb::Rgb(f0));
                spec.reference = reference;
            }
            Material::Glass {
                ior,
                tint,
                reference,
            } => {
                spec.kind = MaterialKind::Glass;
                spec.ior = Some(ior);
                spec.tint = (tint != [1.0; 3]).then_some(Rgb::Rgb(tint));
                spec.reference = reference;
            }
        }
        spec
    }
}

/// A placement: translation, rotation (unit quaternion x, y, z, w), scale.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Transform {
    /// Translation.
    pub translation: [f32; 3],
    /// Rotation quaternion (x, y, z, w), normalized on load.
    pub rotation: [f32; 4],
    /// Scale per axis (non-zero).
    pub scale: [f32; 3],
}

impl Default for Transform {
    fn default() -> Self {
        Transform {
            translation: [0.0; 3],
            rotation: [0.0, 0.0, 0.0, 1.0],
            scale: [1.0; 3],
        }
    }
}

impl Transform {
    /// The model matrix.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(
            Vec3::from(self.scale),
            Quat::from_array(self.rotation).normalize(),
            Vec3::from(self.translation),
        )
    }

    fn check(&self) -> Result<(), (&'static str, String)> {
        let all = self
            .translation
            .iter()
            .chain(&self.rotation)
            .chain(&self.scale);
        if all.clone().any(|v| !v.is_finite()) {
            return Err(("transform", "every number must be finite".into()));
        }
        if Vec3::from(self.scale).abs().min_element() < 1e-12 {
            return Err((
                "transform.scale",
                format!("must be non-zero, got {:?}", self.scale),
            ));
        }
        if glam::Vec4::from(self.rotation).length() < 1e-6 {
            return Err(("transform.rotation", "must be a non-zero quaternion".into()));
        }
        Ok(())
    }
}

/// One object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Object {
    /// The asset (a baked `.glb`, or any glTF/OBJ pelt reads), relative to the scene file.
    pub asset: PathBuf,
    /// Placement.
    #[serde(default)]
    pub transform: Transform,
    /// Material.
    #[serde(default = "opaque")]
    pub material: Material,
    /// Linear colour multiplied into the asset's base colour (white when absent).
    #[serde(default = "white", skip_serializing_if = "is_white")]
    pub color: [f32; 3],
}

fn opaque() -> Material {
    Material::Opaque
}

fn white() -> [f32; 3] {
    [1.0; 3]
}

fn is_white(c: &[f32; 3]) -> bool {
    *c == [1.0; 3]
}

/// A perspective camera.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct Camera {
    /// Eye position.
    pub position: [f32; 3],
    /// Point looked at.
    pub target: [f32; 3],
    /// Up direction.
    pub up: [f32; 3],
    /// Vertical field of view in degrees (0 to 180, exclusive).
    pub fov_y_deg: f32,
    /// Near plane distance.
    pub near: f32,
    /// Far plane distance.
    pub far: f32,
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            position: [0.0, 1.0, 4.0],
            target: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            fov_y_deg: 45.0,
            near: 0.05,
            far: 200.0,
        }
    }
}

/// Output image size.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Size {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

/// A scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct Scene {
    /// Output size.
    pub output: Size,
    /// Camera.
    pub camera: Camera,
    /// Ambient light (linear RGB).
    pub ambient: [f32; 3],
    /// L-buffer resolution as a fraction of the output (0.1 to 1; the paper's 800×450 for
    /// 1280×720 is 0.625).
    pub lbuffer_scale: f32,
    /// Discontinuity-sensitive filtering in the material pass.
    pub dsf: bool,
    /// Objects.
    pub objects: Vec<Object>,
    /// Lights.
    pub lights: Vec<Light>,
    /// Background: none (a flat colour), procedural, or a cube map.
    #[serde(with = "sky_serde")]
    pub sky: Sky,
    /// How fur shells and fins are composited.
    pub fur_blend: FurBlend,
    /// How much of the skin each shell hides.
    pub fur_coverage: FurCoverage,
    /// How the deferred paths light fur.
    pub fur_lighting: FurLighting,
    /// Mirrors and glass: the technique and its knobs.
    pub reflections: Reflections,
    /// The shadow cubes of lights that cast shadows: their size and filtering.
    pub shadow_maps: ShadowMaps,
    /// The wind that stirs the fur (none: still).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wind: Option<Wind>,
    /// Seconds into the scene, where the wind is evaluated: set by `pelt render --time` and
    /// `pelt view`'s clock, not read from the file.
    #[serde(skip)]
    pub time: f32,
}

/// How mirrors and glass are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Technique {
    /// Layered distance maps searched per pixel (GPU Gems 3 ch. 17).
    #[default]
    DistanceMaps,
    /// Classic environment mapping: the same cube maps looked up by direction alone, as if
    /// every ray started at the reference point (the baseline).
    Envmap,
    /// Drawn opaque.
    Off,
}

impl std::str::FromStr for Technique {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "distance-maps" => Ok(Technique::DistanceMaps),
            "envmap" => Ok(Technique::Envmap),
            "off" => Ok(Technique::Off),
            _ => Err(format!(
                "unknown reflection technique {s:?} (expected distance-maps, envmap or off)"
            )),
        }
    }
}

impl fmt::Display for Technique {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Technique::DistanceMaps => "distance-maps",
            Technique::Envmap => "envmap",
            Technique::Off => "off",
        })
    }
}

/// The knobs of mirrors and glass (GPU Gems 3 ch. 17), the scene's `reflections` block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct Reflections {
    /// The technique.
    pub technique: Technique,
    /// Linear search steps per quarter turn of directions seen from the reference point
    /// (§17.2.2, Listing 17-1).
    pub linear_steps: u32,
    /// Secant refinement steps (Listing 17-2).
    pub secant_steps: u32,
    /// Distance-map layers: the object's front faces, its back faces, and depth-peeled
    /// layers of the rest of the scene (3 is the paper's 2 + 1).
    pub layers: u32,
    /// Cube-map face size in texels (a power of two).
    pub cube_size: u32,
    /// Most specular bounces on a path (Listing 17-5's MAXDEPTH).
    pub max_depth: u32,
    /// Min-max acceleration (Figure 17-4).
    pub min_max: bool,
    /// Silhouette handling: four taps that straddle two surfaces are not filtered into a
    /// slope between them, and a ray that passed behind a silhouette seen from the reference
    /// point and found no hit meets the surface behind the silhouette (off: the search as
    /// §17.2.2 has it, where such a ray misses and shows the sky).
    pub silhouettes: bool,
}

impl Default for Reflections {
    fn default() -> Self {
        Reflections {
            technique: Technique::DistanceMaps,
            linear_steps: 32,
            secant_steps: 6,
            layers: 3,
            cube_size: 256,
            max_depth: 4,
            min_max: true,
            silhouettes: true,
        }
    }
}

/// Ranges of the reflection knobs.
pub mod reflection_limits {
    use crate::knobs::range;

    /// Linear steps.
    pub const LINEAR_STEPS: std::ops::RangeInclusive<u32> = range::LINEAR_STEPS_BOUNDS;
    /// Secant steps.
    pub const SECANT_STEPS: std::ops::RangeInclusive<u32> = range::SECANT_STEPS_BOUNDS;
    /// Layers.
    pub const LAYERS: std::ops::RangeInclusive<u32> = range::LAYERS_BOUNDS;
    /// Cube size (also a power of two, and at most the adapter's texture limit).
    pub const CUBE_SIZE: std::ops::RangeInclusive<u32> = range::CUBE_SIZE_BOUNDS;
    /// Bounces.
    pub const MAX_DEPTH: std::ops::RangeInclusive<u32> = range::MAX_DEPTH_BOUNDS;
}

impl Reflections {
    /// The first knob out of range (each checked by its spec, `crate::knobs::spec`), as
    /// (field, message).
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        use crate::knobs::range;
        let knobs = [
            ("linearSteps", self.linear_steps, &range::LINEAR_STEPS),
            ("secantSteps", self.secant_steps, &range::SECANT_STEPS),
            ("layers", self.layers, &range::LAYERS),
            ("maxDepth", self.max_depth, &range::MAX_DEPTH),
            ("cubeSize", self.cube_size, &range::CUBE_SIZE),
        ];
        for (field, v, knob) in knobs {
            knob.check_count(v).map_err(|m| (field, m))?;
        }
        Ok(())
    }
}

/// The knobs of the shadow cubes, the scene's `shadowMaps` block (lights opt in with
/// `"shadows": true`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct ShadowMaps {
    /// Each cube face's side in texels (a power of two).
    pub size: u32,
    /// Percentage-closer filtering: the side of the square of texels a lookup compares (1:
    /// the nearest texel, a hard edge; 2: the 2×2 bilinear comparison).
    pub pcf: u32,
    /// Deep opacity map layers (Yuksel & Keyser 2008) through which fur shadows itself and
    /// everything behind it by its coverage: 0 (fur casts as its base mesh alone) to 3.
    pub opacity_layers: u32,
}

impl Default for ShadowMaps {
    fn default() -> Self {
        ShadowMaps {
            size: 512,
            pcf: 2,
            opacity_layers: 3,
        }
    }
}

impl ShadowMaps {
    /// Face sizes (also a power of two).
    pub const SIZE: std::ops::RangeInclusive<u32> = crate::knobs::range::SHADOW_SIZE_BOUNDS;
    /// PCF sides.
    pub const PCF: std::ops::RangeInclusive<u32> = crate::knobs::range::PCF_BOUNDS;
    /// Deep opacity map layers.
    pub const OPACITY_LAYERS: std::ops::RangeInclusive<u32> =
        crate::knobs::range::OPACITY_LAYERS_BOUNDS;

    /// The first knob out of range (each checked by its spec, `crate::knobs::spec`), as
    /// (field, message).
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        use crate::knobs::range;
        let knobs = [
            ("size", self.size, &range::SHADOW_SIZE),
            ("pcf", self.pcf, &range::PCF),
            ("opacityLayers", self.opacity_layers, &range::OPACITY_LAYERS),
        ];
        for (field, v, knob) in knobs {
            knob.check_count(v).map_err(|m| (field, m))?;
        }
        Ok(())
    }
}

mod sky_serde {
    use super::{Sky, SkySpec};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(s: &Sky, ser: S) -> Result<S::Ok, S::Error> {
        SkySpec::from(s.clone()).serialize(ser)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(de: D) -> Result<Sky, D::Error> {
        Sky::try_from(SkySpec::deserialize(de)?).map_err(serde::de::Error::custom)
    }
}

impl Default for Scene {
    fn default() -> Self {
        Scene {
            output: Size {
                width: 640,
                height: 360,
            },
            camera: Camera::default(),
            ambient: [0.03; 3],
            lbuffer_scale: 0.625,
            dsf: true,
            objects: Vec::new(),
            lights: Vec::new(),
            sky: Sky::None,
            fur_blend: FurBlend::Stipple,
            fur_coverage: FurCoverage::Analytic,
            fur_lighting: FurLighting::KajiyaKay,
            reflections: Reflections::default(),
            shadow_maps: ShadowMaps::default(),
            wind: None,
            time: 0.0,
        }
    }
}

/// Largest output side.
pub use crate::flags::MAX_SIDE;

/// A scene that could not be used.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{}: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Bad JSON, an unknown key, or a value out of range where it is read.
    #[error("{}:{line}:{column}: {field}: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// Path of the field (`objects[2].material.opacity`, `.` for the root).
        field: String,
        /// What is wrong.
        message: String,
    },
    /// A value inconsistent with others (checked after reading).
    #[error("{}: {field}: {message}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// Path of the field.
        field: String,
        /// What is wrong.
        message: String,
    },
}

impl Scene {
    /// Reads and checks a scene file; asset paths become relative to the current directory.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
            path: path.to_owned(),
            source,
        })?;
        let mut scene = Scene::parse(path, &text)?;
        let dir = path.parent().unwrap_or(Path::new(""));
        for o in &mut scene.objects {
            if !o.asset.to_string_lossy().starts_with(BUILTIN) {
                o.asset = dir.join(&o.asset);
            }
        }
        if let Sky::Cubemap(faces) = &mut scene.sky {
            for f in faces {
                *f = dir.join(&*f);
            }
        }
        Ok(scene)
    }

    /// Parses and checks scene text (`path` is used in errors).
    pub fn parse(path: &Path, text: &str) -> Result<Scene, SceneError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let scene: Scene = serde_path_to_error::deserialize(de).map_err(|e| {
            let field = e.path().to_string();
            let inner = e.into_inner();
            let message = inner.to_string();
            let message = message
                .rsplit_once(" at line ")
                .map_or(message.as_str(), |(m, _)| m)
                .to_owned();
            SceneError::Parse {
                path: path.to_owned(),
                line: inner.line(),
                column: inner.column(),
                field,
                message,
            }
        })?;
        scene
            .check()
            .map_err(|(field, message)| SceneError::Invalid {
                path: path.to_owned(),
                field,
                message,
            })?;
        Ok(scene)
    }

    /// Cross-field checks.
    fn check(&self) -> Result<(), (String, String)> {
        let o = self.output;
        if !(1..=MAX_SIDE).contains(&o.width) || !(1..=MAX_SIDE).contains(&o.height) {
            return Err((
                "output".into(),
                format!(
                    "width and height must be 1 to {MAX_SIDE}, got {}×{}",
                    o.width, o.height
                ),
            ));
        }
        crate::knobs::range::LBUFFER_SCALE
            .check(crate::knobs::range::Value::Scale(self.lbuffer_scale))
            .map_err(|m| ("lbufferScale".to_owned(), m))?;
        if self.ambient.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return Err((
                "ambient".into(),
                "components must be finite and at least 0".into(),
            ));
        }
        let c = &self.camera;
        if !(c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0) {
            return Err((
                "camera.fovYDeg".into(),
                format!("must be between 0 and 180, got {}", c.fov_y_deg),
            ));
        }
        if !(c.near > 0.0 && c.far > c.near && c.far.is_finite()) {
            return Err((
                "camera".into(),
                format!("need 0 < near < far, got near {} far {}", c.near, c.far),
            ));
        }
        let (eye, target, up) = (
            Vec3::from(c.position),
            Vec3::from(c.target),
            Vec3::from(c.up),
        );
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return Err((
                "camera".into(),
                "position, target and up must be finite".into(),
            ));
        }
        let dir = target - eye;
        if dir.length() < 1e-6 || dir.normalize().cross(up).length() < 1e-4 {
            return Err((
                "camera".into(),
                "target must differ from position and not lie along up".into(),
            ));
        }
        self.reflections
            .check()
            .map_err(|(f, m)| (format!("reflections.{f}"), m))?;
        self.shadow_maps
            .check()
            .map_err(|(f, m)| (format!("shadowMaps.{f}"), m))?;
        for (i, obj) in self.objects.iter().enumerate() {
            obj.transform
                .check()
                .map_err(|(f, m)| (format!("objects[{i}].{f}"), m))?;
            if !obj.color.iter().all(|c| (0.0..=1.0).contains(c)) {
                return Err((
                    format!("objects[{i}].color"),
                    format!("components must be from 0 to 1, got {:?}", obj.color),
                ));
            }
        }
        Ok(())
    }

    /// L-buffer size for this output (at least 1 × 1).
    pub fn lbuffer_size(&self) -> (u32, u32) {
        let s = |v: u32| ((v as f32 * self.lbuffer_scale).round() as u32).max(1);
        (s(self.output.width), s(self.output.height))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::Emitter;

    fn parse(text: &str) -> Result<Scene, SceneError> {
        Scene::parse(Path::new("scene.json"), text)
    }

    #[test]
    fn a_full_scene_reads_with_defaults_filled() {
        let s = parse(
            r#"{
              "output": {"width": 1280, "height": 720},
              "objects": [
                {"asset": "creature.glb"},
                {"asset": "sphere.glb", "transform": {"translation": [2, 0, 0]},
                 "material": {"kind": "alpha", "opacity": 0.5}},
                {"asset": "torus.glb", "material": {"kind": "glass", "ior": 1.5}}
              ],
              "lights": [{"position": [0, 3, 0], "radius": 5}]
            }"#,
        )
        .expect("valid");
        assert_eq!(s.lbuffer_size(), (800, 450));
        assert_eq!(s.objects[0].material, Material::Opaque);
        assert_eq!(
            s.objects[1].material,
            Material::Alpha { opacity: Unit(0.5) }
        );
        assert_eq!(s.lights[0].intensity, NonNegative(1.0));
        let sun = parse(
            r#"{"lights": [{"kind": "directional", "direction": [0, -3, -4], "shadows": true}]}"#,
        )
        .expect("a sun");
        assert_eq!(
            sun.lights[0].emitter,
            Emitter::Directional {
                direction: Vec3::new(0.0, -0.6, -0.8)
            }
        );
        assert!(sun.lights[0].shadows);
        // It writes back as it was read.
        let text = serde_json::to_string(&sun.lights[0]).expect("writes");
        assert!(text.contains("\"kind\":\"directional\""), "{text}");
        assert!(
            !text.contains("radius") && !text.contains("position"),
            "{text}"
        );

        assert_eq!(s.lights[0].color, [1.0; 3]);
        assert!(s.dsf);
        let m = s.objects[1].transform.matrix();
        assert_eq!(m.transform_point3(Vec3::ZERO), Vec3::new(2.0, 0.0, 0.0));
    }

    #[test]
    fn mirrors_and_glass_read_their_optics_and_reflection_knobs() {
        let s = parse(
            r#"{"objects": [
                {"asset": "a.glb", "material": {"kind": "mirror"}},
                {"asset": "a.glb", "material": {"kind": "mirror", "f0": [0.9, 0.8, 0.5], "reference": [0, 1, 0]}},
                {"asset": "a.glb", "material": {"kind": "mirror", "n": 1.5}},
                {"asset": "a.glb", "material": {"kind": "glass", "ior": 1.33, "tint": [0.8, 1, 0.9]}}
              ],
              "reflections": {"technique": "envmap", "linearSteps": 80, "secantSteps": 10, "layers": 4,
                              "cubeSize": 512, "maxDepth": 8, "minMax": false}}"#,
        )
        .expect("valid");
        let m: Vec<Material> = s.objects.iter().map(|o| o.material).collect();
        assert_eq!(
            m[0],
            Material::Mirror {
                f0: DEFAULT_MIRROR_F0,
                reference: None
            }
        );
        assert_eq!(
            m[1],
            Material::Mirror {
                f0: [0.9, 0.8, 0.5],
                reference: Some([0.0, 1.0, 0.0])
            }
        );
        let Material::Mirror { f0, .. } = m[2] else {
            panic!("mirror")
        };
        assert!((f0[0] - 0.04).abs() < 1e-6, "F0 of n = 1.5, k = 0: {f0:?}");
        assert_eq!(
            m[3],
            Material::Glass {
                ior: Ior(1.33),
                tint: [0.8, 1.0, 0.9],
                reference: None
            }
        );
        let r = s.reflections;
        assert_eq!(
            (
                r.technique,
                r.linear_steps,
                r.secant_steps,
                r.layers,
                r.cube_size,
                r.max_depth,
                r.min_max
            ),
            (Technique::Envmap, 80, 10, 4, 512, 8, false)
        );
        // Round trip through the written form.
        let again = parse(&serde_json::to_string(&s).expect("serialize")).expect("reparse");
        assert_eq!(again, s);
    }

    #[test]
    fn bad_optics_and_reflection_knobs_name_the_field() {
        for (json, field, words) in [
            (
                r#"{"reflections": {"linearSteps": -1}}"#,
                "reflections.linearSteps",
                "invalid value",
            ),
            (
                r#"{"reflections": {"linearSteps": 0}}"#,
                "reflections.linearSteps",
                "1 to 1024",
            ),
            (
                r#"{"reflections": {"cubeSize": 300}}"#,
                "reflections.cubeSize",
                "power of two",
            ),
            (
                r#"{"shadowMaps": {"size": 300}}"#,
                "shadowMaps.size",
                "power of two",
            ),
            (
                r#"{"shadowMaps": {"size": 8192}}"#,
                "shadowMaps.size",
                "power of two from 16 to 4096",
            ),
            (r#"{"shadowMaps": {"pcf": 0}}"#, "shadowMaps.pcf", "1 to 8"),
            (
                r#"{"shadowMaps": {"opacityLayers": 4}}"#,
                "shadowMaps.opacityLayers",
                "0 to 3",
            ),
            (
                r#"{"reflections": {"layers": 2}}"#,
                "reflections.layers",
                "3 to 8",
            ),
            (
                r#"{"reflections": {"maxDepth": 0}}"#,
                "reflections.maxDepth",
                "1 to 16",
            ),
            (
                r#"{"reflections": {"technique": "rays"}}"#,
                "reflections.technique",
                "unknown variant",
            ),
            (
                r#"{"objects": [{"asset": "a", "material": {"kind": "glass", "ior": 0}}]}"#,
                "objects[0].material.ior",
                "from 1 to 3",
            ),
            (
                r#"{"objects": [{"asset": "a", "material": {"kind": "mirror", "f0": 0.5, "n": 1}}]}"#,
                "objects[0].material",
                "not both",
            ),
            (
                r#"{"objects": [{"asset": "a", "material": {"kind": "mirror", "k": 3}}]}"#,
                "objects[0].material",
                "k needs n",
            ),
            (
                r#"{"objects": [{"asset": "a", "material": {"kind": "mirror", "n": -1}}]}"#,
                "objects[0].material",
                "above 0",
            ),
            (
                r#"{"objects": [{"asset": "a", "material": {"kind": "mirror", "f0": 2}}]}"#,
                "objects[0].material",
                "from 0 to 1",
            ),
            (
                r#"{"objects": [{"asset": "a", "material": {"kind": "mirror", "tint": 1}}]}"#,
                "objects[0].material",
                "tint is not",
            ),
            (
                r#"{"objects": [{"asset": "a", "material": {"kind": "opaque", "reference": [0, 0, 0]}}]}"#,
                "objects[0].material",
                "reference is not",
            ),
            (
                r#"{"objects": [{"asset": "a", "material": {"kind": "glass", "f0": 0.5}}]}"#,
                "objects[0].material",
                "f0 is not",
            ),
        ] {
            let e = parse(json).expect_err(json).to_string();
            assert!(e.contains(field) && e.contains(words), "{json}: {e}");
        }
    }

    #[test]
    fn errors_name_file_line_and_field() {
        let e = parse("{\n \"objects\": [\n  {\"asset\": \"a.glb\"},\n  {\"asset\": \"b.glb\", \"material\": {\"kind\": \"alpha\", \"opacity\": 1.5}}\n ]\n}")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("scene.json:4:"), "{e}");
        assert!(e.contains("objects[1].material.opacity"), "{e}");
        assert!(e.contains("must be above 0 and at most 1, got 1.5"), "{e}");

        let e = parse("{\"lights\": [{\"position\": [0,0,0], \"radius\": 0}]}")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("lights[0].radius") && e.contains("above 0"),
            "{e}"
        );

        // A light's mistakes are reported at its place, naming the field.
        for (text, field, says) in [
            (
                "{\n\"lights\": [\n {\"kind\": \"directional\", \"direction\": [0, 0, 0]}]}",
                "direction",
                "not zero",
            ),
            (
                "{\n\"lights\": [\n {\"kind\": \"directional\"}]}",
                "",
                "needs a direction",
            ),
            (
                "{\n\"lights\": [\n {\"kind\": \"directional\", \"direction\": [0,-1,0], \"radius\": 2}]}",
                "",
                "no position or radius",
            ),
            (
                "{\n\"lights\": [\n {\"position\": [0,0,0], \"radius\": 1, \"direction\": [0,-1,0]}]}",
                "direction",
                "only a directional light",
            ),
            (
                "{\n\"lights\": [\n {\"position\": [0,0,0]}]}",
                "",
                "needs a radius",
            ),
            (
                "{\n\"lights\": [\n {\"radius\": 1}]}",
                "",
                "needs a position",
            ),
            (
                "{\n\"lights\": [\n {\"position\": [0,0,0], \"radius\": 1, \"color\": [1,-1,0]}]}",
                "color",
                "at least 0",
            ),
            (
                "{\n\"lights\": [\n {\"kind\": \"area\"}]}",
                "",
                "unknown variant",
            ),
        ] {
            let e = parse(text).unwrap_err().to_string();
            assert!(e.starts_with("scene.json:3:"), "{e}");
            assert!(e.contains("lights[0]") && e.contains(says), "{e}");
            assert!(e.contains(&format!("{field}:")), "{e}");
        }

        let e = parse("{\"objects\": [{\"asset\": \"a.glb\", \"colour\": 1}]}")
            .unwrap_err()
            .to_string();
        assert!(e.contains("objects[0]") && e.contains("colour"), "{e}");

        let e = parse("{\"lbufferScale\": 2}").unwrap_err().to_string();
        assert_eq!(e, "scene.json: lbufferScale: must be from 0.1 to 1, got 2");

        let e =
            parse("{\"objects\": [{\"asset\": \"a.glb\", \"transform\": {\"scale\": [1, 0, 1]}}]}")
                .unwrap_err()
                .to_string();
        assert!(e.contains("objects[0].transform.scale"), "{e}");

        let e = parse("{\"camera\": {\"position\": [0, 5, 0], \"target\": [0, 0, 0]}}")
            .unwrap_err()
            .to_string();
        assert!(e.contains("camera") && e.contains("along up"), "{e}");

        let e =
            parse("{\"objects\": [{\"asset\": \"a.glb\", \"material\": {\"kind\": \"velvet\"}}]}")
                .unwrap_err()
                .to_string();
        assert!(
            e.contains("objects[0].material") && e.contains("velvet"),
            "{e}"
        );
    }

    #[test]
    fn assets_resolve_against_the_scene_folder() {
        let dir = std::env::temp_dir().join(format!("pelt-scene-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("mkdir");
        let file = dir.join("s.json");
        std::fs::write(&file, r#"{"objects": [{"asset": "models/a.glb"}]}"#).expect("write");
        let s = Scene::load(&file).expect("load");
        assert_eq!(s.objects[0].asset, dir.join("models/a.glb"));
        let _ = std::fs::remove_dir_all(&dir);
        let e = Scene::load(&dir.join("missing.json"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing.json"), "{e}");
    }
}
