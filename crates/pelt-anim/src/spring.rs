//! Secondary motion: a damped spring per vertex that lets fur lag behind the skinned motion
//! and settle when it stops. The offset `y` of a strand's tip from where the skin carries it
//! obeys y'' + d y' + k y = −a, with `a` the root's acceleration (the fur is dragged by its
//! root, so it trails it), stiffness `k` (1/s²) and damping `d` (1/s).
//!
//! Each step is integrated exactly for an acceleration held over the step (the closed-form
//! solution of the under-, critically and over-damped oscillator), so the spring is stable at
//! any time step and any velocity: with `d > 0` its energy only decays, and a step of any
//! length lands on the true trajectory of the held forcing. An infinite stiffness keeps the
//! rest pose exactly (no state at all). The driver ([`Cycle`]) follows a looping clip from
//! its periodic state at fixed substeps, so a pose at time T is the same however it was
//! reached.

use glam::Vec3;

/// A spring's settings: stiffness k (1/s², > 0; infinite: rigid) and damping d (1/s, ≥ 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    /// Stiffness k in 1/s² (ω₀² of the undamped oscillator).
    pub stiffness: f32,
    /// Damping d in 1/s (2ζω₀).
    pub damping: f32,
}

impl Spring {
    /// Whether the spring never moves (infinite stiffness).
    pub fn rigid(&self) -> bool {
        self.stiffness.is_infinite()
    }

    /// One exact step of `dt` seconds from offset `y` and velocity `v` under the root
    /// acceleration `a` held over the step: the new (offset, velocity).
    pub fn step(&self, y: Vec3, v: Vec3, a: Vec3, dt: f32) -> (Vec3, Vec3) {
        if self.rigid() || dt <= 0.0 {
            return if self.rigid() {
                (Vec3::ZERO, Vec3::ZERO)
            } else {
                (y, v)
            };
        }
        // About the equilibrium of the held forcing, y'' + d y' + k y = 0.
        self.stepper(dt).step(y, v, a)
    }
}

/// The free oscillator's solution after `t`: y(t) = p₀ y₀ + p₁ v₀, v(t) = q₀ y₀ + q₁ v₀.
/// With h = d/2: y(t) = e^(−ht) (C(t) y₀ + S(t) (v₀ + h y₀)), where C, S are cos ωt and
/// sin ωt / ω (underdamped, ω² = k − h²), 1 and t (critical), cosh ωt and sinh ωt / ω
/// (overdamped, ω² = h² − k). Each product with e^(−ht) is formed so that a long step
/// neither overflows nor loses the slow mode.
fn propagator(k: f64, d: f64, t: f64) -> ([f64; 2], [f64; 2]) {
    let h = d / 2.0;
    let disc = h * h - k;
    // e^(−ht) C, e^(−ht) S and the same times C', S'.
    let (ec, es, ecd, esd) = if disc.abs() <= 1e-12 * k {
        let e = (-h * t).exp();
        (e, e * t, 0.0, e)
    } else if disc < 0.0 {
        let e = (-h * t).exp();
        let w = (-disc).sqrt();
        let (sn, cs) = (w * t).sin_cos();
        (e * cs, e * sn / w, -e * w * sn, e * cs)
    } else {
        let w = disc.sqrt();
        let (ep, em) = ((-(h - w) * t).exp(), (-(h + w) * t).exp());
        (
            0.5 * (ep + em),
            0.5 * (ep - em) / w,
            0.5 * w * (ep - em),
            0.5 * (ep + em),
        )
    };
    let p = [ec + h * es, es];
    let q = [-h * p[0] + ecd + h * esd, -h * p[1] + esd];
    (p, q)
}

/// A spring's exact step over a fixed `dt`: its propagator, formed once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stepper {
    k: f64,
    dt: f32,
    p: [f64; 2],
    q: [f64; 2],
}

impl Spring {
    /// The exact step of `dt` seconds (`dt` > 0, the spring not rigid).
    pub fn stepper(&self, dt: f32) -> Stepper {
        let k = f64::from(self.stiffness);
        let (p, q) = propagator(k, f64::from(self.damping), f64::from(dt));
        Stepper { k, dt, p, q }
    }
}

impl Stepper {
    /// [`Spring::step`] over this stepper's `dt`.
    pub fn step(&self, y: Vec3, v: Vec3, a: Vec3) -> (Vec3, Vec3) {
        let rest = -a.as_dvec3() / self.k;
        let (y0, v0) = (y.as_dvec3() - rest, v.as_dvec3());
        let y1 = y0 * self.p[0] + v0 * self.p[1];
        let v1 = y0 * self.q[0] + v0 * self.q[1];
        ((y1 + rest).as_vec3(), v1.as_vec3())
    }

    /// The free oscillator's 2×2 map over `n` steps (row-major on (y, v)).
    fn power(&self, n: u32) -> [[f64; 2]; 2] {
        let one = [[self.p[0], self.p[1]], [self.q[0], self.q[1]]];
        let mul = |a: [[f64; 2]; 2], b: [[f64; 2]; 2]| {
            [0, 1].map(|i| [0, 1].map(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j]))
        };
        (0..n).fold([[1.0, 0.0], [0.0, 1.0]], |m, _| mul(one, m))
    }
}

/// Substeps per second of a [`Cycle`] (at least one per 1/120 s).
pub const SUBSTEPS_PER_S: f32 = 120.0;

/// Offsets and velocities of every vertex.
type State = Vec<(Vec3, Vec3)>;

/// The springs of a mesh whose roots follow a looping clip, as `pelt view` plays it: the
/// clip's key range `[start, end]` is split into `n` equal substeps (at least 120 a second);
/// the root's acceleration held over a substep is the mean of the second differences of its
/// positions at the substep's two ends, across the loop's seam as if the clip had played before (a
/// clip that carries the mesh along keeps its drift: the seam adds no jerk). The state at the
/// clip's start is the loop's periodic one (solved exactly, no warm-up: the fur of a walk
/// cycle is already swinging at the first frame), and the state at time `t` is that state
/// stepped node by node to `t`'s node, then by the remainder. A playhead keeps the last
/// node's state, so playing forward costs a substep per 1/120 s, and any `t` reached by any
/// path gives the same offsets bit for bit.
#[derive(Debug, Clone)]
pub struct Cycle {
    spring: Spring,
    start: f32,
    end: f32,
    n: u32,
    stepper: Option<Stepper>,
    drift: Vec<Vec3>,
    first: State,
    head: Option<Head>,
}

/// The playhead: node index, the state there, and the roots at the nodes around it (the one
/// before, it, the one after).
#[derive(Debug, Clone)]
struct Head {
    node: u32,
    state: State,
    window: [Vec<Vec3>; 3],
}

impl Cycle {
    /// The springs of the vertices `roots(t)` places for `t` in the key range `(start, end)`
    /// (one position per vertex, the same count at every time). A rigid spring or a range of
    /// no length never samples the roots after the first call and keeps every offset zero.
    pub fn new(
        spring: Spring,
        (start, end): (f32, f32),
        roots: &dyn Fn(f32) -> Vec<Vec3>,
    ) -> Cycle {
        let at_start = roots(start);
        let count = at_start.len();
        let period = end - start;
        let mut c = Cycle {
            spring,
            start,
            end,
            n: 0,
            stepper: None,
            drift: Vec::new(),
            first: vec![(Vec3::ZERO, Vec3::ZERO); count],
            head: None,
        };
        if spring.rigid() || period.is_nan() || period <= 0.0 || count == 0 {
            return c;
        }
        c.n = (period * SUBSTEPS_PER_S).ceil().max(1.0) as u32;
        let stepper = spring.stepper(period / c.n as f32);
        c.stepper = Some(stepper);
        c.drift = roots(end)
            .iter()
            .zip(&at_start)
            .map(|(e, s)| *e - *s)
            .collect();
        // One loop from rest: the forced part F of s(end) = Φⁿ s(start) + F.
        let forced = c.run(c.n, c.rest(roots), roots).state;
        let m = stepper.power(c.n);
        // (I − Φⁿ) s = F, per axis.
        let (a, b, cc, d) = (1.0 - m[0][0], -m[0][1], -m[1][0], 1.0 - m[1][1]);
        let det = a * d - b * cc;
        c.first = forced
            .iter()
            .map(|&(y, v)| {
                if det.abs() < 1e-12 {
                    return (y, v);
                }
                let (y, v) = (y.as_dvec3(), v.as_dvec3());
                (
                    ((y * d - v * b) / det).as_vec3(),
                    ((v * a - y * cc) / det).as_vec3(),
                )
            })
            .collect();
        c
    }

    /// Time of node `i` (0..=n).
    fn time(&self, i: u32) -> f32 {
        if i >= self.n {
            self.end
        } else {
            self.start + (self.end - self.start) * i as f32 / self.n as f32
        }
    }

    /// The roots at node `i`, continued across the seam by the drift (any `i`).
    fn roots_at(&self, i: i64, roots: &dyn Fn(f32) -> Vec<Vec3>) -> Vec<Vec3> {
        let n = i64::from(self.n);
        let loops = if i < 0 {
            (i - n + 1) / n
        } else {
            (i - 1).max(0) / n
        };
        let mut r = roots(self.time((i - loops * n) as u32));
        if loops != 0 {
            let shift = loops as f32;
            r.iter_mut()
                .zip(&self.drift)
                .for_each(|(p, d)| *p += *d * shift);
        }
        r
    }

    /// The playhead at node 0 at rest.
    fn rest(&self, roots: &dyn Fn(f32) -> Vec<Vec3>) -> Head {
        self.head_at(vec![(Vec3::ZERO, Vec3::ZERO); self.first.len()], roots)
    }

    fn head_at(&self, state: State, roots: &dyn Fn(f32) -> Vec<Vec3>) -> Head {
        Head {
            node: 0,
            state,
            window: [-1, 0, 1].map(|i| self.roots_at(i, roots)),
        }
    }

    /// The acceleration held over the substep from the head's node: the mean of the second
    /// differences at its two ends (second order in the substep).
    fn accel(w: &[Vec<Vec3>; 3], ahead: &[Vec3], k: usize, inv: f32) -> Vec3 {
        (ahead[k] - w[2][k] - w[1][k] + w[0][k]) * (0.5 * inv)
    }

    /// `head` advanced to node `to`.
    fn run(&self, to: u32, mut head: Head, roots: &dyn Fn(f32) -> Vec<Vec3>) -> Head {
        let Some(s) = self.stepper else {
            return head;
        };
        let inv = 1.0 / (s.dt * s.dt);
        while head.node < to {
            let ahead = self.roots_at(i64::from(head.node) + 2, roots);
            for (k, st) in head.state.iter_mut().enumerate() {
                *st = s.step(st.0, st.1, Self::accel(&head.window, &ahead, k, inv));
            }
            let [_, b, c] = std::mem::take(&mut head.window);
            head.window = [b, c, ahead];
            head.node += 1;
        }
        head
    }

    /// Every vertex's offset at `t` s (clamped to the key range).
    pub fn offsets(&mut self, t: f32, roots: &dyn Fn(f32) -> Vec<Vec3>) -> Vec<Vec3> {
        let Some(s) = self.stepper else {
            return vec![Vec3::ZERO; self.first.len()];
        };
        let t = t.clamp(self.start, self.end);
        let node = (((t - self.start) / s.dt).floor().max(0.0) as u32).min(self.n);
        let node = if self.time(node) > t {
            node.saturating_sub(1)
        } else {
            node
        };
        let head = match self.head.take() {
            Some(h) if h.node <= node => h,
            _ => self.head_at(self.first.clone(), roots),
        };
        let head = self.run(node, head, roots);
        let rest = t - self.time(node);
        let out = if rest > 0.0 {
            let ahead = self.roots_at(i64::from(node) + 2, roots);
            let inv = 1.0 / (s.dt * s.dt);
            let part = self.spring.stepper(rest);
            head.state
                .iter()
                .enumerate()
                .map(|(k, st)| {
                    part.step(st.0, st.1, Self::accel(&head.window, &ahead, k, inv))
                        .0
                })
                .collect()
        } else {
            head.state.iter().map(|st| st.0).collect()
        };
        self.head = Some(head);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The trajectory of y'' + d y' + k y = 0 by many tiny explicit steps (the check).
    fn brute(k: f32, d: f32, y: f32, v: f32, t: f32) -> (f32, f32) {
        let n = 200_000;
        let h = f64::from(t) / f64::from(n);
        let (mut y, mut v) = (f64::from(y), f64::from(v));
        for _ in 0..n {
            let a = -f64::from(k) * y - f64::from(d) * v;
            v += a * h;
            y += v * h;
        }
        (y as f32, v as f32)
    }

    #[test]
    fn one_exact_step_matches_many_small_ones_in_every_damping_regime() {
        // Under-, critically and over-damped (k = 100: ω₀ = 10, critical d = 20).
        for d in [2.0, 20.0, 60.0] {
            let s = Spring {
                stiffness: 100.0,
                damping: d,
            };
            for t in [0.01, 0.1, 0.7] {
                let (y, v) = s.step(Vec3::X, Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO, t);
                let (by, bv) = brute(100.0, d, 1.0, 0.0, t);
                assert!((y.x - by).abs() < 2e-3, "d {d}, t {t}: {} vs {by}", y.x);
                assert!((v.x - bv).abs() < 2e-2, "d {d}, t {t}: {} vs {bv}", v.x);
                let (by, bv) = brute(100.0, d, 0.0, 3.0, t);
                assert!((y.y - by).abs() < 2e-3, "d {d}, t {t}: {} vs {by}", y.y);
                assert!((v.y - bv).abs() < 2e-2, "d {d}, t {t}: {} vs {bv}", v.y);
            }
        }
    }

    #[test]
    fn large_steps_and_large_velocities_stay_bounded_and_settle() {
        for (k, d) in [(1.0e4, 5.0), (100.0, 20.0), (1.0, 40.0), (1.0e6, 0.5)] {
            let s = Spring {
                stiffness: k,
                damping: d,
            };
            for dt in [1.0 / 120.0, 0.5, 10.0, 1.0e4] {
                let (mut y, mut v) = (Vec3::ZERO, Vec3::new(1.0e3, -2.0e3, 0.0));
                // The energy ½v² + ½ky² of the free spring never grows.
                let energy =
                    |y: Vec3, v: Vec3| 0.5 * v.length_squared() + 0.5 * k * y.length_squared();
                let mut e = energy(y, v);
                for _ in 0..200 {
                    (y, v) = s.step(y, v, Vec3::ZERO, dt);
                    assert!(y.is_finite() && v.is_finite(), "k {k}, d {d}, dt {dt}");
                    let now = energy(y, v);
                    assert!(
                        now <= e * (1.0 + 1e-4) + 1e-9,
                        "k {k}, d {d}, dt {dt}: {now} > {e}"
                    );
                    e = now;
                }
                if dt >= 10.0 {
                    assert!(
                        y.length() < 1e-3 && v.length() < 1e-2,
                        "k {k}, d {d}, dt {dt}: {y} {v}"
                    );
                }
            }
        }
    }

    /// A root swinging along x with period 1 s (a walk cycle's sway), as a looping clip.
    fn sway(t: f32) -> Vec<Vec3> {
        let x = 0.2 * (std::f32::consts::TAU * t).sin();
        vec![Vec3::new(x, 0.0, 0.0), Vec3::new(0.0, 0.5 * x, 0.0)]
    }

    const SOFT: Spring = Spring {
        stiffness: 60.0,
        damping: 4.0,
    };

    #[test]
    fn a_looping_clip_starts_in_its_periodic_state() {
        let mut c = Cycle::new(SOFT, (0.0, 1.0), &sway);
        let first = c.offsets(0.0, &sway);
        let last = c.offsets(1.0, &sway);
        for (a, b) in first.iter().zip(&last) {
            assert!((*a - *b).length() < 1e-4, "{a} vs {b}");
        }
        // The same state as a spring left swinging from rest for 40 loops (its transient
        // decays as e^(−2t)), stepped by brute force at 1/1200 s.
        let h = 1.0 / 1200.0;
        let (mut y, mut v) = (Vec3::ZERO, Vec3::ZERO);
        let accel = |t: f32| {
            let w = std::f32::consts::TAU;
            Vec3::new(-0.2 * w * w * (w * t).sin(), 0.0, 0.0)
        };
        for i in 0..40 * 1200 {
            let a = accel(i as f32 * h);
            let f = -a - SOFT.stiffness * y - SOFT.damping * v;
            v += f * h;
            y += v * h;
        }
        let at = c.offsets(0.0, &sway)[0];
        eprintln!("periodic state {at}, brute force after 40 loops {y}");
        assert!((at - y).length() < 0.01 * y.length() + 1e-4, "{at} vs {y}");
        // The tip swings (at t = 0.25 s the root turns back, its deceleration is greatest),
        // and each vertex along its own root's motion only.
        let q = c.offsets(0.25, &sway);
        assert!(
            q[0].x.abs() > 1e-3 && q[0].y == 0.0 && q[1].x == 0.0,
            "{q:?}"
        );
    }

    #[test]
    fn any_time_reached_any_way_gives_the_same_offsets_bit_for_bit() {
        let fresh = |t: f32| Cycle::new(SOFT, (0.0, 1.0), &sway).offsets(t, &sway);
        let mut played = Cycle::new(SOFT, (0.0, 1.0), &sway);
        for k in 0..=30 {
            let t = k as f32 / 30.0;
            assert_eq!(played.offsets(t, &sway), fresh(t), "at {t}");
        }
        // Back to an earlier time (the clip wrapped, or a scrub).
        assert_eq!(played.offsets(0.1, &sway), fresh(0.1));
        assert_eq!(played.offsets(0.55, &sway), fresh(0.55));
    }

    #[test]
    fn a_rigid_spring_a_still_clip_and_a_steady_drift_keep_the_rest_pose() {
        let rigid = Spring {
            stiffness: f32::INFINITY,
            damping: 1.0,
        };
        let mut c = Cycle::new(rigid, (0.0, 1.0), &sway);
        assert!(c.offsets(0.3, &sway).iter().all(|y| *y == Vec3::ZERO));
        let still = |_: f32| vec![Vec3::new(1.0, 2.0, 3.0); 4];
        let mut c = Cycle::new(SOFT, (0.0, 1.0), &still);
        assert!(c.offsets(0.3, &still).iter().all(|y| *y == Vec3::ZERO));
        // A clip that carries the mesh along at a steady speed: no acceleration, also across
        // the seam where the clip starts again.
        let walk = |t: f32| vec![Vec3::new(1.5 * t, 0.0, -0.5 * t); 2];
        let mut c = Cycle::new(SOFT, (0.0, 0.8), &walk);
        for t in [0.0, 0.01, 0.4, 0.8] {
            for y in c.offsets(t, &walk) {
                assert!(y.length() < 1e-4, "at {t}: {y}");
            }
        }
        // A clip of one key has nothing to follow.
        let mut c = Cycle::new(SOFT, (0.5, 0.5), &sway);
        assert!(c.offsets(0.5, &sway).iter().all(|y| *y == Vec3::ZERO));
    }

    #[test]
    fn violent_clips_and_stiff_or_limp_springs_stay_finite_and_bounded() {
        // A root that jumps 10⁴ units back and forth every substep.
        let jolt = |t: f32| {
            let k = (t * 240.0).round() as i64;
            vec![Vec3::new(if k % 2 == 0 { 1.0e4 } else { -1.0e4 }, 0.0, 0.0)]
        };
        for (k, d) in [(1.0e6, 0.5), (60.0, 4.0), (1.0e-3, 1.0e-3), (1.0, 1.0e4)] {
            let s = Spring {
                stiffness: k,
                damping: d,
            };
            let mut c = Cycle::new(s, (0.0, 1.0), &jolt);
            for t in [0.0, 0.123, 0.5, 1.0] {
                let y = c.offsets(t, &jolt)[0];
                // The peak acceleration is 2·2·10⁴ / dt² = 4·10⁴ · 240²; a damped spring's
                // offset is at most twice its static deflection a / k under it, and a limp
                // one's no more than the acceleration's double integral over a loop.
                let a = 4.0e4 * 240.0 * 240.0;
                let bound = (2.0 * a / k).min(a * 1.0);
                assert!(
                    y.is_finite() && y.length() <= bound,
                    "k {k}, d {d}, t {t}: {y}"
                );
            }
        }
    }
}
