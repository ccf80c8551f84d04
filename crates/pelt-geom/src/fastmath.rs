//! Scalar f32 three-vectors with the exact order of operations of the reference MikkTSpace
//! (Mikkelsen 2011, as ported by `bevy_mikktspace`), so that our tangents match it bit for bit.
//! glam's SIMD dot products add in another order, so MikkTSpace does not use glam.

/// A plain f32 three-vector.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct V3 {
    /// x component.
    pub x: f32,
    /// y component.
    pub y: f32,
    /// z component.
    pub z: f32,
}

impl V3 {
    /// The zero vector.
    pub const ZERO: V3 = V3 {
        x: 0.0,
        y: 0.0,
        z: 0.0,
    };

    /// Builds a vector from an array.
    #[inline]
    pub const fn new(a: [f32; 3]) -> Self {
        V3 {
            x: a[0],
            y: a[1],
            z: a[2],
        }
    }

    /// `x*x + y*y + z*z`, added left to right.
    #[inline]
    pub fn dot(self, r: V3) -> f32 {
        self.x * r.x + self.y * r.y + self.z * r.z
    }

    /// Componentwise sum.
    #[inline]
    pub fn plus(self, r: V3) -> V3 {
        V3 {
            x: self.x + r.x,
            y: self.y + r.y,
            z: self.z + r.z,
        }
    }

    /// Componentwise difference.
    #[inline]
    pub fn minus(self, r: V3) -> V3 {
        V3 {
            x: self.x - r.x,
            y: self.y - r.y,
            z: self.z - r.z,
        }
    }

    /// Scales by `s` (computed as `s * component`, as the reference does).
    #[inline]
    pub fn scale(self, s: f32) -> V3 {
        V3 {
            x: s * self.x,
            y: s * self.y,
            z: s * self.z,
        }
    }

    /// Euclidean length with f32 sqrt.
    #[inline]
    pub fn length(self) -> f32 {
        self.dot(self).sqrt()
    }

    /// Unit vector, or the vector unchanged when every component is zero or subnormal.
    #[inline]
    pub fn normalized_or_zero(self) -> V3 {
        if not_zero(self.x) || not_zero(self.y) || not_zero(self.z) {
            self.scale(self.length().recip())
        } else {
            self
        }
    }

    /// `self` with its component along the unit vector `n` removed, then normalized.
    #[inline]
    pub fn project_normalized(self, n: V3) -> V3 {
        self.minus(n.scale(n.dot(self))).normalized_or_zero()
    }

    /// As an array.
    #[inline]
    pub const fn to_array(self) -> [f32; 3] {
        [self.x, self.y, self.z]
    }
}

/// The reference's test for "not zero": larger in magnitude than the smallest normal f32.
#[inline]
pub fn not_zero(x: f32) -> bool {
    x.abs() > f32::MIN_POSITIVE
}
