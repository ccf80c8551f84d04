//! Assets for the preview: a baked (or any) glTF/OBJ file flattened into one vertex and index
//! list in the asset's space (every node of the default scene, its transform applied), with
//! each primitive's base colour factor and `_NORMAL_GROUP` ID (0 when absent) per vertex. Also
//! built-in shapes (`builtin:cube`, `builtin:sphere`, `builtin:quad`) for test and benchmark
//! scenes; the cube's six faces are six normal groups, as a bake would give.

use std::path::{Path, PathBuf};

use glam::{Mat3, Mat4, Quat, Vec3, Vec4};
use pelt_io::contract::NORMAL_GROUP_ATTRIBUTE;
use pelt_io::{Document, IoError, PrimitiveRef, accessor};
use serde_json::Value;

use crate::fur::{self, FurData};
use crate::light::{KHR_LIGHTS_PUNCTUAL, Light, from_khr};
use crate::material::{Material, MaterialReader, Part};
use crate::skin::SkinBinding;
use crate::vertex::{FurVertex, Vertex};

// Items that moved below this module (the material reader's limit, the scene file's
// built-in prefix, the skin's pose): their old paths here keep working.
pub use crate::material::DEFAULT_MAX_TEXTURE;
pub use crate::scene::BUILTIN;
pub use crate::skin::PoseAt;

/// Why an asset could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum AssetError {
    /// Reading or decoding the file failed.
    #[error(transparent)]
    Io(#[from] IoError),
    /// A `builtin:` name that does not exist.
    #[error("{path}: unknown built-in shape (known: builtin:cube, builtin:sphere, builtin:quad)")]
    UnknownBuiltin {
        /// The name as written.
        path: String,
    },
    /// A `KHR_lights_punctual` light that is not valid.
    #[error("{}: {place}: {what}", path.display())]
    Light {
        /// The file.
        path: PathBuf,
        /// The node that places it.
        place: String,
        /// What is wrong, at the light's place in the extension's lights.
        what: String,
    },
    /// The asset has no triangles to draw.
    #[error("{}: no TRIANGLES primitive reachable from the scene's nodes", path.display())]
    Empty {
        /// The file.
        path: PathBuf,
    },
}

/// A drawable mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshData {
    /// Vertices in the asset's space.
    pub vertices: Vec<Vertex>,
    /// Triangle list.
    pub indices: Vec<u32>,
    /// The fur, when a primitive has a baked `_FUR_COMB`.
    pub fur: Option<FurData>,
    /// Runs of `indices` by material, covering every index in order.
    pub parts: Vec<Part>,
    /// The materials `parts` refer to (at least one).
    pub materials: Vec<Material>,
    /// Each drawn primitive (with NORMAL) and its first vertex in `vertices`.
    pub primitive_bases: Vec<(PrimitiveRef, u32)>,
    /// GPU skinning data, when the asset is skinned and loaded for it ([`skinned`]).
    pub skin: Option<std::sync::Arc<SkinBinding>>,
    /// What loading changed, each naming the file and the place (a texture halved to fit
    /// [`LoadOptions::max_texture`]).
    pub warnings: Vec<String>,
    /// The lights it places (glTF's `KHR_lights_punctual`), in its space.
    pub lights: Vec<Light>,
}

/// How assets load.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LoadOptions {
    /// Textures with a longer side are halved until they fit, while they decode.
    pub max_texture: u32,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            max_texture: DEFAULT_MAX_TEXTURE,
        }
    }
}

impl MeshData {
    /// A mesh of one untextured part.
    pub fn untextured(vertices: Vec<Vertex>, indices: Vec<u32>) -> MeshData {
        MeshData {
            parts: vec![Part {
                first: 0,
                count: indices.len() as u32,
                material: 0,
            }],
            vertices,
            indices,
            fur: None,
            materials: vec![Material::default()],
            primitive_bases: Vec::new(),
            skin: None,
            warnings: Vec::new(),
            lights: Vec::new(),
        }
    }

    /// Whether any material samples a texture.
    pub fn textured(&self) -> bool {
        self.materials.iter().any(Material::textured)
    }

    /// Axis-aligned bounds (min, max) of the vertices.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.vertices.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), v| (lo.min(v.position.into()), hi.max(v.position.into())),
        )
    }
}

/// An object's asset that failed to load (the error names the asset's resolved path).
#[derive(Debug, thiserror::Error)]
#[error("objects[{object}]: {source}")]
pub struct ObjectAssetError {
    /// Object index in the scene.
    pub object: usize,
    /// Its asset path.
    pub path: PathBuf,
    /// Why.
    #[source]
    pub source: AssetError,
}

/// Loads each distinct asset of `scene` once; returns the meshes and each object's index
/// into them. Objects are tinted by their scene colour in the shader, not here.
pub fn load_scene(
    scene: &crate::scene::Scene,
) -> Result<(Vec<MeshData>, Vec<usize>), ObjectAssetError> {
    load_scene_at(scene, None)
}

/// [`load_scene`] with every animated asset posed at `pose` (assets without animations are
/// drawn as they are; an animated asset without the clip is an error listing its clips).
pub fn load_scene_at(
    scene: &crate::scene::Scene,
    pose: Option<&PoseAt>,
) -> Result<(Vec<MeshData>, Vec<usize>), ObjectAssetError> {
    load_scene_with(scene, pose, LoadOptions::default())
}

/// [`load_scene_at`] with `opts`.
pub fn load_scene_with(
    scene: &crate::scene::Scene,
    pose: Option<&PoseAt>,
    opts: LoadOptions,
) -> Result<(Vec<MeshData>, Vec<usize>), ObjectAssetError> {
    let mut paths: Vec<&Path> = Vec::new();
    let mut meshes = Vec::new();
    let mut of = Vec::with_capacity(scene.objects.len());
    for (i, o) in scene.objects.iter().enumerate() {
        match paths.iter().position(|p| *p == o.asset.as_path()) {
            Some(k) => of.push(k),
            None => {
                let m = load_at_with(&o.asset, pose, opts).map_err(|source| ObjectAssetError {
                    object: i,
                    path: o.asset.clone(),
                    source,
                })?;
                paths.push(&o.asset);
                of.push(meshes.len());
                meshes.push(m);
            }
        }
    }
    Ok((meshes, of))
}

/// Loads `path`: a `builtin:` shape, an `.obj`, or a `.gltf`/`.glb`.
pub fn load(path: &Path) -> Result<MeshData, AssetError> {
    load_with(path, LoadOptions::default())
}

/// [`load`] with `opts`.
pub fn load_with(path: &Path, opts: LoadOptions) -> Result<MeshData, AssetError> {
    let name = path.to_string_lossy();
    if let Some(shape) = name.strip_prefix(BUILTIN) {
        return builtin(shape).ok_or_else(|| AssetError::UnknownBuiltin {
            path: name.into_owned(),
        });
    }
    flatten_with(&pelt_io::load(path)?, opts)
}

/// [`load`], posed at `pose` when the asset has animations (on the CPU, `pelt_anim::posed`:
/// the same skinning `pelt pose` writes), with its GPU skinning data ([`skinned`]) so later
/// poses are skinned by the renderer.
pub fn load_at(path: &Path, pose: Option<&PoseAt>) -> Result<MeshData, AssetError> {
    load_at_with(path, pose, LoadOptions::default())
}

/// [`load_at`] with `opts`.
pub fn load_at_with(
    path: &Path,
    pose: Option<&PoseAt>,
    opts: LoadOptions,
) -> Result<MeshData, AssetError> {
    let Some(pose) = pose.filter(|_| !path.to_string_lossy().starts_with(BUILTIN)) else {
        return load_with(path, opts);
    };
    skinned_with(&pelt_io::load(path)?, pose, opts)
}

/// `doc` (a rest document) posed at `pose` on the CPU, with the GPU skinning data attached when
/// the asset can be skinned there ([`crate::skin::binding`]): the renderer then skins the
/// mesh for each pose drawn, and the CPU pose gives the first frame's bounds.
pub fn skinned(doc: &Document, pose: &PoseAt) -> Result<MeshData, AssetError> {
    skinned_with(doc, pose, LoadOptions::default())
}

/// [`skinned`] with `opts`.
pub fn skinned_with(
    doc: &Document,
    pose: &PoseAt,
    opts: LoadOptions,
) -> Result<MeshData, AssetError> {
    let mut m = posed_with(doc, pose, opts)?;
    if let Some(mut b) = crate::skin::binding(doc, &m.primitive_bases)? {
        b.fins = m
            .fur
            .as_ref()
            .map(|f| f.fin_sources.clone())
            .unwrap_or_default();
        b.loaded = Some(pose.clone());
        m.skin = Some(std::sync::Arc::new(b));
    }
    Ok(m)
}

/// `doc` posed at `pose` (when it has animations) and flattened; `doc` itself is unchanged,
/// so a viewer keeps one document and poses it frame after frame.
pub fn posed(doc: &Document, pose: &PoseAt) -> Result<MeshData, AssetError> {
    posed_with(doc, pose, LoadOptions::default())
}

/// [`posed`] with `opts`.
pub fn posed_with(
    doc: &Document,
    pose: &PoseAt,
    opts: LoadOptions,
) -> Result<MeshData, AssetError> {
    if doc.array("animations").is_empty() {
        return flatten_with(doc, opts);
    }
    let mut doc = doc.clone();
    pelt_anim::posed::pose_document(&mut doc, Some(&pose.animation), pose.time)?;
    flatten_with(&doc, opts)
}

/// A built-in shape by name (`cube`, `sphere`, `quad`), white; the closed shapes are
/// single-sided, the quad double-sided.
pub fn builtin(name: &str) -> Option<MeshData> {
    match name {
        "cube" => Some(cube()),
        "sphere" => Some(sphere(24, 48)),
        "quad" => Some(quad()),
        _ => None,
    }
}

fn vertex(p: Vec3, n: Vec3, group: u32) -> Vertex {
    Vertex {
        position: p.into(),
        normal: n.into(),
        albedo: [1.0; 4],
        group,
        uv: [0.0; 2],
    }
}

/// A unit cube (−0.5..0.5), 24 vertices, one normal group per face (IDs 1..6).
fn cube() -> MeshData {
    let mut m = MeshData::untextured(Vec::new(), Vec::new());
    for (face, n) in [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ]
    .into_iter()
    .enumerate()
    {
        let u = if n.y.abs() > 0.5 { Vec3::X } else { Vec3::Y };
        let v = n.cross(u);
        let base = m.vertices.len() as u32;
        for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let p = 0.5 * (n + a * u + b * v);
            m.vertices.push(vertex(p, n, face as u32 + 1));
        }
        // Counter-clockwise seen from outside: (u, v, n) is right-handed.
        m.indices
            .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    m.parts[0].count = m.indices.len() as u32;
    m
}

/// A unit quad in the XY plane (−0.5..0.5) facing +Z, one normal group, double-sided.
pub fn quad() -> MeshData {
    let vertices = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
        .into_iter()
        .map(|(x, y)| vertex(Vec3::new(x, y, 0.0), Vec3::Z, 1))
        .collect();
    let mut m = MeshData::untextured(vertices, vec![0, 1, 2, 0, 2, 3]);
    // A plane is seen from both sides (a floor from below, a card from behind).
    m.materials[0].double_sided = true;
    m
}

/// A UV sphere of radius 0.5, one normal group.
fn sphere(rings: u32, segs: u32) -> MeshData {
    let mut vertices = Vec::new();
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=segs {
            let phi = std::f32::consts::TAU * s as f32 / segs as f32;
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            );
            vertices.push(vertex(0.5 * n, n, 1));
        }
    }
    let mut indices = Vec::new();
    let row = segs + 1;
    for r in 0..rings {
        for s in 0..segs {
            let (a, b) = (r * row + s, (r + 1) * row + s);
            indices.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    MeshData::untextured(vertices, indices)
}

/// The local matrix of a node (`matrix`, or TRS).
fn node_matrix(node: &Value) -> Mat4 {
    let floats = |key: &str, n: usize| -> Option<Vec<f32>> {
        let a = node.get(key)?.as_array()?;
        let v: Vec<f32> = a
            .iter()
            .filter_map(|x| x.as_f64().map(|f| f as f32))
            .collect();
        (v.len() == n && v.iter().all(|f| f.is_finite())).then_some(v)
    };
    if let Some(m) = floats("matrix", 16) {
        return Mat4::from_cols_slice(&m);
    }
    let t = floats("translation", 3).map_or(Vec3::ZERO, |v| Vec3::from_slice(&v));
    let r = floats("rotation", 4).map_or(Quat::IDENTITY, |v| Quat::from_slice(&v).normalize());
    let s = floats("scale", 3).map_or(Vec3::ONE, |v| Vec3::from_slice(&v));
    Mat4::from_scale_rotation_translation(s, r, t)
}

/// Every (mesh, world matrix) reachable from the default scene (or every root node when the
/// file has no scene).
fn mesh_instances(doc: &Document) -> Vec<(usize, Mat4)> {
    let nodes = doc.array("nodes");
    node_worlds(doc)
        .into_iter()
        .filter_map(|(i, world)| {
            let m = nodes[i].get("mesh").and_then(Value::as_u64)?;
            Some((m as usize, world))
        })
        .collect()
}

/// The `KHR_lights_punctual` lights the nodes reachable from the default scene place, in
/// the asset's space. A light that is not valid is an error naming the file and the light's
/// place.
fn lights(doc: &Document) -> Result<Vec<Light>, AssetError> {
    let nodes = doc.array("nodes");
    let defs = doc
        .json
        .get("extensions")
        .and_then(|e| e.get(KHR_LIGHTS_PUNCTUAL)?.get("lights")?.as_array());
    let mut out = Vec::new();
    for (i, world) in node_worlds(doc) {
        let Some(k) = nodes[i]
            .pointer(&format!("/extensions/{KHR_LIGHTS_PUNCTUAL}/light"))
            .map(Value::as_u64)
        else {
            continue;
        };
        let bad = |what: String| AssetError::Light {
            path: doc.path.clone(),
            place: format!("nodes[{i}].extensions.{KHR_LIGHTS_PUNCTUAL}"),
            what,
        };
        let Some(def) = k.and_then(|k| defs?.get(usize::try_from(k).ok()?)) else {
            return Err(bad("light: names no light of the extension's lights".into()));
        };
        let at = format!("lights[{}]", k.unwrap_or_default());
        out.push(from_khr(def, world).map_err(|e| bad(format!("{at}.{e}")))?);
    }
    Ok(out)
}

/// Every (node, world matrix) reachable from the default scene (or every root node when the
/// file has no scene), depth first. Cycles and absurd depths are cut off.
fn node_worlds(doc: &Document) -> Vec<(usize, Mat4)> {
    let nodes = doc.array("nodes");
    let scene = doc.json.get("scene").and_then(Value::as_u64).unwrap_or(0) as usize;
    let roots: Vec<usize> = match doc.array("scenes").get(scene) {
        Some(s) => s
            .get("nodes")
            .and_then(Value::as_array)
            .map(|a| {
                a.iter()
                    .filter_map(|v| v.as_u64().map(|i| i as usize))
                    .collect()
            })
            .unwrap_or_default(),
        None => {
            // No scene: nodes that are nobody's child.
            let mut is_child = vec![false; nodes.len()];
            for n in nodes {
                for c in n
                    .get("children")
                    .and_then(Value::as_array)
                    .into_iter()
                    .flatten()
                {
                    if let Some(c) = c.as_u64().and_then(|c| is_child.get_mut(c as usize)) {
                        *c = true;
                    }
                }
            }
            (0..nodes.len()).filter(|&i| !is_child[i]).collect()
        }
    };
    let mut out = Vec::new();
    let mut visited = vec![false; nodes.len()];
    let mut stack: Vec<(usize, Mat4)> = roots
        .into_iter()
        .rev()
        .map(|r| (r, Mat4::IDENTITY))
        .collect();
    while let Some((i, parent)) = stack.pop() {
        let Some(node) = nodes.get(i) else { continue };
        if std::mem::replace(&mut visited[i], true) {
            continue;
        }
        let world = parent * node_matrix(node);
        out.push((i, world));
        for c in node
            .get("children")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
            .rev()
        {
            if let Some(c) = c.as_u64() {
                stack.push((c as usize, world));
            }
        }
    }
    out
}

/// The linear base colour factor of the primitive's material (white without one).
fn base_color(doc: &Document, r: PrimitiveRef) -> Result<[f32; 4], IoError> {
    let Some(m) = doc.primitive(r)?.get("material").and_then(Value::as_u64) else {
        return Ok([1.0; 4]);
    };
    let factor = doc
        .array("materials")
        .get(m as usize)
        .and_then(|m| m.get("pbrMetallicRoughness"))
        .and_then(|p| p.get("baseColorFactor"))
        .and_then(Value::as_array);
    let Some(f) = factor else { return Ok([1.0; 4]) };
    let v: Vec<f32> = f
        .iter()
        .filter_map(|x| x.as_f64().map(|x| x as f32))
        .collect();
    match <[f32; 4]>::try_from(v) {
        Ok(c) if c.iter().all(|x| (0.0..=1.0).contains(x)) => Ok(c),
        _ => Err(doc.invalid(
            format!("materials[{m}].pbrMetallicRoughness.baseColorFactor"),
            "must be 4 numbers in 0..1",
        )),
    }
}

/// `_NORMAL_GROUP` of the primitive, checked against its vertex count (None when absent).
fn normal_groups(doc: &Document, r: PrimitiveRef, n: usize) -> Result<Option<Vec<u32>>, IoError> {
    let Some(i) = doc.attribute(r, NORMAL_GROUP_ATTRIBUTE)? else {
        return Ok(None);
    };
    let place = format!("{} attribute {NORMAL_GROUP_ATTRIBUTE}", doc.place(r));
    let e = accessor::read(doc, i, &place)?;
    if e.components != 1 || e.count != n {
        return Err(doc.invalid(
            place,
            format!(
                "must be SCALAR with one value per vertex ({n}), found {} × {}",
                e.ty, e.count
            ),
        ));
    }
    Ok(Some(
        (0..n)
            .map(|k| (e.component_f32(k).round() as u32).min(255))
            .collect(),
    ))
}

/// Flattens every TRIANGLES primitive of every mesh instance into one mesh, with the fur
/// of primitives that have a baked comb.
pub fn flatten(doc: &Document) -> Result<MeshData, AssetError> {
    flatten_with(doc, LoadOptions::default())
}

/// [`flatten`] with `opts`.
pub fn flatten_with(doc: &Document, opts: LoadOptions) -> Result<MeshData, AssetError> {
    let mut out = MeshData::untextured(Vec::new(), Vec::new());
    out.parts.clear();
    out.materials.clear();
    let mut reader = MaterialReader::with_max_texture(opts.max_texture);
    let mut fur = FurGathered::default();
    for (mesh, world) in mesh_instances(doc) {
        let normal_world = Mat3::from_mat4(world).inverse().transpose();
        let flips = world.determinant() < 0.0;
        for r in doc.primitives().into_iter().filter(|r| r.mesh == mesh) {
            if !pelt_io::triangles::is_triangles(doc.mode(r)?) {
                continue;
            }
            let p = pelt_io::mesh::read_primitive(doc, r)?;
            let m = &p.mesh;
            let albedo = base_color(doc, r)?;
            let groups = normal_groups(doc, r, m.vertex_count())?;
            let material = reader.index(doc, doc.primitive_material(r)?)?;
            let read = &reader.read[material as usize].1;
            let mut uvs = texcoords(doc, r, read.tex_coord, m)?;
            if let (Some(t), Some(uvs)) = (read.uv_transform, uvs.as_mut()) {
                uvs.iter_mut().for_each(|uv| *uv = t.apply(*uv));
            }
            let uv = |k: usize| uvs.as_ref().map_or([0.0; 2], |u| u[k]);
            let base = out.vertices.len() as u32;
            let first = out.indices.len() as u32;
            match &m.normals {
                Some(normals) => {
                    out.primitive_bases.push((r, base));
                    push_smooth(
                        &mut out,
                        m,
                        normals,
                        (world, normal_world, flips),
                        (albedo, groups.as_deref(), &uv),
                    );
                    let read = &reader.read[material as usize].1;
                    let at = (base as usize, world);
                    fur.primitive((doc, r), m, normals, &out.vertices, at, read)?;
                }
                None => {
                    // glTF: no NORMAL means flat shading. One vertex per corner; no fur.
                    push_flat(
                        &mut out,
                        m,
                        (world, flips),
                        (albedo, groups.as_deref(), &uv),
                    );
                    fur.vertices.resize(out.vertices.len(), FurVertex::NONE);
                }
            }
            push_part(&mut out.parts, first, out.indices.len() as u32, material);
        }
    }
    out.warnings = std::mem::take(&mut reader.warnings);
    out.warnings.append(&mut fur.warnings);
    let file = doc.path.display();
    let collapsed = pelt_io::nodes::collapsed(doc);
    out.warnings
        .extend(collapsed.iter().map(|w| format!("{file}: {w}")));
    if fur.without_uvs {
        out.warnings.push(format!(
            "{file}: a furred primitive has no TEXCOORD_0: the fur's strand textures are laid \
             out by it, so shells draw untextured fur and the strand reference grows no strands"
        ));
    }
    out.materials = reader.read.into_iter().map(|(_, m)| m).collect();
    if out.indices.is_empty() {
        return Err(AssetError::Empty {
            path: doc.path.clone(),
        });
    }
    if fur.any_comb {
        out.fur = Some(fur_data(doc, fur)?);
    }
    out.lights = lights(doc)?;
    Ok(out)
}

/// The fur gathered over an asset's primitives while they are flattened.
#[derive(Default)]
struct FurGathered {
    /// One per flattened vertex ([`FurVertex::NONE`] where there is no fur).
    vertices: Vec<FurVertex>,
    /// The fins of every furred primitive.
    fins: Vec<crate::vertex::FinInstance>,
    /// Where each fin came from (for skinning).
    fin_sources: Vec<crate::skin::FinSource>,
    /// The first furred primitive's fur manifest, if it has one.
    manifest: Option<(pelt_fur::FurManifest, String)>,
    /// Whether any primitive has a comb.
    any_comb: bool,
    /// Whether a furred primitive has no TEXCOORD_0.
    without_uvs: bool,
    /// What reading the fur noted (a lost contract, regenerated tangents, fins).
    warnings: Vec<String>,
}

impl FurGathered {
    /// The fur step of a primitive with NORMAL, its vertices already flattened into `verts`
    /// from `base` by `world`: its comb (if any), tangents regenerated where the stored ones
    /// do not match the bake, the fur vertices and the fins.
    fn primitive(
        &mut self,
        (doc, r): (&Document, PrimitiveRef),
        m: &pelt_geom::Mesh,
        normals: &[Vec3],
        verts: &[Vertex],
        (base, world): (usize, Mat4),
        material: &Material,
    ) -> Result<(), AssetError> {
        let comb = fur::read_comb(doc, r, m.vertex_count())?;
        self.warnings
            .extend(fur::lost_contract(doc, r, comb.is_some())?);
        if comb.is_some() {
            self.any_comb = true;
            self.without_uvs |= m.uvs.is_none();
            if self.manifest.is_none() {
                self.manifest = fur::manifest(doc, r)?;
            }
        }
        let mut tangents = None;
        if comb.is_some()
            && let Some((t, note)) = crate::tangents::regenerate(doc, r, m)?
        {
            self.warnings.push(note);
            tangents = Some(t);
        }
        self.vertices.extend(fur::fur_vertices(
            world,
            normals,
            tangents.as_deref().or(m.tangents.as_deref()),
            m.uvs.as_deref(),
            comb.as_deref(),
        ));
        if comb.is_some() {
            let (f, sources) = fur::fin_instances(
                (doc, r),
                m,
                verts,
                &self.vertices,
                (base, world),
                material,
                &mut self.warnings,
            )?;
            self.fins.extend(f);
            self.fin_sources.extend(sources);
        }
        Ok(())
    }
}

/// What a flattened vertex takes besides its place: the primitive's albedo, its normal groups
/// and its texture coordinates, by source vertex.
type VertexLook<'a> = ([f32; 4], Option<&'a [u32]>, &'a dyn Fn(usize) -> [f32; 2]);

/// A primitive with NORMAL: its vertices placed in the world (normals by `normal_world`)
/// and its triangles, wound the other way where `world` mirrors (`flips`).
fn push_smooth(
    out: &mut MeshData,
    m: &pelt_geom::Mesh,
    normals: &[Vec3],
    (world, normal_world, flips): (Mat4, Mat3, bool),
    (albedo, groups, uv): VertexLook,
) {
    let base = out.vertices.len() as u32;
    for (k, (&pos, &n)) in m.positions.iter().zip(normals).enumerate() {
        out.vertices.push(Vertex {
            position: world.transform_point3(pos).into(),
            normal: (normal_world * n).normalize_or_zero().into(),
            albedo,
            group: groups.map_or(0, |g| g[k]),
            uv: uv(k),
        });
    }
    for t in m.indices.chunks_exact(3) {
        let t = if flips {
            [t[0], t[2], t[1]]
        } else {
            [t[0], t[1], t[2]]
        };
        out.indices.extend(t.map(|i| base + i));
    }
}

/// A primitive without NORMAL, flat shaded as glTF says: one vertex per corner, with its
/// face's world normal, wound the other way where `world` mirrors (`flips`).
fn push_flat(
    out: &mut MeshData,
    m: &pelt_geom::Mesh,
    (world, flips): (Mat4, bool),
    (albedo, groups, uv): VertexLook,
) {
    for t in m.indices.chunks_exact(3) {
        let c = [t[0], t[1], t[2]].map(|i| world.transform_point3(m.positions[i as usize]));
        let mut n = (c[1] - c[0]).cross(c[2] - c[0]).normalize_or_zero();
        if flips {
            n = -n;
        }
        let order = if flips { [0, 2, 1] } else { [0, 1, 2] };
        for k in order {
            out.indices.push(out.vertices.len() as u32);
            out.vertices.push(Vertex {
                position: c[k].into(),
                normal: n.into(),
                albedo,
                group: groups.map_or(0, |g| g[t[k] as usize]),
                uv: uv(t[k] as usize),
            });
        }
    }
}

/// The asset's fur, once every primitive is read: its look, textures and strand model (the
/// manifest's, or generated), with the fur vertices and fins gathered.
fn fur_data(doc: &Document, gathered: FurGathered) -> Result<FurData, AssetError> {
    let FurGathered {
        vertices,
        fins,
        fin_sources,
        manifest,
        ..
    } = gathered;
    let (look, (heightfield, fin), source) = fur::look_and_textures(doc, manifest.as_ref())?;
    let model = manifest
        .as_ref()
        .map_or_else(fur::generated_model, |(m, _)| m.strands.clone());
    Ok(FurData {
        vertices,
        fins,
        fin_sources,
        look,
        heightfield,
        fin,
        source,
        density: fur::density_of(&model),
        model,
    })
}

/// Extends `parts` with indices `first..end` drawn with `material` (merged into the last
/// part when that one uses the same material).
fn push_part(parts: &mut Vec<Part>, first: u32, end: u32, material: u32) {
    match parts.last_mut() {
        Some(p) if p.material == material && p.first + p.count == first => p.count = end - p.first,
        _ if end > first => parts.push(Part {
            first,
            count: end - first,
            material,
        }),
        _ => {}
    }
}

/// TEXCOORD_`set` of the primitive (checked against its vertex count; None when absent).
fn texcoords(
    doc: &Document,
    r: PrimitiveRef,
    set: u32,
    m: &pelt_geom::Mesh,
) -> Result<Option<Vec<[f32; 2]>>, IoError> {
    if set == 0 {
        return Ok(m
            .uvs
            .as_ref()
            .map(|u| u.iter().map(|&v| v.into()).collect()));
    }
    let name = format!("TEXCOORD_{set}");
    let Some(i) = doc.attribute(r, &name)? else {
        return Err(doc.invalid(
            format!("{} attribute {name}", doc.place(r)),
            "is named by the primitive's material but missing",
        ));
    };
    let place = format!("{} attribute {name}", doc.place(r));
    let uvs = accessor::read_vec::<2>(doc, i, &place)?;
    if uvs.len() != m.vertex_count() {
        return Err(doc.invalid(
            place,
            format!(
                "has {} elements, POSITION has {}",
                uvs.len(),
                m.vertex_count()
            ),
        ));
    }
    Ok(Some(uvs))
}

/// Albedo of every vertex replaced (`builtin:` shapes are white; scenes tint them).
pub fn tinted(mut m: MeshData, albedo: Vec4) -> MeshData {
    for v in &mut m.vertices {
        v.albedo = albedo.into();
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outward_winding(m: &MeshData) -> bool {
        m.indices.chunks_exact(3).all(|t| {
            let p = [t[0], t[1], t[2]].map(|i| Vec3::from(m.vertices[i as usize].position));
            let n = Vec3::from(m.vertices[t[0] as usize].normal);
            (p[1] - p[0]).cross(p[2] - p[0]).dot(n) > 0.0
        })
    }

    #[test]
    fn builtins_are_closed_outward_and_grouped() {
        let c = builtin("cube").expect("cube");
        assert_eq!((c.vertices.len(), c.indices.len()), (24, 36));
        assert!(outward_winding(&c));
        let mut groups: Vec<u32> = c.vertices.iter().map(|v| v.group).collect();
        groups.dedup();
        assert_eq!(groups, vec![1, 2, 3, 4, 5, 6]);
        assert_eq!(c.bounds(), (Vec3::splat(-0.5), Vec3::splat(0.5)));
        let s = builtin("sphere").expect("sphere");
        assert!(outward_winding(&s.clone_without_poles()));
        assert!(outward_winding(&builtin("quad").expect("quad")));
        assert!(matches!(
            load(Path::new("builtin:teapot")),
            Err(AssetError::UnknownBuiltin { .. })
        ));
    }

    impl MeshData {
        /// The sphere without its degenerate pole triangles.
        fn clone_without_poles(&self) -> MeshData {
            let indices = self
                .indices
                .chunks_exact(3)
                .filter(|t| {
                    let p =
                        [t[0], t[1], t[2]].map(|i| Vec3::from(self.vertices[i as usize].position));
                    (p[1] - p[0]).cross(p[2] - p[0]).length() > 1e-7
                })
                .flatten()
                .copied()
                .collect();
            MeshData::untextured(self.vertices.clone(), indices)
        }
    }

    #[test]
    fn the_fox_reads_its_base_colour_texture_and_uvs() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        let m = load(&root.join("fox/Fox.glb")).expect("fox");
        assert_eq!(m.materials.len(), 1);
        let mat = &m.materials[0];
        let t = mat.base_color.as_ref().expect("baseColorTexture");
        assert!(t.image.width >= 64 && t.image.height >= 64);
        assert!(mat.normal.is_none() && mat.metallic_roughness.is_none());
        assert!((mat.roughness - 0.58).abs() < 1e-6 && mat.metallic == 0.0);
        assert_eq!(m.parts.len(), 1);
        assert_eq!(m.parts[0].count as usize, m.indices.len());
        assert!(
            m.vertices
                .iter()
                .all(|v| v.uv.iter().all(|c| (0.0..=1.0).contains(c)))
        );
        let spread = m.vertices.iter().fold((1.0f32, 0.0f32), |(lo, hi), v| {
            (lo.min(v.uv[0]), hi.max(v.uv[0]))
        });
        assert!(
            spread.1 - spread.0 > 0.5,
            "UVs span the texture: {spread:?}"
        );
        // The texture is mostly orange: red well above blue on average.
        let (mut r, mut b) = (0u64, 0u64);
        for p in t.image.pixels.chunks_exact(4) {
            r += u64::from(p[0]);
            b += u64::from(p[2]);
        }
        assert!(r > b + b / 2, "red {r} blue {b}");
    }

    #[test]
    fn a_missing_texcoord_set_or_an_undecodable_image_is_an_error_naming_the_place() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        let fox = pelt_io::load(&root.join("fox/Fox.glb")).expect("fox");
        // The base colour texture names TEXCOORD_1, which the primitive does not have.
        let mut doc = fox.clone();
        doc.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] =
            serde_json::json!(1);
        let e = flatten(&doc).expect_err("no TEXCOORD_1").to_string();
        assert!(e.contains("TEXCOORD_1") && e.contains("meshes[0]"), "{e}");
        // The image's bytes are the positions, not a PNG or JPEG.
        let mut doc = fox;
        doc.json["images"][0]["bufferView"] = serde_json::json!(0);
        let e = flatten(&doc).expect_err("not an image").to_string();
        assert!(e.contains("images[0]") && e.contains("PNG"), "{e}");
    }

    /// The sphere fixture with `lights` (KHR_lights_punctual's definitions) placed by one new
    /// root node each: `(light index as written, node fields)`.
    fn sphere_lit(lights: Value, nodes: &[(Value, Value)]) -> Document {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        let mut doc = pelt_io::load(&root.join("sphere.glb")).expect("sphere");
        doc.json
            .entry("extensions")
            .or_insert_with(|| serde_json::json!({}))[KHR_LIGHTS_PUNCTUAL] =
            serde_json::json!({ "lights": lights });
        let scene = doc.json.get("scene").and_then(Value::as_u64).unwrap_or(0) as usize;
        for (light, fields) in nodes {
            let n = doc.array("nodes").len();
            let mut node = fields.clone();
            node["extensions"] = serde_json::json!({ KHR_LIGHTS_PUNCTUAL: { "light": light } });
            doc.json["nodes"].as_array_mut().expect("nodes").push(node);
            doc.json["scenes"][scene]["nodes"]
                .as_array_mut()
                .expect("scene nodes")
                .push(serde_json::json!(n));
        }
        doc
    }

    #[test]
    fn khr_lights_punctual_are_placed_by_their_nodes_and_a_bad_one_is_named() {
        use crate::light::Emitter;
        use serde_json::json;
        let lights = json!([
            {"type": "point", "color": [1, 0.5, 0.25], "intensity": 4, "range": 3},
            {"type": "directional", "intensity": 2},
            {"type": "point", "intensity": 1}
        ]);
        // A quarter turn about x turns the sun node's −z axis down.
        let q = Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2);
        let nodes = [
            (json!(0), json!({"translation": [1, 2, 3]})),
            (json!(1), json!({"rotation": [q.x, q.y, q.z, q.w]})),
            (json!(2), json!({})),
        ];
        let m = flatten(&sphere_lit(lights.clone(), &nodes)).expect("lit sphere");
        assert_eq!(m.lights.len(), 3, "{:?}", m.lights);
        assert_eq!(
            m.lights[0].emitter,
            Emitter::Point {
                position: Vec3::new(1.0, 2.0, 3.0),
                radius: 3.0
            }
        );
        assert_eq!(
            (m.lights[0].color, m.lights[0].intensity.0),
            ([1.0, 0.5, 0.25], 4.0)
        );
        let Emitter::Directional { direction } = m.lights[1].emitter else {
            panic!("a sun: {:?}", m.lights[1]);
        };
        assert!(direction.abs_diff_eq(Vec3::NEG_Y, 1e-6), "{direction}");
        // No range: it reaches where 1/(1 + d²) falls to 1/256.
        assert_eq!(m.lights[2].emitter.radius(), Some(255.0_f32.sqrt()));
        assert!(m.lights.iter().all(|l| !l.shadows));
        // Without the extension there are none (the negative control).
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        assert!(
            load(&root.join("sphere.glb"))
                .expect("sphere")
                .lights
                .is_empty()
        );
        // A node naming no light, and a light with a bad field, are errors at their places.
        for (bad, nodes, says) in [
            (
                lights.clone(),
                vec![(json!(7), json!({}))],
                "names no light",
            ),
            (
                json!([{"type": "area"}]),
                vec![(json!(0), json!({}))],
                "lights[0].type",
            ),
            (
                json!([{"type": "point", "range": -1}]),
                vec![(json!(0), json!({}))],
                "lights[0].range",
            ),
        ] {
            let e = flatten(&sphere_lit(bad, &nodes))
                .expect_err(says)
                .to_string();
            assert!(
                e.contains("sphere.glb") && e.contains("nodes[") && e.contains(says),
                "{e}"
            );
        }
    }

    #[test]
    fn parts_merge_runs_of_one_material() {
        let mut parts = Vec::new();
        push_part(&mut parts, 0, 6, 0);
        push_part(&mut parts, 6, 12, 0);
        push_part(&mut parts, 12, 12, 1);
        push_part(&mut parts, 12, 15, 1);
        push_part(&mut parts, 15, 18, 0);
        let got: Vec<_> = parts
            .iter()
            .map(|p| (p.first, p.count, p.material))
            .collect();
        assert_eq!(got, vec![(0, 12, 0), (12, 3, 1), (15, 3, 0)]);
    }

    #[test]
    fn baked_fixture_keeps_groups_and_colors() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        let m = load(&root.join("torus.glb")).expect("torus");
        assert!(!m.indices.is_empty() && m.indices.len().is_multiple_of(3));
        assert!(m.indices.iter().all(|&i| (i as usize) < m.vertices.len()));
        assert!(
            m.vertices
                .iter()
                .all(|v| Vec3::from(v.normal).is_normalized())
        );
    }

    /// Six times the signed volume `m`'s triangles enclose (positive when they face out).
    fn signed_volume(m: &MeshData) -> f32 {
        m.indices
            .chunks_exact(3)
            .map(|t| {
                let p = [t[0], t[1], t[2]].map(|i| Vec3::from(m.vertices[i as usize].position));
                p[0].dot(p[1].cross(p[2]))
            })
            .sum()
    }

    #[test]
    fn closed_shapes_face_out_and_say_which_sides_are_drawn() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        // glTF's default is single-sided; the committed closed fixtures face out, so culling
        // their back faces hides nothing.
        for name in ["sphere.glb", "torus.glb", "creature.glb"] {
            let m = load(&root.join(name)).expect(name);
            assert!(signed_volume(&m) > 0.0, "{name} faces out");
            assert!(m.materials.iter().all(|x| !x.double_sided), "{name}");
        }
        for name in ["sphere", "cube"] {
            let m = builtin(name).expect(name);
            assert!(signed_volume(&m) > 0.0, "builtin {name} faces out");
            assert!(!m.materials[0].double_sided, "builtin {name}");
        }
        // A plane is seen from both sides, and OBJ states no facing at all.
        assert!(builtin("quad").expect("quad").materials[0].double_sided);
        let obj = load(&root.join("edge/painted.obj")).expect("obj");
        assert!(!obj.materials.is_empty());
        assert!(obj.materials.iter().all(|x| x.double_sided), "OBJ");
    }
}
