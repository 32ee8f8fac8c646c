//! Every method of the crate (and the lab's general solver) behind one name, in f32 or f64.

use rigid3::{Body, Integrator, Real, State, StepError};

use crate::general::GeneralDmv;
use crate::hv_dmv::HvDmv;

/// The method names the CLI accepts, in the order tables list them: the library's
/// ([`LIBRARY_METHODS`]) with the lab's Hairer–Vilmart DMV after the talk's (`seed-mv`) and
/// the lab's oracle (`general`) last.
pub const METHODS: &[&str] = &with_lab_methods();

const fn with_lab_methods() -> [&'static str; LIBRARY_METHODS.len() + 2] {
    let mut out = [""; LIBRARY_METHODS.len() + 2];
    let (mut i, mut k) = (0, 0);
    while i < LIBRARY_METHODS.len() {
        out[k] = LIBRARY_METHODS[i];
        k += 1;
        if same(LIBRARY_METHODS[i], "seed-mv") {
            out[k] = "hv-dmv";
            k += 1;
        }
        i += 1;
    }
    out[k] = "general";
    out
}

const fn same(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

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
        "general" => "DMV by the general-N Cardoso–Leite solver (lab oracle; computes in f64, with --f32 its state is rounded to f32 after each step)",
        _ => "unknown",
    }
}

// the library's integrators by name: one registry for the lab, the benches and the tests
#[path = "../../tests/common/methods.rs"]
mod library;
pub use library::{make_library, LIBRARY_METHODS};

/// A boxed integrator for `name`, or `None` for an unknown name: the
/// library's ([`make_library`]) and the lab's own `hv-dmv` and `general`.
pub fn make<T: Real + 'static>(name: &str, body: Body<T>, h: T) -> Option<Box<dyn Integrator<T>>> {
    match name {
        "hv-dmv" => Some(Box::new(HvDmv::new(body, h))),
        "general" => {
            // the oracle is f64-only; wrap through f64
            Some(Box::new(Widened(
                GeneralDmv::new(body.mass_matrix().map(Real::to_f64), h.to_f64()),
                body,
            )))
        }
        _ => make_library(name, body, h),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_order_and_every_name_builds() {
        // the library's in their order, hv-dmv right after seed-mv, general last
        let lab: Vec<&str> = METHODS
            .iter()
            .copied()
            .filter(|n| !["hv-dmv", "general"].contains(n))
            .collect();
        assert_eq!(lab, LIBRARY_METHODS);
        let seed = METHODS.iter().position(|&n| n == "seed-mv").unwrap();
        assert_eq!(METHODS[seed + 1], "hv-dmv");
        assert_eq!(METHODS.last(), Some(&"general"));
        let body = Body::<f64>::from_mass_matrix(crate::scenes::TALK_J).unwrap();
        for name in METHODS {
            assert!(make(name, body, 0.1).is_some(), "{name}");
            assert_ne!(describe(name), "unknown", "{name}");
        }
    }
}
