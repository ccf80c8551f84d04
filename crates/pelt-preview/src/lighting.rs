//! The lighting inputs, owned by the core: one bind group that every lighting pass reads at
//! [`SLOT`] (the light pass per L-buffer pixel, forward shading, the fur's forward lighting,
//! the OIT layers; Kircher & Lawrance §4: "any lighting/shadow algorithm that is one to one in
//! terms of L-buffer pixels"), its bindings declared here by role and filled by the features
//! that contribute them ([`crate::feature::LightingInput`], registered in each feature's descriptor): the
//! shadow maps and how to read them, the fur's deep opacity layers and theirs. A binding no contributor
//! fills for a scene gets a stand-in (a 1×1 layer, zeroed constants), and the readers'
//! pipeline constants compile its lookup out ([`for_view`]).
//!
//! The WGSL side is shaders/lighting_inputs.wgsl (`pelt::lighting_inputs`), which declares
//! the same bindings; the functions that read them (shaders/shadows.wgsl) import them from
//! there, and the lighting passes import those.
//!
//! The shadow maps' layers are drawn by more than one feature: the shadow maps draw the
//! opaque casters' distances, and the deep opacity maps the nearest fur's into the same
//! layers after them. The shadow maps publish the layers ([`ShadowLayers`]); a feature that
//! draws into them declares a [`crate::feature::LayerWriter`], and the layers are kept from one frame to the
//! next only while the casters and every writer's draws are unchanged ([`layers_kept`]).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use glam::Mat4;

use crate::draw::MissingInput;
use crate::feature::{Feature, Frame, Resource};
use crate::layout::{self, D2_ARRAY, LayoutDesc, UNFILTERABLE, seen_by};
use crate::owned::Owned;
use crate::recipe::Recipe;
use crate::renderer::{PipelineDesc, Renderer};

/// The lighting inputs' group in every pass that reads them (`@group(4)`).
pub const SLOT: u32 = 4;

/// The bindings, by role.
pub mod binding {
    /// The shadow maps: every layer of every shadow-casting light's maps (a 2D array).
    pub const SHADOW_MAPS: u32 = 0;
    /// How to read them (a uniform of [`super::SHADOW_READ_SIZE`] bytes).
    pub const SHADOW_READ: u32 = 1;
    /// The fur's deep opacity layers, one per layer of the shadow maps (a 2D array).
    pub const FUR_OPACITY: u32 = 2;
    /// How to read them (a uniform of [`super::FUR_READ_SIZE`] bytes).
    pub const FUR_READ: u32 = 3;
    /// Every binding.
    pub const ALL: [u32; 4] = [SHADOW_MAPS, SHADOW_READ, FUR_OPACITY, FUR_READ];
}

/// The size of the shadow maps' read constants (`ShadowRead` in shaders/lighting_inputs.wgsl).
pub const SHADOW_READ_SIZE: usize = 16 + 8 * 80;

/// The size of the opacity layers' read constants (`FurRead` in shaders/lighting_inputs.wgsl).
pub const FUR_READ_SIZE: usize = 16;

/// The group's layout.
pub const LAYOUT: LayoutDesc = LayoutDesc {
    label: "lighting inputs",
    entries: &[
        seen_by(
            wgpu::ShaderStages::FRAGMENT,
            layout::texture(binding::SHADOW_MAPS, UNFILTERABLE, D2_ARRAY),
        ),
        seen_by(
            wgpu::ShaderStages::FRAGMENT,
            layout::uniform(binding::SHADOW_READ, SHADOW_READ_SIZE, false),
        ),
        seen_by(
            wgpu::ShaderStages::FRAGMENT,
            layout::texture(binding::FUR_OPACITY, UNFILTERABLE, D2_ARRAY),
        ),
        seen_by(
            wgpu::ShaderStages::FRAGMENT,
            layout::uniform(binding::FUR_READ, FUR_READ_SIZE, false),
        ),
    ],
};

static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// A fresh identity for a contributor's resource holder.
pub fn next_id() -> u64 {
    NEXT_ID.fetch_add(1, Ordering::Relaxed)
}

/// A scene's lighting inputs: the group and which bindings a contributor filled.
#[derive(Debug)]
pub struct LightingInputs {
    /// The group, bound at [`SLOT`].
    pub group: wgpu::BindGroup,
    /// Each binding's holder ([`next_id`]; 0: a stand-in).
    made_from: [u64; 4],
}

impl LightingInputs {
    /// Gathers `features`' contributions from a scene's state `owned` into its group, made
    /// again only where a holder changed.
    pub fn gather(r: &Renderer, features: &[Feature], owned: &mut Owned) {
        let find = |b: u32| {
            features
                .iter()
                .flat_map(|f| f.lighting)
                .find(|i| i.binding == b)
        };
        let ids = binding::ALL.map(|b| {
            find(b)
                .and_then(|i| (i.resource)(owned))
                .map_or(0, |(_, id)| id)
        });
        if owned
            .get::<LightingInputs>()
            .is_some_and(|l| l.made_from == ids)
        {
            return;
        }
        let stand = StandIns::new(r);
        let resources =
            binding::ALL.map(
                |b| match find(b).and_then(|i| (i.resource)(owned)).map(|x| x.0) {
                    Some(Resource::Texture(v)) => wgpu::BindingResource::TextureView(v),
                    Some(Resource::Buffer(b)) => b.as_entire_binding(),
                    None if b == binding::SHADOW_READ => stand.read.as_entire_binding(),
                    None if b == binding::FUR_READ => stand.fur_read.as_entire_binding(),
                    None => wgpu::BindingResource::TextureView(&stand.layer),
                },
            );
        let group = r.group("lighting inputs", &LAYOUT, &resources);
        owned.insert(LightingInputs {
            group,
            made_from: ids,
        });
    }

    /// Whether a contributor filled `binding` (not a stand-in).
    pub fn filled(&self, binding: u32) -> bool {
        self.made_from[binding as usize] != 0
    }
}

/// What an unfilled binding holds.
struct StandIns {
    layer: wgpu::TextureView,
    read: wgpu::Buffer,
    fur_read: wgpu::Buffer,
}

impl StandIns {
    fn new(r: &Renderer) -> StandIns {
        let layer = crate::targets::LayeredTarget::new(
            r,
            "lighting input stand-in",
            (1, 1),
            1,
            1,
            wgpu::TextureFormat::Rgba16Float,
        );
        let read = r.buffer(
            "lighting input stand-in",
            SHADOW_READ_SIZE as u64,
            wgpu::BufferUsages::UNIFORM,
        );
        let fur_read = r.buffer(
            "lighting input stand-in",
            FUR_READ_SIZE as u64,
            wgpu::BufferUsages::UNIFORM,
        );
        StandIns {
            layer: layer.sampled,
            read,
            fur_read,
        }
    }
}

/// The readers' override: whether any light of the view casts shadows.
pub const SHADOWS: &str = "SHADOWS";

/// The readers' override: whether the fur casts by its coverage too.
pub const FUR_SHADOWS: &str = "FUR_SHADOWS";

/// `desc` for views without a shadow-casting light: the lookup compiled out.
pub fn unshadowed(desc: PipelineDesc) -> PipelineDesc {
    desc.with_constant(SHADOWS, Some(0.0))
        .with_constant(FUR_SHADOWS, Some(0.0))
}

/// `desc` for views whose fur casts no coverage: the opacity layers' lookup compiled out.
pub fn without_fur(desc: PipelineDesc) -> PipelineDesc {
    desc.with_constant(FUR_SHADOWS, Some(0.0))
}

/// `descs` and their [`without_fur`] and [`unshadowed`] variants.
pub fn with_unshadowed(descs: Vec<PipelineDesc>) -> Vec<PipelineDesc> {
    descs
        .into_iter()
        .flat_map(|d| [d.clone(), without_fur(d.clone()), unshadowed(d)])
        .collect()
}

/// Whether any light of the view casts shadows.
pub fn any(f: &Frame<'_>) -> bool {
    f.plan.lights.iter().any(|l| l.shadow.is_some())
}

/// Whether the view's fur casts by its coverage (its scene's opacity layers are filled).
pub fn fur_casts(f: &Frame<'_>) -> bool {
    f.scene
        .get::<LightingInputs>()
        .is_some_and(|l| l.filled(binding::FUR_OPACITY))
}

/// `desc` as the view needs it: [`unshadowed`] unless a light of the view casts shadows,
/// [`without_fur`] unless its fur casts too.
pub fn for_view(f: &Frame<'_>, desc: PipelineDesc) -> PipelineDesc {
    match (any(f), fur_casts(f)) {
        (false, _) => unshadowed(desc),
        (true, false) => without_fur(desc),
        (true, true) => desc,
    }
}

/// Binds the view's lighting inputs at [`SLOT`] for `pass`.
pub fn bind<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, pass: &'static str) -> Result<(), MissingInput> {
    let l: &LightingInputs = f.scene.need(pass, "the scene's lighting inputs")?;
    r.bind(SLOT, &l.group, None);
    Ok(())
}

/// One layer's light frame: world to the light's face (or map), as the passes that draw from
/// the light see it.
#[derive(Debug, Clone, Copy)]
pub struct LightFrame {
    /// World to the face's view space.
    pub view: Mat4,
    /// The face's projection.
    pub proj: Mat4,
    /// The near plane's distance (where distances along the axis start).
    pub near: f32,
    /// The layer of the maps.
    pub layer: u32,
    /// Whether its distances run along its axis from the near plane (a light's one map) rather
    /// than out from the light (a cube's face).
    pub along_axis: bool,
}

/// The shadow maps' layers as the features that draw into them after the shadow pass see
/// them, published by the shadow maps for each scene.
#[derive(Debug)]
pub struct ShadowLayers {
    /// Their holder ([`next_id`]): a new one means new layers.
    pub id: u64,
    /// Each layer's side in texels.
    pub size: u32,
    /// The layers of the maps' target.
    pub count: u32,
    /// The whole target as a 2D array.
    pub sampled: wgpu::TextureView,
    /// The layers drawn: each one's view and light frame.
    pub drawn: Vec<(wgpu::TextureView, LightFrame)>,
    /// Whether a frame has drawn them since their casters or lights last changed.
    pub fresh: AtomicBool,
}

/// Whether frame `f` keeps its scene's shadow layers as drawn: their casters and lights
/// unchanged, no caster posed (its vertices change each frame), and every writer's draws
/// unchanged. Otherwise the shadow pass and every writer draw them again.
pub fn layers_kept(f: &Frame<'_>) -> bool {
    f.scene
        .get::<ShadowLayers>()
        .is_some_and(|l| l.fresh.load(Ordering::Relaxed))
        && f.poses.iter().all(Option::is_none)
        && f.features
            .iter()
            .filter_map(|x| x.layer_writer)
            .all(|w| (w.unchanged)(f))
}
