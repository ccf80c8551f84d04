//! One glTF primitive read into pelt's [`Mesh`]: POSITION, NORMAL, TEXCOORD_0, TANGENT and
//! COLOR_0 decoded to f32 (any legal encoding), indices (or the implicit 0..n). Every float
//! attribute of the primitive, morph targets included, is checked finite, because pelt copies
//! what it does not change and must not carry a NaN into its output.

use glam::{Vec2, Vec3, Vec4};
use pelt_geom::Mesh;
use pelt_geom::mesh::check_finite;
use serde_json::Value;

use crate::accessor::{self, ComponentType};
use crate::document::{Document, PrimitiveRef};
use crate::error::Result;
use crate::triangles;

/// How an attribute is stored, for reports.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Encoding {
    /// Accessor index.
    pub accessor: usize,
    /// `VEC3`, `VEC4`, …
    pub ty: String,
    /// Component type.
    pub component: ComponentType,
    /// Normalized integers.
    pub normalized: bool,
    /// Uses sparse storage.
    pub sparse: bool,
}

impl Encoding {
    /// `VEC4 unsigned byte normalized`, `VEC3 float`, …
    pub fn describe(&self) -> String {
        let mut s = format!("{} {}", self.ty, self.component.name());
        if self.normalized {
            s.push_str(" normalized");
        }
        if self.sparse {
            s.push_str(" sparse");
        }
        s
    }
}

/// A primitive read for baking.
#[derive(Debug, Clone)]
pub struct PrimitiveMesh {
    /// The geometry.
    pub mesh: Mesh,
    /// COLOR_0's storage, when present.
    pub color: Option<Encoding>,
    /// Whether the source had an `indices` accessor.
    pub indexed: bool,
    /// The source's mode: TRIANGLES, or a strip or fan whose indices were made a list.
    pub mode: u64,
    /// Degenerate strip or fan triangles dropped from the list.
    pub dropped: usize,
}

/// The encoding of accessor `index`.
pub fn encoding(doc: &Document, index: usize) -> Option<Encoding> {
    let a = doc.array("accessors").get(index)?;
    Some(Encoding {
        accessor: index,
        ty: a.get("type")?.as_str()?.to_owned(),
        component: ComponentType::from_gl(a.get("componentType")?.as_u64()?)?,
        normalized: a
            .get("normalized")
            .and_then(Value::as_bool)
            .unwrap_or(false),
        sparse: a.get("sparse").is_some(),
    })
}

/// A VEC3 color decoded straight to RGBA with alpha 1.
struct Rgb(Vec4);

impl From<[f32; 3]> for Rgb {
    fn from([r, g, b]: [f32; 3]) -> Self {
        Rgb(Vec4::new(r, g, b, 1.0))
    }
}

/// Reads primitive `r` (TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN; strips and fans become
/// lists, [`crate::triangles`]) into a [`PrimitiveMesh`].
pub fn read_primitive(doc: &Document, r: PrimitiveRef) -> Result<PrimitiveMesh> {
    let place = doc.place(r);
    let attr = |name: &str| -> Result<Option<usize>> { doc.attribute(r, name) };
    let at = |name: &str| format!("{place} attribute {name}");

    let pos_i =
        attr("POSITION")?.ok_or_else(|| doc.invalid(&place, "has no POSITION attribute"))?;
    let positions: Vec<Vec3> = accessor::read_vec_as::<3, Vec3>(doc, pos_i, &at("POSITION"))?;
    let n = positions.len();
    let checked_len = |name: &str, len: usize| -> Result<()> {
        if len == n {
            Ok(())
        } else {
            Err(doc.invalid(at(name), format!("has {len} elements, POSITION has {n}")))
        }
    };

    // An optional float vector attribute, with its length checked against POSITION.
    fn optional<const N: usize, T: From<[f32; N]> + Send>(
        doc: &Document,
        index: Option<usize>,
        place: &str,
        checked_len: &dyn Fn(usize) -> Result<()>,
    ) -> Result<Option<Vec<T>>> {
        let Some(i) = index else { return Ok(None) };
        let v = accessor::read_vec_as::<N, T>(doc, i, place)?;
        checked_len(v.len())?;
        Ok(Some(v))
    }
    let colors = || read_colors(doc, r, &place, n);
    let indices = || read_indices(doc, r, &place, n);
    let mode = doc.mode(r)?;
    if !triangles::is_triangles(mode) {
        return Err(doc.invalid(
            &place,
            format!(
                "mode {mode} ({}) draws no triangles",
                triangles::mode_name(mode)
            ),
        ));
    }
    // The attributes and indices are decoded side by side; a file with several faults gets
    // the error of the first in this order, as if read one after another.
    let ((normals, uvs), (tangents, (colors, indices))) = rayon::join(
        || {
            rayon::join(
                || -> Result<Option<Vec<Vec3>>> {
                    optional(doc, attr("NORMAL")?, &at("NORMAL"), &|l| {
                        checked_len("NORMAL", l)
                    })
                },
                || -> Result<Option<Vec<Vec2>>> {
                    optional(doc, attr("TEXCOORD_0")?, &at("TEXCOORD_0"), &|l| {
                        checked_len("TEXCOORD_0", l)
                    })
                },
            )
        },
        || {
            rayon::join(
                || -> Result<Option<Vec<Vec4>>> {
                    optional(doc, attr("TANGENT")?, &at("TANGENT"), &|l| {
                        checked_len("TANGENT", l)
                    })
                },
                || rayon::join(colors, indices),
            )
        },
    );
    let (normals, uvs, tangents) = (normals?, uvs?, tangents?);
    let (colors, color) = colors?;
    let (indices, indexed) = indices?;
    let (indices, dropped) = triangles::triangle_list(mode, indices);

    let mesh = Mesh {
        positions,
        normals,
        uvs,
        tangents,
        colors,
        indices,
    };
    mesh.validate()
        .map_err(|e| doc.invalid(&place, e.to_string()))?;
    check_other_floats(doc, r)?;
    Ok(PrimitiveMesh {
        mesh,
        color,
        indexed,
        mode,
        dropped,
    })
}

/// Reading COLOR_0 (the comb): float, or normalized unsigned byte or short, VEC3 or VEC4,
/// one per vertex (`n`); with the colour encoding the file records for it.
fn read_colors(
    doc: &Document,
    r: PrimitiveRef,
    place: &str,
    n: usize,
) -> Result<(Option<Vec<Vec4>>, Option<Encoding>)> {
    let at = format!("{place} attribute COLOR_0");
    let Some(i) = doc.attribute(r, "COLOR_0")? else {
        return Ok((None, None));
    };
    let e = accessor::locate(doc, i, &at)?;
    let legal = e.component == ComponentType::F32
        || (e.normalized && matches!(e.component, ComponentType::U8 | ComponentType::U16));
    if !legal || !(e.components == 3 || e.components == 4) {
        return Err(doc.invalid(
            format!("{at} (accessor {i})"),
            format!(
                "COLOR_0 must be VEC3 or VEC4 of float or normalized unsigned byte/short, found {} {}{}",
                e.ty,
                e.component.name(),
                if e.normalized { " normalized" } else { "" }
            ),
        ));
    }
    if e.count != n {
        return Err(doc.invalid(at, format!("has {} elements, POSITION has {n}", e.count)));
    }
    let c: Vec<Vec4> = if e.components == 4 {
        e.decode::<4, Vec4>(doc)?
    } else {
        e.decode::<3, Rgb>(doc)?.into_iter().map(|c| c.0).collect()
    };
    Ok((Some(c), encoding(doc, i)))
}

/// Reading the indices: the index accessor's, or `0..n` for a primitive without one (the
/// flag says which).
fn read_indices(
    doc: &Document,
    r: PrimitiveRef,
    place: &str,
    n: usize,
) -> Result<(Vec<u32>, bool)> {
    let prim = doc.primitive(r)?;
    Ok(match prim.get("indices") {
        Some(v) => {
            let i = v
                .as_u64()
                .ok_or_else(|| doc.invalid(format!("{place} indices"), "not an accessor index"))?
                as usize;
            (
                accessor::read_indices(doc, i, &format!("{place} indices"))?,
                true,
            )
        }
        None => ((0..n as u32).collect(), false),
    })
}

/// Every other float attribute (and morph target) must be finite too.
fn check_other_floats(doc: &Document, r: PrimitiveRef) -> Result<()> {
    const READ: [&str; 5] = ["POSITION", "NORMAL", "TEXCOORD_0", "TANGENT", "COLOR_0"];
    let place = doc.place(r);
    let prim = doc.primitive(r)?;
    let mut list: Vec<(String, usize)> = Vec::new();
    if let Some(a) = prim.get("attributes").and_then(Value::as_object) {
        for (k, v) in a {
            if !READ.contains(&k.as_str()) {
                if let Some(i) = v.as_u64() {
                    list.push((format!("attribute {k}"), i as usize));
                }
            }
        }
    }
    if let Some(ts) = prim.get("targets").and_then(Value::as_array) {
        for (t, target) in ts.iter().enumerate() {
            for (k, v) in target.as_object().into_iter().flatten() {
                if let Some(i) = v.as_u64() {
                    list.push((format!("targets[{t}].{k}"), i as usize));
                }
            }
        }
    }
    for (what, i) in list {
        let e = accessor::read(doc, i, &format!("{place} {what}"))?;
        if e.component == ComponentType::F32 {
            let values = (0..e.count * e.components).map(|k| [e.component_f32(k)]);
            check_finite(&what, values).map_err(|err| {
                // Report the element (vertex), not the flat component index.
                let msg = match err {
                    pelt_geom::GeomError::NonFinite { vertex, value, .. } => format!(
                        "{what}: vertex {} has a non-finite value ({value})",
                        vertex / e.components
                    ),
                    other => other.to_string(),
                };
                doc.invalid(&place, msg)
            })?;
        }
    }
    Ok(())
}
