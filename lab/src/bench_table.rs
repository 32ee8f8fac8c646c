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
