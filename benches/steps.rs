//! Host time per step of every method, in one criterion run so ratios cancel machine noise.
//!
//! `cargo bench --bench steps`, then `cargo run --release -p rigid3-lab -- bench-table` for
//! the table with ratios to the 3-rotation splitting.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rigid3::{
    Body, ConstantTorque, Forced, Gravity, GravityGradient, Integrator, Mv, NoTorque, PreMv, Real,
    State,
};

#[path = "../tests/common/cases.rs"]
mod cases;
use cases::{TALK_J, TALK_M0};
const H: f64 = 0.1;

#[path = "../tests/common/methods.rs"]
mod methods;

/// The benchmarked methods, the 3-rotation splitting first (the baseline of the ratios).
const BENCHED: [&str; 10] = [
    "splitting",
    "splitting2",
    "mv",
    "pre-mv4",
    "pre-mv10",
    "seed-mv",
    "midpoint",
    "midpoint-fp",
    "rk4",
    "exact",
];

fn all_methods<T: Real + 'static>(
    body: Body<T>,
    h: T,
) -> Vec<(&'static str, Box<dyn Integrator<T>>)> {
    BENCHED
        .iter()
        .filter_map(|&name| Some((name, methods::make_library(name, body, h)?)))
        .collect()
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

/// The forced step against the free one, with attitude, in one group: the free `Mv` step,
/// the kick–drift–kick with the torque given (zero-order hold), with the heavy-top gravity
/// model, and with a rotor; the free `Mv` under a changed momentum (a kick from outside) and
/// under a step size jittering by +-5% every step.
fn bench_forced<T: Real + 'static>(c: &mut Criterion, ty: &str) {
    let body = Body::<T>::from_mass_matrix(TALK_J.map(T::from_f64)).unwrap();
    let h = T::from_f64(0.01);
    let s0 = State::new(
        TALK_M0.map(T::from_f64),
        [T::ONE, T::ZERO, T::ZERO, T::ZERO],
    );
    let tau = [0.01, -0.02, 0.005].map(T::from_f64);
    let mut group = c.benchmark_group(format!("forced-{ty}"));
    let mut free = Mv::new(body, h);
    let mut s = s0;
    group.bench_function("mv-free", |b| {
        b.iter(|| {
            let _ = free.step_state(black_box(&mut s));
        })
    });
    let mut given = Forced::new(Mv::new(body, h), NoTorque);
    let mut s = s0;
    // the sign flips every 64 steps so the momentum stays bounded over criterion's millions
    // of steps (flipped every step, one step's end kick cancelled the next one's start kick:
    // the drift saw its own output and ran its free path, which this bench measured until
    // scripts/profile showed it)
    let neg = tau.map(|x| -x);
    let mut k = 0u32;
    group.bench_function("mv-torque-given", |b| {
        b.iter(|| {
            k = k.wrapping_add(1);
            let t = if (k / 64).is_multiple_of(2) { tau } else { neg };
            let _ = given.step_state_with(black_box(&mut s), t, t);
        })
    });
    let gravity = Gravity {
        mg: T::from_f64(0.1),
        com: [0.0, 0.0, 0.3].map(T::from_f64),
    };
    let mut top = Forced::new(Mv::new(body, h), gravity);
    let mut s = s0;
    group.bench_function("mv-heavy-top", |b| {
        b.iter(|| {
            let _ = top.step_state(black_box(&mut s));
        })
    });
    let mut wheels = Forced::new(Mv::new(body, h), NoTorque);
    wheels
        .set_rotor([0.02, -0.01, 0.03].map(T::from_f64))
        .unwrap();
    let mut s = s0;
    group.bench_function("mv-rotor", |b| {
        b.iter(|| {
            let _ = wheels.step_state(black_box(&mut s));
        })
    });
    // a controller's command added to the gravity gradient: step_state_plus (the model once a
    // step) against the summed model changed through torque_mut (its cache dropped: twice)
    let gg = GravityGradient {
        k: T::from_f64(0.01),
        n: T::from_f64(0.1),
        inertia: body.inertia(),
    };
    let mut plus = Forced::new(Mv::new(body, h), gg);
    let mut s = s0;
    let mut k = 0u32;
    group.bench_function("mv-gg-plus-command", |b| {
        b.iter(|| {
            k = k.wrapping_add(1);
            let t = if (k / 64).is_multiple_of(2) { tau } else { neg };
            let _ = plus.step_state_plus(black_box(&mut s), t, t);
        })
    });
    let mut summed = Forced::new(Mv::new(body, h), (gg, ConstantTorque(tau)));
    let mut s = s0;
    let mut k = 0u32;
    group.bench_function("mv-gg-command-torque-mut", |b| {
        b.iter(|| {
            k = k.wrapping_add(1);
            let t = if (k / 64).is_multiple_of(2) { tau } else { neg };
            summed.torque_mut().1 = ConstantTorque(t);
            let _ = summed.step_state(black_box(&mut s));
        })
    });
    let mut kicked = Mv::new(body, h);
    let mut s = s0;
    let kick = T::from_f64(1e-4);
    group.bench_function("mv-kicked", |b| {
        b.iter(|| {
            // a kick that turns m (|m| stays put), as a filter's small correction would
            s.m[0] += kick * s.m[1];
            s.m[1] -= kick * s.m[0];
            let _ = kicked.step_state(black_box(&mut s));
        })
    });
    let mut jitter = Mv::new(body, h);
    let mut s = s0;
    let (lo, hi) = (T::from_f64(0.0095), T::from_f64(0.0105));
    let mut k = 0u32;
    group.bench_function("mv-jitter", |b| {
        b.iter(|| {
            k = k.wrapping_add(1);
            jitter.set_step_size(if k.is_multiple_of(2) { lo } else { hi });
            let _ = jitter.step_state(black_box(&mut s));
        })
    });
    group.finish();
}

/// A step with its tangent map (`step_with_jacobian`, for an EKF's covariance) against the
/// plain step, with attitude, along one trajectory (`Mv` and `PreMv` order 4, talk's case,
/// `h = 0.01`).
fn bench_jacobian(c: &mut Criterion) {
    let body = Body::<f64>::from_mass_matrix(TALK_J).unwrap();
    let s0 = State::new(TALK_M0, [1.0, 0.0, 0.0, 0.0]);
    let h = 0.01;
    let mut group = c.benchmark_group("jacobian-f64");
    let mut mv = Mv::new(body, h);
    let mut s = s0;
    group.bench_function("mv step_state", |b| {
        b.iter(|| {
            let _ = mv.step_state(black_box(&mut s));
        })
    });
    let mut mv = Mv::new(body, h);
    let mut s = s0;
    group.bench_function("mv step_with_jacobian", |b| {
        b.iter(|| black_box(mv.step_with_jacobian(black_box(&mut s)).ok()))
    });
    let mut pre = PreMv::new(body, h, 4).unwrap();
    let mut s = s0;
    group.bench_function("pre-mv4 step_state", |b| {
        b.iter(|| {
            let _ = pre.step_state(black_box(&mut s));
        })
    });
    let mut pre = PreMv::new(body, h, 4).unwrap();
    let mut s = s0;
    group.bench_function("pre-mv4 step_with_jacobian", |b| {
        b.iter(|| black_box(pre.step_with_jacobian(black_box(&mut s)).ok()))
    });
    group.finish();
}

fn steps(c: &mut Criterion) {
    bench_momentum::<f64>(c, "f64");
    bench_momentum::<f32>(c, "f32");
    bench_state::<f64>(c, "f64");
    bench_state::<f32>(c, "f32");
    bench_forced::<f64>(c, "f64");
    bench_forced::<f32>(c, "f32");
    bench_jacobian(c);
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(2));
    targets = steps
}
criterion_main!(benches);
