//! McLachlan's splittings: compositions of exact rotations about the principal axes
//! (R. I. McLachlan, "Explicit Lie–Poisson integration and the Euler equations",
//! Phys. Rev. Lett. 71 (1993) 3043; docs/MATH.md §7).
//!
//! The energy `E = sum E_i`, `E_i = m_i^2 / (2 I_i)`, splits into integrable pieces. The flow
//! of `E_i` keeps `m_i` and so `w = m_i / I_i`, and is the rotation `m(t) = R_i(-w t) m`
//! about the body axis `e_i`, with the attitude `q(t) = q (x) (cos(w t / 2), sin(w t / 2) e_i)`;
//! `R(q) m` is unchanged by every piece, so the composition conserves it to round-off, and
//! `|m|^2` too. The energy is not conserved (it oscillates at `O(h^2)`).

use crate::body::Body;
use crate::error::StepError;
use crate::integrator::{
    checked_momentum, checked_state, compose_attitude, write_state, Integrator, State,
};
use crate::linalg::{Quat, Vec3};
use crate::real::{c, Real};

/// The rotation by angle `a` as `(sin a, cos a - 1)`, from the half angle: `cos a - 1 =
/// -2 sin^2(a/2)` to full relative accuracy, where `cos a` itself rounds onto the grid of
/// numbers near 1 (steps of an ulp of 1).
///
/// Why: the rotation `m + (cos a - 1) m_plane + sin a (e x m)` scales `|m_plane|^2` by
/// `sin^2 a + cos^2 a`, and with `cos a` rounded near 1 that is off by up to an ulp of 1, the
/// same way for many steps in a row (the angle moves slowly): in f32 at `a ~ 3e-4` it rounded
/// to 1 or to `1 - 2^-24`, and `|m|^2` drifted 7e-2 in `10^6` steps of `h = 10^-3` (a
/// first-use trial). With `cos a - 1` and `sin a` each to a few ulps the scale is off by a
/// few ulps of `a^2`.
///
/// The flow of `E_axis` for time `t` turns by `a = t m_axis / I_axis` (`w_per_m = 1 / I_axis`);
/// returns `(sin(a/2), cos(a/2), sin a, cos a - 1)`, the half angle's pair for the attitude's
/// quaternion.
#[inline(always)]
fn rotation_pair<T: Real>(m: Vec3<T>, axis: usize, w_per_m: T, t: T) -> (T, T, T, T) {
    let mi = match axis {
        0 => m.x,
        1 => m.y,
        _ => m.z,
    };
    let (sh, ch) = (t * mi * w_per_m * c::<T>(0.5)).sin_cos();
    let two_sh = sh + sh;
    (sh, ch, two_sh * ch, -(two_sh * sh))
}

/// `m` turned about `e_axis` by `(s, cm1) = (sin a, cos a - 1)`: `m_plane + (cm1 m_plane +
/// s e x m)`, the increment rounded relative to itself.
#[inline(always)]
fn turn_about<T: Real>(m: Vec3<T>, axis: usize, s: T, cm1: T) -> Vec3<T> {
    match axis {
        0 => Vec3::new(
            m.x,
            m.y + (cm1 * m.y + s * m.z),
            m.z + (cm1 * m.z - s * m.y),
        ),
        1 => Vec3::new(
            m.x + (cm1 * m.x - s * m.z),
            m.y,
            m.z + (cm1 * m.z + s * m.x),
        ),
        _ => Vec3::new(
            m.x + (cm1 * m.x + s * m.y),
            m.y + (cm1 * m.y - s * m.x),
            m.z,
        ),
    }
}

/// Exact flow of `E_axis` for time `t` on the momentum: rotation of `m` about `e_axis` by
/// `-t m_axis / I_axis`. One `sin` and one `cos` (of the half angle, [`rotation_pair`]).
#[inline]
fn rotate_momentum<T: Real>(m: Vec3<T>, axis: usize, w_per_m: T, t: T) -> Vec3<T> {
    let (_, _, s, cm1) = rotation_pair(m, axis, w_per_m, t);
    turn_about(m, axis, s, cm1)
}

/// Exact flow of `E_axis` for time `t` on momentum and attitude: the half angle's `sin` and
/// `cos` give the quaternion, and the double-angle formulas the rotation of `m`
/// ([`rotation_pair`]).
#[inline]
fn rotate_state<T: Real>(
    m: Vec3<T>,
    q: Quat<T>,
    axis: usize,
    w_per_m: T,
    t: T,
) -> (Vec3<T>, Quat<T>) {
    let (sh, ch, s, cm1) = rotation_pair(m, axis, w_per_m, t);
    let m = turn_about(m, axis, s, cm1);
    let z = T::ZERO;
    let dq = match axis {
        0 => Quat {
            w: ch,
            x: sh,
            y: z,
            z,
        },
        1 => Quat {
            w: ch,
            x: z,
            y: sh,
            z,
        },
        _ => Quat {
            w: ch,
            x: z,
            y: z,
            z: sh,
        },
    };
    (m, compose_attitude(q, dq))
}

fn finish<T: Real>(m: Vec3<T>) -> Result<[T; 3], StepError> {
    if m.is_finite() {
        Ok(m.to_array())
    } else {
        Err(StepError::Overflow)
    }
}

/// McLachlan's symmetric splitting with three axis rotations (order 2):
/// `phi_1(h/2) phi_2(h/2) phi_3(h) phi_2(h/2) phi_1(h/2)`, five rotations a step (five `sin`
/// and five `cos`); [`Splitting::step_many`] merges the half steps of consecutive steps to four
/// rotations a step. Conserves `|m|^2` and `R(q) m` to round-off (each rotation rounds two
/// components without bias: in f32 a random walk of about `eps sqrt(10 n)` after `n` steps,
/// 1e-4 at `10^6`: see the private `rotation_pair`); the energy error is `O(h^2)` and bounded. Error at `t = 10` on the talk's case: about `0.25 h^2`.
///
/// At any step size the result is finite (rotations only); past `h |Omega| ~ 1` it is
/// inaccurate, with no warning: there is no stability limit to report.
#[derive(Clone, Debug)]
pub struct Splitting<T> {
    body: Body<T>,
    inv_i: Vec3<T>,
    h: T,
}

impl<T: Real> Splitting<T> {
    /// A splitting integrator for `body` with step `h`.
    #[must_use]
    pub fn new(body: Body<T>, h: T) -> Self {
        Self {
            body,
            inv_i: body.inverse_inertia(),
            h,
        }
    }

    /// `n` steps at once with the half steps of consecutive steps merged:
    /// `phi_1(h/2) [phi_2(h/2) phi_3(h) phi_2(h/2) phi_1(h)]^(n-1) ... phi_1(h/2)`, four
    /// rotations a step. Same result as `n` calls of `step` up to round-off.
    ///
    /// # Errors
    ///
    /// [`StepError::NonFinite`] for a non-finite `m` or step, [`StepError::Overflow`] when the
    /// result would overflow (`m` is then left as it was).
    pub fn step_many(&mut self, m: &mut [T; 3], n: usize) -> Result<(), StepError> {
        if !self.h.is_finite() {
            return Err(StepError::NonFinite);
        }
        let mut v = checked_momentum(m)?;
        if n == 0 {
            return Ok(());
        }
        let (h, hh, w) = (self.h, self.h * c::<T>(0.5), self.inv_i);
        v = rotate_momentum(v, 0, w.x, hh);
        let mut k = 0;
        while k < n {
            v = rotate_momentum(v, 1, w.y, hh);
            v = rotate_momentum(v, 2, w.z, h);
            v = rotate_momentum(v, 1, w.y, hh);
            v = rotate_momentum(v, 0, w.x, if k + 1 == n { hh } else { h });
            k += 1;
        }
        *m = finish(v)?;
        Ok(())
    }
}

impl<T: Real> Integrator<T> for Splitting<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        self.step_many(m, 1)
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        if !self.h.is_finite() {
            return Err(StepError::NonFinite);
        }
        let (v, q) = checked_state(s)?;
        // h = 0 leaves the state as it is (the trait's promise; the step renormalised q)
        if self.h == T::ZERO {
            return Ok(());
        }
        let (h, hh, w) = (self.h, self.h * c::<T>(0.5), self.inv_i);
        let (v, q) = rotate_state(v, q, 0, w.x, hh);
        let (v, q) = rotate_state(v, q, 1, w.y, hh);
        let (v, q) = rotate_state(v, q, 2, w.z, h);
        let (v, q) = rotate_state(v, q, 1, w.y, hh);
        let (v, q) = rotate_state(v, q, 0, w.x, hh);
        write_state(s, v, q)
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

/// McLachlan's splitting with the Casimir split off (order 2): `E = c |m|^2 / 2 + E_a + E_b`
/// with `c = 1 / I_k` for one axis `k`, so only the two other axes rotate, with frequencies
/// `m_i (1/I_i - 1/I_k)`: `phi_a(h/2) phi_b(h) phi_a(h/2)`, three rotations a step. The
/// Casimir's flow leaves `m` alone and turns the attitude about the spatial momentum by
/// `c |m| h`; it commutes with the rest, so it is applied once per step. The axis split off is
/// the one of the middle moment (`c = 1 / I_mid` leaves the two smallest frequencies
/// `1/I_i - c`, of opposite signs), with the half steps on the axis of the smallest moment:
/// on the talk's case the error at `t = 10` is about `0.0027 h^2`, a hundred times below
/// [`Splitting`] (docs/MATH.md §7; the other five arrangements give `0.0043` to `0.032`).
#[derive(Clone, Debug)]
pub struct Splitting2<T> {
    body: Body<T>,
    /// `1/I_i - 1/I_k` for the two rotating axes, in the order (a, b, k).
    w: Vec3<T>,
    axes: [usize; 3],
    c: T,
    h: T,
}

impl<T: Real> Splitting2<T> {
    /// A Casimir-split integrator for `body` with step `h`.
    #[must_use]
    pub fn new(body: Body<T>, h: T) -> Self {
        let [i1, i2, i3] = body.inertia();
        // a: smallest moment, b: largest, k (split off): the middle one
        let (a, b) = if i1 <= i2 && i1 <= i3 {
            (0, if i2 >= i3 { 1 } else { 2 })
        } else if i2 <= i3 {
            (1, if i1 >= i3 { 0 } else { 2 })
        } else {
            (2, if i1 >= i2 { 0 } else { 1 })
        };
        let k = 3 - a - b;
        // a match, not indexing: the step functions must have no panic path (no_panic example)
        let moment = |axis: usize| match axis {
            0 => i1,
            1 => i2,
            _ => i3,
        };
        let ck = T::ONE / moment(k);
        Self {
            body,
            w: Vec3::new(T::ONE / moment(a) - ck, T::ONE / moment(b) - ck, T::ZERO),
            axes: [a, b, k],
            c: ck,
            h,
        }
    }
}

impl<T: Real> Integrator<T> for Splitting2<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        if !self.h.is_finite() {
            return Err(StepError::NonFinite);
        }
        let v = checked_momentum(m)?;
        let (h, hh) = (self.h, self.h * c::<T>(0.5));
        let [a, b, _] = self.axes;
        let v = rotate_momentum(v, a, self.w.x, hh);
        let v = rotate_momentum(v, b, self.w.y, h);
        let v = rotate_momentum(v, a, self.w.x, hh);
        *m = finish(v)?;
        Ok(())
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        if !self.h.is_finite() {
            return Err(StepError::NonFinite);
        }
        let (v, q) = checked_state(s)?;
        // h = 0 leaves the state as it is (the trait's promise; the step renormalised q)
        if self.h == T::ZERO {
            return Ok(());
        }
        let (h, hh) = (self.h, self.h * c::<T>(0.5));
        let [a, b, _] = self.axes;
        let (v, q) = rotate_state(v, q, a, self.w.x, hh);
        let (v, q) = rotate_state(v, q, b, self.w.y, h);
        let (v, q) = rotate_state(v, q, a, self.w.x, hh);
        // the Casimir: q (x) exp(c h m / 2), a rotation by c h |m| about m (body frame). The
        // axis is taken from `m` scaled by its largest component: `|m|^2` itself is subnormal
        // for f32 momenta below 1e-19 (and overflows above 1e19), and from its rounded root the
        // turn came out of unit length (`|q| = 1.063` at `|m| = 5e-23`, found in review)
        let big = v.max_abs();
        let q = if big > T::ZERO {
            // divided, not scaled by `1 / big`, which overflows for a subnormal `big`
            let u = Vec3::new(v.x / big, v.y / big, v.z / big);
            let nu = u.norm2().sqrt();
            let half = self.c * h * (big * nu) * c::<T>(0.5);
            let (sh, ch) = half.sin_cos();
            let k = sh / nu;
            compose_attitude(
                q,
                Quat {
                    w: ch,
                    x: u.x * k,
                    y: u.y * k,
                    z: u.z * k,
                },
            )
        } else {
            q
        };
        write_state(s, v, q)
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
