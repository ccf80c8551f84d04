//! Stippled alpha (Kircher & Lawrance §4): each alpha object writes only its stipple pattern's
//! pixel of every 2×2 cell of the G-buffer (patterns assigned in the plan so overlapping
//! objects differ), and is drawn blended back to front at output resolution, lit from its own
//! stipple samples by the DSF filter. Both are draws in the transparent phase of the passes
//! features share; with the fur composited by OIT, the composite draws them instead.

use crate::draw::{MissingInput, slot};
use crate::feature::{DrawDesc, Feature, Frame, Phase, Shade, Shared, Sides};
use crate::frame_data::Res;
use crate::recipe::Recipe;
use crate::renderer::Blend;
use crate::scene::FurBlend;
use crate::shading;

/// Stippled alpha's feature (its pipelines are the geometry and material passes').
pub const FEATURE: Feature = Feature {
    draws: &[
        DrawDesc {
            into: Shared::Geometry,
            phase: Phase::Transparent,
            draw: gbuffer,
        },
        DrawDesc {
            into: Shared::Shading,
            phase: Phase::Transparent,
            draw: transparent,
        },
    ],
    ..Feature::named("alpha")
};

/// The alpha objects' stippled G-buffer draws (after opaque and fur).
pub fn gbuffer<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, s: &Shade) -> Result<(), MissingInput> {
    if f.plan.alpha.is_empty() {
        return Ok(());
    }
    r.pipeline(super::geometry::pipeline());
    f.draw_objects(
        r,
        s.pass.name(),
        Some(slot::GBUFFER_MATERIAL),
        Sides::Both,
        &f.plan.alpha,
    )
}

/// The alpha objects in the shading pass, unless the OIT composite draws them.
fn transparent<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, s: &Shade) -> Result<(), MissingInput> {
    if !f.plan.fur.is_empty() && f.plan.fur_blend == FurBlend::Wboit {
        return Ok(());
    }
    draw(f, r, s)
}

/// The alpha objects back to front, blended over, with `s`'s object shader and lighting.
pub fn draw<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, s: &Shade) -> Result<(), MissingInput> {
    if f.plan.alpha.is_empty() {
        return Ok(());
    }
    f.bind_frame(r, Res::Output);
    let (group, offset) = shading::lighting(f, s.lit).0;
    r.bind(slot::LIGHTING, group, offset);
    r.pipeline((s.object)(Blend::Over));
    f.draw_objects(
        r,
        s.pass.name(),
        Some(slot::MATERIAL),
        Sides::Both,
        &f.plan.alpha,
    )
}
