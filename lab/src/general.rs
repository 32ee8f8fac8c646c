//! Independent general-N oracle for the discrete Moser–Veselov (DMV) rigid-body step,
//! following Cardoso & Leite: J. R. Cardoso, F. Silva Leite, "The Moser–Veselov equation",
//! Linear Algebra Appl. 360 (2003) 237–248 (preprint: Cardoso & Leite 2001).
//!
//! Problem: given skew `M` (N x N) and `J = diag(J_1..J_N)`, `J_i >= 0`, find `X ∈ SO(N)` with
//! `M = X J - J X^T` and `W = X J` having all eigenvalues in `Re > 0`.
//! Riccati form: `X = (M/2 + S) J^{-1}`, `S` symmetric positive definite,
//! `(S - M/2)(S + M/2) = J^2`, and `S = Q21 Q11^{-1}` where `[Q11; Q21]` spans the invariant
//! subspace of `H = [[M/2, I], [M^2/4 + J^2, M/2]]` for its eigenvalues with `Re > 0`
//! (`H [I; S] = [I; S] W`, `W = M/2 + S`).
//! That subspace is `range((I + sign(H))/2)`; `sign(H)` is computed by the scaled Newton iteration.

use nalgebra::{DMatrix, DVector};

/// Failure modes.
/// * `NonFinite`: non-finite entry in `M` or `J`, or a negative `J_i` (invalid input).
/// * `NoSplit`: `H` has no N-dimensional `Re > 0` invariant subspace (an eigenvalue of `H` on or
///   numerically at the imaginary axis); this happens beyond the existence limit of the step.
/// * `NoConvergence`: the sign iteration did not converge in 100 steps although `H` splits.
/// * `Singular`: `Q11` singular (no graph-form solution), or more than one zero `J_i`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClError {
    NonFinite,
    NoSplit,
    NoConvergence,
    Singular,
}

/// Eigenvalues via real Schur form with an iteration cap (nalgebra's `complex_eigenvalues`
/// has none and can hang; nalgebra's QR then also fails to converge on some of these H).
fn eigs(h: &DMatrix<f64>) -> Option<DVector<nalgebra::Complex<f64>>> {
    // If QR fails (it does on some structured H), retry on a fixed similarity T^{-1} H T.
    let n = h.nrows();
    let t = DMatrix::from_fn(n, n, |i, j| {
        (i == j) as u8 as f64 + 0.3 * ((7 * i + 3 * j) as f64).sin()
    });
    let ht = t.clone().try_inverse()? * h * t;
    let candidates = [h.clone(), ht];
    candidates.iter().find_map(|a| {
        nalgebra::linalg::Schur::try_new(a.clone(), f64::EPSILON, 10_000)
            .map(|s| s.complex_eigenvalues())
    })
}

/// Reclassify a sign-iteration failure (`NoConvergence`) as `NoSplit` if the spectrum of `h`
/// touches the imaginary axis or has not exactly N eigenvalues with Re > 0.
fn classify(e: ClError, h: &DMatrix<f64>, n: usize) -> ClError {
    if e != ClError::NoConvergence {
        return e;
    }
    let ev = eigs(h).unwrap_or_default();
    let tol = 1e-7 * h.norm().max(f64::MIN_POSITIVE);
    let pos = ev.iter().filter(|z| z.re > tol).count();
    if ev.len() == 2 * n && (pos != n || ev.iter().any(|z| z.re.abs() <= tol)) {
        ClError::NoSplit
    } else {
        ClError::NoConvergence
    }
}

/// Matrix sign function by Newton's iteration `Z <- (cZ + (cZ)^{-1})/2` with determinantal
/// scaling `c = |det Z|^{-1/n}` while the relative change exceeds 1e-2, unscaled afterwards.
/// Stops when the relative (Frobenius) change is <= 1e-15, or when it stagnates at the rounding
/// level (<= 1e-12 and no longer halving), or one step after a change <= 1e-9 (quadratic
/// convergence). `None` if not converged in 100 iterations or a singular iterate.
fn matrix_sign(h: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let n = h.nrows();
    let mut z = h.clone();
    let mut prev = f64::INFINITY;
    for _ in 0..100 {
        let lu = z.clone().lu();
        let det = lu.determinant();
        let zi = lu.try_inverse()?;
        if !det.is_finite() || det == 0.0 {
            return None;
        }
        let c = if prev > 1e-2 {
            det.abs().powf(-1.0 / n as f64)
        } else {
            1.0
        };
        let znew = (&z * c + zi / c) * 0.5;
        let delta = (&znew - &z).norm() / znew.norm();
        z = znew;
        if !delta.is_finite() {
            return None;
        }
        if delta <= 1e-15 || prev <= 1e-9 || (delta <= 1e-12 && delta > 0.5 * prev) {
            return Some(z);
        }
        prev = delta;
    }
    None
}

/// Balanced `H`: `T^{-1} [[M/2, I], [M^2/4 + J^2, M/2]] T` with `T = diag(I, sI)`,
/// `s = max(max J_i, |M|_F/2)`, i.e. `[[M/2, sI], [(M^2/4 + J^2)/s, M/2]]`. Returns `(H, s)`.
fn hamiltonian(m: &DMatrix<f64>, j: &[f64]) -> (DMatrix<f64>, f64) {
    let n = j.len();
    let jm = DMatrix::from_diagonal(&DVector::from_column_slice(j));
    let half = m * 0.5;
    let s = j.iter().cloned().fold(0.5 * m.norm(), f64::max);
    let mut h = DMatrix::<f64>::zeros(2 * n, 2 * n);
    h.view_mut((0, 0), (n, n)).copy_from(&half);
    h.view_mut((0, n), (n, n)).fill_with_identity();
    h.view_mut((0, n), (n, n)).scale_mut(s);
    h.view_mut((n, 0), (n, n))
        .copy_from(&((&half * &half + &jm * &jm) / s));
    h.view_mut((n, n), (n, n)).copy_from(&half);
    (h, s)
}

/// Orthonormal basis (2N x d) of the invariant subspace of `h` for eigenvalues with
/// `Re > sigma`: first d columns of Q in the column-pivoted QR `P Π = Q R` of the spectral
/// projector `P = (I + sign(h - sigma I))/2`. Checks: `trace(sign) = 2d - 2N`, `sign^2 = I`,
/// rank gap `|R_{d+1,d+1}| <= 1e-8 |R_{d,d}|`.
/// (nalgebra's SVD is avoided: it loses accuracy on such matrices, dimforge/nalgebra#1172.)
fn right_basis(h: &DMatrix<f64>, sigma: f64, d: usize) -> Result<DMatrix<f64>, ClError> {
    let nn = h.nrows();
    let i2 = DMatrix::<f64>::identity(nn, nn);
    let z = matrix_sign(&(h - &i2 * sigma)).ok_or(ClError::NoConvergence)?;
    let tr = 2.0 * d as f64 - nn as f64;
    if (z.trace() - tr).abs() > 0.5 || (&z * &z - &i2).amax() > 1e-6 * z.amax().powi(2) {
        return Err(ClError::NoSplit);
    }
    let qr = ((&i2 + &z) * 0.5).col_piv_qr();
    let rd = qr.r().diagonal().map(f64::abs);
    if !(rd[d] <= 1e-8 * rd[d - 1]) {
        return Err(ClError::NoSplit);
    }
    Ok(qr.q().columns(0, d).into_owned())
}

/// Residuals `(|X^T X - I|_max, |X J - J X^T - M|_max)`.
fn residuals(x: &DMatrix<f64>, m: &DMatrix<f64>, j: &[f64]) -> (f64, f64) {
    let n = j.len();
    let jm = DMatrix::from_diagonal(&DVector::from_column_slice(j));
    let orth = (x.transpose() * x - DMatrix::<f64>::identity(n, n)).amax();
    let eq = (x * &jm - &jm * x.transpose() - m).amax();
    (orth, eq)
}

/// Cayley transform `(I - A/2)^{-1} (I + A/2)`, exactly orthogonal for skew `A`.
fn cayley(a: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let n = a.nrows();
    let i = DMatrix::<f64>::identity(n, n);
    (&i - a * 0.5).lu().solve(&(&i + a * 0.5))
}

/// One Newton step for `F(X) = X J - J X^T - M = 0` on SO(N): `X <- X cay(A)`, `A` skew solving
/// `X A J + J A X^T = -F(X)` (upper-triangle equations, N(N-1)/2 unknowns).
fn newton_so(x: &DMatrix<f64>, m: &DMatrix<f64>, jm: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let n = x.nrows();
    let pairs: Vec<(usize, usize)> = (0..n)
        .flat_map(|k| (k + 1..n).map(move |l| (k, l)))
        .collect();
    let p = pairs.len();
    let f = x * jm - jm * x.transpose() - m;
    let mut jac = DMatrix::<f64>::zeros(p, p);
    for (col, &(k, l)) in pairs.iter().enumerate() {
        let mut e = DMatrix::<f64>::zeros(n, n);
        e[(k, l)] = 1.0;
        e[(l, k)] = -1.0;
        let d = x * &e * jm + jm * &e * x.transpose();
        for (row, &(i, jj)) in pairs.iter().enumerate() {
            jac[(row, col)] = d[(i, jj)];
        }
    }
    let rhs = DVector::from_iterator(p, pairs.iter().map(|&(i, jj)| -f[(i, jj)]));
    let a = jac.lu().solve(&rhs)?;
    let mut am = DMatrix::<f64>::zeros(n, n);
    for (t, &(k, l)) in pairs.iter().enumerate() {
        am[(k, l)] = a[t];
        am[(l, k)] = -a[t];
    }
    Some(x * cayley(&am)?)
}

/// General-N DMV solve (Cardoso–Leite): returns `X ∈ SO(N)` with `M = X J - J X^T` and
/// `spec(X J) ⊂ {Re > 0}`.
///
/// Method: `H = [[M/2, I], [M^2/4 + J^2, M/2]]` (Hamiltonian; balanced by the similarity
/// `diag(I, sI)`, `s = max(max J_i, |M|_F/2)`); `Z = sign(H)` by scaled Newton;
/// `P = (I + Z)/2`; orthonormal basis `[Q11; Q21]` of `range(P)` from the column-pivoted QR
/// of `P` (first N columns of Q; rank gap |R_{N+1,N+1}| <= 1e-8 |R_{N,N}| checked);
/// `S = Q21 Q11^{-1}`, then symmetrized, `S <- (S + S^T)/2` (asymmetry before: ~1e-15, checked
/// <= 1e-6 relative); `W = M/2 + S`; `X = W J^{-1}`. If exactly one `J_i = 0` (planar body),
/// `W` is singular and `H` has a Jordan pair at 0; then the subspace is spanned by the `Re > σ`
/// subspace (`sign(H - σI)`, `σ = s 4^-k`, k = 1..10, first with exactly N-1 eigenvalues right
/// of σ) plus `ker H` (col-pivoted QR of `H^T`); `X = W J^{-1}` on the other columns, and
/// column `i` of `X` is the unit vector completing the others to a right-handed orthonormal
/// frame (generalized cross product via cofactors; for N = 3 the cross product of the other
/// two columns). More than one zero `J_i`: `Singular`.
/// Finally `X` is projected onto SO(N) (polar factor, Newton iteration) and refined by up to
/// two Newton steps on `F(X) = X J - J X^T - M` over SO(N) (Cayley update), each kept only if
/// it reduces the residual.
///
/// Accuracy: the raw `X = W J^{-1}` has `|X^T X - I|_max` up to ~2e-14 (random N = 5) and
/// ~1e-13 next to the existence limit; after polar + Newton, both `|X^T X - I|_max` and
/// `|X J - J X^T - M|_max` are <= 7e-16 in all tests (|M| <~ 1, J_i in [0.1, 1.2]; the tests
/// require <= 1e-13).
/// `M` is replaced by its skew part `(M - M^T)/2`. Panics if `M` is not `N x N`, `N = j.len()`.
pub fn dmv_x_general(m_skew: &DMatrix<f64>, j: &[f64]) -> Result<DMatrix<f64>, ClError> {
    let n = j.len();
    assert!(
        m_skew.nrows() == n && m_skew.ncols() == n,
        "M must be N x N with N = j.len()"
    );
    if m_skew.iter().any(|v| !v.is_finite()) || j.iter().any(|v| !v.is_finite() || *v < 0.0) {
        return Err(ClError::NonFinite);
    }
    if n <= 1 {
        return Ok(DMatrix::identity(n, n));
    }
    let zeros: Vec<usize> = (0..n).filter(|&i| j[i] == 0.0).collect();
    if zeros.len() > 1 {
        return Err(ClError::Singular);
    }
    let m = (m_skew - m_skew.transpose()) * 0.5;
    let jm = DMatrix::from_diagonal(&DVector::from_column_slice(j));
    let half = &m * 0.5;
    let (h, s) = hamiltonian(&m, j);
    if !(s > 0.0) {
        return Err(ClError::NoSplit);
    }
    let q = if zeros.is_empty() {
        right_basis(&h, 0.0, n).map_err(|e| classify(e, &h, n))?
    } else {
        // Planar body: W = XJ is singular, so H has a (Jordan) eigenvalue pair at 0 and the wanted
        // subspace is range(Re>0 part, dim N-1) + ker(H) (H [e_i; S e_i] = [I; S] W e_i = 0).
        // Shift σ = s 4^-k decreased until sign(H - σI) has exactly N-1 eigenvalues right of σ.
        let qa = (1..=10)
            .map(|k| right_basis(&h, s * 0.25f64.powi(k), n - 1))
            .find(|r| r.is_ok())
            .unwrap_or(Err(ClError::NoSplit))?;
        let qrh = h.transpose().col_piv_qr();
        let rd = qrh.r().diagonal().map(f64::abs);
        if !(rd[2 * n - 1] <= 1e-8 * rd[0] && rd[2 * n - 2] > 1e-6 * rd[0]) {
            return Err(ClError::Singular);
        }
        let mut q = DMatrix::<f64>::zeros(2 * n, n);
        q.columns_mut(0, n - 1).copy_from(&qa);
        q.set_column(n - 1, &qrh.q().column(2 * n - 1));
        q
    };
    let q11 = q.rows(0, n).into_owned();
    let q21 = q.rows(n, n).into_owned() * s;
    // S Q11 = Q21  <=>  Q11^T S^T = Q21^T
    let st = q11
        .transpose()
        .lu()
        .solve(&q21.transpose())
        .ok_or(ClError::Singular)?;
    let sm = st.transpose();
    if (&sm - sm.transpose()).amax() > 1e-6 * sm.amax() {
        return Err(ClError::NoSplit);
    }
    let mut x = &half + (&sm + sm.transpose()) * 0.5; // W = M/2 + S, then X = W J^{-1}
    for k in 0..n {
        if j[k] != 0.0 {
            x.column_mut(k).scale_mut(1.0 / j[k]);
        }
    }
    if let Some(&i0) = zeros.first() {
        // c_k = det(X with column i0 replaced by e_k): the oriented unit normal (up to scale).
        let mut c = DVector::<f64>::zeros(n);
        for k in 0..n {
            let mut y = x.clone();
            y.column_mut(i0).fill(0.0);
            y[(k, i0)] = 1.0;
            c[k] = y.determinant();
        }
        let cn = c.norm();
        if !(cn > 0.0) {
            return Err(ClError::Singular);
        }
        x.set_column(i0, &(c / cn));
    }
    // Project onto O(N): polar factor by Newton's iteration X <- (X + X^{-T})/2; must be in SO(N).
    let x0 = x.clone();
    for _ in 0..20 {
        let xn = (&x
            + x.clone()
                .try_inverse()
                .ok_or(ClError::Singular)?
                .transpose())
            * 0.5;
        let d = (&xn - std::mem::replace(&mut x, xn.clone())).amax();
        if d <= 1e-15 {
            break;
        }
    }
    if x.determinant() < 0.0 || (&x - &x0).amax() > 1e-6 {
        return Err(ClError::NoSplit);
    }
    let mut r = residuals(&x, &m, j).1;
    for _ in 0..2 {
        let Some(xn) = newton_so(&x, &m, &jm) else {
            break;
        };
        let rn = residuals(&xn, &m, j).1;
        if !(rn < r) {
            break;
        }
        (x, r) = (xn, rn);
    }
    if x.iter().any(|v| !v.is_finite()) {
        return Err(ClError::NoConvergence);
    }
    Ok(x)
}

/// `hat(a) = [[0,-a3,a2],[a3,0,-a1],[-a2,a1,0]]`, so `hat(a) b = a × b`.
fn hat(a: [f64; 3]) -> DMatrix<f64> {
    DMatrix::from_row_slice(
        3,
        3,
        &[0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0],
    )
}

/// N = 3: `X ∈ SO(3)` (row-major) with `h hat(m) = X J - J X^T`, `spec(XJ) ⊂ {Re > 0}`, where
/// `hat(a) = [[0,-a3,a2],[a3,0,-a1],[-a2,a1,0]]` (`hat(a) b = a × b`).
/// Same method, source (Cardoso & Leite, "The Moser–Veselov equation", LAA 360 (2003)
/// 237–248; preprint 2001) and accuracy (residuals <= ~1e-15) as [`dmv_x_general`].
/// For `J_i = 0` (planar body) that column of X is the cross product of the other two.
pub fn dmv_x3(j: [f64; 3], m: [f64; 3], h: f64) -> Result<[[f64; 3]; 3], ClError> {
    if !h.is_finite() || m.iter().any(|v| !v.is_finite()) {
        return Err(ClError::NonFinite);
    }
    let x = dmv_x_general(&(hat(m) * h), &j)?;
    Ok(std::array::from_fn(|r| std::array::from_fn(|c| x[(r, c)])))
}

/// One DMV step for N = 3: solves `h hat(m) = X J - J X^T` (see [`dmv_x3`]) and returns
/// `m_next = X^T m`. Cardoso & Leite (LAA 360 (2003) 237–248; preprint 2001) via the matrix
/// sign function; per-step error ~1e-15 (reversible to <= 6e-16 in tests: the step with `-h`
/// from `m_next` returns `m`). Second order: global error ~0.51 h^2 at t = 10 on the talk case.
/// Errors: `NoSplit` past the existence limit (e.g. h > 1.060273597 at the talk's m0).
pub fn dmv_step3(j: [f64; 3], m: [f64; 3], h: f64) -> Result<[f64; 3], ClError> {
    let x = dmv_x3(j, m, h)?;
    Ok(std::array::from_fn(|c| {
        (0..3).map(|r| x[r][c] * m[r]).sum()
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::rng::Rng;
    use crate::scenes::{TALK_J as J0, TALK_M0 as M0, TALK_M10};

    fn check_random(n: usize, seed: u64) {
        let mut rng = Rng(seed);
        let (mut mo, mut me, mut ok, mut axis) = (0.0f64, 0.0f64, 0, 0);
        for _ in 0..2000 {
            let j: Vec<f64> = (0..n).map(|_| rng.range(0.1, 1.2)).collect();
            let a = DMatrix::from_fn(n, n, |_, _| rng.range(-0.5, 0.5));
            let m = a.upper_triangle() - a.upper_triangle().transpose();
            match dmv_x_general(&m, &j) {
                Ok(x) => {
                    let (o, e) = residuals(&x, &m, &j);
                    assert!(o <= 1e-13 && e <= 1e-13, "residuals {o:e} {e:e}");
                    assert!(x.determinant() > 0.0);
                    let w = &x * DMatrix::from_diagonal(&DVector::from_column_slice(&j));
                    assert!(eigs(&w).unwrap().iter().all(|z| z.re > 0.0));
                    mo = mo.max(o);
                    me = me.max(e);
                    ok += 1;
                }
                Err(ClError::NoSplit) => {
                    // genuine: H has an eigenvalue on the imaginary axis
                    let (hh, _) = hamiltonian(&m, &j);
                    let ev = eigs(&hh).unwrap();
                    let mre = ev.iter().map(|z| z.re.abs()).fold(f64::INFINITY, f64::min);
                    assert!(mre <= 1e-6, "NoSplit but min |Re| = {mre:e}");
                    axis += 1;
                }
                Err(e) => panic!("unexpected {e:?}"),
            }
        }
        assert!(ok > 1500, "too few solvable cases: {ok}");
        println!(
            "N={n}: {ok}/2000 solved ({axis} NoSplit, all with Re(eig H) = 0), \
                  max |X^TX-I| = {mo:e}, max |XJ-JX^T-M| = {me:e}"
        );
    }

    #[test]
    fn random_n3_n5() {
        check_random(3, 0x9E3779B97F4A7C15);
        check_random(5, 0x1234_5678_9ABC_DEF1);
    }

    #[test]
    fn reversibility() {
        let mut rng = Rng(42);
        let (mut worst, mut skipped) = (0.0f64, 0);
        for _ in 0..2000 {
            let j = [
                rng.range(0.1, 1.2),
                rng.range(0.1, 1.2),
                rng.range(0.1, 1.2),
            ];
            let m = [
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ];
            let h = rng.range(0.01, 0.3);
            let Ok(m1) = dmv_step3(j, m, h) else {
                // only where no DMV step exists, as rigid3's own existence limit says
                let body = rigid3::Body::from_mass_matrix(j).unwrap();
                assert!(
                    h >= 0.999 * rigid3::Mv::max_step(&body, &m),
                    "{j:?} {m:?} {h}"
                );
                skipped += 1;
                continue;
            };
            let m0 = dmv_step3(j, m1, -h).unwrap();
            let d = (0..3).map(|i| (m0[i] - m[i]).abs()).fold(0.0, f64::max);
            assert!(d <= 1e-13, "reversibility {d:e}");
            worst = worst.max(d);
        }
        assert!(
            skipped < 20,
            "{skipped} of 2000 steps past the existence limit"
        );
        println!("reversibility max |m - back(fwd(m))| = {worst:e} ({skipped} past the limit)");
    }

    #[test]
    fn talk_case_t10() {
        let mref = TALK_M10;
        let mut m = M0;
        for _ in 0..100 {
            m = dmv_step3(J0, m, 0.1).unwrap();
        }
        let err = (0..3).map(|i| (m[i] - mref[i]).powi(2)).sum::<f64>().sqrt();
        println!("m(10) = {m:?}, |m(10)-mref| = {err:e} (0.51 h^2 = 5.1e-3)");
        assert!((4.5e-3..=5.7e-3).contains(&err), "err {err:e}");
    }

    #[test]
    fn existence_limit() {
        // limit at m0: h = 1.060273597
        for h in [1.05, 1.0602] {
            let x = dmv_x3(J0, M0, h).unwrap();
            let (o, e) = residuals(&DMatrix::from_fn(3, 3, |r, c| x[r][c]), &(hat(M0) * h), &J0);
            println!("h = {h}: |X^TX-I| = {o:e}, |XJ-JX^T-M| = {e:e}");
            assert!(o <= 1e-13 && e <= 1e-13);
        }
        assert_eq!(dmv_step3(J0, M0, 1.07), Err(ClError::NoSplit));
        assert_eq!(dmv_step3(J0, M0, 1.0604), Err(ClError::NoSplit));
    }

    #[test]
    fn planar() {
        let mut rng = Rng(7);
        let (mut mo, mut me, mut ok) = (0.0f64, 0.0f64, 0);
        for _ in 0..2000 {
            let j = [rng.range(0.2, 1.2), rng.range(0.2, 1.2), 0.0];
            let m = [
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ];
            let h = rng.range(0.01, 0.3);
            let r3 = (h * m[1] / j[0]).powi(2) + (h * m[0] / j[1]).powi(2);
            // Row 3 of X is (-h m2/J1, h m1/J2, x33): no solution if r3 > 1.
            let x = match dmv_x3(j, m, h) {
                Ok(x) => x,
                Err(e) => {
                    assert!(
                        r3 > 0.999 && e == ClError::NoSplit,
                        "planar {e:?} r3 = {r3}"
                    );
                    continue;
                }
            };
            assert!(r3 <= 1.0);
            ok += 1;
            let xd = DMatrix::from_fn(3, 3, |r, c| x[r][c]);
            let (o, e) = residuals(&xd, &(hat(m) * h), &j);
            assert!(o <= 1e-13 && e <= 1e-13, "planar residuals {o:e} {e:e}");
            assert!(xd.determinant() > 0.0);
            mo = mo.max(o);
            me = me.max(e);
        }
        println!("planar: {ok}/2000 solved, max |X^TX-I| = {mo:e}, max |XJ-JX^T-M| = {me:e}");
    }

    #[test]
    fn errors() {
        let nan = [f64::NAN, 0.0, 0.0];
        assert_eq!(dmv_step3(J0, nan, 0.1), Err(ClError::NonFinite));
        assert_eq!(dmv_step3([1.0, 0.0, 0.0], M0, 0.1), Err(ClError::Singular));
    }

    #[test]
    fn timing() {
        let (t, mut m) = (std::time::Instant::now(), M0);
        for _ in 0..20000 {
            m = dmv_step3(J0, m, 0.1).unwrap();
        }
        let us = t.elapsed().as_secs_f64() / 20000.0 * 1e6;
        println!("dmv_step3: {us:.2} us/call (m = {m:?})");
    }
}

/// The general solver as an [`rigid3::Integrator`] in f64 (N = 3), for the CLI and the
/// tables: about 20 µs a step, so an oracle, not a method.
#[derive(Clone, Copy, Debug)]
pub struct GeneralDmv {
    j: [f64; 3],
    h: f64,
    body: rigid3::Body<f64>,
}

impl GeneralDmv {
    /// The DMV step for mass matrix `j` (a valid one: non-negative entries) and step `h`.
    pub fn new(j: [f64; 3], h: f64) -> Self {
        let body = rigid3::Body::from_mass_matrix(j).expect("the oracle needs a valid mass matrix");
        Self { j, h, body }
    }
}

fn to_step_error(e: ClError) -> rigid3::StepError {
    match e {
        ClError::NonFinite => rigid3::StepError::NonFinite,
        ClError::NoSplit => rigid3::StepError::StepTooLarge,
        ClError::NoConvergence => rigid3::StepError::NoConvergence,
        ClError::Singular => rigid3::StepError::Degenerate,
    }
}

impl rigid3::Integrator<f64> for GeneralDmv {
    fn step(&mut self, m: &mut [f64; 3]) -> Result<(), rigid3::StepError> {
        *m = dmv_step3(self.j, *m, self.h).map_err(to_step_error)?;
        Ok(())
    }

    fn step_state(&mut self, s: &mut rigid3::State<f64>) -> Result<(), rigid3::StepError> {
        let x = dmv_x3(self.j, s.m, self.h).map_err(to_step_error)?;
        let m = s.m;
        let next = [
            x[0][0] * m[0] + x[1][0] * m[1] + x[2][0] * m[2],
            x[0][1] * m[0] + x[1][1] * m[1] + x[2][1] * m[2],
            x[0][2] * m[0] + x[1][2] * m[1] + x[2][2] * m[2],
        ];
        let q = quat_mul(s.q, quat_from_rotation(x));
        let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
        s.m = next;
        s.q = [q[0] / n, q[1] / n, q[2] / n, q[3] / n];
        Ok(())
    }

    fn step_size(&self) -> f64 {
        self.h
    }

    fn set_step_size(&mut self, h: f64) {
        self.h = h;
    }

    fn body(&self) -> &rigid3::Body<f64> {
        &self.body
    }
}

/// Hamilton product.
fn quat_mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// Unit quaternion of a rotation matrix (row-major) via the eigenvector of the symmetric
/// 4x4 Bar-Itzhack matrix: a route independent of the library's Shepperd formula.
fn quat_from_rotation(r: [[f64; 3]; 3]) -> [f64; 4] {
    let k = nalgebra::Matrix4::new(
        r[0][0] + r[1][1] + r[2][2],
        r[2][1] - r[1][2],
        r[0][2] - r[2][0],
        r[1][0] - r[0][1],
        r[2][1] - r[1][2],
        r[0][0] - r[1][1] - r[2][2],
        r[0][1] + r[1][0],
        r[0][2] + r[2][0],
        r[0][2] - r[2][0],
        r[0][1] + r[1][0],
        r[1][1] - r[0][0] - r[2][2],
        r[1][2] + r[2][1],
        r[1][0] - r[0][1],
        r[0][2] + r[2][0],
        r[1][2] + r[2][1],
        r[2][2] - r[0][0] - r[1][1],
    );
    let e = k.symmetric_eigen();
    let i = e.eigenvalues.imax();
    let v = e.eigenvectors.column(i);
    let s = if v[0] < 0.0 { -1.0 } else { 1.0 };
    [s * v[0], s * v[1], s * v[2], s * v[3]]
}
