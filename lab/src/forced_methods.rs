//! Forced methods behind one name: the torques of a scene, and every forced integrator.

use rigid3::{
    Body, Composed, Exact, Forced, ForcedRk4, Gravity, GravityGradient, Integrator, Midpoint, Mv,
    PeriodicTorque, PreMv, Real, Splitting, State, Torque,
};
use serde::{Deserialize, Serialize};

/// What drives a forced scene (f64 parameters as the CLI and the references give them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ForceSpec {
    /// Rotor momentum `h_r` (body frame).
    pub rotor: Option<[f64; 3]>,
    /// Heavy top: `(M g, centre of mass)`.
    pub gravity: Option<(f64, [f64; 3])>,
    /// Gravity gradient: `(K, N)`.
    pub gravity_gradient: Option<(f64, f64)>,
    /// Body torque `A_i cos(W_i t + P_i)`: `(A, W, P)`.
    pub body_torque: Option<([f64; 3], [f64; 3], [f64; 3])>,
}

impl ForceSpec {
    /// True when nothing forces the body.
    pub fn is_free(&self) -> bool {
        *self == ForceSpec::default()
    }

    /// The torque model of this scene for `body`.
    pub fn torque<T: Real>(&self, body: &Body<T>) -> SceneTorque<T> {
        let v = |a: [f64; 3]| a.map(T::from_f64);
        SceneTorque {
            gravity: self.gravity.map(|(mg, com)| Gravity {
                mg: T::from_f64(mg),
                com: v(com),
            }),
            gravity_gradient: self.gravity_gradient.map(|(k, n)| GravityGradient {
                k: T::from_f64(k),
                n: T::from_f64(n),
                inertia: body.inertia(),
            }),
            periodic: self.body_torque.map(|(a, w, p)| PeriodicTorque {
                amplitude: v(a),
                freq: v(w),
                phase: v(p),
            }),
        }
    }

    /// The rotor (zero when absent).
    pub fn rotor_or_zero(&self) -> [f64; 3] {
        self.rotor.unwrap_or([0.0; 3])
    }

    /// Total energy `1/2 (m - h_r) . I^-1 (m - h_r) + V(t, q)` in f64, or `None` when a
    /// non-conservative (body) torque acts.
    pub fn total_energy(&self, inertia: [f64; 3], t: f64, m: [f64; 3], q: [f64; 4]) -> Option<f64> {
        let body = Body::<f64>::from_inertia(inertia).ok()?;
        let h = self.rotor_or_zero();
        let kinetic: f64 = (0..3)
            .map(|i| 0.5 * (m[i] - h[i]).powi(2) / inertia[i])
            .sum();
        Some(kinetic + self.torque(&body).potential(t, &q)?)
    }

    /// The Jacobi integral `E_total - N e_z . R(q) m` where the potential turns about `e_z` at
    /// the orbit rate `N` (a gravity gradient with `N != 0`, with or without gravity about
    /// `e_z`, which that turn leaves as it is, and a rotor): conserved where the total energy
    /// is not. `None` without such a turn or without a potential.
    pub fn jacobi_integral(
        &self,
        inertia: [f64; 3],
        t: f64,
        m: [f64; 3],
        q: [f64; 4],
    ) -> Option<f64> {
        let (_, n) = self.gravity_gradient?;
        if n == 0.0 {
            return None;
        }
        let e = self.total_energy(inertia, t, m, q)?;
        Some(e - n * State::new(m, q).spatial_momentum()[2])
    }
}

/// The sum of a scene's torques: gravity about a fixed point, gravity gradient, a periodic
/// body torque (each optional).
#[derive(Clone, Copy, Debug)]
pub struct SceneTorque<T> {
    /// Heavy-top gravity.
    pub gravity: Option<Gravity<T>>,
    /// Gravity gradient.
    pub gravity_gradient: Option<GravityGradient<T>>,
    /// Periodic body torque.
    pub periodic: Option<PeriodicTorque<T>>,
}

impl<T: Real> Torque<T> for SceneTorque<T> {
    fn torque(&self, t: T, q: &[T; 4]) -> [T; 3] {
        let mut tau = [T::ZERO; 3];
        let mut add = |x: [T; 3]| {
            for i in 0..3 {
                tau[i] += x[i];
            }
        };
        if let Some(g) = &self.gravity {
            add(g.torque(t, q));
        }
        if let Some(g) = &self.gravity_gradient {
            add(g.torque(t, q));
        }
        if let Some(p) = &self.periodic {
            add(p.torque(t, q));
        }
        tau
    }
    fn potential(&self, t: T, q: &[T; 4]) -> Option<T> {
        if self.periodic.is_some() {
            return None;
        }
        let mut v = T::ZERO;
        if let Some(g) = &self.gravity {
            v += g.potential(t, q)?;
        }
        if let Some(g) = &self.gravity_gradient {
            v += g.potential(t, q)?;
        }
        Some(v)
    }
    fn depends_on_attitude(&self) -> bool {
        self.gravity.is_some() || self.gravity_gradient.is_some()
    }
    fn is_zero(&self) -> bool {
        self.gravity.is_none() && self.gravity_gradient.is_none() && self.periodic.is_none()
    }
    fn turn_rate(&self, t: T, q: &[T; 4], w: [T; 3]) -> Option<[T; 3]> {
        // the periodic body torque does not turn with the body
        let mut rate = [T::ZERO; 3];
        let mut add = |x: [T; 3]| {
            for i in 0..3 {
                rate[i] += x[i];
            }
        };
        if let Some(g) = &self.gravity {
            add(g.turn_rate(t, q, w)?);
        }
        if let Some(g) = &self.gravity_gradient {
            add(g.turn_rate(t, q, w)?);
        }
        Some(rate)
    }
}

/// The forced method names the CLI accepts, in table order.
pub const FORCED_METHODS: &[&str] = &[
    "mv",
    "pre-mv4",
    "pre-mv6",
    "pre-mv8",
    "pre-mv10",
    "forced4",
    "forced6",
    "forced4-pre4",
    "forced6-pre6",
    "forced4-pre10",
    "forced6-pre10",
    "nystrom4-pre6",
    "nystrom6-pre6",
    "nystrom4-pre10",
    "nystrom6-pre10",
    "nystrom4-exact",
    "nystrom6-exact",
    "fg4-pre6",
    "fg4-pre10",
    "fg4-exact",
    "rk4",
    "midpoint",
    "splitting",
];

/// Whether `name` is a Nyström or force-gradient splitting: a scheme that takes the drift for
/// the free body's exact flow, and so no rotor.
pub fn needs_exact_drift(name: &str) -> bool {
    name.starts_with("nystrom") || name.starts_with("fg4")
}

/// Why [`make_forced`] built no integrator for `method` with `spec`, in words (`propagate` and
/// `soak --rotor` report it).
pub fn refusal(method: &str, spec: &ForceSpec) -> String {
    let forced = FORCED_METHODS.contains(&method);
    if forced && needs_exact_drift(method) {
        format!("'{method}' takes no rotor: a Nystrom or force-gradient splitting needs the free body's exact flow, and with a rotor that is a gyrostat (use forced4 or forced6)")
    } else if forced && spec.rotor.is_some() {
        format!("'{method}' refused the rotor: I^-1 h_r overflows")
    } else if forced {
        format!("'{method}' cannot be built for this body and step")
    } else if crate::methods::METHODS.contains(&method) {
        format!(
            "'{method}' has no forced step (forced methods: {})",
            FORCED_METHODS.join(", ")
        )
    } else {
        format!("unknown method '{method}' (see `rigid3-lab methods`)")
    }
}

/// One-line description of a forced method.
pub fn describe_forced(name: &str) -> &'static str {
    match name {
        "mv" => "kick-drift-kick around the closed-form DMV step (explicit LGVI), order 2",
        "pre-mv4" | "pre-mv6" | "pre-mv8" | "pre-mv10" => {
            "kick-drift-kick around preprocessed DMV: order 2 with a torque"
        }
        "forced4" => "McLachlan's 5-stage symmetric composition of the Mv kick-drift-kick, order 4",
        "forced6" => "Kahan-Li 9-stage symmetric composition of the Mv kick-drift-kick, order 6",
        "forced4-pre4" => "forced4 with the order-4 PreMv drift",
        "forced6-pre6" => "forced6 with the order-6 PreMv drift",
        "forced4-pre10" => "forced4 with the order-10 PreMv drift",
        "forced6-pre10" => "forced6 with the order-10 PreMv drift",
        "nystrom4-pre6" | "nystrom4-pre10" | "nystrom4-exact" => {
            "Blanes-Moan SRKN_6^b Nystrom splitting (kicks, near-exact drifts: PreMv or Exact), order 4, no rotor"
        }
        "nystrom6-pre6" | "nystrom6-pre10" | "nystrom6-exact" => {
            "Blanes-Moan SRKN_11^b Nystrom splitting (kicks, near-exact drifts: PreMv or Exact), order 6, no rotor"
        }
        "fg4-pre6" | "fg4-pre10" | "fg4-exact" => {
            "Chin's force-gradient splitting 4A (two near-exact drifts, a kick with [B,[A,B]]), order 4, no rotor"
        }
        "rk4" => "classical Runge-Kutta on the full forced equations, order 4",
        "midpoint" => "kick-drift-kick around the implicit midpoint rule (Newton), order 2",
        "splitting" => "kick-drift-kick around McLachlan's 5-rotation splitting (Strang), order 2",
        _ => "unknown",
    }
}

/// A boxed forced integrator for `name`, or `None` for an unknown name.
pub fn make_forced<T: Real + 'static>(
    name: &str,
    body: Body<T>,
    h: T,
    spec: &ForceSpec,
) -> Option<Box<dyn Integrator<T>>> {
    let torque = spec.torque(&body);
    let rotor = spec.rotor_or_zero().map(T::from_f64);
    fn forced<T: Real + 'static, D: Integrator<T> + 'static>(
        drift: D,
        torque: SceneTorque<T>,
        rotor: [T; 3],
    ) -> Option<Box<dyn Integrator<T>>> {
        let mut f = Forced::new(drift, torque);
        f.set_rotor(rotor).ok()?;
        Some(Box::new(f))
    }
    fn composed<T: Real + 'static, D: Integrator<T> + Clone + 'static>(
        drift: D,
        torque: SceneTorque<T>,
        rotor: [T; 3],
        order: u8,
    ) -> Option<Box<dyn Integrator<T>>> {
        let mut f = Composed::new(drift, torque, order).ok()?;
        f.set_rotor(rotor).ok()?;
        Some(Box::new(f))
    }
    fn nystrom<T: Real + 'static, D: Integrator<T> + Clone + 'static>(
        drift: D,
        torque: SceneTorque<T>,
        rotor: [T; 3],
        order: u8,
    ) -> Option<Box<dyn Integrator<T>>> {
        // a scene with a rotor has no Nystrom splitting: None, as for an unknown name
        let mut f = Composed::nystrom(drift, torque, order).ok()?;
        f.set_rotor(rotor).ok()?;
        Some(Box::new(f))
    }
    fn force_gradient<T: Real + 'static, D: Integrator<T> + Clone + 'static>(
        drift: D,
        torque: SceneTorque<T>,
        rotor: [T; 3],
    ) -> Option<Box<dyn Integrator<T>>> {
        let mut f = Composed::force_gradient(drift, torque).ok()?;
        f.set_rotor(rotor).ok()?;
        Some(Box::new(f))
    }
    match name {
        "mv" => forced(Mv::new(body, h), torque, rotor),
        "pre-mv4" => forced(PreMv::new(body, h, 4).ok()?, torque, rotor),
        "pre-mv6" => forced(PreMv::new(body, h, 6).ok()?, torque, rotor),
        "pre-mv8" => forced(PreMv::new(body, h, 8).ok()?, torque, rotor),
        "pre-mv10" => forced(PreMv::new(body, h, 10).ok()?, torque, rotor),
        "forced4" => composed(Mv::new(body, h), torque, rotor, 4),
        "forced6" => composed(Mv::new(body, h), torque, rotor, 6),
        "forced4-pre4" => composed(PreMv::new(body, h, 4).ok()?, torque, rotor, 4),
        "forced6-pre6" => composed(PreMv::new(body, h, 6).ok()?, torque, rotor, 6),
        "forced4-pre10" => composed(PreMv::new(body, h, 10).ok()?, torque, rotor, 4),
        "forced6-pre10" => composed(PreMv::new(body, h, 10).ok()?, torque, rotor, 6),
        "nystrom4-pre6" => nystrom(PreMv::new(body, h, 6).ok()?, torque, rotor, 4),
        "nystrom6-pre6" => nystrom(PreMv::new(body, h, 6).ok()?, torque, rotor, 6),
        "nystrom4-pre10" => nystrom(PreMv::new(body, h, 10).ok()?, torque, rotor, 4),
        "nystrom6-pre10" => nystrom(PreMv::new(body, h, 10).ok()?, torque, rotor, 6),
        "nystrom4-exact" => nystrom(Exact::new(body, h), torque, rotor, 4),
        "nystrom6-exact" => nystrom(Exact::new(body, h), torque, rotor, 6),
        "fg4-pre6" => force_gradient(PreMv::new(body, h, 6).ok()?, torque, rotor),
        "fg4-pre10" => force_gradient(PreMv::new(body, h, 10).ok()?, torque, rotor),
        "fg4-exact" => force_gradient(Exact::new(body, h), torque, rotor),
        "rk4" => {
            let mut r = ForcedRk4::new(body, h, torque);
            r.set_rotor(rotor).ok()?;
            Some(Box::new(r))
        }
        "midpoint" => forced(Midpoint::new(body, h), torque, rotor),
        "splitting" => forced(Splitting::new(body, h), torque, rotor),
        _ => None,
    }
}

/// Runs `steps` forced steps from `s0`; returns the final state in f64, the number of steps
/// taken and the error that stopped the run, if any.
pub fn run_forced<T: Real>(
    integrator: &mut dyn Integrator<T>,
    s0: State<T>,
    steps: usize,
) -> (State<f64>, usize, Option<rigid3::StepError>) {
    let mut s = s0;
    for k in 0..steps {
        if let Err(e) = integrator.step_state(&mut s) {
            return (widen(&s), k, Some(e));
        }
    }
    (widen(&s), steps, None)
}

fn widen<T: Real>(s: &State<T>) -> State<f64> {
    State::new(s.m.map(Real::to_f64), s.q.map(Real::to_f64))
}
