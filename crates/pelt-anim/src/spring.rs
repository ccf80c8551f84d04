//! Secondary motion: a damped spring per vertex that lets fur lag behind the skinned motion
//! and settle when it stops. The offset `y` of a strand's tip from where the skin carries it
//! obeys y'' + d y' + k y = −a, with `a` the root's acceleration (the fur is dragged by its
//! root, so it trails it), stiffness `k` (1/s²) and damping `d` (1/s).
//!
//! Each step is integrated exactly for an acceleration held over the step (the closed-form
//! solution of the under-, critically and over-damped oscillator), so the spring is stable at
//! any time step and any velocity: with `d > 0` its energy only decays, and a step of any
//! length lands on the true trajectory of the held forcing. An infinite stiffness keeps the
//! rest pose exactly (no state at all). The driver ([`Springs::follow`]) samples the roots at
//! fixed substeps from time 0, so a pose at time T is the same however it was reached.

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
        let k = f64::from(self.stiffness);
        let d = f64::from(self.damping);
        // About the equilibrium of the held forcing, y'' + d y' + k y = 0.
        let rest = -a.as_dvec3() / k;
        let (y0, v0) = (y.as_dvec3() - rest, v.as_dvec3());
        let (p, q) = propagator(k, d, f64::from(dt));
        let y1 = y0 * p[0] + v0 * p[1];
        let v1 = y0 * q[0] + v0 * q[1];
        ((y1 + rest).as_vec3(), v1.as_vec3())
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

/// The springs of a mesh's vertices: each vertex's tip offset and velocity.
#[derive(Debug, Clone, PartialEq)]
pub struct Springs {
    /// The settings every vertex shares.
    pub spring: Spring,
    /// Each vertex's offset.
    pub offset: Vec<Vec3>,
    /// Each vertex's offset velocity.
    pub velocity: Vec<Vec3>,
}

/// Substeps per second of [`Springs::follow`] (one per 1/120 s).
pub const SUBSTEPS_PER_S: f32 = 120.0;

impl Springs {
    /// `count` vertices at rest.
    pub fn new(spring: Spring, count: usize) -> Springs {
        Springs {
            spring,
            offset: vec![Vec3::ZERO; count],
            velocity: vec![Vec3::ZERO; count],
        }
    }

    /// Drives the springs from rest at time 0 to time `t` (s): `roots(time)` gives every
    /// vertex's root position at a time; the root's acceleration over each substep is the
    /// second difference of its positions. Deterministic: the same `t` gives the same offsets
    /// whatever was asked before. A rigid spring keeps every offset zero without sampling.
    pub fn follow(&mut self, t: f32, roots: impl Fn(f32) -> Vec<Vec3>) {
        self.offset.iter_mut().for_each(|y| *y = Vec3::ZERO);
        self.velocity.iter_mut().for_each(|v| *v = Vec3::ZERO);
        if self.spring.rigid() || t <= 0.0 {
            return;
        }
        let steps = (t * SUBSTEPS_PER_S).ceil().max(1.0) as u32;
        let dt = t / steps as f32;
        let (mut before, mut now) = (roots(-dt), roots(0.0));
        for i in 1..=steps {
            let next = roots(i as f32 * dt);
            for (k, (y, v)) in self.offset.iter_mut().zip(&mut self.velocity).enumerate() {
                let a = (next[k] - 2.0 * now[k] + before[k]) / (dt * dt);
                (*y, *v) = self.spring.step(*y, *v, a, dt);
            }
            (before, now) = (now, next);
        }
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

    #[test]
    fn a_rigid_spring_keeps_the_rest_pose_and_a_soft_one_lags_then_settles() {
        // A root that accelerates along +x for 0.5 s, then stops at t = 1 s.
        let roots = |t: f32| {
            let x = if t <= 0.0 {
                0.0
            } else if t < 1.0 {
                t * t
            } else {
                1.0
            };
            vec![Vec3::new(x, 0.0, 0.0); 3]
        };
        let mut rigid = Springs::new(
            Spring {
                stiffness: f32::INFINITY,
                damping: 1.0,
            },
            3,
        );
        rigid.follow(0.8, roots);
        assert!(rigid.offset.iter().all(|y| *y == Vec3::ZERO));
        let soft = Spring {
            stiffness: 60.0,
            damping: 8.0,
        };
        let mut s = Springs::new(soft, 3);
        s.follow(0.5, roots);
        // Dragged forward, the tip trails: its offset points against the acceleration.
        assert!(s.offset[0].x < -0.01, "{}", s.offset[0]);
        // Long after the root stopped, it has settled.
        s.follow(6.0, roots);
        assert!(s.offset[0].length() < 1e-4, "{}", s.offset[0]);
        // Deterministic: the same time gives the same offsets however it was reached.
        let mut a = Springs::new(soft, 3);
        a.follow(0.5, roots);
        let mut b = Springs::new(soft, 3);
        b.follow(0.3, roots);
        b.follow(0.5, roots);
        assert_eq!(a, b);
    }
}
