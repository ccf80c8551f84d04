//! What a feature declares, in one descriptor ([`Feature`]): its name, its render and compute
//! pipelines (descriptors built through the renderer's descriptor → handle cache), the
//! planned passes it builds ([`PassDesc`]: when a plan wants each, what it follows, its
//! `--explain` line; [`planned`] orders them), what it draws inside the passes features share, by [`Phase`] ([`DrawDesc`]), the per-view targets it owns
//! ([`TargetsDesc`]) and the quality knobs it reads ([`KnobDesc`]); and what every pass draws
//! from, one view's [`Frame`]. Part of the renderer's core: the registry of features
//! (`features::registry::FEATURES`) lists one per feature module.

use std::sync::Arc;

use crate::asset::MeshData;
use crate::assets::{GpuMesh, GpuSky, Uploads};
use crate::draw::{MissingInput, slot, vertex_slot};
use crate::frame_data::{FrameData, Res};
use crate::gpu_material::TEXTURED;
use crate::owned::Owned;
use crate::pass::Pass;
use crate::plan::{Plan, ScenePlan};
use crate::poses::ObjectPose;
use crate::recipe::{Recipe, Step};
use crate::renderer::{Blend, ComputeDesc, PipelineDesc};
use crate::scene_state::SceneState;
use crate::shaders::Lighting;
pub use crate::targets::TargetsDesc;
use crate::targets::ViewTargets;
use pelt_scene::knobs::spec::KnobSpec;

/// Builds a planned pass's recipes from the frame.
#[derive(Debug, Clone, Copy)]
pub enum Build {
    /// One render or compute pass.
    One(for<'a> fn(&Frame<'a>) -> Result<Recipe<'a>, MissingInput>),
    /// Several (the distance maps: one per face and layer).
    Many(for<'a> fn(&Frame<'a>) -> Result<Vec<Recipe<'a>>, MissingInput>),
}

impl Build {
    /// The recipes, appended to `out`.
    pub fn run<'a>(self, f: &Frame<'a>, out: &mut Vec<Recipe<'a>>) -> Result<(), MissingInput> {
        match self {
            Build::One(b) => out.push(b(f)?),
            Build::Many(b) => out.extend(b(f)?),
        }
        Ok(())
    }
}

/// Where a pass draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DrawsInto {
    /// The scene colour where the plan blends fur into one (the resolve feature's), else
    /// the output: every pass before the resolve.
    Scene,
    /// The output itself (the resolve).
    Output,
}

/// A planned pass a feature builds: when a plan wants it, what it must follow, what
/// `--explain` says of it, and how its recipes are built.
#[derive(Debug, Clone, Copy)]
pub struct PassDesc {
    /// Its id.
    pub pass: Pass,
    /// Whether a frame of `plan` runs it (a function of the plan's facts: its mode, lights,
    /// fur, mirrors and glass).
    pub wanted: fn(&Plan) -> bool,
    /// The passes it must follow when they run too (what it reads that they write).
    pub after: &'static [Pass],
    /// Its line in `--explain` (after its name).
    pub explain: fn(&Plan) -> String,
    /// Where it draws.
    pub into: DrawsInto,
    /// Whether it draws at the L-buffer's size (its cost scales with the L-buffer scale:
    /// the frame budget's split of a frame's time).
    pub at_lbuffer: bool,
    /// Whether what it draws outlives the frame (the distance maps depend on the scene, not
    /// the camera): the frame then skips it while it is fresh, unless asked to draw every
    /// pass.
    pub cached: Option<Cached>,
    /// Its recipes.
    pub build: Build,
}

impl PassDesc {
    /// A pass drawing into the scene colour at the output's size, following nothing.
    pub const fn new(
        pass: Pass,
        build: Build,
        wanted: fn(&Plan) -> bool,
        explain: fn(&Plan) -> String,
    ) -> PassDesc {
        PassDesc {
            pass,
            wanted,
            after: &[],
            explain,
            into: DrawsInto::Scene,
            at_lbuffer: false,
            cached: None,
            build,
        }
    }
}

/// The passes of `features` that `plan` wants, in order: each after every wanted pass it
/// must follow, otherwise in the order they are registered. (Were the `after` lists ever to
/// form a circle, the rest would keep registry order; the registry's tests rule that out.)
pub fn planned<'f>(features: &'f [Feature], plan: &Plan) -> Vec<&'f PassDesc> {
    let mut left: Vec<&PassDesc> = features
        .iter()
        .flat_map(|f| f.passes)
        .filter(|p| (p.wanted)(plan))
        .collect();
    let mut out = Vec::with_capacity(left.len());
    while !left.is_empty() {
        let waits = |p: &PassDesc| p.after.iter().any(|a| left.iter().any(|q| q.pass == *a));
        let next = left.iter().position(|p| !waits(p)).unwrap_or(0);
        out.push(left.remove(next));
    }
    out
}

/// How a pass whose output outlives the frame tracks it.
#[derive(Debug, Clone, Copy)]
pub struct Cached {
    /// Whether the frame's copy is still valid.
    pub fresh: fn(&Frame<'_>) -> bool,
    /// Records that a submitted frame drew it.
    pub drawn: fn(&Frame<'_>),
}

/// One feature of the renderer, as registered.
#[derive(Debug, Clone, Copy)]
pub struct Feature {
    /// Its name (the module's).
    pub name: &'static str,
    /// Every render pipeline it may draw, each variant once.
    pub pipelines: fn() -> Vec<PipelineDesc>,
    /// Its compute pipelines.
    pub compute: &'static [ComputeDesc],
    /// The planned passes it builds.
    pub passes: &'static [PassDesc],
    /// What it draws inside the passes features share (the G-buffer pass, the shading
    /// pass), by phase.
    pub draws: &'static [DrawDesc],
    /// The per-view targets it owns, made with the view's targets.
    pub targets: Option<TargetsDesc>,
    /// The state it keeps per scene.
    pub scene: Option<SceneState>,
    /// What it draws of mesh `k` of a scene plan beside its vertices and materials (the
    /// asset cache uploads the union of every feature's).
    pub uploads: Option<fn(&ScenePlan, usize, &MeshData) -> Uploads>,
    /// The quality knobs it reads (what `pelt sweep` turns).
    pub knobs: &'static [KnobDesc],
    /// The lighting inputs it fills ([`crate::lighting`]).
    pub lighting: &'static [LightingInput],
    /// How it draws into the shadow layers after the shadow pass, where it does
    /// ([`crate::lighting::layers_kept`]).
    pub layer_writer: Option<LayerWriter>,
}

/// A quality knob a feature reads: a flag of `pelt render` and `pelt view`, a scene-file or
/// bake setting, and a row of `pelt sweep`'s time-against-error table. What it is (name,
/// range, default, reference, whether it re-bakes) is its spec's, declared once in
/// [`pelt_scene::knobs::spec`]; a feature names it with [`KnobDesc::of`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KnobDesc {
    /// The knob.
    pub spec: &'static KnobSpec,
}

impl KnobDesc {
    /// The knob `spec`.
    pub const fn of(spec: &'static KnobSpec) -> KnobDesc {
        KnobDesc { spec }
    }

    /// Its name (the flag without dashes).
    pub fn name(&self) -> &'static str {
        self.spec.name
    }

    /// The values it takes, in words.
    pub fn range(&self) -> String {
        self.spec.range.words()
    }

    /// The converged reference `pelt sweep` measures it against.
    pub fn reference(&self) -> Reference {
        self.spec.reference
    }

    /// Whether a new value needs the asset baked again (fur textures, comb storage).
    pub fn rebakes(&self) -> bool {
        self.spec.rebakes
    }
}

/// What a knob's error is measured against (declared with the knob's spec).
pub use pelt_scene::knobs::spec::Reference;

impl Feature {
    /// A feature with no pipelines, passes, draws or targets yet.
    pub const fn named(name: &'static str) -> Feature {
        Feature {
            name,
            pipelines: Vec::new,
            compute: &[],
            passes: &[],
            draws: &[],
            targets: None,
            scene: None,
            uploads: None,
            knobs: &[],
            lighting: &[],
            layer_writer: None,
        }
    }
}

/// What a contributor binds.
#[derive(Debug, Clone, Copy)]
pub enum Resource<'a> {
    /// A texture view.
    Texture(&'a wgpu::TextureView),
    /// A whole buffer.
    Buffer(&'a wgpu::Buffer),
}

/// One binding a feature fills from its per-scene state.
#[derive(Debug, Clone, Copy)]
pub struct LightingInput {
    /// The binding ([`crate::lighting::binding`]).
    pub binding: u32,
    /// What it is, for errors.
    pub what: &'static str,
    /// The resource for a scene's state and the identity of what holds it
    /// ([`crate::lighting::next_id`]: a new holder makes the group again); `None` where the
    /// scene has none.
    pub resource: fn(&Owned) -> Option<(Resource<'_>, u64)>,
}

/// A feature that draws into the shadow layers after the shadow pass.
#[derive(Debug, Clone, Copy)]
pub struct LayerWriter {
    /// Whether what it draws into them is unchanged since a frame last drew it.
    pub unchanged: fn(&Frame<'_>) -> bool,
}

/// A feature's draw inside a pass that several features draw into.
#[derive(Debug, Clone, Copy)]
pub struct DrawDesc {
    /// The pass it draws into.
    pub into: Shared,
    /// When it runs there.
    pub phase: Phase,
    /// What it records (nothing when the frame has nothing of it to draw).
    pub draw: for<'a> fn(&Frame<'a>, &mut Recipe<'a>, &Shade) -> Result<(), MissingInput>,
}

/// When a draw runs within the shading pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Phase {
    /// Opaque objects, front to back.
    Opaque,
    /// Mirrors and glass, through the distance maps.
    Mirrors,
    /// Each fur object's base mesh (the skin under the shells).
    FurBase,
    /// The sky, behind everything drawn so far.
    Sky,
    /// The fur's shells and fins (or its strands), far to near.
    FurLayers,
    /// Alpha-blended objects, back to front.
    Transparent,
}

impl Phase {
    /// Every phase, in the order they run.
    pub const ALL: [Phase; 6] = [
        Phase::Opaque,
        Phase::Mirrors,
        Phase::FurBase,
        Phase::Sky,
        Phase::FurLayers,
        Phase::Transparent,
    ];
}

/// A pass several features draw into, phase by phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shared {
    /// The G-buffer pass at L-buffer resolution (Kircher & Lawrance §2.1).
    Geometry,
    /// The shading pass at output resolution (material or forward).
    Shading,
}

/// What the draws of one shared pass share.
pub struct Shade {
    /// Which shared pass.
    pub shared: Shared,
    /// The pass (geometry, material, forward, or the OIT composite's alpha objects).
    pub pass: Pass,
    /// How ordinary objects and fur are lit.
    pub lit: Lighting,
    /// The pipeline ordinary objects are drawn with (the material or the forward shader's,
    /// as the view needs it).
    pub object: Box<dyn Fn(Blend) -> PipelineDesc>,
}

/// The output colour a frame renders into.
#[derive(Debug, Clone, Copy)]
pub struct Output<'a> {
    /// The view (a window's surface texture, or the view's own colour target).
    pub view: &'a wgpu::TextureView,
    /// Its format.
    pub format: wgpu::TextureFormat,
}

/// Which faces an object draw keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sides {
    /// Both faces of every triangle (blended layers, whose backs show through, and draws
    /// that read no material).
    Both,
    /// As each part's material says: single-sided materials (glTF's default) cull back
    /// faces, which an opaque closed surface hides anyway; double-sided ones keep both.
    Material,
}

/// Everything one frame of one view draws from.
#[derive(Debug, Clone, Copy)]
pub struct Frame<'a> {
    /// The CPU decisions.
    pub plan: &'a Plan,
    /// The registered features (their draws make up the shading pass).
    pub features: &'static [Feature],
    /// The meshes, by the plan's mesh index (None: not uploaded, no object uses it).
    pub meshes: &'a [Option<Arc<GpuMesh>>],
    /// Each scene object's posed copy of its mesh, by scene index (None: not skinned).
    pub poses: &'a [Option<ObjectPose>],
    /// The cube-map sky, when the scene has one.
    pub sky: Option<&'a GpuSky>,
    /// The view's targets.
    pub targets: &'a ViewTargets,
    /// The frame's uniforms.
    pub data: &'a FrameData,
    /// Where the image goes.
    pub output: Output<'a>,
    /// Which view of the frame's uniforms this is (0 for a single view).
    pub view: usize,
    /// State the scene's features own ([`Owned`]: the distance maps of mirrors and glass).
    pub scene: &'a Owned,
}

impl<'a> Frame<'a> {
    /// Object `k`'s mesh (its own posed copy where it has one).
    pub fn mesh(&self, pass: &'static str, k: usize) -> Result<&'a GpuMesh, MissingInput> {
        let o = &self.plan.objects[k];
        self.object_mesh(pass, o.scene_index, o.mesh)
    }

    /// The mesh scene object `scene_index` draws: its posed copy where it has one, else the
    /// shared mesh `mesh`.
    pub fn object_mesh(
        &self,
        pass: &'static str,
        scene_index: usize,
        mesh: usize,
    ) -> Result<&'a GpuMesh, MissingInput> {
        if let Some(Some(p)) = self.poses.get(scene_index) {
            return Ok(&p.mesh);
        }
        self.meshes
            .get(mesh)
            .and_then(|m| m.as_deref())
            .ok_or_else(|| MissingInput {
                pass,
                what: format!("the mesh of objects[{scene_index}] on the GPU"),
            })
    }

    /// Binds object `k`'s uniforms.
    pub fn bind_object(&self, recipe: &mut Recipe<'a>, k: usize) {
        recipe.bind(
            slot::OBJECT,
            self.data.objects(),
            Some(self.data.object_offset(self.view, k)),
        );
    }

    /// How object `k`'s front faces wind on screen: a mirroring transform (a negative
    /// determinant, glTF's rule) turns counter-clockwise triangles clockwise.
    pub fn front_face(&self, k: usize) -> wgpu::FrontFace {
        if self.plan.objects[k].model.determinant() < 0.0 {
            wgpu::FrontFace::Cw
        } else {
            wgpu::FrontFace::Ccw
        }
    }

    /// Binds fur object `k`'s object constants, mesh, fur vertices and indices (front faces
    /// wound as its transform makes them); its mesh and fur for [`Frame::draw_fur_parts`].
    pub fn bind_fur(
        &self,
        r: &mut Recipe<'a>,
        pass: &'static str,
        k: usize,
    ) -> Result<(&'a GpuMesh, &'a crate::assets::GpuFur), MissingInput> {
        let mesh = self.mesh(pass, k)?;
        let fur = mesh.fur.as_ref().ok_or_else(|| MissingInput {
            pass,
            what: format!(
                "the fur of objects[{}] on the GPU",
                self.plan.objects[k].scene_index
            ),
        })?;
        self.bind_object(r, k);
        r.front(self.front_face(k));
        r.push(Step::Vertices(vertex_slot::MESH, &mesh.vertices));
        r.push(Step::Vertices(vertex_slot::FUR, &fur.vertices));
        r.push(Step::Indices(&mesh.indices));
        Ok((mesh, fur))
    }

    /// Draws `mesh` part by part, each with its material's fur textures, `instances` shells.
    pub fn draw_fur_parts(
        r: &mut Recipe<'a>,
        mesh: &'a GpuMesh,
        fur: &'a crate::assets::GpuFur,
        instances: std::ops::Range<u32>,
    ) {
        for p in &mesh.parts {
            r.bind(slot::FUR, &fur.textures[p.material], None);
            r.push(Step::DrawIndexed(p.indices.clone(), instances.clone()));
        }
    }

    /// Binds this view's frame constants at `res` (at the object passes' frame slot).
    pub fn bind_frame(&self, recipe: &mut Recipe<'a>, res: Res) {
        recipe.bind(
            slot::FRAME,
            self.data.frame(),
            Some(self.data.frame_offset(self.view, res)),
        );
    }

    /// Draws each object of `order` with the current pipeline, part by part, binding each
    /// part's material at `material` where the shader reads one (None: it reads none).
    /// `sides`: whether single-sided materials cull their back faces.
    pub fn draw_objects(
        &self,
        recipe: &mut Recipe<'a>,
        pass: &'static str,
        material: Option<u32>,
        sides: Sides,
        order: &[usize],
    ) -> Result<(), MissingInput> {
        for &k in order {
            let mesh = self.mesh(pass, k)?;
            self.bind_object(recipe, k);
            recipe.push(Step::Vertices(vertex_slot::MESH, &mesh.vertices));
            recipe.push(Step::Indices(&mesh.indices));
            let front = self.front_face(k);
            let Some(at) = material else {
                recipe.sides(None, front);
                recipe.push(Step::DrawIndexed(0..mesh.count, 0..1));
                continue;
            };
            for p in &mesh.parts {
                let m = &mesh.materials[p.material];
                recipe.specialize(TEXTURED, (!m.textured).then_some(0.0));
                let single = sides == Sides::Material && !m.double_sided;
                recipe.sides(single.then_some(wgpu::Face::Back), front);
                recipe.bind(at, &m.group, None);
                recipe.push(Step::DrawIndexed(p.indices.clone(), 0..1));
            }
        }
        Ok(())
    }
}
