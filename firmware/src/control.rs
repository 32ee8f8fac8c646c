//! The attitude controller: PD toward nadir pointing, by momentum exchange with three reaction
//! wheels along the principal axes (wheel torque = - control torque, wheel momentum integrated
//! over the measured period and saturated).

use crate::math::{conj, error_vector, rotate};
use crate::scene::{CTRL_W, CTRL_Z, TORQUE_MAX, WHEEL_MAX};
use rigid3::Real;

/// The nadir-pointing target (principal frame to space) from the orbit angle's `(cos a, sin a)`:
/// the rotation by `a` about the orbit normal, `(1 + cos a, 0, 0, sin a)` normalised (no trig).
pub fn target(orbit: (f32, f32)) -> [f32; 4] {
    let (c, s) = orbit;
    let n = Real::sqrt((1.0 + c) * (1.0 + c) + s * s);
    if n > 1e-6 {
        [(1.0 + c) / n, 0.0, 0.0, s / n]
    } else {
        [0.0, 0.0, 0.0, 1.0]
    }
}

/// One controller tick: from the estimated state, the new wheel momenta (principal frame).
/// Returns `(wheels, commanded body torque)`.
#[inline(never)]
pub fn control(
    q: [f32; 4],
    m: [f32; 3],
    wheels: [f32; 3],
    inertia: [f32; 3],
    orbit: (f32, f32),
    n: f32,
    dt: f32,
) -> ([f32; 3], [f32; 3]) {
    let e = error_vector(target(orbit), q);
    let w_t = rotate(conj(q), [0.0, 0.0, n]);
    let mut out = wheels;
    let mut tau = [0.0f32; 3];
    for k in 0..3 {
        let w = (m[k] - wheels[k]) / inertia[k];
        let t = -inertia[k] * (CTRL_W * CTRL_W * e[k] + 2.0 * CTRL_Z * CTRL_W * (w - w_t[k]));
        let t = t.clamp(-TORQUE_MAX, TORQUE_MAX);
        out[k] = (wheels[k] - t * dt).clamp(-WHEEL_MAX, WHEEL_MAX);
        tau[k] = (wheels[k] - out[k]) / dt;
    }
    (out, tau)
}
