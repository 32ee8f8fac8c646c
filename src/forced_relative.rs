//! The gyrostat's relative splitting: the rotor step [`crate::Forced`] (and every stage of
//! [`crate::Composed`], chosen once a step) takes when the wheels turn the body faster than
//! its own motion does.
//!
//! # Derivation
//!
//! With `m` the total body momentum and `n = m - h_r` (constant `h_r`), the gyrostat is
//! `dn/dt = n x Omega + h_r x Omega`, `dq/dt = q Omega / 2`, `Omega = I^-1 n`. The
//! turn–drift–turn step splits `H = 1/2 m . I^-1 m - m . I^-1 h_r`: the drift follows the
//! free body at `I^-1 m` and the turns undo most of it at `I^-1 h_r`. When the wheels dominate
//! (`|I^-1 h_r|` comparable to or larger than `|Omega|`) both parts are fast and nearly cancel,
//! so the splitting's error is of the size of the fast parts, not of the motion, and in f32
//! each part's rounding (relative to itself) is too: a cubesat with 0.55 N m s of wheels and
//! 1.3e-3 N m s of its own momentum ended its attitude `2.3e-2` rad from the exact solution
//! after 10 s at 160 Hz (f64), and at 1 kHz in f32 it ended 200x the scene's sensitivity to
//! one ulp of `m0` after `10^6` steps, its energy 3e-2 off and drifting (0.2 after `10^7`,
//! a first-use trial).
//!
//! Splitting the vector field by its Poisson tensor instead (`-(n + h_r) x` = `-n x` plus the
//! constant `-h_r x`; McLachlan and Quispel, "Splitting methods", Acta Numerica 11 (2002) 341,
//! on splitting Poisson structures) gives two parts that both keep the energy
//! `E = 1/2 n . I^-1 n`:
//!
//! - the free body in `(n, q)`: `dn/dt = n x I^-1 n`, `dq/dt = q I^-1 n / 2`, the drift's own
//!   step applied to `n`;
//! - the gyroscopic part `dn/dt = h_r x I^-1 n` with `q` fixed, linear, `A = hat(h_r) I^-1`;
//!   `A^3 = -sigma A` with `sigma = h_r . adj(I^-1) h_r`. Its half step is the implicit
//!   midpoint rule, `n' = n + (h/4) A (n + n')`, which keeps every quadratic invariant of a
//!   linear flow (here `E` and `n . h_r`) and solves in closed form: with `a = h h_r / 4`,
//!   `u = a x I^-1 n`, `n' - n = 2 (u + a x I^-1 u) / (1 + sigma_a)`,
//!   `sigma_a = a . adj(I^-1) a` (multiply out `(1 - hat(a) I^-1)^-1` with `A^3 = -sigma A`).
//!   About 25 flops, no division per step.
//!
//! `half(h/2) drift(h) half(h/2)` is symmetric and of order 2; every increment is of the
//! size of the motion, so the rounding is too. It does not keep `|m|^2` and `R(q) m` exactly
//! (each part keeps only one of the pair `|n|^2`, `n . h_r`): on that cubesat at 1 kHz, errors
//! of 1.4e-11 and 1.7e-8 that do not grow over `10^6` steps, and the energy to 6.6e-11. The f64
//! step does not hold them as it does after the turns while the wheels are constant: the
//! holds move the state off the energy, which then drifted (5e-8 after `10^6` steps,
//! growing). After a change of the wheels, which the energy does not survive, it holds
//! them (crate::forced's `Forcing::hold_casimir`): with wheels commanded every tick nothing
//! else keeps them (`tests/gyrostat_relative.rs`). In f32 the roundings of
//! `n = m - h_r`, the half steps and `m = n + h_r` are carried (TwoSum) with the drift's, and
//! the start kick's enters `n` (an ulp of `m` is many ulps of a small `n`): 1.1x the
//! sensitivity after `10^6` steps, the energy within 2e-5 in both halves of the run
//! (tests/gyrostat_relative.rs). Carrying the drift's rounding through the half steps (the
//! linear map applied to it) changed nothing measurable and is not done.
//!
//! # Accuracy and when it is taken
//!
//! Against the turns, in f64 over 110 random bodies, wheels and momenta at `h |Omega| = 0.05`
//! (20 / `|Omega|` of time, an RK4 reference at 250x the steps; a probe, not a test), the
//! ratio of the attitude errors follows `r = |Omega| / |I^-1 m|`, the ratio of the two
//! splittings' free rates: the relative splitting 1.4-150x more accurate for `r < 0.9`, the
//! two within 12 % for `0.95 < r < 1.02`, and above mostly the turns, by up to 53x (a
//! momentum nearly cancelled by the wheels, where the turns are nearly exact; 4 of 38 draws
//! favoured the relative splitting, by up to 2.6x). Where `r <= 1/2` all 13 draws favoured
//! it in attitude by 10.6x or more (in momentum 0.64-19x). The step takes it where that holds
//! all along the torque-free orbit, which a test of the energy and the rotor alone decides
//! ([`relative_wanted`], with a margin): a choice from `r` at each step's start (a first
//! version) mixed the splittings on orbits that cross `r = 1/2`, and they drifted. The
//! gyroscopic half step's constants are formed by the step that takes it (three products
//! and a division).

use crate::forced::kick;
use crate::linalg::Vec3;
use crate::real::{c, Real};

/// The rotor's constants for [`relative_wanted`]: `|I^-1 h_r|^2` and `max_i 1 / I_i`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RotorRates<T> {
    w_r2: T,
    inv_i_max: T,
}

impl<T: Real> RotorRates<T> {
    /// No rotor (never relative).
    pub(crate) fn none() -> Self {
        Self {
            w_r2: T::ZERO,
            inv_i_max: T::ZERO,
        }
    }

    /// For the rotor's `w_r = I^-1 h_r` and the body's `I^-1`.
    pub(crate) fn new(w_r: Vec3<T>, inv_i: Vec3<T>) -> Self {
        Self {
            w_r2: w_r.norm2(),
            inv_i_max: inv_i.x.max(inv_i.y).max(inv_i.z),
        }
    }
}

/// Whether the step from `m` takes the relative splitting, given whether the last step did
/// (`was`): when the wheels turn the body at least `3.6` times (staying: `2.4` times) the
/// fastest rate its own energy allows, `|I^-1 h_r| >= 3.6 sqrt(2 E max_i 1/I_i)`,
/// `E = 1/2 (m - h_r) . I^-1 (m - h_r)` (`|Omega|^2 <= 2 E max_i 1/I_i`). Then
/// `|I^-1 m| >= |I^-1 h_r| - |Omega| >= 2.6 |Omega|` all along the torque-free orbit when it
/// enters (`r <= 0.39`; staying, `1.4 |Omega|`, `r <= 0.71`), where the relative splitting is
/// the more accurate one (module docs: every draw at `r <= 1/2`, 1.4-150x below 0.9), and,
/// the test depending only on the energy and the rotor, a torque-free trajectory with
/// constant wheels never changes splitting. Decided per step from `|Omega| / |I^-1 m|`
/// instead (a first version), trajectories whose ratio swung across the threshold mixed the
/// two splittings, each keeping other invariants, and drifted: the energy 7e-3 and `|m|^2`
/// 7e-4 after `10^6` steps of `I = (1, 2, 3)`, `h_r = (0, 0, 3)` at `h = 0.01`, where either
/// splitting alone stays bounded (found in review). The margin between 3.6 and 2.4 keeps
/// round-off and slow torques from flipping it back and forth. False for a non-finite `m`
/// (the turns' path refuses it), and where either side of the test leaves the range (`0 >= 0`
/// or `inf >= inf` chose the relative splitting whatever the physics: a body-dominated scene
/// scaled by `1e-24` or `1e22` in f32 took it, and at `|m| = 6e28`, `h = 8e-40` its step came
/// out non-finite, found in review). About 10 flops.
#[inline(always)]
pub(crate) fn relative_wanted<T: Real>(
    m: Vec3<T>,
    h_r: Vec3<T>,
    inv_i: Vec3<T>,
    rates: RotorRates<T>,
    was: bool,
) -> bool {
    let n = m.sub(h_r);
    let two_e = n.dot(n.mul_elem(inv_i));
    // 3.6^2 = 12.96 to enter, 2.4^2 = 5.76 to stay
    let k = if was { c::<T>(5.76) } else { c::<T>(12.96) };
    let bound = k * two_e * rates.inv_i_max;
    rates.w_r2 > T::ZERO && rates.w_r2 <= T::MAX && bound <= T::MAX && rates.w_r2 >= bound
}

/// The gyroscopic half step's constants for one rotor and one step size.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Relative<T> {
    /// `h h_r / 4`.
    a: Vec3<T>,
    /// `I^-1`.
    inv_i: Vec3<T>,
    /// `2 / (1 + a . adj(I^-1) a)`.
    scale: T,
}

impl<T: Real> Relative<T> {
    /// The constants for rotor `h_r` at step `h` (`inv_i = I^-1`), formed by the step that
    /// takes them (a flight loop sets `h` and the wheels every tick, and most steps of most
    /// loops take the turns: formed at every change, they cost the M4F's jittered forced
    /// step a division and 20 instructions whether it used them or not).
    #[inline(always)]
    pub(crate) fn new(h_r: Vec3<T>, inv_i: Vec3<T>, h: T) -> Self {
        let a = h_r.scale(h * c::<T>(0.25));
        let sigma = a.x * a.x * inv_i.y * inv_i.z
            + a.y * a.y * inv_i.x * inv_i.z
            + a.z * a.z * inv_i.x * inv_i.y;
        Self {
            a,
            inv_i,
            scale: c::<T>(2.0) / (T::ONE + sigma),
        }
    }

    /// The gyroscopic half step's increment `n' - n` (module docs), rounded relative to
    /// itself.
    #[inline(always)]
    pub(crate) fn increment(&self, n: Vec3<T>) -> Vec3<T> {
        let u = self.a.cross(n.mul_elem(self.inv_i));
        let v = self.a.cross(u.mul_elem(self.inv_i));
        u.add(v).scale(self.scale)
    }
}

/// The relative splitting as one step takes it: the constants and the rotor `h_r`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RelativeStep<T> {
    consts: Relative<T>,
    h_r: Vec3<T>,
}

impl<T: Real> RelativeStep<T> {
    /// The step of length `h` for rotor `h_r` (`inv_i = I^-1`).
    #[inline(always)]
    pub(crate) fn new(h_r: Vec3<T>, inv_i: Vec3<T>, h: T) -> Self {
        Self {
            consts: Relative::new(h_r, inv_i, h),
            h_r,
        }
    }

    /// From the kicked `m` (with `lost0`, what the kick's rounding dropped) to the drift's
    /// input: `n = m - h_r`, then the gyroscopic half step. Returns `n`, the rounding it
    /// dropped and the part of `lost0` still to be applied by the end kick. With `carry` (f32)
    /// every rounding is kept (TwoSum, Fast2Sum) and `lost0` joins `n` here: an ulp of `m` is
    /// many ulps of a small `n`, and left to the end kick it would miss the drift and the half
    /// steps, a bias of `2 lost0 . (n' - n)` in `|m|^2` a step. Without, `n` is formed plainly
    /// and `lost0` waits for the end kick as with the turns.
    #[inline(always)]
    pub(crate) fn enter(
        &self,
        m: Vec3<T>,
        lost0: Vec3<T>,
        carry: bool,
    ) -> (Vec3<T>, Vec3<T>, Vec3<T>) {
        let zero = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
        let minus = Vec3::new(-self.h_r.x, -self.h_r.y, -self.h_r.z);
        if carry {
            let (d, e1) = two_sum(m, minus);
            let (n, e2) = two_sum(d, lost0);
            let (n, e3) = kick(n, self.consts.increment(n));
            (n, e1.add(e2).add(e3), zero)
        } else {
            let n = m.add(minus);
            (n.add(self.consts.increment(n)), zero, lost0)
        }
    }

    /// From the drift's output `n` back to `m`: the second gyroscopic half step, then
    /// `m = n + h_r`, their rounding added to `pending` with `carry`.
    #[inline(always)]
    pub(crate) fn leave(&self, n: Vec3<T>, pending: Vec3<T>, carry: bool) -> (Vec3<T>, Vec3<T>) {
        if carry {
            let (n, e4) = kick(n, self.consts.increment(n));
            let (m, e5) = two_sum(n, self.h_r);
            (m, pending.add(e4).add(e5))
        } else {
            let n = n.add(self.consts.increment(n));
            (n.add(self.h_r), pending)
        }
    }
}

/// `(a + b, what its rounding dropped)`: Knuth's TwoSum, exact for any order of magnitude
/// (`m - h_r` may be either way round).
#[inline(always)]
pub(crate) fn two_sum<T: Real>(a: Vec3<T>, b: Vec3<T>) -> (Vec3<T>, Vec3<T>) {
    let s = a.add(b);
    let bb = s.sub(a);
    let aa = s.sub(bb);
    (s, a.sub(aa).add(b.sub(bb)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The half step against the midpoint rule it solves, `n' = n + (h/4) A (n + n')`, and its
    /// invariants `E = 1/2 n . I^-1 n` and `n . h_r` (exact for the midpoint rule).
    #[test]
    fn half_step_solves_the_midpoint_rule_and_keeps_its_invariants() {
        let inv_i = Vec3::new(1.0 / 0.05, 1.0 / 0.06, 1.0 / 0.08);
        let h_r = Vec3::new(0.1, 0.5, -0.2);
        for h in [1e-3, 1e-2, 0.3] {
            let r = Relative::new(h_r, inv_i, h);
            let n = Vec3::new(5e-4, -1.2e-3, 1.2e-3);
            let want = r.increment(n);
            let next = n.add(want);
            let mid = n.add(want.scale(0.5));
            // (h/4) A (n + n') = (h/2) h_r x I^-1 mid
            let got = h_r.cross(mid.mul_elem(inv_i)).scale(h / 2.0);
            assert!(
                want.sub(got).norm2().sqrt() <= 1e-14 * want.norm2().sqrt(),
                "h {h}: {want:?} {got:?}"
            );
            let e = |v: Vec3<f64>| 0.5 * v.dot(v.mul_elem(inv_i));
            assert!((e(next) / e(n) - 1.0).abs() < 1e-14, "h {h}");
            assert!((next.dot(h_r) - n.dot(h_r)).abs() < 1e-15, "h {h}");
        }
    }

    #[test]
    fn two_sum_is_exact() {
        let a = Vec3::new(0.5f32, 1e-9, -3.0);
        let b = Vec3::new(-0.499_999_97f32, 0.7, 3.0e-8);
        let (s, e) = two_sum(a, b);
        for (x, y, s, e) in [
            (a.x, b.x, s.x, e.x),
            (a.y, b.y, s.y, e.y),
            (a.z, b.z, s.z, e.z),
        ] {
            assert_eq!(f64::from(x) + f64::from(y), f64::from(s) + f64::from(e));
        }
    }
}
