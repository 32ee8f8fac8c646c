//! `Orbit`: the exact trajectory through one initial state, set up once and evaluated at any
//! time (for analysts: dense output, references, event location, plots).

use crate::body::Body;
use crate::error::StepError;
use crate::exact::{finish, Orbit as Flow};
use crate::integrator::{checked_unit_state, State};
use crate::linalg::Quat;
use crate::real::Real;

/// The exact trajectory of the free rigid body through an initial state: momentum and
/// attitude at any time `t` (either sign) from one set-up.
///
/// The set-up ([`Orbit::new`]) does the work that does not depend on `t`: sorting the axes,
/// the modulus and frequency of the Jacobi elliptic functions, the complete integrals `K` and
/// `R_J`, the phase at `t = 0` (Carlson's `R_F`) and the initial attitude's frame (Landau &
/// Lifshitz §37 for `m`, after van Zon & Schofield 2007 for `q`; docs/MATH.md §6).
/// Each evaluation is then one `sn, cn, dn` for the momentum ([`Orbit::momentum_at`], about
/// 60 flops and 7 square roots), plus one `R_J` and a `sin`/`cos` for the attitude
/// ([`Orbit::at`]), with no re-solving: it is what [`crate::Exact::at`] costs less the set-up.
///
/// Accuracy: that of [`crate::Exact`] (f64: `|m - m_ref| <= 3.2e-14 max(1, |m_ref|)`,
/// `|q - q_ref| <= 3.7e-14` against 34-digit references at `t` up to 100; near the
/// separatrix, for nearly symmetric bodies and for thin rods see the exceptions there). [`Orbit::at`] is
/// bit-identical to `Exact::at(body, s0, t)`. Quaternions are `[w, x, y, z]`, body to space;
/// `q(t)` is continuous in `t` and `q(0)` is the initial attitude (normalised).
///
/// ```
/// use rigid3::{Body, Orbit, State};
///
/// let body = Body::<f64>::from_inertia([0.6, 0.8, 1.0]).unwrap();
/// let orbit = Orbit::new(&body, &State::new([1.8, 0.4, -0.9], [1.0, 0.0, 0.0, 0.0])).unwrap();
/// let pi0 = orbit.initial().spatial_momentum();
/// for k in 0..100 {
///     let s = orbit.at(0.1 * k as f64).unwrap();
///     let pi = s.spatial_momentum();
///     assert!((pi[0] - pi0[0]).abs() < 1e-13 && (pi[2] - pi0[2]).abs() < 1e-13);
/// }
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Orbit<T> {
    body: Body<T>,
    flow: Flow<T>,
    /// The initial attitude, normalised as the steps normalise it.
    q0: Quat<T>,
    /// The initial state as given.
    s0: State<T>,
}

impl<T: Real> Orbit<T> {
    /// Sets up the trajectory of `body` through `s0` (at `t = 0`; `s0.q = [w, x, y, z]`, body
    /// to space, normalised here if it is off unit length).
    ///
    /// # Errors
    ///
    /// `NonFinite` for a non-finite entry or a zero quaternion, `Overflow` if `|m|` or
    /// `|m| / I` overflows.
    pub fn new(body: &Body<T>, s0: &State<T>) -> Result<Self, StepError> {
        let (m, q0) = checked_unit_state(s0)?;
        Ok(Self {
            body: *body,
            flow: Flow::new(body, m, true)?,
            q0,
            s0: *s0,
        })
    }

    /// The exact state at time `t` (any sign).
    ///
    /// # Errors
    ///
    /// `NonFinite` for a non-finite `t`; `StepTooLarge` when `t` is so large that the phase
    /// (`omega t`, more than `1 / (8 eps)` periods of the momentum) has no significant digit
    /// left; `Degenerate`
    /// if the result is not finite.
    pub fn at(&self, t: T) -> Result<State<T>, StepError> {
        if !t.is_finite() {
            return Err(StepError::NonFinite);
        }
        let (m, q) = self.flow.eval(Some(self.q0), t)?;
        let q = q.ok_or(StepError::Degenerate)?;
        finish(m, Some(q)).map(|(m, q)| State::new(m, q))
    }

    /// The exact body momentum at time `t` (any sign), without the attitude's cost.
    ///
    /// # Errors
    ///
    /// As [`Orbit::at`].
    pub fn momentum_at(&self, t: T) -> Result<[T; 3], StepError> {
        if !t.is_finite() {
            return Err(StepError::NonFinite);
        }
        let (m, _) = self.flow.eval(None, t)?;
        finish(m, None).map(|(m, _)| m)
    }

    /// The initial state, as given to [`Orbit::new`].
    #[must_use]
    pub fn initial(&self) -> State<T> {
        self.s0
    }

    /// The body.
    #[must_use]
    pub fn body(&self) -> &Body<T> {
        &self.body
    }
}
