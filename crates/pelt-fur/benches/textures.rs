//! Texture-set benchmark: a full set (strands, heightfield, dots, fin texture, all mip chains,
//! PNG encoding) at 512², 1024² and 2048² with the default strand model, median of 7 runs
//! after one warm-up. `cargo bench -p pelt-fur --bench textures`.

use std::time::Instant;

use pelt_fur::{StrandParams, generate};

fn main() {
    let runs = 7;
    println!("threads: {}", rayon::current_num_threads());
    println!("| size | strands | generate (ms) | PNG encode (ms) | total (ms) | PNG bytes |");
    println!("|---|---|---|---|---|---|");
    for size in [512u32, 1024, 2048] {
        // Same strands per tile area at every size: the default density scaled from 1024².
        let p = StrandParams {
            size,
            ..StrandParams::default()
        };
        let mut gen_ms = Vec::new();
        let mut enc_ms = Vec::new();
        let mut bytes = 0;
        for run in 0..=runs {
            let t0 = Instant::now();
            let set = generate(&p).expect("valid parameters");
            let t1 = Instant::now();
            let pngs = set.encode().expect("encodes");
            let t2 = Instant::now();
            bytes = pngs.iter().map(Vec::len).sum::<usize>();
            if run > 0 {
                gen_ms.push((t1 - t0).as_secs_f64() * 1e3);
                enc_ms.push((t2 - t1).as_secs_f64() * 1e3);
            }
        }
        let total: Vec<f64> = gen_ms.iter().zip(&enc_ms).map(|(a, b)| a + b).collect();
        println!(
            "| {size}² | {} | {:.0} | {:.0} | {:.0} | {} |",
            p.strands,
            median(gen_ms),
            median(enc_ms),
            median(total),
            bytes
        );
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}
