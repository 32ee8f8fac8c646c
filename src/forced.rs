//! Forced motion around the free DMV step: torques, potentials and rotors, still explicit.
//!
//! # The splitting
//!
//! The forced gyrostat is
//!
//! `m' = m x Omega + tau(t, q)`, `Omega = I^-1 (m - h_r)`, `q' = 1/2 q (x) (0, Omega)`,
//!
//! with `m` the total body angular momentum, `h_r` the rotor momentum (body frame, reaction
//! wheels; constant over a step) and `tau` a body torque. Its Hamiltonian (for a potential
//! torque) splits as `1/2 m . I^-1 m  -  w . m  +  V(t, q)` with `w = I^-1 h_r`: the free rigid
//! body (the DMV drift), a linear term whose flow turns `m` and the attitude about the fixed body
//! axis `w` (`m(s) = exp(s hat w) m`, `R(s) = R exp(-s hat w)`), and the potential, whose flow
//! at fixed `q` is the kick `m <- m + s tau`. One step is the palindrome
//!
//! `kick(h/2, tau(t_n, q_n))  turn(h/2)  drift(h)  turn(h/2)  kick(h/2, tau(t_n+1, q_n+1))`,
//!
//! symmetric, hence of order 2, and symplectic for a potential torque with the DMV drift
//! (a Strang splitting: Hairer–Vilmart's DMV code treats external potentials the same way;
//! with zero rotor it is the Lie group variational integrator of Lee, Leok and McClamroch,
//! Comput. Methods Appl. Mech. Engrg. 196 (2007) 2907, solved explicitly: the LGVI's implicit
//! equation `h (Pi_k + h/2 M_k)^ = F J_d - J_d F^T` is the DMV equation for the kicked
//! momentum). The end kick's torque is reused by the next step's start kick when `t` and `q`
//! are unchanged (one evaluation a step).
//!
//! The turn is taken in rational form: the half-step rotation by `phi = -(h/2) w` becomes the
//! unit quaternion `((1 - |u|^2), 2u) / (1 + |u|^2)`, `u = phi / 4`, which turns by
//! `4 atan(|phi| / 4) = |phi| (1 - |phi|^2 / 48 + ...)`: no `sin`/`cos` (wheel momenta change
//! every tick), odd in `h` (so the step stays symmetric), and an error of the same order as the
//! drift's. The turn conserves `|m|^2` and `R(q) m` exactly, the kick conserves the spatial
//! momentum about any axis the torque has no component on (the vertical, for gravity).
//!
//! When the wheels turn the body well faster than its own energy allows (`|I^-1 h_r| >= 3.6
//! sqrt(2 E max_i 1/I_i)`, `E = 1/2 (m - h_r) . I^-1 (m - h_r)`; staying while above 2.4
//! times) [`Forced`] splits the rotor's part by its Poisson tensor instead:
//! `turn(h/2) drift(h) turn(h/2)` becomes `half(h/2) drift(h) half(h/2)` with the drift
//! stepping the relative momentum `n = m - h_r` and `half` the gyroscopic term
//! `n' = h_r x I^-1 n` (crate::forced_relative): there the turns' two fast parts nearly
//! cancel and their splitting error and rounding are of their size, not of the motion's
//! (a cubesat with a momentum-bias wheel: 4500x the error in f64, 200x the sensitivity in
//! f32). [`Composed`] makes the same choice once a step, for all its stages.
//!
//! # What is conserved
//!
//! Gyrostat without torque: `|m|^2` and `R(q) m` to round-off, the energy
//! `1/2 (m - h_r) . I^-1 (m - h_r)` bounded (error `O(h^2)`, no drift); with the relative
//! splitting the energy to round-off and `|m|^2`, `R(q) m` bounded (`O(h^2)`). Heavy top:
//! `e_z . R(q) m` to round-off, the total energy bounded; with a wheel fast enough for the
//! relative splitting (a momentum-bias wheel: its gyroscopic half step turns `m` at a fixed
//! attitude) `e_z . R(q) m` bounded to the splitting's `O(h^2)` instead (`I = (1, 1.5, 2)`,
//! `h_r = 8` along the axis, `|m| = 9.2`: 1.0e-3 relative at `h = 0.04`, 2.5e-4 at `0.02`,
//! not growing), and the total energy drifts: no Hamiltonian flow turns `m` at a fixed
//! attitude, so under a potential that step is not symplectic, and the energy error grows
//! linearly at a rate `O(h^2)` (the same top: `2.6e-7` relative per unit time at `h = 0.04`,
//! `6.4e-8` at `0.02`, 1.2e-3 after `10^6` steps; a gravity-gradient satellite with a bias
//! wheel of 9 N m s at `N = 1`: its Jacobi integral 0.2 off by `t = 4 x 10^4` at `h = 0.02`;
//! on a cubesat in low orbit, `N = 1.1e-3`, no drift showed over `2 x 10^4` s). Without a
//! torque every part keeps the energy exactly. Where it matters, take a smaller `h` or
//! [`Composed`] (order 4: 5e-5 after `4 x 10^5` steps at `h = 0.05` on that top); found in
//! review, tests/forced.rs.
//!
//! # Higher order
//!
//! [`Composed`] composes the step symmetrically (Yoshida's construction; coefficients from
//! Hairer, Lubich & Wanner, Geometric Numerical Integration, 2nd ed., §V.3.2): order 4 with
//! McLachlan's five stages (SIAM J. Sci. Comput. 16 (1995) 151, the `p4 s5` method with the
//! smallest error constant among five-stage methods) and order 6 with Kahan and Li's nine stages
//! (Math. Comp. 66 (1997) 1089, `s9odr6`).

use crate::body::Body;
use crate::error::StepError;
use crate::forced_relative::{relative_wanted, RelativeStep, RotorRates};
use crate::integrator::{
    carries_rounding, checked_attitude, checked_momentum, checked_state, compose_attitude,
    compose_attitude_carried, homogeneous_scale, turn_in_space, Integrator, State,
};
use crate::linalg::{Quat, Vec3};
use crate::real::{c, sq, Real};
use crate::torque::Torque;

/// Time kept with a compensated sum, so that `t` stays exact to an ulp after `10^9` steps of
/// a jittering `h` (a plain `t += h` in f32 loses a step in `10^7` at 200 Hz).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Clock<T> {
    pub(crate) t: T,
    carry: T,
}

impl<T: Real> Clock<T> {
    /// `(t + h, carry)` by Kahan's summation.
    #[inline]
    pub(crate) fn after(&self, h: T) -> Self {
        let y = h - self.carry;
        let t = self.t + y;
        Self {
            t,
            carry: (t - self.t) - y,
        }
    }
}

/// The torque at the end of the last step, reused at the start of the next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LastKick<T> {
    pub(crate) t: T,
    pub(crate) q: [T; 4],
    pub(crate) tau: Vec3<T>,
}

/// A gyrostat's step holds its spatial momentum every this many steps
/// ([`Forcing::hold_spatial`]; a power of two).
const SPATIAL_HOLD_PERIOD: u8 = 8;
const _: () = assert!(SPATIAL_HOLD_PERIOD.is_power_of_two());

/// The rotor's half-step turn for step `h`: the Cayley quaternion `((1 - |u|^2), 2 u) /
/// (1 + |u|^2)`, `u = -h I^-1 h_r / 8`, the rotation by `4 atan(|u|)` (`h |I^-1 h_r| / 2` to
/// third order) about `-I^-1 h_r`; `Ok(None)` without a rotor. `StepTooLarge` past half a
/// revolution (`|u| > 1`, `h |I^-1 h_r| > 8`), where the Cayley form wraps around and, further
/// out, `|u|^2` overflows; `NonFinite` for a non-finite `h` with a rotor.
pub(crate) fn half_turn<T: Real>(w: Vec3<T>, h: T) -> Result<Option<Quat<T>>, StepError> {
    if w.x == T::ZERO && w.y == T::ZERO && w.z == T::ZERO {
        return Ok(None);
    }
    let u = w.scale(-h * c::<T>(0.125));
    let n = u.norm2();
    if !(n <= T::ONE) {
        return Err(if h.is_finite() {
            StepError::StepTooLarge
        } else {
            StepError::NonFinite
        });
    }
    let inv = T::ONE / (T::ONE + n);
    let two_inv = inv + inv;
    Ok(Some(Quat {
        w: (T::ONE - n) * inv,
        x: u.x * two_inv,
        y: u.y * two_inv,
        z: u.z * two_inv,
    }))
}

/// `R(p)^T m` for a unit `p = (w, v)`, written as `m + (w t + u x t)`, `u = -v`,
/// `t = 2 u x m` (the rotation formula with the identity split off), and the part of that
/// increment the rounded sum dropped added to `lost` ([`kick`]'s Fast2Sum).
///
/// Why: a rotor's two turns a step each round every component of `m` by up to half an ulp,
/// with nothing conserved to pull it back under a torque, and in f32 that random walk of
/// `m` moved a gravity-gradient orbit's Jacobi integral by `1.2e-3` of the kinetic energy in
/// `10^6` steps at 200 Hz; the increment `O(h |I^-1 h_r|)` is rounded only relative to
/// itself.
#[inline(always)]
pub(crate) fn unrotate<T: Real>(p: Quat<T>, m: Vec3<T>, lost: Vec3<T>) -> (Vec3<T>, Vec3<T>) {
    let v = p.vector();
    let u = Vec3::new(-v.x, -v.y, -v.z);
    let t = u.cross(m).scale(T::ONE + T::ONE);
    let dx = t.scale(p.w).add(u.cross(t));
    let (next, dropped) = kick(m, dx);
    // (below TURN_FIX_W the bias is under 1e-13 of |m| a step and the fix is not spent)
    let lost = lost.add(dropped);
    if p.w < c::<T>(TURN_FIX_W) {
        (next, lost.add(turn_norm_fix(m, dx, next)))
    } else {
        (next, lost)
    }
}

/// The turns by `p` with `p.w = cos(theta / 2)` below this (`theta^2 > 1e-6`: a half step's
/// turn `theta = h |I^-1 h_r| / 2` over 1e-3 rad) keep `|m|` through the carry
/// ([`turn_norm_fix`]).
const TURN_FIX_W: f64 = 1.0 - 1.25e-7;

/// What moves a turned momentum `next = m + dx` back onto `|m|`, for the carry: a rotation
/// keeps `|m|`, so `|m + dx|^2 - |m|^2 = sum dx_i (2 m_i + dx_i)` is what the rounding of `dx`
/// added, computed with rounding relative to `dx` (exact algebra, as crate::mv's
/// `fix_from_increment`), and taken back along `next`.
///
/// Why: with a constant rotor and step every turn is by the same rounded quaternion, and its
/// increment's rounding changes `|m|` by a bias with one sign along a trajectory, about
/// `eps` times `(h |I^-1 h_r|)^2` a step: an f32 gyrostat with a 5 N m s wheel at
/// `h |Omega| = 0.05` drifted `|m|` linearly, 1.2e-5 in `2.56 x 10^5` steps, and its attitude
/// ended 144x the scene's sensitivity to one ulp from f64 (found in review).
#[inline(always)]
fn turn_norm_fix<T: Real>(m: Vec3<T>, dx: Vec3<T>, next: Vec3<T>) -> Vec3<T> {
    let zero = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
    // in range by powers of two (exact; the ratio below is scale-free, and in range, the
    // common case, nothing is scaled): unscaled, dx (2 m + dx) overflowed f32 past |m| about
    // 1.5e20 at a 0.025 rad turn, and the infinite fix made the next step drop the whole
    // carry, every step (found in review). Scaled by 1 / max |m_i| instead, the scaling's
    // own rounding biased the fix (|m| 3x further off on the test). (Moved out of line, cold
    // or not, this cost the M4F's forced steps 1-29 instructions more, though it never runs
    // there: register allocation.)
    let (u, d, n) = match homogeneous_scale(m) {
        Some((up, _)) => (m.scale(up), dx.scale(up), next.scale(up)),
        None => (m, dx, next),
    };
    let w = d.mul_elem(u.add(u).add(d));
    let defect = w.x + w.y + w.z;
    let n2 = n.norm2();
    let fix = next.scale(-defect * c::<T>(0.5) / n2);
    if n2 > T::ZERO && fix.is_finite() {
        fix
    } else {
        zero
    }
}

/// A momentum and an attitude (or what their rounding dropped).
type Pair<T> = (Vec3<T>, Quat<T>);

/// A rotor's turn `p` of the momentum and the attitude: with `carry`, what their rounding
/// drops is added to `pending` and handed back in `lost_q` ([`unrotate`],
/// crate::integrator's `compose_attitude_carried`); without, the plain turn.
#[inline(always)]
pub(crate) fn turn_state<T: Real>(
    p: Quat<T>,
    (m, q): Pair<T>,
    (pending, lost_q): Pair<T>,
    carry: bool,
) -> (Pair<T>, Pair<T>) {
    let (m, pending) = turn_momentum(p, m, pending, carry);
    let (q, lost_q) = if carry {
        compose_attitude_carried(q, p, lost_q, true)
    } else {
        (compose_attitude(q, p), lost_q)
    };
    ((m, q), (pending, lost_q))
}

/// [`turn_state`] for the momentum alone.
#[inline(always)]
pub(crate) fn turn_momentum<T: Real>(
    p: Quat<T>,
    m: Vec3<T>,
    pending: Vec3<T>,
    carry: bool,
) -> (Vec3<T>, Vec3<T>) {
    if carry {
        unrotate(p, m, pending)
    } else {
        (p.inverse_rotate(m), pending)
    }
}

/// `m + d`, and the part of `d` the rounded sum lost (Fast2Sum per component: exact when
/// `|m_i| >= |d_i|`, and otherwise below an ulp of `d_i`, which does not matter).
///
/// Why: a kick `tau h / 2` is often an ulp of `m` or less in f32 (a gravity-gradient torque
/// of `2e-4 N m` at 200 Hz on a momentum of 10 N m s is about half an ulp; `2e-5 N m` a
/// twentieth), so `m + d` rounds it to the nearest whole ulp or away, every step the same way: measured on a sphere under a
/// constant body torque (where `m(t) = m0 + tau t` exactly), f32 applied the torque with a
/// 22 % error, 47 % after `10^6` steps. The lost part is added to the next kick, so over any
/// number of steps the applied torque is exact to an ulp of `m` (tests/forced.rs).
#[inline(always)]
pub(crate) fn kick<T: Real>(m: Vec3<T>, d: Vec3<T>) -> (Vec3<T>, Vec3<T>) {
    let sum = m.add(d);
    (sum, d.sub(sum.sub(m)))
}

/// A carried residue `v` of the momentum (what a kick's or a turn's rounding dropped before
/// the drift, applied to `m` after it) carried across the drift from `m` over `h`: the free
/// body's flow linearised at its input, `v' = v + h (v x Omega + m x I^-1 v)`,
/// `Omega = I^-1 m` (first order; `v` is below an ulp of `m`, so the `O((h |Omega|)^2 |v|)`
/// left is far below one). About 30 flops, in f32's carried steps only.
///
/// Why: a residue computed before the drift and added after it is added in the wrong frame,
/// off by the drift's turn `h |Omega|`, and where it is the same every step (a constant
/// rotor's turn, a sub-ulp turn of its momentum, dropped whole into the carry) so is the
/// error: an f32 gyrostat with `1e-3 N m s` of wheels on the spacecraft at 200 Hz
/// (`h |Omega| = 6.5e-4`) drifted `|m|^2` by `1.3e-12` a step, 1.3e-4 after `10^8` steps,
/// its energy alike (found in review; now bounded, tests/forced.rs).
#[inline(always)]
pub(crate) fn across_drift<T: Real>(v: Vec3<T>, m: Vec3<T>, inv_i: Vec3<T>, h: T) -> Vec3<T> {
    // `h m` first: it has the motion's scale (`h |Omega|` times the moments), so the products
    // with `v`, below an ulp of `m`, stay normal at every scale (`m` at 2^-60 in f32 took them
    // subnormal: 1.2e-6 rad off the unit-scale run, found by the scale test)
    let hm = m.scale(h);
    v.add(v.cross(hm.mul_elem(inv_i)).add(hm.cross(v.mul_elem(inv_i))))
}

/// The carried momentum rounding `lost` for a step from `m`: kept while it is below `64 eps |m|`
/// (after a step of the integrator it is a sum of residues each below an ulp of the sum it was
/// dropped from: `Composed` with a rotor gathers up to 15 a step, and a first limit of
/// `4 eps |m|` dropped them thousands of times in `2 x 10^5` steps, a biased loss that moved
/// f32 `|m|^2` by 9.3e-4, found in review), dropped where the caller changed `m` so much
/// that it is not. A residue kept after the caller shrank `m` by `1e8` was added to the new
/// momentum whole (f32 `1e-8` became `4e-8`, and a momentum set to zero would have moved),
/// and with a rotor the Casimir hold amplified it to `1e11` in three steps (found in review).
/// One test on the squared norms (the M4F's forced step: 20 instructions; per component it
/// cost 27).
#[inline(always)]
pub(crate) fn carried_for<T: Real>(m: Vec3<T>, lost: Vec3<T>) -> Vec3<T> {
    if lost.norm2() <= c::<T>(4096.0) * sq(T::EPSILON) * m.norm2() {
        lost
    } else {
        Vec3::new(T::ZERO, T::ZERO, T::ZERO)
    }
}

/// The spatial momentum `pi0 = R(q) m` a gyrostat's step holds, kept as `pi0 / |pi0|^2`, with
/// the state returned last (the reference is the caller's state whenever the input is not it)
/// and the steps since the last hold.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SpatialHold<T> {
    m: Vec3<T>,
    q: Quat<T>,
    pi: Vec3<T>,
    phase: u8,
}

/// What the forced step needs besides the drift.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Forcing<T, F> {
    pub(crate) torque: F,
    /// Rotor momentum `h_r` (body frame).
    pub(crate) rotor: Vec3<T>,
    /// `I^-1 h_r`.
    pub(crate) rotor_w: Vec3<T>,
    pub(crate) clock: Clock<T>,
    pub(crate) last: Option<LastKick<T>>,
    /// Without torque, `|m|^2` of the trajectory: `(last momentum returned, |m|^2, 1/(2|m|^2))`.
    casimir: Option<(Vec3<T>, T, T)>,
    /// Without torque, with a rotor: the trajectory's spatial momentum ([`Forcing::hold_spatial`]).
    spatial: Option<SpatialHold<T>>,
    /// What the rounding of the state dropped, below an ulp of it: the momentum's part (the
    /// kicks', the rotor turns' and the drift's) is added to the next kick, the attitude's
    /// (the turns' and the drift's) to the next turn of the attitude ([`Forced`]'s error
    /// model). Without it, in f32 the state random-walks by an ulp a step under a torque: a
    /// gravity-gradient orbit's Jacobi integral moved by `3e-4` of the kinetic energy in
    /// `10^7` steps at 200 Hz (`1.4e-2` with wheels), `3.2e-7` (`1.2e-6`) with it
    /// ([`kick`]). Kept when the caller changes `m` or `q` (a filter's correction): it is
    /// torque impulse that acted and round-off of the motion, below an ulp of the state (a
    /// caller's sign flip of `q` applies the attitude's part once with the wrong sign, about
    /// two ulps), unless it is not below a few ulps of the caller's new `m` ([`carried_for`]);
    /// dropped by `reset`.
    pub(crate) lost: State<T>,
    /// A torque has acted or the rotor has turned the state since the integrator was made or
    /// reset: from then on every step carries the state's rounding in f32, torque or not
    /// ([`Forcing::carries`]).
    acted: bool,
    /// The rotor was changed since the last step: the relative splitting's steps then hold
    /// `|m|^2` and `R(q) m` in f64 like the turns' ([`Forcing::bridge_holds`]).
    pub(crate) rotor_moved: bool,
}

impl<T: Real, F: Torque<T>> Forcing<T, F> {
    /// Whether a step carries the state's rounding ([`Forced`]'s error model): at a precision
    /// that needs it ([`carries_rounding`]) and when a torque acts or the rotor turns the
    /// state, or did at any step before (`acted`); a free body that never felt either is left
    /// to the drift's own free-running step and holds.
    ///
    /// Why the steps after a torque carry too (found by a flight-loop trial): a free stretch
    /// left to the drift takes its invariants from the rounded state, about an ulp off the
    /// trajectory the carried steps followed, and every torque pulse then starts a stretch
    /// with a new such error. In f32 on the spacecraft at `10^-3` to `10^-2` rad/s and 200 Hz,
    /// with a pulse of 4 ticks every 200, the attitude random-walked to 25-55x the scene's own
    /// sensitivity to one ulp of `m` after `10^6` steps (104x after `10^7`), where carrying
    /// every step stays at 0.7-1.8x. Carrying costs the free stretch the drift's solve (M4F
    /// 626 instead of 370 instructions). Until the carried drift step kept its input's
    /// invariants (crate::mv's `fix_from_increment`, at every step on an elongated body) only
    /// bodies with a mass-matrix spread up to 16 carried after a torque: an elongated body's
    /// carried free steps drifted (`(8, 120, 122)`: 4.9e-5 rad from f64 in `10^6` steps, the
    /// free `Mv` 2.1e-6), and left to the holds it random-walked with pulses as above (22-58x
    /// the sensitivity on `(8, 120, 122)` and `(2, 100, 101)`); now every body carries, at
    /// 0.35-1.5x (tests/forced.rs `thruster_pulses_in_f32_stay_within_the_scenes_sensitivity`).
    #[inline(always)]
    pub(crate) fn carries(&self, rotor_turns: bool) -> bool {
        carries_rounding::<T>() && (rotor_turns || !self.torque.is_zero() || self.acted)
    }

    /// Notes a successful step that carried (`carry`): every later step carries too
    /// ([`Forcing::carries`]).
    #[inline(always)]
    pub(crate) fn mark_acted(&mut self, carry: bool) {
        if carry {
            self.acted = true;
        }
    }

    /// Without torque, scales `out` back to the Casimir of the trajectory `m_in` is on, to
    /// first order and with no division: the rotor's turns round `m` by an ulp each, and over
    /// `10^5` steps that random walk reached `7.5e-14` (the free `Mv` holds `|m|^2` the same
    /// way). The trajectory's value is taken again whenever `m_in` is not the momentum
    /// returned last (the caller changed it). With a torque `|m|^2` is not conserved and
    /// nothing is done. Called only where the step does not carry its rounding (f64).
    ///
    /// `relative`: after a relative step with the rotor changed
    /// (crate::forced_relative), whose `|m|^2` error is the splitting's, `O(h^3)` a step and
    /// far above round-off (up to 1e-4 on a cubesat whose wheels turn it at 9 rad/s at
    /// `h = 0.01`): the scale is taken to second order (`1 - d/2 + 3 d^2 / 8`) and corrections
    /// up to 1e-2 are applied (with changing wheels nothing else keeps `|m|^2`: left alone it
    /// ratcheted to 6.8e-3 in `10^6` steps there, found in review).
    #[inline]
    pub(crate) fn hold_casimir(&mut self, m_in: Vec3<T>, out: Vec3<T>, relative: bool) -> Vec3<T> {
        if !self.torque.is_zero() {
            return out;
        }
        let (c0, half_inv) = match self.casimir {
            Some((last, c0, hi)) if last == m_in => (c0, hi),
            _ => {
                let c0 = m_in.norm2();
                let hi = if c0 > T::ZERO && c0.is_finite() {
                    c::<T>(0.5) / c0
                } else {
                    T::ZERO
                };
                (c0, hi)
            }
        };
        let corr = (c0 - out.norm2()) * half_inv;
        // a correction far above round-off is not one (a momentum the caller changed by
        // orders of magnitude, found in review): the step's own result stands
        let (limit, second) = if relative {
            (c::<T>(1e-2), c::<T>(1.5) * corr * corr)
        } else {
            (c::<T>(1e-6), T::ZERO)
        };
        let held = if corr.abs() <= limit {
            out.add(out.scale(corr + second))
        } else {
            out
        };
        let held = if held.is_finite() { held } else { out };
        self.casimir = Some((held, c0, half_inv));
        held
    }

    /// Without torque, turns the attitude `q_out` back onto the trajectory's spatial momentum
    /// every [`SPATIAL_HOLD_PERIOD`]-th step: by `theta = pi x pi0 / |pi0|^2`, `pi = R(q_out)
    /// m_out`, to first order (`q + (0, theta / 2) (x) q`, exact to `O(eps^2)`), as the free
    /// `Mv` does (its own hold never runs here: the rotor's turns change the drift's input
    /// every step). Why: the turns and the drift's solve from a turned state round the
    /// attitude by a few ulps a step with nothing pulling it back, and in f32 `R(q) m`
    /// random-walked to `1.7e-3` after `10^6` steps and `2e-2` after `10^8` with a wheel of
    /// `0.01 N m s` (found in review; `3e-7` without a rotor). A gyrostat conserves `R(q) m`
    /// exactly (the wheels' momentum is inside `m`), so this removes round-off only. The
    /// reference is taken again, from this step's result, whenever `(m_in, q_in)` is not the
    /// state returned last (the caller changed it); with a torque nothing is done and the
    /// reference is dropped. Called only where the step does not carry its rounding (f64).
    /// `every`: at this step whatever the period, and twice (after a relative step with the
    /// rotor changed, whose `R(q) m` error is the splitting's, not round-off, as in
    /// [`Forcing::hold_casimir`]).
    #[inline]
    pub(crate) fn hold_spatial(
        &mut self,
        m_in: Vec3<T>,
        q_in: Quat<T>,
        m_out: Vec3<T>,
        q_out: Quat<T>,
        every: bool,
    ) -> Quat<T> {
        if !self.torque.is_zero() {
            self.spatial = None;
            return q_out;
        }
        let sp = match self.spatial.as_mut() {
            Some(sp) if sp.m == m_in && sp.q == q_in => sp,
            _ => {
                // from the step's result, not the caller's state: the drift renormalised the
                // attitude (a caller's q unit only to f32 precision moved the f64 reference,
                // and every later hold, by 7.3e-9: found in review)
                let pi = q_out.rotate(m_out);
                let n2 = pi.norm2();
                let pi = if n2 > T::ZERO && n2.is_finite() {
                    pi.scale(T::ONE / n2)
                } else {
                    Vec3::new(T::ZERO, T::ZERO, T::ZERO)
                };
                self.spatial = Some(SpatialHold {
                    m: m_out,
                    q: q_out,
                    pi,
                    phase: 1,
                });
                return q_out;
            }
        };
        sp.m = m_out;
        sp.phase = (sp.phase + 1) & (SPATIAL_HOLD_PERIOD - 1);
        if sp.phase != 0 && !every {
            sp.q = q_out;
            return q_out;
        }
        let held = turn_in_space(q_out, q_out.rotate(m_out).cross(sp.pi).scale(c::<T>(0.5)));
        // a relative step's `R(q) m` is off by the splitting's error, not round-off: once more
        // takes the first-order turn's `O(theta^2)` rest (2.2e-6 on the review's cubesat with
        // commanded wheels, 1e-12 with it)
        let held = if every {
            turn_in_space(held, held.rotate(m_out).cross(sp.pi).scale(c::<T>(0.5)))
        } else {
            held
        };
        sp.q = held;
        held
    }

    /// After a relative step that is not held (crate::forced_relative: with constant wheels it
    /// keeps the energy, and holding `|m|^2` and `R(q) m` drifted the energy): the holds'
    /// references go on with the trajectory (when `(m_in, q_in)` is the state returned last)
    /// instead of being re-taken from this step's result by the next step that holds, which
    /// would accept the relative stretch's `O(h^2)` error of `|m|^2` and `R(q) m` for good (a
    /// trajectory that changed splitting back and forth ratcheted `|m|^2` by 1.8e-2 in
    /// `10^6` steps, found in review). `q_in`/`q_out` `None` for a momentum-only step.
    pub(crate) fn bridge_holds(
        &mut self,
        m_in: Vec3<T>,
        q_in: Option<Quat<T>>,
        m_out: Vec3<T>,
        q_out: Option<Quat<T>>,
    ) {
        self.casimir = match self.casimir {
            Some((last, c0, hi)) if last == m_in => Some((m_out, c0, hi)),
            _ => None,
        };
        if let (Some(qi), Some(qo)) = (q_in, q_out) {
            self.spatial = match self.spatial {
                Some(sp) if sp.m == m_in && sp.q == qi => Some(SpatialHold {
                    m: m_out,
                    q: qo,
                    ..sp
                }),
                _ => None,
            };
        }
    }

    /// Writes a successful step's state and keeps what the next step starts from: the clock,
    /// the kicks' lost rounding and the end torque (reused while `t` and `q` are unchanged).
    #[inline]
    pub(crate) fn commit(
        &mut self,
        s: &mut State<T>,
        m: Vec3<T>,
        q: Quat<T>,
        clock: Clock<T>,
        lost: State<T>,
        tau: Vec3<T>,
    ) {
        s.m = m.to_array();
        s.q = q.to_array();
        self.clock = clock;
        self.lost = lost;
        self.last = Some(LastKick {
            t: clock.t,
            q: s.q,
            tau,
        });
    }

    pub(crate) fn new(torque: F) -> Self {
        Self {
            torque,
            rotor: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
            rotor_w: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
            clock: Clock {
                t: T::ZERO,
                carry: T::ZERO,
            },
            last: None,
            casimir: None,
            spatial: None,
            lost: State::new([T::ZERO; 3], [T::ZERO; 4]),
            acted: false,
            rotor_moved: false,
        }
    }

    /// Restarts the clock at `t` and drops the cached end torque (it was for the old time);
    /// a non-finite `t` is refused and changes nothing.
    pub(crate) fn set_time(&mut self, t: T) -> Result<(), StepError> {
        if !t.is_finite() {
            return Err(StepError::NonFinite);
        }
        self.clock = Clock { t, carry: T::ZERO };
        self.last = None;
        Ok(())
    }

    /// The clock after a step of `h`, refused when it is not finite (`h` not finite, or
    /// `t + h` overflows): a step must not return a time that is not a number.
    #[inline]
    pub(crate) fn clock_after(&self, h: T) -> Result<Clock<T>, StepError> {
        let next = self.clock.after(h);
        if next.t.is_finite() {
            Ok(next)
        } else if h.is_finite() {
            Err(StepError::Overflow)
        } else {
            Err(StepError::NonFinite)
        }
    }

    /// The rotor `h_r` and `I^-1 h_r` for the body's `inv_i` (the integrator keeps it: no
    /// division on the tick that sets the wheels), checked (`NonFinite`, `Overflow`), not yet
    /// set.
    pub(crate) fn checked_rotor(inv_i: Vec3<T>, h_r: [T; 3]) -> Result<[Vec3<T>; 2], StepError> {
        let r = checked_momentum(&h_r)?;
        let w = r.mul_elem(inv_i);
        if !w.is_finite() {
            return Err(StepError::Overflow);
        }
        Ok([r, w])
    }

    /// Forgets the per-trajectory data ([`Integrator::reset`]): the cached end torque, the
    /// kicks' carried rounding and the holds' references (`|m|^2`, `R(q) m` and the step
    /// count to the next hold), so a reset integrator steps as a fresh one with the same
    /// time, torque and rotor (`step_partial` relies on it).
    pub(crate) fn forget(&mut self) {
        self.last = None;
        self.lost = State::new([T::ZERO; 3], [T::ZERO; 4]);
        self.casimir = None;
        self.spatial = None;
        self.acted = false;
    }

    /// The torque at `(t, q)`, reusing the last step's end evaluation when it is the same.
    #[inline]
    pub(crate) fn torque_at(&self, t: T, q: Quat<T>) -> Result<Vec3<T>, StepError> {
        let qa = q.to_array();
        if let Some(l) = self.last {
            if l.t == t && l.q == qa {
                return Ok(l.tau);
            }
        }
        let tau = Vec3::from_array(self.torque.torque(t, &qa));
        if tau.is_finite() {
            Ok(tau)
        } else {
            Err(StepError::NonFinite)
        }
    }

    /// `None` without a potential, and for a sum that is not finite (a state or potential
    /// that overflows, a potential of `+inf` and `-inf` parts): never NaN.
    pub(crate) fn total_energy(&self, body: &Body<T>, s: &State<T>) -> Option<T> {
        total_energy(
            body.inverse_inertia(),
            self.rotor,
            &self.torque,
            self.clock.t,
            s,
        )
    }
}

/// `1/2 (m - h_r) . I^-1 (m - h_r) + V(t, q)`; `None` without a potential and for a sum that
/// is not finite (shared by the forced integrators and [`crate::ForcedRk4`]).
pub(crate) fn total_energy<T: Real, F: Torque<T>>(
    inv_i: Vec3<T>,
    rotor: Vec3<T>,
    torque: &F,
    t: T,
    s: &State<T>,
) -> Option<T> {
    let m = Vec3::from_array(s.m).sub(rotor);
    let kinetic = c::<T>(0.5) * m.mul_elem(m).dot(inv_i);
    let total = kinetic + torque.potential(t, &s.q)?;
    if total.is_finite() {
        Some(total)
    } else {
        None
    }
}

/// The accessors [`Forced`] and [`crate::Composed`] share: both keep their torque, rotor and
/// clock in a [`Forcing`] field named `forcing`.
macro_rules! forcing_accessors {
    () => {
        /// The rotor momentum `h_r` (body frame).
        #[must_use]
        pub fn rotor(&self) -> [T; 3] {
            self.forcing.rotor.to_array()
        }

        /// The time of the state: advanced by each step's `h` with a compensated sum, so it
        /// stays exact to an ulp of `t` under a jittering `h`. In f32 that ulp is coarse for
        /// long runs (7.8 ms at one day, 0.5 s at `t = 5.5e6 s`, 64 days; 1 s beyond `8.4e6 s`):
        /// a time-dependent torque sees `t` to that resolution, so re-base it with `set_time`
        /// (a periodic torque keeps its phase when `t` moves by whole periods; a circular
        /// orbit's gravity gradient when it moves by whole orbits, to within `N P - 2 pi` a
        /// re-base for the rounded `N` and period `P`: in f32 2.6e-7 to 4e-7 rad as `N` was
        /// rounded, of one sign, up to 4e-4 rad after 1000 orbits, found by a first-use
        /// trial; un-re-based the clock's own ulp costs 5e-4 rad by then). It matters well
        /// before the resolution looks coarse: a first-use trial's 95-minute orbit in f32 kept its
        /// Jacobi integral within 1e-6 of the energy over three days when re-based once an
        /// orbit, and wandered by 1e-5 without (examples/flight_loop.rs re-bases).
        #[must_use]
        pub fn time(&self) -> T {
            self.forcing.clock.t
        }

        /// Sets the time (for time-dependent torques); the cached end torque is dropped.
        ///
        /// # Errors
        ///
        /// `NonFinite` for a non-finite `t`; the time is then left as it was.
        pub fn set_time(&mut self, t: T) -> Result<(), StepError> {
            self.forcing.set_time(t)
        }

        /// The torque model.
        #[must_use]
        pub fn torque(&self) -> &F {
            &self.forcing.torque
        }

        /// The torque model, to change its parameters (the cached end torque is dropped).
        pub fn torque_mut(&mut self) -> &mut F {
            self.forcing.last = None;
            &mut self.forcing.torque
        }
    };
}
pub(crate) use forcing_accessors;

/// A state after a forced step, and the torque at its end (the next step's start torque).
type Kicked<T> = (Vec3<T>, Quat<T>, Vec3<T>);

/// One kick–turn–drift–turn–kick step of length `h` ending at time `t1`, from `(m, q)` with
/// the start torque `tau0` given; returns the new state and the end torque.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn kdk<T: Real, D: Integrator<T>, F: Torque<T>>(
    drift: &mut D,
    torque: &F,
    turn: Option<Quat<T>>,
    rel: Option<RelativeStep<T>>,
    h: T,
    t1: T,
    m: Vec3<T>,
    q: Quat<T>,
    tau0: Vec3<T>,
    lost: &mut State<T>,
    carry: bool,
    given_end: Option<Vec3<T>>,
    inv_i: Vec3<T>,
) -> Result<Kicked<T>, StepError> {
    let half = h * c::<T>(0.5);
    // a non-finite m, q or tau0 makes the drift's input non-finite, and the drift refuses it
    // (NonFinite): no checks of their own on the loop's path
    let (mut m, lost0) = kick(
        m,
        tau0.scale(half)
            .add(carried_for(m, Vec3::from_array(lost.m))),
    );
    // what the turns and the drift drop is added to the carry after the end kick, not into
    // it: the end kick would wait for the drift's rounding (four dependent additions more
    // on the step's critical path: the host's forced step took 15 ns longer)
    let mut pending = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
    let (mut q, mut lost_q) = (q, Quat::from_array(lost.q));
    // with the relative splitting the drift steps `n = m - h_r`, and the start kick's
    // rounding joins `n` (carried: in f32 it is an ulp of `m`, many of the smaller `n`)
    let mut lost0 = lost0;
    if let Some(r) = rel {
        (m, pending, lost0) = r.enter(m, lost0, carry);
    } else if let Some(p) = turn {
        ((m, q), (pending, lost_q)) = turn_state(p, (m, q), (pending, lost_q), carry);
    }
    if carry {
        // the roundings dropped so far are applied after the drift: carried across it
        // ([`across_drift`]); the start kick's with them (it joined `n` on the relative path).
        // (Only with a rotor, whose turns' parts are what biased, the test cost the M4F's
        // forced step with wheels 22 instructions more, register allocation)
        pending = across_drift(pending.add(lost0), m, inv_i, h);
        lost0 = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
    }
    let mut s = State::new(m.to_array(), q.to_array());
    let mut dropped = State::new(pending.to_array(), lost_q.to_array());
    // the free body (no torque, no rotor) is left to the drift's own holds and free-running
    // map (`carry` false: the drift's plain step)
    drift.step_state_carrying(&mut s, &mut dropped, carry)?;
    let (mut pending, mut lost_q) = (Vec3::from_array(dropped.m), Quat::from_array(dropped.q));
    // the drift's output is finite and the turn keeps it so
    let (mut m, mut q) = (Vec3::from_array(s.m), Quat::from_array(s.q));
    if let Some(r) = rel {
        (m, pending) = r.leave(m, pending, carry);
    } else if let Some(p) = turn {
        ((m, q), (pending, lost_q)) = turn_state(p, (m, q), (pending, lost_q), carry);
    }
    let tau1 = Vec3::from_array(torque.torque(t1, &q.to_array()));
    // the model's end torque is returned (the next step's start), the kick adds the given
    let end = match given_end {
        Some(given) => tau1.add(given),
        None => tau1,
    };
    let (m, lost1) = kick(m, end.scale(half).add(lost0));
    let lost1 = if carry { lost1.add(pending) } else { lost1 };
    if !m.is_finite() {
        // the applied torque itself: a model's and a given torque's finite sum that overflows
        // is as non-finite as the summed model's evaluation (NonFinite), as at the start kick
        return Err(if end.is_finite() {
            StepError::Overflow
        } else {
            StepError::NonFinite
        });
    }
    // only on success: a caller may pass its own carry in place. A free body's step in f32
    // (the torque has stopped on a body that does not carry after it) drops it: applied to
    // `m` in this step's kicks, its rest is below half an ulp, and kept it was re-added at
    // every kick of the stretch and now and then rounded into `m`, which the drift took as
    // an outside change and re-took its invariants from (a coast after a small torque on
    // the spacecraft ended 3e-5 to 1.7e-4 rad from f64, a fresh `Mv` 5e-6 to 1.1e-5)
    *lost = if carries_rounding::<T>() && !carry {
        State::new([T::ZERO; 3], [T::ZERO; 4])
    } else {
        State::new(lost1.to_array(), lost_q.to_array())
    };
    Ok((m, q, tau1))
}

/// The same step for momentum only (the torque does not depend on the attitude).
#[allow(clippy::too_many_arguments)]
#[inline]
fn kdk_momentum<T: Real, D: Integrator<T>, F: Torque<T>>(
    drift: &mut D,
    torque: &F,
    turn: Option<Quat<T>>,
    rel: Option<RelativeStep<T>>,
    h: T,
    t0: T,
    t1: T,
    m: Vec3<T>,
    lost: &mut Vec3<T>,
    carry: bool,
    inv_i: Vec3<T>,
) -> Result<Vec3<T>, StepError> {
    let id = [T::ONE, T::ZERO, T::ZERO, T::ZERO];
    let half = h * c::<T>(0.5);
    let tau0 = Vec3::from_array(torque.torque(t0, &id));
    let tau1 = Vec3::from_array(torque.torque(t1, &id));
    if !(tau0.is_finite() && tau1.is_finite()) {
        return Err(StepError::NonFinite);
    }
    let (mut m, mut lost0) = kick(m, tau0.scale(half).add(carried_for(m, *lost)));
    // the turns' and the drift's roundings join the carry after the end kick (as in kdk)
    let mut pending = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
    if let Some(r) = rel {
        (m, pending, lost0) = r.enter(m, lost0, carry);
    } else if let Some(p) = turn {
        (m, pending) = turn_momentum(p, m, pending, carry);
    }
    if carry {
        // as in kdk
        pending = across_drift(pending.add(lost0), m, inv_i, h);
        lost0 = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
    }
    let mut a = m.to_array();
    let mut dropped = pending.to_array();
    // the free body is left to the drift's own holds (as in kdk)
    drift.step_carrying(&mut a, &mut dropped, carry)?;
    pending = Vec3::from_array(dropped);
    let mut m = Vec3::from_array(a);
    if let Some(r) = rel {
        (m, pending) = r.leave(m, pending, carry);
    } else if let Some(p) = turn {
        (m, pending) = turn_momentum(p, m, pending, carry);
    }
    let (m, lost1) = kick(m, tau1.scale(half).add(lost0));
    *lost = if carry {
        lost1.add(pending)
    } else if carries_rounding::<T>() {
        // (as in kdk)
        Vec3::new(T::ZERO, T::ZERO, T::ZERO)
    } else {
        lost1
    };
    if m.is_finite() {
        Ok(m)
    } else {
        Err(StepError::Overflow)
    }
}

/// A free integrator (the drift) driven by a torque model and a rotor: the symmetric
/// kick–turn–drift–turn–kick step, order 2: half kicks `m += h/2 tau` at both ends, the
/// rotor's half turns `exp(-h/2 hat(I^-1 h_r))` around a drift of the free body (docs/MATH.md
/// §9, McLachlan & Quispel's splitting) (with a rotor that turns the
/// body faster than its own motion, kick–half–drift–half–kick on the relative momentum:
/// crate::forced_relative; measured on a cubesat with a momentum-bias wheel, 5.2e-6 rad
/// after 10 s at 160 Hz against RK4, where the turns left 2.3e-2, and f32 within 1.1x the
/// scene's sensitivity after `10^6` steps, where the turns ended 200x; tests/gyrostat_relative.rs).
///
/// With [`crate::Mv`] as the drift this is the explicit Lie group variational integrator of
/// the forced rigid body (the same map as Lee–Leok–McClamroch's Newton-solved LGVI, to
/// round-off: checked in the lab); with [`crate::PreMv`] the drift's phase error is removed
/// but the splitting keeps the order at 2 whenever a torque acts (without torque and rotor
/// it is the `PreMv` step itself); with [`crate::Splitting`] it is the Strang splitting of the
/// forced body with McLachlan's step.
///
/// Cost over the drift: two kicks (15 flops each, their rounding carried), one torque
/// evaluation (the end one is reused), the drift's carried rounding (about 25 flops), and
/// with a rotor two turns (about 50 flops each with their carried rounding; the turn is
/// recomputed, one division, only when `h` or the rotor changes).
///
/// Small torques are applied exactly: each kick's part that the rounding of `m` drops is
/// carried into the next kick (Fast2Sum), so a torque whose kick is a fraction of an ulp of
/// `m` (common in f32: `2e-4 N m` on 10 N m s at 200 Hz is about half of one, `2e-5 N m` a
/// twentieth) still moves `m` by `tau t` to within a few ulps over any number of steps (plain rounding applied it with a 22 %
/// error; tests/forced.rs). The carried part is below an ulp of `m`, kept when the caller
/// changes `m` (it is impulse that acted) and dropped by `reset`.
///
/// The state's rounding is carried the same way (error model): under a torque nothing
/// conserved can be held, so each rounding of `m` and `q` to the working precision would stay
/// in the state, a random walk of about an ulp a step. Instead the drift (for [`crate::Mv`]
/// and [`crate::PreMv`]) and the rotor's turns add their increments as `x + dx` rounded once
/// and hand back what that rounding dropped (`dx - (x' - x)`, exact by Fast2Sum while
/// `|dx| <= |x|`): the momentum's part joins the next kick, the attitude's the next turn of
/// the attitude (a part dropped before the drift crosses it by the drift's tangent map,
/// `across_drift`: added after it unturned, a wheel's sub-ulp turn made `|m|^2` drift). What is
/// left is the rounding of the increments themselves, relative to
/// `h |Omega|`, and of the torque. The drift's increment is also biased by about
/// `eps (h |Omega|)^2` of the invariants a step, with one sign along a trajectory (its
/// rounded constants): at large turns `Mv`'s carried step moves its result back onto its
/// input's `|m|^2` and energy, their change computed from the increment (crate::mv's
/// `fix_from_increment`; a satellite tumbling at `h |Omega| = 0.02` under the gravity
/// gradient had drifted its Jacobi integral by 4.5e-5 of the energy in `10^6` f32 steps and
/// ended 200x the sensitivity below, now within 5e-7 and 0.4-1.6x; found by a first-use
/// trial, tests/forced.rs
/// `an_f32_satellite_tumbling_at_large_steps_keeps_its_jacobi_integral`). Measured in f32 at
/// 200 Hz on a spacecraft-like body under a gravity gradient or a controller's torque, with
/// and without wheels, against the same method in f64: attitude within 9e-7 rad and momentum within 9e-7 after `2 x 10^5` steps,
/// 4.3e-6 after `10^6` (without the carry: 2e-4 to 1.2e-3 rad after `2 x 10^5` steps, 5e-3 to
/// 5e-2 after `10^6`); the gravity gradient's Jacobi integral within 4e-7 of the kinetic
/// energy over `10^6` steps (1.8e-4 and 8.9e-4 with wheels before). Those attitude figures
/// are that body's: how far an ulp travels depends on the dynamics, and so does how close
/// f32 stays to f64. Against f64's own sensitivity (f64 started one f32 ulp of `m0` away) f32
/// is at 0.4-0.75x of it there (1.2x in attitude, 1.5x in `m`, with both runs started from the
/// f32-rounded `m0`), 2.4-2.9x in attitude and 4-5x in `m` on the README firmware's spacecraft
/// (1.5-1.8e-5 rad after `2 x 10^5` steps), and up to 117x in `m` near a sphere (an analyst's
/// review); about 500x without the carry. Without torque and rotor the drift runs its own
/// free-running step, which holds the invariants and (f32) carries its own rounding
/// ([`crate::Mv`]), until a torque has acted or the rotor has turned the state: from then on,
/// in f32, every step carries, torque or not (free stretches between thruster pulses left to
/// the drift's holds took their invariants from the rounded state each time, and the
/// attitude random-walked to 25-104x the scene's sensitivity; now 0.35-1.5x on compact and
/// elongated bodies, tests/forced.rs
/// `thruster_pulses_in_f32_stay_within_the_scenes_sensitivity`; an elongated body's carried
/// steps drifted until the drift's carried step kept its input's invariants,
/// `an_elongated_body_after_a_torque_steps_as_a_free_one`). A gyrostat without torque holds `|m|^2` and `R(q) m` in f64; in f32 it carries instead (holding as well rounded the
/// state without carrying that rounding, which fought the carry: 339x the sensitivity after
/// `10^6` steps, now 0.6x, `an_f32_gyrostat_follows_f64`; `|m|^2` and `R(q) m` within
/// 3.5e-7 over `10^6` steps and 1.6-3.0e-6 over `10^7`, where the holds kept 3e-7). Where
/// the wheels turn the body by more than 1e-3 rad a half step, each turn also hands the carry
/// what moves `m` back onto `|m|` (a turn by the same rounded quaternion every step
/// otherwise drifts `|m|` linearly: 1.2e-5 in `2.56 x 10^5` steps at `h |Omega| = 0.05`
/// with a 5 N m s wheel, now 3.9e-8; `an_f32_gyrostat_with_a_fast_wheel_keeps_its_casimir`).
/// Where
/// the exact increment is zero (a sphere, whose `m` a torque-free step leaves as it is) the
/// carry also keeps the increments' own round-off, about `1e-4` ulp a step at `h |Omega| = 5e-4` (more at
/// faster turns: 5e-3 ulp a step at `2.5e-3`, bounded from `10^5` to `10^6` steps), which
/// rounding used to drop: on a sphere in f32 `m` moves 70 to 125 ulps (1.2e-5) in `10^6` steps
/// of `step_state_with` with zero torques or a small constant torque (it stayed within 4 ulps
/// before). The carry costs the
/// M4F's forced step 17 instructions (597), a soft-float Cortex-M3's about 2000 (19898).
/// Drifts other than `Mv` and `PreMv` carry only the kicks' and the turns' rounding. In f64
/// only the kicks' rounding is carried: the walk is `1e-16` a step there, below the method's
/// error, and the carry's flops would buy nothing.
///
/// The bounded energy error of a potential torque is a property of a fixed step: with a step
/// that changes every tick the map changes with it, and the error can grow slowly (a
/// first-use trial, heavy top in f64 with `h` drawn from 1/144 to 1/30 s and 0.2 % hitches of
/// 0.1 s: energy error 3.7e-3 over the first half of `10^6` steps and 8.7e-3 over the second;
/// [`crate::Composed`] order 4 3.9e-6 then 6.9e-6). What does not depend on the step stays:
/// the heavy top's vertical momentum `e_z . R(q) m` held to 3e-14 there.
///
/// A step that fails (past the drift's limit, a non-finite torque) returns `Err` and leaves
/// the state and the time untouched.
#[derive(Clone, Debug)]
pub struct Forced<T, D, F> {
    drift: D,
    forcing: Forcing<T, F>,
    /// The rotor's half turn; an infinite quaternion when it cannot be taken at the current `h` (a
    /// change of `h` cannot be refused, so the steps are until it comes back): the drift then
    /// refuses the turned, non-finite input, and the step reports why ([`Forced::refusal`]). No
    /// test on the step's path: an early return there cost the M4F 68 instructions a step.
    turn: Option<Quat<T>>,
    /// The body's `I^-1` (set with the drift: the body cannot change), for the relative
    /// splitting (crate::forced_relative) and for carrying f32's roundings across the drift
    /// ([`across_drift`]); the rotor's rates, for the relative splitting, which a step with a
    /// rotor takes when the wheels turn the body well faster than its own energy allows (set
    /// with the rotor); and whether the last step took it (the choice's margin).
    inv_i: Vec3<T>,
    rates: RotorRates<T>,
    relative_on: bool,
}

impl<T: Real, D: Integrator<T>, F: Torque<T>> Forced<T, D, F> {
    /// The free integrator `drift` driven by `torque`, at time zero, without rotor.
    #[must_use]
    pub fn new(drift: D, torque: F) -> Self {
        let inv_i = drift.body().inverse_inertia();
        Self {
            drift,
            forcing: Forcing::new(torque),
            turn: None,
            inv_i,
            rates: RotorRates::none(),
            relative_on: false,
        }
    }

    /// Sets the rotor momentum `h_r` (reaction wheels), in the body frame: the principal axes
    /// of the [`Body`] (wheels mounted along a structure's axes go through
    /// [`crate::Frame::to_principal`]). May change between steps; the value set before a step
    /// is held constant over that whole step (a zero-order hold: for wheels whose momentum
    /// changes within a tick, pass the value the tick should see).
    ///
    /// Convention: `m` is the total angular momentum in the body frame (body and wheels), and
    /// the body turns at `Omega = I^-1 (m - h_r)`; a change of `h_r` alone (a wheel command)
    /// leaves `m` and `R(q) m` as they are. With a step size that is not finite the rotor is
    /// taken and the steps refuse (`NonFinite`) until `h` is finite. Each step chooses how it
    /// splits the rotor's part: turns about `I^-1 h_r`, or, when the wheels turn the body
    /// well faster than its own energy allows, the relative splitting (a free drift of
    /// `n = m - h_r` between two implicit-midpoint half steps of `n' = h_r x I^-1 n` at a fixed
    /// attitude; [`Forced::takes_relative_split`] and the type's docs).
    ///
    /// The steps' limit: the rotor's half turn must stay within half a revolution,
    /// `h |I^-1 h_r| <= 8`. A rotor past it at the current step size is taken, and the steps
    /// return `StepTooLarge` (state and time untouched) until `h` or the rotor is brought back,
    /// as after a change of `h` past it: the limit is the step's, not the rotor's, so a loop
    /// that sets the wheels and then the measured `dt` each tick recovers at the first good
    /// `dt` after a bad one. (Refused here, as before, one huge `dt` made every later
    /// `set_rotor` fail against it, and a loop that returns on that error never set a good
    /// `dt` again: the README's quick start stopped for good, found by a first-use trial.) The
    /// relative splitting has no such limit, but a step it would take is refused with the
    /// turns' (kept as it was, for the steps that take the turns).
    ///
    /// # Errors
    ///
    /// `NonFinite` for a non-finite `h_r` and `Overflow` if `I^-1 h_r` overflows; the rotor is
    /// then left as it was.
    pub fn set_rotor(&mut self, h_r: [T; 3]) -> Result<(), StepError> {
        let [r, w] = Forcing::<T, F>::checked_rotor(self.inv_i, h_r)?;
        let turn = half_turn(w, self.drift.step_size());
        self.forcing.rotor_moved |= r != self.forcing.rotor;
        self.forcing.rotor = r;
        self.forcing.rotor_w = w;
        self.rates = RotorRates::new(w, self.inv_i);
        self.set_turn(turn);
        Ok(())
    }

    fn set_turn(&mut self, turn: Result<Option<Quat<T>>, StepError>) {
        self.turn = match turn {
            Ok(p) => p,
            Err(_) => {
                let inf = T::MAX * c::<T>(2.0);
                Some(Quat {
                    w: inf,
                    x: inf,
                    y: inf,
                    z: inf,
                })
            }
        };
    }

    /// Whether the next step from momentum `m`, with the rotor set to `h_r` first, takes the
    /// relative splitting instead of the turns (the wheels turn the body at least 3.6 times the fastest rate its
    /// energy allows, 2.4 times while the last step took it). For tangent maps of the step
    /// built outside the library (the firmware's EKF composes the step's Jacobian from its
    /// parts). False without rotor, for a non-finite input, and where the rotor's turn is
    /// refused at the current step size.
    #[must_use]
    pub fn takes_relative_split(&self, m: &[T; 3], h_r: &[T; 3]) -> bool {
        let inv_i = self.inv_i;
        let h_r = Vec3::from_array(*h_r);
        let w = h_r.mul_elem(inv_i);
        matches!(half_turn(w, self.drift.step_size()), Ok(Some(_)))
            && relative_wanted(
                Vec3::from_array(*m),
                h_r,
                inv_i,
                RotorRates::new(w, inv_i),
                self.relative_on,
            )
    }

    /// The relative splitting's step for a step from `m`, if it takes it
    /// ([`relative_wanted`]; never while the rotor's turn is refused, whose infinite
    /// quaternion the drift then refuses).
    #[inline(always)]
    fn relative_for(&self, m: Vec3<T>) -> Option<RelativeStep<T>> {
        let h_r = self.forcing.rotor;
        match self.turn {
            Some(p)
                if p.w <= T::MAX
                    && relative_wanted(m, h_r, self.inv_i, self.rates, self.relative_on) =>
            {
                Some(RelativeStep::new(h_r, self.inv_i, self.drift.step_size()))
            }
            _ => None,
        }
    }

    /// A step's error as the caller should see it: while the rotor's turn is refused (the
    /// infinite turn of [`Forced::set_turn`]; the drift saw only the non-finite input it made)
    /// the reason [`half_turn`] gave, derived again from the step size, else the error itself.
    #[cold]
    fn refusal(&self, e: StepError) -> StepError {
        match self.turn {
            Some(p) if !p.is_finite() => {
                if self.drift.step_size().is_finite() {
                    StepError::StepTooLarge
                } else {
                    StepError::NonFinite
                }
            }
            _ => e,
        }
    }

    forcing_accessors!();

    /// The free integrator.
    #[must_use]
    pub fn drift(&self) -> &D {
        &self.drift
    }

    /// Total energy `1/2 (m - h_r) . I^-1 (m - h_r) + V(t, q)` at the current time, or `None`
    /// when the torque has no potential or the sum is not finite (it overflows).
    #[must_use]
    pub fn total_energy(&self, s: &State<T>) -> Option<T> {
        self.forcing.total_energy(self.drift.body(), s)
    }

    /// One step with the torque given at both ends of the step (`tau_start` at `t`,
    /// `tau_end` at `t + h`; pass the same value twice for a zero-order hold) **instead of the
    /// model** (the model is not evaluated): for torques measured or commanded outside (a
    /// controller's output) on a body with no torque model. To add a controller's torque to a
    /// model (gravity gradient plus a command), use [`Forced::step_state_plus`]. Torques are in
    /// the integrator's body frame, the principal axes of [`Body`] (a tensor's
    /// [`crate::Frame`] turns sensor-frame vectors into it). Symmetric and
    /// of order 2 when the values are those of a smooth torque history. The torques are taken
    /// to act, even when zero: the drift takes each step as an outside change and the state's
    /// rounding is carried ([`Forced`]), and in f32 every later step of this integrator
    /// carries it too, torque or not ([`Forced`]'s error model: that keeps
    /// the stretches between pulses on the trajectory). For a long free stretch without
    /// pulses, step the drift itself (its free-running step and holds, cheaper: M4F 370
    /// instead of 650 instructions).
    ///
    /// # Errors
    ///
    /// `NonFinite` for a non-finite state or torque, and the drift's errors; the state and the
    /// time are then left as they were. While the rotor's turn is refused at this `h`
    /// ([`Forced::set_rotor`]) a finite state gets `StepTooLarge`, whatever the torques.
    pub fn step_state_with(
        &mut self,
        s: &mut State<T>,
        tau_start: [T; 3],
        tau_end: [T; 3],
    ) -> Result<(), StepError> {
        // the state and the start torque are checked on their way through the step (kdk):
        // the drift refuses a non-finite input (a non-finite start torque makes one); a turn
        // needs the unit attitude first. The end torque is checked here: found by the end
        // kick, the drift had stepped, and its next step started from a root moved on to a
        // step that never happened (f32 `|m|^2` walked 2.6e-5 with a NaN end torque every
        // 7th tick, found in review)
        if !Vec3::from_array(tau_end).is_finite() {
            return Err(self.refusal(StepError::NonFinite));
        }
        let turn = self.turn;
        let (m, q) = if turn.is_some() {
            checked_state(s)?
        } else {
            // the attitude before the drift sees a kicked momentum: `PreMv` as a forced
            // step's drift does not check it again, and would apply its pending change of `h`
            // before `Mv` refused a zero `q` (f64 twins 6.7e-16 apart, found in review)
            checked_attitude(Some(&s.q))?;
            (Vec3::from_array(s.m), Quat::from_array(s.q))
        };
        let tau0 = Vec3::from_array(tau_start);
        let h = self.drift.step_size();
        let clock = self.forcing.clock_after(h)?;
        let given = crate::torque::ConstantTorque(tau_end);
        let rel = self.relative_for(m);
        let (m, q, _) = kdk(
            &mut self.drift,
            &given,
            turn,
            rel,
            h,
            T::ZERO,
            m,
            q,
            tau0,
            &mut self.forcing.lost,
            // torques given by the caller are taken to act (a free body steps its drift)
            carries_rounding::<T>(),
            None,
            self.inv_i,
        )
        .map_err(|e| self.refusal(e))?;
        s.m = m.to_array();
        s.q = q.to_array();
        self.forcing.clock = clock;
        self.forcing.last = None;
        self.forcing.mark_acted(true);
        self.relative_on = rel.is_some();
        self.forcing.rotor_moved = false;
        Ok(())
    }

    /// One step under the model's torque **plus** a torque given at both ends of the step
    /// (`tau_start` at `t`, `tau_end` at `t + h`; the same value twice for a zero-order hold):
    /// the flight loop's case, an environment model (gravity gradient) and a controller's
    /// command that changes every tick. Each kick applies `tau_model(t, q) + tau_given`; the
    /// model's end torque is kept for the next step's start as in [`Integrator::step_state`]
    /// (one model evaluation a step: adding the command to the model through
    /// [`Forced::torque_mut`] would drop that cache and evaluate the model twice).
    ///
    /// The same map as [`Integrator::step_state`] with the model `(model, ConstantTorque(tau))`
    /// for a constant `tau` (bit for bit: the sums are formed in the same order), zero
    /// included: a command of exactly zero at both ends is the model's own step (with a zero
    /// model, the free body's holds of `|m|^2` and `R(q) m` until a torque has acted; in f32
    /// the state's rounding is carried from then on), any other is taken to act (the state's
    /// rounding carried, nothing held: [`Forced`]). Symmetric and of order 2 for a
    /// smooth torque history. Torques are in the body frame of [`Forced::step_state_with`].
    ///
    /// # Errors
    ///
    /// `NonFinite` for a non-finite state, given torque or model torque, and the drift's
    /// errors; the state and the time are then left as they were.
    pub fn step_state_plus(
        &mut self,
        s: &mut State<T>,
        tau_start: [T; 3],
        tau_end: [T; 3],
    ) -> Result<(), StepError> {
        let zero = [T::ZERO; 3];
        if tau_start == zero && tau_end == zero {
            // no command: the model's own step (with a zero model the free body's holds and
            // free-running map; the summed model `(model, ConstantTorque(0))` does the same)
            return self.step_state(s);
        }
        // written apart from step_state (a shared inlined body moved the M4F's gravity-gradient
        // step 916 -> 922 instructions and the firmware's flash by 2 KB); the end torque
        // checked before the drift steps ([`Forced::step_state_with`])
        if !Vec3::from_array(tau_end).is_finite() {
            return Err(self.refusal(StepError::NonFinite));
        }
        let turn = self.turn;
        let (m0, q0) = checked_state(s)?;
        let h = self.drift.step_size();
        // a non-finite given start torque makes the drift's input non-finite (NonFinite)
        let tau0 = self
            .forcing
            .torque_at(self.forcing.clock.t, q0)?
            .add(Vec3::from_array(tau_start));
        let clock = self.forcing.clock_after(h)?;
        let mut lost = self.forcing.lost;
        let rel = self.relative_for(m0);
        let (m, q, tau1) = kdk(
            &mut self.drift,
            &self.forcing.torque,
            turn,
            rel,
            h,
            clock.t,
            m0,
            q0,
            tau0,
            &mut lost,
            carries_rounding::<T>(),
            Some(Vec3::from_array(tau_end)),
            self.inv_i,
        )
        .map_err(|e| self.refusal(e))?;
        self.forcing.commit(s, m, q, clock, lost, tau1);
        self.forcing.mark_acted(true);
        self.relative_on = rel.is_some();
        self.forcing.rotor_moved = false;
        Ok(())
    }
}

impl<T: Real, D: Integrator<T>, F: Torque<T>> Integrator<T> for Forced<T, D, F> {
    /// Momentum only: allowed when the torque does not depend on the attitude
    /// (`NeedsAttitude` otherwise).
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        if self.forcing.torque.depends_on_attitude() {
            return Err(StepError::NeedsAttitude);
        }
        let turn = self.turn;
        let v = checked_momentum(m)?;
        let h = self.drift.step_size();
        let t0 = self.forcing.clock.t;
        let clock = self.forcing.clock_after(h)?;
        let mut lost = Vec3::from_array(self.forcing.lost.m);
        let carry = self.forcing.carries(turn.is_some());
        let rel = self.relative_for(v);
        let next = kdk_momentum(
            &mut self.drift,
            &self.forcing.torque,
            turn,
            rel,
            h,
            t0,
            clock.t,
            v,
            &mut lost,
            carry,
            self.inv_i,
        )
        .map_err(|e| self.refusal(e))?;
        // the holds only where the rounding is not carried (f64): they round the state
        // without carrying it, which the carry cannot follow (below); not after a relative
        // step (as in step_state)
        let next = if turn.is_some() && !carry && (rel.is_none() || self.forcing.rotor_moved) {
            self.forcing.hold_casimir(v, next, rel.is_some())
        } else {
            if turn.is_some() && !carry {
                self.forcing.bridge_holds(v, None, next, None);
            }
            next
        };
        self.forcing.mark_acted(carry);
        self.relative_on = rel.is_some();
        self.forcing.rotor_moved = false;
        self.forcing.lost.m = lost.to_array();
        *m = next.to_array();
        self.forcing.clock = clock;
        Ok(())
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        let turn = self.turn;
        let (m0, q0) = checked_state(s)?;
        let h = self.drift.step_size();
        let tau0 = self.forcing.torque_at(self.forcing.clock.t, q0)?;
        let clock = self.forcing.clock_after(h)?;
        let mut lost = self.forcing.lost;
        let carry = self.forcing.carries(turn.is_some());
        let rel = self.relative_for(m0);
        let (m, q, tau1) = kdk(
            &mut self.drift,
            &self.forcing.torque,
            turn,
            rel,
            h,
            clock.t,
            m0,
            q0,
            tau0,
            &mut lost,
            carry,
            None,
            self.inv_i,
        )
        .map_err(|e| self.refusal(e))?;
        // the gyrostat's holds only where the rounding is not carried (f64): a hold rounds
        // the state without carrying it, and in f32 that fought the carry (constant wheels,
        // no torque, spacecraft at 0.01 rad/s and 200 Hz: the attitude 339x the scene's
        // sensitivity to one ulp of `m` after `10^6` steps with the holds, 0.8x without;
        // found by a flight-loop trial). Not after a relative step (crate::forced_relative):
        // it keeps the energy and leaves `|m|^2` and `R(q) m` with errors of order `h^2`
        // that stay bounded, which holding them turned into a drift of the energy (a
        // wheel-dominated cubesat in f64: 5e-8 after `10^6` steps and growing, against 4e-11
        // after `10^7` unheld, `|m|^2` 1.4e-11 and `R(q) m` 1.7e-8)
        let (m, q) = if turn.is_some() && !carry && (rel.is_none() || self.forcing.rotor_moved) {
            let relative = rel.is_some();
            let held = self.forcing.hold_casimir(m0, m, relative);
            (held, self.forcing.hold_spatial(m0, q0, held, q, relative))
        } else {
            if turn.is_some() && !carry {
                self.forcing.bridge_holds(m0, Some(q0), m, Some(q));
            }
            (m, q)
        };
        self.forcing.commit(s, m, q, clock, lost, tau1);
        self.forcing.mark_acted(carry);
        self.relative_on = rel.is_some();
        self.forcing.rotor_moved = false;
        Ok(())
    }

    fn step_size(&self) -> T {
        self.drift.step_size()
    }

    /// Sets the drift's step and the rotor's half turn for it; past half a revolution
    /// (`h |I^-1 h_r| > 8`) the steps return `StepTooLarge`, state and time untouched, until
    /// `h` or the rotor comes back. A zero `h` pauses the drift (as its own docs say); the
    /// kicks then apply no torque, but in f32 the first paused step adds the carried sub-ulp
    /// remainder of earlier kicks and wheel turns ([`Forced`]'s error model), which can move
    /// `m` by an ulp, and with wheels `q` too (a first-use trial: about `1e-7` rad).
    fn set_step_size(&mut self, h: T) {
        self.drift.set_step_size(h);
        self.set_turn(half_turn(self.forcing.rotor_w, h));
    }

    fn body(&self) -> &Body<T> {
        self.drift.body()
    }

    /// Forgets the drift's per-trajectory data, the cached end torque, the gyrostat's hold
    /// references and the carried rounding of the kicks and the state (sub-ulp impulse and
    /// round-off, see [`Forced`]): a loop that resets every
    /// step loses small torques' sub-ulp part again (measured in review: `2e-4 N m` on a sphere
    /// in f32 at 200 Hz, 4.6 % of the impulse over `10^5` steps). Keeps the time, the torque
    /// model, the rotor and the step size, and the rotor's splitting (its margin: a reset
    /// scratch copy, `step_partial`, takes the step the integrator would, found in review).
    fn reset(&mut self) {
        self.drift.reset();
        self.forcing.forget();
    }
}
