//! Materials for the preview: a glTF material's base colour, normal and metallic-roughness
//! textures (glTF 2.0 §3.9.2–3.9.4; Frantzen's "textured, normal mapped, roughness mapped
//! objects") with their factors, read through `pelt_io::picture` (the `gltf` crate's typed
//! document, images decoded with the `image` crate), and the mip chains the renderer uploads.
//! Factors that glTF multiplies per vertex (the base colour factor) stay in the vertex albedo;
//! the scalar factors live here. Decoded images are shared between the materials that use them.

use std::collections::HashMap;
use std::sync::Arc;

use pelt_io::picture::{self, Rgba8, Slot, WrappingMode};
use pelt_io::{Document, IoError};

/// The largest texture side an asset is loaded with unless told otherwise: 8192, the 2D
/// texture limit every device wgpu opens with its default limits offers.
pub const DEFAULT_MAX_TEXTURE: u32 = 8192;

/// One texture of a material.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    /// The decoded image (shared by every material that uses it).
    pub image: Arc<Rgba8>,
    /// The sampler's wrap modes (s, t).
    pub wrap: [WrappingMode; 2],
}

/// One material as the preview draws it.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// `baseColorTexture` (sRGB; multiplied into the vertex albedo).
    pub base_color: Option<Texture>,
    /// `normalTexture` (linear, tangent space).
    pub normal: Option<Texture>,
    /// `normalTexture.scale`.
    pub normal_scale: f32,
    /// `metallicRoughnessTexture` (linear: B metalness, G roughness).
    pub metallic_roughness: Option<Texture>,
    /// `metallicFactor`.
    pub metallic: f32,
    /// `roughnessFactor`.
    pub roughness: f32,
    /// The TEXCOORD set every texture of the material is sampled with (the base colour
    /// texture's, else the normal texture's, else the metallic-roughness texture's).
    pub tex_coord: u32,
    /// `KHR_texture_transform` of the texture that chose `tex_coord`, applied to the UVs as
    /// they are read (one transform for the material, as one set of UVs is drawn).
    pub uv_transform: Option<picture::UvTransform>,
    /// glTF's `doubleSided`: false (glTF's default) culls back faces of opaque surfaces,
    /// whose back is never seen; true draws both sides, the back with its normal flipped.
    pub double_sided: bool,
}

impl Default for Material {
    /// The material of a primitive without one and of built-in shapes: no textures, a
    /// dielectric (metallic 0) of roughness 0.5, the preview's neutral surface (its specular
    /// term unscaled), single-sided as glTF's default material is; the material a bake adds to
    /// a furred primitive without one has the same factors. glTF's own default (metallic 1,
    /// roughness 1) would draw such meshes as unlit black metal in a renderer without
    /// environment reflections; materials that exist get glTF's defaults for the factors they
    /// leave out.
    fn default() -> Self {
        Material {
            base_color: None,
            normal: None,
            normal_scale: 1.0,
            metallic_roughness: None,
            metallic: pelt_io::texture::NEUTRAL_METALLIC,
            roughness: pelt_io::texture::NEUTRAL_ROUGHNESS,
            tex_coord: 0,
            uv_transform: None,
            double_sided: false,
        }
    }
}

impl Material {
    /// Whether any texture is sampled (the vertices need UVs).
    pub fn textured(&self) -> bool {
        self.base_color.is_some() || self.normal.is_some() || self.metallic_roughness.is_some()
    }
}

/// A run of a mesh's index list drawn with one material.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Part {
    /// First index.
    pub first: u32,
    /// Index count.
    pub count: u32,
    /// Index into the mesh's materials.
    pub material: u32,
}

/// Reads a document's materials on demand, decoding each image once, no side longer than
/// its `max_texture` (a larger image is halved while it decodes, with a warning).
#[derive(Debug)]
pub struct MaterialReader {
    images: HashMap<usize, Arc<Rgba8>>,
    max_texture: u32,
    /// Materials read so far, by glTF index (None: a primitive without a material).
    pub read: Vec<(Option<usize>, Material)>,
    /// Images decoded smaller than stored, each naming the file and the image.
    pub warnings: Vec<String>,
}

impl Default for MaterialReader {
    fn default() -> Self {
        MaterialReader::with_max_texture(DEFAULT_MAX_TEXTURE)
    }
}

impl MaterialReader {
    /// A reader that decodes no image side longer than `max_texture`.
    pub fn with_max_texture(max_texture: u32) -> Self {
        MaterialReader {
            images: HashMap::new(),
            max_texture,
            read: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// The index (into [`MaterialReader::read`]) of glTF material `m`, read now unless it
    /// already was.
    pub fn index(&mut self, doc: &Document, m: Option<usize>) -> Result<u32, IoError> {
        if let Some(k) = self.read.iter().position(|(i, _)| *i == m) {
            return Ok(k as u32);
        }
        let mut material = match m {
            Some(m) => self.material(doc, m)?,
            None => Material::default(),
        };
        // OBJ says nothing of which side faces out: draw both.
        material.double_sided |= pelt_io::is_obj(&doc.path);
        self.read.push((m, material));
        Ok(self.read.len() as u32 - 1)
    }

    fn texture(
        &mut self,
        doc: &Document,
        m: usize,
        slot: Slot,
    ) -> Result<Option<(Texture, u32)>, IoError> {
        let Some(t) = picture::material_texture(doc, m, slot)? else {
            return Ok(None);
        };
        let image = match self.images.get(&t.image) {
            Some(i) => Arc::clone(i),
            None => {
                let (i, stored) = picture::decode_within(doc, t.image, self.max_texture)?;
                if let Some((w, h)) = stored {
                    self.warnings.push(format!(
                        "{}: images[{}]: {w}×{h} is larger than the {} texture limit: drawn at {}×{}",
                        doc.path.display(),
                        t.image,
                        self.max_texture,
                        i.width,
                        i.height
                    ));
                }
                let i = Arc::new(i);
                self.images.insert(t.image, Arc::clone(&i));
                i
            }
        };
        Ok(Some((
            Texture {
                image,
                wrap: t.wrap,
            },
            t.tex_coord,
        )))
    }

    fn material(&mut self, doc: &Document, m: usize) -> Result<Material, IoError> {
        let [normal_scale, metallic, roughness] = picture::material_factors(doc, m)?;
        let double_sided = picture::double_sided(doc, m)?;
        if !picture::has_textures(doc, m) {
            return Ok(Material {
                normal_scale,
                metallic,
                roughness,
                double_sided,
                ..Material::default()
            });
        }
        let base = self.texture(doc, m, Slot::BaseColor)?;
        let normal = self.texture(doc, m, Slot::Normal)?;
        let mr = self.texture(doc, m, Slot::MetallicRoughness)?;
        let chosen = [
            (&base, Slot::BaseColor),
            (&normal, Slot::Normal),
            (&mr, Slot::MetallicRoughness),
        ]
        .into_iter()
        .find_map(|(t, slot)| t.as_ref().map(|(_, set)| (*set, slot)));
        let (mut tex_coord, mut uv_transform) = (0, None);
        if let Some((set, slot)) = chosen {
            uv_transform = picture::texture_transform(doc, m, slot)?;
            tex_coord = uv_transform.and_then(|t| t.tex_coord).unwrap_or(set);
        }
        Ok(Material {
            base_color: base.map(|(t, _)| t),
            normal: normal.map(|(t, _)| t),
            normal_scale,
            metallic_roughness: mr.map(|(t, _)| t),
            metallic,
            roughness,
            tex_coord,
            uv_transform,
            double_sided,
        })
    }
}

/// sRGB-encoded `c` (0..1) to linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear `c` (0..1) to sRGB-encoded.
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The full mip chain of `image`, level 0 first, each level a 2×2 box filter of the one above
/// ([`next_level`]).
pub fn mip_chain(image: &Rgba8, srgb: bool) -> Vec<Rgba8> {
    let mut levels = vec![image.clone()];
    while let Some(top) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
        let next = next_level(top, srgb);
        levels.push(next);
    }
    levels
}

/// How many levels a full mip chain of a `width` × `height` image has (down to 1×1).
pub fn mip_count(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// The level below `top`: each texel the 2×2 box filter of the texels above it (odd sides
/// clamp their last texel). With `srgb`, colour channels are averaged in linear light and
/// stored sRGB-encoded again (the nearest byte, found among the 255 midpoints between
/// encoded bytes); alpha (and every channel of a linear image) is averaged as stored. Normal
/// maps are averaged as stored too (the shader renormalizes).
pub fn next_level(top: &Rgba8, srgb: bool) -> Rgba8 {
    // An encoded value (in bytes, fractions allowed) in linear light.
    let decode = |b: f32| {
        let c = b / 255.0;
        if srgb { srgb_to_linear(c) } else { c }
    };
    let to_linear: Vec<f32> = (0..256).map(|b| decode(b as f32)).collect();
    // Byte b is nearest to a linear value v when v lies between the midpoints b-½ and b+½
    // (in encoded terms), so the byte is the count of midpoints at or below v.
    let midpoints: Vec<f32> = (0..255).map(|b| decode(b as f32 + 0.5)).collect();
    let (tw, th) = (top.width as usize, top.height as usize);
    let (w, h) = ((tw / 2).max(1), (th / 2).max(1));
    let mut pixels = Vec::with_capacity(w * h * 4);
    for y in 0..h {
        let rows = [(2 * y).min(th - 1), (2 * y + 1).min(th - 1)];
        for x in 0..w {
            let cols = [(2 * x).min(tw - 1), (2 * x + 1).min(tw - 1)];
            for c in 0..4 {
                let mut sum = 0.0;
                for sy in rows {
                    for sx in cols {
                        let b = usize::from(top.pixels[(sy * tw + sx) * 4 + c]);
                        sum += if c < 3 {
                            to_linear[b]
                        } else {
                            b as f32 / 255.0
                        };
                    }
                }
                let mean = sum / 4.0;
                pixels.push(if c < 3 {
                    midpoints.partition_point(|&m| m <= mean) as u8
                } else {
                    (mean * 255.0).round().clamp(0.0, 255.0) as u8
                });
            }
        }
    }
    Rgba8 {
        width: w as u32,
        height: h as u32,
        pixels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mip_chain_halves_to_one_texel_and_averages_in_linear_light() {
        // 3×2: black and white columns; sRGB averaging of black and white is linear 0.5.
        let px = |v: u8| [v, v, v, 255];
        let image = Rgba8 {
            width: 3,
            height: 2,
            pixels: [px(0), px(255), px(0), px(0), px(255), px(0)].concat(),
        };
        let srgb = mip_chain(&image, true);
        assert_eq!(
            srgb.iter().map(|l| (l.width, l.height)).collect::<Vec<_>>(),
            vec![(3, 2), (1, 1)]
        );
        let expect = (linear_to_srgb(0.5) * 255.0).round() as u8;
        assert_eq!(srgb[1].pixels, vec![expect, expect, expect, 255]);
        assert_eq!(expect, 188);
        // Linear images average as stored.
        assert_eq!(mip_chain(&image, false)[1].pixels, vec![128, 128, 128, 255]);
    }

    #[test]
    fn levels_round_to_the_nearest_encoded_byte() {
        // Every 2×2 block of these bytes, against the encoding computed directly.
        let bytes = [0u8, 1, 2, 17, 60, 127, 128, 188, 200, 254, 255];
        let mut checked = 0;
        for &a in &bytes {
            for &b in &bytes {
                for &c in &bytes {
                    let top = Rgba8 {
                        width: 2,
                        height: 2,
                        pixels: [[a, a, a, a], [b, b, b, b], [c, c, c, c], [a, b, c, 255]].concat(),
                    };
                    let mean = [a, b, c, a, b, c]
                        .map(|v| srgb_to_linear(f32::from(v) / 255.0))
                        .iter()
                        .take(4)
                        .sum::<f32>()
                        / 4.0;
                    let direct = (linear_to_srgb(mean) * 255.0).round();
                    let got = f32::from(next_level(&top, true).pixels[0]);
                    // Equal but where the mean falls within float error of a midpoint.
                    assert!(
                        (got - direct).abs() <= 1.0,
                        "{a} {b} {c}: {got} vs {direct}"
                    );
                    checked += usize::from(got == direct);
                }
            }
        }
        assert!(checked >= bytes.len().pow(3) - 2, "{checked} exact");
        assert_eq!(
            (mip_count(1, 1), mip_count(3, 2), mip_count(8192, 8192)),
            (1, 2, 14)
        );
    }

    #[test]
    fn srgb_round_trips() {
        for b in 0..=255u8 {
            let c = f32::from(b) / 255.0;
            assert!((linear_to_srgb(srgb_to_linear(c)) - c).abs() < 1e-5, "{b}");
        }
    }
}
