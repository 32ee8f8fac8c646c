//! [`crate::Mv::max_step`]: the largest step for which the DMV step exists, from the
//! polynomial conditions alone (docs/MATH.md §3).
//!
//! The step from `m` exists iff the cubic `mu^3 - A mu^2 + B mu - C` has no negative real root
//! (the existence argument in [`crate::Mv`]'s module docs: `A > 0 && B > 0`, or a negative
//! discriminant). With `t = (h |m|_max / kappa)^2`, `A(t) = a0 - a1 t` and `B(t) = b0 - b1 t`
//! fall linearly and `C` is constant, so the discriminant
//! `D(t) = 18 A B C - 4 A^3 C + A^2 B^2 - 4 B^3 - 27 C^2` is a quartic in `t`, formed here
//! from the products of the two linear polynomials (`mul11`, `mul21`, `mul22`). The limit is
//! the first `t >= t0` (where `A` or `B` reaches zero) at which `D(t) >= 0`.

use crate::body::Body;
use crate::cubic::{solve_cubic, CubicRoots};
use crate::linalg::Vec3;
use crate::real::{c, sq, Real};

/// The largest `|h|` for which the DMV step from `m` exists; `T::MAX` for `m = 0`, zero for a
/// non-finite `m`.
pub(crate) fn max_step<T: Real>(body: &Body<T>, m: &[T; 3]) -> T {
    let m = Vec3::from_array(*m);
    if !m.is_finite() {
        return T::ZERO;
    }
    let r = m.max_abs();
    if r == T::ZERO {
        return T::MAX;
    }
    let j = body.mass_matrix_vec();
    let kappa = j.max_abs();
    // divide, not multiply by a reciprocal: 1 / r overflows for a subnormal r
    let jn = Vec3::new(j.x / kappa, j.y / kappa, j.z / kappa);
    let mn = Vec3::new(m.x / r, m.y / r, m.z / r);
    let j2 = jn.mul_elem(jn);
    let a2 = mn.mul_elem(mn);
    // A(t) = a0 - a1 t, B(t) = b0 - b1 t, with t = (h r / kappa)^2
    let a0 = j2.x + j2.y + j2.z;
    let a1 = a2.x + a2.y + a2.z;
    let b0 = j2.x * j2.y + j2.x * j2.z + j2.y * j2.z;
    let b1 = a2.dot(j2);
    let cc = sq(jn.x * jn.y * jn.z);
    let t_a = a0 / a1;
    let t0 = if b1 > T::ZERO { t_a.min(b0 / b1) } else { t_a };
    // D(t) as a polynomial, lowest degree first
    let pa = [a0, -a1];
    let pb = [b0, -b1];
    let ab = mul11(pa, pb);
    let a_2 = mul11(pa, pa);
    let b_2 = mul11(pb, pb);
    let a_3 = mul21(a_2, pa);
    let b_3 = mul21(b_2, pb);
    let a2b2 = mul22(a_2, b_2);
    let k18 = c::<T>(18.0) * cc;
    let k4 = c::<T>(4.0) * cc;
    let four = c::<T>(4.0);
    let d = [
        k18 * ab[0] - k4 * a_3[0] + a2b2[0] - four * b_3[0] - c::<T>(27.0) * sq(cc),
        k18 * ab[1] - k4 * a_3[1] + a2b2[1] - four * b_3[1],
        k18 * ab[2] - k4 * a_3[2] + a2b2[2] - four * b_3[2],
        -k4 * a_3[3] + a2b2[3] - four * b_3[3],
        a2b2[4],
    ];
    let t = first_nonnegative(&d, t0);
    (t.sqrt() * kappa / r).min(T::MAX)
}

fn mul11<T: Real>(p: [T; 2], q: [T; 2]) -> [T; 3] {
    [p[0] * q[0], p[0] * q[1] + p[1] * q[0], p[1] * q[1]]
}

fn mul21<T: Real>(p: [T; 3], q: [T; 2]) -> [T; 4] {
    [
        p[0] * q[0],
        p[0] * q[1] + p[1] * q[0],
        p[1] * q[1] + p[2] * q[0],
        p[2] * q[1],
    ]
}

fn mul22<T: Real>(p: [T; 3], q: [T; 3]) -> [T; 5] {
    [
        p[0] * q[0],
        p[0] * q[1] + p[1] * q[0],
        p[0] * q[2] + p[1] * q[1] + p[2] * q[0],
        p[1] * q[2] + p[2] * q[1],
        p[2] * q[2],
    ]
}

fn eval4<T: Real>(d: &[T; 5], t: T) -> T {
    (((d[4] * t + d[3]) * t + d[2]) * t + d[1]) * t + d[0]
}

/// The smallest `t >= t0` with `D(t) >= 0`, for a quartic `D` with positive leading
/// coefficient: `D` is monotone between the real roots of `D'`, so each piece is checked at
/// its ends and bisected where `D` changes sign.
fn first_nonnegative<T: Real>(d: &[T; 5], t0: T) -> T {
    if !(eval4(d, t0) < T::ZERO) {
        return t0;
    }
    // critical points: roots of D'(t) = 4 d4 t^3 + 3 d3 t^2 + 2 d2 t + d1
    let lead = c::<T>(4.0) * d[4];
    let mut breaks = [T::MAX; 3];
    if lead != T::ZERO {
        if let Some(roots) = solve_cubic(
            c::<T>(3.0) * d[3] / lead,
            c::<T>(2.0) * d[2] / lead,
            d[1] / lead,
        ) {
            match roots {
                CubicRoots::Real(r) => breaks = r,
                CubicRoots::Complex { real, .. } => breaks[0] = real,
            }
        }
    }
    let mut lo = t0;
    for &b in breaks.iter() {
        if b > lo && b < T::MAX {
            if !(eval4(d, b) < T::ZERO) {
                return bisect(d, lo, b);
            }
            lo = b;
        }
    }
    // past the last critical point D rises to +infinity: bracket by doubling
    let mut hi = if lo > T::ONE { lo } else { T::ONE };
    let mut k = 0;
    while eval4(d, hi) < T::ZERO && k < 2100 {
        lo = hi;
        hi = hi + hi;
        k += 1;
    }
    bisect(d, lo, hi)
}

/// Bisection for the sign change of `D` in `[lo, hi]` (`D(lo) < 0 <= D(hi)`) to `2 eps`.
fn bisect<T: Real>(d: &[T; 5], mut lo: T, mut hi: T) -> T {
    let mut k = 0;
    while hi - lo > c::<T>(2.0) * T::EPSILON * hi && k < 2200 {
        let mid = lo + (hi - lo) * c(0.5);
        if eval4(d, mid) < T::ZERO {
            lo = mid;
        } else {
            hi = mid;
        }
        k += 1;
    }
    lo
}
