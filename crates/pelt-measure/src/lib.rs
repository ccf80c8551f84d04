//! Measuring pelt's trade of speed for accuracy: the FLIP error (Andersson et al., the
//! image difference wgpu's own tests use) of an image against a reference, over the whole
//! image or over a mask, with its heat map ([`flip`]); and the experiments that set a
//! renderer's knobs against a converged reference and time them ([`reflections`]: mirrors
//! and glass from distance maps against the CPU ray tracer; [`sweep`]: every knob against
//! its reference, `pelt sweep`). [`strands`] accumulates the converged strand reference of
//! the fur; [`luminance`] compares the fur's brightness with it. [`demo_creature`] makes the
//! painted asset the fur experiments draw, [`demo`] runs `pelt demo`, and [`render_bench`]
//! times the papers' experiments as [`table::Table`]s ([`bench_run`]: `pelt render-bench`'s
//! choice of them, run as one call).

pub mod bench_run;
pub mod demo;
pub mod demo_creature;
pub mod flip;
pub mod luminance;
pub mod reflections;
pub mod render_bench;
pub mod strands;
pub mod sweep;
pub mod table;

pub use flip::Flip;
