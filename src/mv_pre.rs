//! `PreMv`: the DMV step with modified moments of inertia, orders 4 to 10 (Hairer & Vilmart,
//! "Preprocessed discrete Moser–Veselov algorithm for the full dynamics of a rigid body",
//! J. Phys. A 39 (2006) 13225; docs/MATH.md §5).
//!
//! DMV's only error is a phase (time) error with a large constant. Hairer and Vilmart showed
//! that running DMV with modified moments `I~` makes it agree with the exact flow to order
//! `2r`, in `m` and in `q`, where
//!
//! `1 / I~_j = (1 / I_j) (1 + s3 + s5 + s7 + s9) + (d3 + d5 + d7 + d9)`,
//!
//! with `s_k`, `d_k` homogeneous polynomials of degree `(k - 1) / 2` in `C = h^2 |m|^2 / 2` and
//! `H = h^2 E` whose coefficients are rational in the moments (the table of docs/MATH.md §5).
//! `C` and `H` are invariants, so `I~` is constant along a trajectory: it is computed once (and
//! again when the state is changed from outside or the step changes), and every step is an
//! `Mv` step.

use crate::body::Body;
use crate::error::StepError;
use crate::integrator::{checked_attitude, power_of_two_scale, Integrator, State};
use crate::linalg::{Mat3, Quat, Vec3};
use crate::mv::Mv;
use crate::mv_pre_series::series_tables;
use crate::real::{c, sq, Real};

/// Preprocessed DMV of order 2, 4, 6, 8 or 10: an [`Mv`] step of a body with modified moments.
///
/// Conserves `|m|^2`, `E` and `R(q) m` exactly like `Mv` (the modified body's DMV map keeps
/// the true invariants because `I~` depends on them only); not symplectic above order 2.
/// Errors at `t = 10` on the talk's case (`|m - m_ref|` / largest entry of `R(q) - R(q_ref)`):
/// order 4, `h = 0.1`: `3.9e-6 / 5.8e-6`; order 6, `h = 0.1`: `1.2e-9 / 1.4e-9`; order 8,
/// `h = 0.2`: `5.5e-11`; order 10, `h = 0.25`: `2.6e-13` (docs/MATH.md §5; the tests
/// reproduce each within 1.25x: 3.89e-6 / 5.76e-6, 1.23e-9 / 1.40e-9, 5.58e-11, 2.41e-13; the
/// quaternion distance `|q - q_ref|` reads about 1.6x smaller). Explicit at every step size up to the
/// modified body's [`Mv::max_step`]; if the modified moments break the triangle inequality
/// (very large steps) the step returns `StepTooLarge`. The modified moments themselves are
/// accurate to a few ulps for every valid body, rods included (src/mv_pre_series.rs; at most
/// 4 ulps over 3000 random bodies against 50-digit arithmetic, rods to `I_min / I_max = 1e-9`),
/// down to rods of `1e-11` in f32 (`1e-80` in f64), where order 10's tables underflow and its
/// steps refuse with `StepTooLarge`; on a rod the steps' accuracy is that of [`Mv`]'s solved
/// steps there (its docs: order 10 stalls near `1e-12` at `I_min / I_max = 1e-3`, `1e-8` at
/// `1e-5`).
///
/// Cost per step: that of `Mv` plus a three-way comparison. When `m` or `h` changes from
/// outside (a filter's correction, a torque kick, a jittering clock) the modified moments are
/// updated incrementally: the polynomials of docs/MATH.md §5 are tabulated per body at
/// construction, so an update is one evaluation of them and three divisions (counted in the
/// README's flops table), and the `Mv` of the modified body keeps its tracked root as the
/// start of a Newton re-solve.
#[derive(Clone, Debug)]
pub struct PreMv<T> {
    body: Body<T>,
    h: T,
    order: u8,
    /// The `Mv` of the modified body for this trajectory (stepped in place: copying its
    /// tracking state in and out each step tripled the cost on a Cortex-M4F)...
    mv: Mv<T>,
    /// ...valid while the momentum is the one it returned last.
    last: Option<[T; 3]>,
    /// The step changed since the last step (the trajectory goes on, its modified body not).
    h_changed: bool,
    /// The trajectory's true invariants `(|m|^2, m . I^-1 m)`, taken when the momentum
    /// changed from outside: a change of `h` alone moves the momentum back onto them before
    /// the modified body is rebuilt, so a jittering clock does not let them random-walk.
    invariants: Invariants<T>,
    /// The modified moments' polynomials for this body.
    modifier: Modifier<T>,
    /// `1 / I~` of the modified body `mv` runs, once built.
    modified_inv: Option<[T; 3]>,
}

impl<T: Real> PreMv<T> {
    /// A preprocessed DMV integrator of `order`: 2 (plain DMV), 4, 6, 8 or 10 (the orders of
    /// the Hairer–Vilmart modified moments, docs/MATH.md §5).
    ///
    /// # Errors
    ///
    /// [`StepError::InvalidOrder`] for any other order (it is not rounded to a nearby one: an
    /// order-5 request that silently ran at order 4 would make an accuracy claim false).
    pub fn new(body: Body<T>, h: T, order: u8) -> Result<Self, StepError> {
        if !matches!(order, 2 | 4 | 6 | 8 | 10) {
            return Err(StepError::InvalidOrder);
        }
        Ok(Self {
            body,
            h,
            order,
            mv: Mv::new(body, h),
            last: None,
            h_changed: false,
            invariants: Invariants::None,
            modifier: Modifier::new(&body, order),
            modified_inv: None,
        })
    }

    /// The order.
    #[must_use]
    pub fn order(&self) -> u8 {
        self.order
    }

    /// A copy with step `h` and no trajectory: what `PreMv::new(body, h, order)` gives (the
    /// same steps to round-off), without computing the modified moments' tables again.
    pub(crate) fn restarted(&self, h: T) -> Self {
        let mut fresh = self.clone();
        fresh.set_step_size(h);
        fresh.reset();
        fresh
    }

    /// [`PreMv::restarted`] on the same trajectory: a fresh DMV with step `h` whose first
    /// step, from the momentum returned last, moves it back onto the trajectory's invariants
    /// first, as after a change of `h` (crate::mv_retimed restarts its inner DMV at each
    /// exact retiming; with the invariants taken again from each restart's input, a clock
    /// that retimed every tick let `|m|^2` random-walk: 3.1e-13 in f64 and 2.2e-5 in f32
    /// after `10^6` jittered steps of the talk's case, where `PreMv` keeps 4e-16 and 9e-9,
    /// found in review). Without a trajectory, [`PreMv::restarted`].
    ///
    /// The inner `Mv` solves its root afresh and keeps its anchor, so the attitude stays held
    /// to the trajectory's spatial momentum ([`Mv::restart_root`]).
    pub(crate) fn restarted_on_trajectory(&self, h: T) -> Self {
        let Some(last) = self.last else {
            return self.restarted(h);
        };
        let mut fresh = self.clone();
        fresh.set_step_size(h);
        fresh.mv.restart_root();
        fresh.last = Some(last);
        fresh.h_changed = true;
        // the body is built again for the first step, which then holds (for the same
        // modified body the hold would be left to the `Mv`, which takes the invariants again
        // from its input after a new root)
        fresh.modified_inv = None;
        if matches!(fresh.invariants, Invariants::None) {
            fresh.invariants = Invariants::Of(last);
        }
        fresh
    }

    /// The modified principal moments `I~` for momentum `m` (docs/MATH.md §5).
    ///
    /// # Errors
    ///
    /// [`StepError::NonFinite`] for a non-finite `m` or step, [`StepError::StepTooLarge`]
    /// when the series gives a non-positive modified moment (the step is too large for the
    /// preprocessing), and [`StepError::Overflow`] when a moment would overflow.
    pub fn modified_inertia(&self, m: &[T; 3]) -> Result<[T; 3], StepError> {
        self.modifier.modified_inertia(self.h, m)
    }

    /// True while `m` is the momentum this integrator returned last (its modified body and
    /// tracking still apply).
    pub(crate) fn follows(&self, m: &[T; 3]) -> bool {
        matches!(&self.last, Some(l) if same3(l, m))
    }

    /// Makes `self.mv` the `Mv` of this trajectory: kept while `m` is the momentum returned
    /// last and `h` is unchanged, updated otherwise. Returns the momentum to step from when
    /// it is not `m` itself: after a change of `h` alone, `m` moved back onto the
    /// trajectory's invariants.
    #[inline(always)]
    fn prepare(&mut self, m: &[T; 3], q: Option<&[T; 4]>) -> Result<Option<[T; 3]>, StepError> {
        if self.follows(m) {
            if !self.h_changed {
                return Ok(None);
            }
            checked_attitude(q)?;
            return self.retime(m);
        }
        checked_attitude(q)?;
        self.rebuild(m, None)?;
        // formed when a change of h first needs them (a loop that changes m every tick
        // never does)
        self.invariants = Invariants::Of(*m);
        Ok(None)
    }

    /// The update after a change of `h` alone: the trajectory goes on.
    #[cold]
    #[inline(never)]
    fn retime(&mut self, m: &[T; 3]) -> Result<Option<[T; 3]>, StepError> {
        if self.h == T::ZERO {
            self.pause();
            return Ok(None);
        }
        let inv = self.modifier.modified_inverse(self.h, m)?;
        if matches!(&self.modified_inv, Some(old) if same3(old, &inv)) {
            // the same modified body: the Mv's own change of h (its invariants rescaled and
            // held) is all there is to do
            self.mv.set_step_size(self.h);
            return Ok(None);
        }
        let held = self.hold_invariants(m);
        // the series again only if the hold moved the momentum
        let inv = if same3(&held, m) {
            inv
        } else {
            self.modifier.modified_inverse(self.h, &held)?
        };
        self.rebuild_with(inv, Some(held))?;
        Ok(Some(held))
    }

    /// `m` moved onto the trajectory's `|m|^2` and `m . I^-1 m` to first order (exact to
    /// `O(eps^2)`): `m + x m + y I^-1 m` with `[[c, e], [e, g]] (x, y) = (dc, de) / 2`,
    /// `c = |m|^2`, `e = m . I^-1 m`, `g = |I^-1 m|^2`, whose determinant is
    /// `sum_{i<k} m_i^2 m_k^2 (1/I_i - 1/I_k)^2` (no cancellation); where it is small (near a
    /// principal axis, or equal moments) only `|m|^2` is corrected.
    ///
    /// All of it in units where the trajectory's `max |m_i|` and `max 1/I_i` are within
    /// `2^16` of one ([`near_unit_scale`]: powers of two, so nothing is rounded), where the
    /// determinant, quartic in `m` and quadratic in `1/I`, stays normal in f32: `x` is
    /// dimensionless and `y` is taken against the scaled `1/I`. In the caller's units the
    /// squares left f32's normal range below `|m|` of about `1e-19` and the determinant
    /// below `1e-10` (and above `1e9`, `1e19`; f64 past `1e+-155`): the hold moved `m` onto a
    /// rounded `|m|^2` or switched itself off, and a jittered f32 `PreMv` at `|m| = 1e-21`
    /// ended with `|m|^2` 2.8e-3 off and `m` 11 % from the exact solution after `10^4`
    /// steps, with `Ok` (found in review; `RetimedMv`, built on `PreMv`, alike).
    #[inline]
    fn hold_invariants(&mut self, m: &[T; 3]) -> [T; 3] {
        let [i0, i1, i2] = self.modifier.inv_i;
        let sa = near_unit_scale(i0.abs().max(i1.abs()).max(i2.abs()));
        let (a0, a1, a2) = (i0 * sa, i1 * sa, i2 * sa);
        let (c0, e0, up) = match self.invariants {
            Invariants::None => return *m,
            Invariants::Taken(c0, e0, up) => (c0, e0, up),
            Invariants::Of(x) => {
                let up = near_unit_scale(x[0].abs().max(x[1].abs()).max(x[2].abs()));
                let (x0, x1, x2) = (x[0] * up, x[1] * up, x[2] * up);
                let (c0, e0) = (
                    sq(x0) + sq(x1) + sq(x2),
                    a0 * sq(x0) + a1 * sq(x1) + a2 * sq(x2),
                );
                self.invariants = Invariants::Taken(c0, e0, up);
                (c0, e0, up)
            }
        };
        let (m0, m1, m2) = (m[0] * up, m[1] * up, m[2] * up);
        let (q0, q1, q2) = (sq(m0), sq(m1), sq(m2));
        let cas = q0 + q1 + q2;
        let e = a0 * q0 + a1 * q1 + a2 * q2;
        let half = c::<T>(0.5);
        let (dc, de) = ((c0 - cas) * half, (e0 - e) * half);
        // within 8 eps of both there is nothing worth a division: the drift stays bounded
        // by that (it cannot random-walk past it)
        let tol = c::<T>(4.0) * T::EPSILON;
        if !(cas > T::ZERO) || (dc.abs() <= tol * c0 && de.abs() <= tol * e0) {
            return *m;
        }
        let (v0, v1, v2) = (a0 * m0, a1 * m1, a2 * m2);
        let g = sq(v0) + sq(v1) + sq(v2);
        let det = q0 * q1 * sq(a0 - a1) + q0 * q2 * sq(a0 - a2) + q1 * q2 * sq(a1 - a2);
        let (x, y) = if det > c::<T>(1e-3) * cas * g {
            let inv = T::ONE / det;
            ((g * dc - e * de) * inv, (cas * de - e * dc) * inv)
        } else {
            (dc / cas, T::ZERO)
        };
        // back in the caller's units: `x` as it is, `y` against the scaled `1/I`
        let [n0, n1, n2] = *m;
        let held = [
            n0 + (x * n0 + y * (a0 * n0)),
            n1 + (x * n1 + y * (a1 * n1)),
            n2 + (x * n2 + y * (a2 * n2)),
        ];
        if held.iter().all(|v| v.is_finite()) {
            held
        } else {
            *m
        }
    }

    /// A step of size zero: the inner `Mv` pauses (its steps leave the state as it is) and
    /// the modified body stays the last non-zero step's; the next non-zero `h` updates it
    /// as any change of `h` does. (No test on the step's own path: a zero `h` reaches here
    /// as a change of `h`, or of `m`.)
    fn pause(&mut self) {
        if self.mv.step_size() != T::ZERO {
            self.mv.set_step_size(T::ZERO);
        }
    }

    /// Updates the modified body for momentum `m` (`from`: see [`Mv::set_body`]).
    #[cold]
    #[inline(never)]
    fn rebuild(&mut self, m: &[T; 3], from: Option<[T; 3]>) -> Result<(), StepError> {
        if self.h == T::ZERO {
            // the caller changed the state during a pause: the Mv forgets the trajectory
            // (its spatial reference too), as a step would after such a change (kept, the
            // next hold turned the attitude back onto the old `R(q) m`: 1.3e-2 rad after a
            // 1e-2 correction, found in review); the body is rebuilt at the next step. A
            // non-finite momentum is refused first, with nothing forgotten (the reset forgot
            // the paused trajectory for an input the Mv then refused: f32 `|m|^2`
            // random-walked to 2.1e-5 with one every 7th tick, found in review)
            if !m.iter().all(|x| x.is_finite()) {
                return Err(StepError::NonFinite);
            }
            self.last = None;
            self.pause();
            self.mv.reset();
            return Ok(());
        }
        // m and h are checked by the modifier (NonFinite there)
        let inv = self.modifier.modified_inverse(self.h, m)?;
        // until the step succeeds (which sets it), the body built here is for `m` alone: a
        // step refused after this leaves the next one to build it again for its own input
        // (kept, a refused momentum's body stepped the caller's unchanged state, found in
        // review: `|m|^2` 7.4e-3 off after a refused zero attitude and a change of `h`, and
        // every step `StepTooLarge` after a refused momentum `1e8` times too large)
        self.last = None;
        self.rebuild_with(inv, from)
    }

    /// [`PreMv::rebuild`] with the series' `1 / I~` already evaluated.
    #[inline(always)]
    fn rebuild_with(&mut self, inv: [T; 3], from: Option<[T; 3]>) -> Result<(), StepError> {
        if matches!(&self.modified_inv, Some(old) if same3(old, &inv)) {
            // the modified body is the same to the last bit (a small change of m or h moves
            // I~ by about (h |Omega|)^2 of its relative size: in f32 usually not at all), so
            // the Mv goes on with its body and tracking and sees only the new m or h
            if self.mv.step_size() != self.h {
                self.mv.set_step_size(self.h);
            }
            if let Some(held) = from {
                // the trajectory goes on from the held momentum (its spatial momentum too)
                self.mv.continue_from(held);
            }
            return Ok(());
        }
        let inertia = self.modifier.moments(inv)?;
        let body = Body::from_positive_inertia(inertia).map_err(|_| StepError::StepTooLarge)?;
        if self.mv.step_size() != self.h {
            self.mv.set_step_size(self.h);
        }
        self.mv.set_body(body, Vec3::from_array(inv), from);
        self.modified_inv = Some(inv);
        Ok(())
    }
}

impl<T: Real> Integrator<T> for PreMv<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        match self.prepare(m, None)? {
            // Mv leaves its input as it was on Err
            None => self.mv.step(m)?,
            Some(held) => {
                let mut next = held;
                self.mv.step(&mut next)?;
                *m = next;
            }
        }
        self.last = Some(*m);
        self.h_changed = false;
        Ok(())
    }

    fn step_carrying(
        &mut self,
        m: &mut [T; 3],
        lost: &mut [T; 3],
        carry: bool,
    ) -> Result<(), StepError> {
        if carry {
            self.step_carried(m, lost)
        } else {
            self.step(m)
        }
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        self.step_state_checking(s, true)
    }

    fn step_state_carrying(
        &mut self,
        s: &mut State<T>,
        lost: &mut State<T>,
        carry: bool,
    ) -> Result<(), StepError> {
        // the forced integrators' drift: their step checked the state it turned and kicked
        // (the attitude's test before `prepare` cost each of their drifts 9 counted flops,
        // 1.5 % of the heavy top's work-precision, and the M4F's forced step 15 instructions)
        if carry {
            self.step_state_carried(s, lost)
        } else {
            self.step_state_checking(s, false)
        }
    }

    fn step_size(&self) -> T {
        self.h
    }

    /// A zero `h` pauses the steps (they leave the state as it is; `PreMv::pause`), and the
    /// next non-zero `h` updates the modified body as any change of `h` does, the trajectory's
    /// invariants kept (as [`Mv`]'s; taken as a change of `h`, zero ticks let the invariants
    /// random-walk). The same `h` as before changes nothing.
    fn set_step_size(&mut self, h: T) {
        // the same h changes nothing (a loop that sets a measured dt every tick)
        if h == self.h {
            return;
        }
        self.h = h;
        self.h_changed = true;
    }

    fn body(&self) -> &Body<T> {
        &self.body
    }

    fn reset(&mut self) {
        self.last = None;
        self.h_changed = false;
        self.mv.reset();
    }
}

/// The polynomials `s = s3 + s5 + s7 + s9` and `d = d3 + ... + d9` of docs/MATH.md §5 as
/// coefficient tables in `C` and `X = H - C / I_max` (crate::mv_pre_series: in Hairer and
/// Vilmart's `C` and `H` the terms cancel on a rod): `s[k][a]` multiplies `C^a X^(k+1-a)`
/// (degree `k + 1`). They depend on the body only, so they are computed once per body, and a
/// change of `m` or `h` costs one evaluation and three divisions.
///
/// The tables are those of the body scaled to `I / kappa`, `kappa = max I`, and are evaluated
/// at `C / kappa^2` and `X / kappa` (the momentum scaled to `h m / kappa`), where `s` is the
/// same and `d` is `kappa` times as large (`s` is a function of `h Omega` alone, `d` has the
/// units of `1 / I`). Unscaled, `delta^4 = (I1 I2 I3)^4` leaves f32's range for moments
/// beyond about `2e3` or below `5e-4` (order 10 refused a 1e6 kg m^2 spacecraft and a
/// 1e-4 kg m^2 CubeSat with `StepTooLarge`), and `|m|^2` for momenta beyond `2e19`.
#[derive(Clone, Copy, Debug)]
struct Modifier<T> {
    order: u8,
    /// `1 / I` (unscaled).
    inv_i: [T; 3],
    /// `kappa / I`, `kappa / I - 1` (`X = sum b_i u_i / 2`, zero on the largest moment's
    /// axis) and `1 / kappa`.
    a: [T; 3],
    b: [T; 3],
    inv_kappa: T,
    s: [[T; 5]; 4],
    d: [[T; 5]; 4],
}

impl<T: Real> Modifier<T> {
    fn new(body: &Body<T>, order: u8) -> Self {
        let [b1, b2, b3] = body.inertia();
        let kappa = b1.max(b2).max(b3);
        let (i1, i2, i3) = (b1 / kappa, b2 / kappa, b3 / kappa);
        let z = [T::ZERO; 5];
        let mut m = Self {
            order,
            inv_i: [T::ONE / b1, T::ONE / b2, T::ONE / b3],
            a: [T::ONE / i1, T::ONE / i2, T::ONE / i3],
            // kappa / I - 1 from the difference (exactly zero on the largest moment's axis)
            b: [(kappa - b1) / b1, (kappa - b2) / b2, (kappa - b3) / b3],
            inv_kappa: T::ONE / kappa,
            s: [z; 4],
            d: [z; 4],
        };
        if order <= 2 {
            return m;
        }
        // the smallest and the middle moment (the largest is kappa): any order of the two
        // would do for the polynomials, but `dl <= lo` (the triangle inequality) holds only
        // with the smallest as `lo`, and that is what keeps their terms free of cancellation
        let (lo, mid) = if b1 <= b2 && b1 <= b3 {
            (b1, b2.min(b3))
        } else if b2 <= b3 {
            (b2, b1.min(b3))
        } else {
            (b3, b1.min(b2))
        };
        let (s, d) = series_tables(
            lo / kappa,
            mid / kappa,
            (kappa - mid) / kappa,
            (order - 2) / 2,
        );
        m.s = s;
        m.d = d;
        m
    }

    /// `I~` for step `h` and momentum `m`: `1 / I~_j = (1 / I_j)(1 + s) + d` (docs/MATH.md §5).
    fn modified_inertia(&self, h: T, m: &[T; 3]) -> Result<[T; 3], StepError> {
        self.moments(self.modified_inverse(h, m)?)
    }

    /// `I~` from `1 / I~` ([`Modifier::modified_inverse`]).
    #[inline]
    fn moments(&self, inv: [T; 3]) -> Result<[T; 3], StepError> {
        if self.order <= 2 {
            let [a1, a2, a3] = self.inv_i;
            return Ok([T::ONE / a1, T::ONE / a2, T::ONE / a3]);
        }
        let out = reciprocals(inv);
        if out[0].is_finite() && out[1].is_finite() && out[2].is_finite() {
            Ok(out)
        } else {
            Err(StepError::Overflow)
        }
    }

    /// `1 / I~` for step `h` and momentum `m`: the series of docs/MATH.md §5, positive (else
    /// `StepTooLarge`). `NonFinite` for a non-finite `m` or `h`.
    #[inline]
    fn modified_inverse(&self, h: T, m: &[T; 3]) -> Result<[T; 3], StepError> {
        if !h.is_finite() {
            return Err(StepError::NonFinite);
        }
        if self.order <= 2 {
            if !(m[0].is_finite() && m[1].is_finite() && m[2].is_finite()) {
                return Err(StepError::NonFinite);
            }
            return Ok(self.inv_i);
        }
        let (cc, xx) = self.scaled_invariants(h, m);
        if !(cc.is_finite() && xx.is_finite()) {
            // with m and h finite, (h m / kappa)^2 overflows only for h |Omega| beyond 1e19
            // (f32), far past any DMV step's limit: the step is too large, as `Mv` says
            return Err(if m.iter().all(|x| x.is_finite()) {
                StepError::StepTooLarge
            } else {
                StepError::NonFinite
            });
        }
        // the monomials C^a X^b with a + b = 1..order/2 - 1 only: an update after a change of
        // m or h is on the loop's path, and order 4 needs the first degree alone
        let [s1, s2, s3, s4] = &self.s;
        let [d1, d2, d3, d4] = &self.d;
        let mut s = s1[0] * xx + s1[1] * cc;
        let mut d = d1[0] * xx + d1[1] * cc;
        if self.order >= 6 {
            let (c2, x2, cx) = (sq(cc), sq(xx), cc * xx);
            s += s2[0] * x2 + s2[1] * cx + s2[2] * c2;
            d += d2[0] * x2 + d2[1] * cx + d2[2] * c2;
            if self.order >= 8 {
                let (x3, cx2, c2x, c3) = (x2 * xx, cx * xx, cx * cc, c2 * cc);
                s += s3[0] * x3 + s3[1] * cx2 + s3[2] * c2x + s3[3] * c3;
                d += d3[0] * x3 + d3[1] * cx2 + d3[2] * c2x + d3[3] * c3;
                if self.order >= 10 {
                    let (x4, cx3, c2x2, c3x, c4) = (sq(x2), cx2 * xx, sq(cx), c3 * xx, sq(c2));
                    s += s4[0] * x4 + s4[1] * cx3 + s4[2] * c2x2 + s4[3] * c3x + s4[4] * c4;
                    d += d4[0] * x4 + d4[1] * cx3 + d4[2] * c2x2 + d4[3] * c3x + d4[4] * c4;
                }
            }
        }
        // the leading term with the unscaled 1 / I (rounded once, as the body's own): scaled
        // back, kappa / I then 1 / kappa rounded it three times, a bias of a few ulps in every
        // step's speed that put the talk's case, order 10, at 2.7e-14 at t = 100 (7e-15)
        let scale = T::ONE + s;
        let dk = d * self.inv_kappa;
        let [b1, b2, b3] = self.inv_i;
        let inv = [scale * b1 + dk, scale * b2 + dk, scale * b3 + dk];
        if !(inv[0] > T::ZERO && inv[1] > T::ZERO && inv[2] > T::ZERO) {
            return Err(StepError::StepTooLarge);
        }
        Ok(inv)
    }

    /// `(C, X) / (kappa^2, kappa)`, from the momentum scaled to `h m / kappa`
    /// (`X = H - C / I_max`, [`Modifier`]).
    #[inline(always)]
    fn scaled_invariants(&self, h: T, m: &[T; 3]) -> (T, T) {
        let [b1, b2, b3] = self.b;
        let hk = h * self.inv_kappa;
        let (u1, u2, u3) = (sq(m[0] * hk), sq(m[1] * hk), sq(m[2] * hk));
        let half = c::<T>(0.5);
        ((u1 + u2 + u3) * half, (u1 * b1 + u2 * b2 + u3 * b3) * half)
    }
}

/// `s3 = a C + b H`, the first term of the modified moments' series (docs/MATH.md §5):
/// `(a, b) = (sig_1 / (6 delta), -sig_-1 / 3)` for the moments `i`, for
/// [`crate::RetimedMv`], whose retimed step is `h (1 + s3 + O(h^4))` (and which updates it only
/// on bodies whose moments span less than 16x, where these monomials do not cancel; `PreMv`'s
/// own tables hold the same term in `C` and `X`, crate::mv_pre_series).
pub(crate) fn s3_coefficients<T: Real>([i1, i2, i3]: [T; 3]) -> (T, T) {
    let sm1 = T::ONE / i1 + T::ONE / i2 + T::ONE / i3;
    (
        (i1 + i2 + i3) / (c::<T>(6.0) * (i1 * i2 * i3)),
        -sm1 / c::<T>(3.0),
    )
}

/// The trajectory's `(|m|^2, m . I^-1 m)` for [`PreMv::hold_invariants`].
#[derive(Clone, Copy, Debug)]
enum Invariants<T> {
    /// No trajectory yet.
    None,
    /// Those of this momentum (the one the caller set), not yet formed.
    Of([T; 3]),
    /// `|m|^2` and `m . I^-1 m` in the scaled units of [`PreMv::hold_invariants`], and the
    /// momentum's scale there.
    Taken(T, T, T),
}

/// The power of two that brings a positive `big` within `[2^-16, 2^16]` (one when it is
/// there already, the common case, or zero or not finite; crate::integrator's
/// `power_of_two_scale`).
#[inline]
fn near_unit_scale<T: Real>(big: T) -> T {
    power_of_two_scale(big, 1.0 / 65536.0, 65536.0).map_or(T::ONE, |(up, _)| up)
}

/// `a == b` component by component (the slice comparison `==` on arrays compiled to a loop
/// call on the M4F).
#[inline(always)]
fn same3<T: Real>(a: &[T; 3], b: &[T; 3]) -> bool {
    a[0] == b[0] && a[1] == b[1] && a[2] == b[2]
}

/// `[1/a, 1/b, 1/c]` for positive `a, b, c` with one division (Montgomery's trick: `r =
/// 1/(abc)`, then `1/a = r b c`), accurate to about 3 ulps instead of half an ulp; three
/// divisions when the product leaves the normal range. A division costs 14 cycles on a
/// Cortex-M4F and is not pipelined, and this runs after every outside change of `m` or `h`.
#[inline]
fn reciprocals<T: Real>([x, y, z]: [T; 3]) -> [T; 3] {
    let xy = x * y;
    let xyz = xy * z;
    if xyz >= T::MIN_POSITIVE && xyz.is_finite() {
        let r = T::ONE / xyz;
        let out = [r * y * z, r * x * z, r * xy];
        // an intermediate r y or r x can still overflow for a very uneven triple
        if out[0].is_finite() && out[1].is_finite() && out[2].is_finite() {
            return out;
        }
    }
    [T::ONE / x, T::ONE / y, T::ONE / z]
}

// The tangent map's pieces (issue 13; used by `crate::tangent`): appended, so the step above is
// unchanged.
impl<T: Real> PreMv<T> {
    /// The carried step ([`Integrator::step_carrying`]) through `Mv`'s.
    fn step_carried(&mut self, m: &mut [T; 3], lost: &mut [T; 3]) -> Result<(), StepError> {
        let mut next = match self.prepare(m, None)? {
            None => *m,
            Some(held) => held,
        };
        // Mv leaves its input and `lost` as they were on Err
        self.mv.step_carrying(&mut next, lost, true)?;
        *m = next;
        self.last = Some(*m);
        self.h_changed = false;
        Ok(())
    }

    /// [`Integrator::step_state`], with the attitude checked before a pending change is
    /// applied where `check_q` (false: the caller has checked it).
    #[inline(always)]
    fn step_state_checking(&mut self, s: &mut State<T>, check_q: bool) -> Result<(), StepError> {
        // in place when the momentum needs no hold: a copy of the state in and out cost
        // the host's f32 step 4 ns in 25
        match self.prepare(&s.m, check_q.then_some(&s.q))? {
            None => self.mv.step_state(s)?,
            Some(held) => {
                let mut next = State::new(held, s.q);
                self.mv.step_state(&mut next)?;
                *s = next;
            }
        }
        self.last = Some(s.m);
        self.h_changed = false;
        Ok(())
    }

    /// The carried step ([`Integrator::step_state_carrying`]) through `Mv`'s.
    fn step_state_carried(
        &mut self,
        s: &mut State<T>,
        lost: &mut State<T>,
    ) -> Result<(), StepError> {
        let mut next = match self.prepare(&s.m, None)? {
            None => *s,
            Some(held) => State::new(held, s.q),
        };
        self.mv.step_state_carrying(&mut next, lost, true)?;
        *s = next;
        self.last = Some(s.m);
        self.h_changed = false;
        Ok(())
    }

    /// `step_state` that also returns the step's turn `p = quat(X)` and the modified body's
    /// mass matrix `J~` it was taken with (the same lines as `step_state`).
    #[inline]
    pub(crate) fn step_state_rotation(
        &mut self,
        s: &mut State<T>,
    ) -> Result<(Quat<T>, Vec3<T>), StepError> {
        let p = match self.prepare(&s.m, Some(&s.q))? {
            None => self.mv.step_state_rotation(s)?,
            Some(held) => {
                let mut next = State::new(held, s.q);
                let p = self.mv.step_state_rotation(&mut next)?;
                *s = next;
                p
            }
        };
        self.last = Some(s.m);
        self.h_changed = false;
        Ok((p, Vec3::from_array(self.mv.body().mass_matrix())))
    }

    /// `d J~ / d m` at momentum `m` (row `i` is the gradient of `J~_i`; zero for order 2).
    pub(crate) fn modified_mass_matrix_jacobian(&self, m: &[T; 3]) -> Result<Mat3<T>, StepError> {
        let di = self.modifier.modified_inertia_jacobian(self.h, m)?;
        // J~_i = (I~_j + I~_k - I~_i) / 2, row by row
        let (r0, r1, r2) = (di.row0(), di.row1(), di.row2());
        let half = c::<T>(0.5);
        let j0 = r1.add(r2).sub(r0).scale(half);
        let j1 = r0.add(r2).sub(r1).scale(half);
        let j2 = r0.add(r1).sub(r2).scale(half);
        Ok(Mat3::from_cols(j0, j1, j2).transpose())
    }
}

impl<T: Real> Modifier<T> {
    /// `d I~ / d m` (row `i` is the gradient of `I~_i`), by differentiating
    /// `1 / I~_i = (1 + s(C, X)) / I_i + d(C, X)` with `grad C = h^2 m`,
    /// `grad X = h^2 (I^-1 - 1 / I_max) m`:
    /// `grad I~_i = -I~_i^2 ((s_C grad C + s_X grad X) / I_i + d_C grad C + d_X grad X)`. The
    /// partials of the tabulated polynomials are exact (monomial by monomial); on a rod
    /// `gs a + gd` cancels on the large axes, where `I~` is nearly `I` (relative error up to
    /// 1.4e-7 in f64 at `I_min / I_max = 3e-8`, against 50-digit arithmetic; elsewhere near
    /// round-off).
    fn modified_inertia_jacobian(&self, h: T, m: &[T; 3]) -> Result<Mat3<T>, StepError> {
        let inertia = self.modified_inertia(h, m)?;
        let zero = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
        if self.order <= 2 {
            return Ok(Mat3::from_cols(zero, zero, zero));
        }
        // in the scaled units of the tables ([`Modifier`]): with `C' = C / kappa^2`,
        // `X' = X / kappa` and `d' = kappa d`, `grad C' = (h / kappa)^2 m`,
        // `grad X' = (h / kappa)^2 (kappa / I - 1) m` and `1 / I~_i = ((1 + s) a_i + d') / kappa`
        let [a1, a2, a3] = self.a;
        let hk2 = sq(h * self.inv_kappa);
        let mv = Vec3::from_array(*m);
        let (cc, xx) = self.scaled_invariants(h, m);
        let cp = [T::ONE, cc, sq(cc), sq(cc) * cc];
        let xp = [T::ONE, xx, sq(xx), sq(xx) * xx];
        let (mut s_c, mut s_x, mut d_c, mut d_x) = (T::ZERO, T::ZERO, T::ZERO, T::ZERO);
        // s[k][a] multiplies C^a X^(k + 1 - a); the powers read with `get` (always in range:
        // at opt-level `s` the indexing kept its bounds checks, a panic path in the firmware's
        // no-panic build there, found in review)
        let pw = |p: &[T; 4], i: usize| p.get(i).copied().unwrap_or(T::ZERO);
        for (k, (sk, dk)) in self.s.iter().zip(self.d.iter()).enumerate() {
            let deg = k + 1;
            for (a, (&sa, &da)) in sk.iter().zip(dk.iter()).enumerate().take(deg + 1) {
                let b = deg - a;
                if a > 0 {
                    let w = c::<T>(a as f64) * pw(&cp, a - 1) * pw(&xp, b);
                    s_c += sa * w;
                    d_c += da * w;
                }
                if b > 0 {
                    let w = c::<T>(b as f64) * pw(&cp, a) * pw(&xp, b - 1);
                    s_x += sa * w;
                    d_x += da * w;
                }
            }
        }
        let grad_c = mv.scale(hk2);
        let [b1, b2, b3] = self.b;
        let grad_x = Vec3::new(b1 * mv.x, b2 * mv.y, b3 * mv.z).scale(hk2);
        let gs = grad_c.scale(s_c).add(grad_x.scale(s_x));
        let gd = grad_c.scale(d_c).add(grad_x.scale(d_x));
        let row = |ii: T, a: T| gs.scale(a).add(gd).scale(-sq(ii) * self.inv_kappa);
        let [i1, i2, i3] = inertia;
        let jac = Mat3::from_cols(row(i1, a1), row(i2, a2), row(i3, a3)).transpose();
        if jac.is_finite() {
            Ok(jac)
        } else {
            Err(StepError::Overflow)
        }
    }
}
