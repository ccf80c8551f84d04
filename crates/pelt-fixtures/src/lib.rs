//! Deterministic generator of vertex-painted meshes with known comb fields, for pelt's tests,
//! fixtures and benchmarks. Every shape is parametric (analytic positions and normals), so the
//! same parameters give byte-identical files on any machine.
//!
//! - [`shapes`]: UV sphere, torus and a blobby creature (body, head, legs, tail), at any
//!   resolution; the creature at 570×1140 is the ~1.3 M-triangle benchmark mesh.
//! - [`comb_field`]: the known comb painted on them, so tests can check the bake against it.
//! - [`edge`]: the small hand-specified edge cases (mirrored UVs, degenerate triangles, comb
//!   along the normal, missing normals, VEC3 u8 colors, sparse colors, non-triangle modes, OBJ).
//! - [`obj`]: OBJ files with materials, textures and the encodings peers read.
//! - [`build`]: turning shapes into glTF documents.
//! - [`bad`]: the bad-input corpus (`fixtures/bad/`): a valid quad broken one way per file.
//! - [`mutate`]: seeded mutations (bit flips, truncations, splices, JSON number edits) for the
//!   fuzz harness.

pub mod bad;
pub mod build;
pub mod comb;
pub mod edge;
pub mod mutate;
pub mod obj;
pub mod shapes;
pub mod skinned;

pub use comb::{comb_field, paint};

/// Writes the committed fixture set into `out`: sphere.glb, torus.glb, creature.glb and
/// edge/*.gltf and obj/*.
pub fn write_all(out: &std::path::Path) -> Result<(), pelt_io::IoError> {
    use build::{BuildOptions, ColorEncoding, document};
    use pelt_io::glb::{write_glb, write_gltf_embedded};
    let mkdir = |p: &std::path::Path| {
        std::fs::create_dir_all(p).map_err(|source| pelt_io::IoError::Fs {
            path: p.to_owned(),
            action: "create",
            source,
        })
    };
    mkdir(&out.join("edge"))?;
    let u8x4 = BuildOptions {
        colors: ColorEncoding::U8x4,
        ..BuildOptions::default()
    };
    for (name, shape, opts) in [
        ("sphere", shapes::sphere(24, 48), BuildOptions::default()),
        (
            "torus",
            shapes::torus(24, 48),
            BuildOptions {
                tangents: true,
                ..BuildOptions::default()
            },
        ),
        ("creature", shapes::creature(64, 128), u8x4),
    ] {
        write_glb(&document(&shape, opts), &out.join(format!("{name}.glb")))?;
    }
    for (name, doc) in edge::all() {
        write_gltf_embedded(&doc, &out.join("edge").join(format!("{name}.gltf")))?;
    }
    let objs = out.join("obj");
    obj::write(&objs).map_err(|source| pelt_io::IoError::Fs {
        path: objs,
        action: "write",
        source,
    })?;
    Ok(())
}

/// Writes the ~1.3 M-triangle benchmark creature (570 × 1140 grid, float colors) twice into
/// `dir`: `creature-1m3.glb` with MikkTSpace tangents and one bufferView per attribute, as
/// Blender's exporter lays it out (about 58 MB), and `creature-1m3-notan.glb` without
/// tangents, interleaved in one bufferView as gltfpack and glTF-Transform write (about 48 MB).
pub fn write_big(dir: &std::path::Path) -> Result<(), pelt_io::IoError> {
    write_creature(dir, 570, 1140)
}

/// Writes the benchmark creature at `rings` × `segments` (about 2 × rings × segments
/// triangles) into `dir`, as [`write_big`] does, named `creature-{triangles}.glb` and
/// `creature-{triangles}-notan.glb` (the 1.3 M one keeps its historical name `creature-1m3`).
pub fn write_creature(
    dir: &std::path::Path,
    rings: u32,
    segments: u32,
) -> Result<(), pelt_io::IoError> {
    let shape = shapes::creature(rings, segments);
    let name = if (rings, segments) == (570, 1140) {
        "creature-1m3".to_owned()
    } else {
        format!("creature-{}", shape.indices.len() / 3)
    };
    let with = build::BuildOptions {
        tangents: true,
        ..build::BuildOptions::default()
    };
    let doc = build::document_laid_out(&shape, with, build::Layout::Separate);
    pelt_io::glb::write_glb(&doc, &dir.join(format!("{name}.glb")))?;
    let without = build::BuildOptions::default();
    let doc = build::document_laid_out(&shape, without, build::Layout::Interleaved);
    pelt_io::glb::write_glb(&doc, &dir.join(format!("{name}-notan.glb")))?;
    Ok(())
}
