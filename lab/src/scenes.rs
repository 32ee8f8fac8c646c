//! The public scenes of docs/MATH.md §8 with their reference values.

/// The talk's case: mass matrix `J`.
pub const TALK_J: [f64; 3] = [0.9218, 0.7382, 0.1763];
/// The talk's case: initial body momentum.
pub const TALK_M0: [f64; 3] = [0.4165, 0.9072, 0.0588];
/// Reference `m(1)` of the talk's case (independent high precision).
pub const TALK_M1: [f64; 3] = [
    0.409_636_768_238_524_6,
    0.912_164_866_891_563_8,
    -0.009_721_302_165_504_741,
];
/// Reference `m(10)` of the talk's case.
pub const TALK_M10: [f64; 3] = [
    0.827_172_818_567_906_3,
    -0.096_647_426_825_883_59,
    -0.553_521_393_543_520_7,
];
/// Reference `m(100)` of the talk's case.
pub const TALK_M100: [f64; 3] = [
    0.666_538_099_972_017_2,
    0.625_775_813_394_612_9,
    0.405_059_406_329_496,
];
/// Hairer–Vilmart's driver case: principal moments.
pub const HV_I: [f64; 3] = [0.6, 0.8, 1.0];
/// Hairer–Vilmart's driver case: initial momentum.
pub const HV_M0: [f64; 3] = [1.8, 0.4, -0.9];

/// The README's spacecraft (`examples/attitude.rs`): inertia tensor in its sensor frame, kg m^2.
pub const SPACECRAFT_TENSOR: [[f64; 3]; 3] =
    [[120.0, -4.0, 2.5], [-4.0, 95.0, 6.0], [2.5, 6.0, 60.0]];
/// The spacecraft's initial angular velocity in the sensor frame, rad/s: a slow tumble.
pub const SPACECRAFT_OMEGA0: [f64; 3] = [0.06, -0.04, 0.11];
/// The spacecraft's loop step: 200 Hz.
pub const SPACECRAFT_H: f64 = 1.0 / 200.0;

/// The spacecraft scene as the firmware sets it up: principal moments, the body momentum
/// `m0` in the principal frame and the attitude `q0` (principal frame to space, the sensor
/// frame being the space frame at `t = 0`), all in f64.
pub fn spacecraft() -> ([f64; 3], [f64; 3], [f64; 4]) {
    let (body, frame) = rigid3::Body::<f64>::from_inertia_tensor(SPACECRAFT_TENSOR)
        .expect("the spacecraft's tensor is valid");
    let t = SPACECRAFT_TENSOR;
    let w = SPACECRAFT_OMEGA0;
    let m_sensor = [0, 1, 2].map(|r| t[r][0] * w[0] + t[r][1] * w[1] + t[r][2] * w[2]);
    // m0 = R(frame)^T m_sensor: rotate by the conjugate
    let conj = [frame[0], -frame[1], -frame[2], -frame[3]];
    let m0 = rigid3::State::new(m_sensor, conj).spatial_momentum();
    (body.inertia(), m0, frame)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spacecraft_in_its_principal_frame_has_the_sensor_frame_momentum() {
        let (inertia, m0, q0) = spacecraft();
        assert!(inertia[0] <= inertia[1] && inertia[1] <= inertia[2]);
        // R(q0) m0 is the momentum in the sensor frame, T omega0
        let p = rigid3::State::new(m0, q0).spatial_momentum();
        let t = SPACECRAFT_TENSOR;
        let w = SPACECRAFT_OMEGA0;
        for r in 0..3 {
            let want = t[r][0] * w[0] + t[r][1] * w[1] + t[r][2] * w[2];
            assert!((p[r] - want).abs() < 1e-12, "{p:?}");
        }
    }
}
