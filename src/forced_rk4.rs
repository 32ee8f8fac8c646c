//! Classical Runge–Kutta on the full forced equations: the baseline for the forced methods.

use crate::body::Body;
use crate::error::StepError;
use crate::integrator::{checked_momentum, checked_state, write_state, Integrator, State};
use crate::linalg::{Quat, Vec3};
use crate::real::{c, Real};
use crate::rk4::{attitude_rate, axpy};
use crate::torque::Torque;

/// RK4 (order 4) on `m' = m x Omega + tau(t, q)`, `Omega = I^-1 (m - h_r)`,
/// `q' = 1/2 q (x) (0, Omega)`, with `q` renormalised after each step.
///
/// Not structure preserving: `|m|^2`, the energy and `R(q) m` drift at `O(h^4)` per unit time.
/// Order 4 measured: the heavy top's energy error at `T = 10` falls at fourth order
/// (tests/forced.rs `rk4_total_energy_is_the_heavy_tops_and_drifts_at_fourth_order`; a
/// review measured 4.00-4.06 with time-dependent torques and a rotor); its cost per accuracy
/// against the forced rigid3 methods is in the README's `forced-work` tables (heavy top:
/// `1e-6` at `T = 10` for about 54,000 counted operations).
/// Four torque evaluations a step (at `t`, twice at `t + h/2`, at `t + h`). The time is
/// advanced by a plain sum. A step whose result overflows returns `Overflow` and leaves the
/// state as it was.
#[derive(Clone, Debug)]
pub struct ForcedRk4<T, F> {
    body: Body<T>,
    inv_i: Vec3<T>,
    h: T,
    t: T,
    rotor: Vec3<T>,
    torque: F,
}

impl<T: Real, F: Torque<T>> ForcedRk4<T, F> {
    /// RK4 for `body` with step `h` and torque model `torque`, at time zero, without rotor.
    #[must_use]
    pub fn new(body: Body<T>, h: T, torque: F) -> Self {
        Self {
            body,
            inv_i: body.inverse_inertia(),
            h,
            t: T::ZERO,
            rotor: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
            torque,
        }
    }

    /// Sets the rotor momentum `h_r` (body frame).
    ///
    /// # Errors
    ///
    /// `NonFinite` for a non-finite `h_r` (the rotor is then unchanged).
    pub fn set_rotor(&mut self, h_r: [T; 3]) -> Result<(), StepError> {
        self.rotor = checked_momentum(&h_r)?;
        Ok(())
    }

    /// The rotor momentum `h_r` (body frame).
    #[must_use]
    pub fn rotor(&self) -> [T; 3] {
        self.rotor.to_array()
    }

    /// The torque model.
    #[must_use]
    pub fn torque(&self) -> &F {
        &self.torque
    }

    /// The torque model, to change its parameters.
    pub fn torque_mut(&mut self) -> &mut F {
        &mut self.torque
    }

    /// Total energy `1/2 (m - h_r) . I^-1 (m - h_r) + V(t, q)` at the current time, or `None`
    /// when the torque has no potential or the sum is not finite (it overflows). RK4 does
    /// not conserve it: it drifts at `O(h^4)` per unit time (the forced methods' stays
    /// bounded).
    #[must_use]
    pub fn total_energy(&self, s: &State<T>) -> Option<T> {
        crate::forced::total_energy(self.inv_i, self.rotor, &self.torque, self.t, s)
    }

    /// The time of the state.
    #[must_use]
    pub fn time(&self) -> T {
        self.t
    }

    /// Sets the time (for time-dependent torques).
    ///
    /// # Errors
    ///
    /// `NonFinite` for a non-finite `t`; the time is then left as it was.
    pub fn set_time(&mut self, t: T) -> Result<(), StepError> {
        if !t.is_finite() {
            return Err(StepError::NonFinite);
        }
        self.t = t;
        Ok(())
    }

    #[inline]
    fn omega(&self, m: Vec3<T>) -> Vec3<T> {
        m.sub(self.rotor).mul_elem(self.inv_i)
    }

    /// `m'` at a stage; a non-finite torque is `NonFinite` (the model's), or `Overflow` where
    /// the stage's attitude is far from unit length (`|q|^2 > 2`: the step has blown up past
    /// RK4's stability, `h |Omega|` above about 2, and the torque overflowed on it; reported as
    /// bad input before, found by an external check: a heavy top at `h = 3`).
    #[inline]
    fn dm(&self, t: T, m: Vec3<T>, q: Quat<T>) -> Result<Vec3<T>, StepError> {
        let tau = Vec3::from_array(self.torque.torque(t, &q.to_array()));
        if !tau.is_finite() {
            return Err(if q.norm2() <= c::<T>(2.0) && m.is_finite() {
                StepError::NonFinite
            } else {
                StepError::Overflow
            });
        }
        Ok(m.cross(self.omega(m)).add(tau))
    }

    #[inline]
    fn dq(&self, m: Vec3<T>, q: Quat<T>) -> Quat<T> {
        attitude_rate(q, self.omega(m))
    }
}

impl<T: Real, F: Torque<T>> Integrator<T> for ForcedRk4<T, F> {
    /// Momentum only, for torques that do not depend on the attitude.
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        if self.torque.depends_on_attitude() {
            return Err(StepError::NeedsAttitude);
        }
        let mut s = State::new(*m, [T::ONE, T::ZERO, T::ZERO, T::ZERO]);
        self.step_state(&mut s)?;
        *m = s.m;
        Ok(())
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        if !(self.h.is_finite() && self.t.is_finite()) {
            return Err(StepError::NonFinite);
        }
        let (v, q) = checked_state(s)?;
        // h = 0 leaves the state as it is (the trait's promise; the step renormalised q)
        if self.h == T::ZERO {
            return Ok(());
        }
        let (h, hh, t) = (self.h, self.h * c::<T>(0.5), self.t);
        let end = t + h;
        if !end.is_finite() {
            return Err(StepError::Overflow);
        }
        let k1 = self.dm(t, v, q)?;
        let l1 = self.dq(v, q);
        let (v2, q2) = (v.add(k1.scale(hh)), axpy(q, hh, l1));
        let k2 = self.dm(t + hh, v2, q2)?;
        let l2 = self.dq(v2, q2);
        let (v3, q3) = (v.add(k2.scale(hh)), axpy(q, hh, l2));
        let k3 = self.dm(t + hh, v3, q3)?;
        let l3 = self.dq(v3, q3);
        let (v4, q4) = (v.add(k3.scale(h)), axpy(q, h, l3));
        let k4 = self.dm(t + h, v4, q4)?;
        let l4 = self.dq(v4, q4);
        let sixth = h * c::<T>(1.0 / 6.0);
        let third = h * c::<T>(1.0 / 3.0);
        let next = v.add(k1.add(k4).add(k2.add(k3).scale(c::<T>(2.0))).scale(sixth));
        let q_next = axpy(
            axpy(axpy(axpy(q, sixth, l1), third, l2), third, l3),
            sixth,
            l4,
        );
        let (q_next, ok) = q_next.normalize();
        if !ok {
            return Err(StepError::Overflow);
        }
        write_state(s, next, q_next)?;
        self.t = end;
        Ok(())
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
