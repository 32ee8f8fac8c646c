//! `PreMv`: the DMV step with modified moments of inertia, orders 4 to 10 (Hairer & Vilmart,
//! "Preprocessed discrete Moser–Veselov algorithm for the full dynamics of a rigid body",
//! J. Phys. A 39 (2006) 13225; MATH.md §5).
//!
//! DMV's only error is a phase (time) error with a large constant. Hairer and Vilmart showed
//! that running DMV with modified moments `I~` makes it agree with the exact flow to order
//! `2r`, in `m` and in `q`, where
//!
//! `1 / I~_j = (1 / I_j) (1 + s3 + s5 + s7 + s9) + (d3 + d5 + d7 + d9)`,
//!
//! with `s_k`, `d_k` homogeneous polynomials of degree `(k - 1) / 2` in `C = h^2 |m|^2 / 2` and
//! `H = h^2 E` whose coefficients are rational in the moments (the table of MATH.md §5). `C` and
//! `H` are invariants, so `I~` is constant along a trajectory: it is computed once (and again
//! when the state is changed from outside or the step changes), and every step is an `Mv` step.

use crate::body::Body;
use crate::error::StepError;
use crate::integrator::{checked_momentum, Integrator, State};
use crate::mv::Mv;
use crate::real::{c, sq, Real};

/// Preprocessed DMV of order 2, 4, 6, 8 or 10: an [`Mv`] step of a body with modified moments.
///
/// Conserves `|m|^2`, `E` and `R(q) m` exactly like `Mv` (the modified body's DMV map keeps
/// the true invariants because `I~` depends on them only); not symplectic above order 2.
/// Errors at `t = 10` on the talk's case (m / q): order 4, `h = 0.1`: `3.9e-6 / 5.8e-6`;
/// order 6, `h = 0.1`: `1.2e-9 / 1.4e-9`; order 8, `h = 0.2`: `5.5e-11`; order 10, `h = 0.25`:
/// `2.6e-13` (MATH.md §5, reproduced by the tests). Explicit at every step size up to the
/// modified body's [`Mv::max_step`]; if the modified moments break the triangle inequality
/// (very large steps) the step returns `StepTooLarge`.
///
/// Cost per step: that of `Mv` plus a three-way comparison; the set-up (about 300 flops for
/// order 10) runs at the first step and whenever `m` is not the momentum returned last.
#[derive(Clone, Copy, Debug)]
pub struct PreMv<T> {
    body: Body<T>,
    h: T,
    order: u8,
    /// The `Mv` of the modified body for this trajectory (stepped in place: copying its
    /// tracking state in and out each step tripled the cost on a Cortex-M4F)...
    mv: Mv<T>,
    /// ...valid while the momentum is the one it returned last.
    last: Option<[T; 3]>,
}

impl<T: Real> PreMv<T> {
    /// A preprocessed DMV integrator of `order` (2, 4, 6, 8 or 10; other values are rounded
    /// down to the nearest of these and clamped to 2..=10).
    pub fn new(body: Body<T>, h: T, order: u8) -> Self {
        let order = order.clamp(2, 10) & !1;
        Self {
            body,
            h,
            order,
            mv: Mv::new(body, h),
            last: None,
        }
    }

    /// The order.
    pub fn order(&self) -> u8 {
        self.order
    }

    /// The modified principal moments `I~` for momentum `m` (MATH.md §5).
    pub fn modified_inertia(&self, m: &[T; 3]) -> Result<[T; 3], StepError> {
        modified_inertia(&self.body, self.h, self.order, m)
    }

    /// True while `m` is the momentum this integrator returned last (its modified body and
    /// tracking still apply).
    pub(crate) fn follows(&self, m: &[T; 3]) -> bool {
        self.last == Some(*m)
    }

    /// Makes `self.mv` the `Mv` of this trajectory: kept while `m` is the momentum returned
    /// last, built again otherwise.
    #[inline(always)]
    fn prepare(&mut self, m: &[T; 3]) -> Result<(), StepError> {
        if !self.follows(m) {
            self.rebuild(m)?;
        }
        Ok(())
    }

    #[cold]
    #[inline(never)]
    fn rebuild(&mut self, m: &[T; 3]) -> Result<(), StepError> {
        checked_momentum(m)?;
        if !self.h.is_finite() {
            return Err(StepError::NonFinite);
        }
        let inertia = modified_inertia(&self.body, self.h, self.order, m)?;
        let body = Body::from_inertia(inertia).map_err(|_| StepError::StepTooLarge)?;
        self.mv = Mv::new(body, self.h);
        Ok(())
    }
}

impl<T: Real> Integrator<T> for PreMv<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        self.prepare(m)?;
        self.mv.step(m)?;
        self.last = Some(*m);
        Ok(())
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        self.prepare(&s.m)?;
        self.mv.step_state(s)?;
        self.last = Some(s.m);
        Ok(())
    }

    fn step_size(&self) -> T {
        self.h
    }

    fn set_step_size(&mut self, h: T) {
        self.h = h;
        self.last = None;
    }

    fn body(&self) -> &Body<T> {
        &self.body
    }

    fn reset(&mut self) {
        self.last = None;
        self.mv.reset();
    }
}

/// `I~` from the table of MATH.md §5, terms up to `s_{order-1}`, `d_{order-1}`.
fn modified_inertia<T: Real>(
    body: &Body<T>,
    h: T,
    order: u8,
    m: &[T; 3],
) -> Result<[T; 3], StepError> {
    let [i1, i2, i3] = body.inertia();
    if order <= 2 {
        return Ok([i1, i2, i3]);
    }
    let h2 = sq(h);
    let cc = h2 * body.casimir(m) * c::<T>(0.5);
    let hh = h2 * body.energy(m);
    if !(cc.is_finite() && hh.is_finite()) {
        return Err(StepError::Overflow);
    }
    let d = i1 * i2 * i3;
    // sigma_k = sum I_i^k
    let pow = |x: T, k: i32| -> T {
        let mut r = T::ONE;
        let base = if k < 0 { T::ONE / x } else { x };
        let mut n = k.unsigned_abs();
        while n > 0 {
            r *= base;
            n -= 1;
        }
        r
    };
    let sig = |k: i32| pow(i1, k) + pow(i2, k) + pow(i3, k);
    // tau_{b,c} = sum over cyclic (i, j, k) of (I_j^b + I_k^b) / I_i^c
    let tau = |b: i32, cexp: i32| {
        (pow(i2, b) + pow(i3, b)) / pow(i1, cexp)
            + (pow(i3, b) + pow(i1, b)) / pow(i2, cexp)
            + (pow(i1, b) + pow(i2, b)) / pow(i3, cexp)
    };
    let k = |x: f64| c::<T>(x);
    let (s1, s2, s3_, s4) = (sig(1), sig(2), sig(3), sig(4));
    let (sm1, sm2, sm3, sm4) = (sig(-1), sig(-2), sig(-3), sig(-4));
    let (t11, t21, t12) = (tau(1, 1), tau(2, 1), tau(1, 2));
    let d2 = sq(d);
    let d3 = d2 * d;
    let d4 = sq(d2);
    let (c2, h2_) = (sq(cc), sq(hh));

    let mut s = cc * s1 / (k(6.0) * d) - hh * sm1 / k(3.0);
    let mut dd = -cc / (k(3.0) * d) + hh * s1 / (k(6.0) * d);
    if order >= 6 {
        s += c2 * (s2 - d * sm1) / (k(30.0) * d2)
            + cc * hh * (T::ONE - t11) / (k(30.0) * d)
            + h2_ * (k(3.0) * s1 + k(2.0) * d * sm2) / (k(60.0) * d);
        dd += -c2 * s1 / (k(60.0) * d2) + cc * hh * (k(6.0) * d * sm1 - s2) / (k(60.0) * d2)
            - h2_ * (k(9.0) + t11) / (k(60.0) * d);
    }
    if order >= 8 {
        let (c3, h3) = (c2 * cc, h2_ * hh);
        s += c3 * (k(4.0) * d + k(17.0) * s3_ - k(15.0) * d * t11) / (k(2520.0) * d3)
            + c2 * hh * (k(9.0) * s1 + k(10.0) * d * sm2 - k(6.0) * t21) / (k(420.0) * d2)
            + cc * h2_ * (k(53.0) * s2 + (k(6.0) * t12 - k(100.0) * sm1) * d) / (k(2520.0) * d2)
            + h3 * (k(15.0) - d * sm3 - k(2.0) * t11) / (k(630.0) * d);
        dd += c3 * (k(34.0) * d * sm1 - k(19.0) * s2) / (k(2520.0) * d3)
            + c2 * hh * (s3_ + k(2.0) * d * t11 - k(85.0) * d) / (k(1260.0) * d3)
            + cc * h2_ * (k(47.0) * s1 + k(13.0) * t21 - k(38.0) * d * sm2) / (k(2520.0) * d2)
            + h3 * (k(9.0) * d * sm1 + d * t12 - k(11.0) * s2) / (k(1260.0) * d2);
    }
    if order >= 10 {
        let (t31, t22, t13) = (tau(3, 1), tau(2, 2), tau(1, 3));
        let (c3, h3, c4, h4) = (c2 * cc, h2_ * hh, sq(c2), sq(h2_));
        s += c4 * (k(62.0) * s4 - k(94.0) * d * t21 + k(66.0) * d2 * sm2 + k(81.0) * d * s1)
            / (k(45360.0) * d4)
            + c3 * hh * (-k(77.0) * t31 + k(75.0) * d * t12 + k(214.0) * s2 - k(240.0) * d * sm1)
                / (k(22680.0) * d3)
            + c2 * h2_
                * (k(26.0) * d * t22 + k(55.0) * s3_ + k(204.0) * d
                    - k(50.0) * d2 * sm3
                    - k(59.0) * d * t11)
                / (k(7560.0) * d3)
            + cc * h3 * (k(137.0) * d * sm2 - d * t13 + k(3.0) * s1 - k(69.0) * t21)
                / (k(11340.0) * d2)
            + h4 * (k(2.0) * d2 * sm4 + k(5.0) * d * t12 - k(171.0) * d * sm1 + k(159.0) * s2)
                / (k(45360.0) * d2);
        dd += c4 * (k(60.0) * d * t11 - k(61.0) * s3_ - k(247.0) * d) / (k(45360.0) * d4)
            + c3 * hh * (k(54.0) * d * s1 - s4 + k(218.0) * d * t21 - k(426.0) * d2 * sm2)
                / (k(45360.0) * d4)
            + c2 * h2_ * (k(125.0) * d * sm1 - k(5.0) * t31 - k(130.0) * s2 + k(4.0) * d * t12)
                / (k(7560.0) * d3)
            + cc * h3
                * (k(67.0) * s3_ - k(735.0) * d - k(15.0) * d * t22
                    + k(87.0) * d * t11
                    + k(34.0) * d2 * sm3)
                / (k(22680.0) * d3)
            + h4 * (k(165.0) * s1 - d * t13 - k(9.0) * t21 - k(145.0) * d * sm2)
                / (k(45360.0) * d2);
    }
    let scale = T::ONE + s;
    let inv = [scale / i1 + dd, scale / i2 + dd, scale / i3 + dd];
    if !(inv[0] > T::ZERO && inv[1] > T::ZERO && inv[2] > T::ZERO) {
        return Err(StepError::StepTooLarge);
    }
    let out = [T::ONE / inv[0], T::ONE / inv[1], T::ONE / inv[2]];
    if out.iter().all(|x| x.is_finite()) {
        Ok(out)
    } else {
        Err(StepError::Overflow)
    }
}
