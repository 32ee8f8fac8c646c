//! `sin x` and `cos x` together in the generic `T` arithmetic: what the torque models evaluate
//! every step (the orbit angle of [`crate::torque::GravityGradient`], the phases of
//! [`crate::torque::PeriodicTorque`]). libm's `sinf` and `cosf` compute in double, which on a
//! Cortex-M4F is software: about 2000 instructions a call, more than three forced steps.
//!
//! # Derivation
//!
//! Reduction (Cody & Waite): `k = round(x 2/pi)`, `r = x - k pi/2` with `|r| <= pi/4` (plus
//! rounding), computed as `((x - k P1) - k P2) - k P3` where `P1 + P2 + P3 = pi/2` to about
//! three times the precision of `T` and `P1`, `P2` have so few significant bits (12 in f32,
//! 33 in f64) that `k P1` and `k P2` are exact for `|k| < 2^12` (f32) or `2^20` (f64), which
//! [`reduction_limit`] enforces; `x - k P1` is exact too (Sterbenz). `k` itself is rounded by
//! adding and subtracting `1.5 2^(p-1)` (`p` the precision), exact for `|x 2/pi| < 2^(p-2)`.
//!
//! Polynomials: the Taylor series of `sin r` to `r^9` (f32) or `r^15` (f64) and of `cos r` to
//! `r^10` or `r^16`. Both alternate with terms that shrink, so the remainder is below the first
//! term left out: at `|r| = pi/4`, `(pi/4)^11 / 11! = 1.8e-9` and `(pi/4)^12 / 12! = 1.1e-10`
//! in f32 (an ulp of one is `1.2e-7`), `(pi/4)^17 / 17! = 4.6e-17` and `(pi/4)^18 / 18! =
//! 2.0e-18` in f64 (`2.2e-16`). Then `sin x`, `cos x` are `(s, c)`, `(c, -s)`, `(-s, -c)` or
//! `(-c, s)` for `k mod 4 = 0, 1, 2, 3`, read off `k - 4 round(k / 4)` (exact in `T`).
//!
//! # Error budget
//!
//! The reduction's roundings leave `r` within about an ulp of `|r|` plus `k ulp(P3)`; the
//! polynomials add about an ulp. Absolute error at most `1.5 eps` (in ulps of one), checked
//! by the unit tests: the f32 function against f64 libm on the same argument, the f64
//! function against f64 libm (itself within an ulp). Near a zero of `sin` or `cos` the bound is
//! absolute, not relative. Beyond the reduction limit (`|x| > 6000` in f32, `1e6` in f64) the
//! reduction is crate::sincos_far's (exact products and TwoSum, up to `6.6e6` rad in f32 and
//! `3.5e15` in f64; the same bound, 0.725 eps worst over every f32 there); beyond that and
//! for non-finite `x` the public [`sin_cos`] calls libm, the torque models get NaN.

use crate::real::{c, Real};
use crate::sincos_far::reduce_far;

/// `(sin x, cos x)` in `T` arithmetic, for angles evaluated every tick (an orbit angle, a
/// torque's phase): 71 instructions for both in f32 on a Cortex-M4F, where libm's `sinf` and
/// `cosf` compute in double in software (4003 for the pair at angles of 1–100 rad;
/// `scripts/firmware`). On x86-64 the two cost about the same.
///
/// Cody–Waite reduction by `pi/2` (`pi/2` split in three parts so that the first two products
/// with the quadrant number are exact), then the Taylor series of `sin` and `cos` on
/// `[-pi/4, pi/4]` to degree 9 and 10 in f32, 15 and 16 in f64 (remainders below
/// `1.8e-9` and `4.6e-17`).
///
/// Accuracy: absolute error at most `1.5 eps` (tested against libm in f64: 0.88 eps worst in
/// f32 over every input up to 6000, checked exhaustively in review; 1.0 in f64) for `|x|` up
/// to 6000 in f32 and `1e6` in f64; from there to `6.6e6` rad in f32 and `3.5e15` in f64 a
/// longer reduction (`pi/2` in five parts, exact products, TwoSum: 206 instructions
/// on the M4F) keeps the bound (0.725 eps worst over every f32 argument there); beyond, and for
/// NaN or infinite `x`, it returns libm's `sin` and `cos` (so NaN for a non-finite `x`). Near a zero of
/// `sin` or `cos` the bound is absolute, not relative.
///
/// ```
/// let (s, c) = rigid3::sin_cos(0.5f32);
/// assert!((s - 0.5f32.sin()).abs() <= 1.5 * f32::EPSILON);
/// assert!((c - 0.5f32.cos()).abs() <= 1.5 * f32::EPSILON);
/// ```
#[inline]
pub fn sin_cos<T: Real>(x: T) -> (T, T) {
    if !(x.abs() <= c::<T>(reduction_limit::<T>())) {
        return far_or_libm(x);
    }
    near(x).unwrap_or_else(|| (x.sin(), x.cos()))
}

/// [`sin_cos`] without libm, NaN for both where it would call libm (`|x|` beyond
/// [`crate::sincos_far::far_limit`], a non-finite `x`, or arithmetic with excess precision):
/// the torque models' angles (crate::torque), whose NaN torque a forced step refuses
/// (`NonFinite`) rather than link libm for an angle with less than two bits left (beyond
/// 6.6e6 rad in f32).
#[inline]
pub(crate) fn sin_cos_or_nan<T: Real>(x: T) -> (T, T) {
    let nan = || {
        let nan = c::<T>(f64::NAN);
        (nan, nan)
    };
    if !(x.abs() <= c::<T>(reduction_limit::<T>())) {
        return far(x).unwrap_or_else(nan);
    }
    near(x).unwrap_or_else(nan)
}

/// Past the Cody–Waite limit: the far reduction, libm beyond it. Out of line (an inlined far
/// path cost every near call two M4F instructions).
#[cold]
#[inline(never)]
fn far_or_libm<T: Real>(x: T) -> (T, T) {
    far(x).unwrap_or_else(|| (x.sin(), x.cos()))
}

/// `(sin x, cos x)` by crate::sincos_far's reduction, `None` beyond its limit.
#[cold]
#[inline(never)]
fn far<T: Real>(x: T) -> Option<(T, T)> {
    let (r, k) = reduce_far(x)?;
    by_quadrant(k, sin_cos_kernel(r), round_magic())
}

/// `1.5 2^(p-1)` (`p` the precision of `T`): `(v + magic) - magic` rounds `v` to the nearest
/// integer for `|v| < 2^(p-2)` (no `round` in core for floats).
#[inline(always)]
pub(crate) fn round_magic<T: Real>() -> T {
    c::<T>(if T::EPSILON.to_f64() > 1e-10 {
        12582912.0
    } else {
        6755399441055744.0
    })
}

/// `(sin x, cos x)` for `|x|` within the Cody–Waite limit; `None` only with excess precision.
#[inline(always)]
fn near<T: Real>(x: T) -> Option<(T, T)> {
    let single = T::EPSILON.to_f64() > 1e-10;
    let (p1, p2, p3) = if single {
        (1.57080078125, -4.453584551811218e-6, -8.705515752716053e-10)
    } else {
        (
            1.5707963267341256,
            6.077100506303966e-11,
            2.0222662487959506e-21,
        )
    };
    let magic = round_magic::<T>();
    // round to nearest by the magic constant (no `round` in core for floats)
    let k = (x * c::<T>(core::f64::consts::FRAC_2_PI) + magic) - magic;
    let r = ((x - k * c::<T>(p1)) - k * c::<T>(p2)) - k * c::<T>(p3);
    by_quadrant(k, sin_cos_kernel(r), magic)
}

/// `(sin x, cos x)` from those of `r = x - k pi/2`: the quadrant `k mod 4` as
/// `q = k - 4 round(k / 4)` in `{-2, ..., 2}`, exactly, in `T` (a conversion to an integer went
/// through f64 in software on the M4F). `None` where `k` was not rounded to an integer: only
/// where the arithmetic keeps excess precision (x87 without SSE), which the magic-constant
/// rounding needs to be absent.
#[inline(always)]
fn by_quadrant<T: Real>(k: T, (s, co): (T, T), magic: T) -> Option<(T, T)> {
    let q = k - c::<T>(4.0) * ((k * c::<T>(0.25) + magic) - magic);
    if q == T::ZERO {
        Some((s, co))
    } else if q == T::ONE {
        Some((co, -s))
    } else if q == -T::ONE {
        Some((-co, s))
    } else if q.abs() == c::<T>(2.0) {
        Some((-s, -co))
    } else {
        None
    }
}

/// `(sin r, cos r)` for `|r| <= pi/4` by the Taylor polynomials of the module docs (no
/// reduction, no libm: what the cubic's trigonometric roots use, whose angle is at most
/// `pi/6` by construction, crate::cubic). Absolute error within an ulp of one on that range
/// (the remainders are below `1.8e-9` in f32 and `4.6e-17` in f64 at `pi/4`).
#[inline]
pub(crate) fn sin_cos_kernel<T: Real>(r: T) -> (T, T) {
    let single = T::EPSILON.to_f64() > 1e-10;
    let r2 = r * r;
    if single {
        (
            r + r
                * r2
                * (c::<T>(-1.0 / 6.0)
                    + r2 * (c::<T>(1.0 / 120.0)
                        + r2 * (c::<T>(-1.0 / 5040.0) + r2 * c::<T>(1.0 / 362880.0)))),
            T::ONE
                + r2 * (c::<T>(-0.5)
                    + r2 * (c::<T>(1.0 / 24.0)
                        + r2 * (c::<T>(-1.0 / 720.0)
                            + r2 * (c::<T>(1.0 / 40320.0) + r2 * c::<T>(-1.0 / 3628800.0))))),
        )
    } else {
        (
            r + r
                * r2
                * (c::<T>(-1.0 / 6.0)
                    + r2 * (c::<T>(1.0 / 120.0)
                        + r2 * (c::<T>(-1.0 / 5040.0)
                            + r2 * (c::<T>(1.0 / 362880.0)
                                + r2 * (c::<T>(-1.0 / 39916800.0)
                                    + r2 * (c::<T>(1.0 / 6227020800.0)
                                        + r2 * c::<T>(-1.0 / 1307674368000.0))))))),
            T::ONE
                + r2 * (c::<T>(-0.5)
                    + r2 * (c::<T>(1.0 / 24.0)
                        + r2 * (c::<T>(-1.0 / 720.0)
                            + r2 * (c::<T>(1.0 / 40320.0)
                                + r2 * (c::<T>(-1.0 / 3628800.0)
                                    + r2 * (c::<T>(1.0 / 479001600.0)
                                        + r2 * (c::<T>(-1.0 / 87178291200.0)
                                            + r2 * c::<T>(1.0 / 20922789888000.0)))))))),
        )
    }
}

/// The largest `|x|` reduced here: `|k| < 2^12` in f32 (`4096 pi/2 = 6434`) and `2^20` in f64
/// (`1.6e6`), so that `k P1` and `k P2` are exact.
#[inline(always)]
fn reduction_limit<T: Real>() -> f64 {
    if T::EPSILON.to_f64() > 1e-10 {
        6000.0
    } else {
        1e6
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_rng::Lcg;

    /// f32 against libm's f64 `sin`/`cos` of the same (exactly representable) argument, and
    /// f64 against libm's f64 (itself within an ulp): absolute errors in ulps of one, over
    /// arguments spread on a log scale up to the reduction limit, multiples of `pi/4` and their
    /// neighbours, and zero.
    #[test]
    fn sin_cos_is_within_one_and_a_half_eps_of_libm() {
        let mut rng = Lcg(11);
        let mut worst32 = 0.0f64;
        let mut worst64 = 0.0f64;
        let mut check = |x: f64| {
            let x32 = x as f32;
            let (s, co) = sin_cos::<f32>(x32);
            let xd = f64::from(x32);
            let e = (f64::from(s) - libm::sin(xd))
                .abs()
                .max((f64::from(co) - libm::cos(xd)).abs());
            worst32 = worst32.max(e / f64::from(f32::EPSILON));
            if x.abs() <= 1e6 {
                let (s, co) = sin_cos::<f64>(x);
                let e = (s - libm::sin(x)).abs().max((co - libm::cos(x)).abs());
                worst64 = worst64.max(e / f64::EPSILON);
            }
        };
        check(0.0);
        for k in -40..=40 {
            let base = f64::from(k) * core::f64::consts::FRAC_PI_4;
            for d in [-1e-7, -1e-12, 0.0, 1e-12, 1e-7] {
                check(base + d);
            }
        }
        for _ in 0..200_000 {
            let mag = 10f64.powf(-6.0 + 9.6 * rng.next()).min(6000.0);
            let sign = if rng.next() < 0.5 { -1.0 } else { 1.0 };
            check(sign * mag);
        }
        for _ in 0..20_000 {
            check(1e6 * (2.0 * rng.next() - 1.0));
        }
        assert!(worst32 <= 1.5, "f32: {worst32} eps");
        assert!(worst64 <= 1.5, "f64: {worst64} eps");
    }

    /// Past the Cody–Waite limit up to the far reduction's (crate::sincos_far), against f64
    /// libm on the same argument (f32) and libm (f64), absolute errors in `eps`: arguments on
    /// a log scale, and the floats nearest to multiples of `pi/2` and their neighbours, where
    /// `x - k pi/2` cancels most (the reduction's hardest inputs).
    #[test]
    fn far_arguments_are_within_one_and_a_half_eps_of_libm() {
        let mut rng = Lcg(13);
        let (mut worst32, mut worst64) = (0.0f64, 0.0f64);
        let mut check32 = |x: f32| {
            let (s, co) = sin_cos_or_nan(x);
            let xd = f64::from(x);
            let e = (f64::from(s) - libm::sin(xd))
                .abs()
                .max((f64::from(co) - libm::cos(xd)).abs());
            worst32 = worst32.max(e / f64::from(f32::EPSILON));
        };
        let lim32 = crate::sincos_far::far_limit::<f32>();
        for _ in 0..300_000 {
            let x = 10f64.powf(3.7 + (lim32.log10() - 3.7) * rng.next()) as f32;
            check32(if rng.next() < 0.5 { x } else { -x });
            // the float nearest k pi/2 and its neighbours
            let k = (rng.next() * lim32 / core::f64::consts::FRAC_PI_2).floor();
            let mut x = (k * core::f64::consts::FRAC_PI_2) as f32;
            if f64::from(x.abs()) < lim32 && x.abs() > 6000.0 {
                for _ in 0..3 {
                    check32(x);
                    x = x.next_up();
                }
            }
        }
        let mut check64 = |x: f64| {
            let (s, co) = sin_cos_or_nan(x);
            let e = (s - libm::sin(x)).abs().max((co - libm::cos(x)).abs());
            worst64 = worst64.max(e / f64::EPSILON);
        };
        let lim64 = crate::sincos_far::far_limit::<f64>();
        for _ in 0..100_000 {
            let x = 10f64.powf(6.0 + (lim64.log10() - 6.0) * rng.next());
            check64(if rng.next() < 0.5 { x } else { -x });
        }
        assert!(worst32 <= 1.5, "f32: {worst32} eps");
        assert!(worst64 <= 1.5, "f64: {worst64} eps");
        // the limit itself: beyond it (and for non-finite x) no result without libm
        assert!(sin_cos_or_nan((lim32 * 1.0001) as f32).0.is_nan());
        assert!(sin_cos_or_nan(lim64 * 1.0001).1.is_nan());
        assert!(sin_cos_or_nan(f32::NAN).0.is_nan() && sin_cos_or_nan(f64::INFINITY).1.is_nan());
        // and the public function agrees with the libm-free one up to the limit
        assert_eq!(sin_cos(1e6f32), sin_cos_or_nan(1e6f32));
        assert_eq!(sin_cos(1e12f64), sin_cos_or_nan(1e12f64));
    }

    /// Beyond the far reduction's limit and for non-finite input the libm functions answer.
    #[test]
    fn large_and_non_finite_arguments_go_to_libm() {
        for x in [7e6f32, -1e20, f32::MAX] {
            assert_eq!(sin_cos(x), (libm::sinf(x), libm::cosf(x)));
        }
        let (s, co) = sin_cos(f64::NAN);
        assert!(s.is_nan() && co.is_nan());
        let (s, co) = sin_cos(f32::INFINITY);
        assert!(s.is_nan() && co.is_nan());
    }
}
