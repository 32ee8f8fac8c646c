//! Small quaternion and vector helpers, and the seeded noise source (f32 and f64 through `Real`).

use rigid3::Real;

/// Hamilton product `a (x) b`, `q = (w, x, y, z)`.
pub fn qmul<T: Real>(a: [T; 4], b: [T; 4]) -> [T; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

pub fn conj<T: Real>(q: [T; 4]) -> [T; 4] {
    [q[0], -q[1], -q[2], -q[3]]
}

/// `R(q) v`.
pub fn rotate<T: Real>(q: [T; 4], v: [T; 3]) -> [T; 3] {
    let two = T::ONE + T::ONE;
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    let t = [
        two * (y * v[2] - z * v[1]),
        two * (z * v[0] - x * v[2]),
        two * (x * v[1] - y * v[0]),
    ];
    [
        v[0] + w * t[0] + (y * t[2] - z * t[1]),
        v[1] + w * t[1] + (z * t[0] - x * t[2]),
        v[2] + w * t[2] + (x * t[1] - y * t[0]),
    ]
}

pub fn normalized<T: Real>(q: [T; 4]) -> [T; 4] {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}

/// `exp(theta / 2)` to first order, normalised: a small rotation vector as a unit quaternion.
pub fn small_rotation<T: Real>(theta: [T; 3]) -> [T; 4] {
    let half = T::from_f64(0.5);
    normalized([T::ONE, half * theta[0], half * theta[1], half * theta[2]])
}

/// The body-frame rotation vector `theta` with `b = a (x) exp(theta / 2)` (small angles: `2 v`
/// of the error quaternion, sign fixed so that `w >= 0`).
pub fn error_vector<T: Real>(a: [T; 4], b: [T; 4]) -> [T; 3] {
    let d = qmul(conj(a), b);
    let two = T::ONE + T::ONE;
    let s = if d[0] < T::ZERO { -two } else { two };
    [s * d[1], s * d[2], s * d[3]]
}

/// Rotation angle between two attitudes, rad.
pub fn angle(a: [f32; 4], b: [f32; 4]) -> f32 {
    let d = qmul(conj(a), b);
    let v = Real::sqrt(d[1] * d[1] + d[2] * d[2] + d[3] * d[3]);
    2.0 * Real::atan2(v, Real::abs(d[0]))
}

pub fn cross<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub fn to_f32<const N: usize>(v: [f64; N]) -> [f32; N] {
    v.map(|x| x as f32)
}

/// xorshift32 and a 4-uniform Irwin–Hall approximation of a unit normal: seeded, cheap.
pub struct Noise(pub u32);

impl Noise {
    pub fn uniform(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 17;
        self.0 ^= self.0 << 5;
        (self.0 >> 8) as f32 * (1.0 / 16_777_216.0)
    }
    pub fn normal(&mut self) -> f32 {
        // sum of 4 uniforms: mean 2, variance 1/3
        let s = self.uniform() + self.uniform() + self.uniform() + self.uniform();
        (s - 2.0) * 1.732_050_8
    }
    pub fn normal3(&mut self, sigma: f32) -> [f32; 3] {
        [
            sigma * self.normal(),
            sigma * self.normal(),
            sigma * self.normal(),
        ]
    }
}
