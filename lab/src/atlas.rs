//! The stability atlas: what one run of a method does at one step size from one initial
//! momentum, classified as accurate, a refused step (by `StepError` variant), NaN, blow-up,
//! or a silent loss of accuracy (phase error only, or drifting invariants).

use crate::methods::make;
use rigid3::{Body, Exact, Mv, StepError};

/// The horizon of an atlas run: `round(ATLAS_T / h)` steps, at least one.
pub const ATLAS_T: f64 = 10.0;

/// Relative error at the end past which a run has lost its accuracy.
pub const MAX_ERROR: f64 = 0.1;

/// Relative drift of `|m|^2` or the energy past which a run has lost its invariants.
pub const MAX_DRIFT: f64 = 1e-3;

/// Growth of `|m|` past which a run has blown up.
pub const BLOW_UP: f64 = 10.0;

/// What one run did.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Outcome {
    /// Every step taken, error at the end `<= MAX_ERROR`, invariants kept to `MAX_DRIFT`.
    Accurate,
    /// Invariants kept, but the end point is off by more than `MAX_ERROR` (a phase error: the
    /// qualitative motion is right, the timing is not).
    PhaseError,
    /// Silent loss of accuracy: finite and bounded, but `|m|^2` or the energy drifted by more
    /// than `MAX_DRIFT` (and the error is large or the invariants are wrong).
    Drift,
    /// `|m|` grew past `BLOW_UP` times its start.
    BlowUp,
    /// A non-finite number came out of a step that reported success.
    NaN,
    /// A step was refused with this error (the state left as it was).
    Refused(StepError),
}

impl Outcome {
    /// All outcomes the atlas draws, in legend order.
    pub const ALL: [Outcome; 10] = [
        Outcome::Accurate,
        Outcome::PhaseError,
        Outcome::Drift,
        Outcome::BlowUp,
        Outcome::NaN,
        Outcome::Refused(StepError::StepTooLarge),
        Outcome::Refused(StepError::NoConvergence),
        Outcome::Refused(StepError::Degenerate),
        Outcome::Refused(StepError::Overflow),
        Outcome::Refused(StepError::NonFinite),
    ];

    /// A short label.
    pub fn label(&self) -> &'static str {
        match self {
            Outcome::Accurate => "accurate",
            Outcome::PhaseError => "phase error > 10% (invariants kept)",
            Outcome::Drift => "silent loss: invariants drift > 1e-3",
            Outcome::BlowUp => "blow-up (|m| x10)",
            Outcome::NaN => "NaN returned as Ok",
            Outcome::Refused(StepError::StepTooLarge) => "Err(StepTooLarge)",
            Outcome::Refused(StepError::NoConvergence) => "Err(NoConvergence)",
            Outcome::Refused(StepError::Degenerate) => "Err(Degenerate)",
            Outcome::Refused(StepError::Overflow) => "Err(Overflow)",
            Outcome::Refused(StepError::NonFinite) => "Err(NonFinite)",
            Outcome::Refused(_) => "Err(other)",
        }
    }

    /// Whether the run is usable (accurate).
    pub fn is_ok(&self) -> bool {
        *self == Outcome::Accurate
    }

    /// Whether the method said so (an `Err`) rather than failing silently.
    pub fn is_reported(&self) -> bool {
        matches!(self, Outcome::Refused(_))
    }
}

fn norm(a: &[f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// Runs `method` (f64, momentum only) on `body` from `m0` with step `h` for
/// `max(1, round(ATLAS_T / h))` steps and classifies the run against the exact solution.
/// `None` for an unknown method (or if the exact solution cannot be computed from `m0`).
pub fn classify(method: &str, body: &Body<f64>, m0: [f64; 3], h: f64) -> Option<Outcome> {
    let n = ((ATLAS_T / h).round() as usize).max(1);
    classify_steps(method, body, m0, h, n)
}

/// As [`classify`] with an explicit number of steps.
pub fn classify_steps(
    method: &str,
    body: &Body<f64>,
    m0: [f64; 3],
    h: f64,
    n: usize,
) -> Option<Outcome> {
    let mut a = make(method, *body, h)?;
    let (c0, e0, n0) = (body.casimir(&m0), body.energy(&m0), norm(&m0));
    let mut m = m0;
    let mut drift = 0.0f64;
    for _ in 0..n {
        if let Err(e) = a.step(&mut m) {
            return Some(Outcome::Refused(e));
        }
        if m.iter().any(|x| !x.is_finite()) {
            return Some(Outcome::NaN);
        }
        if norm(&m) > BLOW_UP * n0 {
            return Some(Outcome::BlowUp);
        }
        let dc = (body.casimir(&m) - c0).abs() / c0.max(f64::MIN_POSITIVE);
        let de = (body.energy(&m) - e0).abs() / e0.max(f64::MIN_POSITIVE);
        drift = drift.max(dc).max(de);
    }
    if !(drift <= MAX_DRIFT) {
        return Some(Outcome::Drift);
    }
    let exact = Exact::momentum_at(body, &m0, n as f64 * h).ok()?;
    let err = norm(&[m[0] - exact[0], m[1] - exact[1], m[2] - exact[2]]) / n0;
    Some(if err <= MAX_ERROR {
        Outcome::Accurate
    } else {
        Outcome::PhaseError
    })
}

/// `n` unit vectors spread evenly over the sphere (Fibonacci lattice): the initial momentum
/// directions of the atlas. Deterministic.
pub fn directions(n: usize) -> Vec<[f64; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = golden * i as f64;
            [r * phi.cos(), r * phi.sin(), z]
        })
        .collect()
}

/// `n` step sizes from `lo` to `hi`, evenly spaced in `log h`.
pub fn step_sizes(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| lo * (hi / lo).powf(i as f64 / (n - 1).max(1) as f64))
        .collect()
}

/// DMV's existence limit from `m` (`Mv::max_step`), infinite when every step exists.
pub fn max_step(body: &Body<f64>, m: &[f64; 3]) -> f64 {
    let s = Mv::max_step(body, m);
    if s >= f64::MAX {
        f64::INFINITY
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::{TALK_J, TALK_M0};

    fn talk() -> Body<f64> {
        Body::from_mass_matrix(TALK_J).unwrap()
    }

    #[test]
    fn mv_at_a_tenth_is_accurate() {
        assert_eq!(
            classify("mv", &talk(), TALK_M0, 0.1),
            Some(Outcome::Accurate)
        );
    }

    #[test]
    fn mv_past_max_step_is_refused_as_too_large() {
        let b = talk();
        let limit = max_step(&b, &TALK_M0);
        assert!((limit - 1.060_273_597).abs() < 1e-8, "{limit}");
        assert_eq!(
            classify("mv", &b, TALK_M0, 1.01 * limit),
            Some(Outcome::Refused(StepError::StepTooLarge))
        );
        // just below the limit the step exists: the run keeps its invariants (phase error)
        let below = classify("mv", &b, TALK_M0, 0.99 * limit).unwrap();
        assert!(
            matches!(below, Outcome::Accurate | Outcome::PhaseError),
            "{below:?}"
        );
    }

    #[test]
    fn midpoint_past_its_limit_does_not_converge() {
        // fixed point: converges to h ~ 7.3 (docs/MATH.md §3); Newton fails at h = 12 (the talk's
        // case), but a single Newton step at h = 50 does converge, to a wrong phase
        let b = talk();
        let refused = Some(Outcome::Refused(StepError::NoConvergence));
        assert_eq!(classify("midpoint-fp", &b, TALK_M0, 50.0), refused);
        assert_eq!(classify("midpoint", &b, TALK_M0, 12.0), refused);
        assert_eq!(
            classify("midpoint", &b, TALK_M0, 50.0),
            Some(Outcome::PhaseError)
        );
    }

    #[test]
    fn rk4_at_five_fails_silently() {
        let o = classify("rk4", &talk(), TALK_M0, 5.0).unwrap();
        assert!(matches!(o, Outcome::BlowUp | Outcome::Drift), "{o:?}");
        assert!(!o.is_reported());
    }

    #[test]
    fn splitting_at_large_steps_keeps_the_casimir_but_not_the_energy() {
        // the splitting keeps |m|^2 exactly, but its energy error grows with h
        let o = classify("splitting", &talk(), TALK_M0, 1.0).unwrap();
        assert_eq!(o, Outcome::Drift);
        assert_eq!(
            classify("splitting", &talk(), TALK_M0, 0.05),
            Some(Outcome::Accurate)
        );
    }

    #[test]
    fn directions_are_unit_and_spread() {
        let d = directions(48);
        assert_eq!(d.len(), 48);
        for v in &d {
            assert!((norm(v) - 1.0).abs() < 1e-12);
        }
        let mean: f64 = d.iter().map(|v| v[2]).sum::<f64>() / 48.0;
        assert!(mean.abs() < 1e-12);
        let h = step_sizes(0.01, 100.0, 5);
        assert!((h[2] - 1.0).abs() < 1e-12 && (h[4] - 100.0).abs() < 1e-9);
    }
}
