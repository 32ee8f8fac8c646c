//! The talk's claims next to our measurements (counted flops, host time, Cortex-M4F
//! instructions, errors, orders, conservation), and the headline comparison at equal accuracy.

use crate::figures::talk::{error_curves, slope};
use crate::figures::work::{host_times, CORTEX_M4F};
use crate::figures::Measured;
use crate::flops::step_cost;
use crate::propagate::propagate;
use crate::scenes::{TALK_J, TALK_M0};
use crate::work_precision::{cost_at, sweep, Point, BASELINES, PRE};
use rigid3::{Body, State};

/// Measures what the table needs without drawing (the `claims` command).
pub fn measure() -> Measured {
    let talk = crate::refs::scene("talk").expect("talk scene");
    let host_ns = host_times().momentum_talk;
    let drift = ["mv", "seed-mv", "splitting", "midpoint", "rk4"]
        .iter()
        .map(|&m| {
            let (_, de, dc) = crate::figures::talk::energy_history(m, 0.5, 100.0);
            (m, de, dc)
        })
        .collect();
    let work = PRE
        .iter()
        .chain(BASELINES.iter())
        .map(|&m| (m, sweep(m, &talk, 10.0)))
        .collect();
    Measured {
        err10: error_curves(10.0),
        drift,
        host_ns,
        work,
    }
}

fn ops(method: &'static str) -> f64 {
    step_cost(method, 0.1)
        .map(|c| (c.momentum.flops() + c.momentum.sqrt + c.momentum.trans) as f64)
        .unwrap_or(f64::NAN)
}

fn flops(method: &'static str) -> f64 {
    step_cost(method, 0.1)
        .map(|c| c.momentum.flops() as f64)
        .unwrap_or(f64::NAN)
}

fn lookup(v: &[(&'static str, f64)], m: &str) -> f64 {
    v.iter().find(|x| x.0 == m).map(|x| x.1).unwrap_or(f64::NAN)
}

fn cortex(label: &str) -> f64 {
    CORTEX_M4F
        .iter()
        .find(|c| c.0 == label)
        .map(|c| c.2)
        .unwrap_or(f64::NAN)
}

fn err_at(m: &Measured, method: &str, h: f64) -> f64 {
    m.err10
        .iter()
        .find(|x| x.0 == method)
        .and_then(|x| x.1.iter().find(|p| p.0 == h))
        .map(|p| p.1)
        .unwrap_or(f64::NAN)
}

/// The claims table as Markdown rows `(claim, measured, verdict)`.
pub fn table(m: &Measured) -> Vec<[String; 3]> {
    let host = |x: &str| lookup(&m.host_ns, x);
    let mut rows = Vec::new();

    let (fs, fsp, fmv, fmid) = (
        flops("seed-mv"),
        flops("splitting"),
        flops("mv"),
        flops("midpoint"),
    );
    let (os, osp, omv, omid) = (ops("seed-mv"), ops("splitting"), ops("mv"), ops("midpoint"));
    rows.push([
        "'about 10x more expensive than the splitting' (the talk's explicit DMV)".into(),
        format!(
            "SeedMv / Splitting: {:.1}x counted flops ({fs:.0} vs {fsp:.0}; {:.1}x with sqrt and \
             sin/cos as one op), {:.1}x host time ({:.0} vs {:.0} ns), {:.2}x Cortex-M4F \
             instructions ({:.0} vs {:.0}; {:.1}x the splitting with rigid3::sin_cos, {:.0}). \
             Mv / Splitting: {:.1}x flops, {:.2}x host time, {:.3}x Cortex-M4F ({:.2}x with \
             sin_cos)",
            fs / fsp,
            os / osp,
            host("seed-mv") / host("splitting"),
            host("seed-mv"),
            host("splitting"),
            cortex("seed-mv") / cortex("split libm"),
            cortex("seed-mv"),
            cortex("split libm"),
            cortex("seed-mv") / cortex("split sin_cos"),
            cortex("split sin_cos"),
            fmv / fsp,
            host("mv") / host("splitting"),
            cortex("mv") / cortex("split libm"),
            cortex("mv") / cortex("split sin_cos"),
        ),
        format!(
            "Partly: 10x is between our flop count (more) and host time (less); on the \
             Cortex-M4F {:.0}x with libm's sin/cos (which return at once below 2^-12, where this \
             scene's half angles are; above it they compute in software double, and the two \
             cost about the same) and {:.0}x with accurate single-precision sin/cos. Mv removes \
             the question: cheaper than the splitting in time on both machines",
            cortex("seed-mv") / cortex("split libm"),
            cortex("seed-mv") / cortex("split sin_cos")
        ),
    ]);
    rows.push([
        "'comparable in cost with IMR'".into(),
        format!(
            "SeedMv / Midpoint (Newton): {:.1}x flops ({fs:.0} vs {fmid:.0}; {:.1}x ops), {:.1}x \
             host time. Mv / Midpoint: {:.2}x flops ({:.2}x ops), {:.2}x host time",
            fs / fmid,
            os / omid,
            host("seed-mv") / host("midpoint"),
            fmv / fmid,
            omv / omid,
            host("mv") / host("midpoint"),
        ),
        "Roughly (within 2-3x) for SeedMv; Mv is about 3x cheaper than IMR".into(),
    ]);
    let (e_mv_half, e_mv_one) = (err_at(m, "mv", 0.5), err_at(m, "mv", 1.0));
    rows.push([
        "'for larger step sizes it appears to have larger errors'".into(),
        format!(
            "error in m at t = 10, h = 1/2: Mv {:.2e}, Splitting {:.2e}, Midpoint {:.2e}, RK4 \
             {:.2e}; h = 1: Mv {:.2e}, Splitting {:.2e}, Midpoint {:.2e}, RK4 {:.2e}; at \
             h = 1/64: Mv {:.1e}, Splitting {:.1e}, Midpoint {:.1e}",
            e_mv_half,
            err_at(m, "splitting", 0.5),
            err_at(m, "midpoint", 0.5),
            err_at(m, "rk4", 0.5),
            e_mv_one,
            err_at(m, "splitting", 1.0),
            err_at(m, "midpoint", 1.0),
            err_at(m, "rk4", 1.0),
            err_at(m, "mv", 1.0 / 64.0),
            err_at(m, "splitting", 1.0 / 64.0),
            err_at(m, "midpoint", 1.0 / 64.0),
        ),
        "Yes, and not only for large steps: DMV's error constant (phase error only) is ~2x the \
         splitting's and ~100x the midpoint rule's at every h; preprocessing (PreMv) removes it"
            .into(),
    ]);
    let order = |x: &str| {
        m.err10
            .iter()
            .find(|c| c.0 == x)
            .and_then(|c| slope(&c.1, 2f64.powi(-7), 2f64.powi(-3)))
            .unwrap_or(f64::NAN)
    };
    rows.push([
        "'second order'".into(),
        format!(
            "slope of the error at t = 10 over h = 2^-7..2^-3: Mv {:.2}, SeedMv {:.2} (PreMv4 \
             {:.2}, PreMv6 {:.2}; Splitting {:.2}, Midpoint {:.2}, RK4 {:.2})",
            order("mv"),
            order("seed-mv"),
            order("pre-mv4"),
            order("pre-mv6"),
            order("splitting"),
            order("midpoint"),
            order("rk4"),
        ),
        "Yes".into(),
    ]);
    let drift = |x: &str| {
        m.drift
            .iter()
            .find(|d| d.0 == x)
            .map(|d| (d.1, d.2))
            .unwrap_or((f64::NAN, f64::NAN))
    };
    let body = Body::<f64>::from_mass_matrix(TALK_J).expect("valid body");
    let mut a = crate::methods::make("mv", body, 0.5).expect("mv");
    let r = propagate(
        "mv",
        a.as_mut(),
        &body,
        State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]),
        200,
        true,
    );
    rows.push([
        "'preserves momentum and energy exactly'".into(),
        format!(
            "max relative drift over [0, 100] at h = 1/2: Mv E {:.1e}, |m|^2 {:.1e}, R(q)m {:.1e}; \
             SeedMv E {:.1e}, |m|^2 {:.1e}; Splitting E {:.1e}; Midpoint E {:.1e}; RK4 E {:.1e}",
            drift("mv").0,
            drift("mv").1,
            r.spatial_momentum_drift.unwrap_or(f64::NAN),
            drift("seed-mv").0,
            drift("seed-mv").1,
            drift("splitting").0,
            drift("midpoint").0,
            drift("rk4").0,
        ),
        "Yes, to round-off (1e-16 to 1e-14), as the midpoint rule; the splitting keeps |m|^2 but \
         not E, RK4 neither"
            .into(),
    ]);
    rows
}

/// The headline: at each error level, the best PreMv's counted cost against each baseline's
/// on the talk's case (T = 10, with attitude).
pub fn headline(m: &Measured) -> Vec<String> {
    let get = |x: &str| -> &[Point] {
        m.work
            .iter()
            .find(|w| w.0 == x)
            .map(|w| w.1.as_slice())
            .unwrap_or(&[])
    };
    let mut out = Vec::new();
    for level in [1e-4, 1e-6, 1e-10] {
        let Some((best, name)) = PRE
            .iter()
            .filter_map(|&p| cost_at(get(p), level).map(|c| (c, p)))
            .min()
        else {
            continue;
        };
        let parts: Vec<String> = BASELINES
            .iter()
            .map(|&b| match cost_at(get(b), level) {
                Some(c) => format!("{b} {:.1}x", c as f64 / best as f64),
                None => format!("{b} never (within 20000 steps)"),
            })
            .collect();
        out.push(format!(
            "error {level:.0e}: {name} {best} ops; baselines cost {}",
            parts.join(", ")
        ));
    }
    out
}

/// Prints the claims table (Markdown) and the headline.
pub fn print(m: &Measured) {
    println!("| the talk says | we measure | verdict |");
    println!("|---|---|---|");
    for row in table(m) {
        let [c, v, d] = row.map(|x| x.replace('|', "\\|"));
        println!("| {c} | {v} | {d} |");
    }
    println!();
    println!(
        "Headline (talk's case, T = 10, with attitude, counted operations to reach the error):"
    );
    for l in headline(m) {
        println!("  {l}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counted_ratios_support_the_verdicts() {
        // the table's verdicts, from counted flops (deterministic): the talk's algorithm costs
        // more than 10x the splitting in flops, Mv less than the implicit midpoint rule, and Mv
        // stays within issue 3's budget
        assert!(flops("seed-mv") / flops("splitting") > 10.0);
        assert!(flops("mv") < flops("midpoint"));
        assert!(flops("mv") <= 150.0);
    }

    #[test]
    fn observed_order_of_dmv_is_two() {
        let s = crate::refs::scene("talk").unwrap();
        let pts: Vec<(f64, f64)> = (3..=6)
            .map(|k| {
                let h = 2f64.powi(-k);
                (
                    h,
                    crate::figures::talk::error_at("mv", &s, 10.0, h).unwrap(),
                )
            })
            .collect();
        let p = slope(&pts, 0.0, 1.0).unwrap();
        assert!((p - 2.0).abs() < 0.05, "{p}");
    }
}
