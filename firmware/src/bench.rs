//! Measuring on the target: instruction counts from SysTick (under QEMU's `-icount shift=0`
//! SysTick ticks once per 40 instructions: QEMU counts instructions, not cycles), and the method
//! benchmark: one table of methods (rows) by regimes (columns), each row one line of the table.

use crate::math::Noise;
use cortex_m::peripheral::SYST;
use rigid3::{
    Body, ConstantTorque, Forced, Integrator, Mv, NoTorque, PreMv, Real, Rk4, SeedMv, Splitting,
    State,
};

/// Instructions executed by `f`, from SysTick (one tick per 40 instructions under
/// `-icount shift=0`); `f` must stay under 2^24 ticks (671M instructions).
pub fn instructions(f: impl FnOnce()) -> u32 {
    let t0 = SYST::get_current();
    f();
    let t1 = SYST::get_current();
    (t0.wrapping_sub(t1) & 0x00ff_ffff) * 40
}

/// SysTick now (for spans that cannot be one closure).
pub fn now() -> u32 {
    SYST::get_current()
}

/// Instructions from `t0` (a [`now`]) to now.
pub fn since(t0: u32) -> u32 {
    (t0.wrapping_sub(SYST::get_current()) & 0x00ff_ffff) * 40
}

pub const BENCH_STEPS: u32 = 2000;

/// An `f32` wrapper whose `sin` and `cos` are `$sin` and `$cos`: everything else is `f32`.
/// Shows the `Real` trait taking a wrapper, and what the splitting costs when its trigonometry
/// is not libm's (which computes `sinf`/`cosf` in software double on the M4F).
macro_rules! trig_f32 {
    ($(#[$doc:meta])* $name:ident, $sin:expr, $cos:expr, $sincos:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
        pub struct $name(pub f32);

        trig_f32!(@op $name, Add, add, AddAssign, add_assign, +);
        trig_f32!(@op $name, Sub, sub, SubAssign, sub_assign, -);
        trig_f32!(@op $name, Mul, mul, MulAssign, mul_assign, *);
        impl core::ops::Div for $name {
            type Output = $name;
            #[inline]
            fn div(self, o: $name) -> $name {
                $name(self.0 / o.0)
            }
        }
        impl core::ops::Neg for $name {
            type Output = $name;
            #[inline]
            fn neg(self) -> $name {
                $name(-self.0)
            }
        }
        impl Real for $name {
            const EPSILON: Self = $name(f32::EPSILON);
            const MIN_POSITIVE: Self = $name(f32::MIN_POSITIVE);
            const MAX: Self = $name(f32::MAX);
            const ZERO: Self = $name(0.0);
            const ONE: Self = $name(1.0);
            fn from_f64(x: f64) -> Self {
                $name(x as f32)
            }
            fn to_f64(self) -> f64 {
                self.0 as f64
            }
            fn sqrt(self) -> Self {
                $name(Real::sqrt(self.0))
            }
            fn abs(self) -> Self {
                $name(Real::abs(self.0))
            }
            fn sin(self) -> Self {
                $name($sin(self.0))
            }
            fn cos(self) -> Self {
                $name($cos(self.0))
            }
            fn sin_cos(self) -> (Self, Self) {
                let (s, c) = $sincos(self.0);
                ($name(s), $name(c))
            }
            fn acos(self) -> Self {
                $name(Real::acos(self.0))
            }
            fn atan2(self, x: Self) -> Self {
                $name(Real::atan2(self.0, x.0))
            }
            fn cbrt(self) -> Self {
                $name(Real::cbrt(self.0))
            }
            fn ln(self) -> Self {
                $name(Real::ln(self.0))
            }
            fn exp(self) -> Self {
                $name(Real::exp(self.0))
            }
            fn is_finite(self) -> bool {
                self.0.is_finite()
            }
        }
    };
    (@op $name:ident, $tr:ident, $f:ident, $tra:ident, $fa:ident, $op:tt) => {
        impl core::ops::$tr for $name {
            type Output = $name;
            #[inline]
            fn $f(self, o: $name) -> $name {
                $name(self.0 $op o.0)
            }
        }
        impl core::ops::$tra for $name {
            #[inline]
            fn $fa(&mut self, o: $name) {
                self.0 = self.0 $op o.0;
            }
        }
    };
}

trig_f32!(
    /// `f32` with micromath's `sin` and `cos` (about 1e-3 absolute error, no libm call).
    Fast,
    micromath::F32Ext::sin,
    micromath::F32Ext::cos,
    |x: f32| (micromath::F32Ext::sin(x), micromath::F32Ext::cos(x))
);

trig_f32!(
    /// `f32` with `rigid3::sin_cos` (at most 1.5 eps absolute error up to 6000 rad, reduction
    /// by `pi/2` and polynomials in `f32`): the splitting with accurate trigonometry that
    /// costs what an FPU's arithmetic costs.
    Poly,
    |x: f32| rigid3::sin_cos(x).0,
    |x: f32| rigid3::sin_cos(x).1,
    rigid3::sin_cos
);

// ---------------------------------------------------------------- momentum table

/// One row of the momentum table: instructions per momentum step (empty-loop overhead removed)
/// and the relative drift of |m|^2, E and R(q) m over 10^4 steps with attitude.
pub struct MomentumRow {
    pub instr: u32,
    pub drift: [f32; 3],
    pub ok: bool,
}

fn momentum_row<T: Real, I: Integrator<T>>(
    mut a: I,
    body: Body<T>,
    m0: [T; 3],
    overhead: u32,
) -> MomentumRow {
    let mut m = m0;
    let mut ok = true;
    let _ = a.step(&mut m); // set-up outside the count
    let n = instructions(|| {
        for _ in 0..BENCH_STEPS {
            ok &= a.step(core::hint::black_box(&mut m)).is_ok();
        }
    });
    let instr = n.saturating_sub(overhead) / BENCH_STEPS;
    let mut s = State::new(m0, [T::ONE, T::ZERO, T::ZERO, T::ZERO]);
    let (c0, e0, p0) = (body.casimir(&m0), body.energy(&m0), s.spatial_momentum());
    for _ in 0..10_000 {
        ok &= a.step_state(&mut s).is_ok();
    }
    let p = s.spatial_momentum();
    let dp = Real::sqrt(
        (p[0] - p0[0]) * (p[0] - p0[0])
            + (p[1] - p0[1]) * (p[1] - p0[1])
            + (p[2] - p0[2]) * (p[2] - p0[2]),
    ) / Real::sqrt(c0);
    let rel = |x: T, x0: T| (Real::abs(x - x0) / x0).to_f64() as f32;
    MomentumRow {
        instr,
        drift: [
            rel(body.casimir(&s.m), c0),
            rel(body.energy(&s.m), e0),
            dp.to_f64() as f32,
        ],
        ok,
    }
}

/// The methods of the momentum table, in its order.
pub const MOMENTUM_METHODS: [&str; 10] = [
    "mv          ",
    "seed-mv     ",
    "pre-mv4     ",
    "pre-mv6     ",
    "pre-mv8     ",
    "pre-mv10    ",
    "splitting   ",
    "splitting-mm",
    "splitting-sc",
    "rk4         ",
];

/// The momentum table's row `k` of [`MOMENTUM_METHODS`] (f32, step `h`); `None` if the method
/// cannot be built.
pub fn momentum_method(
    k: usize,
    body: Body<f32>,
    m0: [f32; 3],
    h: f32,
    overhead: u32,
) -> Option<MomentumRow> {
    Some(match k {
        0 => momentum_row(Mv::new(body, h), body, m0, overhead),
        1 => momentum_row(SeedMv::new(body, h), body, m0, overhead),
        2..=5 => momentum_row(PreMv::new(body, h, 2 * k as u8).ok()?, body, m0, overhead),
        6 => momentum_row(Splitting::new(body, h), body, m0, overhead),
        7 => {
            let fb = Body::<Fast>::from_inertia(body.inertia().map(Fast)).ok()?;
            momentum_row(Splitting::new(fb, Fast(h)), fb, m0.map(Fast), overhead)
        }
        8 => {
            let pb = Body::<Poly>::from_inertia(body.inertia().map(Poly)).ok()?;
            momentum_row(Splitting::new(pb, Poly(h)), pb, m0.map(Poly), overhead)
        }
        _ => momentum_row(Rk4::new(body, h), body, m0, overhead),
    })
}

/// The empty loop's instructions (subtracted from the momentum table).
pub fn overhead(m0: [f32; 3]) -> u32 {
    instructions(|| {
        let mut m = m0;
        for _ in 0..BENCH_STEPS {
            core::hint::black_box(&mut m);
        }
    })
}

// ---------------------------------------------------------------- regimes table

/// Instructions per step of `f(k)` (k = 0..BENCH_STEPS) less `base` per step.
///
/// Never inlined: each measured loop is then a function of its own, with its own register
/// allocation. Inlined, every loop sat in one 50 KB `run` and its spills moved with unrelated
/// code (adding the f64 truth's Nyström splitting moved the forced step 550 -> 563).
#[inline(never)]
pub fn per_step(base: u32, mut f: impl FnMut(u32)) -> u32 {
    let n = instructions(|| {
        for k in 0..BENCH_STEPS {
            f(k);
        }
    });
    (n / BENCH_STEPS).saturating_sub(base)
}

/// What a row's fourth column does each step.
#[derive(Clone, Copy)]
pub enum Fourth {
    /// The row's drift inside `Forced` with a torque kick every step (`step_state_with`).
    Kick,
    /// The row (a forced integrator with a torque model and a rotor) with its rotor set every
    /// step (`set_rotor`: wheels commanded each tick).
    Rotor,
}

/// Instructions per f32 step with attitude in the four regimes of the real loop: fixed `h`;
/// `h` jittered by +-5% every step (`set_step_size`); `m` corrected every step by 1e-4 relative
/// (a filter); and `fourth` ([`Fourth`]). The perturbation's own cost is measured alone and
/// removed. Returns `[fixed, jitter, corrected, fourth]`.
pub fn regimes<I: Integrator<f32> + Clone>(
    a0: I,
    s0: State<f32>,
    h: f32,
    fourth: Fourth,
    rotor: Option<fn(&mut I, [f32; 3]) -> bool>,
) -> [u32; 4] {
    let empty = per_step(0, |_| {
        core::hint::black_box(());
    });
    let mut noise = Noise(0x1234_5678);
    let jitter_cost = per_step(empty, |_| {
        core::hint::black_box(h * (1.0 + 0.1 * (noise.uniform() - 0.5)));
    });
    let mut s1 = s0;
    let correct_cost = per_step(empty, |_| {
        for x in s1.m.iter_mut() {
            *x *= 1.0 + 2e-4 * (noise.uniform() - 0.5);
        }
        core::hint::black_box(&mut s1);
    });
    let run = |mut a: I, f: &mut dyn FnMut(&mut I, &mut State<f32>), base: u32| -> u32 {
        let mut s = s0;
        let _ = a.step_state(&mut s);
        per_step(empty + base, |_| {
            f(&mut a, &mut s);
        })
    };
    let fixed = run(
        a0.clone(),
        &mut |a, s| {
            let _ = a.step_state(core::hint::black_box(s));
        },
        0,
    );
    let jitter = run(
        a0.clone(),
        &mut |a, s| {
            a.set_step_size(h * (1.0 + 0.1 * (noise.uniform() - 0.5)));
            let _ = a.step_state(core::hint::black_box(s));
        },
        jitter_cost,
    );
    let corrected = run(
        a0.clone(),
        &mut |a, s| {
            for x in s.m.iter_mut() {
                *x *= 1.0 + 2e-4 * (noise.uniform() - 0.5);
            }
            let _ = a.step_state(core::hint::black_box(s));
        },
        correct_cost,
    );
    let fourth = match (fourth, rotor) {
        (Fourth::Rotor, Some(set)) => {
            let wheel = [0.5f32, -0.2, 0.3];
            let wheel_cost = per_step(empty, |k| {
                core::hint::black_box(wheel.map(|x| x * (1.0 + 1e-3 * (k & 7) as f32)));
            });
            run(
                a0,
                &mut |a, s| {
                    let k = (s.q[0].to_bits() & 7) as f32;
                    let _ = set(a, wheel.map(|x| x * (1.0 + 1e-3 * k)));
                    let _ = a.step_state(core::hint::black_box(s));
                },
                wheel_cost,
            )
        }
        _ => {
            let mut forced = Forced::new(a0, NoTorque);
            // a controller-sized torque (the flight's limit is 0.05 N m), its sign flipped
            // every 64 steps to keep m bounded. Until this was measured with the profile
            // (scripts/profile) it was 2e-4 N m flipped every step: a tenth of an ulp of m in
            // f32, and one step's end kick cancelled the next one's start kick, so the drift
            // saw its own output and ran its free path: not a kick at all.
            let tau = [0.05f32, -0.03, 0.04];
            let neg = tau.map(|x| -x);
            let mut s = s0;
            let _ = forced.step_state(&mut s);
            per_step(empty, |k| {
                let t = if (k / 64).is_multiple_of(2) { tau } else { neg };
                let _ = forced.step_state_with(core::hint::black_box(&mut s), t, t);
            })
        }
    };
    [fixed, jitter, corrected, fourth]
}

/// Forced `Mv` with a constant torque model (no rotor): the cost of the kicks alone.
pub fn forced_constant(body: Body<f32>, s0: State<f32>, h: f32) -> u32 {
    // controller-sized (a torque below an ulp of m would leave the drift free running)
    let mut held = Forced::new(Mv::new(body, h), ConstantTorque([0.05f32, 0.0, -0.05]));
    let mut s = s0;
    let _ = held.step_state(&mut s);
    per_step(0, |_| {
        let _ = held.step_state(core::hint::black_box(&mut s));
    })
}

// The step functions as separate symbols, so their code size can be read from the ELF.
#[inline(never)]
#[no_mangle]
pub fn rigid3_mv_step(a: &mut Mv<f32>, m: &mut [f32; 3]) -> bool {
    a.step(m).is_ok()
}
#[inline(never)]
#[no_mangle]
pub fn rigid3_mv_step_state(a: &mut Mv<f32>, s: &mut State<f32>) -> bool {
    a.step_state(s).is_ok()
}
