//! The skinning pass (glTF 2.0 §3.7.3.3; skin.wgsl): one compute dispatch per frame moves a
//! skinned primitive's positions, normals and tangents (the comb's frame, Revie §2.4.1) by
//! its joints' matrices into a storage buffer of [`PosedVertex`]. The asset half
//! ([`GpuSkin::new`]: rest vertices and influences, uploaded once) and the frame half
//! ([`GpuSkin::set_pose`]: the joint matrices, written per frame; [`GpuSkin::encode`]: the
//! dispatch) are kept apart, so a clip plays by writing matrices only. Its input is
//! `pelt_anim::posed::SkinJob`, the same data `pelt pose` skins on the CPU.
//!
//! [`GpuSkinned`] wires it into drawing: the skinned vertices are copied into the object's
//! vertex buffers and its fins rebuilt from them, so every pass draws the pose.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};
use pelt_anim::posed::SkinJob;

use crate::feature::Feature;
use crate::layout::STORAGE;
use crate::readback::FrameError;
use crate::renderer::{ComputeDesc, PipelineError, Renderer};
use crate::shaders::ShaderDesc;

/// skin.wgsl: linear blend skinning of positions, normals and tangents.
pub const SKIN: ComputeDesc = ComputeDesc {
    shader: ShaderDesc::compute("skin.wgsl"),
    groups: &[STORAGE, STORAGE],
};
/// skin_scatter.wgsl: skinned vertices into the vertex buffers.
pub const SKIN_SCATTER: ComputeDesc = ComputeDesc {
    shader: ShaderDesc::compute("skin_scatter.wgsl"),
    groups: &[STORAGE, STORAGE],
};
/// fin_rebuild.wgsl: a skinned mesh's fin instances from its vertices.
pub const FIN_REBUILD: ComputeDesc = ComputeDesc {
    shader: ShaderDesc::compute("fin_rebuild.wgsl"),
    groups: &[STORAGE, STORAGE],
};

/// Bind-group slots of the three skinning shaders: each reads two storage groups, a buffer
/// read and one written in each (keep in sync with their `@group` numbers; checked by the
/// shader-validation test against `groups` above).
pub mod slot {
    /// skin.wgsl: rest → posed; skin_scatter.wgsl: posed → vertices; fin_rebuild.wgsl: fin
    /// sources → fin instances.
    pub const FIRST: u32 = 0;
    /// skin.wgsl: influences and joints; skin_scatter.wgsl: params → fur vertices;
    /// fin_rebuild.wgsl: fur vertices and vertices.
    pub const SECOND: u32 = 1;
}

/// Binds a skinning shader's two groups at [`slot::FIRST`] and [`slot::SECOND`].
fn bind_pair(pass: &mut wgpu::ComputePass<'_>, groups: &[wgpu::BindGroup; 2]) {
    pass.set_bind_group(slot::FIRST, &groups[0], &[]);
    pass.set_bind_group(slot::SECOND, &groups[1], &[]);
}

/// The skinning feature.
pub const FEATURE: Feature = Feature {
    compute: &[SKIN, SKIN_SCATTER, FIN_REBUILD],
    ..Feature::named("skin")
};

/// A vertex at rest. Keep in sync with `SkinVertex` in shaders/skin.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct SkinVertex {
    /// Position (w unused).
    pub position: [f32; 4],
    /// Normal (w unused).
    pub normal: [f32; 4],
    /// Tangent, w the handedness.
    pub tangent: [f32; 4],
    /// x: first influence; y: influence count.
    pub influences: [u32; 4],
}

/// A skinned vertex. Keep in sync with `PosedVertex` in shaders/skin.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct PosedVertex {
    /// Position (w = 1).
    pub position: [f32; 4],
    /// Unit normal (w = 0).
    pub normal: [f32; 4],
    /// Unit tangent, w the handedness.
    pub tangent: [f32; 4],
}

/// One skinned primitive on the GPU.
#[derive(Debug)]
pub struct GpuSkin {
    joints: wgpu::Buffer,
    posed: wgpu::Buffer,
    groups: [wgpu::BindGroup; 2],
    vertices: u32,
    joint_count: usize,
}

/// Rest vertices and (joint, weight bits) pairs of `job`, every set's four in order.
pub fn rest_records(job: &SkinJob) -> (Vec<SkinVertex>, Vec<[u32; 2]>) {
    let sets = job.influences.joints.len();
    let mut influences = Vec::with_capacity(job.positions.len() * 4 * sets);
    let rest = (0..job.positions.len())
        .map(|v| {
            let first = influences.len() as u32;
            for (js, ws) in job.influences.joints.iter().zip(&job.influences.weights) {
                for (&j, &w) in js[v].iter().zip(&ws[v]) {
                    influences.push([u32::from(j), w.to_bits()]);
                }
            }
            let n = job.normals.as_ref().map_or(Vec3::Z, |n| n[v]);
            let t = job.tangents.as_ref().map_or(Vec4::X, |t| t[v]);
            SkinVertex {
                position: job.positions[v].extend(1.0).into(),
                normal: n.extend(0.0).into(),
                tangent: t.into(),
                influences: [first, influences.len() as u32 - first, 0, 0],
            }
        })
        .collect();
    // A buffer of zero bytes cannot be bound.
    if influences.is_empty() {
        influences.push([0, 0]);
    }
    (rest, influences)
}

impl GpuSkin {
    /// Uploads `job`'s rest vertices and influences, and its pose's matrices.
    pub fn new(r: &Renderer, job: &SkinJob) -> GpuSkin {
        let (rest, influences) = rest_records(job);
        let storage = wgpu::BufferUsages::STORAGE;
        let rest_buf = r
            .gpu
            .buffer_init("skin rest", bytemuck::cast_slice(&rest), storage);
        let inf_buf = r.gpu.buffer_init(
            "skin influences",
            bytemuck::cast_slice(&influences),
            storage,
        );
        let joint_count = job.joints.as_ref().map_or(0, Vec::len);
        let joints = r.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("skin joints"),
            size: ((joint_count + 1) * 64) as u64,
            usage: storage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let posed = r.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("skinned vertices"),
            size: (rest.len().max(1) * size_of::<PosedVertex>()) as u64,
            usage: storage | wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let groups = [
            r.storage_group(&rest_buf, &posed),
            r.storage_group(&inf_buf, &joints),
        ];
        let skin = GpuSkin {
            joints,
            posed,
            groups,
            vertices: rest.len() as u32,
            joint_count,
        };
        skin.set_pose(r, job.joints.as_deref().unwrap_or(&[]), job.unweighted);
        skin
    }

    /// Writes this frame's joint matrices (as many as the skin has) and the unweighted
    /// vertices' matrix.
    pub fn set_pose(&self, r: &Renderer, joints: &[Mat4], unweighted: Mat4) {
        let mut m: Vec<[f32; 16]> = joints
            .iter()
            .take(self.joint_count)
            .map(Mat4::to_cols_array)
            .collect();
        m.resize(self.joint_count, Mat4::IDENTITY.to_cols_array());
        m.push(unweighted.to_cols_array());
        r.gpu
            .queue
            .write_buffer(&self.joints, 0, bytemuck::cast_slice(&m));
    }

    /// Records the dispatch into `encoder`.
    pub fn encode(
        &self,
        r: &Renderer,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<(), PipelineError> {
        let pipeline = r.compute(&SKIN)?;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("skin"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipeline);
        bind_pair(&mut pass, &self.groups);
        pass.dispatch_workgroups(self.vertices.div_ceil(64), 1, 1);
        Ok(())
    }

    /// The skinned vertices (storage and vertex usage).
    pub fn posed(&self) -> &wgpu::Buffer {
        &self.posed
    }

    /// Vertices skinned.
    pub fn vertex_count(&self) -> u32 {
        self.vertices
    }

    /// Reads the skinned vertices back (tests, benchmarks).
    pub fn read_back(&self, r: &Renderer) -> Result<Vec<PosedVertex>, FrameError> {
        let bytes = crate::readback::read_buffer(r, &self.posed)?;
        let n = self.vertices as usize;
        Ok(bytemuck::cast_slice::<u8, PosedVertex>(&bytes)[..n].to_vec())
    }
}

/// A skinned mesh on the GPU: a [`GpuSkin`] per skinned primitive, whose output is copied into
/// the mesh's vertex buffers (skin_scatter.wgsl), and the fin instances rebuilt from them
/// (fin_rebuild.wgsl). [`GpuSkinned::pose`] runs all of it for one pose; every pass that
/// draws the mesh (G-buffer, material, shells, fins) then reads the skinned vertices, so the
/// cost does not grow with the shell count.
#[derive(Debug)]
pub struct GpuSkinned {
    /// The rig and ranges it skins.
    pub binding: std::sync::Arc<pelt_scene::skin::SkinBinding>,
    ranges: Vec<(GpuSkin, [wgpu::BindGroup; 2])>,
    fins: Option<([wgpu::BindGroup; 2], u32)>,
}

/// The mesh buffers a skinned mesh's passes write.
#[derive(Debug, Clone, Copy)]
pub struct SkinTargets<'a> {
    /// Vertex records (`Vertex`).
    pub vertices: &'a wgpu::Buffer,
    /// Fur vertex records (`FurVertex`), when the mesh has fur.
    pub fur: Option<&'a wgpu::Buffer>,
    /// Fin instances and the loaded ones, when the mesh has fins.
    pub fins: Option<(&'a wgpu::Buffer, &'a [crate::uniforms::FinInstance])>,
}

/// Why a skinned mesh's fins cannot follow its body: drawn at the rest pose while the body
/// moves, they would tear away from it, so the mesh is refused instead.
#[derive(Debug, thiserror::Error)]
pub enum SkinError {
    /// The fins the mesh draws and the edges they are rebuilt from are not parallel.
    #[error(
        "the skinned mesh draws {instances} fins but has {sources} fin edges to rebuild them from"
    )]
    FinCount {
        /// Fin instances drawn.
        instances: usize,
        /// Fin sources in the skin binding.
        sources: usize,
    },
    /// Fins without the fur vertices they are rebuilt from.
    #[error("the skinned mesh draws fins but has no fur vertices to rebuild them from")]
    FinsWithoutFur,
}

impl GpuSkinned {
    /// The skinning of `pose` (an object's copy of `m`, which the GPU skins): it writes the
    /// copy's vertex, fur-vertex and fin buffers. `None` when `m` has no skin binding.
    pub fn for_pose(
        r: &Renderer,
        pose: &crate::poses::ObjectPose,
        m: &crate::asset::MeshData,
    ) -> Result<Option<GpuSkinned>, SkinError> {
        let Some(binding) = &m.skin else {
            return Ok(None);
        };
        let fur = pose.mesh.fur.as_ref();
        let targets = SkinTargets {
            vertices: &pose.mesh.vertices,
            fur: fur.map(|f| &f.vertices),
            fins: fur.and_then(|f| {
                f.fins
                    .as_ref()
                    .zip(m.fur.as_ref().map(|d| d.fins.as_slice()))
            }),
        };
        GpuSkinned::new(r, std::sync::Arc::clone(binding), targets).map(Some)
    }

    /// Uploads `binding`'s ranges and fin sources, writing into `targets`. Fins the mesh draws
    /// that could not be rebuilt from the skinned vertices are an error, never left behind.
    pub fn new(
        r: &Renderer,
        binding: std::sync::Arc<pelt_scene::skin::SkinBinding>,
        targets: SkinTargets<'_>,
    ) -> Result<GpuSkinned, SkinError> {
        let storage = wgpu::BufferUsages::STORAGE;
        // Where there are no fur vertices the scatter writes none; a word stands in.
        let no_fur = r.gpu.buffer_init("no fur", &[0; 16], storage);
        let fur = targets.fur.unwrap_or(&no_fur);
        let ranges = binding
            .ranges
            .iter()
            .map(|range| {
                let skin = GpuSkin::new(r, &range.job);
                let params = [
                    range.base,
                    skin.vertex_count(),
                    u32::from(targets.fur.is_some()),
                    0,
                ];
                let params =
                    r.gpu
                        .buffer_init("skin scatter", bytemuck::cast_slice(&params), storage);
                let groups = [
                    r.storage_group(&skin.posed, targets.vertices),
                    r.storage_group(&params, fur),
                ];
                (skin, groups)
            })
            .collect();
        let fins = match targets.fins.filter(|(_, rest)| !rest.is_empty()) {
            None => None,
            Some((_, rest)) if rest.len() != binding.fins.len() => {
                return Err(SkinError::FinCount {
                    instances: rest.len(),
                    sources: binding.fins.len(),
                });
            }
            Some((buffer, rest)) => {
                let fur = targets.fur.ok_or(SkinError::FinsWithoutFur)?;
                let mut words: Vec<u32> = Vec::with_capacity(rest.len() * 40);
                for (s, f) in binding.fins.iter().zip(rest) {
                    words.extend_from_slice(s);
                    words.extend_from_slice(bytemuck::cast_slice(std::slice::from_ref(f)));
                }
                let fin_in =
                    r.gpu
                        .buffer_init("fin sources", bytemuck::cast_slice(&words), storage);
                let groups = [
                    r.storage_group(&fin_in, buffer),
                    r.storage_group(fur, targets.vertices),
                ];
                Some((groups, rest.len() as u32))
            }
        };
        Ok(GpuSkinned {
            binding,
            ranges,
            fins,
        })
    }

    /// Skins the mesh at `matrices` (one entry per range: joint matrices and the unweighted
    /// vertices' matrix, `SkinBinding::matrices`) and rebuilds its fins; submitted now, before
    /// the frames that draw it.
    pub fn pose(
        &self,
        r: &Renderer,
        matrices: &[pelt_scene::skin::RangeMatrices],
    ) -> Result<(), PipelineError> {
        let mut enc = r
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("skin"),
            });
        for ((skin, _), (joints, unweighted)) in self.ranges.iter().zip(matrices) {
            skin.set_pose(r, joints, *unweighted);
            skin.encode(r, &mut enc)?;
        }
        let scatter = r.compute(&SKIN_SCATTER)?;
        for (skin, groups) in &self.ranges {
            dispatch(&mut enc, &scatter, groups, skin.vertex_count());
        }
        if let Some((groups, n)) = &self.fins {
            let rebuild = r.compute(&FIN_REBUILD)?;
            dispatch(&mut enc, &rebuild, groups, *n);
        }
        r.gpu.queue.submit([enc.finish()]);
        Ok(())
    }
}

/// One compute pass of `pipeline` over `n` items (64 a workgroup).
fn dispatch(
    enc: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    groups: &[wgpu::BindGroup; 2],
    n: u32,
) {
    let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some("skin"),
        timestamp_writes: None,
    });
    pass.set_pipeline(pipeline);
    bind_pair(&mut pass, groups);
    pass.dispatch_workgroups(n.div_ceil(64), 1, 1);
}
