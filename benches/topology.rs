//! Topology benchmark (issue 3): welding, edges and normal groups, group IDs and fin edges on
//! the fixture creature at about 10 k, 100 k and 1.3 M triangles, with the allocator `pelt`
//! uses. Every run is a fresh process, so first-touch memory costs (page faults, zeroing) count
//! as they do in a real bake. Prints the median of `PELT_BENCH_RUNS` runs (default 7) per
//! stage and the time per million triangles, to show the scaling.
//! Run with `cargo bench --bench topology`.

use std::process::Command;
use std::time::Instant;

use pelt_geom::topology::{CornerNormals, TopologyOptions, build};
use pelt_geom::{fins, group_ids};

#[global_allocator]
static GLOBAL: pelt_alloc::HugePageAlloc = pelt_alloc::HugePageAlloc;

const SIZES: [(u32, u32); 3] = [(50, 100), (158, 316), (570, 1140)];

/// One measurement in this process: prints triangles, edges and the stage times in ms.
fn measure(rings: u32, segs: u32) {
    let shape = pelt_fixtures::shapes::creature(rings, segs);
    let (p, n, idx) = (&shape.positions, &shape.normals, &shape.indices);
    let t0 = Instant::now();
    let mut t = build(
        p,
        idx,
        CornerNormals::Vertex(n),
        &TopologyOptions::default(),
    );
    let t1 = Instant::now();
    let ids = group_ids::assign(&t);
    let t2 = Instant::now();
    let lengths: Vec<f32> = shape.colors.iter().map(|c| c[3]).collect();
    let f = fins::build(t.take_edges(), idx, fins::Fur::Lengths(&lengths));
    let t3 = Instant::now();
    std::hint::black_box((&ids, &f));
    let ms = |a: Instant, b: Instant| (b - a).as_secs_f64() * 1e3;
    println!(
        "{} {} {} {} {} {}",
        idx.len() / 3,
        f.len(),
        ms(t0, t1),
        ms(t1, t2),
        ms(t2, t3),
        ms(t0, t3)
    );
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    pelt_alloc::configure_from_env();
    if let Ok(size) = std::env::var("PELT_BENCH_CHILD") {
        let (rings, segs) = SIZES[size.parse::<usize>().unwrap_or(0).min(2)];
        measure(rings, segs);
        return;
    }
    let runs: usize = std::env::var("PELT_BENCH_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(7);
    let exe = std::env::current_exe().unwrap_or_default();
    println!(
        "threads: {}, runs: {runs}, fresh process each (medians, ms)",
        rayon::current_num_threads()
    );
    println!(
        "{:>10} {:>9} {:>9} {:>9} {:>9} {:>12}",
        "triangles", "fin edges", "groups+e", "ids", "fins", "total"
    );
    for size in 0..SIZES.len() {
        let mut rows: Vec<Vec<f64>> = Vec::new();
        for _ in 0..runs {
            let out = Command::new(&exe)
                .env("PELT_BENCH_CHILD", size.to_string())
                .output()
                .unwrap_or_else(|e| panic!("run {}: {e}", exe.display()));
            let text = String::from_utf8_lossy(&out.stdout);
            rows.push(
                text.split_whitespace()
                    .filter_map(|w| w.parse().ok())
                    .collect(),
            );
        }
        let col = |k: usize| median(rows.iter().filter_map(|r| r.get(k).copied()).collect());
        let (tris, total) = (col(0), col(5));
        println!(
            "{:>10} {:>9} {:>9.1} {:>9.1} {:>9.1} {:>9.1} ({:.0} ms per M triangles)",
            tris,
            col(1),
            col(2),
            col(3),
            col(4),
            total,
            total / (tris / 1e6)
        );
    }
}
