//! `Quaternion`: a small public quaternion type for attitudes, with the crate's one order,
//! `[w, x, y, z]`, at every boundary.

use core::ops::Mul;

use crate::linalg::{Mat3, Quat, Vec3};
use crate::real::{c, Real};

/// A quaternion `w + x i + y j + z k` (Hamilton's convention, `i j = k`), as the crate uses it:
/// a unit quaternion is an attitude mapping body to space, `x_space = R(q) x_body`.
///
/// **Order.** Arrays are `[w, x, y, z]` (scalar first) everywhere in this crate
/// ([`crate::State::q`], [`Quaternion::from_array`], [`Quaternion::to_array`]). glam, nalgebra
/// and `mint` store `[x, y, z, w]`: convert through the named fields or the `mint` feature's
/// `From` impls, never by reinterpreting an array.
///
/// The operations are those of [`crate::State`]'s attitude, written out (hand-unrolled, no
/// allocation): [`rotate`](Quaternion::rotate) `R(q) v` (about 30 flops, exact to a few ulps
/// for a unit `q`), composition `p * q` (`R(p q) = R(p) R(q)`), the conjugate,
/// normalisation, and conversion from and to rotation matrices (Shepperd's method: one square
/// root of a number `>= 1`, a few ulps for every rotation). Nothing here checks that a
/// quaternion is a unit one except [`normalize`](Quaternion::normalize).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Quaternion<T> {
    /// Scalar part `w` (`cos(angle / 2)` for a rotation).
    pub w: T,
    /// `i` component.
    pub x: T,
    /// `j` component.
    pub y: T,
    /// `k` component.
    pub z: T,
}

impl<T: Real> Quaternion<T> {
    /// The identity rotation `[1, 0, 0, 0]`.
    pub const IDENTITY: Self = Self {
        w: T::ONE,
        x: T::ZERO,
        y: T::ZERO,
        z: T::ZERO,
    };

    /// `w + x i + y j + z k`.
    #[must_use]
    pub fn new(w: T, x: T, y: T, z: T) -> Self {
        Self { w, x, y, z }
    }

    /// From `[w, x, y, z]` (the order of [`crate::State::q`]).
    #[must_use]
    pub fn from_array(q: [T; 4]) -> Self {
        Self::new(q[0], q[1], q[2], q[3])
    }

    /// To `[w, x, y, z]` (the order of [`crate::State::q`]).
    #[must_use]
    pub fn to_array(self) -> [T; 4] {
        [self.w, self.x, self.y, self.z]
    }

    /// The rotation by `angle` (radians, right-handed) about the unit `axis`:
    /// `[cos(angle/2), sin(angle/2) axis]`. `axis` is not normalised here: a non-unit axis
    /// gives a quaternion of length other than one, which the integrators renormalise at their
    /// next step (so an oracle that rotates by it unnormalised disagrees with them); for an
    /// axis of any length use [`Quaternion::from_rotation_vector`] with `angle * axis / |axis|`.
    #[must_use]
    pub fn from_axis_angle(axis: [T; 3], angle: T) -> Self {
        let half = angle * c::<T>(0.5);
        let (s, w) = (half.sin(), half.cos());
        Self::new(w, axis[0] * s, axis[1] * s, axis[2] * s)
    }

    /// `exp(v / 2)`: the rotation by the rotation vector `v` (angle `|v|` about `v / |v|`), the
    /// attitude error of [`crate::tangent`] (`q = q^ * Quaternion::from_rotation_vector(dtheta)`
    /// is a multiplicative EKF's correction). Exact at `v = 0` (the identity); absolute error
    /// about `eps (1 + |v| / 4)` (a few ulps for angles up to a few turns; rounding `|v|`
    /// itself costs `eps |v|`, so a large angle is only as good as its own digits:
    /// `sin(a)/a` by its series below `a = 2^-13`; `|v|` from
    /// the components scaled by the largest when `|v|^2` overflows, above about `1.8e19` in
    /// f32, so every finite `v` gives a unit quaternion). A NaN or infinite `v` gives a
    /// non-finite quaternion.
    #[must_use]
    pub fn from_rotation_vector(v: [T; 3]) -> Self {
        let n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        let half_angle = if n2.is_finite() {
            n2.sqrt() * c::<T>(0.5)
        } else {
            // |v|^2 overflowed (or v is not finite, which stays so): |v| / 2 = (s / 2) |v / s|,
            // halved first since |v| itself can pass MAX
            let s = v[0].abs().max(v[1].abs()).max(v[2].abs());
            let (a, b, d) = (v[0] / s, v[1] / s, v[2] / s);
            (s * c::<T>(0.5)) * (a * a + b * b + d * d).sqrt()
        };
        // sin(a) / (2 a) as the factor on v, a = |v| / 2
        let k = if half_angle < c::<T>(1.0 / 8192.0) {
            (T::ONE - half_angle * half_angle * c::<T>(1.0 / 6.0)) * c::<T>(0.5)
        } else {
            // halved before the division: 2 a overflows for a above MAX / 2
            (half_angle.sin() * c::<T>(0.5)) / half_angle
        };
        Self::new(half_angle.cos(), v[0] * k, v[1] * k, v[2] * k)
    }

    /// `2 log(q)`: the rotation vector of the unit quaternion `q` (angle in `[0, pi]` about
    /// the rotation's axis), the inverse of [`Quaternion::from_rotation_vector`] for both `q`
    /// and `-q` (the same rotation: the shorter turn is returned). The angle is
    /// `2 atan2(|u|, |w|)`, `u = (x, y, z)`, accurate to a few ulps at every angle (where
    /// `2 acos(w)` loses half the digits of a small angle), and the axis `u / |u|`; a
    /// quaternion that is not unit is taken as its direction (`|u|` is formed from the
    /// components scaled by the largest where its square would leave the normal range, and
    /// `q` divided by its largest component where `|u|` overflows or `angle / |u|` would, so
    /// angles down to the smallest normal number and quaternions up to `T::MAX` keep their
    /// digits, and every finite `q` gives a finite vector). The zero vector for `q = +-1`; a
    /// non-finite `q` gives a non-finite vector.
    #[must_use]
    pub fn to_rotation_vector(self) -> [T; 3] {
        let q = if self.w < T::ZERO {
            Self::new(-self.w, -self.x, -self.y, -self.z)
        } else {
            self
        };
        let (n, k) = angle_factor(q);
        if k.is_finite() && n.is_finite() && q.w.is_finite() {
            return [q.x * k, q.y * k, q.z * k];
        }
        if !(q.w.is_finite() && q.x.is_finite() && q.y.is_finite() && q.z.is_finite()) {
            // a non-finite q carries its non-finite part through (never a finite vector)
            let k = q.w.abs() + n;
            return [q.x * k, q.y * k, q.z * k];
        }
        // a finite q whose |u| overflows (f32 (0, 3.4e38, 3.4e38, 0)) or lies so far below
        // its angle that angle / |u| does (f64 (1e-320, 1e-321, 0, 0)): found in review as
        // inf and NaN. Its direction, by the largest component (then that one is 1, so
        // `|u| >= 1` or `w = 1`, and the factor lies between about 0.9 and pi)
        let s = q.w.max(q.x.abs()).max(q.y.abs()).max(q.z.abs());
        let d = Self::new(q.w / s, q.x / s, q.y / s, q.z / s);
        let (_, k) = angle_factor(d);
        [d.x * k, d.y * k, d.z * k]
    }

    /// The angle of the rotation from attitude `self` to attitude `other` (radians, in
    /// `[0, pi]`): `|(self^* (x) other).to_rotation_vector()|`, the attitude error a test or a
    /// filter reports, with `2 atan2(|u|, |w|)` of the product (where `2 acos` of a dot
    /// product keeps half the digits of a small angle). Accuracy: forming the product rounds
    /// it by about an ulp of one, so the angle is good to a few `eps` absolute (the
    /// attitudes' own resolution: `1e-7` rad in f32); where the product is exact (one of the
    /// two is the identity) to a few ulps of the angle, small ones included. `q` and `-q` are
    /// the same attitude (angle zero). A zero quaternion is no attitude, but its angle to
    /// anything comes out zero (as [`Quaternion::to_rotation_vector`] of it is the zero
    /// vector): check attitudes that can be zeroed (`normalize` returns `None` for them).
    #[must_use]
    pub fn angle_to(self, other: Self) -> T {
        let d = self.conjugate().compose(other);
        c::<T>(2.0) * norm3(d.x, d.y, d.z).atan2(d.w.abs())
    }

    /// The conjugate `[w, -x, -y, -z]`: the inverse rotation of a unit quaternion (space to
    /// body). Exact.
    #[must_use]
    pub fn conjugate(self) -> Self {
        Self::of(self.inner().conjugate())
    }

    /// `|q|^2 = w^2 + x^2 + y^2 + z^2`.
    #[must_use]
    pub fn norm_squared(self) -> T {
        self.inner().norm2()
    }

    /// `q / |q|`, or `None` for a zero or non-finite quaternion (one square root, one
    /// division; the result has unit length to about an ulp).
    #[must_use]
    pub fn normalize(self) -> Option<Self> {
        let (q, ok) = self.inner().normalize();
        if ok && q.is_finite() {
            Some(Self::of(q))
        } else {
            None
        }
    }

    /// The Hamilton product `self (x) o`: for unit quaternions the rotation `R(self) R(o)`
    /// (first `o`, then `self`). Also `self * o`.
    #[must_use]
    pub fn compose(self, o: Self) -> Self {
        Self::of(self.inner().mul(o.inner()))
    }

    /// `R(q) v` for a unit `q` (body to space for an attitude), without forming the matrix:
    /// `v + 2 w (u x v) + 2 u x (u x v)`, `u = (x, y, z)`.
    #[must_use]
    pub fn rotate(self, v: [T; 3]) -> [T; 3] {
        self.inner().rotate(Vec3::from_array(v)).to_array()
    }

    /// `R(q)^T v` for a unit `q` (space to body for an attitude): the rotation by the
    /// conjugate.
    #[must_use]
    pub fn inverse_rotate(self, v: [T; 3]) -> [T; 3] {
        self.inner().inverse_rotate(Vec3::from_array(v)).to_array()
    }

    /// The rotation matrix `R(q)`, row-major (`m[i][j]` is row `i`, column `j`), for a unit
    /// `q`; its columns are the body axes in space.
    #[must_use]
    pub fn to_rotation_matrix(self) -> [[T; 3]; 3] {
        let r = self.inner().to_mat3();
        [
            r.row0().to_array(),
            r.row1().to_array(),
            r.row2().to_array(),
        ]
    }

    /// The unit quaternion of a rotation matrix (row-major, `x_space = R x_body`), with
    /// `w >= 0`, by Shepperd's method (Shepperd, J. Guidance Control 1 (1978) 223): branch on
    /// the largest of the trace and the diagonal so that the one square root is of a number
    /// `>= 1`; a few ulps for every rotation. A matrix that is orthogonal only approximately
    /// gives a nearby rotation (normalised), not the polar factor.
    ///
    /// Returns `None` for a non-finite matrix, a reflection (`det R <= 0`) or a matrix far
    /// from any rotation (`max |R^T R - I| > 1/64`).
    #[must_use]
    pub fn from_rotation_matrix(m: [[T; 3]; 3]) -> Option<Self> {
        if !m.iter().all(|r| r.iter().all(|x| x.is_finite())) {
            return None;
        }
        let r = Mat3::from_cols(
            Vec3::new(m[0][0], m[1][0], m[2][0]),
            Vec3::new(m[0][1], m[1][1], m[2][1]),
            Vec3::new(m[0][2], m[1][2], m[2][2]),
        );
        let det = r.z_axis.dot(r.x_axis.cross(r.y_axis));
        if !(det > T::ZERO) || !(r.orthogonality_defect() <= c::<T>(1.0 / 64.0)) {
            return None;
        }
        let q = Quat::from_mat3(&r);
        let n2 = q.norm2();
        // a rotation gives |q| = 1 to round-off: renormalise only what is off
        if (n2 - T::ONE).abs() <= c::<T>(16.0) * T::EPSILON {
            return Some(Self::of(q));
        }
        Self::of(q).normalize()
    }

    fn inner(self) -> Quat<T> {
        Quat {
            w: self.w,
            x: self.x,
            y: self.y,
            z: self.z,
        }
    }

    fn of(q: Quat<T>) -> Self {
        Self::new(q.w, q.x, q.y, q.z)
    }
}

impl<T: Real> Mul for Quaternion<T> {
    type Output = Self;
    /// The Hamilton product, as [`Quaternion::compose`].
    fn mul(self, o: Self) -> Self {
        self.compose(o)
    }
}

impl<T> From<[T; 4]> for Quaternion<T> {
    /// From `[w, x, y, z]`.
    fn from(q: [T; 4]) -> Self {
        let [w, x, y, z] = q;
        Self { w, x, y, z }
    }
}

impl<T> From<Quaternion<T>> for [T; 4] {
    /// To `[w, x, y, z]`.
    fn from(q: Quaternion<T>) -> Self {
        [q.w, q.x, q.y, q.z]
    }
}

/// `(|u|, 2 atan2(|u|, w) / |u|)` of `q = (w, u)` with `w >= 0`: the rotation vector is `k u`
/// (`k = 0` for `u = 0`: the zero turn, whatever `w`).
fn angle_factor<T: Real>(q: Quaternion<T>) -> (T, T) {
    let n = norm3(q.x, q.y, q.z);
    let angle = c::<T>(2.0) * n.atan2(q.w);
    let k = if n > T::ZERO { angle / n } else { T::ZERO };
    (n, k)
}

/// `sqrt(x^2 + y^2 + z^2)` without leaving the normal range: where the sum of squares would
/// overflow or fall below `MIN_POSITIVE / eps` (where its digits start to go), the
/// components are scaled by the largest first.
fn norm3<T: Real>(x: T, y: T, z: T) -> T {
    let n2 = x * x + y * y + z * z;
    if n2.is_finite() && n2 >= T::MIN_POSITIVE / T::EPSILON {
        return n2.sqrt();
    }
    let s = x.abs().max(y.abs()).max(z.abs());
    if !(s > T::ZERO && s.is_finite()) {
        // zero, or a non-finite component (which the caller carries through)
        return n2.sqrt();
    }
    let (a, b, d) = (x / s, y / s, z / s);
    s * (a * a + b * b + d * d).sqrt()
}
