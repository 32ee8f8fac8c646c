//! `SeedMv`: the talk's explicit spectral algorithm for the 3x3 discrete Moser–Veselov step,
//! kept as published (Zanna & McLachlan, "An explicit, completely integrable, second-order
//! method for the 3x3 rigid body"; docs/MATH.md §2).

use crate::body::Body;
use crate::cubic::{complex_sqrt, solve_cubic, CubicRoots};
use crate::error::StepError;
use crate::integrator::{
    checked_momentum, checked_state, compose_attitude, write_momentum, write_state, Integrator,
    State,
};
use crate::linalg::{Mat3, Quat, Vec3};
use crate::real::{c, sq, Real};

/// The talk's explicit DMV step: a cubic, eigenvalues, quadratic eigenvectors, a QR and a
/// 3x3 solve.
///
/// One step solves `M = X J - J X^T` for `X` in SO(3) with `W = X J` having its spectrum in
/// `Re > 0`, `M = h hat(m_k)`, and sets `m_{k+1} = X^T m_k`, `R_{k+1} = R_k X`. The spectrum
/// `+-lambda_i` of `H = [[M/2, I], [M^2/4 + J^2, M/2]]` comes from the cubic
/// `mu^3 - A mu^2 + B mu - C` in `mu = lambda^2`; each `lambda_i` with `Re > 0` gives a
/// quadratic eigenvector `(lambda^2 I - lambda M - J^2) y = 0` (a cross product of two rows,
/// in real arithmetic for a complex pair), and `[y; lambda y - M y / 2]` spans the invariant
/// subspace; after Gram–Schmidt, `S = Q21 Q11^-1` and `X = (M/2 + S) J^-1`.
///
/// Second order, time-reversible, Poisson; `|m|^2`, the energy and `R(q) m` are conserved to
/// round-off. Phase error at `t = 10` on the talk's case is about `0.51 h^2`.
///
/// Weak spots, inherited from the published method and reported as `Err`, never as a wrong
/// result: repeated `mu` (equal `J_i` with `m = 0`, `m` along an axis at special `h`) give a
/// singular eigenvector system (`Degenerate`); a planar body (`J_i = 0`) has no `J^-1`
/// (`Degenerate`); past the existence limit the cubic has a negative real root
/// (`StepTooLarge`); any `X` further than `450 eps` (1e-13 in f64) from orthogonal is refused (`Degenerate`: about 1 random input in 2500 in the lab's cross-check).
/// Near root collisions the eigenvectors lose accuracy (about `1e-11` in f64). See `Mv` for
/// the closed form that has none of these.
#[derive(Clone, Debug)]
pub struct SeedMv<T> {
    body: Body<T>,
    h: T,
}

impl<T: Real> SeedMv<T> {
    /// An integrator for `body` with step `h` (any finite `h`, negative steps run backwards).
    #[must_use]
    pub fn new(body: Body<T>, h: T) -> Self {
        Self { body, h }
    }

    /// The rotation `X` of one step from momentum `m`, as rows (`X[i][j]`), for checks.
    ///
    /// # Errors
    ///
    /// Those of the step: [`StepError::NonFinite`], [`StepError::StepTooLarge`] (the cubic
    /// has a negative real root), [`StepError::Degenerate`] (a singular eigenvector system, a
    /// repeated root, or an `X` that fails the orthogonality check), [`StepError::Overflow`].
    pub fn step_matrix(&self, m: &[T; 3]) -> Result<[[T; 3]; 3], StepError> {
        let x = self.solve(checked_momentum(m)?)?;
        Ok([
            x.row0().to_array(),
            x.row1().to_array(),
            x.row2().to_array(),
        ])
    }

    fn solve(&self, m: Vec3<T>) -> Result<Mat3<T>, StepError> {
        if !self.h.is_finite() {
            return Err(StepError::NonFinite);
        }
        let j = self.body.mass_matrix_vec();
        if !(j.x > T::ZERO && j.y > T::ZERO && j.z > T::ZERO) {
            return Err(StepError::Degenerate);
        }
        // The equation is homogeneous in (M, J): scale both to order one.
        let hm = m.scale(self.h);
        let kappa = j.max_abs().max(hm.max_abs());
        if !kappa.is_finite() {
            return Err(StepError::Overflow);
        }
        // divide, not multiply by a reciprocal: 1 / kappa overflows for a subnormal kappa
        let j = Vec3::new(j.x / kappa, j.y / kappa, j.z / kappa);
        let mm = Vec3::new(hm.x / kappa, hm.y / kappa, hm.z / kappa);
        let big_m = Mat3::hat(mm);
        let j2 = j.mul_elem(j);
        let a = mm.mul_elem(mm);
        let big_a = j2.x + j2.y + j2.z - (a.x + a.y + a.z);
        let big_b = j2.x * j2.y + j2.x * j2.z + j2.y * j2.z - a.dot(j2);
        let big_c = sq(j.x * j.y * j.z);
        let roots = solve_cubic(-big_a, big_b, -big_c).ok_or(StepError::NonFinite)?;

        let half_m = big_m.scale(c(0.5));
        let (top, bottom) = match roots {
            CubicRoots::Real([mu0, mu1, mu2]) => {
                if !(mu0 > T::ZERO) {
                    return Err(StepError::StepTooLarge);
                }
                let l0 = mu0.sqrt();
                let l1 = mu1.sqrt();
                let l2 = mu2.sqrt();
                let y0 = real_null_vector(l0, &big_m, j2)?;
                let y1 = real_null_vector(l1, &big_m, j2)?;
                let y2 = real_null_vector(l2, &big_m, j2)?;
                let d0 = y0.scale(l0).sub(half_m.mul_vec(y0));
                let d1 = y1.scale(l1).sub(half_m.mul_vec(y1));
                let d2 = y2.scale(l2).sub(half_m.mul_vec(y2));
                (Mat3::from_cols(y0, y1, y2), Mat3::from_cols(d0, d1, d2))
            }
            CubicRoots::Complex { real, re, im } => {
                if !(real > T::ZERO) {
                    return Err(StepError::StepTooLarge);
                }
                let l0 = real.sqrt();
                let y0 = real_null_vector(l0, &big_m, j2)?;
                let d0 = y0.scale(l0).sub(half_m.mul_vec(y0));
                let (u, v) = complex_sqrt(re, im);
                let (yr, yi) = complex_null_vector(re, im, u, v, &big_m, j2)?;
                // lambda y - M y / 2 with lambda = u + i v, y = yr + i yi
                let dr = yr.scale(u).sub(yi.scale(v)).sub(half_m.mul_vec(yr));
                let di = yi.scale(u).add(yr.scale(v)).sub(half_m.mul_vec(yi));
                (Mat3::from_cols(y0, yr, yi), Mat3::from_cols(d0, dr, di))
            }
        };

        let (q11, q21) = gram_schmidt(top, bottom)?;
        let (q11_inv, ok) = q11.inverse_or_zero();
        if !ok {
            return Err(StepError::Degenerate);
        }
        let s = q21.mul_mat(&q11_inv);
        let inv_j = Vec3::new(T::ONE / j.x, T::ONE / j.y, T::ONE / j.z);
        let x = half_m.add(&s).mul_diag(inv_j);
        if !x.is_finite() || !(x.orthogonality_defect() <= c::<T>(450.0) * T::EPSILON) {
            return Err(StepError::Degenerate);
        }
        Ok(x)
    }
}

/// A unit null vector of `lambda^2 I - lambda M - J^2` (rank 2 for a simple eigenvalue): the
/// largest cross product of two rows. `Degenerate` if every cross product is negligible,
/// i.e. the eigenvalue is (numerically) repeated.
fn real_null_vector<T: Real>(lambda: T, m: &Mat3<T>, j2: Vec3<T>) -> Result<Vec3<T>, StepError> {
    let l2 = sq(lambda);
    let k = m
        .scale(-lambda)
        .add(&Mat3::diagonal(Vec3::new(l2 - j2.x, l2 - j2.y, l2 - j2.z)));
    let (r0, r1, r2) = (k.row0(), k.row1(), k.row2());
    let c01 = r0.cross(r1);
    let c02 = r0.cross(r2);
    let c12 = r1.cross(r2);
    let (n01, n02, n12) = (c01.norm2(), c02.norm2(), c12.norm2());
    let (best, n) = if n01 >= n02 && n01 >= n12 {
        (c01, n01)
    } else if n02 >= n12 {
        (c02, n02)
    } else {
        (c12, n12)
    };
    let scale = sq(r0.norm2().max(r1.norm2()).max(r2.norm2()));
    if !(n > c::<T>(1e4) * sq(T::EPSILON) * scale) {
        return Err(StepError::Degenerate);
    }
    Ok(best.scale(T::ONE / n.sqrt()))
}

/// A null vector `yr + i yi` of the complex matrix `mu I - lambda M - J^2`, `mu = re + i im`,
/// `lambda = u + i v`, in real arithmetic: the bilinear cross product of two complex rows is
/// orthogonal (without conjugation) to both, hence to the third when the rank is 2.
fn complex_null_vector<T: Real>(
    re: T,
    im: T,
    u: T,
    v: T,
    m: &Mat3<T>,
    j2: Vec3<T>,
) -> Result<(Vec3<T>, Vec3<T>), StepError> {
    let kr = m
        .scale(-u)
        .add(&Mat3::diagonal(Vec3::new(re - j2.x, re - j2.y, re - j2.z)));
    let ki = m.scale(-v).add(&Mat3::diagonal(Vec3::new(im, im, im)));
    let (a0, a1, a2) = (kr.row0(), kr.row1(), kr.row2());
    let (b0, b1, b2) = (ki.row0(), ki.row1(), ki.row2());
    let cross = |ar: Vec3<T>, ai: Vec3<T>, br: Vec3<T>, bi: Vec3<T>| {
        (
            ar.cross(br).sub(ai.cross(bi)),
            ar.cross(bi).add(ai.cross(br)),
        )
    };
    let c01 = cross(a0, b0, a1, b1);
    let c02 = cross(a0, b0, a2, b2);
    let c12 = cross(a1, b1, a2, b2);
    let n01 = c01.0.norm2() + c01.1.norm2();
    let n02 = c02.0.norm2() + c02.1.norm2();
    let n12 = c12.0.norm2() + c12.1.norm2();
    let (best, n) = if n01 >= n02 && n01 >= n12 {
        (c01, n01)
    } else if n02 >= n12 {
        (c02, n02)
    } else {
        (c12, n12)
    };
    let row = |r: Vec3<T>, i: Vec3<T>| r.norm2() + i.norm2();
    let scale = sq(row(a0, b0).max(row(a1, b1)).max(row(a2, b2)));
    if !(n > c::<T>(1e4) * sq(T::EPSILON) * scale) {
        return Err(StepError::Degenerate);
    }
    let inv = T::ONE / n.sqrt();
    Ok((best.0.scale(inv), best.1.scale(inv)))
}

/// Modified Gram–Schmidt on the three 6-vectors `[top_k; bottom_k]` (the talk's
/// orthonormalisation of the invariant-subspace basis).
fn gram_schmidt<T: Real>(top: Mat3<T>, bottom: Mat3<T>) -> Result<(Mat3<T>, Mat3<T>), StepError> {
    let dot = |a: (Vec3<T>, Vec3<T>), b: (Vec3<T>, Vec3<T>)| a.0.dot(b.0) + a.1.dot(b.1);
    let unit = |a: (Vec3<T>, Vec3<T>)| -> Result<(Vec3<T>, Vec3<T>), StepError> {
        let n = dot(a, a);
        if !(n > T::ZERO) || !n.is_finite() {
            return Err(StepError::Degenerate);
        }
        let inv = T::ONE / n.sqrt();
        Ok((a.0.scale(inv), a.1.scale(inv)))
    };
    let minus = |a: (Vec3<T>, Vec3<T>), b: (Vec3<T>, Vec3<T>), k: T| {
        (a.0.sub(b.0.scale(k)), a.1.sub(b.1.scale(k)))
    };
    let q0 = unit((top.x_axis, bottom.x_axis))?;
    let v1 = (top.y_axis, bottom.y_axis);
    let q1 = unit(minus(v1, q0, dot(v1, q0)))?;
    let v2 = (top.z_axis, bottom.z_axis);
    let v2 = minus(v2, q0, dot(v2, q0));
    let q2 = unit(minus(v2, q1, dot(v2, q1)))?;
    Ok((
        Mat3::from_cols(q0.0, q1.0, q2.0),
        Mat3::from_cols(q0.1, q1.1, q2.1),
    ))
}

impl<T: Real> Integrator<T> for SeedMv<T> {
    fn step(&mut self, m: &mut [T; 3]) -> Result<(), StepError> {
        let v = checked_momentum(m)?;
        // a zero step leaves the state as it is ([`Integrator::set_step_size`]); solved, its
        // rotation came out an ulp from the identity (2.2e-13 over 1000 paused steps, found
        // by a first-use trial)
        if self.h == T::ZERO {
            return Ok(());
        }
        let x = self.solve(v)?;
        let next = x.transpose_mul_vec(v);
        write_momentum(m, next)
    }

    fn step_state(&mut self, s: &mut State<T>) -> Result<(), StepError> {
        let (v, q) = checked_state(s)?;
        // (as in step)
        if self.h == T::ZERO {
            return Ok(());
        }
        let x = self.solve(v)?;
        let next = x.transpose_mul_vec(v);
        write_state(s, next, compose_attitude(q, Quat::from_mat3(&x)))
    }

    fn step_size(&self) -> T {
        self.h
    }

    fn set_step_size(&mut self, h: T) {
        self.h = h;
    }

    fn body(&self) -> &Body<T> {
        &self.body
    }
}
