//! Small quaternion and vector helpers, and the seeded noise source (f32 and f64 through `Real`).

use rigid3::{Quaternion, Real};

// The quaternion algebra is the library's (`rigid3::Quaternion`, order [w, x, y, z]); these
// adapt it to the plain arrays the filters' equations are written in.

/// Hamilton product `a (x) b`, `q = (w, x, y, z)`.
pub fn qmul<T: Real>(a: [T; 4], b: [T; 4]) -> [T; 4] {
    Quaternion::from_array(a)
        .compose(Quaternion::from_array(b))
        .to_array()
}

pub fn conj<T: Real>(q: [T; 4]) -> [T; 4] {
    Quaternion::from_array(q).conjugate().to_array()
}

/// `R(q) v`.
pub fn rotate<T: Real>(q: [T; 4], v: [T; 3]) -> [T; 3] {
    Quaternion::from_array(q).rotate(v)
}

/// `q / |q|` (`q` itself if it cannot be normalised).
pub fn normalized<T: Real>(q: [T; 4]) -> [T; 4] {
    Quaternion::from_array(q)
        .normalize()
        .map_or(q, Quaternion::to_array)
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
