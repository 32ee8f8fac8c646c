//! Cubic and quartic roots against roots built in advance (exact integer cases and
//! rounded random ones with the condition-number bound of the module docs), and the f32
//! routine against the f64 one as the higher-precision oracle.

#![allow(clippy::needless_range_loop)] // index loops read like the matrix formulas

mod common;

use common::Rng;
use rigid3::cubic::{quartic_largest_root, solve_cubic, CubicRoots};

/// Coefficients of (x - r0)(x - r1)(x - r2), monic.
fn coeffs(r: [f64; 3]) -> (f64, f64, f64) {
    (
        -(r[0] + r[1] + r[2]),
        r[0] * r[1] + r[0] * r[2] + r[1] * r[2],
        -(r[0] * r[1] * r[2]),
    )
}

/// The forward-error bound of a simple root the module docs state:
/// 8 eps sum|terms| / |p'(r)|.
fn bound(r: f64, a: f64, b: f64, c: f64, eps: f64) -> f64 {
    let terms = r.abs().powi(3) + a.abs() * r * r + b.abs() * r.abs() + c.abs();
    let dp = (3.0 * r * r + 2.0 * a * r + b).abs();
    8.0 * eps * terms / dp
}

fn real_roots(a: f64, b: f64, c: f64) -> [f64; 3] {
    match solve_cubic(a, b, c).unwrap() {
        CubicRoots::Real(r) => r,
        other => panic!("expected three real roots of {a} {b} {c}, got {other:?}"),
    }
}

#[test]
fn integer_roots_are_exact_to_a_few_ulps() {
    for roots in [
        [1.0, 2.0, 3.0],
        [-5.0, 0.0, 7.0],
        [-3.0, -1.0, 4.0],
        [0.0, 1.0, 1e3],
    ] {
        let (a, b, c) = coeffs(roots);
        let got = real_roots(a, b, c);
        for (g, r) in got.iter().zip(roots.iter()) {
            assert!(
                (g - r).abs() <= 4.0 * f64::EPSILON * r.abs().max(1.0),
                "{got:?} vs {roots:?}"
            );
        }
    }
}

#[test]
fn random_simple_roots_meet_the_condition_number_bound() {
    let mut rng = Rng::new(1);
    for _ in 0..20_000 {
        let mut roots = [
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ];
        let scale = 10f64.powf(rng.range(-6.0, 6.0));
        for r in &mut roots {
            *r *= scale;
        }
        roots.sort_by(|x, y| x.partial_cmp(y).unwrap());
        let (a, b, c) = coeffs(roots);
        match solve_cubic(a, b, c).unwrap() {
            CubicRoots::Real(got) => {
                for (g, r) in got.iter().zip(roots.iter()) {
                    let tol = bound(*r, a, b, c, f64::EPSILON);
                    assert!(
                        (g - r).abs() <= tol,
                        "root {r} got {g} tol {tol:e} ({roots:?})"
                    );
                }
            }
            // a near-double pair can be rounded into a complex pair: then the pair must be
            // within the (huge) bound of the true roots
            CubicRoots::Complex { real, re, im } => {
                let tol = bound(roots[1], a, b, c, f64::EPSILON);
                assert!(
                    im <= tol && (re - roots[1]).abs() <= tol,
                    "{roots:?}: {real} {re} {im}"
                );
            }
        }
    }
}

/// One root far larger than the other two (up to `1e15` apart): the small roots keep their
/// digits. Deflating with the sum `-(a + r)` alone cancelled it to round-off of the large
/// root, and the small roots came out 5.7e-3 and 1.5e-3 off (relative) on the review's case,
/// 9e11 times the bound (found in review). Oracles: mpmath at 60 digits for that case; for a
/// sweep of separations, the f64 routine on the same (f32) coefficients for the f32 one, and
/// roots built in advance with the bound for the f64 one.
#[test]
fn widely_separated_roots_keep_the_small_ones() {
    let got = real_roots(
        -4.523_712_145_035_148_4e7,
        -6.106_395_668_789_611,
        -1.391_766_247_159_223_5e-7,
    );
    // mpmath, 60 digits
    let want = [
        -1.059_474_420_152_312_3e-7,
        -2.903_894_688_423_643_4e-8,
        4.523_712_145_035_162e7,
    ];
    for k in 0..3 {
        let rel = (got[k] - want[k]).abs() / want[k].abs();
        assert!(rel <= 1e-14, "{got:?} vs {want:?}");
    }
    for big in [1e2, 1e4, 1e6, 1e8, 1e10, 1e12, 1e15] {
        for (r1, r2) in [(-0.1, -0.03), (0.1, -0.03), (0.07, 0.02)] {
            let roots = [r1, r2, big];
            let (a, b, c) = coeffs(roots);
            let got = real_roots(a, b, c);
            let small = [got[0], got[1]];
            let mut want = [r1, r2];
            want.sort_by(|x, y| x.partial_cmp(y).unwrap());
            for k in 0..2 {
                let tol = bound(want[k], a, b, c, f64::EPSILON);
                assert!(
                    (small[k] - want[k]).abs() <= tol,
                    "big {big:e}: {got:?} vs {roots:?}, tol {tol:e}"
                );
            }
            // f32 on the rounded coefficients, against f64 on the same numbers
            let (a32, b32, c32) = (a as f32, b as f32, c as f32);
            let exact = real_roots(f64::from(a32), f64::from(b32), f64::from(c32));
            if let Some(CubicRoots::Real(g32)) = solve_cubic(a32, b32, c32) {
                for k in 0..3 {
                    let (a, b, c) = (f64::from(a32), f64::from(b32), f64::from(c32));
                    let tol = bound(exact[k], a, b, c, f64::from(f32::EPSILON));
                    assert!(
                        (f64::from(g32[k]) - exact[k]).abs() <= tol,
                        "f32 big {big:e}: {g32:?} vs {exact:?}"
                    );
                }
            } else {
                panic!("f32 big {big:e}: not three real roots");
            }
        }
    }
}

#[test]
fn complex_pairs_are_found() {
    let mut rng = Rng::new(2);
    for _ in 0..20_000 {
        let real = rng.range(-2.0, 2.0);
        let re = rng.range(-2.0, 2.0);
        let im = rng.range(0.01, 2.0);
        // (x - real)(x^2 - 2 re x + re^2 + im^2)
        let p = -2.0 * re;
        let q = re * re + im * im;
        let (a, b, c) = (p - real, q - real * p, -real * q);
        let CubicRoots::Complex {
            real: g,
            re: gr,
            im: gi,
        } = solve_cubic(a, b, c).unwrap()
        else {
            panic!("expected a complex pair")
        };
        let scale = real.abs().max(q.sqrt()).max(1.0);
        let tol = 1e3 * f64::EPSILON * scale * (1.0 + scale / im);
        assert!((g - real).abs() <= tol, "{g} vs {real}");
        assert!(
            (gr - re).abs() <= tol && (gi - im).abs() <= tol,
            "{gr}+{gi}i vs {re}+{im}i"
        );
    }
}

#[test]
fn zero_coefficients_and_special_shapes() {
    assert_eq!(
        solve_cubic(0.0f64, 0.0, 0.0),
        Some(CubicRoots::Real([0.0; 3]))
    );
    // x^3 - x = x (x - 1)(x + 1)
    assert_eq!(real_roots(0.0, -1.0, 0.0), [-1.0, 0.0, 1.0]);
    // regression: x^3 - 1.5e-200 x^2, where 1 / scale^2 overflows
    assert_eq!(real_roots(-1.5e-200, 0.0, 0.0), [0.0, 0.0, 1.5e-200]);
    // x^3 + x: 0 and +-i
    let CubicRoots::Complex { real, re, im } = solve_cubic(0.0f64, 1.0, 0.0).unwrap() else {
        panic!()
    };
    assert_eq!(real, 0.0);
    assert!(re.abs() < 1e-16 && (im - 1.0).abs() < 1e-15);
    // x^3 - 8: 2 and -1 +- i sqrt 3
    let CubicRoots::Complex { real, re, im } = solve_cubic(0.0f64, 0.0, -8.0).unwrap() else {
        panic!()
    };
    assert!((real - 2.0).abs() < 1e-15 && (re + 1.0).abs() < 1e-15);
    assert!((im - 3f64.sqrt()).abs() < 1e-15);
}

#[test]
fn double_and_triple_roots_to_root_eps() {
    // (x - 1)^2 (x - 2): the double root to sqrt(eps), the simple one to eps
    let (a, b, c) = coeffs([1.0, 1.0, 2.0]);
    let (lo, hi) = match solve_cubic(a, b, c).unwrap() {
        CubicRoots::Real(r) => ((r[0], r[1]), r[2]),
        CubicRoots::Complex { real, re, .. } => ((re, re), real),
    };
    assert!((lo.0 - 1.0).abs() < 1e-7 && (lo.1 - 1.0).abs() < 1e-7);
    assert!((hi - 2.0).abs() < 1e-14);
    // (x - 3)^3
    let (a, b, c) = coeffs([3.0, 3.0, 3.0]);
    match solve_cubic(a, b, c).unwrap() {
        CubicRoots::Real(r) => assert!(r.iter().all(|x| (x - 3.0).abs() < 1e-4)),
        CubicRoots::Complex { real, re, im } => {
            assert!((real - 3.0).abs() < 1e-4 && (re - 3.0).abs() < 1e-4 && im < 1e-4)
        }
    }
}

#[test]
fn widely_scaled_coefficients_do_not_overflow() {
    for s in [1e-90, 1e-60, 1e60, 1e90] {
        let roots = [-2.0 * s, 0.5 * s, 3.0 * s];
        let (a, b, c) = coeffs(roots);
        let got = real_roots(a, b, c);
        for (g, r) in got.iter().zip(roots.iter()) {
            assert!(((g - r) / r).abs() < 1e-14, "scale {s:e}: {got:?}");
        }
    }
    // roots spread over 16 orders of magnitude
    let roots = [1e-8, 1.0, 1e8];
    let (a, b, c) = coeffs(roots);
    let got = real_roots(a, b, c);
    for (g, r) in got.iter().zip(roots.iter()) {
        assert!(((g - r) / r).abs() < 1e-12, "{got:?}");
    }
}

#[test]
fn non_finite_coefficients_give_none() {
    assert_eq!(solve_cubic(f64::NAN, 0.0, 1.0), None);
    assert_eq!(solve_cubic(0.0, f64::INFINITY, 1.0), None);
    assert_eq!(solve_cubic(0.0f32, 0.0, f32::NEG_INFINITY), None);
}

#[test]
fn f32_roots_agree_with_the_f64_oracle() {
    let mut rng = Rng::new(3);
    for _ in 0..20_000 {
        let (a, b, c) = (
            rng.range(-3.0, 3.0) as f32,
            rng.range(-3.0, 3.0) as f32,
            rng.range(-3.0, 3.0) as f32,
        );
        let hi = solve_cubic(a as f64, b as f64, c as f64).unwrap();
        let lo = solve_cubic(a, b, c).unwrap();
        let eps = f32::EPSILON as f64;
        let (a, b, c) = (a as f64, b as f64, c as f64);
        match (hi, lo) {
            (CubicRoots::Real(h), CubicRoots::Real(l)) => {
                for (x, y) in h.iter().zip(l.iter()) {
                    let tol = bound(*x, a, b, c, eps).max(4.0 * eps * x.abs());
                    assert!((x - *y as f64).abs() <= tol, "{h:?} vs {l:?}");
                }
            }
            (
                CubicRoots::Complex { real: x, re, im },
                CubicRoots::Complex {
                    real: y,
                    re: r2,
                    im: i2,
                },
            ) => {
                let tol = bound(x, a, b, c, eps).max(4.0 * eps * x.abs());
                assert!((x - y as f64).abs() <= tol);
                let scale = re.abs().max(im).max(1.0);
                assert!((re - r2 as f64).abs() <= 64.0 * eps * scale * (1.0 + scale / im));
                assert!((im - i2 as f64).abs() <= 64.0 * eps * scale * (1.0 + scale / im));
            }
            // near a double root the classification may differ: both answers then lie
            // within sqrt(eps32) of each other
            (h, l) => {
                let pick = |r: CubicRoots<f64>| match r {
                    CubicRoots::Real(v) => v[1],
                    CubicRoots::Complex { re, .. } => re,
                };
                let l = match l {
                    CubicRoots::Real(v) => {
                        CubicRoots::Real([v[0] as f64, v[1] as f64, v[2] as f64])
                    }
                    CubicRoots::Complex { real, re, im } => CubicRoots::Complex {
                        real: real as f64,
                        re: re as f64,
                        im: im as f64,
                    },
                };
                assert!((pick(h) - pick(l)).abs() < 1e-2, "{h:?} vs {l:?}");
            }
        }
    }
}

/// The quartic's roots are the signed sums of lambda_i = sqrt(mu_i) with an even number of
/// minus signs; the largest real one is the plain sum.
#[test]
fn quartic_largest_root_is_the_sum_of_principal_square_roots() {
    let mut rng = Rng::new(4);
    for k in 0..20_000 {
        let (s_true, big_a, big_b, s3) = if k % 2 == 0 {
            let l = [
                rng.range(0.01, 2.0),
                rng.range(0.01, 2.0),
                rng.range(0.01, 2.0),
            ];
            let mu = [l[0] * l[0], l[1] * l[1], l[2] * l[2]];
            (
                l[0] + l[1] + l[2],
                mu[0] + mu[1] + mu[2],
                mu[0] * mu[1] + mu[0] * mu[2] + mu[1] * mu[2],
                l[0] * l[1] * l[2],
            )
        } else {
            // lambda_1 real, lambda_2,3 = u +- i v with u > 0
            let l1 = rng.range(0.01, 2.0);
            let u = rng.range(0.01, 2.0);
            let v = rng.range(0.0, 2.0);
            let m1 = l1 * l1;
            let (mr, mi) = (u * u - v * v, 2.0 * u * v);
            let mabs2 = mr * mr + mi * mi;
            (
                l1 + 2.0 * u,
                m1 + 2.0 * mr,
                2.0 * m1 * mr + mabs2,
                l1 * (u * u + v * v),
            )
        };
        let s = quartic_largest_root(big_a, big_b, s3).unwrap();
        let tol = 1e-12 * s_true.max(1.0) * (1.0 + 1e-2 / s3.min(1.0));
        assert!((s - s_true).abs() <= tol, "{s} vs {s_true}");
    }
}

#[test]
fn quartic_with_a_negative_mu_has_no_dmv_root() {
    // mu = (-1, 2, 3): A = 4, B = -2 - 3 + 6 = 1, C = -6 cannot be s3^2; use mu = (-1, -2, 3)
    // which has C = 6 = s3^2 with s3 = sqrt 6
    let mu = [-1.0f64, -2.0, 3.0];
    let big_a = mu[0] + mu[1] + mu[2];
    let big_b = mu[0] * mu[1] + mu[0] * mu[2] + mu[1] * mu[2];
    let s3 = (mu[0] * mu[1] * mu[2]).sqrt();
    assert_eq!(quartic_largest_root(big_a, big_b, s3), None);
    assert_eq!(quartic_largest_root(f64::NAN, 1.0, 1.0), None);
    // a negative s3 is no body's (review: Some(0.4813) came back, where the quartic is 9.29;
    // its real roots are -2.435 and -0.807)
    let (a, b, s3) = (2.3747199913755264, -0.4579689017168187, -0.7429634373670322);
    assert_eq!(quartic_largest_root(a, b, s3), None);
}
