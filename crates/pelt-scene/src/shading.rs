//! The local lighting model every renderer of pelt shares, on the CPU: the constants the
//! GPU passes are given (specular strength and power, the background) and CPU twins of
//! `one_light` in shaders/common.wgsl and the procedural sky of shaders/sky.wgsl, so the
//! ray tracer (`pelt-trace`) lights a surface exactly as the rasterizer does; and Schlick's
//! Fresnel approximation with F0 as GPU Gems 3 §17.3 uses it.

use glam::Vec3;

/// Specular strength of every material (no per-asset specular yet).
pub const SPECULAR_STRENGTH: f32 = 0.25;
/// Blinn-Phong exponent for every light.
pub const SPECULAR_POWER: f32 = 32.0;
/// The linear background colour where there is no sky.
pub const BACKGROUND: [f32; 3] = [0.02, 0.022, 0.028];

pub use crate::light::Emitter;

/// A light as the shaders see it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// Where its light comes from.
    pub emitter: Emitter,
    /// Linear colour × intensity.
    pub color: Vec3,
    /// Whether it casts shadows (the ray tracer's shadow rays).
    pub shadows: bool,
}

impl Light {
    /// A point light at `position` reaching `radius`, of linear `color` × intensity, casting
    /// no shadows.
    pub fn point(position: Vec3, radius: f32, color: Vec3) -> Light {
        Light {
            emitter: Emitter::Point { position, radius },
            color,
            shadows: false,
        }
    }
}

/// One light at point `p` with unit normal `n` seen from direction `v` (unit, from `p`
/// toward the viewer): (diffuse irradiance, specular intensity), as `one_light` in
/// common.wgsl: Lambert and Blinn-Phong; a point light's inverse-square falloff is windowed
/// to zero at its radius, a directional light has none.
pub fn one_light(p: Vec3, n: Vec3, v: Vec3, light: &Light) -> (Vec3, f32) {
    let Some((l, atten, _)) = light.emitter.reach(p) else {
        return (Vec3::ZERO, 0.0);
    };
    let ndl = n.dot(l).max(0.0);
    let h = (l + v).normalize_or_zero();
    let spec = n.dot(h).max(0.0).powf(SPECULAR_POWER) * ndl * atten;
    (light.color * (ndl * atten), spec)
}

/// The radiance leaving a diffuse surface of `albedo` at `p` (unit normal `n` facing the
/// viewer, `v` toward it): ambient plus every light's diffuse times the albedo, plus the
/// specular in each light's colour (the forward pass's sum).
pub fn shade(albedo: Vec3, p: Vec3, n: Vec3, v: Vec3, ambient: Vec3, lights: &[Light]) -> Vec3 {
    shade_seen(albedo, p, n, v, ambient, lights, |_| true)
}

/// [`shade`] with each light's contribution kept only where `sees(light)` (asked only of
/// lights that reach `p` and face it): a shadowed point gets the ambient term and the lights
/// it sees.
pub fn shade_seen(
    albedo: Vec3,
    p: Vec3,
    n: Vec3,
    v: Vec3,
    ambient: Vec3,
    lights: &[Light],
    sees: impl Fn(&Light) -> bool,
) -> Vec3 {
    let mut diffuse = ambient;
    let mut specular = Vec3::ZERO;
    for l in lights {
        let (d, s) = one_light(p, n, v, l);
        // Only a light that would add something is asked whether it is seen.
        if (d == Vec3::ZERO && s == 0.0) || !sees(l) {
            continue;
        }
        diffuse += d;
        specular += s * l.color;
    }
    albedo * diffuse + SPECULAR_STRENGTH * specular
}

/// Direction of the procedural sky's sun.
const SUN: Vec3 = Vec3::new(0.48, 0.62, 0.62);

/// The procedural sky in unit direction `d` (sky.wgsl's `procedural`).
pub fn procedural_sky(d: Vec3) -> Vec3 {
    let zenith = Vec3::new(0.10, 0.22, 0.55);
    let horizon = Vec3::new(0.55, 0.63, 0.75);
    let ground = Vec3::new(0.09, 0.08, 0.07);
    let up = d.y;
    let sky = horizon.lerp(zenith, up.clamp(0.0, 1.0).powf(0.6));
    let below = (horizon * 0.6).lerp(ground, (-up * 6.0).clamp(0.0, 1.0));
    let mut c = if up >= 0.0 { sky } else { below };
    let s = d.dot(SUN.normalize()).max(0.0);
    c += Vec3::new(1.0, 0.85, 0.6) * (0.6 * s.powi(64) + 0.15 * s.powi(6));
    c
}

/// Schlick's Fresnel with reflectance `f0` at normal incidence, at `cos` = |N·V|
/// (GPU Gems 3 §17.3: F = F0 + (1 − F0)(1 − N·V)⁵).
pub fn fresnel(f0: Vec3, cos: f32) -> Vec3 {
    let m = (1.0 - cos.abs().min(1.0)).powi(5);
    f0 + (Vec3::ONE - f0) * m
}

/// The exact Fresnel reflectance of a dielectric boundary (unpolarized light) for a ray
/// meeting it at `cos_i` (≥ 0) with `eta` = n₁/n₂; 1 under total internal reflection. Glass
/// uses it rather than Schlick's approximation, which does not vanish at IOR 1 (a glass of air
/// would keep a bright rim).
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// A dielectric's F0 from its index of refraction: ((n − 1) / (n + 1))².
pub fn dielectric_f0(ior: f32) -> f32 {
    let r = (ior - 1.0) / (ior + 1.0);
    r * r
}

/// Linear to 8-bit sRGB, as an sRGB render target stores it.
pub fn srgb8(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// 8-bit sRGB to linear.
pub fn linear_of_srgb8(v: u8) -> f32 {
    linear_of_srgb(f32::from(v) / 255.0)
}

/// sRGB (0 to 1) to linear.
pub fn linear_of_srgb(s: f32) -> f32 {
    if s <= 0.040_45 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_spans_f0_to_one_and_metals_reflect_more() {
        let f0 = Vec3::splat(dielectric_f0(1.5));
        assert!((f0.x - 0.04).abs() < 1e-6);
        assert_eq!(fresnel(f0, 1.0), f0);
        assert!((fresnel(f0, 0.0) - Vec3::ONE).length() < 1e-6);
        assert!(crate::scene::fresnel_f0(0.15, 3.6) > 0.9);
        assert!((crate::scene::fresnel_f0(1.5, 0.0) - 0.04).abs() < 1e-6);
        // The exact dielectric: F0 at normal incidence, 0 for a boundary of equal indices,
        // 1 past the critical angle (41.8° from inside glass).
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert!(fresnel_dielectric(0.3, 1.0) < 1e-12);
        assert_eq!(fresnel_dielectric(0.5, 1.5), 1.0);
        assert!(fresnel_dielectric(0.05, 1.0 / 1.5) > 0.7);
    }

    #[test]
    fn a_light_falls_to_zero_at_its_radius_and_faces_matter() {
        let l = Light::point(Vec3::new(0.0, 2.0, 0.0), 3.0, Vec3::ONE);
        let up = Vec3::Y;
        let (d, s) = one_light(Vec3::ZERO, up, up, &l);
        assert!(d.x > 0.0 && s > 0.0);
        assert_eq!(one_light(Vec3::ZERO, -up, up, &l).0, Vec3::ZERO);
        assert_eq!(
            one_light(Vec3::new(0.0, -1.5, 0.0), up, up, &l).0,
            Vec3::ZERO
        );
        // A directional light: no falloff, anywhere; Lambert's cosine.
        let sun = Light {
            emitter: Emitter::Directional {
                direction: Vec3::new(0.0, -1.0, -1.0).normalize(),
            },
            color: Vec3::ONE,
            shadows: false,
        };
        for p in [Vec3::ZERO, Vec3::splat(1.0e4)] {
            let (d, _) = one_light(p, up, up, &sun);
            assert!((d.x - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6, "{d}");
        }
        assert_eq!(one_light(Vec3::ZERO, -up, up, &sun).0, Vec3::ZERO);
        for v in [0u8, 1, 60, 128, 254, 255] {
            assert_eq!(srgb8(linear_of_srgb8(v)), v);
        }
    }
}
