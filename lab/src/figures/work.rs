//! Figure 6: work-precision on the public scenes (talk, Hairer–Vilmart): error at T = 10
//! (with attitude) against cost, as counted operations, as host time and, for the methods
//! the firmware measured, as Cortex-M4F instructions.

use super::plot::{Bars, Figure, Lines, Panel};
use super::{legend, progress, series, style, Measured, FIG_METHODS};
use crate::methods::make;
use crate::refs::{scene, Scene};
use crate::work_precision::{step_counts, sweep, Point};
use plotters::style::RGBColor;
use rayon::prelude::*;
use rigid3::State;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Instructions per momentum step on the Cortex-M4F, measured by the firmware under QEMU
/// (f32, spacecraft scene; QEMU counts instructions, not cycles).
/// The splitting three ways: micromath's approximate trigonometry (about 1e-3), libm's
/// (software double on the M4F above `2^-12`; below it `sinf(x) = x`, `cosf(x) = 1`, which the
/// half angles of this scene mostly are: 7153 instructions when the splitting took full
/// angles) and `rigid3::sin_cos` (1.5 eps, polynomials in `f32`).
pub const CORTEX_M4F: [(&str, &str, f64); 10] = [
    ("mv", "mv", 191.0),
    ("pre-mv4", "pre-mv4", 231.0),
    ("pre-mv6", "pre-mv6", 231.0),
    ("pre-mv8", "pre-mv8", 231.0),
    ("pre-mv10", "pre-mv10", 231.0),
    ("rk4", "rk4", 145.0),
    ("split µmath", "splitting", 336.0),
    ("split sin_cos", "splitting", 423.0),
    ("split libm", "splitting", 585.0),
    ("seed-mv", "seed-mv", 1761.0),
];

/// The public scenes of the work-precision figure.
pub const SCENES: [&str; 2] = ["talk", "hv"];

/// Horizon of the work-precision runs.
pub const T_END: f64 = 10.0;

/// Host times per step (ns), measured serially.
#[derive(Clone, Debug, Default)]
pub struct HostTimes {
    /// Momentum-only steps on the talk's case, `h = 0.1`.
    pub momentum_talk: Vec<(&'static str, f64)>,
    /// Steps with attitude, per scene, `h = T_END / 200`.
    pub state: Vec<(&'static str, &'static str, f64)>,
}

/// Host ns per step of one timed run of 20000 steps (set-up excluded).
pub fn ns_per_step(method: &str, s: &Scene, h: f64, attitude: bool) -> Option<f64> {
    const N: usize = 20_000;
    let mut a = make(method, s.body::<f64>(), h)?;
    let mut st = State::new(s.m0, s.q0);
    a.step_state(&mut st).ok()?; // set-up out of the timing
    let t = Instant::now();
    for _ in 0..N {
        let r = if attitude {
            a.step_state(black_box(&mut st))
        } else {
            a.step(black_box(&mut st.m))
        };
        r.ok()?;
    }
    Some(t.elapsed().as_nanos() as f64 / N as f64)
}

/// Rounds of the host timing: every method once per round, the fastest round kept (noise
/// from the machine only ever adds time).
pub const ROUNDS: usize = 7;

/// Measures the host times (run it before anything parallel).
pub fn host_times() -> HostTimes {
    let talk = scene("talk").expect("talk scene");
    let scenes: Vec<Scene> = SCENES
        .iter()
        .map(|s| scene(s).expect("public scene"))
        .collect();
    let pb = progress(ROUNDS * FIG_METHODS.len(), "host time per step");
    let mut mom = vec![f64::INFINITY; FIG_METHODS.len()];
    let mut st = vec![[f64::INFINITY; 2]; FIG_METHODS.len()];
    for _ in 0..ROUNDS {
        for (k, &m) in FIG_METHODS.iter().enumerate() {
            mom[k] = mom[k].min(ns_per_step(m, &talk, 0.1, false).unwrap_or(f64::NAN));
            for (i, s) in scenes.iter().enumerate() {
                let t = ns_per_step(m, s, T_END / 200.0, true).unwrap_or(f64::NAN);
                st[k][i] = st[k][i].min(t);
            }
            pb.inc(1);
        }
    }
    pb.finish_and_clear();
    let mut h = HostTimes::default();
    for (k, &m) in FIG_METHODS.iter().enumerate() {
        if mom[k].is_finite() {
            h.momentum_talk.push((m, mom[k]));
        }
        for (i, &sc) in SCENES.iter().enumerate() {
            if st[k][i].is_finite() {
                h.state.push((sc, m, st[k][i]));
            }
        }
    }
    h
}

fn panel(title: String, x_label: &str, series: Vec<super::plot::Series>) -> Panel {
    Panel::Lines(Lines {
        title,
        x_label: x_label.into(),
        y_label: "error at T = 10 (max of |dm|/|m|, |dq|)".into(),
        x_log: true,
        y_log: true,
        x_range: None,
        y_range: Some((1e-16, 10.0)),
        series,
        legend: false,
    })
}

/// Momentum-only error at `T_END` on `s` with `n` steps (for the Cortex-M cost axis, which
/// was measured on momentum steps).
fn momentum_error(method: &str, s: &Scene, n: usize) -> Option<f64> {
    super::talk::error_at(method, s, T_END, T_END / n as f64).map(|e| {
        let r = s.m[s.at(T_END).unwrap_or(0)];
        e / (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt()
    })
}

/// Writes figure 6.
pub fn figure(
    out: &Path,
    host: &HostTimes,
    measured: &mut Measured,
) -> Result<Vec<PathBuf>, String> {
    let jobs: Vec<(&'static str, &'static str)> = SCENES
        .iter()
        .flat_map(|&s| FIG_METHODS.iter().map(move |&m| (s, m)))
        .collect();
    let pb = progress(jobs.len(), "work-precision sweeps");
    let sweeps: Vec<Vec<Point>> = jobs
        .par_iter()
        .map(|&(s, m)| {
            let sc = scene(s).expect("public scene");
            let p = sweep(m, &sc, T_END);
            pb.inc(1);
            p
        })
        .collect();
    pb.finish_and_clear();
    let talk = scene("talk").expect("talk scene");
    let cortex: Vec<(&str, &str, f64, super::Curve)> = CORTEX_M4F
        .par_iter()
        .filter(|c| !c.0.contains("µmath"))
        .map(|&(label, m, instr)| {
            let pts = step_counts()
                .into_iter()
                .filter_map(|n| momentum_error(m, &talk, n).map(|e| (instr * n as f64, e)))
                .collect();
            (label, m, instr, pts)
        })
        .collect();

    let mut panels = Vec::new();
    for (row, &sc) in SCENES.iter().enumerate() {
        let mine = |m: &str| -> &Vec<Point> {
            let k = jobs
                .iter()
                .position(|&(s, jm)| s == sc && jm == m)
                .unwrap_or(0);
            &sweeps[k]
        };
        panels.push(panel(
            format!("{sc}: counted operations"),
            "counted operations of the run (sqrt, sin/cos = 1 each)",
            FIG_METHODS
                .iter()
                .map(|&m| {
                    let pts = mine(m).iter().map(|p| (p.ops as f64, p.error)).collect();
                    series(m, m.into(), pts)
                })
                .collect(),
        ));
        panels.push(panel(
            format!("{sc}: host time (this machine, f64, with attitude)"),
            "host time of the run, ns (steps x measured ns/step)",
            FIG_METHODS
                .iter()
                .filter_map(|&m| {
                    let ns = host.state.iter().find(|(s, hm, _)| *s == sc && *hm == m)?.2;
                    let pts = mine(m).iter().map(|p| (p.n as f64 * ns, p.error)).collect();
                    Some(series(m, m.into(), pts))
                })
                .collect(),
        ));
        if row == 0 {
            let mut p = panel(
                "talk: instructions on Cortex-M4F (QEMU), momentum only".into(),
                "steps x instructions per step (f32 firmware, spacecraft scene)",
                cortex
                    .iter()
                    .map(|(label, m, _, pts)| series(m, label.to_string(), pts.clone()))
                    .collect(),
            );
            if let Panel::Lines(l) = &mut p {
                l.legend = true;
                l.y_label = "error in m at T = 10 (relative)".into();
                l.series
                    .iter_mut()
                    .for_each(|s| s.mark = super::plot::Mark::None);
            }
            panels.push(p);
        } else {
            panels.push(Panel::Bars(Bars {
                title: "instructions per momentum step on Cortex-M4F (QEMU)".into(),
                y_label: "instructions (QEMU counts instructions, not cycles)".into(),
                y_log: true,
                bars: CORTEX_M4F
                    .iter()
                    .map(|&(label, m, v)| {
                        let c = if label.contains("µmath") {
                            RGBColor(255, 180, 110)
                        } else {
                            style(m).0
                        };
                        (label.to_string(), v, c)
                    })
                    .collect(),
            }));
        }
    }
    measured.work = FIG_METHODS
        .iter()
        .filter_map(|&m| {
            let k = jobs.iter().position(|&(s, jm)| s == "talk" && jm == m)?;
            Some((m, sweeps[k].clone()))
        })
        .collect();
    let fig = Figure {
        title: "Figure 6: work-precision at T = 10, every method and order, public scenes".into(),
        size: (2100, 1250),
        grid: (2, 3),
        panels,
        legend: legend(FIG_METHODS),
        legend_width: 200,
    };
    super::plot::save(&fig, out, "fig6")
}
