//! `Mv`, the closed-form DMV step: against `SeedMv` (a different algorithm for the same map),
//! the reference solution, conservation laws over 10^6 steps, time reversal, its existence
//! limit, and the degenerate inputs where the talk's algorithm fails. Agreement with the
//! general Cardoso–Leite solver, degenerate cases included, is in `lab/tests/mv_vs_general.rs`.

#![allow(clippy::needless_range_loop)] // index loops read like the matrix formulas

mod common;

use common::*;
use rigid3::{Body, Exact, Integrator, Mv, PreMv, SeedMv, State, StepError};

fn talk_body() -> Body<f64> {
    Body::from_mass_matrix(TALK_J).unwrap()
}

#[test]
fn agrees_with_the_talks_algorithm_on_random_inputs() {
    let mut rng = Rng::new(31);
    let (mut compared, mut worst) = (0, 0.0f64);
    while compared < 10_000 {
        let j = [
            rng.range(0.05, 1.0),
            rng.range(0.05, 1.0),
            rng.range(0.05, 1.0),
        ];
        let body = Body::from_mass_matrix(j).unwrap();
        let d = rng.direction();
        let r = rng.range(0.1, 3.0);
        let m0 = [r * d[0], r * d[1], r * d[2]];
        let h = rng.range(0.001, 1.0) * Mv::max_step(&body, &m0).min(10.0);
        let mut a = State::new(m0, [1.0, 0.0, 0.0, 0.0]);
        let mut b = a;
        match (
            Mv::new(body, h).step_state(&mut a),
            SeedMv::new(body, h).step_state(&mut b),
        ) {
            (Ok(()), Ok(())) => {
                compared += 1;
                worst = worst.max(dist(a.m, b.m) / r);
                for k in 0..4 {
                    worst = worst.max((a.q[k] - b.q[k]).abs());
                }
            }
            (Ok(()), Err(StepError::Degenerate)) => {}
            (x, y) => panic!("Mv {x:?}, SeedMv {y:?} at h {h} J {j:?} m {m0:?}"),
        }
    }
    assert!(worst <= 1e-13, "max difference {worst:e}");
}

#[test]
fn talk_case_is_second_order_with_the_published_constant() {
    let body = talk_body();
    let hs: Vec<f64> = (3..8).map(|k| 0.5f64.powi(k)).collect();
    let errs: Vec<f64> = hs
        .iter()
        .map(|&h| talk_error_at_10(&mut Mv::new(body, h), h))
        .collect();
    let p = observed_order(&hs, &errs);
    assert!((p - 2.0).abs() <= 0.05, "order {p}");
    let constant = errs.last().unwrap() / hs.last().unwrap().powi(2);
    eprintln!("Mv, talk's case at t = 10: order {p:.3}, error constant {constant:.3}");
    assert!((constant - 0.51).abs() <= 0.05, "error constant {constant}");
}

fn drift_run<T: rigid3::Real>(steps: usize, h: f64) -> [f64; 3] {
    let body = Body::<T>::from_mass_matrix(TALK_J.map(T::from_f64)).unwrap();
    let mut mv = Mv::new(body, T::from_f64(h));
    let mut s = State::new(
        TALK_M0.map(T::from_f64),
        [T::ONE, T::ZERO, T::ZERO, T::ZERO],
    );
    let wide = |s: &State<T>| {
        let m = s.m.map(|x| x.to_f64());
        let b = Body::<f64>::from_mass_matrix(TALK_J).unwrap();
        let p = State::new(m, s.q.map(|x| x.to_f64())).spatial_momentum();
        (b.casimir(&m), b.energy(&m), p)
    };
    let (c0, e0, p0) = wide(&s);
    let mut d = [0.0f64; 3];
    for k in 0..steps {
        mv.step_state(&mut s).unwrap();
        if k % 97 == 0 || k + 1 == steps {
            let (c, e, p) = wide(&s);
            d[0] = d[0].max((c - c0).abs() / c0);
            d[1] = d[1].max((e - e0).abs() / e0);
            d[2] = d[2].max(dist(p, p0) / norm(p0));
        }
    }
    d
}

#[test]
fn talk_case_conserves_invariants_over_a_million_steps_f64() {
    let d = drift_run::<f64>(1_000_000, 0.1);
    println!(
        "f64 drift over 1e6 steps: |m|^2 {:e}, E {:e}, R(q)m {:e}",
        d[0], d[1], d[2]
    );
    assert!(d.iter().all(|&x| x <= 1e-12), "{d:?}");
}

#[test]
fn talk_case_conserves_invariants_over_a_million_steps_f32() {
    let d = drift_run::<f32>(1_000_000, 0.1);
    println!(
        "f32 drift over 1e6 steps: |m|^2 {:e}, E {:e}, R(q)m {:e}",
        d[0], d[1], d[2]
    );
    assert!(d.iter().all(|&x| x <= 1e-4), "{d:?}");
}

#[test]
fn step_back_with_minus_h_is_the_identity() {
    let mut rng = Rng::new(37);
    for _ in 0..2000 {
        let j = [
            rng.range(0.0, 1.0),
            rng.range(0.05, 1.0),
            rng.range(0.05, 1.0),
        ];
        let body = Body::from_mass_matrix(j).unwrap();
        let d = rng.direction();
        let m0 = [d[0], d[1], d[2]];
        let h = rng.range(0.001, 0.9) * Mv::max_step(&body, &m0).min(10.0);
        let mut s = State::new(m0, [1.0, 0.0, 0.0, 0.0]);
        Mv::new(body, h).step_state(&mut s).unwrap();
        Mv::new(body, -h).step_state(&mut s).unwrap();
        assert!(dist(s.m, m0) <= 1e-14, "{:e} J {j:?} h {h}", dist(s.m, m0));
        let dq = (s.q[0] - 1.0)
            .abs()
            .max(s.q[1].abs())
            .max(s.q[2].abs())
            .max(s.q[3].abs());
        assert!(dq <= 1e-14, "attitude {dq:e}");
    }
}

#[test]
fn max_step_on_the_talks_case() {
    let body = talk_body();
    let hmax = Mv::max_step(&body, &TALK_M0);
    eprintln!("Mv::max_step, talk's case: {hmax:.10}");
    assert!((hmax - TALK_MAX_STEP).abs() <= 1e-8, "{hmax}");
    let mut s = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    Mv::new(body, 0.999 * hmax).step_state(&mut s).unwrap();
    assert!((body.casimir(&s.m) - body.casimir(&TALK_M0)).abs() < 1e-14);
    let mut s = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    assert_eq!(
        Mv::new(body, 1.001 * hmax).step_state(&mut s),
        Err(StepError::StepTooLarge)
    );
    assert_eq!(s, State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]));
    let mut m = TALK_M0;
    assert_eq!(
        Mv::new(body, -1.001 * hmax).step(&mut m),
        Err(StepError::StepTooLarge)
    );
    assert_eq!(m, TALK_M0);
}

#[test]
fn max_step_matches_where_the_talks_cubic_gets_a_negative_root() {
    // independent check: bisect on SeedMv, whose existence test solves the cubic
    let mut rng = Rng::new(41);
    for _ in 0..300 {
        let j = [
            rng.range(0.05, 1.0),
            rng.range(0.05, 1.0),
            rng.range(0.05, 1.0),
        ];
        let body = Body::from_mass_matrix(j).unwrap();
        let d = rng.direction();
        let m0 = [d[0], d[1], d[2]];
        let hmax = Mv::max_step(&body, &m0);
        let exists = |h: f64| {
            let mut m = m0;
            !matches!(
                SeedMv::new(body, h).step(&mut m),
                Err(StepError::StepTooLarge)
            )
        };
        let (mut lo, mut hi) = (0.0, 50.0);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if exists(mid) {
                lo = mid
            } else {
                hi = mid
            }
        }
        // SeedMv is the oracle only where it solves: its first failure point from below
        assert!(exists(hmax * (1.0 - 1e-9)), "J {j:?} m {m0:?} hmax {hmax}");
        assert!(
            (hi - hmax).abs() <= 1e-8 * hmax || !exists(hmax * (1.0 + 1e-9)),
            "{hi} vs {hmax}"
        );
        assert!(
            !exists(hmax * (1.0 + 1e-6)),
            "J {j:?} m {m0:?}: step exists past {hmax}"
        );
    }
}

/// Steps once and checks against the exact statement of the degenerate case.
fn step_ok(body: Body<f64>, h: f64, m0: [f64; 3]) -> State<f64> {
    let mut s = State::new(m0, [1.0, 0.0, 0.0, 0.0]);
    Mv::new(body, h).step_state(&mut s).unwrap();
    assert!(s.m.iter().chain(s.q.iter()).all(|x| x.is_finite()));
    let (c0, c1) = (body.casimir(&m0), body.casimir(&s.m));
    assert!(
        (c1 - c0).abs() <= 1e-14 * c0.max(f64::MIN_POSITIVE),
        "casimir {c0} {c1}"
    );
    let (e0, e1) = (body.energy(&m0), body.energy(&s.m));
    assert!(
        (e1 - e0).abs() <= 1e-14 * e0.max(f64::MIN_POSITIVE),
        "energy {e0} {e1}"
    );
    let p0 = State::new(m0, [1.0, 0.0, 0.0, 0.0]).spatial_momentum();
    assert!(dist(s.spatial_momentum(), p0) <= 1e-14 * norm(p0).max(f64::MIN_POSITIVE));
    s
}

#[test]
fn zero_momentum_is_a_fixed_point_for_every_body() {
    for i in [[1.0, 1.0, 1.0], [1.0, 1.0, 2.0], [1.0, 2.0, 3.0], TALK_I] {
        let s = step_ok(Body::from_inertia(i).unwrap(), 0.1, [0.0; 3]);
        assert_eq!(s.m, [0.0; 3]);
        assert!((s.q[0] - 1.0).abs() < 1e-15);
    }
}

#[test]
fn sphere_does_not_move_m_and_rotates_about_it() {
    // I = (1, 1, 1), J = I/2: M = X J - J X^T = sin(theta) hat(n) for X the rotation by theta
    // about n, so the DMV step rotates about m by asin(h |m|) (the flow: by h |m|)
    let body = Body::from_inertia([1.0, 1.0, 1.0]).unwrap();
    let m0 = [0.3, -0.2, 0.9];
    let s = step_ok(body, 0.1, m0);
    assert!(dist(s.m, m0) < 1e-15);
    let angle = (0.1 * norm(m0)).asin();
    let (c, sn) = ((angle / 2.0).cos(), (angle / 2.0).sin() / norm(m0));
    let q = [c, sn * m0[0], sn * m0[1], sn * m0[2]];
    for k in 0..4 {
        assert!((s.q[k] - q[k]).abs() < 1e-15, "{:?} vs {q:?}", s.q);
    }
}

#[test]
fn symmetric_top_keeps_its_axial_momentum() {
    for i in [[1.0, 1.0, 2.0], [2.0, 1.0, 2.0], [1.5, 1.0, 1.0]] {
        let body = Body::from_inertia(i).unwrap();
        let m0 = [0.3, 0.4, 1.2];
        let s = step_ok(body, 0.2, m0);
        let axis = if i[0] == i[1] {
            2
        } else if i[0] == i[2] {
            1
        } else {
            0
        };
        assert!((s.m[axis] - m0[axis]).abs() < 1e-15, "{i:?}");
    }
}

#[test]
fn momentum_on_a_principal_axis_is_a_fixed_point() {
    let body = talk_body();
    let [j1, j2, j3] = TALK_J;
    // including the steps where two roots of the talk's cubic collide
    let special = (j1 * j1 + j3 * j3 - j2 * j2 - j1 * j1 * j3 * j3 / (j2 * j2)).sqrt();
    for (axis, h) in [(0, 0.1), (1, 0.3), (2, 0.5), (0, j2 - j3), (1, special)] {
        let mut m0 = [0.0; 3];
        m0[axis] = 1.0;
        let s = step_ok(body, h, m0);
        assert!(dist(s.m, m0) <= 1e-15, "axis {axis} h {h}: {:?}", s.m);
    }
}

/// Needles (`I1` small, `I2 ~ I3`) turning end over end, within half their step limit at
/// `h |Omega|` up to 0.2, left alone for 5000 steps: `|m|^2` and the energy held to
/// round-off, every step `Ok` (the exact flow keeps them; `PreMv` runs the same step). Found
/// in review: the free-running map amplified its input's round-off where `|hn m|^2` is large
/// against some `d_i` (`J = (0.995, 0.005, 0.005)`, `h |m|` near `sqrt(J_max J_min)`):
/// `|m|^2` 44 % off after 3000 steps at `I = (0.01, 1, 1)`, `m = (0, 0.6, 0.8)`, `h = 0.1`;
/// `1e104` after 88 steps at `h = 0.12`, every step `Ok`; 70 of 400 random needles.
#[test]
fn needles_left_alone_hold_their_invariants() {
    let run = |body: Body<f64>, m0: [f64; 3], h: f64, steps: usize| {
        let mut mv = Mv::new(body, h);
        let mut m = m0;
        let (c0, e0) = (body.casimir(&m0), body.energy(&m0));
        let mut worst = 0.0f64;
        for k in 0..steps {
            if let Err(e) = mv.step(&mut m) {
                panic!("{:?} {m0:?} h {h}: {e} at step {k}", body.inertia());
            }
            let dc = (body.casimir(&m) - c0).abs() / c0;
            let de = (body.energy(&m) - e0).abs() / e0;
            worst = worst.max(dc).max(de);
        }
        worst
    };
    // the named cases
    for (i, h) in [
        ([0.01, 1.0, 1.0], 0.1),
        ([0.01, 1.0, 1.0], 0.12),
        ([0.001, 1.0, 1.0005], 0.1),
    ] {
        let body = Body::from_inertia(i).unwrap();
        let worst = run(body, [0.0, 0.6, 0.8], h, 3000);
        assert!(worst <= 1e-13, "{i:?} h {h}: {worst:e}");
        // PreMv runs the same step on its modified body (14-18 % off before)
        let mut pre = rigid3::PreMv::new(body, h, 4).unwrap();
        let mut m = [0.0, 0.6, 0.8];
        for _ in 0..3000 {
            pre.step(&mut m).unwrap();
        }
        let dc = (body.casimir(&m) - 1.0).abs();
        assert!(dc <= 1e-13, "PreMv order 4, {i:?} h {h}: |m|^2 {dc:e}");
    }
    // random needles
    let mut rng = Rng::new(77);
    let mut runs = 0;
    while runs < 300 {
        let i1 = 10f64.powf(-rng.range(0.0, 3.0));
        let i3 = 1.0 + rng.range(0.0, 0.05f64.min(i1));
        let body = Body::from_inertia([i1, 1.0, i3]).unwrap();
        let m = [
            rng.range(-0.05, 0.05),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ];
        let omega = body.angular_velocity(&m);
        let w = (omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]).sqrt();
        let h = rng.range(0.01, 0.2) / w;
        if h > 0.5 * Mv::max_step(&body, &m) {
            continue;
        }
        runs += 1;
        let worst = run(body, m, h, 5000);
        assert!(
            worst <= 1e-12,
            "{:?} {m:?} h {h}: {worst:e}",
            body.inertia()
        );
    }
}

/// Needles turned by steps with `h |m|` well above `sqrt(J_min J_max)`, where the quartic's
/// two largest roots are close (`J = (1, 5e-8, 5e-8)`, `h |m| = 5e-3`: 1.7 % of `delta`
/// apart). Newton stopped at an absolute tolerance there and left `delta` 5e-8 off relative:
/// the step came out up to 1e-6 off the sphere and was refused (`Degenerate`) from half the
/// starts at `I_min / I_max = 1e-7` (every one at `1e-8`), and after changes of `h` by
/// 5-95 % on `1e-6` (found by a first-use trial). Oracles: `Exact` (elliptic functions),
/// `|m|^2` and, on these symmetric needles, the axial momentum `m_1` (both kept by the
/// map), and the trial's change of `h` against a fresh `Mv` from the same state. At `1e-8`
/// and `1e-9` the solved step's conditioning (`eps J_max / J_min`, 4e-8 and 4e-7) leaves
/// `m_1`, which is `0.3 eps |m|` there, without a correct digit: those steps are checked for
/// being taken and for `|m|` alone.
#[test]
fn needles_step_where_the_quartics_largest_roots_are_close() {
    let mut rng = Rng::new(0x0dd_5eed);
    for eps in [1e-6, 1e-7, 1e-8, 1e-9] {
        let body = Body::<f64>::from_inertia([eps, 1.0, 1.0]).unwrap();
        let mut worst = [0.0f64; 3];
        for _ in 0..20 {
            let d = rng.direction();
            // |Omega| = 0.3 about the transverse axes and along the rod alike
            let m0 = [0.3 * eps * d[0], 0.3 * d[1], 0.3 * d[2]];
            let h0 = 0.0167;
            let mut mv = Mv::new(body, h0);
            let mut s = State::new(m0, [1.0, 0.0, 0.0, 0.0]);
            let mut t = 0.0;
            for n in 0..600 {
                // a jittering clock, +-2.5 %
                let h = h0 * (1.0 + 0.05 * (((n * 7919) % 13) as f64 / 13.0 - 0.5));
                mv.set_step_size(h);
                mv.step_state(&mut s)
                    .unwrap_or_else(|e| panic!("eps {eps:e} m0 {m0:?} step {n}: {e:?}"));
                t += h;
            }
            let r = norm(m0);
            let exact = Exact::at(&body, &State::new(m0, [1.0, 0.0, 0.0, 0.0]), t).unwrap();
            worst[0] = worst[0].max((norm(s.m) - r).abs() / r);
            worst[1] = worst[1].max((s.m[0] - m0[0]).abs() / r);
            worst[2] = worst[2].max(dist(s.m, exact.m) / r);
        }
        println!(
            "needle {eps:e}, 600 jittered steps: |m| {:.1e}, m_1 {:.1e}, from Exact {:.1e}",
            worst[0], worst[1], worst[2]
        );
        // each solved step is accurate to about eps J_max / J_min (Mv's docs), and the
        // error in m_1 moves the rod's fast spin m_1 / I_1: against Exact only down to 1e-7
        // (the method's own error, (h |Omega|)^2 |Omega| t / 12, is about 1e-5)
        assert!(
            worst[0] <= 8.0 * f64::EPSILON * 2.0 / eps,
            "{eps:e}: {worst:?}"
        );
        if eps >= 1e-7 {
            assert!(worst[1] <= 1e-10 && worst[2] <= 1e-4, "{eps:e}: {worst:?}");
        }
    }

    // the trial's change of h on I = (1e-6, 1, 1)
    let body = Body::<f64>::from_inertia([1e-6, 1.0, 1.0]).unwrap();
    let mut mv = Mv::new(body, 0.17655808168376846);
    let mut m = [
        -2.1342451809408865e-7,
        -0.13335013871443654,
        0.16330244854674594,
    ];
    mv.step(&mut m).unwrap();
    mv.set_step_size(0.2244325479212626);
    let mut fresh = m;
    mv.step(&mut m).unwrap();
    Mv::new(body, 0.2244325479212626).step(&mut fresh).unwrap();
    // within the solved step's conditioning, eps J_max / J_min = 4.4e-10 (the tracked step
    // carries the trajectory's invariants to the new h, the fresh one takes its input's)
    assert!(dist(m, fresh) <= 1e-10 * norm(m), "{m:?} {fresh:?}");
}

/// An f32 needle whose smallest moment is below the precision of the largest
/// (`I = (1e-6, 1, 1)`: `Body` sets both small mass-matrix entries, within `4 eps I_max`, to
/// zero) is a zero moment to DMV: `Mv` refuses every step, state untouched, and `max_step`
/// says zero, as `Body::from_inertia`'s docs say (a first-use trial sub-stepped on the
/// refusal and never got through; a `Degenerate` there instead turned `PreMv`'s refusals of
/// too large steps, whose modified bodies degenerate the same way, into `Degenerate` too, so
/// the docs say it). The moments themselves are kept: `Rk4` steps the body, against the f64
/// `Rk4` of the same inputs.
#[test]
fn an_f32_needle_below_the_precision_is_no_body_for_dmv() {
    let body = Body::<f32>::from_inertia([1e-6, 1.0, 1.0]).unwrap();
    let j = body.mass_matrix();
    assert_eq!(j.iter().filter(|&&x| x == 0.0).count(), 2, "{j:?}");
    let start = State::new([1e-7f32, 0.6, -0.8], [1.0, 0.0, 0.0, 0.0]);
    assert_eq!(Mv::max_step(&body, &start.m), 0.0);
    for h in [1e-7f32, 1e-3, 0.0167, 0.2] {
        let mut s = start;
        assert_eq!(
            Mv::new(body, h).step_state(&mut s),
            Err(StepError::StepTooLarge),
            "h {h}"
        );
        assert_eq!(s, start);
        let mut m = start.m;
        assert_eq!(
            Mv::new(body, h).step(&mut m),
            Err(StepError::StepTooLarge),
            "h {h}"
        );
    }
    let mut s = start;
    let mut rk = rigid3::Rk4::new(body, 1e-3f32);
    let b64 = Body::<f64>::from_inertia([1e-6, 1.0, 1.0]).unwrap();
    let mut s64 = State::new(start.m.map(f64::from), [1.0, 0.0, 0.0, 0.0]);
    let mut rk64 = rigid3::Rk4::new(b64, 1e-3);
    for _ in 0..100 {
        rk.step_state(&mut s).unwrap();
        rk64.step_state(&mut s64).unwrap();
    }
    assert!(
        dist(s.m.map(f64::from), s64.m) < 1e-5,
        "{:?} {:?}",
        s.m,
        s64.m
    );
}

/// What costs f32 accuracy is a needle (a small principal moment `I_min / I_max`: two small
/// mass-matrix entries, so the step's 3x3 system is ill-conditioned), not a small mass-matrix
/// entry on its own: a near-planar body (`I_3 = I_1 + I_2 - 1e-4`, `J_min / J_max` 5e-5) keeps
/// f32 `Mv` as close to f64 as on a compact body (closer than f32 RK4 on both), while a needle
/// at `I_min / I_max = 1e-2` loses a few times what f32 RK4 loses there (the same method in f64
/// is the oracle for each; the bound documented on `Mv`). Printed: the worst distances.
#[test]
fn f32_accuracy_is_set_by_the_needle_not_by_a_small_mass_matrix_entry() {
    let mut rng = Rng::new(0x2e_ed1e);
    for (label, inertia, mv_bound, times_rk4) in [
        ("compact (1, 2, 2.5)", [1.0, 2.0, 2.5], 1e-4, 1.0),
        (
            "near-planar (1, 1, 2 - 1e-4)",
            [1.0, 1.0, 2.0 - 1e-4],
            1e-4,
            1.0,
        ),
        ("needle (1e-2, 1, 1.003)", [1e-2, 1.0, 1.003], 2e-3, 4.0),
    ] {
        let b32 = Body::<f32>::from_inertia(inertia.map(|x| x as f32)).unwrap();
        let i64_ = b32.inertia().map(f64::from);
        let b64 = Body::<f64>::from_inertia(i64_).unwrap();
        let (mut worst_mv, mut worst_rk) = (0.0f64, 0.0f64);
        for _ in 0..8 {
            let m = rng.direction().map(|x| x as f32);
            let m64 = m.map(f64::from);
            let omega = norm([m64[0] / i64_[0], m64[1] / i64_[1], m64[2] / i64_[2]]);
            // h |Omega| from 0.01 to 0.1, f32-representable so both runs take the same h
            let h = (rng.range(0.01, 0.1) / omega) as f32;
            let q0 = [1.0, 0.0, 0.0, 0.0];
            let (mut a32, mut a64) = (State::new(m, q0), State::new(m64, q0.map(f64::from)));
            let (mut r32, mut r64) = (a32, a64);
            let (mut mv32, mut mv64) = (Mv::new(b32, h), Mv::new(b64, f64::from(h)));
            let (mut rk32, mut rk64) = (
                rigid3::Rk4::new(b32, h),
                rigid3::Rk4::new(b64, f64::from(h)),
            );
            for _ in 0..5000 {
                mv32.step_state(&mut a32).unwrap();
                mv64.step_state(&mut a64).unwrap();
                rk32.step_state(&mut r32).unwrap();
                rk64.step_state(&mut r64).unwrap();
            }
            worst_mv = worst_mv.max(qdist(a32.q.map(f64::from), a64.q));
            worst_rk = worst_rk.max(qdist(r32.q.map(f64::from), r64.q));
        }
        println!("{label}: f32 from f64 after 5000 steps, Mv {worst_mv:.2e}, Rk4 {worst_rk:.2e}");
        assert!(worst_mv < mv_bound, "{label}: {worst_mv:e}");
        assert!(
            worst_mv < times_rk4 * worst_rk,
            "{label}: {worst_mv:e} {worst_rk:e}"
        );
    }
}

/// The real loop in f32 keeps a slow turn's motion: a filter that corrects `m` or `q` every
/// tick (here by exactly one ulp, alternating in sign, so the corrections cancel and are
/// exact in both precisions) and a clock that reads zero every other tick (a pause) leave
/// `Mv` as close to f64 as the uncorrected loop. Before (found in review), an outside
/// change or a pause dropped the rounding the steps carry, and the slow motion's rounding
/// was lost with a bias: after `2 x 10^5` ticks at 8.4e-4 rad/s and 1 kHz `|m|^2` drifted
/// 1.9e-3 (1e-3 at `10^5`, 5.4e-3 at `10^6`). Oracle: the same sequence in f64.
#[test]
fn f32_slow_turns_keep_their_motion_under_corrections_and_pauses() {
    fn run<T: rigid3::Real>(mode: u8, n: usize) -> ([f64; 3], [f64; 4]) {
        let body = Body::<T>::from_inertia([60.0, 95.0, 120.0].map(T::from_f64)).unwrap();
        let h = T::from_f64(0.001);
        let mut mv = Mv::new(body, h);
        let m0 = [0.0216f32, -0.057, 0.0576].map(|x| T::from_f64(f64::from(x)));
        let mut s = State::new(m0, [1.0, 0.0, 0.0, 0.0].map(T::from_f64));
        // one f32 ulp of m[1] (in [2^-5, 2^-4) throughout) and of q near 0.5
        let (um, uq) = (2f64.powi(-28), 2f64.powi(-25));
        for k in 0..n {
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            match mode {
                0 => s.m[1] += T::from_f64(sign * um),
                1 => s.q[1] += T::from_f64(sign * uq),
                _ => mv.set_step_size(if k % 2 == 0 { T::ZERO } else { h }),
            }
            mv.step_state(&mut s).unwrap();
        }
        (s.m.map(|x| x.to_f64()), s.q.map(|x| x.to_f64()))
    }
    let n = 200_000;
    let c0 = norm(to_f64([0.0216f32, -0.057, 0.0576])).powi(2);
    for (mode, label) in [(0, "m corrected"), (1, "q corrected"), (2, "paused")] {
        let (m32, q32) = run::<f32>(mode, n);
        let (m64, q64) = run::<f64>(mode, n);
        let casimir = (norm(m32).powi(2) / c0 - 1.0).abs();
        let (dm, dq) = (dist(m32, m64) / norm(m64), qdist(q32, q64));
        println!(
            "{label}: f32 from f64 after {n} ticks: m {dm:.1e}, q {dq:.1e}, |m|^2 {casimir:.1e}"
        );
        assert!(
            casimir < 1e-6 && dm < 1e-6 && dq < 1e-6,
            "{label}: {casimir:e} {dm:e} {dq:e}"
        );
    }
}

/// One f32 `Mv` switched between two trajectories every tick (a caller that steps two bodies'
/// states with one integrator, or replaces the state) does not carry one trajectory's
/// rounding into the other: the small trajectory's `|m|^2` stays at round-off. Found in
/// review of a first version that kept the carry across any change of `m` below 64 of its
/// ulps: `|m|` of the smaller drifted 6.8e-3 in `2 x 10^4` ticks (6.6e-2 in `2 x 10^5`).
/// Oracle: the Casimir `|m|^2`. (The large trajectory's `|m|^2` moves 2.5e-4 here, as before
/// the carry was kept across corrections: each tick re-takes its invariants from a rounded
/// state, the known cost of a loop that replaces the state every tick, `Mv`'s docs.)
#[test]
fn f32_trajectories_switched_every_tick_keep_their_own_rounding() {
    let body = Body::<f32>::from_inertia([60.0, 95.0, 120.0]).unwrap();
    let mut mv = Mv::new(body, 0.001);
    let mut a = State::new([0.0216f32, -0.057, 0.0576], [1.0, 0.0, 0.0, 0.0]);
    let mut b = State::new([6.0e-4f32, 1.0e-4, -2.0e-4], [0.0, 1.0, 0.0, 0.0]);
    let c = |s: &State<f32>| norm(to_f64(s.m)).powi(2);
    let (ca, cb) = (c(&a), c(&b));
    for _ in 0..20_000 {
        mv.step_state(&mut a).unwrap();
        mv.step_state(&mut b).unwrap();
    }
    let (da, db) = ((c(&a) / ca - 1.0).abs(), (c(&b) / cb - 1.0).abs());
    println!("switched every tick, 2e4 ticks each: |m|^2 {da:.1e} (large), {db:.1e} (small)");
    assert!(db < 1e-6, "{db:e}");
}

/// A step size that changes by more than 2x (past what the tracked root survives, so it is
/// re-solved) while the caller leaves the state alone: the trajectory goes on, so `|m|^2`,
/// the energy and `R(q) m` stay at round-off (found in review: re-taking the invariants from
/// each re-solved step's input let them drift, 4.4e-13 after 1e5 steps, 4.8e-12 after 1e6;
/// `R(q) m` 2.4e-12).
#[test]
fn large_changes_of_h_keep_the_trajectorys_invariants() {
    let body = talk_body();
    let s0 = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    // talk's case, 0.04 to 0.16: more than 2x apart, so the tracked root is re-solved, in
    // the same scale kappa = J_max; a near-sphere turning near its axis, 0.5 to 1.6: kappa =
    // h max |m_i| at the large steps (up to 1.55, J_max = 1; max_step 1.96), so the scale
    // changes at every re-solve and the invariants' beta must follow it
    let sphere = Body::from_mass_matrix([1.0, 0.95, 0.9]).unwrap();
    // (the last bound: at h |Omega| near 1.5 a turn now and then reads R(q) m 4.8e-14 off,
    // taken back by the next attitude hold, 4 to 6 steps later; 1e6 steps read the same)
    for (label, body, s0, steps, spatial_bound) in [
        (
            "0.04-0.16",
            body,
            s0,
            [0.13, 0.07, 0.11, 0.09, 0.16, 0.04],
            2e-14,
        ),
        (
            "0.5-1.6 (kappa changes)",
            sphere,
            State::new([0.1, 0.2, 0.97], [1.0, 0.0, 0.0, 0.0]),
            [1.6, 0.5, 1.5, 0.6, 1.55, 0.55],
            1e-13,
        ),
        // small changes (the tracked root kept, the invariants rescaled) between large ones
        // (re-solved in another scale): set_step_size's rescale must read the carried scale
        // (reading the taken one failed 23168 of 1e5 steps Degenerate, found in review)
        (
            "0.5-1.6 mixed",
            sphere,
            State::new([0.1, 0.2, 0.97], [1.0, 0.0, 0.0, 0.0]),
            [1.6, 0.5, 0.6, 1.55, 1.4, 0.55],
            1e-13,
        ),
    ] {
        let (c0, e0, p0) = (
            body.casimir(&s0.m),
            body.energy(&s0.m),
            s0.spatial_momentum(),
        );
        let mut mv = Mv::new(body, steps[0]);
        let mut s = s0;
        let mut worst = [0.0f64; 3];
        for k in 0..100_000 {
            mv.set_step_size(steps[k % steps.len()]);
            mv.step_state(&mut s).unwrap();
            worst[0] = worst[0].max((body.casimir(&s.m) - c0).abs() / c0);
            worst[1] = worst[1].max((body.energy(&s.m) - e0).abs() / e0);
            worst[2] = worst[2].max(dist(s.spatial_momentum(), p0) / norm(p0));
        }
        println!(
            "h cycling {label}, 1e5 steps: |m|^2, E, R(q) m {:.1e} {:.1e} {:.1e}",
            worst[0], worst[1], worst[2]
        );
        // measured 0.04-0.16: 8.9e-16, 1.8e-15, 4.3e-15; 0.5-1.6: 1.0e-15, 1.3e-15, 4.8e-14;
        // mixed: 1.0e-15, 1.1e-15, 4.2e-14. Re-taking the invariants at every re-solve gave
        // 7.4e-13 on the first at 1e5 steps; leaving beta in the old scale made the second's
        // steps fail
        assert!(
            worst[0] <= 4e-15 && worst[1] <= 4e-15 && worst[2] <= spatial_bound,
            "h cycling {label}: |m|^2, E, R(q) m: {worst:?}"
        );
    }
}

/// The same in f32 on the talk's case: the invariants stay at f32's round-off while `h`
/// cycles through changes larger than the tracked root survives (re-taken at every re-solve
/// they drifted to 6.1e-4, measured in review).
#[test]
fn large_changes_of_h_keep_the_trajectorys_invariants_f32() {
    let body = Body::<f32>::from_mass_matrix(TALK_J.map(|x| x as f32)).unwrap();
    let s0 = State::new(to_f32(TALK_M0), [1.0, 0.0, 0.0, 0.0]);
    let (c0, e0) = (
        f64::from(body.casimir(&s0.m)),
        f64::from(body.energy(&s0.m)),
    );
    let steps = [0.13f32, 0.07, 0.11, 0.09, 0.16, 0.04];
    let mut mv = Mv::new(body, steps[0]);
    let mut s = s0;
    let mut worst = 0.0f64;
    for k in 0..100_000 {
        mv.set_step_size(steps[k % steps.len()]);
        mv.step_state(&mut s).unwrap();
        let dc = (f64::from(body.casimir(&s.m)) - c0).abs() / c0;
        let de = (f64::from(body.energy(&s.m)) - e0).abs() / e0;
        worst = worst.max(dc).max(de);
    }
    println!("f32, h cycling 0.04-0.16, 1e5 steps: |m|^2 and E within {worst:.1e}");
    assert!(worst <= 4e-6, "f32 invariants {worst:e}");
}

/// The documented error model of a solved step (`Mv`'s docs): `|m|^2` within a few
/// `eps J_max / J_min` of the input's, the condition of the step's 3x3 system on a needle.
/// f32, 2000 random needles (smallest moment 1 to 1e-3 of the others), a fresh solve from a
/// random momentum at `h` from 0.01 to 0.21; measured worst 1.5 of the model here (3.9 over
/// 20000 other draws).
#[test]
fn a_solved_f32_step_on_a_needle_is_within_its_conditioning() {
    let mut rng = Rng::new(2026);
    let (mut worst, mut steps) = (0.0f64, 0);
    while steps < 2000 {
        let i1 = 10f64.powf(-rng.range(0.0, 3.0));
        let i = [i1 as f32, 1.0, (1.0 + rng.range(0.0, 0.05) * i1) as f32];
        let body = Body::<f32>::from_inertia(i).unwrap();
        let j = body.mass_matrix();
        let (j_max, j_min) = (j[0].max(j[1]).max(j[2]), j[0].min(j[1]).min(j[2]));
        let m0 = [
            rng.range(-1.0, 1.0) as f32,
            rng.range(-1.0, 1.0) as f32,
            rng.range(-1.0, 1.0) as f32,
        ];
        let mut m = m0;
        if Mv::new(body, rng.range(0.01, 0.21) as f32)
            .step(&mut m)
            .is_err()
        {
            continue; // past the step's limit: refused, as it should be
        }
        let c0 = f64::from(body.casimir(&m0));
        let err = (f64::from(body.casimir(&m)) - c0).abs() / c0;
        worst = worst.max(err / (f64::from(f32::EPSILON) * f64::from(j_max / j_min)));
        steps += 1;
    }
    println!("f32 needles, one solved step: |m|^2 error up to {worst:.2} eps J_max / J_min");
    assert!(worst <= 8.0, "{worst}");
}

#[test]
fn planar_body_steps_and_conserves() {
    let plate = Body::<f64>::from_inertia([1.0, 2.0, 3.0]).unwrap();
    assert_eq!(plate.mass_matrix()[2], 0.0);
    let mut s = State::new([0.6, -0.5, 0.7], [1.0, 0.0, 0.0, 0.0]);
    let mut mv = Mv::new(plate, 0.1);
    let (c0, e0, p0) = (
        plate.casimir(&s.m),
        plate.energy(&s.m),
        s.spatial_momentum(),
    );
    for _ in 0..10_000 {
        mv.step_state(&mut s).unwrap();
    }
    assert!((plate.casimir(&s.m) - c0).abs() / c0 < 1e-13);
    assert!((plate.energy(&s.m) - e0).abs() / e0 < 1e-13);
    assert!(dist(s.spatial_momentum(), p0) / norm(p0) < 1e-13);
}

#[test]
fn tiny_steps_converge_to_the_flow() {
    // h -> 0: one step is m + h m x Omega + O(h^2)
    let body = talk_body();
    let w = body.angular_velocity(&TALK_M0);
    let f = [
        TALK_M0[1] * w[2] - TALK_M0[2] * w[1],
        TALK_M0[2] * w[0] - TALK_M0[0] * w[2],
        TALK_M0[0] * w[1] - TALK_M0[1] * w[0],
    ];
    for h in [1e-4, 1e-6, 1e-8] {
        let s = step_ok(body, h, TALK_M0);
        for k in 0..3 {
            let rate = (s.m[k] - TALK_M0[k]) / h;
            assert!(
                (rate - f[k]).abs() <= 2.0 * h + 1e-16 / h,
                "h {h}: {rate} vs {}",
                f[k]
            );
        }
    }
}

#[test]
fn huge_and_tiny_momenta_scale_exactly() {
    let body = talk_body();
    let s_ref = step_ok(body, 0.1, TALK_M0);
    for k in [1e-150, 1e-30, 1e30, 1e150] {
        let m = TALK_M0.map(|x| x * k);
        let mut s = State::new(m, [1.0, 0.0, 0.0, 0.0]);
        Mv::new(body, 0.1 / k).step_state(&mut s).unwrap();
        for i in 0..3 {
            assert!((s.m[i] / k - s_ref.m[i]).abs() < 1e-15, "k = {k:e}");
        }
        for i in 0..4 {
            assert!((s.q[i] - s_ref.q[i]).abs() < 1e-15, "k = {k:e}");
        }
    }
}

/// A turn past 60 degrees in one step takes the far branch of the turn's quaternion
/// (`p0^2 = (1 +- root) / 2`), chosen from an estimate that divides by `h |dm|^2`. The step is
/// covariant under scaling the inertia and the momentum together (`Omega` unchanged), so at
/// every scale the attitude must be the scale-1 f64 step's. Before, `|dm|^2` overflowed for
/// `|m|` beyond `sqrt(T::MAX)` (f32 from 1.8e19, f64 from 1e154) and the minus sign was taken:
/// 0.123 rad off, `Ok` (found by a first-use trial).
#[test]
fn large_turns_take_their_branch_at_every_scale() {
    let omega = [9.334014353089962, -1.0457303455141436, 7.468776613394018];
    let inertia = [1.0, 2.0, 2.5];
    let h = 0.0904; // h |Omega| = 1.08, inside max_step (checked below)
    let m1 = [omega[0] * 1.0, omega[1] * 2.0, omega[2] * 2.5];
    let body1 = Body::<f64>::from_inertia(inertia).unwrap();
    assert!(
        h < Mv::max_step(&body1, &m1),
        "max_step {}",
        Mv::max_step(&body1, &m1)
    );
    let mut reference = State::new(m1, [1.0, 0.0, 0.0, 0.0]);
    Mv::new(body1, h).step_state(&mut reference).unwrap();
    // the turn is past 60 degrees: the far branch is taken
    assert!(reference.q[0].abs() < 0.87, "q0 {}", reference.q[0]);
    let mut worst = [0.0f64; 2];
    for e in -37..=37 {
        let k = 10f64.powi(e);
        let b = Body::<f32>::from_inertia(inertia.map(|x| (x * k) as f32)).unwrap();
        let mut s = State::new(m1.map(|x| (x * k) as f32), [1.0, 0.0, 0.0, 0.0]);
        Mv::new(b, h as f32).step_state(&mut s).unwrap();
        let q = s.q.map(f64::from);
        worst[0] = worst[0].max(attitude_angle(q, reference.q));
        assert!(
            attitude_angle(q, reference.q) < 1e-4,
            "f32 scale 1e{e}: {q:?}"
        );
    }
    for e in (-300..=300).step_by(10) {
        let k = 10f64.powi(e);
        let b = Body::<f64>::from_inertia(inertia.map(|x| x * k)).unwrap();
        let mut s = State::new(m1.map(|x| x * k), [1.0, 0.0, 0.0, 0.0]);
        Mv::new(b, h).step_state(&mut s).unwrap();
        worst[1] = worst[1].max(attitude_angle(s.q, reference.q));
        assert!(
            attitude_angle(s.q, reference.q) < 1e-12,
            "f64 scale 1e{e}: {:?}",
            s.q
        );
    }
    println!(
        "worst attitude against the scale-1 f64 step: f32 {:.2e}, f64 {:.2e}",
        worst[0], worst[1]
    );
}

/// The turn of a sphere, or of a body whose momentum is on a principal axis, is
/// `asin(h |Omega|)` about `m` (from `X - X^T = h hat(m)` on a sphere, and likewise in the
/// plane of the axis), at most 90 degrees: the plus sign of `p0^2 = (1 +- root) / 2`. There
/// `(J b) x b = 0` and the step's increment is rounding, and the sign's estimate read that
/// noise as the minus sign: a turn of `pi - asin(h |Omega|)`, 1 rad off, `Ok`, on 997 of 1000
/// spheres at `h |Omega|` in (0.87, 1) (found in review). Oracle: the analytic turn; near the
/// axis (1e-12 off in f64, 1e-5 in f32) the turn is within that of it.
#[test]
fn large_turns_on_an_axis_or_of_a_sphere_are_asin_h_omega() {
    fn turn_f64(j: [f64; 3], m: [f64; 3], h: f64) -> Option<f64> {
        let body = Body::<f64>::from_mass_matrix(j).unwrap();
        if h >= Mv::max_step(&body, &m) {
            return None;
        }
        let mut s = State::new(m, [1.0, 0.0, 0.0, 0.0]);
        Mv::new(body, h).step_state(&mut s).ok()?;
        Some(2.0 * s.q[0].abs().min(1.0).acos())
    }
    fn turn_f32(j: [f64; 3], m: [f64; 3], h: f64) -> Option<f64> {
        let body = Body::<f32>::from_mass_matrix(j.map(|x| x as f32)).unwrap();
        let m = m.map(|x| x as f32);
        if h as f32 >= Mv::max_step(&body, &m) {
            return None;
        }
        let mut s = State::new(m, [1.0f32, 0.0, 0.0, 0.0]);
        Mv::new(body, h as f32).step_state(&mut s).ok()?;
        Some(2.0 * f64::from(s.q[0]).abs().min(1.0).acos())
    }
    let mut rng = Rng::new(0xa515);
    let (mut worst, mut taken) = ([0.0f64; 2], 0);
    for n in 0..3000 {
        let x = rng.range(0.87, 0.999);
        let r = rng.range(0.1, 3.0);
        let sign = if rng.range(-1.0, 1.0) < 0.0 {
            -1.0
        } else {
            1.0
        };
        // a sphere in a random direction, or a triaxial body with m on an axis, nudged
        let (j, m, inertia) = if n % 2 == 0 {
            let d = rng.direction();
            ([1.0, 1.0, 1.0], d.map(|c| r * c), 2.0)
        } else {
            let j = [1.0, 2.0, 3.0];
            let axis = n % 3;
            let mut m = [0.0; 3];
            m[axis] = sign * r;
            let inertia = [j[1] + j[2], j[0] + j[2], j[0] + j[1]][axis];
            (j, m, inertia)
        };
        let h = x * inertia / r;
        let nudge = |m: [f64; 3], e: f64| {
            let d = [1.0, -0.5, 0.25];
            [
                m[0] + e * r * d[0],
                m[1] + e * r * d[1],
                m[2] + e * r * d[2],
            ]
        };
        let exact = x.asin();
        for (k, t) in [
            turn_f64(j, m, h).map(|t| (0, t, 1e-12)),
            turn_f64(j, nudge(m, 1e-12), h).map(|t| (0, t, 1e-9)),
            turn_f32(j, m, h).map(|t| (1, t, 1e-4)),
            turn_f32(j, nudge(m, 1e-5), h).map(|t| (1, t, 1e-2)),
        ]
        .into_iter()
        .flatten()
        .map(|(k, t, tol)| (k, (t, tol)))
        {
            let (t, tol) = t;
            taken += 1;
            worst[k] = worst[k].max((t - exact).abs());
            assert!(
                (t - exact).abs() < tol,
                "J {j:?} m {m:?} h {h}: turn {t}, asin {exact}"
            );
        }
    }
    println!(
        "{taken} large turns: worst |turn - asin(h Omega)| f64 {:.1e}, f32 {:.1e}",
        worst[0], worst[1]
    );
    assert!(taken > 6000, "{taken}");
}

#[test]
fn near_the_separatrix_it_conserves_and_agrees_with_seed() {
    let body = Body::<f64>::from_inertia([1.0, 2.0, 3.0 - 1e-9]).unwrap();
    let body2 = Body::from_inertia([1.0, 2.0, 2.5]).unwrap();
    for b in [body, body2] {
        for m0 in [[1e-3, 1.0, 1e-3], [1e-9, 1.0, 0.0], [0.0, 1.0, 1e-12]] {
            let mut a = m0;
            let mut mv = Mv::new(b, 0.05);
            for _ in 0..2000 {
                mv.step(&mut a).unwrap();
            }
            let c0 = b.casimir(&m0);
            assert!((b.casimir(&a) - c0).abs() / c0 < 1e-13);
            assert!((b.energy(&a) - b.energy(&m0)).abs() / b.energy(&m0) < 1e-13);
        }
    }
}

#[test]
fn a_changed_momentum_is_picked_up_by_the_tracking() {
    // an estimator overwrites m between steps: the next step must be the DMV step of the new m
    let body = talk_body();
    let mut mv = Mv::new(body, 0.1);
    let mut m = TALK_M0;
    mv.step(&mut m).unwrap();
    for (k, scale) in [1.0 + 1e-9, 1.0 + 1e-4, 3.0, 1e-3, 1e2]
        .into_iter()
        .enumerate()
    {
        let mut fresh = [
            m[0] * scale,
            m[1] * scale * (1.0 + 0.01 * k as f64),
            m[2] * scale,
        ];
        let mut tracked = fresh;
        Mv::new(body, 0.1).step(&mut fresh).unwrap();
        mv.step(&mut tracked).unwrap();
        assert!(dist(fresh, tracked) <= 1e-14 * norm(fresh), "scale {scale}");
        m = tracked;
    }
}

#[test]
fn bad_input_is_refused_and_the_state_kept() {
    let body = talk_body();
    for bad in [[f64::NAN, 0.0, 1.0], [f64::INFINITY, 0.0, 0.0]] {
        let mut m = bad;
        assert_eq!(Mv::new(body, 0.1).step(&mut m), Err(StepError::NonFinite));
    }
    let mut m = TALK_M0;
    for h in [f64::NAN, f64::INFINITY] {
        assert_eq!(Mv::new(body, h).step(&mut m), Err(StepError::NonFinite));
        assert_eq!(m, TALK_M0);
    }
    let mut s = State::new(TALK_M0, [0.0; 4]);
    assert_eq!(
        Mv::new(body, 0.1).step_state(&mut s),
        Err(StepError::NonFinite)
    );
    // m large enough that h m overflows
    let mut m = [1e308, 1e308, 0.0];
    assert!(Mv::new(body, 1e10).step(&mut m).is_err());
    assert_eq!(Mv::max_step(&body, &[f64::NAN, 0.0, 0.0]), 0.0);
    assert_eq!(Mv::max_step(&body, &[0.0; 3]), f64::MAX);
}

#[test]
fn f32_order_and_limits() {
    let body = Body::<f32>::from_mass_matrix(to_f32(TALK_J)).unwrap();
    let hs = [0.2f64, 0.1, 0.05];
    let errs: Vec<f64> = hs
        .iter()
        .map(|&h| talk_error_at_10(&mut Mv::new(body, h as f32), h))
        .collect();
    let p = observed_order(&hs, &errs);
    assert!((p - 2.0).abs() <= 0.05, "f32 order {p}");
    let hmax = Mv::max_step(&body, &to_f32(TALK_M0));
    assert!((hmax as f64 - TALK_MAX_STEP).abs() < 1e-5, "{hmax}");
    let mut m = to_f32(TALK_M0);
    assert_eq!(
        Mv::new(body, hmax * 1.001).step(&mut m),
        Err(StepError::StepTooLarge)
    );
    Mv::new(body, hmax * 0.999).step(&mut m).unwrap();
}

/// Regression: a one-step lag in the tracked `s1` made invariant errors grow exponentially
/// at large steps (1e-15 to 3e-8 in 60 steps at h = 0.93 on the talk's case) while every
/// single-step check passed. Long runs near the existence limit must stay at round-off.
#[test]
fn long_runs_near_the_existence_limit_stay_at_round_off() {
    let mut cases = vec![(TALK_J, TALK_M0)];
    let mut rng = Rng::new(53);
    for _ in 0..20 {
        let d = rng.direction();
        cases.push((
            [
                rng.range(0.05, 1.0),
                rng.range(0.05, 1.0),
                rng.range(0.0, 1.0),
            ],
            d,
        ));
    }
    for (j, m0) in cases {
        let body = Body::<f64>::from_mass_matrix(j).unwrap();
        let hmax = Mv::max_step(&body, &m0);
        for frac in [0.5, 0.8, 0.95] {
            let h = frac * hmax.min(50.0);
            let mut mv = Mv::new(body, h);
            let mut s = State::new(m0, [1.0, 0.0, 0.0, 0.0]);
            let (c0, e0, p0) = (body.casimir(&m0), body.energy(&m0), s.spatial_momentum());
            for _ in 0..5000 {
                mv.step_state(&mut s).unwrap();
            }
            let dc = (body.casimir(&s.m) - c0).abs() / c0;
            let de = (body.energy(&s.m) - e0).abs() / e0;
            let dp = dist(s.spatial_momentum(), p0) / norm(p0);
            assert!(
                dc < 1e-13 && de < 1e-12 && dp < 1e-12,
                "J {j:?} h {h} ({frac} of max): {dc:e} {de:e} {dp:e}"
            );
        }
    }
}

#[test]
fn regression_subnormal_momentum_on_a_planar_body() {
    // found by the fuzz smoke test: 1 / 5e-324 overflowed and max_step returned NaN
    let body = Body::<f64>::from_mass_matrix([0.0, 0.000256, 0.000256]).unwrap();
    let m = [5e-324, 0.0, 0.0];
    let hmax = Mv::max_step(&body, &m);
    assert!(hmax > 0.0 && !hmax.is_nan(), "{hmax}");
    let mut mm = m;
    Mv::new(body, 0.1).step(&mut mm).unwrap();
    assert!(mm.iter().all(|x| x.is_finite()));
    // subnormal moments of inertia are refused at construction (their mass matrix underflows);
    // the smallest normal ones step: the scale is divided out, never inverted
    assert_eq!(
        Body::<f64>::from_inertia([3e-310, 4e-310, 5e-310]),
        Err(rigid3::BodyError::SubnormalMoment)
    );
    let t = f64::MIN_POSITIVE;
    let tiny = Body::<f64>::from_inertia([3.0 * t, 4.0 * t, 5.0 * t]).unwrap();
    let mut m = [1e-300, 2e-300, 0.5e-300];
    let r = Mv::new(tiny, 1e-10).step(&mut m);
    assert!(r.is_err() || m.iter().all(|x| x.is_finite()));
}

/// The free-running step (a rational map with the trajectory's constants, src/mv_frozen.rs)
/// against the 3x3 solve from scratch: from every state of a long run, one step of the running
/// integrator and one of a fresh integrator (which solves for `s1` anew and runs the solve)
/// agree to round-off, on random bodies (planar ones too), momenta and small steps, fixed or
/// changed every step (then each step re-solves for `s1` from the tracked value and runs the solve).
#[test]
fn free_running_steps_equal_fresh_solves() {
    let worst = worst_free_running_vs_fresh::<f64>(71, true);
    eprintln!("worst one-step difference {worst:e}");
    assert!(worst < 2e-15, "worst one-step difference {worst:e}");
}

/// The same in f32 (the firmware's precision), at a fixed step: the free-running map and a
/// fresh solve agree to a few ulps of `|m|`.
#[test]
fn free_running_steps_equal_fresh_solves_f32() {
    let worst = worst_free_running_vs_fresh::<f32>(72, false);
    eprintln!("worst one-step difference (f32) {worst:e}");
    assert!(
        worst < 8.0 * f32::EPSILON as f64,
        "worst one-step difference {worst:e}"
    );
}

/// The largest one-step relative difference between a running `Mv<T>` and a fresh one over
/// 40 random cases of 300 steps (every fourth body planar; with `jitter`, every other case
/// changes `h` by up to +-5% every step).
fn worst_free_running_vs_fresh<T: rigid3::Real>(seed: u64, jitter: bool) -> f64 {
    let mut rng = Rng::new(seed);
    let mut worst = 0.0f64;
    for case in 0..40 {
        let j = [
            rng.range(0.05, 1.0),
            rng.range(0.05, 1.0),
            if case % 4 == 0 {
                0.0
            } else {
                rng.range(0.0, 1.0)
            },
        ];
        let body = Body::<T>::from_mass_matrix(j.map(T::from_f64)).unwrap();
        let m0 = rng.direction().map(|x| x * rng.range(0.1, 10.0));
        // h |Omega| from 1e-4 to 3e-2
        let w = norm(
            Body::<f64>::from_mass_matrix(j)
                .unwrap()
                .angular_velocity(&m0),
        );
        let h = rng.range(1e-4, 3e-2) / w;
        let mut mv = Mv::new(body, T::from_f64(h));
        let mut s = State::new(m0.map(T::from_f64), [T::ONE, T::ZERO, T::ZERO, T::ZERO]);
        let jittered = jitter && case % 2 == 1;
        for _ in 0..300 {
            let hk = T::from_f64(if jittered {
                h * rng.range(0.95, 1.05)
            } else {
                h
            });
            if jittered {
                mv.set_step_size(hk);
            }
            let mut fresh = s;
            Mv::new(body, hk).step_state(&mut fresh).unwrap();
            mv.step_state(&mut s).unwrap();
            let (a, b) = (s.m.map(|x| x.to_f64()), fresh.m.map(|x| x.to_f64()));
            worst = worst.max(dist(a, b) / norm(a));
        }
    }
    worst
}

/// Regression from the loop fuzz: mass-matrix diagonal spread over 210 decades and
/// |m| = 7.5e76. The scaled solve kept no correct digit and returned Ok with |m| shrunk
/// to 4.8e63 and a quaternion of norm 7e106; the step now sees that the result left the
/// momentum sphere and refuses it, both with and without attitude, touching nothing.
#[test]
fn a_body_beyond_the_arithmetic_is_refused_not_stepped() {
    let body =
        Body::<f64>::from_mass_matrix([1.5086552185172663e74, 2194.1, 1.2927722311278584e-136])
            .unwrap();
    let m0 = [
        -0.03729744640082714,
        7.473494788292525e76,
        2.6177591158186443e72,
    ];
    let h = 6.550460000000002e-6;
    let mut m = m0;
    assert_eq!(Mv::new(body, h).step(&mut m), Err(StepError::Degenerate));
    assert_eq!(m, m0);
    let mut s = State::new(m0, [1.0, 0.0, 0.0, 0.0]);
    assert_eq!(
        Mv::new(body, h).step_state(&mut s),
        Err(StepError::Degenerate)
    );
    assert_eq!(s, State::new(m0, [1.0, 0.0, 0.0, 0.0]));
}

/// Regression from the loop fuzz: momentum on the axis of a moment 1e146 times the others,
/// `h |Omega| ~ 1e59`: no rotation solves the step, but the existence test (its discriminant
/// underflows at this spread) passed it and the attitude came out with norm 1e118. The turn
/// now sees `4 |b|^2 > 1` and refuses the step with attitude; nothing is changed.
#[test]
fn a_turn_past_the_existence_limit_is_refused() {
    let body = Body::<f64>::from_mass_matrix([143760.0, 7.678952673591547e150, 2695.3]).unwrap();
    let m0 = [-0.26923, -9.054274932288461e260, -99.54];
    let q0 = [1.2708, 21.901, -0.004954, 16947.0];
    let mut s = State::new(m0, q0);
    assert_eq!(
        Mv::new(body, -3.930367410510085e-197).step_state(&mut s),
        Err(StepError::StepTooLarge)
    );
    assert_eq!(s, State::new(m0, q0));
}

/// A method in f32 and in f64.
type Pair = (
    &'static str,
    Box<dyn Integrator<f32>>,
    Box<dyn Integrator<f64>>,
);

/// The attitude angle between two unit quaternions (`2 min(|a - b|, |a + b|)`, to first
/// order).
fn attitude_angle(a: [f64; 4], b: [f64; 4]) -> f64 {
    let minus = (0..4).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
    let plus = (0..4).map(|k| (a[k] + b[k]).powi(2)).sum::<f64>().sqrt();
    2.0 * minus.min(plus)
}

/// f32 steps of a slowly turning body move `m` and `q` by a few ulps each: each step's
/// rounding is carried to the next (`Mv`'s docs), so the motion is not lost. Oracle: the same
/// integrator in f64 from the same (f32) state, whose own rounding is 1e9 times smaller.
/// Before the carry, at 1.3e-3 rad/s and 1 kHz the attitude was 8.3e-3 rad and `m` 7.4e-3
/// off after `10^6` steps (`1000 s`), with the invariants held all along (found by a
/// firmware engineer's trial); at `2 x 10^5` steps 1.7e-3 rad.
#[test]
fn f32_slow_turns_keep_their_phase() {
    let inertia = [60.0, 95.0, 120.0];
    let b32 = Body::<f32>::from_inertia(inertia.map(|x| x as f32)).unwrap();
    let b64 = Body::<f64>::from_inertia(inertia).unwrap();
    let q0 = [0.9f32, 0.1, -0.3, 0.2];
    let n = q0.iter().map(|x| x * x).sum::<f32>().sqrt();
    let q0 = q0.map(|x| x / n);
    let dir = [0.3f64, -0.5, 0.8];
    let dn = common::norm(dir);
    let mut report = Vec::new();
    for (rate, h) in [
        (1.3e-3, 1e-3),
        (1.3e-2, 1e-3),
        (1.3e-1, 1e-3),
        (1.3e-3, 5e-3),
        (0.3, 5e-3),
        (1.0, 5e-3),
    ] {
        let m0: [f32; 3] = std::array::from_fn(|k| (dir[k] / dn * rate * inertia[k]) as f32);
        let start = State::new(m0.map(|x| x as f64), q0.map(|x| x as f64));
        let methods: [Pair; 2] = [
            (
                "mv",
                Box::new(Mv::new(b32, h as f32)),
                Box::new(Mv::new(b64, h)),
            ),
            (
                "pre-mv4",
                Box::new(PreMv::new(b32, h as f32, 4).unwrap()),
                Box::new(PreMv::new(b64, h, 4).unwrap()),
            ),
        ];
        for (name, mut a32, mut a64) in methods {
            let (mut s32, mut s64) = (State::new(m0, q0), start);
            let mut m_only = m0;
            let mut m_ref = start.m;
            let mut mv32 = Mv::new(b32, h as f32);
            let mut mv64 = Mv::new(b64, h);
            for _ in 0..200_000 {
                a32.step_state(&mut s32).unwrap();
                a64.step_state(&mut s64).unwrap();
                mv32.step(&mut m_only).unwrap();
                mv64.step(&mut m_ref).unwrap();
            }
            let q_off = attitude_angle(s32.q.map(|x| x as f64), s64.q);
            let m_off = dist(s32.m.map(|x| x as f64), s64.m) / common::norm(s64.m);
            let m_only_off = dist(m_only.map(|x| x as f64), m_ref) / common::norm(m_ref);
            report.push(format!(
                "{name} {rate:e} rad/s h {h:e}: q {q_off:.2e} rad, m {m_off:.2e}, momentum-only m {m_only_off:.2e}"
            ));
            // fast turns (where nothing is carried, `Mv`'s docs) are limited by the step's
            // own relative rounding, eps of the angle turned
            let bound = (4.0 * f32::EPSILON as f64 * rate * h * 200_000.0).max(1e-5);
            assert!(
                q_off <= bound && m_off <= bound && m_only_off <= bound,
                "{}",
                report.last().unwrap()
            );
        }
    }
    println!("{}", report.join("\n"));
}

/// A carried f32 step (a forced integrator's drift) at a large turn moves its result back
/// onto its input's invariants; a result off the momentum sphere by more than round-off has
/// no correct digits and must still be refused as the plain step refuses it, not moved back
/// onto the sphere and passed (found by the loop fuzz when the fix came in: its `Degenerate`
/// counts fell by 5-21 %, and these bodies spanning 29-41 decades in f32 came out `Ok`, up
/// to 2e-4 from f64). Named cases, and 20000 random wide bodies: the carried step refuses
/// wherever the plain step does.
#[test]
fn a_carried_f32_step_off_the_sphere_is_refused_like_a_plain_one() {
    let cases: [([f32; 3], [f32; 3], f32); 3] = [
        (
            [12018882.0, 275.24164, 3.0915138e-22],
            [-0.00022021927, -10573958000.0, -4.688154e-13],
            1.4955716e-5,
        ),
        (
            [1.701699e17, 745069300000.0, 4.8895116e-13],
            [9.103564e-17, 1.3050217e-7, 589798600000000.0],
            1.813725,
        ),
        (
            [2276241.5, 3664665400000.0, 4.158989e-30],
            [-3.6399413e-13, -4.18189e-20, 59214020000000.0],
            9.810324e-5,
        ),
    ];
    let outcomes = |j: [f32; 3], m: [f32; 3], h: f32| {
        let body = Body::<f32>::from_mass_matrix(j).ok()?;
        let start = State::new(m, [1.0f32, 0.0, 0.0, 0.0]);
        let mut s = start;
        let plain = Mv::new(body, h).step_state(&mut s);
        let mut t = start;
        let mut lost = State::new([0.0f32; 3], [0.0; 4]);
        let carried = Mv::new(body, h).step_state_carrying(&mut t, &mut lost, true);
        if carried.is_err() {
            assert_eq!(t, start, "{j:?} {m:?} {h:e}: the state was changed");
        }
        Some((plain, carried))
    };
    for (j, m, h) in cases {
        // refused, or taken by both and within f32's round-off of the f64 step, normwise
        let (plain, carried) = outcomes(j, m, h).unwrap();
        assert_eq!(plain, carried, "{j:?} {m:?} {h:e}");
        if plain.is_ok() {
            let body = Body::<f32>::from_mass_matrix(j).unwrap();
            let mut s = State::new(m, [1.0f32, 0.0, 0.0, 0.0]);
            Mv::new(body, h).step_state(&mut s).unwrap();
            let b64 = Body::<f64>::from_mass_matrix(j.map(f64::from)).unwrap();
            let mut s64 = State::new(m.map(f64::from), [1.0, 0.0, 0.0, 0.0]);
            Mv::new(b64, f64::from(h)).step_state(&mut s64).unwrap();
            let off = dist(s.m.map(f64::from), s64.m) / norm(s64.m);
            assert!(
                off < 4.0 * f64::from(f32::EPSILON),
                "{j:?} {m:?} {h:e}: {off:e}"
            );
        }
    }
    let mut rng = Rng::new(0x5eed_0ff5);
    let mut refused = 0;
    for _ in 0..20_000 {
        let wide = |rng: &mut Rng, decades: f64| 10f64.powf(rng.range(-0.5, 0.5) * decades);
        let j = [(); 3].map(|_| wide(&mut rng, 60.0) as f32);
        let m = [(); 3].map(|_| (rng.range(-1.0, 1.0) * wide(&mut rng, 40.0)) as f32);
        let h = wide(&mut rng, 20.0) as f32;
        if let Some((plain, carried)) = outcomes(j, m, h) {
            if plain == Err(StepError::Degenerate) {
                refused += 1;
                assert_eq!(carried, plain, "{j:?} {m:?} {h:e}");
            }
        }
    }
    println!("{refused} of 20000 random wide bodies refused by the plain step");
    assert!(
        refused > 100,
        "the sample should reach the refusals: {refused}"
    );
}
