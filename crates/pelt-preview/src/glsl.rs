//! The shared fur functions of `shaders/` (fur_common.wgsl and its neighbours) as GLSL ES 3.00
//! for runtimes that draw with WebGL2 (integrations/three): a WGSL harness whose entry point
//! calls the functions a runtime needs is composed from its imports (naga_oil), validated and
//! written by naga's GLSL back end; the functions it reaches are kept, with naga_oil's name
//! decoration removed, and the entry point and its inputs and outputs dropped. Generated, not
//! ported, so the WebGL formulas cannot drift from the WGSL ones.

use crate::shaders::{ShaderError, compose_str};

/// GLSL ES 3.00 definitions of every struct and function that the fragment entry point
/// `entry` of `harness` (WGSL with `#import`s) reaches, in dependency order, without the entry
/// point itself.
pub fn functions(name: &str, harness: &str, entry: &str) -> Result<String, ShaderError> {
    let invalid = |message: String| ShaderError::Invalid {
        module: name.to_owned(),
        message,
    };
    let module = compose_str(name, harness)?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .map_err(|e| invalid(format!("{e:?}")))?;
    let options = naga::back::glsl::Options {
        version: naga::back::glsl::Version::Embedded {
            version: 300,
            is_webgl: true,
        },
        ..naga::back::glsl::Options::default()
    };
    let pipeline = naga::back::glsl::PipelineOptions {
        shader_stage: naga::ShaderStage::Fragment,
        entry_point: entry.to_owned(),
        multiview: None,
    };
    let mut out = String::new();
    naga::back::glsl::Writer::new(
        &mut out,
        &module,
        &info,
        &options,
        &pipeline,
        naga::proc::BoundsCheckPolicies::default(),
    )
    .and_then(|mut w| w.write().map(|_| ()))
    .map_err(|e| invalid(e.to_string()))?;
    Ok(library_part(&undecorate(&out)))
}

/// `text` without naga_oil's module decoration: `nameX_naga_oil_mod_X<base32>X` becomes `name`.
pub fn undecorate(text: &str) -> String {
    const MARK: &str = "X_naga_oil_mod_X";
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find(MARK) {
        out.push_str(&rest[..at]);
        let tail = &rest[at + MARK.len()..];
        // The base32 module path (upper-case letters and digits 2-7), then a closing `X`.
        let len = tail
            .find(|c: char| !(c.is_ascii_uppercase() || ('2'..='7').contains(&c)))
            .unwrap_or(tail.len());
        rest = &tail[len..];
    }
    out.push_str(rest);
    out
}

/// The struct and function definitions of a GLSL translation unit: everything after the
/// `#version`, precision and in/out declarations, up to the entry point `void main()`.
fn library_part(glsl: &str) -> String {
    let body = glsl.split("\nvoid main()").next().unwrap_or(glsl);
    body.lines()
        .filter(|l| {
            let t = l.trim_start();
            !(t.starts_with("#version")
                || t.starts_with("precision ")
                || t.starts_with("smooth in ")
                || t.starts_with("flat in ")
                || t.starts_with("layout(location"))
        })
        .collect::<Vec<_>>()
        .join("\n")
        .trim()
        .to_owned()
        + "\n"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decoration_is_removed_and_only_the_library_is_kept() {
        assert_eq!(
            undecorate("vec3 _e = shell_offsetX_naga_oil_mod_XOBSWY5B2HJTHK4S7MNXW23LPNYX(n);"),
            "vec3 _e = shell_offset(n);"
        );
        let harness = r#"
#import pelt::fur_common::{shell_offset, strand_tangent}
@fragment
fn probe(@location(0) n: vec3<f32>, @location(1) c: vec3<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(shell_offset(n, c, 0.5, 0.1, 1.0) + strand_tangent(n, c, 0.5), 1.0);
}
"#;
        let glsl = functions("probe", harness, "probe").expect("generated");
        for want in [
            "vec3 shell_offset(vec3 ",
            "vec3 strand_tangent(vec3 ",
            "vec3 strand_velocity(vec3 ",
        ] {
            assert!(glsl.contains(want), "{want} missing:\n{glsl}");
        }
        for gone in ["naga_oil", "void main()", "#version", "_fs2p_location0"] {
            assert!(!glsl.contains(gone), "{gone} left:\n{glsl}");
        }
    }
}
