//! Work-precision of the forced methods: for each error level, the fewest counted operations
//! (and the host time) with which each forced method reaches it at `T`, with attitude,
//! against the mpmath references of the forced scenes.

use crate::count::{count, Counted};
use crate::forced_methods::{make_forced, ForceSpec};
use crate::work_precision::{cost_at, step_counts, Point};
use rigid3::{Body, State};
use std::hint::black_box;
use std::time::Instant;

/// A forced scene with its reference state at `t_end`.
#[derive(Clone, Debug)]
pub struct ForcedScene {
    /// Name.
    pub name: String,
    /// Principal moments.
    pub inertia: [f64; 3],
    /// Initial momentum.
    pub m0: [f64; 3],
    /// Initial attitude.
    pub q0: [f64; 4],
    /// Torques and rotor.
    pub spec: ForceSpec,
    /// Reference time.
    pub t_end: f64,
    /// Reference momentum at `t_end`.
    pub m_ref: [f64; 3],
    /// Reference attitude at `t_end`.
    pub q_ref: [f64; 4],
}

/// The forced scenes of the work-precision chart (figure 9) and tables.
pub const CHARTED_FORCED_SCENES: [&str; 3] = ["heavy_top", "satellite", "gyrostat"];

impl ForcedScene {
    /// The reference scene `name` of `lab/refs/forced_refs.json` with its reference state at
    /// `t_end` (one of the stored times: 1, 2, 5, 10); `None` for an unknown name or time.
    pub fn from_reference(name: &str, t_end: f64) -> Option<Self> {
        let r = crate::forced_refs::scene(name)?;
        let i = r.at(t_end)?;
        Some(Self {
            name: r.name.clone(),
            inertia: r.inertia,
            m0: r.m0,
            q0: r.q0,
            spec: r.spec,
            t_end,
            m_ref: r.m[i],
            q_ref: r.q[i],
        })
    }
}

/// The charted forced scenes ([`CHARTED_FORCED_SCENES`]) at `T = 10`.
pub fn charted_scenes() -> Vec<ForcedScene> {
    CHARTED_FORCED_SCENES
        .iter()
        .filter_map(|n| ForcedScene::from_reference(n, 10.0))
        .collect()
}

/// The forced methods of rigid3 competing for "best".
pub const RIGID3_FORCED: [&str; 19] = [
    "mv",
    "pre-mv4",
    "pre-mv6",
    "pre-mv10",
    "forced4",
    "forced6",
    "forced4-pre4",
    "forced6-pre6",
    "forced4-pre10",
    "forced6-pre10",
    "nystrom4-pre6",
    "nystrom6-pre6",
    "nystrom4-pre10",
    "nystrom6-pre10",
    "nystrom4-exact",
    "nystrom6-exact",
    "fg4-pre6",
    "fg4-pre10",
    "fg4-exact",
];

/// The baselines of the acceptance: RK4 on the full equations and the Strang splitting with
/// McLachlan's step; the midpoint kick-drift-kick is shown too.
pub const FORCED_BASELINES: [&str; 3] = ["rk4", "splitting", "midpoint"];

/// Every forced method of the charts.
pub const FORCED_CHART: [&str; 15] = [
    "mv",
    "pre-mv4",
    "pre-mv10",
    "forced4",
    "forced6",
    "forced4-pre4",
    "forced6-pre6",
    "forced4-pre10",
    "forced6-pre10",
    "nystrom4-pre10",
    "nystrom6-pre10",
    "fg4-pre6",
    "rk4",
    "splitting",
    "midpoint",
];

/// Error levels of the acceptance table.
pub const FORCED_LEVELS: [f64; 7] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];

fn qdist(a: [f64; 4], b: [f64; 4]) -> f64 {
    let d1: f64 = (0..4).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
    let d2: f64 = (0..4).map(|k| (a[k] + b[k]).powi(2)).sum::<f64>().sqrt();
    d1.min(d2)
}

/// The error of a final state against the scene's reference: `max(|dm|/|m|, |dq|)`.
pub fn error(scene: &ForcedScene, m: [f64; 3], q: [f64; 4]) -> f64 {
    let r = scene.m_ref;
    let dm = ((m[0] - r[0]).powi(2) + (m[1] - r[1]).powi(2) + (m[2] - r[2]).powi(2)).sqrt();
    let norm = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
    (dm / norm).max(qdist(q, scene.q_ref))
}

/// The counted operations at which `points` (a sweep, by increasing step count) reach
/// `level`, interpolated linearly in `log ops` against `log error` between the two step
/// counts that bracket it: the sweep's counts are 1.33x apart, so [`cost_at`] (the cheapest
/// count that reaches the level) sits up to a third above the crossing, by an amount that
/// differs from method to method. `None` when the sweep never reaches the level; the first
/// count's cost when already its error is below the level (no extrapolation).
pub fn cost_interpolated(points: &[Point], level: f64) -> Option<f64> {
    let first = points.first()?;
    if first.error <= level {
        return Some(first.ops as f64);
    }
    points.windows(2).find_map(|w| {
        let (a, b) = (&w[0], &w[1]);
        if a.error > level && b.error <= level && b.error > 0.0 {
            let f = (a.error / level).ln() / (a.error / b.error).ln();
            Some(((a.ops as f64).ln() + f * ((b.ops as f64) / (a.ops as f64)).ln()).exp())
        } else {
            None
        }
    })
}

/// Runs `method` on `scene` with `n` steps, counting operations.
pub fn run(method: &str, scene: &ForcedScene, n: usize) -> Option<Point> {
    let body = Body::<Counted>::from_inertia(scene.inertia.map(Counted)).ok()?;
    let h = scene.t_end / n as f64;
    let mut a = make_forced(method, body, Counted(h), &scene.spec)?;
    let mut s = State::new(scene.m0.map(Counted), scene.q0.map(Counted));
    let (ok, c) = count(|| {
        for _ in 0..n {
            if a.step_state(&mut s).is_err() {
                return false;
            }
        }
        true
    });
    if !ok {
        return None;
    }
    let e = error(scene, s.m.map(|x| x.0), s.q.map(|x| x.0));
    e.is_finite().then_some(Point {
        n,
        error: e,
        ops: c.flops() + c.sqrt + c.trans,
    })
}

/// The sweep of one method over the step counts of the work-precision tables.
pub fn sweep(method: &str, scene: &ForcedScene) -> Vec<Point> {
    step_counts()
        .into_iter()
        .filter_map(|n| run(method, scene, n))
        .collect()
}

/// Host ns per step of `method` on `scene` (f64, with attitude, `h = t_end / 200`), the best
/// of `rounds` runs of 20000 steps.
pub fn ns_per_step(method: &str, scene: &ForcedScene, rounds: usize) -> Option<f64> {
    const N: usize = 20_000;
    let body = Body::<f64>::from_inertia(scene.inertia).ok()?;
    let mut best = f64::INFINITY;
    for _ in 0..rounds {
        let mut a = make_forced(method, body, scene.t_end / 200.0, &scene.spec)?;
        let mut s = State::new(scene.m0, scene.q0);
        a.step_state(&mut s).ok()?;
        let t = Instant::now();
        for _ in 0..N {
            a.step_state(black_box(&mut s)).ok()?;
        }
        best = best.min(t.elapsed().as_nanos() as f64 / N as f64);
    }
    Some(best)
}

/// Prints the table of `scene` (counted ops to reach each level: the best rigid3 forced
/// method against each baseline) and returns whether the best rigid3 method needs fewer
/// operations than RK4 and than the splitting at every level.
pub fn print_table(scene: &ForcedScene) -> bool {
    println!(
        "Forced work-precision, scene '{}', T = {}, with attitude: counted ops to reach each \
         error level (max of |dm|/|m| and |dq|); sqrt and sin/cos counted as one op each; the \
         last three columns interpolate each sweep to the level (log ops against log error)",
        scene.name, scene.t_end
    );
    let mine: Vec<(&str, Vec<Point>)> = RIGID3_FORCED
        .iter()
        .map(|&m| (m, sweep(m, scene)))
        .collect();
    let base: Vec<(&str, Vec<Point>)> = FORCED_BASELINES
        .iter()
        .map(|&m| (m, sweep(m, scene)))
        .collect();
    print!("{:>8} {:>22}", "error", "best rigid3");
    for (b, _) in &base {
        print!(" {b:>11}");
    }
    println!(
        " {:>10} {:>10} {:>11} {:>8} {:>9}",
        "rk4/best", "split/best", "best interp", "rk4 int.", "rk4/best"
    );
    let mut wins = true;
    for level in FORCED_LEVELS {
        let best = mine
            .iter()
            .filter_map(|(m, p)| cost_at(p, level).map(|c| (c, *m)))
            .min();
        let costs: Vec<Option<u64>> = base.iter().map(|(_, p)| cost_at(p, level)).collect();
        let cell = |c: Option<u64>| c.map_or("-".to_string(), |c| c.to_string());
        match best {
            Some((c, m)) => print!("{level:>8.0e} {:>22}", format!("{c} ({m})")),
            None => print!("{level:>8.0e} {:>22}", "-"),
        }
        for c in &costs {
            print!(" {:>11}", cell(*c));
        }
        let ratio = |k: usize| match (best, costs[k]) {
            (Some((b, _)), Some(c)) => format!("{:.1}x", c as f64 / b as f64),
            (Some(_), None) => "inf".into(),
            _ => "-".into(),
        };
        print!(" {:>10} {:>10}", ratio(0), ratio(1));
        // the same comparison with each side's cost interpolated to the level itself
        let best_i = mine
            .iter()
            .filter_map(|(_, p)| cost_interpolated(p, level))
            .min_by(f64::total_cmp);
        match (best_i, cost_interpolated(&base[0].1, level)) {
            (Some(b), Some(r)) => println!(" {:>11.0} {:>8.0} {:>8.2}x", b, r, r / b),
            _ => println!(),
        }
        // a baseline that never reaches the level loses there
        let beats = |k: usize| match (best, costs[k]) {
            (Some((b, _)), Some(c)) => b < c,
            (Some(_), None) => true,
            _ => false,
        };
        wins &= beats(0) && beats(1);
    }
    wins
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a sweep that follows a power law exactly (`error = C n^-p`, `ops = k n`) the
    /// interpolated cost is the closed form `k (C / level)^(1/p)`, whichever counts bracket the
    /// level; below the first count it is that count's cost, past the last none.
    #[test]
    fn interpolated_cost_is_exact_on_a_power_law() {
        let (c, p, k) = (3.0, 4.0, 452.0);
        let points: Vec<Point> = step_counts()
            .into_iter()
            .map(|n| Point {
                n,
                error: c * (n as f64).powf(-p),
                ops: (k * n as f64) as u64,
            })
            .collect();
        for level in [1e-4, 3e-7, 1e-10] {
            let exact = k * (c / level).powf(1.0 / p);
            let got = cost_interpolated(&points, level).unwrap();
            assert!(
                (got / exact - 1.0).abs() < 1e-12,
                "{level}: {got} vs {exact}"
            );
            // the grid's cost is the next count up: never below, at most 1.34x above
            let grid = cost_at(&points, level).unwrap() as f64;
            assert!(grid >= got && grid <= 1.34 * got, "{grid} vs {got}");
        }
        assert_eq!(cost_interpolated(&points, 10.0), Some(points[0].ops as f64));
        assert_eq!(cost_interpolated(&points, 1e-30), None);
        assert_eq!(cost_interpolated(&[], 1e-3), None);
    }

    #[test]
    fn charted_scenes_come_from_the_references_and_mv_converges_to_them() {
        let scenes = charted_scenes();
        let names: Vec<&str> = scenes.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, CHARTED_FORCED_SCENES);
        assert!(ForcedScene::from_reference("heavy_top", 3.0).is_none());
        assert!(ForcedScene::from_reference("nope", 10.0).is_none());
        for s in &scenes {
            assert_eq!(s.t_end, 10.0);
            // order 2: 4x less error for twice the steps (counted run, as the tables do it)
            let a = run("mv", s, 200).unwrap();
            let b = run("mv", s, 400).unwrap();
            let ratio = a.error / b.error;
            assert!((3.6..4.4).contains(&ratio), "{}: {a:?} {b:?}", s.name);
            assert!(b.ops > a.ops);
        }
    }
}
