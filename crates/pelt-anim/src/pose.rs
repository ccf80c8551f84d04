//! A rig at one moment: each node's local and global transform and morph weights, with the
//! animated properties of a clip sampled at a time (glTF 2.0 §3.11), and the joint matrices of
//! a skin (global transform of the joint × its inverse bind matrix, §3.7.3).

use glam::{Mat4, Quat, Vec3};

use crate::rig::{Clip, Property, Rig, Trs};
use crate::sample::sample;

/// Node transforms and morph weights at one time.
#[derive(Debug, Clone)]
pub struct Pose {
    /// Each node's transform (animated ones sampled).
    pub trs: Vec<Trs>,
    /// Whether a clip animated the node's transform.
    pub animated: Vec<bool>,
    /// Each node's transform relative to the scene.
    pub global: Vec<Mat4>,
    /// Morph weights set by the clip, per node.
    pub weights: Vec<Option<Vec<f32>>>,
}

impl Rig {
    /// The pose at time `t` of `clip` (the rest pose without one).
    pub fn pose(&self, clip: Option<&Clip>, t: f32) -> Pose {
        let mut trs: Vec<Trs> = self.nodes.iter().map(|n| n.rest).collect();
        let mut animated = vec![false; self.nodes.len()];
        let mut weights = vec![None; self.nodes.len()];
        for ch in clip.iter().flat_map(|c| &c.channels) {
            let mut v = vec![0.0; ch.components];
            let rotation = ch.property == Property::Rotation;
            sample(
                ch.interpolation,
                &ch.times,
                &ch.values,
                ch.components,
                t,
                rotation,
                &mut v,
            );
            let n = &mut trs[ch.node];
            match ch.property {
                Property::Translation => n.translation = Vec3::from_slice(&v),
                Property::Rotation => n.rotation = Quat::from_slice(&v),
                Property::Scale => n.scale = Vec3::from_slice(&v),
                Property::Weights => {
                    weights[ch.node] = Some(v);
                    continue;
                }
            }
            animated[ch.node] = true;
        }
        let mut global = vec![Mat4::IDENTITY; self.nodes.len()];
        for &n in &self.order {
            let local = match (self.nodes[n].matrix, animated[n]) {
                (Some(m), false) => m,
                _ => trs[n].matrix(),
            };
            global[n] = self.parent[n].map_or(local, |p| global[p] * local);
        }
        Pose {
            trs,
            animated,
            global,
            weights,
        }
    }

    /// The joint matrices of skin `s` in pose `p`.
    pub fn joint_matrices(&self, s: usize, p: &Pose) -> Vec<Mat4> {
        let skin = &self.skins[s];
        skin.joints
            .iter()
            .zip(&skin.inverse_bind)
            .map(|(&j, ib)| p.global[j] * *ib)
            .collect()
    }

    /// Morph weights of node `n` in pose `p`: the clip's, else the node's, else its mesh's,
    /// padded with zeros to `targets`.
    pub fn morph_weights(&self, n: usize, p: &Pose, targets: usize) -> Vec<f32> {
        let node = &self.nodes[n];
        let from_mesh = node.mesh.and_then(|m| self.mesh_weights.get(m)).cloned();
        let mut w = p.weights[n]
            .clone()
            .or_else(|| node.weights.clone())
            .or(from_mesh)
            .unwrap_or_default();
        w.resize(targets, 0.0);
        w
    }
}
