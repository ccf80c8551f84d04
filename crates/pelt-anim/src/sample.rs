//! Keyframe sampling as glTF 2.0 defines it (§3.11 and Appendix C): STEP holds the value of the
//! last key at or before `t`; LINEAR interpolates (spherical linear interpolation along the
//! shorter arc for rotations); CUBICSPLINE is the cubic Hermite spline whose keys store (in
//! tangent, value, out tangent), tangents scaled by the key interval. Times before the first
//! key take the first value and times after the last take the last. Rotations come out unit
//! length whatever the interpolation.

use glam::{Quat, Vec4};

/// How values between keys are found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interpolation {
    /// The previous key's value.
    Step,
    /// Linear (slerp for rotations).
    Linear,
    /// Cubic Hermite spline; three outputs per key (in tangent, value, out tangent).
    CubicSpline,
}

/// Where `t` falls: the key before it, the key after it and the fraction between them
/// (`k0 == k1` when clamped or on a single key).
pub fn locate(times: &[f32], t: f32) -> (usize, usize, f32) {
    let last = times.len().saturating_sub(1);
    if times.is_empty() || t.is_nan() || t <= times[0] {
        return (0, 0, 0.0);
    }
    if t >= times[last] {
        return (last, last, 0.0);
    }
    // The first key after t; times ascend strictly (checked on load).
    let k1 = times.partition_point(|&k| k <= t);
    let k0 = k1 - 1;
    let span = times[k1] - times[k0];
    (k0, k1, ((t - times[k0]) / span).clamp(0.0, 1.0))
}

/// Samples a channel of `n`-component values (`values` laid out per key, three per key for
/// cubic splines) at `t`, into `out` (length `n`). `rotation` makes the result a unit
/// quaternion (n = 4) and linear interpolation a slerp.
pub fn sample(
    interpolation: Interpolation,
    times: &[f32],
    values: &[f32],
    n: usize,
    t: f32,
    rotation: bool,
    out: &mut [f32],
) {
    let (k0, k1, s) = locate(times, t);
    let stride = if interpolation == Interpolation::CubicSpline {
        3 * n
    } else {
        n
    };
    // The value of key k (the middle of its triple for cubic splines).
    let value = |k: usize| {
        let at = k * stride + if stride == 3 * n { n } else { 0 };
        &values[at..at + n]
    };
    match interpolation {
        _ if k0 == k1 => out.copy_from_slice(value(k0)),
        Interpolation::Step => out.copy_from_slice(value(k0)),
        Interpolation::Linear if rotation => {
            let q = slerp(quat(value(k0)), quat(value(k1)), s);
            out.copy_from_slice(&q.to_array());
        }
        Interpolation::Linear => {
            for (o, (a, b)) in out.iter_mut().zip(value(k0).iter().zip(value(k1))) {
                *o = a + (b - a) * s;
            }
        }
        Interpolation::CubicSpline => {
            let dt = times[k1] - times[k0];
            let out_tangent = &values[k0 * stride + 2 * n..k0 * stride + 3 * n];
            let in_tangent = &values[k1 * stride..k1 * stride + n];
            let (s2, s3) = (s * s, s * s * s);
            let (h00, h10) = (2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s);
            let (h01, h11) = (-2.0 * s3 + 3.0 * s2, s3 - s2);
            for i in 0..n {
                out[i] = h00 * value(k0)[i]
                    + h10 * dt * out_tangent[i]
                    + h01 * value(k1)[i]
                    + h11 * dt * in_tangent[i];
            }
        }
    }
    if rotation {
        let q = quat(out).normalize();
        let q = if q.is_finite() { q } else { Quat::IDENTITY };
        out.copy_from_slice(&q.to_array());
    }
}

fn quat(v: &[f32]) -> Quat {
    Quat::from_vec4(Vec4::new(v[0], v[1], v[2], v[3]))
}

/// Spherical linear interpolation along the shorter arc, of the normalized endpoints.
pub fn slerp(a: Quat, b: Quat, s: f32) -> Quat {
    let (a, mut b) = (a.normalize(), b.normalize());
    let mut d = a.dot(b);
    if d < 0.0 {
        b = -b;
        d = -d;
    }
    if d > 0.9995 {
        // Nearly equal: normalized lerp (slerp's formula divides by sin of a tiny angle).
        return Quat::from_vec4(Vec4::from(a).lerp(Vec4::from(b), s)).normalize();
    }
    let theta = d.clamp(-1.0, 1.0).acos();
    let sin = theta.sin();
    let wa = ((1.0 - s) * theta).sin() / sin;
    let wb = (s * theta).sin() / sin;
    Quat::from_vec4(Vec4::from(a) * wa + Vec4::from(b) * wb).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: [f32; 3] = [1.0, 2.0, 4.0];

    fn at(i: Interpolation, values: &[f32], n: usize, t: f32) -> Vec<f32> {
        let mut out = vec![0.0; n];
        sample(i, &T, values, n, t, false, &mut out);
        out
    }

    #[test]
    fn step_and_linear_match_hand_values_and_clamp() {
        let v = [0.0, 10.0, 30.0];
        assert_eq!(at(Interpolation::Step, &v, 1, 1.5), [0.0]);
        assert_eq!(at(Interpolation::Step, &v, 1, 2.0), [10.0]);
        assert_eq!(at(Interpolation::Step, &v, 1, 3.9), [10.0]);
        assert_eq!(at(Interpolation::Linear, &v, 1, 1.5), [5.0]);
        assert_eq!(at(Interpolation::Linear, &v, 1, 3.0), [20.0]);
        // Before the first key and after the last: clamped.
        assert_eq!(at(Interpolation::Linear, &v, 1, -7.0), [0.0]);
        assert_eq!(at(Interpolation::Linear, &v, 1, 9.0), [30.0]);
        assert_eq!(at(Interpolation::Step, &v, 1, 9.0), [30.0]);
    }

    #[test]
    fn cubic_spline_is_the_hermite_curve_with_scaled_tangents() {
        // Keys (in, value, out): 0 with out-tangent 2 at t=1, 1 with in-tangent -1 at t=2.
        let v = [9.0, 0.0, 2.0, -1.0, 1.0, 5.0, 0.0, 1.0, 0.0];
        // At s = 0.5 over an interval of 1: h00 = 0.5, h10 = 0.125, h01 = 0.5, h11 = -0.125.
        let (h00, h10, h01, h11) = (0.5, 0.125, 0.5, -0.125);
        let (v0, out0, v1, in1) = (0.0, 2.0, 1.0, -1.0);
        let expect = h00 * v0 + h10 * 1.0 * out0 + h01 * v1 + h11 * 1.0 * in1;
        assert_eq!(at(Interpolation::CubicSpline, &v, 1, 1.5), [expect]);
        // On a key: its value, not its tangents.
        assert_eq!(at(Interpolation::CubicSpline, &v, 1, 2.0), [1.0]);
        // The second interval is 2 long: tangents scale by 2. At s = 0.25:
        let (s, dt) = (0.25f32, 2.0f32);
        let h = [
            2.0 * s.powi(3) - 3.0 * s * s + 1.0,
            s.powi(3) - 2.0 * s * s + s,
            -2.0 * s.powi(3) + 3.0 * s * s,
            s.powi(3) - s * s,
        ];
        let expect = h[0] * 1.0 + h[1] * dt * 5.0 + h[2] * 1.0 + h[3] * dt * 0.0;
        let got = at(Interpolation::CubicSpline, &v, 1, 2.5)[0];
        assert!((got - expect).abs() < 1e-6, "{got} against {expect}");
        // Clamped at both ends to the key values.
        assert_eq!(at(Interpolation::CubicSpline, &v, 1, 0.0), [0.0]);
        assert_eq!(at(Interpolation::CubicSpline, &v, 1, 5.0), [1.0]);
    }

    #[test]
    fn rotations_take_the_shorter_arc_and_come_out_unit() {
        let a = Quat::from_rotation_y(0.0);
        // 350° about Y is -10°: the same rotation as q and -q; slerp must go the short way.
        let b = -Quat::from_rotation_y(20f32.to_radians());
        let mid = slerp(a, b, 0.5);
        let expect = Quat::from_rotation_y(10f32.to_radians());
        assert!(mid.dot(expect).abs() > 1.0 - 1e-6, "{mid} against {expect}");
        // Keys not normalized (as files sometimes store them) still give unit results.
        let times = [0.0, 1.0];
        let values = [0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, -3.0];
        for i in [Interpolation::Step, Interpolation::Linear] {
            let mut out = [0.0; 4];
            sample(i, &times, &values, 4, 0.3, true, &mut out);
            let q = Quat::from_array(out);
            assert!((q.length() - 1.0).abs() < 1e-6, "{i:?}: {q}");
            assert!(q.dot(Quat::IDENTITY).abs() > 1.0 - 1e-6, "{i:?}: {q}");
        }
        // A quarter turn and back: slerp at a third is 30° (hand value).
        let q90 = Quat::from_rotation_x(90f32.to_radians());
        let q = slerp(Quat::IDENTITY, q90, 1.0 / 3.0);
        assert!(q.dot(Quat::from_rotation_x(30f32.to_radians())) > 1.0 - 1e-6);
    }
}
