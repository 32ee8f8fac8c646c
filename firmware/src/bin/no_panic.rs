//! Proof that the step functions cannot panic in a release build for the target.
//!
//! Every integrator's `step` and `step_state` (f32 and f64), `Mv`'s and `PreMv`'s
//! `step_with_jacobian` and `Body`'s constructors are called
//! on inputs the compiler cannot see (volatile reads), and the panic handler calls a symbol that
//! does not exist. If any panic path survives optimisation, the link fails with an undefined
//! reference to `rigid3_step_function_can_panic`: building this example for
//! `thumbv7em-none-eabihf --release` is the check (`scripts/test`; the technique of the
//! `no-panic` crate, applied to the whole binary). Running it is not needed.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    println!("no_panic: a link-time check, built for thumbv7em-none-eabihf by scripts/test");
}

#[cfg(target_os = "none")]
mod firmware {
    use core::ptr::{read_volatile, write_volatile};
    use cortex_m_rt::entry;
    use rigid3::{
        Body, Composed, Exact, FnTorque, Forced, ForcedRk4, Gravity, GravityGradient, Integrator,
        Midpoint, Mv, PeriodicTorque, PreMv, Real, RetimedMv, Rk4, SeedMv, Solver, Splitting,
        Splitting2, State, Torque,
    };

    #[panic_handler]
    fn panic(_: &core::panic::PanicInfo) -> ! {
        extern "C" {
            fn rigid3_step_function_can_panic() -> !;
        }
        // SAFETY: never defined: the link fails if this handler is reachable
        unsafe { rigid3_step_function_can_panic() }
    }

    static mut INPUT: [f64; 16] = [0.0; 16];
    static mut OUTPUT: [f64; 8] = [0.0; 8];

    fn input(k: usize) -> f64 {
        // SAFETY: a plain static read through a volatile pointer, so the value is opaque
        unsafe { read_volatile(core::ptr::addr_of!(INPUT[k % 16])) }
    }

    fn output(k: usize, x: f64) {
        // SAFETY: a plain static write through a volatile pointer
        unsafe { write_volatile(core::ptr::addr_of_mut!(OUTPUT[k % 8]), x) }
    }

    fn exercise<T: Real, I: Integrator<T>>(mut a: I, k: usize) {
        let mut m = [
            T::from_f64(input(k)),
            T::from_f64(input(k + 1)),
            T::from_f64(input(k + 2)),
        ];
        let ok = a.step(&mut m).is_ok();
        let mut s = State::new(
            m,
            [
                T::from_f64(input(k + 3)),
                T::ZERO,
                T::ZERO,
                T::from_f64(input(k + 4)),
            ],
        );
        let ok2 = a.step_state(&mut s).is_ok();
        output(
            k,
            s.m[0].to_f64() + s.q[3].to_f64() + ok as u8 as f64 + ok2 as u8 as f64,
        );
    }

    /// Which functions to check (all by default): a compile-time switch for finding a panic
    /// path, `NO_PANIC_ONLY=mv,body cargo build ...`.
    const ONLY: &str = match option_env!("NO_PANIC_ONLY") {
        Some(s) => s,
        None => "",
    };

    const fn wanted(name: &str) -> bool {
        if ONLY.is_empty() {
            return true;
        }
        // a tiny const `contains`
        let (hay, needle) = (ONLY.as_bytes(), name.as_bytes());
        let mut i = 0;
        while i + needle.len() <= hay.len() {
            let mut j = 0;
            while j < needle.len() && hay[i + j] == needle[j] {
                j += 1;
            }
            if j == needle.len()
                && (i + j == hay.len() || hay[i + j] == b',')
                && (i == 0 || hay[i - 1] == b',')
            {
                return true;
            }
            i += 1;
        }
        false
    }

    fn all<T: Real>(k: usize) {
        let i = [
            T::from_f64(input(5)),
            T::from_f64(input(6)),
            T::from_f64(input(7)),
        ];
        let h = T::from_f64(input(8));
        let Ok(body) = Body::from_inertia(i) else {
            return;
        };
        if wanted("body") {
            if let Ok(b) = Body::<T>::from_mass_matrix(i) {
                output(1, b.energy(&i).to_f64());
            }
        }
        let t = [
            [i[0], T::from_f64(input(9)), T::from_f64(input(10))],
            [T::from_f64(input(9)), i[1], T::from_f64(input(11))],
            [T::from_f64(input(10)), T::from_f64(input(11)), i[2]],
        ];
        if wanted("tensor") {
            if let Ok((b, q)) = Body::from_inertia_tensor(t) {
                output(2, b.inertia()[0].to_f64() + q[0].to_f64());
            }
        }
        if wanted("max_step") {
            output(3, Mv::max_step(&body, &i).to_f64());
        }
        if wanted("mv") {
            exercise(Mv::new(body, h), k);
        }
        if wanted("jacobian") {
            // the step with its tangent map, on an opaque state
            let mut s = State::new(
                [
                    T::from_f64(input(k)),
                    T::from_f64(input(k + 1)),
                    T::from_f64(input(k + 2)),
                ],
                [
                    T::from_f64(input(k + 3)),
                    T::ZERO,
                    T::ZERO,
                    T::from_f64(input(k + 4)),
                ],
            );
            if let Ok(f) = Mv::new(body, h).step_with_jacobian(&mut s) {
                output(5, f[0][0].to_f64() + f[5][5].to_f64());
            }
            if let Ok(mut a) = PreMv::new(body, h, 8) {
                if let Ok(f) = a.step_with_jacobian(&mut s) {
                    output(6, f[2][3].to_f64() + s.q[0].to_f64());
                }
            }
        }
        if wanted("seed") {
            exercise(SeedMv::new(body, h), k + 1);
        }
        if wanted("pre") {
            if let Ok(a) = PreMv::new(body, h, 10) {
                exercise(a, k + 2);
            }
        }
        if wanted("retimed") {
            if let Ok(a) = RetimedMv::new(body, h, 4) {
                exercise(a, k + 3);
            }
        }
        if wanted("splitting") {
            exercise(Splitting::new(body, h), k + 4);
            exercise(Splitting2::new(body, h), k + 5);
        }
        if wanted("midpoint") {
            exercise(Midpoint::new(body, h), k + 6);
            exercise(Midpoint::with_solver(body, h, Solver::FixedPoint), k + 7);
        }
        if wanted("rk4") {
            exercise(Rk4::new(body, h), k + 8);
        }
        if wanted("exact") {
            exercise(Exact::new(body, h), k + 9);
        }
        if wanted("forced") {
            let g = Gravity {
                mg: T::from_f64(input(12)),
                com: [input(13), input(14), input(15)].map(T::from_f64),
            };
            let p = PeriodicTorque {
                amplitude: [input(16), input(17), input(18)].map(T::from_f64),
                freq: [input(19), input(20), input(21)].map(T::from_f64),
                phase: [input(22), input(23), input(24)].map(T::from_f64),
            };
            let gg = GravityGradient {
                k: T::from_f64(input(25)),
                n: T::from_f64(input(26)),
                inertia: i,
            };
            let torque = (g, (p, gg));
            let rotor = [input(27), input(28), input(29)].map(T::from_f64);
            let mut f = Forced::new(Mv::new(body, h), torque);
            let _ = f.set_rotor(rotor);
            exercise(f, k + 10);
            if let Ok(pre) = PreMv::new(body, h, 6) {
                let mut f = Forced::new(pre, torque);
                let _ = f.set_rotor(rotor);
                let mut s = State::new(i, [T::ONE, T::ZERO, T::ZERO, T::ZERO]);
                let tau = [input(30), input(31), input(32)].map(T::from_f64);
                output(4, f.step_state_with(&mut s, tau, tau).is_ok() as u8 as f64);
            }
            if let Ok(mut c) = Composed::new(Mv::new(body, h), torque, 6) {
                let _ = c.set_rotor(rotor);
                exercise(c, k + 11);
            }
            if let Ok(pre) = PreMv::new(body, h, 10) {
                if let Ok(mut c) = Composed::nystrom(pre, torque, 4) {
                    let _ = c.set_rotor(rotor);
                    exercise(c, k + 11);
                }
            }
            // the force-gradient kick: the models' turn rates, and a closure's turned
            // evaluation
            if let Ok(pre) = PreMv::new(body, h, 6) {
                if let Ok(c) = Composed::force_gradient(pre.clone(), torque) {
                    exercise(c, k + 11);
                }
                let closure = FnTorque(move |t: T, q: &[T; 4]| torque.torque(t, q));
                if let Ok(c) = Composed::force_gradient(pre, closure) {
                    exercise(c, k + 11);
                }
            }
            let mut r = ForcedRk4::new(body, h, torque);
            let _ = r.set_rotor(rotor);
            exercise(r, k + 12);
        }
    }

    #[entry]
    fn main() -> ! {
        all::<f32>(0);
        all::<f64>(3);
        loop {
            cortex_m::asm::wfi();
        }
    }
}
