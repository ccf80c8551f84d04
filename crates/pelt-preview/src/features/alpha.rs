//! Stippled alpha (Kircher & Lawrance §4): each alpha object writes only its stipple pattern's
//! pixel of every 2×2 cell of the G-buffer (patterns assigned in the plan so overlapping
//! objects differ), and is drawn blended back to front at output resolution, lit from its own
//! stipple samples by the DSF filter.

use crate::features::registry::Feature;
use crate::features::{Frame, MissingInput, material, slot};
use crate::frame_data::Res;
use crate::recipe::Recipe;
use crate::renderer::Blend;
use crate::shaders::Lighting;

/// Stippled alpha's feature (its pipelines are the geometry and material passes').
pub const FEATURE: Feature = Feature {
    name: "alpha",
    explain: "stippled alpha objects, lit from their own stipple samples",
    pipelines: Vec::new,
    compute: &[],
    passes: &[],
};

/// The alpha objects' stippled G-buffer draws (after opaque and fur).
pub fn gbuffer<'a>(f: &Frame<'a>, r: &mut Recipe<'a>) -> Result<(), MissingInput> {
    if f.plan.alpha.is_empty() {
        return Ok(());
    }
    r.pipeline(super::geometry::pipeline());
    f.draw_objects(r, "geometry", Some(slot::GBUFFER_MATERIAL), &f.plan.alpha)
}

/// The alpha objects back to front, blended over, lit by `lit` (material or forward).
pub fn draw<'a>(
    f: &Frame<'a>,
    r: &mut Recipe<'a>,
    pass: &'static str,
    lit: Lighting,
) -> Result<(), MissingInput> {
    if f.plan.alpha.is_empty() {
        return Ok(());
    }
    f.bind_frame(r, Res::Output);
    let (group, offset) = material::lighting(f, lit).0;
    r.bind(slot::LIGHTING, group, offset);
    r.pipeline(material::object_pipeline(lit, Blend::Over));
    f.draw_objects(r, pass, Some(slot::MATERIAL), &f.plan.alpha)
}
