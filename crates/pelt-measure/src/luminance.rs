//! How bright the fur is against its reference: the fur's pixels are those where the strand
//! reference differs from the same scene drawn without its fur objects, and over them the
//! mean linear luminance (Rec. 709) of a render is compared with the reference's. A ratio of
//! 1 is fur as covered and as lit as the strands; the shells' historic failure was about
//! 0.34 (bare skin showing through).

use pelt_preview::{Image, Mode, Preview, RenderError};
use pelt_scene::asset::MeshData;
use pelt_scene::scene::{Material, Scene};
use pelt_scene::shading::linear_of_srgb8;

/// The smallest difference (sRGB levels, any channel) that makes a pixel the fur's.
pub const MASK_LEVELS: u8 = 3;

/// The fur's pixels of one reference, and their mean luminance there.
#[derive(Debug, Clone, PartialEq)]
pub struct FurMask {
    /// Per pixel: the fur (or what it changes) is there.
    pub mask: Vec<bool>,
    /// Mean linear luminance of the reference over the mask.
    pub reference: f64,
}

/// Mean linear luminance of `image` over `mask` (0 where the mask is empty).
pub fn mean_luminance(image: &Image, mask: &[bool]) -> f64 {
    let (mut sum, mut n) = (0.0, 0u64);
    for (p, &m) in image.rgba.chunks_exact(4).zip(mask) {
        if m {
            let [r, g, b] = [p[0], p[1], p[2]].map(|c| f64::from(linear_of_srgb8(c)));
            sum += 0.2126 * r + 0.7152 * g + 0.0722 * b;
            n += 1;
        }
    }
    if n == 0 { 0.0 } else { sum / n as f64 }
}

/// The pixels where `reference` and `bare` differ by at least [`MASK_LEVELS`].
pub fn mask(reference: &Image, bare: &Image) -> FurMask {
    let mask: Vec<bool> = reference
        .rgba
        .chunks_exact(4)
        .zip(bare.rgba.chunks_exact(4))
        .map(|(a, b)| (0..3).any(|c| a[c].abs_diff(b[c]) >= MASK_LEVELS))
        .collect();
    let reference = mean_luminance(reference, &mask);
    FurMask { mask, reference }
}

/// `scene` drawn (forward) without its fur objects, at its output size.
pub fn bare(
    preview: &mut Preview,
    scene: &Scene,
    meshes: &[MeshData],
    mesh_of: &[usize],
) -> Result<Image, RenderError> {
    let mut s = scene.clone();
    let (objects, of): (Vec<_>, Vec<usize>) = scene
        .objects
        .iter()
        .zip(mesh_of)
        .filter(|(o, _)| !matches!(o.material, Material::Fur(_)))
        .map(|(o, &m)| (o.clone(), m))
        .unzip();
    s.objects = objects;
    let sv = preview.prepare_loaded(&s, meshes, &of, Mode::Forward)?;
    preview.render(&sv)
}

impl FurMask {
    /// `image`'s fur luminance over the reference's (None without fur pixels).
    pub fn ratio(&self, image: &Image) -> Option<f32> {
        (self.reference > 0.0).then(|| (mean_luminance(image, &self.mask) / self.reference) as f32)
    }

    /// How many pixels are the fur's.
    pub fn count(&self) -> usize {
        self.mask.iter().filter(|&&m| m).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(w: u32, h: u32, v: u8) -> Image {
        Image {
            width: w,
            height: h,
            rgba: [v, v, v, 255].repeat((w * h) as usize),
        }
    }

    #[test]
    fn the_ratio_is_taken_over_the_furs_pixels_only() {
        let bare = flat(4, 1, 10);
        let mut reference = bare.clone();
        reference.rgba[4..8].copy_from_slice(&[200, 200, 200, 255]);
        let m = mask(&reference, &bare);
        assert_eq!(m.mask, [false, true, false, false]);
        assert_eq!(m.ratio(&reference), Some(1.0));
        let mut dark = reference.clone();
        dark.rgba[4..8].copy_from_slice(&[10, 10, 10, 255]);
        let r = m.ratio(&dark).expect("fur pixels");
        assert!(r < 0.01, "{r}");
        // A change outside the mask does not count.
        let mut other = reference.clone();
        other.rgba[0..4].copy_from_slice(&[0, 0, 0, 255]);
        assert_eq!(m.ratio(&other), Some(1.0));
        assert_eq!(mask(&bare, &bare).ratio(&bare), None);
    }
}
