//! Shared test fixtures: the public scenes of docs/MATH.md §8 (`cases.rs`), a seeded
//! generator and small vector helpers.
#![allow(dead_code, unused_imports)]

// the public scenes' constants, shared with the benches and the lab (one definition)
mod cases;
pub use cases::*;

// SplitMix64, the lab's generator (one definition for the whole repository)
#[path = "../../lab/src/rng.rs"]
mod rng;
pub use rng::Rng;

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

// the rotation matrix written out (one definition, shared with the lab's tests)
mod rotation;
pub use rotation::rotation;
