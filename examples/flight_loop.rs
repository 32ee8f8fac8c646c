//! A 200 Hz attitude loop as flight software writes it, in f32 and no allocation: a body
//! given by its inertia tensor, the gravity gradient of a circular orbit, a momentum-bias
//! wheel commanded each tick, a measured `dt` that jitters (and one tick whose timer
//! glitched), and a PD controller's torque added to the gravity gradient each tick.
//!
//!     cargo run --release --example flight_loop
//!
//! Everything the integrator sees is in the principal frame of the body: vectors of the
//! structure (the wheel's axis) go in through `Frame::to_principal`. The controller drives the
//! attitude to the identity (principal axes along space axes) against the gravity gradient.

use rigid3::{Forced, Frame, GravityGradient, Integrator, Mv, Quaternion, State, StepError};

fn main() -> Result<(), StepError> {
    // inertia tensor of the structure (kg m^2), with small products of inertia
    let tensor = [[58.8f32, 1.2, -0.5], [1.2, 95.5, 0.8], [-0.5, 0.8, 120.7]];
    let (body, frame) = Frame::from_inertia_tensor(tensor).expect("a valid inertia tensor");
    let inertia = body.inertia();

    // a 95-minute orbit: K = N^2, the body's principal moments (not the tensor's diagonal)
    let period = 95.0 * 60.0;
    let n = 2.0 * core::f32::consts::PI / period;
    let gg = GravityGradient::circular(&body, n);
    let h0 = 0.005;
    let mut f = Forced::new(Mv::new(body, h0), gg);

    // tumbling at a few degrees a second, 30 degrees off the target attitude
    let q0 = Quaternion::from_rotation_vector([0.3, -0.35, 0.2]).to_array();
    let mut s = State::new([3.0, -4.0, 5.0], q0);

    let (kp, kd) = (0.4f32, 12.0f32);
    let mut dt = h0;
    println!("    t (s)   error (deg)   |Omega| (deg/s)");
    for tick in 0..200 * 600 {
        // the wheel: 0.5 N m s along the structure's y axis, trimmed each tick
        let trim = 0.01 * ((tick % 400) as f32 / 400.0 - 0.5);
        let wheel = frame.to_principal([0.0, 0.5 + trim, 0.0]);
        f.set_rotor(wheel)?;

        // the measured dt: +-5 % jitter, and one tick where the timer wrapped; a bad reading
        // keeps the last good step (a negative h would step backwards, NaN would be refused)
        let measured = if tick == 1000 {
            -4.2e9
        } else {
            h0 * (1.0 + 0.05 * ((tick as f32) * 0.37).sin())
        };
        if measured > 0.0 && measured < 4.0 * h0 {
            dt = measured;
        }
        f.set_step_size(dt);

        // PD control toward the identity attitude, in the body's principal frame: the error
        // is the rotation vector from the attitude to the target
        let error = Quaternion::from_array(s.q).conjugate().to_rotation_vector();
        let omega = [0, 1, 2].map(|i| (s.m[i] - wheel[i]) / inertia[i]);
        let tau = [0, 1, 2].map(|i| kp * error[i] - kd * omega[i]);

        // the command adds to the gravity gradient (step_state_with would replace it); on Err
        // the state and the clock are left as they were
        if let Err(e) = f.step_state_plus(&mut s, tau, tau) {
            println!("tick {tick}: step refused ({e}), state kept");
            continue;
        }
        // an f32 clock loses resolution as it grows (7.8 ms at one day): re-base it once an
        // orbit, which leaves the circular orbit's gravity gradient as it was to within
        // N P - 2 pi (2.6e-7 to 4e-7 rad a re-base in f32: up to 4e-4 after 1000 orbits)
        if f.time() >= period {
            f.set_time(f.time() - period)?;
        }
        if tick % (200 * 60) == 0 || tick == 200 * 600 - 1 {
            let angle = Quaternion::<f32>::IDENTITY.angle_to(Quaternion::from_array(s.q));
            let rate = (omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]).sqrt();
            println!(
                "{:9.1}   {:11.5}   {:15.5}",
                f.time(),
                angle.to_degrees(),
                rate.to_degrees()
            );
        }
    }
    let angle = Quaternion::<f32>::IDENTITY.angle_to(Quaternion::from_array(s.q));
    let norm = s.q.iter().map(|x| x * x).sum::<f32>().sqrt();
    println!(
        "after {:.0} s: attitude error {:.2e} rad (the gravity gradient against the gains), |q| - 1 = {:.1e}",
        f.time(),
        angle,
        norm - 1.0
    );
    // in the structure's frame, for telemetry
    let (m_structure, q_structure) = frame.state_from_principal(&s);
    println!("momentum in the structure's frame {m_structure:?}, attitude {q_structure:?}");
    Ok(())
}
