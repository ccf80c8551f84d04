//! Removing textures and images a caller no longer wants (the fur textures of an earlier bake,
//! before a re-bake embeds new ones), with the samplers and bufferViews only they used.
//!
//! A candidate texture is removed only when no material refers to it any more (any
//! `…Texture` object with an `index`, extensions included); a candidate image only when no
//! remaining texture uses it (`source`, or an extension's `source`). A sampler or bufferView
//! goes with them when nothing else uses it. Where the asset uses an extension that might refer
//! to textures or images in ways pelt does not know, nothing is removed. Removed entries are
//! renumbered out of every reference.

use serde_json::{Map, Value, json};

use crate::document::Document;

/// Extensions known to refer to textures only through `…Texture` objects in materials, and to
/// images only through a texture's `source` or an extension's `source` in a texture.
fn known(ext: &str) -> bool {
    ext.starts_with("KHR_materials_")
        || matches!(
            ext,
            "KHR_lights_punctual"
                | "KHR_mesh_quantization"
                | "KHR_texture_basisu"
                | "KHR_texture_transform"
                | "KHR_xmp_json_ld"
                | "EXT_mesh_gpu_instancing"
                | "EXT_meshopt_compression"
                | "KHR_meshopt_compression"
                | "EXT_texture_avif"
                | "EXT_texture_webp"
                | "MSFT_texture_dds"
                | crate::extension::EXTENSION
        )
}

/// What [`Document::remove_textures`] did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RemovedTextures {
    /// Textures removed.
    pub textures: usize,
    /// Images removed.
    pub images: usize,
    /// Samplers removed.
    pub samplers: usize,
    /// Why nothing was removed (an extension pelt does not know).
    pub kept_because: Option<String>,
}

/// Every texture reference inside a material (`…Texture: {"index": i}` at any depth).
fn for_each_texture_ref(v: &mut Value, f: &mut dyn FnMut(&mut Value)) {
    match v {
        Value::Object(o) => {
            for (k, child) in o.iter_mut() {
                if k.ends_with("Texture")
                    && let Some(i) = child.get_mut("index")
                {
                    f(i);
                    continue;
                }
                for_each_texture_ref(child, f);
            }
        }
        Value::Array(a) => a.iter_mut().for_each(|c| for_each_texture_ref(c, f)),
        _ => {}
    }
}

fn materials_texture_refs(json: &mut Map<String, Value>, f: &mut dyn FnMut(&mut Value)) {
    let Some(materials) = json.get_mut("materials").and_then(Value::as_array_mut) else {
        return;
    };
    for m in materials {
        let Some(o) = m.as_object_mut() else {
            continue;
        };
        for (k, child) in o.iter_mut() {
            let exts = (k == "extensions").then(|| child.as_object_mut()).flatten();
            let Some(exts) = exts else {
                // As for_each_texture_ref does for the entries of an object.
                if k.ends_with("Texture")
                    && let Some(i) = child.get_mut("index")
                {
                    f(i);
                    continue;
                }
                for_each_texture_ref(child, f);
                continue;
            };
            for (name, e) in exts.iter_mut() {
                // PELT_fur's textures (mip levels included) are listed by its own module.
                if name == crate::extension::EXTENSION {
                    crate::extension::for_each_material_texture(e, f);
                } else {
                    for_each_texture_ref(e, f);
                }
            }
        }
    }
}

/// Every image reference of a texture: `source`, and `source` in each of its extensions.
fn texture_image_refs(json: &mut Map<String, Value>, f: &mut dyn FnMut(&mut Value)) {
    let Some(textures) = json.get_mut("textures").and_then(Value::as_array_mut) else {
        return;
    };
    for t in textures {
        if let Some(s) = t.get_mut("source") {
            f(s);
        }
        let exts = t.get_mut("extensions").and_then(Value::as_object_mut);
        for e in exts.into_iter().flat_map(|e| e.values_mut()) {
            if let Some(s) = e.get_mut("source") {
                f(s);
            }
        }
    }
}

fn texture_sampler_refs(json: &mut Map<String, Value>, f: &mut dyn FnMut(&mut Value)) {
    let Some(textures) = json.get_mut("textures").and_then(Value::as_array_mut) else {
        return;
    };
    for t in textures {
        if let Some(s) = t.get_mut("sampler") {
            f(s);
        }
    }
}

/// Visits every reference of one kind in the JSON root.
type Visit = fn(&mut Map<String, Value>, &mut dyn FnMut(&mut Value));

/// Marks as used every index that `visit` reaches.
fn used_by(json: &mut Map<String, Value>, len: usize, visit: Visit) -> Vec<bool> {
    let mut used = vec![false; len];
    visit(json, &mut |v| {
        if let Some(i) = v.as_u64().filter(|&i| (i as usize) < len) {
            used[i as usize] = true;
        }
    });
    used
}

/// Which entries of top-level array `key` are among `candidates` and reached by nothing that
/// `visit` visits.
fn unreferenced(
    json: &mut Map<String, Value>,
    key: &str,
    candidates: &[usize],
    visit: Visit,
) -> Vec<bool> {
    let len = json.get(key).and_then(Value::as_array).map_or(0, Vec::len);
    let used = used_by(json, len, visit);
    (0..len)
        .map(|i| candidates.contains(&i) && !used[i])
        .collect()
}

/// Index `field` of each entry of top-level array `key` marked in `removed`.
fn field_of_removed(
    json: &Map<String, Value>,
    key: &str,
    removed: &[bool],
    field: &str,
) -> Vec<usize> {
    let entries = json.get(key).and_then(Value::as_array);
    entries
        .into_iter()
        .flatten()
        .zip(removed)
        .filter(|&(_, &r)| r)
        .filter_map(|(e, _)| e.get(field)?.as_u64())
        .map(|v| v as usize)
        .collect()
}

/// Removes the `removed` entries of top-level array `key`, renumbering the references `visit`
/// reaches. Returns how many went.
fn remove_and_renumber(
    json: &mut Map<String, Value>,
    key: &str,
    removed: &[bool],
    visit: Visit,
) -> usize {
    let count = removed.iter().filter(|&&r| r).count();
    if count == 0 {
        return 0;
    }
    let mut next = 0;
    let map: Vec<Option<usize>> = removed
        .iter()
        .map(|&r| {
            (!r).then(|| {
                next += 1;
                next - 1
            })
        })
        .collect();
    visit(json, &mut |v| {
        if let Some(Some(n)) = v.as_u64().and_then(|i| map.get(i as usize)) {
            *v = json!(n);
        }
    });
    if let Some(entries) = json.get_mut(key).and_then(Value::as_array_mut) {
        let mut i = 0;
        entries.retain(|_| {
            i += 1;
            !removed.get(i - 1).copied().unwrap_or(false)
        });
    }
    count
}

impl Document {
    /// Removes `textures` and `images` where nothing else refers to them, with the samplers and
    /// bufferViews only they used. See the module documentation for the rules.
    pub fn remove_textures(&mut self, textures: &[usize], images: &[usize]) -> RemovedTextures {
        let mut out = RemovedTextures::default();
        if let Some(ext) = self
            .array("extensionsUsed")
            .iter()
            .filter_map(Value::as_str)
            .find(|e| !known(e))
        {
            out.kept_because = Some(format!(
                "old textures were kept: the asset uses {ext}, which may refer to them"
            ));
            return out;
        }
        let tex_removed =
            unreferenced(&mut self.json, "textures", textures, materials_texture_refs);
        let samplers = field_of_removed(&self.json, "textures", &tex_removed, "sampler");
        out.textures = remove_and_renumber(
            &mut self.json,
            "textures",
            &tex_removed,
            materials_texture_refs,
        );

        let img_removed = unreferenced(&mut self.json, "images", images, texture_image_refs);
        let views = field_of_removed(&self.json, "images", &img_removed, "bufferView");
        let n_img = img_removed.len();
        self.uri_images.resize(n_img, None);
        let mut i = 0;
        self.uri_images.retain(|_| {
            i += 1;
            !img_removed[i - 1]
        });
        out.images =
            remove_and_renumber(&mut self.json, "images", &img_removed, texture_image_refs);

        let smp_removed = unreferenced(&mut self.json, "samplers", &samplers, texture_sampler_refs);
        out.samplers = remove_and_renumber(
            &mut self.json,
            "samplers",
            &smp_removed,
            texture_sampler_refs,
        );
        self.detached_views.extend(views);
        self.prune_detached();
        out
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    /// Two images in bufferViews 0 and 1; texture 0 (sampler 0) shows image 0 and is the fur's,
    /// texture 1 (sampler 1) shows image 1 and is the base colour.
    fn doc(extensions: &[&str]) -> Document {
        let json = json!({
            "asset": {"version": "2.0"},
            "extensionsUsed": extensions,
            "buffers": [{"byteLength": 8}],
            "bufferViews": [
                {"buffer": 0, "byteLength": 4},
                {"buffer": 0, "byteOffset": 4, "byteLength": 4}
            ],
            "images": [
                {"bufferView": 0, "mimeType": "image/png"},
                {"bufferView": 1, "mimeType": "image/png"}
            ],
            "samplers": [{}, {"wrapS": 33071}],
            "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 1}],
            "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}}]
        });
        let Value::Object(json) = json else {
            unreachable!("literal object")
        };
        Document::from_parts(Path::new("t.gltf"), json, vec![b"abcdefgh".to_vec()])
    }

    #[test]
    fn unused_textures_go_and_references_are_renumbered() {
        let mut d = doc(&[]);
        let r = d.remove_textures(&[0], &[0]);
        assert_eq!((r.textures, r.images, r.samplers), (1, 1, 1));
        assert_eq!(d.array("textures").len(), 1);
        assert_eq!(d.array("textures")[0]["source"], 0);
        assert_eq!(d.array("textures")[0]["sampler"], 0);
        assert_eq!(d.array("samplers")[0]["wrapS"], 33071);
        let m = &d.array("materials")[0];
        assert_eq!(m["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
        assert_eq!(d.array("bufferViews").len(), 1);
        assert_eq!(d.image_bytes(0).expect("image 1 is now image 0"), b"efgh");
    }

    #[test]
    fn textures_still_used_stay() {
        let mut d = doc(&[]);
        let r = d.remove_textures(&[1], &[1]);
        assert_eq!((r.textures, r.images, r.samplers), (0, 0, 0));
        assert_eq!(d.array("textures").len(), 2);
        assert_eq!(d.array("images").len(), 2);
    }

    #[test]
    fn unknown_extensions_keep_everything() {
        let mut d = doc(&["EXT_something_new"]);
        let r = d.remove_textures(&[0], &[0]);
        assert_eq!(r.textures, 0);
        assert!(
            r.kept_because
                .expect("reason")
                .contains("EXT_something_new")
        );
        assert_eq!(d.array("images").len(), 2);
    }
}
