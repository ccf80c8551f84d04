//! A whole texture set: strands → top and side views → images and mip chains, plus the
//! manifest and writing it all to a folder (everything encoded before anything is written, so
//! an error leaves no partial set).

use std::path::Path;

use rayon::prelude::*;

use crate::error::{FurError, ParamError};
use crate::expect;
use crate::fin::{FinView, side_view};
use crate::image::{Image, Pixels, to8};
use crate::manifest::{
    Coverage, FurConfig, FurManifest, LevelRef, MANIFEST_VERSION, TextureEntries, TextureEntry,
};
use crate::mips::{Groups, coverage_chain, level_size, rgb_chain};
use crate::params::{HeightBits, StrandParams};
use crate::raster::{TopView, top_view};
use crate::strands::{Strand, generate as generate_strands};

/// Where a texture level is: (file name, glTF image index), for [`TextureSet::manifest`].
pub type Locate<'a> = dyn FnMut(&str, usize) -> (Option<String>, Option<usize>) + 'a;

/// Heights at which the manifest reports shell coverage.
pub const REPORT_HEIGHTS: [f64; 4] = [0.0, 0.25, 0.5, 0.75];

/// Everything made from one strand model.
#[derive(Debug, Clone)]
pub struct TextureSet {
    /// The parameters.
    pub params: StrandParams,
    /// The strands.
    pub strands: Vec<Strand>,
    /// The top view (full-precision masks and heights).
    pub top: TopView,
    /// The side view.
    pub side: FinView,
    /// Heightfield levels (level 0 first).
    pub heightfield: Vec<Image>,
    /// Dot texture levels.
    pub dots: Vec<Image>,
    /// Fin texture levels.
    pub fin: Vec<Image>,
    /// Coverage measured on level 0.
    pub coverage: Coverage,
}

/// A popcount of 16 subsamples as a 16-bit coverage code.
pub fn coverage_code(mask: u16) -> u16 {
    ((mask.count_ones() * 65535 + 8) / 16) as u16
}

/// File (and glTF image) name of level `level` of texture `stem`: `heightfield.png`,
/// `heightfield.mip1.png`, ...
pub fn level_name(stem: &str, level: usize) -> String {
    if level == 0 {
        format!("{stem}.png")
    } else {
        format!("{stem}.mip{level}.png")
    }
}

fn gray_levels(stem: &str, levels: &[&[u16]], w: usize, h: usize, bits: HeightBits) -> Vec<Image> {
    levels
        .iter()
        .enumerate()
        .map(|(l, v)| {
            let (lw, lh) = level_size(w, h, l);
            Image {
                name: level_name(stem, l),
                width: lw as u32,
                height: lh as u32,
                pixels: match bits {
                    HeightBits::Sixteen => Pixels::Gray16(v.to_vec()),
                    HeightBits::Eight => Pixels::Gray8(v.iter().map(|&x| to8(x)).collect()),
                },
            }
        })
        .collect()
}

/// Fraction of `values` above `t`.
pub fn fraction_above(values: &[u16], t: u16) -> f64 {
    values.iter().filter(|&&v| v > t).count() as f64 / values.len().max(1) as f64
}

/// A height in [0, 1] as the heightfield's 16-bit code.
pub fn height_threshold(h: f64) -> u16 {
    (h.clamp(0.0, 1.0) * 65535.0).round() as u16
}

/// Generates the set for `p`.
pub fn generate(p: &StrandParams) -> Result<TextureSet, ParamError> {
    p.validate()?;
    let size = p.size as usize;
    let fin_rows = p.fin_rows() as usize;
    let strands = generate_strands(p);
    let (top, side) = rayon::join(
        || top_view(&strands, size),
        || side_view(&strands, p.fin_depth, size, fin_rows),
    );
    let dots0: Vec<u16> = top.mask.iter().map(|&m| coverage_code(m)).collect();
    let alpha0: Vec<u16> = side.mask.iter().map(|&m| coverage_code(m)).collect();
    let chain = |v: &[u16], w, h, g| {
        if p.mips {
            coverage_chain(v, w, h, g)
        } else {
            Vec::new()
        }
    };
    let ((height_mips, dot_mips), fin_mips) = rayon::join(
        || {
            rayon::join(
                || chain(&top.height, size, size, Groups::Whole),
                || chain(&dots0, size, size, Groups::Whole),
            )
        },
        || chain(&alpha0, size, fin_rows, Groups::Rows),
    );
    let mut hl: Vec<&[u16]> = vec![&top.height];
    hl.extend(height_mips.iter().map(Vec::as_slice));
    let mut dl: Vec<&[u16]> = vec![&dots0];
    dl.extend(dot_mips.iter().map(Vec::as_slice));
    let mut al: Vec<&[u16]> = vec![&alpha0];
    al.extend(fin_mips.iter().map(Vec::as_slice));
    let rgb_mips = rgb_chain(&side.rgb, &al, size, fin_rows);
    let heightfield = gray_levels("heightfield", &hl, size, size, p.height_bits);
    let dots = gray_levels("dots", &dl, size, size, HeightBits::Eight);
    let mut rgbs: Vec<&[[u8; 3]]> = vec![&side.rgb];
    rgbs.extend(rgb_mips.iter().map(Vec::as_slice));
    let fin = al
        .iter()
        .zip(&rgbs)
        .enumerate()
        .map(|(l, (a, rgb))| {
            let (lw, lh) = level_size(size, fin_rows, l);
            Image {
                name: level_name("fin", l),
                width: lw as u32,
                height: lh as u32,
                pixels: Pixels::Rgba8(
                    a.iter()
                        .zip(rgb.iter())
                        .map(|(&a, c)| [c[0], c[1], c[2], to8(a)])
                        .collect(),
                ),
            }
        })
        .collect();
    let mean =
        |v: &[u16]| v.iter().map(|&x| f64::from(x)).sum::<f64>() / (v.len() as f64 * 65535.0);
    let coverage = Coverage {
        dots: mean(&dots0),
        shells: REPORT_HEIGHTS
            .iter()
            .map(|&h| [h, fraction_above(&top.height, height_threshold(h))])
            .collect(),
        fin_base: mean(&alpha0[(fin_rows - 1) * size..]),
    };
    Ok(TextureSet {
        params: p.clone(),
        strands,
        top,
        side,
        heightfield,
        dots,
        fin,
        coverage,
    })
}

impl TextureSet {
    /// Every image, heightfield levels first, then dots, then fin.
    pub fn images(&self) -> impl Iterator<Item = &Image> {
        self.heightfield.iter().chain(&self.dots).chain(&self.fin)
    }

    /// Every image encoded as PNG, in [`TextureSet::images`] order (encoded in parallel; the
    /// bytes do not depend on the thread count).
    pub fn encode(&self) -> Result<Vec<Vec<u8>>, FurError> {
        let all: Vec<&Image> = self.images().collect();
        all.par_iter().map(|i| i.to_png()).collect()
    }

    /// The coverage the model predicts (None with clumping).
    pub fn expected_coverage(&self) -> Option<Coverage> {
        let p = &self.params;
        (p.clumping == 0.0).then(|| {
            let rows = p.fin_rows() as f64;
            Coverage {
                dots: expect::dot_coverage(p),
                shells: REPORT_HEIGHTS
                    .iter()
                    .map(|&h| [h, expect::shell_coverage(p, h)])
                    .collect(),
                fin_base: expect::fin_coverage(p, 0.5 / rows),
            }
        })
    }

    /// The manifest, with each level located by `locate(texture, level) -> (file, image)`
    /// and level 0 of each texture by `texture(texture) -> glTF texture index`.
    pub fn manifest(
        &self,
        fur: &FurConfig,
        locate: &mut Locate<'_>,
        texture: &mut dyn FnMut(&str) -> Option<usize>,
    ) -> FurManifest {
        let mut entry = |stem: &str, images: &[Image], format: &str| TextureEntry {
            texture: texture(stem),
            format: format.to_owned(),
            levels: images
                .iter()
                .enumerate()
                .map(|(l, img)| {
                    let (file, image) = locate(stem, l);
                    LevelRef {
                        file,
                        image,
                        width: img.width,
                        height: img.height,
                    }
                })
                .collect(),
        };
        let hf_format = match self.params.height_bits {
            HeightBits::Sixteen => "gray16",
            HeightBits::Eight => "gray8",
        };
        let textures = TextureEntries {
            heightfield: entry("heightfield", &self.heightfield, hf_format),
            dots: entry("dots", &self.dots, "gray8"),
            fin: entry("fin", &self.fin, "rgba8"),
        };
        FurManifest {
            version: MANIFEST_VERSION,
            length: fur.length,
            shells: fur.shells,
            shell_rule: Some(crate::shells::ShellRule::MEASURED),
            uv_scale: fur.uv_scale,
            base_color: fur.base_color,
            tip_color: fur.tip_color,
            color_from_texture: fur.color_from_texture,
            textures,
            strands: self.params.clone(),
            coverage: self.coverage.clone(),
            expected_coverage: self.expected_coverage(),
        }
    }

    /// Writes every PNG and `fur.json` into `dir` (created if missing). Returns the total
    /// bytes written.
    pub fn write_dir(&self, dir: &Path, fur: &FurConfig) -> Result<u64, FurError> {
        let pngs = self.encode()?;
        let manifest = self.manifest(
            fur,
            &mut |stem, l| (Some(level_name(stem, l)), None),
            &mut |_| None,
        );
        let mut json = serde_json::to_vec_pretty(&manifest).map_err(|e| FurError::Png {
            name: "fur.json".into(),
            message: e.to_string(),
        })?;
        json.push(b'\n');
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| FurError::Io { path, source }
        };
        std::fs::create_dir_all(dir).map_err(io(dir))?;
        let mut total = 0u64;
        for (img, bytes) in self.images().zip(&pngs) {
            let path = dir.join(&img.name);
            std::fs::write(&path, bytes).map_err(io(&path))?;
            total += bytes.len() as u64;
        }
        let path = dir.join("fur.json");
        std::fs::write(&path, &json).map_err(io(&path))?;
        Ok(total + json.len() as u64)
    }
}
