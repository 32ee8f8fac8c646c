//! `Body`: validation, the mass matrix, invariants, and the principal axes of a full
//! inertia tensor (recompose and compare).

#![allow(clippy::needless_range_loop)] // index loops read like the matrix formulas

mod common;

use common::{rotation as rot, Rng, TALK_I, TALK_J};
use proptest::prelude::*;
use rigid3::{Body, BodyError};

/// R diag(d) R^T
fn tensor(r: [[f64; 3]; 3], d: [f64; 3]) -> [[f64; 3]; 3] {
    let mut a = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            a[i][j] = (0..3).map(|k| r[i][k] * d[k] * r[j][k]).sum();
        }
    }
    a
}

fn max_diff(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> f64 {
    let mut e: f64 = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            e = e.max((a[i][j] - b[i][j]).abs());
        }
    }
    e
}

fn random_quat(rng: &mut Rng) -> [f64; 4] {
    let q = [
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    ];
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}

#[test]
fn bad_moments_are_named() {
    assert_eq!(
        Body::from_inertia([f64::NAN, 1.0, 1.0]),
        Err(BodyError::NonFinite)
    );
    assert_eq!(
        Body::from_inertia([1.0, f64::INFINITY, 1.0]),
        Err(BodyError::NonFinite)
    );
    assert_eq!(
        Body::from_inertia([1.0, 0.0, 1.0]),
        Err(BodyError::NonPositiveMoment)
    );
    assert_eq!(
        Body::from_inertia([1.0, 1.0, -2.0]),
        Err(BodyError::NonPositiveMoment)
    );
    assert_eq!(
        Body::from_inertia([1.0, 1.0, 3.0]),
        Err(BodyError::TriangleInequality)
    );
    assert_eq!(
        Body::from_inertia([1.0f32, 1.0, 2.001]),
        Err(BodyError::TriangleInequality)
    );
    assert_eq!(
        Body::from_mass_matrix([1.0, -0.1, 1.0]),
        Err(BodyError::NegativeMassMatrix)
    );
    assert_eq!(
        Body::from_mass_matrix([0.0, 0.0, 1.0]),
        Err(BodyError::NonPositiveMoment)
    );
    assert_eq!(
        Body::from_mass_matrix([0.0, f64::NAN, 1.0]),
        Err(BodyError::NonFinite)
    );
}

/// Subnormal moments: the mass matrix underflowed to zero and `Mv::max_step` returned NaN on
/// such a body (found in review: `[1e-45; 3]` in f32, `[5e-324; 3]` in f64), and a step that
/// `max_step` allowed was refused (`[1e-39, 1.2e-39, 1.5e-39]`). Refused at construction by
/// every constructor; the smallest normal body is kept, and its `max_step` is a number the
/// step honours.
#[test]
fn subnormal_moments_are_refused() {
    let sub = Some(BodyError::SubnormalMoment);
    assert_eq!(Body::<f32>::from_inertia([1e-45; 3]).err(), sub);
    assert_eq!(
        Body::<f32>::from_inertia([1e-39, 1.2e-39, 1.5e-39]).err(),
        sub
    );
    assert_eq!(Body::<f64>::from_inertia([5e-324; 3]).err(), sub);
    assert_eq!(
        Body::<f64>::from_inertia([1e-320, 1.0e-320, 1.0e-320]).err(),
        sub
    );
    assert_eq!(
        Body::<f64>::from_mass_matrix([1e-320, 1e-320, 1e-320]).err(),
        sub
    );
    assert_eq!(
        Body::<f32>::from_inertia_tensor([[1e-40, 0.0, 0.0], [0.0, 1e-40, 0.0], [0.0, 0.0, 1e-40]])
            .err(),
        sub
    );
    let tiny = f32::MIN_POSITIVE;
    let b = Body::<f32>::from_inertia([tiny * 2.0, tiny * 3.0, tiny * 4.0]).unwrap();
    let m = [tiny, -2.0 * tiny, 3.0 * tiny];
    let h = rigid3::Mv::max_step(&b, &m);
    assert!(h.is_finite() && h > 0.0, "max_step {h}");
    let mut s = m;
    rigid3::Integrator::step(&mut rigid3::Mv::new(b, 0.5 * h), &mut s).unwrap();
    let (c0, c1) = (b.casimir(&m), b.casimir(&s));
    assert!((c1 - c0).abs() <= 1e-5 * c0, "|m|^2 {c0} -> {c1}");
}

#[test]
fn planar_body_is_valid_despite_rounding() {
    // 0.1 + 0.2 != 0.3 in binary: the flat plate I3 = I1 + I2 must still be accepted
    let plate = Body::from_inertia([0.1f64, 0.2, 0.3]).unwrap();
    assert_eq!(plate.mass_matrix()[2], 0.0);
    let plate = Body::from_inertia([1.0f32, 2.0, 3.0]).unwrap();
    assert_eq!(plate.mass_matrix(), [2.0, 1.0, 0.0]);
}

#[test]
fn mass_matrix_and_inertia_round_trip() {
    // the talk's case: the shared constants TALK_J and TALK_I describe the same body
    let b = Body::<f64>::from_mass_matrix(TALK_J).unwrap();
    let i = b.inertia();
    assert!(
        i.iter().zip(TALK_I).all(|(x, y)| (x - y).abs() < 1e-15),
        "{i:?}"
    );
    let back = Body::from_inertia(i).unwrap().mass_matrix();
    for (x, y) in back.iter().zip(b.mass_matrix().iter()) {
        assert!((x - y).abs() < 1e-15);
    }
}

#[test]
fn invariants_match_their_definitions() {
    let b = Body::<f64>::from_inertia([0.6, 0.8, 1.0]).unwrap();
    let m = [1.8, 0.4, -0.9];
    let w = b.angular_velocity(&m);
    assert_eq!(w, [3.0, 0.5, -0.9]);
    // E = 1/2 m . Omega
    let e = 0.5 * (m[0] * w[0] + m[1] * w[1] + m[2] * w[2]);
    assert!((b.energy(&m) - e).abs() < 1e-15);
    assert!((b.casimir(&m) - 4.21).abs() < 1e-15);
}

fn check_tensor(d: [f64; 3], q: [f64; 4]) {
    let a = tensor(rot(q), d);
    let (body, frame) = Body::from_inertia_tensor(a).unwrap();
    let mut sorted = d;
    sorted.sort_by(|x, y| x.partial_cmp(y).unwrap());
    let scale = sorted[2];
    let got = body.inertia();
    // the test's tensor R D R^T is itself rounded (a few ulps of the scale per entry), and by
    // Weyl's inequality its eigenvalues may sit that far from D: 16 eps (8 eps failed once
    // in a proptest run at 1.6e-13 against 1.5e-13)
    for k in 0..3 {
        assert!(
            (got[k] - sorted[k]).abs() <= 16.0 * f64::EPSILON * scale,
            "{got:?} vs {sorted:?}"
        );
    }
    assert!(got[0] <= got[1] && got[1] <= got[2]);
    let n = frame.iter().map(|x| x * x).sum::<f64>();
    assert!((n - 1.0).abs() < 1e-15 && frame[0] >= 0.0);
    let r = rot(frame);
    assert!(
        max_diff(tensor(r, got), a) <= 16.0 * f64::EPSILON * scale,
        "recompose"
    );
    // sign convention: first two axes have their largest component positive (skipped on a
    // tie to round-off, where either component may lead)
    for col in 0..2 {
        let mut v = [r[0][col].abs(), r[1][col].abs(), r[2][col].abs()];
        let lead = [r[0][col], r[1][col], r[2][col]]
            .into_iter()
            .fold(0.0f64, |acc, x| if x.abs() > acc.abs() { x } else { acc });
        v.sort_by(|x, y| x.partial_cmp(y).unwrap());
        if v[2] - v[1] > 1e-12 {
            assert!(lead > 0.0, "axis {col} leads with {lead}");
        }
    }
}

#[test]
fn principal_axes_recompose_the_tensor() {
    let mut rng = Rng::new(5);
    for _ in 0..5000 {
        let a = rng.range(0.1, 2.0);
        let b = rng.range(0.1, 2.0);
        let c = rng.range((a - b).abs(), a + b);
        check_tensor([a, b, c], random_quat(&mut rng));
    }
}

#[test]
fn repeated_moments_recompose_the_tensor() {
    let mut rng = Rng::new(6);
    for _ in 0..1000 {
        let q = random_quat(&mut rng);
        check_tensor([1.0, 1.0, 1.5], q);
        check_tensor([2.0, 1.0, 2.0], q);
        check_tensor([0.7, 0.7, 0.7], q);
        check_tensor([1.0, 1.0 + 1e-9, 1.5], q);
    }
    // already diagonal and a permutation of the axes
    check_tensor([3.0, 1.0, 2.5], [1.0, 0.0, 0.0, 0.0]);
    check_tensor([3.0, 1.0, 2.5], [0.5, 0.5, 0.5, 0.5]);
}

#[test]
fn bad_tensors_are_named() {
    let a = tensor(rot([0.8, 0.6, 0.0, 0.0]), [1.0, 2.0, 2.5]);
    let mut b = a;
    b[0][1] += 1e-3;
    assert_eq!(
        Body::from_inertia_tensor(b).unwrap_err(),
        BodyError::NotSymmetric
    );
    let mut b = a;
    b[2][2] = f64::NAN;
    assert_eq!(
        Body::from_inertia_tensor(b).unwrap_err(),
        BodyError::NonFinite
    );
    let b = tensor(rot([0.8, 0.6, 0.0, 0.0]), [-1.0, 2.0, 2.5]);
    assert_eq!(
        Body::from_inertia_tensor(b).unwrap_err(),
        BodyError::NonPositiveMoment
    );
    let b = tensor(rot([0.8, 0.6, 0.0, 0.0]), [1.0, 1.0, 2.5]);
    assert_eq!(
        Body::from_inertia_tensor(b).unwrap_err(),
        BodyError::TriangleInequality
    );
}

#[test]
fn f32_tensor_recomposes() {
    let q = [0.9238795, 0.0, 0.3826834, 0.0];
    let a = tensor(rot(q), [1.0, 2.0, 2.5]);
    let a32 = a.map(|r| r.map(|x| x as f32));
    let (body, frame) = Body::<f32>::from_inertia_tensor(a32).unwrap();
    let got = body.inertia();
    assert!(
        (got[0] - 1.0).abs() < 1e-5 && (got[1] - 2.0).abs() < 1e-5 && (got[2] - 2.5).abs() < 1e-5
    );
    let r = rot(frame.map(|x| x as f64));
    assert!(max_diff(tensor(r, got.map(|x| x as f64)), a) < 1e-5);
}

proptest! {
    #[test]
    fn any_valid_tensor_recomposes(
        a in 0.01f64..100.0, b in 0.01f64..100.0, t in 0.0f64..1.0,
        q0 in -1.0f64..1.0, q1 in -1.0f64..1.0, q2 in -1.0f64..1.0, q3 in -1.0f64..1.0,
    ) {
        let n = (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3).sqrt();
        prop_assume!(n > 1e-3);
        let c = (a - b).abs() + t * (a + b - (a - b).abs());
        prop_assume!(c > 0.0);
        check_tensor([a, b, c], [q0 / n, q1 / n, q2 / n, q3 / n]);
    }
}

#[test]
fn errors_are_core_errors_without_any_feature() {
    fn describe(e: &dyn core::error::Error) -> String {
        e.to_string()
    }
    assert!(describe(&rigid3::BodyError::NonFinite).contains("NaN"));
    assert!(describe(&rigid3::StepError::StepTooLarge).contains("limit"));
    // and as a boxed std error, through `?`
    let boxed: Box<dyn std::error::Error> = rigid3::StepError::Overflow.into();
    assert!(boxed.to_string().contains("overflow"));
}

/// Homogeneity: `2^k A` has the eigenvalues `2^k lambda` and the same axes, and scaling by a
/// power of two rounds nothing, so every normal scale gives the scale-1 result bit for bit
/// (moments times `2^k`, the same frame). Regression (first-use trial): the sweeps' stopping
/// test summed squares, which overflowed from `1e154` in f64 (the diagonal came back, moments
/// 1 % off) and `1e19` in f32, and underflowed below `1e-155` (axes 0.22 rad off at `1e-165`).
#[test]
fn tensors_at_any_scale_decompose_as_at_scale_one() {
    let a = [[2.0, 0.1, 0.0], [0.1, 3.0, -0.2], [0.0, -0.2, 4.0]];
    let (b1, q1) = Body::<f64>::from_inertia_tensor(a).unwrap();
    for k in (-1000..=1000).step_by(10) {
        let s = 2f64.powi(k);
        let (b, q) = Body::<f64>::from_inertia_tensor(a.map(|r| r.map(|x| x * s))).unwrap();
        assert_eq!(q, q1, "2^{k}");
        assert_eq!(b.inertia(), b1.inertia().map(|x| x * s), "2^{k}");
    }
    // the trial's case against mpmath's eigsy (40 digits): moments 1.98990102456512e154,
    // 2.97140630649139e154, 4.03869266894349e154
    let (b, _) = Body::<f64>::from_inertia_tensor(a.map(|r| r.map(|x| x * 1e154))).unwrap();
    let want = [
        1.98990102456512e154,
        2.97140630649139e154,
        4.03869266894349e154,
    ];
    for (g, w) in b.inertia().into_iter().zip(want) {
        assert!(((g - w) / w).abs() < 1e-13, "{g:e} {w:e}");
    }
    let a32 = a.map(|r| r.map(|x| x as f32));
    let (b1, q1) = Body::<f32>::from_inertia_tensor(a32).unwrap();
    for k in -100..=100 {
        let s = 2f32.powi(k);
        let (b, q) = Body::<f32>::from_inertia_tensor(a32.map(|r| r.map(|x| x * s))).unwrap();
        assert_eq!(q, q1, "f32 2^{k}");
        assert_eq!(b.inertia(), b1.inertia().map(|x| x * s), "f32 2^{k}");
    }
    // a singular tensor near the top of the range (eigenvalues 0, 3.4e308, 1.7e308) is refused,
    // not returned as its diagonal
    let big = 1.7e308;
    let singular = [[big, big, 0.0], [big, big, 0.0], [0.0, 0.0, big]];
    assert!(Body::<f64>::from_inertia_tensor(singular).is_err());
}
