//! The scalar type every method is written against.
//!
//! All arithmetic in the crate goes through [`Real`], so that the same code runs in `f32` and
//! `f64`, and so that a wrapper type (the lab's flop counter) can observe every operation.
//! This is the only file that calls `libm` (and crate::fpu_sqrt the only unsafe code).

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// A real floating-point scalar: `f32`, `f64`, or a wrapper around one of them.
///
/// The elementary functions are those of `libm` (correctly rounded or within 1 ulp for
/// `sqrt`, `abs`; within 1–2 ulp for the transcendental ones, see libm's notes). Methods that
/// compare or classify (`is_finite`, `<`) are not arithmetic and a counting wrapper need not
/// count them.
pub trait Real:
    Copy
    + Debug
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
{
    /// Machine epsilon: the gap between 1 and the next representable number.
    const EPSILON: Self;
    /// Smallest positive normal number.
    const MIN_POSITIVE: Self;
    /// Largest finite number.
    const MAX: Self;
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;

    /// Converts an `f64` constant, rounding to nearest. Constants are not counted as flops.
    #[must_use]
    fn from_f64(x: f64) -> Self;
    /// Widens (or unwraps) to `f64`; exact for `f32` and `f64`.
    #[must_use]
    fn to_f64(self) -> f64;

    /// Square root, correctly rounded.
    #[must_use]
    fn sqrt(self) -> Self;
    /// Absolute value, exact.
    #[must_use]
    fn abs(self) -> Self;
    /// Sine, libm (about 1 ulp).
    #[must_use]
    fn sin(self) -> Self;
    /// Cosine, libm (about 1 ulp).
    #[must_use]
    fn cos(self) -> Self;
    /// `(sin x, cos x)`: by default the two calls above (libm, about 1 ulp each). A type
    /// whose sine and cosine can share their work (one reduction, a polynomial pair, as
    /// [`crate::sin_cos`]) overrides it; the splitting's rotations take both at once.
    #[must_use]
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        (Real::sin(self), Real::cos(self))
    }
    /// Arc cosine, libm (about 1 ulp).
    #[must_use]
    fn acos(self) -> Self;
    /// Two-argument arc tangent, libm (about 2 ulp).
    #[must_use]
    fn atan2(self, x: Self) -> Self;
    /// Cube root, libm (about 1 ulp).
    #[must_use]
    fn cbrt(self) -> Self;
    /// Natural logarithm, libm (about 1 ulp).
    #[must_use]
    fn ln(self) -> Self;
    /// Exponential, libm (about 1 ulp).
    #[must_use]
    fn exp(self) -> Self;

    /// True unless NaN or infinite.
    #[must_use]
    fn is_finite(self) -> bool;

    /// True if none of `self`, `b`, `c` is NaN or infinite: a classification (a counting
    /// wrapper need not count it). On hard-float ARM, `f32` and `f64` test
    /// `(a - a) + (b - b) + (c - c) == 0`, which is NaN, hence false, exactly when an input is
    /// NaN or infinite: one comparison instead of three (on a Cortex-M4F about 8 instructions
    /// instead of 15; in software floating point the three bit tests are cheaper, and on x86
    /// the two measure the same).
    #[inline]
    #[must_use]
    fn all_finite3(self, b: Self, c: Self) -> bool {
        self.is_finite() && b.is_finite() && c.is_finite()
    }

    /// The larger of two numbers; `self` if `other` is NaN.
    #[inline]
    #[must_use]
    fn max(self, other: Self) -> Self {
        if other > self {
            other
        } else {
            self
        }
    }
    /// The smaller of two numbers; `self` if `other` is NaN.
    #[inline]
    #[must_use]
    fn min(self, other: Self) -> Self {
        if other < self {
            other
        } else {
            self
        }
    }
    /// `|self|` with the sign of `sign`.
    #[inline]
    #[must_use]
    fn copysign(self, sign: Self) -> Self {
        let a = self.abs();
        if sign < Self::ZERO {
            -a
        } else {
            a
        }
    }
}

macro_rules! impl_real {
    ($t:ty, $sqrt:ident, $sin:ident, $cos:ident, $acos:ident, $atan2:ident, $cbrt:ident, $ln:ident, $exp:ident) => {
        impl Real for $t {
            const EPSILON: Self = <$t>::EPSILON;
            const MIN_POSITIVE: Self = <$t>::MIN_POSITIVE;
            const MAX: Self = <$t>::MAX;
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;

            #[inline]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline]
            fn sqrt(self) -> Self {
                $sqrt(self)
            }
            #[inline]
            fn abs(self) -> Self {
                // core's: one VABS on an FPU (a comparison and a branch were four instructions)
                <$t>::abs(self)
            }
            #[inline]
            fn sin(self) -> Self {
                libm::$sin(self)
            }
            #[inline]
            fn cos(self) -> Self {
                libm::$cos(self)
            }
            #[inline]
            fn acos(self) -> Self {
                libm::$acos(self)
            }
            #[inline]
            fn atan2(self, x: Self) -> Self {
                libm::$atan2(self, x)
            }
            #[inline]
            fn cbrt(self) -> Self {
                libm::$cbrt(self)
            }
            #[inline]
            fn ln(self) -> Self {
                libm::$ln(self)
            }
            #[inline]
            fn exp(self) -> Self {
                libm::$exp(self)
            }
            #[inline]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline]
            #[allow(clippy::eq_op)] // x - x is the point
            fn all_finite3(self, b: Self, c: Self) -> bool {
                if cfg!(all(target_arch = "arm", target_abi = "eabihf")) {
                    // x - x is +0 for every finite x (round to nearest) and NaN otherwise
                    (self - self) + (b - b) + (c - c) == 0.0
                } else {
                    self.is_finite() && b.is_finite() && c.is_finite()
                }
            }
        }
    };
}

impl_real!(f32, sqrt_f32, sinf, cosf, acosf, atan2f, cbrtf, logf, expf);
impl_real!(f64, sqrt_f64, sin, cos, acos, atan2, cbrt, log, exp);

/// The correctly rounded `f32` square root: the FPU's instruction on hard-float ARM
/// (crate::fpu_sqrt; libm computes it in software there), libm's elsewhere (an instruction on
/// x86 and aarch64).
#[inline]
fn sqrt_f32(x: f32) -> f32 {
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    {
        crate::fpu_sqrt::sqrtf(x)
    }
    #[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
    {
        libm::sqrtf(x)
    }
}

/// The correctly rounded `f64` square root (libm; in software on an FPU without double
/// precision such as the Cortex-M4F's).
#[inline]
fn sqrt_f64(x: f64) -> f64 {
    libm::sqrt(x)
}

/// `x * x`.
#[inline]
pub(crate) fn sq<T: Real>(x: T) -> T {
    x * x
}

/// A small integer or simple constant as `T` (not counted as a flop).
#[inline]
pub(crate) fn c<T: Real>(x: f64) -> T {
    T::from_f64(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-comparison finiteness test against three `is_finite` calls, on every triple of
    /// special and ordinary values (NaN, infinities, signed zeros, subnormals, the extremes).
    #[allow(clippy::eq_op)] // x - x is the point
    fn all_finite3_agrees<T: Real>(values: &[T]) {
        for &a in values {
            for &b in values {
                for &c in values {
                    let want = a.is_finite() && b.is_finite() && c.is_finite();
                    assert_eq!(a.all_finite3(b, c), want, "{a:?} {b:?} {c:?}");
                    // the hard-float ARM form, evaluated here too (same IEEE arithmetic)
                    let trick = (a - a) + (b - b) + (c - c) == T::ZERO;
                    assert_eq!(trick, want, "{a:?} {b:?} {c:?}");
                }
            }
        }
    }

    #[test]
    fn all_finite3_is_three_is_finite_tests() {
        all_finite3_agrees(&[
            0.0f32,
            -0.0,
            1.5,
            -3.0e-41,
            f32::MIN_POSITIVE,
            f32::MAX,
            -f32::MAX,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ]);
        all_finite3_agrees(&[
            0.0f64,
            -0.0,
            1.5,
            -5.0e-320,
            f64::MIN_POSITIVE,
            f64::MAX,
            -f64::MAX,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ]);
    }

    /// The FPU's square root is libm's, bit for bit (on hard-float ARM this runs on the target
    /// only; on the host both sides are libm and the test checks the wrapper).
    #[test]
    fn sqrt_f32_is_correctly_rounded() {
        let mut x = 1.0e-38f32;
        while x < 1.0e38 {
            assert_eq!(Real::sqrt(x).to_bits(), libm::sqrtf(x).to_bits());
            // and against f64: the correctly rounded root of an f32 is the f64 root rounded
            let wide = (x as f64).sqrt() as f32;
            assert_eq!(Real::sqrt(x).to_bits(), wide.to_bits(), "{x}");
            x *= 1.37;
        }
    }
}
