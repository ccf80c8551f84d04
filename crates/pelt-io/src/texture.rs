//! Adding images, samplers and textures to a document (the fur textures a bake embeds), and
//! reading a material's `extras`.

use serde_json::{Map, Value, json};

use crate::document::Document;
use crate::edit::push_to;
use crate::error::Result;

/// glTF sampler constants.
pub mod gl {
    /// `LINEAR`.
    pub const LINEAR: u32 = 9729;
    /// `LINEAR_MIPMAP_LINEAR`.
    pub const LINEAR_MIPMAP_LINEAR: u32 = 9987;
    /// `REPEAT`.
    pub const REPEAT: u32 = 10497;
    /// `CLAMP_TO_EDGE`.
    pub const CLAMP_TO_EDGE: u32 = 33071;
}

/// `metallicFactor` of the material a bake adds: a dielectric.
pub const NEUTRAL_METALLIC: f32 = 0.0;
/// `roughnessFactor` of the material a bake adds.
pub const NEUTRAL_ROUGHNESS: f32 = 0.5;

fn neutral_pbr() -> Value {
    json!({ "metallicFactor": NEUTRAL_METALLIC, "roughnessFactor": NEUTRAL_ROUGHNESS })
}

impl Document {
    /// Appends an image stored in a new bufferView; returns the image index.
    pub fn push_image(&mut self, bytes: Vec<u8>, mime: &str, name: &str) -> usize {
        let view = self.push_view(bytes, None);
        self.uri_images.resize(self.array("images").len(), None);
        let index = push_to(
            &mut self.json,
            "images",
            json!({ "bufferView": view, "mimeType": mime, "name": name }),
        );
        self.uri_images.push(None);
        index
    }

    /// Appends a sampler; returns its index.
    pub fn push_sampler(&mut self, mag: u32, min: u32, wrap_s: u32, wrap_t: u32) -> usize {
        push_to(
            &mut self.json,
            "samplers",
            json!({ "magFilter": mag, "minFilter": min, "wrapS": wrap_s, "wrapT": wrap_t }),
        )
    }

    /// Appends a texture; returns its index.
    pub fn push_texture(&mut self, image: usize, sampler: usize, name: &str) -> usize {
        push_to(
            &mut self.json,
            "textures",
            json!({ "sampler": sampler, "source": image, "name": name }),
        )
    }

    /// Appends a material named `name`: a dielectric of roughness 0.5 ([`NEUTRAL_METALLIC`],
    /// [`NEUTRAL_ROUGHNESS`]), the surface pelt's preview draws for a primitive without a
    /// material, where glTF's defaults (metallic 1, roughness 1) would be black metal in a
    /// renderer without environment light. Returns its index.
    pub fn push_material(&mut self, name: &str) -> usize {
        push_to(
            &mut self.json,
            "materials",
            json!({ "name": name, "pbrMetallicRoughness": neutral_pbr() }),
        )
    }

    /// Gives `materials[material]` the neutral dielectric's factors when it has no
    /// `pbrMetallicRoughness` at all (a material made with glTF's defaults). Returns whether
    /// it changed anything.
    pub fn make_neutral_if_default(&mut self, material: usize) -> bool {
        let Some(m) = self.material_mut(material) else {
            return false;
        };
        if m.contains_key("pbrMetallicRoughness") {
            return false;
        }
        m.insert("pbrMetallicRoughness".to_owned(), neutral_pbr());
        true
    }

    /// `materials[material]` as an object, when it is one.
    fn material_mut(&mut self, material: usize) -> Option<&mut Map<String, Value>> {
        self.json
            .get_mut("materials")
            .and_then(Value::as_array_mut)
            .and_then(|a| a.get_mut(material))
            .and_then(Value::as_object_mut)
    }

    /// Whether `materials[material]` has a `normalTexture` (false for a material that does
    /// not exist).
    pub fn material_has_normal_texture(&self, material: usize) -> bool {
        self.array("materials")
            .get(material)
            .and_then(|m| m.get("normalTexture"))
            .is_some_and(|t| !t.is_null())
    }

    /// The material's name, if any.
    pub fn material_name(&self, material: usize) -> Option<&str> {
        self.array("materials").get(material)?.get("name")?.as_str()
    }

    /// Sets `materials[material].extras[key]`, keeping other extras. Returns false, and
    /// changes nothing, when the material does not exist or its `extras` is not an object.
    pub fn set_material_extra(&mut self, material: usize, key: &str, value: Value) -> bool {
        self.set_in_material(material, "extras", key, value)
    }

    /// Sets `materials[material].extensions[name]` and lists `name` in `extensionsUsed`.
    /// Returns false, and changes nothing, when the material does not exist or its
    /// `extensions` is not an object.
    pub fn set_material_extension(&mut self, material: usize, name: &str, value: Value) -> bool {
        let set = self.set_in_material(material, "extensions", name, value);
        if set {
            self.use_extension(name);
        }
        set
    }

    /// Whether `materials[material].extensions` has `name` (false for a material that does
    /// not exist).
    pub fn material_has_extension(&self, material: usize, name: &str) -> bool {
        self.array("materials")
            .get(material)
            .and_then(|m| m.get("extensions"))
            .is_some_and(|e| e.get(name).is_some())
    }

    /// Sets `materials[material][object][key]` (creating `object`), keeping its other keys;
    /// false when the material does not exist or `object` is not a JSON object.
    fn set_in_material(&mut self, material: usize, object: &str, key: &str, value: Value) -> bool {
        let Some(m) = self.material_mut(material) else {
            return false;
        };
        let entry = m.entry(object).or_insert_with(|| Value::Object(Map::new()));
        match entry.as_object_mut() {
            Some(o) => {
                o.insert(key.to_owned(), value);
                true
            }
            None => false,
        }
    }

    /// The bytes of `images[image]`: from its bufferView, or as loaded from its URI. The
    /// error names the image.
    pub fn image_bytes(&self, image: usize) -> Result<&[u8]> {
        let place = format!("images[{image}]");
        let img = self.array("images").get(image).ok_or_else(|| {
            self.invalid(
                &place,
                format!("does not exist ({} defined)", self.array("images").len()),
            )
        })?;
        if let Some(Some(u)) = self.uri_images.get(image) {
            return Ok(&u.bytes);
        }
        let view = img
            .get("bufferView")
            .and_then(Value::as_u64)
            .ok_or_else(|| self.invalid(&place, "has neither a loaded URI nor a bufferView"))?;
        Ok(crate::accessor::view_bytes(self, view as usize, &place)?.0)
    }

    /// The primitive's material index, if any.
    pub fn primitive_material(&self, r: crate::PrimitiveRef) -> Result<Option<usize>> {
        Ok(self
            .primitive(r)?
            .get("material")
            .and_then(Value::as_u64)
            .map(|m| m as usize))
    }

    /// Sets the primitive's material.
    pub fn set_primitive_material(
        &mut self,
        r: crate::PrimitiveRef,
        material: usize,
    ) -> Result<()> {
        self.primitive_checked(r)?
            .insert("material".into(), json!(material));
        Ok(())
    }
}
