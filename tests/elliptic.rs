//! Carlson's `R_C` and `R_J` where their arguments are far apart, against mpmath
//! (lab/refs/carlson_refs.txt, made by lab/refs/make_carlson_refs.py): `R_C(x, y)` for
//! `x / y` from `1e-12` to `1e12`, `R_J(x, y, z, p)` for `p` from `1e-13` to `1e13` times the
//! others and between them; Legendre's `Pi(n; phi | m)` for `n` from `-1` to `-1e21`. Every
//! input is an f32 value, so one table checks both precisions.

use rigid3::elliptic::{carlson_rc, carlson_rf, carlson_rj, incomplete_pi};

struct Row {
    kind: &'static str,
    args: Vec<f64>,
    reference: f64,
}

fn rows() -> Vec<Row> {
    include_str!("../lab/refs/carlson_refs.txt")
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let mut it = l.split_whitespace();
            let kind = it.next().unwrap();
            let nums: Vec<f64> = it.map(|w| w.parse().unwrap()).collect();
            let (reference, args) = nums.split_last().unwrap();
            Row {
                kind,
                args: args.to_vec(),
                reference: *reference,
            }
        })
        .collect()
}

fn value<T: rigid3::Real>(row: &Row, of: impl Fn(f64) -> T) -> Option<T> {
    let a = &row.args;
    match row.kind {
        "rc" => carlson_rc(of(a[0]), of(a[1])),
        "rj" => carlson_rj(of(a[0]), of(a[1]), of(a[2]), of(a[3])),
        "pi" => incomplete_pi(of(a[0]), of(a[1]), of(a[2])),
        _ => unreachable!(),
    }
}

/// The worst relative error in units of `eps` over the rows of one kind.
fn worst(kind: &str, eps: f64, eval: impl Fn(&Row) -> Option<f64>) -> (f64, String) {
    let mut worst = (0.0, String::new());
    let mut n = 0;
    for row in rows().iter().filter(|r| r.kind == kind) {
        let got = eval(row).unwrap_or(f64::NAN);
        let err = (got - row.reference).abs() / row.reference / eps;
        assert!(err.is_finite(), "{kind}{:?}: {got}", row.args);
        if err > worst.0 {
            worst = (err, format!("{kind}{:?}", row.args));
        }
        n += 1;
    }
    assert!(n > 40, "{kind}: {n} rows");
    worst
}

/// The worst errors over one kind's rows, in f64 and in f32 (each in its own `eps`), printed
/// and asserted within `bound` eps.
fn check_kind(kind: &str, name: &str, bound: f64) {
    let (e64, at64) = worst(kind, f64::EPSILON, |r| value(r, |x| x));
    let (e32, at32) = worst(kind, f64::from(f32::EPSILON), |r| {
        value(r, |x| x as f32).map(f64::from)
    });
    println!("{name} worst: f64 {e64:.2} eps at {at64}, f32 {e32:.2} eps at {at32}");
    assert!(e64 <= bound && e32 <= bound);
}

#[test]
fn rc_keeps_a_few_ulps_at_every_ratio() {
    // the docs' "a few ulps": 5 eps
    check_kind("rc", "R_C", 5.0);
}

#[test]
fn rj_keeps_a_few_ulps_with_p_far_from_the_others() {
    check_kind("rj", "R_J", 8.0);
}

/// `Pi(n; phi | m)` at large negative `n` (a nearly symmetric body's attitude, crate::exact),
/// where `F` and `(n / 3) sin^3 phi R_J` cancelled (1100 ulps in f64 at `n = -3e5`, 1.7e-4
/// relative in f32 at `n = -1e6`): through the change of parameter of `R_J` it keeps a few
/// ulps, `phi` past a half turn and near `pi / 2` with `m` near one included; and at `n` near
/// one near `pi / 2`, where `1 - n sin^2 phi` cancelled (quadrature and mpmath's own `Pi` at
/// 60 digits).
#[test]
fn pi_keeps_a_few_ulps_at_extreme_characteristics() {
    check_kind("pi", "Pi", 8.0);
}

/// `R_C(x, y) = R_F(x, y, y)` (DLMF 19.2.17): two algorithms, at ratios of `x / y` out to
/// `1e±30` and in between the table's (R_F's duplication has no special case to share).
#[test]
fn rc_equals_rf_with_two_equal_arguments() {
    let mut worst = 0.0f64;
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    for _ in 0..20_000 {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let u = (state >> 11) as f64 / (1u64 << 53) as f64;
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let v = (state >> 11) as f64 / (1u64 << 53) as f64;
        let y = 10f64.powf(4.0 * v - 2.0);
        let x = y * 10f64.powf(60.0 * u - 30.0);
        let rc = carlson_rc(x, y).unwrap();
        let rf = carlson_rf(x, y, y).unwrap();
        worst = worst.max((rc - rf).abs() / rf / f64::EPSILON);
    }
    println!("R_C against R_F(x, y, y): worst {worst:.2} eps");
    assert!(worst <= 8.0);
}

/// Arguments so far apart that no power-of-four scale keeps the duplication's products normal
/// are refused, not answered wrongly; the ones a scale keeps are answered. Found in review:
/// scaled by the largest argument alone, f32 `R_J(1e-30, 1.3e-30, 2.1e-30, 1e-10)` settled at
/// subnormal products (0.75 % off), and in steps of `2^80` scales that existed were missed
/// (`R_J(1e-30, 1, 1, 1e30)` refused; in the table above now). Oracle: mpmath (f64 subnormal
/// arguments, which the f32-valued table cannot hold), the domain, and that a result below
/// the normal range has no relative accuracy.
#[test]
fn rj_answers_what_a_scale_keeps_normal_and_refuses_the_rest() {
    // mpmath at 60 digits
    for (args, reference) in [
        ([1.0f64, 5e-323, 1.0, 2e-323], 5.684_791_406_522_584e161),
        ([1e-290, 1e190, 1e190, 1e190], 2.356_194_490_192_344_7e-285),
        // all tiny: the scale f64 has is capped, not refused
        ([1e-200, 1e-200, 1e-200, 1e-200], 1e300),
        ([0.0, 1e-190, 1e-190, 1e-190], 2.356_194_490_192_345e285),
    ] {
        let got = carlson_rj(args[0], args[1], args[2], args[3]).unwrap();
        let err = (got - reference).abs() / reference / f64::EPSILON;
        assert!(err <= 8.0, "{args:?}: {got:e}, {err:.1} eps");
    }
    // the settled level (p, or two of x, y, z) below the range after the best scale
    assert_eq!(carlson_rj(1e-40f32, 1e-40, 1.0, 1e30), None);
    assert_eq!(carlson_rj(1.0f64, 1.0, 1.0, 1e-300 * 1e-300), None);
    // results below the normal range: refused (f32 `R_J(1e30, ...)` is 1.0e-45)
    assert_eq!(carlson_rj(1e30f32, 1e30, 1e30, 1e30), None);
    assert_eq!(carlson_rj(3e38f32, 3e38, 3e38, 3e38), None);
    // and never a non-finite value: the largest and smallest finite arguments
    for (x, p) in [(f32::MAX, f32::MIN_POSITIVE), (f32::MIN_POSITIVE, f32::MAX)] {
        assert!(carlson_rj(x, x, x, p).is_none_or(f32::is_finite));
    }
    for (x, p) in [(f64::MAX, f64::MIN_POSITIVE), (f64::MIN_POSITIVE, f64::MAX)] {
        assert!(carlson_rj(x, x, x, p).is_none_or(f64::is_finite));
    }
}
