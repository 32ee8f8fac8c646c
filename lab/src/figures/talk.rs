//! Figures 1–5: the talk's experiments on its case (`J = (0.9218, 0.7382, 0.1763)`,
//! `m0 = (0.4165, 0.9072, 0.0588)`), every method on the same axes.

use super::plot::{Figure, Lines, Panel, Series};
use super::{legend, progress, series, Measured, FIG_METHODS};
use crate::count::{count, Counted};
use crate::methods::make;
use crate::refs::{scene, Scene};
use crate::scenes::{TALK_J, TALK_M0};
use plotters::style::RGBColor;
use rayon::prelude::*;
use rigid3::{Body, Exact};
use std::path::{Path, PathBuf};

/// The talk's step sizes of the error plots: `2^-k`, `k = 0..8`.
pub fn step_sizes() -> Vec<f64> {
    (0..=8).map(|k| 2f64.powi(-k)).collect()
}

/// Errors below this are drawn at it (round-off; log axes cannot show zero).
pub const FLOOR: f64 = 1e-17;

fn talk() -> Scene {
    scene("talk").expect("the talk's scene is in refs.json")
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// `|m_n - m(t)|` of `method` (f64, momentum only) at a reference time `t` of `scene` with
/// step `h`; `None` if a step is refused or the result is not finite.
pub fn error_at(method: &str, scene: &Scene, t: f64, h: f64) -> Option<f64> {
    let i = scene.at(t)?;
    let n = (t / h).round() as usize;
    let mut a = make(method, scene.body::<f64>(), h)?;
    let mut m = scene.m0;
    for _ in 0..n {
        a.step(&mut m).ok()?;
    }
    let e = dist(m, scene.m[i]);
    e.is_finite().then_some(e)
}

/// Error at `t` versus `h = 2^-k` of every charted method, in parallel.
pub fn error_curves(t: f64) -> Vec<(&'static str, Vec<(f64, f64)>)> {
    let s = talk();
    let hs = step_sizes();
    let jobs: Vec<(&'static str, f64)> = FIG_METHODS
        .iter()
        .flat_map(|&m| hs.iter().map(move |&h| (m, h)))
        .collect();
    let pb = progress(jobs.len(), &format!("errors at t = {t}"));
    let errs: Vec<Option<f64>> = jobs
        .par_iter()
        .map(|&(m, h)| {
            let e = error_at(m, &s, t, h);
            pb.inc(1);
            e
        })
        .collect();
    pb.finish_and_clear();
    FIG_METHODS
        .iter()
        .map(|&m| {
            let pts = jobs
                .iter()
                .zip(&errs)
                .filter(|((jm, _), _)| *jm == m)
                .filter_map(|((_, h), e)| e.map(|e| (*h, e.max(FLOOR))))
                .collect();
            (m, pts)
        })
        .collect()
}

/// Least-squares slope of `log err` against `log h` over `h` in `[lo, hi]`.
pub fn slope(points: &[(f64, f64)], lo: f64, hi: f64) -> Option<f64> {
    let p: Vec<(f64, f64)> = points
        .iter()
        .filter(|(h, e)| *h >= lo && *h <= hi && *e > 1e-13)
        .map(|(h, e)| (h.ln(), e.ln()))
        .collect();
    if p.len() < 2 {
        return None;
    }
    let n = p.len() as f64;
    let (mx, my) = (
        p.iter().map(|q| q.0).sum::<f64>() / n,
        p.iter().map(|q| q.1).sum::<f64>() / n,
    );
    let sxy: f64 = p.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
    let sxx: f64 = p.iter().map(|q| (q.0 - mx).powi(2)).sum();
    Some(sxy / sxx)
}

fn error_figure(t: f64, curves: &[(&'static str, Vec<(f64, f64)>)], n: u32) -> Figure {
    Figure {
        title: format!(
            "Figure {n}: error |m_n - m(t)| at t = {t} versus step size (talk's case, h = 2^-k)"
        ),
        size: (1300, 820),
        grid: (1, 1),
        panels: vec![Panel::Lines(Lines {
            title: String::new(),
            x_label: "step size h".into(),
            y_label: format!("error in m at t = {t}"),
            x_log: true,
            y_log: true,
            x_range: Some((2f64.powi(-9), 2.0)),
            y_range: Some((FLOOR, 10.0)),
            series: curves
                .iter()
                .map(|(m, p)| series(m, m.to_string(), p.clone()))
                .collect(),
            legend: false,
        })],
        legend: legend(FIG_METHODS),
        legend_width: 220,
    }
}

/// Relative energy and `|m|^2` error after each step over `[0, t_end]` with step `h`.
pub fn energy_history(method: &str, h: f64, t_end: f64) -> (Vec<(f64, f64)>, f64, f64) {
    let body = Body::<f64>::from_mass_matrix(TALK_J).expect("valid body");
    let (e0, c0) = (body.energy(&TALK_M0), body.casimir(&TALK_M0));
    let mut pts = Vec::new();
    let (mut de, mut dc) = (0.0f64, 0.0f64);
    let Some(mut a) = make(method, body, h) else {
        return (pts, f64::NAN, f64::NAN);
    };
    let mut m = TALK_M0;
    let n = (t_end / h).round() as usize;
    for k in 1..=n {
        if a.step(&mut m).is_err() {
            break;
        }
        let e = (body.energy(&m) - e0).abs() / e0;
        de = de.max(e);
        dc = dc.max((body.casimir(&m) - c0).abs() / c0);
        pts.push((k as f64 * h, e.max(FLOOR)));
    }
    (pts, de, dc)
}

/// Counted operations (`+ - * /`, each sqrt and transcendental call as one) of a whole
/// momentum-only run over `[0, t_end]` with step `h`, set-up included.
pub fn run_ops(method: &str, h: f64, t_end: f64) -> Option<u64> {
    let body = Body::<Counted>::from_mass_matrix(TALK_J.map(Counted)).ok()?;
    let mut a = make(method, body, Counted(h))?;
    let mut m = TALK_M0.map(Counted);
    let n = (t_end / h).round() as usize;
    let (ok, c) = count(|| (0..n).all(|_| a.step(&mut m).is_ok()));
    ok.then_some(c.flops() + c.sqrt + c.trans)
}

/// Figure 5 gives each of its four methods its own marker.
fn fig5_mark(method: &str) -> super::plot::Mark {
    use super::plot::Mark;
    match method {
        "mv" => Mark::Circle,
        "splitting" => Mark::Cross,
        "midpoint" => Mark::Square,
        _ => Mark::Triangle,
    }
}

fn component_panel(h: f64, t_end: f64) -> Panel {
    let body = Body::<f64>::from_mass_matrix(TALK_J).expect("valid body");
    let grey = [
        RGBColor(150, 150, 150),
        RGBColor(150, 150, 150),
        RGBColor(150, 150, 150),
    ];
    let samples = 700;
    let exact: Vec<[f64; 3]> = (0..=samples)
        .map(|k| {
            let t = t_end * k as f64 / samples as f64;
            Exact::momentum_at(&body, &TALK_M0, t).unwrap_or([f64::NAN; 3])
        })
        .collect();
    let mut s: Vec<Series> = (0..3)
        .map(|c| Series {
            label: if c == 0 {
                "exact".into()
            } else {
                String::new()
            },
            points: exact
                .iter()
                .enumerate()
                .map(|(k, m)| (t_end * k as f64 / samples as f64, m[c]))
                .collect(),
            color: grey[c],
            line: true,
            dashed: false,
            mark: super::plot::Mark::None,
        })
        .collect();
    let n = (t_end / h).round() as usize;
    let stride = (n / 60).max(1);
    for method in ["mv", "splitting", "midpoint", "rk4"] {
        let Some(mut a) = make(method, body, h) else {
            continue;
        };
        let mut m = TALK_M0;
        let mut traj = vec![(0.0, m)];
        for k in 1..=n {
            if a.step(&mut m).is_err() {
                break;
            }
            if k % stride == 0 {
                traj.push((k as f64 * h, m));
            }
        }
        for c in 0..3 {
            let mut ser = series(
                method,
                if c == 0 {
                    method.to_string()
                } else {
                    String::new()
                },
                traj.iter().map(|(t, m)| (*t, m[c])).collect(),
            );
            ser.line = false;
            ser.mark = fig5_mark(method);
            s.push(ser);
        }
    }
    Panel::Lines(Lines {
        title: format!("h = {h}: m1 (from 0.42), m2 (from 0.91), m3 (from 0.06); grey: exact"),
        x_label: "t".into(),
        y_label: "m_k components".into(),
        x_log: false,
        y_log: false,
        x_range: Some((0.0, t_end)),
        y_range: Some((-1.15, 1.15)),
        series: s,
        legend: false,
    })
}

/// Writes figures 1–5 and records what the claims table needs.
pub fn figures(out: &Path, measured: &mut Measured) -> Result<Vec<PathBuf>, String> {
    let mut files = Vec::new();
    let e1 = error_curves(1.0);
    files.extend(super::plot::save(&error_figure(1.0, &e1, 1), out, "fig1")?);
    let e10 = error_curves(10.0);
    files.extend(super::plot::save(
        &error_figure(10.0, &e10, 2),
        out,
        "fig2",
    )?);
    measured.err10 = e10;

    // 3: energy error over [0, 100] at h = 1/2
    let hist: Vec<(&'static str, (super::Curve, f64, f64))> = FIG_METHODS
        .par_iter()
        .map(|&m| (m, energy_history(m, 0.5, 100.0)))
        .collect();
    measured.drift = hist.iter().map(|(m, (_, de, dc))| (*m, *de, *dc)).collect();
    let fig3 = Figure {
        title: "Figure 3: relative energy error over [0, 100] at h = 1/2 (talk's case)".into(),
        size: (1300, 820),
        grid: (1, 1),
        panels: vec![Panel::Lines(Lines {
            title: String::new(),
            x_label: "t".into(),
            y_label: "|E(m_n) - E(m_0)| / E(m_0)".into(),
            x_log: false,
            y_log: true,
            x_range: Some((0.0, 100.0)),
            y_range: Some((FLOOR, 10.0)),
            // the conserving methods last, on top of the others
            series: hist
                .iter()
                .rev()
                .map(|(m, (p, _, _))| {
                    let mut s = series(m, m.to_string(), p.clone());
                    s.mark = super::plot::Mark::None;
                    s
                })
                .collect(),
            legend: false,
        })],
        legend: legend(FIG_METHODS)
            .into_iter()
            .map(|mut e| {
                e.mark = super::plot::Mark::None;
                e
            })
            .collect(),
        legend_width: 220,
    };
    files.extend(super::plot::save(&fig3, out, "fig3")?);

    // 4: counted operations of the whole run over [0, 100] versus h
    let hs = step_sizes();
    let jobs: Vec<(&'static str, f64)> = FIG_METHODS
        .iter()
        .flat_map(|&m| hs.iter().map(move |&h| (m, h)))
        .collect();
    let pb = progress(jobs.len(), "counted flops over [0, 100]");
    let ops: Vec<Option<u64>> = jobs
        .par_iter()
        .map(|&(m, h)| {
            let o = run_ops(m, h, 100.0);
            pb.inc(1);
            o
        })
        .collect();
    pb.finish_and_clear();
    let fig4 = Figure {
        title:
            "Figure 4: counted operations of the run over [0, 100] versus step size (talk's case)"
                .into(),
        size: (1300, 820),
        grid: (1, 1),
        panels: vec![Panel::Lines(Lines {
            title: String::new(),
            x_label: "step size h".into(),
            y_label: "operations (+ - * /, sqrt and sin/cos as one each)".into(),
            x_log: true,
            y_log: true,
            x_range: Some((2f64.powi(-9), 2.0)),
            y_range: None,
            series: FIG_METHODS
                .iter()
                .map(|&m| {
                    let pts = jobs
                        .iter()
                        .zip(&ops)
                        .filter(|((jm, _), _)| *jm == m)
                        .filter_map(|((_, h), o)| o.map(|o| (*h, o as f64)))
                        .collect();
                    series(m, m.to_string(), pts)
                })
                .collect(),
            legend: false,
        })],
        legend: legend(FIG_METHODS),
        legend_width: 220,
    };
    files.extend(super::plot::save(&fig4, out, "fig4")?);

    // 5: components of m_k over the exact solution, h = 1/10, 1/2, 1
    let panels: Vec<Panel> = [0.1, 0.5, 1.0]
        .par_iter()
        .map(|&h| component_panel(h, 35.0))
        .collect();
    let mut l5 = legend(&["mv", "splitting", "midpoint", "rk4"]);
    for e in &mut l5 {
        e.line = false;
        e.mark = fig5_mark(&e.label);
    }
    l5.insert(
        0,
        super::plot::Entry {
            label: "exact".into(),
            color: RGBColor(150, 150, 150),
            mark: super::plot::Mark::None,
            line: true,
            dashed: false,
        },
    );
    let fig5 = Figure {
        title:
            "Figure 5: components of m_k over the exact solution, t in [0, 35] (one period of m)"
                .into(),
        size: (1300, 1300),
        grid: (3, 1),
        panels,
        legend: l5,
        legend_width: 180,
    };
    files.extend(super::plot::save(&fig5, out, "fig5")?);
    Ok(files)
}
