//! The common interface of every method, and the full state.

use crate::error::StepError;
use crate::linalg::{Quat, Vec3};
use crate::real::Real;

/// Body angular momentum and attitude.
///
/// `m` is the angular momentum in the body frame; `q = (w, x, y, z)` is the unit quaternion
/// that maps body to space (`x_space = R(q) x_body`), so the spatial momentum `R(q) m` is
/// constant under the free motion.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct State<T> {
    /// Body angular momentum.
    pub m: [T; 3],
    /// Attitude quaternion `(w, x, y, z)`, body to space.
    pub q: [T; 4],
}

impl<T: Real> State<T> {
    /// A state with attitude `q` (not normalised here; steps check and normalise).
    pub fn new(m: [T; 3], q: [T; 4]) -> Self {
        Self { m, q }
    }

    /// The spatial angular momentum `pi = R(q) m`, conserved exactly by the flow and, to
    /// round-off, by the DMV and splitting methods.
    pub fn spatial_momentum(&self) -> [T; 3] {
        Quat::from_array(self.q)
            .rotate(Vec3::from_array(self.m))
            .to_array()
    }
}

/// A one-step method for the free rigid body with a fixed step size.
///
/// Both methods leave the state untouched when they return `Err`, and never produce NaN.
pub trait Integrator<T> {
    /// Advances the body angular momentum by one step (momentum-only scenes: attitude is not
    /// computed, and costs nothing).
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError>;

    /// Advances momentum and attitude by one step.
    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError>;

    /// The step size `h`.
    fn step_size(&self) -> T;
}

/// Checks a state before a step: finite entries and a non-zero quaternion. Returns the
/// momentum and the normalised attitude.
pub(crate) fn checked_state<T: Real>(s: &State<T>) -> Result<(Vec3<T>, Quat<T>), StepError> {
    let m = Vec3::from_array(s.m);
    if !m.is_finite() {
        return Err(StepError::NonFinite);
    }
    let (q, ok) = Quat::from_array(s.q).normalize();
    if !ok {
        return Err(StepError::NonFinite);
    }
    Ok((m, q))
}

/// Checks a momentum before a step.
pub(crate) fn checked_momentum<T: Real>(m: &[T; 3]) -> Result<Vec3<T>, StepError> {
    let v = Vec3::from_array(*m);
    if v.is_finite() {
        Ok(v)
    } else {
        Err(StepError::NonFinite)
    }
}
