//! `RetimedMv`: the DMV step with its step size chosen so that its iterates land on the exact
//! orbit exactly at the requested times (docs/MATH.md §2, §5).
//!
//! DMV's only error is in time: its iterates lie on the exact momentum orbit at times
//! `n tau(h')`, `tau(h') = h' (1 + tau_3 h'^2 + ...)`, with `tau` constant along a trajectory.
//! So at set-up the step `h'` with `tau(h') = h` is found from the exact solution (a Newton
//! step and secant steps on `h'`, each trial a DMV step whose exact time is found by a Newton
//! step and secant steps along the orbit, set up once), and every step after that is an
//! ordinary DMV step of size `h'`: the momentum is exact to round-off at DMV's cost per step.
//! After an outside change of `m` or `h` the solve starts from the last `h' / h`.
//!
//! The attitude is not only late but also turned about the spatial momentum by an `O(h^2)`
//! angle that retiming cannot remove, so a retimed order-2 DMV has `q` still at order 2. On top
//! of preprocessing ([`crate::PreMv`]) the same retiming takes `m` to round-off and leaves `q`
//! at the preprocessed order: `RetimedMv::new(body, h, 10)` is exact in `m` and order 10 in `q`.

use crate::body::Body;
use crate::error::StepError;
use crate::exact::Orbit as Flow;
use crate::integrator::{checked_momentum, Integrator, State};
use crate::linalg::Vec3;
use crate::mv_pre::PreMv;
use crate::real::{c, Real};

/// DMV (plain or preprocessed to `order`) retimed so that the momentum is exact at `t = n h`.
///
/// Set-up (at the first step and whenever the momentum is not the one returned last, or the
/// step size changed): the exact orbit is set up once ([`crate::Orbit`]) and the retiming
/// equation solved by a Newton step and secant steps, each trial a DMV step and a few
/// evaluations of the Jacobi functions. After an outside change of `m` or `h` the last ratio
/// `h' / h` starts the solve and one or two trials suffice: on the host 19–47x a free-running
/// step (f32 and f64, `rigid3-lab loop-cost`), where rebuilding from scratch was about 600x.
/// Per step: exactly an [`crate::Mv`] step (78 flops free running, no sqrt, no trigonometry),
/// and at steps 64, 512, 4096, ... after a set-up one evaluation of the exact time (83 flops a
/// step averaged over the first 100).
/// Accuracy: `m` to round-off at the requested times. The set-up solves `tau(h') = h` only as
/// precisely as the exact time of one step can be evaluated (a few `eps / |Omega|`), an error
/// that repeats every step; after 64, 512, 4096, ... free-running steps `h'` is refined from
/// the phase gained, and the phase gained is absorbed by the next step (talk's
/// case, order 2, `h = 0.1`: `m` off by `1.8e-15` at `t = 10` and `7.7e-15` at `t = 100`
/// against the mpmath reference; without the refinement `3.8e-13` at `t = 10`). `q` at the
/// order of the underlying DMV. On an equilibrium (momentum on a
/// principal axis, or zero) there is no time to match and `h' = h`.
#[derive(Clone, Debug)]
pub struct RetimedMv<T> {
    body: Body<T>,
    h: T,
    /// The DMV with the retimed step, stepped in place; valid while it follows the momentum.
    inner: PreMv<T>,
    /// `h' / h` of the last retiming: the start of the next one after an outside change of
    /// `m` or `h` (the ratio depends on the invariants and `h` smoothly, so a small change
    /// leaves it close and the secant needs three evaluations of the exact time, not seven).
    ratio: Option<T>,
    /// The refinement of `h'` from the phase the steps have gained ([`PhaseCheck`]); `None`
    /// before the first retiming and on an equilibrium.
    check: Option<PhaseCheck<T>>,
}

/// Free-running steps after a retiming at which `h'` is first refined (then after 8x as many,
/// 64x, ...): see [`PhaseCheck`].
const FIRST_CHECK: u32 = 64;

/// The retiming solves `tau(h') = h` only as precisely as the exact time of one step can be
/// evaluated (a few `eps / |Omega|`), and that error repeats every step: on the talk's case
/// (order 2, `h = 0.1`) `m` was `3.8e-13` off at `t = 10`. After `n` free-running steps the
/// exact time of the momentum reached, `tau_n`, is known to the same few `eps`, so
/// `h' n h / tau_n` is `n` times more precise; the next step absorbs the phase already gained
/// (exact time `h - (tau_n - n h)`), and the steps after it run with the refined `h'`. One
/// evaluation of the exact time at steps 64, 512, 4096, ...: nothing in a loop that changes
/// the state every tick (each change retimes afresh).
#[derive(Clone, Copy, Debug)]
struct PhaseCheck<T> {
    /// The momentum's exact orbit from where the retiming started.
    orbit: Flow<T>,
    /// Steps taken since then, and the count at the next refinement.
    steps: u32,
    next: u32,
    /// The refined `h'`, set after the step that absorbs the phase.
    resume: Option<T>,
}

impl<T: Real> RetimedMv<T> {
    /// A retimed DMV of `order` (2: plain DMV; 4, 6, 8 or 10: preprocessed) with step `h`.
    ///
    /// # Errors
    ///
    /// [`StepError::InvalidOrder`] for any other order, as [`PreMv::new`].
    pub fn new(body: Body<T>, h: T, order: u8) -> Result<Self, StepError> {
        Ok(Self {
            body,
            h,
            inner: PreMv::new(body, h, order)?,
            ratio: None,
            check: None,
        })
    }

    /// The DMV step `h'` whose exact time is `h` from momentum `m`.
    ///
    /// # Errors
    ///
    /// [`StepError::NonFinite`] for a non-finite `m` or `h`, the errors of the DMV steps it
    /// tries (past the existence limit: [`StepError::StepTooLarge`]), and
    /// [`StepError::NoConvergence`] when the secant iteration for `h'` fails.
    pub fn retimed_step(&self, m: &[T; 3]) -> Result<T, StepError> {
        Ok(retime(&self.inner, self.h, m, None)?.0)
    }

    #[inline(always)]
    fn prepare(&mut self, m: &[T; 3]) -> Result<(), StepError> {
        if !self.inner.follows(m) {
            self.rebuild(m)?;
        }
        Ok(())
    }

    #[cold]
    #[inline(never)]
    fn rebuild(&mut self, m: &[T; 3]) -> Result<(), StepError> {
        let (h, orbit) = retime(&self.inner, self.h, m, self.ratio)?;
        self.inner = self.inner.restarted(h);
        self.ratio = Some(h / self.h);
        self.check = orbit.map(|orbit| PhaseCheck {
            orbit,
            steps: 0,
            next: FIRST_CHECK,
            resume: None,
        });
        Ok(())
    }

    /// Counts a successful step that ended at momentum `m`, and refines `h'` when due
    /// ([`PhaseCheck`]).
    #[inline(always)]
    fn count_step(&mut self, m: &[T; 3]) {
        let Some(check) = self.check.as_mut() else {
            return;
        };
        check.steps = check.steps.saturating_add(1);
        if let Some(hp) = check.resume.take() {
            self.inner.set_step_size(hp);
        } else if check.steps == check.next && check.next != u32::MAX {
            // (the count saturates after 2^32 steps: no check from then on)
            self.refine(m);
        }
    }

    /// The refinement of [`PhaseCheck`] at momentum `m`; nothing changes if the exact time
    /// cannot be found or the correction is not small.
    #[cold]
    #[inline(never)]
    fn refine(&mut self, m: &[T; 3]) {
        let Some(check) = self.check.as_mut() else {
            return;
        };
        check.next = check.next.saturating_mul(8);
        let target = c::<T>(f64::from(check.steps)) * self.h;
        let Ok(tau) = exact_time(&self.body, &check.orbit, m, target) else {
            return;
        };
        let gained = tau - target;
        let hp = self.inner.step_size();
        let refined = hp * (target / tau);
        let absorb = refined * ((self.h - gained) / self.h);
        // a correction at round-off level; anything larger means the check is not valid
        let small = (gained / self.h).abs() <= c::<T>(1e-6);
        if small && refined.is_finite() && absorb.is_finite() {
            self.inner.set_step_size(absorb);
            check.resume = Some(refined);
            self.ratio = Some(refined / self.h);
        }
    }
}

/// Time `tau` at which the exact orbit from `m0` reaches `m1` (which lies on it), near `guess`:
/// secant on the component of `m(tau) - m1` along the orbit's tangent at `m1`. The orbit is
/// set up once by the caller (the momentum part of [`crate::Orbit`]: elliptic modulus, periods
/// and phase, none of the attitude's constants), so each trial
/// time costs one evaluation of the Jacobi functions.
fn exact_time<T: Real>(
    body: &Body<T>,
    orbit: &Flow<T>,
    m1: &[T; 3],
    guess: T,
) -> Result<T, StepError> {
    let w = body.angular_velocity(m1);
    let v1 = Vec3::from_array(*m1);
    let tangent = v1.cross(Vec3::from_array(w));
    let f = |tau: T| -> Result<T, StepError> {
        if !tau.is_finite() {
            return Err(StepError::NonFinite);
        }
        let (m, _) = orbit.eval(None, tau)?;
        if !m.is_finite() {
            return Err(StepError::Degenerate);
        }
        Ok(m.sub(v1).dot(tangent))
    };
    // f'(tau) = (m x Omega) . tangent, which is |tangent|^2 at the solution: a Newton step with
    // that slope first, then secant steps; done when f is at its round-off floor (the
    // momentum's ulps along the tangent), which leaves m(tau) - m1 at round-off
    let slope = tangent.norm2();
    let floor = c::<T>(8.0) * T::EPSILON * v1.max_abs() * tangent.max_abs();
    let (mut t0, mut f0) = (guess, f(guess)?);
    if f0.abs() <= floor || !(slope > T::ZERO) {
        return Ok(t0);
    }
    let mut t1 = t0 - f0 / slope;
    let mut f1 = f(t1)?;
    let mut k = 0;
    while k < 30
        && f1 != f0
        && f1.abs() > floor
        && (t1 - t0).abs() > c::<T>(2.0) * T::EPSILON * t1.abs()
    {
        let t2 = t1 - f1 * (t1 - t0) / (f1 - f0);
        t0 = t1;
        f0 = f1;
        t1 = t2;
        f1 = f(t1)?;
        k += 1;
    }
    if t1.is_finite() {
        Ok(t1)
    } else {
        Err(StepError::NoConvergence)
    }
}

/// The step `h'` with `tau(h') = h`: a Newton step from `h`, or, given the ratio `h' / h` of an
/// earlier retiming (`warm`), from that guess (after a small change of `m` or `h` it lands at
/// round-off), then secant steps.
/// Returns `h'` and the momentum's exact orbit from `m` (`None` on an equilibrium).
fn retime<T: Real>(
    template: &PreMv<T>,
    h: T,
    m: &[T; 3],
    warm: Option<T>,
) -> Result<(T, Option<Flow<T>>), StepError> {
    let body = template.body();
    let v = checked_momentum(m)?;
    if !h.is_finite() {
        return Err(StepError::NonFinite);
    }
    // an equilibrium (or m = 0) has no phase: nothing to retime
    let w = Vec3::from_array(body.angular_velocity(m));
    if !(v.cross(w).max_abs() > c::<T>(1e3) * T::EPSILON * v.max_abs() * w.max_abs()) {
        return Ok((h, None));
    }
    // tau(h') - h by one DMV step and the exact time of its result
    // the momentum's orbit only: the attitude's constants (an elliptic integral of the third
    // kind) were a sixth of a re-solve
    let orbit = Flow::new(body, v, false)?;
    let tau = |hp: T| -> Result<T, StepError> {
        let mut m1 = *m;
        // a restarted copy of the integrator: the modified moments' tables are the body's and
        // are not computed again (building a PreMv per trial step did, every time)
        template.restarted(hp).step(&mut m1)?;
        // near the solution the exact time is h itself (hp is off by tau_3 h^3)
        exact_time(body, &orbit, &m1, h)
    };
    // the warm start, or h itself
    let mut a = match warm {
        Some(r) if r.is_finite() && r > c::<T>(0.5) && r < c::<T>(2.0) => h * r,
        _ => h,
    };
    let mut fa = tau(a)? - h;
    // converged when the residual is at round-off (`h'` is off by about the residual:
    // `tau' ~ 1`) or the step between iterates is
    let tol = c::<T>(4.0) * T::EPSILON * h.abs();
    let done = |fx: T| fx.abs() <= tol;
    if done(fa) {
        return Ok((a, Some(orbit)));
    }
    // a Newton step first: tau(h') = h' (1 + tau_3 h'^2 + ...), so tau' is about
    // 1 + 3 (tau(a) / a - 1), from the same evaluation
    let slope = T::ONE + c::<T>(3.0) * ((fa + h) / a - T::ONE);
    let mut b = a - fa / slope;
    let mut fb = tau(b)? - h;
    let mut k = 0;
    while k < 30 && fb != fa && (b - a).abs() > c::<T>(8.0) * T::EPSILON * b.abs() && !done(fb) {
        let next = b - fb * (b - a) / (fb - fa);
        a = b;
        fa = fb;
        b = next;
        fb = tau(b)? - h;
        k += 1;
    }
    if b.is_finite() && b != T::ZERO {
        Ok((b, Some(orbit)))
    } else {
        Err(StepError::NoConvergence)
    }
}

impl<T: Real> Integrator<T> for RetimedMv<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        self.prepare(m)?;
        self.inner.step(m)?;
        self.count_step(m);
        Ok(())
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        self.prepare(&s.m)?;
        self.inner.step_state(s)?;
        self.count_step(&s.m);
        Ok(())
    }

    fn step_size(&self) -> T {
        self.h
    }

    /// Changes the step size; the retimed step is solved again at the next step.
    fn set_step_size(&mut self, h: T) {
        self.h = h;
        self.inner.reset();
        self.check = None;
    }

    fn body(&self) -> &Body<T> {
        &self.body
    }

    fn reset(&mut self) {
        self.inner.reset();
        self.check = None;
    }
}
