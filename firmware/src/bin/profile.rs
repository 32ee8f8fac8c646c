//! The step under an instruction trace: runs one method in one regime of the real loop for
//! `PROFILE_STEPS` steps and exits, so that `scripts/profile` can run it under QEMU with one
//! instruction per translation block and attribute every executed instruction to the (inlined)
//! function it came from. The method and regime are chosen at build time
//! (`PROFILE_METHOD=mv|pre-mv4|pre-mv10`, `PROFILE_REGIME=fixed|jitter|corrected|kick`, `wheels`: `Forced` with the gravity-gradient model and a rotor at fixed `h`, or `momentum`: fixed `h`, no attitude), as in
//! the firmware's regimes table (`bench.rs`): f32 with attitude, `h = 1/200`, a tumble of about
//! 0.1 rad/s, `h` jittered by +-5 %, `m` corrected by 1e-4, a torque kick every step.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    println!("profile: firmware for thumbv7em-none-eabihf; run it with scripts/profile");
}

#[cfg(target_os = "none")]
mod firmware {
    use cortex_m_rt::entry;
    use cortex_m_semihosting::debug::{exit, EXIT_FAILURE, EXIT_SUCCESS};
    use defmt_semihosting as _;
    use rigid3::{Body, Forced, GravityGradient, Integrator, Mv, NoTorque, PreMv, State};

    #[panic_handler]
    fn panic(_: &core::panic::PanicInfo) -> ! {
        exit(EXIT_FAILURE);
        loop {
            cortex_m::asm::wfi();
        }
    }

    const METHOD: &str = match option_env!("PROFILE_METHOD") {
        Some(s) => s,
        None => "mv",
    };
    const REGIME: &str = match option_env!("PROFILE_REGIME") {
        Some(s) => s,
        None => "jitter",
    };
    const STEPS: u32 = 1000;

    /// The firmware's noise (xorshift32).
    struct Noise(u32);
    impl Noise {
        fn uniform(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 17;
            self.0 ^= self.0 << 5;
            (self.0 >> 8) as f32 * (1.0 / 16_777_216.0)
        }
    }

    #[inline(never)]
    fn run<I: Integrator<f32>>(mut a: I, h: f32, s0: State<f32>) -> f32 {
        let mut s = s0;
        let mut noise = Noise(0x1234_5678);
        if REGIME.as_bytes()[0] == b'k' {
            let mut forced = Forced::new(a, NoTorque);
            let _ = forced.step_state(&mut s);
            let tau = [0.05f32, -0.03, 0.04];
            let mut failed = 0u32;
            for k in 0..STEPS {
                let t = if (k / 64).is_multiple_of(2) {
                    tau
                } else {
                    tau.map(|x| -x)
                };
                failed += forced
                    .step_state_with(core::hint::black_box(&mut s), t, t)
                    .is_err() as u32;
            }
            return s.m[0] + s.q[0] + failed as f32 * 1000.0;
        }
        if REGIME.as_bytes()[0] == b'w' {
            // wheels: Forced with the gravity-gradient model and a rotor, fixed h
            let gg = GravityGradient {
                k: 1.3e-6,
                n: 1.1e-3,
                inertia: a.body().inertia(),
            };
            let mut forced = Forced::new(a, gg);
            let _ = forced.set_rotor([0.5, -0.2, 0.3]);
            let _ = forced.step_state(&mut s);
            for _ in 0..STEPS {
                let _ = forced.step_state(core::hint::black_box(&mut s));
            }
            return s.m[0] + s.q[0];
        }
        let _ = a.step_state(&mut s);
        if REGIME.as_bytes()[0] == b'm' {
            for _ in 0..STEPS {
                let _ = a.step(core::hint::black_box(&mut s.m));
            }
            return s.m[0];
        }
        for _ in 0..STEPS {
            match REGIME.as_bytes()[0] {
                b'j' => a.set_step_size(h * (1.0 + 0.1 * (noise.uniform() - 0.5))),
                b'c' => {
                    for x in s.m.iter_mut() {
                        *x *= 1.0 + 2e-4 * (noise.uniform() - 0.5);
                    }
                }
                _ => {}
            }
            let _ = a.step_state(core::hint::black_box(&mut s));
        }
        s.m[0] + s.q[0]
    }

    #[entry]
    fn main() -> ! {
        let body = Body::<f32>::from_inertia([125.0, 96.0, 54.0]).unwrap_or_else(|_| exit_now());
        let h = 1.0f32 / 200.0;
        let s0 = State::new([7.5, -3.8, 5.9], [1.0, 0.0, 0.0, 0.0]);
        let out = match METHOD {
            "mv" => run(Mv::new(body, h), h, s0),
            "pre-mv4" => run(PreMv::new(body, h, 4).unwrap_or_else(|_| exit_now()), h, s0),
            _ => run(
                PreMv::new(body, h, 10).unwrap_or_else(|_| exit_now()),
                h,
                s0,
            ),
        };
        defmt::println!(
            "profile {=str} {=str}: {=u32} steps, {=f32}",
            METHOD,
            REGIME,
            STEPS,
            out
        );
        exit(EXIT_SUCCESS);
        loop {
            cortex_m::asm::wfi();
        }
    }

    fn exit_now() -> ! {
        exit(EXIT_FAILURE);
        loop {
            cortex_m::asm::wfi();
        }
    }
}
