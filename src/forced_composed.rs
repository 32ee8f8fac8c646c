//! Forced steps of order 4 and 6: symmetric compositions of the kick–turn–drift–turn–kick
//! step, and Nyström and force-gradient splittings of kicks and near-exact drifts.
//!
//! # Three kinds of scheme
//!
//! Every scheme here is a palindrome of kicks and drifts,
//!
//! `kick(b_0 h) drift(a_1 h) kick(b_1 h) ... drift(a_n h) kick(b_n h)`,
//!
//! where `kick(s)` is `m <- m + s tau(t, q)` at the current time and attitude, `drift(s)` the
//! free integrator over `s` (with the rotor's turns around it) and the clock advances with
//! the drifts. They differ in what they assume of the drift.
//!
//! - **Compositions** ([`Composed::new`]) compose [`crate::Forced`]'s symmetric order-2 step
//!   with lengths `gamma_i h`, so `a_i = gamma_i` and `b_i = (gamma_i + gamma_i+1) / 2`
//!   (consecutive half kicks merged). The drift may be any symmetric order-2 free integrator
//!   (`Mv` included) and a rotor is allowed. Coefficients (Hairer, Lubich & Wanner, Geometric
//!   Numerical Integration, 2nd ed., §V.3.2): order 4 with McLachlan's five stages (SIAM J.
//!   Sci. Comput. 16 (1995) 151, `p4 s5`, the smallest error constant among five-stage
//!   methods), order 6 with Kahan and Li's nine (Math. Comp. 66 (1997) 1089, `s9odr6`).
//! - **Nyström splittings** ([`Composed::nystrom`]) split the forced body into the kick `B`
//!   and the free flow `A` and take the drift for `A`'s exact flow. A torque of the time
//!   and the attitude, `tau(t, q)`, gives `[B, [B, [B, A]]] = 0`: the kick's vector field
//!   does not depend on `m` and the free body's is quadratic in `m` (and affine in it on the
//!   attitude), so three brackets with `B` differentiate `A` three times in `m`. The order
//!   conditions are then those of Runge–Kutta–Nyström methods for `y'' = f(y)`, fewer than a
//!   general splitting's, and Blanes & Moan (J. Comput. Appl. Math. 142 (2002) 313) spent
//!   the freedom on small error terms: `SRKN_6^b` (order 4, 6 drifts) and `SRKN_11^b`
//!   (order 6, 11 drifts). The drift must be exact to the scheme's order: [`crate::PreMv`]
//!   of order at least 4 or 6, or [`crate::Exact`]; with `Mv` (order 2) the scheme is of
//!   order 2. A rotor breaks the property (the free gyrostat is not split exactly by the
//!   turns), so a Nyström scheme refuses one.
//! - **The force-gradient splitting** ([`Composed::force_gradient`]): Chin's scheme 4A
//!   (Phys. Lett. A 226 (1997) 344), `B(h/6) A(h/2) B~(2h/3) A(h/2) B(h/6)`, order 4 with two
//!   drifts where `SRKN_6^b` takes six. The same property makes `[B, [A, B]]` a kick too, and
//!   the middle kick `B~` carries it: its torque is `tau + (h^2/24) (tau'[w] - tau x w)`,
//!   `w = I^-1 tau` (docs/MATH.md §9). Same drift requirements and no rotor.
//!
//! Measured at `T = 10` against mpmath references (README, `rigid3-lab forced-work`): on the
//! heavy top, with `PreMv` order 10 as the drift, the order-6 Nyström scheme reaches `1e-10`
//! with about half the counted operations of RK4 and the order-4 one `1e-8` with 1.5x fewer;
//! the force-gradient scheme (`PreMv` order 6 drift) reaches `1e-5` and `1e-6` with slightly
//! fewer than RK4 and `1e-4` with 2 % more (the Nyström schemes needed 1.4x more there); the
//! compositions need more than RK4 at every level from `1e-4` to `1e-10`.

use crate::body::Body;
use crate::error::StepError;
use crate::forced::{
    across_drift, carried_for, forcing_accessors, half_turn, kick, turn_momentum, turn_state,
    Forcing,
};
use crate::forced_relative::{relative_wanted, RelativeStep, RotorRates};
use crate::integrator::{carries_rounding, checked_momentum, checked_state, Integrator, State};
use crate::linalg::{Quat, Vec3};
use crate::real::{c, Real};
use crate::torque::Torque;

/// The most distinct drift lengths a scheme has (`SRKN_11^b`).
const STAGES: usize = 6;
/// The most kicks a step has (`SRKN_11^b`: 11 drifts, 12 kicks).
const KICKS: usize = 12;

/// A palindromic scheme: its distinct drift lengths, the order the drifts are taken in, and
/// the kick lengths (one more than the drifts; empty for a composition, whose kicks follow
/// from the drifts).
struct Scheme {
    order: u8,
    drifts: [f64; STAGES],
    pattern: &'static [u8],
    kicks: &'static [f64],
    /// Per kick, the coefficient `c_k` of its force-gradient term (empty: none; see
    /// [`CHIN_4A`]).
    gradient: &'static [f64],
}

// the coefficients keep the digits their sources give; the last of each palindrome follows
// from consistency (the drifts and the kicks each sum to 1)
#[allow(clippy::excessive_precision)]
const MCLACHLAN_4: Scheme = Scheme {
    order: 4,
    drifts: [
        0.28,
        0.625_466_428_467_670_045_01,
        -0.810_932_856_935_340_090_02,
        0.0,
        0.0,
        0.0,
    ],
    pattern: &[0, 1, 2, 1, 0],
    kicks: &[],
    gradient: &[],
};

#[allow(clippy::excessive_precision)]
const KAHAN_LI_6: Scheme = Scheme {
    order: 6,
    drifts: [
        0.392_161_444_007_314_139_279_250_56,
        0.332_599_136_789_359_438_599_748_64,
        -0.706_246_172_557_639_359_809_964_82,
        0.082_213_596_293_550_800_231_490_45,
        0.798_543_990_934_829_963_398_950_35,
        0.0,
    ],
    pattern: &[0, 1, 2, 3, 4, 3, 2, 1, 0],
    kicks: &[],
    gradient: &[],
};

#[allow(clippy::excessive_precision)]
const BM4_A: [f64; 2] = [0.245_298_957_184_271, 0.604_872_665_711_080];
#[allow(clippy::excessive_precision)]
const BM4_B: [f64; 3] = [
    0.082_984_406_417_405_2,
    0.396_309_801_498_368,
    -0.039_056_304_922_348_6,
];
const BM4_B4: f64 = 1.0 - 2.0 * (BM4_B[0] + BM4_B[1] + BM4_B[2]);

/// Blanes & Moan's `SRKN_6^b`: `B A B A B A B A B A B A B`, order 4.
const BLANES_MOAN_4: Scheme = Scheme {
    order: 4,
    drifts: [BM4_A[0], BM4_A[1], 0.5 - BM4_A[0] - BM4_A[1], 0.0, 0.0, 0.0],
    pattern: &[0, 1, 2, 2, 1, 0],
    kicks: &[
        BM4_B[0], BM4_B[1], BM4_B[2], BM4_B4, BM4_B[2], BM4_B[1], BM4_B[0],
    ],
    gradient: &[],
};

#[allow(clippy::excessive_precision)]
const BM6_A: [f64; 5] = [
    0.123_229_775_946_271,
    0.290_553_797_799_558,
    -0.127_049_212_625_417,
    -0.246_331_761_062_075,
    0.357_208_872_795_928,
];
#[allow(clippy::excessive_precision)]
const BM6_B: [f64; 5] = [
    0.041_464_998_518_262_4,
    0.198_128_671_918_067,
    -0.040_006_192_104_153_3,
    0.075_253_984_301_580_7,
    -0.011_511_387_420_687_9,
];
const BM6_A6: f64 = 1.0 - 2.0 * (BM6_A[0] + BM6_A[1] + BM6_A[2] + BM6_A[3] + BM6_A[4]);
const BM6_B6: f64 = 0.5 - (BM6_B[0] + BM6_B[1] + BM6_B[2] + BM6_B[3] + BM6_B[4]);

/// Blanes & Moan's `SRKN_11^b`: 11 drifts between 12 kicks, order 6.
const BLANES_MOAN_6: Scheme = Scheme {
    order: 6,
    drifts: [BM6_A[0], BM6_A[1], BM6_A[2], BM6_A[3], BM6_A[4], BM6_A6],
    pattern: &[0, 1, 2, 3, 4, 5, 4, 3, 2, 1, 0],
    kicks: &[
        BM6_B[0], BM6_B[1], BM6_B[2], BM6_B[3], BM6_B[4], BM6_B6, BM6_B6, BM6_B[4], BM6_B[3],
        BM6_B[2], BM6_B[1], BM6_B[0],
    ],
    gradient: &[],
};

/// Chin's forward scheme 4A (Phys. Lett. A 226 (1997) 344):
/// `B(h/6) A(h/2) B~(2h/3) A(h/2) B(h/6)`, order 4 with two drifts, where the middle kick
/// carries the force-gradient term `[B, [A, B]]` (see [`Composed::force_gradient`]).
const CHIN_4A: Scheme = Scheme {
    order: 4,
    drifts: [0.5, 0.0, 0.0, 0.0, 0.0, 0.0],
    pattern: &[0, 0],
    kicks: &[1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
    gradient: &[0.0, FG_C, 0.0],
};

/// The force-gradient coefficient of [`CHIN_4A`]'s middle kick: its torque is
/// `tau + FG_C h^2 (tau'[I^-1 tau] - tau x I^-1 tau)`.
const FG_C: f64 = 1.0 / 24.0;

impl Scheme {
    /// The kick coefficients `b_0 .. b_n` (zeros past `n`).
    fn kick_coefficients(&self) -> [f64; KICKS] {
        let mut b = [0.0; KICKS];
        if self.kicks.is_empty() {
            // a composition: half of each stage's length on either side of it
            for (k, &i) in self.pattern.iter().enumerate() {
                let g = 0.5 * self.drifts.get(usize::from(i)).copied().unwrap_or(0.0);
                if let Some(x) = b.get_mut(k) {
                    *x += g;
                }
                if let Some(x) = b.get_mut(k + 1) {
                    *x += g;
                }
            }
        } else {
            for (x, &v) in b.iter_mut().zip(self.kicks) {
                *x = v;
            }
        }
        b
    }

    /// The force-gradient coefficients `c_k` of the kicks (zeros past `n`, and for a scheme
    /// without).
    fn gradient_coefficients(&self) -> [f64; KICKS] {
        let mut g = [0.0; KICKS];
        for (x, &v) in g.iter_mut().zip(self.gradient) {
            *x = v;
        }
        g
    }
}

/// The torque of a force-gradient kick, `tau + eps (tau'[w] - tau x w)` with `w = I^-1 tau`
/// and `eps = c_k h^2`: the kick's torque plus `eps / 2` times the bracket `[B, [A, B]]`,
/// which is `2 (tau'[w] - tau x w)` (a field of the time and the attitude alone, so still a
/// kick; docs/MATH.md §9). `tau'[w]` is the torque's rate of change as the body turns at `w`
/// ([`Torque::turn_rate`], linear in `w`, so it is taken at `eps w`: `tau x w` and `w` itself
/// can overflow in f32 where `eps w` does not). A model without it in closed form is evaluated
/// once more at the attitude turned by `eps w`, through the Cayley quaternion
/// `((1 - |v|^2), 2 v) / (1 + |v|^2)`, `v = eps w / 4`: unit to rounding (a torque model may
/// assume a unit attitude) and the rotation by `eps w` to first order, which is enough (the
/// difference quotient's error is `O(eps^2) = O(h^4)`, and a kick multiplies it by `h`).
/// `Overflow` for a turn too large to represent (a non-finite torque is refused by the drift
/// it is kicked into, or by the step's final check). A kick without a gradient term
/// (`eps = 0`) keeps `tau` as it is.
#[inline]
fn kick_torque<T: Real, F: Torque<T>>(
    torque: &F,
    t: T,
    q: Quat<T>,
    tau: Vec3<T>,
    inv_i: Vec3<T>,
    eps: T,
) -> Result<Vec3<T>, StepError> {
    if eps == T::ZERO {
        return Ok(tau);
    }
    let ew = inv_i.mul_elem(tau).scale(eps);
    let bracket = tau.cross(ew);
    if let Some(rate) = torque.turn_rate(t, &q.to_array(), ew.to_array()) {
        return Ok(tau.add(Vec3::from_array(rate)).sub(bracket));
    }
    let v = ew.scale(c::<T>(0.25));
    let v2 = v.norm2();
    if !v2.is_finite() {
        return Err(blown(tau));
    }
    let inv = T::ONE / (T::ONE + v2);
    let two = inv + inv;
    let p = Quat {
        w: (T::ONE - v2) * inv,
        x: v.x * two,
        y: v.y * two,
        z: v.z * two,
    };
    let turned = Vec3::from_array(torque.torque(t, &q.mul(p).to_array()));
    Ok(turned.sub(bracket))
}

/// Stage `i`'s drift, length and turn (a match, not indexing: no panic path).
#[inline]
fn stage<'a, T: Copy, D>(
    stages: &'a mut [D; STAGES],
    lengths: &[T; STAGES],
    turns: &[Option<Quat<T>>; STAGES],
    i: u8,
) -> (&'a mut D, T, Option<Quat<T>>) {
    let [s0, s1, s2, s3, s4, s5] = stages;
    let [g0, g1, g2, g3, g4, g5] = *lengths;
    let [t0, t1, t2, t3, t4, t5] = *turns;
    match i {
        0 => (s0, g0, t0),
        1 => (s1, g1, t1),
        2 => (s2, g2, t2),
        3 => (s3, g3, t3),
        4 => (s4, g4, t4),
        _ => (s5, g5, t5),
    }
}

/// A forced step of order 4 or 6 built from kicks and a free integrator's drifts: a
/// symmetric composition of [`crate::Forced`]'s step ([`Composed::new`]) or a Nyström
/// splitting ([`Composed::nystrom`]), or Chin's force-gradient splitting
/// ([`Composed::force_gradient`]); each constructor names its scheme and source (McLachlan
/// 1995, Kahan & Li 1997, Blanes & Moan 2002, Chin 1997).
///
/// Each distinct drift length has its own copy of the drift (up to 6), so an `Mv` or `PreMv`
/// drift keeps its tracked root and modified body per stage. Cost per step: 5, 9, 6 or 11
/// drifts (composition 4, 6; Nyström 4, 6), one torque evaluation per drift plus the start
/// one (with attitude, [`Integrator::step_state`] reuses the last step's end torque instead) and
/// one kick more than drifts (15 flops each, their rounding
/// carried as in [`crate::Forced`], and so are the drifts' and the rotor turns' rounding of
/// the state: [`crate::Forced`]'s error model). Conserves what [`crate::Forced`] conserves and, for a
/// potential torque and a symplectic drift, is symplectic. Errors at `T = 10` on the forced
/// scenes are in the README's work-precision tables.
///
/// In f32 without a torque (a free body or gyrostat composed to order 4 or 6), every stage's
/// drift solves its 3x3 system from the last stage's result, and that solve's relative
/// error (about `eps`, not a rounding of a sum) is not carried: on the spacecraft
/// `I = (60, 95, 120)` at 0.1 rad/s and 200 Hz the attitude ends 5.5e-5 rad (order 4) and
/// 1.2e-4 (order 6) from f64 after `10^6` steps, where the free `Mv` ends 1.5e-5 (the
/// scene's sensitivity to one ulp of `m`: 1.5e-6); at 1 rad/s 3.1e-4 and 6.2e-4 against
/// 9.3e-5; at 1.3e-3 rad/s and 1 kHz all three end within 6e-8. For the free body in f32
/// use `Mv`. With wheels, each stage's turn is one rotation rounded once (its angle off by
/// about `eps` relative, the same every step), so the attitude drifts linearly, as much as
/// one f32 ulp of the wheels' momentum moves it: on that spacecraft with a 2 N m s wheel
/// under the gravity gradient at 200 Hz, 8.6e-7 rad from f64 after `2 x 10^5` steps, 0.9x
/// the f64 run's sensitivity to one ulp of `h_r` and 5.8x its sensitivity to one ulp of
/// `m0` (a review counting the momentum's error too: 19x; [`crate::Forced`]'s single turn
/// about 1.6x; tests/forced.rs `f32_composed_with_a_wheel_drifts_as_one_ulp_of_the_wheel`).
///
/// A step that fails returns `Err` and leaves the state and the time untouched.
#[derive(Clone, Debug)]
pub struct Composed<T, D, F> {
    stages: [D; STAGES],
    turns: [Option<Quat<T>>; STAGES],
    /// Why a stage's rotor turn cannot be taken at this `h`, if so (the steps refuse).
    turn_check: Result<(), StepError>,
    /// `a_i`, the distinct drift coefficients.
    drift_coef: [T; STAGES],
    /// `a_i h`.
    drift_len: [T; STAGES],
    /// `b_k`, the kick coefficients.
    kick_coef: [T; KICKS],
    /// `b_k h`.
    kick_len: [T; KICKS],
    /// `c_k`, the force-gradient coefficients (zero for a kick without).
    grad_coef: [T; KICKS],
    /// `c_k h^2`.
    grad_len: [T; KICKS],
    /// `I^-1`, for the force-gradient kicks and the relative splitting.
    inv_i: Vec3<T>,
    /// The rotor's rates and whether the last step took the relative splitting
    /// (crate::forced_relative's `relative_wanted`).
    rates: RotorRates<T>,
    relative_on: bool,
    pattern: &'static [u8],
    order: u8,
    nystrom: bool,
    h: T,
    forcing: Forcing<T, F>,
}

impl<T: Real, D: Integrator<T> + Clone, F: Torque<T>> Composed<T, D, F> {
    fn with_scheme(drift: D, torque: F, scheme: &Scheme, nystrom: bool) -> Self {
        let h = drift.step_size();
        let drift_coef = scheme.drifts.map(c::<T>);
        let kick_coef = scheme.kick_coefficients().map(c::<T>);
        let grad_coef = scheme.gradient_coefficients().map(c::<T>);
        let inv_i = drift.body().inverse_inertia();
        let mut stages = [
            drift.clone(),
            drift.clone(),
            drift.clone(),
            drift.clone(),
            drift.clone(),
            drift,
        ];
        for (d, a) in stages.iter_mut().zip(drift_coef) {
            d.set_step_size(a * h);
        }
        Self {
            stages,
            turns: [None; STAGES],
            turn_check: Ok(()),
            drift_coef,
            drift_len: drift_coef.map(|a| a * h),
            kick_coef,
            kick_len: kick_coef.map(|b| b * h),
            grad_coef,
            grad_len: grad_coef.map(|g| g * h * h),
            inv_i,
            rates: RotorRates::none(),
            relative_on: false,
            pattern: scheme.pattern,
            order: scheme.order,
            nystrom,
            h,
            forcing: Forcing::new(torque),
        }
    }

    /// The symmetric composition of `order` (4 or 6) of the forced step with `drift` (its
    /// step size is the composed step `h`) and `torque`, at time zero, without rotor. Any
    /// symmetric order-2 drift gives the order (`Mv`, `PreMv`, `Splitting`, `Midpoint`).
    /// Order 4: McLachlan's five stages (SIAM J. Sci. Comput. 16 (1995) 151, `p4 s5`, the
    /// smallest error constant of the five-stage methods); order 6: Kahan and Li's nine (Math.
    /// Comp. 66 (1997) 1089, `s9odr6`). Orders measured 3.96–4.11 and 5.9–6.15 with
    /// time-dependent torques and a rotor (lab/tests/forced_orders.rs).
    ///
    /// # Errors
    ///
    /// `InvalidOrder` for an order other than 4 or 6.
    pub fn new(drift: D, torque: F, order: u8) -> Result<Self, StepError> {
        let scheme = match order {
            4 => &MCLACHLAN_4,
            6 => &KAHAN_LI_6,
            _ => return Err(StepError::InvalidOrder),
        };
        Ok(Self::with_scheme(drift, torque, scheme, false))
    }

    /// Blanes and Moan's Nyström splitting of `order` (4: `SRKN_6^b`, 6: `SRKN_11^b`) with
    /// `drift` taken as the free body's exact flow and `torque`, at time zero. The order holds
    /// when the drift is exact to it: [`crate::PreMv`] of order at least `order` (order 10
    /// measured best) or [`crate::Exact`]; with [`crate::Mv`] the step is of order 2. For a
    /// torque of order one these need fewer operations for a given accuracy than the
    /// compositions of [`Composed::new`] (README: heavy top, gravity gradient, periodic body
    /// torque). No rotor: [`Composed::set_rotor`] refuses a non-zero one. In f32 prefer the
    /// `PreMv` drift: an f32 `Exact` drift rounds its elliptic functions at every call (up to
    /// 11 a step), and a heavy top at `h = 0.05` ended 7.9e-6 off against 9.2e-8 with the
    /// order-10 `PreMv` drift (a trial of the lab's CLI, `propagate --method nystrom6-exact`).
    ///
    /// # Errors
    ///
    /// `InvalidOrder` for an order other than 4 or 6.
    pub fn nystrom(drift: D, torque: F, order: u8) -> Result<Self, StepError> {
        let scheme = match order {
            4 => &BLANES_MOAN_4,
            6 => &BLANES_MOAN_6,
            _ => return Err(StepError::InvalidOrder),
        };
        Ok(Self::with_scheme(drift, torque, scheme, true))
    }

    /// Chin's force-gradient splitting 4A (Phys. Lett. A 226 (1997) 344; Chin & Chen,
    /// Celest. Mech. Dyn. Astron. 91 (2005) 301): `B(h/6) A(h/2) B~(2h/3) A(h/2) B(h/6)`, order
    /// 4 with two drifts a step where Blanes and Moan's `SRKN_6^b` takes six. The middle kick
    /// `B~` also carries the bracket `[B, [A, B]]`, which for a torque `tau(t, q)` is again a
    /// kick: its torque is `tau + (h^2 / 24) (tau'[w] - tau x w)`, `w = I^-1 tau`, where
    /// `tau'[w]` is the torque's rate as the body turns at `w` and the cross product is the Lie
    /// bracket's part (docs/MATH.md §9). `tau'[w]` comes from [`Torque::turn_rate`]: in closed
    /// form for `Gravity`, `GravityGradient`, their sums and the torques that do not depend on
    /// the attitude, and then the modified kick is exactly that of the potential
    /// `V - (h^2/48) tau . I^-1 tau` and the step is symplectic for a potential torque (two
    /// torque evaluations and one rate a step; with attitude the start torque is the last
    /// step's end one). A model without a closed form (a closure) is evaluated once more, at the
    /// attitude turned by `h^2 w / 24`: the order is kept, symplecticity only to `O(h^5)` a
    /// step. The drift must be exact to order 4, as for [`Composed::nystrom`] (`PreMv` of order
    /// at least 4, order 6 measured best here, or `Exact`); no rotor. [`Composed::is_nystrom`]
    /// is true for it (it shares those requirements).
    ///
    /// Measured (`rigid3-lab forced-work`, `PreMv` order 6 drift, about 1060 counted operations
    /// a step on the heavy top): at `1e-4` on the README's heavy top 1.4x fewer operations than
    /// `SRKN_6^b`, and 4 % and 0.3 % more than RK4 at `1e-4` and `1e-5` (ties at the sweep's
    /// 1.33x step spacing; interpolated to the level, 2 % and 1 % fewer), the cheapest rigid3
    /// method there in counted operations. Host time differs: RK4's operations are cheap multiply-adds, so on
    /// the host RK4 is faster at these errors (the README's figure 9, host-time panel).
    ///
    /// # Errors
    ///
    /// None today; `Result` like the other constructors.
    pub fn force_gradient(drift: D, torque: F) -> Result<Self, StepError> {
        Ok(Self::with_scheme(drift, torque, &CHIN_4A, true))
    }

    /// The order (4 or 6).
    #[must_use]
    pub fn order(&self) -> u8 {
        self.order
    }

    /// True for a Nyström splitting ([`Composed::nystrom`]) and the force-gradient splitting
    /// ([`Composed::force_gradient`]): the schemes that need the free body's exact flow and
    /// take no rotor.
    #[must_use]
    pub fn is_nystrom(&self) -> bool {
        self.nystrom
    }

    /// Sets the rotor momentum `h_r` (body frame), as [`crate::Forced::set_rotor`]: a rotor
    /// whose turn at a stage passes half a revolution at the current step size is taken, and
    /// the steps return `StepTooLarge` until `h` or the rotor is brought back.
    ///
    /// # Errors
    ///
    /// `NonFinite` or `Overflow` as [`crate::Forced::set_rotor`]; `RotorUnsupported` for a
    /// non-zero rotor on a Nyström or force-gradient splitting. The rotor is then unchanged.
    pub fn set_rotor(&mut self, h_r: [T; 3]) -> Result<(), StepError> {
        if self.nystrom && h_r.iter().any(|&x| x != T::ZERO) {
            return Err(if h_r.iter().all(|x| x.is_finite()) {
                StepError::RotorUnsupported
            } else {
                StepError::NonFinite
            });
        }
        let [r, w] = Forcing::<T, F>::checked_rotor(self.inv_i, h_r)?;
        let (turns, check) = Self::turns_for(w, &self.drift_len);
        self.forcing.rotor_moved |= r != self.forcing.rotor;
        self.forcing.rotor = r;
        self.forcing.rotor_w = w;
        self.rates = RotorRates::new(w, self.inv_i);
        self.turns = turns;
        self.turn_check = check;
        Ok(())
    }

    /// Each stage's rotor half turn for `w = I^-1 h_r`, and the first stage's refusal if any
    /// turn cannot be taken ([`half_turn`]).
    fn turns_for(
        w: Vec3<T>,
        lengths: &[T; STAGES],
    ) -> ([Option<Quat<T>>; STAGES], Result<(), StepError>) {
        let mut turns = [None; STAGES];
        let mut check = Ok(());
        for (t, &a) in turns.iter_mut().zip(lengths) {
            match half_turn(w, a) {
                Ok(p) => *t = p,
                Err(e) => {
                    if check.is_ok() {
                        check = Err(e);
                    }
                }
            }
        }
        (turns, check)
    }

    /// The rotor `h_r` when the step from `m` takes the relative splitting (as
    /// [`crate::Forced`]'s: crate::forced_relative; the same for every stage of the step, so
    /// the composition keeps its order), `None` for the turns.
    #[inline(always)]
    fn relative(&self, m: Vec3<T>) -> Option<Vec3<T>> {
        let h_r = self.forcing.rotor;
        (self.turns[0].is_some()
            && relative_wanted(m, h_r, self.inv_i, self.rates, self.relative_on))
        .then_some(h_r)
    }

    fn update_turns(&mut self) {
        (self.turns, self.turn_check) = Self::turns_for(self.forcing.rotor_w, &self.drift_len);
    }

    forcing_accessors!();

    /// Total energy (kinetic of the gyrostat plus the potential), `None` without a potential
    /// or when the sum is not finite (it overflows).
    #[must_use]
    pub fn total_energy(&self, s: &State<T>) -> Option<T> {
        self.forcing.total_energy(self.stages[0].body(), s)
    }

    /// One step under the model's torque **plus** a torque given at both ends of the step
    /// (`tau_start` at `t`, `tau_end` at `t + h`; the same value twice for a zero-order hold),
    /// as [`crate::Forced::step_state_plus`] does for the order-2 step: the controller's
    /// command added to an environment model. The given torque is taken linear in time
    /// between the two values, so each kick inside the step sees it at its own time; a
    /// command held over the step, or one that varies linearly, keeps the scheme's order (4
    /// or 6), a smooth command sampled at the ends gives order 2 in its own part. The model's
    /// end torque is kept for the next step's start (one model evaluation per kick, as in
    /// [`Integrator::step_state`]). A command of exactly zero at both ends is the model's own
    /// step. Torques are in the body frame of [`Body`].
    ///
    /// # Errors
    ///
    /// `NonFinite` for a non-finite state, given torque or model torque, and the drift's
    /// errors; the state and the time are then left as they were (the given torques are
    /// checked before any drift steps).
    pub fn step_state_plus(
        &mut self,
        s: &mut State<T>,
        tau_start: [T; 3],
        tau_end: [T; 3],
    ) -> Result<(), StepError> {
        let zero = [T::ZERO; 3];
        if tau_start == zero && tau_end == zero {
            return self.step_state(s);
        }
        let (start, end) = (Vec3::from_array(tau_start), Vec3::from_array(tau_end));
        if !(start.is_finite() && end.is_finite()) {
            return Err(StepError::NonFinite);
        }
        let slope = end.sub(start).scale(T::ONE / self.h);
        let given = Linear {
            start,
            end,
            // a zero `h` (a pause) has no slope to take
            slope: if slope.is_finite() {
                slope
            } else {
                Vec3::new(T::ZERO, T::ZERO, T::ZERO)
            },
            h: self.h,
        };
        self.step_state_given(s, given)
    }

    /// [`Integrator::step_state`] with `given` added to the model's torque at every kick.
    #[inline(always)]
    fn step_state_given<G: Given<T>>(
        &mut self,
        s: &mut State<T>,
        given: G,
    ) -> Result<(), StepError> {
        let (m0, q0) = checked_state(s)?;
        self.turn_check?;
        let mut clock = self.forcing.clock;
        let end = self.forcing.clock_after(self.h)?;
        let last = self.pattern.len() - 1;
        let mut tau = self.forcing.torque_at(clock.t, q0)?;
        let eps = self.grad_len[0];
        let first = given_kick(
            &self.forcing.torque,
            &given,
            T::ZERO,
            clock.t,
            q0,
            tau,
            self.inv_i,
            eps,
        )?;
        // the drifts' lengths so far, for the given torque's time
        let mut elapsed = T::ZERO;
        let lost0 = carried_for(m0, Vec3::from_array(self.forcing.lost.m));
        let (mut m, mut lost) = kick(m0, first.scale(self.kick_len[0]).add(lost0));
        let (mut q, mut lost_q) = (q0, Quat::from_array(self.forcing.lost.q));
        let carry = carries_rounding::<T>();
        // the turns' and the drifts' roundings join the carry after the last kick, as in `step`
        let mut pending = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
        let rel = self.relative(m0);
        for (k, ((&i, &b), &g)) in self
            .pattern
            .iter()
            .zip(self.kick_len.iter().skip(1))
            .zip(self.grad_len.iter().skip(1))
            .enumerate()
        {
            let (d, a, turn) = stage(&mut self.stages, &self.drift_len, &self.turns, i);
            let rel = rel.map(|h_r| RelativeStep::new(h_r, self.inv_i, a));
            if let Some(r) = rel {
                // the kicks' carried rounding joins `n` (crate::forced_relative's `enter`), and
                // so does the last stage's: `m = n + h_r` rounded `n` to an ulp of `|h_r|`,
                // and left in `pending` to the step's end the later stages ran from the rounded
                // `n` (f32 energy 4.7e-3 then 7.4e-3 in `2 x 10^5` steps where `Forced` keeps
                // 1.8e-4, found in review); f64 carries nothing
                let (n, dropped, left) = r.enter(m, lost.add(pending), carry);
                (m, pending, lost) = (n, dropped, left);
            } else if let Some(p) = turn {
                ((m, q), (pending, lost_q)) = turn_state(p, (m, q), (pending, lost_q), carry);
            }
            if carry {
                // the roundings applied after this drift cross it (crate::forced's
                // `across_drift`), the last kick's with them
                pending = across_drift(pending.add(lost), m, self.inv_i, a);
                lost = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
            }
            // a non-finite kick makes the drift's input non-finite, and the drift refuses it
            let mut st = State::new(m.to_array(), q.to_array());
            let mut dropped = State::new(pending.to_array(), lost_q.to_array());
            // the free body is left to the drift's own holds (crate::forced's kdk)
            d.step_state_carrying(&mut st, &mut dropped, carry)?;
            (pending, lost_q) = (Vec3::from_array(dropped.m), Quat::from_array(dropped.q));
            m = Vec3::from_array(st.m);
            q = Quat::from_array(st.q);
            if let Some(r) = rel {
                (m, pending) = r.leave(m, pending, carry);
            } else if let Some(p) = turn {
                ((m, q), (pending, lost_q)) = turn_state(p, (m, q), (pending, lost_q), carry);
            }
            // the stages' rounded `a_i h` need not sum to `h`: the step ends at `t + h` exactly
            clock = if k == last { end } else { clock.after(a) };
            elapsed += a;
            tau = Vec3::from_array(self.forcing.torque.torque(clock.t, &q.to_array()));
            let at = if k == last { self.h } else { elapsed };
            let pushed = given_kick(
                &self.forcing.torque,
                &given,
                at,
                clock.t,
                q,
                tau,
                self.inv_i,
                g,
            )?;
            (m, lost) = kick(m, pushed.scale(b).add(lost));
        }
        if !m.is_finite() {
            return Err(blown(tau));
        }
        // (as in `step`); not while a given torque acts, which the holds (they test the model
        // alone) took for none: with a zero model and a command, `R(q) m` was held against the
        // command's torque and the attitude came out 6.7e-2 rad off at every step size (found
        // in review)
        if self.turns[0].is_some() && !carry && given.at(T::ZERO).is_none() {
            // relative steps as in crate::forced's step_state
            if rel.is_none() || self.forcing.rotor_moved {
                m = self.forcing.hold_casimir(m0, m, rel.is_some());
                q = self.forcing.hold_spatial(m0, q0, m, q, rel.is_some());
            } else {
                self.forcing.bridge_holds(m0, Some(q0), m, Some(q));
            }
        }
        let lost = if carry { lost.add(pending) } else { lost };
        let lost = State::new(lost.to_array(), lost_q.to_array());
        self.forcing.commit(s, m, q, clock, lost, tau);
        self.relative_on = rel.is_some();
        self.forcing.rotor_moved = false;
        Ok(())
    }
}

/// A torque given on top of the model at a step's kicks ([`Composed::step_state_plus`]).
trait Given<T: Real> {
    /// The given torque after drifts of total length `elapsed` (`None`: none given).
    fn at(&self, elapsed: T) -> Option<Vec3<T>>;
}

/// No given torque: [`Integrator::step_state`].
struct NoGiven;

impl<T: Real> Given<T> for NoGiven {
    #[inline(always)]
    fn at(&self, _elapsed: T) -> Option<Vec3<T>> {
        None
    }
}

/// A torque given at both ends of a step of length `h`, linear in time between them (the
/// kicks of a composition fall inside the step).
struct Linear<T> {
    start: Vec3<T>,
    end: Vec3<T>,
    /// `(end - start) / h`.
    slope: Vec3<T>,
    h: T,
}

impl<T: Real> Given<T> for Linear<T> {
    #[inline(always)]
    fn at(&self, elapsed: T) -> Option<Vec3<T>> {
        Some(if elapsed == self.h {
            self.end
        } else {
            self.start.add(self.slope.scale(elapsed))
        })
    }
}

/// The model's torque plus a given body-frame torque at one instant, as a model: the given
/// part does not turn with the body, so the turn rate is the model's.
struct Plus<'a, T, F> {
    model: &'a F,
    given: Vec3<T>,
}

impl<T: Real, F: Torque<T>> Torque<T> for Plus<'_, T, F> {
    fn torque(&self, t: T, q: &[T; 4]) -> [T; 3] {
        Vec3::from_array(self.model.torque(t, q))
            .add(self.given)
            .to_array()
    }
    fn depends_on_attitude(&self) -> bool {
        self.model.depends_on_attitude()
    }
    fn turn_rate(&self, t: T, q: &[T; 4], w: [T; 3]) -> Option<[T; 3]> {
        self.model.turn_rate(t, q, w)
    }
}

/// [`kick_torque`] for the model's torque `tau` plus what `given` gives after `elapsed`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn given_kick<T: Real, F: Torque<T>, G: Given<T>>(
    model: &F,
    given: &G,
    elapsed: T,
    t: T,
    q: Quat<T>,
    tau: Vec3<T>,
    inv_i: Vec3<T>,
    eps: T,
) -> Result<Vec3<T>, StepError> {
    match given.at(elapsed) {
        None => kick_torque(model, t, q, tau, inv_i, eps),
        Some(g) => kick_torque(&Plus { model, given: g }, t, q, tau.add(g), inv_i, eps),
    }
}

/// The error of a step whose momentum came out non-finite.
fn blown<T: Real>(tau: Vec3<T>) -> StepError {
    if tau.is_finite() {
        StepError::Overflow
    } else {
        StepError::NonFinite
    }
}

impl<T: Real, D: Integrator<T> + Clone, F: Torque<T>> Integrator<T> for Composed<T, D, F> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        if self.forcing.torque.depends_on_attitude() {
            return Err(StepError::NeedsAttitude);
        }
        let id = [T::ONE, T::ZERO, T::ZERO, T::ZERO];
        let v0 = checked_momentum(m)?;
        self.turn_check?;
        let mut clock = self.forcing.clock;
        let end = self.forcing.clock_after(self.h)?;
        let last = self.pattern.len() - 1;
        let mut tau = Vec3::from_array(self.forcing.torque.torque(clock.t, &id));
        let qid = Quat::from_array(id);
        // (no scheme here has a gradient term on its first kick; this keeps one that did)
        let eps = self.grad_len[0];
        let first = kick_torque(&self.forcing.torque, clock.t, qid, tau, self.inv_i, eps)?;
        let lost0 = carried_for(v0, Vec3::from_array(self.forcing.lost.m));
        let (mut v, mut lost) = kick(v0, first.scale(self.kick_len[0]).add(lost0));
        // the rounding is carried whenever the precision needs it, torque or not: `Forced`
        // leaves a free body to its drift's own free-running step and holds, but here each
        // stage's drift starts from another stage's result, so it never runs free and never
        // holds (without torque and rotor, f32 `R(q) m` drifted by 1.2e-3 in `10^6` steps of
        // order 4 at 1 kHz, found in review); f64 carries nothing
        let carry = carries_rounding::<T>();
        // the turns' and the drifts' roundings join the carry after the last kick, off the
        // step's critical path (crate::forced's kdk)
        let mut pending = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
        let rel = self.relative(v0);
        for (k, ((&i, &b), &g)) in self
            .pattern
            .iter()
            .zip(self.kick_len.iter().skip(1))
            .zip(self.grad_len.iter().skip(1))
            .enumerate()
        {
            let (d, a, turn) = stage(&mut self.stages, &self.drift_len, &self.turns, i);
            let rel = rel.map(|h_r| RelativeStep::new(h_r, self.inv_i, a));
            if let Some(r) = rel {
                // (as in step_state_given: the last stage's rounding joins `n` too)
                let (n, dropped, left) = r.enter(v, lost.add(pending), carry);
                (v, pending, lost) = (n, dropped, left);
            } else if let Some(p) = turn {
                (v, pending) = turn_momentum(p, v, pending, carry);
            }
            if carry {
                // (as in step_state_given)
                pending = across_drift(pending.add(lost), v, self.inv_i, a);
                lost = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
            }
            let mut arr = v.to_array();
            let mut dropped = pending.to_array();
            // the free body is left to the drift's own holds (crate::forced's kdk)
            d.step_carrying(&mut arr, &mut dropped, carry)?;
            pending = Vec3::from_array(dropped);
            v = Vec3::from_array(arr);
            if let Some(r) = rel {
                (v, pending) = r.leave(v, pending, carry);
            } else if let Some(p) = turn {
                (v, pending) = turn_momentum(p, v, pending, carry);
            }
            // the stages' rounded `a_i h` need not sum to `h`: the step ends at `t + h` exactly
            clock = if k == last { end } else { clock.after(a) };
            tau = Vec3::from_array(self.forcing.torque.torque(clock.t, &id));
            let pushed = kick_torque(&self.forcing.torque, clock.t, qid, tau, self.inv_i, g)?;
            (v, lost) = kick(v, pushed.scale(b).add(lost));
        }
        if !v.is_finite() {
            return Err(blown(tau));
        }
        // the gyrostat's holds only where the rounding is not carried (f64; crate::forced),
        // and not after relative steps (crate::forced's step_state)
        if self.turns[0].is_some() && !carry {
            if rel.is_none() || self.forcing.rotor_moved {
                v = self.forcing.hold_casimir(v0, v, rel.is_some());
            } else {
                self.forcing.bridge_holds(v0, None, v, None);
            }
        }
        self.forcing.lost.m = if carry { lost.add(pending) } else { lost }.to_array();
        *m = v.to_array();
        self.forcing.clock = clock;
        self.relative_on = rel.is_some();
        self.forcing.rotor_moved = false;
        Ok(())
    }

    // out of line: left to the heuristics it was inlined into the firmware's truth loop, 3.3
    // KB more flash and 3.6 KB more stack once the relative splitting's choice had its margin
    #[inline(never)]
    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        self.step_state_given(s, NoGiven)
    }

    fn step_size(&self) -> T {
        self.h
    }

    fn set_step_size(&mut self, h: T) {
        // the same h changes nothing (each stage's drift would see it as its own no-op, but
        // Exact drops its cache on a change)
        if h == self.h {
            return;
        }
        self.h = h;
        self.drift_len = self.drift_coef.map(|a| a * h);
        self.kick_len = self.kick_coef.map(|b| b * h);
        self.grad_len = self.grad_coef.map(|g| g * h * h);
        for (d, a) in self.stages.iter_mut().zip(self.drift_len) {
            d.set_step_size(a);
        }
        self.update_turns();
    }

    fn body(&self) -> &Body<T> {
        self.stages[0].body()
    }

    fn reset(&mut self) {
        for d in self.stages.iter_mut() {
            d.reset();
        }
        self.forcing.forget();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scheme on the pendulum `y'' = -sin y` (drift `y += s v` exact, kick
    /// `v += s F~`) over `[0, 3]` with `n` steps. `F = -sin y`; a force-gradient kick adds
    /// `c_k h^2 F' F = c_k h^2 sin y cos y` (flat space: no bracket term).
    fn pendulum(s: &Scheme, n: usize) -> (f64, f64) {
        let h = 3.0 / n as f64;
        let b = s.kick_coefficients();
        let g = s.gradient_coefficients();
        let force = |y: f64, k: usize| -libm::sin(y) + g[k] * h * h * libm::sin(y) * libm::cos(y);
        let (mut y, mut v) = (1.2f64, 0.3f64);
        for _ in 0..n {
            v += b[0] * h * force(y, 0);
            for (k, &i) in s.pattern.iter().enumerate() {
                y += s.drifts[usize::from(i)] * h * v;
                v += b[k + 1] * h * force(y, k + 1);
            }
        }
        (y, v)
    }

    /// Classical RK4 with `n` steps: the independent reference.
    fn pendulum_rk4(n: usize) -> (f64, f64) {
        let h = 3.0 / n as f64;
        let f = |y: f64, v: f64| (v, -libm::sin(y));
        let (mut y, mut v) = (1.2f64, 0.3f64);
        for _ in 0..n {
            let k1 = f(y, v);
            let k2 = f(y + 0.5 * h * k1.0, v + 0.5 * h * k1.1);
            let k3 = f(y + 0.5 * h * k2.0, v + 0.5 * h * k2.1);
            let k4 = f(y + h * k3.0, v + h * k3.1);
            y += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            v += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        }
        (y, v)
    }

    #[test]
    fn every_scheme_has_its_order_on_the_pendulum() {
        let (yr, vr) = pendulum_rk4(200_000);
        for (name, s) in [
            ("McLachlan 4", &MCLACHLAN_4),
            ("Kahan-Li 6", &KAHAN_LI_6),
            ("Blanes-Moan 4", &BLANES_MOAN_4),
            ("Blanes-Moan 6", &BLANES_MOAN_6),
            ("Chin 4A", &CHIN_4A),
        ] {
            let err = |n: usize| {
                let (y, v) = pendulum(s, n);
                (y - yr).abs().max((v - vr).abs())
            };
            let (e1, e2) = (err(10), err(20));
            let p = (e1 / e2).log2();
            assert!(
                (p - f64::from(s.order)).abs() < 0.15,
                "{name}: order {p:.2} ({e1:.2e}, {e2:.2e})"
            );
        }
    }

    /// Without its gradient term Chin's scheme is of order 2: the term is what the order
    /// rests on (and a wrong sign of `FG_C` fails the order test above).
    #[test]
    fn chin_4a_needs_its_gradient_term() {
        let plain = Scheme {
            gradient: &[],
            ..CHIN_4A
        };
        let (yr, vr) = pendulum_rk4(200_000);
        let err = |n: usize| {
            let (y, v) = pendulum(&plain, n);
            (y - yr).abs().max((v - vr).abs())
        };
        let p = (err(10) / err(20)).log2();
        assert!((p - 2.0).abs() < 0.15, "order {p:.2}");
    }

    #[test]
    fn composition_kicks_are_the_merged_half_kicks() {
        let k = MCLACHLAN_4.kick_coefficients();
        let g = MCLACHLAN_4.drifts;
        assert_eq!(k[0], 0.5 * g[0]);
        assert_eq!(k[1], 0.5 * g[0] + 0.5 * g[1]);
        assert_eq!(k[2], 0.5 * g[1] + 0.5 * g[2]);
        assert_eq!(k[5], 0.5 * g[0]);
    }
}
