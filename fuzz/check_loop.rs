//! The real loop on raw bytes: a forced or free integrator driven for a few ticks while the
//! caller changes what a flight loop changes — the step (a measured `dt`), the momentum (a
//! filter's correction, or a new value), the wheels' momentum, the clock, the torque given
//! from outside — in any order, with values from moderate to NaN. The promise checked after
//! every call: a step is `Ok` with a finite state and a finite time, or `Err` with the state
//! and the time untouched; a setter is `Ok` or `Err` with nothing changed that can be seen;
//! the total energy is never NaN for a finite state. A panic anywhere is a failure. Shared by
//! the libFuzzer target `loop` and the stable smoke test `tests/fuzz_smoke.rs`.

use crate::check::{by_precision, kind, same, Reader, Tally};
use rigid3::{
    Body, Composed, ConstantTorque, Exact, Forced, ForcedRk4, Gravity, GravityGradient, Integrator,
    Midpoint, Mv, PeriodicTorque, PreMv, Real, RetimedMv, Splitting, State, StepError, Torque,
};

/// Method names by selector (`method % 11`).
pub const LOOP_METHODS: [&str; 11] = [
    "forced mv",
    "forced pre-mv",
    "forced splitting",
    "forced midpoint",
    "forced rk4",
    "composed",
    "nystrom",
    "mv",
    "pre-mv",
    "retimed-mv",
    "force gradient",
];

/// Every torque model of the crate behind one type, picked by the bytes.
#[derive(Clone, Copy, Debug)]
pub enum AnyTorque<T> {
    Constant(ConstantTorque<T>),
    Periodic(PeriodicTorque<T>),
    Gravity(Gravity<T>),
    Gradient(GravityGradient<T>),
}

impl<T: Real> Torque<T> for AnyTorque<T> {
    fn torque(&self, t: T, q: &[T; 4]) -> [T; 3] {
        match self {
            AnyTorque::Constant(x) => x.torque(t, q),
            AnyTorque::Periodic(x) => x.torque(t, q),
            AnyTorque::Gravity(x) => x.torque(t, q),
            AnyTorque::Gradient(x) => x.torque(t, q),
        }
    }
    fn potential(&self, t: T, q: &[T; 4]) -> Option<T> {
        match self {
            AnyTorque::Constant(x) => x.potential(t, q),
            AnyTorque::Periodic(x) => x.potential(t, q),
            AnyTorque::Gravity(x) => x.potential(t, q),
            AnyTorque::Gradient(x) => x.potential(t, q),
        }
    }
    fn depends_on_attitude(&self) -> bool {
        match self {
            AnyTorque::Constant(x) => x.depends_on_attitude(),
            AnyTorque::Periodic(x) => x.depends_on_attitude(),
            AnyTorque::Gravity(x) => x.depends_on_attitude(),
            AnyTorque::Gradient(x) => x.depends_on_attitude(),
        }
    }
    fn is_zero(&self) -> bool {
        match self {
            AnyTorque::Constant(x) => x.is_zero(),
            AnyTorque::Periodic(x) => x.is_zero(),
            AnyTorque::Gravity(x) => x.is_zero(),
            AnyTorque::Gradient(x) => x.is_zero(),
        }
    }
    fn turn_rate(&self, t: T, q: &[T; 4], w: [T; 3]) -> Option<[T; 3]> {
        match self {
            AnyTorque::Constant(x) => x.turn_rate(t, q, w),
            AnyTorque::Periodic(x) => x.turn_rate(t, q, w),
            AnyTorque::Gravity(x) => x.turn_rate(t, q, w),
            AnyTorque::Gradient(x) => x.turn_rate(t, q, w),
        }
    }
}

/// What the loop can do to an integrator besides stepping it; the free ones have no clock,
/// no rotor and no given torque (`None`).
trait Loop<T: Real>: Integrator<T> {
    fn time(&self) -> Option<T> {
        None
    }
    fn set_rotor(&mut self, _h_r: [T; 3]) -> Option<Result<(), StepError>> {
        None
    }
    fn set_time(&mut self, _t: T) -> Option<Result<(), StepError>> {
        None
    }
    fn step_with(
        &mut self,
        _s: &mut State<T>,
        _a: [T; 3],
        _b: [T; 3],
    ) -> Option<Result<(), StepError>> {
        None
    }
    fn energy(&self, _s: &State<T>) -> Option<T> {
        None
    }
}

impl<T: Real> Loop<T> for Mv<T> {}
impl<T: Real> Loop<T> for PreMv<T> {}
impl<T: Real> Loop<T> for RetimedMv<T> {}

impl<T: Real, D: Integrator<T>, F: Torque<T>> Loop<T> for Forced<T, D, F> {
    fn time(&self) -> Option<T> {
        Some(Forced::time(self))
    }
    fn set_rotor(&mut self, h_r: [T; 3]) -> Option<Result<(), StepError>> {
        Some(Forced::set_rotor(self, h_r))
    }
    fn set_time(&mut self, t: T) -> Option<Result<(), StepError>> {
        Some(Forced::set_time(self, t))
    }
    fn step_with(
        &mut self,
        s: &mut State<T>,
        a: [T; 3],
        b: [T; 3],
    ) -> Option<Result<(), StepError>> {
        Some(self.step_state_with(s, a, b))
    }
    fn energy(&self, s: &State<T>) -> Option<T> {
        self.total_energy(s)
    }
}

impl<T: Real, D: Integrator<T> + Clone, F: Torque<T>> Loop<T> for Composed<T, D, F> {
    fn time(&self) -> Option<T> {
        Some(Composed::time(self))
    }
    fn set_rotor(&mut self, h_r: [T; 3]) -> Option<Result<(), StepError>> {
        Some(Composed::set_rotor(self, h_r))
    }
    fn set_time(&mut self, t: T) -> Option<Result<(), StepError>> {
        Some(Composed::set_time(self, t))
    }
    fn energy(&self, s: &State<T>) -> Option<T> {
        self.total_energy(s)
    }
}

impl<T: Real, F: Torque<T>> Loop<T> for ForcedRk4<T, F> {
    fn time(&self) -> Option<T> {
        Some(ForcedRk4::time(self))
    }
    fn set_rotor(&mut self, h_r: [T; 3]) -> Option<Result<(), StepError>> {
        Some(ForcedRk4::set_rotor(self, h_r))
    }
    fn set_time(&mut self, t: T) -> Option<Result<(), StepError>> {
        Some(ForcedRk4::set_time(self, t))
    }
}

/// The promise of a step with attitude: `Ok` gives a finite state, a finite time and a total
/// energy that is not NaN; `Err` leaves state and time as they were.
fn check_stepped<T: Real>(
    out: Result<(), StepError>,
    s: &State<T>,
    before: &State<T>,
    time_before: Option<T>,
    (time, energy): (Option<T>, Option<T>),
) {
    match out {
        Ok(()) => {
            assert!(finite(s), "non-finite state from Ok");
            assert!(
                time.is_none_or(|t| t.is_finite()),
                "non-finite time from Ok"
            );
            assert!(
                energy.is_none_or(|e| e == e),
                "NaN total energy for a finite state"
            );
        }
        Err(_) => {
            assert!(
                same(&s.m, &before.m) && same(&s.q, &before.q),
                "state changed on Err"
            );
            assert!(time_kept(time, time_before), "time changed on Err");
        }
    }
}

/// The clock (if the integrator has one) is bitwise what it was.
fn time_kept<T: Real>(now: Option<T>, before: Option<T>) -> bool {
    match (now, before) {
        (Some(a), Some(b)) => same(&[a], &[b]),
        (None, None) => true,
        _ => false,
    }
}

fn finite<T: Real>(s: &State<T>) -> bool {
    s.m.iter().chain(s.q.iter()).all(|x| x.is_finite())
}

fn vec3<T: Real>(r: &mut Reader) -> [T; 3] {
    [r.number(), r.number(), r.number()].map(T::from_f64)
}

/// A value near `x`: relative change `i8 / 1000` (a jittering clock, a filter's correction),
/// or a value from the bytes (anything, NaN included).
fn nudged<T: Real>(r: &mut Reader, x: T) -> T {
    if r.pick() % 4 == 0 {
        T::from_f64(r.number())
    } else {
        x * (T::ONE + T::from_f64(r.pick() as i8 as f64 / 1000.0))
    }
}

/// Up to 12 calls on `a`, picked by the bytes; checks every outcome (see the module docs).
fn drive<T: Real, I: Loop<T>>(mut a: I, r: &mut Reader, m: [T; 3], q: [T; 4]) -> Tally {
    let mut tally = [0u32; 7];
    let mut s = State::new(m, q);
    let mut mm = m;
    for _ in 0..12 {
        let before = (s, mm, a.time());
        let op = r.pick() % 8;
        match op {
            0..=2 => {
                let out = a.step_state(&mut s);
                tally[kind(&out)] += 1;
                let after = (a.time(), a.energy(&s));
                check_stepped(out, &s, &before.0, before.2, after);
            }
            3 => {
                let out = a.step(&mut mm);
                tally[kind(&out)] += 1;
                match out {
                    Ok(()) => assert!(
                        mm.iter().all(|x| x.is_finite()),
                        "non-finite momentum from Ok"
                    ),
                    Err(_) => {
                        assert!(same(&mm, &before.1), "momentum changed on Err");
                        assert!(time_kept(a.time(), before.2), "time changed on Err");
                    }
                }
            }
            4 => {
                let h = nudged(r, a.step_size());
                a.set_step_size(h);
            }
            5 => {
                // a filter's correction of the momentum, or a new one
                let k = (r.pick() % 3) as usize;
                s.m[k] = nudged(r, s.m[k]);
                mm[k] = nudged(r, mm[k]);
            }
            6 => {
                let h_r = vec3::<T>(r);
                let old = a.energy(&s);
                if let Some(Err(_)) = a.set_rotor(h_r) {
                    let new = a.energy(&s);
                    assert!(
                        same(&[old.unwrap_or(T::ZERO)], &[new.unwrap_or(T::ZERO)]),
                        "rotor changed on Err"
                    );
                }
            }
            _ => {
                if r.pick() % 2 == 0 {
                    let t = T::from_f64(r.number());
                    if let Some(out) = a.set_time(t) {
                        let now = a.time().unwrap_or(T::ZERO);
                        match out {
                            Ok(()) => assert!(now == t, "time not set"),
                            Err(_) => {
                                assert!(!t.is_finite(), "finite time refused");
                                assert!(time_kept(a.time(), before.2), "time changed on Err");
                            }
                        }
                    }
                } else {
                    let (t0, t1) = (vec3::<T>(r), vec3::<T>(r));
                    if let Some(out) = a.step_with(&mut s, t0, t1) {
                        tally[kind(&out)] += 1;
                        let after = (a.time(), a.energy(&s));
                        check_stepped(out, &s, &before.0, before.2, after);
                    }
                }
            }
        }
    }
    tally
}

/// A model seen through a closure: no closed-form turn rate, so the force-gradient kick
/// evaluates it once more at a turned attitude.
#[derive(Clone, Copy, Debug)]
pub struct Opaque<F>(pub F);

impl<T: Real, F: Torque<T>> Torque<T> for Opaque<F> {
    fn torque(&self, t: T, q: &[T; 4]) -> [T; 3] {
        self.0.torque(t, q)
    }
    fn potential(&self, t: T, q: &[T; 4]) -> Option<T> {
        self.0.potential(t, q)
    }
    fn depends_on_attitude(&self) -> bool {
        self.0.depends_on_attitude()
    }
    fn is_zero(&self) -> bool {
        self.0.is_zero()
    }
    fn turn_rate(&self, _t: T, _q: &[T; 4], _w: [T; 3]) -> Option<[T; 3]> {
        None
    }
}

/// [`drive`] of `Composed::force_gradient` around `drift`, with the model's turn rates or
/// (`opaque`) without them.
fn force_gradient<T: Real, D: Integrator<T> + Clone>(
    drift: D,
    tq: AnyTorque<T>,
    opaque: bool,
    r: &mut Reader,
    m: [T; 3],
    q: [T; 4],
) -> Option<Tally> {
    Some(if opaque {
        drive(Composed::force_gradient(drift, Opaque(tq)).ok()?, r, m, q)
    } else {
        drive(Composed::force_gradient(drift, tq).ok()?, r, m, q)
    })
}

fn torque<T: Real>(r: &mut Reader, inertia: [T; 3]) -> AnyTorque<T> {
    let c = |x: f64| T::from_f64(x);
    match r.pick() % 4 {
        0 => AnyTorque::Constant(ConstantTorque(vec3(r))),
        1 => AnyTorque::Periodic(PeriodicTorque {
            amplitude: vec3(r),
            freq: vec3(r),
            phase: vec3(r),
        }),
        2 => AnyTorque::Gravity(Gravity {
            mg: c(r.number()),
            com: vec3(r),
        }),
        _ => AnyTorque::Gradient(GravityGradient {
            k: c(r.number()),
            n: c(r.number()),
            inertia,
        }),
    }
}

fn all<T: Real>(r: &mut Reader, method: u8) -> Option<Tally> {
    let i = vec3::<T>(r);
    // most inputs through the mass matrix with |J| (valid bodies), so that the loop, not the
    // validation, sees them; steps mostly of a loop's size
    let body = if r.pick() % 4 == 0 {
        Body::from_inertia(i)
    } else {
        Body::from_mass_matrix(i.map(|x| x.abs()))
    };
    let body = body.ok()?;
    let m = vec3::<T>(r);
    let q = [r.number(), r.number(), r.number(), r.number()].map(T::from_f64);
    let h = T::from_f64(r.number() * 0.01);
    let tq = torque(r, body.inertia());
    let order = 4 + 2 * (r.pick() % 4);
    let composed_order = 4 + 2 * (r.pick() % 2);
    Some(match method as usize % LOOP_METHODS.len() {
        0 => drive(Forced::new(Mv::new(body, h), tq), r, m, q),
        1 => drive(Forced::new(PreMv::new(body, h, order).ok()?, tq), r, m, q),
        2 => drive(Forced::new(Splitting::new(body, h), tq), r, m, q),
        3 => drive(Forced::new(Midpoint::new(body, h), tq), r, m, q),
        4 => drive(ForcedRk4::new(body, h, tq), r, m, q),
        5 => drive(
            Composed::new(Mv::new(body, h), tq, composed_order).ok()?,
            r,
            m,
            q,
        ),
        6 => drive(
            Composed::nystrom(PreMv::new(body, h, 10).ok()?, tq, composed_order).ok()?,
            r,
            m,
            q,
        ),
        7 => drive(Mv::new(body, h), r, m, q),
        8 => drive(PreMv::new(body, h, order).ok()?, r, m, q),
        9 => drive(RetimedMv::new(body, h, 2).ok()?, r, m, q),
        // the models' turn rates or a turned evaluation, around PreMv or the exact flow
        _ => {
            let pick = r.pick() % 4;
            let opaque = pick % 2 == 1;
            if pick < 2 {
                force_gradient(PreMv::new(body, h, 6).ok()?, tq, opaque, r, m, q)?
            } else {
                force_gradient(Exact::new(body, h), tq, opaque, r, m, q)?
            }
        }
    })
}

/// One input for the `loop` target: any method, f32 or f64. Returns the method selector and
/// the outcomes, or `None` when the bytes make no valid body or constructor.
pub fn check_loop(data: &[u8]) -> Option<(usize, Tally)> {
    by_precision(data, LOOP_METHODS.len(), all::<f64>, all::<f32>)
}
