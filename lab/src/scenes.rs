//! The public scenes of docs/MATH.md §8 with their reference values.

// the constants are defined once for the library's tests, its benches and the lab
#[path = "../../tests/common/cases.rs"]
mod cases;
pub use cases::{
    HV_I, HV_M0, HV_M10, HV_Q10, TALK_I, TALK_J, TALK_M0, TALK_M1, TALK_M10, TALK_M100,
    TALK_MAX_STEP, TALK_Q10,
};

/// The README's spacecraft (`firmware/src/bin/attitude.rs`): inertia tensor in its sensor frame, kg m^2.
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
