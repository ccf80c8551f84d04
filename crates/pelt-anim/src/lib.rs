//! pelt-anim: skins and animations on the CPU (no GPU).
//!
//! - [`sample`]: keyframe sampling (glTF 2.0 §3.11, Appendix C): step, linear (shortest-arc
//!   slerp for rotations), cubic spline; clamped outside the keys.
//! - [`rig`]: the node hierarchy, skins and clips of an asset, read through the `gltf` crate's
//!   typed document and checked.
//! - [`pose`]: node transforms and morph weights at a time, joint matrices.
//! - [`skinning`]: linear blend skinning of positions, normals and tangents (and morph
//!   targets), the CPU twin of the preview's skinning pass.
//! - [`posed`]: `pelt pose`: a static mesh in one pose, the skin and animations removed.
//! - [`spring`]: secondary motion, a damped spring per vertex integrated exactly per step
//!   (stable at any step), driven by the skinned roots from time 0.
//!
//! The comb is baked in tangent space (Revie §2.4.1) exactly so that skinning the frame carries
//! it: nothing here touches `_FUR_COMB`.

pub mod pose;
pub mod posed;
pub mod rig;
pub mod sample;
pub mod skinning;
pub mod spring;

pub use pose::Pose;
pub use rig::{Clip, Rig};
