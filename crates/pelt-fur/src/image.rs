//! The texture images pelt writes and their PNG encoding (deterministic: no time or text
//! chunks; 16-bit samples big-endian as PNG requires).

use crate::error::FurError;

/// Texel data of one image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Pixels {
    /// 8-bit gray.
    Gray8(Vec<u8>),
    /// 16-bit gray.
    Gray16(Vec<u16>),
    /// 8-bit RGBA (not premultiplied).
    Rgba8(Vec<[u8; 4]>),
}

/// One image (one mip level of one texture).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// File name (`heightfield.png`, `heightfield.mip1.png`, ...).
    pub name: String,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Texels, row 0 at the top.
    pub pixels: Pixels,
}

impl Image {
    /// Encodes the image as PNG.
    pub fn to_png(&self) -> Result<Vec<u8>, FurError> {
        let err = |e: png::EncodingError| FurError::Png {
            name: self.name.clone(),
            message: e.to_string(),
        };
        let mut out = Vec::new();
        let mut enc = png::Encoder::new(&mut out, self.width, self.height);
        enc.set_compression(png::Compression::Fast);
        let bytes: std::borrow::Cow<'_, [u8]> = match &self.pixels {
            Pixels::Gray8(v) => {
                enc.set_color(png::ColorType::Grayscale);
                enc.set_depth(png::BitDepth::Eight);
                v.as_slice().into()
            }
            Pixels::Gray16(v) => {
                enc.set_color(png::ColorType::Grayscale);
                enc.set_depth(png::BitDepth::Sixteen);
                v.iter()
                    .flat_map(|x| x.to_be_bytes())
                    .collect::<Vec<u8>>()
                    .into()
            }
            Pixels::Rgba8(v) => {
                enc.set_color(png::ColorType::Rgba);
                enc.set_depth(png::BitDepth::Eight);
                v.as_flattened().into()
            }
        };
        let mut w = enc.write_header().map_err(err)?;
        w.write_image_data(&bytes).map_err(err)?;
        w.finish().map_err(err)?;
        Ok(out)
    }

    /// MIME type of [`Image::to_png`]'s output.
    pub const MIME: &'static str = "image/png";
}

/// A 16-bit code to 8 bits, rounded.
pub fn to8(v: u16) -> u8 {
    ((u32::from(v) * 255 + 32767) / 65535) as u8
}
