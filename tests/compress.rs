//! Compressed output (`pelt bake --compress`, `EXT_meshopt_compression`): the file reads back
//! as the plain bake within the stated quantization bounds (vertices, combs, fins, the
//! rendered picture), every reader takes it, and it is deterministic and validator-clean.

mod common;

use std::path::{Path, PathBuf};

use common::*;
use glam::Vec3;
use pelt_io::{Document, PrimitiveRef};

const R: PrimitiveRef = PrimitiveRef {
    mesh: 0,
    primitive: 0,
};

fn bake_to(input: &Path, out: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        input.to_str().unwrap_or_default(),
        "-o",
        out.to_str().unwrap_or_default(),
    ];
    args.extend_from_slice(extra);
    bake_report(&args)
}

/// Each vertex of `packed` paired with the plain vertex at the same position and UV.
fn match_vertices(plain: &Baked, packed: &Baked, uvs: [&[glam::Vec2]; 2], tol: f32) -> Vec<usize> {
    let mut order: Vec<usize> = (0..plain.positions.len()).collect();
    order.sort_by(|&a, &b| plain.positions[a].x.total_cmp(&plain.positions[b].x));
    let xs: Vec<f32> = order.iter().map(|&i| plain.positions[i].x).collect();
    packed
        .positions
        .iter()
        .enumerate()
        .map(|(v, p)| {
            let lo = xs.partition_point(|&x| x < p.x - tol);
            order[lo..]
                .iter()
                .take_while(|&&i| plain.positions[i].x <= p.x + tol)
                .copied()
                .find(|&i| {
                    plain.positions[i].distance(*p) <= tol && uvs[0][i].distance(uvs[1][v]) <= 1e-3
                })
                .unwrap_or_else(|| {
                    let near = (0..plain.positions.len())
                        .min_by(|&a, &b| {
                            plain.positions[a]
                                .distance(*p)
                                .total_cmp(&plain.positions[b].distance(*p))
                        })
                        .unwrap_or(0);
                    panic!(
                        "packed vertex {v} at {p} (uv {}) has no plain twin; nearest {near} at {} (uv {})",
                        uvs[1][v], plain.positions[near], uvs[0][near]
                    )
                })
        })
        .collect()
}

fn uvs(path: &Path) -> Vec<glam::Vec2> {
    let doc = Document::load(path).expect("load");
    let m = pelt_io::mesh::read_primitive(&doc, R).expect("read");
    m.mesh.uvs.expect("TEXCOORD_0")
}

/// Each fin as (its two end positions, the third vertex of each of its faces), each pair
/// ordered (a boundary fin's second face is its first).
fn fin_shapes(path: &Path) -> Vec<[[Vec3; 2]; 2]> {
    let doc = Document::load(path).expect("load");
    let m = pelt_io::mesh::read_primitive(&doc, R).expect("read");
    let fins = doc.read_fins(R).expect("fins").expect("present");
    let (ix, pos) = (&m.mesh.indices, &m.mesh.positions);
    let p = |c: u32| pos[ix[c as usize] as usize];
    let (next, prev) = (
        |c: u32| c / 3 * 3 + (c + 1) % 3,
        |c: u32| c / 3 * 3 + (c + 2) % 3,
    );
    let sorted = |mut x: [Vec3; 2]| {
        if x[1].to_array() < x[0].to_array() {
            x.swap(0, 1);
        }
        x
    };
    fins.iter()
        .map(|e| {
            let second = if e.second_corner == u32::MAX {
                e.corner
            } else {
                e.second_corner
            };
            [
                sorted([p(e.corner), p(next(e.corner))]),
                sorted([p(prev(e.corner)), p(prev(second))]),
            ]
        })
        .collect()
}

/// Every packed fin has a plain twin (the same edge between the same two faces: every
/// position within `tol`), each plain fin used once; and each fin's faces share its edge.
fn fins_match(plain: &Path, packed: &Path, tol: f32) {
    fins_are_edges_of_both_faces(packed);
    let (a, b) = (fin_shapes(plain), fin_shapes(packed));
    assert_eq!(a.len(), b.len(), "fin count");
    let cell = |f: &[[Vec3; 2]; 2]| ((f[0][0] + f[0][1]) / 0.1).floor().as_ivec3();
    let mut grid: std::collections::HashMap<glam::IVec3, Vec<usize>> = Default::default();
    for (i, f) in a.iter().enumerate() {
        grid.entry(cell(f)).or_default().push(i);
    }
    let mut used = vec![false; a.len()];
    // Pairs compared either way round (quantization may swap their order).
    let pair = |x: &[Vec3; 2], y: &[Vec3; 2]| {
        let d = |i: usize, j: usize| x[i].distance(y[j]) <= tol;
        (d(0, 0) && d(1, 1)) || (d(0, 1) && d(1, 0))
    };
    let same = |x: &[[Vec3; 2]; 2], y: &[[Vec3; 2]; 2]| pair(&x[0], &y[0]) && pair(&x[1], &y[1]);
    for (k, f) in b.iter().enumerate() {
        let c = cell(f);
        let near = (-1..=1).flat_map(|x| {
            (-1..=1).flat_map(move |y| (-1..=1).map(move |z| c + glam::IVec3::new(x, y, z)))
        });
        let twin = near
            .filter_map(|c| grid.get(&c))
            .flatten()
            .copied()
            .find(|&i| !used[i] && same(&a[i], f));
        let i = twin.unwrap_or_else(|| panic!("packed fin {k} {f:?} has no plain twin"));
        used[i] = true;
    }
}

#[test]
fn compressed_output_reads_back_as_the_plain_bake() {
    let dir = scratch("compress-round-trip");
    let input = fixture("creature.glb");
    let (plain, packed) = (dir.join("plain.glb"), dir.join("packed.glb"));
    let rp = bake_to(&input, &plain, &["--quantize", "u8"]);
    let rk = bake_to(&input, &packed, &["--compress"]);
    for key in ["vertices", "triangles"] {
        assert_eq!(rp[key], rk[key], "{key}");
    }
    let c = &rk["compression"];
    assert_eq!(c["extension"], "EXT_meshopt_compression");
    assert_eq!(c["primitives_reordered"], 1);
    let size = |p: &Path| std::fs::metadata(p).expect("size").len();
    assert!(
        size(&packed) * 3 < size(&plain),
        "{} vs {}",
        size(&packed),
        size(&plain)
    );

    let (a, b) = (read_baked(&plain, 0, 0), read_baked(&packed, 0, 0));
    // Half a quantization step per axis: 2^(e − 13) where 2^e is above the axis's largest |x|
    // (2.44e-4, 1.22e-4 and 6.1e-5 on the creature), 2.8e-4 in length.
    let tol = 2.8e-4;
    let map = match_vertices(&a, &b, [&uvs(&plain), &uvs(&packed)], tol);
    let mut worst = 0f64;
    for (v, &w) in map.iter().enumerate() {
        // The object-space comb: 8-bit octahedral normal and tangent, u8 comb on both sides.
        worst = worst.max(angle(a.object_comb(w), b.object_comb(v)));
        assert!(
            (a.comb[w][3] - b.comb[v][3]).abs() <= 1.0 / 255.0,
            "length at {v}"
        );
    }
    eprintln!("object-space comb: worst {:.3}°", worst.to_degrees());
    assert!(
        worst.to_degrees() < 2.0,
        "comb off by {:.3}°",
        worst.to_degrees()
    );
    fins_match(&plain, &packed, tol);

    // pelt inspect: the same counts and topology.
    let inspect = |p: &Path| -> serde_json::Value {
        let o = pelt_ok(&["inspect", p.to_str().unwrap_or_default(), "--json"]);
        serde_json::from_slice(&o.stdout).expect("json")
    };
    let (ia, ib) = (inspect(&plain), inspect(&packed));
    let topo = |j: &serde_json::Value| j["topology"].clone();
    assert_eq!(topo(&ia), topo(&ib));
    validate_clean(&[&packed]);
}

#[test]
fn compressed_output_renders_as_the_plain_bake() {
    let dir = scratch("compress-render");
    let input = fixture("creature.glb");
    let render = |glb: &Path, name: &str| {
        let png = dir.join(name);
        pelt_ok(&[
            "render",
            glb.to_str().unwrap_or_default(),
            "-o",
            png.to_str().unwrap_or_default(),
            "--size",
            "192x128",
            "--fins",
            "on",
        ]);
        load_png(&png)
    };
    let glb = |name: &str, extra: &[&str]| -> PathBuf {
        let out = dir.join(name);
        bake_to(&input, &out, extra);
        out
    };
    let plain = render(&glb("plain.glb", &[]), "plain.png");
    let packed = render(&glb("packed.glb", &["--compress"]), "packed.png");
    let flip = |x: &pelt_preview::Image| {
        pelt_measure::flip::Flip::new(&plain, x)
            .expect("same size")
            .mean()
    };
    let f = flip(&packed);
    eprintln!("compressed against plain: FLIP {f}");
    // Measured 0.0044 on llvmpipe (0.0015 without fins): the difference lies on the
    // silhouette, where 14-bit positions tilt the creature's sliver triangles at its poles
    // and the fins fade in by their faces' normals.
    assert!(f <= 0.006, "compressed against plain: FLIP {f}");
    // Negative control: another comb fails the same threshold (measured 0.039).
    let other = render(&glb("other.glb", &["--comb", "generate:x"]), "other.png");
    assert!(flip(&other) > 0.006, "another comb: FLIP {}", flip(&other));
}

#[test]
fn every_reader_takes_compressed_output_and_it_is_deterministic() {
    let dir = scratch("compress-readers");
    let fox = dir.join("fox.glb");
    let fox_args = ["--comb", "generate", "--compress"];
    bake_to(&fixture("fox/Fox.glb"), &fox, &fox_args);
    // Byte-identical at one thread and at the default count.
    let one = dir.join("fox-1.glb");
    let o = pelt(
        &[
            "bake",
            fixture("fox/Fox.glb").to_str().unwrap_or_default(),
            "-o",
            one.to_str().unwrap_or_default(),
            "--comb",
            "generate",
            "--compress",
        ],
        &[("RAYON_NUM_THREADS", "1")],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(std::fs::read(&fox).ok(), std::fs::read(&one).ok());
    // Posed, rendered mid-walk, and baked again (compressed again).
    let walk = dir.join("walk.glb");
    let (f, w) = (
        fox.to_str().unwrap_or_default(),
        walk.to_str().unwrap_or_default(),
    );
    pelt_ok(&["pose", f, "--animation", "Walk", "--time", "0.4", "-o", w]);
    let png = dir.join("walk.png");
    let p = png.to_str().unwrap_or_default();
    pelt_ok(&[
        "render",
        f,
        "-o",
        p,
        "--size",
        "96x64",
        "--animation",
        "Walk",
        "--time",
        "0.4",
    ]);
    let again = dir.join("again.glb");
    bake_to(&fox, &again, &["--comb", "generate", "--compress"]);
    let doc = Document::load(&again).expect("load");
    assert!(
        doc.read_fins(R)
            .expect("fins")
            .is_some_and(|f| !f.is_empty())
    );
    validate_clean(&[&fox, &walk, &again]);
}

#[test]
fn a_bake_config_asks_for_compression_and_a_bad_value_is_named() {
    let dir = scratch("compress-config");
    let cfg = dir.join("bake.json");
    std::fs::write(&cfg, r#"{"compress": "meshopt"}"#).expect("write");
    let out = dir.join("out.glb");
    let r = bake_to(
        &fixture("torus.glb"),
        &out,
        &["--config", cfg.to_str().unwrap_or_default()],
    );
    assert_eq!(r["compression"]["extension"], "EXT_meshopt_compression");
    // The flag overrides the config.
    let plain = dir.join("plain.glb");
    let r = bake_to(
        &fixture("torus.glb"),
        &plain,
        &[
            "--config",
            cfg.to_str().unwrap_or_default(),
            "--compress",
            "none",
        ],
    );
    assert!(r.get("compression").is_none());
    std::fs::write(&cfg, r#"{"compress": "zip"}"#).expect("write");
    let bad = dir.join("bad.glb");
    let o = pelt(
        &[
            "bake",
            fixture("torus.glb").to_str().unwrap_or_default(),
            "-o",
            bad.to_str().unwrap_or_default(),
            "--config",
            cfg.to_str().unwrap_or_default(),
        ],
        &[],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("compress") && err.contains("zip"), "{err}");
    assert!(!bad.exists());
}

/// Every fin's second face runs its edge the other way (by position: seams are welded).
fn fins_are_edges_of_both_faces(path: &Path) {
    let doc = Document::load(path).expect("load");
    let m = pelt_io::mesh::read_primitive(&doc, R).expect("read");
    let fins = doc.read_fins(R).expect("fins").expect("present");
    let (ix, pos) = (&m.mesh.indices, &m.mesh.positions);
    let p = |c: u32| pos[ix[c as usize] as usize];
    let next = |c: u32| c / 3 * 3 + (c + 1) % 3;
    for (k, e) in fins.iter().enumerate() {
        if e.second_corner == u32::MAX {
            continue;
        }
        let (a, b) = (p(e.corner), p(next(e.corner)));
        let (c, d) = (p(e.second_corner), p(next(e.second_corner)));
        assert!(
            (a == d && b == c) || (a == c && b == d),
            "{}: fin {k} {e:?}: {a} {b} vs {c} {d}",
            path.display()
        );
    }
}

#[test]
fn fins_derived_from_the_index_list_that_lie_are_refused() {
    let dir = scratch("compress-lying-fins");
    let packed = dir.join("packed.glb");
    bake_to(&fixture("torus.glb"), &packed, &["--compress"]);
    let bytes = std::fs::read(&packed).expect("read");
    let edit = |f: &dyn Fn(&mut serde_json::Value)| -> Document {
        let (json, _) = pelt_fixtures::mutate::glb_chunks(&bytes).expect("glb");
        let mut j: serde_json::Value = serde_json::from_slice(&bytes[json.clone()]).expect("json");
        f(&mut j["meshes"][0]["primitives"][0]);
        let glb = pelt_fixtures::mutate::assemble_glb(
            &serde_json::to_vec(&j).expect("json"),
            &bytes[json.end..],
        );
        Document::from_bytes(Path::new("lying.glb"), glb).expect("loads")
    };
    let ok = edit(&|_| {});
    assert!(
        ok.read_fins(R)
            .is_ok_and(|f| f.is_some_and(|f| f.len() == 3456))
    );
    for (what, f, needle) in [
        (
            "count",
            &(|p: &mut serde_json::Value| {
                p["extensions"]["PELT_fur"]["fins"]["count"] = 3457.into()
            }) as &dyn Fn(&mut serde_json::Value),
            "count is 3457",
        ),
        (
            "removed",
            // POSITION's accessor: not corner pairs.
            &|p: &mut serde_json::Value| {
                p["extensions"]["PELT_fur"]["fins"]["fromIndices"]["removed"] =
                    p["attributes"]["POSITION"].clone();
            },
            "must be VEC2 UNSIGNED_INT",
        ),
    ] {
        let err = edit(f).read_fins(R).expect_err(what).to_string();
        assert!(
            err.contains("lying.glb")
                && err.contains("extensions.PELT_fur.fins")
                && err.contains(needle),
            "{what}: {err}"
        );
    }
}
