//! The L-buffer scale knob measured: frame time and FLIP error against the full-resolution
//! deferred render, with DSF on and off, on the inferred-lighting paper's second scene
//! (122 lights, 1280 × 720; Kircher & Lawrance §6, Figure 9). `PELT_BACKEND` picks the back
//! end. Run: `cargo bench -p pelt-preview --bench lbuffer_scale`.

use std::path::Path;

use pelt_preview::procedural::paper_lbuffer_scale;
use pelt_preview::{Backend, Image, Mode, Preview, Scene};

fn flip(reference: &Image, test: &Image) -> f32 {
    pelt_measure::Flip::new(reference, test)
        .expect("images of one size")
        .mean()
}

#[expect(
    clippy::expect_used,
    reason = "a benchmark binary: failing loudly is the point"
)]
fn main() {
    let backend: Backend = std::env::var("PELT_BACKEND")
        .ok()
        .and_then(|b| b.parse().ok())
        .unwrap_or_default();
    let mut p = Preview::new(backend).expect("adapter");
    println!("adapter: {}", p.adapter());
    let base = paper_lbuffer_scale(Path::new("builtin:sphere"));
    let full = Scene {
        lbuffer_scale: 1.0,
        dsf: false,
        ..base.clone()
    };
    let d = p.prepare(&full, Mode::Deferred).expect("prepare");
    let reference = p.render(&d).expect("render");
    let t_ref = p.time(&d, 2, 7).expect("time").frame_ms;
    println!(
        "| L-buffer scale | L-buffer | DSF | frame ms (median of 7) | FLIP mean vs deferred 1.0 |"
    );
    println!("|---|---|---|---|---|");
    println!("| 1.0 (deferred) | 1280×720 | off | {t_ref:.1} | 0 |");
    for scale in [0.25_f32, 0.375, 0.5, 0.625, 0.75, 1.0] {
        for dsf in [true, false] {
            let s = Scene {
                lbuffer_scale: scale,
                dsf,
                ..base.clone()
            };
            let d = p.prepare(&s, Mode::Inferred).expect("prepare");
            let img = p.render(&d).expect("render");
            let t = p.time(&d, 2, 7).expect("time").frame_ms;
            let (w, h) = s.lbuffer_size();
            println!(
                "| {scale} | {w}×{h} | {} | {t:.1} | {:.4} |",
                if dsf { "on" } else { "off" },
                flip(&reference, &img)
            );
        }
    }
}
