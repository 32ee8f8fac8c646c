//! The analyst's API of issue 13: the public exact trajectory `Orbit` and `step_partial`.

mod common;

use common::*;
use rigid3::{Body, Exact, Integrator, Mv, Orbit, PreMv, Rk4, State, StepError};

fn qdist(a: [f64; 4], b: [f64; 4]) -> f64 {
    let d: f64 = (0..4).map(|i| (a[i] - b[i]).powi(2)).sum();
    let s: f64 = (0..4).map(|i| (a[i] + b[i]).powi(2)).sum();
    d.min(s).sqrt()
}

#[test]
fn orbit_at_is_exact_at_for_many_times_after_one_set_up() {
    let mut rng = Rng::new(13);
    for _ in 0..50 {
        let j = [
            rng.range(0.05, 1.0),
            rng.range(0.05, 1.0),
            rng.range(0.05, 1.0),
        ];
        let body = Body::<f64>::from_mass_matrix(j).unwrap();
        let m = rng.direction().map(|x| x * rng.range(0.1, 3.0));
        let q = [0.3, -0.5, 0.7, 0.2];
        let s0 = State::new(m, q);
        let orbit = Orbit::new(&body, &s0).unwrap();
        assert_eq!(orbit.initial(), s0);
        assert_eq!(orbit.body(), &body);
        for k in 0..40 {
            let t = rng.range(-200.0, 200.0) * if k == 0 { 0.0 } else { 1.0 };
            let a = orbit.at(t).unwrap();
            assert_eq!(a, Exact::at(&body, &s0, t).unwrap(), "t = {t}");
            assert_eq!(
                orbit.momentum_at(t).unwrap(),
                Exact::momentum_at(&body, &m, t).unwrap()
            );
            assert!(dist(a.m, orbit.momentum_at(t).unwrap()) <= 1e-14 * norm(m).max(1.0));
        }
    }
}

#[test]
fn orbit_agrees_with_references_and_a_fine_rk4_run() {
    let body = Body::<f64>::from_mass_matrix(TALK_J).unwrap();
    let orbit = Orbit::new(&body, &State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0])).unwrap();
    assert!(dist(orbit.momentum_at(1.0).unwrap(), TALK_M1) < 1e-13);
    assert!(dist(orbit.momentum_at(10.0).unwrap(), TALK_M10) < 1e-13);
    assert!(dist(orbit.momentum_at(100.0).unwrap(), TALK_M100) < 1e-12);
    assert!(qdist(orbit.at(10.0).unwrap().q, TALK_Q10) < 1e-13);
    // Hairer–Vilmart's case against a fine RK4 run, at every step's time
    let body = Body::<f64>::from_inertia(HV_I).unwrap();
    let s0 = State::new(HV_M0, [1.0, 0.0, 0.0, 0.0]);
    let orbit = Orbit::new(&body, &s0).unwrap();
    let h = 1e-3;
    let mut rk = Rk4::new(body, h);
    let mut s = s0;
    let mut worst = 0.0f64;
    for n in 1..=10_000 {
        rk.step_state(&mut s).unwrap();
        if n % 500 == 0 {
            let e = orbit.at(n as f64 * h).unwrap();
            worst = worst.max(dist(e.m, s.m)).max(qdist(e.q, s.q));
        }
    }
    assert!(
        worst < 1e-10,
        "Orbit vs RK4 (h = 1e-3) to t = 10: {worst:e}"
    );
    let end = orbit.at(10.0).unwrap();
    assert!(dist(end.m, HV_M10) < 1e-13 && qdist(end.q, HV_Q10) < 1e-13);
}

#[test]
fn orbit_refuses_bad_input() {
    let body = Body::<f64>::from_inertia(HV_I).unwrap();
    let good = State::new(HV_M0, [1.0, 0.0, 0.0, 0.0]);
    for bad in [
        State::new([f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]),
        State::new([0.0, f64::INFINITY, 0.0], [1.0, 0.0, 0.0, 0.0]),
        State::new(HV_M0, [0.0; 4]),
        State::new(HV_M0, [f64::NAN, 0.0, 0.0, 0.0]),
    ] {
        assert_eq!(Orbit::new(&body, &bad).err(), Some(StepError::NonFinite));
    }
    assert!(Orbit::new(
        &body,
        &State::new([1.5e308, 1.5e308, 0.0], [1.0, 0.0, 0.0, 0.0])
    )
    .is_err());
    let orbit = Orbit::new(&body, &good).unwrap();
    for t in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(orbit.at(t).err(), Some(StepError::NonFinite));
        assert_eq!(orbit.momentum_at(t).err(), Some(StepError::NonFinite));
    }
    assert_eq!(orbit.at(1e300).err(), Some(StepError::StepTooLarge));
    // m = 0 and steady rotations
    let still = Orbit::new(&body, &State::new([0.0; 3], [0.0, 0.0, 0.0, 2.0])).unwrap();
    assert_eq!(
        still.at(5.0).unwrap(),
        State::new([0.0; 3], [0.0, 0.0, 0.0, 1.0])
    );
    let axis = Orbit::new(&body, &State::new([0.0, 0.0, 2.0], [1.0, 0.0, 0.0, 0.0])).unwrap();
    let s = axis.at(core::f64::consts::PI).unwrap(); // Omega = 2 about z: one turn
    assert_eq!(s.m, [0.0, 0.0, 2.0]);
    assert!(qdist(s.q, [-1.0, 0.0, 0.0, 0.0]) < 1e-15);
    // f32
    let b32 = Body::<f32>::from_inertia([0.6, 0.8, 1.0]).unwrap();
    let o32 = Orbit::new(&b32, &State::new([1.8f32, 0.4, -0.9], [1.0, 0.0, 0.0, 0.0])).unwrap();
    let m = o32.momentum_at(10.0).unwrap();
    assert!(dist(to_f64(m), HV_M10) < 1e-5);
}

/// Steps `a` 60 times from `s0`, taking partial steps of every size in `fracs` before each
/// step when `partial`; returns the states after each full step.
fn run<I: Integrator<f64> + Clone>(
    mut a: I,
    s0: State<f64>,
    partial: bool,
    fresh: impl Fn(f64) -> I,
) -> Vec<State<f64>> {
    let h = a.step_size();
    let mut s = s0;
    let mut out = Vec::new();
    for _ in 0..60 {
        if partial {
            for frac in [0.25, 0.5, 0.9, -0.3] {
                let p = a.step_partial(&s, frac * h).unwrap();
                let mut f = s;
                fresh(frac * h).step_state(&mut f).unwrap();
                assert_eq!(
                    p,
                    f,
                    "partial step differs from a fresh step of {}",
                    frac * h
                );
            }
        }
        a.step_state(&mut s).unwrap();
        out.push(s);
    }
    out
}

#[test]
fn partial_steps_leave_the_tracked_trajectory_bit_identical() {
    let body = Body::<f64>::from_mass_matrix(TALK_J).unwrap();
    let s0 = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    let h = 0.1;
    let mv = |h| Mv::new(body, h);
    assert_eq!(run(mv(h), s0, false, mv), run(mv(h), s0, true, mv));
    for order in [4u8, 10] {
        let pre = |h| PreMv::new(body, h, order).unwrap();
        assert_eq!(run(pre(h), s0, false, pre), run(pre(h), s0, true, pre));
    }
    // (RetimedMv's reset kept the last retiming's ratio as the next one's warm start, and its
    // partial steps differed from a fresh integrator's by 4e-16: found in a first-use trial)
    for order in [2u8, 4, 10] {
        let ret = |h| rigid3::RetimedMv::new(body, h, order).unwrap();
        assert_eq!(run(ret(h), s0, false, ret), run(ret(h), s0, true, ret));
    }
    let ex = |h| Exact::new(body, h);
    assert_eq!(run(ex(h), s0, false, ex), run(ex(h), s0, true, ex));
    // the exact flow's partial step is Orbit::at
    let e = Exact::new(body, h).step_partial(&s0, 0.037).unwrap();
    let o = Orbit::new(&body, &s0).unwrap().at(0.037).unwrap();
    assert!(dist(e.m, o.m) < 1e-15 && qdist(e.q, o.q) < 1e-15);
    // errors: the state is only read
    let mv = Mv::new(body, h);
    let big = 1.01 * Mv::max_step(&body, &s0.m);
    assert_eq!(
        mv.step_partial(&s0, big).err(),
        Some(StepError::StepTooLarge)
    );
    assert_eq!(
        mv.step_partial(&s0, f64::NAN).err(),
        Some(StepError::NonFinite)
    );
    assert_eq!(mv.step_size(), h);
}

/// A zero-length partial step, and a reset during a pause, leave the state as it is for every
/// integrator [the state itself]: `RetimedMv::reset` once recomputed its pause flag from the
/// last non-zero `h` it keeps, so after `set_step_size(0)` a reset stepped again with the old
/// step and `step_partial(s, 0)` took a whole step (found in review).
#[test]
fn a_zero_partial_step_and_a_reset_pause_move_nothing() {
    let body = Body::<f64>::from_inertia([1.0, 1.5, 2.0]).unwrap();
    let s0 = State::new([0.3, -0.6, 1.1], [1.0, 0.0, 0.0, 0.0]);
    fn check<I: Integrator<f64> + Clone>(name: &str, mut a: I, s0: State<f64>) {
        let mut s = s0;
        a.step_state(&mut s).unwrap();
        assert_eq!(
            a.step_partial(&s, 0.0).unwrap(),
            s,
            "{name}: step_partial(s, 0)"
        );
        a.set_step_size(0.0);
        a.reset();
        let before = s;
        a.step_state(&mut s).unwrap();
        assert_eq!(s, before, "{name}: a step after set_step_size(0) and reset");
    }
    check("mv", Mv::new(body, 0.05), s0);
    for order in [2u8, 4] {
        check("pre-mv", PreMv::new(body, 0.05, order).unwrap(), s0);
        check(
            "retimed-mv",
            rigid3::RetimedMv::new(body, 0.05, order).unwrap(),
            s0,
        );
    }
    check("exact", Exact::new(body, 0.05), s0);
}

/// A slightly non-unit `q0` is the attitude it points to (regression, first-use trial: the
/// evaluation pulled `|q|` back to one to first order about `q0`, which turned `|q0| = 1.0004`
/// into an attitude 8e-4 rad off and an f32-normalised `q0` widened to f64 into 6.6e-8 rad;
/// `Exact`'s steps, which normalised, and `Exact::at` differed by as much). Oracle: the same
/// orbit from the normalised `q0`, and `Exact`'s steps. A tiny or huge `q0` is a direction too.
#[test]
fn a_non_unit_initial_attitude_is_its_direction() {
    let body = Body::<f64>::from_inertia([0.6, 0.8, 1.0]).unwrap();
    let m = [1.8, 0.4, -0.9];
    let unit = [0.5, 0.5, -0.5, 0.5];
    let reference = Orbit::new(&body, &State::new(m, unit)).unwrap();
    let widened = [0.5f32, 0.5, -0.5, 0.5].map(|x| f64::from(x * (1.0 - 3.0 * f32::EPSILON)));
    for q0 in [
        unit.map(|x| x * 1.0004),
        unit.map(|x| x * 0.9996),
        unit.map(|x| x * (1.0 + 1e-10)),
        widened,
        unit.map(|x| x * 1e-200),
        unit.map(|x| x * 1e200),
    ] {
        let orbit = Orbit::new(&body, &State::new(m, q0)).unwrap();
        for t in [0.0, 0.7, 3.0, 10.0, -10.0] {
            let (a, r) = (orbit.at(t).unwrap(), reference.at(t).unwrap());
            assert!(
                qdist(a.q, r.q) <= 4e-16,
                "{q0:?} t {t}: {:e}",
                qdist(a.q, r.q)
            );
            let n2: f64 = a.q.iter().map(|x| x * x).sum();
            assert!((n2 - 1.0).abs() <= 4.0 * f64::EPSILON, "{q0:?} t {t}");
        }
        let mut ex = Exact::new(body, 10.0);
        let mut s = State::new(m, q0);
        ex.step_state(&mut s).unwrap();
        assert!(qdist(s.q, orbit.at(10.0).unwrap().q) <= 4e-16, "{q0:?}");
    }
}

/// A subnormal momentum is a (very slow) motion like any other: `Orbit` and `Exact` follow it
/// as `Mv` steps it (regression, first-use trial: refused as `Overflow`, nothing overflowing).
/// Oracle: the same orbit scaled up by `2^600` (Euler's equations are homogeneous: `m -> k m`,
/// `t -> t / k`), and `Mv`.
#[test]
fn a_subnormal_momentum_is_followed() {
    let body = Body::<f64>::from_inertia([0.6, 0.8, 1.0]).unwrap();
    let m = [1.8e-310, 0.4e-310, -0.9e-310];
    let k = 2f64.powi(600);
    let tiny = Orbit::new(&body, &State::new(m, [1.0, 0.0, 0.0, 0.0])).unwrap();
    let scaled = Orbit::new(&body, &State::new(m.map(|x| x * k), [1.0, 0.0, 0.0, 0.0])).unwrap();
    // the largest phase f64 time allows: |m| t / I about 0.04 rad
    let t = 1e308;
    let (a, b) = (tiny.at(t).unwrap(), scaled.at(t / k).unwrap());
    assert!(qdist(b.q, [1.0, 0.0, 0.0, 0.0]) > 1e-2, "the body turned");
    for i in 0..3 {
        // the subnormal components carry about 40 bits
        assert!(
            (a.m[i] * k - b.m[i]).abs() <= 1e-11 * norm(b.m),
            "{a:?} {b:?}"
        );
    }
    assert!(qdist(a.q, b.q) <= 1e-11);
    let mut mv = Mv::new(body, 1.0);
    let mut stepped = m;
    mv.step(&mut stepped).unwrap();
    assert_eq!(
        Exact::momentum_at(&body, &m, 1.0).unwrap(),
        tiny.momentum_at(1.0).unwrap()
    );
    assert!(dist(stepped, tiny.momentum_at(1.0).unwrap()) <= 1e-320);
}
