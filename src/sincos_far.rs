//! `x mod pi/2` for large `|x|` in the generic `T` arithmetic: the reduction behind
//! [`crate::sin_cos`] from its Cody–Waite limit (6000 rad in f32, `1e6` in f64) up to
//! `|x| < 2^(p-2) pi/2` (`p` the precision: 6.6e6 rad in f32, `3.5e15` in f64), so that the
//! torque models' angles never need libm (whose `sinf`/`cosf` compute in double, software on a
//! Cortex-M4F: with their reduction and the double routines about 10 KB of a firmware's flash,
//! measured in a first-use trial's minimal `Forced` + `GravityGradient` build).
//!
//! # Derivation
//!
//! `k = round(x 2/pi)` by the magic constant `1.5 2^(p-1)` (an integer for `|x 2/pi| <
//! 2^(p-2)`), possibly one off the nearest integer to the exact `x 2/pi` (the product rounds;
//! corrected at the end). `pi/2 = P1 + P2 + P3 + P4 + P5 + O(2^-(4b + p))` with `P1..P4` of
//! `b = 12` (f32) or `26` (f64) significant bits and `P5` rounded to `T`. `k` splits exactly
//! into `k_hi = 2^b round(k 2^-b)` (at most `p - 2 - b <= b` significant bits) and
//! `k_lo = k - k_hi` (`|k_lo| <= 2^(b-1)`), so each `k_hi P_i`, `k_lo P_i` (`i <= 4`) has at
//! most `2b <= p` bits: exact. They are subtracted from `x` with Knuth's TwoSum, which keeps
//! each rounding error exactly in a second word, so `r = x - k pi/2` is known as `hi + lo` up
//! to the rounding of `k P5` and the sum of the small words; `r` is then `hi + lo` rounded
//! once, and where `|r| > pi/4` (the one-off `k`) one more `pi/2` is taken, the same way.
//!
//! # Error budget
//!
//! The truncation `k (pi/2 - P1 - ... - P5)`: below `2^(p-2) 2^-(4b+p)` absolute, `2^-50` (f32)
//! and `2^-107` (f64). `k P5` rounds by an ulp of a number below `2^(p-2) |P5|` (`2.4e-11` in
//! f32, `5e-18` in f64), the small words' sum by a few ulps of numbers near `eps`: together a
//! few hundredths of `eps`. The final rounding of `r`: half an ulp of `r`, at most a quarter
//! of `eps`. So `r` is within about `0.3 eps` (absolute) of `x - k pi/2`, and the kernel's `sin`,
//! `cos` of it within the `1.5 eps` of [`crate::sin_cos`]. Measured: 0.725 eps worst over
//! every f32 argument from 6000 to the limit (1.7e8 of them, against f64 libm on the same
//! argument, once); the unit tests sample them, the floats nearest multiples of `pi/2`, and
//! f64 against libm.

use crate::real::{c, Real};
use crate::sincos::round_magic;

/// `(r, k)`: `r = x - k pi/2` with `|r| <= pi/4` (plus rounding) and `k` an integer in `T`,
/// for `|x| < `[`far_limit`]; `None` beyond (or for a non-finite `x`).
#[inline(never)]
pub(crate) fn reduce_far<T: Real>(x: T) -> Option<(T, T)> {
    if !(x.abs() < c::<T>(far_limit::<T>())) {
        return None;
    }
    let single = T::EPSILON.to_f64() > 1e-10;
    // converted to T here, literal by literal (a table of f64 converted inside the loop was
    // converted at run time at opt-level `s`, software double on the M4F, found in review)
    let (parts, b_scale) = if single {
        (
            [
                c::<T>(1.57080078125),
                c::<T>(-4.453584551811218e-6),
                c::<T>(-8.706138032721356e-10),
                c::<T>(6.222800053024002e-14),
                c::<T>(5.721188916458728e-18),
            ],
            4096.0,
        )
    } else {
        (
            [
                c::<T>(1.5707963407039642),
                c::<T>(-1.3909067675399456e-8),
                c::<T>(6.123233932053594e-17),
                c::<T>(6.368317178484799e-25),
                c::<T>(-1.4973849048591698e-33),
            ],
            67108864.0,
        )
    };
    let magic = round_magic::<T>();
    let k = (x * c::<T>(core::f64::consts::FRAC_2_PI) + magic) - magic;
    let (r, adjust) = remainder(x, k, &parts, c::<T>(b_scale), magic);
    Some((r, k + adjust))
}

/// `x - k pi/2` by the exact products and TwoSum of the module docs, then one more `pi/2` off
/// where the first `k` was one off: `(r, the change of k)`.
#[inline(always)]
fn remainder<T: Real>(x: T, k: T, p: &[T; 5], b_scale: T, magic: T) -> (T, T) {
    let k_hi = ((k / b_scale + magic) - magic) * b_scale;
    let k_lo = k - k_hi;
    let (mut hi, mut lo) = (x, T::ZERO);
    let [p1, p2, p3, p4, p5] = *p;
    for part in [p1, p2, p3, p4] {
        for term in [k_hi * part, k_lo * part] {
            let (s, e) = two_sum(hi, -term);
            hi = s;
            lo += e;
        }
    }
    lo -= k * p5;
    let r = hi + lo;
    let quarter = c::<T>(core::f64::consts::FRAC_PI_4);
    if !(r.abs() > quarter) {
        return (r, T::ZERO);
    }
    // the first k was one off: r - sign(r) pi/2, from hi + lo with the same parts (k = +-1:
    // every product exact)
    let one = T::ONE.copysign(r);
    for part in [p1, p2, p3, p4, p5] {
        let (s, e) = two_sum(hi, -(one * part));
        hi = s;
        lo += e;
    }
    (hi + lo, one)
}

/// Knuth's TwoSum: `s = a + b` rounded and `e` with `a + b = s + e` exactly (six operations,
/// no branch, any order of magnitude).
#[inline(always)]
fn two_sum<T: Real>(a: T, b: T) -> (T, T) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// The largest `|x|` reduced here: `2^(p-2) pi/2`, where the magic constant still rounds
/// `x 2/pi` to an integer (6.59e6 rad in f32, `3.5e15` in f64; an ulp of `x` there is a
/// quarter radian, so the argument itself has about two bits of angle left).
#[inline(always)]
pub(crate) fn far_limit<T: Real>() -> f64 {
    if T::EPSILON.to_f64() > 1e-10 {
        4194304.0 * core::f64::consts::FRAC_PI_2
    } else {
        2251799813685248.0 * core::f64::consts::FRAC_PI_2
    }
}
