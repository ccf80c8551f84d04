//! An OBJ's materials as glTF materials: each `mtllib` is read (relative to the OBJ, never
//! outside its folder) in any encoding [`crate::text`] reads and parsed by `tobj`; each
//! material an object uses becomes a glTF material: `Kd` (or white under a `map_Kd`) and `d` the
//! base colour, `map_Kd` the base colour texture, `map_Bump`/`bump`/`norm` the normal texture
//! (`-bm` its scale), `Pr`/`Pm` (or `Ns`, as Blender converts it) roughness and metalness.
//! Texture images are embedded; PNG and JPEG only, as glTF allows.
//!
//! What cannot be read is a warning, never a refusal: a missing, empty or unreadable `.mtl`
//! leaves the mesh without materials, a missing or unsupported image leaves the material
//! without that texture. A `newmtl` or `usemtl` line without a name (which assimp and
//! Blender read, and tobj refuses) is read as the material [`UNNAMED`], with a warning.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

use serde_json::{Map, Value, json};

use crate::document::{Document, mime_from_bytes};
use crate::texture::gl;

/// Reads the `.mtl` files an OBJ names, collecting warnings and the files read.
pub(crate) struct MtlReader<'a> {
    obj: &'a Path,
    pub(crate) warnings: RefCell<Vec<String>>,
    pub(crate) files: RefCell<Vec<PathBuf>>,
}

/// Why a file an OBJ or MTL names was not read: a warning, since the OBJ loads without it.
/// The message names the file as the OBJ or MTL spells it.
#[derive(Debug, thiserror::Error)]
pub(crate) enum NamedFileError {
    /// The name is empty, absolute, or leaves the OBJ's folder.
    #[error("{name:?} {why}")]
    NotFollowed {
        /// The name as written.
        name: String,
        /// Why it is not followed.
        why: &'static str,
    },
    /// The file could not be read.
    #[error("{name:?}: {source}")]
    Read {
        /// The name as written.
        name: String,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
}

/// A path an OBJ or MTL names, as a relative path that stays in the asset's folder.
fn relative(name: &str) -> Result<PathBuf, &'static str> {
    let path = PathBuf::from(name.replace('\\', "/"));
    if path.as_os_str().is_empty() {
        return Err("is empty");
    }
    if path.is_absolute() || name.contains(':') {
        return Err("is an absolute path; only paths relative to the OBJ are followed");
    }
    if path
        .components()
        .any(|c| !matches!(c, Component::Normal(_) | Component::CurDir))
    {
        return Err("leaves the OBJ's folder");
    }
    Ok(path)
}

impl<'a> MtlReader<'a> {
    pub(crate) fn new(obj: &'a Path) -> Self {
        MtlReader {
            obj,
            warnings: RefCell::new(Vec::new()),
            files: RefCell::new(Vec::new()),
        }
    }

    fn warn(&self, message: String) {
        self.warnings.borrow_mut().push(message);
    }

    /// Reads a file named in the OBJ or an MTL, relative to the OBJ's folder.
    fn read(&self, name: &str) -> Result<(PathBuf, Vec<u8>), NamedFileError> {
        let rel = relative(name).map_err(|why| NamedFileError::NotFollowed {
            name: name.to_owned(),
            why,
        })?;
        let path = self
            .obj
            .parent()
            .map_or_else(|| rel.clone(), |d| d.join(&rel));
        let bytes = std::fs::read(&path).map_err(|source| NamedFileError::Read {
            name: name.to_owned(),
            source,
        })?;
        self.files.borrow_mut().push(path.clone());
        Ok((path, bytes))
    }

    /// tobj's material loader: never an error, so the OBJ always loads.
    pub(crate) fn load(&self, name: &Path) -> tobj::MTLLoadResult {
        let name = name.to_string_lossy();
        let empty = || Ok((Vec::new(), Default::default()));
        let (_, bytes) = match self.read(&name) {
            Ok(read) => read,
            Err(why) => {
                self.warn(format!(
                    "mtllib {why}: the mesh is baked without its materials"
                ));
                return empty();
            }
        };
        let mut warnings = Vec::new();
        let text = crate::text::decode(&name, &bytes, &mut warnings);
        let text = name_unnamed(&text, "newmtl", &format!("mtllib {name:?} "), &mut warnings);
        self.warnings.borrow_mut().extend(warnings);
        match tobj::load_mtl_buf(&mut std::io::Cursor::new(text.as_bytes())) {
            Ok((mats, _)) if mats.is_empty() => {
                self.warn(format!(
                    "mtllib {name:?} holds no materials: the mesh is baked without them"
                ));
                empty()
            }
            Ok(loaded) => Ok(loaded),
            Err(e) => {
                self.warn(format!(
                    "mtllib {name:?} cannot be read ({e}): the mesh is baked without its \
                     materials"
                ));
                empty()
            }
        }
    }
}

/// The name a `newmtl` or `usemtl` line without one is read under.
pub(crate) const UNNAMED: &str = "unnamed";

/// `text` with every `keyword` line that names nothing naming [`UNNAMED`] instead, and a
/// warning per such line (`label` names the file, or is empty for the OBJ itself).
pub(crate) fn name_unnamed<'a>(
    text: &'a str,
    keyword: &str,
    label: &str,
    warnings: &mut Vec<String>,
) -> std::borrow::Cow<'a, str> {
    let unnamed = |line: &str| {
        let mut words = line.split_whitespace();
        words.next() == Some(keyword) && words.next().is_none()
    };
    if !text.lines().any(unnamed) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 16);
    for (n, line) in text.split_inclusive('\n').enumerate() {
        if unnamed(line) {
            warnings.push(format!(
                "{label}line {}: {keyword} without a name: read as the material {UNNAMED:?}",
                n + 1
            ));
            out.push_str(&format!("{keyword} {UNNAMED}\n"));
        } else {
            out.push_str(line);
        }
    }
    std::borrow::Cow::Owned(out)
}

/// The file name of a texture statement, past its options (`-s 1 1 1`, `-bm 0.5`, …), and the
/// `-bm` scale when given.
fn texture_name(statement: &str) -> (String, Option<f32>) {
    let words: Vec<&str> = statement.split_whitespace().collect();
    let mut i = 0;
    let mut bm = None;
    while i < words.len() && words[i].starts_with('-') && words[i].len() > 1 {
        let option = words[i];
        i += 1;
        // Option arguments: numbers, on/off, or the one word -type/-imfchan take.
        let takes_word = matches!(option, "-type" | "-imfchan");
        while i < words.len()
            && (words[i].parse::<f32>().is_ok()
                || matches!(words[i], "on" | "off")
                || (takes_word && i > 0 && words[i - 1] == option))
        {
            if option == "-bm" {
                bm = words[i].parse().ok();
            }
            i += 1;
        }
    }
    (words[i.min(words.len())..].join(" "), bm)
}

/// Builds glTF materials, images and textures for the OBJ's materials as objects use them.
pub(crate) struct MaterialWriter<'a> {
    reader: &'a MtlReader<'a>,
    materials: &'a [tobj::Material],
    /// tobj material index → glTF material.
    made: BTreeMap<usize, usize>,
    /// Texture file name → glTF texture (None: could not be embedded).
    textures: BTreeMap<String, Option<usize>>,
    sampler: Option<usize>,
}

impl<'a> MaterialWriter<'a> {
    pub(crate) fn new(reader: &'a MtlReader<'a>, materials: &'a [tobj::Material]) -> Self {
        MaterialWriter {
            reader,
            materials,
            made: BTreeMap::new(),
            textures: BTreeMap::new(),
            sampler: None,
        }
    }

    /// The glTF material of tobj material `id`, made on first use.
    pub(crate) fn material(&mut self, doc: &mut Document, id: usize) -> Option<usize> {
        if let Some(&m) = self.made.get(&id) {
            return Some(m);
        }
        let mat = self.materials.get(id)?;
        let value = self.describe(doc, mat);
        let m = crate::edit::push_to(&mut doc.json, "materials", value);
        self.made.insert(id, m);
        Some(m)
    }

    fn describe(&mut self, doc: &mut Document, mat: &tobj::Material) -> Value {
        let alpha = mat.dissolve.unwrap_or(1.0).clamp(0.0, 1.0);
        let mut pbr = Map::new();
        let base = match &mat.diffuse_texture {
            Some(t) => {
                let (name, _) = texture_name(t);
                if let Some(index) = self.texture(doc, &name) {
                    pbr.insert("baseColorTexture".into(), json!({ "index": index }));
                }
                [1.0; 3]
            }
            None => mat.diffuse.unwrap_or([0.8; 3]),
        };
        let base = base.map(|c| c.clamp(0.0, 1.0));
        pbr.insert(
            "baseColorFactor".into(),
            json!([base[0], base[1], base[2], alpha]),
        );
        let param = |k: &str| -> Option<f32> { mat.unknown_param.get(k)?.trim().parse().ok() };
        let metallic = param("Pm").unwrap_or(0.0).clamp(0.0, 1.0);
        let roughness = param("Pr")
            .or_else(|| {
                mat.shininess
                    .map(|ns| 1.0 - (ns.clamp(0.0, 1000.0) / 1000.0).sqrt())
            })
            .unwrap_or(1.0)
            .clamp(0.0, 1.0);
        pbr.insert("metallicFactor".into(), json!(metallic));
        pbr.insert("roughnessFactor".into(), json!(roughness));
        let mut out = Map::new();
        out.insert("name".into(), json!(mat.name));
        out.insert("pbrMetallicRoughness".into(), Value::Object(pbr));
        let normal = mat
            .normal_texture
            .clone()
            .or_else(|| mat.unknown_param.get("norm").cloned());
        if let Some(statement) = normal {
            let (name, scale) = texture_name(&statement);
            if let Some(index) = self.texture(doc, &name) {
                let mut info = json!({ "index": index });
                if let Some(s) = scale.filter(|s| s.is_finite() && *s != 1.0) {
                    info["scale"] = json!(s);
                }
                out.insert("normalTexture".into(), info);
            }
        }
        if alpha < 1.0 {
            out.insert("alphaMode".into(), json!("BLEND"));
        }
        Value::Object(out)
    }

    /// The glTF texture showing image file `name`, embedded on first use.
    fn texture(&mut self, doc: &mut Document, name: &str) -> Option<usize> {
        if let Some(&t) = self.textures.get(name) {
            return t;
        }
        let t = self.embed(doc, name);
        self.textures.insert(name.to_owned(), t);
        t
    }

    fn embed(&mut self, doc: &mut Document, name: &str) -> Option<usize> {
        let bytes = match self.reader.read(name) {
            Ok((_, bytes)) => bytes,
            Err(why) => {
                self.reader
                    .warn(format!("texture {why}: the material is baked without it"));
                return None;
            }
        };
        let Some(mime) = mime_from_bytes(&bytes).filter(|m| m == "image/png" || m == "image/jpeg")
        else {
            self.reader.warn(format!(
                "texture {name:?} is not PNG or JPEG (all glTF allows without extensions): \
                 the material is baked without it"
            ));
            return None;
        };
        let image = doc.push_image(bytes, &mime, name);
        let sampler = *self.sampler.get_or_insert_with(|| {
            doc.push_sampler(gl::LINEAR, gl::LINEAR_MIPMAP_LINEAR, gl::REPEAT, gl::REPEAT)
        });
        Some(doc.push_texture(image, sampler, name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_options_are_skipped() {
        assert_eq!(texture_name("fur.png"), ("fur.png".into(), None));
        assert_eq!(
            texture_name("-s 2 2 1 -o 0 0 my fur.png"),
            ("my fur.png".into(), None)
        );
        assert_eq!(texture_name("-bm 0.5 n.png"), ("n.png".into(), Some(0.5)));
        assert_eq!(
            texture_name("-clamp on -imfchan l h.png"),
            ("h.png".into(), None)
        );
    }

    #[test]
    fn paths_stay_in_the_folder() {
        assert!(relative("tex/a.png").is_ok());
        assert!(relative("tex\\a.png").is_ok());
        assert!(relative("../a.png").is_err());
        assert!(relative("/etc/passwd").is_err());
        assert!(relative("C:\\a.png").is_err());
        assert!(relative("").is_err());
    }
}
