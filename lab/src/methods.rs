//! Every method of the crate (and the lab's general solver) behind one name, in f32 or f64.

use rigid3::{
    Body, Exact, Integrator, Midpoint, Mv, PreMv, Real, RetimedMv, Rk4, SeedMv, Solver, Splitting,
    Splitting2, State, StepError,
};

use crate::general::GeneralDmv;
use crate::hv_dmv::HvDmv;

/// The method names the CLI accepts, in the order tables list them.
pub const METHODS: &[&str] = &[
    "mv",
    "pre-mv4",
    "pre-mv6",
    "pre-mv8",
    "pre-mv10",
    "retimed-mv",
    "retimed-pre-mv10",
    "seed-mv",
    "hv-dmv",
    "splitting",
    "splitting2",
    "midpoint",
    "midpoint-fp",
    "rk4",
    "exact",
    "general",
];

/// One-line description of a method, for tables and `--help`.
pub fn describe(name: &str) -> &'static str {
    match name {
        "mv" => "closed-form explicit DMV (one 3x3 solve, no sqrt/trig), order 2",
        "pre-mv4" => "preprocessed DMV (Hairer-Vilmart modified inertia), order 4",
        "pre-mv6" => "preprocessed DMV, order 6",
        "pre-mv8" => "preprocessed DMV, order 8",
        "pre-mv10" => "preprocessed DMV, order 10",
        "retimed-mv" => "DMV retimed from the exact solution: m exact, q order 2",
        "retimed-pre-mv10" => "order-10 preprocessed DMV, retimed: m exact, q order 10",
        "seed-mv" => "talk's explicit DMV (cubic + eigenvectors), order 2",
        "hv-dmv" => "Hairer-Vilmart DMV: quaternion stage by fixed-point sweeps, order 2",
        "splitting" => "McLachlan's splitting, 3 axis rotations (5 a step), order 2",
        "splitting2" => "McLachlan's splitting with the Casimir split off, 2 rotations, order 2",
        "midpoint" => "implicit midpoint rule, Newton, order 2",
        "midpoint-fp" => "implicit midpoint rule, fixed-point iteration, order 2",
        "rk4" => "classical Runge-Kutta, order 4",
        "exact" => "exact solution (Jacobi elliptic functions, Carlson R_F/R_J), stepped by h",
        "general" => "DMV by the general-N Cardoso–Leite solver (lab oracle, f64 only)",
        _ => "unknown",
    }
}

/// A boxed integrator for `name`, or `None` for an unknown name (or `general` in f32).
pub fn make<T: Real + 'static>(name: &str, body: Body<T>, h: T) -> Option<Box<dyn Integrator<T>>> {
    match name {
        "mv" => Some(Box::new(Mv::new(body, h))),
        "pre-mv4" => Some(Box::new(PreMv::new(body, h, 4))),
        "pre-mv6" => Some(Box::new(PreMv::new(body, h, 6))),
        "pre-mv8" => Some(Box::new(PreMv::new(body, h, 8))),
        "pre-mv10" => Some(Box::new(PreMv::new(body, h, 10))),
        "retimed-mv" => Some(Box::new(RetimedMv::new(body, h, 2))),
        "retimed-pre-mv10" => Some(Box::new(RetimedMv::new(body, h, 10))),
        "seed-mv" => Some(Box::new(SeedMv::new(body, h))),
        "hv-dmv" => Some(Box::new(HvDmv::new(body, h))),
        "splitting" => Some(Box::new(Splitting::new(body, h))),
        "splitting2" => Some(Box::new(Splitting2::new(body, h))),
        "midpoint" => Some(Box::new(Midpoint::new(body, h))),
        "midpoint-fp" => Some(Box::new(Midpoint::with_solver(body, h, Solver::FixedPoint))),
        "rk4" => Some(Box::new(Rk4::new(body, h))),
        "exact" => Some(Box::new(Exact::new(body, h))),
        "general" => {
            // the oracle is f64-only; wrap through f64
            Some(Box::new(Widened(
                GeneralDmv::new(body.mass_matrix().map(Real::to_f64), h.to_f64()),
                body,
            )))
        }
        _ => None,
    }
}

/// Runs an f64 integrator on any `Real` state by widening and narrowing.
struct Widened<T>(GeneralDmv, Body<T>);

impl<T: Real> Integrator<T> for Widened<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        let mut w = m.map(Real::to_f64);
        self.0.step(&mut w)?;
        *m = w.map(T::from_f64);
        Ok(())
    }
    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        let mut w = State::new(s.m.map(Real::to_f64), s.q.map(Real::to_f64));
        self.0.step_state(&mut w)?;
        s.m = w.m.map(T::from_f64);
        s.q = w.q.map(T::from_f64);
        Ok(())
    }
    fn step_size(&self) -> T {
        T::from_f64(self.0.step_size())
    }
    fn set_step_size(&mut self, h: T) {
        self.0.set_step_size(h.to_f64());
    }
    fn body(&self) -> &Body<T> {
        &self.1
    }
}
