//! The scene as flown, and its f64 truth.
//!
//! A spacecraft (the full inertia tensor below; dynamics in its principal frame) in a circular
//! orbit of 90 minutes, with the gravity-gradient torque ([`GravityGradient`], `K = N^2`) and a
//! small unmodelled disturbance torque (solar pressure, constant in the body: the estimators do
//! not know it), three reaction wheels along the principal axes driven by a PD controller
//! toward nadir pointing (momentum exchange: the wheels take `-` the control torque, their
//! momentum is integrated and saturates), and a flight loop whose period jitters by +-5%
//! (seeded) and is measured by a 1 us timer.
//!
//! Truth: f64, `Composed` of order 4 over `Mv` with the gravity gradient and
//! the disturbance as its torque model, the wheels as its rotor (`set_rotor` every tick), stepped
//! by the loop's true period (`set_step_size` every tick).

use crate::math::{conj, qmul, rotate, Noise};
use rigid3::{Body, Composed, ConstantTorque, GravityGradient, Integrator, Mv, State, StepError};

/// Inertia tensor of the spacecraft in its body (sensor) frame, kg m^2.
pub const TENSOR: [[f64; 3]; 3] = [[120.0, -4.0, 2.5], [-4.0, 95.0, 6.0], [2.5, 6.0, 60.0]];
/// Nominal loop rate and period.
pub const RATE_HZ: u32 = 200;
pub const H: f64 = 1.0 / RATE_HZ as f64;
/// Loop period jitter: uniform, +-5% of `H`; measured with a 1 us timer.
pub const JITTER: f64 = 0.05;
pub const TIMER_HZ: f64 = 1e6;
/// Simulated time: 10 minutes.
pub const SECONDS: u32 = 600;
/// Orbit rate: a 90-minute circular orbit, rad/s (`K = mu / R^3 = N^2`).
pub const ORBIT_N: f64 = 2.0 * core::f64::consts::PI / 5400.0;
/// Unmodelled disturbance torque (body principal frame), N m.
pub const DISTURBANCE: [f64; 3] = [2e-6, -1.5e-6, 1e-6];
/// Initial body rate (principal frame), rad/s, and attitude offset from the target, rad.
pub const OMEGA0: [f64; 3] = [0.004, -0.003, 0.005];
pub const OFFSET0: [f64; 3] = [0.20, -0.15, 0.25];

/// Wheels: momentum capacity per wheel (N m s) and torque limit (N m).
pub const WHEEL_MAX: f32 = 4.0;
pub const TORQUE_MAX: f32 = 0.05;
/// PD gains: natural frequency (rad/s) and damping of each axis, `K_p = I w^2`, `K_d = 2 z w I`.
pub const CTRL_W: f32 = 0.05;
pub const CTRL_Z: f32 = 0.9;

pub type TruthTorque = (GravityGradient<f64>, ConstantTorque<f64>);

/// The f64 truth: state (principal frame), its integrator, the wheels and the clock.
pub struct Truth {
    pub body: Body<f64>,
    /// Principal frame in the sensor frame (`x_sensor = R(frame) x_principal`).
    pub frame: [f64; 4],
    pub integ: Composed<f64, Mv<f64>, TruthTorque>,
    pub s: State<f64>,
    pub t: f64,
}

/// The nadir-pointing target attitude (principal frame to space) at time `t`: principal x
/// (smallest moment) along the nadir `(cos N t, sin N t, 0)` of [`GravityGradient`], z (largest)
/// along the orbit normal: the gravity-gradient-stable orientation.
pub fn target(t: f64) -> [f64; 4] {
    let a = 0.5 * ORBIT_N * t;
    [rigid3::Real::cos(a), 0.0, 0.0, rigid3::Real::sin(a)]
}

impl Truth {
    pub fn new() -> Result<Self, StepError> {
        let (body, frame) =
            Body::<f64>::from_inertia_tensor(TENSOR).map_err(|_| StepError::Degenerate)?;
        let i = body.inertia();
        let gg = GravityGradient {
            k: ORBIT_N * ORBIT_N,
            n: ORBIT_N,
            inertia: i,
        };
        let integ = Composed::new(Mv::new(body, H), (gg, ConstantTorque(DISTURBANCE)), 4)?;
        let m0 = [i[0] * OMEGA0[0], i[1] * OMEGA0[1], i[2] * OMEGA0[2]];
        let q0 = qmul(target(0.0), crate::math::small_rotation(OFFSET0));
        Ok(Self {
            body,
            frame,
            integ,
            s: State::new(m0, q0),
            t: 0.0,
        })
    }

    /// One loop period `dt` with the wheels' momentum `wheels` (principal frame) held.
    pub fn step(&mut self, dt: f64, wheels: [f32; 3]) -> Result<(), StepError> {
        self.integ.set_step_size(dt);
        self.integ.set_rotor(wheels.map(|x| x as f64))?;
        self.integ.step_state(&mut self.s)?;
        self.t += dt;
        Ok(())
    }

    /// Body rate (principal frame) with the wheels `wheels`.
    pub fn rate(&self, wheels: [f32; 3]) -> [f64; 3] {
        let i = self.body.inertia();
        [
            (self.s.m[0] - wheels[0] as f64) / i[0],
            (self.s.m[1] - wheels[1] as f64) / i[1],
            (self.s.m[2] - wheels[2] as f64) / i[2],
        ]
    }

    /// Body rate in the sensor frame.
    pub fn rate_sensor(&self, wheels: [f32; 3]) -> [f64; 3] {
        rotate(self.frame, self.rate(wheels))
    }

    /// Attitude of the sensor frame (sensor to space).
    pub fn attitude_sensor(&self) -> [f64; 4] {
        qmul(self.s.q, conj(self.frame))
    }
}

/// The loop's true period this tick (+-5% uniform) and what the 1 us timer measures of it.
/// Returns `(true period s, measured period in timer ticks)`.
pub fn period(noise: &mut Noise) -> (f64, u32) {
    let dt = H * (1.0 + 2.0 * JITTER * (noise.uniform() as f64 - 0.5));
    (dt, (dt * TIMER_HZ + 0.5) as u32)
}
