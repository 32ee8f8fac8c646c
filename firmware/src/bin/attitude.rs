//! Attitude estimation on an emulated Cortex-M4F (`thumbv7em-none-eabihf`, QEMU `mps2-an386`).
//!
//! A tumbling spacecraft with a full (non-diagonal) inertia tensor. On the target:
//! - truth: `PreMv` of order 10 in f64 (error ~1e-12 over the run) at the loop rate;
//! - sensors, simulated with seeded noise behind an `embedded_hal::i2c::I2c` register map so a
//!   board's HAL drops in: a rate gyro with a constant bias at the loop rate (200 Hz) and a star
//!   tracker (attitude quaternion) at 1 Hz;
//! - the estimator: attitude and body momentum propagated with `Mv` in f32 at 200 Hz, corrected
//!   by a complementary filter (see `Estimator`);
//! - measurements: instructions per propagation step of six methods (SysTick under
//!   `-icount shift=0` counts one tick per 40 instructions: QEMU counts instructions, not
//!   cycles), their invariant drift, the stack high-water mark, and the estimator's error.
//!
//! Logs go out as defmt frames over semihosting (`defmt-print -e ELF` decodes them); the
//! firmware exits 0 only when the estimator meets its accuracy bound and the invariants hold.
//! Run with `scripts/demo` (or `scripts/firmware`).
#![cfg_attr(target_os = "none", no_std, no_main)]
// index loops read like the filter equations
#![allow(clippy::needless_range_loop)]

#[cfg(not(target_os = "none"))]
fn main() {
    println!("attitude: firmware for thumbv7em-none-eabihf; run it with scripts/firmware");
}

#[cfg(target_os = "none")]
mod firmware {
    use core::convert::Infallible;
    use cortex_m::peripheral::syst::SystClkSource;
    use cortex_m::peripheral::SYST;
    use cortex_m_rt::entry;
    use cortex_m_semihosting::debug::{exit, EXIT_FAILURE, EXIT_SUCCESS};
    use defmt_semihosting as _;
    use embedded_hal::i2c::{I2c, Operation};
    use heapless::Vec as HVec;
    use rigid3::{
        Body, ConstantTorque, Forced, Integrator, Mv, NoTorque, PreMv, Quaternion, Real, Rk4,
        SeedMv, Splitting, State, StepError,
    };

    /// `f32` whose `sin` and `cos` are micromath's approximations (about 1e-3 absolute error,
    /// no libm call): everything else is `f32`. Shows the `Real` trait taking a wrapper, and
    /// what the splitting costs when its trigonometry is cheap and inaccurate.
    #[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
    pub struct Fast(pub f32);

    macro_rules! fast_op {
        ($tr:ident, $f:ident, $tra:ident, $fa:ident, $op:tt) => {
            impl core::ops::$tr for Fast {
                type Output = Fast;
                #[inline]
                fn $f(self, o: Fast) -> Fast {
                    Fast(self.0 $op o.0)
                }
            }
            impl core::ops::$tra for Fast {
                #[inline]
                fn $fa(&mut self, o: Fast) {
                    self.0 = self.0 $op o.0;
                }
            }
        };
    }
    fast_op!(Add, add, AddAssign, add_assign, +);
    fast_op!(Sub, sub, SubAssign, sub_assign, -);
    fast_op!(Mul, mul, MulAssign, mul_assign, *);
    impl core::ops::Div for Fast {
        type Output = Fast;
        #[inline]
        fn div(self, o: Fast) -> Fast {
            Fast(self.0 / o.0)
        }
    }
    impl core::ops::Neg for Fast {
        type Output = Fast;
        #[inline]
        fn neg(self) -> Fast {
            Fast(-self.0)
        }
    }
    impl Real for Fast {
        const EPSILON: Self = Fast(f32::EPSILON);
        const MIN_POSITIVE: Self = Fast(f32::MIN_POSITIVE);
        const MAX: Self = Fast(f32::MAX);
        const ZERO: Self = Fast(0.0);
        const ONE: Self = Fast(1.0);
        fn from_f64(x: f64) -> Self {
            Fast(x as f32)
        }
        fn to_f64(self) -> f64 {
            self.0 as f64
        }
        fn sqrt(self) -> Self {
            Fast(Real::sqrt(self.0))
        }
        fn abs(self) -> Self {
            Fast(Real::abs(self.0))
        }
        fn sin(self) -> Self {
            Fast(micromath::F32Ext::sin(self.0))
        }
        fn cos(self) -> Self {
            Fast(micromath::F32Ext::cos(self.0))
        }
        fn acos(self) -> Self {
            Fast(Real::acos(self.0))
        }
        fn atan2(self, x: Self) -> Self {
            Fast(Real::atan2(self.0, x.0))
        }
        fn cbrt(self) -> Self {
            Fast(Real::cbrt(self.0))
        }
        fn ln(self) -> Self {
            Fast(Real::ln(self.0))
        }
        fn exp(self) -> Self {
            Fast(Real::exp(self.0))
        }
        fn is_finite(self) -> bool {
            self.0.is_finite()
        }
    }

    #[panic_handler]
    fn panic(_: &core::panic::PanicInfo) -> ! {
        defmt::error!("panic");
        exit(EXIT_FAILURE);
        loop {
            cortex_m::asm::wfi();
        }
    }

    // ---------------------------------------------------------------- scene

    /// Inertia tensor of the spacecraft in its body (sensor) frame, kg m^2.
    const TENSOR: [[f64; 3]; 3] = [[120.0, -4.0, 2.5], [-4.0, 95.0, 6.0], [2.5, 6.0, 60.0]];
    /// Initial angular velocity in the body frame, rad/s: a tumble.
    const OMEGA0: [f64; 3] = [0.06, -0.04, 0.11];
    /// Loop rate and step.
    const RATE_HZ: u32 = 200;
    const H: f64 = 1.0 / RATE_HZ as f64;
    /// Simulated time: 10 minutes.
    const SECONDS: u32 = 600;
    /// Star tracker: one measurement per second, noise (1 sigma per axis), rad.
    const STAR_SIGMA: f32 = 5e-4;
    /// Gyro: white noise (1 sigma per axis and sample), rad/s, and constant bias, rad/s.
    const GYRO_SIGMA: f32 = 2e-4;
    const GYRO_BIAS: [f32; 3] = [1.5e-3, -1.0e-3, 0.5e-3];
    /// The accuracy bound on the attitude error after the first 30 s (see README: the filter
    /// averages star-tracker noise to about 0.42 sigma per axis, 0.73 sigma in angle; the
    /// bound is 4x that, 1.5e-3 rad = 0.086 deg).
    const ATTITUDE_BOUND: f32 = 1.5e-3;

    // ---------------------------------------------------------------- small math

    // the quaternion algebra is the library's (rigid3::Quaternion, order [w, x, y, z]); these
    // adapt it to the plain arrays the filter's equations are written in
    fn qmul<T: Real>(a: [T; 4], b: [T; 4]) -> [T; 4] {
        Quaternion::from_array(a)
            .compose(Quaternion::from_array(b))
            .to_array()
    }
    fn qmulf(a: [f32; 4], b: [f32; 4]) -> [f32; 4] {
        qmul(a, b)
    }
    fn conj<T: Real>(q: [T; 4]) -> [T; 4] {
        Quaternion::from_array(q).conjugate().to_array()
    }
    /// `R(q) v`.
    fn rotate<T: Real>(q: [T; 4], v: [T; 3]) -> [T; 3] {
        Quaternion::from_array(q).rotate(v)
    }
    fn normalized(q: [f32; 4]) -> [f32; 4] {
        Quaternion::from_array(q)
            .normalize()
            .map_or(q, Quaternion::to_array)
    }
    /// Rotation angle between two attitudes, rad.
    fn angle(a: [f32; 4], b: [f32; 4]) -> f32 {
        let d = qmulf(conj(a), b);
        let v = Real::sqrt(d[1] * d[1] + d[2] * d[2] + d[3] * d[3]);
        2.0 * Real::atan2(v, Real::abs(d[0]))
    }

    /// xorshift32 and a 4-uniform Irwin–Hall approximation of a unit normal: seeded, cheap.
    struct Noise(u32);
    impl Noise {
        fn uniform(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 17;
            self.0 ^= self.0 << 5;
            (self.0 >> 8) as f32 * (1.0 / 16_777_216.0)
        }
        fn normal(&mut self) -> f32 {
            // sum of 4 uniforms: mean 2, variance 1/3
            let s = self.uniform() + self.uniform() + self.uniform() + self.uniform();
            (s - 2.0) * 1.732_050_8
        }
    }

    // ---------------------------------------------------------------- simulated sensors

    /// The simulated sensor board: an I2C target with a register map.
    /// `0x00..0x0c`: gyro rate (x, y, z) as little-endian f32, body frame, rad/s;
    /// `0x10..0x20`: star tracker quaternion (w, x, y, z) body to space, f32;
    /// `0x20`: status, bit 0 = a new star tracker fix since the last read of `0x10`.
    pub struct SimBoard {
        regs: [u8; 0x24],
        pointer: usize,
    }

    pub const BOARD_ADDR: u8 = 0x68;

    impl SimBoard {
        fn new() -> Self {
            Self {
                regs: [0; 0x24],
                pointer: 0,
            }
        }
        fn put(&mut self, at: usize, v: f32) {
            self.regs[at..at + 4].copy_from_slice(&v.to_le_bytes());
        }
        fn set_gyro(&mut self, w: [f32; 3]) {
            self.put(0x00, w[0]);
            self.put(0x04, w[1]);
            self.put(0x08, w[2]);
        }
        fn set_star(&mut self, q: [f32; 4]) {
            self.put(0x10, q[0]);
            self.put(0x14, q[1]);
            self.put(0x18, q[2]);
            self.put(0x1c, q[3]);
            self.regs[0x20] |= 1;
        }
    }

    impl embedded_hal::i2c::ErrorType for SimBoard {
        type Error = Infallible;
    }

    impl I2c for SimBoard {
        fn transaction(
            &mut self,
            _address: u8,
            operations: &mut [Operation<'_>],
        ) -> Result<(), Infallible> {
            for op in operations {
                match op {
                    Operation::Write(bytes) => {
                        if let Some(&r) = bytes.first() {
                            self.pointer = r as usize;
                        }
                    }
                    Operation::Read(buf) => {
                        let start = self.pointer.min(self.regs.len());
                        let end = (start + buf.len()).min(self.regs.len());
                        buf[..end - start].copy_from_slice(&self.regs[start..end]);
                        if start <= 0x10 && end > 0x10 {
                            self.regs[0x20] &= !1;
                        }
                        self.pointer = end;
                    }
                }
            }
            Ok(())
        }
    }

    /// The sensor driver, generic over any `embedded-hal` I2C bus.
    pub struct Sensors<B> {
        bus: B,
    }

    impl<B: I2c> Sensors<B> {
        fn f32s<const N: usize>(&mut self, reg: u8) -> Result<[f32; N], B::Error> {
            let mut raw = [0u8; 16];
            self.bus.write_read(BOARD_ADDR, &[reg], &mut raw[..4 * N])?;
            let mut out = [0.0f32; N];
            for (k, o) in out.iter_mut().enumerate() {
                *o = f32::from_le_bytes([
                    raw[4 * k],
                    raw[4 * k + 1],
                    raw[4 * k + 2],
                    raw[4 * k + 3],
                ]);
            }
            Ok(out)
        }
        pub fn gyro(&mut self) -> Result<[f32; 3], B::Error> {
            self.f32s(0x00)
        }
        /// A new star tracker fix, if there is one.
        pub fn star(&mut self) -> Result<Option<[f32; 4]>, B::Error> {
            let mut status = [0u8];
            self.bus.write_read(BOARD_ADDR, &[0x20], &mut status)?;
            if status[0] & 1 == 0 {
                return Ok(None);
            }
            self.f32s(0x10).map(Some)
        }
    }

    // ---------------------------------------------------------------- estimator

    /// Complementary filter around the `Mv` propagation (all f32, principal frame).
    ///
    /// Why this filter: the dynamics are known exactly (a free body), so the model carries the
    /// attitude between star-tracker fixes with no drift of its own; what needs correcting is
    /// the momentum (from the gyro, whose bias is estimated) and the slow attitude error (from
    /// the star tracker). A multiplicative EKF would also estimate a covariance, at about ten
    /// times the arithmetic, for the same steady-state error with white noise of known size;
    /// a constant-gain complementary filter is its fixed point and fits a few hundred bytes.
    /// - momentum: `m <- m + K_M (I (w_gyro - b) - m)` every step;
    /// - attitude: at each fix, the body-frame error rotation `theta` (small angle) is fed
    ///   back as `q <- q (x) exp(K_Q theta / 2)`;
    /// - bias: `b <- b - K_B theta / T_fix` (a persistent rate error shows up as a persistent
    ///   attitude error over the fix interval).
    struct Estimator {
        mv: Mv<f32>,
        s: State<f32>,
        bias: [f32; 3],
        inertia: [f32; 3],
        /// principal frame in the body frame (x_body = R(frame) x_principal)
        frame: [f32; 4],
    }

    const K_M: f32 = 0.02;
    const K_Q: f32 = 0.3;
    const K_B: f32 = 0.05;

    impl Estimator {
        fn propagate(&mut self, gyro_body: [f32; 3]) -> Result<(), StepError> {
            let w = [
                gyro_body[0] - self.bias[0],
                gyro_body[1] - self.bias[1],
                gyro_body[2] - self.bias[2],
            ];
            let wp = rotate(conj(self.frame), w);
            for k in 0..3 {
                let mg = self.inertia[k] * wp[k];
                self.s.m[k] += K_M * (mg - self.s.m[k]);
            }
            self.mv.step_state(&mut self.s)
        }

        fn correct(&mut self, star_body: [f32; 4], interval: f32) {
            // measured principal-frame attitude, and the error rotation in the principal frame
            let meas = qmulf(star_body, self.frame);
            let mut d = qmulf(conj(self.s.q), meas);
            if d[0] < 0.0 {
                d = [-d[0], -d[1], -d[2], -d[3]];
            }
            let theta = [2.0 * d[1], 2.0 * d[2], 2.0 * d[3]];
            let dq = [
                1.0,
                0.5 * K_Q * theta[0],
                0.5 * K_Q * theta[1],
                0.5 * K_Q * theta[2],
            ];
            self.s.q = normalized(qmulf(self.s.q, dq));
            let tb = rotate(self.frame, theta);
            for k in 0..3 {
                self.bias[k] -= K_B * tb[k] / interval;
            }
        }

        fn attitude_body(&self) -> [f32; 4] {
            qmulf(self.s.q, conj(self.frame))
        }
    }

    // ---------------------------------------------------------------- instruction counting

    /// Instructions executed by `f`, from SysTick (one tick per 40 instructions under
    /// `-icount shift=0`); `f` must stay under 2^24 ticks (671M instructions).
    fn instructions(f: impl FnOnce()) -> u32 {
        let t0 = SYST::get_current();
        f();
        let t1 = SYST::get_current();
        (t0.wrapping_sub(t1) & 0x00ff_ffff) * 40
    }

    const BENCH_STEPS: u32 = 2000;

    /// Momentum steps of one method on the spacecraft (f32, h = 1/200 s): instructions per
    /// step (empty-loop overhead removed) and the relative drift of |m|^2, E and R(q) m.
    fn bench<T: Real, I: Integrator<T>>(
        mut a: I,
        body: Body<T>,
        m0: [T; 3],
        overhead: u32,
    ) -> (u32, [f32; 3], bool) {
        let mut m = m0;
        let mut ok = true;
        let _ = a.step(&mut m); // set-up outside the count
        let n = instructions(|| {
            for _ in 0..BENCH_STEPS {
                ok &= a.step(core::hint::black_box(&mut m)).is_ok();
            }
        });
        let per = n.saturating_sub(overhead) / BENCH_STEPS;
        // drift over a longer attitude run (10^4 steps = 50 s)
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
        (
            per,
            [
                rel(body.casimir(&s.m), c0),
                rel(body.energy(&s.m), e0),
                dp.to_f64() as f32,
            ],
            ok,
        )
    }

    // The step functions as separate symbols, so their code size can be read from the ELF.
    #[inline(never)]
    #[no_mangle]
    fn rigid3_mv_step(a: &mut Mv<f32>, m: &mut [f32; 3]) -> bool {
        a.step(m).is_ok()
    }
    #[inline(never)]
    #[no_mangle]
    fn rigid3_mv_step_state(a: &mut Mv<f32>, s: &mut State<f32>) -> bool {
        a.step_state(s).is_ok()
    }

    // ---------------------------------------------------------------- the loop's regimes

    /// Instructions per step of `f(k)` (k = 0..BENCH_STEPS) less `base` per step.
    fn per_step(base: u32, mut f: impl FnMut(u32)) -> u32 {
        let n = instructions(|| {
            for k in 0..BENCH_STEPS {
                f(k);
            }
        });
        (n / BENCH_STEPS).saturating_sub(base)
    }

    /// Instructions per f32 step with attitude in the four regimes of the real loop: fixed
    /// `h`; `h` jittered by +-5% every step (`set_step_size`); `m` corrected every step by
    /// 1e-4 relative (a filter); a torque kick every step (the forced kick–drift–kick with
    /// the torque given). The perturbation's own cost is measured alone and removed.
    /// Returns `[fixed, jitter, corrected, torque]`.
    fn regimes<I: Integrator<f32> + Clone>(a0: I, s0: State<f32>, h: f32) -> [u32; 4] {
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
        let mut forced = Forced::new(a0, NoTorque);
        let tau = [2e-4f32, -1e-4, 5e-5];
        let neg = tau.map(|x| -x);
        let mut s = s0;
        let _ = forced.step_state(&mut s);
        let torque = per_step(empty, |k| {
            let t = if k % 2 == 0 { tau } else { neg };
            let _ = forced.step_state_with(core::hint::black_box(&mut s), t, t);
        });
        [fixed, jitter, corrected, torque]
    }

    // ---------------------------------------------------------------- stack painting

    const PAINT: u32 = 0xC0FF_EE55;
    const PAINT_WORDS: usize = 8 * 1024; // 32 KiB below the current stack pointer

    fn paint_stack() -> usize {
        let sp = cortex_m::register::msp::read() as usize;
        let bottom = sp - 256 - PAINT_WORDS * 4;
        for k in 0..PAINT_WORDS {
            // SAFETY: the words between `bottom` and `sp - 256` are unused stack in RAM
            unsafe { core::ptr::write_volatile((bottom + 4 * k) as *mut u32, PAINT) };
        }
        bottom
    }

    fn stack_used(bottom: usize, top: usize) -> usize {
        let mut k = 0;
        // SAFETY: reads back the words painted above
        while k < PAINT_WORDS
            && unsafe { core::ptr::read_volatile((bottom + 4 * k) as *const u32) } == PAINT
        {
            k += 1;
        }
        top - (bottom + 4 * k)
    }

    // ---------------------------------------------------------------- main

    #[entry]
    fn main() -> ! {
        let top = 0x2040_0000usize; // ORIGIN(RAM) + LENGTH(RAM), where cortex-m-rt puts the stack
        let bottom = paint_stack();
        let cp = cortex_m::Peripherals::take();
        let Some(cp) = cp else {
            exit(EXIT_FAILURE);
            loop {
                cortex_m::asm::wfi();
            }
        };
        let mut syst = cp.SYST;
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(0x00ff_ffff);
        syst.clear_current();
        syst.enable_counter();

        defmt::println!("rigid3 attitude firmware: Cortex-M4F (QEMU mps2-an386), instruction counts from SysTick (QEMU counts instructions, not cycles)");
        let pass = run(top, bottom);
        if pass {
            defmt::println!("PASS");
            exit(EXIT_SUCCESS);
        } else {
            defmt::println!("FAIL");
            exit(EXIT_FAILURE);
        }
        loop {
            cortex_m::asm::wfi();
        }
    }

    fn run(top: usize, bottom: usize) -> bool {
        // the body from its full inertia tensor: principal moments and the principal frame
        let Ok((body64, frame64)) = Body::<f64>::from_inertia_tensor(TENSOR) else {
            return false;
        };
        let tensor32 = TENSOR.map(|r| r.map(|x| x as f32));
        let Ok((body32, frame32)) = Body::<f32>::from_inertia_tensor(tensor32) else {
            return false;
        };
        let i = body64.inertia();
        defmt::println!(
            "spacecraft: principal moments {=f64} {=f64} {=f64} kg m^2",
            i[0],
            i[1],
            i[2]
        );
        // initial state in the principal frame; body-to-space attitude = identity
        let m_body = [
            TENSOR[0][0] * OMEGA0[0] + TENSOR[0][1] * OMEGA0[1] + TENSOR[0][2] * OMEGA0[2],
            TENSOR[1][0] * OMEGA0[0] + TENSOR[1][1] * OMEGA0[1] + TENSOR[1][2] * OMEGA0[2],
            TENSOR[2][0] * OMEGA0[0] + TENSOR[2][1] * OMEGA0[1] + TENSOR[2][2] * OMEGA0[2],
        ];
        let m0 = rotate(conj(frame64), m_body);
        let q0 = frame64; // principal frame to space = (body to space) (x) frame = frame
        let Ok(mut truth) = PreMv::new(body64, H, 10) else {
            return false;
        };
        let mut ts = State::new(m0, q0);

        let mut board = SimBoard::new();
        let mut noise = Noise(0x1234_5678);
        let mut est = Estimator {
            mv: Mv::new(body32, H as f32),
            // start with the first star fix and an uncorrected gyro-based momentum
            s: State::new([0.0; 3], [1.0, 0.0, 0.0, 0.0]),
            bias: [0.0; 3],
            inertia: body32.inertia(),
            frame: frame32,
        };
        let mut errors: HVec<f32, 16> = HVec::new();
        let mut worst_after_30s = 0.0f32;
        let mut failures = 0u32;
        let total = SECONDS * RATE_HZ;
        let mut window = (0u32, 0u32);
        for k in 0..total {
            if k == RATE_HZ {
                window.0 = SYST::get_current();
            }
            if k == 2 * RATE_HZ {
                window.1 = SYST::get_current();
            }
            // truth and sensors
            if truth.step_state(&mut ts).is_err() {
                return false;
            }
            let w_true = body64.angular_velocity(&ts.m);
            let w_body = rotate(frame64, w_true);
            let gyro = [
                w_body[0] as f32 + GYRO_BIAS[0] + GYRO_SIGMA * noise.normal(),
                w_body[1] as f32 + GYRO_BIAS[1] + GYRO_SIGMA * noise.normal(),
                w_body[2] as f32 + GYRO_BIAS[2] + GYRO_SIGMA * noise.normal(),
            ];
            board.set_gyro(gyro);
            let q_body_true = qmul(ts.q, conj(frame64));
            if k % RATE_HZ == 0 {
                let e = [
                    STAR_SIGMA * noise.normal(),
                    STAR_SIGMA * noise.normal(),
                    STAR_SIGMA * noise.normal(),
                ];
                let qe = [1.0, 0.5 * e[0], 0.5 * e[1], 0.5 * e[2]];
                board.set_star(normalized(qmulf(q_body_true.map(|x| x as f32), qe)));
            }
            // the flight software: read through the I2C driver, propagate, correct
            let mut sensors = Sensors { bus: &mut board };
            let Ok(g) = sensors.gyro();
            let star = sensors.star().ok().flatten();
            if k == 0 {
                let Some(q) = star else { return false };
                est.s.q = qmulf(q, est.frame);
                let wp = rotate(conj(est.frame), g);
                est.s.m = [
                    est.inertia[0] * wp[0],
                    est.inertia[1] * wp[1],
                    est.inertia[2] * wp[2],
                ];
                continue;
            }
            if est.propagate(g).is_err() {
                failures += 1;
            }
            if let Some(q) = star {
                est.correct(q, 1.0);
            }
            let err = angle(est.attitude_body(), q_body_true.map(|x| x as f32));
            if k >= 30 * RATE_HZ {
                worst_after_30s = worst_after_30s.max(err);
            }
            if k % (60 * RATE_HZ) == 0 {
                let _ = errors.push(err);
            }
        }
        let loop_instr = (window.0.wrapping_sub(window.1) & 0x00ff_ffff) * 40 / RATE_HZ;
        let final_err = angle(
            est.attitude_body(),
            qmul(ts.q, conj(frame64)).map(|x| x as f32),
        );
        defmt::println!(
            "estimator: 10 min at 200 Hz; attitude error each minute (rad): {=[?]}",
            errors.as_slice()
        );
        defmt::println!(
            "estimator: final error {=f32} rad, worst after 30 s {=f32} rad (bound {=f32}); bias estimate {=f32} {=f32} {=f32} (true {=f32} {=f32} {=f32}); failed steps {=u32}",
            final_err, worst_after_30s, ATTITUDE_BOUND, est.bias[0], est.bias[1], est.bias[2],
            GYRO_BIAS[0], GYRO_BIAS[1], GYRO_BIAS[2], failures
        );
        defmt::println!("one 200 Hz loop (truth in soft-float f64 + sensors + I2C + filter): {=u32} instructions", loop_instr);

        // instructions per momentum step, and drift, for each method (f32)
        let m32 = m0.map(|x| x as f32);
        let overhead = instructions(|| {
            let mut m = m32;
            for _ in 0..BENCH_STEPS {
                core::hint::black_box(&mut m);
            }
        });
        defmt::println!("method        instructions/step   |m|^2 drift   E drift   R(q)m drift   (f32, h = 1/200 s, drift over 10^4 steps)");
        let h = H as f32;
        let (mv_instr, d, ok1) = bench(Mv::new(body32, h), body32, m32, overhead);
        defmt::println!(
            "mv            {=u32}  {=f32}  {=f32}  {=f32}",
            mv_instr,
            d[0],
            d[1],
            d[2]
        );
        let (n, d, ok2) = bench(SeedMv::new(body32, h), body32, m32, overhead);
        defmt::println!(
            "seed-mv       {=u32}  {=f32}  {=f32}  {=f32}",
            n,
            d[0],
            d[1],
            d[2]
        );
        let Ok(pre4) = PreMv::new(body32, h, 4) else {
            return false;
        };
        let (n, d, ok3) = bench(pre4, body32, m32, overhead);
        defmt::println!(
            "pre-mv4       {=u32}  {=f32}  {=f32}  {=f32}",
            n,
            d[0],
            d[1],
            d[2]
        );
        let (n, d, ok4) = bench(Splitting::new(body32, h), body32, m32, overhead);
        defmt::println!(
            "splitting     {=u32}  {=f32}  {=f32}  {=f32}   (libm sinf/cosf)",
            n,
            d[0],
            d[1],
            d[2]
        );
        let Ok(fast_body) = Body::<Fast>::from_inertia(body32.inertia().map(Fast)) else {
            return false;
        };
        let (n, d, ok5) = bench(
            Splitting::new(fast_body, Fast(h)),
            fast_body,
            m32.map(Fast),
            overhead,
        );
        defmt::println!(
            "splitting-mm  {=u32}  {=f32}  {=f32}  {=f32}   (micromath sin/cos)",
            n,
            d[0],
            d[1],
            d[2]
        );
        let (n, d, ok6) = bench(Rk4::new(body32, h), body32, m32, overhead);
        defmt::println!(
            "rk4           {=u32}  {=f32}  {=f32}  {=f32}",
            n,
            d[0],
            d[1],
            d[2]
        );

        // the real loop's regimes, with attitude (f32, h = 1/200 s)
        let s32 = State::new(m32, [1.0f32, 0.0, 0.0, 0.0]);
        defmt::println!("with attitude, instructions/step  fixed  jitter  corrected  torque   (f32; jitter: h +-5% every step; corrected: m by 1e-4; torque: a kick every step)");
        let r = regimes(Mv::new(body32, h), s32, h);
        defmt::println!(
            "mv        {=u32}  {=u32}  {=u32}  {=u32}   ratios to fixed x100: {=u32} {=u32} {=u32}",
            r[0],
            r[1],
            r[2],
            r[3],
            100 * r[1] / r[0].max(1),
            100 * r[2] / r[0].max(1),
            100 * r[3] / r[0].max(1)
        );
        let Ok(pre4) = PreMv::new(body32, h, 4) else {
            return false;
        };
        let r = regimes(pre4, s32, h);
        defmt::println!(
            "pre-mv4   {=u32}  {=u32}  {=u32}  {=u32}   ratios to fixed x100: {=u32} {=u32} {=u32}",
            r[0],
            r[1],
            r[2],
            r[3],
            100 * r[1] / r[0].max(1),
            100 * r[2] / r[0].max(1),
            100 * r[3] / r[0].max(1)
        );
        let Ok(pre10) = PreMv::new(body32, h, 10) else {
            return false;
        };
        let r = regimes(pre10, s32, h);
        defmt::println!(
            "pre-mv10  {=u32}  {=u32}  {=u32}  {=u32}   ratios to fixed x100: {=u32} {=u32} {=u32}",
            r[0],
            r[1],
            r[2],
            r[3],
            100 * r[1] / r[0].max(1),
            100 * r[2] / r[0].max(1),
            100 * r[3] / r[0].max(1)
        );
        // forced steps next to the free one: a torque model (constant body torque) and a rotor
        let mut held = Forced::new(Mv::new(body32, h), ConstantTorque([1e-4f32, 0.0, -1e-4]));
        let mut s = s32;
        let _ = held.step_state(&mut s);
        let model = per_step(0, |_| {
            let _ = held.step_state(core::hint::black_box(&mut s));
        });
        let mut wheels = Forced::new(Mv::new(body32, h), NoTorque);
        let rotor_ok = wheels.set_rotor([0.5f32, -0.2, 0.3]).is_ok();
        let mut s = s32;
        let _ = wheels.step_state(&mut s);
        let rotor = per_step(0, |_| {
            let _ = wheels.step_state(core::hint::black_box(&mut s));
        });
        defmt::println!("forced mv with attitude: torque model (constant) {=u32}, rotor {=u32} instructions/step", model, rotor);

        // 10^6 propagation steps of Mv in f32 with attitude: the invariants' drift
        let mut mv = Mv::new(body32, h);
        let mut s = State::new(m32, [1.0f32, 0.0, 0.0, 0.0]);
        let (c0, e0, p0) = (
            body32.casimir(&m32) as f64,
            body32.energy(&m32) as f64,
            s.spatial_momentum(),
        );
        let mut steps_ok = true;
        for _ in 0..1_000_000u32 {
            steps_ok &= rigid3_mv_step_state(&mut mv, &mut s);
        }
        let mut m_only = m32;
        steps_ok &= rigid3_mv_step(&mut mv, &mut m_only);
        let dc = ((body32.casimir(&s.m) as f64 - c0) / c0).abs();
        let de = ((body32.energy(&s.m) as f64 - e0) / e0).abs();
        let p = s.spatial_momentum();
        let d3 = [
            (p[0] - p0[0]) as f64,
            (p[1] - p0[1]) as f64,
            (p[2] - p0[2]) as f64,
        ];
        let dp = Real::sqrt(d3[0] * d3[0] + d3[1] * d3[1] + d3[2] * d3[2]) / Real::sqrt(c0);
        defmt::println!("mv f32, 10^6 steps with attitude (5000 s): drift |m|^2 {=f64}, E {=f64}, R(q)m {=f64} (bound 1e-4)", dc, de, dp);

        let stack = stack_used(bottom, top);
        defmt::println!(
            "stack high-water mark: {=usize} bytes; heap: none (no allocator is linked)",
            stack
        );

        let attitude_ok =
            worst_after_30s <= ATTITUDE_BOUND && final_err <= ATTITUDE_BOUND && failures == 0;
        let drift_ok = dc <= 1e-4 && de <= 1e-4 && dp <= 1e-4 && steps_ok;
        defmt::println!(
            "mv instructions per momentum step: {=u32} (target <= 400)",
            mv_instr
        );
        attitude_ok && drift_ok && rotor_ok && ok1 && ok2 && ok3 && ok4 && ok5 && ok6
    }
}
