//! Allocation-free roots of real cubics, and the largest real root of the DMV quartic.
//!
//! # Method and error budget
//!
//! [`solve_cubic`] first rescales `x = s y` with `s = max(|a|, |b|^(1/2), |c|^(1/3))`, so
//! the scaled coefficients are at most 1 and nothing overflows for any finite input
//! (scale invariance). It takes the real root of largest magnitude from the trigonometric
//! (three real roots) or Cardano (one real root) formula, with the crate's own `asin`, sine
//! and cosine of an angle within `pi/6`, and cube root (no libm: crate::asin), polishes it by Newton's method on
//! the scaled polynomial, and deflates: the other two roots have product `-c / r` and sum
//! `-(a + r)`, or `(b + c / r) / r` where the two are small against `r` (the sum from `a`
//! then cancels), and are found from that quadratic with the cancellation-free formula. Deflating
//! by the largest root is forward stable (Wilkinson), so every simple root `r` satisfies
//!
//! `|r_computed - r| <= 8 eps (|r|^3 + |a| r^2 + |b| |r| + |c|) / |p'(r)|`,
//!
//! a few ulps times the root's condition number (a review against mpmath over 38,000 cubics
//! with roots spread up to `1e16` apart, clustered, nearly cancelling or complex: at most
//! 0.25 of it), wherever the scaled coefficients stay normal: a root below about `1e-19`
//! (f32) or `1e-150` (f64) of the largest can be lost to their underflow (`x^3 - x^2 -
//! 1e-170 x` gives `-5e-171` for `-1e-170`); a double root is found to about
//! `sqrt(eps)` relative (its condition number is infinite) and may come out as a complex
//! pair with an imaginary part of that size. The tests check this bound against roots built
//! in advance and against the `f64` result for the `f32` routine.

use crate::asin::asin;
use crate::cbrt::cbrt;
use crate::real::{c, sq, Real};
use crate::sincos::sin_cos_kernel;

/// The roots of a real cubic.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CubicRoots<T> {
    /// Three real roots in ascending order (repeated roots are repeated).
    Real([T; 3]),
    /// One real root and the complex pair `re +- i im` with `im > 0`.
    Complex {
        /// The real root.
        real: T,
        /// Real part of the pair.
        re: T,
        /// Imaginary part of the pair, positive.
        im: T,
    },
}

/// Roots of the monic cubic `x^3 + a x^2 + b x + c`.
///
/// Returns `None` when a coefficient is not finite or a root overflows. Accuracy: see the module docs (a few
/// ulps times each simple root's condition number). Uses one `sqrt`, one cube root and either
/// one `asin` and one `(sin, cos)` pair of an angle within `pi/6` (three real roots) or one
/// more `sqrt` and cube root (one real root), all the crate's own (crate::asin,
/// crate::cbrt, crate::sincos: no libm, so a firmware that solves a cubic links none of
/// libm's double-precision code).
#[must_use]
pub fn solve_cubic<T: Real>(a: T, b: T, cc: T) -> Option<CubicRoots<T>> {
    if !(a.is_finite() && b.is_finite() && cc.is_finite()) {
        return None;
    }
    let s = a.abs().max(b.abs().sqrt()).max(cbrt(cc.abs()));
    if s == T::ZERO {
        return Some(CubicRoots::Real([T::ZERO; 3]));
    }
    let inv = T::ONE / s;
    let a1 = a * inv;
    // one factor at a time: inv^2 alone can overflow while b * inv^2 cannot
    let b1 = b * inv * inv;
    let c1 = cc * inv * inv * inv;

    let r = polish(largest_root_guess(a1, b1, c1), a1, b1, c1);

    // The other two roots: y^2 + p y + q = 0 with q = -c1 / r (r != 0 since it is the root
    // of largest magnitude and the scaled polynomial is not y^3) and p = -(y2 + y3), from
    // either coefficient: `a1 + r` has an absolute error of about eps |r|, `(q - b1) / r`
    // (`b1 = r (y2 + y3) + q`) one of about eps (|b1| + |q|) / |r|, far smaller when the two
    // are small against r. Taken from `a1 + r` alone, roots 1e15 apart lost the small ones'
    // digits: `x^3 - 4.5e7 x^2 - 6.1 x - 1.4e-7` gave them 5.7e-3 and 1.5e-3 off (relative),
    // 9e11 times the bound below (found in review).
    let q = if r != T::ZERO { -c1 / r } else { b1 };
    let p = if r != T::ZERO && b1.abs() + q.abs() < sq(r) {
        (q - b1) / r
    } else {
        a1 + r
    };
    let half_p = p * c(0.5);
    let disc = sq(half_p) - q;
    let roots = if disc >= T::ZERO {
        let big = -half_p - disc.sqrt().copysign(half_p);
        let small = if big != T::ZERO { q / big } else { T::ZERO };
        let (y1, y2) = polish_pair(big, small, r, a1, b1, c1);
        CubicRoots::Real(sort3(r * s, y1 * s, y2 * s))
    } else {
        CubicRoots::Complex {
            real: r * s,
            re: -half_p * s,
            im: (-disc).sqrt() * s,
        }
    };
    let finite = match roots {
        CubicRoots::Real([x, y, z]) => x.is_finite() && y.is_finite() && z.is_finite(),
        CubicRoots::Complex { real, re, im } => {
            real.is_finite() && re.is_finite() && im.is_finite()
        }
    };
    if finite {
        Some(roots)
    } else {
        None
    }
}

/// The real root of largest magnitude of the scaled cubic (coefficients at most 1), from
/// the classical closed forms; accurate to a few ulps unless two roots nearly coincide.
fn largest_root_guess<T: Real>(a: T, b: T, cc: T) -> T {
    let third = c::<T>(1.0 / 3.0);
    let shift = a * third;
    let qq = (sq(a) - c::<T>(3.0) * b) * c(1.0 / 9.0);
    let rr = (c::<T>(2.0) * sq(a) * a - c::<T>(9.0) * a * b + c::<T>(27.0) * cc) * c(1.0 / 54.0);
    let qq3 = sq(qq) * qq;
    if sq(rr) < qq3 {
        // three real roots: -2 sqrt(Q) cos(theta + 2 pi k / 3) - a / 3 with
        // theta = acos(t) / 3 = pi/6 - phi, phi = asin(t) / 3 in [-pi/6, pi/6], so the three
        // cosines are sqrt(3)/2 cos phi + sin phi / 2, -sqrt(3)/2 cos phi + sin phi / 2 and
        // -sin phi: one sine and cosine pair of a small angle, no reduction
        let sqrt_q = qq.sqrt();
        let t = (rr / (qq * sqrt_q)).max(-T::ONE).min(T::ONE);
        let (sin_phi, cos_phi) = sin_cos_kernel(asin(t) * third);
        let m = c::<T>(-2.0) * sqrt_q;
        let even = c::<T>(0.8660254037844386) * cos_phi;
        let odd = sin_phi * c::<T>(0.5);
        let x1 = m * (even + odd) - shift;
        let x2 = m * (odd - even) - shift;
        let x3 = -(m * sin_phi) - shift;
        let mut best = x1;
        if x2.abs() > best.abs() {
            best = x2;
        }
        if x3.abs() > best.abs() {
            best = x3;
        }
        best
    } else {
        let root = (sq(rr) - qq3).max(T::ZERO).sqrt();
        let big_a = -cbrt(rr.abs() + root).copysign(rr);
        let big_b = if big_a != T::ZERO {
            qq / big_a
        } else {
            T::ZERO
        };
        big_a + big_b - shift
    }
}

#[inline]
fn eval<T: Real>(x: T, a: T, b: T, cc: T) -> (T, T) {
    let p = ((x + a) * x + b) * x + cc;
    let dp = (c::<T>(3.0) * x + c::<T>(2.0) * a) * x + b;
    (p, dp)
}

/// At most three Newton steps, each kept only if it lowers the residual.
fn polish<T: Real>(mut x: T, a: T, b: T, cc: T) -> T {
    let (mut p, mut dp) = eval(x, a, b, cc);
    let mut k = 0;
    while k < 3 && p != T::ZERO && dp != T::ZERO {
        let xn = x - p / dp;
        let (pn, dpn) = eval(xn, a, b, cc);
        if !(pn.abs() < p.abs()) {
            break;
        }
        x = xn;
        p = pn;
        dp = dpn;
        k += 1;
    }
    x
}

/// Polishes the two deflated real roots by Newton on the full cubic, keeping a step only if
/// it lowers the residual and moves the root by less than half its distance to the nearest
/// other root, so that near a double root the two never merge.
fn polish_pair<T: Real>(y1: T, y2: T, r: T, a: T, b: T, cc: T) -> (T, T) {
    let gap1 = (y1 - y2).abs().min((y1 - r).abs()) * c(0.5);
    let gap2 = (y2 - y1).abs().min((y2 - r).abs()) * c(0.5);
    (
        polish_guarded(y1, gap1, a, b, cc),
        polish_guarded(y2, gap2, a, b, cc),
    )
}

fn polish_guarded<T: Real>(x: T, gap: T, a: T, b: T, cc: T) -> T {
    let (p, dp) = eval(x, a, b, cc);
    if p == T::ZERO || dp == T::ZERO {
        return x;
    }
    let step = p / dp;
    if !(step.abs() < gap) {
        return x;
    }
    let xn = x - step;
    let (pn, _) = eval(xn, a, b, cc);
    if pn.abs() < p.abs() {
        xn
    } else {
        x
    }
}

fn sort3<T: Real>(x: T, y: T, z: T) -> [T; 3] {
    let (lo, hi) = if x <= y { (x, y) } else { (y, x) };
    if z <= lo {
        [z, lo, hi]
    } else if z <= hi {
        [lo, z, hi]
    } else {
        [lo, hi, z]
    }
}

/// Principal square root of `re + i im`: returns `(u, v)` with `u >= 0`, `(u + i v)^2 = re + i im`.
/// Cancellation-free in both half planes.
pub(crate) fn complex_sqrt<T: Real>(re: T, im: T) -> (T, T) {
    let r = re.abs().max(im.abs());
    if r == T::ZERO {
        return (T::ZERO, T::ZERO);
    }
    // |z| without overflow
    let modulus = r * (sq(re / r) + sq(im / r)).sqrt();
    if re >= T::ZERO {
        let u = ((modulus + re) * c(0.5)).sqrt();
        (u, im / (c::<T>(2.0) * u))
    } else {
        let v = ((modulus - re) * c(0.5)).sqrt().copysign(im);
        (im / (c::<T>(2.0) * v), v)
    }
}

/// Largest real root `s1` of the DMV quartic `(s^2 - A)^2 - 8 s3 s - 4 B = 0` (docs/MATH.md §4).
///
/// The quartic's roots are `+-lambda_1 +- lambda_2 +- lambda_3` (an even number of minus
/// signs), where `mu_i = lambda_i^2` are the roots of `mu^3 - A mu^2 + B mu - s3^2`. So the
/// cubic is solved, `s1 = sum sqrt(mu_i)` (principal branch; a complex pair contributes twice
/// its real part) and `s1` is polished by up to three Newton steps on the quartic. Returns
/// `None` when the cubic has a negative real root (then no real DMV step exists: docs/MATH.md §3)
/// or the input is not finite. Accuracy: a few ulps of `s1` times the quartic's condition
/// number at `s1`, which stays moderate because `s1` is a simple root even where two `mu_i`
/// meet. Inputs should be of order one (the DMV steps scale them so). `s3 = J1 J2 J3` is
/// positive for every body; `None` for a negative `s3` (the `mu_i` then do not give the
/// quartic's roots as above; found in review: `Some` of a non-root came back).
#[must_use]
pub fn quartic_largest_root<T: Real>(big_a: T, big_b: T, s3: T) -> Option<T> {
    if s3 < T::ZERO {
        return None;
    }
    let roots = solve_cubic(-big_a, big_b, -sq(s3))?;
    let s = match roots {
        CubicRoots::Real([m0, m1, m2]) => {
            if m0 < T::ZERO {
                return None;
            }
            m0.sqrt() + m1.sqrt() + m2.sqrt()
        }
        CubicRoots::Complex { real, re, im } => {
            if real < T::ZERO {
                return None;
            }
            let (u, _) = complex_sqrt(re, im);
            real.sqrt() + c::<T>(2.0) * u
        }
    };
    let s = polish_quartic(s, big_a, big_b, s3);
    if s.is_finite() {
        Some(s)
    } else {
        None
    }
}

/// Value and derivative of the DMV quartic at `s`.
#[inline]
fn quartic_eval<T: Real>(s: T, big_a: T, big_b: T, s3: T) -> (T, T) {
    let u = sq(s) - big_a;
    let q = sq(u) - c::<T>(8.0) * s3 * s - c::<T>(4.0) * big_b;
    let dq = c::<T>(4.0) * s * u - c::<T>(8.0) * s3;
    (q, dq)
}

fn polish_quartic<T: Real>(mut s: T, big_a: T, big_b: T, s3: T) -> T {
    let (mut q, mut dq) = quartic_eval(s, big_a, big_b, s3);
    let mut k = 0;
    while k < 3 && q != T::ZERO && dq != T::ZERO {
        let sn = s - q / dq;
        let (qn, dqn) = quartic_eval(sn, big_a, big_b, s3);
        if !(qn.abs() < q.abs()) {
            break;
        }
        s = sn;
        q = qn;
        dq = dqn;
        k += 1;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_rng::Lcg;

    /// The closed forms' guess, before any Newton step, on cubics built from their roots
    /// (three real roots: the trigonometric branch; one real root and a pair: Cardano's),
    /// scaled as `solve_cubic` scales them: within a few ulps of the root of largest
    /// magnitude where the roots are well apart, so the polish refines a right answer rather
    /// than hiding a wrong one.
    #[test]
    fn the_closed_forms_guess_the_largest_root_to_a_few_ulps() {
        let mut rng = Lcg(37);
        let (mut worst_trig, mut worst_cardano) = (0.0f64, 0.0f64);
        for _ in 0..20_000 {
            // three real roots at least 0.2 apart in [-1, 1]
            let mut r = [
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ];
            r.sort_by(f64::total_cmp);
            if r[1] - r[0] >= 0.2 && r[2] - r[1] >= 0.2 {
                let a = -(r[0] + r[1] + r[2]);
                let b = r[0] * r[1] + r[1] * r[2] + r[0] * r[2];
                let cc = -(r[0] * r[1] * r[2]);
                let big = if r[0].abs() > r[2].abs() { r[0] } else { r[2] };
                let g = largest_root_guess(a, b, cc);
                worst_trig = worst_trig.max((g - big).abs() / f64::EPSILON);
            }
            // one real root x and a pair re +- i im (im >= 0.2)
            let (x, re, im) = (
                rng.range(-1.0, 1.0),
                rng.range(-0.5, 0.5),
                rng.range(0.2, 0.6),
            );
            let a = -(x + 2.0 * re);
            let b = 2.0 * re * x + re * re + im * im;
            let cc = -x * (re * re + im * im);
            let g = largest_root_guess(a, b, cc);
            worst_cardano = worst_cardano.max((g - x).abs() / f64::EPSILON);
        }
        assert!(worst_trig <= 32.0, "trigonometric: {worst_trig} eps");
        assert!(worst_cardano <= 32.0, "Cardano: {worst_cardano} eps");
    }
}
