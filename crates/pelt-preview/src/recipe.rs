//! A pass as data before it is encoded (kajiya's passes as functions from inputs to outputs;
//! re_renderer's per-frame draw data): its attachments, with their formats, and the steps it
//! takes (pipeline, bind groups by named slot, buffers, scissor, draws). Feature modules build
//! recipes; the frame compiles every pipeline the recipes name, then encodes them. A pipeline
//! is asked for by its descriptor only: its key takes the formats from the recipe's own
//! attachments, so what is prepared is exactly what is drawn.

use std::ops::Range;

use crate::pass::Pass;
use crate::renderer::{
    ComputeDesc, MAX_COLOR_TARGETS, PipelineDesc, PipelineError, PipelineKey, Renderer,
};

/// A colour attachment.
#[derive(Debug, Clone, Copy)]
pub struct Color<'a> {
    /// The view written.
    pub view: &'a wgpu::TextureView,
    /// Its format (goes into the pipeline keys).
    pub format: wgpu::TextureFormat,
    /// Clear or keep.
    pub load: wgpu::LoadOp<wgpu::Color>,
}

/// A depth attachment.
#[derive(Debug, Clone, Copy)]
pub struct Depth<'a> {
    /// The view.
    pub view: &'a wgpu::TextureView,
    /// Its format.
    pub format: wgpu::TextureFormat,
    /// Clear or keep.
    pub load: wgpu::LoadOp<f32>,
}

/// One thing a pass does.
#[derive(Debug, Clone)]
pub enum Step<'a> {
    /// Switch pipeline.
    Pipeline(PipelineKey),
    /// Bind a group at a slot, with its dynamic offset if it has one.
    Bind {
        /// The slot (a named constant of the feature).
        slot: u32,
        /// The group.
        group: &'a wgpu::BindGroup,
        /// Its dynamic offset.
        offset: Option<u32>,
    },
    /// A vertex buffer at a slot.
    Vertices(u32, &'a wgpu::Buffer),
    /// The index buffer (u32 indices).
    Indices(&'a wgpu::Buffer),
    /// Scissor rectangle `[x0, y0, x1, y1)`.
    Scissor([u32; 4]),
    /// Non-indexed draw.
    Draw(Range<u32>, Range<u32>),
    /// Indexed draw.
    DrawIndexed(Range<u32>, Range<u32>),
    /// Switch to a compute pipeline (compute recipes).
    Compute(ComputeDesc),
    /// Dispatch workgroups (compute recipes).
    Dispatch([u32; 3]),
}

/// What a pass asks of the GPU, counted from its steps after redundant state changes are
/// dropped (what [`Recipe::encode`] submits): the profile's per-pass columns.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Counts {
    /// Draw calls.
    pub draws: u32,
    /// Compute dispatches.
    pub dispatches: u32,
    /// Pipeline changes.
    pub pipelines: u32,
    /// Bind-group changes.
    pub binds: u32,
    /// Vertex- and index-buffer changes.
    pub buffers: u32,
    /// Triangles submitted (every pipeline draws triangle lists).
    pub triangles: u64,
    /// Vertices fetched: indices (or vertices) drawn, times instances.
    pub vertices: u64,
    /// Vertex-buffer bytes those fetches read (each draw's vertices times its pipeline's
    /// per-vertex stride; storage-buffer reads are not counted).
    pub vertex_bytes: u64,
}

impl std::ops::AddAssign for Counts {
    fn add_assign(&mut self, o: Counts) {
        self.draws += o.draws;
        self.dispatches += o.dispatches;
        self.pipelines += o.pipelines;
        self.binds += o.binds;
        self.buffers += o.buffers;
        self.triangles += o.triangles;
        self.vertices += o.vertices;
        self.vertex_bytes += o.vertex_bytes;
    }
}

/// The state a pass has set so far, to drop steps that would set it again.
#[derive(Default)]
struct State<'s> {
    pipeline: Option<&'s PipelineKey>,
    compute: Option<ComputeDesc>,
    groups: [Option<(*const wgpu::BindGroup, Option<u32>)>; 8],
    vertices: [Option<*const wgpu::Buffer>; 4],
    indices: Option<*const wgpu::Buffer>,
    scissor: Option<[u32; 4]>,
}

impl<'s> State<'s> {
    /// Whether `step` changes nothing already set (and records what it sets).
    fn redundant(&mut self, step: &'s Step<'_>) -> bool {
        fn same<T: PartialEq + Copy>(slot: Option<&mut Option<T>>, v: T) -> bool {
            match slot {
                Some(s) if *s == Some(v) => true,
                Some(s) => {
                    *s = Some(v);
                    false
                }
                None => false,
            }
        }
        match step {
            Step::Pipeline(k) if self.pipeline == Some(k) => true,
            Step::Pipeline(k) => {
                self.pipeline = Some(k);
                false
            }
            Step::Compute(d) => same(Some(&mut self.compute), *d),
            Step::Bind {
                slot,
                group,
                offset,
            } => same(
                self.groups.get_mut(*slot as usize),
                (std::ptr::from_ref(*group), *offset),
            ),
            Step::Vertices(slot, b) => same(
                self.vertices.get_mut(*slot as usize),
                std::ptr::from_ref(*b),
            ),
            Step::Indices(b) => same(Some(&mut self.indices), std::ptr::from_ref(*b)),
            Step::Scissor(r) => same(Some(&mut self.scissor), *r),
            Step::Draw(..) | Step::DrawIndexed(..) | Step::Dispatch(_) => false,
        }
    }
}

/// What kind of GPU work a recipe is.
#[derive(Debug)]
enum Kind<'a> {
    /// A render pass.
    Render,
    /// A compute pass.
    Compute,
    /// A copy of `count` layers of `src` from layer `from` to `dst` at layer `to`.
    Copy {
        src: &'a wgpu::Texture,
        from: u32,
        dst: &'a wgpu::Texture,
        to: u32,
        count: u32,
        size: (u32, u32),
    },
}

/// The queries a pass writes as it is encoded, each optional: its two timestamps, and one
/// occlusion query (samples that passed its depth test and were written) and one
/// pipeline-statistics query (fragment-shader invocations) around all its draws.
#[derive(Default)]
pub struct Queries<'q> {
    /// Timestamps at its start and end.
    pub timestamps: Option<wgpu::RenderPassTimestampWrites<'q>>,
    /// An occlusion query set and the index to write.
    pub occlusion: Option<(&'q wgpu::QuerySet, u32)>,
    /// A pipeline-statistics query set (fragment-shader invocations) and the index to write.
    pub statistics: Option<(&'q wgpu::QuerySet, u32)>,
}

/// A pass before encoding.
#[derive(Debug)]
pub struct Recipe<'a> {
    /// Which pass (label and timing name).
    pub pass: Pass,
    kind: Kind<'a>,
    colors: Vec<Color<'a>>,
    depth: Option<Depth<'a>>,
    steps: Vec<Step<'a>>,
    /// The current pipeline: its step's index and whether anything has drawn with it, so
    /// varying it per object part needs no search through the steps.
    current: Option<(usize, bool)>,
}

impl<'a> Recipe<'a> {
    /// An empty pass writing `colors` and `depth`.
    pub fn new(pass: Pass, colors: Vec<Color<'a>>, depth: Option<Depth<'a>>) -> Recipe<'a> {
        debug_assert!(colors.len() <= MAX_COLOR_TARGETS);
        Recipe {
            pass,
            kind: Kind::Render,
            colors,
            depth,
            steps: Vec::new(),
            current: None,
        }
    }

    /// An empty compute pass.
    pub fn compute(pass: Pass) -> Recipe<'a> {
        Recipe {
            pass,
            kind: Kind::Compute,
            colors: Vec::new(),
            depth: None,
            steps: Vec::new(),
            current: None,
        }
    }

    /// A copy of `count` layers (mip 0, `size`) of `src` from layer `from` into `dst` at
    /// layer `to`.
    pub fn copy(
        pass: Pass,
        src: &'a wgpu::Texture,
        from: u32,
        dst: &'a wgpu::Texture,
        to: u32,
        count: u32,
        size: (u32, u32),
    ) -> Recipe<'a> {
        Recipe {
            pass,
            kind: Kind::Copy {
                src,
                from,
                dst,
                to,
                count,
                size,
            },
            colors: Vec::new(),
            depth: None,
            steps: Vec::new(),
            current: None,
        }
    }

    /// The key of `desc` drawn into this pass's attachments.
    pub fn key(&self, desc: PipelineDesc) -> PipelineKey {
        let mut colors = [None; MAX_COLOR_TARGETS];
        for (c, a) in colors.iter_mut().zip(&self.colors) {
            *c = Some(a.format);
        }
        PipelineKey {
            desc,
            colors,
            depth: self.depth.map(|d| d.format),
        }
    }

    /// Switches to the pipeline of `desc`.
    pub fn pipeline(&mut self, desc: PipelineDesc) {
        let key = self.key(desc);
        self.push(Step::Pipeline(key));
    }

    /// Switches to a specialization of the current pipeline: the same descriptor with the
    /// shader's override constant `name` set to `value` (`None`: the shader's default).
    /// Nothing when that is the current pipeline already, or there is none.
    pub fn specialize(&mut self, name: &'static str, value: Option<f64>) {
        self.vary(
            |d| d.constant(name) != value,
            |d| d.with_constant(name, value),
        );
    }

    /// Switches to the current pipeline with faces `cull` culled and front faces wound
    /// `front`. Nothing when that is the current pipeline already, or there is none.
    pub fn sides(&mut self, cull: Option<wgpu::Face>, front: wgpu::FrontFace) {
        self.vary(
            |d| d.spec.cull != cull || d.spec.front_face != front,
            |mut d| {
                d.spec.cull = cull;
                d.spec.front_face = front;
                d
            },
        );
    }

    /// Switches to the current pipeline with front faces wound `front`, where it culls (a
    /// pipeline that culls nothing draws alike either way, so it is kept).
    pub fn front(&mut self, front: wgpu::FrontFace) {
        self.vary(
            |d| d.spec.cull.is_some() && d.spec.front_face != front,
            |mut d| {
                d.spec.front_face = front;
                d
            },
        );
    }

    /// Switches to `change` of the current pipeline's descriptor where `differs` says it is
    /// not that already. Drawing code asks once per object part: it compares before cloning.
    fn vary(
        &mut self,
        differs: impl Fn(&PipelineDesc) -> bool,
        change: impl FnOnce(PipelineDesc) -> PipelineDesc,
    ) {
        let Some((at, drawn)) = self.current else {
            return;
        };
        let Step::Pipeline(current) = &self.steps[at] else {
            return;
        };
        if !differs(&current.desc) {
            return;
        }
        let mut key = current.clone();
        key.desc = change(key.desc);
        // A pipeline nothing has drawn with yet is replaced, not followed: it is neither set
        // nor compiled for nothing.
        if drawn {
            self.push(Step::Pipeline(key));
        } else {
            self.steps[at] = Step::Pipeline(key);
        }
    }

    /// Binds `group` at `slot`.
    pub fn bind(&mut self, slot: u32, group: &'a wgpu::BindGroup, offset: Option<u32>) {
        self.push(Step::Bind {
            slot,
            group,
            offset,
        });
    }

    /// Any other step.
    pub fn push(&mut self, step: Step<'a>) {
        match (&step, &mut self.current) {
            (Step::Pipeline(_), c) => *c = Some((self.steps.len(), false)),
            (Step::Draw(..) | Step::DrawIndexed(..), Some((_, drawn))) => *drawn = true,
            _ => {}
        }
        self.steps.push(step);
    }

    /// Every pipeline key the pass uses.
    pub fn keys(&self) -> impl Iterator<Item = &PipelineKey> {
        self.steps.iter().filter_map(|s| match s {
            Step::Pipeline(k) => Some(k),
            _ => None,
        })
    }

    /// The steps that change something: a pipeline, bind group, buffer or scissor already
    /// set is not set again.
    fn effective(&self) -> impl Iterator<Item = &Step<'a>> {
        let mut state = State::default();
        self.steps.iter().filter(move |s| !state.redundant(s))
    }

    /// What the pass asks of the GPU.
    pub fn counts(&self) -> Counts {
        let mut c = Counts::default();
        let mut stride = 0u64;
        let draw = |c: &mut Counts, n: &Range<u32>, i: &Range<u32>, stride: u64| {
            let v = u64::from(n.len() as u32) * u64::from(i.len() as u32);
            c.draws += 1;
            c.vertices += v;
            c.triangles += v / 3;
            c.vertex_bytes += v * stride;
        };
        for s in self.effective() {
            match s {
                Step::Pipeline(k) => {
                    c.pipelines += 1;
                    stride = k
                        .desc
                        .spec
                        .vertex_buffers
                        .iter()
                        .filter(|b| b.step_mode == wgpu::VertexStepMode::Vertex)
                        .map(|b| b.array_stride)
                        .sum();
                }
                Step::Compute(_) => c.pipelines += 1,
                Step::Bind { .. } => c.binds += 1,
                Step::Vertices(..) | Step::Indices(_) => c.buffers += 1,
                Step::Scissor(_) => {}
                Step::Draw(n, i) | Step::DrawIndexed(n, i) => draw(&mut c, n, i, stride),
                Step::Dispatch(_) => c.dispatches += 1,
            }
        }
        c
    }

    /// Encodes the pass (its render pipelines must be prepared; compute pipelines are made
    /// on first use), writing the queries `q` asks for. A copy has no pass of its own: it
    /// times an empty compute pass before it, so every recipe writes its two timestamps.
    pub fn encode(
        &self,
        r: &Renderer,
        enc: &mut wgpu::CommandEncoder,
        q: Queries<'_>,
    ) -> Result<(), PipelineError> {
        let timestamps = q.timestamps;
        let compute_ts = timestamps
            .as_ref()
            .map(|t| wgpu::ComputePassTimestampWrites {
                query_set: t.query_set,
                beginning_of_pass_write_index: t.beginning_of_pass_write_index,
                end_of_pass_write_index: t.end_of_pass_write_index,
            });
        match &self.kind {
            Kind::Render => {}
            Kind::Compute => return self.encode_compute(r, enc, compute_ts),
            Kind::Copy {
                src,
                from,
                dst,
                to,
                count,
                size,
            } => {
                if compute_ts.is_some() {
                    drop(enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some(self.pass.name()),
                        timestamp_writes: compute_ts,
                    }));
                }
                let at = |texture, z| wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d { x: 0, y: 0, z },
                    aspect: wgpu::TextureAspect::All,
                };
                enc.copy_texture_to_texture(
                    at(src, *from),
                    at(dst, *to),
                    wgpu::Extent3d {
                        width: size.0,
                        height: size.1,
                        depth_or_array_layers: *count,
                    },
                );
                return Ok(());
            }
        }
        let colors: Vec<Option<wgpu::RenderPassColorAttachment<'_>>> = self
            .colors
            .iter()
            .map(|c| {
                Some(wgpu::RenderPassColorAttachment {
                    view: c.view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: c.load,
                        store: wgpu::StoreOp::Store,
                    },
                })
            })
            .collect();
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(self.pass.name()),
            color_attachments: &colors,
            depth_stencil_attachment: self.depth.map(|d| wgpu::RenderPassDepthStencilAttachment {
                view: d.view,
                depth_ops: Some(wgpu::Operations {
                    load: d.load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: q.occlusion.map(|(set, _)| set),
            multiview_mask: None,
        });
        if let Some((_, i)) = q.occlusion {
            pass.begin_occlusion_query(i);
        }
        if let Some((set, i)) = q.statistics {
            pass.begin_pipeline_statistics_query(set, i);
        }
        for s in self.effective() {
            match s {
                Step::Pipeline(k) => pass.set_pipeline(&r.pipeline(k)?),
                Step::Bind {
                    slot,
                    group,
                    offset,
                } => pass.set_bind_group(*slot, *group, offset.as_slice()),
                Step::Vertices(slot, b) => pass.set_vertex_buffer(*slot, b.slice(..)),
                Step::Indices(b) => pass.set_index_buffer(b.slice(..), wgpu::IndexFormat::Uint32),
                Step::Scissor([x0, y0, x1, y1]) => {
                    pass.set_scissor_rect(*x0, *y0, x1 - x0, y1 - y0)
                }
                Step::Draw(v, i) => pass.draw(v.clone(), i.clone()),
                Step::DrawIndexed(v, i) => pass.draw_indexed(v.clone(), 0, i.clone()),
                Step::Compute(_) | Step::Dispatch(_) => {}
            }
        }
        if q.statistics.is_some() {
            pass.end_pipeline_statistics_query();
        }
        if q.occlusion.is_some() {
            pass.end_occlusion_query();
        }
        Ok(())
    }

    /// Whether the pass is a render pass (the kind whose draws [`Queries`] count).
    pub fn renders(&self) -> bool {
        matches!(self.kind, Kind::Render)
    }

    /// The pass's steps, to change in place (experiments and negative controls: the same
    /// pass drawn with another depth test, specialization or scissor; none added or removed).
    pub fn steps_mut(&mut self) -> &mut [Step<'a>] {
        &mut self.steps
    }

    fn encode_compute(
        &self,
        r: &Renderer,
        enc: &mut wgpu::CommandEncoder,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), PipelineError> {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(self.pass.name()),
            timestamp_writes: timestamps,
        });
        for s in self.effective() {
            match s {
                Step::Compute(desc) => pass.set_pipeline(&r.compute(desc)?),
                Step::Bind {
                    slot,
                    group,
                    offset,
                } => pass.set_bind_group(*slot, *group, offset.as_slice()),
                Step::Dispatch([x, y, z]) => pass.dispatch_workgroups(*x, *y, *z),
                _ => {}
            }
        }
        Ok(())
    }
}
