//! Dropping the data a bake left behind. A vertex split re-gathers every attribute of a
//! primitive into new accessors, and a rewritten NORMAL or TANGENT replaces the old one; the
//! accessors they replace (and their bufferViews) would otherwise stay in the output unused,
//! nearly doubling its size after a split.
//!
//! Only accessors the bake detached are candidates, and one is removed only when nothing in the
//! document refers to it any more: primitives (attributes, indices, morph targets), skins,
//! animation samplers, `EXT_mesh_gpu_instancing` and `PELT_fur`. A bufferView goes with them when no
//! remaining accessor (sparse parts included) or image uses it. Where the asset uses an
//! extension that might refer to accessors or bufferViews in ways pelt does not know, nothing
//! is removed. Removed entries are renumbered out of every reference listed above.

use serde_json::{Value, json};

use crate::document::Document;

/// Extensions known not to refer to accessors or bufferViews (or, for
/// `EXT_mesh_gpu_instancing`, whose references are followed here).
const SAFE_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_anisotropy",
    "KHR_materials_clearcoat",
    "KHR_materials_diffuse_transmission",
    "KHR_materials_dispersion",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_iridescence",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_unlit",
    "KHR_materials_variants",
    "KHR_materials_volume",
    "KHR_mesh_quantization",
    "KHR_texture_basisu",
    "KHR_texture_transform",
    "KHR_xmp_json_ld",
    "EXT_mesh_gpu_instancing",
    "EXT_texture_avif",
    "EXT_texture_webp",
    "MSFT_lod",
    "MSFT_texture_dds",
    crate::extension::EXTENSION,
];

/// What [`Document::prune_detached`] did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Pruned {
    /// Accessors removed.
    pub accessors: usize,
    /// BufferViews removed.
    pub buffer_views: usize,
    /// Why nothing was removed although candidates were unused (an unknown extension).
    pub kept_because: Option<String>,
}

/// Every place that holds an accessor index, visited mutably.
pub(crate) fn for_each_accessor_ref(
    json: &mut serde_json::Map<String, Value>,
    f: &mut impl FnMut(&mut Value),
) {
    let in_object = |o: Option<&mut Value>, f: &mut dyn FnMut(&mut Value)| {
        if let Some(o) = o.and_then(Value::as_object_mut) {
            o.values_mut().for_each(f);
        }
    };
    if let Some(meshes) = json.get_mut("meshes").and_then(Value::as_array_mut) {
        for m in meshes {
            let prims = m.get_mut("primitives").and_then(Value::as_array_mut);
            for p in prims.into_iter().flatten() {
                in_object(p.get_mut("attributes"), f);
                if let Some(i) = p.get_mut("indices") {
                    f(i);
                }
                let targets = p.get_mut("targets").and_then(Value::as_array_mut);
                for t in targets.into_iter().flatten() {
                    in_object(Some(t), f);
                }
                // pelt's own fin records (crate::extension).
                let fins = p
                    .get_mut("extensions")
                    .and_then(|e| e.get_mut(crate::extension::EXTENSION))
                    .and_then(|e| e.get_mut("fins"));
                if let Some(fins) = fins {
                    crate::extension::for_each_fin_accessor(fins, f);
                }
            }
        }
    }
    if let Some(skins) = json.get_mut("skins").and_then(Value::as_array_mut) {
        for s in skins {
            if let Some(i) = s.get_mut("inverseBindMatrices") {
                f(i);
            }
        }
    }
    if let Some(anims) = json.get_mut("animations").and_then(Value::as_array_mut) {
        for a in anims {
            let samplers = a.get_mut("samplers").and_then(Value::as_array_mut);
            for s in samplers.into_iter().flatten() {
                for key in ["input", "output"] {
                    if let Some(i) = s.get_mut(key) {
                        f(i);
                    }
                }
            }
        }
    }
    if let Some(nodes) = json.get_mut("nodes").and_then(Value::as_array_mut) {
        for n in nodes {
            let inst = n
                .get_mut("extensions")
                .and_then(|e| e.get_mut("EXT_mesh_gpu_instancing"))
                .and_then(|e| e.get_mut("attributes"));
            in_object(inst, f);
        }
    }
}

/// Every place that holds a bufferView index, visited mutably.
fn for_each_view_ref(json: &mut serde_json::Map<String, Value>, f: &mut impl FnMut(&mut Value)) {
    if let Some(accessors) = json.get_mut("accessors").and_then(Value::as_array_mut) {
        for a in accessors {
            if let Some(v) = a.get_mut("bufferView") {
                f(v);
            }
            if let Some(sparse) = a.get_mut("sparse") {
                for part in ["indices", "values"] {
                    if let Some(v) = sparse.get_mut(part).and_then(|p| p.get_mut("bufferView")) {
                        f(v);
                    }
                }
            }
        }
    }
    if let Some(images) = json.get_mut("images").and_then(Value::as_array_mut) {
        for im in images {
            if let Some(v) = im.get_mut("bufferView") {
                f(v);
            }
        }
    }
    // pelt's legacy fin records (see crate::topology).
    if let Some(meshes) = json.get_mut("meshes").and_then(Value::as_array_mut) {
        for m in meshes {
            let prims = m.get_mut("primitives").and_then(Value::as_array_mut);
            for p in prims.into_iter().flatten() {
                let fins = p
                    .get_mut("extras")
                    .and_then(|e| e.get_mut("pelt"))
                    .and_then(|e| e.get_mut("fins"));
                if let Some(fins) = fins {
                    crate::extension::for_each_fin_view(fins, f);
                }
            }
        }
    }
}

/// Renumbers one reference through `map` (old index → new index; None = removed).
fn renumber(v: &mut Value, map: &[Option<usize>]) {
    if let Some(Some(n)) = v.as_u64().and_then(|i| map.get(i as usize)) {
        *v = json!(n);
    }
}

/// Removes the entries of top-level array `key` marked in `removed`.
fn remove_entries(json: &mut serde_json::Map<String, Value>, key: &str, removed: &[bool]) {
    if let Some(entries) = json.get_mut(key).and_then(Value::as_array_mut) {
        let mut i = 0;
        entries.retain(|_| {
            i += 1;
            !removed.get(i - 1).copied().unwrap_or(false)
        });
    }
}

/// Old → new indices for an array of `len` entries with `removed` taken out.
fn index_map(len: usize, removed: &[bool]) -> Vec<Option<usize>> {
    let mut next = 0;
    (0..len)
        .map(|i| {
            if removed[i] {
                None
            } else {
                next += 1;
                Some(next - 1)
            }
        })
        .collect()
}

impl Document {
    /// Removes the accessors the bake detached (and their bufferViews) where nothing refers
    /// to them any more. See the module documentation for the rules.
    pub fn prune_detached(&mut self) -> Pruned {
        let mut pruned = Pruned::default();
        let n_acc = self.array("accessors").len();
        let mut candidate = vec![false; n_acc];
        for &a in &self.detached {
            if a < n_acc {
                candidate[a] = true;
            }
        }
        let mut view_candidate = vec![false; self.array("bufferViews").len()];
        for &v in &self.detached_views {
            if let Some(c) = view_candidate.get_mut(v) {
                *c = true;
            }
        }
        if !candidate.contains(&true) && !view_candidate.contains(&true) {
            return pruned;
        }
        if let Some(ext) = self
            .array("extensionsUsed")
            .iter()
            .filter_map(Value::as_str)
            .find(|e| !SAFE_EXTENSIONS.contains(e) && !e.starts_with("KHR_materials_"))
        {
            pruned.kept_because = Some(format!(
                "replaced accessors were kept: the asset uses {ext}, which may refer to them"
            ));
            return pruned;
        }

        // Accessors: candidates nothing refers to.
        let mut used = vec![false; n_acc];
        for_each_accessor_ref(&mut self.json, &mut |v| {
            if let Some(i) = v.as_u64().filter(|&i| (i as usize) < n_acc) {
                used[i as usize] = true;
            }
        });
        let removed: Vec<bool> = (0..n_acc).map(|i| candidate[i] && !used[i]).collect();
        // The bufferViews those accessors used (sparse parts included).
        for (a, acc) in self.array("accessors").iter().enumerate() {
            if !removed[a] {
                continue;
            }
            let sparse = acc.get("sparse");
            let refs = [
                acc.get("bufferView"),
                sparse.and_then(|s| s.get("indices")?.get("bufferView")),
                sparse.and_then(|s| s.get("values")?.get("bufferView")),
            ];
            for v in refs.into_iter().flatten().filter_map(Value::as_u64) {
                if let Some(c) = view_candidate.get_mut(v as usize) {
                    *c = true;
                }
            }
        }
        if removed.contains(&true) {
            let map = index_map(n_acc, &removed);
            for_each_accessor_ref(&mut self.json, &mut |v| renumber(v, &map));
            remove_entries(&mut self.json, "accessors", &removed);
            pruned.accessors = removed.iter().filter(|&&r| r).count();
        }
        self.detached.clear();
        self.detached_views.clear();

        // BufferViews no remaining accessor or image uses, among those the removed ones used.
        let n_views = self.array("bufferViews").len();
        let mut view_used = vec![false; n_views];
        for_each_view_ref(&mut self.json, &mut |v| {
            if let Some(i) = v.as_u64().filter(|&i| (i as usize) < n_views) {
                view_used[i as usize] = true;
            }
        });
        let view_removed: Vec<bool> = (0..n_views)
            .map(|i| view_candidate.get(i).copied().unwrap_or(false) && !view_used[i])
            .collect();
        if view_removed.contains(&true) {
            let vmap = index_map(n_views, &view_removed);
            for_each_view_ref(&mut self.json, &mut |v| renumber(v, &vmap));
            remove_entries(&mut self.json, "bufferViews", &view_removed);
            // New views are stored after the source ones: keep both parts in step.
            let source = self.source_views;
            let mut k = source;
            self.new_views.retain(|_| {
                k += 1;
                !view_removed[k - 1]
            });
            self.source_views = view_removed[..source].iter().filter(|&&r| !r).count();
            pruned.buffer_views = view_removed.iter().filter(|&&r| r).count();
        }
        pruned
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::PrimitiveRef;
    use crate::accessor;

    /// Two primitives sharing POSITION (accessor 0); the first also has NORMAL (accessor 1).
    fn doc(extensions: &[&str]) -> Document {
        let f = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
        let mut bin = f(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        bin.extend(f(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0]));
        let json = json!({
            "asset": {"version": "2.0"},
            "extensionsUsed": extensions,
            "buffers": [{"byteLength": 72}],
            "bufferViews": [
                {"buffer": 0, "byteLength": 36},
                {"buffer": 0, "byteOffset": 36, "byteLength": 36}
            ],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"}
            ],
            "meshes": [{"primitives": [
                {"attributes": {"POSITION": 0, "NORMAL": 1}},
                {"attributes": {"POSITION": 0}}
            ]}]
        });
        let Value::Object(json) = json else {
            unreachable!("literal object")
        };
        Document::from_parts(Path::new("t.gltf"), json, vec![bin])
    }

    fn split_first(d: &mut Document) {
        let r = PrimitiveRef {
            mesh: 0,
            primitive: 0,
        };
        d.remap_primitive(r, &[0, 1, 2, 0], &[0, 1, 2, 3, 2, 1], &[])
            .expect("remap");
    }

    #[test]
    fn detached_accessors_go_and_shared_ones_stay() {
        let mut d = doc(&[]);
        split_first(&mut d);
        assert_eq!(d.array("accessors").len(), 5);
        let p = d.prune_detached();
        // The old NORMAL and its view go; POSITION (still used by primitive 1) stays.
        assert_eq!((p.accessors, p.buffer_views), (1, 1));
        assert_eq!(d.array("accessors").len(), 4);
        assert_eq!(d.array("bufferViews").len(), 4);
        let second = d.attribute(
            PrimitiveRef {
                mesh: 0,
                primitive: 1,
            },
            "POSITION",
        );
        let pos = accessor::read_vec::<3>(&d, second.expect("ok").expect("set"), "POSITION")
            .expect("still readable");
        assert_eq!(pos[1], [1.0, 0.0, 0.0]);
        let first = PrimitiveRef {
            mesh: 0,
            primitive: 0,
        };
        let n = d.attribute(first, "NORMAL").expect("ok").expect("set");
        let normals = accessor::read_vec::<3>(&d, n, "NORMAL").expect("renumbered view");
        assert_eq!(normals.len(), 4);
        assert_eq!(normals[3], [0.0, 0.0, 1.0]);
        // Every remaining view is used by an accessor.
        let mut used = vec![false; d.array("bufferViews").len()];
        for a in d.array("accessors") {
            used[a["bufferView"].as_u64().expect("view") as usize] = true;
        }
        assert!(used.iter().all(|&u| u));
    }

    #[test]
    fn unknown_extensions_keep_everything() {
        let mut d = doc(&["EXT_structural_metadata"]);
        split_first(&mut d);
        let p = d.prune_detached();
        assert_eq!(p.accessors, 0);
        assert!(
            p.kept_because
                .expect("reason")
                .contains("EXT_structural_metadata")
        );
        assert_eq!(d.array("accessors").len(), 5);
    }
}
