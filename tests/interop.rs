//! The `mint` and `micromath` conversions (`cargo test --features mint,micromath`): field
//! order checked by rotating a vector on both sides, not only by comparing components.
#![cfg(any(feature = "mint", feature = "micromath"))]

use rigid3::{Quaternion, State};

/// A rotation by 90 degrees about z, `[w, x, y, z]`: takes x to y.
fn quarter_turn_z() -> Quaternion<f32> {
    let h = core::f32::consts::FRAC_1_SQRT_2;
    Quaternion::new(h, 0.0, 0.0, h)
}

#[cfg(feature = "mint")]
#[test]
fn mint_quaternions_are_x_y_z_then_w() {
    let q = Quaternion::new(0.1f64, 0.2, 0.3, 0.4);
    let m: mint::Quaternion<f64> = q.into();
    assert_eq!(m.s, 0.1);
    assert_eq!([m.v.x, m.v.y, m.v.z], [0.2, 0.3, 0.4]);
    // mint's own array order is [x, y, z, w] (glam, nalgebra)
    let arr: [f64; 4] = m.into();
    assert_eq!(arr, [0.2, 0.3, 0.4, 0.1]);
    assert_eq!(Quaternion::from(m), q);
    assert_eq!(
        Quaternion::from(mint::Quaternion::from([0.2, 0.3, 0.4, 0.1])),
        q
    );
    // IntoMint
    fn takes<Q: mint::IntoMint<MintType = mint::Quaternion<f32>>>(q: Q) -> mint::Quaternion<f32> {
        q.into()
    }
    let z = takes(quarter_turn_z());
    assert_eq!(z.s, core::f32::consts::FRAC_1_SQRT_2);
    assert_eq!(z.v.z, core::f32::consts::FRAC_1_SQRT_2);
    // the rotation survives the round trip: x -> y
    let back = Quaternion::from(z);
    let v = back.rotate([1.0, 0.0, 0.0]);
    assert!(v[0].abs() < 1e-7 && (v[1] - 1.0).abs() < 1e-7 && v[2].abs() < 1e-7);
}

#[cfg(feature = "mint")]
#[test]
fn mint_states_and_vectors() {
    let s = State::new([1.0f64, 2.0, 3.0], [0.5, 0.5, -0.5, 0.5]);
    let (m, q): (mint::Vector3<f64>, mint::Quaternion<f64>) = s.into();
    assert_eq!([m.x, m.y, m.z], s.m);
    assert_eq!((q.s, q.v.x, q.v.y, q.v.z), (0.5, 0.5, -0.5, 0.5));
    assert_eq!(State::from((m, q)), s);
    // vectors: [T; 3] converts through mint's own impls
    let v: mint::Vector3<f64> = s.m.into();
    assert_eq!(<[f64; 3]>::from(v), s.m);
    // the spatial momentum, computed from the mint parts, matches
    let pi = Quaternion::from(q).rotate(m.into());
    assert_eq!(pi, s.spatial_momentum());
}

#[cfg(feature = "micromath")]
#[test]
fn micromath_quaternions_are_w_x_y_z() {
    let q = Quaternion::new(0.1f32, 0.2, 0.3, 0.4);
    let m: micromath::Quaternion = q.into();
    assert_eq!((m.w(), m.x(), m.y(), m.z()), (0.1, 0.2, 0.3, 0.4));
    assert_eq!(m.to_array(), q.to_array());
    assert_eq!(Quaternion::from(m), q);
    // the same rotation on both sides: micromath rotates x to y too
    let z: micromath::Quaternion = quarter_turn_z().into();
    let v = z.rotate(micromath::vector::F32x3 {
        x: 1.0,
        y: 0.0,
        z: 0.0,
    });
    let ours = quarter_turn_z().rotate([1.0, 0.0, 0.0]);
    assert!((v.x - ours[0]).abs() < 1e-6 && (v.y - ours[1]).abs() < 1e-6);
    assert!((v.y - 1.0).abs() < 1e-6);
    // and composes in the same order
    let p = Quaternion::<f32>::from_axis_angle([1.0, 0.0, 0.0], 0.7);
    let mp: micromath::Quaternion = p.into();
    let ours = Quaternion::from(mp * z);
    let direct = p * quarter_turn_z();
    for (a, b) in ours.to_array().iter().zip(direct.to_array()) {
        assert!((a - b).abs() < 1e-6);
    }
}

#[cfg(feature = "micromath")]
#[test]
fn micromath_states_and_vectors() {
    use micromath::vector::F32x3;
    use rigid3::interop::{from_f32x3, to_f32x3};
    let s = State::new([1.0f32, 2.0, 3.0], [0.5, 0.5, -0.5, 0.5]);
    let (m, q): (F32x3, micromath::Quaternion) = s.into();
    assert_eq!((m.x, m.y, m.z), (1.0, 2.0, 3.0));
    assert_eq!(q.to_array(), s.q);
    assert_eq!(State::from((m, q)), s);
    assert_eq!(from_f32x3(to_f32x3(s.m)), s.m);
    assert_eq!(
        to_f32x3([4.0, 5.0, 6.0]),
        F32x3 {
            x: 4.0,
            y: 5.0,
            z: 6.0
        }
    );
}
