//! Hand-unrolled 3-vectors, 3x3 matrices and quaternions: only what the integrators use.
//!
//! Matrices are stored by columns (`x_axis`, `y_axis`, `z_axis`), as in glam. Every
//! operation is written out in full with named temporaries; there are no loops over a
//! fixed 3 so that the compiler keeps everything in registers on a Cortex-M4F.

use crate::real::{c, Real};

/// A 3-vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Vec3<T> {
    pub x: T,
    pub y: T,
    pub z: T,
}

impl<T: Real> Vec3<T> {
    #[inline]
    pub fn new(x: T, y: T, z: T) -> Self {
        Self { x, y, z }
    }
    #[inline]
    pub fn from_array(a: [T; 3]) -> Self {
        Self::new(a[0], a[1], a[2])
    }
    #[inline]
    pub fn to_array(self) -> [T; 3] {
        [self.x, self.y, self.z]
    }
    #[inline]
    pub fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
    #[inline]
    pub fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
    #[inline]
    pub fn scale(self, s: T) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
    /// Each component divided by `s` (three divisions, no reciprocal: the reciprocal of a
    /// subnormal `s` overflows; for scaling a vector to its largest entry off the hot path).
    #[inline]
    pub fn divided_by(self, s: T) -> Self {
        Self::new(self.x / s, self.y / s, self.z / s)
    }
    /// Component-wise product (a diagonal matrix times a vector).
    #[inline]
    pub fn mul_elem(self, o: Self) -> Self {
        Self::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }
    #[inline]
    pub fn dot(self, o: Self) -> T {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline]
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    #[inline]
    pub fn norm2(self) -> T {
        self.dot(self)
    }
    /// Largest component.
    #[inline]
    pub fn max_element(self) -> T {
        self.x.max(self.y).max(self.z)
    }
    /// Largest absolute component (the max norm).
    #[inline]
    pub fn max_abs(self) -> T {
        self.x.abs().max(self.y.abs()).max(self.z.abs())
    }
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.all_finite3(self.y, self.z)
    }
}

/// A 3x3 matrix stored by columns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Mat3<T> {
    pub x_axis: Vec3<T>,
    pub y_axis: Vec3<T>,
    pub z_axis: Vec3<T>,
}

impl<T: Real> Mat3<T> {
    #[inline]
    pub fn from_cols(x_axis: Vec3<T>, y_axis: Vec3<T>, z_axis: Vec3<T>) -> Self {
        Self {
            x_axis,
            y_axis,
            z_axis,
        }
    }
    #[inline]
    pub fn identity() -> Self {
        let (o, z) = (T::ONE, T::ZERO);
        Self::from_cols(Vec3::new(o, z, z), Vec3::new(z, o, z), Vec3::new(z, z, o))
    }
    #[inline]
    pub fn diagonal(d: Vec3<T>) -> Self {
        let z = T::ZERO;
        Self::from_cols(
            Vec3::new(d.x, z, z),
            Vec3::new(z, d.y, z),
            Vec3::new(z, z, d.z),
        )
    }
    /// `hat(a)`, the skew matrix with `hat(a) b = a x b`.
    #[inline]
    pub fn hat(a: Vec3<T>) -> Self {
        let z = T::ZERO;
        Self::from_cols(
            Vec3::new(z, a.z, -a.y),
            Vec3::new(-a.z, z, a.x),
            Vec3::new(a.y, -a.x, z),
        )
    }
    /// Row `i` as a vector (i in 0..3).
    #[inline]
    pub fn row0(&self) -> Vec3<T> {
        Vec3::new(self.x_axis.x, self.y_axis.x, self.z_axis.x)
    }
    #[inline]
    pub fn row1(&self) -> Vec3<T> {
        Vec3::new(self.x_axis.y, self.y_axis.y, self.z_axis.y)
    }
    #[inline]
    pub fn row2(&self) -> Vec3<T> {
        Vec3::new(self.x_axis.z, self.y_axis.z, self.z_axis.z)
    }
    #[inline]
    pub fn transpose(&self) -> Self {
        Self::from_cols(self.row0(), self.row1(), self.row2())
    }
    #[inline]
    pub fn add(&self, o: &Self) -> Self {
        Self::from_cols(
            self.x_axis.add(o.x_axis),
            self.y_axis.add(o.y_axis),
            self.z_axis.add(o.z_axis),
        )
    }
    #[inline]
    pub fn sub(&self, o: &Self) -> Self {
        Self::from_cols(
            self.x_axis.sub(o.x_axis),
            self.y_axis.sub(o.y_axis),
            self.z_axis.sub(o.z_axis),
        )
    }
    #[inline]
    pub fn scale(&self, s: T) -> Self {
        Self::from_cols(
            self.x_axis.scale(s),
            self.y_axis.scale(s),
            self.z_axis.scale(s),
        )
    }
    /// `self * diag(d)`: scales the columns.
    #[inline]
    pub fn mul_diag(&self, d: Vec3<T>) -> Self {
        Self::from_cols(
            self.x_axis.scale(d.x),
            self.y_axis.scale(d.y),
            self.z_axis.scale(d.z),
        )
    }
    #[inline]
    pub fn mul_vec(&self, v: Vec3<T>) -> Vec3<T> {
        self.x_axis
            .scale(v.x)
            .add(self.y_axis.scale(v.y))
            .add(self.z_axis.scale(v.z))
    }
    /// `self^T v` without forming the transpose.
    #[inline]
    pub fn transpose_mul_vec(&self, v: Vec3<T>) -> Vec3<T> {
        Vec3::new(self.x_axis.dot(v), self.y_axis.dot(v), self.z_axis.dot(v))
    }
    #[inline]
    pub fn mul_mat(&self, o: &Self) -> Self {
        Self::from_cols(
            self.mul_vec(o.x_axis),
            self.mul_vec(o.y_axis),
            self.mul_vec(o.z_axis),
        )
    }
    /// Inverse by the adjugate, with `ok = false` when the determinant is zero or not finite
    /// relative to the size of the entries. Accurate to `cond(A) * eps`.
    #[inline]
    pub fn inverse_or_zero(&self) -> (Self, bool) {
        let c0 = self.y_axis.cross(self.z_axis);
        let c1 = self.z_axis.cross(self.x_axis);
        let c2 = self.x_axis.cross(self.y_axis);
        let det = self.z_axis.dot(c2);
        let ok = det != T::ZERO && det.is_finite();
        if !ok {
            return (Self::identity().scale(T::ZERO), false);
        }
        let inv_det = T::ONE / det;
        // rows of the inverse are the cross products
        let inv = Self::from_cols(c0, c1, c2).transpose().scale(inv_det);
        (inv, inv.is_finite())
    }
    /// Largest absolute entry.
    #[cfg(test)]
    #[inline]
    pub fn max_abs(&self) -> T {
        self.x_axis
            .max_abs()
            .max(self.y_axis.max_abs())
            .max(self.z_axis.max_abs())
    }
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.x_axis.is_finite() && self.y_axis.is_finite() && self.z_axis.is_finite()
    }
    /// `max |X^T X - I|`, the departure from orthogonality.
    #[inline]
    pub fn orthogonality_defect(&self) -> T {
        let a = self.x_axis;
        let b = self.y_axis;
        let c = self.z_axis;
        let one = T::ONE;
        (a.dot(a) - one)
            .abs()
            .max((b.dot(b) - one).abs())
            .max((c.dot(c) - one).abs())
            .max(a.dot(b).abs())
            .max(a.dot(c).abs())
            .max(b.dot(c).abs())
    }
}

/// A quaternion `w + x i + y j + z k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Quat<T> {
    pub w: T,
    pub x: T,
    pub y: T,
    pub z: T,
}

impl<T: Real> Quat<T> {
    #[inline]
    pub fn from_array(a: [T; 4]) -> Self {
        Self {
            w: a[0],
            x: a[1],
            y: a[2],
            z: a[3],
        }
    }
    #[inline]
    pub fn to_array(self) -> [T; 4] {
        [self.w, self.x, self.y, self.z]
    }
    #[inline]
    pub fn vector(self) -> Vec3<T> {
        Vec3::new(self.x, self.y, self.z)
    }
    #[inline]
    pub fn is_finite(self) -> bool {
        self.w.is_finite() && self.x.all_finite3(self.y, self.z)
    }
    #[inline]
    pub fn norm2(self) -> T {
        self.w * self.w + self.x * self.x + self.y * self.y + self.z * self.z
    }
    /// Hamilton product `self (x) o`.
    #[inline]
    pub fn mul(self, o: Self) -> Self {
        Self {
            w: self.w * o.w - self.x * o.x - self.y * o.y - self.z * o.z,
            x: self.w * o.x + self.x * o.w + self.y * o.z - self.z * o.y,
            y: self.w * o.y - self.x * o.z + self.y * o.w + self.z * o.x,
            z: self.w * o.z + self.x * o.y - self.y * o.x + self.z * o.w,
        }
    }
    /// `self / |self|`, with `ok = false` for a zero or non-finite quaternion. Unit length to
    /// about an ulp for every finite nonzero `self`: where `|self|^2` is below
    /// `MIN_POSITIVE / EPSILON` (its rounding no longer relative: `[3e-160, 4e-160, 0, 0]` came
    /// out `5.6e-6` off unit length, found in a first-use trial) or overflows, the components
    /// are divided by the largest first.
    #[inline]
    pub fn normalize(self) -> (Self, bool) {
        let n2 = self.norm2();
        if !(n2 >= c::<T>(T::MIN_POSITIVE.to_f64() / T::EPSILON.to_f64()) && n2.is_finite()) {
            return self.normalize_scaled();
        }
        (self.scale(T::ONE / n2.sqrt()), true)
    }

    /// [`Quat::normalize`] outside the range where `|self|^2` is formed to relative accuracy.
    #[cold]
    #[inline(never)]
    fn normalize_scaled(self) -> (Self, bool) {
        let finite = self.w.is_finite() && self.x.is_finite() && self.y.is_finite();
        let big = self
            .w
            .abs()
            .max(self.x.abs())
            .max(self.y.abs())
            .max(self.z.abs());
        if !(finite && self.z.is_finite() && big > T::ZERO) {
            return (self, false);
        }
        // divided, not multiplied by 1 / big, which overflows for a subnormal big
        let q = Self {
            w: self.w / big,
            x: self.x / big,
            y: self.y / big,
            z: self.z / big,
        };
        (q.scale(T::ONE / q.norm2().sqrt()), true)
    }

    /// `self` times the scalar `k`.
    #[inline]
    fn scale(self, k: T) -> Self {
        Self {
            w: self.w * k,
            x: self.x * k,
            y: self.y * k,
            z: self.z * k,
        }
    }
    /// The rotation matrix of a unit quaternion (`x_space = R x_body`).
    #[inline]
    pub fn to_mat3(self) -> Mat3<T> {
        let two = T::ONE + T::ONE;
        let (w, x, y, z) = (self.w, self.x, self.y, self.z);
        let (xx, yy, zz) = (x * x, y * y, z * z);
        let (xy, xz, yz) = (x * y, x * z, y * z);
        let (wx, wy, wz) = (w * x, w * y, w * z);
        let one = T::ONE;
        Mat3::from_cols(
            Vec3::new(one - two * (yy + zz), two * (xy + wz), two * (xz - wy)),
            Vec3::new(two * (xy - wz), one - two * (xx + zz), two * (yz + wx)),
            Vec3::new(two * (xz + wy), two * (yz - wx), one - two * (xx + yy)),
        )
    }
    /// The conjugate `(w, -x, -y, -z)` (the inverse of a unit quaternion).
    #[inline]
    pub fn conjugate(self) -> Self {
        Self {
            w: self.w,
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
    /// `R(self)^T v` for a unit quaternion: the rotation by the conjugate.
    #[inline]
    pub fn inverse_rotate(self, v: Vec3<T>) -> Vec3<T> {
        self.conjugate().rotate(v)
    }
    /// `R(self) v` for a unit quaternion, without forming the matrix.
    #[inline]
    pub fn rotate(self, v: Vec3<T>) -> Vec3<T> {
        // v + 2 w (u x v) + 2 u x (u x v), u the vector part
        let u = self.vector();
        let t = u.cross(v).scale(T::ONE + T::ONE);
        v.add(t.scale(self.w)).add(u.cross(t))
    }
    /// The unit quaternion of a rotation matrix by Shepperd's method: branch on the largest
    /// of `trace`, `R_xx`, `R_yy`, `R_zz` so the one square root is of a number >= 1, which
    /// keeps the relative error at a few ulps for every rotation. The result has `w >= 0`.
    #[inline]
    pub fn from_mat3(r: &Mat3<T>) -> Self {
        let (m00, m11, m22) = (r.x_axis.x, r.y_axis.y, r.z_axis.z);
        let (m10, m20, m01) = (r.x_axis.y, r.x_axis.z, r.y_axis.x);
        let (m21, m02, m12) = (r.y_axis.z, r.z_axis.x, r.z_axis.y);
        let one = T::ONE;
        let half = T::from_f64(0.5);
        let trace = m00 + m11 + m22;
        let q = if trace >= m00 && trace >= m11 && trace >= m22 {
            let s = (one + trace).sqrt();
            let f = half / s;
            Self {
                w: half * s,
                x: (m21 - m12) * f,
                y: (m02 - m20) * f,
                z: (m10 - m01) * f,
            }
        } else if m00 >= m11 && m00 >= m22 {
            let s = (one + m00 - m11 - m22).sqrt();
            let f = half / s;
            Self {
                w: (m21 - m12) * f,
                x: half * s,
                y: (m01 + m10) * f,
                z: (m02 + m20) * f,
            }
        } else if m11 >= m22 {
            let s = (one + m11 - m00 - m22).sqrt();
            let f = half / s;
            Self {
                w: (m02 - m20) * f,
                x: (m01 + m10) * f,
                y: half * s,
                z: (m12 + m21) * f,
            }
        } else {
            let s = (one + m22 - m00 - m11).sqrt();
            let f = half / s;
            Self {
                w: (m10 - m01) * f,
                x: (m02 + m20) * f,
                y: (m12 + m21) * f,
                z: half * s,
            }
        };
        if q.w < T::ZERO {
            Self {
                w: -q.w,
                x: -q.x,
                y: -q.y,
                z: -q.z,
            }
        } else {
            q
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quaternion_matrix_round_trip() {
        let (q, ok) = Quat::from_array([0.3f64, -0.5, 0.7, 0.2]).normalize();
        assert!(ok);
        let back = Quat::from_mat3(&q.to_mat3());
        for (a, b) in q.to_array().iter().zip(back.to_array().iter()) {
            assert!((a - b).abs() < 1e-15);
        }
        let v = Vec3::new(0.1, 2.0, -0.4);
        let d = q.rotate(v).sub(q.to_mat3().mul_vec(v));
        assert!(d.max_abs() < 1e-15);
        // composition: R(p q) = R(p) R(q)
        let (p, _) = Quat::from_array([-0.1f64, 0.9, 0.2, -0.3]).normalize();
        let lhs = p.mul(q).to_mat3();
        let rhs = p.to_mat3().mul_mat(&q.to_mat3());
        assert!(lhs.sub(&rhs).max_abs() < 1e-15);
    }

    #[test]
    fn inverse_recomposes() {
        let a = Mat3::from_cols(
            Vec3::new(2.0f64, 0.3, -1.0),
            Vec3::new(0.5, 1.5, 0.2),
            Vec3::new(-0.7, 0.1, 3.0),
        );
        let (inv, ok) = a.inverse_or_zero();
        assert!(ok);
        assert!(a.mul_mat(&inv).sub(&Mat3::identity()).max_abs() < 1e-15);
        let singular = Mat3::from_cols(a.x_axis, a.x_axis.scale(2.0), a.z_axis);
        assert!(!singular.inverse_or_zero().1);
    }

    #[test]
    fn hat_is_cross_product() {
        let a = Vec3::new(0.3f64, -1.2, 2.5);
        let b = Vec3::new(-0.7, 0.4, 1.1);
        assert!(Mat3::hat(a).mul_vec(b).sub(a.cross(b)).max_abs() < 1e-15);
    }
}
