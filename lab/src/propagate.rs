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

/// The larger of a running maximum and a new value, NaN if either is: `f64::max` drops a NaN,
/// and an overflowed invariant's drift read 0 (found by an external check).
pub(crate) fn worse(acc: f64, x: f64) -> f64 {
    if x.is_nan() || x > acc {
        x
    } else {
        acc
    }
}

/// The energy `1/2 m . I^-1 m`, `|m|^2` and the spatial momentum `R(q) m` of `s`, in f64. The
/// energy as `1/2 sum m_i (m_i / I_i)`: `m_i^2` alone overflowed where the energy does not
/// (`m` and `I` of `1e200`).
fn invariants<T: Real>(inertia: [f64; 3], s: &State<T>) -> (f64, f64, [f64; 3]) {
    scaled_invariants(inertia, s, (1.0, 1.0))
}

/// [`invariants`] with `m` multiplied by `unit.0` and `I` by `unit.1` (powers of two: the
/// drifts are computed in units where the start's momentum and moments are near one, so
/// they are those of the caller's units with nothing rounded, and an invariant of a momentum
/// of `1e-200`, which underflows in the caller's units, still has its digits; found by an
/// external check: `|m|^2` drift 0 with exit 0 there).
fn scaled_invariants<T: Real>(
    inertia: [f64; 3],
    s: &State<T>,
    unit: (f64, f64),
) -> (f64, f64, [f64; 3]) {
    let inertia = inertia.map(|x| x * unit.1);
    let st = State::new(s.m.map(|x| x.to_f64() * unit.0), s.q.map(Real::to_f64));
    let m = st.m;
    let energy = 0.5
        * (m[0] * (m[0] / inertia[0]) + m[1] * (m[1] / inertia[1]) + m[2] * (m[2] / inertia[2]));
    (
        energy,
        m[0] * m[0] + m[1] * m[1] + m[2] * m[2],
        st.spatial_momentum(),
    )
}

impl Report {
    /// The names of the reported numbers that are not finite (empty for a sound report).
    pub fn non_finite_fields(&self) -> Vec<&'static str> {
        let all = |v: &[f64]| v.iter().all(|x| x.is_finite());
        // an invariant of a non-zero momentum that underflowed to zero or a subnormal has lost
        // its digits (`|m|^2` of a momentum of `1e-200`): not a measurement either
        let moving = self.m.iter().any(|&x| x != 0.0);
        let held = |x: f64| x.is_finite() && (!moving || x.abs() >= f64::MIN_POSITIVE);
        let opt = |x: Option<f64>| x.is_none_or(f64::is_finite);
        [
            ("m", all(&self.m)),
            ("q", self.q.is_none_or(|q| all(&q))),
            ("energy", held(self.energy)),
            ("casimir", held(self.casimir)),
            (
                "spatial_momentum",
                self.spatial_momentum.is_none_or(|p| all(&p)),
            ),
            ("casimir_drift", self.casimir_drift.is_finite()),
            ("energy_drift", self.energy_drift.is_finite()),
            ("spatial_momentum_drift", opt(self.spatial_momentum_drift)),
            ("total_energy", opt(self.total_energy)),
            ("total_energy_drift", opt(self.total_energy_drift)),
            ("jacobi_integral", opt(self.jacobi_integral)),
            ("jacobi_integral_drift", opt(self.jacobi_integral_drift)),
        ]
        .into_iter()
        .filter(|&(_, ok)| !ok)
        .map(|(name, _)| name)
        .collect()
    }
}

/// The power of two that brings a positive finite `x` near one (one for zero or a
/// non-finite `x`): the unit the lab's drifts are computed in ([`scaled_invariants`],
/// crate::soak), where nothing rounds.
pub(crate) fn unit_of(x: f64) -> f64 {
    if x > 0.0 && x.is_finite() {
        // (clamped: 2^1030 for a subnormal x is infinite)
        2f64.powi(-(x.log2().round() as i32).clamp(-1000, 1000))
    } else {
        1.0
    }
}

/// The largest magnitude of `v`'s components.
pub(crate) fn max_abs(v: [f64; 3]) -> f64 {
    v[0].abs().max(v[1].abs()).max(v[2].abs())
}

/// Powers of two that bring `m0`'s largest component and the largest moment near one (see
/// [`scaled_invariants`]).
fn units(m0: [f64; 3], inertia: [f64; 3]) -> (f64, f64) {
    (unit_of(max_abs(m0)), unit_of(max_abs(inertia)))
}

/// `|a - b|`, in units of its largest component (squared, a spatial momentum of `1e200`
/// overflowed).
fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let big = d[0].abs().max(d[1].abs()).max(d[2].abs());
    if !(big > 0.0 && big.is_finite()) {
        return big;
    }
    let u = d.map(|x| x / big);
    big * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt()
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
    let inertia = body.inertia().map(Real::to_f64);
    let unit = units(s0.m.map(Real::to_f64), inertia);
    let wide = |s: &State<T>| scaled_invariants(inertia, s, unit);
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
        de = worse(de, rel(e, e0));
        dc = worse(dc, rel(c, c0));
        if with_attitude {
            dp = worse(dp, dist(p, p0) / pn.max(f64::MIN_POSITIVE));
        }
    }
    let (e, c, p) = invariants(inertia, &s);
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
    let unit = units(s0.m.map(Real::to_f64), inertia);
    let wide = |s: &State<T>| scaled_invariants(inertia, s, unit);
    let (en0, c0, p0) = wide(&s0);
    let p0n = dist(p0, [0.0; 3]);
    let (mut dc, mut de, mut dp) = (0.0f64, 0.0f64, 0.0f64);
    let mut s = s0;
    let mut taken = 0;
    let mut error = None;
    for k in 1..=steps {
        if let Err(e) = integrator.step_state(&mut s) {
            // a torque whose angle has left the torque models' sine is refused as not
            // finite: name it where that is the cause (it read "state or step size is not
            // finite", found by an analyst's trial; an overflow keeps its own message)
            let t = k as f64 * h;
            let limit = if T::EPSILON.to_f64() > 1e-10 {
                6.6e6
            } else {
                3.5e15
            };
            let orbit = spec.gravity_gradient.map_or(0.0, |(_, n)| (n * t).abs());
            let own = spec.body_torque.map_or(0.0, |(_, w, p)| {
                (0..3).map(|i| (w[i] * t + p[i]).abs()).fold(0.0, f64::max)
            });
            let past = orbit.max(own) > limit;
            error = Some(if e == rigid3::StepError::NonFinite && past {
                format!(
                    "{e}: the torque is not, its angle ({:e} rad at t = {t:e}) past the \
                     torque models' sine ({limit:e} rad in this precision)",
                    orbit.max(own)
                )
            } else {
                e.to_string()
            });
            break;
        }
        taken = k;
        if let (Some(e), Some(e0)) = (total(k, &s), e0) {
            drift = worse(drift, rel(e, e0));
        }
        if let (Some(j), Some(j0)) = (jacobi(k, &s), j0) {
            j_drift = worse(j_drift, rel(j, j0));
        }
        let (en, c, p) = wide(&s);
        dc = worse(dc, rel(c, c0));
        de = worse(de, rel(en, en0));
        dp = worse(dp, dist(p, p0) / p0n.max(f64::MIN_POSITIVE));
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
