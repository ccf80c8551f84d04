//! One module per feature of the renderer. Each owns its shaders' pipeline layouts and builds
//! its passes, or its part of shared passes, as [`crate::recipe::Recipe`]s from a frame's
//! inputs:
//!
//! - [`geometry`]: opaque geometry into the G-buffer (Kircher & Lawrance §2.1);
//! - [`lights`]: scissored point lights into the L-buffer (§2.2);
//! - [`material`]: the material pass with DSF (§2.3, §3), which draws what the other features
//!   put at output resolution;
//! - [`alpha`]: stippled alpha (§4);
//! - [`fur`]: Revie's deferred fur: base and outer shell in the G-buffer, stipple
//!   obliteration, shells and fins;
//! - [`wboit`]: weighted blended OIT accumulation and composite (McGuire & Bavoil);
//! - [`sky`]: procedural and cube-map skies;
//! - [`forward`]: the forward reference;
//! - [`upscale`]: a reduced-resolution frame scaled up to a window (`pelt view`);
//! - [`resolve`]: the half-float scene colour the fur's layers blend into, to the output;
//! - [`mips`]: mip chains of layered targets (cube faces, arrays);
//! - [`overlay`]: `pelt view`'s text overlay;
//! - [`reflect`]: mirrors and glass from layered distance maps (GPU Gems 3 ch. 17);
//! - [`shadows`]: shadow cubes and directional maps, read where lights are applied;
//! - [`opacity`]: deep opacity maps, through which fur shadows itself and what lies behind it;
//! - [`strands`]: explicit strands, the converged fur reference;
//! - [`skin`]: the skinning compute pass (glTF linear blend skinning) into storage buffers;
//! - [`debug`]: the debug views (normal groups, the decoded comb).
//!
//! Each module declares its shaders, bind-group layouts and pipelines as descriptors and one
//! [`crate::feature::Feature`], listed in [`registry::FEATURES`]. Features import the core
//! ([`crate::draw`], [`crate::feature`], [`crate::renderer`], …), never the reverse.

pub mod alpha;
pub mod debug;
pub mod forward;
pub mod fur;
pub mod geometry;
pub mod lights;
pub mod material;
pub mod mips;
pub mod opacity;
pub mod overlay;
pub mod reflect;
pub mod registry;
pub mod resolve;
pub mod shadows;
pub mod skin;
pub mod sky;
pub mod strands;
pub mod upscale;
pub mod wboit;

pub use crate::draw::{
    ADD, MissingInput, fur_vertex_layout, object_blends, object_depth, slot, vertex_layout,
    vertex_slot, wboit_blends,
};
pub use crate::feature::{Frame, Output};
