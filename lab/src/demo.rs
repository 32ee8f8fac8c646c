//! The demo table: the talk's case with every method, errors against the reference
//! solution and the drift of the invariants.

use crate::methods::{make, METHODS};
use crate::propagate::propagate;
use crate::scenes::{TALK_J, TALK_M0, TALK_M10, TALK_M100};
use rigid3::{Body, State};

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// One row of the demo table.
pub struct Row {
    /// Method name.
    pub method: &'static str,
    /// Error in m at t = 10 and t = 100.
    pub err10: f64,
    /// Error in m at t = 100.
    pub err100: f64,
    /// Max relative drift of |m|^2, E and R(q) m over `drift_steps` steps with attitude.
    pub drift: [f64; 3],
    /// Counted flops per steady momentum step (`None` for the f64-only oracle).
    pub flops: Option<u64>,
}

/// Steps of the drift run.
pub const DRIFT_STEPS: usize = 100_000;

/// Runs the talk's case with every method at step `h`.
pub fn rows(h: f64) -> Vec<Row> {
    let body = Body::<f64>::from_mass_matrix(TALK_J).expect("valid body");
    let s0 = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    let n10 = (10.0 / h).round() as usize;
    METHODS
        .iter()
        .filter_map(|&name| {
            let mut a = make(name, body, h)?;
            let r10 = propagate(name, a.as_mut(), &body, s0, n10, false);
            let mut a = make(name, body, h)?;
            let r100 = propagate(name, a.as_mut(), &body, s0, 10 * n10, false);
            let mut a = make(name, body, h)?;
            let rd = propagate(name, a.as_mut(), &body, s0, DRIFT_STEPS, true);
            Some(Row {
                method: name,
                err10: dist(r10.m, TALK_M10),
                err100: dist(r100.m, TALK_M100),
                drift: [
                    rd.casimir_drift,
                    rd.energy_drift,
                    rd.spatial_momentum_drift.unwrap_or(f64::NAN),
                ],
                flops: crate::flops::step_cost(name, h).map(|c| c.momentum.flops()),
            })
        })
        .collect()
}

/// Prints the demo table.
pub fn print_demo() {
    let h = 0.1;
    println!("The talk's case: J = {TALK_J:?}, m0 = {TALK_M0:?}, h = {h}");
    println!(
        "errors |m(t) - m_ref(t)| against the high-precision reference; drift = max relative \
         change over {DRIFT_STEPS} steps with attitude"
    );
    println!(
        "{:<17} {:>11} {:>11} {:>11} {:>11} {:>11} {:>10}",
        "method", "err t=10", "err t=100", "|m|^2 drift", "E drift", "R(q)m drift", "flops/step"
    );
    for r in rows(h) {
        println!(
            "{:<17} {:>11.3e} {:>11.3e} {:>11.3e} {:>11.3e} {:>11.3e} {:>10}",
            r.method,
            r.err10,
            r.err100,
            r.drift[0],
            r.drift[1],
            r.drift[2],
            r.flops.map(|f| f.to_string()).unwrap_or_else(|| "-".into())
        );
    }
}
