//! Shared test fixtures: the public scenes of docs/MATH.md §8 and a seeded generator.
#![allow(dead_code)]
// the references keep every digit the high-precision solver gave
#![allow(clippy::excessive_precision)]

/// The talk's case: mass matrix J and initial momentum.
pub const TALK_J: [f64; 3] = [0.9218, 0.7382, 0.1763];
pub const TALK_M0: [f64; 3] = [0.4165, 0.9072, 0.0588];
/// Reference m(1), m(10), m(100) of the talk's case (docs/MATH.md §8, independent high precision).
pub const TALK_M1: [f64; 3] = [
    0.40963676823852457273,
    0.91216486689156377454,
    -0.0097213021655047406612,
];
pub const TALK_M10: [f64; 3] = [
    0.82717281856790628525,
    -0.096647426825883589630,
    -0.55352139354352065378,
];
pub const TALK_M100: [f64; 3] = [
    0.66653809997201721994,
    0.62577581339461293974,
    0.40505940632949599801,
];
/// Existence limit of the DMV step at the talk's initial state (docs/MATH.md §3).
pub const TALK_MAX_STEP: f64 = 1.060273597;

/// Hairer–Vilmart's driver case.
pub const HV_I: [f64; 3] = [0.6, 0.8, 1.0];
pub const HV_M0: [f64; 3] = [1.8, 0.4, -0.9];

/// Reference attitude q(10) of the talk's case from q0 = 1 (mpmath, lab/refs/refs.json).
pub const TALK_Q10: [f64; 4] = [
    0.05848376704928084885,
    -0.7688612700282374779,
    -0.5298928566545770041,
    0.35305177652681915446,
];
/// Reference m(10), q(10) of Hairer–Vilmart's driver case from q0 = 1.
pub const HV_M10: [f64; 3] = [
    1.76596250851820753572,
    -0.6954641970330891194,
    0.77955498148187108610,
];
pub const HV_Q10: [f64; 4] = [
    -0.7360613641607939361,
    -0.5707869512403507332,
    -0.2993885718307900937,
    -0.2068390861046731924,
];

/// SplitMix64: a small, seeded, reproducible generator for test inputs.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// Uniform on the unit sphere.
    pub fn direction(&mut self) -> [f64; 3] {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, 2.0 * std::f64::consts::PI);
        let r = (1.0 - z * z).sqrt();
        [r * phi.cos(), r * phi.sin(), z]
    }
}

pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

pub fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm(sub(a, b))
}

pub fn to_f32(a: [f64; 3]) -> [f32; 3] {
    [a[0] as f32, a[1] as f32, a[2] as f32]
}

pub fn to_f64(a: [f32; 3]) -> [f64; 3] {
    [a[0] as f64, a[1] as f64, a[2] as f64]
}

/// `|m(10) - m_ref(10)|` on the talk's case: `a` (momentum only) stepped from `TALK_M0` to
/// t = 10 with step `h`, in any precision.
pub fn talk_error_at_10<T: rigid3::Real>(a: &mut dyn rigid3::Integrator<T>, h: f64) -> f64 {
    let mut m = TALK_M0.map(T::from_f64);
    for _ in 0..(10.0 / h).round() as usize {
        a.step(&mut m).unwrap();
    }
    dist(m.map(|x| x.to_f64()), TALK_M10)
}

/// Least-squares slope of log(err) against log(h): the observed order.
pub fn observed_order(hs: &[f64], errs: &[f64]) -> f64 {
    let n = hs.len() as f64;
    let xs: Vec<f64> = hs.iter().map(|h| h.ln()).collect();
    let ys: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
    let mx = xs.iter().sum::<f64>() / n;
    let my = ys.iter().sum::<f64>() / n;
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Distance between unit quaternions up to sign (q and -q are the same attitude).
pub fn qdist(a: [f64; 4], b: [f64; 4]) -> f64 {
    let d1: f64 = (0..4).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
    let d2: f64 = (0..4).map(|k| (a[k] + b[k]).powi(2)).sum::<f64>().sqrt();
    d1.min(d2)
}
