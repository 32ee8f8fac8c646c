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
mod common;

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

/// The table of the README's "Hardening" section: 200,000 seeded random inputs through the fuzz
/// checks, outcomes by method and kind. Fails on any panic or non-finite `Ok` (inside `check`).
#[test]
fn tally_of_outcomes_by_method_and_kind() {
    let mut rng = common::Rng::new(0x5eed);
    let mut next = || rng.next_u64();
    let mut table = [[0u32; 7]; 11];
    let (mut inputs, mut refused_bodies, mut tensors_ok) = (0u32, 0u32, 0u32);
    for _ in 0..200_000 {
        let len = (next() % 96) as usize;
        let data: Vec<u8> = (0..len).map(|_| next() as u8).collect();
        inputs += 1;
        match check::check_steps(&data) {
            Some((method, t)) => {
                for k in 0..7 {
                    table[method][k] += t[k];
                }
            }
            None => refused_bodies += 1,
        }
        tensors_ok += check::check_tensor(&data) as u32;
    }
    println!("{inputs} random inputs; {refused_bodies} refused as invalid bodies (BodyError); inertia tensors accepted: {tensors_ok}");
    println!(
        "{:<12} {}",
        "method",
        check::OUTCOMES.map(|o| format!("{o:>13}")).join("")
    );
    for (m, row) in table.iter().enumerate() {
        println!(
            "{:<12} {}",
            check::METHODS[m],
            row.map(|x| format!("{x:>13}")).join("")
        );
    }
    let total: u32 = table.iter().flatten().sum();
    assert!(total > 100_000);
}
