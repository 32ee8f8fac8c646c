//! The footprint check: the propagator of the README's firmware quick start
//! (`Forced<f32, Mv, GravityGradient>` with wheels set and a measured, guarded `dt` every tick; the same
//! calls, written again here: scripts/downstream compiles the README's own block) alone in a
//! binary, on inputs the compiler
//! cannot see (volatile reads), with a panic handler that calls a symbol that does not exist.
//! `scripts/footprint` builds it at opt-levels 3, `s` and `z` and checks that it links (no
//! panic path), that it holds no libm function and no software double (`__aeabi_d*`), and
//! prints its flash: what a firmware team's own minimal propagator costs.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    println!("footprint: a link-time check, built for thumbv7em-none-eabihf by scripts/footprint");
}

#[cfg(target_os = "none")]
mod firmware {
    use core::ptr::{read_volatile, write_volatile};
    use cortex_m_rt::entry;
    use rigid3::{Body, Forced, GravityGradient, Integrator, Mv, State};

    #[panic_handler]
    fn panic(_: &core::panic::PanicInfo) -> ! {
        extern "C" {
            fn rigid3_footprint_can_panic() -> !;
        }
        // SAFETY: never defined: the link fails if this handler is reachable
        unsafe { rigid3_footprint_can_panic() }
    }

    // the README's state sizes (608 and 372 bytes on this target), kept within budget
    const _: () =
        assert!(core::mem::size_of::<Forced<f32, Mv<f32>, GravityGradient<f32>>>() <= 640);
    const _: () = assert!(core::mem::size_of::<Mv<f32>>() <= 400);

    static mut INPUT: [f32; 8] = [0.0; 8];
    static mut OUTPUT: [f32; 8] = [0.0; 8];

    fn input(k: usize) -> f32 {
        // SAFETY: a plain static read through a volatile pointer, so the value is opaque
        unsafe { read_volatile(core::ptr::addr_of!(INPUT[k % 8])) }
    }

    fn output(k: usize, x: f32) {
        // SAFETY: a plain static write through a volatile pointer
        unsafe { write_volatile(core::ptr::addr_of_mut!(OUTPUT[k % 8]), x) }
    }

    #[entry]
    fn main() -> ! {
        let Ok(body) = Body::<f32>::from_inertia([input(0), input(1), input(2)]) else {
            loop {
                cortex_m::asm::wfi();
            }
        };
        let gravity_gradient = GravityGradient::circular(&body, input(3));
        let mut p = Forced::new(Mv::new(body, input(4)), gravity_gradient);
        let mut s = State::new([input(5), input(6), input(7)], [1.0, 0.0, 0.0, 0.0]);
        loop {
            let wheels = [input(0), input(1), input(2)];
            if p.set_rotor(wheels).is_ok() {
                // the README's guard against a glitched timer reading
                let dt = input(4);
                if (1e-6..=0.01).contains(&dt) {
                    p.set_step_size(dt);
                }
                let _ = p.step_state(&mut s);
            }
            output(0, s.m[0]);
            output(1, s.q[0]);
        }
    }
}
