//! The public quaternion and frame API (issue 13): `Quaternion` and `Frame`.

mod common;

use common::*;
use rigid3::{Body, Frame, Integrator, Mv, Quaternion};

fn random_unit(rng: &mut Rng) -> Quaternion<f64> {
    Quaternion::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    )
    .normalize()
    .unwrap()
}

fn matvec(r: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2])
}

fn matmul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

fn qclose(a: Quaternion<f64>, b: Quaternion<f64>, tol: f64) -> bool {
    let (a, b) = (a.to_array(), b.to_array());
    let d: f64 = (0..4).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max);
    let s: f64 = (0..4).map(|i| (a[i] + b[i]).abs()).fold(0.0, f64::max);
    d.min(s) <= tol
}

#[test]
fn quaternion_operations_agree_with_rotation_matrices() {
    let mut rng = Rng::new(4);
    for _ in 0..1000 {
        let (p, q) = (random_unit(&mut rng), random_unit(&mut rng));
        let v = rng.direction().map(|x| x * rng.range(0.1, 10.0));
        let (rp, rq) = (p.to_rotation_matrix(), q.to_rotation_matrix());
        // rotate is R(q) v, inverse_rotate R(q)^T v
        assert!(dist(q.rotate(v), matvec(&rq, v)) <= 1e-14 * norm(v));
        assert!(dist(q.inverse_rotate(q.rotate(v)), v) <= 1e-14 * norm(v));
        assert!(dist(q.conjugate().rotate(v), q.inverse_rotate(v)) == 0.0);
        // composition: R(p q) = R(p) R(q), and * is compose
        let pq = (p * q).to_rotation_matrix();
        let prod = matmul(&rp, &rq);
        for i in 0..3 {
            assert!(dist(pq[i], prod[i]) <= 1e-14);
        }
        assert_eq!(p * q, p.compose(q));
        assert!(qclose(q * q.conjugate(), Quaternion::IDENTITY, 1e-15));
        // matrix round trip, w >= 0
        let back = Quaternion::from_rotation_matrix(rq).unwrap();
        assert!(back.w >= 0.0);
        assert!(qclose(back, q, 4e-16 * 8.0));
        // [w, x, y, z] at the array boundary
        assert_eq!(q.to_array(), [q.w, q.x, q.y, q.z]);
        assert_eq!(Quaternion::from_array(q.to_array()), q);
        assert_eq!(<[f64; 4]>::from(q), q.to_array());
        assert_eq!(Quaternion::from(q.to_array()), q);
    }
}

/// `to_rotation_vector` inverts `from_rotation_vector` (recompose and compare) for `q` and
/// `-q`, to a few ulps at every angle up to a half turn, and returns the shorter turn past it;
/// `angle_to` is the norm of the rotation vector between two attitudes, small angles
/// included (where `2 acos` of the dot product has half the digits: 1e-9 rad read 0 or 2.1e-8).
#[test]
fn rotation_vectors_recompose_and_angles_between_attitudes() {
    let mut rng = Rng(0x0005_eed0_fa11);
    let pi = core::f64::consts::PI;
    for k in 0..20_000 {
        let dir = rng.direction();
        // angles spread over decades, up to and past the half turn
        let angle = match k % 4 {
            0 => rng.range(0.0, pi),
            1 => 10f64.powf(rng.range(-12.0, 0.0)),
            2 => pi - 10f64.powf(rng.range(-8.0, -1.0)),
            _ => rng.range(pi, 2.0 * pi - 1e-3),
        };
        let v = dir.map(|x| x * angle);
        let q = Quaternion::from_rotation_vector(v);
        let neg = Quaternion::new(-q.w, -q.x, -q.y, -q.z);
        // past a half turn the same rotation is the shorter turn the other way
        let want = if angle <= pi {
            v
        } else {
            dir.map(|x| x * (angle - 2.0 * pi))
        };
        let scale = want.iter().map(|x| x.abs()).fold(0.0, f64::max);
        for got in [q.to_rotation_vector(), neg.to_rotation_vector()] {
            let err = (0..3).map(|i| (got[i] - want[i]).abs()).fold(0.0, f64::max);
            // relative to the angle; near a half turn the axis is set by |u| = sin(a/2) ~ 1
            // and the angle by w ~ 0: both well-conditioned
            let far = if angle > 3.0 { 2e-15 } else { 0.0 };
            assert!(
                err <= 1e-15 * scale + far,
                "{v:?}: {got:?} vs {want:?} ({err:e})"
            );
        }
        // angle_to: an attitude turned by v in the body frame, from a random attitude
        let turn = rng.range(0.0, 3.0);
        let a = Quaternion::from_rotation_vector(rng.direction().map(|x| x * turn));
        let b = a.compose(q);
        let want_angle = want.iter().map(|x| x * x).sum::<f64>().sqrt();
        // forming b rounds it by an ulp: an absolute error of about 1e-16 rad in the angle
        // (past about 3 rad, q's own rounding at from_rotation_vector is an ulp of one)
        let far = if angle > 3.0 { 2e-15 } else { 0.0 };
        let got = a.angle_to(b);
        assert!(
            (got - want_angle).abs() <= 1e-15 + 1e-15 * want_angle + far,
            "angle {angle:e}: {got:e} vs {want_angle:e}"
        );
        // from the identity nothing is rounded before: a few ulps of the angle itself
        let got = Quaternion::IDENTITY.angle_to(q);
        assert!(
            (got - want_angle).abs() <= 1e-15 * want_angle + far,
            "angle {angle:e}: {got:e} vs {want_angle:e}"
        );
        assert!(b.angle_to(b) <= 1e-15);
        assert!(a.angle_to(Quaternion::new(-a.w, -a.x, -a.y, -a.z)) <= 1e-15);
    }
    // f32: the small-angle digits survive in single precision too
    let a = Quaternion::<f32>::from_rotation_vector([0.3, -1.2, 0.7]);
    for angle in [1e-6f32, 1e-4, 0.3, 3.0] {
        let turn = Quaternion::from_rotation_vector([0.0, angle, 0.0]);
        let got = Quaternion::IDENTITY.angle_to(turn);
        assert!(
            (got - angle).abs() <= 4.0 * f32::EPSILON * angle,
            "{angle}: {got}"
        );
        // b rounded to f32 moves the angle by about an ulp of one (absolute)
        let got = a.angle_to(a.compose(turn));
        assert!(
            (got - angle).abs() <= 4.0 * f32::EPSILON * (1.0 + angle),
            "{angle}: {got}"
        );
    }
    // where the squares leave the normal range (found in review: a quaternion of size 1e200
    // gave NaN, a turn of 2e-170 rad gave zero, f32 angles below 1e-19 lost their digits)
    let half = core::f64::consts::FRAC_PI_2;
    let big = Quaternion::<f64>::new(1e200, 1e200, 0.0, 0.0).to_rotation_vector();
    assert!(
        (big[0] - half).abs() <= 4e-16 && big[1] == 0.0 && big[2] == 0.0,
        "{big:?}"
    );
    let big = Quaternion::<f32>::new(2e19, 2e19, 0.0, 0.0).to_rotation_vector();
    assert!((big[0] - half as f32).abs() <= 2e-7, "{big:?}");
    let tiny = Quaternion::<f64>::new(1.0, 1e-170, -3e-171, 0.0).to_rotation_vector();
    assert!((tiny[0] - 2e-170).abs() <= 4e-16 * 2e-170, "{tiny:?}");
    assert!((tiny[1] + 6e-171).abs() <= 4e-16 * 6e-171, "{tiny:?}");
    for angle in [1e-22f32, 1e-30, 1e-36] {
        let turn = Quaternion::from_rotation_vector([0.0, 0.0, angle]);
        let got = Quaternion::IDENTITY.angle_to(turn);
        assert!(
            (got - angle).abs() <= 4.0 * f32::EPSILON * angle,
            "{angle:e}: {got:e}"
        );
    }
    assert_eq!(Quaternion::<f64>::IDENTITY.to_rotation_vector(), [0.0; 3]);
    // finite quaternions whose |u| overflows, or whose angle / |u| does (found in review:
    // inf and NaN); oracle: the same direction at unit scale (powers of two scale exactly),
    // and the half turn about (1, 1, 0) / sqrt(2), pi / sqrt(2) per component
    let tiny = 2f64.powi(-1074);
    let unit = Quaternion::<f64>::new(8.0, 1.0, 0.0, 0.0).to_rotation_vector();
    let sub = Quaternion::<f64>::new(8.0 * tiny, tiny, 0.0, 0.0).to_rotation_vector();
    assert!(
        (sub[0] - unit[0]).abs() <= 4e-16 * unit[0] && sub[1] == 0.0,
        "{sub:?}"
    );
    let half_turn = Quaternion::<f64>::new(0.0, 2f64.powi(-1030), 0.0, 0.0).to_rotation_vector();
    assert!((half_turn[0] - pi).abs() <= 4e-16 * pi, "{half_turn:?}");
    let diag = pi / 2f64.sqrt();
    let huge = Quaternion::<f64>::new(1.0, 1.5e308, 1.5e308, 0.0).to_rotation_vector();
    assert!(
        (huge[0] - diag).abs() <= 4e-16 * diag && huge[0] == huge[1] && huge[2] == 0.0,
        "{huge:?}"
    );
    let huge = Quaternion::<f32>::new(0.0, 3.4e38, 3.4e38, 0.0).to_rotation_vector();
    assert!(
        (f64::from(huge[0]) - diag).abs() <= 2e-7 * diag && huge[0] == huge[1] && huge[2] == 0.0,
        "{huge:?}"
    );
    let bad = Quaternion::new(f64::NAN, 0.0, 0.0, 0.0).to_rotation_vector();
    assert!(bad.iter().any(|x| !x.is_finite()));
}

#[test]
fn rotations_by_half_turns_and_small_angles() {
    // Shepperd's branches: half turns about each axis (trace = -1) and near them
    for axis in [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.6, 0.0, 0.8],
    ] {
        for angle in [
            core::f64::consts::PI,
            core::f64::consts::PI - 1e-5,
            1e-9,
            0.0,
            -2.0,
        ] {
            let q = Quaternion::from_axis_angle(axis, angle);
            let back = Quaternion::from_rotation_matrix(q.to_rotation_matrix()).unwrap();
            assert!(qclose(back, q, 4e-16), "{axis:?} {angle}");
            // from_rotation_vector is from_axis_angle of (axis, |v|)
            let v = axis.map(|a| a * angle);
            let r = Quaternion::from_rotation_vector(v);
            assert!(qclose(r, q, 4e-16), "{axis:?} {angle}: {r:?} {q:?}");
        }
    }
    // the rotation vector's first order: exp(v/2) = (1, v/2) + O(v^2)
    let r = Quaternion::from_rotation_vector([2e-9, -4e-9, 6e-9]);
    assert_eq!(r.to_array(), [1.0, 1e-9, -2e-9, 3e-9]);
    assert_eq!(
        Quaternion::<f64>::from_rotation_vector([0.0; 3]),
        Quaternion::IDENTITY
    );
    // past the overflow of |v|^2 (about 1.8e19 in f32): still from_axis_angle of (axis, |v|),
    // whose angle the f64 oracle reduces from the same f32 |v| (review: all NaN at 1e30)
    for v in [
        [1e30f32, 0.0, 0.0],
        [3e19, -4e19, 1e19],
        [f32::MAX, f32::MAX, 0.0],
    ] {
        let r = Quaternion::from_rotation_vector(v).to_array();
        let n = v.map(f64::from);
        let norm = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let angle = f64::from((norm * 0.5) as f32);
        let want = [
            angle.cos(),
            n[0] / norm * angle.sin(),
            n[1] / norm * angle.sin(),
            n[2] / norm * angle.sin(),
        ];
        for k in 0..4 {
            assert!(
                (f64::from(r[k]) - want[k]).abs() < 1e-6,
                "{v:?}: {r:?} {want:?}"
            );
        }
    }
}

#[test]
fn quaternion_refusals() {
    assert_eq!(Quaternion::new(0.0f64, 0.0, 0.0, 0.0).normalize(), None);
    assert_eq!(Quaternion::new(f64::NAN, 1.0, 0.0, 0.0).normalize(), None);
    assert_eq!(
        Quaternion::new(f64::INFINITY, 1.0, 0.0, 0.0).normalize(),
        None
    );
    let n = Quaternion::new(0.0f64, 3.0, 0.0, 4.0).normalize().unwrap();
    assert!(qclose(n, Quaternion::new(0.0, 0.6, 0.0, 0.8), 2e-16));
    let mut bad = Quaternion::<f64>::IDENTITY.to_rotation_matrix();
    bad[1][2] = f64::NAN;
    assert_eq!(Quaternion::from_rotation_matrix(bad), None);
    assert_eq!(Quaternion::from_rotation_matrix([[0.0f64; 3]; 3]), None);
    let reflection = [[1.0f64, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]];
    assert_eq!(Quaternion::from_rotation_matrix(reflection), None);
    let mut sheared = Quaternion::<f64>::IDENTITY.to_rotation_matrix();
    sheared[0][1] = 0.1;
    assert_eq!(Quaternion::from_rotation_matrix(sheared), None);
    sheared[0][1] = 1e-6; // slightly off: a nearby unit rotation
    let q = Quaternion::from_rotation_matrix(sheared).unwrap();
    assert!((q.norm_squared() - 1.0).abs() < 1e-15);
    // f32
    let q = Quaternion::<f32>::from_axis_angle([0.0, 0.0, 1.0], 1.0);
    let v = q.rotate([1.0, 0.0, 0.0]);
    assert!((v[0] - 1f32.cos()).abs() < 1e-7 && (v[1] - 1f32.sin()).abs() < 1e-7);
}

#[test]
fn frame_moves_vectors_attitudes_and_states_between_the_tensor_and_principal_frames() {
    let mut rng = Rng::new(5);
    for _ in 0..200 {
        // a random tensor R diag(I) R^T in a random frame
        let j = [
            rng.range(0.1, 1.0),
            rng.range(0.1, 1.0),
            rng.range(0.1, 1.0),
        ];
        let i = [j[1] + j[2], j[0] + j[2], j[0] + j[1]];
        let r = random_unit(&mut rng).to_rotation_matrix();
        let tensor = [0, 1, 2]
            .map(|a| [0, 1, 2].map(|b| (0..3).map(|k| r[a][k] * i[k] * r[b][k]).sum::<f64>()));
        let (body, frame) = Frame::from_inertia_tensor(tensor).unwrap();
        let (body2, f) = Body::from_inertia_tensor(tensor).unwrap();
        assert_eq!(body, body2);
        assert_eq!(frame.quaternion().to_array(), f);
        // the tensor is diagonal in the principal frame: A v = R(f) diag(I) R(f)^T v
        let v = rng.direction();
        let av = matvec(&tensor, v);
        let vp = frame.to_principal(v);
        let ip = body.inertia();
        let back = frame.from_principal([ip[0] * vp[0], ip[1] * vp[1], ip[2] * vp[2]]);
        assert!(dist(av, back) <= 1e-13 * norm(av));
        // states: the spatial momentum is the same in both frames, and the round trip holds
        let q = random_unit(&mut rng).to_array();
        let s = frame.state_to_principal(av, q);
        let pi_tensor = Quaternion::from_array(q).rotate(av);
        assert!(dist(s.spatial_momentum(), pi_tensor) <= 1e-14 * norm(av));
        let (m2, q2) = frame.state_from_principal(&s);
        assert!(dist(m2, av) <= 1e-14 * norm(av));
        assert!(qclose(
            Quaternion::from_array(q2),
            Quaternion::from_array(q),
            1e-15
        ));
        // a sensor vector fixed in the structure keeps its direction in space along a step:
        // R(q_tensor) v_tensor = R(q_principal) v_principal
        let mut mv = Mv::new(body, 0.01);
        let mut x = s;
        mv.step_state(&mut x).unwrap();
        let (_, q_t) = frame.state_from_principal(&x);
        let a = Quaternion::from_array(q_t).rotate(v);
        let b = Quaternion::from_array(x.q).rotate(frame.to_principal(v));
        assert!(dist(a, b) <= 1e-14);
    }
}

/// `normalize` gives unit length and the same direction at any scale (regression, first-use
/// trial: `[3e-160, 4e-160, 0, 0]` came out `5.6e-6` off unit length in f64, `[3e-22, 4e-22, 0,
/// 0]` `1.1e-3` in f32, and `[3e200, 4e200, 0, 0]` was refused as `None`).
#[test]
fn normalize_at_any_scale() {
    for s in [1e-320, 1e-300, 3e-160, 1e-100, 1.0, 1e100, 1e200, 1e300] {
        let (x, z) = (3.0 * s / 5.0, 4.0 * s / 5.0);
        let n = Quaternion::new(0.0f64, x, 0.0, z).normalize().unwrap();
        // a subnormal input has few significant bits: its own direction, read at a normal
        // scale (times 2^1000, exact)
        let want = if s < 1e-300 {
            let k = 2f64.powi(1000);
            Quaternion::new(0.0, x * k, 0.0, z * k).normalize().unwrap()
        } else {
            Quaternion::new(0.0, 0.6, 0.0, 0.8)
        };
        assert!(qclose(n, want, 4e-16), "{s:e}: {n:?}");
        assert!(
            (n.norm_squared() - 1.0).abs() <= 4.0 * f64::EPSILON,
            "{s:e}"
        );
    }
    for s in [1e-44f32, 1e-30, 3e-22, 1.0, 1e20, 1e38] {
        let c = [0.3 * s, 0.4 * s, -0.5 * s, 0.1 * s];
        let n = Quaternion::from_array(c).normalize().unwrap();
        // a subnormal input (1e-44: a few significant bits) has its own direction
        let k = if s < 1e-38 { 2f32.powi(100) } else { 1.0 / s };
        let want = Quaternion::from_array(c.map(|x| x * k))
            .normalize()
            .unwrap();
        let d = n
            .to_array()
            .into_iter()
            .zip(want.to_array())
            .fold(0.0f32, |acc, (a, b)| acc.max((a - b).abs()));
        assert!(d <= 4.0 * f32::EPSILON, "{s:e}: {d:e}");
        assert!(
            (n.norm_squared() - 1.0).abs() <= 4.0 * f32::EPSILON,
            "{s:e}"
        );
    }
}
