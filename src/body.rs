//! The rigid body: principal moments of inertia, the Moser–Veselov mass matrix, invariants.

use crate::error::BodyError;
use crate::linalg::{Mat3, Quat, Vec3};
use crate::real::{c, sq, Real};

/// A free rigid body in its principal frame.
///
/// Holds the principal moments of inertia `I = (I1, I2, I3)` and the Moser–Veselov mass
/// matrix `J = diag(J1, J2, J3)` with `I_i = J_j + J_k`, i.e. `J_i = (I_j + I_k - I_i) / 2`
/// (docs/MATH.md §1; Moser & Veselov, Comm. Math. Phys. 139 (1991) 217). A physical body has
/// `J_i >= 0` (the triangle inequality `I_i <= I_j + I_k`); `J_i = 0` is a planar body.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Body<T> {
    inertia: [T; 3],
    mass_matrix: [T; 3],
}

/// `SubnormalMoment` for a positive moment below `T::MIN_POSITIVE` (the moments are known
/// positive): the mass matrix and the step's products of moments underflow there.
#[inline]
fn refuse_subnormal<T: Real>([i1, i2, i3]: [T; 3]) -> Result<(), BodyError> {
    if i1 < T::MIN_POSITIVE || i2 < T::MIN_POSITIVE || i3 < T::MIN_POSITIVE {
        Err(BodyError::SubnormalMoment)
    } else {
        Ok(())
    }
}

impl<T: Real> Body<T> {
    /// A body from its principal moments of inertia.
    ///
    /// A `J_i` within `4 eps` of the largest moment of zero is set to exactly zero (a planar
    /// body), so that `I = (0.1, 0.2, 0.3)` is the flat plate it means despite binary
    /// rounding. A needle whose smallest moment is below about `8 eps` of the largest (in f32
    /// from about `1e-6`: `I = (1e-6, 1, 1)`) has both small entries within that and set to
    /// zero, a zero moment to DMV, which has no step for it: [`crate::Mv`] and the methods
    /// built on it refuse every step (`StepTooLarge`, whatever `h`: sub-stepping does not
    /// help; `Mv::max_step` is zero), while `Rk4`, `Midpoint` and the splittings, which use
    /// the moments, step it. Use f64 for such needles.
    ///
    /// # Errors
    ///
    /// [`BodyError::NonFinite`] for a NaN or infinite moment,
    /// [`BodyError::NonPositiveMoment`] for a moment `<= 0`,
    /// [`BodyError::SubnormalMoment`] for a positive moment below `T::MIN_POSITIVE`, and
    /// [`BodyError::TriangleInequality`] when a moment exceeds the sum of the other two by
    /// more than `4 eps` of the largest.
    pub fn from_inertia(inertia: [T; 3]) -> Result<Self, BodyError> {
        let [i1, i2, i3] = inertia;
        if !(i1.is_finite() && i2.is_finite() && i3.is_finite()) {
            return Err(BodyError::NonFinite);
        }
        if !(i1 > T::ZERO && i2 > T::ZERO && i3 > T::ZERO) {
            return Err(BodyError::NonPositiveMoment);
        }
        refuse_subnormal(inertia)?;
        Self::from_positive_inertia(inertia)
    }

    /// [`Body::from_inertia`] for moments already known finite and positive (a `PreMv`'s
    /// modified moments, on the loop's path after every outside change): the triangle
    /// inequality is still checked, with the same tolerance and snapping.
    #[inline]
    pub(crate) fn from_positive_inertia(inertia: [T; 3]) -> Result<Self, BodyError> {
        let [i1, i2, i3] = inertia;
        let half = c::<T>(0.5);
        // (i2 + i3) can overflow only above MAX / 2; halve first.
        let j1 = i2 * half + i3 * half - i1 * half;
        let j2 = i1 * half + i3 * half - i2 * half;
        let j3 = i1 * half + i2 * half - i3 * half;
        let tol = c::<T>(4.0) * T::EPSILON * i1.max(i2).max(i3);
        if j1 < -tol || j2 < -tol || j3 < -tol {
            return Err(BodyError::TriangleInequality);
        }
        // within the tolerance the body is planar: snap to exactly zero, so that methods
        // that treat J_i = 0 specially see it
        let snap = |j: T| if j <= tol { T::ZERO } else { j };
        Ok(Self {
            inertia,
            mass_matrix: [snap(j1), snap(j2), snap(j3)],
        })
    }

    /// A body from the Moser–Veselov mass matrix `J = diag(J1, J2, J3)`, `J_i >= 0`, at most
    /// one of them zero (two zeros would give a zero moment of inertia).
    ///
    /// # Errors
    ///
    /// [`BodyError::NonFinite`] for a NaN or infinite entry (or moments `J_j + J_k` that
    /// overflow), [`BodyError::NegativeMassMatrix`] for a `J_i < 0`,
    /// [`BodyError::NonPositiveMoment`] when two entries are zero, and
    /// [`BodyError::SubnormalMoment`] for a moment `J_j + J_k` below `T::MIN_POSITIVE`.
    pub fn from_mass_matrix(mass_matrix: [T; 3]) -> Result<Self, BodyError> {
        let [j1, j2, j3] = mass_matrix;
        if !(j1.is_finite() && j2.is_finite() && j3.is_finite()) {
            return Err(BodyError::NonFinite);
        }
        if j1 < T::ZERO || j2 < T::ZERO || j3 < T::ZERO {
            return Err(BodyError::NegativeMassMatrix);
        }
        let inertia = [j2 + j3, j1 + j3, j1 + j2];
        if !(inertia[0] > T::ZERO && inertia[1] > T::ZERO && inertia[2] > T::ZERO) {
            return Err(BodyError::NonPositiveMoment);
        }
        if !(inertia[0].is_finite() && inertia[1].is_finite() && inertia[2].is_finite()) {
            return Err(BodyError::NonFinite);
        }
        refuse_subnormal(inertia)?;
        Ok(Self {
            inertia,
            mass_matrix,
        })
    }

    /// A body from a full symmetric inertia tensor given in some body frame (row-major).
    ///
    /// Returns the body in its principal frame and the unit quaternion `(w, x, y, z)` of that
    /// frame: `x_body = R(q) x_principal`, so momentum in the given frame is `R(q) m`.
    /// Principal moments come out ascending (`I1 <= I2 <= I3`); the first two axes have
    /// their largest component positive and the third is their cross product (right-handed);
    /// `w >= 0`. Axes of a repeated moment are any orthonormal basis of its eigenspace.
    ///
    /// Method: cyclic Jacobi rotations (at most 12 sweeps; it converges quadratically and
    /// needs about 4 for a 3x3), so eigenvalues are accurate to a few ulps of the largest
    /// and the recomposed tensor matches the input to about `8 eps |A|` (a review against
    /// 50-digit eigen-decompositions: eigenvalues within 1.1 ulp of the largest, recomposition
    /// 5.8 / 8.7 eps in f64 / f32, axes within `eps |A| / gap` of a moment from its
    /// neighbours). So the axes of close moments are less certain in f32: moments 1 % apart
    /// give axes to about `1e-5` rad, which a long f32 propagation carries (a first-use trial:
    /// attitudes 3.7x further from f64's after `10^6` ticks than with the frame decomposed in
    /// f64). Where the tensor is known in f64, decompose it there and hand the f32 code the
    /// rounded moments ([`Body::from_inertia`]) and [`crate::Frame::from_quaternion`].
    ///
    /// The tests for a body (positive moments, the triangle inequality) are made on the
    /// computed moments, so they are as good as those: a tensor a few `eps |A|` from singular
    /// (a rod's, rotated and rounded) may be taken with a tiny moment or refused.
    ///
    /// # Errors
    ///
    /// [`BodyError::NonFinite`] for a NaN or infinite entry, [`BodyError::NotSymmetric`] when
    /// the tensor is not symmetric to `64 eps |A|`, and those of [`Body::from_inertia`] for
    /// its principal moments (not positive definite, or not a physical body).
    pub fn from_inertia_tensor(tensor: [[T; 3]; 3]) -> Result<(Self, [T; 4]), BodyError> {
        let (values, axes) = principal_axes(tensor)?;
        let body = Self::from_inertia(values)?;
        let (frame, ok) = Quat::from_mat3(&axes).normalize();
        if !ok {
            return Err(BodyError::NonFinite);
        }
        Ok((body, frame.to_array()))
    }

    /// Principal moments of inertia `(I1, I2, I3)`.
    #[must_use]
    pub fn inertia(&self) -> [T; 3] {
        self.inertia
    }

    /// Moser–Veselov mass matrix `(J1, J2, J3)`, `J_i = (I_j + I_k - I_i) / 2`.
    #[must_use]
    pub fn mass_matrix(&self) -> [T; 3] {
        self.mass_matrix
    }

    /// Kinetic energy `E = 1/2 sum m_i^2 / I_i`, conserved by the flow.
    #[must_use]
    pub fn energy(&self, m: &[T; 3]) -> T {
        let [i1, i2, i3] = self.inertia;
        c::<T>(0.5) * (sq(m[0]) / i1 + sq(m[1]) / i2 + sq(m[2]) / i3)
    }

    /// The Casimir `|m|^2`, conserved by the flow.
    #[must_use]
    pub fn casimir(&self, m: &[T; 3]) -> T {
        sq(m[0]) + sq(m[1]) + sq(m[2])
    }

    /// Body angular velocity `Omega = I^-1 m`.
    #[must_use]
    pub fn angular_velocity(&self, m: &[T; 3]) -> [T; 3] {
        let [i1, i2, i3] = self.inertia;
        [m[0] / i1, m[1] / i2, m[2] / i3]
    }

    /// `(1/I1, 1/I2, 1/I3)`, what the explicit baselines multiply by.
    pub(crate) fn inverse_inertia(&self) -> Vec3<T> {
        let [i1, i2, i3] = self.inertia;
        Vec3::new(T::ONE / i1, T::ONE / i2, T::ONE / i3)
    }

    pub(crate) fn mass_matrix_vec(&self) -> Vec3<T> {
        Vec3::from_array(self.mass_matrix)
    }
}

/// Symmetric eigendecomposition `A = V diag(values) V^T` with ascending values and a
/// right-handed `V` under the sign convention of [`Body::from_inertia_tensor`].
fn principal_axes<T: Real>(a: [[T; 3]; 3]) -> Result<([T; 3], Mat3<T>), BodyError> {
    let mut scale = T::ZERO;
    for row in &a {
        for x in row {
            if !x.is_finite() {
                return Err(BodyError::NonFinite);
            }
            scale = scale.max(x.abs());
        }
    }
    let tol = c::<T>(64.0) * T::EPSILON * scale;
    if (a[0][1] - a[1][0]).abs() > tol
        || (a[0][2] - a[2][0]).abs() > tol
        || (a[1][2] - a[2][1]).abs() > tol
    {
        return Err(BodyError::NotSymmetric);
    }
    // in units where the largest entry is in [1, 2): the sweeps' stopping test sums squares,
    // which overflowed (a tensor of 1e154 came back as its diagonal, found in a first-use
    // trial) or underflowed (axes 0.22 rad off at 1e-165); powers of two round nothing
    let (up, down) = unit_scale(scale);
    let a = a.map(|row| row.map(|x| x * up));
    let half = c::<T>(0.5);
    let mut s = [
        [
            a[0][0],
            (a[0][1] + a[1][0]) * half,
            (a[0][2] + a[2][0]) * half,
        ],
        [T::ZERO, a[1][1], (a[1][2] + a[2][1]) * half],
        [T::ZERO, T::ZERO, a[2][2]],
    ];
    s[1][0] = s[0][1];
    s[2][0] = s[0][2];
    s[2][1] = s[1][2];
    let mut v = [
        [T::ONE, T::ZERO, T::ZERO],
        [T::ZERO, T::ONE, T::ZERO],
        [T::ZERO, T::ZERO, T::ONE],
    ];
    let mut sweep = 0;
    while sweep < 12 {
        let off = sq(s[0][1]) + sq(s[0][2]) + sq(s[1][2]);
        let diag = sq(s[0][0]) + sq(s[1][1]) + sq(s[2][2]);
        if off <= sq(T::EPSILON) * sq(T::EPSILON) * diag || off == T::ZERO {
            break;
        }
        jacobi_rotate(&mut s, &mut v, 0, 1);
        jacobi_rotate(&mut s, &mut v, 0, 2);
        jacobi_rotate(&mut s, &mut v, 1, 2);
        sweep += 1;
    }
    // columns of v are the eigenvectors
    let mut cols = [
        (s[0][0], Vec3::new(v[0][0], v[1][0], v[2][0])),
        (s[1][1], Vec3::new(v[0][1], v[1][1], v[2][1])),
        (s[2][2], Vec3::new(v[0][2], v[1][2], v[2][2])),
    ];
    if cols[1].0 < cols[0].0 {
        cols.swap(0, 1);
    }
    if cols[2].0 < cols[1].0 {
        cols.swap(1, 2);
    }
    if cols[1].0 < cols[0].0 {
        cols.swap(0, 1);
    }
    let e1 = largest_component_positive(cols[0].1);
    let e2 = largest_component_positive(cols[1].1);
    let e3 = e1.cross(e2);
    Ok((
        [cols[0].0 * down, cols[1].0 * down, cols[2].0 * down],
        Mat3::from_cols(e1, e2, e3),
    ))
}

/// Powers of two `(up, down = 1 / up)` with `x up` in `[1, 2)`; for a subnormal `x` the
/// largest power of two `T` holds (`x up` then normal, short of 1: such moments are refused
/// later anyway, [`Body::from_inertia`]); `(1, 1)` for zero or non-finite `x`.
fn unit_scale<T: Real>(x: T) -> (T, T) {
    if !(x > T::ZERO && x.is_finite()) {
        return (T::ONE, T::ONE);
    }
    // into [2^-40, 2^40] by the steppers' powers of 2^40 (the largest for a subnormal x),
    // then by 2
    let (mut up, mut down) = crate::integrator::homogeneous_scale(Vec3::new(x, T::ZERO, T::ZERO))
        .unwrap_or((T::ONE, T::ONE));
    let mut y = x * up;
    while y >= c::<T>(2.0) {
        (y, up, down) = (y * c::<T>(0.5), up * c::<T>(0.5), down * c::<T>(2.0));
    }
    while y < T::ONE {
        let next = up * c::<T>(2.0);
        if !next.is_finite() {
            break;
        }
        (y, up, down) = (y * c::<T>(2.0), next, down * c::<T>(0.5));
    }
    (up, down)
}

fn largest_component_positive<T: Real>(v: Vec3<T>) -> Vec3<T> {
    let (ax, ay, az) = (v.x.abs(), v.y.abs(), v.z.abs());
    let lead = if ax >= ay && ax >= az {
        v.x
    } else if ay >= az {
        v.y
    } else {
        v.z
    };
    if lead < T::ZERO {
        v.scale(-T::ONE)
    } else {
        v
    }
}

/// One Jacobi rotation zeroing `s[p][q]` (Golub & Van Loan, Alg. 8.5.1, with the small
/// tangent so the rotation angle is at most pi/4).
fn jacobi_rotate<T: Real>(s: &mut [[T; 3]; 3], v: &mut [[T; 3]; 3], p: usize, q: usize) {
    let apq = s[p][q];
    if apq == T::ZERO {
        return;
    }
    let theta = (s[q][q] - s[p][p]) / (c::<T>(2.0) * apq);
    let t = if theta.abs() * T::EPSILON > T::ONE {
        // theta^2 would lose everything or overflow; t ~ 1 / (2 theta)
        c::<T>(0.5) / theta
    } else {
        T::ONE.copysign(theta) / (theta.abs() + (sq(theta) + T::ONE).sqrt())
    };
    let cs = T::ONE / (sq(t) + T::ONE).sqrt();
    let sn = t * cs;
    let r = 3 - p - q; // the third index
    let spp = s[p][p] - t * apq;
    let sqq = s[q][q] + t * apq;
    let srp = cs * s[r][p] - sn * s[r][q];
    let srq = sn * s[r][p] + cs * s[r][q];
    s[p][p] = spp;
    s[q][q] = sqq;
    s[p][q] = T::ZERO;
    s[q][p] = T::ZERO;
    s[r][p] = srp;
    s[p][r] = srp;
    s[r][q] = srq;
    s[q][r] = srq;
    for row in v.iter_mut() {
        let vp = row[p];
        let vq = row[q];
        row[p] = cs * vp - sn * vq;
        row[q] = sn * vp + cs * vq;
    }
}
