//! `HvDmv` (Hairer–Vilmart's DMV with the fixed-point stage iteration) against the closed-form
//! `rigid3::Mv` (the same map) and against the exact solution (second order).

use rigid3::{Body, Exact, Integrator, Mv, State, StepError};
use rigid3_lab::hv_dmv::HvDmv;
use rigid3_lab::scenes::{TALK_J, TALK_M0};
mod common;

use common::Rng;

/// One step of each from the same state: max difference of m (relative to |m|) and of q
/// (the attitude as a rotation: q and -q are the same).
fn one_step(body: Body<f64>, s0: State<f64>, h: f64) -> Result<(f64, f64, u64), StepError> {
    let mut hv = HvDmv::new(body, h);
    let mut a = s0;
    hv.step_state(&mut a)?;
    let mut b = s0;
    Mv::new(body, h)
        .step_state(&mut b)
        .unwrap_or_else(|e| panic!("Mv {e:?}: {body:?} {s0:?} h {h}"));
    let r = (s0.m.iter().map(|x| x * x).sum::<f64>())
        .sqrt()
        .max(f64::MIN_POSITIVE);
    let dm = (0..3).map(|k| (a.m[k] - b.m[k]).abs()).fold(0.0, f64::max) / r;
    let sign = if (0..4).map(|k| a.q[k] * b.q[k]).sum::<f64>() < 0.0 {
        -1.0
    } else {
        1.0
    };
    let dq = (0..4)
        .map(|k| (a.q[k] - sign * b.q[k]).abs())
        .fold(0.0, f64::max);
    // the momentum-only step is the same map
    let mut m = s0.m;
    HvDmv::new(body, h).step(&mut m)?;
    assert_eq!(m, a.m);
    Ok((dm, dq, hv.stats().1))
}

fn random_unit_quaternion(rng: &mut Rng) -> [f64; 4] {
    let q = [
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    ];
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    q.map(|x| x / n)
}

#[test]
fn hv_dmv_is_mv_on_a_thousand_random_steps() {
    let mut rng = Rng(12);
    let (mut worst_m, mut worst_q) = (0.0f64, 0.0f64);
    let (mut converged, mut refused, mut sweeps) = (0u32, 0u32, 0u64);
    for _ in 0..1000 {
        let j = [
            rng.range(0.02, 1.0),
            rng.range(0.02, 1.0),
            rng.range(0.02, 1.0),
        ];
        let body = Body::from_mass_matrix(j).unwrap();
        let r = rng.range(0.1, 3.0);
        let m0 = [
            r * rng.range(-1.0, 1.0),
            r * rng.range(-1.0, 1.0),
            r * rng.range(-1.0, 1.0),
        ];
        // log-uniform over three decades up to 0.9 of the existence limit
        let h = Mv::max_step(&body, &m0).min(20.0) * 0.9 * 10f64.powf(rng.range(-3.0, 0.0));
        let s0 = State::new(m0, random_unit_quaternion(&mut rng));
        match one_step(body, s0, h) {
            Ok((dm, dq, n)) => {
                converged += 1;
                sweeps += n;
                worst_m = worst_m.max(dm);
                worst_q = worst_q.max(dq);
                assert!(
                    dm <= 1e-13 && dq <= 1e-13,
                    "J {j:?} m {m0:?} h {h}: {dm:e} {dq:e}"
                );
            }
            Err(e) => {
                assert_eq!(e, StepError::NoConvergence);
                refused += 1;
            }
        }
    }
    println!(
        "HvDmv vs Mv, 1000 random steps: {converged} converged (mean {:.2} sweeps after the \
         predictor), {refused} NoConvergence; max difference m {worst_m:.2e} (relative to |m|), \
         q {worst_q:.2e}",
        sweeps as f64 / f64::from(converged)
    );
    assert!(converged >= 900, "{converged}");
}

#[test]
fn a_refused_step_leaves_the_state_untouched() {
    // far past the fixed point's limit (~0.93 on the talk's case)
    let body = Body::from_mass_matrix(TALK_J).unwrap();
    let s0 = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    let mut s = s0;
    let mut hv = HvDmv::new(body, 3.0);
    assert_eq!(hv.step_state(&mut s), Err(StepError::NoConvergence));
    assert_eq!(s, s0);
    let mut m = s0.m;
    assert_eq!(hv.step(&mut m), Err(StepError::NoConvergence));
    assert_eq!(m, s0.m);
    assert_eq!(hv.stats(), (0, 0));
    let mut bad = State::new([f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]);
    assert_eq!(hv.step_state(&mut bad), Err(StepError::NonFinite));
    // h = 0 is the identity
    let mut z = s0;
    HvDmv::new(body, 0.0).step_state(&mut z).unwrap();
    assert_eq!(z, s0);
}

/// Error of `HvDmv` in m and q against the exact solution at t = 10 on the talk's case.
fn error_at_10(h: f64) -> (f64, f64, f64) {
    let body = Body::from_mass_matrix(TALK_J).unwrap();
    let s0 = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    let n = (10.0 / h).round() as usize;
    let mut hv = HvDmv::new(body, h);
    let mut s = s0;
    for _ in 0..n {
        hv.step_state(&mut s).unwrap();
    }
    let e = Exact::at(&body, &s0, 10.0).unwrap();
    let dm = (0..3)
        .map(|k| (s.m[k] - e.m[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    let sign = if (0..4).map(|k| s.q[k] * e.q[k]).sum::<f64>() < 0.0 {
        -1.0
    } else {
        1.0
    };
    let dq = (0..4)
        .map(|k| (s.q[k] - sign * e.q[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    (dm, dq, hv.mean_sweeps())
}

#[test]
fn second_order_against_the_exact_solution() {
    let hs: Vec<f64> = (3..=7).map(|k| 0.5f64.powi(k)).collect();
    let errs: Vec<(f64, f64, f64)> = hs.iter().map(|&h| error_at_10(h)).collect();
    for (h, (dm, dq, sw)) in hs.iter().zip(&errs) {
        println!(
            "h = {h:<9} err m {dm:.4e} ({:.4} h^2)  err q {dq:.4e}  sweeps/step {sw:.2}",
            dm / (h * h)
        );
    }
    for k in 1..hs.len() {
        let pm = (errs[k - 1].0 / errs[k].0).log2();
        let pq = (errs[k - 1].1 / errs[k].1).log2();
        println!("slope m {pm:.3} q {pq:.3}");
        assert!(
            (pm - 2.0).abs() < 0.05 && (pq - 2.0).abs() < 0.05,
            "{pm} {pq}"
        );
    }
    // DMV's error constant at t = 10 on the talk's case is 0.51 (docs/MATH.md §2)
    let c = errs[2].0 / (hs[2] * hs[2]);
    assert!((c - 0.51).abs() < 0.02, "{c}");
}

/// The identity the stage equation rests on: for `X = R(p)`, `p = (p0, v)` unit,
/// `X J - J X^T = 2 p0 hat(I v) + 2 hat((J v) x v)`.
#[test]
fn the_quaternion_form_of_the_dmv_equation() {
    let mut rng = Rng(5);
    let mut worst = 0.0f64;
    for _ in 0..1000 {
        let j = [rng.unit(), rng.unit(), rng.unit()];
        let i = [j[1] + j[2], j[0] + j[2], j[0] + j[1]];
        let p = random_unit_quaternion(&mut rng);
        let [w, x, y, z] = p;
        let r = common::rotation(p);
        let v = [x, y, z];
        let jv = [j[0] * x, j[1] * y, j[2] * z];
        let cross = [
            jv[1] * v[2] - jv[2] * v[1],
            jv[2] * v[0] - jv[0] * v[2],
            jv[0] * v[1] - jv[1] * v[0],
        ];
        let u: Vec<f64> = (0..3)
            .map(|k| 2.0 * w * i[k] * v[k] + 2.0 * cross[k])
            .collect();
        let hat = [[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]];
        for a in 0..3 {
            for b in 0..3 {
                let lhs = r[a][b] * j[b] - j[a] * r[b][a];
                worst = worst.max((lhs - hat[a][b]).abs());
            }
        }
    }
    assert!(worst < 1e-14, "{worst:e}");
}

/// docs/MATH.md §3: the fixed-point stage iteration stops converging at `h ~ 0.93` on the talk's
/// case (first step from m0), where the DMV step itself exists up to `1.06`.
#[test]
fn the_iteration_fails_near_h_0_93_on_the_talks_case() {
    let body = Body::from_mass_matrix(TALK_J).unwrap();
    let converges = |h: f64| HvDmv::new(body, h).step(&mut TALK_M0.clone()).is_ok();
    let (mut lo, mut hi) = (0.5, 1.06);
    assert!(converges(lo) && !converges(hi));
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if converges(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    println!(
        "HvDmv's first step converges up to h = {lo:.6} (Mv::max_step {:.6})",
        Mv::max_step(&body, &TALK_M0)
    );
    assert!((0.85..1.0).contains(&lo), "{lo}");
}
