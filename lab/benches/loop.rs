//! Host time per step with attitude in a loop of consecutive steps: `rigid3::Mv` (closed form),
//! the lab's `HvDmv` (Hairer–Vilmart's fixed-point iteration) and the 5-rotation
//! `rigid3::Splitting`, at h = 0.001, 0.01 and 0.1 on the talk's case, f64.
//!
//! Each iteration is a batch of `LOOP_BATCH` consecutive steps (the trajectory continues
//! across iterations; the state passes through `black_box`). Run with
//! `cargo bench -p rigid3-lab --bench loop -- --warm-up-time 1 --measurement-time 2`, then
//! `cargo run --release -p rigid3-lab -- loop-table` for ns per step and the ratios.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rigid3::{Body, Integrator, Mv, Splitting, State};
use rigid3_lab::bench_table::{LOOP_BATCH, LOOP_METHODS, LOOP_STEPS};
use rigid3_lab::hv_dmv::HvDmv;
use rigid3_lab::scenes::{TALK_J, TALK_M0};

fn batch<I: Integrator<f64>>(
    c: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    mut it: I,
) {
    let mut s = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    c.bench_function(name, |b| {
        b.iter(|| {
            for _ in 0..LOOP_BATCH {
                if it.step_state(black_box(&mut s)).is_err() {
                    panic!("{name}: step failed");
                }
            }
        })
    });
}

fn loop_steps(c: &mut Criterion) {
    let body = Body::<f64>::from_mass_matrix(TALK_J).unwrap();
    for h_text in LOOP_STEPS {
        let h: f64 = h_text.parse().unwrap();
        let mut group = c.benchmark_group(format!("loop-h{h_text}"));
        for name in LOOP_METHODS {
            match name {
                "mv" => batch(&mut group, name, Mv::new(body, h)),
                "hv-dmv" => batch(&mut group, name, HvDmv::new(body, h)),
                _ => batch(&mut group, name, Splitting::new(body, h)),
            }
        }
        group.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(std::time::Duration::from_secs(1))
        .measurement_time(std::time::Duration::from_secs(2));
    targets = loop_steps
}
criterion_main!(benches);
