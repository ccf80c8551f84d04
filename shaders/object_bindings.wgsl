// object_bindings.wgsl: the two bind groups every pass that draws objects shares (the
// G-buffer, material, forward, shells, fins, strands, mirrors, debug views, and the fur's
// lighting chunks): the view's frame constants at @group(0) and the object's constants at
// @group(1). Keep the groups in sync with `slot::FRAME` and `slot::OBJECT` in
// crates/pelt-preview/src/draw.rs (checked by the shader-validation test).

#define_import_path pelt::object_bindings

#import pelt::common::{Frame, Object}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(0) var<uniform> object: Object;
