//! The fuzz targets' checks (`fuzz/check.rs`) on random bytes, on stable Rust: the CI smoke
//! run of `cargo +nightly fuzz run steps` / `inertia_tensor` / `loop` (see README, "Hardening").

#![allow(
    clippy::needless_range_loop,
    clippy::eq_op,
    clippy::manual_is_multiple_of,
    clippy::neg_cmp_op_on_partial_ord
)]

#[path = "../fuzz/check.rs"]
mod check;
#[path = "../fuzz/check_loop.rs"]
mod check_loop;
mod common;

use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    #[test]
    fn steps_never_panic_nor_return_nan(data in proptest::collection::vec(any::<u8>(), 0..96)) {
        check::check_steps(&data);
    }

    #[test]
    fn the_loop_never_panics_nor_returns_nan(data in proptest::collection::vec(any::<u8>(), 0..160)) {
        check_loop::check_loop(&data);
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
    print_tally(&check::METHODS, &table);
    let total: u32 = table.iter().flatten().sum();
    assert!(total > 100_000);
}

/// The loop's table (README, "Hardening"): 100,000 seeded random inputs through
/// `fuzz/check_loop.rs` — forced and free integrators driven for up to 12 calls while the step,
/// the momentum, the wheels, the clock and given torques change — outcomes of the steps by
/// method and kind. Fails on any panic, non-finite `Ok` or state changed on `Err`.
#[test]
fn tally_of_loop_outcomes_by_method_and_kind() {
    let mut rng = common::Rng::new(
        std::env::var("LOOP_SEED")
            .map(|s| s.parse().unwrap())
            .unwrap_or(0x100b),
    );
    let n: u32 = std::env::var("LOOP_N")
        .map(|s| s.parse().unwrap())
        .unwrap_or(100_000);
    let mut next = || rng.next_u64();
    let mut table = [[0u32; 7]; 11];
    let (mut inputs, mut refused) = (0u32, 0u32);
    for _ in 0..n {
        let len = (next() % 160) as usize;
        let data: Vec<u8> = (0..len).map(|_| next() as u8).collect();
        inputs += 1;
        let out = std::panic::catch_unwind(|| check_loop::check_loop(&data));
        let out = out.unwrap_or_else(|e| {
            println!("failing input: {data:?}");
            std::panic::resume_unwind(e)
        });
        match out {
            Some((method, t)) => {
                for k in 0..7 {
                    table[method][k] += t[k];
                }
            }
            None => refused += 1,
        }
    }
    println!(
        "{inputs} random loops; {refused} refused at construction (invalid body, order or step)"
    );
    print_tally(&check_loop::LOOP_METHODS, &table);
    // every method was driven, and stepped to Ok many times
    for (m, row) in table.iter().enumerate() {
        assert!(
            row[0] > 1000,
            "{}: only {} Ok steps",
            check_loop::LOOP_METHODS[m],
            row[0]
        );
    }
}

/// Found by the loop fuzz: a body with inertia spread over 210 decades (1.5e74, 2.2e3,
/// 1.3e-136) and |m| = 7.5e76, where `Mv`'s solve lost the momentum sphere and
/// returned Ok with a quaternion of norm 7e106; now a clean `Err(Degenerate)`.
#[test]
fn loop_regression_mv_lost_the_momentum_sphere() {
    let data: Vec<u8> = vec![
        170, 94, 207, 184, 132, 207, 77, 194, 88, 85, 79, 60, 181, 85, 27, 243, 89, 215, 39, 1, 14,
        184, 163, 130, 10, 216, 169, 168, 155, 224, 235, 76, 171, 141, 222, 74, 208, 69, 150, 109,
        226, 205, 148, 153, 15, 118, 147, 2, 132, 51, 196, 165, 225, 219, 82, 179, 145, 48, 14, 8,
        81, 145, 129, 137, 31, 107, 84, 34, 250, 46, 142, 169, 91, 23, 201, 175, 110, 13, 25, 139,
        24, 1, 127, 39, 147, 125, 217, 40, 119, 10,
    ];
    check_loop::check_loop(&data);
}

/// The outcome table: a row per method, a column per kind of outcome.
fn print_tally(methods: &[&str], table: &[check::Tally]) {
    let w = methods.iter().map(|m| m.len()).max().unwrap_or(0) + 1;
    let head = check::OUTCOMES.map(|o| format!("{o:>14}")).join("");
    println!("{:<w$}{head}", "method");
    for (name, row) in methods.iter().zip(table) {
        println!("{name:<w$}{}", row.map(|x| format!("{x:>14}")).join(""));
    }
}
