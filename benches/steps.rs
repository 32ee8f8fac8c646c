//! Host time per step of every method, in one criterion run so ratios cancel machine noise.
//!
//! `cargo bench --bench steps`, then `cargo run --release -p rigid3-lab -- bench-table` for
//! the table with ratios to the 3-rotation splitting.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rigid3::{
    Body, Exact, Integrator, Midpoint, Mv, PreMv, Real, Rk4, SeedMv, Solver, Splitting, Splitting2,
    State,
};

const TALK_J: [f64; 3] = [0.9218, 0.7382, 0.1763];
const TALK_M0: [f64; 3] = [0.4165, 0.9072, 0.0588];
const H: f64 = 0.1;

/// Every method, the 3-rotation splitting first (the baseline of the ratios).
fn all_methods<T: Real + 'static>(
    body: Body<T>,
    h: T,
) -> Vec<(&'static str, Box<dyn Integrator<T>>)> {
    vec![
        ("splitting", Box::new(Splitting::new(body, h))),
        ("splitting2", Box::new(Splitting2::new(body, h))),
        ("mv", Box::new(Mv::new(body, h))),
        ("pre-mv4", Box::new(PreMv::new(body, h, 4))),
        ("pre-mv10", Box::new(PreMv::new(body, h, 10))),
        ("seed-mv", Box::new(SeedMv::new(body, h))),
        ("midpoint", Box::new(Midpoint::new(body, h))),
        (
            "midpoint-fp",
            Box::new(Midpoint::with_solver(body, h, Solver::FixedPoint)),
        ),
        ("rk4", Box::new(Rk4::new(body, h))),
        ("exact", Box::new(Exact::new(body, h))),
    ]
}

fn bench_momentum<T: Real + 'static>(c: &mut Criterion, ty: &str) {
    let body = Body::<T>::from_mass_matrix(TALK_J.map(T::from_f64)).unwrap();
    let h = T::from_f64(H);
    let mut group = c.benchmark_group(format!("momentum-{ty}"));
    for (name, mut integrator) in all_methods(body, h) {
        let mut m = TALK_M0.map(T::from_f64);
        group.bench_function(name, |b| {
            b.iter(|| {
                let _ = integrator.step(black_box(&mut m));
            })
        });
    }
    group.finish();
}

fn bench_state<T: Real + 'static>(c: &mut Criterion, ty: &str) {
    let body = Body::<T>::from_mass_matrix(TALK_J.map(T::from_f64)).unwrap();
    let h = T::from_f64(H);
    let mut group = c.benchmark_group(format!("state-{ty}"));
    for (name, mut integrator) in all_methods(body, h) {
        let mut s = State::new(
            TALK_M0.map(T::from_f64),
            [T::ONE, T::ZERO, T::ZERO, T::ZERO],
        );
        group.bench_function(name, |b| {
            b.iter(|| {
                let _ = integrator.step_state(black_box(&mut s));
            })
        });
    }
    group.finish();
}

fn steps(c: &mut Criterion) {
    bench_momentum::<f64>(c, "f64");
    bench_momentum::<f32>(c, "f32");
    bench_state::<f64>(c, "f64");
    bench_state::<f32>(c, "f32");
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(2));
    targets = steps
}
criterion_main!(benches);
