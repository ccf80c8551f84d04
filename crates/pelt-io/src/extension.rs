//! The `PELT_fur` glTF extension: the one home of its names and layouts. The bake writes
//! through it; `pelt inspect`, the preview and the runtimes read through it (or are tested
//! against it). The specification, with JSON Schemas, is `docs/extension/PELT_fur/`.
//!
//! - On a primitive, `extensions.PELT_fur`: the comb and normal-group attribute names, the
//!   topology summary, the fin records as an accessor (VEC2 UNSIGNED_INT corner pairs, see
//!   [`crate::topology`]) and `computedFrom` (the triangle count and [`index_hash`] of the index
//!   list the records were computed from, so a reader tells stale records from good ones).
//! - On a material, `extensions.PELT_fur`: the fur manifest (length, shells, colours, the
//!   strand model's parameters) with its textures as texture references
//!   (`heightfieldTexture`, `dotsTexture`, `finTexture`: a textureInfo with the level-0
//!   texture, plus `mipLevels`, the textures of levels 1 and on).
//! - Listed in `extensionsUsed`, never in `extensionsRequired`: a viewer that does not know it
//!   draws the mesh.
//!
//! Files written before the extension kept the same data in `extras.pelt` (the legacy form):
//! every reader here falls back to it, and a bake writes the extension form and removes it.

use serde_json::{Map, Value, json};

use crate::document::{Document, PrimitiveRef};
use crate::error::Result;

/// The extension's name.
pub const EXTENSION: &str = "PELT_fur";

/// The extension fur materials also carry for viewers without a `PELT_fur` runtime
/// ([`sheen_fallback`]).
pub const SHEEN: &str = "KHR_materials_sheen";

/// The key of the legacy form (`extras.pelt`).
pub const LEGACY_KEY: &str = "pelt";

/// The three fur textures, by their stem in the manifest.
pub const TEXTURE_STEMS: [&str; 3] = ["heightfield", "dots", "fin"];

/// Where a primitive's or material's fur data was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Form {
    /// `extensions.PELT_fur`.
    Extension,
    /// `extras.pelt` (files written before the extension).
    Legacy,
}

/// xxHash32 (seed 0) of the index list as little-endian u32 values: `computedFrom.indexHash`
/// (docs/extension/PELT_fur/README.md, "Stale records"). xxHash32 rather than a byte-serial
/// hash such as FNV-1a: it runs at memory speed, about 2 ms for the 15.6 MB index list of the
/// 1.3 M-triangle benchmark mesh, half of FNV-1a's time (docs/benchmarks.md, "What the
/// extension costs the bake").
pub fn index_hash(indices: &[u32]) -> u32 {
    #[cfg(target_endian = "little")]
    let bytes: std::borrow::Cow<'_, [u8]> =
        std::borrow::Cow::Borrowed(bytemuck::cast_slice(indices));
    #[cfg(not(target_endian = "little"))]
    let bytes: std::borrow::Cow<'_, [u8]> =
        std::borrow::Cow::Owned(indices.iter().flat_map(|i| i.to_le_bytes()).collect());
    xxhash_rust::xxh32::xxh32(&bytes, 0)
}

/// The `computedFrom` object for the index list `indices`.
pub fn computed_from(indices: &[u32]) -> Value {
    json!({ "triangles": indices.len() / 3, "indexHash": index_hash(indices) })
}

/// The object at `extensions.PELT_fur` of `v`, if any.
fn extension_of(v: &Value) -> Option<&Map<String, Value>> {
    v.get("extensions")?.get(EXTENSION)?.as_object()
}

/// The object at `extras.pelt` of `v`, if any.
fn legacy_of(v: &Value) -> Option<&Map<String, Value>> {
    v.get("extras")?.get(LEGACY_KEY)?.as_object()
}

impl Document {
    /// The primitive's fur data: `extensions.PELT_fur`, or the legacy `extras.pelt`.
    pub fn fur_primitive(&self, r: PrimitiveRef) -> Result<Option<(&Map<String, Value>, Form)>> {
        let prim = self.primitive(r)?;
        if let Some(e) = prim
            .get("extensions")
            .and_then(|e| e.get(EXTENSION))
            .and_then(Value::as_object)
        {
            return Ok(Some((e, Form::Extension)));
        }
        Ok(prim
            .get("extras")
            .and_then(|e| e.get(LEGACY_KEY))
            .and_then(Value::as_object)
            .map(|m| (m, Form::Legacy)))
    }

    /// The place of the primitive's fur data, for messages.
    pub fn fur_place(&self, r: PrimitiveRef, form: Form) -> String {
        match form {
            Form::Extension => format!("{} extensions.{EXTENSION}", self.place(r)),
            Form::Legacy => format!("{} extras.{LEGACY_KEY}", self.place(r)),
        }
    }

    /// Sets the primitive's `extensions.PELT_fur` to `fur`, removes a legacy `extras.pelt`
    /// (an emptied `extras` goes too) and lists the extension in `extensionsUsed`. Accessors
    /// and bufferViews the old data named are detached (pruned if nothing else uses them).
    /// Returns false, and changes nothing, when the primitive's `extensions` is not an object.
    pub(crate) fn set_fur_primitive(
        &mut self,
        r: PrimitiveRef,
        fur: Map<String, Value>,
    ) -> Result<bool> {
        let ok = self
            .primitive(r)?
            .get("extensions")
            .is_none_or(Value::is_object);
        if !ok {
            return Ok(false);
        }
        self.detach_fur_records(r)?;
        let prim = self.primitive_checked(r)?;
        if let Some(extras) = prim.get_mut("extras").and_then(Value::as_object_mut) {
            extras.shift_remove(LEGACY_KEY);
            if extras.is_empty() {
                prim.shift_remove("extras");
            }
        }
        let exts = prim.entry("extensions").or_insert_with(|| json!({}));
        if let Some(e) = exts.as_object_mut() {
            e.insert(EXTENSION.into(), Value::Object(fur));
        }
        self.use_extension(EXTENSION);
        Ok(true)
    }

    /// Detaches the accessors (extension form) and bufferViews (legacy form) of the
    /// primitive's stored fin records.
    fn detach_fur_records(&mut self, r: PrimitiveRef) -> Result<()> {
        let Some((fur, form)) = self.fur_primitive(r)? else {
            return Ok(());
        };
        let Some(mut fins) = fur.get("fins").cloned() else {
            return Ok(());
        };
        let mut found = Vec::new();
        match form {
            Form::Extension => for_each_fin_accessor(&mut fins, &mut |v| found.extend(v.as_u64())),
            Form::Legacy => {
                for_each_fin_view(&mut fins, &mut |v| found.extend(v.as_u64()));
            }
        }
        let found = found.into_iter().map(|i| i as usize);
        match form {
            Form::Extension => self.detached.extend(found),
            Form::Legacy => self.detached_views.extend(found),
        }
        Ok(())
    }

    /// Adds `name` to `extensionsUsed` (once).
    pub(crate) fn use_extension(&mut self, name: &str) {
        let list = self
            .json
            .entry("extensionsUsed")
            .or_insert_with(|| Value::Array(Vec::new()));
        if let Some(l) = list.as_array_mut()
            && !l.iter().any(|e| e.as_str() == Some(name))
        {
            l.push(Value::from(name));
        }
    }

    /// The material's fur manifest in the manifest layout (`docs/format.md`: textures by
    /// image per level): converted from `extensions.PELT_fur`, or the legacy
    /// `extras.pelt.fur` as stored. With the place it was read from.
    pub fn fur_manifest_json(&self, material: usize) -> Result<Option<(Value, String)>> {
        let Some(m) = self.array("materials").get(material) else {
            return Ok(None);
        };
        if let Some(e) = extension_of(m) {
            let place = format!("materials[{material}].extensions.{EXTENSION}");
            return Ok(Some((self.manifest_from_extension(e, &place)?, place)));
        }
        Ok(legacy_of(m).and_then(|p| p.get("fur")).map(|f| {
            let place = format!("materials[{material}].extras.{LEGACY_KEY}.fur");
            (f.clone(), place)
        }))
    }

    /// The manifest layout of a material extension object: each `…Texture` (level 0 and
    /// `mipLevels`) becomes `textures.STEM.levels[]` of images, with each level's size halved
    /// from level 0's (at least 1).
    fn manifest_from_extension(&self, e: &Map<String, Value>, place: &str) -> Result<Value> {
        let mut out = e.clone();
        let mut textures = Map::new();
        for stem in TEXTURE_STEMS {
            let key = format!("{stem}Texture");
            let tplace = format!("{place}.{key}");
            let t = out
                .shift_remove(&key)
                .ok_or_else(|| self.invalid(&tplace, "is missing"))?;
            textures.insert(stem.into(), self.texture_levels(&t, &tplace)?);
        }
        out.insert("textures".into(), Value::Object(textures));
        out.insert("version".into(), json!(1));
        Ok(Value::Object(out))
    }

    /// One extension texture object as a manifest texture entry.
    fn texture_levels(&self, t: &Value, place: &str) -> Result<Value> {
        let uint = |k: &str| {
            t.get(k)
                .and_then(Value::as_u64)
                .ok_or_else(|| self.invalid(place, format!("{k} is missing or not an integer")))
        };
        let (w, h) = (uint("width")?, uint("height")?);
        if !(1..=MAX_SIDE).contains(&w) || !(1..=MAX_SIDE).contains(&h) {
            return Err(self.invalid(
                place,
                format!("is {w}×{h}; each side must be 1 to {MAX_SIDE}"),
            ));
        }
        let mut textures = vec![uint("index")?];
        let mips = t.get("mipLevels").and_then(Value::as_array);
        for (k, m) in mips.into_iter().flatten().enumerate() {
            textures.push(m.as_u64().ok_or_else(|| {
                self.invalid(format!("{place}.mipLevels[{k}]"), "is not a texture index")
            })?);
        }
        let chain = 64 - w.max(h).leading_zeros() as usize;
        if textures.len() > chain {
            return Err(self.invalid(
                place,
                format!(
                    "has {} levels; a {w}×{h} texture has at most {chain}",
                    textures.len()
                ),
            ));
        }
        let mut levels = Vec::with_capacity(textures.len());
        for (l, &tex) in textures.iter().enumerate() {
            let image = self.texture_source(tex as usize, place)?;
            levels.push(json!({
                "image": image,
                "width": (w >> l).max(1),
                "height": (h >> l).max(1),
            }));
        }
        Ok(json!({ "texture": textures[0], "format": t.get("format"), "levels": levels }))
    }

    /// `textures[t].source`, checked.
    fn texture_source(&self, t: usize, place: &str) -> Result<u64> {
        let tex = self.array("textures").get(t).ok_or_else(|| {
            self.invalid(
                place,
                format!(
                    "texture {t} does not exist ({} defined)",
                    self.array("textures").len()
                ),
            )
        })?;
        tex.get("source").and_then(Value::as_u64).ok_or_else(|| {
            self.invalid(
                place,
                format!(
                    "texture {t} has no PNG source (a texture compressed by a tool is not \
                     read: bake the source again)"
                ),
            )
        })
    }

    /// Sets the material's `extensions.PELT_fur` to `fur` (and removes a legacy
    /// `extras.pelt.fur`). Returns false, and changes nothing, when the material does not
    /// exist or its `extensions` is not an object.
    pub fn set_fur_material(&mut self, material: usize, fur: Value) -> bool {
        let Some(m) = self
            .json
            .get_mut("materials")
            .and_then(Value::as_array_mut)
            .and_then(|a| a.get_mut(material))
            .and_then(Value::as_object_mut)
        else {
            return false;
        };
        if !m.get("extensions").is_none_or(Value::is_object) {
            return false;
        }
        remove_legacy_fur(m);
        let exts = m.entry("extensions").or_insert_with(|| json!({}));
        if let Some(e) = exts.as_object_mut() {
            e.insert(EXTENSION.into(), fur);
        }
        self.use_extension(EXTENSION);
        true
    }
}

/// The largest side of a fur texture (the strand model's `size` limit).
pub const MAX_SIDE: u64 = 16384;

/// Removes `extras.pelt.fur` from a material (and `extras.pelt`, `extras` if emptied).
pub fn remove_legacy_fur(m: &mut Map<String, Value>) -> Option<Value> {
    let extras = m.get_mut("extras")?.as_object_mut()?;
    let pelt = extras.get_mut(LEGACY_KEY)?.as_object_mut()?;
    let fur = pelt.shift_remove("fur");
    if pelt.is_empty() {
        extras.shift_remove(LEGACY_KEY);
    }
    if extras.is_empty() {
        m.shift_remove("extras");
    }
    fur
}

/// The material extension object for `manifest` (the manifest layout, textures by image per
/// level): each level's image becomes the texture `texture_of(image)` gives.
pub fn extension_from_manifest(
    manifest: &Value,
    texture_of: &mut dyn FnMut(usize) -> usize,
) -> Value {
    let mut out = manifest.as_object().cloned().unwrap_or_default();
    out.shift_remove("version");
    let textures = out.shift_remove("textures").unwrap_or(Value::Null);
    for stem in TEXTURE_STEMS {
        let entry = &textures[stem];
        let levels = entry["levels"].as_array().cloned().unwrap_or_default();
        let mut refs = levels
            .iter()
            .filter_map(|l| l["image"].as_u64())
            .map(|i| texture_of(i as usize));
        let index = refs.next();
        let mips: Vec<usize> = refs.collect();
        let mut t = json!({
            "index": index,
            "format": entry["format"],
            "width": levels.first().map(|l| &l["width"]),
            "height": levels.first().map(|l| &l["height"]),
        });
        if !mips.is_empty() {
            t["mipLevels"] = json!(mips);
        }
        out.insert(format!("{stem}Texture"), t);
    }
    Value::Object(out)
}

/// The `KHR_materials_sheen` a fur material also carries: the far-field look of fur for viewers
/// without a `PELT_fur` runtime (a soft, fuzzy rim instead of a bare surface). From the
/// manifest (its layout, or the extension's: the keys used are shared):
///
/// - colour: the strands' colour as seen from afar, root to tip mixed by how much the strands
///   hide their roots (t = 0.5 + 0.5 · dots coverage), times min(1, 2 · coverage) (sparse fur
///   shows its skin, not a sheen);
/// - roughness: 0.3 (dense, straight, a velvet-like tight rim) up to 1 (sparse and leaning
///   strands scatter the rim broadly): 0.3 + 0.5 · (1 − coverage) + 0.2 · min(1, tilt / 3).
///
/// With `colorFromTexture` the material's base colour texture also tints the sheen
/// (`sheenColorTexture`, given as `base_color_texture`).
pub fn sheen_fallback(manifest: &Value, base_color_texture: Option<&Value>) -> Value {
    let num = |v: &Value, d: f64| v.as_f64().unwrap_or(d);
    let coverage = num(&manifest["coverage"]["dots"], 0.5).clamp(0.0, 1.0);
    let t = 0.5 + 0.5 * coverage;
    let strength = (2.0 * coverage).min(1.0);
    let color: Vec<Value> = (0..3)
        .map(|k| {
            let (b, tip) = (
                num(&manifest["baseColor"][k], 0.0),
                num(&manifest["tipColor"][k], 0.0),
            );
            let c = ((b + (tip - b) * t) * strength).clamp(0.0, 1.0);
            json!((c * 1e4).round() / 1e4)
        })
        .collect();
    let tilt = num(&manifest["strands"]["tilt"], 0.0).max(0.0);
    let rough = (0.3 + 0.5 * (1.0 - coverage) + 0.2 * (tilt / 3.0).min(1.0)).clamp(0.3, 1.0);
    let mut sheen = json!({
        "sheenColorFactor": color,
        "sheenRoughnessFactor": (rough * 1e4).round() / 1e4,
    });
    if manifest["colorFromTexture"].as_bool() == Some(true)
        && let Some(t) = base_color_texture
    {
        sheen["sheenColorTexture"] = t.clone();
    }
    sheen
}

/// Every accessor reference in a primitive extension's `fins` (the records, or the
/// exceptions of fins derived from the index list), visited mutably.
pub fn for_each_fin_accessor(fins: &mut Value, f: &mut impl FnMut(&mut Value)) {
    if let Some(v) = fins.get_mut("accessor") {
        f(v);
    }
    if let Some(d) = fins.get_mut("fromIndices") {
        for part in ["added", "removed"] {
            if let Some(v) = d.get_mut(part) {
                f(v);
            }
        }
    }
}

/// Every texture reference in a material extension object (`…Texture.index` and
/// `…Texture.mipLevels[]`), visited mutably.
pub fn for_each_material_texture(fur: &mut Value, f: &mut dyn FnMut(&mut Value)) {
    let Some(o) = fur.as_object_mut() else {
        return;
    };
    for stem in TEXTURE_STEMS {
        let Some(t) = o.get_mut(&format!("{stem}Texture")) else {
            continue;
        };
        if let Some(i) = t.get_mut("index") {
            f(i);
        }
        if let Some(m) = t.get_mut("mipLevels").and_then(Value::as_array_mut) {
            m.iter_mut().for_each(&mut *f);
        }
    }
}

/// Every bufferView reference in a primitive's `extras.pelt.fins` (the records, or the
/// exceptions of fins derived from the index list), visited mutably.
pub(crate) fn for_each_fin_view(fins: &mut Value, f: &mut impl FnMut(&mut Value)) {
    if let Some(v) = fins.get_mut("bufferView") {
        f(v);
    }
    if let Some(d) = fins.get_mut("fromIndices") {
        for part in ["added", "removed"] {
            if let Some(v) = d.get_mut(part).and_then(|p| p.get_mut("bufferView")) {
                f(v);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_hash_is_xxh32_over_little_endian_words() {
        // Reference values from the xxHash C library (Python's `xxhash.xxh32(bytes, seed=0)`):
        // the empty input, <u32 1, and <u32 [0, 1, 2, 2, 1, 3].
        assert_eq!(index_hash(&[]), 46_947_589);
        assert_eq!(index_hash(&[1]), 4_089_149_075);
        assert_eq!(index_hash(&[0, 1, 2, 2, 1, 3]), 1_175_828_522);
        // Reordering triangles changes it (a stale record's tell).
        assert_ne!(
            index_hash(&[0, 1, 2, 2, 3, 0]),
            index_hash(&[2, 3, 0, 0, 1, 2])
        );
    }

    #[test]
    fn manifest_round_trips_through_the_extension_layout() {
        let manifest = json!({
            "version": 1, "length": 0.04, "shells": 16, "uvScale": 6.0,
            "textures": {
                "heightfield": {"texture": 0, "format": "gray16", "levels": [
                    {"image": 0, "width": 4, "height": 4}, {"image": 1, "width": 2, "height": 2},
                    {"image": 2, "width": 1, "height": 1}]},
                "dots": {"texture": 1, "format": "gray8", "levels": [
                    {"image": 3, "width": 4, "height": 4}]},
                "fin": {"texture": 2, "format": "rgba8", "levels": [
                    {"image": 4, "width": 4, "height": 1}, {"image": 5, "width": 2, "height": 1}]}
            }
        });
        // Texture k holds image k.
        let ext = extension_from_manifest(&manifest, &mut |i| i);
        assert_eq!(ext["heightfieldTexture"]["mipLevels"], json!([1, 2]));
        assert!(ext.get("textures").is_none() && ext.get("version").is_none());
        let root = json!({
            "asset": {"version": "2.0"},
            "textures": (0..6).map(|i| json!({"source": i})).collect::<Vec<_>>(),
        });
        let doc = Document::from_parts(
            std::path::Path::new("t.glb"),
            root.as_object().expect("object").clone(),
            Vec::new(),
        );
        let back = doc
            .manifest_from_extension(ext.as_object().expect("object"), "m")
            .expect("converts");
        let mut want = manifest.clone();
        // The texture entry's level-0 texture is the level-0 reference.
        want["textures"]["dots"]["texture"] = json!(3);
        want["textures"]["fin"]["texture"] = json!(4);
        assert_eq!(back["textures"], want["textures"]);
        // A chain longer than the size allows is refused (no allocation from the count).
        let mut bad = ext.clone();
        bad["finTexture"]["mipLevels"] = json!([5, 5, 5, 5]);
        assert!(
            doc.manifest_from_extension(bad.as_object().expect("object"), "m")
                .unwrap_err()
                .to_string()
                .contains("at most 3")
        );
    }
}
