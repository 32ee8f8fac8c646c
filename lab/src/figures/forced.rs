//! Figure 9: work-precision of the forced methods on the three charted forced scenes (heavy
//! top, gravity-gradient satellite with a wheel, gyrostat): error at `T = 10` (with attitude,
//! against the mpmath references) against counted operations and against host time.

use super::plot::{Bars, Figure, Lines, Panel};
use super::{legend, progress, series};
use crate::forced_work::{ns_per_step, sweep, ForcedScene, FORCED_CHART};
use crate::work_precision::Point;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// Instructions per forced f32 step with attitude on the Cortex-M4F, gravity gradient and
/// three wheels (`scripts/firmware`'s regime table, fixed step; QEMU counts instructions, not
/// cycles): the forced methods the firmware flies.
pub const CORTEX_M4F_FORCED: [(&str, &str, f64); 2] = [
    ("forced mv (M4F)", "mv", 1058.0),
    ("forced pre-mv4 (M4F)", "pre-mv4", 1300.0),
];

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

/// Host ns per step of every charted method on every scene, measured serially (before the
/// parallel sweeps), best of 5.
pub fn host_times(scenes: &[ForcedScene]) -> Vec<Vec<Option<f64>>> {
    let pb = progress(
        scenes.len() * FORCED_CHART.len(),
        "forced host time per step",
    );
    let t = scenes
        .iter()
        .map(|s| {
            FORCED_CHART
                .iter()
                .map(|m| {
                    let ns = ns_per_step(m, s, 5);
                    pb.inc(1);
                    ns
                })
                .collect()
        })
        .collect();
    pb.finish_and_clear();
    t
}

/// Writes figure 9 for `scenes` (one row of two panels per scene).
pub fn figure(
    out: &Path,
    scenes: &[ForcedScene],
    host: &[Vec<Option<f64>>],
) -> Result<Vec<PathBuf>, String> {
    let jobs: Vec<(usize, &'static str)> = (0..scenes.len())
        .flat_map(|s| FORCED_CHART.iter().map(move |&m| (s, m)))
        .collect();
    let pb = progress(jobs.len(), "forced work-precision sweeps");
    let sweeps: Vec<Vec<Point>> = jobs
        .par_iter()
        .map(|&(s, m)| {
            let p = sweep(m, &scenes[s]);
            pb.inc(1);
            p
        })
        .collect();
    pb.finish_and_clear();
    let mut panels = Vec::new();
    for (si, sc) in scenes.iter().enumerate() {
        let of = |m: &str| -> &Vec<Point> {
            let k = jobs
                .iter()
                .position(|&(s, jm)| s == si && jm == m)
                .unwrap_or(0);
            &sweeps[k]
        };
        panels.push(panel(
            format!("{}: counted operations", sc.name),
            "counted operations of the run (sqrt, sin/cos = 1 each)",
            FORCED_CHART
                .iter()
                .map(|&m| {
                    let pts = of(m).iter().map(|p| (p.ops as f64, p.error)).collect();
                    series(m, m.into(), pts)
                })
                .collect(),
        ));
        panels.push(panel(
            format!("{}: host time (this machine, f64, with attitude)", sc.name),
            "host time of the run, ns (steps x measured ns/step)",
            FORCED_CHART
                .iter()
                .enumerate()
                .filter_map(|(k, &m)| {
                    let ns = host.get(si)?.get(k).copied().flatten()?;
                    let pts = of(m).iter().map(|p| (p.n as f64 * ns, p.error)).collect();
                    Some(series(m, m.into(), pts))
                })
                .collect(),
        ));
    }
    // the target: the firmware's forced steps (gravity gradient and wheels, f32, with attitude)
    // in instructions per step, on the satellite scene (gravity gradient and a wheel)
    let target_row = scenes.iter().position(|s| s.name == "satellite");
    if let Some(si) = target_row {
        let k_of = |m: &str| jobs.iter().position(|&(s, jm)| s == si && jm == m);
        panels.push(panel(
            "satellite: instructions on Cortex-M4F (QEMU), forced steps with attitude".into(),
            "steps x instructions per step (f32 firmware: gravity gradient and wheels)",
            CORTEX_M4F_FORCED
                .iter()
                .filter_map(|&(label, m, instr)| {
                    let pts = sweeps[k_of(m)?]
                        .iter()
                        .map(|p| (p.n as f64 * instr, p.error))
                        .collect();
                    Some(series(m, label.into(), pts))
                })
                .collect(),
        ));
        panels.push(Panel::Bars(Bars {
            title: "instructions per forced step on Cortex-M4F (QEMU)".into(),
            y_label: "instructions (QEMU counts instructions, not cycles)".into(),
            y_log: false,
            bars: CORTEX_M4F_FORCED
                .iter()
                .map(|&(label, m, v)| (label.to_string(), v, super::style(m).0))
                .collect(),
        }));
    }
    let rows = scenes.len().max(1) + usize::from(target_row.is_some());
    let fig = Figure {
        title: "Figure 9: forced work-precision at T = 10: torques, gravity gradient and rotors"
            .into(),
        size: (1500, 420 * rows as u32 + 80),
        grid: (rows, 2),
        panels,
        legend: legend(&FORCED_CHART),
        legend_width: 200,
    };
    super::plot::save(&fig, out, "fig9")
}
