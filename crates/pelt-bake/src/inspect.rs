//! What a file holds, as a report (`pelt inspect`): per primitive, attributes with their
//! encodings and counts, position bounds, statistics of `_FUR_COMB` (or of COLOR_0 before a
//! bake), and the topology a bake stored (normal groups, IDs used, fin edges, boundary and
//! non-manifold edges, split vertices), with totals over the file, its skins and animations.
//! The comb decodes through `pelt_io::contract`, the same rules the bake and the preview use.

use std::collections::BTreeSet;

use pelt_io::accessor;
use pelt_io::contract::{self, NORMAL_GROUP_ATTRIBUTE};
use pelt_io::extension::{EXTENSION, Form};
use pelt_io::mesh::encoding;
use pelt_io::topology::StoredFins;
use serde_json::{Value, json};

/// The report of `doc`: file totals, topology totals, skins, animations, and per primitive
/// its attributes with their encodings, bounds, comb statistics (or COLOR_0's alpha before a
/// bake) and stored topology. `pelt inspect --json` prints it as it is.
pub fn describe(doc: &pelt_io::Document) -> Result<Value, pelt_io::IoError> {
    let mut prims = Vec::new();
    let mut ids = BTreeSet::new();
    let mut totals: Vec<(&str, Option<u64>)> = [
        "normal_groups",
        "split_vertices",
        "fin_edges",
        "boundary_edges",
        "nonmanifold_edges",
    ]
    .into_iter()
    .map(|k| (k, None))
    .collect();
    let (mut vertices, mut triangles) = (0usize, 0usize);
    for r in doc.primitives() {
        let place = doc.place(r);
        let (mut entry, count, tris) = primitive_entry(doc, r, &place)?;
        vertices += count;
        triangles += tris;
        if let Some(t) = topology(doc, r, &place)? {
            ids.extend(t.ids.iter().copied());
            for (k, v) in &mut totals {
                *v = v
                    .or(Some(0))
                    .map(|sum| sum + t.fields[*k].as_u64().unwrap_or(0));
            }
            entry["topology"] = t.fields;
        }
        entry["contract"] = contract_parts(doc, r, &entry)?;
        prims.push(entry);
    }
    let rig = if doc.array("skins").is_empty() && doc.array("animations").is_empty() {
        None
    } else {
        Some(pelt_anim::Rig::load(doc)?.summary())
    };
    let mut info = json!({
        "file": doc.path, "meshes": doc.array("meshes").len(), "primitives": prims.len(),
        "vertices": vertices, "triangles": triangles, "nodes": doc.array("nodes").len(),
        "materials": doc.array("materials").len(), "images": doc.array("images").len(),
    });
    if let Some(r) = rig {
        info["skins"] = json!(r.skins);
        info["animations"] = json!(r.animations);
    }
    // Topology totals: null when no primitive has any (not baked, or --topology off).
    for (k, v) in totals {
        info[k] = json!(v);
    }
    info["ids_used"] = if ids.is_empty() && info["normal_groups"].is_null() {
        json!(null)
    } else {
        json!(ids.len())
    };
    info["primitive"] = Value::Array(prims);
    Ok(info)
}

/// One primitive's entry, before its topology and contract: mesh, mode, vertex and triangle
/// counts, attributes, bounds, and the comb's statistics (or COLOR_0's lengths when it holds
/// no comb). Returns the entry with its vertex and triangle counts.
fn primitive_entry(
    doc: &pelt_io::Document,
    r: pelt_io::PrimitiveRef,
    place: &str,
) -> Result<(Value, usize, usize), pelt_io::IoError> {
    let p = doc.primitive(r)?;
    let mode = doc.mode(r)?;
    let (attrs, count) = attribute_table(doc, place, p)?;
    let indices = match p.get("indices").and_then(Value::as_u64) {
        Some(i) => accessor::read_indices(doc, i as usize, &format!("{place} indices"))?.len(),
        None => count,
    };
    let tris = match mode {
        4 => indices / 3,
        5 | 6 => indices.saturating_sub(2),
        _ => 0,
    };
    let mut entry = json!({
        "mesh": r.mesh, "primitive": r.primitive, "name": doc.mesh_name(r.mesh),
        "mode": mode, "vertices": count, "triangles": tris, "attributes": attrs,
    });
    if let Some(i) = doc.attribute(r, "POSITION")? {
        let p = accessor::read_vec::<3>(doc, i, &format!("{place} attribute POSITION"))?;
        let (lo, hi) = p.iter().fold(
            ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]),
            |(lo, hi), v| {
                (
                    std::array::from_fn(|k| lo[k].min(v[k])),
                    std::array::from_fn(|k| hi[k].max(v[k])),
                )
            },
        );
        entry["bounds"] = json!({"min": lo, "max": hi});
    }
    if let Some(c) = contract::read_comb(doc, r, count)? {
        entry["comb"] = comb_stats(c.iter().map(|&c| c.to_array()));
    } else if let Some(i) = doc.attribute(r, "COLOR_0")? {
        let e = accessor::read(doc, i, &format!("{place} attribute COLOR_0"))?;
        let lens: Vec<f32> = (0..e.count)
            .map(|k| {
                if e.components == 4 {
                    e.component_f32(4 * k + 3)
                } else {
                    1.0
                }
            })
            .collect();
        entry["color_0_length"] = range_stats(&lens);
    }
    Ok((entry, count, tris))
}

/// The attribute table of primitive `p`: each attribute's accessor, colour encoding and
/// count, and the vertex count (the last attribute's count).
fn attribute_table(
    doc: &pelt_io::Document,
    place: &str,
    p: &serde_json::Map<String, Value>,
) -> Result<(serde_json::Map<String, Value>, usize), pelt_io::IoError> {
    let mut attrs = serde_json::Map::new();
    let mut count = 0usize;
    for (name, v) in p
        .get("attributes")
        .and_then(Value::as_object)
        .into_iter()
        .flatten()
    {
        let Some(i) = v.as_u64().map(|i| i as usize) else {
            continue;
        };
        let e = accessor::read(doc, i, &format!("{place} attribute {name}"))?;
        count = e.count;
        let enc = encoding(doc, i).map(|e| e.describe()).unwrap_or_default();
        attrs.insert(
            name.clone(),
            json!({"accessor": i, "encoding": enc, "count": e.count}),
        );
    }
    Ok((attrs, count))
}

/// A primitive's topology as stored by a bake.
struct Topology {
    /// normal_groups, split_vertices, edges, boundary_edges, nonmanifold_edges, fin_edges,
    /// ids_used (this primitive's).
    fields: Value,
    /// Distinct IDs in `_NORMAL_GROUP`.
    ids: BTreeSet<u16>,
}

/// Reads the primitive's `PELT_fur` (or legacy `extras.pelt`), the fin records (checked; stale
/// records are reported as such, with why) and the IDs actually stored in `_NORMAL_GROUP`.
/// None when the primitive has neither.
fn topology(
    doc: &pelt_io::Document,
    r: pelt_io::PrimitiveRef,
    place: &str,
) -> Result<Option<Topology>, pelt_io::IoError> {
    let Some((pelt, form)) = doc.fur_primitive(r)? else {
        return Ok(None);
    };
    let num = |v: &Value| v.as_u64().unwrap_or(0);
    let groups = &pelt["normalGroups"];
    let edges = &pelt["edges"];
    let mut ids = BTreeSet::new();
    if let Some(i) = doc.attribute(r, NORMAL_GROUP_ATTRIBUTE)? {
        let e = accessor::read(
            doc,
            i,
            &format!("{place} attribute {NORMAL_GROUP_ATTRIBUTE}"),
        )?;
        ids.extend((0..e.count).map(|k| accessor::raw(e.component, &e.bytes, k) as u16));
        ids.remove(&0);
    }
    let (fins, stale) = match doc.read_stored_fins(r)? {
        Some(StoredFins::Valid(f)) => (Some(f.len()), None),
        Some(StoredFins::Stale(why)) => (None, Some(why)),
        None => (None, None),
    };
    Ok(Some(Topology {
        fields: json!({
            "form": match form {
                Form::Extension => EXTENSION.to_owned(),
                Form::Legacy => format!("extras.pelt version {}", num(&pelt["version"])),
            },
            "tangents": pelt.get("tangents").and_then(Value::as_str),
            "normal_groups": num(&groups["groups"]),
            "ids_used": ids.len(),
            "split_vertices": num(&groups["splitVertices"]),
            "edges": num(&edges["unique"]),
            "boundary_edges": num(&edges["boundary"]),
            "nonmanifold_edges": num(&edges["nonmanifold"]),
            "fin_edges": fins,
            "fins_stale": stale,
        }),
        ids,
    }))
}

/// Which parts of pelt's contract the primitive carries (`pelt inspect`'s `contract`): the
/// comb and group attributes, the stored topology and the material's fur manifest, each
/// present or not, and what a file that lost some of them will do.
fn contract_parts(
    doc: &pelt_io::Document,
    r: pelt_io::PrimitiveRef,
    entry: &Value,
) -> Result<Value, pelt_io::IoError> {
    let comb = doc.attribute(r, contract::COMB_ATTRIBUTE)?.is_some();
    let groups = doc.attribute(r, NORMAL_GROUP_ATTRIBUTE)?.is_some();
    let manifest = match doc.primitive_material(r)? {
        Some(m) => doc.fur_manifest_json(m)?.map(|(_, place)| place),
        None => None,
    };
    let t = &entry["topology"];
    let fins = if !t["fins_stale"].is_null() {
        "stale (rebuilt at load)"
    } else if !t["fin_edges"].is_null() {
        "present"
    } else {
        "absent"
    };
    Ok(json!({
        "comb": comb,
        "normal_groups": groups,
        "topology": t["form"],
        "fins": fins,
        "fur_manifest": manifest,
    }))
}

fn range_stats(v: &[f32]) -> Value {
    if v.is_empty() {
        return json!(null);
    }
    let (lo, hi) = v
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    let mean = v.iter().map(|&x| f64::from(x)).sum::<f64>() / v.len() as f64;
    json!({"min": lo, "mean": mean, "max": hi})
}

fn comb_stats(c: impl Iterator<Item = [f32; 4]>) -> Value {
    let c: Vec<[f32; 4]> = c.collect();
    let lens: Vec<f32> = c.iter().map(|c| c[3]).collect();
    let zero = lens.iter().filter(|&&l| l == 0.0).count();
    let (mut max_z, mut max_unit_err) = (0f64, 0f64);
    for v in &c {
        let (x, y, z) = (f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
        max_z = max_z.max(z.abs());
        max_unit_err = max_unit_err.max(((x * x + y * y + z * z).sqrt() - 1.0).abs());
    }
    json!({"count": c.len(), "zero_length": zero, "length": range_stats(&lens), "max_abs_z": max_z, "max_unit_error": max_unit_err})
}

/// Appends a formatted line to the `String` `out`.
macro_rules! say {
    ($out:expr, $($t:tt)*) => {{
        $out.push_str(&format!($($t)*));
        $out.push('\n');
    }};
}

/// [`describe`]'s report as the lines `pelt inspect` prints.
pub fn text(v: &Value) -> String {
    let mut out = String::new();
    asset_lines(v, &mut out);
    for p in v["primitive"].as_array().into_iter().flatten() {
        primitive_lines(p, &mut out);
    }
    out
}

/// The asset's lines: its counts, its topology totals (when baked), its skins and animations.
fn asset_lines(v: &Value, out: &mut String) {
    say!(
        out,
        "{}: {} meshes, {} primitives, {} vertices, {} triangles, {} nodes, {} materials, {} images",
        v["file"].as_str().unwrap_or("?"),
        v["meshes"],
        v["primitives"],
        v["vertices"],
        v["triangles"],
        v["nodes"],
        v["materials"],
        v["images"]
    );
    if !v["normal_groups"].is_null() {
        say!(
            out,
            "topology: {} normal groups, {} IDs used, {} split vertices, {} fin edges, {} boundary and {} non-manifold edges",
            v["normal_groups"],
            v["ids_used"],
            v["split_vertices"],
            v["fin_edges"],
            v["boundary_edges"],
            v["nonmanifold_edges"]
        );
    }
    for s in v["skins"].as_array().into_iter().flatten() {
        let names: Vec<&str> = s["joint_names"]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(Value::as_str)
            .collect();
        say!(
            out,
            "skin{}: {} joints ({})",
            s["name"]
                .as_str()
                .map(|n| format!(" {n:?}"))
                .unwrap_or_default(),
            s["joints"],
            names.join(", ")
        );
    }
    for a in v["animations"].as_array().into_iter().flatten() {
        say!(
            out,
            "animation {:?}: {:.3} s ({:.3} to {:.3} s), {} channels",
            a["name"].as_str().unwrap_or("?"),
            a["duration"].as_f64().unwrap_or(0.0),
            a["start"].as_f64().unwrap_or(0.0),
            a["end"].as_f64().unwrap_or(0.0),
            a["channels"]
        );
    }
}

/// One primitive's lines: its counts, attributes, bounds, comb (or COLOR_0's lengths) and
/// contract.
fn primitive_lines(p: &Value, out: &mut String) {
    let name = p["name"]
        .as_str()
        .map(|n| format!(" {n:?}"))
        .unwrap_or_default();
    say!(
        out,
        "meshes[{}]{name} primitives[{}]: mode {}, {} vertices, {} triangles",
        p["mesh"],
        p["primitive"],
        p["mode"],
        p["vertices"],
        p["triangles"]
    );
    for (k, a) in p["attributes"].as_object().into_iter().flatten() {
        say!(
            out,
            "  {k:<13} {} ({} elements, accessor {})",
            a["encoding"].as_str().unwrap_or("?"),
            a["count"],
            a["accessor"]
        );
    }
    if let Some(b) = p.get("bounds") {
        say!(out, "  bounds        min {} max {}", b["min"], b["max"]);
    }
    if let Some(c) = p.get("comb") {
        say!(
            out,
            "  comb          {} vertices, {} of length 0, length {}..{} (mean {:.3}), max |z| {:.2e}, max unit error {:.2e}",
            c["count"],
            c["zero_length"],
            c["length"]["min"],
            c["length"]["max"],
            c["length"]["mean"].as_f64().unwrap_or(0.0),
            c["max_abs_z"].as_f64().unwrap_or(0.0),
            c["max_unit_error"].as_f64().unwrap_or(0.0)
        );
    }
    if let Some(c) = p.get("color_0_length") {
        say!(
            out,
            "  COLOR_0 A     {}..{} (mean {:.3}); not baked yet",
            c["min"],
            c["max"],
            c["mean"].as_f64().unwrap_or(0.0)
        );
    }
    say!(
        out,
        "  contract      {}",
        contract_line(&p["contract"], &p["topology"])
    );
}

/// One line on which parts of pelt's contract a primitive carries.
fn contract_line(c: &Value, t: &Value) -> String {
    let has = |b: &Value, what: &str| {
        if b.as_bool() == Some(true) {
            what.to_owned()
        } else {
            format!("no {what}")
        }
    };
    let mut parts = vec![
        has(&c["comb"], "_FUR_COMB"),
        has(&c["normal_groups"], "_NORMAL_GROUP"),
    ];
    parts.push(match c["topology"].as_str() {
        Some(form) => format!("topology in {form}"),
        None => "no stored topology".into(),
    });
    parts.push(format!("fins {}", c["fins"].as_str().unwrap_or("?")));
    parts.push(match c["fur_manifest"].as_str() {
        Some(place) => format!("fur manifest at {place}"),
        None => "no fur manifest".into(),
    });
    let mut line = parts.join(", ");
    if let Some(why) = t["fins_stale"].as_str() {
        line.push_str(&format!("\n  stale fins    {why}"));
    }
    line
}
