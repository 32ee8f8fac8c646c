//! `Mv` in the loop it is built for: a step size that changes every tick and a momentum the
//! caller changes between steps. Oracle: a freshly built `Mv` (which solves the quartic from
//! scratch) taking the same step from the same state, and the conservation laws.

mod common;

use common::{dist, Rng, TALK_J, TALK_M0, TALK_MAX_STEP};
use rigid3::{Body, Integrator, Mv, State, StepError};

fn talk() -> Body<f64> {
    Body::from_mass_matrix(TALK_J).unwrap()
}

fn qdist(a: [f64; 4], b: [f64; 4]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// One step by a tracked integrator equals one step by a new integrator, to round-off.
fn assert_same_step(tracked: &mut Mv<f64>, s: &mut State<f64>, body: Body<f64>, h: f64) {
    let mut fresh = Mv::new(body, h);
    let mut f = *s;
    fresh.step_state(&mut f).unwrap();
    tracked.step_state(s).unwrap();
    let scale = common::norm(f.m).max(1e-300);
    assert!(
        dist(s.m, f.m) <= 4e-15 * scale,
        "h {h} m {:?} vs {:?}: {:e}",
        s.m,
        f.m,
        dist(s.m, f.m) / scale
    );
    assert!(qdist(s.q, f.q) <= 4e-15, "q {:?} vs {:?}", s.q, f.q);
}

#[test]
fn jittered_step_equals_a_fresh_solve() {
    let body = talk();
    let mut rng = Rng::new(11);
    for &h0 in &[0.001, 0.01, 0.1, 0.5, 0.9] {
        let mut mv = Mv::new(body, h0);
        let mut s = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
        for _ in 0..200 {
            let h = h0 * (1.0 + rng.range(-0.05, 0.05));
            mv.set_step_size(h);
            assert_same_step(&mut mv, &mut s, body, h);
        }
    }
}

#[test]
fn kicked_momentum_equals_a_fresh_solve() {
    let body = talk();
    let mut rng = Rng::new(12);
    for &(h, kick) in &[(0.005, 1e-4), (0.05, 1e-3), (0.3, 1e-2), (0.8, 0.05)] {
        let mut mv = Mv::new(body, h);
        let mut s = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
        for _ in 0..200 {
            let d = rng.direction();
            for (mi, di) in s.m.iter_mut().zip(d) {
                *mi += kick * di;
            }
            assert_same_step(&mut mv, &mut s, body, h);
        }
    }
}

#[test]
fn large_changes_of_h_still_agree() {
    // factors past two drop the tracking; the series + Newton start or the exact solve takes
    // over, and the answer is the same
    let body = talk();
    let mut mv = Mv::new(body, 0.01);
    let mut s = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    for &h in &[0.01, 0.5, 0.002, 1.0, -0.3, 1e-7, 0.7] {
        mv.set_step_size(h);
        assert_same_step(&mut mv, &mut s, body, h);
    }
}

#[test]
fn invariants_hold_under_jitter_without_a_random_walk() {
    // the Casimir anchor is rescaled from one value, not re-taken at every change of h
    let body = talk();
    let mut rng = Rng::new(13);
    let s0 = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    let (c0, e0, p0) = (
        body.casimir(&s0.m),
        body.energy(&s0.m),
        s0.spatial_momentum(),
    );
    let mut mv = Mv::new(body, 0.01);
    let mut s = s0;
    let (mut dc, mut de, mut dp) = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..100_000 {
        mv.set_step_size(0.01 * (1.0 + rng.range(-0.05, 0.05)));
        mv.step_state(&mut s).unwrap();
        dc = dc.max((body.casimir(&s.m) - c0).abs() / c0);
        de = de.max((body.energy(&s.m) - e0).abs() / e0);
        dp = dp.max(dist(s.spatial_momentum(), p0) / common::norm(p0));
    }
    assert!(dc <= 1e-15, "|m|^2 drift {dc:e}");
    assert!(de <= 1e-13, "energy drift {de:e}");
    assert!(dp <= 1e-13, "R(q) m drift {dp:e}");

    // f32: the same loop stays at a few ulps of |m|^2
    let body32 = Body::<f32>::from_mass_matrix(TALK_J.map(|x| x as f32)).unwrap();
    let m32 = TALK_M0.map(|x| x as f32);
    let c32 = body32.casimir(&m32) as f64;
    let mut mv = Mv::new(body32, 0.01f32);
    let mut s = State::new(m32, [1.0f32, 0.0, 0.0, 0.0]);
    let mut dc = 0.0f64;
    for _ in 0..100_000 {
        mv.set_step_size(0.01 * (1.0 + rng.range(-0.05, 0.05)) as f32);
        mv.step_state(&mut s).unwrap();
        let m = s.m.map(|x| x as f64);
        dc = dc.max(((m[0] * m[0] + m[1] * m[1] + m[2] * m[2]) - c32).abs() / c32);
    }
    assert!(dc <= 1e-6, "f32 |m|^2 drift {dc:e}");
}

#[test]
fn existence_is_checked_again_after_a_change_of_h() {
    let body = talk();
    let mut mv = Mv::new(body, 0.99 * TALK_MAX_STEP);
    let mut s = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    // stay on the orbit, where the limit is that of the initial state, then step past it
    mv.step_state(&mut s).unwrap();
    let limit = Mv::max_step(&body, &s.m);
    mv.set_step_size(1.01 * limit);
    let before = s;
    assert_eq!(mv.step_state(&mut s), Err(StepError::StepTooLarge));
    assert_eq!(s, before);
    // and back inside it works again
    mv.set_step_size(0.98 * limit);
    mv.step_state(&mut s).unwrap();
}
