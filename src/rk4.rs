//! The classical fourth-order Runge–Kutta method.

use crate::body::Body;
use crate::error::StepError;
use crate::integrator::{
    checked_momentum, checked_state, in_homogeneous_units, unscaled, write_momentum, write_state,
    Integrator, State,
};
use crate::linalg::{Quat, Vec3};
use crate::real::{c, Real};

/// Classical Runge–Kutta (order 4) on `m' = m x I^-1 m` and, with attitude, on
/// `q' = 1/2 q (x) (0, I^-1 m)`, with `q` renormalised after each step (the RK4 stages leave
/// it off unit length at `O(h^5)`).
///
/// Not structure preserving: `|m|^2`, `E` and `R(q) m` drift at `O(h^4)` per unit time, so it
/// is the accuracy-per-cost leader at short horizons and loses at long ones. Explicit, so
/// at large steps it blows up, from `h |Omega|` about 2.6 on some bodies (3 to 6 on most of
/// 300 random ones, past 15 on a few): a step whose result overflows returns
/// `StepError::Overflow` and leaves the state as it was; below that, and often well above
/// 2.8, the step stays finite but silently dissipative (the talk's case at `h |Omega| = 2.8`:
/// `|m|^2` lost 67 % over `10^5` steps, every step `Ok`). At momenta outside `[2^-40, 2^40]`
/// (about `1e-12` to `1e12`) the step runs on `m` scaled by a power of two and `h` by its
/// inverse, the same motion (Euler's equations are quadratic in `m`), so in f32 `m x I^-1 m`
/// does not underflow to a step that leaves `m` as it was (it did at `|m| = 1e-25`); inside,
/// bit for bit the plain step. The scale is chosen from `m` alone: with moments far from one
/// as well the products can still leave the range (f32, moments `1e30`, `|m| = 1e-8`: `m`
/// unchanged; moments `1e20`, `|m| = 1e-11`: 2e-4 off), so keep f32 units near one.
#[derive(Clone, Debug)]
pub struct Rk4<T> {
    body: Body<T>,
    inv_i: Vec3<T>,
    h: T,
}

impl<T: Real> Rk4<T> {
    /// An RK4 integrator for `body` with step `h`.
    #[must_use]
    pub fn new(body: Body<T>, h: T) -> Self {
        Self {
            body,
            inv_i: body.inverse_inertia(),
            h,
        }
    }

    #[inline]
    fn f(&self, m: Vec3<T>) -> Vec3<T> {
        m.cross(m.mul_elem(self.inv_i))
    }

    #[inline]
    fn g(&self, m: Vec3<T>, q: Quat<T>) -> Quat<T> {
        attitude_rate(q, m.mul_elem(self.inv_i))
    }
}

/// `q' = 1/2 q (x) (0, omega)`: the attitude's rate for the body angular velocity `omega`
/// (shared with [`crate::ForcedRk4`]).
#[inline]
pub(crate) fn attitude_rate<T: Real>(q: Quat<T>, omega: Vec3<T>) -> Quat<T> {
    let w = omega.scale(c::<T>(0.5));
    q.mul(Quat {
        w: T::ZERO,
        x: w.x,
        y: w.y,
        z: w.z,
    })
}

/// `q + k d`, componentwise: an RK4 stage of the attitude (shared with [`crate::ForcedRk4`]).
pub(crate) fn axpy<T: Real>(q: Quat<T>, k: T, d: Quat<T>) -> Quat<T> {
    Quat {
        w: q.w + k * d.w,
        x: q.x + k * d.x,
        y: q.y + k * d.y,
        z: q.z + k * d.z,
    }
}

impl<T: Real> Integrator<T> for Rk4<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        if !self.h.is_finite() {
            return Err(StepError::NonFinite);
        }
        let v = checked_momentum(m)?;
        // at momenta whose products leave the range, the same motion in other units
        // (crate::integrator's homogeneous_scale: bit for bit the plain step in range)
        let (v, h, scale) = in_homogeneous_units(v, self.h)?;
        let hh = h * c::<T>(0.5);
        let k1 = self.f(v);
        let k2 = self.f(v.add(k1.scale(hh)));
        let k3 = self.f(v.add(k2.scale(hh)));
        let k4 = self.f(v.add(k3.scale(h)));
        let sum = k1.add(k4).add(k2.add(k3).scale(c::<T>(2.0)));
        let next = v.add(sum.scale(h * c::<T>(1.0 / 6.0)));
        write_momentum(m, unscaled(next, scale))
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        if !self.h.is_finite() {
            return Err(StepError::NonFinite);
        }
        let (v, q) = checked_state(s)?;
        // h = 0 leaves the state as it is (the trait's promise; the step renormalised q)
        if self.h == T::ZERO {
            return Ok(());
        }
        let (v, h, scale) = in_homogeneous_units(v, self.h)?;
        let hh = h * c::<T>(0.5);
        let k1 = self.f(v);
        let l1 = self.g(v, q);
        let (v2, q2) = (v.add(k1.scale(hh)), axpy(q, hh, l1));
        let k2 = self.f(v2);
        let l2 = self.g(v2, q2);
        let (v3, q3) = (v.add(k2.scale(hh)), axpy(q, hh, l2));
        let k3 = self.f(v3);
        let l3 = self.g(v3, q3);
        let (v4, q4) = (v.add(k3.scale(h)), axpy(q, h, l3));
        let k4 = self.f(v4);
        let l4 = self.g(v4, q4);
        let sixth = h * c::<T>(1.0 / 6.0);
        let next = v.add(k1.add(k4).add(k2.add(k3).scale(c::<T>(2.0))).scale(sixth));
        let third = h * c::<T>(1.0 / 3.0);
        let q_next = axpy(
            axpy(axpy(axpy(q, sixth, l1), third, l2), third, l3),
            sixth,
            l4,
        );
        let (q_next, ok) = q_next.normalize();
        if !ok {
            return Err(StepError::Overflow);
        }
        write_state(s, unscaled(next, scale), q_next)
    }

    fn step_size(&self) -> T {
        self.h
    }

    fn set_step_size(&mut self, h: T) {
        self.h = h;
    }

    fn body(&self) -> &Body<T> {
        &self.body
    }
}
