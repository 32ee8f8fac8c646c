//! `asin t` in the generic `T` arithmetic, without libm: the angle of the cubic's
//! trigonometric roots (crate::cubic), so that the exact solve behind every `Mv` links no
//! transcendental function. libm's `acosf`/`cosf` compute in double, which on a Cortex-M4F is
//! software: about 1500 instructions a call and, with the double routines they pull in, about
//! 10 KB of flash in a firmware that runs nothing else of libm (a first-use trial's minimal
//! propagator: 23 KB for the free `Mv`, 9.6 KB of it libm's `cosf`, `acosf`, `sqrtf`, `cbrtf`
//! and the software double arithmetic).
//!
//! # Derivation
//!
//! On `|t| <= 1/2`: `asin t = t + t z P(z)`, `z = t^2`, where
//!
//! `asin x / x - 1 = sum_{n >= 1} c_n x^(2n)`,  `c_n = (2n)! / (4^n (n!)^2 (2n + 1))`
//!
//! is the Taylor series (Abramowitz & Stegun 4.4.40). Every term is positive and the ratio of
//! two consecutive ones is below `z <= 1/4`, so the tail after `N` terms is below
//! `4/3 c_(N+1) z^(N+1)`: with `N = 9` (f32) `1.1e-8` (0.09 of f32's `eps`), with `N = 23`
//! (f64) `1.1e-17` (0.05 of f64's). The coefficients are written out rounded to f64 (from
//! `c_n = a_n / (2n + 1)`, `a_(n+1) = a_n (2n + 1) / (2n + 2)`, `a_0 = 1`, which the unit test
//! checks them against).
//!
//! On `1/2 < |t| <= 1`: `asin |t| = pi/2 - 2 asin sqrt(w)` with `w = (1 - |t|) / 2 <= 1/4`
//! (the half-angle identity `cos(pi/2 - 2y) = 1 - 2 sin^2 y`), the same series at
//! `x = sqrt(w)`; `1 - |t|` and the halving are exact (Sterbenz).
//!
//! # Error budget
//!
//! On `|t| <= 1/2` the polynomial's rounding and the final sum `t + t z P` (whose correction
//! is below 0.05 of `t`): within an ulp of the result. Above, `sqrt` (half an ulp of `x`,
//! which `2 asin` turns into up to 0.6 ulp of `2 asin x` near `t = 1/2`), the series,
//! the doubling's rounding and the difference with `pi/2 = hi + lo`, `hi - (2 asin x - lo)`,
//! whose result is at least `pi/6`, so an ulp of `2 asin x` is up to two of it: relative error
//! within `2.5 eps` (measured over every f32 in `[0, 1]`: 2.32 eps, just past `t = 1/2`, in review; 2.1 ulp in
//! f64 against mpmath; libm's are within an ulp).
//! Checked by the unit tests against f64 libm (f32 on the same argument over every
//! `2^-12`-th of `[-1, 1]`, their neighbours and random points; f64 against libm's `asin`,
//! itself within an ulp).

use crate::real::{c, Real};

/// `asin t` for `t` in `[-1, 1]` (an input outside is clamped to it; NaN gives NaN), within
/// `2.5 eps` relatively (module docs), by the series of `asin x / x` on `|x| <= 1/2` and the half-angle
/// identity above: no libm, no division.
#[inline]
pub(crate) fn asin<T: Real>(t: T) -> T {
    let t = t.max(-T::ONE).min(T::ONE);
    let a = t.abs();
    let series = |x: T, z: T| x + x * z * series_p(z);
    if a <= c::<T>(0.5) {
        return series(t, t * t);
    }
    let w = (T::ONE - a) * c::<T>(0.5);
    let x = w.sqrt();
    // pi/2 = hi + lo: hi the nearest T, lo the rest (pi/2 - FRAC_PI_2 = 6.12e-17 plus, in
    // f32, the f32 rounding of FRAC_PI_2), so that pi/2's own rounding is not in the result
    let pio2_hi = c::<T>(core::f64::consts::FRAC_PI_2);
    let pio2_lo = c::<T>(core::f64::consts::FRAC_PI_2 - pio2_hi.to_f64() + 6.123233995736766e-17);
    let y = pio2_hi - (c::<T>(2.0) * series(x, w) - pio2_lo);
    y.copysign(t)
}

/// `P(z) = sum_{n >= 1} c_n z^(n-1)`, 9 terms in f32 and 23 in f64 (module docs), the
/// coefficients written out (a loop over a table kept a bounds check and converted the f32
/// coefficients from f64 at run time at opt-level `s`, found in review).
#[inline(always)]
fn series_p<T: Real>(z: T) -> T {
    // f32 starts at c_9; f64 runs c_23 .. c_10 first, then the same steps
    let mut p = c::<T>(0.009761609529194078);
    if T::EPSILON.to_f64() <= 1e-10 {
        let mut q = c::<T>(0.0024894486782468836);
        q = c::<T>(0.00265787063820729) + z * q;
        q = c::<T>(0.002846178401108942) + z * q;
        q = c::<T>(0.0030578216492580306) + z * q;
        q = c::<T>(0.003297059503473485) + z * q;
        q = c::<T>(0.0035692053938259347) + z * q;
        q = c::<T>(0.003880964558837669) + z * q;
        q = c::<T>(0.004240907093679363) + z * q;
        q = c::<T>(0.004660143486915096) + z * q;
        q = c::<T>(0.005153309682319905) + z * q;
        q = c::<T>(0.005740037670841924) + z * q;
        q = c::<T>(0.006447210311889649) + z * q;
        q = c::<T>(0.0073125258735988454) + z * q;
        q = c::<T>(0.008390335809616815) + z * q;
        p = c::<T>(0.009761609529194078) + z * q;
    }
    p = c::<T>(0.011551800896139705) + z * p;
    p = c::<T>(0.01396484375) + z * p;
    p = c::<T>(0.017352764423076924) + z * p;
    p = c::<T>(0.022372159090909092) + z * p;
    p = c::<T>(0.030381944444444444) + z * p;
    p = c::<T>(0.044642857142857144) + z * p;
    p = c::<T>(0.075) + z * p;
    p = c::<T>(0.16666666666666666) + z * p;
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_rng::Lcg;

    /// `|got - want|` in units of `eps |want|`.
    fn ulps64(got: f64, want: f64) -> f64 {
        (got - want).abs() / (want.abs().max(f64::MIN_POSITIVE) * f64::EPSILON)
    }

    /// f32 against f64 libm on the same argument, f64 against libm (itself within an ulp), as
    /// relative errors in units of `eps`, over a grid of `[-1, 1]`, random points, the branch
    /// point `1/2` and its neighbours, and the ends.
    #[test]
    fn asin_is_within_two_and_a_half_eps_of_libm() {
        let mut worst32 = 0.0f64;
        let mut worst64 = 0.0f64;
        let mut check = |t: f64| {
            let t32 = t as f32;
            let want = libm::asin(f64::from(t32));
            let got = f64::from(asin::<f32>(t32));
            let ulp32 = f64::from(f32::EPSILON) * want.abs().max(f64::from(f32::MIN_POSITIVE));

            worst32 = worst32.max((got - want).abs() / ulp32);
            worst64 = worst64.max(ulps64(asin::<f64>(t), libm::asin(t)));
        };
        for k in -4096..=4096 {
            let t = f64::from(k) / 4096.0;
            for d in [-1e-9, -1e-16, 0.0, 1e-16, 1e-9] {
                check((t + d).clamp(-1.0, 1.0));
            }
        }
        let mut rng = Lcg(29);
        for _ in 0..200_000 {
            check(rng.range(-1.0, 1.0));
            check(1.0 - 10f64.powf(-16.0 * rng.next()));
            check(10f64.powf(-30.0 * rng.next()));
        }
        for t in [
            0.5,
            f64::from(0.5f32.next_up()),
            f64::from(0.5f32.next_down()),
            1.0,
            -1.0,
            0.0,
            1e-300,
        ] {
            check(t);
        }
        assert!(worst32 <= 2.5, "f32: {worst32} eps");
        assert!(worst64 <= 2.5, "f64: {worst64} eps");
        assert!(
            worst32 > 1.0 && worst64 > 0.5,
            "f32 {worst32}, f64 {worst64}: the test misses the branch's edge"
        );
    }

    /// Outside `[-1, 1]` the input is clamped; NaN stays NaN.
    #[test]
    fn out_of_range_is_clamped_and_nan_propagates() {
        assert_eq!(asin(1.5f64), asin(1.0f64));
        assert_eq!(asin(-7.0f32), asin(-1.0f32));
        assert!(asin(f64::NAN).is_nan());
    }

    /// The written-out series against the Taylor coefficients from their recurrence
    /// (`c_n = a_n / (2n + 1)`, `a_(n+1) = a_n (2n + 1) / (2n + 2)`): `P` at several `z`
    /// equals the sum of the first 9 (f32) or 23 (f64) terms, and the first term left out is
    /// below a tenth of `eps` at `z = 1/4` (module docs).
    #[test]
    fn the_series_is_the_taylor_series() {
        let mut cs = [0.0f64; 24];
        let mut a = 1.0f64;
        for (n, cn) in cs.iter_mut().enumerate() {
            let k = n as f64;
            a = a * (2.0 * k + 1.0) / (2.0 * k + 2.0);
            *cn = a / (2.0 * k + 3.0);
        }
        assert_eq!(cs[0], 1.0 / 6.0);
        assert!((cs[1] - 3.0 / 40.0).abs() < 1e-17 && (cs[2] - 5.0 / 112.0).abs() < 1e-17);
        for z in [0.0, 0.01, 0.1, 0.2, 0.25] {
            let sum = |terms: usize| cs[..terms].iter().rev().fold(0.0, |p, c| p * z + c);
            assert!(
                (series_p(z) - sum(23)).abs() <= 2.0 * f64::EPSILON,
                "f64 {z}"
            );
            let p32 = f64::from(series_p(z as f32));
            assert!(
                (p32 - sum(9)).abs() <= 2.0 * f64::from(f32::EPSILON),
                "f32 {z}"
            );
        }
        let tail32 = 4.0 / 3.0 * cs[9] * 0.25f64.powi(10);
        let tail64 = 4.0 / 3.0 * cs[23] * 0.25f64.powi(24);
        assert!(tail32 < 0.1 * f64::from(f32::EPSILON), "{tail32}");
        assert!(tail64 < 0.1 * f64::EPSILON, "{tail64}");
    }
}
