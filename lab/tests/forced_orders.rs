//! Orders of the forced methods against the mpmath references of the forced scenes
//! (lab/refs/forced_refs.json): `mv` (kick–drift–kick, 2), `forced4` (4) and `forced6` (6)
//! on a heavy top, a Lagrange top, a gravity-gradient orbit, a time-periodic body torque and
//! a gyrostat, each within 0.15 of nominal.

use rigid3_lab::forced_refs::scene;
use rigid3_lab::forced_work::run;

/// Least-squares slope of log(error) against log(h) (`h = T / n`).
fn order(ns: &[usize], errs: &[f64]) -> f64 {
    let xs: Vec<f64> = ns.iter().map(|&n| -(n as f64).ln()).collect();
    let ys: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
    let k = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / k, ys.iter().sum::<f64>() / k);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

#[test]
fn orders_two_four_six_on_five_forced_scenes_against_the_references() {
    // step counts over t in [0, 1]: errors between about 1e-3 and 1e-11, in the asymptotic
    // range and well above the references' and f64's round-off
    let plans: [(&str, f64, [usize; 3]); 3] = [
        ("mv", 2.0, [40, 80, 160]),
        ("forced4", 4.0, [10, 20, 40]),
        ("forced6", 6.0, [5, 10, 20]),
    ];
    let mut bad = Vec::new();
    // the Lagrange top spins fast (|Omega_3| = 4): four times the steps
    for (name, more) in [
        ("heavy_top", 1),
        ("lagrange_top", 4),
        ("gravity_gradient", 1),
        ("body_torque", 1),
        ("gyrostat", 1),
    ] {
        let sc = scene(name, 1.0).expect("reference at t = 1");
        for (method, nominal, ns) in plans {
            let ns = ns.map(|n| n * more);
            let errs: Vec<f64> = ns
                .iter()
                .map(|&n| run(method, &sc, n).expect("the run succeeds").error)
                .collect();
            let p = order(&ns, &errs);
            let shown: Vec<String> = errs.iter().map(|e| format!("{e:.2e}")).collect();
            println!("{name:<17} {method:<8} errors {shown:?} order {p:.3}");
            if (p - nominal).abs() > 0.15 {
                bad.push(format!("{name} {method}: {p:.3}"));
            }
        }
    }
    assert!(bad.is_empty(), "orders off nominal: {bad:?}");
}
