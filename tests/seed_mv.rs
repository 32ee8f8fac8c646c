//! `SeedMv`, the talk's explicit DMV step, against the reference solution, conservation
//! laws, time reversal and its own failure modes. Agreement with the independent general
//! Cardoso–Leite solver is checked in `lab/tests/seed_vs_general.rs`.

#![allow(clippy::needless_range_loop)] // index loops read like the matrix formulas

mod common;

use common::*;
use rigid3::{Body, Integrator, SeedMv, State, StepError};

fn talk_body() -> Body<f64> {
    Body::from_mass_matrix(TALK_J).unwrap()
}

#[test]
fn talk_case_is_second_order_with_the_published_constant() {
    let ks = [3, 4, 5, 6, 7];
    let hs: Vec<f64> = ks.iter().map(|&k| 0.5f64.powi(k)).collect();
    let errs: Vec<f64> = hs
        .iter()
        .map(|&h| talk_error_at_10(&mut SeedMv::new(talk_body(), h), h))
        .collect();
    let p = observed_order(&hs, &errs);
    assert!((p - 2.0).abs() <= 0.05, "order {p}, errors {errs:?}");
    let constant = errs.last().unwrap() / hs.last().unwrap().powi(2);
    eprintln!("SeedMv, talk's case at t = 10: order {p:.3}, error constant {constant:.3}");
    assert!((constant - 0.51).abs() <= 0.05, "error constant {constant}");
}

#[test]
fn talk_case_conserves_invariants_and_spatial_momentum_over_1e5_steps() {
    let body = talk_body();
    let mut dmv = SeedMv::new(body, 0.1);
    let mut s = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    let c0 = body.casimir(&s.m);
    let e0 = body.energy(&s.m);
    let p0 = s.spatial_momentum();
    let (mut dc, mut de, mut dp) = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..100_000 {
        dmv.step_state(&mut s).unwrap();
        dc = dc.max((body.casimir(&s.m) - c0).abs() / c0);
        de = de.max((body.energy(&s.m) - e0).abs() / e0);
        dp = dp.max(dist(s.spatial_momentum(), p0) / norm(p0));
    }
    assert!(dc <= 1e-13, "casimir drift {dc:e}");
    assert!(de <= 1e-13, "energy drift {de:e}");
    assert!(dp <= 1e-13, "spatial momentum drift {dp:e}");
}

#[test]
fn step_back_with_minus_h_is_the_identity() {
    let mut rng = Rng::new(7);
    let body = talk_body();
    for _ in 0..1000 {
        let h = rng.range(0.01, 0.6);
        let d = rng.direction();
        let r = rng.range(0.2, 1.5);
        let m0 = [r * d[0], r * d[1], r * d[2]];
        let mut s = State::new(m0, [1.0, 0.0, 0.0, 0.0]);
        SeedMv::new(body, h).step_state(&mut s).unwrap();
        SeedMv::new(body, -h).step_state(&mut s).unwrap();
        assert!(dist(s.m, m0) <= 1e-14 * r, "{:e}", dist(s.m, m0));
        let dq = (s.q[0] - 1.0)
            .abs()
            .max(s.q[1].abs())
            .max(s.q[2].abs())
            .max(s.q[3].abs());
        assert!(dq <= 1e-14, "attitude {dq:e}");
    }
}

#[test]
fn step_matrix_solves_the_dmv_equation() {
    // residuals of M = X J - J X^T and X^T X = I, the defining equations (docs/MATH.md §2)
    let body = talk_body();
    let j = body.mass_matrix();
    let mut rng = Rng::new(11);
    for _ in 0..2000 {
        let h = rng.range(0.001, 1.0);
        let d = rng.direction();
        let m = [d[0], d[1], d[2]];
        let x = match SeedMv::new(body, h).step_matrix(&m) {
            Ok(x) => x,
            Err(StepError::StepTooLarge) => continue,
            Err(e) => panic!("{e:?} at h = {h}"),
        };
        let hat = [
            [0.0, -h * m[2], h * m[1]],
            [h * m[2], 0.0, -h * m[0]],
            [-h * m[1], h * m[0], 0.0],
        ];
        for r in 0..3 {
            for c in 0..3 {
                let res = x[r][c] * j[c] - j[r] * x[c][r] - hat[r][c];
                assert!(res.abs() <= 1e-13, "equation residual {res:e}");
                let xtx: f64 =
                    (0..3).map(|k| x[k][r] * x[k][c]).sum::<f64>() - if r == c { 1.0 } else { 0.0 };
                assert!(xtx.abs() <= 1e-13, "orthogonality {xtx:e}");
            }
        }
    }
}

#[test]
fn past_the_existence_limit_the_step_is_refused_and_the_state_kept() {
    let body = talk_body();
    let mut s = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    for factor in [1.001, 1.01, 1.5, 3.0, 100.0] {
        let mut dmv = SeedMv::new(body, TALK_MAX_STEP * factor);
        assert_eq!(dmv.step_state(&mut s), Err(StepError::StepTooLarge));
        assert_eq!(s.m, TALK_M0);
        assert_eq!(s.q, [1.0, 0.0, 0.0, 0.0]);
    }
    // just inside, the step exists and is a rotation
    let x = SeedMv::new(body, TALK_MAX_STEP * 0.999)
        .step_matrix(&TALK_M0)
        .unwrap();
    let det = x[0][0] * (x[1][1] * x[2][2] - x[1][2] * x[2][1])
        - x[0][1] * (x[1][0] * x[2][2] - x[1][2] * x[2][0])
        + x[0][2] * (x[1][0] * x[2][1] - x[1][1] * x[2][0]);
    assert!((det - 1.0).abs() < 1e-12);
}

/// Checks the weak spots of docs/MATH.md §2: the result is an `Err`, or a momentum that keeps
/// `|m|` and the energy (a correct DMV step does), never NaN.
fn err_or_correct(body: Body<f64>, h: f64, m0: [f64; 3]) -> Result<[f64; 3], StepError> {
    let mut m = m0;
    let r = SeedMv::new(body, h).step(&mut m);
    match r {
        Ok(()) => {
            assert!(m.iter().all(|x| x.is_finite()));
            let (c0, c1) = (body.casimir(&m0), body.casimir(&m));
            assert!((c1 - c0).abs() <= 1e-13 * c0.max(1e-300));
            Ok(m)
        }
        Err(e) => {
            assert_eq!(m, m0, "state changed on error");
            Err(e)
        }
    }
}

#[test]
fn zero_momentum_with_equal_moments_is_refused_or_exact() {
    let sphere = Body::from_inertia([1.0, 1.0, 1.0]).unwrap();
    if let Ok(m) = err_or_correct(sphere, 0.1, [0.0; 3]) {
        assert_eq!(m, [0.0; 3]);
    }
    let top = Body::from_inertia([1.0, 1.0, 2.0]).unwrap();
    if let Ok(m) = err_or_correct(top, 0.1, [0.0; 3]) {
        assert_eq!(m, [0.0; 3]);
    }
}

#[test]
fn momentum_along_a_principal_axis_is_refused_or_a_fixed_point() {
    let body = talk_body();
    for axis in 0..3 {
        let mut m0 = [0.0; 3];
        m0[axis] = 1.0;
        for h in [0.05, 0.1, 0.3, 0.5] {
            if let Ok(m) = err_or_correct(body, h, m0) {
                assert!(dist(m, m0) <= 1e-13, "axis {axis} h {h}: {m:?}");
            }
        }
    }
}

#[test]
fn symmetric_body_is_refused_or_matches_the_rotation_about_the_symmetry_axis() {
    // I1 = I2: m3 is constant and (m1, m2) rotates; the DMV step keeps |m| and m3
    let top = Body::from_inertia([1.0, 1.0, 2.0]).unwrap();
    if let Ok(m) = err_or_correct(top, 0.1, [0.3, 0.4, 1.2]) {
        assert!((m[2] - 1.2).abs() < 1e-13);
    }
}

#[test]
fn planar_body_is_refused_as_degenerate() {
    // J3 = 0: the published algorithm needs J^-1
    let plate = Body::from_inertia([1.0, 2.0, 3.0]).unwrap();
    assert_eq!(plate.mass_matrix()[2], 0.0);
    assert_eq!(
        err_or_correct(plate, 0.1, [0.6, -0.5, 0.7]),
        Err(StepError::Degenerate)
    );
}

#[test]
fn non_finite_inputs_are_refused() {
    let body = talk_body();
    let mut m = [f64::NAN, 0.0, 1.0];
    assert_eq!(
        SeedMv::new(body, 0.1).step(&mut m),
        Err(StepError::NonFinite)
    );
    let mut m = TALK_M0;
    assert_eq!(
        SeedMv::new(body, f64::INFINITY).step(&mut m),
        Err(StepError::NonFinite)
    );
    assert_eq!(
        SeedMv::new(body, f64::NAN).step(&mut m),
        Err(StepError::NonFinite)
    );
    assert_eq!(m, TALK_M0);
    let mut s = State::new(TALK_M0, [0.0; 4]);
    assert_eq!(
        SeedMv::new(body, 0.1).step_state(&mut s),
        Err(StepError::NonFinite)
    );
}

#[test]
fn huge_and_tiny_momenta_are_scale_invariant() {
    // X depends on h m only through h m / |J|: scaling m by k and h by 1/k gives the same X
    let body = talk_body();
    let x_ref = SeedMv::new(body, 0.1).step_matrix(&TALK_M0).unwrap();
    for k in [1e-150, 1e-30, 1e30, 1e150] {
        let m = [TALK_M0[0] * k, TALK_M0[1] * k, TALK_M0[2] * k];
        let x = SeedMv::new(body, 0.1 / k).step_matrix(&m).unwrap();
        for r in 0..3 {
            for c in 0..3 {
                assert!((x[r][c] - x_ref[r][c]).abs() < 1e-14, "k = {k:e}");
            }
        }
    }
}

#[test]
fn f32_talk_case_order_and_invariants() {
    let body = Body::<f32>::from_mass_matrix(to_f32(TALK_J)).unwrap();
    let hs = [0.2f64, 0.1, 0.05];
    let errs: Vec<f64> = hs
        .iter()
        .map(|&h| talk_error_at_10(&mut SeedMv::new(body, h as f32), h))
        .collect();
    let p = observed_order(&hs, &errs);
    assert!((p - 2.0).abs() <= 0.05, "f32 order {p}");
    // invariants over 1e4 steps in f32
    let mut dmv = SeedMv::new(body, 0.1f32);
    let mut s = State::new(to_f32(TALK_M0), [1.0f32, 0.0, 0.0, 0.0]);
    let c0 = body.casimir(&s.m) as f64;
    let e0 = body.energy(&s.m) as f64;
    let p0 = to_f64(s.spatial_momentum());
    let steps = 10_000;
    for _ in 0..steps {
        dmv.step_state(&mut s).unwrap();
    }
    // round-off in f32 accumulates at most linearly: N eps (measured about 1.5e-4 here)
    let tol = steps as f64 * f32::EPSILON as f64;
    assert!((body.casimir(&s.m) as f64 - c0).abs() / c0 < tol);
    assert!((body.energy(&s.m) as f64 - e0).abs() / e0 < tol);
    assert!(dist(to_f64(s.spatial_momentum()), p0) / norm(p0) < tol);
    // past the limit in f32 too
    let mut m = to_f32(TALK_M0);
    assert_eq!(
        SeedMv::new(body, (TALK_MAX_STEP * 1.01) as f32).step(&mut m),
        Err(StepError::StepTooLarge)
    );
}

#[test]
fn momentum_on_an_axis_at_the_step_where_two_roots_collide() {
    // m = r e_i makes X a rotation about e_i, so mu = J_i^2 is a root and the other two solve
    // mu^2 - (J_j^2 + J_k^2 - h^2 r^2) mu + J_j^2 J_k^2 = 0. They collide with each other at
    // h r = J_j - J_k, and with J_i^2 where h^2 r^2 = J_j^2 + J_k^2 - J_i^2 - J_j^2 J_k^2 / J_i^2.
    // There the eigenvectors are not unique: Err or the exact answer (m is a fixed point).
    let body = talk_body();
    let [j1, j2, j3] = TALK_J;
    let double_in_plane = j2 - j3; // axis 1
    let with_axis = (j1 * j1 + j3 * j3 - j2 * j2 - j1 * j1 * j3 * j3 / (j2 * j2)).sqrt(); // axis 2
    let cases = [
        ([1.0, 0.0, 0.0], double_in_plane),
        ([0.0, 1.0, 0.0], with_axis),
    ];
    for (m0, h) in cases {
        for dh in [0.0, 1e-12, -1e-12] {
            if let Ok(m) = err_or_correct(body, h + dh, m0) {
                assert!(dist(m, m0) <= 1e-12, "m0 {m0:?} h {h}: {m:?}");
            }
        }
    }
}
