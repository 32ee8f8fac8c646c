//! `sqrt` of an `f32` by the FPU's `VSQRT.F32` on 32-bit ARM with a hard-float ABI.
//!
//! libm 0.2 has no ARM implementation of `sqrtf`, so on a Cortex-M4F it computes the root
//! bit by bit in software (about 35 instructions a call, two calls in every step with
//! attitude: `scripts/profile` showed 70 of `Mv`'s 805 instructions a step there), and
//! `core` has no stable `f32::sqrt`. Every `eabihf` ARM target has an FPU with `VSQRT.F32`
//! (VFPv2 and later, FPv4-SP of the Cortex-M4F, FPv5 of the M7 and M33), which is IEEE 754's
//! correctly rounded square root: the same result as libm's, bit for bit, in one instruction
//! (14 cycles on the M4F).
//!
//! The operand goes through a core register and `s0`, which is saved and restored around
//! it: stable Rust does not let `asm!` name the `sreg` class on `thumbv7em-none-eabihf`
//! (its `vfp2` feature is not a stable `target_feature`).
#![allow(unsafe_code)]

/// The correctly rounded square root of `x` (NaN for `x < 0`, as IEEE 754 and libm).
#[inline]
pub(crate) fn sqrtf(x: f32) -> f32 {
    let r: u32;
    // SAFETY: five FPU register moves and one VSQRT; `s0` is restored before the block ends,
    // no memory or stack is touched, and the result depends on the input alone.
    unsafe {
        core::arch::asm!(
            "vmov {t}, s0",
            "vmov s0, {x}",
            "vsqrt.f32 s0, s0",
            "vmov {r}, s0",
            "vmov s0, {t}",
            x = in(reg) x.to_bits(),
            r = lateout(reg) r,
            t = out(reg) _,
            options(pure, nomem, nostack)
        );
    }
    f32::from_bits(r)
}
