//! Shared by the lab's integration tests.

pub use rigid3_lab::rng::Rng;
