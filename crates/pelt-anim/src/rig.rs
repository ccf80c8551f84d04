//! The parts of a glTF asset that move, read through the `gltf` crate's typed document: the
//! node hierarchy with rest transforms, skins (joints, inverse bind matrices) and animation
//! clips (channels with their keys). Everything is checked on load, each error naming the
//! place: a node with two parents or in a cycle, skin joints outside the scene, singular or
//! non-finite inverse bind matrices, keyframe times that are not finite and strictly
//! increasing, NaN or infinite key values, outputs whose count does not match their inputs.

use glam::{Mat4, Quat, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::animation::util::ReadOutputs;
use pelt_io::{Document, IoError, typed};

use crate::sample::Interpolation;

/// A node's transform as translation, rotation, scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trs {
    /// Translation.
    pub translation: Vec3,
    /// Rotation (unit).
    pub rotation: Quat,
    /// Scale.
    pub scale: Vec3,
}

impl Trs {
    /// As a matrix (T · R · S).
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// One node.
#[derive(Debug, Clone)]
pub struct Node {
    /// Its name, if any.
    pub name: Option<String>,
    /// Rest transform.
    pub rest: Trs,
    /// The rest transform as the file gives it, when it is a matrix.
    pub matrix: Option<Mat4>,
    /// Children.
    pub children: Vec<usize>,
    /// Mesh drawn here.
    pub mesh: Option<usize>,
    /// Skin of that mesh.
    pub skin: Option<usize>,
    /// Morph weights of this node (overriding the mesh's).
    pub weights: Option<Vec<f32>>,
}

/// A skin.
#[derive(Debug, Clone)]
pub struct Skin {
    /// Its name, if any.
    pub name: Option<String>,
    /// The joint nodes.
    pub joints: Vec<usize>,
    /// Inverse bind matrix per joint (identity when the file gives none).
    pub inverse_bind: Vec<Mat4>,
}

/// What a channel animates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Property {
    /// Translation (3 values).
    Translation,
    /// Rotation (unit quaternion, x y z w).
    Rotation,
    /// Scale (3 values).
    Scale,
    /// Morph target weights (one per target).
    Weights,
}

/// One animated property of one node.
#[derive(Debug, Clone)]
pub struct Channel {
    /// Target node.
    pub node: usize,
    /// Target property.
    pub property: Property,
    /// How keys are interpolated.
    pub interpolation: Interpolation,
    /// Key times (seconds, strictly increasing).
    pub times: Vec<f32>,
    /// Key values, `components` per value (three values per key for cubic splines).
    pub values: Vec<f32>,
    /// Components per value.
    pub components: usize,
}

/// An animation.
#[derive(Debug, Clone)]
pub struct Clip {
    /// Its name (`animation N` when the file gives none).
    pub name: String,
    /// First key time over all channels.
    pub start: f32,
    /// Last key time over all channels.
    pub end: f32,
    /// Channels.
    pub channels: Vec<Channel>,
}

impl Clip {
    /// Length in seconds (last key time minus first).
    pub fn duration(&self) -> f32 {
        self.end - self.start
    }
}

/// Nodes, skins and clips of an asset.
#[derive(Debug, Clone)]
pub struct Rig {
    /// Nodes, as indexed in the file.
    pub nodes: Vec<Node>,
    /// Parent of each node.
    pub parent: Vec<Option<usize>>,
    /// Every node, parents before children.
    pub order: Vec<usize>,
    /// Nodes of the scene drawn (the default scene, else scene 0, else every root).
    pub in_scene: Vec<bool>,
    /// Skins.
    pub skins: Vec<Skin>,
    /// Animations.
    pub clips: Vec<Clip>,
    /// Default morph weights of each mesh.
    pub mesh_weights: Vec<Vec<f32>>,
}

impl Rig {
    /// Reads and checks the rig of `doc`.
    pub fn load(doc: &Document) -> Result<Rig, IoError> {
        let g = typed::document(doc)?;
        let nodes: Vec<Node> = g.nodes().map(node).collect();
        let (parent, order) = hierarchy(doc, &nodes)?;
        let in_scene = scene_nodes(&g, &nodes, &parent);
        let skins = g
            .skins()
            .map(|s| skin(doc, &s, &in_scene))
            .collect::<Result<_, _>>()?;
        let clips = g
            .animations()
            .map(|a| clip(doc, &a))
            .collect::<Result<_, _>>()?;
        let mesh_weights = g
            .meshes()
            .map(|m| m.weights().map(<[f32]>::to_vec).unwrap_or_default())
            .collect();
        Ok(Rig {
            nodes,
            parent,
            order,
            in_scene,
            skins,
            clips,
            mesh_weights,
        })
    }

    /// The clip named `name`; the error lists the names there are.
    pub fn clip(&self, doc: &Document, name: &str) -> Result<&Clip, IoError> {
        self.clips.iter().find(|c| c.name == name).ok_or_else(|| {
            let names: Vec<String> = self.clips.iter().map(|c| format!("{:?}", c.name)).collect();
            let have = if names.is_empty() {
                "the file has no animations".to_owned()
            } else {
                format!("the file has {}", names.join(", "))
            };
            doc.invalid("animations", format!("no animation named {name:?}: {have}"))
        })
    }
}

fn node(n: gltf::Node<'_>) -> Node {
    let (matrix, rest) = match n.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            let m = Mat4::from_cols_array_2d(&matrix);
            let (s, r, t) = m.to_scale_rotation_translation();
            (
                Some(m),
                Trs {
                    translation: t,
                    rotation: r,
                    scale: s,
                },
            )
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => (
            None,
            Trs {
                translation: Vec3::from(translation),
                rotation: Quat::from_array(rotation).normalize(),
                scale: Vec3::from(scale),
            },
        ),
    };
    Node {
        name: n.name().map(str::to_owned),
        rest,
        matrix,
        children: n.children().map(|c| c.index()).collect(),
        mesh: n.mesh().map(|m| m.index()),
        skin: n.skin().map(|s| s.index()),
        weights: n.weights().map(<[f32]>::to_vec),
    }
}

/// Parents, and an order with parents first; a node with two parents or in a cycle is an
/// error.
fn hierarchy(doc: &Document, nodes: &[Node]) -> Result<(Vec<Option<usize>>, Vec<usize>), IoError> {
    let mut parent = vec![None; nodes.len()];
    for (p, n) in nodes.iter().enumerate() {
        for &c in &n.children {
            if let Some(other) = parent[c] {
                return Err(doc.invalid(
                    format!("nodes[{p}].children"),
                    format!("node {c} is already a child of node {other}"),
                ));
            }
            parent[c] = Some(p);
        }
    }
    let mut order = Vec::with_capacity(nodes.len());
    let mut stack: Vec<usize> = (0..nodes.len())
        .rev()
        .filter(|&n| parent[n].is_none())
        .collect();
    while let Some(n) = stack.pop() {
        order.push(n);
        stack.extend(nodes[n].children.iter().rev());
    }
    if order.len() != nodes.len() {
        let lost = (0..nodes.len()).find(|n| !order.contains(n)).unwrap_or(0);
        return Err(doc.invalid(
            format!("nodes[{lost}]"),
            "the node hierarchy has a cycle through this node",
        ));
    }
    Ok((parent, order))
}

fn scene_nodes(g: &gltf::Document, nodes: &[Node], parent: &[Option<usize>]) -> Vec<bool> {
    let roots: Vec<usize> = match g.default_scene().or_else(|| g.scenes().next()) {
        Some(s) => s.nodes().map(|n| n.index()).collect(),
        None => (0..nodes.len()).filter(|&n| parent[n].is_none()).collect(),
    };
    let mut inside = vec![false; nodes.len()];
    let mut stack = roots;
    while let Some(n) = stack.pop() {
        if !std::mem::replace(&mut inside[n], true) {
            stack.extend(&nodes[n].children);
        }
    }
    inside
}

fn skin(doc: &Document, s: &gltf::Skin<'_>, in_scene: &[bool]) -> Result<Skin, IoError> {
    let place = format!("skins[{}]", s.index());
    let joints: Vec<usize> = s.joints().map(|j| j.index()).collect();
    if let Some((k, &j)) = joints.iter().enumerate().find(|(_, j)| !in_scene[**j]) {
        return Err(doc.invalid(
            format!("{place}.joints[{k}]"),
            format!("node {j} is not in the scene, so it has no place to pose"),
        ));
    }
    let inverse_bind: Vec<Mat4> = match s.inverse_bind_matrices() {
        Some(a) => {
            let at = format!("{place}.inverseBindMatrices");
            typed::check_kind(doc, &a, &at, Dimensions::Mat4, &[DataType::F32])?;
            let reader = s.reader(typed::buffers(doc));
            let m: Vec<Mat4> = reader
                .read_inverse_bind_matrices()
                .ok_or_else(|| doc.invalid(&at, "cannot be read"))?
                .map(|m| Mat4::from_cols_array_2d(&m))
                .collect();
            if m.len() != joints.len() {
                return Err(doc.invalid(
                    &at,
                    format!("{} matrices for {} joints", m.len(), joints.len()),
                ));
            }
            for (k, m) in m.iter().enumerate() {
                // Relative to the linear part (not the translation, which can be large where
                // an exporter rescaled the mesh, as gltfpack's quantization does).
                let linear = [
                    m.x_axis.truncate(),
                    m.y_axis.truncate(),
                    m.z_axis.truncate(),
                ];
                let scale = linear
                    .iter()
                    .fold(0f32, |a, c| a.max(c.abs().max_element()));
                let det = m.determinant();
                if !m.is_finite() || !det.is_finite() || det.abs() <= 1e-12 * scale.powi(3) {
                    return Err(doc.invalid(
                        format!("{at}[{k}]"),
                        format!("singular or not finite (determinant {det})"),
                    ));
                }
            }
            m
        }
        None => vec![Mat4::IDENTITY; joints.len()],
    };
    Ok(Skin {
        name: s.name().map(str::to_owned),
        joints,
        inverse_bind,
    })
}

/// Animation `a` as a clip: its channels, and the time span they cover.
fn clip(doc: &Document, a: &gltf::Animation<'_>) -> Result<Clip, IoError> {
    let place = format!("animations[{}]", a.index());
    let mut channels = Vec::new();
    for ch in a.channels() {
        channels.push(channel(doc, &place, &ch)?);
    }
    let start = channels
        .iter()
        .map(|c| c.times[0])
        .fold(f32::INFINITY, f32::min);
    let end = channels
        .iter()
        .map(|c| c.times[c.times.len() - 1])
        .fold(f32::NEG_INFINITY, f32::max);
    Ok(Clip {
        name: a
            .name()
            .map_or_else(|| format!("animation {}", a.index()), str::to_owned),
        start: if start.is_finite() { start } else { 0.0 },
        end: if end.is_finite() { end } else { 0.0 },
        channels,
    })
}

/// Reading one channel of the animation at `place`: its sampler's accessors checked, its key
/// times (finite, strictly increasing) and its values (finite, whole keyframes for the
/// interpolation).
fn channel(
    doc: &Document,
    place: &str,
    ch: &gltf::animation::Channel<'_>,
) -> Result<Channel, IoError> {
    let sampler = ch.sampler();
    let at = format!("{place}.samplers[{}]", sampler.index());
    check_sampler_kinds(doc, &at, ch)?;
    let reader = ch.reader(typed::buffers(doc));
    let times: Vec<f32> = reader
        .read_inputs()
        .ok_or_else(|| doc.invalid(format!("{at}.input"), "cannot be read"))?
        .collect();
    if let Some(k) =
        (0..times.len()).find(|&k| !times[k].is_finite() || (k > 0 && times[k] <= times[k - 1]))
    {
        return Err(doc.invalid(
            format!("{at}.input"),
            format!(
                "key {k} at time {}: times must be finite and strictly increasing",
                times[k]
            ),
        ));
    }
    let (property, values) = match reader.read_outputs() {
        Some(ReadOutputs::Translations(v)) => (Property::Translation, v.flatten().collect()),
        Some(ReadOutputs::Rotations(v)) => (Property::Rotation, v.into_f32().flatten().collect()),
        Some(ReadOutputs::Scales(v)) => (Property::Scale, v.flatten().collect()),
        Some(ReadOutputs::MorphTargetWeights(v)) => (Property::Weights, v.into_f32().collect()),
        None => return Err(doc.invalid(format!("{at}.output"), "cannot be read")),
    };
    let values: Vec<f32> = values;
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(doc.invalid(
            format!("{at}.output"),
            format!("value {i} is {}: keyframes must be finite", values[i]),
        ));
    }
    let interpolation = match sampler.interpolation() {
        gltf::animation::Interpolation::Step => Interpolation::Step,
        gltf::animation::Interpolation::Linear => Interpolation::Linear,
        gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
    };
    let per_key = times.len()
        * if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
    let components = match property {
        Property::Translation | Property::Scale => 3,
        Property::Rotation => 4,
        Property::Weights => values.len() / per_key.max(1),
    };
    if times.is_empty() || components == 0 || values.len() != per_key * components {
        return Err(doc.invalid(
            format!("{at}.output"),
            format!(
                "{} values for {} keys ({interpolation:?}) do not make whole keyframes",
                values.len(),
                times.len()
            ),
        ));
    }
    Ok(Channel {
        node: ch.target().node().index(),
        property,
        interpolation,
        times,
        values,
        components,
    })
}

/// The kinds of a channel's sampler accessors (at `at`): float scalar times; values float VEC3
/// for translation and scale, and float or normalized integers (VEC4 for rotation, scalars for
/// morph weights).
fn check_sampler_kinds(
    doc: &Document,
    at: &str,
    ch: &gltf::animation::Channel<'_>,
) -> Result<(), IoError> {
    let sampler = ch.sampler();
    typed::check_kind(
        doc,
        &sampler.input(),
        &format!("{at}.input"),
        Dimensions::Scalar,
        &[DataType::F32],
    )?;
    let ints = [
        DataType::F32,
        DataType::I8,
        DataType::U8,
        DataType::I16,
        DataType::U16,
    ];
    let (dims, types): (Dimensions, &[DataType]) = match ch.target().property() {
        gltf::animation::Property::Translation | gltf::animation::Property::Scale => {
            (Dimensions::Vec3, &[DataType::F32])
        }
        gltf::animation::Property::Rotation => (Dimensions::Vec4, &ints),
        gltf::animation::Property::MorphTargetWeights => (Dimensions::Scalar, &ints),
    };
    typed::check_kind(doc, &sampler.output(), &format!("{at}.output"), dims, types)?;
    Ok(())
}

/// What `pelt inspect` lists of a rig.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RigSummary {
    /// Skins: name and joint names (or node indices).
    pub skins: Vec<SkinSummary>,
    /// Animations: name, key range, duration, channels.
    pub animations: Vec<ClipSummary>,
}

/// One skin in a [`RigSummary`].
#[derive(Debug, Clone, serde::Serialize)]
pub struct SkinSummary {
    /// Its name.
    pub name: Option<String>,
    /// Joint count.
    pub joints: usize,
    /// Joint node names (`node N` where unnamed).
    pub joint_names: Vec<String>,
}

/// One clip in a [`RigSummary`].
#[derive(Debug, Clone, serde::Serialize)]
pub struct ClipSummary {
    /// Its name.
    pub name: String,
    /// First key time (s).
    pub start: f32,
    /// Last key time (s).
    pub end: f32,
    /// `end - start` (s).
    pub duration: f32,
    /// Channels.
    pub channels: usize,
}

impl Rig {
    /// Skins and clips, for `pelt inspect`.
    pub fn summary(&self) -> RigSummary {
        let node_name = |n: usize| {
            self.nodes[n]
                .name
                .clone()
                .unwrap_or_else(|| format!("node {n}"))
        };
        RigSummary {
            skins: self
                .skins
                .iter()
                .map(|s| SkinSummary {
                    name: s.name.clone(),
                    joints: s.joints.len(),
                    joint_names: s.joints.iter().map(|&j| node_name(j)).collect(),
                })
                .collect(),
            animations: self
                .clips
                .iter()
                .map(|c| ClipSummary {
                    name: c.name.clone(),
                    start: c.start,
                    end: c.end,
                    duration: c.duration(),
                    channels: c.channels.len(),
                })
                .collect(),
        }
    }
}
