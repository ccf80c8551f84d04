//! FLIP between two 8-bit sRGB images (nv-flip, at its default 67 pixels per degree): the
//! per-pixel error map, its mean, its mean over a mask of pixels, and FLIP's magma heat map.

use pelt_preview::Image;

/// A FLIP comparison.
#[derive(Debug, Clone)]
pub struct Flip {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Per-pixel error, 0 (same) to 1, rows top to bottom.
    pub map: Vec<f32>,
}

/// Why two images cannot be compared.
#[derive(Debug, thiserror::Error)]
#[error("cannot compare a {0}×{1} image with a {2}×{3} one")]
pub struct SizeMismatch(pub u32, pub u32, pub u32, pub u32);

fn rgb(i: &Image) -> nv_flip::FlipImageRgb8 {
    let data: Vec<u8> = i
        .rgba
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    nv_flip::FlipImageRgb8::with_data(i.width, i.height, &data)
}

fn average(v: impl Iterator<Item = f32>) -> f32 {
    let (sum, n) = v.fold((0.0f64, 0usize), |(s, n), e| (s + f64::from(e), n + 1));
    if n == 0 { 0.0 } else { (sum / n as f64) as f32 }
}

impl Flip {
    /// `test` against `reference`.
    pub fn new(reference: &Image, test: &Image) -> Result<Flip, SizeMismatch> {
        if (reference.width, reference.height) != (test.width, test.height) {
            return Err(SizeMismatch(
                reference.width,
                reference.height,
                test.width,
                test.height,
            ));
        }
        let err = nv_flip::flip(
            rgb(reference),
            rgb(test),
            nv_flip::DEFAULT_PIXELS_PER_DEGREE,
        );
        Ok(Flip {
            width: reference.width,
            height: reference.height,
            map: err.to_vec(),
        })
    }

    /// The mean error.
    pub fn mean(&self) -> f32 {
        average(self.map.iter().copied())
    }

    /// The mean error over the pixels where `mask` is true (0 when it has none).
    pub fn masked_mean(&self, mask: &[bool]) -> f32 {
        average(
            self.map
                .iter()
                .zip(mask)
                .filter(|(_, m)| **m)
                .map(|(e, _)| *e),
        )
    }

    /// The share of the pixels where `mask` is true whose error exceeds `above` (0 when it
    /// has none).
    pub fn share_above(&self, mask: &[bool], above: f32) -> f32 {
        average(
            self.map
                .iter()
                .zip(mask)
                .filter(|(_, m)| **m)
                .map(|(e, _)| if *e > above { 1.0 } else { 0.0 }),
        )
    }

    /// The error as FLIP's magma heat map (black 0, yellow-white 1).
    pub fn heat_map(&self) -> Image {
        let err = nv_flip::FlipImageFloat::with_data(self.width, self.height, &self.map);
        let rgba = err
            .apply_color_lut(&nv_flip::magma_lut())
            .to_vec()
            .chunks_exact(3)
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect();
        Image {
            width: self.width,
            height: self.height,
            rgba,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> Image {
        Image {
            width: w,
            height: h,
            rgba: (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .flat_map(|(x, y)| f(x, y))
                .collect(),
        }
    }

    #[test]
    fn same_images_have_no_error_and_a_changed_half_shows_only_there() {
        let base = |x: u32, y: u32| [(x * 8) as u8, (y * 8) as u8, 90, 255];
        let a = image(32, 32, base);
        assert_eq!(Flip::new(&a, &a).expect("same size").mean(), 0.0);
        let b = image(
            32,
            32,
            |x, y| if x < 16 { base(x, y) } else { [255, 0, 0, 255] },
        );
        let f = Flip::new(&a, &b).expect("same size");
        let left: Vec<bool> = (0..32 * 32).map(|i| i % 32 < 6).collect();
        let right: Vec<bool> = (0..32 * 32).map(|i| i % 32 >= 20).collect();
        assert!(f.masked_mean(&left) < 0.01, "{}", f.masked_mean(&left));
        assert!(f.masked_mean(&right) > 0.3, "{}", f.masked_mean(&right));
        assert!(f.mean() > 0.1);
        assert!(Flip::new(&a, &image(8, 8, |_, _| [0; 4])).is_err());
        assert_eq!(f.heat_map().rgba.len(), 32 * 32 * 4);
    }
}
