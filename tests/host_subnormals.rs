//! x86-64 only: f32 steps take no subnormal operand.
//!
//! LLVM's SLP vectorizer packs the crate's 3-vectors into 4-lane SSE registers. When it loads a
//! struct field 16 bytes at a time, the fourth lane holds the bits of whatever field follows,
//! and an integer or flag read as an f32 is usually subnormal: each SSE multiply with it took
//! a microcode assist (about 100 cycles), on 7 of 8 f32 `Mv` steps, which made the host's f32
//! rows of `rigid3-lab loop-cost` read up to 1.9x slower than the same code with the vectorizer
//! off. The oracle is the hardware: the MXCSR's denormal-operand flag (DE, bit 1), which every
//! SSE instruction with a subnormal input sets and nothing else clears. The tests' profile
//! optimizes (opt-level 2, SLP on), so the codegen checked is the vectorized one.
#![cfg(target_arch = "x86_64")]

use rigid3::{
    Body, Composed, ConstantTorque, Forced, Integrator, Mv, NoTorque, PreMv, RetimedMv, Splitting,
    State, StepError,
};

/// The MXCSR register.
fn mxcsr() -> u32 {
    let mut x: u32 = 0;
    // SAFETY: stmxcsr stores the 4-byte register into `x`, a valid, aligned u32.
    unsafe { core::arch::asm!("stmxcsr [{}]", in(reg) &mut x, options(nostack)) };
    x
}

/// Clears the six sticky exception flags (bits 0-5), keeping the masks and modes.
fn clear_flags() {
    let x = mxcsr() & !0x3f;
    // SAFETY: ldmxcsr loads a valid MXCSR value (the current one with its flags cleared).
    unsafe { core::arch::asm!("ldmxcsr [{}]", in(reg) &x, options(nostack, readonly)) };
}

const DENORMAL_FLAG: u32 = 1 << 1;

/// Makes a fresh integrator for one regime's run.
type Make<'a> = &'a dyn Fn() -> Box<dyn Integrator<f32>>;

/// The flight loop's four regimes (fixed `h`, `h` jittered by +-5 %, `m` corrected by 1e-4,
/// a small kick) on the README's spacecraft at 200 Hz, counting the steps after which the
/// denormal flag is set; the perturbations run before the flags are cleared.
fn flagged_steps(make: Make) -> [u32; 4] {
    let mut hits = [0; 4];
    for (regime, hit) in hits.iter_mut().enumerate() {
        let mut a = make();
        let mut s = State::new([3.0f32, 4.0, 2.0], [1.0, 0.0, 0.0, 0.0]);
        let mut seed = 12345u32;
        for _ in 0..400 {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            let u = (seed as f32 / u32::MAX as f32) * 2.0 - 1.0;
            match regime {
                1 => a.set_step_size(0.005 * (1.0 + 0.05 * u)),
                2 => s.m[0] *= 1.0 + 1e-4 * u,
                3 => s.m[1] += 5e-6 * u,
                _ => {}
            }
            clear_flags();
            let r: Result<(), StepError> = a.step_state(std::hint::black_box(&mut s));
            let flags = mxcsr();
            r.unwrap();
            if flags & DENORMAL_FLAG != 0 {
                *hit += 1;
            }
        }
    }
    hits
}

#[test]
fn f32_steps_take_no_subnormal_operand() {
    let body = Body::<f32>::from_inertia([58.8396, 95.4957, 120.6647]).unwrap();
    let h = 0.005f32;
    let methods: [(&str, Make); 8] = [
        ("mv", &|| Box::new(Mv::new(body, h))),
        ("pre-mv4", &|| Box::new(PreMv::new(body, h, 4).unwrap())),
        ("pre-mv10", &|| Box::new(PreMv::new(body, h, 10).unwrap())),
        ("retimed-mv", &|| {
            Box::new(RetimedMv::new(body, h, 2).unwrap())
        }),
        ("forced mv", &|| {
            Box::new(Forced::new(
                Mv::new(body, h),
                ConstantTorque([1e-3f32, -2e-3, 5e-4]),
            ))
        }),
        ("splitting", &|| Box::new(Splitting::new(body, h))),
        ("forced mv, wheels", &|| {
            let mut f = Forced::new(Mv::new(body, h), NoTorque);
            f.set_rotor([0.5, -0.2, 0.3]).unwrap();
            Box::new(f)
        }),
        ("composed, wheels", &|| {
            let mut c = Composed::new(Mv::new(body, h), NoTorque, 4).unwrap();
            c.set_rotor([0.5, -0.2, 0.3]).unwrap();
            Box::new(c)
        }),
    ];
    let mut bad = Vec::new();
    for (name, make) in methods {
        let hits = flagged_steps(make);
        println!("{name:>10}: steps with a subnormal operand (fixed, jitter, corrected, kick) {hits:?} of 400 each");
        if hits.iter().any(|&n| n > 0) {
            bad.push((name, hits));
        }
    }
    assert!(bad.is_empty(), "subnormal operands in f32 steps: {bad:?}");
}
