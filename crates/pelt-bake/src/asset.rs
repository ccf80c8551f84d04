//! Baking a whole asset: every TRIANGLES primitive with COLOR_0 gets `_FUR_COMB` (and TANGENT,
//! NORMAL or a vertex split where needed); everything else is left as it was. Any error fails
//! the whole asset, so no partial output is ever written. The report counts every special case
//! per primitive and times each stage.

use std::time::Instant;

use pelt_io::edit::NewAccessor;
use pelt_io::mesh::read_primitive;
use pelt_io::{Document, IoError};
use serde::Serialize;

use crate::comb;
use crate::options::{BakeOptions, Quantize};
use crate::primitive::{PrimitiveStats, bake_primitive};

/// The attribute pelt writes.
pub const COMB_ATTRIBUTE: &str = "_FUR_COMB";

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
}

/// Stage timings in milliseconds.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Timings {
    /// Decoding primitives.
    pub decode_ms: f64,
    /// Normals, tangents and comb.
    pub bake_ms: f64,
    /// Encoding the new accessors into the document.
    pub encode_ms: f64,
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
    /// Per primitive.
    pub primitives: Vec<PrimitiveReport>,
    /// Accessors the bake replaced and removed (nothing else referred to them).
    pub removed_accessors: usize,
    /// BufferViews removed with them.
    pub removed_buffer_views: usize,
    /// Warnings, each naming its primitive.
    pub warnings: Vec<String>,
    /// Stage timings.
    pub timings: Timings,
}

/// Bakes every eligible primitive of `doc` in place.
pub fn bake_document(doc: &mut Document, opts: &BakeOptions) -> Result<AssetReport, IoError> {
    let mut report = AssetReport::default();
    for r in doc.primitives() {
        let place = doc.place(r);
        let mut entry = PrimitiveReport {
            mesh: r.mesh,
            name: doc.mesh_name(r.mesh).map(str::to_owned),
            primitive: r.primitive,
            status: String::new(),
            color_0: None,
            stats: None,
        };
        let mode = doc.mode(r)?;
        if mode != 4 {
            entry.status = format!("skipped: mode {mode} is not TRIANGLES");
            report.warnings.push(format!("{place}: {}", entry.status));
            report.primitives.push(entry);
            continue;
        }
        let t0 = Instant::now();
        let prim = read_primitive(doc, r)?;
        report.timings.decode_ms += ms(t0);
        entry.color_0 = prim.color.as_ref().map(pelt_io::mesh::Encoding::describe);
        if prim.mesh.colors.is_none() {
            entry.status = "skipped: no COLOR_0 (no comb painted)".to_owned();
            report.warnings.push(format!("{place}: {}", entry.status));
            report.primitives.push(entry);
            continue;
        }

        let t1 = Instant::now();
        let baked = bake_primitive(&prim.mesh, opts);
        report.timings.bake_ms += ms(t1);

        let t2 = Instant::now();
        if let Some((map, indices)) = &baked.remap {
            let mut replaced = vec![COMB_ATTRIBUTE];
            if baked.normals.is_some() {
                replaced.push("NORMAL");
            }
            if baked.tangents.is_some() {
                replaced.push("TANGENT");
            }
            doc.remap_primitive(r, map, indices, &replaced)?;
        }
        if let Some(n) = &baked.normals {
            let a = doc.push_accessor(NewAccessor::f32(n));
            doc.set_attribute(r, "NORMAL", a)?;
        }
        if let Some(t) = &baked.tangents {
            let a = doc.push_accessor(NewAccessor::f32(t));
            doc.set_attribute(r, "TANGENT", a)?;
        }
        let comb = match opts.quantize {
            Quantize::Float => NewAccessor::f32(&baked.comb),
            Quantize::U16 => NewAccessor::u16_norm(
                &baked
                    .comb
                    .iter()
                    .map(|&c| comb::encode_u16(c))
                    .collect::<Vec<_>>(),
            ),
            Quantize::U8 => NewAccessor::u8_norm(
                &baked
                    .comb
                    .iter()
                    .map(|&c| comb::encode_u8(c))
                    .collect::<Vec<_>>(),
            ),
        };
        let a = doc.push_accessor(comb);
        doc.set_attribute(r, COMB_ATTRIBUTE, a)?;
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
    let t3 = Instant::now();
    let pruned = doc.prune_detached();
    report.removed_accessors = pruned.accessors;
    report.removed_buffer_views = pruned.buffer_views;
    report.warnings.extend(pruned.kept_because);
    report.timings.encode_ms += ms(t3);
    // Sums of rounded values: round again so the report shows two decimals.
    let t = &mut report.timings;
    for v in [&mut t.decode_ms, &mut t.bake_ms, &mut t.encode_ms] {
        *v = (*v * 100.0).round() / 100.0;
    }
    Ok(report)
}

fn ms(t: Instant) -> f64 {
    (t.elapsed().as_secs_f64() * 1e5).round() / 100.0
}
