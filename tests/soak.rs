//! Soak run (not in normal CI): 10^8 `Mv` steps in f64 on the talk's case, with the drift of
//! |m|^2, the energy and the spatial momentum sampled every 1000 steps.
//! `cargo test --release --test soak -- --ignored --nocapture` (about 15 s).

mod common;

use common::*;
use rigid3::{Body, Integrator, Mv, State};

#[test]
#[ignore]
fn soak_1e8_mv_steps_f64() {
    let body = Body::<f64>::from_mass_matrix(TALK_J).unwrap();
    let mut mv = Mv::new(body, 0.1);
    let mut s = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    let (c0, e0, p0) = (body.casimir(&s.m), body.energy(&s.m), s.spatial_momentum());
    let mut d = [0.0f64; 3];
    let steps: u64 = 100_000_000;
    for k in 0..steps {
        mv.step_state(&mut s).unwrap();
        if k % 1000 == 0 {
            d[0] = d[0].max((body.casimir(&s.m) - c0).abs() / c0);
            d[1] = d[1].max((body.energy(&s.m) - e0).abs() / e0);
            d[2] = d[2].max(dist(s.spatial_momentum(), p0) / norm(p0));
        }
    }
    println!(
        "soak: 1e8 Mv steps (f64, talk's case, h = 0.1): max drift |m|^2 {:e}, E {:e}, R(q)m {:e}",
        d[0], d[1], d[2]
    );
    assert!(d[0] < 1e-12 && d[1] < 1e-11 && d[2] < 1e-11, "{d:?}");
}
