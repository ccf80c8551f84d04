//! pelt-geom: the plain-CPU geometry layer of pelt (glam, no GPU, no file formats).
//!
//! - [`mesh`]: the triangle-mesh model the bake works on (positions, normals, UVs, tangents,
//!   colors, indices) and its validation.
//! - [`normals`]: per-corner unit normals in f64, flat normals where a file has none (glTF 2.0
//!   §3.7.2.1), repair of zero and non-unit normals.
//! - [`weld`]: exact-bit welding of vertex tables.
//! - [`smooth`]: smooth normals (angle-weighted, with a crease angle) for meshes without NORMAL.
//! - [`flow`]: a comb direction field along an axis, for meshes nobody painted.
//! - [`mikktspace`]: a parallel MikkTSpace tangent generator that matches the reference
//!   implementation (tested against `bevy_mikktspace`).
//! - [`gradient`]: a one-pass per-vertex tangent frame from UV gradients, for meshes whose
//!   tangents only carry the comb (no normal map).
//! - [`topology`]: welded positions, unique edges with their faces, and normal groups (the
//!   dual-graph components of Kircher & Lawrance §3.1); not yet wired into the bake.
//! - [`fastmath`]: the scalar f32 vector operations MikkTSpace needs, in the reference's order
//!   of operations.

pub mod fastmath;
pub mod fins;
pub mod flow;
pub mod frame;
pub mod gradient;
pub mod group_ids;
pub mod mesh;
pub mod mikktspace;
pub mod normals;
pub mod smooth;
pub mod topology;
pub mod union_find;
pub mod weld;

pub use mesh::{GeomError, Mesh};

/// Items per parallel task for `n` items: about four tasks per thread, at least 256 items and
/// at most `max`. Large meshes get `max`-sized tasks (little overhead); small ones are still
/// split into several tasks per core.
pub fn task_len(n: usize, max: usize) -> usize {
    (n / (4 * rayon::current_num_threads().max(1))).clamp(256, max.max(256))
}
