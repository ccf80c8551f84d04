//! Texture images and what samples them: a material's texture found through the `gltf`
//! crate's typed document (texture, image, sampler wrap modes, TEXCOORD set), the image
//! decoded with the `image` crate (glTF 2.0 allows PNG and JPEG), and bilinear lookups with the
//! sampler's wrap modes. Decoding is bounded: at most [`MAX_SIDE`] pixels a side and
//! [`MAX_ALLOC`] bytes, checked from the header before any pixel is allocated.

use std::io::Cursor;

pub use gltf::texture::WrappingMode;

// The decoded image is the bounded decoder's type; its lookups are below.
pub use crate::picture_bounded::Rgba8;

use crate::error::Result;
use crate::{Document, typed};

/// Largest width or height decoded.
pub const MAX_SIDE: u32 = 16384;
/// Most bytes one decode may allocate.
pub const MAX_ALLOC: u64 = 1 << 30;

/// Largest width or height of an image decoded smaller than it is stored
/// ([`decode_within`]): its memory follows the size used.
pub const MAX_STORED_SIDE: u32 = 65535;

/// Decodes `images[image]` of `doc` (PNG or JPEG) at its stored size; errors name the image.
pub fn decode(doc: &Document, image: usize) -> Result<Rgba8> {
    decode_within(doc, image, MAX_SIDE).map(|(img, _)| img)
}

/// Decodes `images[image]` of `doc` with no side longer than `max_side`: a larger image is
/// halved until it fits while it is decoded ([`crate::picture_bounded`]), and its stored
/// size is returned with it (None when it was decoded as stored). Errors name the image.
pub fn decode_within(
    doc: &Document,
    image: usize,
    max_side: u32,
) -> Result<(Rgba8, Option<(u32, u32)>)> {
    let place = format!("images[{image}]");
    let bytes = doc.image_bytes(image)?;
    let format = match image::guess_format(bytes) {
        Ok(f @ (image::ImageFormat::Png | image::ImageFormat::Jpeg)) => f,
        _ => {
            return Err(doc.invalid(
                &place,
                "is neither PNG nor JPEG (glTF 2.0 allows only those)",
            ));
        }
    };
    let (w, h) = image::ImageReader::with_format(Cursor::new(bytes), format)
        .into_dimensions()
        .map_err(|e| doc.invalid(&place, format!("cannot be decoded: {e}")))?;
    let k = crate::picture_bounded::halvings(w, h, max_side.clamp(1, MAX_SIDE));
    if k == 1 {
        return decode_stored(doc, bytes, format, &place).map(|i| (i, None));
    }
    let small = match format {
        image::ImageFormat::Png => crate::picture_bounded::png(bytes, k, MAX_STORED_SIDE),
        _ => crate::picture_bounded::jpeg(bytes, k, MAX_STORED_SIDE),
    };
    let small = small.map_err(|e| doc.invalid(&place, format!("cannot be decoded: {e}")))?;
    Ok((small, Some((w, h))))
}

/// The image at its stored size, through the `image` crate (at most [`MAX_SIDE`] a side).
fn decode_stored(
    doc: &Document,
    bytes: &[u8],
    format: image::ImageFormat,
    place: &str,
) -> Result<Rgba8> {
    let mut reader = image::ImageReader::with_format(Cursor::new(bytes), format);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    limits.max_alloc = Some(MAX_ALLOC);
    reader.limits(limits);
    // into_rgba8: an RGBA image is not copied (RGB: 1.75× the result at the peak).
    let img = reader
        .decode()
        .map_err(|e| doc.invalid(place, format!("cannot be decoded: {e}")))?
        .into_rgba8();
    Ok(Rgba8 {
        width: img.width(),
        height: img.height(),
        pixels: img.into_raw(),
    })
}

/// A material's texture slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slot {
    /// `pbrMetallicRoughness.baseColorTexture`.
    BaseColor,
    /// `pbrMetallicRoughness.metallicRoughnessTexture`.
    MetallicRoughness,
    /// `normalTexture`.
    Normal,
    /// `occlusionTexture`.
    Occlusion,
    /// `emissiveTexture`.
    Emissive,
}

impl Slot {
    /// Parses `baseColor`, `metallicRoughness`, `normal`, `occlusion`, `emissive`.
    pub fn parse(s: &str) -> Option<Slot> {
        Some(match s {
            "baseColor" => Slot::BaseColor,
            "metallicRoughness" => Slot::MetallicRoughness,
            "normal" => Slot::Normal,
            "occlusion" => Slot::Occlusion,
            "emissive" => Slot::Emissive,
            _ => return None,
        })
    }
}

/// Where a material's texture comes from and how it is sampled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TextureUse {
    /// The image.
    pub image: usize,
    /// Which TEXCOORD_n.
    pub tex_coord: u32,
    /// Wrap modes (s, t).
    pub wrap: [WrappingMode; 2],
}

/// The texture in `slot` of material `material`, if it has one.
pub fn material_texture(doc: &Document, material: usize, slot: Slot) -> Result<Option<TextureUse>> {
    let g = typed::document(doc)?;
    let Some(m) = g.materials().nth(material) else {
        return Err(doc.invalid(format!("materials[{material}]"), "does not exist"));
    };
    let pbr = m.pbr_metallic_roughness();
    let found = match slot {
        Slot::BaseColor => pbr
            .base_color_texture()
            .map(|i| (i.texture(), i.tex_coord())),
        Slot::MetallicRoughness => pbr
            .metallic_roughness_texture()
            .map(|i| (i.texture(), i.tex_coord())),
        Slot::Normal => m.normal_texture().map(|i| (i.texture(), i.tex_coord())),
        Slot::Occlusion => m.occlusion_texture().map(|i| (i.texture(), i.tex_coord())),
        Slot::Emissive => m.emissive_texture().map(|i| (i.texture(), i.tex_coord())),
    };
    Ok(found.map(|(t, tex_coord)| TextureUse {
        image: t.source().index(),
        tex_coord,
        wrap: [t.sampler().wrap_s(), t.sampler().wrap_t()],
    }))
}

/// `KHR_texture_transform` on a texture reference: `uv' = matrix · (u, v, 1)` (the
/// extension's translation · rotation · scale), and the TEXCOORD set it overrides to, if any.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UvTransform {
    /// Rows of the 2×3 affine matrix.
    pub matrix: [[f32; 3]; 2],
    /// `texCoord` of the extension (replaces the textureInfo's).
    pub tex_coord: Option<u32>,
}

impl UvTransform {
    /// `uv` transformed.
    pub fn apply(&self, uv: [f32; 2]) -> [f32; 2] {
        let [a, b] = self.matrix;
        [
            a[0] * uv[0] + a[1] * uv[1] + a[2],
            b[0] * uv[0] + b[1] * uv[1] + b[2],
        ]
    }
}

/// The `KHR_texture_transform` of the texture in `slot` of material `material`, if it has
/// one (gltfpack writes one with its quantized UVs); an error names a malformed field.
pub fn texture_transform(
    doc: &Document,
    material: usize,
    slot: Slot,
) -> Result<Option<UvTransform>> {
    let path: &[&str] = match slot {
        Slot::BaseColor => &["pbrMetallicRoughness", "baseColorTexture"],
        Slot::MetallicRoughness => &["pbrMetallicRoughness", "metallicRoughnessTexture"],
        Slot::Normal => &["normalTexture"],
        Slot::Occlusion => &["occlusionTexture"],
        Slot::Emissive => &["emissiveTexture"],
    };
    let mut v = material_json(doc, material)?;
    for key in path {
        match v.get(key) {
            Some(x) => v = x,
            None => return Ok(None),
        }
    }
    let Some(t) = v
        .get("extensions")
        .and_then(|e| e.get("KHR_texture_transform"))
    else {
        return Ok(None);
    };
    let place = format!(
        "materials[{material}].{}.extensions.KHR_texture_transform",
        path.join(".")
    );
    let pair = |key: &str, default: [f32; 2]| -> Result<[f32; 2]> {
        let Some(x) = t.get(key) else {
            return Ok(default);
        };
        let n = x.as_array().filter(|a| a.len() == 2).and_then(|a| {
            let f = |i: usize| a[i].as_f64().filter(|v| v.is_finite()).map(|v| v as f32);
            Some([f(0)?, f(1)?])
        });
        n.ok_or_else(|| doc.invalid(format!("{place}.{key}"), "must be two finite numbers"))
    };
    let offset = pair("offset", [0.0, 0.0])?;
    let scale = pair("scale", [1.0, 1.0])?;
    let rotation =
        match t.get("rotation") {
            None => 0.0,
            Some(r) => r.as_f64().filter(|v| v.is_finite()).ok_or_else(|| {
                doc.invalid(format!("{place}.rotation"), "must be a finite number")
            })? as f32,
        };
    let tex_coord = match t.get("texCoord") {
        None => None,
        Some(c) => Some(
            c.as_u64()
                .and_then(|c| u32::try_from(c).ok())
                .ok_or_else(|| doc.invalid(format!("{place}.texCoord"), "must be an index"))?,
        ),
    };
    let (sin, cos) = rotation.sin_cos();
    Ok(Some(UvTransform {
        matrix: [
            [cos * scale[0], sin * scale[1], offset[0]],
            [-sin * scale[0], cos * scale[1], offset[1]],
        ],
        tex_coord,
    }))
}

/// Material `material`'s JSON object, or an error naming it when the document has none.
fn material_json(doc: &Document, material: usize) -> Result<&serde_json::Value> {
    doc.array("materials")
        .get(material)
        .ok_or_else(|| doc.invalid(format!("materials[{material}]"), "does not exist"))
}

/// A material's scalar factors: (`normalTexture.scale`, `metallicFactor`, `roughnessFactor`),
/// glTF's defaults (1, 1, 1) where the material leaves them out. Read from the JSON itself, so
/// a document still being built (its buffers not yet laid out) has factors too.
pub fn material_factors(doc: &Document, material: usize) -> Result<[f32; 3]> {
    let m = material_json(doc, material)?;
    let field = |path: [&str; 2], name: &str| -> Result<f32> {
        let v = m.get(path[0]).and_then(|p| p.get(path[1]));
        match v {
            None => Ok(1.0),
            Some(v) => match v.as_f64() {
                Some(x) if x.is_finite() => Ok(x as f32),
                _ => Err(doc.invalid(
                    format!("materials[{material}].{name}"),
                    "must be a finite number",
                )),
            },
        }
    };
    let f = [
        field(["normalTexture", "scale"], "normalTexture.scale")?,
        field(
            ["pbrMetallicRoughness", "metallicFactor"],
            "pbrMetallicRoughness.metallicFactor",
        )?,
        field(
            ["pbrMetallicRoughness", "roughnessFactor"],
            "pbrMetallicRoughness.roughnessFactor",
        )?,
    ];
    if !(0.0..=1.0).contains(&f[1]) || !(0.0..=1.0).contains(&f[2]) {
        return Err(doc.invalid(
            format!("materials[{material}].pbrMetallicRoughness"),
            "metallicFactor and roughnessFactor must be in 0..1",
        ));
    }
    Ok(f)
}

/// Whether material `material` is double-sided (glTF 2.0 §3.9.5: `doubleSided`, default
/// false: back faces are culled and a single-sided surface is seen from its front only).
pub fn double_sided(doc: &Document, material: usize) -> Result<bool> {
    match material_json(doc, material)?.get("doubleSided") {
        None => Ok(false),
        Some(v) => v.as_bool().ok_or_else(|| {
            doc.invalid(
                format!("materials[{material}].doubleSided"),
                "must be true or false",
            )
        }),
    }
}

/// Whether material `material` names any texture (so its textures need the typed document).
pub fn has_textures(doc: &Document, material: usize) -> bool {
    let Some(m) = doc.array("materials").get(material) else {
        return false;
    };
    let pbr = m.get("pbrMetallicRoughness");
    ["normalTexture", "occlusionTexture", "emissiveTexture"]
        .iter()
        .any(|k| m.get(*k).is_some())
        || ["baseColorTexture", "metallicRoughnessTexture"]
            .iter()
            .any(|k| pbr.and_then(|p| p.get(*k)).is_some())
}

/// Texel coordinate `x` (in pixels, continuous) wrapped into `0..n`.
fn wrap(x: i64, n: u32, mode: WrappingMode) -> usize {
    let n = i64::from(n.max(1));
    let w = match mode {
        WrappingMode::ClampToEdge => x.clamp(0, n - 1),
        WrappingMode::Repeat => x.rem_euclid(n),
        WrappingMode::MirroredRepeat => {
            let m = x.rem_euclid(2 * n);
            if m < n { m } else { 2 * n - 1 - m }
        }
    };
    w as usize
}

impl Rgba8 {
    /// Bilinear lookup of channel `c` (0-3) at UV `(u, v)` (glTF: v down the image), 0 to 1.
    pub fn sample(&self, u: f32, v: f32, c: usize, wrap_mode: [WrappingMode; 2]) -> f32 {
        if self.width == 0 || self.height == 0 {
            return 0.0;
        }
        let (u, v) = (
            if u.is_finite() { u } else { 0.0 },
            if v.is_finite() { v } else { 0.0 },
        );
        let x = f64::from(u) * f64::from(self.width) - 0.5;
        let y = f64::from(v) * f64::from(self.height) - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
        let texel = |dx: i64, dy: i64| {
            let px = wrap(x0 as i64 + dx, self.width, wrap_mode[0]);
            let py = wrap(y0 as i64 + dy, self.height, wrap_mode[1]);
            f32::from(self.pixels[(py * self.width as usize + px) * 4 + c]) / 255.0
        };
        let top = texel(0, 0) * (1.0 - fx) + texel(1, 0) * fx;
        let bottom = texel(0, 1) * (1.0 - fx) + texel(1, 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_lookups_wrap_as_the_sampler_says() {
        // 2×1: left texel 0, right texel 255 in channel 0.
        let img = Rgba8 {
            width: 2,
            height: 1,
            pixels: vec![0, 0, 0, 0, 255, 0, 0, 0],
        };
        let r = [WrappingMode::Repeat; 2];
        let c = [WrappingMode::ClampToEdge; 2];
        assert_eq!(img.sample(0.25, 0.5, 0, r), 0.0);
        assert_eq!(img.sample(0.75, 0.5, 0, r), 1.0);
        assert!((img.sample(0.5, 0.5, 0, r) - 0.5).abs() < 1e-6);
        // At u = 0 repeat blends with the right edge; clamp does not.
        assert!((img.sample(0.0, 0.5, 0, r) - 0.5).abs() < 1e-6);
        assert_eq!(img.sample(0.0, 0.5, 0, c), 0.0);
        assert_eq!(img.sample(1.25, 0.5, 0, r), 0.0);
        assert_eq!(wrap(-1, 4, WrappingMode::MirroredRepeat), 0);
        assert_eq!(wrap(4, 4, WrappingMode::MirroredRepeat), 3);
        assert_eq!(wrap(5, 4, WrappingMode::Repeat), 1);
    }

    #[test]
    fn materials_are_single_sided_unless_they_say_otherwise() {
        let json = br#"{"asset":{"version":"2.0"},"materials":[{},{"doubleSided":true},{"doubleSided":false},{"doubleSided":1}]}"#;
        let doc = Document::from_bytes(std::path::Path::new("m.gltf"), json.to_vec())
            .expect("a document");
        assert!(!double_sided(&doc, 0).expect("a bool"));
        assert!(double_sided(&doc, 1).expect("a bool"));
        assert!(!double_sided(&doc, 2).expect("a bool"));
        let e = double_sided(&doc, 3).unwrap_err().to_string();
        assert!(
            e.contains("m.gltf") && e.contains("materials[3].doubleSided"),
            "{e}"
        );
        assert!(double_sided(&doc, 4).is_err());
    }

    #[test]
    fn texture_transforms_are_translation_rotation_scale() {
        let json = br#"{"asset":{"version":"2.0"},"materials":[
            {"pbrMetallicRoughness":{"baseColorTexture":{"index":0,"extensions":{"KHR_texture_transform":
                {"offset":[0.5,0],"rotation":1.5707963267948966,"scale":[2,2],"texCoord":1}}}}},
            {"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}},
            {"normalTexture":{"index":0,"extensions":{"KHR_texture_transform":{"scale":[1]}}}}]}"#;
        let doc = Document::from_bytes(std::path::Path::new("t.gltf"), json.to_vec())
            .expect("a document");
        let t = texture_transform(&doc, 0, Slot::BaseColor)
            .expect("valid")
            .expect("a transform");
        // The extension's example order: scale (2, 0), rotate by 90° (to (0, -2)), translate.
        let [u, v] = t.apply([1.0, 0.0]);
        assert!((u - 0.5).abs() < 1e-6 && (v + 2.0).abs() < 1e-6, "{u} {v}");
        assert_eq!(t.tex_coord, Some(1));
        assert_eq!(
            texture_transform(&doc, 1, Slot::BaseColor).expect("valid"),
            None
        );
        assert_eq!(
            texture_transform(&doc, 0, Slot::Normal).expect("valid"),
            None
        );
        let e = texture_transform(&doc, 2, Slot::Normal)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("materials[2].normalTexture.extensions.KHR_texture_transform.scale"),
            "{e}"
        );
    }
}
