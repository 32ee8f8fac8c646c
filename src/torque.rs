//! Torque models for the forced rigid body: what the kick of a kick–drift–kick step applies.
//!
//! A model gives the body-frame torque `tau(t, q)` at time `t` and attitude `q` (`(w, x, y, z)`,
//! body to space). A torque that depends on `q` only (not on `m`) makes the kick
//! `m <- m + (h/2) tau` the exact flow of the potential part, which is what keeps the splitting
//! symplectic for a potential `V(q)`. Where a model derives from a potential it says so through
//! [`Torque::potential`], so integrators can report the total energy.
//!
//! With `Gamma = R(q)^T e` the body-frame image of a fixed spatial direction `e`, a potential
//! `V(Gamma)` exerts the body torque `tau = Gamma x dV/dGamma` (a virtual rotation `R -> R
//! exp(hat xi)` moves `Gamma` by `-xi x Gamma`, and `dV = -tau . xi`).

use crate::linalg::{Quat, Vec3};
use crate::real::{c, Real};
use crate::sincos::sin_cos_or_nan;

/// A body-frame torque as a function of time and attitude.
///
/// Implementations must be pure (the same `(t, q)` gives the same torque): the integrators
/// reuse the last evaluation of a step at the start of the next one when `t` and `q` are
/// unchanged. A non-finite torque makes the step return `StepError::NonFinite`, the state
/// and the time left as they were; a torque at the step's end is known only after the drift
/// has stepped, so then the drift's own trajectory has moved on (its tracked root and anchor)
/// and the next step starts it again from the state: the steps after such a refusal agree
/// with those of a loop that never saw it to round-off, not bit for bit (a model that
/// returned NaN every 7th tick over `2 x 10^5` ticks: `|m|^2` and `E` 3.6e-14 off, against
/// 1.5e-15 without; saving the drift to restore it would cost every step a copy of it;
/// found in review).
pub trait Torque<T> {
    /// The torque in the body frame at time `t` and attitude `q = (w, x, y, z)` (unit,
    /// body to space).
    fn torque(&self, t: T, q: &[T; 4]) -> [T; 3];

    /// The potential energy `V(t, q)` whose torque this is, if there is one (`None` for
    /// non-conservative torques). Used only for reporting the total energy.
    fn potential(&self, _t: T, _q: &[T; 4]) -> Option<T> {
        None
    }

    /// Whether the torque depends on the attitude. Momentum-only stepping (`step`) is refused
    /// with `StepError::NeedsAttitude` for models that do.
    fn depends_on_attitude(&self) -> bool {
        true
    }

    /// Whether the torque is identically zero (then `|m|^2` is an invariant, and the forced
    /// integrators hold it at round-off across the rotor's turns).
    fn is_zero(&self) -> bool {
        false
    }

    /// The torque's rate of change as the body turns at the body-frame angular velocity `w`,
    /// `d/ds tau(t, q (x) exp(s w / 2))` at `s = 0`, where the model has it in closed form.
    /// The force-gradient kick of [`crate::Composed::force_gradient`] needs it; where this is
    /// `None` it takes it from one more evaluation at a slightly turned attitude (accurate to
    /// the scheme's order, but then the step is symplectic only to `O(h^5)`). The default: zero
    /// for a model that does not depend on the attitude, else `None`.
    fn turn_rate(&self, _t: T, _q: &[T; 4], _w: [T; 3]) -> Option<[T; 3]>
    where
        T: Real,
    {
        if self.depends_on_attitude() {
            None
        } else {
            Some([T::ZERO; 3])
        }
    }
}

/// No torque: the free body (with a rotor, a free gyrostat).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NoTorque;

impl<T: Real> Torque<T> for NoTorque {
    fn torque(&self, _t: T, _q: &[T; 4]) -> [T; 3] {
        [T::ZERO; 3]
    }
    fn potential(&self, _t: T, _q: &[T; 4]) -> Option<T> {
        Some(T::ZERO)
    }
    fn depends_on_attitude(&self) -> bool {
        false
    }
    fn is_zero(&self) -> bool {
        true
    }
}

/// A constant body-frame torque (a thruster or magnetorquer command held over the step).
/// Exact (no arithmetic). Not conservative, so it has no potential, except the zero torque:
/// its potential is zero and it is [`Torque::is_zero`], so a sum with it keeps the other
/// part's total energy and a torque-free step with a rotor holds `|m|^2` and `R(q) m` (in f64;
/// in f32 it carries the state's rounding instead, [`crate::Forced`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ConstantTorque<T>(pub [T; 3]);

impl<T: Real> Torque<T> for ConstantTorque<T> {
    fn torque(&self, _t: T, _q: &[T; 4]) -> [T; 3] {
        self.0
    }
    fn potential(&self, _t: T, _q: &[T; 4]) -> Option<T> {
        self.is_zero().then_some(T::ZERO)
    }
    fn depends_on_attitude(&self) -> bool {
        false
    }
    fn is_zero(&self) -> bool {
        let [a, b, c] = self.0;
        a == T::ZERO && b == T::ZERO && c == T::ZERO
    }
}

/// A periodic body-frame torque `tau_i(t) = A_i cos(W_i t + P_i)`.
///
/// Three cosines per evaluation, by the crate's own reduction and polynomial (absolute error at
/// most `1.5 eps` for `|W_i t + P_i|` up to 6.6e6 rad in f32 and `3.5e15` in f64; about 70
/// instructions each on a Cortex-M4F up to 6000 rad, where libm's `cosf` computes in double in
/// software, about 2000; no libm is linked). Beyond, where an ulp of the angle is a quarter
/// radian or more, the torque is NaN and a forced step refuses it (`NonFinite`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PeriodicTorque<T> {
    /// Amplitudes `A`.
    pub amplitude: [T; 3],
    /// Angular frequencies `W` (rad per unit time).
    pub freq: [T; 3],
    /// Phases `P` (rad).
    pub phase: [T; 3],
}

impl<T: Real> Torque<T> for PeriodicTorque<T> {
    fn torque(&self, t: T, _q: &[T; 4]) -> [T; 3] {
        let [a1, a2, a3] = self.amplitude;
        let [w1, w2, w3] = self.freq;
        let [p1, p2, p3] = self.phase;
        [
            a1 * sin_cos_or_nan(w1 * t + p1).1,
            a2 * sin_cos_or_nan(w2 * t + p2).1,
            a3 * sin_cos_or_nan(w3 * t + p3).1,
        ]
    }
    fn depends_on_attitude(&self) -> bool {
        false
    }
}

/// Uniform gravity about a fixed point: the heavy top.
///
/// `V = mg <R(q) chi, e_z>` with `chi` the centre of mass in the body frame and `e_z` the
/// spatial vertical (up), so `tau = mg (Gamma x chi)`, `Gamma = R(q)^T e_z`
/// (Holm, Geometric Mechanics I, §2.4). The vertical spatial momentum `e_z . R(q) m` is
/// conserved by the flow, and exactly by the kick (`Gamma . tau = 0`) and by the DMV drift
/// (with a rotor, by the turns too; a fast wheel's relative splitting keeps it to `O(h^2)`,
/// crate::forced's docs).
/// About 20 flops per evaluation, no transcendental call.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Gravity<T> {
    /// Weight times distance scale: `M g` (torque = `M g` times a length in `chi`'s units).
    pub mg: T,
    /// Centre of mass in the body frame, from the fixed point.
    pub com: [T; 3],
}

/// `Gamma = R(q)^T e_z`: the third row of `R(q)`.
#[inline]
fn vertical_in_body<T: Real>(q: &[T; 4]) -> Vec3<T> {
    let [w, x, y, z] = *q;
    let two = c::<T>(2.0);
    Vec3::new(
        two * (x * z - w * y),
        two * (y * z + w * x),
        T::ONE - two * (x * x + y * y),
    )
}

impl<T: Real> Torque<T> for Gravity<T> {
    fn torque(&self, _t: T, q: &[T; 4]) -> [T; 3] {
        let gamma = vertical_in_body(q);
        gamma
            .cross(Vec3::from_array(self.com))
            .scale(self.mg)
            .to_array()
    }
    fn potential(&self, _t: T, q: &[T; 4]) -> Option<T> {
        Some(self.mg * vertical_in_body(q).dot(Vec3::from_array(self.com)))
    }
    /// `mg (Gamma x w) x chi`: turning the body by `s w` moves `Gamma` by `s Gamma x w`.
    fn turn_rate(&self, _t: T, q: &[T; 4], w: [T; 3]) -> Option<[T; 3]> {
        let gamma = vertical_in_body(q);
        Some(
            gamma
                .cross(Vec3::from_array(w))
                .cross(Vec3::from_array(self.com))
                .scale(self.mg)
                .to_array(),
        )
    }
}

/// Gravity gradient in a circular orbit whose nadir direction turns at the orbit rate.
///
/// `tau = 3 K (r x I r)`, `r = R(q)^T (cos N t, sin N t, 0)`, from the potential
/// `V = (3K/2) r . I r` (the quadrupole term of `-mu/|R + rho|` integrated over the body;
/// `K = mu / R^3 = N^2` for a Keplerian circular orbit; Hughes, Spacecraft Attitude Dynamics,
/// §8.2). The orbit is in the spatial x–y plane. One `sin`/`cos` pair per evaluation, by the
/// crate's own reduction and polynomials, no libm (absolute error at most `1.5 eps` for `|N t|`
/// up to 6.6e6 rad in f32, 180 years of a 90-minute orbit, and `3.5e15` in f64; beyond, where
/// an ulp of the angle is a quarter radian or more, the torque is NaN and a forced step refuses
/// it with `NonFinite`; about 70 M4F instructions up to 6000 rad, 64 days, 206
/// beyond). That
/// bound is for the argument as formed: `N t` carries the rounding of `t` itself, an ulp of
/// which is 0.5 s at 64 days in f32 (`t = 5.5e6 s`), so the nadir direction is then good to
/// `N ulp(t)`, about `5e-4` rad (the torque measured `7e-4` relative off its f64 value there,
/// `1.3e-4` at `1e6 s`). A long f32 mission keeps `t` small: re-base it with
/// [`crate::Forced::set_time`] once per orbit (the torque is periodic in `t` with period
/// `2 pi / N`; each re-base by the rounded period moves the phase by `N P - 2 pi`,
/// 2.6e-7 to `4e-7` rad in f32 with `P = 5700 s`, as `N` was rounded), or runs the clock in
/// f64. `inertia` must be the integrated body's principal
/// moments (`body.inertia()`, not the diagonal of an inertia tensor with products of
/// inertia): [`GravityGradient::circular`] takes them from the body. It is not checked
/// against the integrator's body.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GravityGradient<T> {
    /// `K = mu / R^3`.
    pub k: T,
    /// Orbit rate `N` (rad per unit time).
    pub n: T,
    /// Principal moments of inertia of the body.
    pub inertia: [T; 3],
}

impl<T: Real> GravityGradient<T> {
    /// The gravity gradient of a Keplerian circular orbit of rate `n` (`K = N^2`) on `body`,
    /// with the body's principal moments (the frame every torque of the integrator is in).
    #[must_use]
    pub fn circular(body: &crate::Body<T>, n: T) -> Self {
        Self {
            k: n * n,
            n,
            inertia: body.inertia(),
        }
    }

    /// `r = R(q)^T (cos N t, sin N t, 0)`.
    #[inline]
    fn nadir(&self, t: T, q: &[T; 4]) -> Vec3<T> {
        let (sin, cos) = sin_cos_or_nan(self.n * t);
        let n = Vec3::new(cos, sin, T::ZERO);
        Quat::from_array(*q).inverse_rotate(n)
    }
}

impl<T: Real> Torque<T> for GravityGradient<T> {
    fn torque(&self, t: T, q: &[T; 4]) -> [T; 3] {
        let r = self.nadir(t, q);
        let ir = r.mul_elem(Vec3::from_array(self.inertia));
        r.cross(ir).scale(c::<T>(3.0) * self.k).to_array()
    }
    fn potential(&self, t: T, q: &[T; 4]) -> Option<T> {
        let r = self.nadir(t, q);
        let ir = r.mul_elem(Vec3::from_array(self.inertia));
        Some(c::<T>(1.5) * self.k * r.dot(ir))
    }
    /// `3K ((r x w) x I r + r x I (r x w))`: turning the body by `s w` moves `r` by
    /// `s r x w`.
    fn turn_rate(&self, t: T, q: &[T; 4], w: [T; 3]) -> Option<[T; 3]> {
        let inertia = Vec3::from_array(self.inertia);
        let r = self.nadir(t, q);
        let dr = r.cross(Vec3::from_array(w));
        let rate = dr
            .cross(r.mul_elem(inertia))
            .add(r.cross(dr.mul_elem(inertia)));
        Some(rate.scale(c::<T>(3.0) * self.k).to_array())
    }
}

/// A closure `Fn(t, &q) -> tau` as a torque model (non-conservative, attitude-dependent).
#[derive(Clone, Copy, Debug)]
pub struct FnTorque<F>(pub F);

impl<T: Real, F: Fn(T, &[T; 4]) -> [T; 3]> Torque<T> for FnTorque<F> {
    fn torque(&self, t: T, q: &[T; 4]) -> [T; 3] {
        (self.0)(t, q)
    }
}

/// The sum of two models (nest pairs for more). Its potential is the sum of the parts'; `None`
/// (no total energy) when either part has none (a zero part has potential zero: a
/// [`ConstantTorque`] of zero added to a gravity gradient keeps the total energy). It is zero,
/// depends on the attitude and has a turn rate when both parts are, either does, and both have.
impl<T: Real, A: Torque<T>, B: Torque<T>> Torque<T> for (A, B) {
    fn torque(&self, t: T, q: &[T; 4]) -> [T; 3] {
        let [a1, a2, a3] = self.0.torque(t, q);
        let [b1, b2, b3] = self.1.torque(t, q);
        [a1 + b1, a2 + b2, a3 + b3]
    }
    fn potential(&self, t: T, q: &[T; 4]) -> Option<T> {
        Some(self.0.potential(t, q)? + self.1.potential(t, q)?)
    }
    fn depends_on_attitude(&self) -> bool {
        self.0.depends_on_attitude() || self.1.depends_on_attitude()
    }
    fn is_zero(&self) -> bool {
        self.0.is_zero() && self.1.is_zero()
    }
    fn turn_rate(&self, t: T, q: &[T; 4], w: [T; 3]) -> Option<[T; 3]> {
        let [a1, a2, a3] = self.0.turn_rate(t, q, w)?;
        let [b1, b2, b3] = self.1.turn_rate(t, q, w)?;
        Some([a1 + b1, a2 + b2, a3 + b3])
    }
}
