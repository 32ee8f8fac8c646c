//! The common interface of every method, and the full state.

use crate::body::Body;
use crate::error::StepError;
use crate::linalg::{Quat, Vec3};
use crate::real::{c, Real};

/// Body angular momentum and attitude.
///
/// `m` is the angular momentum in the body frame; `q = (w, x, y, z)` is the unit quaternion
/// that maps body to space (`x_space = R(q) x_body`), so the spatial momentum `R(q) m` is
/// constant under the free motion.
///
/// A step takes `q` as it is while `|q|` is within `2^-10` of one (renormalising a unit
/// quaternion every step would turn it by about an ulp each time), and normalises it beyond.
/// A `q` that is off unit length by `d` within that band costs a relative error of about `d`
/// in the step's turn in some methods (`Mv`, `PreMv`, `Midpoint`, `Splitting`: 1.75e-6
/// rad on a 4.4e-3 rad step at `d = 4e-4`, found in review); a caller who builds `q` from
/// measurements should normalise it (`Quaternion::normalize`).
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
    #[must_use]
    pub fn new(m: [T; 3], q: [T; 4]) -> Self {
        Self { m, q }
    }

    /// The spatial angular momentum `pi = R(q) m`, conserved exactly by the flow and, to
    /// round-off, by the DMV and splitting methods.
    #[must_use]
    pub fn spatial_momentum(&self) -> [T; 3] {
        Quat::from_array(self.q)
            .rotate(Vec3::from_array(self.m))
            .to_array()
    }
}

/// A one-step method for the free rigid body with a fixed step size.
///
/// Both methods leave the state untouched when they return `Err`, and never produce NaN.
///
/// # Integrators are `Clone`, not `Copy`
///
/// Every integrator of this crate derives `Clone` but not `Copy` (the body, the state and the
/// errors stay `Copy`). Most of them carry per-trajectory data between steps (`Mv`'s tracked
/// root and invariant anchors, `PreMv`'s modified body, `Exact`'s set-up orbit), and each step
/// checks whether its input is the state it returned last. A stepped copy is therefore never
/// wrong, only silently worse: the original, stepped later, sees a state it did not return and
/// treats it as an outside change, re-solving its root (for `PreMv` about 1.5 times a step's
/// cost on the Cortex-M4F) and re-anchoring its invariants to the input, so the round-off
/// holding of `|m|^2`, `E` and `R(q) m` restarts from whatever the copy drifted to. With `Copy`,
/// `fn tick<I: Integrator<f32>>(mut i: I, ..)` or `let mut a = b;` compiles and does exactly
/// that; without it the compiler points at the move. A deliberate copy (firmware keeping a
/// checkpoint, event location on a scratch integrator) is `.clone()`, the same memcpy of a few
/// hundred bytes. Integrators without state (`Rk4`, `Splitting`) follow the rule too, so that
/// adding a cache later is not a breaking change. (The same reasoning keeps
/// `core::ops::Range`, an iterator, from being `Copy`.)
pub trait Integrator<T> {
    /// Advances the body angular momentum by one step (momentum-only scenes: attitude is not
    /// computed, and costs nothing).
    ///
    /// # Errors
    ///
    /// A [`StepError`] when the step cannot be taken; `m` is then left as it was. Every
    /// method refuses non-finite input ([`StepError::NonFinite`]) and results that would
    /// overflow ([`StepError::Overflow`]); the DMV methods refuse steps past their existence
    /// limit ([`StepError::StepTooLarge`], see [`crate::Mv::max_step`]), the implicit
    /// midpoint rule an iteration that does not converge ([`StepError::NoConvergence`]), and
    /// forced integrators whose torque needs the attitude return
    /// [`StepError::NeedsAttitude`]. Each type's docs list its own cases.
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError>;

    /// Advances momentum and attitude by one step.
    ///
    /// # Errors
    ///
    /// As [`Integrator::step`] (less [`StepError::NeedsAttitude`]), and
    /// [`StepError::NonFinite`] for a zero or non-finite quaternion; the state is then left
    /// as it was.
    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError>;

    /// [`Integrator::step_state_carrying`] for momentum only. Not part of the stable API.
    #[doc(hidden)]
    fn step_carrying(
        &mut self,
        m: &mut [T; 3],
        lost: &mut [T; 3],
        carry: bool,
    ) -> Result<(), StepError> {
        let _ = (lost, carry);
        self.step(m)
    }

    /// The forced integrators' drift step (crate::forced). With `carry`, the step from `s`
    /// taken as an outside change (no hold onto the trajectory's invariants: a torque acts),
    /// with the attitude from `s.q + lost.q` (`lost.q`, what earlier roundings of the attitude
    /// dropped, below an ulp of it, is added to the attitude's increment and replaced by what
    /// this step's rounding of it drops), and what the rounding of the momentum's update drops
    /// (`applied - (m' - m)` for `m' = m + applied` rounded once) added to `lost.m`, which the
    /// forced integrators carry into their next kick. So in f32 the state does not random-walk
    /// by an ulp a step under a torque. Without `carry`, exactly [`Integrator::step_state`]
    /// (for `Mv` a function of its own beside the carried one: a forced integrator links both,
    /// as it decides at run time). The default is `step_state`. On `Err` `lost` is untouched.
    /// Not part of the stable API.
    #[doc(hidden)]
    fn step_state_carrying(
        &mut self,
        s: &mut State<T>,
        lost: &mut State<T>,
        carry: bool,
    ) -> Result<(), StepError> {
        let _ = (lost, carry);
        self.step_state(s)
    }

    /// The step size `h`.
    #[must_use]
    fn step_size(&self) -> T;

    /// Changes the step size. Integrators that keep per-trajectory data decide what survives
    /// (`Mv` keeps its tracked root across small changes); nothing is checked here: an invalid
    /// `h` (not finite, or past the method's limit) is refused by the next step (`Err`, state
    /// untouched), and by every step after it until a valid `h` is set. A negative `h` steps
    /// backwards in time and `h = 0` leaves the state as it is (the forced integrators in f32
    /// may add the sub-ulp remainder their kicks and wheel turns carry, an ulp of `m` or `q`,
    /// and they normalise a `q` more than `2^-10` off unit length): a loop that sets a measured
    /// `dt` each tick should refuse a non-positive or implausible `dt` itself (a timer that
    /// wrapped) and keep the last good one.
    fn set_step_size(&mut self, h: T);

    /// The body being integrated (for [`crate::PreMv`] the true body, not the modified one).
    #[must_use]
    fn body(&self) -> &Body<T>;

    /// Forgets per-trajectory data (tracked roots, caches), so the next step starts afresh as
    /// after construction with the current step size (a forced integrator also keeps its
    /// time, torque and rotor). Integrators without such data do nothing.
    ///
    /// Not needed after changing the state: every integrator sees a momentum or attitude it
    /// did not return and takes it as a new start (a filter's correction, a torque kick). In f32
    /// a reset also drops the carried rounding, which costs accuracy in a loop that resets at
    /// every correction: `Forced<Mv>` at 200 Hz under a jittering clock with a correction of
    /// `m` and `q` every 100 ticks ended 5-11x the loop's floor (the same loop in f64 with the
    /// corrections rounded to f32) where without the resets it stayed at 1x (a first-use trial).
    fn reset(&mut self) {}

    /// The state one step of size `h` after `s` (any `h`, typically a fraction of the step),
    /// leaving this integrator untouched: for output between steps and event location.
    ///
    /// The step is taken by a scratch copy of the integrator with its step size set to `h` and
    /// its per-trajectory data forgotten, so the result is bit-identical to a freshly built
    /// integrator's `step_state` with step `h` (for a forced integrator: one built with the same
    /// time, torque and rotor, which the copy keeps), and the tracked state of `self` (its roots,
    /// anchors, caches), hence every later step, is exactly as if no partial step had been
    /// taken. Its cost is that of a first step (for `Mv`, the root is found by Newton from its
    /// series, no transcendental call at small `h |Omega|`); `q = [w, x, y, z]` as everywhere.
    /// For [`crate::Exact`] it is the exact flow over `h`, as [`crate::Orbit::at`].
    ///
    /// # Errors
    ///
    /// Those of `step_state` with step `h` (`s` is only read).
    fn step_partial(&self, s: &State<T>, h: T) -> Result<State<T>, StepError>
    where
        Self: Sized + Clone,
        T: Copy,
    {
        let mut scratch = self.clone();
        scratch.set_step_size(h);
        scratch.reset();
        let mut out = *s;
        scratch.step_state(&mut out)?;
        Ok(out)
    }
}

/// Whether `|after|^2` is `|before|^2` to `tol` relative, both measured in units of
/// `before`'s largest component (so neither square overflows or underflows apart); a zero
/// `before` agrees only with a zero `after`. The check a step makes where its arithmetic keeps
/// `|m|^2` and a result off the sphere means it went wrong (`Mv` below the scaled units'
/// resolution, `Midpoint` stopped short of a solution).
pub(crate) fn norms_agree<T: Real>(before: Vec3<T>, after: Vec3<T>, tol: T) -> bool {
    let big = before.max_abs();
    if !(big > T::ZERO) {
        return after.max_abs() == T::ZERO;
    }
    let to_unit = T::ONE / big;
    let (b, a) = (before.scale(to_unit).norm2(), after.scale(to_unit).norm2());
    (a - b).abs() <= tol * b
}

/// Checks a state before a step: finite entries and a non-zero quaternion. Returns the
/// momentum and the attitude, normalised only if it is off unit length by more than `2^-10`
/// (renormalising a unit quaternion every step rounds each component and so turns it by
/// about an ulp; [`compose_attitude`] keeps the length instead).
pub(crate) fn checked_state<T: Real>(s: &State<T>) -> Result<(Vec3<T>, Quat<T>), StepError> {
    let m = Vec3::from_array(s.m);
    if !m.is_finite() {
        return Err(StepError::NonFinite);
    }
    Ok((m, checked_quat(&s.q)?))
}

/// The attitude of [`checked_state`]: `q` as it is within `2^-10` of unit length, else
/// normalised, and `NonFinite` for a non-finite or zero one.
#[inline(always)]
fn checked_quat<T: Real>(q: &[T; 4]) -> Result<Quat<T>, StepError> {
    let quat = Quat::from_array(*q);
    // first: it fails for a NaN or infinite |q|^2, so the loop's state passes with one
    // comparison (the two tests below cost about 20 instructions a step on the M4F)
    if (quat.norm2() - T::ONE).abs() <= T::from_f64(1.0 / 1024.0) {
        return Ok(quat);
    }
    unit_or_refused(q)
}

/// [`checked_state`]'s test of the attitude alone (the momentum is checked by the set-up it
/// guards), where the step has one: taken by a step that changes its own set-up (a modified
/// body, a re-timed step) before its inner step checks the state, so that a refused state
/// leaves the pending change pending. Without it `RetimedMv` and `PreMv` applied a change of
/// `h` or `m` and then refused a zero `q`, and the steps after differed from a twin's that
/// never saw the bad call (1.5e-14 against 6.2e-15 from `Exact` at `t = 10`, found in
/// review). The unit quaternion passes with one comparison (the whole of `checked_state`
/// cost the M4F's `PreMv` step 30-38 instructions in the loop's regimes).
#[inline(always)]
pub(crate) fn checked_attitude<T: Real>(q: Option<&[T; 4]>) -> Result<(), StepError> {
    match q {
        Some(q) => checked_quat(q).map(|_| ()),
        None => Ok(()),
    }
}

/// [`checked_state`] with the attitude at unit length to the last bit: where an exact
/// trajectory starts (`Orbit`, `Exact`). `checked_state` leaves `|q|` within `2^-10` as it
/// is, and the exact evaluation's pull back to unit length is first order about `q0`, which
/// turns an error of `|q0|` into one of the attitude (`|q0| = 1.0004`: 8e-4 rad; an
/// f32-normalised `q0` widened to f64: 6.6e-8 rad, found in a first-use trial; past half a
/// turn a step rebuilt from its own output grew `|q| - 1` 1.8x a step, found in another).
pub(crate) fn checked_unit_state<T: Real>(s: &State<T>) -> Result<(Vec3<T>, Quat<T>), StepError> {
    let (m, q) = checked_state(s)?;
    // normalize returns q itself where it cannot (checked_state has refused those)
    Ok((m, q.normalize().0))
}

/// A quaternion off unit length by more than `2^-10` as its direction: any finite nonzero
/// `q`, `|q|^2` overflowing or underflowing included (as `Quaternion::normalize`; found in a
/// first-use trial: `1e-200` was refused). Out of line: inlined into every step's
/// [`checked_state`] it cost the M4F's free-running `Mv` step 32 instructions it never runs.
#[cold]
#[inline(never)]
fn unit_or_refused<T: Real>(q: &[T; 4]) -> Result<Quat<T>, StepError> {
    match Quat::from_array(*q).normalize() {
        (q, true) => Ok(q),
        _ => Err(StepError::NonFinite),
    }
}

/// `q` turned in space by the small angle `2 half` to first order: `q + (0, half) (x) q`
/// (exact to `O(|half|^2)`; no square root). The holds of `R(q) m` ([`crate::Mv`]'s and a
/// gyrostat's forced step) turn the attitude back onto the trajectory's spatial momentum with
/// it, by `half = (pi x pi0 / |pi0|^2) / 2`. A non-finite result returns `q` unchanged.
#[inline(always)]
pub(crate) fn turn_in_space<T: Real>(q: Quat<T>, half: Vec3<T>) -> Quat<T> {
    let turned = Quat {
        w: q.w - half.dot(q.vector()),
        x: q.x + (half.x * q.w + (half.y * q.z - half.z * q.y)),
        y: q.y + (half.y * q.w + (half.z * q.x - half.x * q.z)),
        z: q.z + (half.z * q.w + (half.x * q.y - half.y * q.x)),
    };
    if turned.is_finite() {
        turned
    } else {
        q
    }
}

/// Whether the steps carry the state's rounding at this precision (Fast2Sum residues handed
/// to the next step: [`crate::Forced`]'s error model, and [`crate::Mv`]'s plain steps at slow
/// turns): in f32 an ulp a step of random walk, or a biased loss of a slow motion, is what
/// limits a long run; in f64 it is `1e-16` a step (`1e-12` after `10^8` steps), below the
/// methods' own error, and the carry's flops would buy nothing (they would also count against
/// every method in the work-precision tables). A constant per type: the branches fold.
#[inline(always)]
pub(crate) fn carries_rounding<T: Real>() -> bool {
    T::EPSILON.to_f64() > 1e-10
}

/// `q (x) dq` for a (nearly) unit `q` and a unit increment `dq`, with one rounding in the
/// directions that turn the attitude: written as `q + (q (x) (dq - 1) + nu q)`, where
/// `q (x) (dq - 1)` is small (relative rounding only) and `nu = (1 - |q (x) dq|^2) / 2` pulls
/// the length back to one to first order (its rounding only scales q, which turns nothing).
/// With the plain product and a renormalisation, every component is rounded two or three
/// times a step, which in f32 turns the attitude by about `2e-7` a step and limits the
/// conservation of `R(q) m` to about `2e-4` over `10^6` steps; this form halves that twice.
/// No square root.
pub(crate) fn compose_attitude<T: Real>(q: Quat<T>, dq: Quat<T>) -> Quat<T> {
    let applied = attitude_increment(q, dq);
    Quat {
        w: q.w + applied.w,
        x: q.x + applied.x,
        y: q.y + applied.y,
        z: q.z + applied.z,
    }
}

/// [`compose_attitude`] from `q + lost` (`lost` below an ulp of `q`: what earlier roundings
/// dropped), and what this rounding drops (Fast2Sum per component, as [`crate::forced`]'s
/// kicks): the forced steps carry the attitude's rounding from turn to turn, so in f32 it
/// does not random-walk by an ulp a step under a torque (where no spatial momentum is held).
/// `lost` is added to the increment, not to `q`, so its own effect on the turn is dropped:
/// `O(eps |dq - 1|)`. Without `renormalise`, as [`compose_unrenormalised`].
#[inline(always)]
pub(crate) fn compose_attitude_carried<T: Real>(
    q: Quat<T>,
    dq: Quat<T>,
    lost: Quat<T>,
    renormalise: bool,
) -> (Quat<T>, Quat<T>) {
    let a = if renormalise {
        attitude_increment(q, dq)
    } else {
        turn_increment(q, dq)
    };
    let a = Quat {
        w: a.w + lost.w,
        x: a.x + lost.x,
        y: a.y + lost.y,
        z: a.z + lost.z,
    };
    let next = Quat {
        w: q.w + a.w,
        x: q.x + a.x,
        y: q.y + a.y,
        z: q.z + a.z,
    };
    let dropped = Quat {
        w: a.w - (next.w - q.w),
        x: a.x - (next.x - q.x),
        y: a.y - (next.y - q.y),
        z: a.z - (next.z - q.z),
    };
    (next, dropped)
}

/// `q (x) dq - q` with the first-order pull back to unit length: `q (x) (dq - 1) + nu q`,
/// `nu = (1 - |q (x) dq|^2) / 2` ([`compose_attitude`]).
#[inline(always)]
fn attitude_increment<T: Real>(q: Quat<T>, dq: Quat<T>) -> Quat<T> {
    let inc = turn_increment(q, dq);
    let half = T::from_f64(0.5);
    // |q + inc|^2 = |q|^2 + 2 q.inc + |inc|^2
    let q_inc = q.w * inc.w + q.x * inc.x + q.y * inc.y + q.z * inc.z;
    let nu = (T::ONE - q.norm2()) * half - q_inc - inc.norm2() * half;
    Quat {
        w: inc.w + nu * q.w,
        x: inc.x + nu * q.x,
        y: inc.y + nu * q.y,
        z: inc.z + nu * q.z,
    }
}

/// `q (x) dq` as `q + q (x) (dq - 1)`: [`compose_attitude`] without its pull back to unit
/// length, for the steps of `Mv` between two full attitude steps (`HOLD_PERIOD` in
/// crate::mv). `|dq| = 1` to an ulp, so `|q|` moves by about an ulp a step, and the next full
/// step's first-order renormalisation takes it back (it converges quadratically from any
/// `| |q| - 1 |` below `1e-3`).
#[inline(always)]
pub(crate) fn compose_unrenormalised<T: Real>(q: Quat<T>, dq: Quat<T>) -> Quat<T> {
    let inc = turn_increment(q, dq);
    Quat {
        w: q.w + inc.w,
        x: q.x + inc.x,
        y: q.y + inc.y,
        z: q.z + inc.z,
    }
}

/// `q (x) (dq - 1)`: the small change a turn `dq` near the identity makes to `q`, with
/// relative rounding only.
#[inline(always)]
fn turn_increment<T: Real>(q: Quat<T>, dq: Quat<T>) -> Quat<T> {
    q.mul(Quat {
        w: dq.w - T::ONE,
        x: dq.x,
        y: dq.y,
        z: dq.z,
    })
}

/// Writes a momentum step's result if it is finite (`Overflow` otherwise, and `m` is left as
/// it was): the last line of a `step`.
pub(crate) fn write_momentum<T: Real>(m: &mut [T; 3], next: Vec3<T>) -> Result<(), StepError> {
    if !next.is_finite() {
        return Err(StepError::Overflow);
    }
    *m = next.to_array();
    Ok(())
}

/// Writes a step's result into the state if it is finite (`Overflow` otherwise, and the state
/// is left as it was): the last line of every `step_state`.
pub(crate) fn write_state<T: Real>(
    s: &mut State<T>,
    m: Vec3<T>,
    q: Quat<T>,
) -> Result<(), StepError> {
    if !(m.is_finite() && q.is_finite()) {
        return Err(StepError::Overflow);
    }
    s.m = m.to_array();
    s.q = q.to_array();
    Ok(())
}

/// [`write_state`] for a step whose momentum `m` is known finite (the step checked it): only
/// the attitude is checked.
#[inline(always)]
pub(crate) fn write_state_stepped<T: Real>(
    s: &mut State<T>,
    m: Vec3<T>,
    q: Quat<T>,
) -> Result<(), StepError> {
    if !q.is_finite() {
        return Err(StepError::Overflow);
    }
    s.m = m.to_array();
    s.q = q.to_array();
    Ok(())
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

/// `2^-40` and `2^40`: the range [`homogeneous_scale`] brings a momentum into.
const HOMOGENEOUS_LO: f64 = 9.094947017729282e-13;
const HOMOGENEOUS_HI: f64 = 1099511627776.0;

/// Powers of two `(up, down = 1 / up)` that bring `max |v|` into `[2^-40, 2^40]`, for the
/// integrators whose step is homogeneous in `(m, h)` (Euler's equations are quadratic in `m`:
/// `m -> m up`, `h -> h down` is the same motion, and scaling by a power of two rounds
/// nothing, so a step in range is the plain step bit for bit). `None` when `v` is in range
/// already (the common case: two comparisons) or zero. Below `2^-1040` (f64 subnormals) the
/// largest power of `2^40` that `T` holds, `2^1000`, leaves `v` short of the range but
/// normal, which is all the steps need. Without it `Rk4` and `Midpoint` in f32 left `m` as it was at `|m| = 1e-25`
/// (`m x I^-1 m` underflowed) whatever `h |Omega|` was (found in a first-use trial), and
/// `Midpoint` refused every f64 momentum below `2^-1022` (its on-the-sphere check divided by a
/// subnormal `max |m|`, found in review; a first fix scaled that check alone).
pub(crate) fn homogeneous_scale<T: Real>(v: Vec3<T>) -> Option<(T, T)> {
    power_of_two_scale(v.max_abs(), HOMOGENEOUS_LO, HOMOGENEOUS_HI)
}

/// Powers of two `(up, down = 1 / up)` that bring a positive `big` into `[lo, hi]`, stepping by
/// `hi` (`lo = 1 / hi`, both powers of two); `None` when `big` is in range already (two
/// comparisons), zero or not finite. Where `T` holds no such power (f64 subnormals below
/// `lo / 2^1000`), the largest one it holds: `big` then ends short of the range but normal.
/// Scaling by a power of two rounds nothing. ([`homogeneous_scale`] for a step's momentum;
/// crate::mv_pre's hold of the invariants, whose determinant is quartic in `m`, in a
/// narrower range.)
pub(crate) fn power_of_two_scale<T: Real>(big: T, lo: f64, hi: f64) -> Option<(T, T)> {
    let (lo, hi) = (c::<T>(lo), c::<T>(hi));
    if (big >= lo && big <= hi) || !(big > T::ZERO) || !big.is_finite() {
        return None;
    }
    let (mut up, mut down) = (T::ONE, T::ONE);
    while big * up < lo {
        let next = up * hi;
        if !next.is_finite() {
            break;
        }
        (up, down) = (next, down * lo);
    }
    while big * up > hi {
        (up, down) = (up * lo, down * hi);
    }
    Some((up, down))
}

/// `v` back in the caller's units after a step in [`homogeneous_scale`]'s.
#[inline(always)]
pub(crate) fn unscaled<T: Real>(v: Vec3<T>, scale: Option<(T, T)>) -> Vec3<T> {
    match scale {
        Some((_, down)) => v.scale(down),
        None => v,
    }
}

/// A momentum and a step in [`homogeneous_scale`]'s units, and the scale (`None`: as given).
pub(crate) type Scaled<T> = (Vec3<T>, T, Option<(T, T)>);

/// `(v, h)` in [`homogeneous_scale`]'s units, and the scale. `Overflow` where a finite `h`
/// leaves the range on scaling (a momentum beyond `2^40` with a step so large that `h |m|`
/// overflows: the step would blow up anyway; without it such a step was refused as
/// `NonFinite`, an error about the input, found by the loop fuzz).
#[inline(always)]
pub(crate) fn in_homogeneous_units<T: Real>(v: Vec3<T>, h: T) -> Result<Scaled<T>, StepError> {
    match homogeneous_scale(v) {
        Some((up, down)) => {
            let scaled = h * down;
            if h.is_finite() && !scaled.is_finite() {
                return Err(StepError::Overflow);
            }
            Ok((v.scale(up), scaled, Some((up, down))))
        }
        None => Ok((v, h, None)),
    }
}
