//! Host time per step of every method, in one criterion run so ratios cancel machine noise.
//!
//! `cargo bench --bench steps`, then `cargo run --release -p rigid3-lab -- bench-table` for
//! the table with ratios to the 3-rotation splitting.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rigid3::{Body, Integrator, Mv, Real, SeedMv, State};

const TALK_J: [f64; 3] = [0.9218, 0.7382, 0.1763];
const TALK_M0: [f64; 3] = [0.4165, 0.9072, 0.0588];
const H: f64 = 0.1;

/// Minimal symmetric Strang splitting of McLachlan (1993) with 5 exact axis rotations
/// (1/2, 2/2, 3, 2/2, 1/2): the reference cost the closed-form step is measured against.
struct Strang5<T> {
    inv_i: [T; 3],
    h: T,
}

impl<T: Real> Strang5<T> {
    fn new(body: Body<T>, h: T) -> Self {
        let i = body.inertia();
        Self {
            inv_i: [T::ONE / i[0], T::ONE / i[1], T::ONE / i[2]],
            h,
        }
    }
    /// Exact flow of E_k = m_k^2 / (2 I_k) for time t: rotation of m about axis k by
    /// -t m_k / I_k.
    #[inline]
    fn rotate(&self, m: &mut [T; 3], k: usize, t: T) {
        let (a, b) = ((k + 1) % 3, (k + 2) % 3);
        let angle = t * m[k] * self.inv_i[k];
        let (s, c) = (angle.sin(), angle.cos());
        let (ma, mb) = (m[a], m[b]);
        m[a] = c * ma + s * mb;
        m[b] = c * mb - s * ma;
    }
}

impl<T: Real> Integrator<T> for Strang5<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), rigid3::StepError> {
        let half = self.h * T::from_f64(0.5);
        self.rotate(m, 0, half);
        self.rotate(m, 1, half);
        self.rotate(m, 2, self.h);
        self.rotate(m, 1, half);
        self.rotate(m, 0, half);
        Ok(())
    }
    fn step_state(&mut self, _s: &mut State<T>) -> Result<(), rigid3::StepError> {
        unimplemented!("momentum-only bench baseline")
    }
    fn step_size(&self) -> T {
        self.h
    }
}

fn bench_momentum<T: Real + 'static>(c: &mut Criterion, ty: &str) {
    let body = Body::<T>::from_mass_matrix(TALK_J.map(T::from_f64)).unwrap();
    let h = T::from_f64(H);
    let mut group = c.benchmark_group(format!("momentum-{ty}"));
    let methods: Vec<(&str, Box<dyn Integrator<T>>)> = vec![
        ("strang5", Box::new(Strang5::new(body, h))),
        ("mv", Box::new(Mv::new(body, h))),
        ("seed-mv", Box::new(SeedMv::new(body, h))),
    ];
    for (name, mut integrator) in methods {
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
    let methods: Vec<(&str, Box<dyn Integrator<T>>)> = vec![
        ("mv", Box::new(Mv::new(body, h))),
        ("seed-mv", Box::new(SeedMv::new(body, h))),
    ];
    for (name, mut integrator) in methods {
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
