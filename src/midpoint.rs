//! The implicit midpoint rule, solved by Newton's method (default) or fixed-point iteration.

use crate::body::Body;
use crate::error::StepError;
use crate::integrator::{
    checked_momentum, checked_state, compose_attitude, in_homogeneous_units, norms_agree, unscaled,
    write_momentum, write_state, Integrator, State,
};
use crate::linalg::{Mat3, Quat, Vec3};
use crate::real::{c, Real};

/// How [`Midpoint`] solves its implicit equation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Solver {
    /// Newton's method with the exact 3x3 Jacobian: quadratic convergence, at most 20
    /// iterations (on the talk's case it converges up to `h ~ 10`).
    Newton,
    /// Fixed-point iteration `y <- m + h/2 f(y)`: no solve, linear convergence with rate
    /// `~ h |Omega|`, at most 200 iterations (on the talk's case up to `h ~ 7`).
    FixedPoint,
}

/// The implicit midpoint rule (order 2): `m_{k+1} = m_k + h f((m_k + m_{k+1}) / 2)` with
/// `f(m) = m x I^-1 m`.
///
/// The midpoint `y` solves `y = m_k + h/2 f(y)`, by Newton or fixed point, until the update is
/// below `4 eps |y|`; a step that has not converged within the iteration limit returns
/// `StepError::NoConvergence` and leaves the state as it was. Conserves every quadratic
/// invariant (`|m|^2`, `E`) up to the solver tolerance; symmetric; error at `t = 10` on the
/// talk's case about `0.0047 h^2` (docs/MATH.md §7). At momenta outside `[2^-40, 2^40]` the
/// step is solved on `m` scaled by a power of two and `h` by its inverse, the same motion, bit
/// for bit the plain step inside (as [`crate::Rk4`], with the same limit: the scale comes from
/// `m` alone, not from the moments).
///
/// Attitude: the midpoint rule applied to `q' = 1/2 q (x) (0, Omega(y))` with the midpoint's
/// `Omega` is linear in `q` and gives the Cayley transform
/// `q_{k+1} = q_k (x) (1 + w) / (1 - w)`, `w = (0, h Omega(y) / 4)`, a unit quaternion by
/// construction (renormalised only against round-off). `R(q) m` is a cubic invariant and is
/// conserved only to the order of the method.
#[derive(Clone, Debug)]
pub struct Midpoint<T> {
    body: Body<T>,
    inv_i: Vec3<T>,
    h: T,
    solver: Solver,
    iterations: u32,
}

impl<T: Real> Midpoint<T> {
    /// A Newton-solved implicit midpoint integrator for `body` with step `h`.
    #[must_use]
    pub fn new(body: Body<T>, h: T) -> Self {
        Self {
            body,
            inv_i: body.inverse_inertia(),
            h,
            solver: Solver::Newton,
            iterations: 0,
        }
    }

    /// The same with another solver.
    #[must_use]
    pub fn with_solver(body: Body<T>, h: T, solver: Solver) -> Self {
        Self {
            solver,
            ..Self::new(body, h)
        }
    }

    /// Iterations the last step took (whether it converged or not).
    #[must_use]
    pub fn last_iterations(&self) -> u32 {
        self.iterations
    }

    /// The midpoint `y` of a step from `m`.
    fn midpoint(&mut self, m: Vec3<T>, h: T) -> Result<Vec3<T>, StepError> {
        if !h.is_finite() {
            return Err(StepError::NonFinite);
        }
        let hh = h * c::<T>(0.5);
        let w = self.inv_i;
        let f = |y: Vec3<T>| y.cross(y.mul_elem(w));
        let tol = c::<T>(4.0) * T::EPSILON;
        let mut y = m;
        let mut k = 0u32;
        let limit = match self.solver {
            Solver::Newton => 20,
            Solver::FixedPoint => 200,
        };
        while k < limit {
            k += 1;
            let next = match self.solver {
                Solver::FixedPoint => m.add(f(y).scale(hh)),
                Solver::Newton => {
                    // G(y) = y - m - h/2 f(y), G' = I - h/2 (hat(y) I^-1 - hat(I^-1 y))
                    let g = y.sub(m).sub(f(y).scale(hh));
                    let df = Mat3::hat(y).mul_diag(w).sub(&Mat3::hat(y.mul_elem(w)));
                    let jac = Mat3::identity().sub(&df.scale(hh));
                    let (inv, ok) = jac.inverse_or_zero();
                    if !ok {
                        self.iterations = k;
                        return Err(StepError::NoConvergence);
                    }
                    y.sub(inv.mul_vec(g))
                }
            };
            if !next.is_finite() {
                self.iterations = k;
                return Err(StepError::NoConvergence);
            }
            let change = next.sub(y).max_abs();
            y = next;
            if change <= tol * y.max_abs() {
                self.iterations = k;
                return Ok(y);
            }
        }
        self.iterations = k;
        Err(StepError::NoConvergence)
    }
}

/// `Ok` when `|next|^2` is `|m|^2` to `sqrt(eps)`, else `NoConvergence`. Every solution of
/// the midpoint equation keeps `|m|^2` (`|m'|^2 - |m|^2 = 2 h y . f(y) = 0`), so a result off
/// the sphere is a point where the iteration stopped without solving it: at a large `|y|` the
/// stopping test `|update| <= 4 eps |y|` passes with a residual far above `|m|` (found in
/// review: an f32 rod at `h |Omega|` near 0.6 returned `Ok` with `|m|^2` from 1 to 1.4e15, an
/// f64 body `|m|` from 3e32 to 3e144).
fn on_sphere<T: Real>(m: Vec3<T>, next: Vec3<T>) -> Result<(), StepError> {
    if norms_agree(m, next, T::EPSILON.sqrt()) {
        Ok(())
    } else {
        Err(StepError::NoConvergence)
    }
}

impl<T: Real> Integrator<T> for Midpoint<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        let v = checked_momentum(m)?;
        // at momenta whose products leave the range, the same motion in other units
        // (crate::integrator's homogeneous_scale: bit for bit the plain step in range)
        let (v, h, scale) = in_homogeneous_units(v, self.h)?;
        let y = self.midpoint(v, h)?;
        // m_{k+1} = 2 y - m_k
        let next = y.scale(c::<T>(2.0)).sub(v);
        on_sphere(v, next)?;
        write_momentum(m, unscaled(next, scale))
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        let (v, q) = checked_state(s)?;
        // h = 0 leaves the state as it is (the trait's promise; the step renormalised q)
        if self.h == T::ZERO {
            return Ok(());
        }
        let (v, h, scale) = in_homogeneous_units(v, self.h)?;
        let y = self.midpoint(v, h)?;
        let next = y.scale(c::<T>(2.0)).sub(v);
        on_sphere(v, next)?;
        // Cayley: (1 + w)/(1 - w) = (1 + w)^2 / (1 + |w|^2) for pure w = h Omega / 4
        let w = y.mul_elem(self.inv_i).scale(h * c::<T>(0.25));
        let w2 = w.norm2();
        let inv = T::ONE / (T::ONE + w2);
        let dq = Quat {
            w: (T::ONE - w2) * inv,
            x: c::<T>(2.0) * w.x * inv,
            y: c::<T>(2.0) * w.y * inv,
            z: c::<T>(2.0) * w.z * inv,
        };
        write_state(s, unscaled(next, scale), compose_attitude(q, dq))
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
