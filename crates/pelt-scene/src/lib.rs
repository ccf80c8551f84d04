//! pelt-scene: the CPU half of pelt's preview, with no GPU dependency (as `bevy_mesh` is to
//! `bevy_render`). Everything here compiles and is tested without wgpu; the renderer
//! (`pelt-preview`) depends on it, never the reverse.
//!
//! - [`scene`], [`procedural`], [`framing`]: what is rendered: scene files, generated scenes,
//!   the default scene around one asset;
//! - [`asset`], [`fur`], [`vertex`]: glTF/OBJ (and built-in shapes) flattened into vertex
//!   records with normal-group IDs, the baked fur (comb, fins, textures, manifest);
//! - [`material`]: base colour, normal and metallic-roughness textures and their mip chains;
//! - [`view`], [`plan`]: the camera and the CPU decisions of a frame (Kircher & Lawrance
//!   §2.2 scissor rectangles, §4 stipple patterns, culling, draw order, the L-buffer);
//! - [`footprint`]: how fine a pixel can get on a fur object (whether its shells must
//!   resolve single strands at this view);
//! - [`orbit`], [`budget`]: the interactive orbit camera of `pelt view` and its frame budget;
//! - [`sky`]: the cube-map sky's images;
//! - [`debug`]: the normal groups' colour classes of the debug views;
//! - [`flags`]: the scene's values as text (flags, knob lists), checked against its ranges.

pub mod asset;
pub mod budget;
pub mod checked;
pub mod debug;
pub mod flags;
pub mod footprint;
pub mod framing;
pub mod fur;
pub mod knobs;
pub mod light;
pub mod material;
pub mod orbit;
pub mod plan;
pub mod precision;
pub mod procedural;
pub mod scene;
pub mod shading;
pub mod skin;
pub mod sky;
pub mod springs;
pub mod strands;
pub mod tangents;
pub mod vertex;
pub mod view;
pub mod wind;

pub use plan::{Mode, Plan, PlanError};
pub use scene::{Scene, SceneError};
