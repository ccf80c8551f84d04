//! Texture images decoded within a size bound: an image with a side longer than the bound
//! (the GPU's 2D texture limit, or `--max-texture`) is halved until it fits, while it is
//! decoded, so memory follows the size used, not the size stored:
//!
//! - PNG is read one row at a time (the `png` crate) and each k × k block averaged into the
//!   output (an interlaced PNG, whose rows arrive in seven passes, keeps each block's
//!   top-left pixel instead);
//! - JPEG is decoded at 1/2, 1/4 or 1/8 scale by its inverse DCT (the `jpeg-decoder` crate:
//!   the `image` crate's JPEG decoder has no scaled decode), then halved further if needed.
//!
//! The peak is the output plus one input row (PNG) or the scaled RGB decode (JPEG: 1.75× the
//! RGBA output). Sizes are checked from the header first; a header that lies about its size
//! is a decode error naming the image.

use std::io::Cursor;

/// An 8-bit RGBA image, rows top to bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rgba8 {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// 4 bytes per pixel.
    pub pixels: Vec<u8>,
}

/// Why an image could not be decoded smaller than it is stored. The caller names the file and
/// the image (`images[3]`).
#[derive(Debug, thiserror::Error)]
pub enum DecodeError {
    /// The PNG decoder refused the data.
    #[error(transparent)]
    Png(#[from] png::DecodingError),
    /// The JPEG decoder refused the data.
    #[error(transparent)]
    Jpeg(#[from] jpeg_decoder::Error),
    /// The header gives a side longer than any image is decoded from.
    #[error("{width}×{height} is larger than {max_side} a side")]
    TooLarge {
        /// The stored width.
        width: u32,
        /// The stored height.
        height: u32,
        /// The longest side read.
        max_side: u32,
    },
    /// An interlaced PNG has fewer rows than its header gives.
    #[error("the image data ends early")]
    EndsEarly,
    /// The JPEG decoder read no header.
    #[error("no header")]
    NoHeader,
    /// A JPEG pixel format other than grey or RGB (CMYK, 16-bit grey).
    #[error("pixel format {0:?} is not read")]
    PixelFormat(Option<jpeg_decoder::PixelFormat>),
}

/// [`DecodeError::TooLarge`] unless both sides are within `max_side`.
fn check_size(width: u32, height: u32, max_side: u32) -> Result<(), DecodeError> {
    if width > max_side || height > max_side {
        return Err(DecodeError::TooLarge {
            width,
            height,
            max_side,
        });
    }
    Ok(())
}

/// The smallest power of two `k` with both sides divided by it (rounded up) within `max`.
pub fn halvings(width: u32, height: u32, max: u32) -> u32 {
    let mut k = 1u32;
    while width.div_ceil(k) > max.max(1) || height.div_ceil(k) > max.max(1) {
        k *= 2;
    }
    k
}

/// A `k`-times smaller RGBA image built from rows, one k × k block averaged per pixel.
struct Shrink {
    k: usize,
    width: usize,
    out_width: usize,
    sums: Vec<u32>,
    rows_in: usize,
    out: Vec<u8>,
}

impl Shrink {
    fn new(width: u32, height: u32, k: u32) -> Shrink {
        let (w, k) = (width as usize, k as usize);
        let out_width = w.div_ceil(k);
        Shrink {
            k,
            width: w,
            out_width,
            sums: vec![0; out_width * 4],
            rows_in: 0,
            out: Vec::with_capacity(out_width * (height as usize).div_ceil(k) * 4),
        }
    }

    /// One input row of RGBA pixels.
    fn row(&mut self, rgba: impl Iterator<Item = [u8; 4]>) {
        for (x, px) in rgba.take(self.width).enumerate() {
            let s = &mut self.sums[x / self.k * 4..x / self.k * 4 + 4];
            for c in 0..4 {
                s[c] += u32::from(px[c]);
            }
        }
        self.rows_in += 1;
        if self.rows_in == self.k {
            self.flush();
        }
    }

    /// Emits the output row of the rows gathered so far.
    fn flush(&mut self) {
        if self.rows_in == 0 {
            return;
        }
        for ox in 0..self.out_width {
            let cols = self.k.min(self.width - ox * self.k);
            let n = (cols * self.rows_in) as u32;
            for c in 0..4 {
                let s = &mut self.sums[ox * 4 + c];
                self.out.push(((*s + n / 2) / n) as u8);
                *s = 0;
            }
        }
        self.rows_in = 0;
    }

    fn finish(mut self, height: u32) -> Rgba8 {
        self.flush();
        Rgba8 {
            width: self.out_width as u32,
            height: height.div_ceil(self.k as u32),
            pixels: self.out,
        }
    }
}

/// `img` `k` times smaller, each k × k block averaged (for an image already decoded that is
/// still larger than a device's limit).
pub fn halve(img: &Rgba8, k: u32) -> Rgba8 {
    let mut shrink = Shrink::new(img.width, img.height, k);
    for row in img.pixels.chunks_exact(img.width as usize * 4) {
        shrink.row(row.chunks_exact(4).map(|p| [p[0], p[1], p[2], p[3]]));
    }
    shrink.finish(img.height)
}

/// Pixels of an 8-bit row of `channels` samples (1 grey, 2 grey-alpha, 3 RGB, 4 RGBA) as RGBA.
fn rgba(row: &[u8], channels: usize) -> impl Iterator<Item = [u8; 4]> + '_ {
    row.chunks_exact(channels).map(move |p| match p {
        [g] => [*g, *g, *g, 255],
        [g, a] => [*g, *g, *g, *a],
        [r, g, b] => [*r, *g, *b, 255],
        [r, g, b, a] => [*r, *g, *b, *a],
        _ => [0, 0, 0, 255],
    })
}

/// A PNG decoded `k` times smaller (k > 1), row by row.
pub fn png(bytes: &[u8], k: u32, max_side: u32) -> Result<Rgba8, DecodeError> {
    let mut decoder = png::Decoder::new(Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::normalize_to_color8());
    let mut reader = decoder.read_info()?;
    let (width, height) = (reader.info().width, reader.info().height);
    check_size(width, height, max_side)?;
    let channels = reader.output_color_type().0.samples();
    let mut shrink = Shrink::new(width, height, k);
    if !reader.info().interlaced {
        while let Some(row) = reader.next_row()? {
            shrink.row(rgba(row.data(), channels));
        }
        return Ok(shrink.finish(height));
    }
    // Adam7: rows arrive pass by pass (passes with no pixels are skipped); keep each
    // block's top-left pixel.
    let (ow, oh) = (width.div_ceil(k) as usize, height.div_ceil(k) as usize);
    let mut out = vec![0u8; ow * oh * 4];
    let rows = (1..=7u8).flat_map(|p| {
        let (x0, dx, y0, dy) = adam7(p);
        let (pw, ph) = (
            width.saturating_sub(x0).div_ceil(dx),
            height.saturating_sub(y0).div_ceil(dy),
        );
        (0..if pw == 0 { 0 } else { ph }).map(move |line| (p, line))
    });
    for (pass, line) in rows {
        let Some(row) = reader.next_row()? else {
            return Err(DecodeError::EndsEarly);
        };
        let (x0, dx, y0, dy) = adam7(pass);
        let y = (y0 + dy * line) as usize;
        if !y.is_multiple_of(k as usize) {
            continue;
        }
        for (i, px) in rgba(row.data(), channels).enumerate() {
            let x = x0 as usize + dx as usize * i;
            if x.is_multiple_of(k as usize) && x < width as usize {
                let at = ((y / k as usize) * ow + x / k as usize) * 4;
                out[at..at + 4].copy_from_slice(&px);
            }
        }
    }
    Ok(Rgba8 {
        width: ow as u32,
        height: oh as u32,
        pixels: out,
    })
}

/// Adam7 pass `p` (1-7): first column, column step, first row, row step.
fn adam7(p: u8) -> (u32, u32, u32, u32) {
    match p {
        1 => (0, 8, 0, 8),
        2 => (4, 8, 0, 8),
        3 => (0, 4, 4, 8),
        4 => (2, 4, 0, 4),
        5 => (0, 2, 2, 4),
        6 => (1, 2, 0, 2),
        _ => (0, 1, 1, 2),
    }
}

/// A JPEG decoded `k` times smaller (k > 1): scaled by its inverse DCT (up to 1/8), the rest
/// by averaging.
pub fn jpeg(bytes: &[u8], k: u32, max_side: u32) -> Result<Rgba8, DecodeError> {
    let mut d = jpeg_decoder::Decoder::new(Cursor::new(bytes));
    d.read_info()?;
    let info = d.info().ok_or(DecodeError::NoHeader)?;
    let (width, height) = (u32::from(info.width), u32::from(info.height));
    check_size(width, height, max_side)?;
    let idct = k.min(8);
    let want = |s: u32| s.div_ceil(idct).clamp(1, u32::from(u16::MAX)) as u16;
    let (sw, sh) = d.scale(want(width), want(height))?;
    let data = d.decode()?;
    let channels = match d.info().map(|i| i.pixel_format) {
        Some(jpeg_decoder::PixelFormat::L8) => 1,
        Some(jpeg_decoder::PixelFormat::RGB24) => 3,
        other => return Err(DecodeError::PixelFormat(other)),
    };
    let (sw, sh) = (u32::from(sw), u32::from(sh));
    let rest = halvings(sw, sh, width.div_ceil(k).max(height.div_ceil(k)));
    let mut shrink = Shrink::new(sw, sh, rest);
    for row in data.chunks_exact(sw as usize * channels).take(sh as usize) {
        shrink.row(rgba(row, channels));
    }
    Ok(shrink.finish(sh))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halvings_fit_both_sides() {
        assert_eq!(halvings(16384, 16384, 8192), 2);
        assert_eq!(halvings(8192, 100, 8192), 1);
        assert_eq!(halvings(12000, 3000, 8192), 2);
        assert_eq!(halvings(16385, 1, 4096), 8);
    }

    #[test]
    fn blocks_average_and_edges_take_what_is_left() {
        // 3 × 3 RGBA, k = 2: output 2 × 2; the right column and bottom row average less.
        let mut s = Shrink::new(3, 3, 2);
        for y in 0..3u8 {
            s.row((0..3u8).map(|x| [10 * (x + 3 * y), 0, 0, 255]));
        }
        let img = s.finish(3);
        assert_eq!((img.width, img.height), (2, 2));
        let reds: Vec<u8> = img.pixels.chunks(4).map(|p| p[0]).collect();
        // (0+10+30+40)/4, (20+50)/2, (60+70)/2, 80.
        assert_eq!(reds, [20, 35, 65, 80]);
    }
}
