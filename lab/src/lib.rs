//! `rigid3-lab`: the host-side lab of `rigid3`.
//!
//! Independent reference solvers (the general-N Cardoso–Leite DMV solver), the method
//! registry used by the CLI, and the experiments behind the README's tables.

pub mod atlas;
pub mod bench_table;
pub mod claims;
pub mod count;
pub mod demo;
pub mod figures;
pub mod flops;
pub mod forced_methods;
pub mod forced_refs;
pub mod forced_work;
pub mod general;
pub mod hv_dmv;
pub mod inputs;
pub mod lgvi;
pub mod loop_cost;
pub mod methods;
pub mod propagate;
pub mod refs;
pub mod rng;
pub mod scenes;
pub mod soak;
pub mod work_precision;
