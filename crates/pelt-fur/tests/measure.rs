//! Measurements of the generated textures against the strand model: shell coverage against the
//! analytic expectation, seamless tiling, coverage of every mip level, and the fin texture
//! against the heightfield. `cargo test -p pelt-fur --test measure -- --nocapture` prints the
//! measured errors.

use pelt_fur::expect;
use pelt_fur::fin::side_view;
use pelt_fur::mips::{Groups, box_chain, coverage_chain, level_size};
use pelt_fur::raster::top_view;
use pelt_fur::set::{coverage_code, fraction_above, height_threshold};
use pelt_fur::strands::{Strand, generate as strands};
use pelt_fur::{StrandParams, generate};

/// Fraction of the subsamples of `masks` that are covered.
fn mask_coverage(masks: &[u16]) -> f64 {
    masks.iter().map(|m| f64::from(m.count_ones())).sum::<f64>() / (16.0 * masks.len() as f64)
}

fn configs() -> Vec<(&'static str, StrandParams)> {
    vec![
        (
            "fine, uniform heights",
            StrandParams {
                size: 1024,
                strands: 60_000,
                radius: 0.0012,
                radius_jitter: 0.3,
                height_min: 0.2,
                height_max: 1.0,
                ..StrandParams::default()
            },
        ),
        (
            "short-biased, leaning",
            StrandParams {
                seed: 11,
                size: 1024,
                strands: 40_000,
                radius: 0.0015,
                radius_jitter: 0.5,
                height_min: 0.1,
                height_max: 0.9,
                height_bias: 2.5,
                tilt: 4.0,
                ..StrandParams::default()
            },
        ),
        (
            "coarse, tall-biased",
            StrandParams {
                seed: 5,
                size: 1024,
                strands: 8_000,
                radius: 0.003,
                radius_jitter: 0.2,
                height_min: 0.0,
                height_max: 1.0,
                height_bias: 0.5,
                tilt: 1.0,
                ..StrandParams::default()
            },
        ),
    ]
}

#[test]
fn shell_and_dot_coverage_match_the_model_within_2_percent() {
    let mut worst: f64 = 0.0;
    for (name, p) in configs() {
        let set = generate(&p).expect("valid");
        for h in [0.0, 0.1, 0.3, 0.5, 0.7] {
            let want = expect::shell_coverage(&p, h);
            let got = fraction_above(&set.top.height, height_threshold(h));
            let err = (got / want - 1.0).abs();
            println!(
                "{name}: shell {h:.1}: measured {got:.5} model {want:.5} ({:+.2} %)",
                (got / want - 1.0) * 100.0
            );
            assert!(want > 0.02, "{name}: the check needs coverage, got {want}");
            assert!(
                err <= 0.02,
                "{name}: shell at {h}: measured {got}, model {want}"
            );
            worst = worst.max(err);
        }
        // Dot texture: mean alpha, exactly from the subsample masks and from the 8-bit image.
        let want = expect::dot_coverage(&p);
        let masks = mask_coverage(&set.top.mask);
        let pelt_fur::Pixels::Gray8(dots) = &set.dots[0].pixels else {
            panic!("dots are 8-bit")
        };
        let image = dots.iter().map(|&v| f64::from(v)).sum::<f64>() / (255.0 * dots.len() as f64);
        println!("{name}: dots: masks {masks:.5} image {image:.5} model {want:.5}");
        for got in [masks, image] {
            assert!(
                (got / want - 1.0).abs() <= 0.02,
                "{name}: dots {got} vs {want}"
            );
            worst = worst.max((got / want - 1.0).abs());
        }
    }
    println!("worst relative error: {:.2} %", worst * 100.0);
}

/// Strands with positions on a 2^-20 grid, so that shifting by whole texels is exact.
fn dyadic(p: &StrandParams) -> Vec<Strand> {
    let q = |v: f64| (v * f64::from(1u32 << 20)).floor() / f64::from(1u32 << 20);
    strands(p)
        .into_iter()
        .map(|s| Strand {
            x: q(s.x),
            y: q(s.y),
            ..s
        })
        .collect()
}

#[test]
fn textures_tile_seamlessly() {
    // Moving every strand by (dx, dy) texels on the torus must roll the textures by exactly
    // that: a strand cut by a border continues on the other side, texel for texel.
    let p = StrandParams {
        size: 256,
        strands: 3000,
        radius: 0.006,
        tilt: 3.0,
        fin_depth: 0.05,
        ..StrandParams::default()
    };
    let n = p.size as usize;
    let base = dyadic(&p);
    let (dx, dy) = (101usize, 37usize);
    let shifted: Vec<Strand> = base
        .iter()
        .map(|s| Strand {
            x: pelt_fur::strands::wrap_unit(s.x + dx as f64 / n as f64),
            y: pelt_fur::strands::wrap_unit(s.y + dy as f64 / n as f64),
            ..*s
        })
        .collect();
    let a = top_view(&base, n);
    let b = top_view(&shifted, n);
    let crossing = base
        .iter()
        .filter(|s| {
            let r = s.r + s.tx.abs().max(s.ty.abs());
            s.x < r || s.x > 1.0 - r || s.y < r || s.y > 1.0 - r
        })
        .count();
    assert!(crossing > 50, "only {crossing} strands cross a border");
    for y in 0..n {
        for x in 0..n {
            let i = y * n + x;
            let j = ((y + dy) % n) * n + (x + dx) % n;
            assert_eq!(a.mask[i], b.mask[j], "mask at ({x}, {y})");
            assert_eq!(a.height[i], b.height[j], "height at ({x}, {y})");
        }
    }
    // The fin texture wraps along its width the same way (roots kept in the slab).
    let rows = 64;
    let shifted_x: Vec<Strand> = base
        .iter()
        .map(|s| Strand {
            x: pelt_fur::strands::wrap_unit(s.x + dx as f64 / n as f64),
            ..*s
        })
        .collect();
    let fa = side_view(&base, p.fin_depth, n, rows);
    let fb = side_view(&shifted_x, p.fin_depth, n, rows);
    for y in 0..rows {
        for x in 0..n {
            assert_eq!(
                fa.mask[y * n + x],
                fb.mask[y * n + (x + dx) % n],
                "fin at ({x}, {y})"
            );
        }
    }
    // And the seam is no different from any other texel boundary: the mean difference across
    // the border matches the mean difference between neighbouring interior columns.
    let height = &a.height;
    let diff = |x0: usize, x1: usize| {
        (0..n)
            .map(|y| (f64::from(height[y * n + x0]) - f64::from(height[y * n + x1])).abs())
            .sum::<f64>()
    };
    let seam = diff(n - 1, 0);
    let interior = (0..n - 1).map(|x| diff(x, x + 1)).sum::<f64>() / (n - 1) as f64;
    assert!(seam < 1.5 * interior, "seam {seam} vs interior {interior}");
}

fn mean(v: &[u16]) -> f64 {
    v.iter().map(|&x| f64::from(x)).sum::<f64>() / v.len() as f64
}

#[test]
fn every_mip_level_keeps_coverage_within_2_percent() {
    let p = StrandParams {
        size: 1024,
        tilt: 2.0,
        clumps: 300,
        clumping: 0.4,
        ..StrandParams::default()
    };
    let set = generate(&p).expect("valid");
    let n = p.size as usize;
    let chain = coverage_chain(&set.top.height, n, n, Groups::Whole);
    assert_eq!(chain.len(), 10);
    let mut worst: f64 = 0.0;
    for (l, level) in chain.iter().enumerate() {
        let texels = level.len() as f64;
        for h in [0.0, 0.25, 0.5, 0.75, 0.9] {
            let t = height_threshold(h);
            let want = fraction_above(&set.top.height, t);
            let got = fraction_above(level, t);
            // A level of n texels can only show coverage in steps of 1/n.
            let bound = (0.02 * want).max(1.0 / texels);
            assert!(
                (got - want).abs() <= bound,
                "level {}: height {h}: {got} vs {want}",
                l + 1
            );
            if texels >= 1024.0 {
                worst = worst.max((got / want - 1.0).abs());
            }
        }
        let m = mean(level) / mean(&set.top.height);
        assert!((m - 1.0).abs() < 0.02, "level {}: mean ratio {m}", l + 1);
    }
    println!(
        "heightfield mips: worst relative coverage error (levels ≥ 32²): {:.3} %",
        worst * 100.0
    );
    // A box filter (what a GPU's mipmap generation does) thins the fur: at level 3 it keeps
    // far less of the coverage above half height.
    let boxed = box_chain(&set.top.height, n, n);
    let t = height_threshold(0.5);
    let kept = fraction_above(&boxed[2], t) / fraction_above(&set.top.height, t);
    println!(
        "box-filtered level 3 keeps {:.1} % of the coverage above height 0.5",
        kept * 100.0
    );
    assert!(kept < 0.7, "box filter kept {kept}");

    // Dots: mean alpha (blended coverage) at every level, and alpha-test coverage at 0.5.
    let dots0: Vec<u16> = set.top.mask.iter().map(|&m| coverage_code(m)).collect();
    let dchain = coverage_chain(&dots0, n, n, Groups::Whole);
    for (l, level) in dchain.iter().enumerate() {
        let m = mean(level) / mean(&dots0);
        assert!(
            (m - 1.0).abs() < 0.02,
            "dots level {}: mean ratio {m}",
            l + 1
        );
        let want = fraction_above(&dots0, 32767);
        let got = fraction_above(level, 32767);
        assert!(
            (got - want).abs() <= (0.02 * want).max(1.0 / level.len() as f64),
            "dots level {}",
            l + 1
        );
    }

    // Fin texture: each row band keeps its coverage (the height profile survives).
    let rows = p.fin_rows() as usize;
    let a0: Vec<u16> = set.side.mask.iter().map(|&m| coverage_code(m)).collect();
    let fchain = coverage_chain(&a0, n, rows, Groups::Rows);
    for (l, level) in fchain.iter().enumerate() {
        let (lw, lh) = level_size(n, rows, l + 1);
        let s = rows / lh;
        for j in 0..lh {
            let want = mean(&a0[j * s * n..(j + 1) * s * n]);
            let got = mean(&level[j * lw..(j + 1) * lw]);
            assert!(
                (got - want).abs() <= 0.02 * want + 1.0,
                "fin level {} row {j}: {got} vs {want}",
                l + 1
            );
        }
    }
}

/// Exact covered length of row height z in the side view, from the strands themselves.
fn slab_union(strands: &[Strand], depth: f64, z: f64) -> f64 {
    let mut spans: Vec<(f64, f64)> = Vec::new();
    for s in strands.iter().filter(|s| s.y < depth && s.h >= z) {
        let c = s.x + s.tx * z;
        let (lo, hi) = (c - s.r, c + s.r);
        for o in [-1.0, 0.0, 1.0] {
            let (a, b) = ((lo + o).max(0.0), (hi + o).min(1.0));
            if b > a {
                spans.push((a, b));
            }
        }
    }
    spans.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut total, mut end) = (0.0, 0.0f64);
    for (a, b) in spans {
        if b > end {
            total += b - a.max(end);
            end = b;
        }
    }
    total
}

#[test]
fn the_fin_texture_shows_the_heightfields_strands() {
    let p = StrandParams {
        size: 1024,
        strands: 20_000,
        radius: 0.0015,
        fin_height: 256,
        fin_depth: 0.02,
        ..StrandParams::default()
    };
    let set = generate(&p).expect("valid");
    let (n, rows) = (p.size as usize, 256usize);
    // 1. Row by row, the fin's coverage is the union of the slab strands taller than the row
    //    (averaged over the row's four subsample heights).
    let mut worst: f64 = 0.0;
    for k in 0..rows {
        let want = [0.125, 0.375, 0.625, 0.875]
            .iter()
            .map(|o| slab_union(&set.strands, p.fin_depth, (k as f64 + o) / rows as f64))
            .sum::<f64>()
            / 4.0;
        let row = rows - 1 - k;
        let got = mask_coverage(&set.side.mask[row * n..(row + 1) * n]);
        if want > 0.05 {
            worst = worst.max((got / want - 1.0).abs());
            assert!((got / want - 1.0).abs() <= 0.02, "row {k}: {got} vs {want}");
        } else {
            assert!((got - want).abs() <= 0.002, "row {k}: {got} vs {want}");
        }
    }
    println!(
        "fin rows vs slab strands: worst relative error {:.2} %",
        worst * 100.0
    );

    // 2. Strand by strand: where no taller slab strand stands in front of or behind a slab
    //    strand, its top in the fin texture is the height the heightfield holds at its root.
    let slab: Vec<&Strand> = set.strands.iter().filter(|s| s.y < p.fin_depth).collect();
    let mut checked = 0;
    for s in &slab {
        let alone = slab.iter().all(|o| {
            std::ptr::eq(*o, *s) || o.h < s.h - 1.0 / rows as f64 || {
                let d = (o.x - s.x).abs();
                d.min(1.0 - d) > o.r + s.r + 2.0 / n as f64
            }
        });
        let (cx, cy) = ((s.x * n as f64) as usize, (s.y * n as f64) as usize);
        let hf = set.top.height[cy * n + cx];
        let code = (s.h * 65535.0).round() as u16;
        if !alone || hf != code {
            continue; // hidden by a neighbour in one of the views
        }
        let top = (0..rows)
            .find(|&row| set.side.mask[row * n + cx] != 0)
            .expect("strand visible");
        let fin_height = (rows - top) as f64 / rows as f64; // top of the highest covered row
        assert!(
            (fin_height - s.h).abs() <= 1.0 / rows as f64,
            "strand at x {}: fin {fin_height} heightfield {}",
            s.x,
            f64::from(hf) / 65535.0
        );
        checked += 1;
    }
    println!(
        "{checked} of {} slab strands checked one by one",
        slab.len()
    );
    assert!(checked >= 75, "only {checked} strands stood alone");

    // 3. The profiles agree: the fraction of strands taller than z implied by the fin
    //    texture's coverage matches the one implied by the heightfield's, and the model's.
    let r2 = p.radius * p.radius * (1.0 + p.radius_jitter * p.radius_jitter / 3.0);
    let strands_n = f64::from(p.strands);
    for z in [0.5, 0.6, 0.7, 0.8] {
        let hf = expect::implied_taller(
            fraction_above(&set.top.height, height_threshold(z)),
            strands_n,
            std::f64::consts::PI * r2,
        );
        let row = rows - 1 - (z * rows as f64) as usize;
        let cov = mask_coverage(&set.side.mask[row * n..(row + 1) * n]);
        let fin = expect::implied_taller(cov, strands_n, p.fin_depth * 2.0 * p.radius);
        let model = expect::taller(&p, z);
        println!("taller than {z}: heightfield {hf:.3} fin {fin:.3} model {model:.3}");
        assert!(
            (hf - model).abs() <= 0.02 * model.max(0.25),
            "heightfield {hf} vs {model}"
        );
        // The slab holds about 400 strands: its own sampling noise is a few percent.
        assert!(
            (fin - model).abs() <= 0.1 * model.max(0.25),
            "fin {fin} vs {model}"
        );
    }
}

#[test]
fn same_seed_gives_identical_pngs_at_any_thread_count() {
    let p = StrandParams {
        size: 256,
        tilt: 2.0,
        clumps: 50,
        clumping: 0.5,
        ..StrandParams::default()
    };
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| generate(&p).expect("valid").encode().expect("png"))
    };
    let one = run(1);
    assert_eq!(one.len(), 3 * 9);
    for threads in [2, 3, 8] {
        assert!(one == run(threads), "{threads} threads");
    }
    let other = generate(&StrandParams {
        seed: 2,
        ..p.clone()
    })
    .expect("valid")
    .encode()
    .expect("png");
    assert_ne!(one[0], other[0]);
}
