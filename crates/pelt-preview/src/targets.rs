//! Per-view state (re_renderer's view targets): the render targets of one view, sized to it
//! and made for its output format (a window surface's or the PNG's), and the bind groups that
//! read them: the G-buffer and L-buffer at L-buffer resolution (Kircher & Lawrance §2.1–2.2),
//! the obliterated composition copy (Revie §2.4.4), the output's depth and, for PNGs, the
//! output colour; and the targets features own (the OIT accumulation, the scene colour). Made from a [`TargetSpec`] the plan
//! derives; a view whose spec changes (resize, L-buffer scale, a pass turned on) gets new
//! targets, and nothing else does.

use crate::owned::Owned;
use crate::plan::Plan;
use crate::renderer::{DEPTH_FORMAT, DSF_FORMAT, LBUFFER_FORMAT, Renderer};

/// What a view's targets depend on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TargetSpec {
    /// Output size.
    pub output: (u32, u32),
    /// G-buffer and L-buffer size, when the frame has them.
    pub lbuffer: Option<(u32, u32)>,
    /// The output colour format.
    pub color_format: wgpu::TextureFormat,
    /// The view renders into a colour texture of its own (PNG output) rather than into one
    /// the caller gives each frame (a window's surface).
    pub own_color: bool,
    /// The obliteration pass's composition copy is needed (fur with an L-buffer).
    pub composition: bool,
    /// Which of the features' own targets the view needs (bit i: the i-th registered).
    pub owned: u64,
}

impl TargetSpec {
    /// The targets `plan` needs, with output colour in `color_format`; `owned` are the
    /// registered features' own targets (those the plan needs are made).
    pub fn of(
        plan: &Plan,
        color_format: wgpu::TextureFormat,
        own_color: bool,
        owned: &[TargetsDesc],
    ) -> TargetSpec {
        let owned = owned
            .iter()
            .enumerate()
            .filter(|(_, t)| (t.needed)(plan))
            .fold(0, |bits, (i, _)| bits | 1 << i);
        TargetSpec {
            output: plan.output,
            lbuffer: plan.lbuffer,
            color_format,
            own_color,
            composition: plan.deferred_fur(),
            owned,
        }
    }
}

/// Per-view targets a feature owns.
#[derive(Debug, Clone, Copy)]
pub struct TargetsDesc {
    /// Whether a view drawing `plan` needs them.
    pub needed: fn(&Plan) -> bool,
    /// Makes them for a view of `spec`, kept in the view's [`crate::owned::Owned`] and found
    /// there by type.
    pub make: fn(&Renderer, &TargetSpec, &mut Owned),
}

/// A texture and its default view.
#[derive(Debug)]
pub struct Target {
    /// The texture.
    pub texture: wgpu::Texture,
    /// Its view.
    pub view: wgpu::TextureView,
    /// Its format.
    pub format: wgpu::TextureFormat,
}

impl Target {
    /// A 2D render target of `size` in `format` that passes can also read and copy from.
    pub fn new(
        device: &wgpu::Device,
        label: &str,
        size: (u32, u32),
        format: wgpu::TextureFormat,
    ) -> Target {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        Target {
            texture,
            view,
            format,
        }
    }
}

/// The geometry pass's outputs (Kircher & Lawrance §2.1).
#[derive(Debug)]
pub struct GBuffer {
    /// View normals, X/Y after eq. 1.
    pub normals: Target,
    /// Linear depth code and DSF ID.
    pub dsf: Target,
    /// Hardware depth.
    pub depth: Target,
    /// Normals and DSF, for the light pass.
    pub read: wgpu::BindGroup,
}

/// The obliteration pass's output: the L-buffer and DSF buffer with the outer-shell stipple
/// texels replaced (Revie §2.4.4).
#[derive(Debug)]
pub struct Composition {
    /// Light.
    pub light: Target,
    /// Depth code and ID.
    pub dsf: Target,
}

/// One view's targets.
#[derive(Debug)]
pub struct ViewTargets {
    /// What they were made for.
    pub spec: TargetSpec,
    /// G-buffer (absent without an L-buffer).
    pub gbuffer: Option<GBuffer>,
    /// The light pass's output: RGB diffuse, A specular intensity (§2.2).
    pub lbuffer: Option<Target>,
    /// The original L-buffer and DSF buffer (1×1 stand-ins without one): the light the fur
    /// reads at root and tip.
    pub lbuffer_read: wgpu::BindGroup,
    /// The obliteration pass's composition copy.
    pub composition: Option<Composition>,
    /// What the material pass reads: the composition copy when there is one, else
    /// `lbuffer_read`'s textures.
    pub material_read: wgpu::BindGroup,
    /// The targets features own (the OIT accumulation, the scene colour), made when the
    /// plan runs the feature ([`crate::feature::TargetsDesc`]).
    pub owned: Owned,
    /// The output colour, when the view owns it.
    pub color: Option<Target>,
    /// The output's depth.
    pub depth: Target,
}

/// The two textures `a` and `b` as a pass reads them (`layout::TEXTURES`).
fn pair(r: &Renderer, a: &wgpu::TextureView, b: &wgpu::TextureView) -> wgpu::BindGroup {
    r.group(
        "read pair",
        &crate::layout::TEXTURES,
        &[
            wgpu::BindingResource::TextureView(a),
            wgpu::BindingResource::TextureView(b),
        ],
    )
}

impl ViewTargets {
    /// Creates the targets of `spec`, with the features' own targets of `owned` (as `spec`
    /// was made with).
    pub fn new(r: &Renderer, spec: TargetSpec, owned: &[TargetsDesc]) -> ViewTargets {
        let device = &r.gpu.device;
        let tex = |label, size, format| Target::new(device, label, size, format);
        let gbuffer = spec.lbuffer.map(|s| {
            let normals = tex("normals", s, r.gpu.normal_format);
            let dsf = tex("dsf", s, DSF_FORMAT);
            let read = pair(r, &normals.view, &dsf.view);
            GBuffer {
                normals,
                dsf,
                depth: tex("gbuffer depth", s, DEPTH_FORMAT),
                read,
            }
        });
        let lbuffer = spec.lbuffer.map(|s| tex("lbuffer", s, LBUFFER_FORMAT));
        let lbuffer_read = match (&lbuffer, &gbuffer) {
            (Some(lb), Some(g)) => pair(r, &lb.view, &g.dsf.view),
            _ => {
                // Stand-ins the material shader never reads (flags.w = 0: ambient only).
                let a = tex("no lbuffer", (1, 1), LBUFFER_FORMAT);
                let b = tex("no dsf", (1, 1), DSF_FORMAT);
                pair(r, &a.view, &b.view)
            }
        };
        let composition = spec
            .lbuffer
            .filter(|_| spec.composition)
            .map(|s| Composition {
                light: tex("composition", s, LBUFFER_FORMAT),
                dsf: tex("composition dsf", s, DSF_FORMAT),
            });
        let material_read = match &composition {
            Some(c) => pair(r, &c.light.view, &c.dsf.view),
            None => lbuffer_read.clone(),
        };
        let mut made = Owned::default();
        for (i, t) in owned.iter().enumerate() {
            if spec.owned & (1 << i) != 0 {
                (t.make)(r, &spec, &mut made);
            }
        }
        ViewTargets {
            spec,
            gbuffer,
            lbuffer,
            lbuffer_read,
            composition,
            material_read,
            owned: made,
            color: spec
                .own_color
                .then(|| tex("output", spec.output, spec.color_format)),
            depth: tex("output depth", spec.output, DEPTH_FORMAT),
        }
    }
}

/// A render target of several layers (a cube's six faces, +X −X +Y −Y +Z −Z, or any 2D
/// array) with a mip chain, rendered one layer and mip at a time ([`LayeredTarget::layer`])
/// and sampled whole as a 2D array ([`LayeredTarget::sampled`]; shaders pick a cube's face
/// by direction themselves, as `textureLoad` cannot read cube textures anyway). What layered
/// distance maps and reflection probes render into.
///
/// wgpu's GL back end makes every square texture with a multiple of 6 layers a GL cube map,
/// whose faces it can neither render to one by one nor read back; on GL such a target gets
/// one spare layer, so it stays a 2D array.
#[derive(Debug)]
pub struct LayeredTarget {
    /// The texture.
    pub texture: wgpu::Texture,
    /// Its format.
    pub format: wgpu::TextureFormat,
    /// Size of mip 0.
    pub size: (u32, u32),
    /// Layers (6 for a cube).
    pub layers: u32,
    /// Mip levels.
    pub mips: u32,
    /// The layers as a 2D array.
    pub sampled: wgpu::TextureView,
}

/// Mip levels of a full chain down to 1×1.
pub fn full_chain(size: (u32, u32)) -> u32 {
    32 - size.0.max(size.1).max(1).leading_zeros()
}

impl LayeredTarget {
    /// `layers` layers of `size` with `mips` levels.
    pub fn new(
        r: &Renderer,
        label: &str,
        size: (u32, u32),
        layers: u32,
        mips: u32,
        format: wgpu::TextureFormat,
    ) -> LayeredTarget {
        let cube_like = size.0 == size.1 && layers.is_multiple_of(6);
        let allocated = if cube_like && r.gpu.info.backend == wgpu::Backend::Gl {
            layers + 1
        } else {
            layers
        };
        let texture = r.gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: allocated,
            },
            mip_level_count: mips,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let sampled = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            array_layer_count: Some(layers),
            ..Default::default()
        });
        LayeredTarget {
            texture,
            format,
            size,
            layers,
            mips,
            sampled,
        }
    }

    /// One layer (face) at one mip level, as a 2D view to render into.
    pub fn layer(&self, layer: u32, mip: u32) -> wgpu::TextureView {
        self.texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_array_layer: layer,
            array_layer_count: Some(1),
            base_mip_level: mip,
            mip_level_count: Some(1),
            ..Default::default()
        })
    }

    /// The size of mip `mip`.
    pub fn mip_size(&self, mip: u32) -> (u32, u32) {
        ((self.size.0 >> mip).max(1), (self.size.1 >> mip).max(1))
    }
}
