//! Topology benchmark (issue 3): welding, edges and normal groups, group IDs and fin edges on
//! the fixture creature at about 10 k, 100 k and 1.3 M triangles. Prints the median of
//! `PELT_BENCH_RUNS` runs (default 7) per stage, and time per million triangles to show the
//! scaling. Run with `cargo bench --bench topology`.

use std::time::Instant;

// The binary's allocator, so allocation costs (page faults) are those of `pelt bake`.
#[global_allocator]
static GLOBAL: pelt_alloc::HugePageAlloc = pelt_alloc::HugePageAlloc;

use pelt_geom::topology::{CornerNormals, TopologyOptions, build};
use pelt_geom::{fins, group_ids};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    pelt_alloc::configure_from_env();
    let runs: usize = std::env::var("PELT_BENCH_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(7);
    println!(
        "threads: {}, runs: {runs} (medians, ms)",
        rayon::current_num_threads()
    );
    println!(
        "{:>10} {:>9} {:>9} {:>9} {:>9} {:>9} {:>12}",
        "triangles", "groups+e", "ids", "fins", "total", "edges", "ms/M tris"
    );
    for (rings, segs) in [(50u32, 100u32), (158, 316), (570, 1140)] {
        let shape = pelt_fixtures::shapes::creature(rings, segs);
        let (p, n, idx) = (&shape.positions, &shape.normals, &shape.indices);
        let tris = idx.len() / 3;
        let (mut tb, mut ti, mut tf, mut tt) = (vec![], vec![], vec![], vec![]);
        let mut edges = 0;
        for _ in 0..runs {
            let t0 = Instant::now();
            let t = build(
                p,
                idx,
                CornerNormals::Vertex(n),
                &TopologyOptions::default(),
            );
            let t1 = Instant::now();
            let ids = group_ids::assign(&t);
            let t2 = Instant::now();
            let f = fins::build(&t, idx, |v| shape.colors[v as usize][3] > 0.0);
            let t3 = Instant::now();
            std::hint::black_box((&ids, &f));
            edges = f.len();
            tb.push((t1 - t0).as_secs_f64() * 1e3);
            ti.push((t2 - t1).as_secs_f64() * 1e3);
            tf.push((t3 - t2).as_secs_f64() * 1e3);
            tt.push((t3 - t0).as_secs_f64() * 1e3);
        }
        let total = median(tt);
        println!(
            "{tris:>10} {:>9.1} {:>9.1} {:>9.1} {total:>9.1} {edges:>9} {:>12.1}",
            median(tb),
            median(ti),
            median(tf),
            total / (tris as f64 / 1e6)
        );
    }
}
