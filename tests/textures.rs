//! Fur textures end to end: `pelt textures` writes the set and its manifest, deterministically,
//! and refuses bad parameters; `pelt bake --config` embeds the textures and the manifest in the
//! `.glb`, validator-clean, and refuses bad configs without writing anything.

mod common;

use std::path::Path;

use common::*;
use serde_json::Value;

fn png_info(bytes: &[u8]) -> (u32, u32, png::ColorType, png::BitDepth) {
    let d = png::Decoder::new(std::io::Cursor::new(bytes));
    let r = d.read_info().expect("valid PNG");
    let i = r.info();
    (i.width, i.height, i.color_type, i.bit_depth)
}

/// Loads a baked file; returns it and the material of its first primitive.
fn load_with_material(glb: &Path) -> (pelt_io::Document, usize) {
    let doc = pelt_io::Document::load(glb).expect("load");
    let prim = doc
        .primitive(pelt_io::PrimitiveRef {
            mesh: 0,
            primitive: 0,
        })
        .expect("prim");
    let m = prim["material"].as_u64().expect("material assigned") as usize;
    (doc, m)
}

/// The documented file name of level `l` (spelled out here, not taken from pelt-fur).
fn file_name(stem: &str, l: usize) -> String {
    if l == 0 {
        format!("{stem}.png")
    } else {
        format!("{stem}.mip{l}.png")
    }
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn textures_writes_every_level_and_a_manifest() {
    let dir = scratch("textures");
    let out = dir.join("fur");
    pelt_ok(&[
        "textures",
        "-q",
        "--seed",
        "3",
        "--size",
        "64",
        "--strands",
        "800",
        "-o",
        out.to_str().unwrap_or_default(),
    ]);
    // 64² mips down to 1²: 7 levels; fin 64 × 16: 7 levels.
    for stem in ["heightfield", "dots", "fin"] {
        for l in 0..7 {
            let name = file_name(stem, l);
            assert!(out.join(&name).exists(), "{name}");
        }
        assert!(!out.join(format!("{stem}.mip7.png")).exists());
    }
    assert_eq!(
        png_info(&read(&out.join("heightfield.png"))),
        (64, 64, png::ColorType::Grayscale, png::BitDepth::Sixteen)
    );
    assert_eq!(
        png_info(&read(&out.join("dots.png"))),
        (64, 64, png::ColorType::Grayscale, png::BitDepth::Eight)
    );
    assert_eq!(
        png_info(&read(&out.join("fin.png"))),
        (64, 16, png::ColorType::Rgba, png::BitDepth::Eight)
    );
    assert_eq!(png_info(&read(&out.join("fin.mip6.png"))).0, 1);
    let m: Value = serde_json::from_slice(&read(&out.join("fur.json"))).expect("fur.json is JSON");
    assert_eq!(m["version"], 1);
    assert_eq!(m["strands"]["seed"], 3);
    assert_eq!(m["strands"]["strands"], 800);
    assert_eq!(m["textures"]["heightfield"]["format"], "gray16");
    assert_eq!(m["textures"]["fin"]["levels"][0]["file"], "fin.png");
    assert_eq!(
        m["textures"]["dots"]["levels"].as_array().map(Vec::len),
        Some(7)
    );
    let measured = m["coverage"]["dots"].as_f64().expect("coverage");
    let expected = m["expectedCoverage"]["dots"]
        .as_f64()
        .expect("expected coverage");
    assert!(
        measured > 0.0 && (measured / expected - 1.0).abs() < 0.1,
        "{measured} {expected}"
    );
    // No absolute paths in the manifest.
    let text = String::from_utf8_lossy(&read(&out.join("fur.json"))).into_owned();
    assert!(!text.contains(dir.to_str().unwrap_or("/")), "{text}");

    // 8-bit heightfield, no mips.
    let out8 = dir.join("fur8");
    pelt_ok(&[
        "textures",
        "-q",
        "--size",
        "64",
        "--height-bits",
        "8",
        "--no-mips",
        "-o",
        out8.to_str().unwrap_or_default(),
    ]);
    assert_eq!(
        png_info(&read(&out8.join("heightfield.png"))).3,
        png::BitDepth::Eight
    );
    assert!(!out8.join("dots.mip1.png").exists());
}

#[test]
fn textures_are_byte_identical_at_any_thread_count() {
    let dir = scratch("textures-threads");
    let mut sets = Vec::new();
    for threads in ["1", "2", "5"] {
        let out = dir.join(threads);
        let o = pelt(
            &[
                "textures",
                "-q",
                "--seed",
                "9",
                "--size",
                "128",
                "--tilt",
                "2",
                "--clumps",
                "20",
                "--clumping",
                "0.5",
                "-o",
                out.to_str().unwrap_or_default(),
            ],
            &[("RAYON_NUM_THREADS", threads)],
        );
        assert!(o.status.success());
        let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(&out)
            .expect("output")
            .flatten()
            .map(|e| {
                (
                    e.file_name().to_string_lossy().into_owned(),
                    read(&e.path()),
                )
            })
            .collect();
        files.sort();
        assert_eq!(files.len(), 3 * 8 + 1);
        sets.push(files);
    }
    assert!(sets[0] == sets[1] && sets[1] == sets[2]);
}

#[test]
fn bad_texture_parameters_are_usage_errors() {
    let dir = scratch("textures-bad");
    for (args, needle) in [
        (&["--size", "1000"][..], "size: must be a power of two"),
        (&["--radius", "0.5"][..], "radius"),
        (
            &["--height-min", "0.9", "--height-max", "0.5"][..],
            "heightMax",
        ),
        (&["--clumping", "0.5"][..], "clumps"),
        (&["--fin-height", "128", "--size", "64"][..], "finHeight"),
    ] {
        let out = dir.join("x");
        let mut a = vec!["textures", "-o", out.to_str().unwrap_or_default()];
        a.extend_from_slice(args);
        let o = pelt(&a, &[]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?} wrote output");
    }
}

const CONFIG: &str = r#"{
  "fur": {
    "length": 0.03,
    "shells": 12,
    "uvScale": 5.0,
    "baseColor": [0.1, 0.05, 0.02],
    "tipColor": [0.7, 0.5, 0.3],
    "textures": { "seed": 4, "size": 128, "strands": 3000, "radius": 0.004 }
  }
}"#;

#[test]
fn bake_embeds_the_textures_and_the_manifest() {
    let dir = scratch("bake-fur");
    let config = dir.join("pelt.json");
    std::fs::write(&config, CONFIG).expect("write config");
    let c = config.to_str().unwrap_or_default();
    let glb = bake(&fixture("creature.glb"), &dir, &["--config", c]);
    let (doc, material) = load_with_material(&glb);
    // The manifest is the material's PELT_fur (in the manifest layout, as readers see it).
    let m = &doc.json["materials"][material];
    assert!(
        m["extensions"]["PELT_fur"].is_object() && m["extras"].get("pelt").is_none(),
        "{m}"
    );
    let (fur, place) = doc
        .fur_manifest_json(material)
        .expect("read")
        .expect("manifest");
    assert_eq!(place, format!("materials[{material}].extensions.PELT_fur"));
    let fur = &fur;
    assert_eq!(fur["version"], 1);
    assert_eq!(fur["length"], 0.03);
    assert_eq!(fur["shells"], 12);
    assert_eq!(fur["uvScale"], 5.0);
    assert_eq!(fur["tipColor"][0], 0.7);
    assert_eq!(fur["strands"]["seed"], 4);
    // The textures the manifest names hold exactly what `pelt textures` writes.
    let tex_dir = dir.join("tex");
    pelt_ok(&[
        "textures",
        "-q",
        "--config",
        c,
        "-o",
        tex_dir.to_str().unwrap_or_default(),
    ]);
    let images = doc.json["images"].as_array().expect("images");
    for stem in ["heightfield", "dots", "fin"] {
        let entry = &fur["textures"][stem];
        let t = entry["texture"].as_u64().expect("texture index") as usize;
        let texture = &doc.json["textures"][t];
        let levels = entry["levels"].as_array().expect("levels");
        assert_eq!(texture["source"], levels[0]["image"]);
        let sampler = &doc.json["samplers"][texture["sampler"].as_u64().expect("sampler") as usize];
        assert_eq!(sampler["wrapS"], 10497);
        assert_eq!(sampler["minFilter"], 9987);
        assert_eq!(levels.len(), 8, "{stem}: 128² has 8 levels");
        for (l, level) in levels.iter().enumerate() {
            let i = level["image"].as_u64().expect("image") as usize;
            assert_eq!(images[i]["mimeType"], "image/png");
            let view = images[i]["bufferView"].as_u64().expect("view") as usize;
            let v = &doc.json["bufferViews"][view];
            let start = v["byteOffset"].as_u64().unwrap_or(0) as usize;
            let len = v["byteLength"].as_u64().expect("len") as usize;
            let bytes = &doc.buffers[0][start..start + len];
            let name = file_name(stem, l);
            assert_eq!(images[i]["name"], name.as_str());
            assert!(
                bytes == read(&tex_dir.join(&name)).as_slice(),
                "{name} differs"
            );
        }
    }
    // Same config, other thread count: same bytes.
    let dir2 = scratch("bake-fur-threads");
    let out2 = dir2.join("creature.glb");
    let o = pelt(
        &[
            "bake",
            "-q",
            fixture("creature.glb").to_str().unwrap_or_default(),
            "-o",
            out2.to_str().unwrap_or_default(),
            "--config",
            c,
        ],
        &[("RAYON_NUM_THREADS", "1")],
    );
    assert!(o.status.success());
    assert!(read(&glb) == read(&out2), "thread count changed the output");
    validate_clean(&[&glb]);
}

/// Baking a pelt output again replaces its fur: one set of images, a file of the same size,
/// and a second bake of that byte for byte the first. The Fox keeps its own base colour
/// texture through it.
#[test]
fn re_baking_a_baked_file_keeps_one_set_of_fur_images() {
    let dir = scratch("rebake");
    let config = dir.join("pelt.json");
    std::fs::write(&config, CONFIG).expect("write config");
    let c = config.to_str().unwrap_or_default();
    for (input, extra) in [
        (fixture("creature.glb"), &[][..]),
        (fixture("fox/Fox.glb"), &["--comb", "generate"][..]),
    ] {
        let stem = input
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        let mut args = vec!["--config", c];
        args.extend_from_slice(extra);
        let sub = |n: usize| {
            let d = dir.join(format!("{stem}-{n}"));
            std::fs::create_dir_all(&d).expect("folder");
            d
        };
        let first = bake(&input, &sub(1), &args);
        let second = bake(&first, &sub(2), &args);
        let third = bake(&second, &sub(3), &args);
        let count =
            |p: &Path, key: &str| pelt_io::Document::load(p).expect("load").array(key).len();
        let own = count(&input, "images");
        // 3 textures × 8 levels.
        assert_eq!(count(&first, "images"), own + 24, "{stem}");
        for key in ["images", "textures", "samplers", "bufferViews", "accessors"] {
            assert_eq!(count(&second, key), count(&first, key), "{stem}: {key}");
        }
        assert_eq!(read(&first).len(), read(&second).len(), "{stem}: size");
        assert!(
            read(&second) == read(&third),
            "{stem}: the second re-bake differs"
        );
        let (doc, m) = load_with_material(&second);
        let fur = &doc.json["materials"][m]["extensions"]["PELT_fur"];
        let t = fur["heightfieldTexture"]["index"]
            .as_u64()
            .expect("texture");
        assert!((t as usize) < doc.array("textures").len());
        validate_clean(&[&second]);
    }
}

#[test]
fn comb_primitives_without_a_material_get_one() {
    let dir = scratch("bake-fur-obj");
    let config = dir.join("pelt.json");
    std::fs::write(&config, CONFIG).expect("write config");
    let obj = fixture("edge/painted.obj");
    let glb = bake(
        &obj,
        &dir,
        &["--config", config.to_str().unwrap_or_default()],
    );
    let (doc, m) = load_with_material(&glb);
    assert_eq!(doc.json["materials"][m]["name"], "pelt fur");
    assert_eq!(
        doc.json["materials"][m]["extensions"]["PELT_fur"]["shells"],
        12
    );
}

#[test]
fn bad_configs_name_the_file_and_write_nothing() {
    let dir = scratch("bake-fur-bad");
    let out = dir.join("out.glb");
    for (text, needle, code) in [
        (
            "{\n  \"fur\": {\n    \"lenght\": 1\n  }\n}",
            "pelt.json:3:",
            2,
        ),
        (
            r#"{"fur": {"textures": {"size": 100}}}"#,
            "pelt.json: fur.textures.size",
            2,
        ),
        (r#"{"fur": {"materials": ["Nope"]}}"#, "\"Nope\"", 1),
        ("{\"fur\": ", "pelt.json:1:", 2),
    ] {
        let config = dir.join("pelt.json");
        std::fs::write(&config, text).expect("write config");
        let o = pelt(
            &[
                "bake",
                fixture("creature.glb").to_str().unwrap_or_default(),
                "-o",
                out.to_str().unwrap_or_default(),
                "--config",
                config.to_str().unwrap_or_default(),
            ],
            &[],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(code), "{text}: {err}");
        assert!(err.contains(needle), "{text}: {err}");
        if code == 1 {
            assert!(err.contains("creature.glb"), "{err}");
        }
        assert!(!out.exists(), "{text}: output written");
    }
}
