//! GPU assets, the longest-lived data after the pipelines: meshes (vertex and index
//! buffers), their fur (fur vertices, fin instances, the heightfield and fin texture with
//! every mip level) and cube-map skies, uploaded once and shared by every view and frame that
//! draws them. The cache is keyed by content (a BLAKE3 hash of the bytes uploaded), so a
//! re-prepared scene, a turntable or a window's every frame reuses what is on the GPU, and a
//! reloaded file whose bytes changed uploads again. Entries no live scene holds are dropped
//! by [`AssetCache::sweep`].

use std::collections::HashMap;
use std::sync::Arc;

use crate::asset::MeshData;
use crate::fur::{FurData, Level};
use crate::gpu_material::{self, GpuMaterial};
use crate::renderer::{DENSITY_FORMAT, FIN_FORMAT, HEIGHT_FORMAT, Renderer, SKY_FORMAT};
use crate::sky::CubeImages;

/// One mesh on the GPU.
#[derive(Debug)]
pub struct GpuMesh {
    /// Vertices.
    pub vertices: wgpu::Buffer,
    /// Triangle indices.
    pub indices: wgpu::Buffer,
    /// Index count.
    pub count: u32,
    /// Runs of the index list by material.
    pub parts: Vec<GpuPart>,
    /// The materials `parts` refer to.
    pub materials: Vec<GpuMaterial>,
    /// Its fur, when a fur object uses it.
    pub fur: Option<GpuFur>,
    /// Each vertex's normal-group colour class ([`crate::debug::group_classes`]), when a
    /// debug view of the groups draws the mesh.
    pub groups: Option<wgpu::Buffer>,
}

/// What a scene draws of a mesh beside its vertices and materials.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Uploads {
    /// Its fur (fur vertices, fins, textures).
    pub fur: bool,
    /// Its normal groups' colour classes (the groups debug view).
    pub groups: bool,
}

impl Uploads {
    /// What either `self` or `other` needs.
    pub fn with(self, other: Uploads) -> Uploads {
        Uploads {
            fur: self.fur || other.fur,
            groups: self.groups || other.groups,
        }
    }
}

/// A run of a mesh's indices drawn with one material.
#[derive(Debug, Clone)]
pub struct GpuPart {
    /// The indices.
    pub indices: std::ops::Range<u32>,
    /// Index into the mesh's materials (and its fur's texture groups).
    pub material: usize,
}

/// A mesh's fur on the GPU.
#[derive(Debug, Clone)]
pub struct GpuFur {
    /// Fur vertices (vertex buffer 1 of the fur pipelines).
    pub vertices: wgpu::Buffer,
    /// Fin instances.
    pub fins: Option<wgpu::Buffer>,
    /// Fin count.
    pub fin_count: u32,
    /// Heightfield, fin texture, the material's base colour and samplers: one group per
    /// material of the mesh.
    pub textures: Vec<wgpu::BindGroup>,
}

/// A mesh's explicit strands on the GPU (the strand reference, [`crate::strands`]).
#[derive(Debug)]
pub struct GpuStrands {
    /// One [`crate::uniforms::StrandRoot`] per strand (an instance buffer).
    pub roots: wgpu::Buffer,
    /// Strands.
    pub count: u32,
    /// The strands as planted (the strand reference's shadow rays start from them).
    pub planted: Vec<crate::uniforms::StrandRoot>,
}

/// A cube-map sky on the GPU.
#[derive(Debug)]
pub struct GpuSky {
    /// The cube map and its sampler.
    pub group: wgpu::BindGroup,
}

type Key = [u8; 32];

/// The uploaded assets.
#[derive(Debug, Default)]
pub struct AssetCache {
    meshes: HashMap<Key, Arc<GpuMesh>>,
    skies: HashMap<Key, Arc<GpuSky>>,
    strands: HashMap<Key, Arc<GpuStrands>>,
}

fn level_bytes<T: bytemuck::Pod>(h: &mut blake3::Hasher, levels: &[Level<T>]) {
    for l in levels {
        h.update(&l.width.to_le_bytes());
        h.update(&l.height.to_le_bytes());
        h.update(bytemuck::cast_slice(&l.texels));
    }
}

fn mesh_key(m: &MeshData, uploads: Uploads) -> Key {
    let mut h = blake3::Hasher::new();
    h.update(&(m.vertices.len() as u64).to_le_bytes());
    h.update(bytemuck::cast_slice(&m.vertices));
    h.update(bytemuck::cast_slice(&m.indices));
    for p in &m.parts {
        h.update(
            &[p.first, p.count, p.material]
                .map(u32::to_le_bytes)
                .concat(),
        );
    }
    for mat in &m.materials {
        h.update(bytemuck::bytes_of(&gpu_material::uniforms(mat)));
        h.update(&[u8::from(mat.double_sided)]);
        for t in [&mat.base_color, &mat.normal, &mat.metallic_roughness] {
            match t {
                Some(t) => {
                    h.update(
                        format!("{}x{} {:?}", t.image.width, t.image.height, t.wrap).as_bytes(),
                    );
                    h.update(&t.image.pixels);
                }
                None => {
                    h.update(b"none");
                }
            }
        }
    }
    if uploads.groups {
        h.update(b"group classes");
    }
    if let Some(f) = m.fur.as_ref().filter(|_| uploads.fur) {
        h.update(b"fur");
        h.update(bytemuck::cast_slice(&f.vertices));
        h.update(bytemuck::cast_slice(&f.fins));
        level_bytes(&mut h, &f.heightfield);
        level_bytes(&mut h, &f.fin);
    }
    *h.finalize().as_bytes()
}

impl AssetCache {
    /// `m` on the GPU with what `uploads` asks for, uploaded now unless it already is. A
    /// skinned mesh is uploaded at rest: each object posing it draws its own copy
    /// ([`crate::poses`]).
    pub fn mesh(&mut self, r: &Renderer, m: &MeshData, uploads: Uploads) -> Arc<GpuMesh> {
        let key = mesh_key(m, uploads);
        if let Some(g) = self.meshes.get(&key) {
            return Arc::clone(g);
        }
        let g = {
            let materials: Vec<GpuMaterial> = m
                .materials
                .iter()
                .map(|mat| gpu_material::upload(r, mat))
                .collect();
            let fur = m
                .fur
                .as_ref()
                .filter(|_| uploads.fur)
                .map(|f| gpu_fur(r, f, &materials));
            let groups = uploads.groups.then(|| {
                let classes = crate::debug::group_classes(&m.vertices, &m.indices);
                r.gpu.buffer_init(
                    "normal-group classes",
                    bytemuck::cast_slice(&classes),
                    wgpu::BufferUsages::VERTEX,
                )
            });
            let vertices = r.gpu.buffer_init(
                "vertices",
                bytemuck::cast_slice(&m.vertices),
                wgpu::BufferUsages::VERTEX,
            );
            Arc::new(GpuMesh {
                fur,
                groups,
                parts: m
                    .parts
                    .iter()
                    .map(|p| GpuPart {
                        indices: p.first..p.first + p.count,
                        material: p.material as usize,
                    })
                    .collect(),
                materials,
                vertices,
                indices: r.gpu.buffer_init(
                    "indices",
                    bytemuck::cast_slice(&m.indices),
                    wgpu::BufferUsages::INDEX,
                ),
                count: m.indices.len() as u32,
            })
        };
        self.meshes.insert(key, Arc::clone(&g));
        g
    }

    /// The explicit strands `m`'s fur plants ([`crate::strands::plant`]), planted and
    /// uploaded now unless they already are.
    pub fn strands(
        &mut self,
        r: &Renderer,
        m: &MeshData,
    ) -> Result<Arc<GpuStrands>, crate::strands::StrandError> {
        let mut h = blake3::Hasher::new();
        h.update(b"strands");
        h.update(&mesh_key(
            m,
            Uploads {
                fur: true,
                groups: false,
            },
        ));
        if let Some(f) = &m.fur {
            h.update(
                format!(
                    "{:?} {} {}",
                    f.model, f.look.uv_scale, f.look.color_from_texture
                )
                .as_bytes(),
            );
        }
        let key = *h.finalize().as_bytes();
        if let Some(s) = self.strands.get(&key) {
            return Ok(Arc::clone(s));
        }
        let roots = crate::strands::plant(m)?;
        // A buffer of zero bytes cannot be bound: an empty set keeps one unused record.
        let bytes: &[u8] = if roots.is_empty() {
            &[0; size_of::<crate::uniforms::StrandRoot>()]
        } else {
            bytemuck::cast_slice(&roots)
        };
        let s = Arc::new(GpuStrands {
            roots: r
                .gpu
                .buffer_init("strand roots", bytes, wgpu::BufferUsages::VERTEX),
            count: roots.len() as u32,
            planted: roots,
        });
        self.strands.insert(key, Arc::clone(&s));
        Ok(s)
    }

    /// The cube map of `cube`, uploaded now unless it already is.
    pub fn sky(&mut self, r: &Renderer, cube: &CubeImages) -> Arc<GpuSky> {
        let mut h = blake3::Hasher::new();
        h.update(&cube.size.to_le_bytes());
        for f in &cube.faces {
            h.update(f);
        }
        let key = *h.finalize().as_bytes();
        Arc::clone(self.skies.entry(key).or_insert_with(|| {
            Arc::new(GpuSky {
                group: sky_group(r, cube),
            })
        }))
    }

    /// Drops the assets no scene holds any more; returns how many.
    pub fn sweep(&mut self) -> usize {
        let before = self.meshes.len() + self.skies.len() + self.strands.len();
        self.meshes.retain(|_, m| Arc::strong_count(m) > 1);
        self.skies.retain(|_, s| Arc::strong_count(s) > 1);
        self.strands.retain(|_, s| Arc::strong_count(s) > 1);
        before - self.meshes.len() - self.skies.len() - self.strands.len()
    }

    /// Meshes held.
    pub fn mesh_count(&self) -> usize {
        self.meshes.len()
    }
}

/// f32 to IEEE half-float bits (round to nearest even), for the heightfield texture.
pub fn f16_bits(v: f32) -> u16 {
    let x = v.to_bits();
    let sign = ((x >> 16) & 0x8000) as u16;
    let exp = ((x >> 23) & 0xff) as i32;
    let man = x & 0x7f_ffff;
    if exp == 0xff {
        return sign | 0x7c00 | if man != 0 { 0x200 } else { 0 };
    }
    let e = exp - 127 + 15;
    if e >= 0x1f {
        return sign | 0x7c00;
    }
    if e <= 0 {
        if e < -10 {
            return sign;
        }
        let m = man | 0x80_0000;
        let shift = (14 - e) as u32;
        let half = 1u32 << (shift - 1);
        let mut r = m >> shift;
        let rest = m & ((1 << shift) - 1);
        if rest > half || (rest == half && r & 1 == 1) {
            r += 1;
        }
        return sign | r as u16;
    }
    let mut r = ((e as u32) << 10) | (man >> 13);
    let rest = man & 0x1fff;
    if rest > 0x1000 || (rest == 0x1000 && r & 1 == 1) {
        r += 1;
    }
    sign | r as u16
}

/// Four of the density's bins, from `first`, as RGBA levels (shells.wgsl's `density_lo`
/// and `density_hi`).
fn density_levels(d: &crate::fur::Density, first: usize) -> Vec<Level<[f32; 4]>> {
    d.levels
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let side = (d.side >> i).max(1);
            Level {
                width: side,
                height: side,
                texels: l
                    .iter()
                    .map(|t| [t[first], t[first + 1], t[first + 2], t[first + 3]])
                    .collect(),
            }
        })
        .collect()
}

fn gpu_fur(r: &Renderer, fur: &FurData, materials: &[GpuMaterial]) -> GpuFur {
    let device = &r.gpu.device;
    let height = r
        .gpu
        .upload_levels("heightfield", HEIGHT_FORMAT, &fur.heightfield, |l| {
            l.iter()
                .flat_map(|&h| f16_bits(f32::from(h) / 65535.0).to_le_bytes())
                .collect::<Vec<u8>>()
                .into()
        });
    let fin = r
        .gpu
        .upload_levels("fin texture", FIN_FORMAT, &fur.fin, |l| {
            bytemuck::cast_slice(l).into()
        });
    let [density_lo, density_hi] = [0, 4].map(|first| {
        let levels = density_levels(&fur.density, first);
        r.gpu
            .upload_levels("fur density", DENSITY_FORMAT, &levels, |l| {
                l.iter()
                    .flat_map(|t| t.iter().flat_map(|&v| f16_bits(v).to_le_bytes()))
                    .collect::<Vec<u8>>()
                    .into()
            })
    });
    let sampler = |v_mode| {
        device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("fur"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: v_mode,
            address_mode_w: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        })
    };
    let repeat = sampler(wgpu::AddressMode::Repeat);
    let fin_sampler = sampler(wgpu::AddressMode::ClampToEdge);
    let group = |m: &GpuMaterial| {
        r.group(
            "fur textures",
            &crate::layout::FUR_TEXTURES,
            &[
                wgpu::BindingResource::TextureView(&height),
                wgpu::BindingResource::TextureView(&fin),
                wgpu::BindingResource::Sampler(&repeat),
                wgpu::BindingResource::Sampler(&fin_sampler),
                wgpu::BindingResource::TextureView(&m.base_view),
                wgpu::BindingResource::Sampler(&m.base_sampler),
                wgpu::BindingResource::TextureView(&density_lo),
                wgpu::BindingResource::TextureView(&density_hi),
            ],
        )
    };
    let textures = materials.iter().map(group).collect();
    GpuFur {
        vertices: r.gpu.buffer_init(
            "fur vertices",
            bytemuck::cast_slice(&fur.vertices),
            wgpu::BufferUsages::VERTEX,
        ),
        fins: (!fur.fins.is_empty()).then(|| {
            r.gpu.buffer_init(
                "fins",
                bytemuck::cast_slice(&fur.fins),
                wgpu::BufferUsages::VERTEX,
            )
        }),
        fin_count: fur.fins.len() as u32,
        textures,
    }
}

fn sky_group(r: &Renderer, cube: &CubeImages) -> wgpu::BindGroup {
    let device = &r.gpu.device;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("sky"),
        size: wgpu::Extent3d {
            width: cube.size,
            height: cube.size,
            depth_or_array_layers: 6,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: SKY_FORMAT,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (i, face) in cube.faces.iter().enumerate() {
        r.gpu.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d {
                    x: 0,
                    y: 0,
                    z: i as u32,
                },
                aspect: wgpu::TextureAspect::All,
            },
            face,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(cube.size * 4),
                rows_per_image: Some(cube.size),
            },
            wgpu::Extent3d {
                width: cube.size,
                height: cube.size,
                depth_or_array_layers: 1,
            },
        );
    }
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::Cube),
        ..Default::default()
    });
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("sky"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    r.group(
        "sky",
        &crate::layout::SKY_CUBE,
        &[
            wgpu::BindingResource::TextureView(&view),
            wgpu::BindingResource::Sampler(&sampler),
        ],
    )
}
