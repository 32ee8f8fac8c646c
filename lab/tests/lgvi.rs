//! rigid3's kick–drift–kick `Forced<Mv>` against the Newton-solved Lie group variational
//! integrator of Lee, Leok and McClamroch (`rigid3_lab::lgvi`): the same map, to round-off.

use rigid3::{Body, Forced, Gravity, GravityGradient, Integrator, Mv, NoTorque, State, Torque};
use rigid3_lab::lgvi::{Coordinates, Lgvi, LgviError};
use rigid3_lab::rng::Rng;

fn unit_q(r: &mut Rng) -> [f64; 4] {
    let q = [0; 4].map(|_| r.unit() - 0.5);
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    q.map(|x| x / n)
}

/// Max over `steps` consecutive steps from random states of the relative difference of `m`
/// and the difference of `q` (up to sign) between the two integrators, each step from the
/// same state.
fn worst<F: Torque<f64> + Clone>(
    body: Body<f64>,
    torque: F,
    hs: &[f64],
    states: usize,
    seed: u64,
    coordinates: Coordinates,
) -> f64 {
    let mut r = Rng::new(seed);
    let mut worst = 0.0f64;
    for &h in hs {
        for _ in 0..states {
            let m = [0; 3].map(|_| 2.0 * r.unit() - 1.0);
            let q = unit_q(&mut r);
            let mut a = State::new(m, q);
            let mut b = a;
            let mut kdk = Forced::new(Mv::new(body, h), torque.clone());
            let mut lgvi = Lgvi::with_coordinates(&body, h, torque.clone(), coordinates);
            // a few steps each, so the reuse of the end torque is exercised too
            for _ in 0..3 {
                kdk.step_state(&mut a).unwrap();
                lgvi.step(&mut b).expect("Newton converges");
                let nm = (b.m.iter().map(|x| x * x).sum::<f64>()).sqrt().max(1e-300);
                let dm = (0..3).map(|k| (a.m[k] - b.m[k]).abs()).fold(0.0, f64::max) / nm;
                let dq = (0..4).map(|k| (a.q[k] - b.q[k]).abs()).fold(0.0, f64::max);
                let dq2 = (0..4).map(|k| (a.q[k] + b.q[k]).abs()).fold(0.0, f64::max);
                worst = worst.max(dm).max(dq.min(dq2));
                b = a;
            }
        }
    }
    worst
}

const HS: [f64; 4] = [0.01, 0.05, 0.1, 0.2];

#[test]
fn kick_drift_kick_mv_is_the_lgvi_on_the_heavy_top() {
    let body = Body::from_inertia([1.0, 1.5, 2.0]).unwrap();
    let g = Gravity {
        mg: 1.0,
        com: [0.2, -0.1, 0.5],
    };
    for c in [Coordinates::Cayley, Coordinates::Exponential] {
        let w = worst(body, g, &HS, 200, 1, c);
        println!("heavy top: max difference per step Forced<Mv> vs LGVI ({c:?}) {w:.2e}");
        assert!(w <= 1e-13, "{w:e}");
    }
}

#[test]
fn kick_drift_kick_mv_is_the_lgvi_in_a_gravity_gradient() {
    let body = Body::from_inertia([1.2, 1.5, 1.9]).unwrap();
    let gg = GravityGradient {
        k: 1.0,
        n: 1.0,
        inertia: body.inertia(),
    };
    for c in [Coordinates::Cayley, Coordinates::Exponential] {
        let w = worst(body, gg, &HS, 200, 2, c);
        println!("gravity gradient: max difference per step Forced<Mv> vs LGVI ({c:?}) {w:.2e}");
        assert!(w <= 1e-13, "{w:e}");
    }
}

#[test]
fn free_lgvi_is_mv() {
    let body = Body::from_inertia([0.9145, 1.0981, 1.66]).unwrap();
    for c in [Coordinates::Cayley, Coordinates::Exponential] {
        let w = worst(body, NoTorque, &HS, 200, 3, c);
        println!("free body: max difference per step Mv vs LGVI ({c:?}) {w:.2e}");
        assert!(w <= 1e-13, "{w:e}");
    }
}

#[test]
fn newton_converges_in_few_iterations() {
    let body = Body::from_inertia([1.0, 1.5, 2.0]).unwrap();
    for c in [Coordinates::Cayley, Coordinates::Exponential] {
        let mut lgvi = Lgvi::with_coordinates(&body, 0.1, NoTorque, c);
        let mut s = State::new([0.3, -0.6, 1.1], [1.0, 0.0, 0.0, 0.0]);
        lgvi.step(&mut s).unwrap();
        assert!(lgvi.iterations <= 6, "{c:?}: {}", lgvi.iterations);
    }
}

#[test]
fn a_step_newton_cannot_take_is_an_error_and_leaves_the_state() {
    // far past the existence limit of the step (docs/MATH.md §3): no rotation solves the
    // equation, and Newton must say so instead of returning an iterate
    let body = Body::from_inertia([0.9145, 1.0981, 1.66]).unwrap();
    for c in [Coordinates::Cayley, Coordinates::Exponential] {
        let mut lgvi = Lgvi::with_coordinates(&body, 50.0, NoTorque, c);
        let s0 = State::new([0.4165, 0.9072, 0.0588], [1.0, 0.0, 0.0, 0.0]);
        let mut s = s0;
        let e = lgvi.step(&mut s).unwrap_err();
        println!("{c:?}: h = 50: {e}");
        assert!(
            matches!(e, LgviError::NoConvergence { .. } | LgviError::Singular),
            "{e:?}"
        );
        assert_eq!(s, s0);
        let mut bad = State::new([f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(lgvi.step(&mut bad), Err(LgviError::NonFinite));
    }
}
