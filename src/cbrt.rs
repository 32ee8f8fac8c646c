//! `cbrt x` in the generic `T` arithmetic, without libm: the cubic's scale and its one-real-root
//! (Cardano) branch (crate::cubic). libm's `cbrtf` computes in double, software on a
//! Cortex-M4F (crate::asin's module docs for what that costs a firmware).
//!
//! # Derivation
//!
//! `cbrt(8^k y) = 2^k cbrt(y)`, and multiplying by a power of two is exact (also into and
//! out of the subnormal range, for the factors used here: `y` is brought into `[1, 8)`
//! before anything is rounded). So `y` is scaled into `[1, 8)` by factors `2^(+-48)`, then
//! `2^(+-3)` (bounded loops: at most 23 and 16 rounds in f64, 3 and 16 in f32), and
//! `g = cbrt(y)` in `[1, 2)` comes from the quadratic through `(1, 1)`, `(27/8, 3/2)`,
//! `(8, 2)` (relative error below 2.5 %), then Newton's method on `g^3 = y`,
//!
//! `g <- g - (g^3 - y) / (3 g^2)`,
//!
//! which squares the relative error (about `e -> e^2`): below `6.2e-4`, `3.8e-7`, `1.5e-13`,
//! `2e-26` after one to four steps (measured on a grid of `[1, 8)` in 40 digits); three steps
//! in f32, four in f64.
//!
//! # Error budget
//!
//! The last step's correction is `(g^3 - y) / (3 g^2)` with `g^3 - y` formed from a `g`
//! within `1.5e-13` (f64) or `3.8e-7` (f32) relatively, so its rounding is a few ulps of a
//! correction that is itself tiny, and the step's own subtraction rounds once more: about an
//! ulp of `cbrt x`. Checked by the unit tests, in units of `eps |cbrt x|`: f32 within 0.67
//! of f64 libm on the same argument, f64 within 1.0 of libm's `cbrt` (itself within an ulp);
//! bound 1.5, over arguments from the smallest subnormal to the largest finite number.

use crate::real::{c, sq, Real};

/// `cbrt x` for any `x` (odd: `cbrt(-x) = -cbrt(x)`; zero, infinite and NaN `x` returned as
/// they are), within about an ulp (module docs): one division per Newton step (three in f32, four
/// in f64), no libm.
#[inline]
pub(crate) fn cbrt<T: Real>(x: T) -> T {
    let single = T::EPSILON.to_f64() > 1e-10;
    let mut y = x.abs();
    if y == T::ZERO || !y.is_finite() {
        return x;
    }
    let mut scale = T::ONE;
    let (big, small) = (c::<T>(281474976710656.0), c::<T>(3.552713678800501e-15)); // 2^(+-48)
    let (up, down) = (c::<T>(65536.0), c::<T>(1.52587890625e-5)); // 2^(+-16)
    while y >= big {
        y *= small;
        scale *= up;
    }
    while y < small {
        y *= big;
        scale *= down;
    }
    while y >= c::<T>(8.0) {
        y *= c::<T>(0.125);
        scale *= c::<T>(2.0);
    }
    while y < T::ONE {
        y *= c::<T>(8.0);
        scale *= c::<T>(0.5);
    }
    // the quadratic through (1, 1), (27/8, 3/2), (8, 2)
    let mut g = c::<T>(0.7400934769355823)
        + y * (c::<T>(0.27453769559032715) + y * c::<T>(-0.014631172525909368));
    let steps = if single { 3 } else { 4 };
    for _ in 0..steps {
        g -= (sq(g) * g - y) / (c::<T>(3.0) * sq(g));
    }
    (g * scale).copysign(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_rng::Lcg;

    /// f32 against f64 libm on the same argument, f64 against libm's `cbrt` (itself within an
    /// ulp), in units of `eps |cbrt x|`, on a log scale over the whole finite range of each type
    /// (subnormals included), the ends of the `[1, 8)` interval and powers of two.
    #[test]
    fn cbrt_is_within_an_ulp_and_a_half_of_libm() {
        let mut rng = Lcg(31);
        let mut worst32 = 0.0f64;
        let mut worst64 = 0.0f64;
        let mut check32 = |x: f32| {
            let want = libm::cbrt(f64::from(x));
            let got = f64::from(cbrt(x));
            let ulp = want.abs() * f64::from(f32::EPSILON);
            worst32 = worst32.max((got - want).abs() / ulp);
        };
        let mut check64 = |x: f64| {
            let want = libm::cbrt(x);
            let got = cbrt(x);
            worst64 = worst64.max((got - want).abs() / (want.abs() * f64::EPSILON));
        };
        for _ in 0..300_000 {
            let sign = if rng.next() < 0.5 { -1.0 } else { 1.0 };
            check32((sign * 10f64.powf(-45.0 + 83.5 * rng.next())) as f32);
            check64(sign * 10f64.powf(-323.0 + 631.0 * rng.next()));
            check64(rng.range(1.0, 8.0));
        }
        for k in -149..=127 {
            check32(2f32.powi(k));
        }
        for k in -1074..=1023 {
            check64(2f64.powi(k));
        }
        for x in [1.0, 8.0, 27.0 / 8.0, f64::MAX, f64::MIN_POSITIVE, 5e-324] {
            check64(x);
            check32(x as f32);
        }
        check32(f32::MAX);
        assert!(worst32 <= 1.5, "f32: {worst32} eps");
        assert!(worst64 <= 1.5, "f64: {worst64} eps");
    }

    /// Zero, infinities and NaN come back as they are; the sign is kept.
    #[test]
    fn special_values() {
        assert_eq!(cbrt(0.0f64).to_bits(), 0.0f64.to_bits());
        assert_eq!(cbrt(-0.0f32).to_bits(), (-0.0f32).to_bits());
        assert_eq!(cbrt(f64::INFINITY), f64::INFINITY);
        assert_eq!(cbrt(f32::NEG_INFINITY), f32::NEG_INFINITY);
        assert!(cbrt(f64::NAN).is_nan());
        assert_eq!(cbrt(-27.0f64), -3.0);
        assert_eq!(cbrt(-8.0f32), -2.0);
    }
}
