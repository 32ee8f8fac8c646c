//! Figure 7: the long horizon. Every method gets the same counted cost per unit time (its
//! step size is its cost per step with attitude over the budget), and the error against the
//! exact solution is followed up to `T = 10^4`.

use super::plot::{Figure, Lines, Panel};
use super::{legend, progress, series, FIG_METHODS};
use crate::flops::step_cost;
use crate::methods::make;
use crate::scenes::{TALK_J, TALK_M0};
use rayon::prelude::*;
use rigid3::{Body, Exact, State};
use std::path::{Path, PathBuf};

/// Counted operations per unit time every method may spend (with attitude).
pub const BUDGET: f64 = 6000.0;

/// Horizon.
pub const T_END: f64 = 1e4;

/// Step size of `method` at the budget: its steady cost per step with attitude (flops, each
/// sqrt and transcendental call as one) over `BUDGET`.
pub fn step_at_budget(method: &'static str) -> Option<f64> {
    let c = step_cost(method, 0.1)?.state;
    Some((c.flops() + c.sqrt + c.trans) as f64 / BUDGET)
}

fn qdist(a: [f64; 4], b: [f64; 4]) -> f64 {
    let d1: f64 = (0..4).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
    let d2: f64 = (0..4).map(|k| (a[k] + b[k]).powi(2)).sum::<f64>().sqrt();
    d1.min(d2)
}

/// Error `max(|dm|/|m|, |dq|)` against the exact solution at about 40 times per decade
/// from `t = 1` to `T_END`, running `method` with step `h` (talk's case, with attitude).
pub fn history(method: &str, h: f64) -> Vec<(f64, f64)> {
    let body = Body::<f64>::from_mass_matrix(TALK_J).expect("valid body");
    let s0 = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    let Some(mut a) = make(method, body, h) else {
        return Vec::new();
    };
    let n_end = (T_END / h).round() as usize;
    let mut marks: Vec<usize> = (0..=160)
        .map(|k| ((10f64.powf(k as f64 / 40.0)) / h).round() as usize)
        .filter(|&n| n >= 1 && n <= n_end)
        .collect();
    marks.dedup();
    let norm = (TALK_M0.iter().map(|x| x * x).sum::<f64>()).sqrt();
    let mut s = s0;
    let mut out = Vec::new();
    let mut k = 0;
    for n in marks {
        while k < n {
            if a.step_state(&mut s).is_err() {
                return out;
            }
            k += 1;
        }
        let t = n as f64 * h;
        let Ok(e) = Exact::at(&body, &s0, t) else {
            continue;
        };
        let dm = (0..3)
            .map(|i| (s.m[i] - e.m[i]).powi(2))
            .sum::<f64>()
            .sqrt()
            / norm;
        let err = dm.max(qdist(s.q, e.q));
        if !err.is_finite() {
            return out;
        }
        out.push((t, err.max(super::talk::FLOOR)));
    }
    out
}

/// Writes figure 7.
pub fn figure(out: &Path) -> Result<Vec<PathBuf>, String> {
    let pb = progress(FIG_METHODS.len(), "long horizon");
    let runs: Vec<(&'static str, f64, super::Curve)> = FIG_METHODS
        .par_iter()
        .filter_map(|&m| {
            let h = step_at_budget(m)?;
            let r = history(m, h);
            pb.inc(1);
            Some((m, h, r))
        })
        .collect();
    pb.finish_and_clear();
    let mut leg = legend(FIG_METHODS);
    for e in &mut leg {
        if let Some((_, h, _)) = runs.iter().find(|r| r.0 == e.label) {
            e.label = format!("{} h={h:.3}", e.label);
        }
        e.mark = super::plot::Mark::None;
    }
    let fig = Figure {
        title: format!(
            "Figure 7: error versus time to T = 10^4 at equal cost ({BUDGET:.0} counted operations \
             per unit time, with attitude; talk's case)"
        ),
        size: (1400, 850),
        grid: (1, 1),
        panels: vec![Panel::Lines(Lines {
            title: String::new(),
            x_label: "t".into(),
            y_label: "error max(|dm|/|m|, |dq|) against the exact solution".into(),
            x_log: true,
            y_log: true,
            x_range: Some((1.0, T_END)),
            y_range: Some((1e-16, 10.0)),
            series: runs
                .iter()
                .map(|(m, _, r)| {
                    let mut s = series(m, m.to_string(), r.clone());
                    s.mark = super::plot::Mark::None;
                    s
                })
                .collect(),
            legend: false,
        })],
        legend: leg,
        legend_width: 260,
    };
    super::plot::save(&fig, out, "fig7")
}
