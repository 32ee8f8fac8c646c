//! The host-speed table: reads criterion's estimates (`cargo bench --bench steps`) and prints
//! time per step with ratios to the splitting baseline of the same run.

use std::path::Path;

/// Median time per step in ns of `group/name`, from criterion's `new/estimates.json`.
pub fn median_ns(criterion_dir: &Path, group: &str, name: &str) -> Option<f64> {
    let p = criterion_dir
        .join(group)
        .join(name)
        .join("new/estimates.json");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(p).ok()?).ok()?;
    v["median"]["point_estimate"].as_f64()
}

/// Prints the table for every group of the `steps` bench found under `criterion_dir`.
pub fn print(criterion_dir: &Path) -> bool {
    let groups = ["momentum-f64", "momentum-f32", "state-f64", "state-f32"];
    // the splitting first: it is the baseline of the ratios
    let names = std::iter::once("splitting").chain(
        crate::methods::METHODS
            .iter()
            .copied()
            .filter(|&n| n != "splitting"),
    );
    let mut any = false;
    println!(
        "Host time per step (criterion medians, one run; ratios to the splitting of the same run)"
    );
    println!(
        "{:<14} {:<10} {:>10} {:>12}",
        "group", "method", "ns/step", "x splitting"
    );
    for g in groups {
        let base = median_ns(criterion_dir, g, "splitting")
            .or_else(|| median_ns(criterion_dir, g, "strang5"));
        for n in names.clone() {
            if let Some(t) = median_ns(criterion_dir, g, n) {
                any = true;
                let ratio = base
                    .map(|b| format!("{:.2}", t / b))
                    .unwrap_or_else(|| "-".into());
                println!("{g:<14} {n:<17} {t:>10.1} {ratio:>12}");
            }
        }
    }
    any
}

/// The step sizes of the `loop` bench (`lab/benches/loop.rs`), one criterion group each.
pub const LOOP_STEPS: [&str; 3] = ["0.001", "0.01", "0.1"];
/// The methods of the `loop` bench.
pub const LOOP_METHODS: [&str; 3] = ["mv", "hv-dmv", "splitting"];
/// Steps per timed batch in the `loop` bench.
pub const LOOP_BATCH: usize = 1000;

/// Prints the table of the `loop` bench (`cargo bench -p rigid3-lab --bench loop`): ns per
/// step of each method per step size, and the ratios mv/hv-dmv and mv/splitting.
pub fn print_loop(criterion_dir: &Path) -> bool {
    let mut any = false;
    println!(
        "Host time per step with attitude, talk's case, f64, batches of {LOOP_BATCH} consecutive \
         steps (criterion medians, one run)"
    );
    println!(
        "{:<8} {:>10} {:>10} {:>10} {:>12} {:>14} {:>14}",
        "h", "mv", "hv-dmv", "splitting", "mv/hv-dmv", "mv/splitting", "hv sweeps/step"
    );
    for h in LOOP_STEPS {
        let group = format!("loop-h{h}");
        let ns = LOOP_METHODS
            .map(|m| median_ns(criterion_dir, &group, m).map(|t| t / LOOP_BATCH as f64));
        if ns.iter().all(Option::is_none) {
            continue;
        }
        any = true;
        let cell = |x: Option<f64>| x.map_or_else(|| "-".to_string(), |t| format!("{t:.1}"));
        let ratio = |a: Option<f64>, b: Option<f64>| match (a, b) {
            (Some(a), Some(b)) => format!("{:.3}", a / b),
            _ => "-".to_string(),
        };
        println!(
            "{:<8} {:>10} {:>10} {:>10} {:>12} {:>14} {:>14}",
            h,
            cell(ns[0]),
            cell(ns[1]),
            cell(ns[2]),
            ratio(ns[0], ns[1]),
            ratio(ns[0], ns[2]),
            hv_sweeps(h.parse().unwrap_or(f64::NAN), 10 * LOOP_BATCH)
                .map_or_else(|| "-".to_string(), |x| format!("{x:.2}"))
        );
    }
    if any {
        println!(
            "hv sweeps/step: Gauss-Seidel sweeps after the predictor, mean over the first {} steps",
            10 * LOOP_BATCH
        );
    }
    any
}

/// Mean sweeps per step of `HvDmv` (after its predictor) over the first `n` steps with
/// attitude on the talk's case at step `h`, or `None` if a step fails.
pub fn hv_sweeps(h: f64, n: usize) -> Option<f64> {
    use rigid3::Integrator;
    let body = rigid3::Body::<f64>::from_mass_matrix(crate::scenes::TALK_J).ok()?;
    let mut hv = crate::hv_dmv::HvDmv::new(body, h);
    let mut s = rigid3::State::new(crate::scenes::TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    for _ in 0..n {
        hv.step_state(&mut s).ok()?;
    }
    Some(hv.mean_sweeps())
}
