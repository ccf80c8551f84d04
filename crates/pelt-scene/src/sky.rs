//! The cube-map sky's six images (Frantzen's skybox: six images, one `samplerCube`): read
//! and checked before any GPU work. Faces are PNGs in the order +X, −X, +Y, −Y, +Z, −Z, square,
//! all the same size, 8-bit gray, RGB or RGBA, taken as sRGB.

use std::path::{Path, PathBuf};

/// Six decoded cube faces (+X, −X, +Y, −Y, +Z, −Z), RGBA8 sRGB, `size` × `size` each.
#[derive(Debug, Clone)]
pub struct CubeImages {
    /// Side length.
    pub size: u32,
    /// Faces, rows top to bottom.
    pub faces: Vec<Vec<u8>>,
}

/// Largest face side.
pub const MAX_FACE: u32 = 4096;

/// Why the sky could not be loaded: the face, its file, and what is wrong with it.
#[derive(Debug, thiserror::Error)]
#[error("sky.faces[{face}] ({}): {source}", path.display())]
pub struct SkyError {
    /// Index of the face (0 = +X … 5 = −Z).
    pub face: usize,
    /// Its file.
    pub path: PathBuf,
    /// What is wrong.
    #[source]
    pub source: FaceError,
}

/// What is wrong with one face of the sky.
#[derive(Debug, thiserror::Error)]
pub enum FaceError {
    /// The file could not be opened.
    #[error("{0}")]
    Open(#[source] std::io::Error),
    /// The PNG decoder refused it.
    #[error("{0}")]
    Png(#[from] png::DecodingError),
    /// Not square, empty, or larger than [`MAX_FACE`].
    #[error("faces must be square and at most {MAX_FACE} texels, this is {width}×{height}")]
    Shape {
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
    },
    /// Its decoded size does not fit in memory.
    #[error("image too large")]
    TooLarge,
    /// An indexed PNG the decoder did not expand.
    #[error("indexed colour was not expanded")]
    Indexed,
    /// Not the size of the first face.
    #[error("is {size}×{size}, the first face is {first}×{first}")]
    Size {
        /// Its side.
        size: u32,
        /// The first face's side.
        first: u32,
    },
}

fn face(path: &Path) -> Result<(u32, Vec<u8>), FaceError> {
    let file = std::fs::File::open(path).map_err(FaceError::Open)?;
    let mut dec = png::Decoder::new(std::io::BufReader::new(file));
    dec.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = dec.read_info()?;
    let (w, h) = (reader.info().width, reader.info().height);
    if w != h || w == 0 || w > MAX_FACE {
        return Err(FaceError::Shape {
            width: w,
            height: h,
        });
    }
    let size = reader.output_buffer_size().ok_or(FaceError::TooLarge)?;
    let mut buf = vec![0; size];
    let info = reader.next_frame(&mut buf)?;
    buf.truncate(info.buffer_size());
    let rgba: Vec<u8> = match info.color_type {
        png::ColorType::Rgba => buf,
        png::ColorType::Rgb => buf
            .chunks_exact(3)
            .flat_map(|c| [c[0], c[1], c[2], 255])
            .collect(),
        png::ColorType::Grayscale => buf.iter().flat_map(|&g| [g, g, g, 255]).collect(),
        png::ColorType::GrayscaleAlpha => buf
            .chunks_exact(2)
            .flat_map(|c| [c[0], c[0], c[0], c[1]])
            .collect(),
        png::ColorType::Indexed => return Err(FaceError::Indexed),
    };
    Ok((w, rgba))
}

/// Reads the six faces.
pub fn load_cube(faces: &[PathBuf; 6]) -> Result<CubeImages, SkyError> {
    let mut size = 0;
    let mut out = Vec::with_capacity(6);
    for (i, p) in faces.iter().enumerate() {
        let err = |source: FaceError| SkyError {
            face: i,
            path: p.clone(),
            source,
        };
        let (s, rgba) = face(p).map_err(err)?;
        if i > 0 && s != size {
            return Err(err(FaceError::Size {
                size: s,
                first: size,
            }));
        }
        size = s;
        out.push(rgba);
    }
    Ok(CubeImages { size, faces: out })
}
