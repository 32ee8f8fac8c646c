//! Figure 8: the stability atlas. For each method and inertia shape, every (step size,
//! initial momentum direction) cell coloured by what the run did (`crate::atlas`), with
//! DMV's existence limit `Mv::max_step` drawn over it.

use super::plot::{Entry, Figure, Heat, Mark, Panel, Series};
use super::progress;
use crate::atlas::{classify, directions, max_step, step_sizes, Outcome, ATLAS_T};
use plotters::style::RGBColor;
use rayon::prelude::*;
use rigid3::{Body, StepError};
use std::path::{Path, PathBuf};

/// Methods of the atlas.
pub const METHODS: [&str; 8] = [
    "mv",
    "seed-mv",
    "pre-mv4",
    "splitting",
    "splitting2",
    "midpoint",
    "midpoint-fp",
    "rk4",
];

/// Inertia shapes `(name, I)`: the talk's body, an elongated asteroid, a flat plate (`J3 = 0`).
pub const SHAPES: [(&str, [f64; 3]); 3] = [
    ("talk", crate::scenes::TALK_I),
    ("asteroid", [0.35, 0.9, 1.0]),
    ("flat plate", [1.0, 2.0, 3.0]),
];

/// Grid: step sizes (log-spaced) and directions (|m| = 1).
pub const N_STEPS: usize = 40;
/// Directions on the sphere.
pub const N_DIRS: usize = 64;
/// Step range.
pub const H_RANGE: (f64, f64) = (0.02, 50.0);

/// Colour of an outcome.
pub fn color(o: Outcome) -> RGBColor {
    match o {
        Outcome::Accurate => RGBColor(120, 200, 120),
        Outcome::PhaseError => RGBColor(250, 225, 120),
        Outcome::Drift => RGBColor(240, 140, 60),
        Outcome::BlowUp => RGBColor(200, 30, 30),
        Outcome::NaN => RGBColor(0, 0, 0),
        Outcome::Refused(StepError::StepTooLarge) => RGBColor(80, 120, 210),
        Outcome::Refused(StepError::NoConvergence) => RGBColor(160, 100, 210),
        Outcome::Refused(StepError::Degenerate) => RGBColor(80, 210, 230),
        Outcome::Refused(StepError::Overflow) => RGBColor(120, 70, 30),
        Outcome::Refused(_) => RGBColor(110, 110, 110),
    }
}

/// The atlas of one shape: directions sorted by `Mv::max_step`, and per method the outcome
/// of every (step, direction) cell.
pub struct ShapeAtlas {
    /// Shape name.
    pub name: &'static str,
    /// Sorted directions and their `max_step`.
    pub dirs: Vec<([f64; 3], f64)>,
    /// `outcomes[method][step][dir]`.
    pub outcomes: Vec<Vec<Vec<Outcome>>>,
}

/// Computes the whole atlas (in parallel).
pub fn compute() -> Vec<ShapeAtlas> {
    let hs = step_sizes(H_RANGE.0, H_RANGE.1, N_STEPS);
    let total = SHAPES.len() * METHODS.len() * N_STEPS * N_DIRS;
    let pb = progress(total, "stability atlas");
    let atlas = SHAPES
        .iter()
        .map(|&(name, inertia)| {
            let body = Body::<f64>::from_inertia(inertia).expect("valid shape");
            let mut dirs: Vec<([f64; 3], f64)> = directions(N_DIRS)
                .into_iter()
                .map(|d| (d, max_step(&body, &d)))
                .collect();
            dirs.sort_by(|a, b| a.1.total_cmp(&b.1));
            let outcomes = METHODS
                .par_iter()
                .map(|&m| {
                    hs.par_iter()
                        .map(|&h| {
                            let row = dirs
                                .iter()
                                .map(|(d, _)| classify(m, &body, *d, h).unwrap_or(Outcome::NaN))
                                .collect();
                            pb.inc(N_DIRS as u64);
                            row
                        })
                        .collect()
                })
                .collect();
            ShapeAtlas {
                name,
                dirs,
                outcomes,
            }
        })
        .collect();
    pb.finish_and_clear();
    atlas
}

/// Fractions of accurate, phase-error, silent-failure and refused cells per method, over
/// all shapes.
pub fn summary(atlas: &[ShapeAtlas]) -> Vec<(&'static str, [f64; 4])> {
    METHODS
        .iter()
        .enumerate()
        .map(|(k, &m)| {
            let mut c = [0usize; 4];
            let mut n = 0;
            for s in atlas {
                for o in s.outcomes[k].iter().flatten() {
                    n += 1;
                    match o {
                        Outcome::Accurate => c[0] += 1,
                        Outcome::PhaseError => c[1] += 1,
                        Outcome::Refused(_) => c[3] += 1,
                        _ => c[2] += 1,
                    }
                }
            }
            (m, c.map(|x| x as f64 / n.max(1) as f64))
        })
        .collect()
}

/// Writes figure 8 and prints the summary.
pub fn figure(out: &Path) -> Result<Vec<PathBuf>, String> {
    let atlas = compute();
    let hs = step_sizes(H_RANGE.0, H_RANGE.1, N_STEPS);
    let mut panels = Vec::new();
    for (k, &m) in METHODS.iter().enumerate() {
        for s in &atlas {
            let cells = s.outcomes[k]
                .iter()
                .enumerate()
                .flat_map(|(i, row)| row.iter().enumerate().map(move |(j, &o)| (i, j, color(o))))
                .collect();
            let curve = s
                .dirs
                .iter()
                .enumerate()
                .filter(|(_, (_, l))| l.is_finite())
                .map(|(j, (_, l))| (*l, j as f64 + 0.5))
                .collect();
            panels.push(Panel::Heat(Heat {
                title: format!("{m} — {}", s.name),
                x_label: "step size h".into(),
                y_label: "direction".into(),
                xs: hs.clone(),
                ny: N_DIRS,
                cells,
                overlay: vec![Series {
                    label: String::new(),
                    points: curve,
                    color: RGBColor(0, 0, 0),
                    line: true,
                    dashed: true,
                    mark: Mark::None,
                }],
            }));
        }
    }
    let mut legend: Vec<Entry> = Outcome::ALL
        .iter()
        .map(|&o| Entry {
            label: o.label().into(),
            color: color(o),
            mark: Mark::None,
            line: false,
            dashed: false,
        })
        .collect();
    legend.push(Entry {
        label: "Mv::max_step (DMV exists left of it)".into(),
        color: RGBColor(0, 0, 0),
        mark: Mark::None,
        line: true,
        dashed: true,
    });
    let fig = Figure {
        title: format!(
            "Figure 8: stability atlas, |m| = 1, {N_DIRS} directions (sorted by Mv::max_step) x \
             {N_STEPS} step sizes, run to t = {ATLAS_T}"
        ),
        size: (1900, 2600),
        grid: (METHODS.len(), SHAPES.len()),
        panels,
        legend,
        legend_width: 330,
    };
    println!("stability atlas: share of cells per method (all shapes)");
    println!(
        "{:<12} {:>9} {:>12} {:>15} {:>9}",
        "method", "accurate", "phase error", "silent failure", "refused"
    );
    for (m, f) in summary(&atlas) {
        println!(
            "{m:<12} {:>8.0}% {:>11.0}% {:>14.0}% {:>8.0}%",
            100.0 * f[0],
            100.0 * f[1],
            100.0 * f[2],
            100.0 * f[3]
        );
    }
    super::plot::save(&fig, out, "fig8")
}
