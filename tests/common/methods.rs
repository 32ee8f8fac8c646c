//! The library's integrators by name: the one registry shared by the lab
//! (`lab/src/methods.rs`, which adds its own `hv-dmv` and `general`), the criterion benches
//! (`benches/steps.rs`) and the library's tests, each through `#[path]` (none of them can
//! depend on another). The fuzz checks (`fuzz/check.rs`) keep their own selector: their
//! inputs choose orders and step counts, and they build monomorphic integrators.
#![allow(dead_code)]

use rigid3::{
    Body, Exact, Integrator, Midpoint, Mv, PreMv, Real, RetimedMv, Rk4, SeedMv, Solver, Splitting,
    Splitting2,
};

/// The names of the library's integrators, in the order tables list them.
pub const LIBRARY_METHODS: [&str; 14] = [
    "mv",
    "pre-mv4",
    "pre-mv6",
    "pre-mv8",
    "pre-mv10",
    "retimed-mv",
    "retimed-pre-mv10",
    "seed-mv",
    "splitting",
    "splitting2",
    "midpoint",
    "midpoint-fp",
    "rk4",
    "exact",
];

/// A boxed library integrator for `name`, or `None` for a name not in [`LIBRARY_METHODS`].
pub fn make_library<T: Real + 'static>(
    name: &str,
    body: Body<T>,
    h: T,
) -> Option<Box<dyn Integrator<T>>> {
    Some(match name {
        "mv" => Box::new(Mv::new(body, h)),
        "pre-mv4" => Box::new(PreMv::new(body, h, 4).ok()?),
        "pre-mv6" => Box::new(PreMv::new(body, h, 6).ok()?),
        "pre-mv8" => Box::new(PreMv::new(body, h, 8).ok()?),
        "pre-mv10" => Box::new(PreMv::new(body, h, 10).ok()?),
        "retimed-mv" => Box::new(RetimedMv::new(body, h, 2).ok()?),
        "retimed-pre-mv10" => Box::new(RetimedMv::new(body, h, 10).ok()?),
        "seed-mv" => Box::new(SeedMv::new(body, h)),
        "splitting" => Box::new(Splitting::new(body, h)),
        "splitting2" => Box::new(Splitting2::new(body, h)),
        "midpoint" => Box::new(Midpoint::new(body, h)),
        "midpoint-fp" => Box::new(Midpoint::with_solver(body, h, Solver::FixedPoint)),
        "rk4" => Box::new(Rk4::new(body, h)),
        "exact" => Box::new(Exact::new(body, h)),
        _ => return None,
    })
}
