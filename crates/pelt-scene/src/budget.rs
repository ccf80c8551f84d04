//! The frame budget of `pelt view`: while the camera moves, hold a target frame time by
//! lowering the L-buffer scale and the shell count, whichever the measured pass costs say
//! saves more first, and the render resolution last; when the camera stops, draw at full
//! quality.
//!
//! The cost model is fitted to recorded pass times of the full-quality frame ([`Costs`]):
//! the passes at L-buffer resolution (geometry, light, obliteration) scale with the L-buffer's
//! pixel count, (scale × render scale)²; the output-resolution passes with the render
//! scale²; and the part of them that draws fur shells also with the shell count (measured as
//! the difference between a frame at full shells and one at a single shell). What the model
//! leaves out (vertex work that does not shrink with resolution, the upscale, presenting) is
//! learned from the moving frames themselves: predictions are scaled by the running ratio of
//! measured to predicted time ([`Budget::observe`]).

/// The knobs the budget turns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quality {
    /// L-buffer scale (0.1 to 1).
    pub lbuffer_scale: f32,
    /// Shells per fur object.
    pub shells: u32,
    /// Render resolution as a fraction of the window's (output passes run at it; the image
    /// is scaled up to the window).
    pub render_scale: f32,
}

/// Lowest values the budget goes to.
pub const FLOOR: Quality = Quality {
    lbuffer_scale: 0.25,
    shells: 2,
    render_scale: 0.35,
};

/// Factor of one step down in L-buffer scale or render scale; shells halve.
pub const STEP: f32 = 0.8;

/// Recorded costs of the full-quality frame, milliseconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Costs {
    /// The quality they were measured at.
    pub full: Quality,
    /// Passes at L-buffer resolution.
    pub lbuffer_ms: f64,
    /// Output-resolution passes, without the shells.
    pub output_ms: f64,
    /// Each shell at output resolution.
    pub per_shell_ms: f64,
}

impl Costs {
    /// Fits the model to two recorded frames at the same resolution: pass times at full
    /// quality (`full_passes`: L-buffer-resolution passes, output passes) and the output
    /// passes' time with a single shell.
    pub fn fit(full: Quality, lbuffer_ms: f64, output_ms: f64, output_one_shell_ms: f64) -> Costs {
        let extra = full.shells.saturating_sub(1).max(1) as f64;
        let per_shell = ((output_ms - output_one_shell_ms) / extra).max(0.0);
        Costs {
            full,
            lbuffer_ms,
            output_ms: (output_ms - per_shell * full.shells as f64).max(0.0),
            per_shell_ms: per_shell,
        }
    }

    /// Predicted frame time at `q`.
    pub fn predict(&self, q: &Quality) -> f64 {
        let f = &self.full;
        let r = f64::from(q.render_scale / f.render_scale).powi(2);
        let l = f64::from(q.lbuffer_scale / f.lbuffer_scale).powi(2);
        self.lbuffer_ms * l * r + (self.output_ms + self.per_shell_ms * f64::from(q.shells)) * r
    }
}

/// One step down of each knob, where it has room (None at its floor).
fn steps(q: &Quality, full: &Quality) -> [Option<Quality>; 3] {
    let floor = |v: f32, lo: f32| (v * STEP).max(lo.min(v));
    let l = floor(q.lbuffer_scale, FLOOR.lbuffer_scale);
    let s = (q.shells / 2).max(FLOOR.shells.min(full.shells));
    let r = floor(q.render_scale, FLOOR.render_scale);
    [
        (l < q.lbuffer_scale).then_some(Quality {
            lbuffer_scale: l,
            ..*q
        }),
        (s < q.shells).then_some(Quality { shells: s, ..*q }),
        (r < q.render_scale).then_some(Quality {
            render_scale: r,
            ..*q
        }),
    ]
}

/// The frame budget.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    /// Target frame time while the camera moves, milliseconds.
    pub target_ms: f64,
    /// The costs it predicts with.
    pub costs: Costs,
    /// Measured over predicted frame time of the moving frames so far (what the pass model
    /// leaves out: vertex work that does not shrink with resolution, the upscale, presenting),
    /// an exponential average; 1 until a frame is observed.
    pub correction: f64,
}

/// Weight of the newest frame in [`Budget::correction`].
const CORRECTION_WEIGHT: f64 = 0.4;

impl Budget {
    /// A budget of `target_ms` with `costs`, before any frame is observed.
    pub fn new(target_ms: f64, costs: Costs) -> Budget {
        Budget {
            target_ms,
            costs,
            correction: 1.0,
        }
    }

    /// Predicted frame time at `q`, corrected by what frames took.
    pub fn predict(&self, q: &Quality) -> f64 {
        self.costs.predict(q) * self.correction
    }

    /// A frame drawn at `q` took `ms`: the correction moves towards measured / predicted
    /// (kept within 0.5 to 4, so one outlier cannot throw the budget off).
    pub fn observe(&mut self, q: &Quality, ms: f64) {
        let model = self.costs.predict(q);
        if !(model > 0.0 && ms.is_finite() && ms > 0.0) {
            return;
        }
        let ratio = (ms / model).clamp(0.5, 4.0);
        self.correction = (1.0 - CORRECTION_WEIGHT) * self.correction + CORRECTION_WEIGHT * ratio;
    }
}

impl Budget {
    /// The quality to draw at: full when the camera is still; while it moves, the full
    /// quality lowered one step at a time until the prediction fits the target. Each step
    /// lowers whichever of the L-buffer scale and the shell count saves more predicted time
    /// (the measured costs decide); the render resolution, which blurs everything, goes down
    /// only once both are at their floors.
    pub fn choose(&self, moving: bool) -> Quality {
        let full = self.costs.full;
        let mut q = full;
        if !moving {
            return q;
        }
        while self.predict(&q) > self.target_ms {
            let now = self.predict(&q);
            let [lbuffer, shells, render] = steps(&q, &full);
            let best = [lbuffer, shells]
                .into_iter()
                .flatten()
                .map(|s| (now - self.predict(&s), s))
                .filter(|(saved, _)| *saved > 0.0)
                .max_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, s)| s)
                .or(render);
            match best {
                Some(s) => q = s,
                None => break,
            }
        }
        q
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FULL: Quality = Quality {
        lbuffer_scale: 0.625,
        shells: 16,
        render_scale: 1.0,
    };

    /// Pass times recorded for the demo scene at 1280×720 (16 shells) on this project's
    /// 2-core CPU machine: L-buffer passes 120 ms, output passes 420 ms, 80 ms with 1 shell.
    fn demo() -> Costs {
        Costs::fit(FULL, 120.0, 420.0, 80.0)
    }

    #[test]
    fn the_model_reproduces_what_it_was_fitted_to() {
        let c = demo();
        assert!((c.predict(&FULL) - 540.0).abs() < 1e-9);
        let one = Quality { shells: 1, ..FULL };
        assert!((c.predict(&one) - (120.0 + 80.0)).abs() < 1e-9);
        // Halving the render scale quarters everything.
        let half = Quality {
            render_scale: 0.5,
            ..FULL
        };
        assert!((c.predict(&half) - 135.0).abs() < 1e-9);
    }

    #[test]
    fn a_moving_camera_gets_settings_that_fit_and_a_still_one_full_quality() {
        let c = demo();
        for target in [66.0, 100.0, 200.0, 400.0] {
            let b = Budget::new(target, c);
            let q = b.choose(true);
            assert!(
                c.predict(&q) <= target,
                "{target}: {q:?} predicts {}",
                c.predict(&q)
            );
            assert_eq!(b.choose(false), FULL);
        }
        // A budget the full frame meets changes nothing.
        let easy = Budget::new(1000.0, c);
        assert_eq!(easy.choose(true), FULL);
    }

    #[test]
    fn the_knob_that_saves_most_goes_first() {
        // Shells dominate: the first step halves them.
        let b = Budget::new(500.0, demo());
        assert_eq!(b.choose(true), Quality { shells: 8, ..FULL });
        // Resolution goes last: with a budget the other two cannot reach, both are at their
        // floors before it moves.
        let b = Budget::new(100.0, demo());
        let q = b.choose(true);
        assert!(q.render_scale < 1.0, "{q:?}");
        assert_eq!(q.shells, FLOOR.shells);
        assert!(
            (q.lbuffer_scale - FLOOR.lbuffer_scale).abs() < 1e-6,
            "{q:?}"
        );
        // Without fur the L-buffer passes dominate: the L-buffer scale goes down first.
        let lit = Costs::fit(Quality { shells: 1, ..FULL }, 300.0, 100.0, 100.0);
        let q = Budget::new(350.0, lit).choose(true);
        assert!(
            q.lbuffer_scale < FULL.lbuffer_scale && q.render_scale == 1.0,
            "{q:?}"
        );
    }

    #[test]
    fn observed_frames_correct_a_model_that_is_too_optimistic() {
        // The real frames take 1.6 × the model (fixed costs it does not see).
        let actual = |q: &Quality| demo().predict(q) * 1.6;
        let mut b = Budget::new(150.0, demo());
        let first = b.choose(true);
        assert!(actual(&first) > 150.0, "uncorrected, the model overshoots");
        for _ in 0..12 {
            let q = b.choose(true);
            b.observe(&q, actual(&q));
        }
        let q = b.choose(true);
        assert!(actual(&q) <= 150.0, "corrected: {q:?} takes {}", actual(&q));
        assert!((b.correction - 1.6).abs() < 0.05, "{}", b.correction);
        // A still camera is still full quality, and nonsense is ignored.
        assert_eq!(b.choose(false), FULL);
        b.observe(&q, f64::NAN);
        assert!((b.correction - 1.6).abs() < 0.05);
    }

    #[test]
    fn an_impossible_budget_stops_at_the_floors() {
        let b = Budget::new(0.001, demo());
        let q = b.choose(true);
        assert_eq!(q.shells, FLOOR.shells);
        assert!(
            (q.lbuffer_scale - FLOOR.lbuffer_scale).abs() < 1e-6,
            "{q:?}"
        );
        assert!((q.render_scale - FLOOR.render_scale).abs() < 1e-6, "{q:?}");
    }
}
