//! The curve every strand follows over the surface (Revie, Listing 2.1): at height z (a
//! fraction of the fur length) a strand rooted where the surface has unit normal n and comb c
//! stands at
//!
//! P(z) = z · k · D(z),  D(z) = (n + c z) / |n + c z|,  k = fur length × comb length,
//!
//! so it leaves the skin along the normal and bends toward the comb as it rises (the shells
//! are drawn at these offsets). Its direction, the tangent Kajiya-Kay lights, is the
//! derivative P'(z) = k (D + z D'), D' = (c − D (D·c)) / |n + c z|. shaders/fur_common.wgsl
//! (`shell_offset`, `strand_tangent`) evaluates the same two formulas on the GPU; the strand
//! reference draws its strands along them.

/// A 3-vector.
pub type V3 = [f64; 3];

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: V3, s: f64) -> V3 {
    a.map(|x| x * s)
}

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalized(a: V3) -> V3 {
    let l = dot(a, a).sqrt();
    if l > 0.0 { scale(a, 1.0 / l) } else { a }
}

/// P(z) with k = 1: the offset from the root at height `z` for unit normal `n`, comb `c`.
pub fn point(n: V3, c: V3, z: f64) -> V3 {
    scale(normalized(add(n, scale(c, z))), z)
}

/// The unit direction P'(z) / |P'(z)| of the strand at height `z`.
pub fn tangent(n: V3, c: V3, z: f64) -> V3 {
    let m = add(n, scale(c, z));
    let len = dot(m, m).sqrt();
    if len <= 1e-12 {
        return normalized(c);
    }
    let d = scale(m, 1.0 / len);
    let dd = scale(add(c, scale(d, -dot(d, c))), 1.0 / len);
    normalized(add(d, scale(dd, z)))
}

/// The length of the curve between heights `z0` and `z1` with k = 1 (Simpson's rule on
/// |P'|, exact to 1e-6 for combs of unit length).
pub fn length(n: V3, c: V3, z0: f64, z1: f64) -> f64 {
    const STEPS: usize = 16;
    let speed = |z: f64| {
        let m = add(n, scale(c, z));
        let len = dot(m, m).sqrt().max(1e-12);
        let d = scale(m, 1.0 / len);
        let dd = scale(add(c, scale(d, -dot(d, c))), 1.0 / len);
        let v = add(d, scale(dd, z));
        dot(v, v).sqrt()
    };
    let h = (z1 - z0) / STEPS as f64;
    let mut sum = speed(z0) + speed(z1);
    for i in 1..STEPS {
        sum += speed(z0 + h * i as f64) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * h / 3.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tangent_is_the_derivative_of_the_point() {
        let n = [0.0, 0.0, 1.0];
        for c in [
            [1.0, 0.0, 0.0],
            [0.6, 0.8, 0.0],
            [0.0, 0.0, 1.0],
            [0.3, -0.2, 0.1],
        ] {
            for z in [0.0, 0.1, 0.5, 0.9, 1.0] {
                let e = 1e-6;
                let a = point(n, c, z + e);
                let b = point(n, c, (z - e).max(0.0));
                let fd = normalized(add(a, scale(b, -1.0)));
                let t = tangent(n, c, z);
                assert!(dot(fd, t) > 1.0 - 1e-6, "c {c:?} z {z}: {fd:?} vs {t:?}");
            }
        }
    }

    #[test]
    fn a_combed_strand_leans_further_than_its_offset() {
        // Combed along the surface with a unit comb: at the tip the offset direction is 45°
        // from the normal, the strand itself about 72°.
        let t = tangent([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], 1.0);
        let angle = t[2].acos().to_degrees();
        assert!((angle - 71.57).abs() < 0.05, "{angle}");
        let l = length([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], 0.0, 1.0);
        // Longer than the chord from root to tip (|P(1)| = 1), not by much.
        let tip = point([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], 1.0);
        assert!((dot(tip, tip).sqrt() - 1.0).abs() < 1e-12);
        assert!(l > 1.0 && l < 1.2, "{l}");
    }
}
