//! `rigid3-lab loop-cost`: host time per step with attitude in the real loop, where the step
//! size, the momentum or the torque change every tick, against the fixed-step case.
//!
//! Scene: the README's spacecraft (`firmware/src/bin/attitude.rs`, [`crate::scenes::spacecraft`]) at
//! `h0 = 1/200`. Regimes, each applied before every step:
//! - `fixed`: nothing changes;
//! - `jitter`: `set_step_size(h)` with `h` uniform in `h0 (1 +- 0.05)`;
//! - `corrected`: `m_i *= 1 + 1e-4 r_i`, `r_i` uniform in `[-1, 1]` (a filter's correction);
//! - `torque`: `m += h0 tau` with the body torque `tau = 0.01 |m0| (cos t, sin t, 0.5)`, turned
//!   by `h0` a step (a rotation by precomputed `cos h0`, `sin h0`: no trigonometry in the loop).
//!
//! Random factors come from the lab's seeded generator ([`crate::rng::Rng`]) and are tabled
//! (4096 entries, cycled) before timing, so the timed loop does only what a user's loop would:
//! read a number and apply it. That work is part of the timed step; the loop with the same
//! perturbations and no integrator step is timed too and reported as `perturbation_ns`.
//! Timing: `std::time::Instant` over `steps` consecutive steps (the trajectory continues, the
//! state passes through `black_box`), after a warm-up of `steps / 10`, best of 3 repeats.

use crate::rng::Rng;
use crate::scenes::{spacecraft, SPACECRAFT_H};
use rigid3::{Body, Integrator, Mv, PreMv, Real, RetimedMv, Splitting, State, StepError};
use serde::Serialize;
use std::hint::black_box;
use std::time::Instant;

/// The regimes, in table order.
pub const REGIMES: [&str; 4] = ["fixed", "jitter", "corrected", "torque"];
/// The methods, in table order (the 5-rotation splitting last, as the yardstick).
pub const METHODS: [&str; 5] = ["mv", "pre-mv4", "pre-mv10", "retimed-mv", "splitting"];
/// Default steps per timed batch.
pub const DEFAULT_STEPS: usize = 300_000;

const TABLE: usize = 4096;

/// One measurement.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Method name.
    pub method: &'static str,
    /// "f64" or "f32".
    pub precision: &'static str,
    /// One of [`REGIMES`].
    pub regime: &'static str,
    /// Best of 3 over `steps` steps, ns per step (the perturbation included).
    pub ns_per_step: f64,
    /// `ns_per_step` over the same method's and precision's `fixed` row.
    pub ratio_to_fixed: f64,
}

/// The cost of the perturbation alone (the same loop without the integrator step).
#[derive(Clone, Debug, Serialize)]
pub struct Overhead {
    /// "f64" or "f32".
    pub precision: &'static str,
    /// One of [`REGIMES`].
    pub regime: &'static str,
    /// ns per step.
    pub ns_per_step: f64,
}

/// The whole measurement.
#[derive(Clone, Debug, Serialize)]
pub struct LoopCost {
    /// Steps per timed batch.
    pub steps: usize,
    /// Step size `h0`.
    pub h: f64,
    /// Principal moments of the scene.
    pub inertia: [f64; 3],
    /// Initial momentum.
    pub m0: [f64; 3],
    /// Initial attitude.
    pub q0: [f64; 4],
    /// Every method, precision and regime.
    pub rows: Vec<Row>,
    /// The perturbations' own cost, per precision and regime.
    pub perturbation_ns: Vec<Overhead>,
}

/// The perturbation tables of one precision.
struct Tables<T> {
    h: Vec<T>,
    factors: Vec<[T; 3]>,
    h0: T,
    /// `0.01 |m0|`.
    tau_size: T,
    /// `cos h0`, `sin h0`.
    turn: (T, T),
}

impl<T: Real> Tables<T> {
    fn new(h0: f64, m0: [f64; 3]) -> Self {
        let mut rng = Rng(0x100C);
        let h = (0..TABLE)
            .map(|_| T::from_f64(h0 * (1.0 + 0.05 * rng.range(-1.0, 1.0))))
            .collect();
        let factors = (0..TABLE)
            .map(|_| [0; 3].map(|_| T::from_f64(1.0 + 1e-4 * rng.range(-1.0, 1.0))))
            .collect();
        let norm = (m0[0] * m0[0] + m0[1] * m0[1] + m0[2] * m0[2]).sqrt();
        Self {
            h,
            factors,
            h0: T::from_f64(h0),
            tau_size: T::from_f64(0.01 * norm),
            turn: (T::from_f64(h0.cos()), T::from_f64(h0.sin())),
        }
    }
}

/// A step that does nothing: times the perturbations alone.
struct Null<T>(Body<T>, T);

impl<T: Real> Integrator<T> for Null<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        black_box(m);
        Ok(())
    }
    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        black_box(s);
        Ok(())
    }
    fn step_size(&self) -> T {
        self.1
    }
    fn set_step_size(&mut self, h: T) {
        self.1 = black_box(h);
    }
    fn body(&self) -> &Body<T> {
        &self.0
    }
}

/// `n` steps of `it` from `s` in `regime`, continuing the trajectory (and the torque's phase
/// `tau_xy`); returns the elapsed seconds.
fn run<T: Real, I: Integrator<T>>(
    it: &mut I,
    s: &mut State<T>,
    tau_xy: &mut (T, T),
    regime: &str,
    tables: &Tables<T>,
    n: usize,
) -> Result<f64, StepError> {
    let t0 = Instant::now();
    match regime {
        "fixed" => {
            for _ in 0..n {
                it.step_state(black_box(&mut *s))?;
            }
        }
        "jitter" => {
            for k in 0..n {
                it.set_step_size(tables.h[k % TABLE]);
                it.step_state(black_box(&mut *s))?;
            }
        }
        "corrected" => {
            for k in 0..n {
                let f = tables.factors[k % TABLE];
                s.m = [s.m[0] * f[0], s.m[1] * f[1], s.m[2] * f[2]];
                it.step_state(black_box(&mut *s))?;
            }
        }
        _ => {
            let (c, sn) = tables.turn;
            let k = tables.h0 * tables.tau_size;
            let half = T::from_f64(0.5);
            let (mut x, mut y) = *tau_xy;
            for _ in 0..n {
                s.m = [s.m[0] + k * x, s.m[1] + k * y, s.m[2] + k * half];
                (x, y) = (c * x - sn * y, sn * x + c * y);
                it.step_state(black_box(&mut *s))?;
            }
            *tau_xy = (x, y);
        }
    }
    Ok(t0.elapsed().as_secs_f64())
}

/// ns per step: warm-up, then the best of 3 batches of `steps`.
fn time<T: Real, I: Integrator<T>>(
    mut it: I,
    s0: State<T>,
    regime: &str,
    tables: &Tables<T>,
    steps: usize,
) -> Result<f64, StepError> {
    let mut s = s0;
    let mut tau = (T::ONE, T::ZERO);
    run(
        &mut it,
        &mut s,
        &mut tau,
        regime,
        tables,
        (steps / 10).max(1000),
    )?;
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        best = best.min(run(&mut it, &mut s, &mut tau, regime, tables, steps)?);
    }
    Ok(best * 1e9 / steps as f64)
}

/// The scene: principal moments, initial momentum and attitude.
type Scene = ([f64; 3], [f64; 3], [f64; 4]);

fn measure_precision<T: Real>(
    precision: &'static str,
    steps: usize,
    (inertia, m0, q0): Scene,
    rows: &mut Vec<Row>,
    overhead: &mut Vec<Overhead>,
) -> Result<(), String> {
    let body = Body::<T>::from_inertia(inertia.map(T::from_f64)).map_err(|e| e.to_string())?;
    let h = T::from_f64(SPACECRAFT_H);
    let s0 = State::new(m0.map(T::from_f64), q0.map(T::from_f64));
    let tables = Tables::<T>::new(SPACECRAFT_H, m0);
    for regime in REGIMES {
        let ns = time(Null(body, h), s0, regime, &tables, steps).map_err(|e| e.to_string())?;
        overhead.push(Overhead {
            precision,
            regime,
            ns_per_step: ns,
        });
    }
    for method in METHODS {
        let mut fixed = f64::NAN;
        for regime in REGIMES {
            let ns = match method {
                "mv" => time(Mv::new(body, h), s0, regime, &tables, steps),
                "pre-mv4" => time(
                    PreMv::new(body, h, 4).map_err(|e| e.to_string())?,
                    s0,
                    regime,
                    &tables,
                    steps,
                ),
                "pre-mv10" => time(
                    PreMv::new(body, h, 10).map_err(|e| e.to_string())?,
                    s0,
                    regime,
                    &tables,
                    steps,
                ),
                "retimed-mv" => time(
                    RetimedMv::new(body, h, 2).map_err(|e| e.to_string())?,
                    s0,
                    regime,
                    &tables,
                    steps,
                ),
                _ => time(Splitting::new(body, h), s0, regime, &tables, steps),
            }
            .map_err(|e| format!("{method} {precision} {regime}: {e}"))?;
            if regime == "fixed" {
                fixed = ns;
            }
            rows.push(Row {
                method,
                precision,
                regime,
                ns_per_step: ns,
                ratio_to_fixed: if regime == "fixed" { 1.0 } else { ns / fixed },
            });
        }
    }
    Ok(())
}

/// Runs every method, precision and regime with `steps` steps per timed batch, from the
/// spacecraft's initial momentum or `m0`.
pub fn measure(steps: usize, m0: Option<[f64; 3]>) -> Result<LoopCost, String> {
    let steps = steps.max(1);
    let (inertia, default_m0, q0) = spacecraft();
    let m0 = m0.unwrap_or(default_m0);
    if !m0.iter().all(|x| x.is_finite()) {
        return Err("--m0 must be finite".into());
    }
    let mut rows = Vec::new();
    let mut overhead = Vec::new();
    let scene = (inertia, m0, q0);
    measure_precision::<f64>("f64", steps, scene, &mut rows, &mut overhead)?;
    measure_precision::<f32>("f32", steps, scene, &mut rows, &mut overhead)?;
    Ok(LoopCost {
        steps,
        h: SPACECRAFT_H,
        inertia,
        m0,
        q0,
        rows,
        perturbation_ns: overhead,
    })
}

/// Prints the table: ns per step and the ratio to the fixed case, one line per method and
/// precision.
pub fn print(r: &LoopCost) {
    println!(
        "Host ns per step with attitude (step_state), spacecraft I = ({:.4}, {:.4}, {:.4}), \
         h0 = {}; best of 3 x {} steps; (x) = ratio to fixed",
        r.inertia[0], r.inertia[1], r.inertia[2], r.h, r.steps
    );
    print!("{:<10} {:<5}", "method", "prec");
    for g in REGIMES {
        print!(" {g:>19}");
    }
    println!();
    for precision in ["f64", "f32"] {
        for method in METHODS {
            print!("{method:<10} {precision:<5}");
            for regime in REGIMES {
                match r
                    .rows
                    .iter()
                    .find(|x| x.method == method && x.precision == precision && x.regime == regime)
                {
                    Some(x) => print!(" {:>10.1} ({:>5.2})", x.ns_per_step, x.ratio_to_fixed),
                    None => print!(" {:>19}", "-"),
                }
            }
            println!();
        }
        print!("{:<10} {precision:<5}", "(perturb.)");
        for regime in REGIMES {
            match r
                .perturbation_ns
                .iter()
                .find(|x| x.precision == precision && x.regime == regime)
            {
                Some(x) => print!(" {:>10.1} {:>7}", x.ns_per_step, ""),
                None => print!(" {:>19}", "-"),
            }
        }
        println!();
    }
    println!(
        "(perturb.): the loop with the same perturbations and no step (included in the rows above)"
    );
}
