//! The fuzz targets' checks (`fuzz/check.rs`) on random bytes, on stable Rust: the CI smoke
//! run of `cargo +nightly fuzz run steps` / `inertia_tensor` (see README, "Hardening").

#![allow(
    clippy::needless_range_loop,
    clippy::eq_op,
    clippy::manual_is_multiple_of,
    clippy::neg_cmp_op_on_partial_ord
)]

#[path = "../fuzz/check.rs"]
mod check;

use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    #[test]
    fn steps_never_panic_nor_return_nan(data in proptest::collection::vec(any::<u8>(), 0..96)) {
        check::check_steps(&data);
    }

    #[test]
    fn inertia_tensor_never_panics(data in proptest::collection::vec(any::<u8>(), 0..96)) {
        check::check_tensor(&data);
    }
}
