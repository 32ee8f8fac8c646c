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
pub const RIGID3_FORCED: [&str; 17] = [
    "mv",
    "pre-mv4",
    "pre-mv6",
    "pre-mv10",
    "forced4",
    "forced6",
    "forced4-pre4",
    "forced6-pre6",
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
pub const FORCED_CHART: [&str; 13] = [
    "mv",
    "pre-mv4",
    "pre-mv10",
    "forced4",
    "forced6",
    "forced4-pre4",
    "forced6-pre6",
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
         error level (max of |dm|/|m| and |dq|); sqrt and sin/cos counted as one op each",
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
    println!(" {:>10} {:>10}", "rk4/best", "split/best");
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
        println!(" {:>10} {:>10}", ratio(0), ratio(1));
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
