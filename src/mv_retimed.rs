//! `RetimedMv`: the DMV step with its step size chosen so that its iterates land on the exact
//! orbit exactly at the requested times (docs/MATH.md §2, §5).
//!
//! DMV's only error is in time: its iterates lie on the exact momentum orbit at times
//! `n tau(h')`, `tau(h') = h' (1 + tau_3 h'^2 + ...)`, with `tau` constant along a trajectory.
//! So at set-up the step `h'` with `tau(h') = h` is found from the exact solution (a secant
//! iteration on `h'`, each trial a DMV step whose exact time is found by a second secant
//! iteration along the orbit), and every step after that is an ordinary DMV step of size `h'`:
//! the momentum is exact to round-off at DMV's cost per step.
//!
//! The attitude is not only late but also turned about the spatial momentum by an `O(h^2)`
//! angle that retiming cannot remove, so a retimed order-2 DMV has `q` still at order 2. On top
//! of preprocessing ([`crate::PreMv`]) the same retiming takes `m` to round-off and leaves `q`
//! at the preprocessed order: `RetimedMv::new(body, h, 10)` is exact in `m` and order 10 in `q`.

use crate::body::Body;
use crate::error::StepError;
use crate::exact::Exact;
use crate::integrator::{checked_momentum, Integrator, State};
use crate::linalg::Vec3;
use crate::mv_pre::PreMv;
use crate::real::{c, Real};

/// DMV (plain or preprocessed to `order`) retimed so that the momentum is exact at `t = n h`.
///
/// Set-up (at the first step and whenever the momentum is not the one returned last): about
/// 30 evaluations of the exact solution (a few microseconds on a desktop). Per step: exactly an
/// [`crate::Mv`] step (150 flops, no sqrt, no trigonometry). Accuracy: `m` to round-off at the
/// requested times (the set-up solves `tau(h') = h` to `8 eps`, so the phase error grows as
/// `8 eps n`); `q` at the order of the underlying DMV. On an equilibrium (momentum on a
/// principal axis, or zero) there is no time to match and `h' = h`.
#[derive(Clone, Debug)]
pub struct RetimedMv<T> {
    body: Body<T>,
    h: T,
    order: u8,
    /// The DMV with the retimed step, stepped in place; valid while it follows the momentum.
    inner: PreMv<T>,
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
            order,
            inner: PreMv::new(body, h, order)?,
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
        retime(&self.body, self.h, self.order, m)
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
        let h = retime(&self.body, self.h, self.order, m)?;
        self.inner = PreMv::new(self.body, h, self.order)?;
        Ok(())
    }
}

/// Time `tau` at which the exact orbit from `m0` reaches `m1` (which lies on it), near `guess`:
/// secant on the component of `m(tau) - m1` along the orbit's tangent at `m1`.
fn exact_time<T: Real>(body: &Body<T>, m0: &[T; 3], m1: &[T; 3], guess: T) -> Result<T, StepError> {
    let w = body.angular_velocity(m1);
    let v1 = Vec3::from_array(*m1);
    let tangent = v1.cross(Vec3::from_array(w));
    let f = |tau: T| -> Result<T, StepError> {
        let m = Vec3::from_array(Exact::momentum_at(body, m0, tau)?);
        Ok(m.sub(v1).dot(tangent))
    };
    let (mut t0, mut t1) = (guess, guess * c::<T>(1.0 + 1e-3));
    let (mut f0, mut f1) = (f(t0)?, f(t1)?);
    let mut k = 0;
    while k < 30 && f1 != f0 && (t1 - t0).abs() > c::<T>(2.0) * T::EPSILON * t1.abs() {
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

fn retime<T: Real>(body: &Body<T>, h: T, order: u8, m: &[T; 3]) -> Result<T, StepError> {
    let v = checked_momentum(m)?;
    if !h.is_finite() {
        return Err(StepError::NonFinite);
    }
    // an equilibrium (or m = 0) has no phase: nothing to retime
    let w = Vec3::from_array(body.angular_velocity(m));
    if !(v.cross(w).max_abs() > c::<T>(1e3) * T::EPSILON * v.max_abs() * w.max_abs()) {
        return Ok(h);
    }
    // tau(h') - h by one DMV step and the exact time of its result
    let tau = |hp: T| -> Result<T, StepError> {
        let mut m1 = *m;
        PreMv::new(*body, hp, order)?.step(&mut m1)?;
        exact_time(body, m, &m1, hp)
    };
    let (mut a, mut b) = (h, h * c::<T>(0.99));
    let (mut fa, mut fb) = (tau(a)? - h, tau(b)? - h);
    let mut k = 0;
    while k < 30 && fb != fa && (b - a).abs() > c::<T>(8.0) * T::EPSILON * b.abs() {
        let next = b - fb * (b - a) / (fb - fa);
        a = b;
        fa = fb;
        b = next;
        fb = tau(b)? - h;
        k += 1;
    }
    if b.is_finite() && b != T::ZERO {
        Ok(b)
    } else {
        Err(StepError::NoConvergence)
    }
}

impl<T: Real> Integrator<T> for RetimedMv<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        self.prepare(m)?;
        self.inner.step(m)
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        self.prepare(&s.m)?;
        self.inner.step_state(s)
    }

    fn step_size(&self) -> T {
        self.h
    }

    /// Changes the step size; the retimed step is solved again at the next step.
    fn set_step_size(&mut self, h: T) {
        self.h = h;
        self.inner.reset();
    }

    fn body(&self) -> &Body<T> {
        &self.body
    }

    fn reset(&mut self) {
        self.inner.reset();
    }
}
