//! Propagation with invariant bookkeeping: what the CLI's `propagate` and the demo print.

use rigid3::{Body, Integrator, Real, State, StepError};
use serde::Serialize;

/// The outcome of a propagation.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Method name.
    pub method: String,
    /// Step size.
    pub h: f64,
    /// Number of steps taken.
    pub steps: usize,
    /// Final time `steps * h`.
    pub t: f64,
    /// Final momentum.
    pub m: [f64; 3],
    /// Final attitude (absent for a momentum-only run).
    pub q: Option<[f64; 4]>,
    /// Final energy and Casimir.
    pub energy: f64,
    /// Final `|m|^2`.
    pub casimir: f64,
    /// Final spatial momentum `R(q) m` (absent for a momentum-only run).
    pub spatial_momentum: Option<[f64; 3]>,
    /// Max relative drift of `|m|^2` over the run (under a torque, where it is not conserved,
    /// the largest relative change; the key keeps its name for the checks that read it).
    pub casimir_drift: f64,
    /// Max relative drift of the energy `1/2 m . I^-1 m` over the run (a change, likewise,
    /// under a torque or a rotor).
    pub energy_drift: f64,
    /// Max relative drift of the spatial momentum over the run (attitude runs only; a change,
    /// likewise, under a torque).
    pub spatial_momentum_drift: Option<f64>,
    /// The error that stopped the run early, if any.
    pub error: Option<String>,
    /// Forced runs with a potential: the final total energy
    /// `1/2 (m - h_r) . I^-1 (m - h_r) + V(t, q)`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub total_energy: Option<f64>,
    /// Forced runs with a potential: max relative drift of the total energy over the run
    /// (a change, not a drift, where the potential turns with the orbit: see
    /// `jacobi_integral`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub total_energy_drift: Option<f64>,
    /// A gravity gradient whose nadir turns (`N != 0`): the final Jacobi integral
    /// `E_total - N e_z . R(q) m`, the scene's conserved quantity.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jacobi_integral: Option<f64>,
    /// Its max relative drift over the run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jacobi_integral_drift: Option<f64>,
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Takes `steps` steps from `s0` (with attitude if `with_attitude`), tracking the drift of
/// the invariants in f64 after every step.
pub fn propagate<T: Real>(
    method: &str,
    integrator: &mut dyn Integrator<T>,
    body: &Body<T>,
    s0: State<T>,
    steps: usize,
    with_attitude: bool,
) -> Report {
    let wide = |s: &State<T>| {
        let m = s.m.map(Real::to_f64);
        let b = Body::<f64>::from_inertia(body.inertia().map(Real::to_f64)).ok();
        let e = b.map(|b| b.energy(&m)).unwrap_or(f64::NAN);
        let c = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
        let p = State::new(m, s.q.map(Real::to_f64)).spatial_momentum();
        (e, c, p)
    };
    let (e0, c0, p0) = wide(&s0);
    let pn = dist(p0, [0.0; 3]);
    let mut s = s0;
    let (mut de, mut dc, mut dp) = (0.0f64, 0.0f64, 0.0f64);
    let mut error: Option<StepError> = None;
    let mut taken = 0;
    for _ in 0..steps {
        let r = if with_attitude {
            integrator.step_state(&mut s)
        } else {
            integrator.step(&mut s.m)
        };
        if let Err(e) = r {
            error = Some(e);
            break;
        }
        taken += 1;
        let (e, c, p) = wide(&s);
        de = de.max(rel(e, e0));
        dc = dc.max(rel(c, c0));
        if with_attitude {
            dp = dp.max(dist(p, p0) / pn.max(f64::MIN_POSITIVE));
        }
    }
    let (e, c, p) = wide(&s);
    let h = integrator.step_size().to_f64();
    Report {
        method: method.to_string(),
        h,
        steps: taken,
        t: taken as f64 * h,
        m: s.m.map(Real::to_f64),
        q: with_attitude.then(|| s.q.map(Real::to_f64)),
        energy: e,
        casimir: c,
        spatial_momentum: with_attitude.then_some(p),
        casimir_drift: dc,
        energy_drift: de,
        spatial_momentum_drift: with_attitude.then_some(dp),
        error: error.map(|e| e.to_string()),
        total_energy: None,
        total_energy_drift: None,
        jacobi_integral: None,
        jacobi_integral_drift: None,
    }
}

/// Propagation of a forced scene (always with attitude): as [`propagate`], plus the total
/// energy where the forcing has a potential (its drift is then the conservation check; `|m|^2`,
/// `E` and `R(q) m` are reported but are not invariants under a torque).
pub fn propagate_forced<T: Real>(
    method: &str,
    integrator: &mut dyn Integrator<T>,
    spec: &crate::forced_methods::ForceSpec,
    s0: State<T>,
    steps: usize,
) -> Report {
    let inertia = integrator.body().inertia().map(Real::to_f64);
    let h = integrator.step_size().to_f64();
    let total = |k: usize, s: &State<T>| {
        spec.total_energy(
            inertia,
            k as f64 * h,
            s.m.map(Real::to_f64),
            s.q.map(Real::to_f64),
        )
    };
    let jacobi = |k: usize, s: &State<T>| {
        spec.jacobi_integral(
            inertia,
            k as f64 * h,
            s.m.map(Real::to_f64),
            s.q.map(Real::to_f64),
        )
    };
    let body = *integrator.body();
    let mut report = propagate(method, integrator, &body, s0, 0, true);
    let e0 = total(0, &s0);
    let j0 = jacobi(0, &s0);
    let mut drift = 0.0f64;
    let mut j_drift = 0.0f64;
    // |m|^2, E and R(q) m change under a torque: their max relative change over the run (they
    // are invariants only for a rotor without torque, where this is their drift)
    let wide = |s: &State<T>| {
        let st = State::new(s.m.map(Real::to_f64), s.q.map(Real::to_f64));
        let b = Body::<f64>::from_inertia(inertia).ok();
        (
            b.map_or(f64::NAN, |b| b.casimir(&st.m)),
            b.map_or(f64::NAN, |b| b.energy(&st.m)),
            st.spatial_momentum(),
        )
    };
    let (c0, en0, p0) = wide(&s0);
    let p0n = (p0[0] * p0[0] + p0[1] * p0[1] + p0[2] * p0[2]).sqrt();
    let (mut dc, mut de, mut dp) = (0.0f64, 0.0f64, 0.0f64);
    let mut s = s0;
    let mut taken = 0;
    let mut error = None;
    for k in 1..=steps {
        if let Err(e) = integrator.step_state(&mut s) {
            error = Some(e.to_string());
            break;
        }
        taken = k;
        if let (Some(e), Some(e0)) = (total(k, &s), e0) {
            drift = drift.max(rel(e, e0));
        }
        if let (Some(j), Some(j0)) = (jacobi(k, &s), j0) {
            j_drift = j_drift.max(rel(j, j0));
        }
        let (c, en, p) = wide(&s);
        dc = dc.max(rel(c, c0));
        de = de.max(rel(en, en0));
        let d = ((p[0] - p0[0]).powi(2) + (p[1] - p0[1]).powi(2) + (p[2] - p0[2]).powi(2)).sqrt();
        dp = dp.max(d / p0n.max(f64::MIN_POSITIVE));
    }
    let tail = propagate(method, integrator, &body, s, 0, true);
    report.steps = taken;
    report.t = taken as f64 * h;
    report.m = tail.m;
    report.q = tail.q;
    report.energy = tail.energy;
    report.casimir = tail.casimir;
    report.spatial_momentum = tail.spatial_momentum;
    report.casimir_drift = dc;
    report.energy_drift = de;
    report.spatial_momentum_drift = Some(dp);
    report.error = error;
    report.total_energy = total(taken, &s);
    report.total_energy_drift = e0.map(|_| drift);
    report.jacobi_integral = jacobi(taken, &s);
    report.jacobi_integral_drift = j0.map(|_| j_drift);
    report
}
