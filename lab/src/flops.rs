//! Counted flops per step of every method (with the counting `Real`): the cost axis of the
//! work-precision tables, independent of the machine.

use crate::count::{count, Counted, Counts};
use crate::methods::{make, METHODS};
use crate::scenes::{TALK_J, TALK_M0};
use rigid3::{Body, State};

/// Counts of one method: the first step (set-up included) and the average steady step.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct StepCost {
    /// Method name.
    pub method: &'static str,
    /// The first momentum step, set-up included.
    pub first: Counts,
    /// Average momentum step after the first, over `STEPS` steps (rounded up).
    pub momentum: Counts,
    /// Average step with attitude.
    pub state: Counts,
    /// The first refusal of any counted step (a step past the method's limit, say): then the
    /// counts are those of refused calls, not of steps, and the table says so.
    #[serde(skip)]
    pub refused: Option<rigid3::StepError>,
}

/// Steps averaged.
pub const STEPS: u64 = 100;

fn per_step(c: Counts, n: u64) -> Counts {
    let d = |x: u64| x.div_ceil(n);
    Counts {
        add: d(c.add),
        sub: d(c.sub),
        mul: d(c.mul),
        div: d(c.div),
        sqrt: d(c.sqrt),
        trans: d(c.trans),
    }
}

/// The cost of `method` on the talk's case at step `h`, or `None` if it is not countable
/// (the lab's f64-only oracle).
pub fn step_cost(method: &'static str, h: f64) -> Option<StepCost> {
    if method == "general" {
        return None;
    }
    let body = Body::<Counted>::from_mass_matrix(TALK_J.map(Counted)).ok()?;
    let mut a = make(method, body, Counted(h))?;
    let mut m = TALK_M0.map(Counted);
    let mut refused = None;
    let mut note = |r: Result<(), rigid3::StepError>| {
        if let Err(e) = r {
            refused = refused.or(Some(e));
        }
    };
    let (r, first) = count(|| a.step(&mut m));
    note(r);
    // the second step takes what the first left lazy (Mv's Casimir factor: one division)
    note(a.step(&mut m));
    let (r, many) = count(|| {
        for _ in 0..STEPS {
            a.step(&mut m)?;
        }
        Ok(())
    });
    note(r);
    let mut b = make(method, body, Counted(h))?;
    let mut s = State::new(TALK_M0.map(Counted), [1.0, 0.0, 0.0, 0.0].map(Counted));
    note(b.step_state(&mut s));
    note(b.step_state(&mut s));
    let (r, states) = count(|| {
        for _ in 0..STEPS {
            b.step_state(&mut s)?;
        }
        Ok(())
    });
    note(r);
    Some(StepCost {
        method,
        first,
        momentum: per_step(many, STEPS),
        state: per_step(states, STEPS),
        refused,
    })
}

/// The methods whose steps the real loop's regimes are counted for ([`changed_cost`]).
pub const CHANGED: [&str; 3] = ["mv", "pre-mv4", "pre-mv10"];

/// Counted operations per step with attitude when the caller changes `h` (a jittering clock,
/// +-5 %) or `m` (a filter's correction, relative 1e-4, sign alternating) before every step:
/// `[jitter, corrected]`, averaged over [`STEPS`] steps; `None` if a step is refused. The
/// changes themselves are f64 arithmetic on the raw values, which the count does not see
/// (`rigid3-lab loop-cost` times the same regimes on the host).
pub fn changed_cost(method: &'static str, h: f64) -> Option<[Counts; 2]> {
    let body = Body::<Counted>::from_mass_matrix(TALK_J.map(Counted)).ok()?;
    let mut out = [Counts::default(); 2];
    for (regime, slot) in out.iter_mut().enumerate() {
        let mut a = make(method, body, Counted(h))?;
        let mut s = State::new(TALK_M0.map(Counted), [1.0, 0.0, 0.0, 0.0].map(Counted));
        a.step_state(&mut s).ok()?;
        a.step_state(&mut s).ok()?;
        // the changes are f64 arithmetic on the raw values: not counted
        let (r, c) = count(|| {
            for n in 0..STEPS {
                if regime == 0 {
                    // a fixed sequence in [-1, 1]
                    let u = ((n * 7919) % 13) as f64 / 6.0 - 1.0;
                    a.set_step_size(Counted(h * (1.0 + 0.05 * u)));
                } else {
                    let f = if n % 2 == 0 { 1.0 + 1e-4 } else { 1.0 - 1e-4 };
                    s.m = s.m.map(|x| Counted(x.0 * f));
                }
                a.step_state(&mut s)?;
            }
            Ok::<(), rigid3::StepError>(())
        });
        r.ok()?;
        *slot = per_step(c, STEPS);
    }
    Some(out)
}

/// Costs of every countable method at step `h`.
pub fn all(h: f64) -> Vec<StepCost> {
    METHODS.iter().filter_map(|m| step_cost(m, h)).collect()
}

/// Prints the flop table.
pub fn print_table(h: f64) {
    println!(
        "Counted operations per step (talk's case, h = {h}; counting Real, {STEPS}-step average)"
    );
    println!(
        "{:<17} {:>10} {:>6} {:>6} {:>6} | {:>10} {:>6} {:>6} | {:>12}",
        "method", "flops/step", "div", "sqrt", "trig", "with q", "sqrt", "trig", "first step"
    );
    for c in all(h) {
        if let Some(e) = c.refused {
            println!("{:<17} refused at this step size ({e})", c.method);
            continue;
        }
        println!(
            "{:<17} {:>10} {:>6} {:>6} {:>6} | {:>10} {:>6} {:>6} | {:>5} +{}s+{}t",
            c.method,
            c.momentum.flops(),
            c.momentum.div,
            c.momentum.sqrt,
            c.momentum.trans,
            c.state.flops(),
            c.state.sqrt,
            c.state.trans,
            c.first.flops(),
            c.first.sqrt,
            c.first.trans
        );
    }
    println!("After an outside change before every step, with q (the real loop's regimes):");
    println!("{:<17} {:>10} {:>10}", "method", "jitter", "corrected");
    for method in CHANGED {
        match changed_cost(method, h) {
            Some([jitter, corrected]) => println!(
                "{:<17} {:>10} {:>10}",
                method,
                jitter.flops(),
                corrected.flops()
            ),
            None => println!("{method:<17} refused at this step size"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mv_steady_step_has_no_sqrt_and_no_trig() {
        let c = step_cost("mv", 0.1).unwrap();
        assert_eq!((c.momentum.sqrt, c.momentum.trans), (0, 0), "{c:?}");
        // the exact solve at the first step is where the cubic's square roots go
        assert!(c.first.sqrt > 0);
    }
}
