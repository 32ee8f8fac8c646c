//! `PreMv` in the loop: corrected momenta and a jittering step size update the modified
//! moments incrementally. Oracles: a freshly built `PreMv` taking the same step, and the exact
//! solution for the order under a random step sequence.

mod common;

use common::{dist, observed_order, Rng, TALK_J, TALK_M0};
use rigid3::{Body, Exact, Integrator, PreMv, State};

fn talk() -> Body<f64> {
    Body::from_mass_matrix(TALK_J).unwrap()
}

fn qdist(a: [f64; 4], b: [f64; 4]) -> f64 {
    let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let s: f64 = a.iter().zip(b).map(|(x, y)| (x + y).powi(2)).sum();
    d.min(s).sqrt()
}

#[test]
fn corrected_and_jittered_steps_equal_a_fresh_build() {
    let body = talk();
    let mut rng = Rng::new(21);
    for order in [4u8, 6, 8, 10] {
        for &h0 in &[0.005, 0.05, 0.2] {
            let mut pre = PreMv::new(body, h0, order).unwrap();
            let mut s = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
            for k in 0..100 {
                let h = if k % 2 == 0 {
                    h0 * (1.0 + rng.range(-0.05, 0.05))
                } else {
                    h0
                };
                pre.set_step_size(h);
                for mi in s.m.iter_mut() {
                    *mi *= 1.0 + 1e-4 * rng.range(-1.0, 1.0);
                }
                let mut fresh = PreMv::new(body, h, order).unwrap();
                let mut f = s;
                fresh.step_state(&mut f).unwrap();
                pre.step_state(&mut s).unwrap();
                assert!(
                    dist(s.m, f.m) <= 4e-15 * common::norm(f.m),
                    "order {order}, h {h}: {:e}",
                    dist(s.m, f.m)
                );
                assert!(qdist(s.q, f.q) <= 4e-15);
            }
        }
    }
}

/// The same in f32 on the firmware's spacecraft at 200 Hz, where a 5 % change of `h` or a
/// 1e-4 correction of `m` usually leaves `1 / I~` the same to the last bit and `PreMv` keeps
/// its modified body and tracking instead of rebuilding: each step must still be a fresh
/// build's step to a few ulps (both sides in f32; the distance is measured in f64).
#[test]
fn f32_steps_that_keep_the_modified_body_equal_a_fresh_build() {
    let body = Body::<f32>::from_inertia([58.84, 95.50, 120.66]).unwrap();
    let mut rng = Rng::new(5);
    let h0 = 1.0f32 / 200.0;
    let to64 = |v: [f32; 3]| v.map(f64::from);
    for order in [4u8, 10] {
        let mut pre = PreMv::new(body, h0, order).unwrap();
        let mut s = State::new([6.59f32, -1.08, -8.22], [1.0, 0.0, 0.0, 0.0]);
        let mut worst = 0.0f64;
        for k in 0..300 {
            match k % 3 {
                0 => pre.set_step_size(h0 * (1.0 + rng.range(-0.05, 0.05) as f32)),
                1 => {
                    for mi in s.m.iter_mut() {
                        *mi *= 1.0 + 1e-4 * rng.range(-1.0, 1.0) as f32;
                    }
                }
                _ => {}
            }
            let mut fresh = PreMv::new(body, pre.step_size(), order).unwrap();
            let mut f = s;
            fresh.step_state(&mut f).unwrap();
            pre.step_state(&mut s).unwrap();
            let (a, b) = (to64(s.m), to64(f.m));
            worst = worst.max(dist(a, b) / common::norm(b));
        }
        println!("f32 order {order}: worst one-step distance to a fresh build {worst:.1e}");
        // a few ulps of f32 (6e-8): the fresh build re-solves what the kept body tracks
        assert!(
            worst <= 4.0 * f32::EPSILON as f64,
            "order {order}: {worst:e}"
        );
    }
}

/// Error at `t = 10` of `PreMv(order)` stepping a fixed random sequence of steps within
/// +-5% of `h` (the last step lands on `t = 10`).
fn jittered_error(body: Body<f64>, order: u8, h: f64) -> f64 {
    let mut rng = Rng::new(99);
    let s0 = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    let mut pre = PreMv::new(body, h, order).unwrap();
    let mut s = s0;
    let mut t = 0.0;
    while t < 10.0 - 1e-12 {
        let hk = (h * (1.0 + rng.range(-0.05, 0.05))).min(10.0 - t);
        pre.set_step_size(hk);
        pre.step_state(&mut s).unwrap();
        t += hk;
    }
    let exact = Exact::at(&body, &s0, t).unwrap();
    dist(s.m, exact.m).max(qdist(s.q, exact.q))
}

#[test]
fn orders_hold_under_a_jittering_step() {
    let body = talk();
    for (order, hs) in [
        (4u8, [0.1, 0.05, 0.025]),
        (6, [0.2, 0.1, 0.05]),
        (8, [0.4, 0.2, 0.1]),
    ] {
        let errs: Vec<f64> = hs.iter().map(|&h| jittered_error(body, order, h)).collect();
        let p = observed_order(&hs, &errs);
        println!("PreMv order {order} under +-5% jitter: {p:.3} {errs:?}");
        assert!(
            (p - order as f64).abs() <= 0.3,
            "order {order}: {p} {errs:?}"
        );
    }
}
