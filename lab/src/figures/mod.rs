//! `rigid3-lab figures`: every chart of the README, as SVG and PNG, from one command.
//!
//! 1–5 are the talk's experiments on its case (`talk.rs`), 6 work-precision (`work.rs`),
//! 7 the long horizon at equal cost (`horizon.rs`), 8 the stability atlas (`stability.rs`).
//! Everything is deterministic (no random numbers; the atlas directions are a Fibonacci
//! lattice); host times are measured, so they vary from run to run by a few percent.

pub mod forced;
pub mod horizon;
pub mod plot;
pub mod stability;
pub mod talk;
pub mod work;

use indicatif::{ProgressBar, ProgressStyle};
use plot::{Entry, Mark};
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The methods compared in the charts: every integrator of the registry but the lab's
/// oracle (`general`, identical to `mv`) and `exact` (the reference itself).
pub const FIG_METHODS: &[&str] = &[
    "mv",
    "seed-mv",
    "pre-mv4",
    "pre-mv6",
    "pre-mv8",
    "pre-mv10",
    "retimed-mv",
    "retimed-pre-mv10",
    "splitting",
    "splitting2",
    "midpoint",
    "midpoint-fp",
    "rk4",
];

/// Points `(x, y)` of one curve.
pub type Curve = Vec<(f64, f64)>;

/// Colour, marker and dash of a method, the same in every chart.
pub fn style(method: &str) -> (RGBColor, Mark, bool) {
    match method {
        "mv" => (RGBColor(31, 119, 180), Mark::Circle, false),
        "seed-mv" => (RGBColor(120, 180, 240), Mark::Cross, true),
        "pre-mv4" => (RGBColor(44, 160, 44), Mark::Triangle, false),
        "pre-mv6" => (RGBColor(23, 170, 190), Mark::Square, false),
        "pre-mv8" => (RGBColor(90, 90, 210), Mark::Triangle, false),
        "pre-mv10" => (RGBColor(148, 103, 189), Mark::Square, false),
        "retimed-mv" => (RGBColor(140, 86, 75), Mark::Circle, true),
        "retimed-pre-mv10" => (RGBColor(188, 170, 34), Mark::Square, true),
        "splitting" => (RGBColor(255, 127, 14), Mark::Circle, false),
        "splitting2" => (RGBColor(214, 39, 40), Mark::Triangle, false),
        "midpoint" => (RGBColor(20, 20, 20), Mark::Square, false),
        "midpoint-fp" => (RGBColor(130, 130, 130), Mark::Cross, true),
        "rk4" => (RGBColor(227, 119, 194), Mark::Circle, false),
        "forced4" => (RGBColor(0, 100, 0), Mark::Triangle, false),
        "forced6" => (RGBColor(0, 0, 139), Mark::Square, false),
        "forced4-pre4" => (RGBColor(0, 100, 0), Mark::Cross, true),
        "forced6-pre6" => (RGBColor(0, 0, 139), Mark::Cross, true),
        "forced4-pre10" => (RGBColor(60, 179, 113), Mark::Circle, true),
        "forced6-pre10" => (RGBColor(65, 105, 225), Mark::Circle, true),
        "nystrom4-pre10" => (RGBColor(200, 0, 90), Mark::Triangle, false),
        "nystrom6-pre10" => (RGBColor(110, 0, 160), Mark::Square, false),
        "fg4-pre6" => (RGBColor(230, 120, 0), Mark::Triangle, false),
        _ => (RGBColor(100, 100, 100), Mark::None, false),
    }
}

/// A series of `method` in its style.
pub fn series(method: &str, label: String, points: Vec<(f64, f64)>) -> plot::Series {
    let (color, mark, dashed) = style(method);
    plot::Series {
        label,
        points,
        color,
        line: true,
        dashed,
        mark,
    }
}

/// Legend entries for `methods` in their styles.
pub fn legend(methods: &[&str]) -> Vec<Entry> {
    methods
        .iter()
        .map(|m| {
            let (color, mark, dashed) = style(m);
            Entry {
                label: m.to_string(),
                color,
                mark,
                line: true,
                dashed,
            }
        })
        .collect()
}

/// A progress bar on stderr (drawn only on a terminal).
pub fn progress(len: usize, msg: &str) -> ProgressBar {
    let pb = ProgressBar::new(len as u64);
    pb.set_style(
        ProgressStyle::with_template("{msg:<28} [{bar:40}] {pos}/{len} {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    pb.set_message(msg.to_string());
    pb
}

/// What the charts measured that the claims table needs.
#[derive(Clone, Debug, Default)]
pub struct Measured {
    /// Error at t = 10 versus h, per method (figure 2).
    pub err10: Vec<(&'static str, Vec<(f64, f64)>)>,
    /// Max relative energy and |m|^2 drift over [0, 100] at h = 1/2 (figure 3).
    pub drift: Vec<(&'static str, f64, f64)>,
    /// Host ns per momentum step, talk's case (f64).
    pub host_ns: Vec<(&'static str, f64)>,
    /// Work-precision sweeps on the talk's case (counted ops).
    pub work: Vec<(&'static str, Vec<crate::work_precision::Point>)>,
}

/// Writes every figure into `out` and returns the files and what was measured.
pub fn all(out: &Path) -> Result<(Vec<PathBuf>, Measured), String> {
    let font = plot::register_font()?;
    eprintln!("chart font: {}", font.display());
    let mut files = Vec::new();
    let mut measured = Measured::default();
    let t0 = Instant::now();
    let step =
        |name: &str, t: Instant| eprintln!("{name} done in {:.1} s", t.elapsed().as_secs_f64());

    // host times first, alone on the machine (the parallel sweeps would disturb them)
    let t = Instant::now();
    let host = work::host_times();
    measured.host_ns = host.momentum_talk.clone();
    step("host times", t);

    let t = Instant::now();
    files.extend(talk::figures(out, &mut measured)?);
    step("figures 1-5", t);

    let t = Instant::now();
    files.extend(work::figure(out, &host, &mut measured)?);
    step("figure 6", t);

    let t = Instant::now();
    files.extend(horizon::figure(out)?);
    step("figure 7", t);

    let t = Instant::now();
    files.extend(stability::figure(out)?);
    step("figure 8", t);

    let t = Instant::now();
    let scenes = crate::forced_work::charted_scenes();
    let host = forced::host_times(&scenes);
    files.extend(forced::figure(out, &scenes, &host)?);
    step("figure 9", t);

    eprintln!("all figures in {:.1} s", t0.elapsed().as_secs_f64());
    Ok((files, measured))
}
