//! The flight estimators (all f32, principal frame; the sensors speak the sensor frame):
//!
//! - [`Complementary`] (gyro mode): momentum blended toward the gyro's `I (w - b) + h_w`, attitude
//!   and gyro bias corrected at each star-tracker fix, propagated between ticks by the forced
//!   `Mv` step (wheels as the rotor, the gravity gradient as the torque model);
//! - [`Ekf`] (gyro-less mode): a multiplicative EKF on `(dm, dtheta)` (body momentum 3, then the
//!   body-frame attitude error of `q = q^ (x) exp(dtheta / 2)`, the order and coordinates of
//!   `rigid3::tangent`), propagated by the same forced `Mv` step with the measured period, its
//!   covariance by the step's 6x6 Jacobian from [`transition`], updated at star-tracker fixes.

use crate::math::{conj, cross, error_vector, qmul, rotate, small_rotation};
use rigid3::torque::Torque;
use rigid3::{Body, Forced, Integrator, Mv, Real, State, StepError};

/// Gravity gradient for the flight software: [`rigid3::GravityGradient`]'s torque
/// `3 K (r x I r)`, `r = R(q)^T (cos N t, sin N t, 0)`, with the orbit angle taken from
/// `(cos, sin)` at the start of the tick (set each tick from the clock, one `sinf`/`cosf` pair a
/// tick) and advanced within the step by its Taylor series (`N h` is 6e-6 rad: exact in f32),
/// instead of a `sinf`/`cosf` pair per evaluation (about 2400 instructions on the M4F).
#[derive(Clone, Copy, Debug)]
pub struct Gg {
    pub k: f32,
    pub n: f32,
    pub inertia: [f32; 3],
    pub cos0: f32,
    pub sin0: f32,
}

impl Gg {
    /// The nadir in the body frame at time `t` since the tick's start, attitude `q`.
    #[inline]
    pub fn nadir(&self, t: f32, q: &[f32; 4]) -> [f32; 3] {
        let d = self.n * t;
        let c1 = 1.0 - 0.5 * d * d;
        let n = [
            self.cos0 * c1 - self.sin0 * d,
            self.sin0 * c1 + self.cos0 * d,
            0.0,
        ];
        rotate(conj(*q), n)
    }
}

impl Torque<f32> for Gg {
    fn torque(&self, t: f32, q: &[f32; 4]) -> [f32; 3] {
        let r = self.nadir(t, q);
        let ir = [
            r[0] * self.inertia[0],
            r[1] * self.inertia[1],
            r[2] * self.inertia[2],
        ];
        cross(r, ir).map(|x| 3.0 * self.k * x)
    }
}

pub type Propagator = Forced<f32, Mv<f32>, Gg>;

/// The forced `Mv` propagator of both estimators.
pub fn propagator(body: Body<f32>, h: f32, gg: Gg) -> Propagator {
    Forced::new(Mv::new(body, h), gg)
}

/// One tick of the propagator: the measured period, the wheels' momentum (known from their
/// tachometers), the orbit angle's `(cos, sin)` now; the model's time restarts at 0 each tick.
#[inline(never)]
pub fn tick(
    f: &mut Propagator,
    s: &mut State<f32>,
    dt: f32,
    wheels: [f32; 3],
    orbit: (f32, f32),
) -> Result<(), StepError> {
    f.set_step_size(dt);
    f.set_rotor(wheels)?;
    let g = f.torque_mut();
    g.cos0 = orbit.0;
    g.sin0 = orbit.1;
    f.set_time(0.0);
    f.step_state(s)
}

// ---------------------------------------------------------------- complementary filter

/// Gains: momentum blend per tick, attitude per fix, bias per fix.
const K_M: f32 = 0.02;
const K_Q: f32 = 0.3;
const K_B: f32 = 0.05;

/// Complementary filter around the forced `Mv` propagation (gyro mode).
///
/// - momentum: `m <- m + K_M (I (w_gyro - b) + h_w - m)` every tick;
/// - attitude: at each fix, the body-frame error rotation `theta` is fed back as
///   `q <- q (x) exp(K_Q theta / 2)`;
/// - bias: `b <- b - K_B theta / T_fix`.
pub struct Complementary {
    pub f: Propagator,
    pub s: State<f32>,
    pub bias: [f32; 3],
    pub inertia: [f32; 3],
    pub frame: [f32; 4],
}

impl Complementary {
    pub fn init(&mut self, star_sensor: [f32; 4], gyro_sensor: [f32; 3], wheels: [f32; 3]) {
        self.s.q = qmul(star_sensor, self.frame);
        let wp = rotate(conj(self.frame), gyro_sensor);
        self.s.m = [0, 1, 2].map(|k| self.inertia[k] * wp[k] + wheels[k]);
    }

    #[inline(never)]
    pub fn propagate(
        &mut self,
        gyro_sensor: [f32; 3],
        dt: f32,
        wheels: [f32; 3],
        orbit: (f32, f32),
    ) -> Result<(), StepError> {
        let w = [0, 1, 2].map(|k| gyro_sensor[k] - self.bias[k]);
        let wp = rotate(conj(self.frame), w);
        for k in 0..3 {
            let mg = self.inertia[k] * wp[k] + wheels[k];
            self.s.m[k] += K_M * (mg - self.s.m[k]);
        }
        tick(&mut self.f, &mut self.s, dt, wheels, orbit)
    }

    #[inline(never)]
    pub fn correct(&mut self, star_sensor: [f32; 4], interval: f32) {
        let meas = qmul(star_sensor, self.frame);
        let theta = error_vector(self.s.q, meas);
        self.s.q = qmul(self.s.q, small_rotation(theta.map(|x| K_Q * x)));
        let tb = rotate(self.frame, theta);
        for k in 0..3 {
            self.bias[k] -= K_B * tb[k] / interval;
        }
    }
}

// ---------------------------------------------------------------- EKF

pub type M6 = [[f32; 6]; 6];

/// Process noise: unmodelled torque (N m per sqrt(s)) and attitude (rad per sqrt(s)).
const Q_TORQUE: f32 = 1e-5;
const Q_ATT: f32 = 1e-6;

/// The step's Jacobian `F = d(m', dtheta') / d(m, dtheta)` (6x6, row-major, momentum first, then
/// the body-frame attitude error of `q = q^ (x) exp(dtheta / 2)`: `rigid3::tangent`'s
/// coordinates) at the state `s` before a step of length `h`, wheels `hw`, gravity gradient `gg`.
///
/// THE ONE PLACE the covariance gets its transition: here the first-order linearisation of the
/// continuous forced dynamics, `F = I + h A`, with
///
/// `A = [[hat(m) I^-1 - hat(W), G], [I^-1, -hat(W)]]`, `W = I^-1 (m - hw)`,
/// `G = dtau/dtheta = 3K (hat(r) I - hat(I r)) hat(r)` (right perturbation moves
/// `r = R^T n` by `hat(r) dtheta`).
///
/// A legitimate EKF choice (error `O(h^2 |A|^2)`, 1e-9 here per tick). The library's exact
/// tangent map of the free DMV step, `Mv::step_with_jacobian` (same coordinates), would be
/// composed here with the kicks' and the rotor turns' Jacobians to replace it.
#[inline(never)]
pub fn transition(s: &State<f32>, inertia: [f32; 3], hw: [f32; 3], gg: &Gg, h: f32) -> M6 {
    let m = s.m;
    let inv = inertia.map(|x| 1.0 / x);
    let w = [0, 1, 2].map(|k| (m[k] - hw[k]) * inv[k]);
    let r = gg.nadir(0.0, &s.q);
    let ir = [0, 1, 2].map(|k| r[k] * inertia[k]);
    let hat = |v: [f32; 3]| [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]];
    let (hm, hw_, hr, hir) = (hat(m), hat(w), hat(r), hat(ir));
    let mut f = [[0.0f32; 6]; 6];
    for i in 0..3 {
        for j in 0..3 {
            // momentum block: hat(m) I^-1 - hat(W)
            f[i][j] = h * (hm[i][j] * inv[j] - hw_[i][j]);
            // G = 3K (hat(r) I - hat(Ir)) hat(r)
            let mut g = 0.0;
            for k in 0..3 {
                g += (hr[i][k] * inertia[k] - hir[i][k]) * hr[k][j];
            }
            f[i][3 + j] = h * 3.0 * gg.k * g;
            f[3 + i][3 + j] = -h * hw_[i][j];
        }
        f[3 + i][i] = h * inv[i];
    }
    for i in 0..6 {
        f[i][i] += 1.0;
    }
    f
}

fn inverse3(a: [[f32; 3]; 3]) -> Option<[[f32; 3]; 3]> {
    let c = [
        [
            a[1][1] * a[2][2] - a[1][2] * a[2][1],
            a[0][2] * a[2][1] - a[0][1] * a[2][2],
            a[0][1] * a[1][2] - a[0][2] * a[1][1],
        ],
        [
            a[1][2] * a[2][0] - a[1][0] * a[2][2],
            a[0][0] * a[2][2] - a[0][2] * a[2][0],
            a[0][2] * a[1][0] - a[0][0] * a[1][2],
        ],
        [
            a[1][0] * a[2][1] - a[1][1] * a[2][0],
            a[0][1] * a[2][0] - a[0][0] * a[2][1],
            a[0][0] * a[1][1] - a[0][1] * a[1][0],
        ],
    ];
    let det = a[0][0] * c[0][0] + a[0][1] * c[1][0] + a[0][2] * c[2][0];
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let d = 1.0 / det;
    Some(c.map(|row| row.map(|x| x * d)))
}

/// The multiplicative EKF of the gyro-less mode.
pub struct Ekf {
    pub f: Propagator,
    pub s: State<f32>,
    pub p: M6,
    pub inertia: [f32; 3],
    pub frame: [f32; 4],
    /// Star-tracker noise, 1 sigma per axis, rad.
    pub sigma: f32,
}

impl Ekf {
    /// From the first fix: attitude from the star tracker (covariance `sigma^2`), momentum
    /// that of the wheels (the body assumed at rest) with a 1 sigma of `sigma_m` per axis.
    pub fn init(&mut self, star_sensor: [f32; 4], wheels: [f32; 3], sigma_m: f32) {
        self.s = State::new(wheels, qmul(star_sensor, self.frame));
        self.p = [[0.0; 6]; 6];
        for i in 0..3 {
            self.p[i][i] = sigma_m * sigma_m;
            self.p[3 + i][3 + i] = self.sigma * self.sigma;
        }
    }

    /// Predict over the measured period `dt`: state by the forced `Mv` step, covariance by
    /// `P <- F P F^T + Q dt`.
    #[inline(never)]
    pub fn predict(
        &mut self,
        dt: f32,
        wheels: [f32; 3],
        orbit: (f32, f32),
    ) -> Result<(), StepError> {
        let mut gg = *self.f.torque();
        gg.cos0 = orbit.0;
        gg.sin0 = orbit.1;
        let f = transition(&self.s, self.inertia, wheels, &gg, dt);
        tick(&mut self.f, &mut self.s, dt, wheels, orbit)?;
        let mut fp = [[0.0f32; 6]; 6];
        for i in 0..6 {
            for j in 0..6 {
                let mut a = 0.0;
                for k in 0..6 {
                    a += f[i][k] * self.p[k][j];
                }
                fp[i][j] = a;
            }
        }
        for i in 0..6 {
            for j in i..6 {
                let mut a = 0.0;
                for k in 0..6 {
                    a += fp[i][k] * f[j][k];
                }
                self.p[i][j] = a;
                self.p[j][i] = a;
            }
        }
        for i in 0..3 {
            self.p[i][i] += Q_TORQUE * Q_TORQUE * dt;
            self.p[3 + i][3 + i] += Q_ATT * Q_ATT * dt;
        }
        Ok(())
    }

    /// Update with a star-tracker fix (sensor-frame attitude): measurement `dtheta` with noise
    /// `sigma^2 I`, `H = [0 I]`; Joseph-form covariance update; the attitude reset
    /// `q <- q (x) exp(dtheta / 2)`.
    #[inline(never)]
    pub fn fix(&mut self, star_sensor: [f32; 4]) -> bool {
        let z = error_vector(self.s.q, qmul(star_sensor, self.frame));
        let r = self.sigma * self.sigma;
        let mut sm = [[0.0f32; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                sm[i][j] = self.p[3 + i][3 + j] + if i == j { r } else { 0.0 };
            }
        }
        let Some(si) = inverse3(sm) else { return false };
        // K = P H^T S^-1 (6x3)
        let mut k = [[0.0f32; 3]; 6];
        for i in 0..6 {
            for j in 0..3 {
                k[i][j] = (0..3).map(|l| self.p[i][3 + l] * si[l][j]).sum();
            }
        }
        let dx: [f32; 6] = core::array::from_fn(|i| (0..3).map(|j| k[i][j] * z[j]).sum());
        for i in 0..3 {
            self.s.m[i] += dx[i];
        }
        self.s.q = qmul(self.s.q, small_rotation([dx[3], dx[4], dx[5]]));
        // Joseph form: P = (I - K H) P (I - K H)^T + K R K^T
        let mut a = [[0.0f32; 6]; 6];
        for i in 0..6 {
            a[i][i] = 1.0;
            for j in 0..3 {
                a[i][3 + j] -= k[i][j];
            }
        }
        let mut ap = [[0.0f32; 6]; 6];
        for i in 0..6 {
            for j in 0..6 {
                ap[i][j] = (0..6).map(|l| a[i][l] * self.p[l][j]).sum();
            }
        }
        for i in 0..6 {
            for j in i..6 {
                let v: f32 = (0..6).map(|l| ap[i][l] * a[j][l]).sum::<f32>()
                    + r * (0..3).map(|l| k[i][l] * k[j][l]).sum::<f32>();
                self.p[i][j] = v;
                self.p[j][i] = v;
            }
        }
        true
    }

    /// 1 sigma of the attitude error per axis, and of the attitude angle (`sqrt(tr P_qq)`).
    pub fn attitude_sigma(&self) -> ([f32; 3], f32) {
        let d = [self.p[3][3], self.p[4][4], self.p[5][5]];
        (d.map(Real::sqrt), Real::sqrt(d[0] + d[1] + d[2]))
    }
}
