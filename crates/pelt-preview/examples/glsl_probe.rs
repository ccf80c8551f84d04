//! Probe (issue 59 design): can naga's GLSL ES 3.00 back end carry fur_common.wgsl's shared
//! functions to WebGL2? Composes a harness fragment entry that calls them and prints the GLSL.
use pelt_preview::shaders::compose_str;

const HARNESS: &str = r#"
#import pelt::fur_common::{shell_offset, strand_tangent, comb_object}

@fragment
fn probe(@location(0) n: vec3<f32>, @location(1) c: vec3<f32>, @location(2) t: vec4<f32>, @location(3) z: f32) -> @location(0) vec4<f32> {
    let o = shell_offset(n, c, z, 0.1, 1.0);
    let s = strand_tangent(n, c, z);
    let d = comb_object(n, t, c);
    return vec4<f32>(o + s + d, 1.0);
}
"#;

fn main() {
    let module = compose_str("probe", HARNESS).expect("compose");
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .expect("valid");
    let mut out = String::new();
    let options = naga::back::glsl::Options {
        version: naga::back::glsl::Version::Embedded { version: 300, is_webgl: true },
        ..Default::default()
    };
    let pipeline = naga::back::glsl::PipelineOptions {
        shader_stage: naga::ShaderStage::Fragment,
        entry_point: "probe".into(),
        multiview: None,
    };
    let mut w = naga::back::glsl::Writer::new(
        &mut out,
        &module,
        &info,
        &options,
        &pipeline,
        naga::proc::BoundsCheckPolicies::default(),
    )
    .expect("writer");
    w.write().expect("write");
    println!("{out}");
}
