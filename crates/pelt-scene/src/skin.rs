//! What the preview needs to skin an asset on the GPU (Revie §2.4.1: the comb baked in
//! tangent space rides on the skinned frame): the rig, each skinned primitive's rest vertices
//! and influences (`pelt_anim::posed::SkinJob` at rest) with where its vertices start in the
//! flattened mesh, and every fin edge as vertex indices (the edge's two vertices and both
//! faces' three, in winding order), so the fins follow the skinned positions instead of
//! copying them. A frame asks [`SkinBinding::matrices`] for a pose's joint matrices; the
//! renderer does the rest.

use glam::Mat4;
use pelt_anim::posed::SkinJob;
use pelt_anim::rig::Rig;
use pelt_io::{Document, IoError, PrimitiveRef};

/// A moment of an animation: assets are loaded posed there (`pelt render --animation`).
#[derive(Debug, Clone, PartialEq)]
pub struct PoseAt {
    /// The clip's name.
    pub animation: String,
    /// Seconds (clamped to the clip's keys).
    pub time: f32,
}

/// One skinned primitive.
#[derive(Debug, Clone)]
pub struct SkinRange {
    /// Its rest vertices and influences.
    pub job: SkinJob,
    /// The node drawing it.
    pub node: usize,
    /// Its skin.
    pub skin: usize,
    /// Its first vertex in the flattened mesh.
    pub base: u32,
}

/// One fin edge by vertex index (flattened mesh): the edge (a, b in its first face's
/// winding), its first face and its second (the first again on a boundary), each as three
/// vertices whose (v1 − v0) × (v2 − v0) is the face's normal.
pub type FinSource = [u32; 8];

/// An asset's GPU skinning data.
#[derive(Debug, Clone)]
pub struct SkinBinding {
    /// Nodes, skins, clips.
    pub rig: Rig,
    /// The skinned primitives.
    pub ranges: Vec<SkinRange>,
    /// Parallel to the fur's fin instances.
    pub fins: Vec<FinSource>,
    /// The pose the CPU loaded the mesh at ([`crate::asset::skinned`]): a view prepared from
    /// the mesh stands there, and fur springs are bent for it.
    pub loaded: Option<PoseAt>,
}

impl PartialEq for SkinBinding {
    /// Bindings are compared by identity: two loads of one file are two bindings (the mesh's
    /// content hash already tells equal assets apart).
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self, other)
    }
}

/// A range's joint matrices in the asset's space, and its unweighted vertices' matrix.
pub type RangeMatrices = (Vec<Mat4>, Mat4);

impl SkinBinding {
    /// The joint matrices of every range at `time` s of the clip `animation`; an unknown clip
    /// is an error listing those there are.
    pub fn matrices(
        &self,
        doc_path: &std::path::Path,
        animation: &str,
        time: f32,
    ) -> Result<Vec<RangeMatrices>, IoError> {
        Ok(self.matrices_at(self.clip(doc_path, animation)?, time))
    }

    /// The index of clip `animation`; an unknown clip is an error (at `doc_path`) listing
    /// those there are.
    pub fn clip(&self, doc_path: &std::path::Path, animation: &str) -> Result<usize, IoError> {
        self.rig
            .clips
            .iter()
            .position(|c| c.name == animation)
            .ok_or_else(|| {
                let known: Vec<&str> = self.rig.clips.iter().map(|c| c.name.as_str()).collect();
                IoError::Invalid {
                    path: doc_path.to_owned(),
                    place: "animations".into(),
                    message: format!(
                        "no animation named {animation:?} (the file has: {})",
                        known.join(", ")
                    ),
                }
            })
    }

    /// The joint matrices of every range at `time` s of clip `clip` (an index from
    /// [`SkinBinding::clip`]).
    pub fn matrices_at(&self, clip: usize, time: f32) -> Vec<RangeMatrices> {
        let pose = self.rig.pose(self.rig.clips.get(clip), time);
        self.ranges
            .iter()
            .map(|r| (self.rig.joint_matrices(r.skin, &pose), pose.global[r.node]))
            .collect()
    }
}

/// The skin binding of `doc` (its rest document), when every moving primitive can be skinned
/// on the GPU: skinned (not only morphed), without morph targets, with NORMAL (so the
/// flattened mesh has one vertex per glTF vertex). `ranges` gives each primitive's first
/// vertex in the flattened mesh. None otherwise (the CPU poses such assets).
pub fn binding(
    doc: &Document,
    ranges: &[(PrimitiveRef, u32)],
) -> Result<Option<SkinBinding>, IoError> {
    if doc.array("skins").is_empty() {
        return Ok(None);
    }
    let rig = Rig::load(doc)?;
    let jobs = pelt_anim::posed::skin_jobs(doc, None, 0.0)?;
    let mut out = Vec::new();
    for job in jobs {
        let r = job.primitive;
        let has_targets = doc.primitive(r)?.get("targets").is_some();
        let node = rig
            .order
            .iter()
            .copied()
            .find(|&n| rig.nodes[n].mesh == Some(r.mesh));
        let skin = node.and_then(|n| rig.nodes[n].skin);
        let base = ranges.iter().find(|(p, _)| *p == r).map(|(_, b)| *b);
        match (node, skin, base, has_targets, job.normals.is_some()) {
            (Some(node), Some(skin), Some(base), false, true) => out.push(SkinRange {
                job,
                node,
                skin,
                base,
            }),
            _ => return Ok(None),
        }
    }
    Ok((!out.is_empty()).then_some(SkinBinding {
        rig,
        ranges: out,
        fins: Vec::new(),
        loaded: None,
    }))
}
