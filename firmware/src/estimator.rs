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
/// `(cos, sin)` at the start of the tick (set each tick from the clock by `rigid3::sin_cos`,
/// 70 instructions; libm's `sinf`/`cosf` pair is about 4000 on the M4F) and advanced
/// within the step by its Taylor series (`N h` is 6e-6 rad: exact in f32), instead of a pair
/// per evaluation.
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
    f.set_time(0.0)?;
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

/// Which tangent map the EKF's covariance propagation uses (see [`transition`]).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Jacobian {
    /// `F = I + h A`: the first-order linearisation of the continuous forced dynamics.
    Linearised,
    /// The exact Jacobian of the forced step as the library takes it (kick, rotor turn, DMV
    /// drift, turn, kick): `K1 T D T K0`, with `D` from rigid3's `Mv::step_with_jacobian`
    /// (taken by a scratch `Mv` on the kicked and turned state) and the kicks' and turns'
    /// Jacobians in closed form.
    Dmv,
}

/// The EKF's choice (the one switch).
pub const JACOBIAN: Jacobian = Jacobian::Dmv;

/// `dtau/dtheta = 3K (hat(r) I - hat(I r)) hat(r)` at the nadir `r` (body frame): a right
/// perturbation `q (x) exp(dtheta / 2)` moves `r = R^T n` by `hat(r) dtheta`.
fn torque_gradient(r: [f32; 3], inertia: [f32; 3], k: f32) -> [[f32; 3]; 3] {
    let ir = [0, 1, 2].map(|i| r[i] * inertia[i]);
    let (hr, hir) = (hat(r), hat(ir));
    let mut g = [[0.0f32; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let mut a = 0.0;
            for l in 0..3 {
                a += (hr[i][l] * inertia[l] - hir[i][l]) * hr[l][j];
            }
            g[i][j] = 3.0 * k * a;
        }
    }
    g
}

fn hat(v: [f32; 3]) -> [[f32; 3]; 3] {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}

/// `R(p)` of a unit quaternion, row-major.
fn rotation(p: [f32; 4]) -> [[f32; 3]; 3] {
    let c = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].map(|e| rotate(p, e));
    // c[j] is column j
    [0, 1, 2].map(|i| [c[0][i], c[1][i], c[2][i]])
}

fn mul6(a: &M6, b: &M6) -> M6 {
    let mut c = [[0.0f32; 6]; 6];
    for i in 0..6 {
        for j in 0..6 {
            let mut s = 0.0;
            for k in 0..6 {
                s += a[i][k] * b[k][j];
            }
            c[i][j] = s;
        }
    }
    c
}

/// The step's Jacobian `F = d(m', dtheta') / d(m, dtheta)` (6x6, row-major, momentum first,
/// then the body-frame attitude error of `q = q^ (x) exp(dtheta / 2)`: `rigid3::tangent`'s
/// coordinates) at the state `s` before a step of length `h`, wheels `hw`, gravity gradient `gg`
/// (its orbit angle that of the tick's start); `relative`: the step takes the library's
/// relative splitting (`Forced::takes_relative_split`).
///
/// THE ONE PLACE the covariance gets its transition; [`JACOBIAN`] picks the map:
/// - [`Jacobian::Dmv`]: the forced step's exact tangent map, `K1 T D T K0` (with the
///   library's relative splitting, taken when the wheels turn the body well faster than its
///   own energy allows, `T` is the gyroscopic half step's matrix on the momentum), where
///   `K = [[I, h/2 G], [0, I]]` is a kick (`G = dtau/dtheta`), `T = diag(P^T, P^T)` the rotor's
///   half-step turn `p` (`m <- R(p)^T m`, `q <- q (x) p`), and `D` the DMV drift's Jacobian from
///   rigid3's `Mv::step_with_jacobian` (`scratch` takes that step; the state itself is stepped
///   by the library's `Forced`);
/// - [`Jacobian::Linearised`]: `F = I + h A`, the first-order linearisation of the continuous
///   forced dynamics, `A = [[hat(m) I^-1 - hat(W), G], [I^-1, -hat(W)]]`,
///   `W = I^-1 (m - hw)` (error `O(h^2 |A|^2)`, about 1e-9 per tick here).
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub fn transition(
    scratch: &mut Mv<f32>,
    s: &State<f32>,
    inertia: [f32; 3],
    hw: [f32; 3],
    gg: &Gg,
    h: f32,
    relative: bool,
) -> Result<M6, StepError> {
    transition_as(JACOBIAN, scratch, s, inertia, hw, gg, h, relative)
}

/// [`transition`] with the map chosen by the caller (the firmware compares the two).
#[allow(clippy::too_many_arguments)]
pub fn transition_as(
    kind: Jacobian,
    scratch: &mut Mv<f32>,
    s: &State<f32>,
    inertia: [f32; 3],
    hw: [f32; 3],
    gg: &Gg,
    h: f32,
    relative: bool,
) -> Result<M6, StepError> {
    let inv = inertia.map(|x| 1.0 / x);
    let g0 = torque_gradient(gg.nadir(0.0, &s.q), inertia, gg.k);
    if kind == Jacobian::Linearised {
        let m = s.m;
        let w = [0, 1, 2].map(|k| (m[k] - hw[k]) * inv[k]);
        let (hm, hw_) = (hat(m), hat(w));
        let mut f = [[0.0f32; 6]; 6];
        for i in 0..3 {
            for j in 0..3 {
                f[i][j] = h * (hm[i][j] * inv[j] - hw_[i][j]);
                f[i][3 + j] = h * g0[i][j];
                f[3 + i][3 + j] = -h * hw_[i][j];
            }
            f[3 + i][i] = h * inv[i];
        }
        for i in 0..6 {
            f[i][i] += 1.0;
        }
        return Ok(f);
    }
    let half = 0.5 * h;
    // the first kick
    let tau0 = gg.torque(0.0, &s.q);
    let m1 = [0, 1, 2].map(|i| s.m[i] + half * tau0[i]);
    // the rotor's part, on both sides of the drift: `t` (6x6) its tangent map, `x` the drift's
    // input and `p` the turn of the attitude after it (one `step_with_jacobian` call site:
    // with two, the firmware's free-running `Mv` step took 20 instructions more)
    let mut t = [[0.0f32; 6]; 6];
    let (mut x, p) = if relative {
        // the library's relative splitting (rigid3's crate::forced_relative; the caller asks
        // the propagating `Forced` whether the step takes it): the drift steps n = m - hw between two
        // gyroscopic half steps n' = B n, B = 1 + c (A + A^2), A = hat(a) I^-1, a = h hw / 4,
        // c = 2 / (1 + a . adj(I^-1) a); the attitude does not move in them
        let a = hw.map(|x| x * h * 0.25);
        let sigma = a[0] * a[0] * inv[1] * inv[2]
            + a[1] * a[1] * inv[0] * inv[2]
            + a[2] * a[2] * inv[0] * inv[1];
        let c = 2.0 / (1.0 + sigma);
        let ha = hat(a);
        let am = [0, 1, 2].map(|i| [0, 1, 2].map(|j| ha[i][j] * inv[j]));
        for i in 0..3 {
            for j in 0..3 {
                let a2 = am[i][0] * am[0][j] + am[i][1] * am[1][j] + am[i][2] * am[2][j];
                t[i][j] = c * (am[i][j] + a2) + if i == j { 1.0 } else { 0.0 };
            }
            t[3 + i][3 + i] = 1.0;
        }
        let n0 = [0, 1, 2].map(|i| m1[i] - hw[i]);
        let n1 = [0, 1, 2].map(|i| t[i][0] * n0[0] + t[i][1] * n0[1] + t[i][2] * n0[2]);
        (State::new(n1, s.q), [1.0, 0.0, 0.0, 0.0])
    } else {
        // the rotor's half-step turn, in the library's rational form: u = -(h/8) I^-1 hw
        let u = [0, 1, 2].map(|i| -h * 0.125 * hw[i] * inv[i]);
        let n = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        let d = 1.0 / (1.0 + n);
        let p = [
            (1.0 - n) * d,
            2.0 * u[0] * d,
            2.0 * u[1] * d,
            2.0 * u[2] * d,
        ];
        let pm = rotation(p);
        for i in 0..3 {
            for j in 0..3 {
                t[i][j] = pm[j][i];
                t[3 + i][3 + j] = pm[j][i];
            }
        }
        let pt =
            |v: [f32; 3]| [0, 1, 2].map(|i| pm[0][i] * v[0] + pm[1][i] * v[1] + pm[2][i] * v[2]);
        (State::new(pt(m1), qmul(s.q, p)), p)
    };
    scratch.set_step_size(h);
    scratch.reset();
    let dmv = scratch.step_with_jacobian(&mut x)?;
    let q4 = qmul(x.q, p);
    let g1 = torque_gradient(gg.nadir(h, &q4), inertia, gg.k);
    let mut k0 = [[0.0f32; 6]; 6];
    let mut k1 = [[0.0f32; 6]; 6];
    for i in 0..6 {
        k0[i][i] = 1.0;
        k1[i][i] = 1.0;
    }
    for i in 0..3 {
        for j in 0..3 {
            k0[i][3 + j] = half * g0[i][j];
            k1[i][3 + j] = half * g1[i][j];
        }
    }
    let a = mul6(&dmv, &mul6(&t, &k0));
    Ok(mul6(&k1, &mul6(&t, &a)))
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
    /// The scratch DMV step of [`transition`] (`Jacobian::Dmv`).
    pub scratch: Mv<f32>,
    pub s: State<f32>,
    pub p: M6,
    pub inertia: [f32; 3],
    pub frame: [f32; 4],
    /// Star-tracker noise, 1 sigma per axis, rad.
    pub sigma: f32,
    /// Predicts, and those whose step took the library's relative splitting (the wheels
    /// turning the body well faster than its own energy allows), for the report.
    pub steps: u32,
    pub relative_steps: u32,
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
        let relative = self.f.takes_relative_split(&self.s.m, &wheels);
        self.relative_steps += u32::from(relative);
        self.steps += 1;
        let f = transition(
            &mut self.scratch,
            &self.s,
            self.inertia,
            wheels,
            &gg,
            dt,
            relative,
        )?;
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
