//! `Exact`: the exact flow of the free rigid body, momentum and attitude, in closed form
//! with Jacobi elliptic functions and the elliptic integral of the third kind
//! ([`crate::elliptic`]).
//!
//! # Momentum (Landau & Lifshitz, *Mechanics*, §37)
//!
//! Scale `m = |m| y` (`|y| = 1`), `I = I_max i`, time `s = t |m| / I_max`; then `y` solves the
//! same Euler equations with inertia `i`. Sort the axes `i_a <= i_b <= i_c = 1` and write
//! the invariants as sums of non-negative terms (no cancellation except the physical one in
//! `D_b`): `D_a = |y|^2 - 2E i_a = y_b^2 (i_b - i_a)/i_b + y_c^2 (1 - i_a) >= 0`,
//! `D_c = 2E - |y|^2 = y_a^2 (1 - i_a)/i_a + y_b^2 (1 - i_b)/i_b >= 0`,
//! `D_b = |y|^2 - 2E i_b = y_c^2 (1 - i_b) - y_a^2 (i_b - i_a)/i_a`.
//! In a right-handed relabelling `(p, r, d)` of the principal axes,
//! `y = (alpha cn tau, beta sn tau, gamma dn tau)`, `tau = omega s + tau_0`, where
//!
//! - `D_b >= 0` (rotation about the largest axis, `d = c`, `p = a`, `r = b`):
//!   `alpha^2 = D_c i_a/(1-i_a)`, `beta^2 = D_c i_b/(1-i_b)`, `gamma^2 = D_a/(1-i_a)`,
//!   `omega^2 = (1-i_b) D_a/(i_a i_b)`, `k^2 = (i_b-i_a) D_c/((1-i_b) D_a)`,
//!   `1 - k^2 = (1-i_a) D_b/((1-i_b) D_a)`;
//! - `D_b < 0` (rotation about the smallest axis, `d = a`, `p = c`, `r = b`):
//!   `alpha^2 = D_a/(1-i_a)`, `beta^2 = D_a i_b/(i_b-i_a)`, `gamma^2 = D_c i_a/(1-i_a)`,
//!   `omega^2 = (i_b-i_a) D_c/(i_a i_b)`, `k^2 = (1-i_b) D_a/((i_b-i_a) D_c)`,
//!   `1 - k^2 = (1-i_a)(-D_b)/((i_b-i_a) D_c)`.
//!
//! `alpha > 0`, `gamma` has the sign of `y_d` (which never changes), and Euler's equations fix
//! `sign beta = sign gamma` in the first case and `-sign gamma` in the second. `1 - k^2` is
//! computed from `D_b` directly, so `k -> 1` (the separatrix `D_b = 0`, where `sn = tanh`,
//! `cn = dn = sech`) keeps full accuracy. The phase `tau_0 = F(am, k)` comes from Carlson's
//! `R_F` with the quadrant of `(cn, sn)` at `t = 0`. (The 2008 paper of Celledoni, Fassò,
//! Säfström and Zanna, SIAM J. Sci. Comput. 30, 2084, states these cases with sign errata;
//! every sign here was checked numerically against an independent 34-digit integration.)
//! Symmetric bodies come out as `k = 0` (trigonometric); `m` on a principal axis, `m = 0`,
//! the sphere and `m` in the plane of two equal moments are steady rotations.
//!
//! # Attitude (after van Zon & Schofield, J. Comput. Phys. 225 (2007) 145)
//!
//! `pi = R m` is constant. Let `Q(t)` (body to an intermediate frame) have rows
//! `e1 = (u - (u.n) n)/|..|`, `e2 = n x e1`, `n = m/|m|`, with `u` the `d` axis, which the
//! orbit circles, so `Q` is smooth on the whole orbit. Then `R(t) Q(t)^T e_z = pi/|pi|` and
//! `R(t) = R(0) Q(0)^T Rz(psi(t) - psi(0)) Q(t)`, with (from `P = R Q^T`, `P^T P' = hat(Q Omega) +
//! Q Q'^T`) `psi' = n.Omega + e2.e1' = |m| (2E - m_d^2/I_d) / (|m|^2 - m_d^2)`. With
//! `|m|^2 - m_d^2 = |m|^2 alpha^2 (1 - nu sn^2)`, `nu = -gamma^2 k^2/alpha^2` (a constant of the
//! body: `-(i_b-i_a)/(i_a(1-i_b))`, resp. `-i_a(1-i_b)/(i_b-i_a)`), this integrates to
//!
//! `psi(s) - psi(0) = s / i_p + sigma (1-i_a)/(i_a omega) (nu/3) [S(tau) - S(tau_0)]`,
//!
//! `sigma = +1` (first case) or `-1`, `S(tau) = sn^3 R_J(cn^2, dn^2, 1, 1 - nu sn^2) + 2 j R_J(0, 1-k^2,
//! 1, 1 - nu)` for `tau = 2 j K + tau_r`, `|tau_r| <= K` (this is `(Pi(nu; am tau) - tau) 3/nu`,
//! DLMF 19.25.14). Where `-nu > 1` (a nearly symmetric body: `-nu` grows without bound as two
//! moments approach) `S` is nearly `-3 tau / nu`, a large linear part that cancels against
//! `s / i_p`; there the two linear parts are taken together exactly,
//! `psi(s) - psi(0) = s L + sigma (1-i_a)/(i_a omega) [Pi(nu; am tau) - Pi(nu; am tau_0)]`
//! with `L = 1` (first case) or `1 / i_a`, and `Pi` from Carlson's change of parameter of
//! `R_J`, three terms that do not cancel. The phase `tau = omega s + tau_0` is rounded
//! relative to `tau_0`, which is a long time when `omega` is small, so the angle's part moves
//! by its slope times what the sum dropped (TwoSum). `Q = Rz(pi) Ry(-theta) Rz(-chi)` with `(theta, chi)` the polar angles of `y`
//! about `d`; the quaternion is built from half angles, with `chi` lifted continuously
//! through the reduction by `2K`, so `q(t)` is continuous in `t` and `q(0) = q0`.
//!
//! # Accuracy and cost
//!
//! Against 34-digit references (tests/exact.rs: eight scenes, `t = 1, 10, 100`), `f64`:
//! `|m - m_ref| <= 3.2e-14 max(1, |m_ref|)` and `|q - q_ref| <= 3.7e-14` (up to the sign of `q`);
//! `f32`: within `1e-5` of the f64 solution from the same inputs for rotations up to about
//! 200 rad where the motion is not more sensitive than that to one f32 ulp of the inputs
//! (where it is, as much as that: 2.2e-5 after 85 rad on `I = (0.46, 0.34, 0.77)`, where an
//! ulp of any input moves the solution by 1.85e-5, found in review), beyond that about
//! `eps_f32 / 2` per radian turned (the phase itself is rounded: 5e-5 after 2000 rad).
//! Where these bounds do not hold (a first-use trial against a 30-digit integration of
//! Euler's equations and the attitude):
//! - near the separatrix (`E` near `|m|^2 / (2 I_mid)`) the orbit itself is ill-conditioned
//!   and the error is that of an ulp's change of the input (`E` `1e-8` off the separatrix:
//!   `1e-9` at `t = 30`, as much as one ulp of `m0` moves the true solution; in f32 errors of
//!   order one by then); exactly on it (`k = 1`) [`Exact::at`] and [`crate::Orbit::at`] refuse
//!   with `StepTooLarge` once the orbit's approach to the middle axis underflows, from about
//!   `lambda t = 370` in f64 (`lambda = |m| sqrt((1/I_a - 1/I_b)(1/I_b - 1/I_c))`: `t = 1755`
//!   for `I = (2, 3, 4)`, `m0 = (1, 0.5, sqrt 2)`; a review found the `t = 1e4` stated before
//!   wrong), while the momentum goes on;
//! - nearly symmetric bodies keep the bounds (tests/exact.rs
//!   `nearly_symmetric_bodies_keep_their_attitude`, against RK4: at most `4.5e-13` in f64 over
//!   seven bodies down to two moments an ulp apart, `I = (1e-8, 2, 2 + 1 ulp)` included, and
//!   `3.2e-7` in f32 for moments `1e-4` apart). Before the angle's linear parts were taken
//!   together (above) they cancelled: `1e-3` off for `I = (1e-8, 2, 2 + 1 ulp)` at every `t`
//!   (`3e-4` already at `t = 1e-6`), `3.4e-7` for `I = (0.1, 2, 2 + 1 ulp)` at `t = 10`, and
//!   `1.6e-4` in f32 for `I = (1, 2, 2.0001)` at `t = 0.01` (found in reviews);
//! - thin rods (`I_min / I_max` down to `1e-6`) are within the bounds or their own
//!   sensitivity to an ulp of a moment (tests/exact.rs `thin_rods_keep_their_attitude`:
//!   `2.3e-14` to `1.7e-11` against RK4, where one ulp of `I_max` moves the solution by `6e-12`
//!   to `3e-9`; before, `2.6e-9` for `I = (1e-6, 1 - 1e-6, 1)`, `m0 = (1e-7, 0.8, 0.6)` at
//!   `t = 10`, found in review).
//!
//! Cost (talk's case, `f64`; the README's flops and host-time tables): a momentum step 60
//! counted flops, 7 `sqrt`, 17 libm calls (one `sn, cn, dn`), about 0.4 us on x86-64; a step
//! with attitude 462 flops, 35 `sqrt`, 25 libm calls (plus one `R_J`, and where `-nu > 1`, as
//! on the talk's case, one `R_C`; a `sin`/`cos`), about
//! 0.7 us; a fresh [`Exact::at`] about 1.5 us (set-up: sorting, `K`, `R_F` for the phase, `R_J`
//! twice).

use crate::body::Body;
use crate::elliptic::{carlson_rf, carlson_rj, pi_negative, Jacobi};
use crate::error::StepError;
use crate::integrator::{
    checked_momentum, checked_state, checked_unit_state, compose_attitude, Integrator, State,
};
use crate::linalg::{Quat, Vec3};
use crate::real::{c, sq, Real};

/// A proper (right-handed) signed relabelling of the body axes: `prd_i = sign_i body[idx_i]`.
#[derive(Clone, Copy, Debug)]
struct Frame {
    idx: [u8; 3],
    neg: [bool; 3],
}

fn pick<T: Real>(v: Vec3<T>, i: u8) -> T {
    match i {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

impl Frame {
    fn prd<T: Real>(self, v: Vec3<T>) -> Vec3<T> {
        let [i0, i1, i2] = self.idx;
        let [n0, n1, n2] = self.neg;
        let s = |x: T, n: bool| if n { -x } else { x };
        Vec3::new(s(pick(v, i0), n0), s(pick(v, i1), n1), s(pick(v, i2), n2))
    }
    fn body<T: Real>(self, v: Vec3<T>) -> Vec3<T> {
        let mut out = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
        for (k, (&i, &n)) in self.idx.iter().zip(self.neg.iter()).enumerate() {
            let x = match k {
                0 => v.x,
                1 => v.y,
                _ => v.z,
            };
            let x = if n { -x } else { x };
            match i {
                0 => out.x = x,
                1 => out.y = x,
                _ => out.z = x,
            }
        }
        out
    }
}

/// One trajectory, set up from an initial state (public as [`crate::Orbit`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Orbit<T> {
    /// `|m|`.
    norm: T,
    /// `|m| / I_max`: scaled time per unit time.
    rate: T,
    motion: Motion<T>,
}

#[derive(Clone, Copy, Debug)]
enum Motion<T> {
    /// `m` constant, turning about the body axis `omega` at `|omega|` per unit scaled time.
    Steady {
        m: Vec3<T>,
        omega: Vec3<T>,
    },
    Tumbling(Tumble<T>),
}

#[derive(Clone, Copy, Debug)]
struct Tumble<T> {
    frame: Frame,
    jac: Jacobi<T>,
    /// Coefficients of `(cn, sn, dn)` in the `(p, r, d)` frame (`alpha > 0`).
    alpha: T,
    beta: T,
    gamma: T,
    /// Frequency in scaled time and phase at `t = 0`.
    omega: T,
    tau0: T,
    /// Separatrix orbit with `y_p < 0`: the solution is the one with `-alpha`, `-beta`.
    half_turn: bool,
    /// `nu`; whether the angle takes `Pi` itself (`-nu > 1`, [`Tumble::angle_part`]); the
    /// angle's part at a whole period (`R_J(0, 1 - k^2, 1, 1 - nu)`, or `Pi(nu)`), its
    /// coefficient (`sigma (1 - i_a)/(i_a omega) nu / 3`, or `sigma (1 - i_a)/(i_a omega)`)
    /// and its rate in scaled time (`1 / i_p`, or `1 / i_p - sigma (1 - i_a) / i_a`).
    nu: T,
    pi_form: bool,
    complete: T,
    coef: T,
    lin: T,
    head0: Quat<T>,
    s0: T,
}

/// What tells the two tumbling cases apart (the momentum circling the axis of largest
/// inertia, `|m|^2 > 2 E I_b`, or of smallest): the `(p, r, d)` frame and the squared
/// constants of the solution, each formed without cancellation from the sorted moments.
struct Case<T> {
    frame: Frame,
    /// `alpha^2`, `beta^2`, `gamma^2`: the squared coefficients of `(cn, sn, dn)`.
    alpha2: T,
    beta2: T,
    gamma2: T,
    /// The squared frequency in scaled time.
    omega2: T,
    /// The modulus `k^2` and its complement `1 - k^2`.
    k2: T,
    kc2: T,
    /// The characteristic `nu` of the third-kind integral of the attitude.
    nu: T,
    /// `1` about the largest axis, `-1` about the smallest.
    sigma: T,
    /// The moment of inertia `i_p` of the axis `p`.
    ip: T,
}

/// The state of a tumbling trajectory at phase `tau`: unit momentum in `(p, r, d)`, the
/// quaternion `qz(chi) qy(theta)`, the angle's part `S(tau)` or `Pi(nu; am tau)`
/// ([`Tumble::angle_part`]) and its derivative in `tau`.
struct Phase<T> {
    y: Vec3<T>,
    head: Quat<T>,
    s: T,
    slope: T,
}

/// `i^k`, `k` mod 4, as `(cos, sin)` of `k pi / 2`.
fn quarter_turns<T: Real>(k: i64) -> (T, T) {
    match k.rem_euclid(4) {
        0 => (T::ONE, T::ZERO),
        1 => (T::ZERO, T::ONE),
        2 => (-T::ONE, T::ZERO),
        _ => (T::ZERO, -T::ONE),
    }
}

impl<T: Real> Tumble<T> {
    fn phase(&self, tau: T, attitude: bool) -> Option<Phase<T>> {
        let (tr, j, j4) = self.jac.reduce(tau)?;
        let (sn, cn, dn) = self.jac.sncndn_reduced(tr);
        let turns = i64::from(j4) + i64::from(self.half_turn);
        let flip = if turns % 2 == 1 { -T::ONE } else { T::ONE };
        let (yp, yr) = (self.alpha * cn, self.beta * sn); // at the reduced phase
        let y = Vec3::new(flip * yp, flip * yr, self.gamma * dn);
        if !attitude {
            return Some(Phase {
                y,
                head: Quat::from_array([T::ONE, T::ZERO, T::ZERO, T::ZERO]),
                s: T::ZERO,
                slope: T::ZERO,
            });
        }
        let half = c::<T>(0.5);
        // azimuth chi about d: half angle of the reduced one (cos >= 0), then j half turns
        // in the sense of rotation (sign of beta)
        let rho = (sq(yp) + sq(yr)).sqrt();
        let ch = ((T::ONE + yp / rho) * half).sqrt();
        let sh = yr / rho * half / ch;
        let k = if self.beta < T::ZERO { -turns } else { turns };
        let (qc, qs) = quarter_turns::<T>(k);
        let (cchi, schi) = (ch * qc - sh * qs, ch * qs + sh * qc);
        // polar angle theta from d
        let yd = y.z;
        let (cth, sth) = if yd >= T::ZERO {
            let ct = ((T::ONE + yd) * half).sqrt();
            (ct, rho * half / ct)
        } else {
            let st = ((T::ONE - yd) * half).sqrt();
            (rho * half / st, st)
        };
        let head = Quat {
            w: cchi * cth,
            x: -schi * sth,
            y: cchi * sth,
            z: schi * cth,
        };
        let (s, slope) = self.angle_part(tr, j, (sn, cn, dn))?;
        Some(Phase { y, head, s, slope })
    }

    /// The part of the attitude's angle that is not linear in time, at the phase
    /// `tau = 2 j K + tau_r` (`sn, cn, dn` of `tau_r`), and its derivative in `tau`.
    ///
    /// `psi(s) - psi(0) = s / i_p + sigma (1 - i_a)/(i_a omega) (Pi(nu; am tau) - tau)` up to
    /// the value at `tau_0`. With `N = -nu >= 0` small, `Pi - tau = (nu / 3) S(tau)`,
    /// `S = sn^3 R_J(cn^2, dn^2, 1, 1 + N sn^2) + 2 j R_J(0, 1 - k^2, 1, 1 + N)`, a term with no
    /// large linear part. With `N` large (a nearly symmetric body, `N = 1e16` for two moments
    /// an ulp apart), `Pi` is `O(N^-1/2)` and `Pi - tau` nearly `-tau`: its linear part,
    /// `sigma (1 - i_a)/(i_a omega) tau`, then cancels against `s / i_p` (and so came from a
    /// rounded `tau` and a rounded `R_J`: attitudes `1e-3` off for `I = (1e-8, 2, 2 + 1 ulp)`,
    /// `1.6e-4` in f32 for `I = (1, 2, 2.0001)` at `t = 0.01`, found in review). For `N > 1`
    /// the linear parts are taken together exactly (`1 / i_p - sigma (1 - i_a) / i_a` is `1`
    /// about the largest axis, `1 / i_a` about the smallest) and `Pi` itself comes from the
    /// change of parameter of `R_J`, three terms that do not cancel
    /// (crate::elliptic::pi_negative).
    fn angle_part(&self, tr: T, j: T, (sn, cn, dn): (T, T, T)) -> Option<(T, T)> {
        if self.nu == T::ZERO {
            return Some((T::ZERO, T::ZERO));
        }
        let big_n = -self.nu;
        let sn2 = sq(sn);
        let rate = T::ONE / (T::ONE + big_n * sn2);
        let two_j = c::<T>(2.0) * j;
        if self.pi_form {
            let kc2 = self.jac.complement();
            let pi = pi_negative(big_n, tr, sn, cn, sq(dn), kc2)?;
            Some((pi + two_j * self.complete, rate))
        } else {
            let rj = carlson_rj(sq(cn), sq(dn), T::ONE, T::ONE + big_n * sn2)?;
            Some((
                sn2 * sn * rj + two_j * self.complete,
                c::<T>(3.0) * sn2 * rate,
            ))
        }
    }
}

impl<T: Real> Orbit<T> {
    pub(crate) fn new(body: &Body<T>, m: Vec3<T>, attitude: bool) -> Result<Self, StepError> {
        let big = m.max_abs();
        let inertia = Vec3::from_array(body.inertia());
        let imax = inertia.max_abs();
        if big == T::ZERO {
            let z = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
            return Ok(Self {
                norm: T::ZERO,
                rate: T::ZERO,
                motion: Motion::Steady { m, omega: z },
            });
        }
        // a subnormal |m| has no finite reciprocal: divided instead (it was refused as
        // Overflow where Mv steps it, found in a first-use trial)
        let inv = T::ONE / big;
        let v = if inv.is_finite() {
            m.scale(inv)
        } else {
            Vec3::new(m.x / big, m.y / big, m.z / big)
        };
        let len = v.norm2().sqrt();
        let norm = big * len;
        let rate = norm / imax;
        if !(norm.is_finite() && rate.is_finite()) {
            return Err(StepError::Overflow);
        }
        let y = v.scale(T::ONE / len);
        let i = inertia.scale(T::ONE / imax);
        let steady = Motion::Steady {
            m,
            omega: Vec3::new(y.x / i.x, y.y / i.y, y.z / i.z),
        };
        let tumble = Tumble::new(i, y, attitude);
        Ok(Self {
            norm,
            rate,
            motion: tumble.map_or(steady, Motion::Tumbling),
        })
    }

    /// Momentum and, when `q0` is given, attitude at time `t`.
    pub(crate) fn eval(
        &self,
        q0: Option<Quat<T>>,
        t: T,
    ) -> Result<(Vec3<T>, Option<Quat<T>>), StepError> {
        let s = self.rate * t;
        if !s.is_finite() {
            return Err(StepError::StepTooLarge);
        }
        match &self.motion {
            Motion::Steady { m, omega } => {
                let q = q0.map(|q0| {
                    let w2 = omega.norm2();
                    if w2 == T::ZERO {
                        return q0;
                    }
                    let w = w2.sqrt();
                    let a = s * w * c::<T>(0.5);
                    let v = omega.scale(a.sin() / w);
                    compose_attitude(q0, Quat::from_array([a.cos(), v.x, v.y, v.z]))
                });
                Ok((*m, q))
            }
            Motion::Tumbling(tb) => {
                let ws = tb.omega * s;
                let tau = ws + tb.tau0;
                let ph = tb.phase(tau, q0.is_some()).ok_or(StepError::StepTooLarge)?;
                let m = tb.frame.body(ph.y).scale(self.norm);
                let q = match q0 {
                    None => None,
                    Some(q0) => {
                        // what the phase's sum rounded away (TwoSum): m, the head and the
                        // angle's part are taken at the rounded phase, the angle's linear part
                        // at `s` itself, so the part moves by its slope times this (an ulp of
                        // `tau_0` is a long time when `omega` is small: attitudes 3e-4 off at
                        // `t = 1e-6`, found in review)
                        let back = tau - ws;
                        let lost = (ws - (tau - back)) + (tb.tau0 - back);
                        let dpsi = s * tb.lin + tb.coef * ((ph.s - tb.s0) + ph.slope * lost);
                        let a = dpsi * c::<T>(0.5);
                        let z = Quat::from_array([a.cos(), T::ZERO, T::ZERO, a.sin()]);
                        let tail = ph.head.conjugate();
                        let rel = tb.head0.mul(z).mul(tail);
                        let v = tb.frame.body(rel.vector());
                        Some(compose_attitude(
                            q0,
                            Quat::from_array([rel.w, v.x, v.y, v.z]),
                        ))
                    }
                };
                Ok((m, q))
            }
        }
    }
}

impl<T: Real> Tumble<T> {
    /// `None` for a steady rotation (or a trajectory too close to one to resolve). The
    /// attitude data (`R_J` terms, `Q(0)`) are set up only when `attitude` is asked for.
    fn new(i: Vec3<T>, y: Vec3<T>, attitude: bool) -> Option<Self> {
        // sort the axes by inertia, remembering the parity
        let mut ord = [0u8, 1, 2];
        let mut odd = false;
        for (a, b) in [(0usize, 1usize), (1, 2), (0, 1)] {
            let (ia, ib) = (ord.get(a).copied()?, ord.get(b).copied()?);
            if pick(i, ib) < pick(i, ia) {
                ord.swap(a, b);
                odd = !odd;
            }
        }
        let [xa, xb, xc] = ord;
        let (ia, ib, ic) = (pick(i, xa), pick(i, xb), pick(i, xc));
        let (ya, yb, yc) = (pick(y, xa), pick(y, xb), pick(y, xc));
        let (dba, dca, dcb) = (ib - ia, ic - ia, ic - ib);
        let da = sq(yb) * dba / ib + sq(yc) * dca / ic;
        let dc = sq(ya) * dca / ia + sq(yb) * dcb / ib;
        let db = sq(yc) * dcb / ic - sq(ya) * dba / ia;
        if !(da > T::ZERO && dc > T::ZERO) {
            return None;
        }
        let largest = db >= T::ZERO;
        let case = if largest {
            if !(dcb > T::ZERO) {
                return None;
            }
            let den = dcb * da;
            Case {
                frame: Frame {
                    idx: [xa, xb, xc],
                    neg: [false, odd, false],
                },
                alpha2: dc * ia / dca,
                beta2: dc * ib / dcb,
                gamma2: da / dca,
                omega2: dcb * da / (ia * ib),
                k2: dba * dc / den,
                kc2: dca * db / den,
                nu: -dba / (ia * dcb),
                sigma: T::ONE,
                ip: ia,
            }
        } else {
            if !(dba > T::ZERO) {
                return None;
            }
            let den = dba * dc;
            Case {
                frame: Frame {
                    idx: [xc, xb, xa],
                    neg: [false, !odd, false],
                },
                alpha2: da / dca,
                beta2: da * ib / dba,
                gamma2: dc * ia / dca,
                omega2: dba * dc / (ia * ib),
                k2: dcb * da / den,
                kc2: dca * (-db) / den,
                nu: -ia * dcb / dba,
                sigma: -T::ONE,
                ip: ic,
            }
        };
        let Case {
            frame,
            alpha2: a2,
            beta2: b2,
            gamma2: g2,
            omega2: w2,
            k2,
            kc2,
            nu,
            sigma,
            ip,
        } = case;
        let (alpha, beta, gamma, omega) = (a2.sqrt(), b2.sqrt(), g2.sqrt(), w2.sqrt());
        if !(alpha > T::ZERO && beta > T::ZERO && gamma > T::ZERO && omega > T::ZERO) {
            return None;
        }
        if !(alpha.is_finite() && beta.is_finite() && gamma.is_finite() && omega.is_finite()) {
            return None;
        }
        let yprd = frame.prd(y);
        let sd = if yprd.z < T::ZERO { -T::ONE } else { T::ONE };
        let gamma = gamma * sd;
        let beta = beta * sd * sigma;
        // phase at t = 0 from the quadrant of (cn, sn)
        let (x0, s0) = (yprd.x / alpha, yprd.y / beta);
        let r = (sq(x0) + sq(s0)).sqrt();
        let (mut cn0, sn0) = (x0 / r, s0 / r);
        let (k2, kc2) = (k2.min(T::ONE), kc2.max(T::ZERO).min(T::ONE));
        let jac = Jacobi::new(k2, kc2)?;
        let separatrix = kc2 == T::ZERO;
        let half_turn = separatrix && cn0 < T::ZERO;
        if half_turn {
            cn0 = -cn0;
        }
        let sn0 = if half_turn { -sn0 } else { sn0 };
        if separatrix && cn0 == T::ZERO {
            return None; // the unstable equilibrium on the middle axis
        }
        let dn0 = (kc2 + k2 * sq(cn0)).sqrt();
        let f = sn0 * carlson_rf(sq(cn0), sq(dn0), T::ONE)?;
        let tau0 = if cn0 >= T::ZERO {
            f
        } else {
            c::<T>(2.0) * jac.complete() * T::ONE.copysign(sn0) - f
        };
        // the angle's form (Tumble::angle_part) and its whole-period part
        let pi_form = -nu > T::ONE;
        let complete = if nu == T::ZERO || separatrix || !attitude {
            T::ZERO
        } else if pi_form {
            pi_negative(-nu, jac.complete(), T::ONE, T::ZERO, kc2, kc2)?
        } else {
            carlson_rj(T::ZERO, kc2, T::ONE, T::ONE - nu)?
        };
        let rate = sigma * (T::ONE - ia) / (ia * omega);
        let (coef, lin) = if pi_form {
            // 1 / i_p - sigma (1 - i_a) / i_a: 1 about the largest axis (i_p = i_a), and
            // 1 / i_a about the smallest (i_p = 1)
            (rate, if sigma > T::ZERO { T::ONE } else { T::ONE / ia })
        } else {
            (rate * nu / c::<T>(3.0), T::ONE / ip)
        };
        let mut tb = Self {
            frame,
            jac,
            alpha,
            beta,
            gamma,
            omega,
            tau0,
            half_turn,
            nu,
            pi_form,
            complete,
            coef,
            lin,
            head0: Quat::from_array([T::ONE, T::ZERO, T::ZERO, T::ZERO]),
            s0: T::ZERO,
        };
        if attitude {
            let p0 = tb.phase(tau0, true)?;
            tb.head0 = p0.head;
            tb.s0 = p0.s;
        }
        Some(tb)
    }
}

/// The exact solution of the free rigid body (momentum and attitude), as an integrator.
///
/// `step` and `step_state` advance by the exact flow over `h` (Jacobi elliptic functions for
/// `m`, Landau & Lifshitz §37; Carlson's `R_J` for the attitude's angle, after van Zon &
/// Schofield 2007; docs/MATH.md §6). The trajectory is set up once from the state the integrator first sees and
/// each step evaluates it at `n h`, so stepping has no error accumulation at all: `n` steps
/// agree with [`Exact::at`] at `n h` to round-off. If the caller changes the state between
/// steps, or after `2^20` steps, the trajectory is set up again from the current state.
/// `h` may be negative (backwards in time). A step's errors are those of [`Exact::at`].
///
/// Accuracy (f64, against 34-digit references on eight scenes up to `t = 100`,
/// tests/exact.rs): `|m - m_ref| <= 3.2e-14 max(1, |m_ref|)`, `|q - q_ref| <= 3.7e-14`; f32
/// within `1e-5` of f64's solution for rotations up to about 200 rad, then about `eps / 2`
/// per radian turned. Worse, as [`Exact::at`] states: near the separatrix (as sensitive as the
/// orbit itself), and on a thin rod as much as an ulp of its moments moves the solution.
#[derive(Clone, Debug)]
pub struct Exact<T> {
    body: Body<T>,
    h: T,
    cache: Option<Cache<T>>,
}

#[derive(Clone, Copy, Debug)]
struct Cache<T> {
    orbit: Orbit<T>,
    /// Attitude at the start of the trajectory (`None` for momentum-only stepping).
    q0: Option<Quat<T>>,
    steps: T,
    last_m: [T; 3],
    last_q: [T; 4],
}

/// Steps before the trajectory is set up afresh (keeps `n` exact in `f32`).
const REBASE: f64 = 1_048_576.0;

impl<T: Real> Exact<T> {
    /// An integrator for `body` stepping by `h`.
    #[must_use]
    pub fn new(body: Body<T>, h: T) -> Self {
        Self {
            body,
            h,
            cache: None,
        }
    }

    /// The exact state at time `t` (any sign) from `s0`. The quaternion is continuous in `t`
    /// and equals `s0.q` (normalised) at `t = 0`.
    ///
    /// Accuracy (f64, tests/exact.rs against 34-digit references, `t` up to 100):
    /// `|m - m_ref| <= 3.2e-14 max(1, |m_ref|)` and `|q - q_ref| <= 3.7e-14` up to the sign of
    /// `q`; f32 within `1e-5` of the f64 solution from the same inputs for rotations up to about
    /// 200 rad (or as much as one f32 ulp of the input moves the motion, where that is more),
    /// then about `eps / 2` per radian turned. Near the separatrix (`E` near
    /// `|m|^2 / (2 I_mid)`) the error is that of an ulp's change of the input (the orbit is
    /// that sensitive); nearly symmetric bodies keep the bounds (two moments an ulp apart
    /// included: at most `4.5e-13` in f64 against RK4); for a thin rod see the module docs
    /// (within its own sensitivity to an ulp of a moment). Exactly on the separatrix it refuses with `StepTooLarge` once the orbit's
    /// approach to the middle axis underflows, from about `lambda t = 370` in f64 (`lambda =
    /// |m| sqrt((1/I_a - 1/I_b)(1/I_b - 1/I_c))`, its rate: `t = 1755` for `I = (2, 3, 4)`,
    /// `m0 = (1, 0.5, sqrt 2)`), while [`Exact::momentum_at`] goes on.
    ///
    /// # Errors
    ///
    /// [`StepError::NonFinite`] for a non-finite state or `t` or a zero quaternion,
    /// [`StepError::StepTooLarge`] when the phase `omega t` is past what the float type can
    /// represent (about `1 / (8 eps)` periods of the momentum: `5.6e14` in f64, `1.05e6` in
    /// f32), [`StepError::Overflow`] when the result would
    /// overflow, and [`StepError::Degenerate`] when the elliptic functions cannot be
    /// evaluated for this orbit.
    pub fn at(body: &Body<T>, s0: &State<T>, t: T) -> Result<State<T>, StepError> {
        if !t.is_finite() {
            return Err(StepError::NonFinite);
        }
        crate::orbit::Orbit::new(body, s0)?.at(t)
    }

    /// The exact body momentum at time `t` (any sign) from `m0`: one `sn, cn, dn` after the
    /// set-up. Accuracy as [`Exact::at`]'s for `m` (f64 `3.2e-14 max(1, |m|)`).
    ///
    /// # Errors
    ///
    /// As [`Exact::at`] (without the quaternion's).
    pub fn momentum_at(body: &Body<T>, m0: &[T; 3], t: T) -> Result<[T; 3], StepError> {
        let m = checked_momentum(m0)?;
        if !t.is_finite() {
            return Err(StepError::NonFinite);
        }
        let (m, _) = Orbit::new(body, m, false)?.eval(None, t)?;
        finish(m, None).map(|(m, _)| m)
    }

    fn advance(&mut self, m: &[T; 3], q: Option<[T; 4]>) -> Result<([T; 3], [T; 4]), StepError> {
        if !self.h.is_finite() {
            return Err(StepError::NonFinite);
        }
        // a zero step leaves the state as it is ([`Integrator::set_step_size`]) and the
        // trajectory where it was; evaluated at `t = 0` of a rebuilt trajectory it moved `m` by
        // an ulp (1.1e-16 over 1000 paused steps, found by a first-use trial)
        if self.h == T::ZERO {
            return match q {
                Some(q) => checked_state(&State::new(*m, q)).map(|_| (*m, q)),
                None => checked_momentum(m).map(|_| (*m, [T::ONE, T::ZERO, T::ZERO, T::ZERO])),
            };
        }
        let reuse = match &self.cache {
            Some(cc) => {
                cc.last_m == *m
                    && q.is_some() == cc.q0.is_some()
                    && q.is_none_or(|q| q == cc.last_q)
                    && cc.steps < c::<T>(REBASE)
            }
            None => false,
        };
        let mut cache = match (reuse, self.cache) {
            (true, Some(cc)) => cc,
            _ => {
                let (mv, qv) = match q {
                    Some(q) => {
                        // a new trajectory starts from a unit attitude: past half a turn a
                        // step (`cos(theta / 2) < 0`) scales an error of `|q0|` by up to
                        // `1 - cos(theta / 2)`; rebuilt from its own output at every change of
                        // `h`, a tumble at 5 rad a step grew `|q| - 1` 1.8x a step to 8.6e-4
                        let (mv, qv) = checked_unit_state(&State::new(*m, q))?;
                        (mv, Some(qv))
                    }
                    None => (checked_momentum(m)?, None),
                };
                Cache {
                    orbit: Orbit::new(&self.body, mv, qv.is_some())?,
                    q0: qv,
                    steps: T::ZERO,
                    last_m: *m,
                    last_q: q.unwrap_or([T::ZERO; 4]),
                }
            }
        };
        let steps = cache.steps + T::ONE;
        let (mn, qn) = cache.orbit.eval(cache.q0, steps * self.h)?;
        let (mn, qn) = finish(mn, qn)?;
        cache.steps = steps;
        cache.last_m = mn;
        cache.last_q = qn;
        self.cache = Some(cache);
        Ok((mn, qn))
    }
}

/// Final check: finite output, or an error (the caller's state stays untouched).
pub(crate) fn finish<T: Real>(
    m: Vec3<T>,
    q: Option<Quat<T>>,
) -> Result<([T; 3], [T; 4]), StepError> {
    let q = q.unwrap_or(Quat::from_array([T::ONE, T::ZERO, T::ZERO, T::ZERO]));
    if m.is_finite() && q.is_finite() {
        Ok((m.to_array(), q.to_array()))
    } else {
        Err(StepError::Degenerate)
    }
}

impl<T: Real> Integrator<T> for Exact<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        let (mn, _) = self.advance(m, None)?;
        *m = mn;
        Ok(())
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        let (mn, qn) = self.advance(&s.m, Some(s.q))?;
        s.m = mn;
        s.q = qn;
        Ok(())
    }

    fn step_size(&self) -> T {
        self.h
    }

    /// The same `h` as before changes nothing (a loop that sets a measured `dt` every tick:
    /// dropping the cache made the next step differ by an ulp, found in review).
    fn set_step_size(&mut self, h: T) {
        if h == self.h {
            return;
        }
        self.h = h;
        self.cache = None;
    }

    fn body(&self) -> &Body<T> {
        &self.body
    }

    fn reset(&mut self) {
        self.cache = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separatrix_branch_is_exercised() {
        // tests/exact.rs checks this case against RK4; here: it really takes the k = 1 branch
        let body = Body::<f64>::from_inertia([2.0, 3.0, 4.0]).unwrap();
        for m in [
            [1.0, 0.5, core::f64::consts::SQRT_2],
            [-1.0, 0.5, core::f64::consts::SQRT_2],
        ] {
            let orbit = Orbit::new(&body, Vec3::from_array(m), true).unwrap();
            match orbit.motion {
                Motion::Tumbling(tb) => assert!(tb.jac.is_hyperbolic()),
                Motion::Steady { .. } => panic!("steady"),
            }
        }
        let orbit = Orbit::new(&body, Vec3::new(0.0, 1.3, 0.0), true).unwrap();
        assert!(matches!(orbit.motion, Motion::Steady { .. }));
    }
}
