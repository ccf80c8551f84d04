//! `pelt pose`: an asset in one pose of one clip, written as a static mesh. Every primitive
//! drawn by a skinned or morphed node gets POSITION, NORMAL and TANGENT posed on the CPU
//! (morph targets, then the skin's joint matrices), expressed in its node's space so the node
//! hierarchy stays as it is; every animated node gets its sampled transform. JOINTS_n,
//! WEIGHTS_n, morph targets, skins and animations are removed. `_FUR_COMB` stays as baked: it
//! is in tangent space, so the posed frame carries it (Revie §2.4.1); fins refer to corners,
//! so they follow the posed positions too.

use glam::{Mat4, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use pelt_io::edit::NewAccessor;
use pelt_io::{Document, IoError, PrimitiveRef, typed};
use serde::Serialize;
use serde_json::{Value, json};

use crate::pose::Pose;
use crate::rig::Rig;
use crate::skinning::{Influences, morph, transform};

/// What `pelt pose` did.
#[derive(Debug, Clone, Default, Serialize)]
pub struct PoseReport {
    /// The clip posed (None: the rest pose).
    pub animation: Option<String>,
    /// The time sampled, in seconds.
    pub time: f32,
    /// The clip's first and last key times.
    pub clip_range: Option<[f32; 2]>,
    /// Primitives whose vertices were posed.
    pub posed_primitives: usize,
    /// Vertices posed.
    pub posed_vertices: usize,
    /// Nodes given a sampled transform.
    pub animated_nodes: usize,
    /// Vertices whose weights did not sum to 1 and were normalized.
    pub normalized_weights: usize,
    /// Skinned vertices without any weight (left where their node puts them).
    pub unweighted_vertices: usize,
    /// Things the user should know.
    pub warnings: Vec<String>,
}

/// Poses `doc` in place at `time` seconds of the clip `animation` (the rest pose when None).
pub fn pose_document(
    doc: &mut Document,
    animation: Option<&str>,
    time: f32,
) -> Result<PoseReport, IoError> {
    let rig = Rig::load(doc)?;
    let clip = animation.map(|a| rig.clip(doc, a)).transpose()?;
    let pose = rig.pose(clip, time);
    let mut report = PoseReport {
        animation: clip.map(|c| c.name.clone()),
        time,
        clip_range: clip.map(|c| [c.start, c.end]),
        ..PoseReport::default()
    };
    let meshes = posed_meshes(doc, &rig)?;
    for (node, mesh) in meshes {
        pose_mesh(doc, &rig, &pose, node, mesh, &mut report)?;
    }
    report.animated_nodes = write_nodes(doc, &rig, &pose);
    strip_animation(doc);
    doc.prune_detached();
    if report.normalized_weights > 0 {
        report.warnings.push(format!(
            "{} vertices had weights that do not sum to 1; they were normalized",
            report.normalized_weights
        ));
    }
    if report.unweighted_vertices > 0 {
        report.warnings.push(format!(
            "{} skinned vertices have no weight; they stay where their node puts them",
            report.unweighted_vertices
        ));
    }
    Ok(report)
}

/// (node, mesh) for every mesh that moves (skinned or morphed); a moving mesh drawn by two
/// nodes is an error (posing would need a copy per node).
fn posed_meshes(doc: &Document, rig: &Rig) -> Result<Vec<(usize, usize)>, IoError> {
    let targets = |m: usize| {
        doc.array("meshes")
            .get(m)
            .and_then(|m| m.get("primitives"))
            .and_then(Value::as_array)
            .is_some_and(|ps| ps.iter().any(|p| p.get("targets").is_some()))
    };
    let mut out: Vec<(usize, usize)> = Vec::new();
    for &n in &rig.order {
        let node = &rig.nodes[n];
        let Some(m) = node.mesh else { continue };
        if node.skin.is_none() && !targets(m) {
            continue;
        }
        if let Some(&(other, _)) = out.iter().find(|(_, mm)| *mm == m) {
            return Err(doc.invalid(
                format!("nodes[{n}].mesh"),
                format!(
                    "mesh {m} moves and is also drawn by node {other}; pelt pose needs one \
                     node per skinned or morphed mesh"
                ),
            ));
        }
        out.push((n, m));
    }
    Ok(out)
}

/// Every primitive of `mesh`, drawn by `node`, ready to skin in `pose`.
fn mesh_jobs(
    doc: &Document,
    rig: &Rig,
    pose: &Pose,
    node: usize,
    mesh: usize,
) -> Result<Vec<SkinJob>, IoError> {
    let skin = rig.nodes[node].skin;
    let mats = skin.map(|s| rig.joint_matrices(s, pose));
    // Skinned vertices land in the scene's space; the node keeps its place in the hierarchy,
    // so they are written relative to it.
    let to_node = pose.global[node].inverse();
    if skin.is_some() && !to_node.is_finite() {
        return Err(doc.invalid(
            format!("nodes[{node}]"),
            "its transform in this pose is singular, so posed vertices cannot be placed under it",
        ));
    }
    let count = doc.array("meshes")[mesh]["primitives"]
        .as_array()
        .map_or(0, Vec::len);
    (0..count)
        .map(|p| {
            let r = PrimitiveRef { mesh, primitive: p };
            skin_job(doc, rig, pose, node, r, mats.as_deref(), to_node)
        })
        .collect()
}

fn pose_mesh(
    doc: &mut Document,
    rig: &Rig,
    pose: &Pose,
    node: usize,
    mesh: usize,
    report: &mut PoseReport,
) -> Result<(), IoError> {
    for job in mesh_jobs(doc, rig, pose, node, mesh)? {
        let r = job.primitive;
        let (positions, normals, tangents) = job.on_cpu(report);
        let mut pa = NewAccessor::f32(&positions);
        pa.min_max = true;
        let a = doc.push_accessor(pa);
        doc.set_attribute(r, "POSITION", a)?;
        if let Some(n) = normals {
            let a = doc.push_accessor(NewAccessor::f32(&n));
            doc.set_attribute(r, "NORMAL", a)?;
        }
        if let Some(t) = tangents {
            let a = doc.push_accessor(NewAccessor::f32(&t));
            doc.set_attribute(r, "TANGENT", a)?;
        }
        for set in 0.. {
            let j = doc.remove_attribute(r, &format!("JOINTS_{set}"))?;
            let w = doc.remove_attribute(r, &format!("WEIGHTS_{set}"))?;
            if j.is_none() && w.is_none() {
                break;
            }
        }
        remove_targets(doc, r);
        report.posed_primitives += 1;
        report.posed_vertices += positions.len();
    }
    if let Some(m) = doc.json.get_mut("meshes").and_then(|m| m.get_mut(mesh)) {
        if let Some(o) = m.as_object_mut() {
            o.shift_remove("weights");
        }
    }
    Ok(())
}

/// Posed (positions, normals, tangents) of one primitive.
pub type Posed = (Vec<[f32; 3]>, Option<Vec<[f32; 3]>>, Option<Vec<[f32; 4]>>);

/// One primitive ready to skin: its vertices after morphing, its joints and weights, and the
/// matrices of this pose. `pelt pose` skins it on the CPU ([`SkinJob::on_cpu`]); the
/// preview's skinning pass (shaders/skin.wgsl) does the same arithmetic on the GPU.
#[derive(Debug, Clone)]
pub struct SkinJob {
    /// The primitive.
    pub primitive: PrimitiveRef,
    /// Positions after morph targets, in the mesh's space.
    pub positions: Vec<Vec3>,
    /// Normals after morph targets (None: the primitive has none).
    pub normals: Option<Vec<Vec3>>,
    /// Tangents after morph targets, w the handedness (None: none).
    pub tangents: Option<Vec<Vec4>>,
    /// JOINTS_n / WEIGHTS_n (empty when the node has no skin).
    pub influences: Influences,
    /// Each joint's matrix in this pose, already taken into the node's space (None: the node
    /// has no skin, so vertices only morph).
    pub joints: Option<Vec<Mat4>>,
    /// Where a vertex with no weight goes (the node's own transform, in its space).
    pub unweighted: Mat4,
}

/// The job that poses primitive `r` of `node`: its attributes read, morphed by the pose's
/// weights, with the influences and joint matrices `mats` when the node has a skin.
fn skin_job(
    doc: &Document,
    rig: &Rig,
    pose: &Pose,
    node: usize,
    r: PrimitiveRef,
    mats: Option<&[Mat4]>,
    to_node: Mat4,
) -> Result<SkinJob, IoError> {
    let place = doc.place(r);
    let m = pelt_io::mesh::read_primitive(doc, r)?.mesh;
    let g = typed::document(doc)?;
    let prim = g
        .meshes()
        .nth(r.mesh)
        .and_then(|m| m.primitives().nth(r.primitive))
        .ok_or_else(|| doc.invalid(&place, "not found"))?;
    let mut positions = m.positions.clone();
    let mut normals = m.normals.clone();
    let mut tangents: Option<Vec<Vec3>> = m
        .tangents
        .as_ref()
        .map(|t| t.iter().map(|t| t.truncate()).collect());
    // Morph targets first (glTF: morphing happens before skinning).
    let targets = prim.morph_targets().len();
    if targets > 0 {
        let w = rig.morph_weights(node, pose, targets);
        let [dp, dn, dt] = target_deltas(doc, &place, &prim, positions.len())?;
        morph(&mut positions, &dp, &w);
        if let Some(n) = normals.as_mut() {
            morph(n, &dn, &w);
        }
        if let Some(t) = tangents.as_mut() {
            morph(t, &dt, &w);
        }
    }
    let influences = match mats {
        Some(mats) => skin_influences(doc, &place, &prim, positions.len(), mats.len())?,
        None => Influences::default(),
    };
    let tangents = tangents.map(|t| {
        t.iter()
            .enumerate()
            .map(|(v, t)| t.extend(m.tangents.as_ref().map_or(1.0, |o| o[v].w)))
            .collect()
    });
    Ok(SkinJob {
        primitive: r,
        positions,
        normals,
        tangents,
        influences,
        joints: mats.map(|ms| ms.iter().map(|j| to_node * *j).collect()),
        unweighted: to_node * pose.global[node],
    })
}

/// Reading the morph targets: each target's POSITION, NORMAL and TANGENT displacements (absent
/// ones `None`), checked to be float VEC3 with one element per vertex (`vertices`).
fn target_deltas(
    doc: &Document,
    place: &str,
    prim: &gltf::Primitive<'_>,
    vertices: usize,
) -> Result<[Vec<Option<Vec<Vec3>>>; 3], IoError> {
    let get = typed::buffers(doc);
    let read = |a: Option<gltf::Accessor<'_>>, what: &str, k: usize| {
        a.map(|a| {
            typed::check_kind(
                doc,
                &a,
                &format!("{place}.targets[{k}].{what}"),
                Dimensions::Vec3,
                &[DataType::F32],
            )?;
            let it = gltf::accessor::Iter::<[f32; 3]>::new(a, get.clone()).ok_or_else(|| {
                doc.invalid(format!("{place}.targets[{k}].{what}"), "cannot be read")
            })?;
            let v: Vec<Vec3> = it.map(Vec3::from).collect();
            if v.len() != vertices {
                return Err(doc.invalid(
                    format!("{place}.targets[{k}].{what}"),
                    format!("{} elements for {} vertices", v.len(), vertices),
                ));
            }
            Ok(v)
        })
        .transpose()
    };
    let mut dp = Vec::new();
    let mut dn = Vec::new();
    let mut dt = Vec::new();
    for (k, t) in prim.morph_targets().enumerate() {
        dp.push(read(t.positions(), "POSITION", k)?);
        dn.push(read(t.normals(), "NORMAL", k)?);
        dt.push(read(t.tangents(), "TANGENT", k)?);
    }
    Ok([dp, dn, dt])
}

/// Reading the skin's influences: every JOINTS_n/WEIGHTS_n pair of `prim`, checked (kinds,
/// one element per vertex, finite weights that are not negative, joints within the skin's
/// `joints`). A skinned primitive must have at least JOINTS_0 and WEIGHTS_0.
fn skin_influences(
    doc: &Document,
    place: &str,
    prim: &gltf::Primitive<'_>,
    vertices: usize,
    joints: usize,
) -> Result<Influences, IoError> {
    let reader = prim.reader(typed::buffers(doc));
    let mut influences = Influences::default();
    for set in 0u32.. {
        let (Some(ja), Some(wa)) = (
            prim.get(&gltf::Semantic::Joints(set)),
            prim.get(&gltf::Semantic::Weights(set)),
        ) else {
            break;
        };
        typed::check_kind(
            doc,
            &ja,
            &format!("{place}.attributes.JOINTS_{set}"),
            Dimensions::Vec4,
            &[DataType::U8, DataType::U16],
        )?;
        typed::check_kind(
            doc,
            &wa,
            &format!("{place}.attributes.WEIGHTS_{set}"),
            Dimensions::Vec4,
            &[DataType::F32, DataType::U8, DataType::U16],
        )?;
        let j: Vec<[u16; 4]> = reader
            .read_joints(set)
            .map(|j| j.into_u16().collect())
            .unwrap_or_default();
        let w: Vec<[f32; 4]> = reader
            .read_weights(set)
            .map(|w| w.into_f32().collect())
            .unwrap_or_default();
        if j.len() != vertices || w.len() != vertices {
            return Err(doc.invalid(
                format!("{place}.attributes.JOINTS_{set}"),
                format!(
                    "{} joints and {} weights for {} vertices",
                    j.len(),
                    w.len(),
                    vertices
                ),
            ));
        }
        if let Some(i) = w.iter().flatten().position(|x| !x.is_finite() || *x < 0.0) {
            return Err(doc.invalid(
                format!("{place}.attributes.WEIGHTS_{set}"),
                format!("vertex {}: weights must be finite and not negative", i / 4),
            ));
        }
        influences.joints.push(j);
        influences.weights.push(w);
    }
    if influences.joints.is_empty() {
        return Err(doc.invalid(
            place,
            "the node has a skin but the primitive has no JOINTS_0 and WEIGHTS_0",
        ));
    }
    if let Some(b) = influences.bad_joint(joints) {
        return Err(doc.invalid(
            format!("{place}.attributes.JOINTS_{}", b.set),
            format!(
                "vertex {} names joint {}, but the skin has {} joints",
                b.vertex, b.joint, joints
            ),
        ));
    }
    Ok(influences)
}

impl SkinJob {
    /// Skins the job on the CPU (the reference the GPU pass is tested against), counting
    /// normalized and unweighted vertices into `report`.
    pub fn on_cpu(&self, report: &mut PoseReport) -> Posed {
        let n_v = self.positions.len();
        let mut out_p = Vec::with_capacity(n_v);
        let mut out_n = self.normals.as_ref().map(|_| Vec::with_capacity(n_v));
        let mut out_t = self.tangents.as_ref().map(|_| Vec::with_capacity(n_v));
        for v in 0..n_v {
            let n = self.normals.as_ref().map_or(Vec3::Z, |n| n[v]);
            let t = self.tangents.as_ref().map_or(Vec4::X, |t| t[v]);
            let (p, n, t) = match &self.joints {
                Some(mats) => match self.influences.blend(v, mats) {
                    (Some(b), off) => {
                        report.normalized_weights += usize::from(off);
                        transform(&b, self.positions[v], n, t)
                    }
                    (None, _) => {
                        report.unweighted_vertices += 1;
                        // Unweighted: where the node itself would put it.
                        transform(&self.unweighted, self.positions[v], n, t)
                    }
                },
                None => (self.positions[v], n.normalize_or(n), t),
            };
            out_p.push(p.to_array());
            if let Some(o) = out_n.as_mut() {
                o.push(n.to_array());
            }
            if let Some(o) = out_t.as_mut() {
                o.push(t.to_array());
            }
        }
        (out_p, out_n, out_t)
    }
}

/// Every skinned or morphed primitive of `doc` ready to skin at `time` seconds of
/// `animation` (the rest pose when None), with the same checks `pelt pose` makes.
pub fn skin_jobs(
    doc: &Document,
    animation: Option<&str>,
    time: f32,
) -> Result<Vec<SkinJob>, IoError> {
    let rig = Rig::load(doc)?;
    let clip = animation.map(|a| rig.clip(doc, a)).transpose()?;
    let pose = rig.pose(clip, time);
    let mut jobs = Vec::new();
    for (node, mesh) in posed_meshes(doc, &rig)? {
        jobs.extend(mesh_jobs(doc, &rig, &pose, node, mesh)?);
    }
    Ok(jobs)
}

fn remove_targets(doc: &mut Document, r: PrimitiveRef) {
    let Some(prim) = doc
        .json
        .get_mut("meshes")
        .and_then(|m| m.get_mut(r.mesh))
        .and_then(|m| m.get_mut("primitives"))
        .and_then(|p| p.get_mut(r.primitive))
        .and_then(Value::as_object_mut)
    else {
        return;
    };
    let Some(targets) = prim.shift_remove("targets") else {
        return;
    };
    let used: Vec<usize> = targets
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(Value::as_object)
        .flat_map(|t| t.values().filter_map(Value::as_u64).map(|a| a as usize))
        .collect();
    doc.detach_accessors(used);
}

/// Writes the sampled transform of every animated node; returns how many.
fn write_nodes(doc: &mut Document, rig: &Rig, pose: &Pose) -> usize {
    let mut count = 0;
    for n in (0..rig.nodes.len()).filter(|&n| pose.animated[n]) {
        let Some(o) = doc
            .json
            .get_mut("nodes")
            .and_then(|a| a.get_mut(n))
            .and_then(Value::as_object_mut)
        else {
            continue;
        };
        let t = pose.trs[n];
        o.shift_remove("matrix");
        o.insert("translation".into(), json!(t.translation.to_array()));
        o.insert("rotation".into(), json!(t.rotation.to_array()));
        o.insert("scale".into(), json!(t.scale.to_array()));
        count += 1;
    }
    for o in doc
        .json
        .get_mut("nodes")
        .and_then(Value::as_array_mut)
        .into_iter()
        .flatten()
        .filter_map(Value::as_object_mut)
    {
        o.shift_remove("skin");
        o.shift_remove("weights");
    }
    count
}

/// Removes skins and animations, detaching the accessors they used.
fn strip_animation(doc: &mut Document) {
    let mut used = Vec::new();
    if let Some(skins) = doc.json.shift_remove("skins") {
        used.extend(
            skins
                .as_array()
                .into_iter()
                .flatten()
                .filter_map(|s| s.get("inverseBindMatrices")?.as_u64()),
        );
    }
    if let Some(anims) = doc.json.shift_remove("animations") {
        for s in anims
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(|a| a.get("samplers")?.as_array())
            .flatten()
        {
            used.extend(
                ["input", "output"]
                    .iter()
                    .filter_map(|k| s.get(*k)?.as_u64()),
            );
        }
    }
    doc.detach_accessors(used.into_iter().map(|a| a as usize));
}
