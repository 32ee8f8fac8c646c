//! `rigid3-lab`: the host-side lab of `rigid3`.
//!
//! Independent reference solvers (the general-N Cardoso–Leite DMV solver), the method
//! registry used by the CLI, and the experiments behind the README's tables.

// `!(x <= y)` is deliberate: it is true for NaN, which must fail the check too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// index loops read like the matrix formulas they implement
#![allow(clippy::needless_range_loop)]

pub mod demo;
pub mod general;
pub mod methods;
pub mod propagate;
pub mod scenes;
