//! Normal groups, their IDs and fin edges, end to end: bake a file, read back what a renderer
//! would read (`_NORMAL_GROUP`, `extras.pelt`, the fin records) and `pelt inspect --json`.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use common::*;
use glam::Vec3;
use pelt_geom::topology::{NO_CORNER, next_corner};
use pelt_io::topology::fin_geometry;
use pelt_io::{Document, PrimitiveRef, accessor};
use serde_json::Value;

const PRIM: PrimitiveRef = PrimitiveRef {
    mesh: 0,
    primitive: 0,
};

/// `pelt inspect FILE --json`.
fn inspect(file: &Path) -> Value {
    let out = pelt_ok(&["inspect", file.to_str().unwrap_or_default(), "--json"]);
    serde_json::from_slice(&out.stdout).expect("inspect prints JSON")
}

/// What a renderer reads: positions, indices, group ID per vertex, fin records.
struct Read {
    doc: Document,
    positions: Vec<Vec3>,
    indices: Vec<u32>,
    ids: Vec<u16>,
}

fn read(file: &Path) -> Read {
    let doc = Document::load(file).expect("load output");
    let m = pelt_io::mesh::read_primitive(&doc, PRIM).expect("primitive");
    let a = doc
        .attribute(PRIM, "_NORMAL_GROUP")
        .expect("attributes")
        .expect("_NORMAL_GROUP written");
    let e = accessor::read(&doc, a, "_NORMAL_GROUP").expect("read ids");
    assert_eq!((e.components, e.normalized), (1, false));
    let ids = (0..e.count)
        .map(|k| accessor::raw(e.component, &e.bytes, k) as u16)
        .collect();
    Read {
        positions: m.mesh.positions.clone(),
        indices: m.mesh.indices.clone(),
        ids,
        doc,
    }
}

impl Read {
    /// The ID every face sees, checking its three corners agree.
    fn face_ids(&self) -> Vec<u16> {
        self.indices
            .chunks_exact(3)
            .enumerate()
            .map(|(f, t)| {
                let id = self.ids[t[0] as usize];
                assert!(
                    t.iter().all(|&v| self.ids[v as usize] == id),
                    "face {f} sees more than one group ID"
                );
                id
            })
            .collect()
    }

    /// Position bits, for exact welding in checks.
    fn key(&self, v: u32) -> [u32; 3] {
        self.positions[v as usize]
            .to_array()
            .map(|x| if x == 0.0 { 0 } else { x.to_bits() })
    }

    /// Faces sharing at least one position, as pairs.
    fn vertex_neighbours(&self) -> BTreeSet<(usize, usize)> {
        let mut at: BTreeMap<[u32; 3], Vec<usize>> = BTreeMap::new();
        for (c, &v) in self.indices.iter().enumerate() {
            at.entry(self.key(v)).or_default().push(c / 3);
        }
        let mut pairs = BTreeSet::new();
        for faces in at.values() {
            for (i, &a) in faces.iter().enumerate() {
                for &b in &faces[i + 1..] {
                    if a != b {
                        pairs.insert((a.min(b), a.max(b)));
                    }
                }
            }
        }
        pairs
    }
}

fn topology_of(info: &Value) -> [u64; 7] {
    [
        "normal_groups",
        "ids_used",
        "fin_edges",
        "boundary_edges",
        "nonmanifold_edges",
        "split_vertices",
        "triangles",
    ]
    .map(|k| {
        info[k]
            .as_u64()
            .unwrap_or_else(|| panic!("{k} missing: {info}"))
    })
}

#[test]
fn flat_shaded_cube_has_six_groups_and_closed_fins() {
    let dir = scratch("cube");
    let out = bake(&fixture("edge/flat-cube.gltf"), &dir, &[]);
    // 6 groups, 6 IDs, 18 = 3F/2 fin edges, no boundary, nothing split (already per side).
    assert_eq!(topology_of(&inspect(&out)), [6, 6, 18, 0, 0, 0, 12]);
    let r = read(&out);
    let ids = r.face_ids();
    for side in ids.chunks_exact(2) {
        assert_eq!(side[0], side[1], "the two triangles of a side differ");
    }
    let distinct: BTreeSet<u16> = ids.iter().copied().collect();
    assert_eq!(distinct.len(), 6);
    assert!(!distinct.contains(&0), "0 is reserved for 'no group'");
}

#[test]
fn uv_sphere_seam_is_one_group_with_no_duplicated_fin_edges() {
    let dir = scratch("sphere");
    let out = bake(&fixture("sphere.glb"), &dir, &["--report", "-"]);
    let info = inspect(&out);
    let r = read(&out);
    let fins = r.doc.read_fins(PRIM).expect("fins").expect("fins stored");
    // Pole rows are degenerate: the proper faces close up, so fins = 3/2 of them.
    let proper = r
        .indices
        .chunks_exact(3)
        .filter(|t| {
            let k = [r.key(t[0]), r.key(t[1]), r.key(t[2])];
            k[0] != k[1] && k[1] != k[2] && k[0] != k[2]
        })
        .count();
    assert_eq!(info["normal_groups"], 1);
    assert_eq!(info["boundary_edges"], 0);
    assert_eq!(fins.len(), 3 * proper / 2);
    // The seam column is duplicated in the file, but each welded edge appears once.
    let mut seen = BTreeSet::new();
    for f in &fins {
        let [v0, v1] = fin_geometry(f, &r.indices, &r.positions).vertices;
        let (a, b) = (r.key(v0), r.key(v1));
        assert!(seen.insert((a.min(b), a.max(b))), "edge {a:?}-{b:?} twice");
    }
    // The sphere's file really has a seam: more vertices than welded positions.
    let positions: BTreeSet<[u32; 3]> = (0..r.positions.len() as u32).map(|v| r.key(v)).collect();
    assert!(positions.len() < r.positions.len());
}

#[test]
fn torus_with_two_rings_of_hard_edges_has_two_groups() {
    let dir = scratch("hard-torus");
    let out = bake(&fixture("edge/hard-torus.gltf"), &dir, &[]);
    let info = inspect(&out);
    assert_eq!(info["normal_groups"], 2);
    let r = read(&out);
    let ids = r.face_ids();
    // The generator writes the upper half's faces first, then the lower half's.
    let half = ids.len() / 2;
    assert!(ids[..half].iter().all(|&i| i == ids[0]));
    assert!(ids[half..].iter().all(|&i| i == ids[half]));
    assert_ne!(ids[0], ids[half]);
    // Still one closed surface for the fins: the hard rings are edges, not boundaries.
    assert_eq!(topology_of(&info)[2..5], [3 * ids.len() as u64 / 2, 0, 0]);
}

#[test]
fn closed_manifold_has_3f_over_2_fin_edges_each_with_both_faces() {
    let dir = scratch("torus");
    let out = bake(&fixture("torus.glb"), &dir, &[]);
    let r = read(&out);
    let fins = r.doc.read_fins(PRIM).expect("fins").expect("stored");
    let faces = r.indices.len() / 3;
    assert_eq!(fins.len(), 3 * faces / 2);
    for f in &fins {
        assert_ne!(f.second_corner, NO_CORNER);
        // Both corners' edges join the same two positions, in opposite directions (the torus
        // is consistently wound).
        let end = |c: u32| r.key(r.indices[c as usize]);
        let (c0, c1) = (f.corner, f.second_corner);
        assert_ne!(c0 / 3, c1 / 3, "one face twice");
        assert_eq!(
            (end(c0), end(next_corner(c0))),
            (end(next_corner(c1)), end(c1))
        );
        // The decoded face normals are the faces' own.
        let g = fin_geometry(f, &r.indices, &r.positions);
        for (k, c) in [c0, c1].into_iter().enumerate() {
            let face = (c / 3) as usize;
            let t = &r.indices[3 * face..3 * face + 3];
            let p = |i: usize| r.positions[t[i] as usize];
            let n = (p(1) - p(0)).cross(p(2) - p(0)).normalize();
            assert!(n.dot(g.face_normals[k]) > 0.9999, "face {face}");
        }
        assert_eq!(
            g.vertices,
            [r.indices[c0 as usize], r.indices[next_corner(c0) as usize]]
        );
    }
}

#[test]
fn open_grid_counts_its_boundary() {
    // sparse-color is a 3 × 2 quad plane.
    let dir = scratch("grid");
    let out = bake(&fixture("edge/sparse-color.gltf"), &dir, &[]);
    let info = inspect(&out);
    let t = topology_of(&info);
    assert_eq!((t[3], t[4]), (2 * (3 + 2), 0));
    // Every edge of the plane: 3·3 horizontal, 4·2 vertical, 6 diagonals.
    assert_eq!(info["primitive"][0]["topology"]["edges"], 9 + 8 + 6);
}

/// A document with one mesh from raw arrays (comb +X, given normals).
fn write_mesh(
    dir: &Path,
    name: &str,
    positions: &[Vec3],
    normals: &[Vec3],
    indices: &[u32],
) -> std::path::PathBuf {
    let shape = pelt_fixtures::shapes::Shape {
        name: name.to_owned(),
        positions: positions.to_vec(),
        normals: normals.to_vec(),
        uvs: positions
            .iter()
            .map(|p| glam::Vec2::new(p.x, p.y))
            .collect(),
        colors: positions
            .iter()
            .map(|_| pelt_fixtures::paint(Vec3::X, 1.0))
            .collect(),
        indices: indices.to_vec(),
    };
    let doc = pelt_fixtures::build::document(&shape, pelt_fixtures::build::BuildOptions::default());
    let path = dir.join(format!("{name}.gltf"));
    pelt_io::glb::write_gltf_embedded(&doc, &path).expect("write");
    path
}

#[test]
fn a_vertex_shared_by_two_groups_is_duplicated() {
    // A bow tie: two triangles meeting only at vertex 0 (which both index), tilted apart.
    let dir = scratch("bowtie");
    let p = [
        Vec3::ZERO,
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.5),
        Vec3::new(-1.0, -1.0, 0.5),
    ];
    let n = [Vec3::Z; 5];
    let input = write_mesh(&dir, "bowtie", &p, &n, &[0, 2, 1, 0, 3, 4]);
    let out = bake(&input, &dir, &[]);
    let info = inspect(&out);
    assert_eq!(info["normal_groups"], 2);
    assert_eq!(info["split_vertices"], 1);
    assert_eq!(info["vertices"], 6);
    let r = read(&out);
    let ids = r.face_ids();
    assert_ne!(ids[0], ids[1]);
    assert_ne!(r.indices[0], r.indices[3], "vertex 0 was not split");
    // The copy carries its source's comb, normal and tangent (the per-vertex pass runs over the
    // source vertices beside the topology; the copy gathers its source's results).
    let b = read_baked(&out, 0, 0);
    let (v, copy) = (r.indices[0] as usize, r.indices[3] as usize);
    assert_eq!(b.positions[v], b.positions[copy]);
    assert_eq!(b.comb[v], b.comb[copy]);
    assert_eq!(b.normals[v], b.normals[copy]);
    assert_eq!(b.tangents[v], b.tangents[copy]);
    assert!(b.comb[v][3] > 0.0, "{:?}", b.comb[v]);
}

#[test]
fn many_groups_get_ids_no_neighbours_share_and_the_report_compares_random_ids() {
    // A sphere without NORMAL, baked with flat normals (crease angle 0): nearly every face is
    // its own group, far beyond 255.
    let dir = scratch("flat-sphere");
    let shape = pelt_fixtures::shapes::sphere(24, 48);
    let doc = pelt_fixtures::build::document(
        &shape,
        pelt_fixtures::build::BuildOptions {
            normals: false,
            ..Default::default()
        },
    );
    let input = dir.join("flat-sphere.gltf");
    pelt_io::glb::write_gltf_embedded(&doc, &input).expect("write");
    let rep = dir.join("report.json");
    let out = bake(
        &input,
        &dir,
        &[
            "--report",
            rep.to_str().unwrap_or_default(),
            "--crease-angle",
            "0",
        ],
    );
    let report: Value =
        serde_json::from_slice(&std::fs::read(&rep).expect("report")).expect("json");
    let p = &report["inputs"][0]["primitives"][0];
    let groups = p["normal_groups"].as_u64().expect("groups");
    assert!(groups > 1000, "{groups} groups");
    assert_eq!(p["shared_id_pairs"], 0, "{p}");
    assert_eq!(p["uncolorable_groups"], 0);
    // Use is spread over every ID, and random IDs would have collided on some neighbours.
    assert_eq!(p["ids_used"], 255);
    assert!(p["random_id_collisions"].as_u64() > Some(0), "{p}");
    // Check it from the file: faces of different groups that share a position never share
    // an ID.
    let r = read(&out);
    let ids = r.face_ids();
    let groups_of = group_labels(&r);
    let proper = |f: usize| {
        let t = &r.indices[3 * f..3 * f + 3];
        let k = [r.key(t[0]), r.key(t[1]), r.key(t[2])];
        k[0] != k[1] && k[1] != k[2] && k[0] != k[2]
    };
    // Degenerate (pole) faces cover no pixels and join a neighbour by pelt's rule: skip them.
    for (a, b) in r
        .vertex_neighbours()
        .into_iter()
        .filter(|&(a, b)| proper(a) && proper(b))
    {
        if groups_of[a] != groups_of[b] {
            assert_ne!(
                ids[a], ids[b],
                "faces {a} and {b}: neighbouring groups share an ID"
            );
        }
    }
}

/// Groups recomputed from the output file for the check above: faces joined across welded
/// edges where their flat normals agree within 0.1° (on this sphere they either agree to
/// rounding, the two halves of a planar quad, or differ by degrees).
fn group_labels(r: &Read) -> Vec<usize> {
    let faces = r.indices.len() / 3;
    let mut parent: Vec<usize> = (0..faces).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    let normal = |f: usize| {
        let p = |k: usize| r.positions[r.indices[3 * f + k] as usize];
        (p(1) - p(0)).cross(p(2) - p(0)).normalize_or_zero()
    };
    let mut by_edge: BTreeMap<([u32; 3], [u32; 3]), Vec<usize>> = BTreeMap::new();
    for (f, t) in r.indices.chunks_exact(3).enumerate() {
        for k in 0..3 {
            let (a, b) = (r.key(t[k]), r.key(t[(k + 1) % 3]));
            if a != b {
                by_edge.entry((a.min(b), a.max(b))).or_default().push(f);
            }
        }
    }
    let cos_tol = 0.1f32.to_radians().cos();
    for fs in by_edge.values() {
        for w in fs.windows(2) {
            if normal(w[0]).dot(normal(w[1])) >= cos_tol {
                let (x, y) = (find(&mut parent, w[0]), find(&mut parent, w[1]));
                parent[x.max(y)] = x.min(y);
            }
        }
    }
    (0..faces).map(|f| find(&mut parent, f)).collect()
}

#[test]
fn edges_without_fur_are_left_out_of_the_fins() {
    // comb-parallel has a gray (length 0) column.
    let dir = scratch("bare");
    let rep = dir.join("r.json");
    let out = bake(
        &fixture("edge/comb-parallel.gltf"),
        &dir,
        &["--report", rep.to_str().unwrap_or_default()],
    );
    let report: Value =
        serde_json::from_slice(&std::fs::read(&rep).expect("report")).expect("json");
    let p = &report["inputs"][0]["primitives"][0];
    let bare = p["bare_edges"].as_u64().expect("bare_edges");
    assert!(bare > 0, "{p}");
    assert_eq!(
        p["fin_edges"].as_u64().map(|f| f + bare),
        p["edges"].as_u64()
    );
    let doc = Document::load(&out).expect("load");
    let comb = accessor::read_vec::<4>(
        &doc,
        doc.attribute(PRIM, "_FUR_COMB")
            .expect("attrs")
            .expect("comb"),
        "_FUR_COMB",
    )
    .expect("comb");
    let m = pelt_io::mesh::read_primitive(&doc, PRIM).expect("prim");
    let fins = doc.read_fins(PRIM).expect("fins").expect("stored");
    // Every stored fin has fur at an end of its edge, in one of its faces.
    let ends = |c: u32| [c, next_corner(c)].map(|k| m.mesh.indices[k as usize]);
    for f in &fins {
        let mut at_ends = ends(f.corner).to_vec();
        if f.second_corner != NO_CORNER {
            at_ends.extend(ends(f.second_corner));
        }
        assert!(
            at_ends.iter().any(|&v| comb[v as usize][3] > 0.0),
            "fin {f:?} has no fur"
        );
    }
}

#[test]
fn topology_can_be_limited_to_groups_or_turned_off() {
    let dir = scratch("modes");
    let input = fixture("edge/hard-torus.gltf");
    for (mode, groups, fins) in [("groups", true, false), ("off", false, false)] {
        let sub = dir.join(mode);
        std::fs::create_dir_all(&sub).expect("dir");
        let out = bake(&input, &sub, &["--topology", mode]);
        let doc = Document::load(&out).expect("load");
        assert_eq!(
            doc.attribute(PRIM, "_NORMAL_GROUP")
                .expect("attrs")
                .is_some(),
            groups,
            "{mode}"
        );
        assert_eq!(doc.read_fins(PRIM).expect("fins").is_some(), fins, "{mode}");
        assert_eq!(
            doc.fur_primitive(PRIM).expect("PELT_fur").is_some(),
            groups,
            "{mode}"
        );
    }
}

#[test]
fn topology_output_is_identical_at_any_thread_count() {
    let dir = scratch("threads");
    for input in [
        "fixtures/edge/hard-torus.gltf",
        "fixtures/creature.glb",
        "fixtures/edge/flat-cube.gltf",
    ] {
        let mut outs = Vec::new();
        for threads in ["1", "2", "8"] {
            let o = dir.join(format!("t{threads}.glb"));
            let r = pelt(
                &["bake", "-q", input, "-o", o.to_str().unwrap_or_default()],
                &[("RAYON_NUM_THREADS", threads)],
            );
            assert!(r.status.success(), "{input}");
            outs.push(std::fs::read(&o).expect("output"));
        }
        assert!(
            outs.iter().all(|o| *o == outs[0]),
            "{input} differs across thread counts"
        );
    }
}

#[test]
fn weld_epsilon_and_normal_tolerance_reach_the_bake() {
    let dir = scratch("flags");
    // Two triangles whose shared edge is 1e-5 apart, normals 0.05° apart.
    let a = 0.05f32.to_radians();
    let tilted = Vec3::new(0.0, a.sin(), a.cos());
    let p = [
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::new(0.0, 1e-5, 0.0),
        Vec3::new(1.0, 1e-5, 0.0),
        Vec3::new(0.5, -1.0, 0.0),
    ];
    let n = [Vec3::Z, Vec3::Z, Vec3::Z, tilted, tilted, tilted];
    let input = write_mesh(&dir, "near", &p, &n, &[0, 1, 2, 3, 5, 4]);
    let groups = |extra: &[&str]| {
        let sub = dir.join(extra.join("_").replace(['-', '.'], ""));
        std::fs::create_dir_all(&sub).expect("dir");
        let info = inspect(&bake(&input, &sub, extra));
        (
            info["normal_groups"].as_u64(),
            info["boundary_edges"].as_u64(),
        )
    };
    assert_eq!(groups(&[]), (Some(2), Some(6)));
    assert_eq!(groups(&["--weld-epsilon", "1e-4"]), (Some(1), Some(4)));
    assert_eq!(
        groups(&["--weld-epsilon", "1e-4", "--normal-tolerance", "0.01"]),
        (Some(2), Some(4))
    );
    let bad = pelt(
        &[
            "bake",
            "-q",
            input.to_str().unwrap_or_default(),
            "-o",
            "x.glb",
            "--normal-tolerance",
            "200",
        ],
        &[],
    );
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("0 to 180"));
}

/// Rewrites the legacy fixture's `extras.pelt` with `edit` and writes it to `to`.
fn with_legacy_extras(to: &Path, edit: impl FnOnce(&mut Value)) {
    let mut doc = Document::load(&fixture("legacy/sphere-extras.glb")).expect("load");
    let pelt = doc.json["meshes"][0]["primitives"][0]["extras"]
        .get_mut("pelt")
        .expect("extras.pelt");
    edit(pelt);
    write_input(&doc, to);
}

#[test]
fn readers_refuse_other_format_versions_and_corners_out_of_range() {
    let dir = scratch("versions");
    let out = bake(&fixture("torus.glb"), &dir, &[]);
    let info = inspect(&out);
    assert!(info["fin_edges"].as_u64().is_some_and(|n| n > 0), "{info}");
    assert_eq!(
        info["primitive"][0]["topology"]["form"], "PELT_fur",
        "{info}"
    );
    // The torus brings its own TANGENT, kept.
    assert_eq!(
        info["primitive"][0]["topology"]["tangents"], "kept",
        "{info}"
    );
    // A legacy version-1 file: refused, naming the version and what to do.
    let v1 = dir.join("v1.glb");
    with_legacy_extras(&v1, |p| p["version"] = 1.into());
    let r = pelt(&["inspect", v1.to_str().unwrap_or_default()], &[]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success());
    assert!(
        err.contains("extras.pelt.version")
            && err.contains("format version 1")
            && err.contains("bake the source again"),
        "{err}"
    );
    // A record whose corner lies past the index list (the index list unchanged, so the
    // records are not stale but corrupt): an error naming the record, no panic.
    let doc = Document::load(&out).expect("load");
    let acc = doc.json["meshes"][0]["primitives"][0]["extensions"]["PELT_fur"]["fins"]["accessor"]
        .as_u64()
        .expect("fins accessor") as usize;
    let view = doc.json["accessors"][acc]["bufferView"]
        .as_u64()
        .expect("view") as usize;
    let mut bad = doc.clone();
    let (offset, buffer) = (
        bad.json["bufferViews"][view]["byteOffset"]
            .as_u64()
            .unwrap_or(0) as usize
            + bad.json["accessors"][acc]["byteOffset"]
                .as_u64()
                .unwrap_or(0) as usize,
        bad.json["bufferViews"][view]["buffer"]
            .as_u64()
            .expect("buffer") as usize,
    );
    bad.buffers[buffer][offset + 8..offset + 12].copy_from_slice(&u32::MAX.to_le_bytes());
    let broken = dir.join("broken.glb");
    write_input(&bad, &broken);
    let r = pelt(&["inspect", broken.to_str().unwrap_or_default()], &[]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success());
    assert!(
        err.contains("extensions.PELT_fur.fins record 1") && err.contains("corners"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}
