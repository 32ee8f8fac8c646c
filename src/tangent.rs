//! The tangent map (Jacobian) of the DMV step, for covariance propagation in a multiplicative
//! extended Kalman filter: [`Mv::step_with_jacobian`] and [`PreMv::step_with_jacobian`].
//!
//! # Tangent coordinates
//!
//! A state `(m, q)` near the estimate `(m^, q^)` is written `m = m^ + dm` (body momentum,
//! 3 entries) and `q = q^ (x) exp(dtheta / 2)`, i.e. `q = q^ (x) (cos(|dtheta|/2),
//! sin(|dtheta|/2) dtheta/|dtheta|)` (Hamilton product, `q = (w, x, y, z)` body to space): the
//! attitude error `dtheta` (3 entries, radians) is a rotation vector in the **body** frame, a
//! right perturbation. This is the error of a multiplicative EKF whose estimate is corrected
//! by `q^ <- q^ (x) exp(dtheta / 2)` (Markley, "Attitude error representations for Kalman
//! filtering", J. Guid. Control Dyn. 26 (2003) 311, with the error on the body side). The
//! Jacobian `F` (row-major, `F[i][j] = d out_i / d in_j`) maps `(dm, dtheta)` before the step
//! to `(dm', dtheta')` after it, to first order.
//!
//! # Derivation (implicit differentiation of the DMV equation)
//!
//! The step solves `h hat(m) = X J - J X^T` (docs/MATH.md §2) and sets `m' = X^T m`,
//! `q' = q (x) quat(X)`. Perturb `X -> X (I + hat(phi))`, `m -> m + dm`, `J -> J + dJ` (for
//! [`PreMv`] the modified mass matrix depends on `m` through `|m|^2` and the energy). With
//! `W = X J` and the identity `hat(psi) W + W^T hat(psi) = hat((tr W I - W) psi)` (valid for any
//! 3x3 `W`), the linearised equation is `h dm = (tr W I - W) X phi + vee(X dJ - dJ X^T)`, so
//!
//! `phi = Phi dm`,   `Phi = X^T (tr W I - W)^-1 (h I - V(X) dJ/dm)`,
//!
//! where `V(X) d = vee(X diag(d) - diag(d) X^T)`. `tr W I - W` has the eigenvalues
//! `lambda_j + lambda_k` of the DMV spectrum (all with positive real part), so it is invertible
//! wherever the step exists. Then `dm' = X^T dm - hat(phi) X^T m`, and
//! `exp(dtheta'/2) = quat(X)^* exp(dtheta/2) quat(X) (x) quat(X^T X(m + dm))`, so
//!
//! ```text
//! F = [ X^T + hat(m') Phi    0   ]
//!     [ Phi                  X^T ]
//! ```
//!
//! The momentum does not depend on the attitude (the upper right block is zero), and the
//! attitude error is carried to the new body frame by `X^T`.
//!
//! # Accuracy and cost
//!
//! This is the exact derivative of the DMV map (not of its round-off). Against forward-mode
//! dual numbers run through the generic step of a fresh integrator (tests/jacobian.rs, f64,
//! `10^3` random bodies, states and steps up to 0.9 of the existence limit or one radian of
//! turn), `max |F - F_dual| / max(1, max |F|)` is `1.4e-15` for `Mv` and `7.8e-16` for
//! `PreMv` (orders 2 to 10); Richardson-extrapolated central differences agree to their own
//! accuracy (`2e-10`). This is the derivative of the map of the stored body, whose mass
//! matrix `J` is rounded to `eps J_max` absolutely, evaluated at the step's computed turn: on
//! an elongated body the step's own rounding grows to about `eps I_max / I_min` of `|m|` in
//! the momentum and `h / I_min` times that in the attitude ([`Mv`]'s docs), and the Jacobian
//! (whose entries reach `h / I_min`) moves with it. Against a 50-digit DMV of the stored body
//! (a review): `1.5e-13` of `max |F|` at `I_min / I_max = 1e-3`, `3e-12` at `1e-4`,
//! `5.6e-7`–`1.6e-6` at `1e-6` (`I = (1e-6, 1, 1)`, `m = (3e-7, 0.4, 1)`, `h = 0.1`: the
//! conserved `m_x` comes out `1.2e-3` off relatively, `3.4e-10` of `|m|`, and the attitude
//! `1.8e-5` rad; an earlier trial's `1.9e-9` at `1e-6` was a gentler case). The step itself
//! is the ordinary `step_state` (same result, same tracking); the Jacobian adds `X = R(p)`
//! from the step's turn `p`, one 3x3 inverse (one division) and two 3x3 products (`PreMv`:
//! two more, and the gradient of its modified moments, no division). Measured on x86-64
//! (f64, talk's case at `h = 0.01`, `cargo bench --bench steps -- jacobian`, one run on a
//! 2-core Intel Xeon): a step with its Jacobian costs about 4.7 free-running `step_state`s
//! for `Mv` (141 vs 29.9 ns) and 6.0 for `PreMv` order 4 (191 vs 31.7 ns): the tangent map's
//! 3x3 inverse and products are about 230 flops, more than the free-running step itself.

use crate::error::StepError;
use crate::integrator::{checked_state, Integrator, State};
use crate::linalg::{Mat3, Vec3};
use crate::mv::Mv;
use crate::mv_pre::PreMv;
use crate::real::Real;

/// `F` of the module docs from the step's rotation `X`, the mass matrix `j` it was taken with,
/// the step `h`, the new momentum `m'` and, for `PreMv`, `dJ/dm` (rows: gradients of `J_i`).
fn dmv_tangent<T: Real>(
    x: &Mat3<T>,
    j: Vec3<T>,
    h: T,
    m_next: Vec3<T>,
    dj: Option<&Mat3<T>>,
) -> Result<[[T; 6]; 6], StepError> {
    let w = x.mul_diag(j);
    let tr = w.x_axis.x + w.y_axis.y + w.z_axis.z;
    let n = Mat3::identity().scale(tr).sub(&w);
    let (n_inv, ok) = n.inverse_or_zero();
    if !ok {
        return Err(StepError::Degenerate);
    }
    let xt = x.transpose();
    let xn = xt.mul_mat(&n_inv);
    // Phi = X^T N^-1 (h I - V(X) dJ/dm); V(X) has rows (0, X21, -X12), (-X20, 0, X02),
    // (X10, -X01, 0)
    let phi = match dj {
        None => xn.scale(h),
        Some(dj) => {
            let z = T::ZERO;
            let (x01, x02) = (x.y_axis.x, x.z_axis.x);
            let (x10, x12) = (x.x_axis.y, x.z_axis.y);
            let (x20, x21) = (x.x_axis.z, x.y_axis.z);
            let v = Mat3::from_cols(
                Vec3::new(z, -x20, x10),
                Vec3::new(x21, z, -x01),
                Vec3::new(-x12, x02, z),
            );
            xn.mul_mat(&Mat3::identity().scale(h).sub(&v.mul_mat(dj)))
        }
    };
    let a = xt.add(&Mat3::hat(m_next).mul_mat(&phi));
    let (a0, a1, a2) = (a.row0(), a.row1(), a.row2());
    let (p0, p1, p2) = (phi.row0(), phi.row1(), phi.row2());
    let (t0, t1, t2) = (xt.row0(), xt.row1(), xt.row2());
    let z = T::ZERO;
    let f = [
        [a0.x, a0.y, a0.z, z, z, z],
        [a1.x, a1.y, a1.z, z, z, z],
        [a2.x, a2.y, a2.z, z, z, z],
        [p0.x, p0.y, p0.z, t0.x, t0.y, t0.z],
        [p1.x, p1.y, p1.z, t1.x, t1.y, t1.z],
        [p2.x, p2.y, p2.z, t2.x, t2.y, t2.z],
    ];
    if f.iter().all(|r| r.iter().all(|v| v.is_finite())) {
        Ok(f)
    } else {
        Err(StepError::Overflow)
    }
}

impl<T: Real> Mv<T> {
    /// One `step_state` that also returns its Jacobian `F = d(m', dtheta') / d(m, dtheta)`,
    /// 6x6, row-major, in the tangent coordinates of [`crate::tangent`]: momentum first (3),
    /// then the body-frame attitude error `dtheta` of `q = q^ (x) exp(dtheta / 2)` (3),
    /// `q = [w, x, y, z]`.
    ///
    /// The step is exactly [`Integrator::step_state`] (same state, same tracking); `F` is the
    /// implicit derivative of the DMV equation (module docs), exact to round-off (`1.4e-15`
    /// relative in f64 against dual numbers), for one 3x3 inverse and two 3x3 products more
    /// than the step: about 4.7 times a free-running step's host time (`PreMv` 6.0; the
    /// module docs).
    ///
    /// # Errors
    ///
    /// Those of `step_state`, and `Degenerate` or `Overflow` if the Jacobian is not finite; the
    /// state is left as it was on `Err`.
    ///
    /// # Example: covariance propagation in a multiplicative EKF
    ///
    /// ```
    /// use rigid3::{Body, Mv, State};
    ///
    /// let body = Body::<f64>::from_inertia([0.6, 0.8, 1.0]).unwrap();
    /// let mut mv = Mv::new(body, 0.01);
    /// let mut x = State::new([1.8, 0.4, -0.9], [1.0, 0.0, 0.0, 0.0]);
    /// // P: covariance of (dm, dtheta); Q: process noise per step
    /// let mut p = [[0.0f64; 6]; 6];
    /// for i in 0..6 {
    ///     p[i][i] = if i < 3 { 1e-4 } else { 1e-6 };
    /// }
    /// let q_noise = 1e-9;
    /// for _ in 0..100 {
    ///     let f = mv.step_with_jacobian(&mut x).unwrap();
    ///     // P' = F P F^T + Q
    ///     let mut fp = [[0.0; 6]; 6];
    ///     for i in 0..6 {
    ///         for j in 0..6 {
    ///             fp[i][j] = (0..6).map(|k| f[i][k] * p[k][j]).sum();
    ///         }
    ///     }
    ///     for i in 0..6 {
    ///         for j in 0..6 {
    ///             p[i][j] = (0..6).map(|k| fp[i][k] * f[j][k]).sum::<f64>()
    ///                 + if i == j { q_noise } else { 0.0 };
    ///         }
    ///     }
    /// }
    /// // symmetric, positive diagonal, and grown by the dynamics: the momentum's uncertainty
    /// // turns into the attitude's (about 4e-4 after t = 1; with F = I the trace would stay
    /// // near its 3e-6 plus the noise)
    /// for i in 0..6 {
    ///     assert!(p[i][i] > 0.0);
    ///     for j in 0..6 {
    ///         assert!((p[i][j] - p[j][i]).abs() <= 1e-12 * p[i][i].max(p[j][j]));
    ///     }
    /// }
    /// assert!(p[3][3] + p[4][4] + p[5][5] > 1e-4);
    /// ```
    pub fn step_with_jacobian(&mut self, s: &mut State<T>) -> Result<[[T; 6]; 6], StepError> {
        let mut out = *s;
        let x = self.step_state_rotation(&mut out)?.to_mat3();
        let j = Vec3::from_array(self.body().mass_matrix());
        let f = dmv_tangent(&x, j, self.step_size(), Vec3::from_array(out.m), None)?;
        *s = out;
        Ok(f)
    }
}

impl<T: Real> PreMv<T> {
    /// One `step_state` that also returns its Jacobian, as [`Mv::step_with_jacobian`] (same
    /// tangent coordinates: momentum, then the body-frame attitude error of
    /// `q = q^ (x) exp(dtheta / 2)`, `q = [w, x, y, z]`).
    ///
    /// The modified moments `I~` depend on the momentum through `|m|^2` and the energy, so the
    /// Jacobian includes their gradient (`dJ~/dm`, from the tabulated polynomials of
    /// docs/MATH.md §5, exact); it is the derivative of the order-`2r` map, and so agrees with the
    /// exact flow's Jacobian to `O(h^(2r))`.
    ///
    /// # Errors
    ///
    /// Those of `step_state`, and `Degenerate` or `Overflow` if the Jacobian is not finite; the
    /// state is left as it was on `Err`.
    pub fn step_with_jacobian(&mut self, s: &mut State<T>) -> Result<[[T; 6]; 6], StepError> {
        // the step's own refusals first (the gradient would call a NaN an overflow)
        checked_state(s)?;
        if !self.step_size().is_finite() {
            return Err(StepError::NonFinite);
        }
        let dj = self.modified_mass_matrix_jacobian(&s.m)?;
        let mut out = *s;
        let (p, j) = self.step_state_rotation(&mut out)?;
        let x = p.to_mat3();
        let f = dmv_tangent(&x, j, self.step_size(), Vec3::from_array(out.m), Some(&dj))?;
        *s = out;
        Ok(f)
    }
}
