//! Stippled alpha (Kircher & Lawrance §4): each alpha object writes only its stipple pattern's
//! pixel of every 2×2 cell of the G-buffer (patterns assigned in the plan so overlapping
//! objects differ), and is drawn blended back to front at output resolution, lit from its own
//! stipple samples by the DSF filter.

use crate::features::{Frame, MissingInput, material, slot};
use crate::frame_data::Res;
use crate::recipe::Recipe;
use crate::renderer::Blend;
use crate::shaders::Shader;

/// The alpha objects' stippled G-buffer draws (after opaque and fur).
pub fn gbuffer<'a>(f: &Frame<'a>, r: &mut Recipe<'a>) -> Result<(), MissingInput> {
    if f.plan.alpha.is_empty() {
        return Ok(());
    }
    r.pipeline(Shader::GBuffer, Blend::None);
    f.draw_objects(r, "geometry", Shader::GBuffer, &f.plan.alpha)
}

/// The alpha objects back to front, blended over with `shader` (material or forward).
pub fn draw<'a>(
    f: &Frame<'a>,
    r: &mut Recipe<'a>,
    pass: &'static str,
    shader: Shader,
) -> Result<(), MissingInput> {
    if f.plan.alpha.is_empty() {
        return Ok(());
    }
    f.bind_frame(r, Res::Output);
    let (group, offset) = material::lighting(f, shader).0;
    r.bind(slot::LIGHTING, group, offset);
    r.pipeline(shader, Blend::Over);
    f.draw_objects(r, pass, shader, &f.plan.alpha)
}
