//! Shared by the lab's integration tests.
#![allow(dead_code, unused_imports)]

pub use rigid3_lab::rng::Rng;

// the rotation matrix written out (one definition, with the crate's tests)
#[path = "../../../tests/common/rotation.rs"]
mod rotation;
pub use rotation::rotation;
