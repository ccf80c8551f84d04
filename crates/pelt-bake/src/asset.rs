//! Baking a whole asset: every TRIANGLES primitive with COLOR_0 gets `_FUR_COMB` (and TANGENT,
//! NORMAL or a vertex split where needed), `_NORMAL_GROUP` and its fin edges; a TRIANGLES
//! primitive without COLOR_0 but with NORMAL gets `_NORMAL_GROUP` only; everything else is
//! left as it was. Topology goes into each primitive's `extras.pelt` (format in
//! [`pelt_io::topology`]). Any error fails the whole asset, so no partial output is ever
//! written. The report counts every special case per primitive and times each stage.

use std::time::Instant;

use pelt_io::edit::NewAccessor;
use pelt_io::mesh::read_primitive;
use pelt_io::picture::{self, Rgba8};
use pelt_io::topology::NORMAL_GROUP_ATTRIBUTE;
use pelt_io::triangles;
use pelt_io::{Document, IoError, PrimitiveRef};
use serde::Serialize;
use serde_json::{Map, Value, json};

use crate::comb;
use crate::options::{
    BakeOptions, CombSource, Compression, GeneratedComb, LengthTexture, Quantize, TangentGenerator,
    TopologyMode,
};
use crate::primitive::{
    BakedPrimitive, PrimitiveStats, TangentSource, TopologyStats, bake_primitive_with,
    group_primitive,
};

/// The attribute pelt writes.
pub use pelt_io::contract::COMB_ATTRIBUTE;

/// One primitive in the report.
#[derive(Debug, Clone, Serialize)]
pub struct PrimitiveReport {
    /// Mesh index.
    pub mesh: usize,
    /// Mesh name, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Primitive index.
    pub primitive: usize,
    /// `baked`, or why it was skipped.
    pub status: String,
    /// COLOR_0 storage (e.g. `VEC4 unsigned byte normalized`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub color_0: Option<String>,
    /// Counts (absent when skipped).
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub stats: Option<PrimitiveStats>,
    /// Topology counts of a primitive that got normal groups only.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub groups_only: Option<TopologyStats>,
}

/// Stage timings in milliseconds.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Timings {
    /// Decoding primitives.
    pub decode_ms: f64,
    /// Normals, tangents, comb and topology.
    pub bake_ms: f64,
    /// Of which topology: normal groups, IDs and fin edges.
    pub topology_ms: f64,
    /// Encoding the new accessors into the document.
    pub encode_ms: f64,
    /// Checking the whole document before it is written ([`pelt_io::validate`]).
    pub validate_ms: f64,
    /// Ordering, quantizing and compressing for `--compress` ([`pelt_io::pack`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compress_ms: Option<f64>,
}

/// The bake of one asset.
#[derive(Debug, Clone, Default, Serialize)]
pub struct AssetReport {
    /// Total vertices written.
    pub vertices: usize,
    /// Total triangles.
    pub triangles: usize,
    /// Primitives baked.
    pub primitives_baked: usize,
    /// Primitives without a comb that got normal groups only.
    pub primitives_grouped: usize,
    /// Per primitive.
    pub primitives: Vec<PrimitiveReport>,
    /// Accessors the bake replaced and removed (nothing else referred to them).
    pub removed_accessors: usize,
    /// BufferViews removed with them.
    pub removed_buffer_views: usize,
    /// Warnings, each naming its primitive.
    pub warnings: Vec<String>,
    /// What `--compress` did (absent for plain output).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compression: Option<pelt_io::pack::PackReport>,
    /// Stage timings.
    pub timings: Timings,
}

/// Bakes every eligible primitive of `doc` in place. A document without a single TRIANGLES
/// primitive is an error ("nothing to bake"): the output would be the input.
pub fn bake_document(doc: &mut Document, opts: &BakeOptions) -> Result<AssetReport, IoError> {
    let mut report = AssetReport::default();
    // What loading read past or repaired (an OBJ's missing materials, lossy text).
    report.warnings.append(&mut doc.warnings);
    // Texture images decoded for comb lengths, once each.
    let mut images: Vec<(usize, Rgba8)> = Vec::new();
    for r in doc.primitives() {
        let place = doc.place(r);
        let mut entry = PrimitiveReport {
            mesh: r.mesh,
            name: doc.mesh_name(r.mesh).map(str::to_owned),
            primitive: r.primitive,
            status: String::new(),
            color_0: None,
            stats: None,
            groups_only: None,
        };
        let mode = doc.mode(r)?;
        if !triangles::is_triangles(mode) {
            entry.status = format!(
                "skipped: mode {mode} ({}) draws no triangles; passed through unchanged",
                triangles::mode_name(mode)
            );
            report.warnings.push(format!("{place}: {}", entry.status));
            report.primitives.push(entry);
            continue;
        }
        let t0 = Instant::now();
        let prim = read_primitive(doc, r)?;
        report.timings.decode_ms += ms(t0);
        if prim.mesh.indices.is_empty() {
            // A strip or fan of degenerate triangles only: nothing to put fur on.
            entry.status = format!(
                "skipped: {} holds only degenerate triangles; passed through unchanged",
                triangles::mode_name(prim.mode)
            );
            report.warnings.push(format!("{place}: {}", entry.status));
            report.primitives.push(entry);
            continue;
        }
        entry.color_0 = prim.color.as_ref().map(pelt_io::mesh::Encoding::describe);
        let generate = matches!(opts.comb, CombSource::Generate(_));
        if generate && prim.mesh.colors.is_some() {
            report.warnings.push(format!(
                "{place}: COLOR_0 not read: the comb is generated (--comb generate)"
            ));
        }
        if prim.mesh.colors.is_none() && !generate {
            group_only(doc, r, &prim, opts, &mut report, &mut entry)?;
            report.primitives.push(entry);
            continue;
        }

        let t1 = Instant::now();
        let lengths = match opts.comb {
            CombSource::Generate(GeneratedComb {
                length_texture: Some(lt),
                ..
            }) => texture_lengths(doc, r, &prim.mesh, lt, &mut images, &mut report.warnings)?,
            _ => None,
        };
        let prim_opts = resolve_generator(doc, r, opts)?;
        let mut baked = bake_primitive_with(&prim.mesh, &prim_opts, lengths.as_deref());
        report.timings.bake_ms += ms(t1);

        let t2 = Instant::now();
        report.timings.topology_ms += baked.topology_ms;
        write_baked(doc, r, &prim, &mut baked, opts, &mut report.warnings)?;
        report.timings.encode_ms += ms(t2);

        report.vertices += baked.stats.vertices_out;
        report.triangles += baked.stats.triangles;
        report.primitives_baked += 1;
        report
            .warnings
            .extend(baked.warnings.iter().map(|w| format!("{place}: {w}")));
        entry.status = "baked".to_owned();
        entry.stats = Some(baked.stats);
        report.primitives.push(entry);
    }
    finish(doc, &mut report)?;
    Ok(report)
}

/// A primitive without a comb (no COLOR_0, none generated): normal groups only, written with
/// their extras, or skipped with why in `entry`'s status.
fn group_only(
    doc: &mut Document,
    r: PrimitiveRef,
    prim: &pelt_io::mesh::PrimitiveMesh,
    opts: &BakeOptions,
    report: &mut AssetReport,
    entry: &mut PrimitiveReport,
) -> Result<(), IoError> {
    let place = doc.place(r);
    let t1 = Instant::now();
    let grouped = (opts.topology_mode != TopologyMode::Off)
        .then(|| group_primitive(&prim.mesh, opts))
        .flatten();
    report.timings.bake_ms += ms(t1);
    match grouped {
        Some(g) => {
            let t2 = Instant::now();
            as_list(doc, r, prim, &mut report.warnings)?;
            if let Some((map, indices)) = &g.remap {
                doc.remap_primitive(r, map, indices, &[NORMAL_GROUP_ATTRIBUTE])?;
            }
            let a = doc.push_accessor(NewAccessor::u16(&as_scalars(&g.normal_group)));
            doc.set_attribute(r, NORMAL_GROUP_ATTRIBUTE, a)?;
            let extras = Extras {
                topology: &g.stats,
                comb: false,
                tangents: None,
                fins: None,
                indices: g.remap.as_ref().map_or(&prim.mesh.indices, |(_, i)| i),
            };
            write_extras(doc, r, extras, opts, &mut report.warnings)?;
            report.timings.encode_ms += ms(t2);
            report.timings.topology_ms += g.topology_ms;
            report.primitives_grouped += 1;
            entry.status = "normal groups only: no COLOR_0 (no comb painted)".to_owned();
            report
                .warnings
                .extend(g.warnings.iter().map(|w| format!("{place}: {w}")));
            entry.groups_only = Some(g.stats);
        }
        None if opts.topology_mode == TopologyMode::Off => {
            entry.status = "skipped: no COLOR_0 (no comb painted)".to_owned();
        }
        None => {
            entry.status = "skipped: no COLOR_0 (no comb painted) and no NORMAL (flat \
                            shaded); --comb generate grows fur on it"
                .to_owned();
        }
    }
    report.warnings.push(format!("{place}: {}", entry.status));
    Ok(())
}

/// The encode step: a baked primitive's arrays written into the document (remapped where
/// vertices were split), as new accessors for NORMAL, TANGENT, the comb and the normal
/// groups, with the extras.
fn write_baked(
    doc: &mut Document,
    r: PrimitiveRef,
    prim: &pelt_io::mesh::PrimitiveMesh,
    baked: &mut BakedPrimitive,
    opts: &BakeOptions,
    warnings: &mut Vec<String>,
) -> Result<(), IoError> {
    as_list(doc, r, prim, warnings)?;
    if let Some((map, indices)) = &baked.remap {
        let mut replaced = vec![COMB_ATTRIBUTE, NORMAL_GROUP_ATTRIBUTE];
        if baked.normals.is_some() {
            replaced.push("NORMAL");
        }
        if baked.tangents.is_some() {
            replaced.push("TANGENT");
        }
        doc.remap_primitive(r, map, indices, &replaced)?;
    }
    // The baked arrays become the new bufferViews as they are (no copy).
    if let Some(n) = baked.normals.take() {
        let a = doc.push_accessor(NewAccessor::f32_owned(n));
        doc.set_attribute(r, "NORMAL", a)?;
    }
    if let Some(t) = baked.tangents.take() {
        let a = doc.push_accessor(NewAccessor::f32_owned(t));
        doc.set_attribute(r, "TANGENT", a)?;
    }
    let comb = comb_accessor(opts, &mut baked.comb);
    let a = doc.push_accessor(comb);
    doc.set_attribute(r, COMB_ATTRIBUTE, a)?;
    if opts.topology_mode != TopologyMode::Off {
        let a = doc.push_accessor(NewAccessor::u16(&as_scalars(&baked.normal_group)));
        doc.set_attribute(r, NORMAL_GROUP_ATTRIBUTE, a)?;
        let fins = baked.fins.take();
        let extras = Extras {
            topology: &baked.stats.topology,
            comb: true,
            tangents: baked.stats.tangents,
            fins,
            indices: baked.remap.as_ref().map_or(&prim.mesh.indices, |(_, i)| i),
        };
        write_extras(doc, r, extras, opts, warnings)?;
    }
    Ok(())
}

/// The comb's accessor, as `opts` stores it: float (the baked array, taken as it is), or
/// normalized u16 or u8.
fn comb_accessor(opts: &BakeOptions, baked: &mut Vec<[f32; 4]>) -> NewAccessor {
    match comb_storage(opts) {
        Quantize::Float => NewAccessor::f32_owned(std::mem::take(baked)),
        Quantize::U16 => NewAccessor::u16_norm(
            &baked
                .iter()
                .map(|&c| comb::encode_u16(c))
                .collect::<Vec<_>>(),
        ),
        Quantize::U8 => NewAccessor::u8_norm(
            &baked
                .iter()
                .map(|&c| comb::encode_u8(c))
                .collect::<Vec<_>>(),
        ),
    }
}

/// After every primitive: "nothing to bake" when no primitive had a triangle, the check of
/// the whole document, the pruning of what the bake detached, and the timings rounded.
fn finish(doc: &mut Document, report: &mut AssetReport) -> Result<(), IoError> {
    if report
        .primitives
        .iter()
        .all(|p| p.status.starts_with("skipped: mode") || p.status.contains("only degenerate"))
    {
        let why = match report.primitives.len() {
            0 => "the file has no mesh primitives".to_owned(),
            n => format!(
                "none of its {n} primitives has a triangle (points, lines, or strips and \
                 fans of degenerate triangles only), so there is no surface to grow fur on"
            ),
        };
        return Err(doc.invalid("meshes", format!("nothing to bake: {why}")));
    }
    // No fault the bake passed through reaches the output (before pruning, so that places
    // name the input's indices: edits only append).
    let tv = Instant::now();
    // Every triangle primitive was read above (floats and indices checked there).
    report.warnings.extend(pelt_io::validate::check(doc, true)?);
    report.timings.validate_ms = ms(tv);
    let t3 = Instant::now();
    let pruned = doc.prune_detached();
    report.removed_accessors = pruned.accessors;
    report.removed_buffer_views = pruned.buffer_views;
    report.warnings.extend(pruned.kept_because);
    report.timings.encode_ms += ms(t3);
    // Sums of rounded values: round again so the report shows two decimals.
    let t = &mut report.timings;
    for v in [
        &mut t.decode_ms,
        &mut t.bake_ms,
        &mut t.topology_ms,
        &mut t.encode_ms,
    ] {
        *v = (*v * 100.0).round() / 100.0;
    }
    Ok(())
}

/// Packs a baked document for output as `opts.compress` asks (nothing for plain output):
/// the last step before writing, after fur textures and records are embedded, since the
/// compressed streams name bufferViews by index.
pub fn pack_output(
    doc: &mut Document,
    opts: &BakeOptions,
    report: &mut AssetReport,
) -> Result<(), IoError> {
    if opts.compress == Compression::Meshopt {
        let tc = Instant::now();
        report.compression = Some(doc.pack_meshopt()?);
        report.timings.compress_ms = Some(ms(tc));
    }
    Ok(())
}

/// How `_FUR_COMB` is stored: as asked, except that compressed output stores a float comb
/// as normalized u8, as precise as its 8-bit normals and tangents (the bound is stated in
/// docs/bake.md).
fn comb_storage(opts: &BakeOptions) -> Quantize {
    match (opts.compress, opts.quantize) {
        (Compression::Meshopt, Quantize::Float) => Quantize::U8,
        (_, q) => q,
    }
}

/// Writes a strip or fan primitive's triangles as a list (mode TRIANGLES), with a warning
/// that says so; a list is left as it is.
fn as_list(
    doc: &mut Document,
    r: PrimitiveRef,
    prim: &pelt_io::mesh::PrimitiveMesh,
    warnings: &mut Vec<String>,
) -> Result<(), IoError> {
    if prim.mode == triangles::TRIANGLES {
        return Ok(());
    }
    let mesh = &prim.mesh;
    doc.set_triangle_list(r, &mesh.indices, mesh.vertex_count())?;
    warnings.push(format!(
        "{}: {} written as a triangle list ({} triangles, {} degenerate dropped)",
        doc.place(r),
        triangles::mode_name(prim.mode),
        mesh.indices.len() / 3,
        prim.dropped
    ));
    Ok(())
}

/// IDs as one-component elements.
fn as_scalars(v: &[u16]) -> Vec<[u16; 1]> {
    v.iter().map(|&x| [x]).collect()
}

/// `opts` with [`TangentGenerator::Auto`] resolved for primitive `r`: MikkTSpace where its
/// material has a normal texture, the gradient frame elsewhere.
fn resolve_generator(
    doc: &Document,
    r: PrimitiveRef,
    opts: &BakeOptions,
) -> Result<BakeOptions, IoError> {
    if opts.tangent_generator != TangentGenerator::Auto {
        return Ok(*opts);
    }
    let normal_mapped = match doc.primitive_material(r)? {
        Some(m) => doc.material_has_normal_texture(m),
        None => false,
    };
    Ok(BakeOptions {
        tangent_generator: if normal_mapped {
            TangentGenerator::Mikktspace
        } else {
            TangentGenerator::Gradient
        },
        ..*opts
    })
}

/// What one primitive's `extensions.PELT_fur` records.
struct Extras<'a> {
    topology: &'a TopologyStats,
    /// Whether the primitive has a comb (`_FUR_COMB`).
    comb: bool,
    /// Where TANGENT came from (None: the primitive has no comb and kept its own).
    tangents: Option<TangentSource>,
    fins: Option<Vec<pelt_geom::fins::FinEdge>>,
    /// The index list the primitive now has (as written: `computedFrom` describes it).
    indices: &'a [u32],
}

/// Writes `extensions.PELT_fur` (attribute names, tangent source, normal groups, fins when
/// given, and the index list they were computed from).
fn write_extras(
    doc: &mut Document,
    r: PrimitiveRef,
    e: Extras,
    opts: &BakeOptions,
    warnings: &mut Vec<String>,
) -> Result<(), IoError> {
    let (t, fins) = (e.topology, e.fins);
    let mut pelt = Map::new();
    if e.comb {
        pelt.insert("combAttribute".into(), json!(COMB_ATTRIBUTE));
    }
    if let Some(source) = e.tangents {
        pelt.insert("tangents".into(), json!(tangent_label(doc, r, source)?));
    }
    let (groups, edges) = topology_fields(t, opts);
    pelt.insert("normalGroups".into(), groups);
    pelt.insert("edges".into(), edges);
    if fins.is_some() {
        let mut f = Map::new();
        f.insert("count".into(), json!(t.fin_edges));
        if t.bare_edges > 0 {
            f.insert("bareEdgesLeftOut".into(), json!(t.bare_edges));
        }
        pelt.insert("fins".into(), Value::Object(f));
    }
    // The bake's own copy, not a second read of what it just wrote (the same list).
    debug_assert_eq!(doc.corner_list(r)?, e.indices);
    if !doc.set_topology(r, pelt, fins, e.indices)? {
        warnings.push(format!(
            "{}: extensions is not a JSON object: normal-group counts and fin edges were not stored",
            doc.place(r)
        ));
    }
    Ok(())
}

/// `PELT_fur.normalGroups` and `edges` for topology `t`, without the values the
/// specification gives as defaults (the attribute `_NORMAL_GROUP`, zero counts, the default
/// normal tolerance, exact welding), as glTF leaves its own defaults out.
fn topology_fields(t: &TopologyStats, opts: &BakeOptions) -> (Value, Value) {
    let mut groups = Map::new();
    groups.insert("groups".into(), json!(t.normal_groups));
    groups.insert("idsUsed".into(), json!(t.ids_used));
    // As given in degrees: the radians they were stored as, back to degrees, to 5 decimals.
    let degrees = |x: f64| (x * 1e5).round() / 1e5;
    let tolerance = degrees(f64::from(opts.topology.normal_tolerance).to_degrees());
    let default_tolerance = degrees(f64::from(pelt_geom::topology::DEFAULT_NORMAL_TOLERANCE_DEG));
    // The shortest decimal that reads back as the f32 given (0.001, not 0.0010000000474974513).
    let weld: f64 = opts
        .topology
        .weld_epsilon
        .to_string()
        .parse()
        .unwrap_or(0.0);
    let optional = [
        (
            "splitVertices",
            json!(t.group_split_vertices),
            t.group_split_vertices == 0,
        ),
        (
            "sharedIdPairs",
            json!(t.shared_id_pairs),
            t.shared_id_pairs == 0,
        ),
        (
            "normalToleranceDeg",
            json!(tolerance),
            tolerance == default_tolerance,
        ),
        ("weldEpsilon", json!(weld), weld == 0.0),
    ];
    for (key, value, default) in optional {
        if !default {
            groups.insert(key.into(), value);
        }
    }
    let mut edges = Map::new();
    edges.insert("unique".into(), json!(t.edges));
    for (key, n) in [
        ("boundary", t.boundary_edges),
        ("nonmanifold", t.nonmanifold_edges),
    ] {
        if n > 0 {
            edges.insert(key.into(), json!(n));
        }
    }
    (Value::Object(groups), Value::Object(edges))
}

/// The tangents' label in `extras.pelt`: where a re-bake keeps tangents an earlier bake
/// generated, the generator that made them (so baking a pelt output again writes the same file).
fn tangent_label(
    doc: &Document,
    r: PrimitiveRef,
    source: TangentSource,
) -> Result<&'static str, IoError> {
    if source != TangentSource::Kept {
        return Ok(source.name());
    }
    let before = doc
        .fur_primitive(r)?
        .and_then(|(f, _)| f.get("tangents")?.as_str());
    Ok(
        match [TangentSource::Mikktspace, TangentSource::Gradient]
            .into_iter()
            .find(|g| Some(g.name()) == before)
        {
            Some(g) => g.name(),
            None => source.name(),
        },
    )
}

fn ms(t: Instant) -> f64 {
    (t.elapsed().as_secs_f64() * 1e5).round() / 100.0
}

/// A generated comb's length factor per vertex: channel `lt.channel` of the primitive's
/// material texture `lt.slot`, sampled at each vertex's TEXCOORD. None (with a warning) when
/// the primitive has no such texture.
fn texture_lengths(
    doc: &Document,
    r: PrimitiveRef,
    mesh: &pelt_geom::Mesh,
    lt: LengthTexture,
    images: &mut Vec<(usize, Rgba8)>,
    warnings: &mut Vec<String>,
) -> Result<Option<Vec<f32>>, IoError> {
    let place = doc.place(r);
    let found = match doc.primitive_material(r)? {
        Some(m) => picture::material_texture(doc, m, lt.slot)?,
        None => None,
    };
    let Some(tex) = found else {
        warnings.push(format!(
            "{place}: comb.lengthTexture: no {:?} texture on this primitive's material; the \
             constant length is used",
            lt.slot
        ));
        return Ok(None);
    };
    let uvs: Vec<glam::Vec2> = if tex.tex_coord == 0 {
        mesh.uvs.clone().unwrap_or_default()
    } else {
        let name = format!("TEXCOORD_{}", tex.tex_coord);
        match doc.attribute(r, &name)? {
            Some(a) => {
                pelt_io::accessor::read_vec::<2>(doc, a, &format!("{place} attribute {name}"))?
                    .iter()
                    .map(|&[u, v]| glam::Vec2::new(u, v))
                    .collect()
            }
            None => Vec::new(),
        }
    };
    if uvs.len() != mesh.vertex_count() {
        return Err(doc.invalid(
            &place,
            format!(
                "comb.lengthTexture reads TEXCOORD_{}, which this primitive lacks",
                tex.tex_coord
            ),
        ));
    }
    if !images.iter().any(|(i, _)| *i == tex.image) {
        images.push((tex.image, picture::decode(doc, tex.image)?));
    }
    let img = images
        .iter()
        .find(|(i, _)| *i == tex.image)
        .map(|(_, img)| img)
        .ok_or_else(|| doc.invalid(&place, "texture image missing"))?;
    Ok(Some(
        uvs.iter()
            .map(|uv| img.sample(uv.x, uv.y, usize::from(lt.channel), tex.wrap))
            .collect(),
    ))
}
