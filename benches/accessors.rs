//! Why pelt-io keeps its own accessor reader for the bake's vertex data: POSITION, NORMAL,
//! TEXCOORD_0 and the indices of the fixture creature at 1.3 M triangles decoded by
//! `pelt_io::accessor` (bounds-checked, decoded in parallel straight into the final vectors)
//! and by the `gltf` crate's typed readers (`Reader::read_positions` and friends, collected),
//! over the same loaded document. Prints the median of 7 runs of each.
//! Run with `cargo bench --bench accessors`.

use std::time::Instant;

use pelt_fixtures::build::{BuildOptions, document};
use pelt_io::{PrimitiveRef, accessor, typed};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn time(f: &mut dyn FnMut()) -> f64 {
    f();
    median(
        (0..7)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect(),
    )
}

#[expect(
    clippy::expect_used,
    reason = "a benchmark binary: failing loudly is the point"
)]
fn main() {
    let shape = pelt_fixtures::shapes::creature(570, 1140);
    let dir = std::env::temp_dir().join(format!("pelt-accessors-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("creature.glb");
    pelt_io::glb::write_glb(&document(&shape, BuildOptions::default()), &path).expect("write");
    let doc = pelt_io::load(&path).expect("load");
    let r = PrimitiveRef {
        mesh: 0,
        primitive: 0,
    };
    let attr = |name: &str| doc.attribute(r, name).expect("attr").expect(name);
    let (pos, nor, uv) = (attr("POSITION"), attr("NORMAL"), attr("TEXCOORD_0"));
    let idx = doc.primitive(r).expect("prim")["indices"]
        .as_u64()
        .expect("indices") as usize;
    let tris = shape.indices.len() / 3;
    let mut pelt = || {
        let p = accessor::read_vec::<3>(&doc, pos, "POSITION").expect("positions");
        let n = accessor::read_vec::<3>(&doc, nor, "NORMAL").expect("normals");
        let t = accessor::read_vec::<2>(&doc, uv, "TEXCOORD_0").expect("uvs");
        let i = accessor::read_indices(&doc, idx, "indices").expect("indices");
        std::hint::black_box((p, n, t, i));
    };
    let g = typed::document(&doc).expect("typed");
    let prim = g
        .meshes()
        .next()
        .and_then(|m| m.primitives().next())
        .expect("primitive");
    let mut gltf = || {
        let reader = prim.reader(typed::buffers(&doc));
        let p: Vec<[f32; 3]> = reader.read_positions().expect("positions").collect();
        let n: Vec<[f32; 3]> = reader.read_normals().expect("normals").collect();
        let t: Vec<[f32; 2]> = reader.read_tex_coords(0).expect("uvs").into_f32().collect();
        let i: Vec<u32> = reader.read_indices().expect("indices").into_u32().collect();
        std::hint::black_box((p, n, t, i));
    };
    let (a, b) = (time(&mut pelt), time(&mut gltf));
    println!("{tris} triangles, {} vertices", shape.positions.len());
    println!("| reader | POSITION + NORMAL + TEXCOORD_0 + indices, ms (median of 7) |");
    println!("|---|---|");
    println!("| pelt_io::accessor | {a:.1} |");
    println!("| gltf Reader (collected) | {b:.1} |");
    std::fs::remove_dir_all(&dir).ok();
}
