//! `Mv`: the discrete Moser–Veselov step in closed form, with no eigenvectors, no square root
//! and no trigonometry per step (docs/MATH.md §4).
//!
//! # Derivation
//!
//! `W = X J` is a right solvent of `W^2 - M W - J^2 = 0` with spectrum `lambda_1..3` (the
//! roots with `Re > 0`, docs/MATH.md §2). With `s1 = sum lambda_i`, `s2 = sum lambda_i lambda_j`,
//! `s3 = lambda_1 lambda_2 lambda_3 = J1 J2 J3`, Cayley–Hamilton for `W` and the solvent
//! equation give the linear system `L W = R`,
//!
//! `L = M^2 + J^2 - s1 M + s2 I`,  `R = s1 J^2 + s3 I - M J^2`.
//!
//! Since `M^T = -M`, `X^T = J^-1 W^T = J^-1 R^T L^-T = (diag(s1 J + s3 J^-1) + J M) L^-T`, and
//! `s3 J^-1 = diag(J2 J3, J1 J3, J1 J2)` needs no division. So one step is
//!
//! `L^T y = m_k`,   `m_{k+1} = (s1 J + diag(J2 J3, J1 J3, J1 J2)) y + J (M y)`,
//!
//! one 3x3 solve with one right-hand side, and nothing divides by `J_i`: planar bodies work.
//! `s1` is the largest real root of `(s^2 - A)^2 - 8 s3 s - 4 B` ([`crate::cubic`]), and
//! `s2 = (s1^2 - A) / 2`. `A` and `B` depend on `m` only through `|m|^2` and
//! `sum J_i^2 m_i^2`, which the DMV map conserves, so `s1` is constant along a trajectory: it is
//! found exactly once and then tracked, which keeps it at round-off (freezing it lets
//! round-off grow without bound, docs/MATH.md §4, unless each step's input is moved back
//! onto the invariants, as here, and `h |Omega|` is small).
//!
//! # The free-running step
//!
//! While the caller leaves the state alone and `|s1 - sum J| <= 1e-2 sum J` (about
//! `h |Omega| < 0.2`), `s1`, `s2` and `|m|^2` are constants of the trajectory, the solve above
//! collapses to a rational map of `m` with precomputed coefficients (crate::mv_frozen, one
//! division and no 3x3 solve), and the attitude is renormalised and held to the spatial
//! momentum only every 8th step (`HOLD_PERIOD`). An outside change of `m`, `h` or the body
//! takes the solve above for that step.
//!
//! # Existence
//!
//! A real solution exists iff the cubic `mu^3 - A mu^2 + B mu - C` (`C = s3^2`) has no negative
//! real root (docs/MATH.md §3). Its roots have product `C >= 0`, so either all are real (then all
//! are positive iff `A > 0` and `B > 0`) or one is real and positive with a complex pair. Hence
//! the step exists iff `A > 0 && B > 0`, or the discriminant of the cubic is negative: two
//! comparisons on the common path, a discriminant only for large steps.

use crate::body::Body;
use crate::cubic::quartic_largest_root;
use crate::error::StepError;
use crate::integrator::{
    carries_rounding, checked_momentum, checked_state, compose_attitude, compose_attitude_carried,
    compose_unrenormalised, norms_agree, turn_in_space, write_state_stepped, Integrator, State,
};
use crate::linalg::{Mat3, Quat, Vec3};
use crate::mv_frozen::FrozenMap;
use crate::real::{c, sq, Real};

/// Per-trajectory data of the closed-form step: the scale, the scaled body and
/// `delta = s1 - (j1 + j2 + j3)`.
///
/// `s1` itself is `J1 + J2 + J3 + O(h^2)`, and the step needs `s1 - sum J` (and the rest of
/// the map minus the identity) to full relative accuracy when `h |Omega|` is small: computing
/// `s1` and subtracting would leave the increment with an error of `eps / (h |Omega|)`, which
/// in f32 at a 200 Hz loop (`h |Omega| ~ 5e-4`) drifted the energy by 2% in 10^6 steps. So the
/// quartic is written about `s1_0 = sum j`: with `alpha = |mm|^2`, `beta = sum a_i j_i^2`,
/// `eps_u = 2 s1_0 delta + delta^2 + alpha` and `u0 = s1_0^2 - sum j_i^2 = 2 s2_0`,
///
/// `g(delta) = 2 u0 eps_u + eps_u^2 - 8 s3 delta + 4 beta = 0`,
///
/// every term of which is small when `h` is (the quartic of docs/MATH.md §4 minus its value at
/// `h = 0`).
#[derive(Clone, Copy, Debug)]
struct Track<T> {
    /// The scale `kappa`, chosen at the exact solve (`max(J_max, h |m|)`).
    kappa: T,
    /// `1 / kappa` (infinite for a subnormal `kappa`: then [`Track::scaled`] divides), so that
    /// the updates after a change of `h` or of a `PreMv`'s modified body need no division.
    inv_kappa: T,
    /// `h / kappa`, applied to `m`.
    hn: T,
    /// `J / kappa`.
    j: Vec3<T>,
    /// `(J / kappa)^2`.
    j2: Vec3<T>,
    /// `j_i^2 + s2_0`, the diagonal of `L^T` at `h = 0` less `s2 - s2_0`.
    c0: Vec3<T>,
    /// `sum j_i^2`.
    sum_j2: T,
    /// `j1^2 j2^2 + j1^2 j3^2 + j2^2 j3^2`.
    pair_j2: T,
    /// `8 s3 = 8 j1 j2 j3`.
    s3x8: T,
    /// `s3 = j1 j2 j3`.
    s3: T,
    /// `s1_0 = j1 + j2 + j3`.
    s0: T,
    /// `2 s1_0`.
    two_s0: T,
    /// `2 u0 = 4 s2_0`.
    two_u0: T,
    /// `delta = s1 - s1_0` for the current invariants.
    delta: T,
    /// `1 / g'(delta)` at the exact solve: the invariants are constant along a trajectory, so
    /// the derivative is too, and the tracking step needs no division (a chord step, which
    /// converges like Newton's while the invariants move by at most `sqrt(eps)`).
    inv_dg: T,
    /// `2 sqrt(eps) s1_0`: a tracking correction above it means the invariants moved.
    newton_tol: T,
    /// `2 sqrt(eps)`.
    tol_unit: T,
    /// `delta` is small enough (`h |Omega|` small) that a free-running step keeps it as it
    /// is and runs the rational map: see [`Mv::system`] and [`Mv::advance_frozen`].
    may_freeze: bool,
}

impl<T: Real> Track<T> {
    /// All zero: the fields are set by [`Track::set_mass_matrix`] and the caller.
    fn zero() -> Self {
        let z = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
        Self {
            kappa: T::ONE,
            inv_kappa: T::ONE,
            hn: T::ZERO,
            j: z,
            j2: z,
            c0: z,
            sum_j2: T::ZERO,
            pair_j2: T::ZERO,
            s3x8: T::ZERO,
            s3: T::ZERO,
            s0: T::ZERO,
            two_s0: T::ZERO,
            two_u0: T::ZERO,
            delta: T::ZERO,
            inv_dg: T::ZERO,
            newton_tol: T::ZERO,
            tol_unit: T::ZERO,
            may_freeze: false,
        }
    }

    /// `x / kappa`, by the stored reciprocal unless `kappa` is subnormal.
    #[inline]
    fn scaled(&self, x: T) -> T {
        if self.inv_kappa.is_finite() {
            x * self.inv_kappa
        } else {
            x / self.kappa
        }
    }

    /// The body's part of the tracking data for mass matrix `j` in the kept scale `kappa`
    /// (`delta` is left as it is: the start of the next Newton solve).
    fn set_mass_matrix(&mut self, j: Vec3<T>) {
        let jn = Vec3::new(self.scaled(j.x), self.scaled(j.y), self.scaled(j.z));
        let j2 = jn.mul_elem(jn);
        let s0 = jn.x + jn.y + jn.z;
        let s2_0 = jn.x * jn.y + jn.x * jn.z + jn.y * jn.z;
        self.j = jn;
        self.j2 = j2;
        self.c0 = Vec3::new(j2.x + s2_0, j2.y + s2_0, j2.z + s2_0);
        self.sum_j2 = j2.x + j2.y + j2.z;
        self.pair_j2 = j2.x * j2.y + j2.x * j2.z + j2.y * j2.z;
        self.s3x8 = c::<T>(8.0) * jn.x * jn.y * jn.z;
        self.s3 = jn.x * jn.y * jn.z;
        self.s0 = s0;
        self.two_s0 = s0 + s0;
        self.two_u0 = c::<T>(4.0) * s2_0;
        self.newton_tol = self.tol_unit * s0;
    }
}

/// The new momentum, and the DMV part of its increment (`X^T m - m`, without the
/// invariants' correction).
struct Advanced<T> {
    next: Vec3<T>,
    increment: Vec3<T>,
    /// What was added to `m` (the increment with the invariants' fix): `next = m + applied`
    /// rounded once, so `applied - (next - m)` is what that rounding lost.
    applied: Vec3<T>,
    /// A carried step's fix onto its input's invariants ([`fix_from_increment`]), handed to
    /// the carry whole: added to the increment it was below an ulp of it at large turns and
    /// rounding dropped most of it (at `h |Omega| = 0.2` the fixed steps still drifted the
    /// energy 5-30x more than the unfixed ones, found in review).
    fix: Vec3<T>,
}

impl<T: Real> Advanced<T> {
    /// `lost + (applied - (next - m))`: what the rounding of `m + applied` dropped, added to
    /// the carry `lost` (Fast2Sum, as crate::forced's kicks).
    #[inline(always)]
    fn carry_into(&self, m: Vec3<T>, lost: [T; 3]) -> [T; 3] {
        Vec3::from_array(lost)
            .add(dropped_by_sum(m, self.applied, self.next).add(self.fix))
            .to_array()
    }
}

/// What rounding `next = m + added` dropped: `added - (next - m)`, exact (Fast2Sum: `added`
/// is the smaller term).
#[inline(always)]
fn dropped_by_sum<T: Real>(m: Vec3<T>, added: Vec3<T>, next: Vec3<T>) -> Vec3<T> {
    added.sub(next.sub(m))
}

/// The explicit discrete Moser–Veselov step in closed form: the crate's flagship (order 2).
///
/// Solves `h hat(m_k) = X J - J X^T` for `X` in SO(3) with `X J` having its spectrum in
/// `Re > 0` (Moser & Veselov 1991; the talk's eq. (2)) and sets `m_{k+1} = X^T m_k`,
/// `R_{k+1} = R_k X`, through the linear system of the module docs: 78 counted flops per
/// free-running momentum step on average (one division: the rational map of
/// crate::mv_frozen; the invariants held every 8th step) and 152–163 with attitude (the
/// turn's quaternion is read off the momentum pair, by a series at small turns, else with two
/// square roots; the attitude is renormalised and held every 8th step), and 250–300 with
/// attitude on a step after an outside change (the 3x3 solve; talk's case, `h` = 0.01–0.1,
/// `rigid3-lab flops`); no
/// `sqrt` in the momentum step, no trigonometry, no eigenvectors. `s1` is solved when the integrator is built or reset,
/// and re-solved when the caller changes `m` (a filter's correction, a torque kick) or `h` (a
/// jittering clock): by guarded Newton steps from the tracked value (one or two divisions,
/// no transcendental call), or from its series in `h^2` for a fresh start; only at
/// `h |Omega|` of order one does it fall back to the closed-form quartic root.
///
/// Invariants held to round-off, not just conserved by the map: while the caller leaves the
/// state alone, every 8th step moves its input back onto the trajectory's `|m|^2` and energy
/// (to first order, division-free on most steps) and turns the new attitude back onto the
/// trajectory's spatial momentum `R(q) m`. Without this, rounding drifts them: in f32 at
/// 200 Hz on the firmware's spacecraft, `E` by `2.6e-5` and `R(q) m` by `7.3e-5` after `10^6`
/// steps, growing; held, all three stay below `2e-6` through `10^8` steps (tests/soak.rs).
///
/// Motion along the invariants carried, not rounded away (f32): a slowly turning body moves
/// `m` and `q` by a few ulps a step, and rounding each step's sum lost a biased part of that
/// motion, which no hold can restore (at 1.3e-3 rad/s and 1 kHz the attitude was 8.3e-3 rad
/// and `m` 7.4e-3 off after `10^6` steps). In f32 the plain steps keep what the rounding of
/// `m + increment` and `q + turn` dropped (Fast2Sum: the error of a sum is exact) and add it
/// to the next step's increments, also across a caller's small corrections (`m` within 1 %
/// of the momentum returned last, `q` within about 0.02 rad of the attitude) and across
/// pauses (a filter or a clock that dropped it every tick lost the slow motion's rounding
/// with a bias: `|m|^2` 1.3e-3 off after `2 x 10^5` ticks at 8.4e-4 rad/s, now 1.2e-8,
/// tests/mv.rs
/// `f32_slow_turns_keep_their_motion_under_corrections_and_pauses`; found in review), on
/// trajectories with `h |Omega|` below `1e-3` (above, rounding is unbiased, carrying it
/// measured worse, and the steps are the plain ones): 1.0e-7 rad and 2.6e-8 there, 1.4e-5
/// rad at 1.3e-1 rad/s, 5.7e-6 at 0.1 rad/s and 200 Hz (was 9.1e-5;
/// tests/mv.rs `f32_slow_turns_keep_their_phase`, against f64). The attitude hold skips turns below `8 eps`, the noise of measuring
/// `R(q) m` in f32: taken at every hold they drove the phase about the spatial momentum by
/// 8e-6 rad in the same run. Cost on the M4F, measured when it was added: 18 instructions of
/// the 188 of a momentum step then, 49 of the 370 with attitude (the steps are 191 and 369
/// now, `scripts/firmware`). In f64 the rounding costs about 1e-13 rad there, and nothing
/// is carried (the branches are constants, folded away).
///
/// Accuracy: agrees with the general Cardoso–Leite solver to about `1e-15` per step (f64);
/// second order, time-reversible, Poisson; the phase error on the talk's case is `0.51 h^2`
/// at `t = 10` (see `PreMv` to remove it). A solved step (the first, and every step after
/// the caller changed `m` or `h` by much) is accurate to about `eps I_max / I_min` (its 3x3
/// system's condition on a needle, whose two small mass-matrix entries add up to `I_min`;
/// [`Body::mass_matrix`]. One small entry alone costs nothing: on a near-planar body
/// `(1, 1, 2 - 1e-4)`, `J_min / J_max = 5e-5`, f32 stays within 2.4e-5 rad of f64 after
/// 5000 steps at `h |Omega|` up to 0.1, as on a compact body, where f32 RK4 is 2.1e-4 off):
/// negligible in f64, but in f32 a body of inertia `(0.001, 1, 1.0005)` starts `|m|^2` 5.8e-4
/// off, and a loop that re-takes the invariants every tick ([`Integrator::reset`], or a
/// correction of `m` every step) adds such errors up (29 % in 3000 steps there, 2.4e-5 at
/// `(0.01, 1, 1)`). Use f64 for needles with `I_min / I_max` below about `1e-2`: at `1e-2`
/// f32 `Mv` already ends 2.6x as far from f64 as f32 RK4 does (4.0e-4 against 1.5e-4 rad
/// after 5000 steps; tests/mv.rs `f32_accuracy_is_set_by_the_needle_not_by_a_small_mass_matrix_entry`),
/// 3-7x at `1e-3`, and below that a step can be `Ok` with its attitude far off (1.2 rad at
/// `3.4e-6`, where the f64 step is 2e-9 off; found in review). On a rod (one moment `eps`
/// times the others) that error lands, in f64 too, on the momentum's component along the rod,
/// whose rate `m_1 / I_1` the small moment magnifies: `I = (1e-7, 1, 1)`,
/// `m0 = (3e-8, -0.6, 1.1)`, `h = 0.05` ends 2.2e-2 off the exact solution at `t = 10`,
/// where the method's own error is 3.0e-3 (at `eps = 1e-2` to `1e-5`: 3.0e-3 to 3.1e-3); and
/// [`PreMv`](crate::PreMv) stalls near `1e-12` at `eps = 1e-3`, `1e-8` at `1e-5`, `1e-2` at
/// `1e-7` (tests/mv_pre.rs `pre_mv_on_a_rod_is_no_worse_than_mv`).
///
/// Known limit (found in review, not fixed): within about `1e-3` of [`Mv::max_step`] on a
/// planar or near-planar body (a mass-matrix entry below about `1e-3` of the largest), a step
/// can turn the body by more than 120 degrees, and the attitude then takes the turn of the
/// same `|sin|` below 60 degrees with `Ok` (11 of 2800 such steps on those bodies at 0.9 to
/// 0.9999 of `max_step`, none on others): the branch is tested only for turns between 60 and
/// 120 degrees, since a test on every large turn would cost the common steps. Such steps are
/// far outside any useful accuracy (the map's sensitivity grows without bound at the limit).
///
/// Works for every valid body (equal moments, planar bodies `J_i = 0`), `m = 0`, `m` on a
/// principal axis, `|m|` from `1e-150` to `1e150` (f64: everything is scaled by
/// `max(J_max, h |m|)`), and up to [`Mv::max_step`], past which a step returns
/// `StepTooLarge` and leaves the state as it was.
#[derive(Clone, Debug)]
pub struct Mv<T> {
    body: Body<T>,
    h: T,
    track: Option<Track<T>>,
    anchor: Option<Anchor<T>>,
    /// The step size changed since the last step: the next step checks existence even when
    /// `m` is the momentum returned last.
    recheck: bool,
    /// The body changed since the last step: the DMV invariants are taken afresh from the
    /// next input (they depend on `J`), while the spatial momentum is kept (it does not).
    retake: bool,
    /// The rational map was refused on this trajectory (it would amplify round-off: a
    /// needle, [`FrozenMap::new`], or a hold found `|m|^2` moved): each solved step clears
    /// the tracking data's `may_freeze`, which its update sets again, until a re-solve from
    /// scratch. (Here, not in the tracking data: there it cost the free-running M4F step 3
    /// instructions.)
    no_map: bool,
    /// `I^-1`.
    inv_i: Vec3<T>,
    /// `h I^-1 / 4`, for the attitude's update ([`Mv::rotation_between`]).
    turn_scale: Lane4<T>,
    /// The free-running map's coefficients for the current trajectory, `h` and body (built
    /// by the first free-running step at small `h |Omega|`, dropped by every other step).
    frozen: Option<FrozenMap<T>>,
    /// Steps since the last full attitude step (`0` = the next step is one): see
    /// [`HOLD_PERIOD`].
    phase: u8,
    /// What the rounding of the plain steps' `m + increment` and `q + turn` dropped (f32,
    /// [`carries_rounding`]): added to the next step's increments while the caller leaves the
    /// state alone, so that increments below an ulp are not lost (Fast2Sum, as the carried
    /// step's).
    carry_m: Vec3<T>,
    carry_q: Quat<T>,
    /// The `alpha` above which a carried f32 step keeps its input's invariants: [`FIX_ALPHA`]
    /// on a compact body, zero (every step) on an elongated one ([`FIX_SPREAD`]); set with
    /// the body (a `PreMv`'s modified bodies differ from its own by `O(h^2)` and keep it).
    fix_alpha: T,
}

/// A step with attitude renormalises `q` and turns it back onto the spatial momentum (about
/// 110 flops) only every `HOLD_PERIOD`-th step, and whenever the caller changed `q`;
/// the steps between compose the turn without either. Both correct round-off of an ulp or so
/// a step, so between two holds `|q|` and `R(q) m` move by at most a few ulps, and the drift
/// stays bounded (tests/soak.rs); a step never costs more than before.
const HOLD_PERIOD: u8 = 8;
/// In f32 (where the steps carry their rounding, [`carries_rounding`]) the attitude hold turns
/// only when `|pi x pi0| / (2 |pi0|^2)`, half its angle, exceeds `sqrt(DEADBAND) eps = 4 eps`: below
/// that is the noise of computing `R(q) m` in f32, and turning by it at every hold drove the
/// phase about `pi0` (8e-6 rad in `10^6` steps at 1.3e-3 rad/s and 1 kHz, 60x the carried
/// steps' own error). `R(q) m` then stays within about `8 eps` of the trajectory's.
const DEADBAND: f64 = 16.0;
/// The plain f32 steps carry their rounding ([`carries_rounding`]) while the trajectory's
/// `(h |Omega|)^2` (taken with its invariants, [`Anchor::retake`]) is at most this: there a
/// step moves `m` and `q` by few enough ulps that rounding loses a biased part of the
/// motion. Above, rounding is unbiased, and carrying it measured worse in review (spacecraft
/// at 1 rad/s and 200 Hz, median over 8 directions after `10^6` steps: 1.7e-3 rad from f64
/// against 5.2e-4, 5.5e-2 against 4.4e-3 after `10^7`; a rod spinning about its axis under a
/// jittering clock, 0.71 against 0.082 rad; mechanism not found), so those steps are the
/// plain ones, bit for bit. (A first version gated on `|h m / kappa|^2`, which follows
/// `h |Omega|` only for compact bodies: on the rod it carried up to `h |Omega| = 0.1`.)
const CARRY_TURN2: f64 = 1e-6;
/// A carried f32 step on a compact body moves its result back onto its input's invariants
/// ([`fix_from_increment`]) where `alpha = |h m / kappa|^2` is above this. `kappa` is at least
/// `J_max` and `|Omega| >= |m| / (2 J_max)`, so there `h |Omega| > 5e-4`; the test is one
/// comparison with a number the step has (a test on the increment's size cost the M4F's
/// forced step 15 instructions, this one with its per-body threshold 12). Below, the bias the
/// fix removes is about `1e-13` of the energy a step on compact bodies (measured on three),
/// `1e-7` over `10^6` steps, and the fix's own cost (about 180 instructions) is not spent.
const FIX_ALPHA: f64 = 1e-6;
/// A body whose mass matrix spreads by more than this (`J_max > FIX_SPREAD J_min`) has its
/// carried f32 steps kept on their input's invariants at every `h`: there the bias does not
/// shrink with `h |Omega|` (measured per step, in units of `eps (h |Omega|)^2`: 5000 at
/// `h |Omega| = 5e-5` on `I = (8, 120, 122)`, spread 39, against 0.1-2 on compact bodies; it
/// drifted that body's carried free steps to 4.9e-5 rad from f64 in `10^6` steps, 1.0e-6 with
/// the fix). 16 is where the last release stopped carrying such bodies after a torque (their
/// carried steps drifted), between the measured spreads 4.4 and 39.
const FIX_SPREAD: f64 = 16.0;

/// `Mv::fix_alpha` for `body` ([`FIX_ALPHA`], [`FIX_SPREAD`]).
fn fix_alpha<T: Real>(body: &Body<T>) -> T {
    let [j1, j2, j3] = body.mass_matrix();
    let (lo, hi) = (j1.min(j2).min(j3), j1.max(j2).max(j3));
    if hi <= c::<T>(FIX_SPREAD) * lo {
        c::<T>(FIX_ALPHA)
    } else {
        T::ZERO
    }
}

/// A hold step of the free-running map finds `|m|^2` within this many ulps of the anchored
/// value (the steps between holds move it by about one each; the talk's case and random bodies
/// stay below 3 in f32 and f64), or the map is stopped on the trajectory ([`Mv::refuse_map`]).
const HELD_ALPHA_ULPS: f64 = 64.0;
const _: () = assert!(HOLD_PERIOD.is_power_of_two());

/// A 3-vector followed by a zero on hosts: x86's SLP vectorizer loads a field like this 16
/// bytes at a time, and the fourth lane it multiplies along is then zero, not the bits of
/// whatever field follows (a flag read as a subnormal f32: each multiply with it took a
/// microcode assist, on 7 of 8 f32 steps; tests/host_subnormals.rs). Bare-metal targets have
/// no vector lanes and keep the 12 bytes (an integrator on a Cortex-M4F stack is not made
/// larger for a host's sake).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
struct Lane4<T> {
    v: Vec3<T>,
    #[cfg(not(target_os = "none"))]
    zero: T,
}

impl<T: Real> Lane4<T> {
    fn new(v: Vec3<T>) -> Self {
        Self {
            v,
            #[cfg(not(target_os = "none"))]
            zero: T::ZERO,
        }
    }
}

/// The invariants the trajectory must keep: taken from the input whenever it is not the
/// momentum this integrator returned last (the caller changed it). They are the DMV map's
/// `alpha = |mm|^2` and `beta = sum j_i^2 mm_i^2`, which the quartic needs anyway, kept in the
/// step's scaled units (`|m|^2` itself overflows f32 above `1.8e19`); each step moves its
/// input back onto them to first order (exact to `O(eps^2)`) by `x m + y (j^2 m)`
/// ([`Anchor::correction`]).
#[derive(Clone, Copy, Debug)]
struct Anchor<T> {
    last: Vec3<T>,
    /// The invariants of the DMV map in the step's scaled units for the current `h`:
    /// `alpha = |mm|^2` and `beta = sum j_i^2 mm_i^2` (`mm = h m / kappa`), which fix `|m|^2`
    /// and the energy (docs/MATH.md §2).
    alpha: T,
    beta: T,
    /// `16 eps beta`: the energy's drift tolerated before it is corrected.
    beta_tol: T,
    /// `1 / (2 alpha)` once a step has needed it (zero before, and for `m = 0`): a step that
    /// takes the anchor from its own input has nothing to correct, so a loop that changes `m`
    /// every tick (a torque kick) never pays this division.
    half_inv: T,
    /// `h / kappa` when the invariants were taken, and their values then: a change of `h`
    /// rescales `taken (hn / hn0)^2` (rounded afresh each time from the same numbers, so a
    /// jittering step does not let the invariants random-walk, as rescaling `alpha` itself
    /// would). The ratio is taken before squaring: `hn^2` leaves f32's range for `h / kappa`
    /// below `1e-19`, a body of moments `1e20` at `h = 0.1` (the anchor then read zero, and the
    /// step after a change of `h` was refused as `Degenerate`).
    hn0: T,
    taken: (T, T),
    /// The scale `kappa` when the invariants were taken, and `taken.1` in the current scale:
    /// a re-solve after a large change of `h` may choose another `kappa`, and `beta`
    /// (`j = J / kappa` in it) moves by its square. Both are carried from the taken values,
    /// so repeated re-solves do not let `beta` random-walk.
    kappa0: T,
    beta_base: T,
    /// Free-running steps since the last one that moved its input back onto the invariants
    /// (`0` = the next one does): see [`Mv::advance_frozen`].
    unheld: u8,
    /// `(h |Omega|)^2` when the invariants were taken, and whether the plain f32 steps carry
    /// their rounding on this trajectory at the current `h` ([`CARRY_TURN2`]).
    turn2_taken: T,
    carry: bool,
    /// A change of `h` since the invariants were last scaled to the current `h`: `alpha`,
    /// `beta`, `beta_tol` and `half_inv` are stale until [`Anchor::settle`], which the steps
    /// that read them call (a hold, the free-running map's build). Under a jittering clock a
    /// hold comes every [`HOLD_PERIOD`]-th step, so the other steps do not rescale (two
    /// divisions; 36 of the 634 instructions of the M4F's jittered step when every change
    /// rescaled). `turn2` follows the changes meanwhile (multiplied by each change's ratio:
    /// it only sets `carry`, and each settle takes it afresh from `turn2_taken`). A byte, not
    /// a `bool`: a second `bool` moved the niche of `Option<Anchor>` and the free-running
    /// step's test of `carry` took 3 instructions more on the M4F.
    stale: u8,
    turn2: T,
    /// With attitude: the spatial momentum of the trajectory (`pi0 = R(q) m` as taken, then
    /// `pi0 / |pi0|^2` once a step needs it) and the attitude returned last.
    spatial: Option<Spatial<T>>,
}

/// The 2x2 solve of [`Anchor::correction`], or `None` where the Gram determinant is small.
///
/// The determinant's products `a_i a_k` are of order `alpha^2`, which leaves the normal range
/// long before `alpha` does (f32 below `h |Omega|` of about `1e-10`: it went subnormal, its
/// inverse overflowed, and a step at `h = 1e-9` returned `Overflow`, found in review): there
/// every invariant is first divided by `alpha = sum a_i` (elsewhere the scale is one, and
/// exact).
#[cold]
#[inline(never)]
fn energy_correction<T: Real>(k: Invariants<T>, t: &Track<T>, da: T, db: T) -> Option<(T, T)> {
    let scale = if k.sum_a >= (T::MIN_POSITIVE / T::EPSILON).sqrt() {
        T::ONE
    } else {
        T::ONE / k.sum_a
    };
    if !scale.is_finite() {
        return None;
    }
    let a = k.a.scale(scale);
    let (sum_a, beta, da, db) = (k.sum_a * scale, k.beta * scale, da * scale, db * scale);
    let j2 = t.j2;
    // formed here, out of line, not kept in the Track: a PreMv updates its body after every
    // outside change, and only this cold path needs them
    let (d12, d13, d23) = (sq(j2.x - j2.y), sq(j2.x - j2.z), sq(j2.y - j2.z));
    let det = a.x * a.y * d12 + a.x * a.z * d13 + a.y * a.z * d23;
    let gamma = a.dot(j2.mul_elem(j2));
    if det > c::<T>(1e-3) * sum_a * gamma {
        let inv = c::<T>(0.5) / det;
        Some((
            (gamma * da - beta * db) * inv,
            (sum_a * db - beta * da) * inv,
        ))
    } else {
        None
    }
}

/// The fix that moves `m + inc` back onto the invariants `alpha`, `beta` of `m` (as
/// [`Anchor::correction`] moves an input onto the anchored ones), with their change computed
/// from the increment itself: `|m + inc|^2 - |m|^2 = sum inc_i (2 m_i + inc_i)` (and with
/// weights `j_i^2` for `beta`), exact algebra whose rounding is relative to the increment,
/// not to `m`. The fix is taken along the invariants' gradients at `m + inc`, where it is
/// applied, and goes to the carry ([`Advanced::fix`]).
///
/// Why: a carried f32 step (every step of a forced integrator under a torque) changes `|m|^2`
/// and the energy by a bias with the same sign along the trajectory: about `eps (h |Omega|)^2`
/// a step on compact bodies (mean `-4.7e-11` of the energy at `h |Omega| = 0.02`, `-1e-12` at
/// `0.002`, against a spread of `8e-8` that the carry takes back), more on elongated ones
/// ([`FIX_SPREAD`]). The step's constants (the scaled body's `j_i^2`, `s1_0`, `s2_0`, `s3`,
/// each rounded on its own) and the tracked root are rounded the same way at every step of a
/// trajectory whose invariants do not move, so their error does not average out; a free
/// trajectory's holds remove it, under a torque nothing is held. A satellite tumbling at
/// 0.2 rad/s under the gravity gradient at 10 Hz drifted its Jacobi integral by `-4.5e-5` of
/// the energy in `10^6` f32 steps and ended 200x the scene's sensitivity to one ulp of `m0`
/// from f64 (a first-use trial); with this fix about `2e-7` and 0.4-1.6x. The fix's own
/// rounding is relative to the increment: about `eps h |Omega|` a step, unbiased. Taken at
/// `m` and added to the increment, a review found it leaving a bias of relative size
/// `h |Omega|` and most of it rounded away (the fix is below an ulp of a large increment):
/// at `h |Omega| = 0.2` on the talk's body the energy then drifted `-3e-5` in `10^6` steps,
/// more than without the fix; now within `4e-6` either way (`|m|^2` 100x better than
/// without).
#[inline(never)]
fn fix_from_increment<T: Real>(
    m: Vec3<T>,
    inc: Vec3<T>,
    k: Invariants<T>,
    t: &Track<T>,
) -> Vec3<T> {
    // in the scaled units of `k` (`|hn m| <= 1`: unscaled, `inc_i m_i` overflowed f32 for
    // momenta near 1e36, which the step itself takes)
    let mm = m.scale(t.hn);
    let di = inc.scale(t.hn);
    let w = di.mul_elem(mm.add(mm).add(di));
    let (da, db) = (-(w.x + w.y + w.z), -w.dot(t.j2));
    if !(da.abs() <= t.tol_unit * k.sum_a) {
        // off the sphere by more than round-off: a step without correct digits, which the
        // step's sphere test refuses (`Degenerate`); moved back onto the sphere it passed
        // (the loop fuzz's `Degenerate` counts fell by 5-21 %)
        return Vec3::new(T::ZERO, T::ZERO, T::ZERO);
    }
    // the fix is added to the result, so its effect on the invariants is taken there (at `m`
    // it missed a part of relative size `h |Omega|`: at `h |Omega| = 0.2` a fifth of the
    // bias was left, and the energy drifted 30x more than without the fix, found in review)
    let end = mm.add(di);
    let a = end.mul_elem(end);
    let at_end = Invariants {
        a,
        sum_a: a.x + a.y + a.z,
        beta: a.dot(t.j2),
    };
    let (x, y) = match energy_correction(at_end, t, da, db) {
        Some(xy) => xy,
        None if at_end.sum_a > T::ZERO => (da * c::<T>(0.5) / at_end.sum_a, T::ZERO),
        None => (T::ZERO, T::ZERO),
    };
    let end_m = m.add(inc);
    let fix = t.invariant_fix(end_m, x, y);
    // the bias is below an ulp of `m` a step; a larger fix is the 2x2 solve amplifying the
    // rounding of `da`, `db` on a needle (`I = (1e-4, 1, 1.00005)` at `h |Omega| = 0.2`: moved
    // `m` without `q`, `R(q) m` drifted 0.45 where it drifts 0.055 unfixed, found in review)
    if fix.norm2() <= c::<T>(16.0) * sq(T::EPSILON) * end_m.norm2() {
        fix
    } else {
        Vec3::new(T::ZERO, T::ZERO, T::ZERO)
    }
}

/// What [`Mv::advance`] returns for a step of size zero; [`Mv::refused`] turns it into `Ok`
/// with the state as it was.
const PAUSED: StepError = StepError::Degenerate;

/// The smallest anchored `alpha = |h m / kappa|^2` that keeps all its digits
/// (`MIN_POSITIVE / eps`, about `1e-31` in f32 and `1e-292` in f64: `h |Omega|` below about
/// `1e-15` and `1e-146`). Below it the anchor corrects nothing: its invariants have lost
/// digits to underflow, and moving a momentum onto them moved it by up to its own size (the
/// step's own increment there is far below an ulp of `m`).
#[inline(always)]
fn full_digits<T: Real>(alpha: T) -> bool {
    alpha >= T::MIN_POSITIVE / T::EPSILON
}

/// The spatial momentum the attitude is held to.
#[derive(Clone, Copy, Debug)]
struct Spatial<T> {
    /// `pi0 / |pi0|^2` once `ready`. Until then there is no reference: the next full step
    /// takes it from its own result (the free flow keeps `R(q) m`, so any state of the
    /// trajectory will do, and the few ulps of the steps before it are accepted). A loop that
    /// changes `m` every tick re-takes it every step, which stores only a flag and `last_q`
    /// (storing the input state for it cost 7 instructions a step on the M4F).
    pi: Vec3<T>,
    ready: bool,
    last_q: Quat<T>,
}

impl<T: Real> Anchor<T> {
    /// The anchor for momentum `m` with invariants `alpha`, `beta` in scaled units.
    #[inline]
    fn take(m: Vec3<T>, k: Invariants<T>, hn: T, kappa: T, turn_scale: Option<Vec3<T>>) -> Self {
        let mut a = Self {
            last: m,
            alpha: T::ZERO,
            beta: T::ZERO,
            beta_tol: T::ZERO,
            half_inv: T::ZERO,
            hn0: T::ZERO,
            taken: (T::ZERO, T::ZERO),
            kappa0: T::ONE,
            beta_base: T::ZERO,
            unheld: 0,
            turn2_taken: T::ZERO,
            carry: false,
            stale: 0,
            turn2: T::ZERO,
            spatial: None,
        };
        a.retake(m, k, hn, kappa, turn_scale);
        a
    }

    /// Counts a step that did not hold the invariants (`unheld` wraps to `0`, "hold next", every
    /// [`HOLD_PERIOD`] steps).
    #[inline(always)]
    fn count_unheld(&mut self) {
        self.unheld = self.unheld.wrapping_add(1) & (HOLD_PERIOD - 1);
    }

    /// [`Anchor::take`] in place, keeping the spatial reference (`turn_scale`: `h I^-1 / 4`
    /// for a plain step, which may carry its rounding; `None` for a carried step, whose
    /// caller carries it: the test costs the forced step nothing).
    #[inline(always)]
    fn retake(
        &mut self,
        m: Vec3<T>,
        k: Invariants<T>,
        hn: T,
        kappa: T,
        turn_scale: Option<Vec3<T>>,
    ) {
        match turn_scale {
            Some(ts) if carries_rounding::<T>() => {
                self.turn2_taken = c::<T>(16.0) * ts.mul_elem(m).norm2();
                self.carry = self.turn2_taken <= c::<T>(CARRY_TURN2);
            }
            _ => {
                self.turn2_taken = T::MAX;
                self.carry = false;
            }
        }
        self.turn2 = self.turn2_taken;
        self.stale = 0;
        self.last = m;
        self.alpha = k.sum_a;
        self.beta = k.beta;
        self.beta_tol = c::<T>(16.0) * T::EPSILON * k.beta;
        self.half_inv = T::ZERO;
        self.hn0 = hn;
        self.taken = (k.sum_a, k.beta);
        self.kappa0 = kappa;
        self.beta_base = k.beta;
    }

    /// The first-order correction `delta = x m + y (j^2 m)` that takes the input's invariants
    /// back to the anchored ones: `[[alpha, beta], [beta, gamma]] (x, y) = (d_alpha, d_beta) / 2`
    /// with `gamma = sum a_i j_i^4`, whose determinant `sum_{i<k} a_i a_k (j_i^2 - j_k^2)^2` is
    /// formed without cancellation. Where it is small (the momentum near a principal axis, or
    /// equal moments) the energy is fixed by `|m|^2` to first order and only the Casimir is
    /// corrected (`y = 0`). Returns `(x, y)`.
    #[inline]
    fn correction(&mut self, k: Invariants<T>, t: &Track<T>) -> (T, T) {
        if self.half_inv == T::ZERO {
            // m = 0, or an anchor without its digits: nothing to correct with
            if !full_digits(self.alpha) {
                return (T::ZERO, T::ZERO);
            }
            self.half_inv = c::<T>(0.5) / self.alpha;
        }
        let da = self.alpha - k.sum_a;
        let db = self.beta - k.beta;
        // the energy drifts by a few ulps a step: correct it when it has moved by 16 (a
        // comparison on most steps, the 2x2 solve, out of line, now and then)
        if db.abs() > self.beta_tol {
            if let Some(xy) = energy_correction(k, t, da, db) {
                return xy;
            }
        }
        (da * self.half_inv, T::ZERO)
    }

    /// The same invariants for the scaled step `hn`, in place (the spatial reference is
    /// kept: it does not depend on `h`; the scale `kappa` is the one of the last
    /// [`Anchor::retake`] or [`Anchor::carried_correction`]). Out of line: inlined at the
    /// two sites that settle stale invariants it grew the M4F build by 584 bytes.
    #[inline(never)]
    fn rescale(&mut self, hn: T) {
        let r = if self.hn0 != T::ZERO {
            sq(hn / self.hn0)
        } else {
            T::ZERO
        };
        let (alpha, beta) = (self.taken.0 * r, self.beta_base * r);
        // (a zero or non-finite r turns the carry off)
        self.follow_turn2(self.turn2_taken * r);
        self.carry &= r > T::ZERO;
        self.stale = 0;
        let ok = alpha.is_finite() && beta.is_finite();
        self.alpha = if ok { alpha } else { T::ZERO };
        self.beta = if ok { beta } else { T::ZERO };
        self.beta_tol = c::<T>(16.0) * T::EPSILON * self.beta;
        // formed here, not by the next step: the division then runs beside the step's chain
        // instead of in it (a jittering clock rescales before every step)
        self.half_inv = if full_digits(self.alpha) {
            c::<T>(0.5) / self.alpha
        } else {
            T::ZERO
        };
    }

    /// The invariants scaled to the current `hn` if a change of `h` left them stale
    /// ([`Anchor::stale`]).
    #[inline(always)]
    fn settle(&mut self, hn: T) {
        if self.stale != 0 {
            self.rescale(hn);
        }
    }

    /// A change of `h` by `r2 = (h / h_old)^2` within the tracked root's range: the carry's
    /// test follows now, the invariants when a step reads them ([`Anchor::settle`]).
    #[inline(always)]
    fn rescale_later(&mut self, r2: T) {
        self.stale = 1;
        self.follow_turn2(self.turn2 * r2);
    }

    /// `(h |Omega|)^2` at the current `h` and scale, and with it whether the plain f32 steps
    /// carry ([`CARRY_TURN2`]).
    #[inline(always)]
    fn follow_turn2(&mut self, turn2: T) {
        self.turn2 = turn2;
        self.carry = carries_rounding::<T>() && turn2 <= c::<T>(CARRY_TURN2);
    }

    /// The correction towards the trajectory's invariants carried to the scaled step `t.hn`
    /// and the scale `t.kappa` chosen by a re-solve (after a change of `h` larger than the
    /// tracked root survives); `None` when they cannot be carried (the anchor read zero, or
    /// lost digits, [`full_digits`]) and must be re-taken. Out of line and cold: it runs only after a re-solve. Inlined beside
    /// the step's own correction it grew the M4F step by 370 bytes; inlined, or called from
    /// the re-solve in `Mv::system`, the host's free-running f64 step took 390 instead of
    /// 380 instructions and 8 % more time. (This shape cost the M4F's free-running step 5
    /// instructions against those, 321 vs 316 when it was measured: the layout of one large
    /// step function.)
    #[cold]
    #[inline(never)]
    fn carried_correction(&mut self, k: Invariants<T>, t: &Track<T>) -> Option<(T, T)> {
        self.beta_base = self.taken.1 * sq(self.kappa0 / t.kappa);
        self.rescale(t.hn);
        // (h |Omega|)^2 is in unscaled units: the re-solve's scale enters with h
        if self.carry {
            let r = sq(t.hn / self.hn0 * (t.kappa / self.kappa0));
            self.follow_turn2(self.turn2_taken * r);
        }
        // invariants taken at a step so small that they lost digits cannot be carried
        // (the carried correction moved m by up to its size, and the step was refused as
        // Degenerate at every step after h = 1e-22 -> 1e-3 in f32, found in review): they
        // are taken again
        if full_digits(self.taken.0) && full_digits(self.alpha) {
            self.unheld = 1;
            Some(self.correction(k, t))
        } else {
            None
        }
    }
}

impl<T: Real> Mv<T> {
    /// The unit quaternion `p` of the step's rotation `X` from the momentum before and after
    /// the step, with no matrix: writing `X = R(p)`, `p = (p0, v)`, the DMV equation
    /// `h hat(m_k) = X J - J X^T` is `h m_k = 2 p0 I v + 2 (J v) x v`, and
    /// `h hat(m_k+1) = J X - X^T J` is `h m_k+1 = 2 p0 I v - 2 (J v) x v`. Their sum gives
    /// `v = b / p0` with `b = h I^-1 (m_k + m_k+1) / 4`, and `|p| = 1` gives
    /// `p0^4 - p0^2 + |b|^2 = 0`, whose root on the step's branch (`p0 = 1` at `h = 0`) is
    /// `p0^2 = (1 + sqrt(1 - 4 |b|^2)) / 2` for steps that turn by less than about 60
    /// degrees (`1 - 4 |b|^2 >= 1/4`). About 25 flops, where forming `X` and converting it
    /// took about 200: at small turns (`h |Omega|` below about 0.035 in f64, 0.1 in f32)
    /// `p0 - 1` and `1 / p0` come from their series in `|b|^2` ([`turn_series`]: no square
    /// root, no division, which also marks the new attitude finite without a test), beyond
    /// from two square roots and one division. Accurate to a few ulps: `b` is a sum of
    /// like-signed terms. For larger turns the two roots approach each other
    /// (they meet where `4 |b|^2 = 1`) and the branch is told by the difference of the two
    /// equations, `h (m_k - m_k+1) = 4 (J v) x v`: see [`Mv::far_branch`]. Returns `p` and
    /// whether it came from the series, or `StepTooLarge` when `4 |b|^2` exceeds one by more
    /// than round-off: no rotation solves the step, so the momentum solve was past the
    /// existence limit where its own test could not tell (found by the loop fuzz: momentum on
    /// the axis of a moment 1e150 times the others, `h |Omega| = 1e59`, where the cubic's
    /// discriminant underflows; `p` came out with norm 1e113).
    #[inline]
    fn rotation_between(
        &self,
        m: Vec3<T>,
        next: Vec3<T>,
        increment: Vec3<T>,
    ) -> Result<(Quat<T>, bool), StepError> {
        let w = self.turn_scale.v;
        let b = Vec3::new(
            w.x * (m.x + next.x),
            w.y * (m.y + next.y),
            w.z * (m.z + next.z),
        );
        let b2 = b.norm2();
        if b2 <= c::<T>(series_limit::<T>()) {
            let (w_minus_1, inv) = turn_series(b2);
            let p = Quat {
                w: T::ONE + w_minus_1,
                x: b.x * inv,
                y: b.y * inv,
                z: b.z * inv,
            };
            return Ok((p, true));
        }
        let r = T::ONE - c::<T>(4.0) * b2;
        // at the existence limit r is zero up to the round-off of b (a few eps); sqrt(eps)
        // is far outside it and far inside any real excess
        if !(r >= -c::<T>(2.0) * T::EPSILON.sqrt()) {
            return Err(StepError::StepTooLarge);
        }
        let root = if r > T::ZERO { r.sqrt() } else { T::ZERO };
        let root = if root >= c::<T>(0.5) {
            root
        } else {
            self.far_branch(b, root, increment)
        };
        let p0 = ((T::ONE + root) * c::<T>(0.5)).sqrt();
        let inv = T::ONE / p0;
        let p = Quat {
            w: p0,
            x: b.x * inv,
            y: b.y * inv,
            z: b.z * inv,
        };
        Ok((p, false))
    }

    /// For a large turn, `+-sqrt(1 - 4 |b|^2)`: the sign of the root `p0^2 = (1 +- root) / 2`
    /// nearer to `-4 ((J b) x b) . dm / (h |dm|^2)`, the value the difference of the two DMV
    /// equations gives (`dm = m_k+1 - m_k`). With `(J v) x v = 0` (momentum on a principal
    /// axis, or a sphere; `dm` is then rounding) the turn is `asin(h Omega) <= 90` degrees:
    /// the plus sign, taken wherever `|(J b) x b|` is below `sqrt(eps) |b|^2 J_max`.
    ///
    /// `J` and `dm` enter divided by their largest entries: `|dm|^2` itself overflows for
    /// `|m|` beyond `sqrt(T::MAX)` (f32: 1.8e19), and an infinite denominator read as an
    /// estimate of zero took the minus sign, a turn 0.12 rad off returned `Ok` (found by a
    /// first-use trial); below `sqrt(MIN_POSITIVE)` it underflowed to zero and took the plus
    /// sign whatever the turn.
    ///
    /// Near a quarter turn the root itself is read more accurately off the momentum pair
    /// ([`quarter_turn_cosine`]), which also gives its sign.
    #[cold]
    #[inline(never)]
    fn far_branch(&self, b: Vec3<T>, root: T, dm: Vec3<T>) -> T {
        // m from b = w (m + next) and dm = next - m: passing m in cost the M4F's steps three
        // instructions each, on the hot path
        let w = self.turn_scale.v;
        let sum = Vec3::new(b.x / w.x, b.y / w.y, b.z / w.z);
        let m = sum.sub(dm).scale(c::<T>(0.5));
        if let Some(cos) = quarter_turn_cosine(m, b, root, dm) {
            return cos;
        }
        let j = self.body.mass_matrix_vec();
        let (sj, sd) = (j.max_abs(), dm.max_abs());
        if !(sd > T::ZERO && sj > T::ZERO && sd <= T::MAX && sj <= T::MAX) {
            return root;
        }
        // componentwise divisions (cold path): a reciprocal of a subnormal overflows
        let jb = Vec3::new(j.x / sj * b.x, j.y / sj * b.y, j.z / sj * b.z);
        let jbb = jb.cross(b);
        // (J b) x b below sqrt(eps) |b|^2 relative: the momentum on a principal axis (or
        // within sqrt(eps) of it) or a sphere, where m does not move in the body and dm is
        // rounding: the estimate is noise there (it took the minus sign, a turn of
        // pi - asin(h Omega), on 997 of 1000 spheres at h Omega in (0.87, 1), found in review)
        if !(jbb.norm2() > T::EPSILON * sq(b.norm2())) {
            return root;
        }
        let u = dm.divided_by(sd);
        // est = -4 ((J b) x b) . dm / (h |dm|^2) = k sj / (h sd), |u|^2 in [1, 3]
        let k = -c::<T>(4.0) * jbb.dot(u) / u.norm2();
        let est = if k == T::ZERO {
            T::ZERO
        } else {
            k * (sj / (self.h * sd))
        };
        let plus = (T::ONE + root) * c::<T>(0.5);
        let minus = (T::ONE - root) * c::<T>(0.5);
        if (est - minus).abs() < (est - plus).abs() {
            -root
        } else {
            root
        }
    }

    /// An integrator for `body` with step `h` (negative `h` runs backwards).
    #[must_use]
    pub fn new(body: Body<T>, h: T) -> Self {
        Self {
            body,
            h,
            track: None,
            anchor: None,
            recheck: false,
            retake: false,
            no_map: false,
            inv_i: body.inverse_inertia(),
            turn_scale: Lane4::new(body.inverse_inertia().scale(h * c::<T>(0.25))),
            phase: 0,
            frozen: None,
            carry_m: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
            carry_q: Quat::from_array([T::ZERO; 4]),
            fix_alpha: fix_alpha(&body),
        }
    }

    /// Holds the spatial momentum `R(q) m` of the trajectory: the attitude's rounding (about
    /// an ulp a step, biased) made it drift linearly in f32 (`7e-5` after `10^6` steps and
    /// `7e-4` after `10^7` at 200 Hz on the spacecraft). While the caller leaves the state
    /// alone, every [`HOLD_PERIOD`]-th new attitude (`full`) is turned in space by the small
    /// rotation `theta = pi x pi0 / |pi0|^2` that takes `pi = R(q') m'` back to the direction
    /// of `pi0` (to first order, exact to `O(eps^2)`: `q' + (0, theta/2) (x) q'`, no square
    /// root); the turn about `pi0` itself is left free. The free flow keeps `pi` constant, so
    /// this only removes round-off. The reference is dropped whenever the caller changed `m`
    /// or `q`, and taken again by the next full step from its own result.
    #[inline]
    fn hold_spatial(
        &mut self,
        follows: bool,
        full: bool,
        next: Vec3<T>,
        q_next: Quat<T>,
    ) -> Quat<T> {
        let Some(anchor) = self.anchor.as_mut() else {
            return q_next;
        };
        let sp = match anchor.spatial.as_mut() {
            Some(sp) if follows => sp,
            Some(sp) => {
                // dropped in place (see `advance`)
                sp.ready = false;
                sp.last_q = q_next;
                return q_next;
            }
            None => {
                anchor.spatial = Some(Spatial {
                    pi: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
                    ready: false,
                    last_q: q_next,
                });
                return q_next;
            }
        };
        if !full {
            sp.last_q = q_next;
            return q_next;
        }
        let pi = q_next.rotate(next);
        if !sp.ready {
            // the reference is this state's: nothing to turn now
            let n2 = pi.norm2();
            sp.pi = if n2 > T::ZERO && n2.is_finite() {
                pi.scale(T::ONE / n2)
            } else {
                Vec3::new(T::ZERO, T::ZERO, T::ZERO)
            };
            sp.ready = true;
            sp.last_q = q_next;
            return q_next;
        }
        let half = pi.cross(sp.pi).scale(c::<T>(0.5));
        // ([`DEADBAND`]: in f32 a turn at the measurement's noise is not made)
        if carries_rounding::<T>()
            && anchor.carry
            && !(half.norm2() > c::<T>(DEADBAND) * sq(T::EPSILON))
        {
            sp.last_q = q_next;
            return q_next;
        }
        let held = turn_in_space(q_next, half);
        sp.last_q = held;
        held
    }

    /// Whether `q` is the attitude this integrator returned last, and whether `m` is the
    /// momentum it returned last; decided before the step moves the anchor on (a flag, not a
    /// copy: see `system`), once for the step (comparing again in `advance` cost about 15
    /// instructions a step on the M4F).
    #[inline(always)]
    fn follows_state(&self, m: Vec3<T>, q: Quat<T>) -> (bool, bool) {
        match &self.anchor {
            Some(Anchor {
                last,
                spatial: Some(sp),
                ..
            }) => (sp.last_q == q, *last == m),
            Some(a) => (false, a.last == m),
            None => (false, false),
        }
    }

    /// The new attitude `q (x) p` and its hold; a full step renormalises and holds, the
    /// others compose the turn alone ([`HOLD_PERIOD`]). With `carry`, from `q + lost` and
    /// with what the rounding dropped (crate::integrator's `compose_attitude_carried`);
    /// without, `lost` is returned as it came.
    #[inline(always)]
    fn turn_attitude(
        &mut self,
        (ours, m_ours): (bool, bool),
        q: Quat<T>,
        next: Vec3<T>,
        p: Quat<T>,
        lost: Quat<T>,
        carry: bool,
    ) -> (Quat<T>, Quat<T>) {
        let full = self.phase == 0 || !ours;
        let (q_next, lost) = if carry {
            compose_attitude_carried(q, p, lost, full)
        } else if full {
            (compose_attitude(q, p), lost)
        } else {
            (compose_unrenormalised(q, p), lost)
        };
        (self.hold_spatial(ours && m_ours, full, next, q_next), lost)
    }

    /// Whether the plain steps carry their rounding on this trajectory: in f32, below
    /// [`CARRY_TURN2`].
    #[inline(always)]
    fn carrying(&self) -> bool {
        matches!(&self.anchor, Some(a) if a.carry)
    }

    /// What the last plain step's attitude rounding dropped, to add to this step's turn
    /// (always zero in f64), also after the caller changed `m` or corrected `q` by a little
    /// ([`Mv::turned_by_little`]): dropped there, a filter correcting every tick lost the slow
    /// turn's rounding with a bias (4.2e-3 rad from f64 after 10^6 ticks at 8e-4 rad/s, found
    /// in review).
    #[inline(always)]
    fn carried_turn(&self, (ours, _): (bool, bool), q: Quat<T>) -> Quat<T> {
        if carries_rounding::<T>() && (ours || self.turned_by_little(q)) {
            self.carry_q
        } else {
            Quat::from_array([T::ZERO; 4])
        }
    }

    /// Whether `m`, not the momentum returned last, is that one corrected by a little (within
    /// 1 % of `|m|`, so the carry, a few ulps of the last momentum at most, is a few of `m`'s):
    /// a filter's correction, whose state the carried rounding still belongs to. Not a
    /// replacement: one `Mv` switched between two trajectories every tick leaked each one's
    /// carry into the other (`|m|` of the smaller drifted 6.6e-2 in `2 x 10^5` ticks), and a
    /// momentum replaced by one 120 times smaller took up to 64 of its ulps (found in review
    /// of a first version that tested the carry's size alone).
    #[inline(always)]
    fn corrected_by_little(&self, m: Vec3<T>) -> bool {
        matches!(&self.anchor, Some(a) if m.sub(a.last).norm2() <= c::<T>(1e-4) * m.norm2())
    }

    /// Whether `q`, not the attitude returned last, is that one turned by a little (within
    /// `1e-2` of it, about 0.02 rad): a filter's correction keeps the attitude's carry, a
    /// replacement does not ([`Mv::corrected_by_little`]).
    #[inline(always)]
    fn turned_by_little(&self, q: Quat<T>) -> bool {
        match &self.anchor {
            Some(Anchor {
                spatial: Some(sp), ..
            }) => {
                let d = Quat {
                    w: q.w - sp.last_q.w,
                    x: q.x - sp.last_q.x,
                    y: q.y - sp.last_q.y,
                    z: q.z - sp.last_q.z,
                };
                d.norm2() <= c::<T>(1e-4)
            }
            _ => false,
        }
    }

    /// Keeps what this plain step's attitude rounding dropped for the next step, where the
    /// trajectory carries ([`Mv::carrying`]; nothing in f64).
    #[inline(always)]
    fn keep_turn_carry(&mut self, lost: Quat<T>) {
        if carries_rounding::<T>() {
            self.carry_q = if self.carrying() {
                lost
            } else {
                Quat::from_array([T::ZERO; 4])
            };
        }
    }

    /// After a momentum-only step: the attitude did not move with `m`, so a step with attitude
    /// after it takes its `q` as the caller's (a new spatial reference, no carried turn).
    /// Kept, the hold turned `q` onto `R(q) m` of an attitude that had not been stepped: a
    /// jump of 8.4e-2 rad (found in review, `step` between `step_state` calls).
    #[inline(always)]
    fn forget_attitude(&mut self) {
        if let Some(a) = self.anchor.as_mut() {
            a.spatial = None;
        }
    }

    /// Counts a successful step with attitude towards the next full one.
    #[inline(always)]
    fn count_attitude_step(&mut self) {
        // HOLD_PERIOD is a power of two: a mask, not a comparison
        self.phase = self.phase.wrapping_add(1) & (HOLD_PERIOD - 1);
    }

    /// `step_state` that also returns the step's turn `p = quat(X)` (`q' = q (x) p`,
    /// `m' = R(p)^T m`), for the tangent map ([`crate::tangent`]). The same lines as
    /// `step_state` (kept apart so the loop's step stays as it is: `step_state` calling this and
    /// dropping the turn measured 734 instead of 703 instructions per f32 step on the M4F;
    /// tests/jacobian.rs checks the two give bit-identical states).
    pub(crate) fn step_state_rotation(&mut self, s: &mut State<T>) -> Result<Quat<T>, StepError> {
        let (v, q) = checked_state(s)?;
        let follows = self.follows_state(v, q);
        let step = match self.advance(v, follows.1, true) {
            Ok(step) => step,
            Err(e) => {
                return self
                    .refused(e)
                    .map(|()| Quat::from_array([T::ONE, T::ZERO, T::ZERO, T::ZERO]))
            }
        };
        let next = step.next;
        let (p, _) = self.rotation_between(v, next, step.increment)?;
        let lost = self.carried_turn(follows, q);
        let (held, lost) = self.turn_attitude(follows, q, next, p, lost, carries_rounding::<T>());
        write_state_stepped(s, next, held)?;
        self.keep_turn_carry(lost);
        self.count_attitude_step();
        Ok(p)
    }

    /// Changes the body, keeping the tracked root as the start of the next solve when the
    /// new mass matrix is within a factor of two of the old (the scale stays valid): what
    /// [`crate::PreMv`] does when the momentum or the step changes its modified moments
    /// slightly. The next step checks existence and re-solves by Newton.
    ///
    /// `from` is the momentum the next step will start from when the caller moved the one
    /// returned last onto the trajectory's invariants (PreMv on a change of `h` alone): the
    /// trajectory goes on, so its spatial momentum is still held. `None` when the momentum
    /// itself changed.
    ///
    /// `inv_i` is `1 / I` of the new body (the caller has it: no division here).
    pub(crate) fn set_body(&mut self, body: Body<T>, inv_i: Vec3<T>, from: Option<[T; 3]>) {
        let j = body.mass_matrix_vec();
        // J_i >= 0: the largest entry is the largest magnitude
        let (new, old) = (j.max_element(), self.body.mass_matrix_vec().max_element());
        self.body = body;
        self.inv_i = inv_i;
        self.turn_scale.v = inv_i.scale(self.h * c::<T>(0.25));
        self.recheck = true;
        // the anchored beta depends on J: taken again at the next step
        self.retake = true;
        match (from, self.anchor.as_mut()) {
            (Some(m), Some(a)) => a.last = Vec3::from_array(m),
            _ => self.anchor = None,
        }
        match self.track.as_mut() {
            Some(t) if new <= old * c::<T>(2.0) && old <= new * c::<T>(2.0) => {
                t.set_mass_matrix(j);
            }
            _ => self.track = None,
        }
    }

    /// Takes `m` as the momentum returned last: a `PreMv` moved that momentum back onto the
    /// trajectory's invariants (a change of `h` alone) and its modified body did not change,
    /// so the trajectory, its anchored invariants and its spatial momentum go on.
    pub(crate) fn continue_from(&mut self, m: [T; 3]) {
        if let Some(a) = self.anchor.as_mut() {
            a.last = Vec3::from_array(m);
        }
    }

    /// The largest `|h|` for which the DMV step from `m` exists (the cubic of docs/MATH.md §2
    /// keeps no negative real root, docs/MATH.md §3), from the polynomial conditions alone:
    /// with `t = h^2`, `A` and `B` fall linearly in `t`, the step exists while both are
    /// positive, and after that while the cubic's discriminant `D(t)` (a quartic in `t`) is
    /// negative. The first root of `D` after both stop being positive is found on a monotone
    /// piece between the roots of `D'` (a cubic) by bisection to `2 eps` relative
    /// (`src/max_step.rs`). Accuracy: that of the computed `D`, whose coefficients round and
    /// which is flat near the bound: within about `2e-5` relative in f64 and `2 %` in f32
    /// (worst of two million random bodies and momenta in a review, against mpmath and
    /// against bisection on the step's own test: `1.6e-5` and `1.7 %`, the returned bound
    /// the larger; an earlier review's `5.5e-6` and `0.8 %` were from fewer cases), so a step
    /// near the returned bound (in f32 at `0.98` of it) may be taken or refused
    /// (`StepTooLarge`) by the step's own test.
    ///
    /// Returns `T::MAX` for `m = 0` (every step exists) and zero for a non-finite `m`.
    /// Talk's case: `1.060273597`.
    ///
    /// This is the mathematical bound, which [`Mv`]'s step meets wherever its scaled
    /// quantities stay in the floating-point range (checked at 0.5 and 0.99 of the bound for
    /// moments `10^-37` to `10^37` and momenta down to `10^-30` in f32, `h / I` below
    /// `10^30`). Beyond that, with a subnormal `m` or `h / I` near `T::MAX` (`m = 0` on a body
    /// of moments `1e-37` and `h = 1e38`, where the bound is `T::MAX`), the step refuses with
    /// `StepTooLarge` a step this bound allows.
    #[must_use]
    pub fn max_step(body: &Body<T>, m: &[T; 3]) -> T {
        crate::max_step::max_step(body, m)
    }

    /// Solves for `s1` exactly and sets the scale for momentum `m`. Cold: it runs at set-up
    /// and after outside changes, and keeping it out of line keeps the step's code small.
    #[cold]
    #[inline(never)]
    fn resync(body: &Body<T>, h: T, m: Vec3<T>) -> Result<Track<T>, StepError> {
        if h == T::ZERO {
            // a pause ([`Mv::set_far_step_size`])
            return Err(PAUSED);
        }
        if !h.is_finite() {
            return Err(StepError::NonFinite);
        }
        let j = body.mass_matrix_vec();
        let hm = m.max_abs() * h.abs();
        let kappa = j.max_abs().max(hm);
        if !kappa.is_finite() {
            return Err(StepError::Overflow);
        }
        let mut t = Track {
            kappa,
            inv_kappa: T::ONE / kappa,
            hn: h / kappa,
            delta: T::ZERO,
            inv_dg: T::ZERO,
            tol_unit: c::<T>(2.0) * T::EPSILON.sqrt(),
            ..Track::zero()
        };
        t.set_mass_matrix(j);
        let k = t.coefficients(m);
        if !exists(k.big_a, k.big_b, sq(t.s3)) {
            return Err(StepError::StepTooLarge);
        }
        // the first term of delta's series in h^2 (g linearised at delta = 0; the
        // denominator is 8 I1 I2 I3 in scaled units), then guarded Newton: no transcendental
        // call in the common regime, where h |Omega| is small
        let lin = t.two_u0 * (t.two_s0 + t.two_s0) - t.s3x8;
        if lin > T::ZERO {
            t.delta = -(t.two_u0 * k.sum_a + c::<T>(4.0) * k.beta) / lin;
            if t.newton(k.invariants()) {
                return Ok(t);
            }
        }
        Self::solve_exactly(t, &k)
    }

    /// The exact solve of the quartic (the cubic's roots from the crate's own `asin`, sine,
    /// cosine and cube root: no libm, crate::cubic), polished on the
    /// cancellation-free `g`: the fallback when Newton from the series cannot be trusted
    /// (`h |Omega|` of order one).
    #[cold]
    #[inline(never)]
    fn solve_exactly(mut t: Track<T>, k: &Coefficients<T>) -> Result<Track<T>, StepError> {
        let s0 = t.s0;
        let s1 = quartic_largest_root(k.big_a, k.big_b, t.s3).ok_or(StepError::StepTooLarge)?;
        // polish delta on the cancellation-free g: s1 - s0 has only absolute accuracy.
        // (Guarded Newton from here instead, run to Track::settled, moved delta by 3e-15 on
        // a step at 0.9996 of max_step on a needle, and the turn check then refused a step
        // taken before within its accuracy, found in review: this runs where the map is that
        // sensitive, and the steps that must each reduce |g| stay.)
        let mut delta = s1 - s0;
        let (mut g, mut dg) = t.g(delta, k.invariants());
        let mut it = 0;
        while it < 4 && dg > T::ZERO && g != T::ZERO {
            let next = delta - g / dg;
            let (gn, dgn) = t.g(next, k.invariants());
            if !(gn.abs() < g.abs()) {
                break;
            }
            delta = next;
            g = gn;
            dg = dgn;
            it += 1;
        }
        if !(dg > T::ZERO) || !delta.is_finite() {
            // the largest root is simple (docs/MATH.md §4); a flat quartic means no valid split
            return Err(StepError::Degenerate);
        }
        t.set_delta(delta);
        t.inv_dg = T::ONE / dg;
        Ok(t)
    }

    /// The tracking data and the coefficients for momentum `m`: one chord step takes the
    /// tracked `delta` to the current invariants before it is used (or it is solved exactly
    /// when the correction is large). Using the previous step's value instead would shorten
    /// the dependency chain, but feeds an invariant error at step `k` back into step `k + 1`;
    /// at large steps that loop amplifies (on the talk's case at `h = 0.93`, `|m|^2` errors
    /// grew from `1e-15` to `3e-8` in 60 steps), so it is not done. The existence test is
    /// needed only when `m` is not the momentum returned last: otherwise its invariants, which
    /// decide existence, are those of a step that existed.
    #[inline(always)]
    fn system(
        &mut self,
        m: Vec3<T>,
        free_running: bool,
    ) -> Result<(Coefficients<T>, bool), StepError> {
        // the tracking data is updated in place: copying it in and out (30 words) made the
        // compiler call memcpy, which on a Cortex-M4F cost more than the step itself
        let mut resynced = false;
        if self.track.is_none() {
            self.track = Some(Self::resync(&self.body, self.h, m)?);
            self.no_map = false;
            resynced = true;
        }
        let Some(t) = self.track.as_mut() else {
            return Err(StepError::Degenerate);
        };
        let k = t.coefficients(m);
        if !free_running && !exists(k.big_a, k.big_b, sq(t.s3)) {
            return Err(StepError::StepTooLarge);
        }
        if free_running && t.may_freeze {
            // the input is on the anchored invariants (each step moves it back onto them),
            // and delta was solved for those: nothing to update
            return Ok((k, resynced));
        }
        let (g, _) = t.g_only(t.delta, k.invariants());
        let correction = g * t.inv_dg;
        // after an outside change of m or h: two chord steps whose second shows the
        // convergence (no division), else Newton
        let chord =
            correction.abs() <= t.newton_tol && t.chord_converges(k.invariants(), correction);
        if !chord && !t.newton(k.invariants()) {
            // far from the tracked root (a large change of m or h): solve exactly, with the
            // scale re-chosen for this m
            *t = Self::resync(&self.body, self.h, m)?;
            self.no_map = false;
            return Ok((t.coefficients(m), true));
        }
        Ok((k, resynced))
    }

    /// One momentum step from `m` (`follows`: `m` is the momentum returned last, so the
    /// trajectory goes on); returns the new momentum and the DMV part of its increment.
    ///
    /// With `D = diag(s1 J + s3 J^-1)`, the map is `m' = (D + J M) y`, `L^T y = m`. At `h = 0`,
    /// `D = L^T`, so `D + J M = L^T + Delta` with `Delta` small, and the step is computed as
    /// `m' = m + Delta y`: the increment keeps full relative accuracy and only the final
    /// addition rounds `m`. The jobs, in order: bring `s1` up to date ([`Mv::system`]), hold
    /// the invariants ([`Anchor`]), build `L^T` ([`Track::transposed_system`]), solve
    /// it ([`solve_cramer`]), form the increment ([`Track::increment_matrix`],
    /// [`Track::invariant_fix`]) the
    /// increment itself, from which the attitude's turn is read ([`Mv::rotation_between`]).
    #[inline(always)]
    fn advance(
        &mut self,
        m: Vec3<T>,
        follows: bool,
        plain: bool,
    ) -> Result<Advanced<T>, StepError> {
        if follows && !self.recheck && !self.retake {
            if let Some(step) = self.advance_frozen(m, plain) {
                return Ok(step);
            }
        }
        self.frozen = None;
        // taken before the anchor moves to `m`: whether the carry goes on (a small correction)
        let carry_on = carries_rounding::<T>() && (follows || self.corrected_by_little(m));
        let (k, resynced) = self.system(m, follows && !self.recheck)?;
        if self.no_map {
            if let Some(t) = self.track.as_mut() {
                t.may_freeze = false;
            }
        }
        let Some(t) = self.track.as_ref() else {
            return Err(StepError::Degenerate);
        };
        // hold the invariants: X is orthogonal only to round-off, and that round-off is
        // correlated along the orbit, so |m|^2 and the energy would drift (|m|^2 by 7.6e-12 in
        // f64, 2e-3 in f32 after 10^6 steps on the talk's case; the energy by 3e-5 in f32 on
        // the spacecraft). Each step moves its input back onto the trajectory's invariants
        // ([`Anchor::correction`]; at small h |Omega| every HOLD_PERIOD-th step); the anchor
        // is re-taken when the caller changed m (a filter's correction is kept, not undone),
        // the scale moved or the body changed. (Kept inline: as a function taking
        // `&mut Option<Anchor>` it cost an instruction per step on the M4F.)
        // the |m|^2 the step must land on: the input's, or the anchored one it is moved to
        let mut target = k.sum_a;
        let correction = match self.anchor.as_mut() {
            // at small h |Omega| a step whose input goes on the trajectory (a jittering clock)
            // holds the invariants every HOLD_PERIOD-th step, like a free-running one
            Some(a) if follows && !resynced && !self.retake && t.may_freeze && a.unheld != 0 => {
                a.count_unheld();
                None
            }
            Some(a) if follows && !resynced && !self.retake => {
                a.unheld = 1;
                a.settle(t.hn);
                target = a.alpha;
                Some(a.correction(k.invariants(), t))
            }
            // h changed by more than the tracked root survives (set_step_size dropped it, or
            // the update did not converge), m did not: the trajectory goes on, its invariants
            // carried to the new step and scale. Re-taking them from the input instead let
            // them random-walk, then drift: on the talk's case with h cycling through 0.04 to
            // 0.16, |m|^2 and E moved 4.8e-12 in 10^6 steps (found in review; 9e-16 now).
            Some(a) if follows && self.recheck && !self.retake => {
                match a.carried_correction(k.invariants(), t) {
                    Some(corr) => {
                        target = a.alpha;
                        Some(corr)
                    }
                    None => {
                        a.retake(
                            m,
                            k.invariants(),
                            t.hn,
                            t.kappa,
                            plain.then_some(self.turn_scale.v),
                        );
                        None
                    }
                }
            }
            _ => {
                // the spatial momentum stays the trajectory's (hold_spatial re-takes it if
                // the attitude changed too)
                // (in place: building a new anchor and moving it in copied about 50 words a
                // step on the M4F in a loop that changes m every tick)
                match self.anchor.as_mut() {
                    Some(a) => a.retake(
                        m,
                        k.invariants(),
                        t.hn,
                        t.kappa,
                        plain.then_some(self.turn_scale.v),
                    ),
                    None => {
                        self.anchor = Some(Anchor::take(
                            m,
                            k.invariants(),
                            t.hn,
                            t.kappa,
                            plain.then_some(self.turn_scale.v),
                        ));
                    }
                }
                None
            }
        };
        // the correction is tiny: it goes into the increment, never into a product with m
        // (m * (1 + eps) rounds each component on its own and turns m by a biased ulp); the
        // m part is folded into the solve, the j^2 m part added after it (its rotation by the
        // step is a second-order small term)
        let scale = match correction {
            Some((corr, _)) => corr + T::ONE,
            None => T::ONE,
        };
        let sys = t.transposed_system(&k);
        let y = solve_cramer(&sys.lt, m, scale)?;
        let increment = t.increment_matrix(&sys).mul_vec(y);
        let zero = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
        let (applied, fix) = match correction {
            Some((corr, corr_v)) => (increment.add(t.invariant_fix(m, corr, corr_v)), zero),
            // a carried f32 step at a large turn keeps its input's invariants, through the
            // carry ([`fix_from_increment`], [`FIX_ALPHA`])
            None if carries_rounding::<T>() && !plain && k.sum_a > self.fix_alpha => (
                increment,
                fix_from_increment(m, increment, k.invariants(), t),
            ),
            // a re-taken anchor has nothing to correct
            None => (increment, zero),
        };
        // a plain step adds what the last step's rounding dropped: from its own last result,
        // and from a momentum the caller corrected by a little ([`Mv::corrected_by_little`];
        // dropped there, a filter every tick lost the slow motion's rounding with a bias,
        // |m|^2 5.4e-3 off after 10^6 ticks at 8e-4 rad/s, found in review)
        let sum = if carries_rounding::<T>() && plain && carry_on {
            applied.add(self.carry_m)
        } else {
            applied
        };
        let next = m.add(sum);
        if !next.is_finite() {
            return Err(StepError::Overflow);
        }
        // the step keeps |m|^2 to round-off; a body whose moments span hundreds of decades
        // (found by the loop fuzz: J = (1.5e74, 2194, 1.3e-136)) leaves the scaled system
        // without a correct digit, and the only sign is a result off the sphere. sqrt(eps)
        // is far above the round-off of any step the arithmetic can resolve.
        // (in scaled units, |hn m| <= 1: neither side overflows or underflows apart)
        let drift = next.scale(t.hn).norm2() - target;
        if !(drift.abs() <= t.tol_unit * target)
            && !Self::on_sphere_unscaled(next, applied, target, t)
        {
            return Err(StepError::Degenerate);
        }
        self.recheck = false;
        self.retake = false;
        if let Some(a) = self.anchor.as_mut() {
            a.last = next;
        }
        if carries_rounding::<T>() {
            // the carried step hands its rounding to the caller's carry instead
            self.carry_m = if plain && self.carrying() {
                dropped_by_sum(m, sum, next)
            } else {
                Vec3::new(T::ZERO, T::ZERO, T::ZERO)
            };
        }
        Ok(Advanced {
            next,
            increment,
            applied,
            fix,
        })
    }
}

impl<T: Real> Mv<T> {
    /// The carried step ([`Integrator::step_state_carrying`]), a function of its own beside
    /// `step_state` (sharing one generic body cost the host's free-running step 1.5 ns in 25,
    /// and a flag read at run time cost the M4F's forced step 73 instructions).
    ///
    /// Every step is taken as an outside change (a torque acts): its rounding is carried,
    /// not held onto the trajectory's invariants. A torque's kick below an ulp of `m` leaves
    /// `m` as returned, and the holds then fought the carry: in f32 the momentum was 15x
    /// further from f64's after `10^6` steps.
    #[inline(never)]
    fn step_state_carry(&mut self, s: &mut State<T>, lost: &mut State<T>) -> Result<(), StepError> {
        let (v, q) = checked_state(s)?;
        let step = match self.advance(v, false, false) {
            Ok(step) => step,
            Err(e) => return self.refused(e),
        };
        let next = step.next;
        let (p, small) = self.rotation_between(v, next, step.increment)?;
        // the caller carries the rounding: a plain step after this one starts without, and
        // takes the invariants again with the test of whether it carries its own
        if carries_rounding::<T>() {
            self.carry_q = Quat::from_array([T::ZERO; 4]);
            self.retake = true;
        }
        // an attitude that goes on from the last step's is renormalised every HOLD_PERIOD-th
        // step, as in step_state (every step cost the soft-float build 1776 instructions; on
        // the M4F the comparison costs about what it saves); nothing is held. Asked after
        // `advance`, which step_state avoids: harmless here, as its outside-change path keeps
        // the anchor's spatial part (`retake`) or makes a new anchor without one (false, as
        // before the step); asked before, the M4F step took 5 instructions more
        let ours = self.follows_state(v, q).0;
        let (held, lost_q) =
            self.turn_attitude((ours, false), q, next, p, Quat::from_array(lost.q), true);
        if small {
            // as in step_state
            s.m = next.to_array();
            s.q = held.to_array();
        } else {
            write_state_stepped(s, next, held)?;
        }
        lost.m = step.carry_into(v, lost.m);
        lost.q = lost_q.to_array();
        self.count_attitude_step();
        Ok(())
    }

    /// The free-running step at small `h |Omega|` (crate::mv_frozen): the same map as the
    /// solve, with the trajectory's constants folded into a [`FrozenMap`]. `None` when it
    /// does not apply (no tracked root yet, or `h |Omega|` large) or its result overflows;
    /// then nothing has changed but the anchor's cached `1 / (2 alpha)`.
    #[inline(always)]
    fn advance_frozen(&mut self, m: Vec3<T>, plain: bool) -> Option<Advanced<T>> {
        let t = self.track.as_ref()?;
        if !t.may_freeze {
            return None;
        }
        let a = self.anchor.as_mut()?;
        if self.frozen.is_none() {
            // the map forms the products m_i m_k unscaled: below |m|^2 ~ MIN_POSITIVE / eps
            // they leave the normal range and lose their digits (f32 bodies of moments near
            // 1e-20 went 3 % off a step with Ok, found in review), so the solve stays
            if !(m.norm2() >= T::MIN_POSITIVE / T::EPSILON) {
                return None;
            }
            a.settle(t.hn);
            match FrozenMap::new(t.j, t.c0, t.s0, t.delta, t.hn, a.alpha) {
                Some(map) => self.frozen = Some(map),
                None => {
                    // the map would amplify round-off here: this trajectory solves
                    self.refuse_map();
                    return None;
                }
            }
        }
        // by reference: a copy of the 19 words was a memcpy call
        let map = self.frozen.as_ref()?;
        // the invariants are held every HOLD_PERIOD-th step, like the attitude: each
        // free-running step moves |m|^2 and the energy by an ulp or so, and the hold takes
        // them back, so between two holds they stay within a few ulps of the trajectory's
        // (tests/soak.rs); the steps between skip about 50 flops
        let (increment, applied) = if a.unheld == 0 {
            // the invariants by value: a reference to a Coefficients put it on the stack,
            // and reading it back stalled the step on the host (57 instead of 45 ns)
            let k = t.invariants(m);
            let (corr, corr_v) = a.correction(k, t);
            if !((a.alpha - k.sum_a).abs() <= c::<T>(HELD_ALPHA_ULPS) * T::EPSILON * a.alpha) {
                // |m|^2 moved by far more than the free-running steps' ulps since the last
                // hold: the map amplifies round-off on this trajectory (FrozenMap::new's test
                // missed it, or a NaN). It solves from now on, this step included: the
                // solve's hold takes back the small error made so far (a comparison every
                // HOLD_PERIOD-th step)
                self.refuse_map();
                return None;
            }
            // a non-finite increment (a momentum whose cube overflows) makes next non-finite
            let increment = map.increment(m, corr + T::ONE);
            (increment, increment.add(t.invariant_fix(m, corr, corr_v)))
        } else {
            let increment = map.increment(m, T::ONE);
            (increment, increment)
        };
        let sum = if carries_rounding::<T>() && plain {
            applied.add(self.carry_m)
        } else {
            applied
        };
        let next = m.add(sum);
        if !next.is_finite() {
            return None;
        }
        a.count_unheld();
        a.last = next;
        if carries_rounding::<T>() {
            self.carry_m = if plain && a.carry {
                dropped_by_sum(m, sum, next)
            } else {
                Vec3::new(T::ZERO, T::ZERO, T::ZERO)
            };
        }
        Some(Advanced {
            next,
            increment,
            applied,
            fix: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
        })
    }

    /// The sphere check of [`Mv::advance`] where the scaled `|hn m|^2` has lost digits to
    /// underflow (`h |Omega|` below about `1e-15` in f32): `|m'|^2` against `|m|^2` scaled
    /// by the largest component, with `m = m' - applied` (to an ulp; taking `m` itself kept
    /// it live through the step, 17 instructions on the M4F). Only then: a target with all
    /// its digits was checked in scaled units, and a step that moves such an input by more
    /// than `sqrt(eps)` is wrong. (No correction is applied below [`full_digits`], so
    /// `|m|^2` is the step's own.)
    #[cold]
    #[inline(never)]
    fn on_sphere_unscaled(next: Vec3<T>, applied: Vec3<T>, target: T, t: &Track<T>) -> bool {
        if full_digits(target) {
            return false;
        }
        norms_agree(next.sub(applied), next, t.tol_unit)
    }

    /// [`Integrator::set_step_size`] beyond what the tracked root survives: a change by more
    /// than 2x, the first step after a pause, or zero, which pauses the steps: the tracked
    /// root is dropped, so each step goes to the re-solve ([`Mv::resync`]), which refuses it
    /// with a marker that [`Mv::refused`] turns into `Ok` with the state as it was. No test
    /// on the step's own path (a test and early return there made LLVM lay the M4F's steps
    /// out 5 to 36 instructions longer). The anchored invariants stay, and the first step
    /// after the pause carries them to its `h`, as after a large change of `h`.
    #[cold]
    #[inline(never)]
    fn set_far_step_size(&mut self, h: T) {
        self.track = None;
        // the carry stays (sub-ulp residues of the state, whatever h is): dropped, a clock
        // that reads zero now and then (a pause) lost the slow motion's rounding at each one
        // (attitude 1.3e-3 rad off f64 after 10^6 ticks with every second one a pause, found
        // in review); a step that leaves the carry's range ([`CARRY_TURN2`]) adds it once and
        // keeps none
        self.h = h;
        self.turn_scale.v = self.inv_i.scale(h * c::<T>(0.25));
        self.recheck = true;
    }

    /// A step [`Mv::advance`] refused with `e`: `Ok` (nothing done) for a step of size zero,
    /// else `Err(e)` (the state untouched). `Overflow` and `Degenerate` with a tracked root
    /// come from the solve and the checks after it, once the root was tracked to the refused
    /// input and the anchor re-taken or corrected: they forget the trajectory
    /// ([`Mv::failed`]). `StepTooLarge` and `NonFinite` come before that (the existence check,
    /// the re-solve after a change of `h`), and so do `Overflow` and `Degenerate` without a
    /// tracked root (a re-solve from scratch that failed: `kappa = max(J, h |m|)` overflows
    /// at `h = f32::MAX`, found in review, where forgetting let f32 `|m|^2` random-walk to
    /// 2.3e-5 with such a refusal every 7th tick): they changed nothing. (A re-solve from a
    /// tracked root that fails forgets too: rare, and then the next step re-takes the
    /// invariants once. Sorting by kind here keeps the step's own code as it was: a call at
    /// each late exit cost the M4F's jittered step 12 instructions.)
    #[cold]
    #[inline(never)]
    fn refused(&mut self, e: StepError) -> Result<(), StepError> {
        if self.h == T::ZERO {
            Ok(())
        } else if matches!(e, StepError::Overflow | StepError::Degenerate) && self.track.is_some() {
            Err(self.failed(e))
        } else {
            Err(e)
        }
    }

    /// A step refused after it tracked the root to its input and re-took or corrected the
    /// anchor (the solve, the overflow and the sphere checks; [`Mv::refused`]) forgets the
    /// trajectory (tracked root, anchored invariants, carries): kept, they made the next step
    /// from the caller's unchanged state another one (found in review: on a needle,
    /// `Err(Degenerate)` and then the identical call `Ok` with `|m|^2` 1.1e-2 off). The next
    /// step starts afresh from its input, as a new integrator would. A refusal before that
    /// (the existence check, the re-solve after a change of `h`) changed nothing and forgets
    /// nothing: a loop that asks for too large an `h` now and then keeps its invariants, and a
    /// pause carries them to the next `h` that steps (forgetting there let f32 `|m|^2`
    /// random-walk to 2.3e-5 in `2 x 10^5` ticks with a refusal every 7th, found in review of
    /// the first version). (A step refused after `advance` succeeded, by the turn or the state
    /// check, needs none of this: `advance` moved the anchor on to its result, so the caller's
    /// unchanged state is an outside change for the next step, re-taken as it is.)
    #[cold]
    #[inline(never)]
    fn failed(&mut self, e: StepError) -> StepError {
        self.forget_trajectory();
        e
    }

    /// Everything an `Mv` keeps about its trajectory, dropped: it steps on as one built
    /// afresh with its body and `h` would, bit for bit ([`Integrator::reset`], a late
    /// refusal). (`reset` kept the step count to the next full attitude step: a reset `Mv`
    /// held its attitude at other steps than a new one, found in review.)
    #[cold]
    #[inline(never)]
    fn forget_trajectory(&mut self) {
        self.track = None;
        self.anchor = None;
        self.frozen = None;
        self.recheck = false;
        self.retake = false;
        self.no_map = false;
        self.phase = 0;
        self.carry_m = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
        self.carry_q = Quat::from_array([T::ZERO; 4]);
    }

    /// A fresh root for the next step, the trajectory's anchor kept (its invariants, which
    /// the next step takes again from its input, and its spatial momentum, which the attitude
    /// stays held to): what crate::mv_retimed's exact retiming needs on the same trajectory,
    /// steps solved afresh as the retiming measured them. (A whole reset there lost the
    /// spatial reference at every retiming, and under a jittering clock `R(q) m`
    /// random-walked: 2.6e-12 in f64 and 5.4e-4 in f32 after `4 x 10^5` steps on
    /// `I = (1.5, 1000, 1001)`, where `PreMv` keeps 2.1e-14 and 1.2e-5, found in review.)
    /// The f32 carry is dropped, as a reset drops it.
    pub(crate) fn restart_root(&mut self) {
        self.track = None;
        self.frozen = None;
        self.phase = 0;
        self.carry_m = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
        self.carry_q = Quat::from_array([T::ZERO; 4]);
    }

    /// Stops the rational map on this trajectory (see [`Mv::no_map`]).
    #[cold]
    #[inline(never)]
    fn refuse_map(&mut self) {
        self.frozen = None;
        self.no_map = true;
        if let Some(t) = self.track.as_mut() {
            t.may_freeze = false;
        }
    }
}

/// `L^T = M^2 + J^2 + s1 M + s2 I` for one step (scaled units), with the pieces of it the
/// increment `Delta = D + J M - L^T` reuses.
struct TransposedSystem<T> {
    lt: Mat3<T>,
    /// `a_i + e` (`e = s2 - |mm|^2 - s2_0`), shared by the diagonals of `L^T` and `Delta`.
    ae: Vec3<T>,
    /// `L^T`'s entries above the diagonal, `(01, 02, 12)`.
    upper: (T, T, T),
    /// `L^T`'s entries below the diagonal, `(10, 20, 21)`.
    lower: (T, T, T),
    /// `h m / kappa`.
    mm: Vec3<T>,
}

/// `L^T y = fix * m` by Cramer's rule: the rows of `adj(L^T)` are cross products of its
/// columns. `Degenerate` for a zero or non-finite determinant.
#[inline(always)]
fn solve_cramer<T: Real>(lt: &Mat3<T>, m: Vec3<T>, fix: T) -> Result<Vec3<T>, StepError> {
    let r0 = lt.y_axis.cross(lt.z_axis);
    let r1 = lt.z_axis.cross(lt.x_axis);
    let r2 = lt.x_axis.cross(lt.y_axis);
    let det = lt.x_axis.dot(r0);
    // one range test (false for NaN): the finiteness test it replaces cost 5 instructions on
    // the M4F
    let size = det.abs();
    if !(size > T::ZERO && size <= T::MAX) {
        return Err(StepError::Degenerate);
    }
    let inv_det = T::ONE / det;
    Ok(Vec3::new(r0.dot(m), r1.dot(m), r2.dot(m)).scale(inv_det * fix))
}

impl<T: Real> Track<T> {
    /// `L^T` for the tracked `delta` and the coefficients `k` of the step's input.
    #[inline(always)]
    fn transposed_system(&self, k: &Coefficients<T>) -> TransposedSystem<T> {
        let (mm, a, alpha) = (k.mm, k.a, k.sum_a);
        let delta = self.delta;
        let s1 = self.s0 + delta;
        // s2 - s2_0 = s1_0 delta + delta^2 / 2 + |mm|^2 / 2, and e = s2 - |mm|^2 - s2_0
        let e = self.s0 * delta + (sq(delta) - alpha) * c::<T>(0.5);
        // L^T = M^2 + J^2 + s1 M + s2 I with M = hat(mm), M^2 = mm mm^T - |mm|^2 I
        let (xy, xz, yz) = (mm.x * mm.y, mm.x * mm.z, mm.y * mm.z);
        let (sx, sy, sz) = (s1 * mm.x, s1 * mm.y, s1 * mm.z);
        let (l01, l02, l12) = (xy - sz, xz + sy, yz - sx);
        let (l10, l20, l21) = (xy + sz, xz - sy, yz + sx);
        let ae = Vec3::new(a.x + e, a.y + e, a.z + e);
        let lt = Mat3::from_cols(
            Vec3::new(self.c0.x + ae.x, l10, l20),
            Vec3::new(l01, self.c0.y + ae.y, l21),
            Vec3::new(l02, l12, self.c0.z + ae.z),
        );
        TransposedSystem {
            lt,
            ae,
            upper: (l01, l02, l12),
            lower: (l10, l20, l21),
            mm,
        }
    }

    /// `Delta = D + J M - L^T`: diagonal `delta j_i - (s2 - s2_0) - a_i + |mm|^2`,
    /// off-diagonal `j_i M_ij - L^T_ij`.
    #[inline(always)]
    fn increment_matrix(&self, sys: &TransposedSystem<T>) -> Mat3<T> {
        let (j, ae, mm, delta) = (self.j, sys.ae, sys.mm, self.delta);
        let (l01, l02, l12) = sys.upper;
        let (l10, l20, l21) = sys.lower;
        let dd = Vec3::new(delta * j.x - ae.x, delta * j.y - ae.y, delta * j.z - ae.z);
        Mat3::from_cols(
            Vec3::new(dd.x, j.y * mm.z - l10, -(j.z * mm.y) - l20),
            Vec3::new(-(j.x * mm.z) - l01, dd.y, j.z * mm.x - l21),
            Vec3::new(j.x * mm.y - l02, -(j.y * mm.x) - l12, dd.z),
        )
    }

    /// The part of the invariants' correction added after the solve: `x m + y (j^2 m)` less
    /// the `m` part folded into the solve, i.e. `x m` (and `y j^2 m` when the energy is
    /// corrected).
    #[inline(always)]
    fn invariant_fix(&self, m: Vec3<T>, corr: T, corr_v: T) -> Vec3<T> {
        if corr_v == T::ZERO {
            m.scale(corr)
        } else {
            let v = Vec3::new(self.j2.x * m.x, self.j2.y * m.y, self.j2.z * m.z);
            m.scale(corr).add(v.scale(corr_v))
        }
    }
}

/// `A`, `B` of the cubic for one momentum, with the pieces the step reuses.
struct Coefficients<T> {
    big_a: T,
    big_b: T,
    /// `h m / kappa`.
    mm: Vec3<T>,
    /// `mm_i^2`.
    a: Vec3<T>,
    /// `alpha = |mm|^2`.
    sum_a: T,
    /// `beta = sum a_i j_i^2`.
    beta: T,
}

/// The DMV invariants of one input in scaled units: `a_i = mm_i^2`, `alpha = sum a_i` and
/// `beta = sum a_i j_i^2`.
#[derive(Clone, Copy)]
struct Invariants<T> {
    a: Vec3<T>,
    sum_a: T,
    beta: T,
}

impl<T: Real> Coefficients<T> {
    #[inline(always)]
    fn invariants(&self) -> Invariants<T> {
        Invariants {
            a: self.a,
            sum_a: self.sum_a,
            beta: self.beta,
        }
    }
}

impl<T: Real> Track<T> {
    /// [`Invariants`] of momentum `m`.
    #[inline(always)]
    fn invariants(&self, m: Vec3<T>) -> Invariants<T> {
        let mm = m.scale(self.hn);
        let a = mm.mul_elem(mm);
        Invariants {
            a,
            sum_a: a.x + a.y + a.z,
            beta: a.dot(self.j2),
        }
    }

    #[inline(always)]
    fn coefficients(&self, m: Vec3<T>) -> Coefficients<T> {
        let Invariants { a, sum_a, beta } = self.invariants(m);
        Coefficients {
            big_a: self.sum_j2 - sum_a,
            big_b: self.pair_j2 - beta,
            mm: m.scale(self.hn),
            a,
            sum_a,
            beta,
        }
    }

    /// `g(delta)` (see [`Track`]) and `eps_u`.
    #[inline]
    fn g_only(&self, delta: T, k: Invariants<T>) -> (T, T) {
        let eps_u = self.two_s0 * delta + sq(delta) + k.sum_a;
        let g = self.two_u0 * eps_u + sq(eps_u) - self.s3x8 * delta + c::<T>(4.0) * k.beta;
        (g, eps_u)
    }

    /// Newton's method on `g` from the tracked `delta`, to the largest root: `true` with
    /// `delta` and `inv_dg` updated, or `false` (nothing trusted) when an iterate leaves the
    /// region where convergence to the largest root is guaranteed, or after 12 iterations.
    ///
    /// Why it is safe: in `s = s1_0 + delta` the quartic `q(s) = (s^2 - A)^2 - 8 s3 s - 4 B`
    /// has `q'' = 12 s^2 - 4 A`, so it is convex for `3 s^2 > A`, and every real root lies
    /// either left of that region or in it, where there are at most two. At an iterate with
    /// `s > 0`, `3 s^2 > A` and `q'(s) > 0`, either `q(s) > 0` (then `s` is right of every
    /// root and Newton descends monotonically onto the largest) or `q(s) < 0` (then the one
    /// root to its right is the largest, and the convex tangent step lands right of it).
    /// Each iteration costs one division; from a tracked value after a small change of `m`
    /// or `h` it takes one or two, from the series at small `h |Omega|` two to four.
    #[inline(never)]
    fn newton(&mut self, k: Invariants<T>) -> bool {
        let big_a = self.sum_j2 - k.sum_a;
        let mut delta = self.delta;
        // the last iterate that met the absolute test alone (see below)
        let mut loose = None;
        let mut it = 0;
        while it < 12 {
            let s = self.s0 + delta;
            if !(s > T::ZERO && c::<T>(3.0) * sq(s) > big_a) {
                return false;
            }
            let (g, dg) = self.g(delta, k);
            if !(dg > T::ZERO) || !g.is_finite() {
                return false;
            }
            let inv_dg = T::ONE / dg;
            let step = g * inv_dg;
            delta -= step;
            if step.abs() <= self.newton_tol {
                // quadratic convergence leaves about step^2 / s1, which is round-off of s1
                // but not of delta = O(h^2); one chord step with this derivative (no
                // division) takes delta to round-off too
                let (g, _) = self.g_only(delta, k);
                let chord = g * inv_dg;
                delta -= chord;
                if !delta.is_finite() {
                    return false;
                }
                if Self::settled(chord, step, delta) {
                    self.set_delta(delta);
                    self.inv_dg = inv_dg;
                    return true;
                }
                loose = Some((delta, inv_dg));
            }
            it += 1;
        }
        // a double root (the momentum on a principal axis at a large turn, or a step at the
        // existence limit), where Newton converges only linearly and the test above may never
        // hold: the last iterate that met the absolute test, as before that test (refusing
        // it refused steps the old acceptance took, some within their accuracy, found in
        // review)
        match loose {
            Some((d, inv)) => {
                self.set_delta(d);
                self.inv_dg = inv;
                true
            }
            None => false,
        }
    }

    /// Whether the chord step `chord` after a Newton step `step` (to `delta`) left `delta` at
    /// round-off. With `K = g'' / (2 g')`, the Newton step leaves an error of about
    /// `K step^2`, which the chord step (its size) removes up to a factor `2 K |step|`: what
    /// is left is about `2 chord^2 / |step|`, kept when below `16 eps |delta|` (rounding
    /// makes `chord` itself a few `eps |delta|`: a stricter test took Newton steps that
    /// changed nothing).
    ///
    /// On most bodies `K` is about `1 / s1` and the first Newton step below `newton_tol`
    /// passes: three products a solve (the lab's counted operations of the forced scenes grew
    /// 0.3-1 %; kept as a per-trajectory tolerance instead, the larger tracking data cost the
    /// M4F's filter tick, which copies an integrator, 52 instructions). On a needle
    /// turned by a step with `h |m|` well above `sqrt(J_min J_max)` the quartic's two largest
    /// roots are close (`J = (1, 5e-8, 5e-8)` at `h |m| = 5e-3`, from the trial's start
    /// `m = (1.2e-9, 0.024, 0.299)`: `delta = -1.191e-5` and `-1.211e-5`; the values move with
    /// the momentum's direction), `K` is the inverse of their separation, and stopping after the first
    /// chord step (as before) left `delta` 5e-8 off relative, the step `2e-7` off the sphere
    /// and refused (`Degenerate`; found by a first-use trial: half the starts on
    /// `I = (1e-7, 1, 1)`, 54 % of changes of `h` by 5-95 % on `(1e-6, 1, 1)`). There Newton
    /// goes on, two or three steps more.
    #[inline(always)]
    fn settled(chord: T, step: T, delta: T) -> bool {
        // 2 chord^2 / |step| <= 16 eps |delta|
        sq(chord) <= c::<T>(8.0 * T::EPSILON.to_f64()) * (delta * step).abs()
    }

    /// After an outside change of `m` or `h`: a chord step of size `correction` from the
    /// tracked `delta`, then a second, kept (and `true`) only if it shows the stale
    /// derivative good enough. A chord step contracts the error by `r = |1 - g'/g'_stale|`,
    /// measured as the ratio of the two corrections, so after the second the error is about
    /// `c2 r`; it must be below `eps |delta|` (the relative accuracy the increment needs,
    /// [`Track`]). `r` is `O(h^2 |Omega|^2)` times the relative change of the invariants, so a
    /// jittering clock or a filter's correction passes; a large change goes to Newton.
    ///
    /// When the second correction is below `4 eps |d1|` (the usual case: `r` is tiny), the
    /// first step's value is kept and the convergence test is skipped (16 instructions a
    /// step after an outside change on the M4F).
    #[inline]
    fn chord_converges(&mut self, k: Invariants<T>, correction: T) -> bool {
        let d1 = self.delta - correction;
        let (g1, _) = self.g_only(d1, k);
        let c2 = g1 * self.inv_dg;
        if c2.abs() <= c::<T>(4.0) * T::EPSILON * d1.abs() && d1.is_finite() {
            self.set_delta(d1);
            return true;
        }
        let d2 = d1 - c2;
        let converged = c2.abs() * c::<T>(2.0) <= correction.abs()
            && sq(c2) <= T::EPSILON * d2.abs() * correction.abs();
        if converged && d2.is_finite() {
            self.set_delta(d2);
            true
        } else {
            false
        }
    }

    /// Sets the tracked root, and whether free-running steps may keep it as it is.
    #[inline]
    fn set_delta(&mut self, delta: T) {
        self.delta = delta;
        self.may_freeze = delta.abs() <= c::<T>(FROZEN_BELOW) * self.s0;
    }

    /// `g(delta)` and `g'(delta)`.
    fn g(&self, delta: T, k: Invariants<T>) -> (T, T) {
        let (g, eps_u) = self.g_only(delta, k);
        let dg = (self.two_u0 + eps_u + eps_u) * (self.two_s0 + delta + delta) - self.s3x8;
        (g, dg)
    }
}

/// The cosine of a large turn read off the momentum pair, where that is the better reading:
/// `m + dm = Q m` with `Q` a turn by `theta` about `b`'s direction (either sense), so
/// `dm . m_perp = (cos theta - 1) |m_perp|^2` with `m_perp` the part of `m` normal to `b`.
/// Its error is about `eps |m|^2 / |m_perp|^2`; `root = |cos theta| = sqrt(1 - 4 |b|^2)`, read
/// off `|b|^2 = sin^2 theta / 4`, which is stationary at a quarter turn, has `eps / root`, up
/// to `sqrt(eps)` there: half the digits (a step at 0.977 of `max_step` turned the attitude
/// 4.7e-8 rad off in f64 and 5.4e-4 in f32, found in review). Taken where
/// `|m_perp|^2 > max(root, sqrt(eps)) |m|^2` and it agrees with `root` to `4 sqrt(eps)` (a
/// larger disagreement is not a quarter turn's rounding, and the sign test decides);
/// `None` otherwise (momentum near the axis: a sphere, a principal axis).
#[cold]
fn quarter_turn_cosine<T: Real>(m: Vec3<T>, b: Vec3<T>, root: T, dm: Vec3<T>) -> Option<T> {
    let (sm, sb) = (m.max_abs(), b.max_abs());
    if !(sm > T::ZERO && sb > T::ZERO && sm <= T::MAX && sb <= T::MAX) {
        return None;
    }
    let u = m.divided_by(sm);
    let d = dm.divided_by(sm);
    let a = b.divided_by(sb);
    let along = a.dot(u) / a.norm2();
    let perp = u.sub(a.scale(along));
    let (perp2, u2) = (perp.norm2(), u.norm2());
    let sqrt_eps = T::EPSILON.sqrt();
    if !(perp2 > u2 * root.max(sqrt_eps)) {
        return None;
    }
    let cos = T::ONE + d.dot(perp) / perp2;
    if !((cos.abs() - root).abs() <= c::<T>(4.0) * sqrt_eps) {
        return None;
    }
    Some(cos.max(-T::ONE).min(T::ONE))
}

/// `(p0 - 1, 1 / p0)` for `p0^2 = (1 + sqrt(1 - 4 |b|^2)) / 2` from `b2 = |b|^2 <=`
/// [`series_limit`], by their series: two square roots and a division in a row were the
/// longest stretch of the step's dependency chain on the host (and two software square roots
/// on a Cortex-M3), and `p0 - 1` comes out with full relative accuracy.
///
/// In `x = 4 |b|^2` (`p0 = cos(phi / 2)` for `x = sin^2 phi`),
/// `p0 - 1 = -x/8 - 5x^2/128 - 21x^3/1024 - 429x^4/32768 - 2431x^5/262144 - ...` and
/// `1/p0 = 1 + x/8 + 7x^2/128 + 33x^3/1024 + 715x^4/32768 + 4199x^5/262144 + ...`, both with
/// positive coefficients that shrink, so the part left out after degree `n` is at most
/// `c_{n+1} x^{n+1} / (1 - x)`. f64 sums to degree 4 (left out: below `0.017 x^5`), f32 to
/// degree 2 (below `0.033 x^3`); with [`series_limit`] that is at most a quarter of an ulp of
/// one. Rounding adds about an ulp; the unit tests check both against the closed forms.
#[inline(always)]
fn turn_series<T: Real>(b2: T) -> (T, T) {
    if T::EPSILON.to_f64() > 1e-10 {
        (
            -b2 * (c::<T>(0.5) + b2 * c::<T>(5.0 / 8.0)),
            T::ONE + b2 * (c::<T>(0.5) + b2 * c::<T>(7.0 / 8.0)),
        )
    } else {
        (
            -b2 * (c::<T>(0.5)
                + b2 * (c::<T>(5.0 / 8.0)
                    + b2 * (c::<T>(21.0 / 16.0) + b2 * c::<T>(429.0 / 128.0)))),
            T::ONE
                + b2 * (c::<T>(0.5)
                    + b2 * (c::<T>(7.0 / 8.0)
                        + b2 * (c::<T>(33.0 / 16.0) + b2 * c::<T>(715.0 / 128.0)))),
        )
    }
}

/// The largest `|b|^2` for which [`turn_series`] is used: `x = 4 |b|^2 = 1.25e-3` in f64
/// (`0.017 x^5 < eps / 4`; `h |Omega|` up to about `0.035`) and `x = 0.0095` in f32
/// (`0.033 x^3 < eps / 4`; `h |Omega|` up to about `0.1`, which covers a 200 Hz loop below
/// 20 rad/s). Larger turns take the square roots.
#[inline(always)]
fn series_limit<T: Real>() -> f64 {
    if T::EPSILON.to_f64() > 1e-10 {
        0.0095 / 4.0
    } else {
        1.25e-3 / 4.0
    }
}

/// `|delta| / sum j` below which a free-running step keeps `delta` (and runs the rational map
/// of crate::mv_frozen): at large `h |Omega|` a frozen `s1` lets round-off grow even with the
/// invariants held (docs/MATH.md §4). `tests/mv.rs` `long_runs_near_the_existence_limit_stay_at_round_off`
/// (21 bodies at 0.5, 0.8 and 0.95 of their step limit) passes with this bound raised to `0.2`
/// and fails at `0.3` (the talk's case at `0.95 h_max` has `0.4`): a margin of 20. The talk's
/// case has `2.6e-3` at `h = 0.1`.
const FROZEN_BELOW: f64 = 1e-2;

/// True iff `mu^3 - A mu^2 + B mu - C` (`C >= 0`) has no negative real root.
#[inline]
fn exists<T: Real>(big_a: T, big_b: T, big_c: T) -> bool {
    if big_a > T::ZERO && big_b > T::ZERO {
        return true;
    }
    discriminant(big_a, big_b, big_c) < T::ZERO
}

/// Discriminant of `mu^3 - A mu^2 + B mu - C`: `18ABC - 4A^3 C + A^2 B^2 - 4B^3 - 27C^2`.
#[inline]
fn discriminant<T: Real>(a: T, b: T, cc: T) -> T {
    c::<T>(18.0) * a * b * cc - c::<T>(4.0) * sq(a) * a * cc + sq(a) * sq(b)
        - c::<T>(4.0) * sq(b) * b
        - c::<T>(27.0) * sq(cc)
}

impl<T: Real> Integrator<T> for Mv<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        let v = checked_momentum(m)?;
        let follows = matches!(&self.anchor, Some(a) if a.last == v);
        let next = match self.advance(v, follows, true) {
            Ok(step) => step.next,
            Err(e) => return self.refused(e),
        };
        self.forget_attitude();
        *m = next.to_array();
        Ok(())
    }

    fn step_carrying(
        &mut self,
        m: &mut [T; 3],
        lost: &mut [T; 3],
        carry: bool,
    ) -> Result<(), StepError> {
        let v = checked_momentum(m)?;
        // as step_state_carry: with carry, every step an outside change, its rounding
        // carried
        let follows = !carry && matches!(&self.anchor, Some(a) if a.last == v);
        let step = match self.advance(v, follows, !carry) {
            Ok(step) => step,
            Err(e) => return self.refused(e),
        };
        if carry {
            *lost = step.carry_into(v, *lost);
            // as step_state_carry
            self.retake = true;
        }
        self.forget_attitude();
        *m = step.next.to_array();
        Ok(())
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        let (v, q) = checked_state(s)?;
        let follows = self.follows_state(v, q);
        let step = match self.advance(v, follows.1, true) {
            Ok(step) => step,
            Err(e) => return self.refused(e),
        };
        let next = step.next;
        let (p, small) = self.rotation_between(v, next, step.increment)?;
        let lost = self.carried_turn(follows, q);
        let (held, lost) = self.turn_attitude(follows, q, next, p, lost, carries_rounding::<T>());
        if small {
            // a finite unit q turned by a finite p within 1e-4 of one: finite (and a
            // hold that is not is dropped), so the check is skipped
            s.m = next.to_array();
            s.q = held.to_array();
        } else {
            write_state_stepped(s, next, held)?;
        }
        self.keep_turn_carry(lost);
        self.count_attitude_step();
        Ok(())
    }

    #[inline(always)]
    fn step_state_carrying(
        &mut self,
        s: &mut State<T>,
        lost: &mut State<T>,
        carry: bool,
    ) -> Result<(), StepError> {
        // a branch to two functions: the plain step stays the one `step_state` runs
        if carry {
            self.step_state_carry(s, lost)
        } else {
            self.step_state(s)
        }
    }

    fn step_size(&self) -> T {
        self.h
    }

    /// A zero `h` (a timer read twice in one tick) pauses the steps: they leave the state as
    /// it is, and the trajectory's invariants are kept and carried to the next non-zero `h`
    /// (its first step solves the root again). (Before, a step at `h = 0` re-took the
    /// invariants from its input and so did the step after it, and they random-walked: in
    /// f32 `|m|^2` and `E` 4e-4 off after `2 x 10^5` ticks of which one in seven was zero,
    /// found in review.) The `h` of the last step changes nothing
    /// either: a loop that sets a measured `dt` every tick pays for a change only when the
    /// reading changes (the same `dt` set every tick cost what a jittering one does, 1.7x
    /// the free-running step, found in review).
    fn set_step_size(&mut self, h: T) {
        if h == self.h {
            return;
        }
        // the tracked root is kept within 2x of the old step: (h / old)^2 in [1/4, 4], false
        // for a zero, NaN or infinite h and for old = 0 (one division: the four comparisons
        // of magnitudes it replaced cost more on the M4F); paused, there is no root
        let r2 = sq(h / self.h);
        match self.track.as_mut() {
            Some(t) if r2 >= c::<T>(0.25) && r2 <= c::<T>(4.0) => {
                self.h = h;
                self.turn_scale.v = self.inv_i.scale(h * c::<T>(0.25));
                self.recheck = true;
                let hn = t.scaled(h);
                t.hn = hn;
                t.delta *= r2;
                if let Some(a) = self.anchor.as_mut() {
                    let carried = a.carry;
                    a.rescale_later(r2);
                    if carries_rounding::<T>() && carried && !a.carry {
                        self.carry_m = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
                        self.carry_q = Quat::from_array([T::ZERO; 4]);
                    }
                }
            }
            _ => self.set_far_step_size(h),
        }
    }

    fn body(&self) -> &Body<T> {
        &self.body
    }

    /// Forgets the tracked `s1` and the Casimir anchor, so the next step solves for `s1`
    /// afresh (after a reset of the state; not needed for corrections, which the tracking
    /// absorbs).
    fn reset(&mut self) {
        // the fields `forget_trajectory` clears that a next step reads after a reset (the
        // others are only read with an anchor); calling it from here, cold or not, moved the
        // M4F's free-running step 370 -> 390 instructions (code layout), and cold it laid a
        // filter's tick that resets a scratch copy every time 1470 instructions longer
        self.track = None;
        self.anchor = None;
        self.phase = 0;
        self.carry_m = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
        self.carry_q = Quat::from_array([T::ZERO; 4]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Which path a step takes: the rational map while free running at small `h |Omega|`,
    /// the solve after any outside change and at large `h |Omega|`.
    #[test]
    fn free_running_small_steps_take_the_rational_map() {
        let body = Body::<f64>::from_mass_matrix([0.9218, 0.7382, 0.1763]).unwrap();
        let mut m = [0.4165, 0.9072, 0.0588];
        let mut mv = Mv::new(body, 0.01);
        mv.step(&mut m).unwrap();
        assert!(mv.frozen.is_none(), "the first step solves");
        mv.step(&mut m).unwrap();
        assert!(mv.frozen.is_some(), "a free-running step takes the map");
        mv.set_step_size(0.011);
        mv.step(&mut m).unwrap();
        assert!(mv.frozen.is_none(), "a changed h solves");
        m[0] *= 1.0 + 1e-4;
        mv.step(&mut m).unwrap();
        assert!(mv.frozen.is_none(), "a changed m solves");
        let mut big = Mv::new(body, 0.9);
        let mut m = [0.4165, 0.9072, 0.0588];
        for _ in 0..3 {
            big.step(&mut m).unwrap();
        }
        assert!(big.frozen.is_none(), "large h |Omega| tracks s1");
    }

    /// The hold step's guard on its own: on needles where [`FrozenMap::new`] refuses the map,
    /// the map is forced in (built without the refusal) and left to run. The guard must find
    /// the invariants moving at a hold, stop the map for good and let the trajectory solve,
    /// whose hold takes the damage back. Oracle: the conservation laws. Up to
    /// `HOLD_PERIOD` free steps pass before a hold looks: on the fastest needle here the map
    /// has moved `|m|^2` by 2.1e-5 by then (measured), which is why the refusal is the main
    /// guard. Without this guard `|m|^2` ends 44 % off; with a refusal that does not stick
    /// (`Track::set_delta` re-allowing the map) the map comes back.
    #[test]
    fn a_hold_stops_a_map_that_amplifies_round_off() {
        for (i, h) in [
            ([0.01, 1.0, 1.0], 0.1),
            ([0.01, 1.0, 1.0], 0.12),
            ([0.001, 1.0, 1.0005], 0.1),
        ] {
            let body = Body::<f64>::from_inertia(i).unwrap();
            let mut m = [0.0, 0.6, 0.8];
            let (c0, e0) = (body.casimir(&m), body.energy(&m));
            let mut mv = Mv::new(body, h);
            mv.step(&mut m).unwrap();
            let (t, a) = (mv.track.as_ref().unwrap(), mv.anchor.as_ref().unwrap());
            assert!(
                FrozenMap::new(t.j, t.c0, t.s0, t.delta, t.hn, a.alpha).is_none(),
                "{i:?} h {h}: the refusal alone would keep the map out"
            );
            mv.frozen =
                FrozenMap::with_limit(t.j, t.c0, t.s0, t.delta, t.hn, a.alpha, f64::INFINITY);
            assert!(mv.frozen.is_some());
            let (mut worst, mut stopped_at, mut after) = (0.0f64, None, 0.0f64);
            for k in 0..3000 {
                mv.step(&mut m).unwrap();
                let dc = (body.casimir(&m) - c0).abs() / c0;
                let de = (body.energy(&m) - e0).abs() / e0;
                worst = worst.max(dc).max(de);
                if stopped_at.is_none() && mv.no_map {
                    stopped_at = Some(k);
                }
                if stopped_at.is_some_and(|s| k > s + 8) {
                    after = after.max(dc).max(de);
                }
            }
            extern crate std;
            std::println!(
                "{i:?} h {h}: map stopped at step {stopped_at:?}; invariants worst {worst:.1e}, \
                 from 8 steps after the stop {after:.1e}"
            );
            let t = mv.track.as_ref().unwrap();
            assert!(
                mv.no_map && !t.may_freeze && mv.frozen.is_none(),
                "{i:?} h {h}"
            );
            assert!(
                after <= 1e-13,
                "{i:?} h {h}: invariants after the stop {after:e}"
            );
            assert!(
                worst <= 1e-4,
                "{i:?} h {h}: invariants before the stop {worst:e}"
            );
        }
    }

    /// `(p0 - 1, 1 / p0)` in f64 from closed forms without cancellation:
    /// `p0^2 - 1 = -x / (2 (1 + sqrt(1 - x)))`, `p0 - 1 = (p0^2 - 1) / (p0 + 1)`.
    fn turn_closed_form(b2: f64) -> (f64, f64) {
        let x = 4.0 * b2;
        let p0sq_minus_1 = -x / (2.0 * (1.0 + (1.0 - x).sqrt()));
        let p0 = (1.0 + p0sq_minus_1).sqrt();
        (p0sq_minus_1 / (p0 + 1.0), 1.0 / p0)
    }

    /// The series of [`turn_series`] up to [`series_limit`] against the closed forms: `p0 - 1`
    /// within half an ulp of one (the truncation's quarter plus rounding; a wrong coefficient
    /// of the last term kept is off by more), `1 / p0` within the closed form's own rounding.
    /// The f32 steps carry their rounding where `h |Omega|` is below 1e-3 and nowhere else
    /// ([`CARRY_TURN2`]); oracle: `h |I^-1 m|` from the body, not the step's scaled units
    /// (a first gate on `|h m / kappa|^2` carried a rod spinning about its axis at
    /// `h |Omega| = 0.1`, found in review). Where it does not carry, nothing is kept.
    #[test]
    fn the_f32_carry_runs_only_at_small_h_omega() {
        let cases: [([f32; 3], [f32; 3], f32); 5] = [
            ([0.01, 1.0, 1.0], [1.0, 0.02, -0.02], 1e-3),
            ([60.0, 95.0, 120.0], [0.02, -0.05, 0.1], 1e-3),
            ([60.0, 95.0, 120.0], [60.0, -95.0, 120.0], 5e-3),
            ([60.0, 95.0, 120.0], [6.0, -9.5, 12.0], 5e-3),
            ([1.0, 100.0, 100.0], [20.0, 1.0, 1.0], 1e-3),
        ];
        for (inertia, m0, h) in cases {
            let body = Body::<f32>::from_inertia(inertia).unwrap();
            let w = Vec3::new(m0[0] / inertia[0], m0[1] / inertia[1], m0[2] / inertia[2]);
            let hw2 = (h * h * w.norm2()) as f64;
            let mut mv = Mv::new(body, h);
            let mut s = State::new(m0, [1.0, 0.0, 0.0, 0.0]);
            // a carried (forced) step first: the plain steps after it take the test again
            let mut lost = State::new([0.0; 3], [0.0; 4]);
            mv.step_state_carrying(&mut s, &mut lost, true).unwrap();
            assert!(!mv.anchor.as_ref().unwrap().carry);
            for _ in 0..100 {
                mv.step_state(&mut s).unwrap();
            }
            let carrying = mv.anchor.as_ref().unwrap().carry;
            // (a margin around the bound: h |Omega| moves a little along the orbit)
            if hw2 < 0.5 * CARRY_TURN2 {
                assert!(carrying, "{inertia:?} {m0:?} h {h}: (h w)^2 {hw2:e}");
            } else if hw2 > 2.0 * CARRY_TURN2 {
                assert!(!carrying, "{inertia:?} {m0:?} h {h}: (h w)^2 {hw2:e}");
                assert_eq!(mv.carry_m.to_array(), [0.0; 3]);
                assert_eq!(mv.carry_q.to_array(), [0.0; 4]);
            }
        }
        // f64 never carries
        let body = Body::<f64>::from_inertia([60.0, 95.0, 120.0]).unwrap();
        let mut mv = Mv::new(body, 1e-3);
        let mut s = State::new([0.02, -0.05, 0.1], [1.0, 0.0, 0.0, 0.0]);
        for _ in 0..100 {
            mv.step_state(&mut s).unwrap();
        }
        assert!(!mv.anchor.as_ref().unwrap().carry);
    }

    #[test]
    fn turn_series_matches_the_closed_forms() {
        let (lim64, lim32) = (series_limit::<f64>(), series_limit::<f32>());
        let mut worst = [0.0f64; 4];
        for i in 0..=4000 {
            // dense near the limit, where the truncation is largest
            let t = 1.0 - (i as f64 / 4000.0).powi(3);
            let b2 = lim64 * t;
            let (w, inv) = turn_series::<f64>(b2);
            let (w_ref, inv_ref) = turn_closed_form(b2);
            worst[0] = worst[0].max((w - w_ref).abs() / f64::EPSILON);
            worst[1] = worst[1].max((inv - inv_ref).abs() / f64::EPSILON);
            let b2 = (lim32 * t) as f32;
            let (w, inv) = turn_series::<f32>(b2);
            let (w_ref, inv_ref) = turn_closed_form(f64::from(b2));
            let eps = f64::from(f32::EPSILON);
            worst[2] = worst[2].max((f64::from(w) - w_ref).abs() / eps);
            worst[3] = worst[3].max((f64::from(inv) - inv_ref).abs() / eps);
        }
        assert!(worst[0] <= 0.5, "f64 p0 - 1: {} eps", worst[0]);
        assert!(worst[1] <= 1.5, "f64 1 / p0: {} eps", worst[1]);
        assert!(worst[2] <= 0.5, "f32 p0 - 1: {} eps", worst[2]);
        assert!(worst[3] <= 1.0, "f32 1 / p0: {} eps", worst[3]);
    }
}
