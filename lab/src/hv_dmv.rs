//! `HvDmv`: the discrete Moser–Veselov step as Hairer and Vilmart solve it, by a fixed-point
//! iteration on the rotation's quaternion (E. Hairer, G. Vilmart, "Preprocessed discrete
//! Moser–Veselov algorithm for the full dynamics of a rigid body", J. Phys. A 39 (2006)
//! 13225, and their code `DMV2` in `DMV10.f`): the lab's iterative DMV, the yardstick for
//! `rigid3::Mv`'s closed form.
//!
//! # The stage equation
//!
//! Write the DMV rotation as `X = R(p)` with the unit quaternion `p = (p0, v)`. Then
//! `X J - J X^T = 2 p0 hat(I v) + 2 hat((J v) x v)` (`I_i = J_j + J_k`), so the DMV equation
//! `h hat(m_k) = X J - J X^T` (docs/MATH.md §2) is `h m_k = 2 p0 I v + 2 (J v) x v`. In the
//! Rodrigues (Gibbs) vector `c = v / p0`, with `1 / p0^2 = 1 + |c|^2 = alpha`, this is
//!
//! `I c = alpha h m_k / 2 - (J c) x c`,  componentwise `c_i = alpha a_i + f_i c_j c_k`,
//!
//! with `a = h I^-1 m_k / 2` and `f_i = (I_j - I_k) / I_i` (cyclic `i, j, k`), because
//! `((J c) x c)_i = (J_j - J_k) c_j c_k = (I_k - I_j) c_j c_k`. Hairer and Vilmart solve it by
//! Gauss–Seidel sweeps (each component uses the ones already updated in the same sweep;
//! `alpha` from the previous sweep). Their predictor, used here too, is one such sweep from
//! `c = a` with `alpha = 1`: `c1 = a1 + f1 a2 a3`, `c2 = a2 + f2 c1 a3`, `c3 = a3 + f3 c1 c2`.
//! They stop when `sum |c_new - c_old| < 1e-15 |h|` (at most 50 sweeps); here the bound is
//! scale-free, `8 eps sum |a_i|` (on the talk's case `sum |a_i| = 0.66 h`, so in f64 this is
//! `1.2e-15 h`, theirs), so it also works in f32 and for any `|Omega|`. A step that has not
//! converged after [`MAX_SWEEPS`] sweeps returns `NoConvergence` and leaves the state as it was
//! (their code silently takes the last iterate).
//!
//! # The update
//!
//! `X^T` turns `m_k` into `m_{k+1}`, and the same identity for `X^T = R(conj p)` gives
//! `h m_{k+1} = 2 p0 I v - 2 (J v) x v`, so `m_{k+1} = m_k - (4 / h) (J v) x v`, i.e.
//!
//! `m_{k+1, i} = m_{k, i} + (4 / h) (I_j - I_k) c_j c_k / alpha`,
//!
//! an increment (no cancellation at small `h`). The attitude is `q_{k+1} = q_k (x) (1, c)`,
//! normalised (one square root and one division a step), as in their code. Which branch is
//! the forward second-order map (rather than its inverse) is fixed by comparison with
//! `rigid3::Mv` in `lab/tests/hv_dmv.rs`: one step agrees to round-off.

use rigid3::{Body, Integrator, Real, State, StepError};

/// Most Gauss–Seidel sweeps after the predictor (Hairer–Vilmart's 50).
pub const MAX_SWEEPS: u32 = 50;

/// Hairer–Vilmart's DMV step (order 2) with the fixed-point stage iteration.
///
/// The same map as `rigid3::Mv` where both exist and the iteration converges (Hairer and
/// Vilmart's iteration stops converging at `h ~ 0.93` on the talk's case, docs/MATH.md §3, where
/// `Mv` works up to `1.06`). Counts the sweeps it takes ([`HvDmv::mean_sweeps`]).
#[derive(Clone, Copy, Debug)]
pub struct HvDmv<T> {
    body: Body<T>,
    h: T,
    /// `h / 2`.
    half_h: T,
    /// `4 / h` (zero for `h = 0`, where the step is the identity).
    four_over_h: T,
    /// `1 / I_i`.
    inv_i: [T; 3],
    /// `(I_j - I_k) / I_i`.
    fac: [T; 3],
    /// `I_j - I_k`.
    fad: [T; 3],
    /// `8 eps`: the stopping bound relative to `sum |a_i|`.
    tol: T,
    steps: u64,
    sweeps: u64,
}

impl<T: Real> HvDmv<T> {
    /// An integrator for `body` with step `h`.
    pub fn new(body: Body<T>, h: T) -> Self {
        let [i1, i2, i3] = body.inertia();
        let fad = [i2 - i3, i3 - i1, i1 - i2];
        let inv_i = [T::ONE / i1, T::ONE / i2, T::ONE / i3];
        let mut s = Self {
            body,
            h,
            half_h: T::ZERO,
            four_over_h: T::ZERO,
            inv_i,
            fac: [fad[0] * inv_i[0], fad[1] * inv_i[1], fad[2] * inv_i[2]],
            fad,
            tol: T::from_f64(8.0) * T::EPSILON,
            steps: 0,
            sweeps: 0,
        };
        s.set_step_size(h);
        s
    }

    /// Steps taken (successful ones) and Gauss–Seidel sweeps they took after the predictor.
    pub fn stats(&self) -> (u64, u64) {
        (self.steps, self.sweeps)
    }

    /// Mean sweeps per successful step (after the predictor sweep; add one for the predictor).
    pub fn mean_sweeps(&self) -> f64 {
        if self.steps == 0 {
            0.0
        } else {
            self.sweeps as f64 / self.steps as f64
        }
    }

    /// Solves the stage equation for `m`: the Rodrigues vector `c` and `alpha = 1 + |c|^2`.
    fn stage(&mut self, m: &[T; 3]) -> Result<([T; 3], T), StepError> {
        if !(finite(m) && self.h.is_finite()) {
            return Err(StepError::NonFinite);
        }
        let [f1, f2, f3] = self.fac;
        let a1 = m[0] * self.half_h * self.inv_i[0];
        let a2 = m[1] * self.half_h * self.inv_i[1];
        let a3 = m[2] * self.half_h * self.inv_i[2];
        let bound = self.tol * (a1.abs() + a2.abs() + a3.abs());
        // the predictor: one sweep from c = a with alpha = 1
        let mut c1 = a1 + f1 * a2 * a3;
        let mut c2 = a2 + f2 * c1 * a3;
        let mut c3 = a3 + f3 * c1 * c2;
        let mut alpha = T::ONE + c1 * c1 + c2 * c2 + c3 * c3;
        let mut k = 0;
        while k < MAX_SWEEPS {
            k += 1;
            let (b1, b2, b3) = (c1, c2, c3);
            c1 = alpha * a1 + f1 * c2 * c3;
            c2 = alpha * a2 + f2 * c1 * c3;
            c3 = alpha * a3 + f3 * c1 * c2;
            alpha = T::ONE + c1 * c1 + c2 * c2 + c3 * c3;
            let change = (b1 - c1).abs() + (b2 - c2).abs() + (b3 - c3).abs();
            if !change.is_finite() || !alpha.is_finite() {
                return Err(StepError::NoConvergence);
            }
            if change <= bound {
                self.steps += 1;
                self.sweeps += u64::from(k);
                return Ok(([c1, c2, c3], alpha));
            }
        }
        Err(StepError::NoConvergence)
    }

    /// `m + (4 / h) (I_j - I_k) c_j c_k / alpha`.
    fn advance(&self, m: &[T; 3], c: [T; 3], alpha: T) -> [T; 3] {
        let g = self.four_over_h / alpha;
        [
            m[0] + self.fad[0] * c[1] * c[2] * g,
            m[1] + self.fad[1] * c[0] * c[2] * g,
            m[2] + self.fad[2] * c[0] * c[1] * g,
        ]
    }
}

fn finite<T: Real>(x: &[T]) -> bool {
    x.iter().all(|v| v.is_finite())
}

impl<T: Real> Integrator<T> for HvDmv<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        let (c, alpha) = self.stage(m)?;
        let next = self.advance(m, c, alpha);
        if !finite(&next) {
            return Err(StepError::Overflow);
        }
        *m = next;
        Ok(())
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        if !finite(&s.q) {
            return Err(StepError::NonFinite);
        }
        let (c, alpha) = self.stage(&s.m)?;
        let next = self.advance(&s.m, c, alpha);
        // q (x) (1, c), then normalised
        let [w, x, y, z] = s.q;
        let [c1, c2, c3] = c;
        let p = [
            w - c1 * x - c2 * y - c3 * z,
            x + c1 * w + c3 * y - c2 * z,
            y + c2 * w + c1 * z - c3 * x,
            z + c3 * w + c2 * x - c1 * y,
        ];
        let n2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3];
        if !(n2 > T::ZERO) {
            return Err(StepError::NonFinite);
        }
        let inv = T::ONE / n2.sqrt();
        let q = [p[0] * inv, p[1] * inv, p[2] * inv, p[3] * inv];
        if !(finite(&next) && finite(&q)) {
            return Err(StepError::Overflow);
        }
        s.m = next;
        s.q = q;
        Ok(())
    }

    fn step_size(&self) -> T {
        self.h
    }

    fn set_step_size(&mut self, h: T) {
        self.h = h;
        self.half_h = h * T::from_f64(0.5);
        let f = T::from_f64(4.0) / h;
        // h = 0: c = 0 and the step is the identity; 4 / h must not turn 0 into NaN
        self.four_over_h = if f.is_finite() { f } else { T::ZERO };
    }

    fn body(&self) -> &Body<T> {
        &self.body
    }
}
