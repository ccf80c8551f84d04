//! The shared fur functions evaluated by pelt and by the three.js runtime on the same inputs:
//! the WGSL of `shaders/` as pelt's GPU runs it (a compute pass on wgpu) and the generated GLSL
//! library of `integrations/three` as a browser runs it (WebGL2 in headless Chromium,
//! `test/pages/eval.html`): the shell offset (Listing 2.1), the strand tangent, the layer
//! opacity of the strand model as a medium, the comb decoded from tangent space, the wind,
//! the fins' visibility, the lights' reach with Kajiya-Kay and Blinn-Phong terms, and the
//! procedural sky. A library with one constant changed (the negative control) must fail the
//! same tolerance. Skipped where Chromium or the package's `npm ci` is missing, unless
//! PELT_REQUIRE_BROWSER is set (CI sets it).

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::preview;

/// Each expression, valid WGSL and GLSL alike, of the record's four vectors a, b, c, d.
const EXPRS: [&str; 9] = [
    "vec4(shell_offset(a.xyz, b.xyz, c.x, c.y, c.z), 0.0)",
    "vec4(strand_tangent(a.xyz, b.xyz, c.w), 0.0)",
    "vec4(layer_opacity(abs(d), abs(b), abs(c.x) * 0.5, abs(c.x) * 0.5 + abs(c.y) * 0.5, abs(a.w) * 10.0, abs(c.z), abs(c.w), max(abs(a.x), 0.1)), 0.0, 0.0, 0.0)",
    "vec4(comb_object(a.xyz, b, c.xyz), 0.0)",
    "vec4(fin_visibility(a.x, b.x, abs(c.x), c.w > 0.0), 0.0, 0.0, 0.0)",
    "strand_light(c.xyz * 3.0, normalize(d.xyz), light_reach(c.xyz * 3.0, mk_light(a, b), true), mk_light(a, b), 32.0)",
    "one_light(c.xyz * 3.0, normalize(d.xyz), light_reach(c.xyz * 3.0, mk_light(a, b), true), mk_light(a, b), 32.0)",
    "vec4(procedural(normalize(a.xyz)), 0.0)",
    "vec4(wind_case(a, b, c, d), 0.0)",
];

/// The helpers the expressions call, in each language: a light from two vectors (a point
/// light of radius 2 to 6 at a·4, or a directional one toward a where b.w < −0.5), and the
/// wind at a strand (comb b, normal a, root c·3; wind d·2 at time d.w·5, gusting at 0.8 Hz
/// with turbulence 0.5; the object rotated and scaled).
const WGSL_HELPERS: &str = r#"
fn mk_light(a: vec4<f32>, b: vec4<f32>) -> Light {
    var l: Light;
    l.position_radius = select(vec4<f32>(a.xyz * 4.0, 4.0 + 2.0 * b.w), vec4<f32>(normalize(a.xyz), 0.0), b.w < -0.5);
    l.color = vec4<f32>(abs(b.xyz) * 3.0, dot(abs(b.xyz) * 3.0, vec3<f32>(0.2126, 0.7152, 0.0722)));
    l.cone = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    return l;
}
fn wind_case(a: vec4<f32>, b: vec4<f32>, c: vec4<f32>, d: vec4<f32>) -> vec3<f32> {
    var frame: Frame;
    frame.wind = vec4<f32>(d.xyz * 2.0, d.w * 5.0);
    frame.gust = vec4<f32>(0.8, 0.5, 0.0, 0.0);
    var object: Object;
    object.normal_model = mat4x4<f32>(vec4<f32>(0.0, 0.5, 0.0, 0.0), vec4<f32>(-0.5, 0.0, 0.0, 0.0), vec4<f32>(0.0, 0.0, 0.5, 0.0), vec4<f32>(0.0, 0.0, 0.0, 1.0));
    object.fur_base = vec4<f32>(0.0, 0.0, 0.0, 0.05);
    return wind_comb(b.xyz, a.xyz, c.xyz * 3.0, frame, object);
}
"#;

const GLSL_HELPERS: &str = r#"
Light mk_light(vec4 a, vec4 b) {
    Light l;
    l.position_radius = b.w < -0.5 ? vec4(normalize(a.xyz), 0.0) : vec4(a.xyz * 4.0, 4.0 + 2.0 * b.w);
    l.color = vec4(abs(b.xyz) * 3.0, dot(abs(b.xyz) * 3.0, vec3(0.2126, 0.7152, 0.0722)));
    l.cone = vec4(0.0, 0.0, 0.0, 1.0);
    return l;
}
vec3 wind_case(vec4 a, vec4 b, vec4 c, vec4 d) {
    Frame frame;
    frame.wind = vec4(d.xyz * 2.0, d.w * 5.0);
    frame.gust = vec4(0.8, 0.5, 0.0, 0.0);
    Object object;
    object.normal_model = mat4(vec4(0.0, 0.5, 0.0, 0.0), vec4(-0.5, 0.0, 0.0, 0.0), vec4(0.0, 0.0, 0.5, 0.0), vec4(0.0, 0.0, 0.0, 1.0));
    object.fur_base = vec4(0.0, 0.0, 0.0, 0.05);
    return wind_comb(b.xyz, a.xyz, c.xyz * 3.0, frame, object);
}
"#;

fn package() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../integrations/three")
}

fn browser_ready() -> bool {
    let found = package().join("node_modules/puppeteer-core").exists()
        && Path::new(&std::env::var("CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into()))
            .exists();
    if !found {
        assert!(
            std::env::var_os("PELT_REQUIRE_BROWSER").is_none(),
            "PELT_REQUIRE_BROWSER is set but chromium or integrations/three's packages are \
             missing (apt-get install chromium; npm ci --prefix integrations/three)"
        );
        eprintln!("skipped: chromium or integrations/three's packages not found");
    }
    found
}

/// Records of four vectors: a deterministic spread in −1..1 (the evaluations are smooth
/// there), with the normal kept away from zero.
fn records() -> Vec<[[f32; 4]; 4]> {
    let mut x = 0x9e37_79b9_u32;
    let mut rnd = || {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        x as f32 / u32::MAX as f32 * 2.0 - 1.0
    };
    let mut out = Vec::new();
    while out.len() < 512 {
        let r = [(); 4].map(|_| [rnd(), rnd(), rnd(), rnd()]);
        let n = r[0][0].hypot(r[0][1]).hypot(r[0][2]);
        if n > 0.2 {
            out.push(r);
        }
    }
    out
}

/// The expressions over `records` on pelt's GPU: one compute invocation per record.
fn wgsl(records: &[[[f32; 4]; 4]]) -> Vec<Vec<f32>> {
    let p = preview();
    let r = &p.renderer;
    let mut src = String::from(
        "#import pelt::common::{Frame, Light, Object, light_reach, one_light, procedural, strand_light}\n\
         #import pelt::fur_common::{comb_object, fin_visibility, layer_opacity, shell_offset, strand_tangent, wind_comb}\n\
         @group(0) @binding(0) var<storage, read> inputs: array<vec4<f32>>;\n\
         @group(0) @binding(1) var<storage, read_write> outputs: array<vec4<f32>>;\n",
    );
    src += WGSL_HELPERS;
    src += "@compute @workgroup_size(64)\nfn main(@builtin(global_invocation_id) id: vec3<u32>) {\n\
            let i = id.x;\n    if i >= arrayLength(&inputs) / 4u { return; }\n\
            let a = inputs[4u * i];\n    let b = inputs[4u * i + 1u];\n\
            let c = inputs[4u * i + 2u];\n    let d = inputs[4u * i + 3u];\n";
    let n = records.len();
    for (k, e) in EXPRS.iter().enumerate() {
        src += &format!("    outputs[{k}u * {n}u + i] = {e};\n");
    }
    src += "}\n";
    let module =
        pelt_preview::shaders::compose_str("glsl_cross", &src).expect("the harness composes");
    let device = &r.gpu.device;
    let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("glsl_cross"),
        source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("glsl_cross"),
        layout: None,
        module: &shader,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let flat: Vec<[f32; 4]> = records.iter().flatten().copied().collect();
    let input = r.gpu.buffer_init(
        "records",
        bytemuck::cast_slice(&flat),
        wgpu::BufferUsages::STORAGE,
    );
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("values"),
        size: (EXPRS.len() * n * 16) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((n as u32).div_ceil(64), 1, 1);
    }
    r.gpu.queue.submit([enc.finish()]);
    let bytes = pelt_preview::frame::read_buffer(r, &output).expect("read back");
    let all: Vec<f32> = bytemuck::cast_slice(&bytes).to_vec();
    all.chunks_exact(n * 4).map(<[f32]>::to_vec).collect()
}

/// The expressions over `records` in the browser, with the library mutated or not.
fn glsl(records: &[[[f32; 4]; 4]], mutate: bool) -> Vec<Vec<f32>> {
    let dir = std::env::temp_dir().join(format!("pelt-glsl-cross-{}-{mutate}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch");
    let cases = dir.join("cases.json");
    let inputs: Vec<Vec<f32>> = records.iter().map(|r| r.concat()).collect();
    let json = serde_json::json!({ "inputs": inputs, "exprs": EXPRS, "helpers": GLSL_HELPERS });
    std::fs::write(&cases, serde_json::to_vec(&json).expect("JSON")).expect("write cases");
    let o = Command::new("node")
        .arg(package().join("test/page.mjs"))
        .arg("eval")
        .arg(&cases)
        .arg(format!("mutate={}", u8::from(mutate)))
        .output()
        .expect("run node");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON result");
    assert!(v.get("error").is_none(), "the page failed: {}", v["error"]);
    assert_eq!(v["consoleErrors"], serde_json::json!([]), "console errors");
    eprintln!("browser: {}", v["renderer"]);
    v["values"]
        .as_array()
        .expect("values")
        .iter()
        .map(|e| {
            e.as_array()
                .expect("floats")
                .iter()
                .map(|x| x.as_f64().unwrap_or(f64::NAN) as f32)
                .collect()
        })
        .collect()
}

/// Per expression, the largest difference over every record and component, relative to
/// max(1, |pelt's value|).
fn worst(pelt: &[Vec<f32>], web: &[Vec<f32>]) -> Vec<f32> {
    pelt.iter()
        .zip(web)
        .map(|(p, w)| {
            p.iter()
                .zip(w)
                .map(|(x, y)| {
                    if x.is_finite() && y.is_finite() {
                        (x - y).abs() / x.abs().max(1.0)
                    } else {
                        f32::INFINITY
                    }
                })
                .fold(0.0f32, f32::max)
        })
        .collect()
}

/// The most either GPU's single-precision arithmetic (and its exp, pow, sin) may differ.
const TOLERANCE: f32 = 5e-4;

#[test]
fn the_generated_glsl_evaluates_as_pelts_wgsl_on_the_same_inputs() {
    if !browser_ready() {
        return;
    }
    let recs = records();
    let pelt = wgsl(&recs);
    let web = glsl(&recs, false);
    let w = worst(&pelt, &web);
    for (e, d) in EXPRS.iter().zip(&w) {
        eprintln!("{d:.2e}  {e}");
    }
    for (e, d) in EXPRS.iter().zip(&w) {
        assert!(
            *d <= TOLERANCE,
            "{e}: WGSL and GLSL differ by {d} (relative)"
        );
    }
    // Negative control: the layer opacity's mid-height and the lights' falloff changed by
    // 10 % and 1 % in the GLSL fail the same tolerance.
    let mutated = worst(&pelt, &glsl(&recs, true));
    assert!(
        mutated[2] > TOLERANCE,
        "a changed layer_opacity passed ({})",
        mutated[2]
    );
    assert!(
        mutated[5] > TOLERANCE,
        "a changed point falloff passed ({})",
        mutated[5]
    );
}

/// The runtime's strand model as a medium (`src/density.js`, computed at load from the
/// manifest's `strands`) against `pelt_fur::density` on the same parameters: every bin of
/// every level, κ and the mean diameter. Needs only Node.js.
#[test]
fn the_runtime_density_is_pelts() {
    let node = Command::new("node").arg("--version").output().is_ok();
    if !node {
        assert!(
            std::env::var_os("PELT_REQUIRE_BROWSER").is_none(),
            "PELT_REQUIRE_BROWSER is set but node is missing"
        );
        eprintln!("skipped: node not found");
        return;
    }
    for p in [
        pelt_fur::StrandParams {
            strands: 3000,
            tilt: 1.0,
            ..pelt_fur::StrandParams::default()
        },
        pelt_fur::StrandParams {
            strands: 2000,
            seed: 11,
            clumps: 7,
            clumping: 0.6,
            clump_radius: 0.03,
            height_bias: 2.0,
            ..pelt_fur::StrandParams::default()
        },
    ] {
        let side = pelt_fur::density::side_for(p.strands, 1024);
        let want = pelt_fur::density::density(&p, side);
        let script = format!(
            "import {{ density, strandParams }} from {:?};\n\
             const d = density(strandParams({}), {side});\n\
             console.log(JSON.stringify({{ kappa: d.kappa, diameter: d.diameter, levels: d.levels.map((l) => Array.from(l)) }}));",
            package().join("src/density.js").to_str().expect("UTF-8"),
            serde_json::to_string(&p).expect("params JSON"),
        );
        let o = Command::new("node")
            .args(["--input-type=module", "-e", &script])
            .output()
            .expect("run node");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let got: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-5 * a.abs().max(b.abs()).max(1e-3);
        assert!(
            close(got["kappa"].as_f64().expect("kappa"), want.kappa),
            "κ {} vs {}",
            got["kappa"],
            want.kappa
        );
        assert!(
            close(got["diameter"].as_f64().expect("d"), want.diameter),
            "diameter"
        );
        let levels = got["levels"].as_array().expect("levels");
        assert_eq!(levels.len(), want.levels.len(), "level count");
        for (l, (g, w)) in levels.iter().zip(&want.levels).enumerate() {
            let g = g.as_array().expect("level");
            assert_eq!(g.len(), w.len() * 8, "level {l} size");
            for (k, (x, y)) in g.iter().zip(w.iter().flatten()).enumerate() {
                let x = x.as_f64().expect("float");
                assert!(close(x, f64::from(*y)), "level {l} value {k}: {x} vs {y}");
            }
        }
        // Negative control: another seed's density differs.
        let other = pelt_fur::density::density(
            &pelt_fur::StrandParams {
                seed: p.seed + 1,
                ..p.clone()
            },
            side,
        );
        assert!(
            other.levels[0]
                .iter()
                .flatten()
                .zip(levels[0].as_array().expect("level"))
                .any(|(a, b)| !close(f64::from(*a), b.as_f64().unwrap_or(0.0)))
        );
    }
}
