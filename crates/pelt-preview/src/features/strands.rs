//! Explicit strands, the converged fur reference (`--mode strands`): in the forward pass, in
//! place of each fur object's shells and fins, its strands ([`crate::strands`]) drawn as
//! capsules, opaque and depth tested, lit per light with Kajiya-Kay (Revie Listing 2.4,
//! shaders/strands.wgsl). One frame is one sample: the caller jitters the projection and
//! accumulates (`pelt_measure::strands`).
//!
//! Where a light of the view casts shadows, each strand is lit as its shadow rays found it
//! ([`TracedShadows`], `pelt_trace::strands`): a bit per sample (its segments' ends) and
//! light, traced on the CPU through every other strand and the scene when the view is
//! prepared, with the strands where the frame's wind blows them, and again when the scene's
//! time (so the wind) changes; blended along each segment (the `TRACED_SHADOWS` def of
//! strands.wgsl).

use super::lights;
use crate::draw::{MissingInput, object_blends, object_depth, slot};
use crate::feature::{DrawDesc, Feature, Frame, Phase, Shade, Shared};
use crate::plan::ScenePlan;
use crate::recipe::{Recipe, Step};
use crate::renderer::{Blend, PipelineDesc, PipelineSpec};
use crate::scene_state::{Prepared, SceneInputs, SceneState, StateError};
use crate::shaders::ShaderDesc;
use crate::shading;
use crate::uniforms::StrandRoot;
use pelt_scene::asset::MeshData;
use std::collections::HashMap;
use std::sync::Arc;

/// Segments per strand. Keep in sync with `SEGMENTS` in shaders/strands.wgsl.
pub const STRAND_SEGMENTS: u32 = 4;

const ATTRIBUTES: [wgpu::VertexAttribute; 5] = wgpu::vertex_attr_array![
    0 => Float32x4, 1 => Float32x4, 2 => Float32x4, 3 => Float32x4, 4 => Float32x4
];

/// The strand instance buffer: one [`StrandRoot`] per strand (`StrandIn` in strands.wgsl).
pub fn layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: size_of::<StrandRoot>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &ATTRIBUTES,
    }
}

const TRACED_ATTRIBUTES: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![5 => Uint32x2];

/// The shadow bits' instance buffer: one `[u32; 2]` per strand (`Traced` in strands.wgsl).
pub fn traced_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: size_of::<[u32; 2]>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &TRACED_ATTRIBUTES,
    }
}

/// strands.wgsl, lit per light with Kajiya-Kay.
pub const SHADER: ShaderDesc = ShaderDesc::render("strands.wgsl");

/// strands.wgsl weighing each shadow-casting light by the strand's traced bits.
pub const TRACED: ShaderDesc = SHADER.with_defs(&[("TRACED_SHADOWS", 1)]);

/// The pipeline of strands.wgsl (opaque strands), `traced`: reading the shadow bits.
pub fn pipeline(traced: bool) -> PipelineDesc {
    PipelineDesc {
        shader: if traced { TRACED } else { SHADER },
        spec: PipelineSpec {
            groups: vec![
                crate::layout::FRAME,
                crate::layout::OBJECT,
                crate::layout::LIGHT_ARRAY,
            ],
            vertex_buffers: if traced {
                vec![layout(), traced_layout()]
            } else {
                vec![layout()]
            },
            blends: object_blends(Blend::None),
            depth: object_depth(Blend::None),
            ..PipelineSpec::default()
        },
    }
}

/// Each fur object's strands' shadow bits (`pelt_trace::strands::shadow_bits`), on the GPU,
/// with what they are traced through, so a new wind (a new scene time) traces them again.
#[derive(Debug)]
pub struct TracedShadows {
    /// By scene object index: one `[u32; 2]` per strand.
    bits: HashMap<usize, wgpu::Buffer>,
    /// What they were traced for (the casting lights, the objects and their fur).
    key: String,
    /// The wind they were traced in.
    wind: ([f32; 4], [f32; 4]),
    /// The scene's triangles, which the rays pass through (None: no light casts, nothing is
    /// traced).
    world: Option<pelt_trace::World>,
    /// Each fur object with strands: scene index, object to world, fur length, strands.
    sets: Vec<(usize, glam::Mat4, f32, Arc<crate::assets::GpuStrands>)>,
    /// The casting lights.
    lights: Vec<pelt_scene::shading::Emitter>,
}

impl TracedShadows {
    /// What `plan`'s bits depend on, besides the wind.
    fn key_of(plan: &ScenePlan) -> String {
        let lights: Vec<_> = plan.shadow_lights().map(|l| l.emitter).collect();
        let objects: Vec<_> = plan
            .objects
            .iter()
            .map(|(o, _)| (o.mesh, o.model, o.pattern, o.fur.map(|f| f.length)))
            .collect();
        format!("{lights:?} {objects:?}")
    }

    /// Whether these bits were traced for `plan`'s lights and objects (the wind aside:
    /// [`TracedShadows::follow`] traces them again in a new one).
    pub fn fits(&self, plan: &ScenePlan) -> bool {
        self.key == Self::key_of(plan)
    }

    /// Traces the shadow rays of every fur object's `strands` (by mesh) of `plan` toward its
    /// shadow-casting lights through the strands and `meshes`, in `plan`'s wind, and uploads
    /// the bits.
    pub fn new(
        r: &crate::renderer::Renderer,
        plan: &ScenePlan,
        meshes: &[MeshData],
        strands: &[Option<Arc<crate::assets::GpuStrands>>],
    ) -> TracedShadows {
        let sets = plan
            .objects
            .iter()
            .filter_map(|(o, _)| {
                let (f, s) = (o.fur?, strands.get(o.mesh)?.as_ref()?);
                Some((o.scene_index, o.model, f.length, Arc::clone(s)))
            })
            .collect();
        let lights: Vec<_> = plan.shadow_lights().map(|l| l.emitter).collect();
        let world = (!lights.is_empty())
            .then(|| pelt_trace::World::new(plan, meshes, pelt_trace::SkyModel::Background));
        let mut t = TracedShadows {
            bits: HashMap::new(),
            key: Self::key_of(plan),
            wind: plan.wind,
            world,
            sets,
            lights,
        };
        t.bits = t
            .sets
            .iter()
            .zip(t.trace())
            .map(|((k, ..), b)| {
                let buffer = r.gpu.buffer_init(
                    "strand shadow bits",
                    bytemuck::cast_slice(&b),
                    wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                );
                (*k, buffer)
            })
            .collect();
        t
    }

    /// Each set's bits in the wind last followed (one record for an empty set: a buffer of
    /// zero bytes cannot be bound).
    fn trace(&self) -> Vec<Vec<[u32; 2]>> {
        let sets: Vec<_> = self
            .sets
            .iter()
            .map(|(_, model, length, s)| pelt_trace::strands::StrandSet {
                model: *model,
                length: *length,
                roots: &s.planted,
                wind: self.wind,
            })
            .collect();
        let bits = match &self.world {
            Some(world) if !sets.is_empty() => {
                pelt_trace::strands::shadow_bits(world, &sets, &self.lights)
            }
            _ => vec![Vec::new(); sets.len()],
        };
        bits.into_iter()
            .map(|b| if b.is_empty() { vec![[0; 2]] } else { b })
            .collect()
    }

    /// Traces the bits again where `plan`'s wind (its time) is not the one they were traced
    /// in, and uploads them. The strands blow as strands.wgsl draws them.
    pub fn follow(&mut self, r: &crate::renderer::Renderer, plan: &ScenePlan) {
        if plan.wind == self.wind || self.world.is_none() {
            return;
        }
        self.wind = plan.wind;
        for ((k, ..), b) in self.sets.iter().zip(self.trace()) {
            if let Some(buffer) = self.bits.get(k) {
                r.gpu.write_buffer(buffer, 0, bytemuck::cast_slice(&b));
            }
        }
    }
}

/// The strand reference's feature.
pub const FEATURE: Feature = Feature {
    pipelines: || {
        let both = [pipeline(false), pipeline(true)];
        both.into_iter()
            .flat_map(|d| [d.clone(), lights::without_suns(d)])
            .collect()
    },
    draws: &[DrawDesc {
        into: Shared::Shading,
        phase: Phase::FurLayers,
        draw: shade,
    }],
    scene: Some(SceneState {
        make: |r, s, prepared, owned| {
            if s.plan.mode == crate::plan::Mode::Strands {
                let strands = SceneStrands::plant(r, s, prepared)?;
                owned.insert(TracedShadows::new(r, s.plan, prepared.meshes, &strands.0));
                owned.insert(strands);
            }
            Ok(())
        },
        follow: |r, s, owned| match owned.get_mut::<TracedShadows>() {
            Some(t) if !t.fits(s.plan) => Err(StateError::of(StaleShadows)),
            Some(t) => {
                t.follow(r, s.plan);
                Ok(())
            }
            None => Ok(()),
        },
    }),
    ..Feature::named("strands")
};

/// Each mesh's explicit strands on the GPU, by mesh index (strands mode): planted once per
/// mesh a fur object draws, shared with other scenes through the asset cache.
#[derive(Debug)]
pub struct SceneStrands(pub Vec<Option<Arc<crate::assets::GpuStrands>>>);

impl SceneStrands {
    /// Plants the strands of every fur object's mesh of `s`, bent by the fur's springs at
    /// the pose the mesh was loaded at, as the shells are (`pelt_scene::springs`).
    fn plant(
        r: &crate::renderer::Renderer,
        s: &SceneInputs<'_>,
        prepared: &mut Prepared<'_>,
    ) -> Result<SceneStrands, StateError> {
        let meshes = prepared.meshes;
        let mut out: Vec<Option<Arc<crate::assets::GpuStrands>>> = vec![None; meshes.len()];
        for (o, _) in &s.plan.objects {
            let (Some(f), None) = (o.fur, &out[o.mesh]) else {
                continue;
            };
            let object = o.scene_index;
            let path = &s.scene.objects[object].asset;
            let bent = match f.spring {
                Some(k) => pelt_scene::springs::bent(&meshes[o.mesh], k, f.length, path)
                    .map_err(|source| StateError::of(PlantError::Springs { object, source }))?,
                None => None,
            };
            let planted = prepared
                .assets
                .strands(r, bent.as_ref().unwrap_or(&meshes[o.mesh]))
                .map_err(|source| StateError::of(PlantError::Strands { object, source }))?;
            out[o.mesh] = Some(planted);
        }
        Ok(SceneStrands(out))
    }
}

/// A fur object's strands cannot be planted.
#[derive(Debug, thiserror::Error)]
pub enum PlantError {
    /// Its springs cannot follow the pose the mesh was loaded at.
    #[error("objects[{object}]: {source}")]
    Springs {
        /// The scene object.
        object: usize,
        /// Why.
        #[source]
        source: pelt_io::IoError,
    },
    /// The strand model cannot plant them.
    #[error("objects[{object}]: {source}")]
    Strands {
        /// The scene object.
        object: usize,
        /// Why.
        #[source]
        source: crate::strands::StrandError,
    },
}

/// The strand reference's shadow rays were traced for other lights or objects than a knob
/// change asks for (the CPU meshes they need are not kept).
#[derive(Debug, thiserror::Error)]
#[error(
    "the strands' shadow rays were traced for other lights or objects: prepare the scene again"
)]
pub struct StaleShadows;

/// The strands in the shading pass, lit as fur (strands mode only).
fn shade<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, s: &Shade) -> Result<(), MissingInput> {
    if f.plan.fur.is_empty() || f.plan.mode != crate::plan::Mode::Strands {
        return Ok(());
    }
    let (group, offset) = shading::lighting(f, s.lit).1;
    r.bind(slot::LIGHTING, group, offset);
    draw(f, r, s.pass.name())
}

/// Every fur object's strands. The frame and forward light-array groups must be bound.
pub fn draw<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, pass: &'static str) -> Result<(), MissingInput> {
    let traced = crate::lighting::any(f);
    let bits = if traced {
        Some(
            f.scene
                .need::<TracedShadows>(pass, "the strands' traced shadow bits")?,
        )
    } else {
        None
    };
    r.pipeline(lights::suns_for_view(f, pipeline(traced)));
    let planted = f
        .scene
        .need::<SceneStrands>(pass, "the scene's strands on the GPU")?;
    for &k in &f.plan.fur {
        let o = &f.plan.objects[k];
        let strands = planted
            .0
            .get(o.mesh)
            .and_then(|s| s.as_deref())
            .ok_or_else(|| MissingInput {
                pass,
                what: format!("the strands of objects[{}] on the GPU", o.scene_index),
            })?;
        if strands.count == 0 {
            continue;
        }
        f.bind_object(r, k);
        r.push(Step::Vertices(
            crate::draw::vertex_slot::INSTANCES,
            &strands.roots,
        ));
        if let Some(t) = bits {
            let b = t.bits.get(&o.scene_index).ok_or_else(|| MissingInput {
                pass,
                what: format!("the shadow bits of objects[{}]'s strands", o.scene_index),
            })?;
            r.push(Step::Vertices(crate::draw::vertex_slot::TRACED, b));
        }
        r.push(Step::Draw(0..3 * STRAND_SEGMENTS, 0..strands.count));
    }
    Ok(())
}
