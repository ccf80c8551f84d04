//! Explicit strands for the converged fur reference (`pelt render --mode strands`): the one
//! strand model the fur textures are rendered from ([`pelt_fur::strands`]: density, radius
//! and jitter, heights and bias, lean, clumping) planted on the baked surface. The tile is
//! repeated over the mesh's `TEXCOORD_0 × uvScale`, exactly where the shells sample the
//! heightfield, so strand i of a tile stands where the heightfield shows it. Each strand
//! follows the shells' path (Revie Listing 2.1: along the normal bent toward the baked comb,
//! scaled by the fur length and the comb length) plus the model's lean mapped through the
//! triangle's UV-to-surface Jacobian; its radius is the model's, in tile widths, mapped the
//! same way. The vertex stage of shaders/strands.wgsl builds the segments.

use glam::{DVec2, Vec3, Vec4};

use crate::asset::MeshData;
use crate::fur::comb_object;
use crate::material::Texture;
use crate::vertex::StrandRoot;

/// Most strands one mesh may plant (80 bytes each on the GPU: 240 MB, under wgpu's default
/// 256 MiB buffer limit).
pub const MAX_STRANDS: u64 = 3_000_000;
/// Most tiles the UV boxes of a mesh's triangles may span together.
const MAX_TILE_VISITS: u64 = 50_000_000;

/// Why a mesh's strands cannot be planted.
#[derive(Debug, thiserror::Error)]
pub enum StrandError {
    /// The mesh has no fur.
    #[error("the asset has no baked fur (_FUR_COMB) to plant strands on")]
    NoFur,
    /// Too many strands.
    #[error(
        "the strand reference would plant about {count} strands (at most {MAX_STRANDS}): the fur's UV area × uvScale² × {per_tile} strands per tile is too large"
    )]
    TooMany {
        /// Expected count.
        count: u64,
        /// Strands per tile.
        per_tile: u32,
    },
    /// UV boxes span too many tiles (a sliver triangle across a huge UV range).
    #[error(
        "the fur's triangles span {tiles} texture tiles at uvScale (at most {MAX_TILE_VISITS})"
    )]
    TooManyTiles {
        /// Tiles spanned.
        tiles: u64,
    },
}

/// The model's strands binned into a `side × side` grid over the unit tile.
struct Bins {
    side: usize,
    cells: Vec<Vec<u32>>,
}

impl Bins {
    fn new(strands: &[pelt_fur::strands::Strand]) -> Bins {
        let side = ((strands.len() as f64).sqrt() / 4.0).clamp(1.0, 256.0) as usize;
        let mut cells = vec![Vec::new(); side * side];
        for (i, s) in strands.iter().enumerate() {
            let cx = ((s.x * side as f64) as usize).min(side - 1);
            let cy = ((s.y * side as f64) as usize).min(side - 1);
            cells[cy * side + cx].push(i as u32);
        }
        Bins { side, cells }
    }
}

/// One triangle in tile units with its surface data.
struct Tri<'m> {
    uv: [DVec2; 3],
    v: [usize; 3],
    /// The base colour texture that colours the strands (the fur's `colorFromTexture`).
    texture: Option<&'m Texture>,
}

impl Tri<'_> {
    /// Barycentric coordinates of `p`, or None outside (or a degenerate triangle).
    fn barycentric(&self, p: DVec2) -> Option<[f64; 3]> {
        let [a, b, c] = self.uv;
        let (e1, e2, d) = (b - a, c - a, p - a);
        let det = e1.perp_dot(e2);
        if det.abs() < 1e-18 {
            return None;
        }
        let w1 = d.perp_dot(e2) / det;
        let w2 = e1.perp_dot(d) / det;
        let w0 = 1.0 - w1 - w2;
        (w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0).then_some([w0, w1, w2])
    }
}

/// The strands `mesh`'s fur plants, in triangle order (deterministic).
pub fn plant(mesh: &MeshData) -> Result<Vec<StrandRoot>, StrandError> {
    let fur = mesh.fur.as_ref().ok_or(StrandError::NoFur)?;
    let scale = f64::from(fur.look.uv_scale);
    let tris: Vec<Tri> = mesh
        .indices
        .chunks_exact(3)
        .enumerate()
        .map(|(k, t)| {
            let v = [t[0] as usize, t[1] as usize, t[2] as usize];
            Tri {
                uv: v.map(|i| DVec2::from(fur.vertices[i].uv.map(f64::from)) * scale),
                v,
                texture: fur
                    .look
                    .color_from_texture
                    .then(|| base_color_of(mesh, 3 * k as u32))
                    .flatten(),
            }
        })
        .collect();
    let (mut area, mut tiles) = (0.0, 0u64);
    for t in &tris {
        let [a, b, c] = t.uv;
        area += (b - a).perp_dot(c - a).abs() / 2.0;
        let lo = a.min(b).min(c).floor();
        let hi = a.max(b).max(c).floor();
        tiles += ((hi.x - lo.x + 1.0) * (hi.y - lo.y + 1.0)) as u64;
    }
    let count = (area * f64::from(fur.model.strands)).ceil() as u64;
    if count > MAX_STRANDS {
        return Err(StrandError::TooMany {
            count,
            per_tile: fur.model.strands,
        });
    }
    if tiles > MAX_TILE_VISITS {
        return Err(StrandError::TooManyTiles { tiles });
    }
    let strands = pelt_fur::strands::generate(&fur.model);
    let bins = Bins::new(&strands);
    let mut out = Vec::with_capacity(count as usize + 16);
    for t in &tris {
        plant_triangle(mesh, t, &strands, &bins, &mut out);
    }
    Ok(out)
}

/// The base colour texture of the part holding index `first`, if it has one.
fn base_color_of(mesh: &MeshData, first: u32) -> Option<&Texture> {
    let part = mesh
        .parts
        .iter()
        .find(|p| (p.first..p.first + p.count).contains(&first))?;
    mesh.materials
        .get(part.material as usize)?
        .base_color
        .as_ref()
}

/// Plants every strand whose root falls in triangle `t` (over every tile its UVs span).
fn plant_triangle(
    mesh: &MeshData,
    t: &Tri,
    strands: &[pelt_fur::strands::Strand],
    bins: &Bins,
    out: &mut Vec<StrandRoot>,
) {
    let [a, b, c] = t.uv;
    let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
    let g = bins.side as f64;
    for ty in lo.y.floor() as i64..=hi.y.floor() as i64 {
        for tx in lo.x.floor() as i64..=hi.x.floor() as i64 {
            let origin = DVec2::new(tx as f64, ty as f64);
            let (l, h) = (lo - origin, hi - origin);
            let cx0 = ((l.x * g).floor().max(0.0)) as usize;
            let cy0 = ((l.y * g).floor().max(0.0)) as usize;
            let cx1 = ((h.x * g).floor().min(g - 1.0)).max(0.0) as usize;
            let cy1 = ((h.y * g).floor().min(g - 1.0)).max(0.0) as usize;
            for cy in cy0..=cy1 {
                for cx in cx0..=cx1 {
                    for &i in &bins.cells[cy * bins.side + cx] {
                        let s = &strands[i as usize];
                        let p = origin + DVec2::new(s.x, s.y);
                        if let Some(w) = t.barycentric(p) {
                            out.push(root(mesh, t, s, w));
                        }
                    }
                }
            }
        }
    }
}

/// The strand `s` rooted at barycentric `w` of triangle `t`.
fn root(mesh: &MeshData, t: &Tri, s: &pelt_fur::strands::Strand, w: [f64; 3]) -> StrandRoot {
    let fur = mesh.fur.as_ref().map(|f| &f.vertices);
    let lerp3 = |f: &dyn Fn(usize) -> Vec3| -> Vec3 {
        (0..3).fold(Vec3::ZERO, |acc, k| acc + f(t.v[k]) * w[k] as f32)
    };
    let vert = |i: usize| &mesh.vertices[i];
    let p = lerp3(&|i| Vec3::from(vert(i).position));
    let n = lerp3(&|i| Vec3::from(vert(i).normal)).normalize_or(Vec3::Z);
    // The comb length (0..1, what the fade reads) and its length in the asset's units.
    let (mut comb, mut comb_len, mut length) = (Vec3::ZERO, 0.0, 0.0);
    if let Some(fv) = fur {
        comb = lerp3(&|i| {
            let c = Vec4::from(fv[i].comb);
            comb_object(
                Vec3::from(vert(i).normal),
                Vec4::from(fv[i].tangent),
                c.truncate(),
            )
        })
        .normalize_or(Vec3::ZERO)
            // The springs' bend (crate::springs), as the shells add it.
            + lerp3(&|i| Vec4::from(fv[i].bend).truncate());
        comb_len = (0..3).map(|k| fv[t.v[k]].comb[3] * w[k] as f32).sum();
        length = (0..3).map(|k| fv[t.v[k]].comb_length() * w[k] as f32).sum();
    }
    let mut albedo: Vec4 = (0..3).fold(Vec4::ZERO, |acc, k| {
        acc + Vec4::from(vert(t.v[k]).albedo) * w[k] as f32
    });
    // With colorFromTexture the base colour texture under the root colours the strand, as
    // it colours the shells (sampled there in linear light).
    if let Some(tex) = t.texture {
        let uv: [f32; 2] =
            std::array::from_fn(|c| (0..3).map(|k| vert(t.v[k]).uv[c] * w[k] as f32).sum());
        for c in 0..3 {
            let s = tex.image.sample(uv[0], uv[1], c, tex.wrap);
            albedo[c] *= crate::shading::linear_of_srgb(s);
        }
    }
    let (du, dv, per_uv) = jacobian(mesh, t);
    let lean = du * s.tx as f32 + dv * s.ty as f32;
    // The shells fade fur whose comb length is under 5 % of the length (shells.wgsl): the
    // strands thin the same way.
    let fade = (comb_len * 20.0).clamp(0.0, 1.0);
    StrandRoot {
        root: p.extend(s.h as f32).into(),
        normal: n.extend(length).into(),
        comb: comb.extend(s.r as f32 * per_uv * fade).into(),
        lean: lean.extend(s.tint as f32).into(),
        albedo: albedo.into(),
    }
}

/// The triangle's surface derivatives along the tile's x and y (asset units per tile
/// width) and its mean length scale (the square root of the area ratio).
fn jacobian(mesh: &MeshData, t: &Tri) -> (Vec3, Vec3, f32) {
    let p =
        t.v.map(|i| Vec3::from(mesh.vertices[i].position).as_dvec3());
    let (e1, e2) = (t.uv[1] - t.uv[0], t.uv[2] - t.uv[0]);
    let (f1, f2) = (p[1] - p[0], p[2] - p[0]);
    let det = e1.perp_dot(e2);
    if det.abs() < 1e-18 {
        return (Vec3::ZERO, Vec3::ZERO, 0.0);
    }
    // [f1 f2] = [du dv] [e1 e2]  ⇒  [du dv] = [f1 f2] [e1 e2]⁻¹.
    let du = (f1 * e2.y - f2 * e1.y) / det;
    let dv = (f2 * e1.x - f1 * e2.x) / det;
    let area_ratio = f1.cross(f2).length() / det.abs();
    (du.as_vec3(), dv.as_vec3(), area_ratio.sqrt() as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fur::{FurData, FurLook, TextureSource};
    use crate::vertex::{FurVertex, Vertex};

    /// A flat unit square in the XY plane with UVs 0..1, combed along +x, fur on.
    pub(crate) fn patch(model: pelt_fur::StrandParams, uv_scale: f32) -> MeshData {
        let corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let vertices = corners
            .iter()
            .map(|&[x, y]| Vertex {
                position: [x, y, 0.0],
                normal: [0.0, 0.0, 1.0],
                albedo: [1.0; 4],
                group: 1,
                uv: [x, y],
            })
            .collect();
        let fur_vertices = corners
            .iter()
            .map(|&uv| FurVertex {
                tangent: [1.0, 0.0, 0.0, 1.0],
                uv,
                comb: [1.0, 0.0, 0.0, 1.0],
                bend: FurVertex::NONE.bend,
            })
            .collect();
        MeshData {
            fur: Some(FurData {
                vertices: fur_vertices,
                fins: Vec::new(),
                fin_sources: Vec::new(),
                look: FurLook {
                    length: 0.1,
                    shells: 16,
                    shell_rule: None,
                    uv_scale,
                    base_color: Vec3::ONE,
                    tip_color: Vec3::ONE,
                    color_from_texture: false,
                },
                heightfield: Vec::new(),
                fin: Vec::new(),
                source: TextureSource::Generated,
                density: crate::fur::density_of(&model),
                model,
            }),
            ..MeshData::untextured(vertices, vec![0, 1, 2, 0, 2, 3])
        }
    }

    #[test]
    fn every_strand_of_every_tile_is_planted_once() {
        let model = pelt_fur::StrandParams {
            strands: 3000,
            tilt: 2.0,
            ..Default::default()
        };
        let roots = plant(&patch(model.clone(), 3.0)).expect("plant");
        // 9 tiles, each strand once (the diagonal splits the square without overlap; a
        // root exactly on it would count twice, which this seed does not produce).
        assert_eq!(roots.len(), 9 * 3000);
        let strands = pelt_fur::strands::generate(&model);
        let s = &strands[17];
        let want = Vec3::new((s.x / 3.0) as f32, (s.y / 3.0) as f32, 0.0);
        let found = roots
            .iter()
            .any(|r| (Vec3::new(r.root[0], r.root[1], r.root[2]) - want).length() < 1e-6);
        assert!(found, "strand 17 of tile (0, 0) stands at its UV / uvScale");
        for r in &roots {
            // Radius and lean in asset units: tile widths / uvScale on this unit square.
            assert!((r.comb[3] * 3.0 - 0.0025).abs() <= 0.0025 * 0.3 + 1e-6);
            let lean = Vec3::new(r.lean[0], r.lean[1], r.lean[2]).length() * 3.0;
            assert!(lean <= (model.tilt * model.radius) as f32 + 1e-6);
            assert_eq!(r.comb[..3], [1.0, 0.0, 0.0]);
        }
    }

    /// With colorFromTexture the base colour texture under each root colours its strand, in
    /// linear light; without it, the texture is not read (as the shells do).
    #[test]
    fn colour_from_texture_tints_each_strand_by_the_texel_under_its_root() {
        let model = pelt_fur::StrandParams {
            strands: 400,
            ..Default::default()
        };
        let mut mesh = patch(model, 1.0);
        // 2 × 1: sRGB 255 red on the left half of the UVs, sRGB 128 green on the right.
        mesh.materials[0].base_color = Some(Texture {
            image: std::sync::Arc::new(pelt_io::picture::Rgba8 {
                width: 2,
                height: 1,
                pixels: vec![255, 0, 0, 255, 0, 128, 0, 255],
            }),
            wrap: [pelt_io::picture::WrappingMode::ClampToEdge; 2],
        });
        let plain = plant(&mesh).expect("plant");
        let white = |r: &StrandRoot| r.albedo[..3].iter().all(|c| (c - 1.0).abs() < 1e-5);
        assert!(plain.iter().all(white), "texture unread");
        mesh.fur.as_mut().expect("fur").look.color_from_texture = true;
        let tinted = plant(&mesh).expect("plant");
        assert_eq!(tinted.len(), plain.len());
        let green = crate::shading::linear_of_srgb8(128);
        let (mut left, mut right) = (0, 0);
        for r in &tinted {
            // Texel centres at u = 0.25 and 0.75: pure texels outside, blends between.
            if r.root[0] < 0.25 {
                assert!(
                    (r.albedo[0] - 1.0).abs() < 1e-5 && r.albedo[1] == 0.0,
                    "{r:?}"
                );
                left += 1;
            } else if r.root[0] > 0.75 {
                assert!(
                    r.albedo[0] == 0.0 && (r.albedo[1] - green).abs() < 1e-5,
                    "{r:?}"
                );
                right += 1;
            }
        }
        assert!(left > 50 && right > 50, "{left} {right}");
    }

    #[test]
    fn too_many_strands_is_an_error_before_planting() {
        let model = pelt_fur::StrandParams::default();
        match plant(&patch(model, 1000.0)) {
            Err(StrandError::TooMany { count, .. }) => assert_eq!(count, 12_000_000_000),
            other => panic!("expected TooMany, got {other:?}"),
        }
    }
}
