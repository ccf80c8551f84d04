//! pelt-bake: turns a painted mesh into a fur-ready one.
//!
//! - [`options`]: what a user can choose (tangents, comb color space and axes, quantization).
//! - [`frame`]: the orthonormal tangent frame (T, B = cross(N, T)·w, N) a comb is expressed in.
//! - [`comb`]: Revie's Listing 2.7 (decode, Gram-Schmidt against N, normalize, into tangent
//!   space) with defined results at the extremes, and the `_FUR_COMB` encodings.
//! - [`primitive`]: one primitive: normals, tangents (kept or MikkTSpace), vertex splits, comb.
//! - `vertex_pass`: the per-vertex frame, comb, NORMAL and TANGENT, beside the topology where
//!   it can be.
//! - [`asset`]: a whole document, with the per-primitive report.
//! - [`config`]: the bake config file (its `fur` section).
//! - [`flags`]: the options as `pelt bake`'s flags (clap `Args` with the `cli` feature),
//!   merged with a config.
//! - [`fur`]: embedding generated fur textures and the fur manifest in a baked asset.
//! - [`inspect`]: what a file holds, baked or not, as a report (`pelt inspect`).

pub mod asset;
pub mod comb;
pub mod config;
pub mod flags;
pub use pelt_geom::frame;
pub mod fur;
pub mod inspect;
pub mod options;
pub mod primitive;
mod vertex_pass;

pub use asset::{AssetReport, bake_document, pack_output};
pub use options::BakeOptions;
