//! The per-vertex pass of the bake: each vertex's tangent frame ([`crate::frame`]), its comb in
//! that frame (Revie, Listing 2.7; [`crate::comb`]) and the NORMAL and TANGENT to write where
//! the bake rewrites them.
//!
//! It runs over the source vertices, beside the topology, when every vertex's normal and tangent
//! are its own (per-vertex data): then nothing in it waits for the normal groups, and split
//! vertices copy their source's results ([`VertexOut::gather`]). With per-corner normals or
//! tangents it runs over the output vertices once the split is known.

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use crate::comb::CombCase;
use crate::frame::Frame;

/// Which of NORMAL and TANGENT the bake rewrites.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Writes {
    pub normals: bool,
    pub tangents: bool,
}

/// Output vertices handled by one parallel task (the vertex pass's and the bake's other
/// per-vertex loops).
pub(crate) const CHUNK: usize = 4096;

/// Flag bits per vertex.
const DEGENERATE: u8 = 1;
const GRAY: u8 = 2;
const PARALLEL: u8 = 4;

/// What the pass writes, one entry per vertex it ran over.
pub(crate) struct VertexOut {
    /// `_FUR_COMB`.
    pub comb: Vec<[f32; 4]>,
    /// NORMAL to write, when rewritten.
    pub normals: Option<Vec<[f32; 3]>>,
    /// TANGENT to write, when rewritten.
    pub tangents: Option<Vec<[f32; 4]>>,
    /// [`DEGENERATE`], [`GRAY`], [`PARALLEL`].
    flags: Vec<u8>,
}

/// Counts for the report.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct Counts {
    pub degenerate_tangents: usize,
    pub gray: usize,
    pub parallel: usize,
}

/// `n` chunks of `len` items of `v` (or `n` Nones), for zipping optional outputs into the pass.
fn chunks_or_none<T>(v: Option<&mut Vec<T>>, len: usize, n: usize) -> Vec<Option<&mut [T]>> {
    match v {
        Some(v) => v.chunks_mut(len).map(Some).collect(),
        None => (0..n).map(|_| None).collect(),
    }
}

/// Runs the pass over `n` vertices. `inputs(o)` gives vertex `o`'s source vertex, normal and
/// tangent; `comb_at(source, frame)` its comb; `tangent_out(frame, degenerate, tangent)` the
/// TANGENT written for it.
pub(crate) fn run(
    n: usize,
    inputs: &(impl Fn(usize) -> (usize, Vec3, Vec4) + Sync),
    comb_at: &(impl Fn(usize, &Frame) -> ([f32; 4], CombCase) + Sync),
    tangent_out: &(impl Fn(&Frame, bool, Vec4) -> [f32; 4] + Sync),
    write: Writes,
) -> VertexOut {
    // Tasks sized like the topology's, so a small mesh still spreads over every core.
    let chunk = pelt_geom::task_len(n, CHUNK);
    let tasks = n.div_ceil(chunk);
    let mut comb = vec![[0.0f32; 4]; n];
    let mut flags = vec![0u8; n];
    let mut normals = write.normals.then(|| vec![[0.0f32; 3]; n]);
    let mut tangents = write.tangents.then(|| vec![[0.0f32; 4]; n]);
    comb.par_chunks_mut(chunk)
        .zip(flags.par_chunks_mut(chunk))
        .zip(chunks_or_none(normals.as_mut(), chunk, tasks))
        .zip(chunks_or_none(tangents.as_mut(), chunk, tasks))
        .enumerate()
        .for_each(|(task, (((comb, flags), mut normals), mut tangents))| {
            for (k, slot) in comb.iter_mut().enumerate() {
                let (v, nrm, t) = inputs(task * chunk + k);
                let (frame, degenerate) = Frame::new(nrm, t);
                let (combed, case) = comb_at(v, &frame);
                *slot = combed;
                if let Some(out) = normals.as_deref_mut() {
                    out[k] = nrm.to_array();
                }
                if let Some(out) = tangents.as_deref_mut() {
                    out[k] = tangent_out(&frame, degenerate, t);
                }
                flags[k] = if degenerate { DEGENERATE } else { 0 }
                    | match case {
                        CombCase::Combed => 0,
                        CombCase::Gray => GRAY,
                        CombCase::ParallelToNormal => PARALLEL,
                    };
            }
        });
    VertexOut {
        comb,
        normals,
        tangents,
        flags,
    }
}

/// `src[map[o]]` for every output vertex `o`.
fn gather<T: Copy + Send + Sync>(src: &[T], map: &[u32]) -> Vec<T> {
    map.par_iter()
        .with_min_len(CHUNK)
        .map(|&v| src[v as usize])
        .collect()
}

impl VertexOut {
    /// The results of the output vertices, from those of the source vertices they copy
    /// (`map`: output vertex → source vertex).
    pub fn gather(&self, map: &[u32]) -> VertexOut {
        VertexOut {
            comb: gather(&self.comb, map),
            normals: self.normals.as_deref().map(|n| gather(n, map)),
            tangents: self.tangents.as_deref().map(|t| gather(t, map)),
            flags: gather(&self.flags, map),
        }
    }

    /// How many vertices had a degenerate tangent, a gray comb, a comb along the normal.
    pub fn counts(&self) -> Counts {
        let count = |f: u8, bit: u8| usize::from(f & bit != 0);
        self.flags
            .par_iter()
            .with_min_len(CHUNK)
            .fold(Counts::default, |c, &f| Counts {
                degenerate_tangents: c.degenerate_tangents + count(f, DEGENERATE),
                gray: c.gray + count(f, GRAY),
                parallel: c.parallel + count(f, PARALLEL),
            })
            .reduce(Counts::default, |a, b| Counts {
                degenerate_tangents: a.degenerate_tangents + b.degenerate_tangents,
                gray: a.gray + b.gray,
                parallel: a.parallel + b.parallel,
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tangent(frame: &Frame, _: bool, _: Vec4) -> [f32; 4] {
        frame.tangent4()
    }

    /// Three vertices: combed, gray, and a degenerate tangent whose comb runs along the normal.
    fn three() -> VertexOut {
        let normals = [Vec3::Z, Vec3::Z, Vec3::Y];
        let tangents = [
            Vec4::new(1.0, 0.0, 0.0, 1.0),
            Vec4::X,
            Vec4::new(0.0, 2.0, 0.0, -1.0),
        ];
        let combs = [
            ([0.5, 0.5, 0.0, 1.0], CombCase::Combed),
            ([1.0, 0.0, 0.0, 0.0], CombCase::Gray),
            ([1.0, 0.0, 0.0, 0.5], CombCase::ParallelToNormal),
        ];
        run(
            3,
            &|o| (o, normals[o], tangents[o]),
            &|v, _| combs[v],
            &tangent,
            Writes {
                normals: true,
                tangents: true,
            },
        )
    }

    #[test]
    fn pass_counts_every_case_once() {
        let out = three();
        assert_eq!(
            out.counts(),
            Counts {
                degenerate_tangents: 1,
                gray: 1,
                parallel: 1
            }
        );
        assert_eq!(
            out.normals,
            Some(vec![[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
        );
        // The degenerate tangent (along N = +Y) is replaced by a perpendicular, w kept.
        let t = out.tangents.as_ref().expect("tangents written")[2];
        assert_eq!(t[1], 0.0);
        assert_eq!(t[3], -1.0);
    }

    #[test]
    fn gather_copies_results_and_counts_copies() {
        let out = three().gather(&[0, 1, 2, 2, 0]);
        assert_eq!(out.comb.len(), 5);
        assert_eq!(out.comb[3], out.comb[2]);
        assert_eq!(out.comb[4], [0.5, 0.5, 0.0, 1.0]);
        let c = out.counts();
        assert_eq!((c.degenerate_tangents, c.gray, c.parallel), (2, 1, 2));
        assert_eq!(out.tangents.map(|t| t.len()), Some(5));
    }
}
