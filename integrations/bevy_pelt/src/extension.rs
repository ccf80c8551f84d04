//! The `PELT_fur` glTF extension (docs/extension/PELT_fur) read as Bevy's glTF loader loads a
//! file: a `GltfExtensionHandler` that decodes each fur primitive with pelt's own reader
//! (`pelt_io`'s document and comb decode, `pelt_scene::fur`'s manifest, `pelt_fur`'s
//! density), keeps it as a labelled sub-asset of the glTF ([`PeltFurData`]) and tags the
//! primitive's entity in the glTF's scenes with [`PeltFur`]. Bevy's loader drops `_FUR_COMB`
//! (a custom attribute it is not told of, in whichever of the extension's four encodings);
//! [`crate::attach`] adds the decoded comb to the mesh.

use std::path::Path;
use std::sync::Arc;

use bevy::asset::LoadContext;
use bevy::ecs::world::EntityWorldMut;
use bevy::gltf::extensions::{ErasedGltfExtensionHandler, GltfExtensionHandler};
use bevy::gltf::gltf;
use bevy::mesh::MeshVertexAttribute;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::tasks::ConditionalSendFuture;
use gltf_crate::Semantic as GltfSemantic;
use pelt_fur::density::Density;
use pelt_io::topology::StoredFins;
use pelt_io::{Document, PrimitiveRef};
use pelt_scene::fur::{FurLook, Level};

/// The extension's name.
pub use pelt_io::extension::EXTENSION;

/// One fur primitive as pelt decodes it.
#[derive(Asset, TypePath, Debug, Clone)]
pub struct PeltFurData {
    /// `FILE meshes[m].primitives[p]`, for messages.
    pub place: String,
    /// The decoded comb, one per vertex (xyz tangent space, w the comb length).
    pub comb: Vec<[f32; 4]>,
    /// The manifest's look (`pelt_scene::fur::look_of`): length, shells and their rule, UV
    /// scale, colours.
    pub look: FurLook,
    /// The strand model as a medium (shared by the primitives of one material).
    pub density: Arc<Density>,
    /// Where TANGENT came from (`kept`, `mikktspace`, `gradient`): how to regenerate it.
    pub tangents: String,
    /// The fin records as edges (empty without records, or with stale ones).
    pub fins: Vec<FinEdge>,
    /// The fin texture's levels (RGBA8: R height along the strand, A coverage), shared by
    /// the primitives of one material.
    pub fin_texture: Arc<Vec<Level<[u8; 4]>>>,
}

/// One fin: an edge of the mesh with fur at an end (docs/extension/PELT_fur, fin records).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FinEdge {
    /// Its two vertices (indices into the mesh), in its first face's winding.
    pub ends: [u32; 2],
    /// The geometric normals of its two faces (the first twice on a boundary), mesh space.
    pub faces: [[f32; 3]; 2],
    /// The fin texture's horizontal offset for the edge (`pelt_scene::fur::edge_offset`) and
    /// the edge's length in UV units.
    pub u: [f32; 2],
}

/// The primitive's fins from its records (pelt_io's reader and fin geometry); stale records
/// are warned about and give none.
fn fin_edges(doc: &Document, r: PrimitiveRef) -> Result<Vec<FinEdge>, pelt_io::IoError> {
    let edges = match doc.read_stored_fins(r)? {
        None => return Ok(Vec::new()),
        Some(StoredFins::Valid(e)) => e,
        Some(StoredFins::Stale(why)) => {
            warn!(
                "bevy_pelt: {}: the fin records are stale ({why}); drawn without fins",
                doc.place(r)
            );
            return Ok(Vec::new());
        }
    };
    let m = pelt_io::mesh::read_primitive(doc, r)?.mesh;
    let uv = |v: u32| m.uvs.as_ref().map_or(glam30::Vec2::ZERO, |u| u[v as usize]);
    Ok(edges
        .iter()
        .map(|e| {
            let g = pelt_io::topology::fin_geometry(e, &m.indices, &m.positions);
            let [a, b] = g.vertices;
            FinEdge {
                ends: [a, b],
                faces: g.face_normals.map(|f| f.to_array()),
                u: [pelt_scene::fur::edge_offset(a, b), (uv(a) - uv(b)).length()],
            }
        })
        .collect())
}

/// On a glTF mesh entity: its primitive's fur, which [`crate::attach`] draws.
#[derive(Component, Reflect, Clone, Debug)]
#[reflect(Component)]
pub struct PeltFur(pub Handle<PeltFurData>);

/// On a glTF mesh entity whose fur could not be read: why (the file and the place). The
/// primitive is drawn as Bevy loaded it.
#[derive(Component, Reflect, Clone, Debug)]
#[reflect(Component)]
pub struct PeltFurError(pub String);

/// The handler; one clone per load holds that file's document.
#[derive(Clone, Default)]
pub struct FurExtensionHandler {
    doc: Option<Result<Arc<Document>, String>>,
    found: HashMap<(usize, usize), Result<Handle<PeltFurData>, String>>,
    densities: HashMap<usize, Arc<Density>>,
    fin_textures: HashMap<usize, Arc<Vec<Level<[u8; 4]>>>>,
}

fn uses_fur(g: &gltf::Gltf, p: &gltf::Primitive) -> bool {
    g.extensions_used().any(|e| e == EXTENSION)
        || p.attributes()
            .any(|(s, _)| matches!(s, GltfSemantic::Extras(ref n) if n == "FUR_COMB"))
}

/// The file as pelt reads it: a GLB from its own bytes; a `.gltf` from its JSON and the
/// buffers Bevy loaded (its URIs are Bevy's to resolve). Errors name the file.
pub fn document(path: &Path, bytes: Vec<u8>, buffers: &[Vec<u8>]) -> Result<Document, String> {
    if bytes.starts_with(b"glTF") {
        return Document::from_bytes(path, bytes).map_err(|e| e.to_string());
    }
    let json: serde_json::Map<String, serde_json::Value> =
        serde_json::from_slice(&bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(Document::from_parts(path, json, buffers.to_vec()))
}

impl FurExtensionHandler {
    async fn load_document(&mut self, cx: &mut LoadContext<'_>, buffers: &[Vec<u8>]) {
        if self.doc.is_some() {
            return;
        }
        let path = cx.path().clone();
        let read = cx.read_asset_bytes(path.clone()).await;
        let doc = match read {
            Ok(bytes) => document(path.path(), bytes, buffers).map(Arc::new),
            Err(e) => Err(format!("{path}: {e}")),
        };
        self.doc = Some(doc);
    }

    fn decode(
        &mut self,
        doc: &Document,
        r: PrimitiveRef,
        n: usize,
    ) -> Result<Option<PeltFurData>, String> {
        let e = |e: pelt_io::IoError| e.to_string();
        let Some((ext, _)) = doc.fur_primitive(r).map_err(e)? else {
            return Ok(None);
        };
        let tangents = ext
            .get("tangents")
            .and_then(|t| t.as_str())
            .unwrap_or("mikktspace")
            .to_owned();
        let Some(comb) = pelt_io::contract::read_comb(doc, r, n).map_err(e)? else {
            return Ok(None);
        };
        let place = doc.place(r);
        let Some((m, mplace)) = pelt_scene::fur::manifest(doc, r).map_err(e)? else {
            return Err(format!(
                "{place}: a fur primitive whose material has no {EXTENSION} manifest"
            ));
        };
        let material = doc.primitive_material(r).map_err(e)?.unwrap_or(usize::MAX);
        let density = self
            .densities
            .entry(material)
            .or_insert_with(|| Arc::new(pelt_scene::fur::density_of(&m.strands)))
            .clone();
        let fin_texture = match self.fin_textures.get(&material) {
            Some(t) => t.clone(),
            None => {
                let t = Arc::new(pelt_scene::fur::fin_levels(doc, &m, &mplace).map_err(e)?);
                self.fin_textures.insert(material, t.clone());
                t
            }
        };
        let fins = fin_edges(doc, r).map_err(e)?;
        Ok(Some(PeltFurData {
            place,
            comb: comb.into_iter().map(|c| c.to_array()).collect(),
            look: pelt_scene::fur::look_of(&m),
            density,
            tangents,
            fins,
            fin_texture,
        }))
    }
}

impl GltfExtensionHandler for FurExtensionHandler {
    fn dyn_clone(&self) -> Box<dyn ErasedGltfExtensionHandler> {
        Box::new(FurExtensionHandler::default())
    }

    fn on_gltf_primitive(
        &mut self,
        load_context: &mut LoadContext<'_>,
        gltf_document: &gltf::Gltf,
        gltf_mesh: &gltf::Mesh,
        gltf_primitive: &gltf::Primitive,
        buffer_data: &[Vec<u8>],
        _custom_vertex_attributes: &HashMap<Box<str>, MeshVertexAttribute>,
        _gltf_mesh_on_skinned_nodes: bool,
        _gltf_mesh_on_non_skinned_nodes: bool,
        _user_mesh: &mut Option<Mesh>,
    ) -> impl ConditionalSendFuture<Output = ()> {
        async move {
            if !uses_fur(gltf_document, gltf_primitive) {
                return;
            }
            self.load_document(load_context, buffer_data).await;
            let r = PrimitiveRef {
                mesh: gltf_mesh.index(),
                primitive: gltf_primitive.index(),
            };
            let n = gltf_primitive
                .get(&GltfSemantic::Positions)
                .map_or(0, |a| a.count());
            let decoded = match self.doc.clone() {
                Some(Ok(doc)) => self.decode(&doc, r, n),
                Some(Err(e)) => Err(e),
                None => return,
            };
            let result = match decoded {
                Ok(None) => return,
                Ok(Some(data)) => {
                    let label = format!("PeltFur{}/Primitive{}", r.mesh, r.primitive);
                    Ok(load_context.add_labeled_asset(label, data))
                }
                Err(e) => {
                    error!("bevy_pelt: {e}");
                    Err(e)
                }
            };
            self.found.insert((r.mesh, r.primitive), result);
        }
    }

    fn on_spawn_mesh_and_material(
        &mut self,
        _load_context: &mut LoadContext<'_>,
        primitive: &gltf::Primitive,
        mesh: &gltf::Mesh,
        _material: &gltf::Material,
        entity: &mut EntityWorldMut,
        _material_label: &str,
    ) {
        match self.found.get(&(mesh.index(), primitive.index())) {
            Some(Ok(h)) => {
                entity.insert(PeltFur(h.clone()));
            }
            Some(Err(e)) => {
                entity.insert(PeltFurError(e.clone()));
            }
            None => {}
        }
    }
}
