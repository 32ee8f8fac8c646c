//! The free-running DMV step as a rational map of `m` with per-trajectory coefficients: what
//! [`crate::Mv`] runs while the caller leaves the state alone at small `h |Omega|`.
//!
//! # Derivation
//!
//! In the step's scaled units (`u = hn m`, `hn = h / kappa`, `a_i = u_i^2`) the system of
//! `Mv` is `L^T y = m` with
//!
//! `L^T = u u^T + diag(d) + s1 hat(u)`,  `d_i = j_i^2 + s2 - alpha`,  `alpha = |u|^2`,
//!
//! and the increment is `m' - m = Delta y`, `Delta = diag(dd) - u u^T + diag(j - s1) hat(u)`,
//! `dd_i = delta j_i - e` (`e = s2 - s2_0 - alpha`; crate::mv). Along a trajectory `s1`, `s2`
//! and `alpha` are constants, so `d` is too. For `A = diag(d) + hat(w)`,
//!
//! `A^-1 = (adj(D) + w w^T - hat(D w)) / (d1 d2 d3 + w^T D w)`
//!
//! (multiply out: `hat(w) adj(D) = D hat(D w)` and `hat(w) hat(D w) = D w w^T - (w . D w) I`),
//! and `L^T = A + u u^T` with `w = s1 u`. The right-hand side is parallel to `u`, so
//! Sherman–Morrison scales `A^-1 m` by a number, `hat(u) m = 0` removes the rest, and
//!
//! `y = N / den`,  `N = P m - (ds m) x m`,  `den = C0 + sum W_i m_i^2`,
//!
//! with the constant diagonals `P = adj(D) + s1^2 alpha`, `ds = s1 hn d`,
//! `W = hn^2 (adj(D) + s1^2 d)` and `C0 = d1 d2 d3 + s1^2 alpha^2` (`den = det L^T`). Then
//! `m . N = sum P_i m_i^2` and `m x N = m x (P m) - |m|^2 (ds m) + m sum ds_i m_i^2`, so
//!
//! `m' - m = (dd N - hn^2 m sum P_i m_i^2 + hn (j - s1) (m x N)) / den`:
//!
//! about 100 flops and one division, every product of two quantities of the input and no
//! 3x3 solve, so the chain from `m` to `m'` is about ten operations deep (the solve's was
//! about thirty-five). Each term is computed to relative accuracy: `dd = O(h^2)` is formed
//! once without cancellation (crate::mv's `Track`), and `m x (P m)` has components
//! `m_j m_k (P_k - P_j)` with `P_k - P_j = d_i (j_j^2 - j_k^2)` formed once (so do
//! `(ds m) x m`'s): both cross products cost three products of the pairs `m_j m_k`.
//!
//! The coefficients use the trajectory's anchored `alpha`, not the input's own: the two
//! differ by round-off, which the step's invariant correction removes. At large
//! `h |Omega|` that stops being harmless (a round-off change of `s1`'s invariants is
//! amplified from step to step), which is why `Mv` runs this map only while
//! `|s1 - sum j| <= 1e-2 sum j` and tracks `s1` otherwise.

use crate::linalg::Vec3;
use crate::real::{c, sq, Real};

/// The coefficients of the free-running map for one trajectory, one `h` and one body.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrozenMap<T> {
    p: Vec3<T>,
    ds: Vec3<T>,
    w: Vec3<T>,
    c0: T,
    dd: Vec3<T>,
    /// `hn (j - s1)`.
    hjs: Vec3<T>,
    /// `(P_z - P_y, P_x - P_z, P_y - P_x)`, formed as `d_x (j_y^2 - j_z^2)` and so on
    /// (`P = adj(D) + s1^2 alpha` and `d_i - d_k = j_i^2 - j_k^2`): `m x (P m)` is then
    /// `(m_y m_z, m_x m_z, m_x m_y)` times these, with no cancellation between nearly equal
    /// products when two moments are close.
    p_diff: Vec3<T>,
    /// `(ds_y - ds_z, ds_z - ds_x, ds_x - ds_y) = s1 hn (j_y^2 - j_z^2, ...)`, for
    /// `(ds m) x m` alike.
    ds_diff: Vec3<T>,
    /// `hn^2`.
    hn2: T,
}

impl<T: Real> FrozenMap<T> {
    /// The coefficients for the scaled body `j` (with `c0_i = j_i^2 + s2_0` and
    /// `s0 = sum j`), the tracked `delta = s1 - s0`, the scaled step `hn` and the anchored
    /// `alpha = |hn m|^2`; `None` where the map would amplify round-off (below).
    ///
    /// The map is built for the anchored `alpha`, and between two holds its input's `|m|^2`
    /// is off by a few ulps; the solve it replaces is isospectral for any input, the map is
    /// not, and it turns that error into an increment error through `d_i = c0_i + e`, which
    /// moves by `-alpha / 2` per unit of relative error in `alpha`. Where some `|d_i|` is
    /// small against `alpha` (a needle, `J = (0.995, 0.005, 0.005)`, turning about a
    /// transverse axis at `h |m|` near `sqrt(J_max J_min)`) that is amplified step after
    /// step: `|m|^2` came out 44 % off after 3000 steps at `h |Omega| = 0.1`, or blew up to
    /// `1e104` in 88, every step `Ok` (found in review). Over 521 random needle trajectories
    /// every one with `alpha / min |d_i|` below 1.42 held round-off and the failures started
    /// there (some held up to 4.6): the map is refused above 0.5, and the trajectory solves.
    #[inline(never)]
    pub(crate) fn new(j: Vec3<T>, c0: Vec3<T>, s0: T, delta: T, hn: T, alpha: T) -> Option<Self> {
        Self::with_limit(j, c0, s0, delta, hn, alpha, 0.5)
    }

    /// [`FrozenMap::new`] refusing the map where `alpha > limit * min |d_i|` (tests build
    /// the map where `new` refuses it, to check the step's own guard).
    #[inline(always)]
    pub(crate) fn with_limit(
        j: Vec3<T>,
        c0: Vec3<T>,
        s0: T,
        delta: T,
        hn: T,
        alpha: T,
        limit: f64,
    ) -> Option<Self> {
        let s1 = s0 + delta;
        // e = s2 - s2_0 - alpha, with s2 - s2_0 = s0 delta + (delta^2 + alpha) / 2
        let e = s0 * delta + (sq(delta) - alpha) * c::<T>(0.5);
        let d = Vec3::new(c0.x + e, c0.y + e, c0.z + e);
        let d_min = d.x.abs().min(d.y.abs()).min(d.z.abs());
        if !(alpha <= c::<T>(limit) * d_min) {
            return None;
        }
        let adj = Vec3::new(d.y * d.z, d.x * d.z, d.x * d.y);
        let s1sq = sq(s1);
        let s1a = s1sq * alpha;
        let hn2 = sq(hn);
        // differences of squares as products: exact up to the two roundings
        let j2_diff = Vec3::new(
            (j.y - j.z) * (j.y + j.z),
            (j.z - j.x) * (j.z + j.x),
            (j.x - j.y) * (j.x + j.y),
        );
        let s1hn = s1 * hn;
        Some(Self {
            p_diff: d.mul_elem(j2_diff),
            ds_diff: j2_diff.scale(s1hn),
            p: Vec3::new(adj.x + s1a, adj.y + s1a, adj.z + s1a),
            ds: d.scale(s1hn),
            w: adj.add(d.scale(s1sq)).scale(hn2),
            c0: d.x * adj.x + s1a * alpha,
            dd: Vec3::new(delta * j.x - e, delta * j.y - e, delta * j.z - e),
            hjs: Vec3::new((j.x - s1) * hn, (j.y - s1) * hn, (j.z - s1) * hn),
            hn2,
        })
    }

    /// `(m' - m) * scale` for the input `m`; not finite for a momentum so large that its cube
    /// overflows (the caller checks `m'` and then solves with its scaling instead).
    #[inline(always)]
    pub(crate) fn increment(&self, m: Vec3<T>, scale: T) -> Vec3<T> {
        let m2 = m.mul_elem(m);
        let msq = m2.x + m2.y + m2.z;
        // (m_y m_z, m_x m_z, m_x m_y): both cross products below are these times constants
        let pairs = Vec3::new(m.y * m.z, m.x * m.z, m.x * m.y);
        let pm = self.p.mul_elem(m);
        let dm = self.ds.mul_elem(m);
        let n = pm.sub(pairs.mul_elem(self.ds_diff));
        let pmm = self.p.dot(m2);
        let dmm = self.ds.dot(m2);
        let den = self.c0 + self.w.dot(m2);
        let m_x_n = pairs
            .mul_elem(self.p_diff)
            .sub(dm.scale(msq))
            .add(m.scale(dmm));
        let sum = self
            .dd
            .mul_elem(n)
            .sub(m.scale(self.hn2 * pmm))
            .add(self.hjs.mul_elem(m_x_n));
        sum.scale(scale / den)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_rng::Lcg;

    /// `x` solving the 3x3 system `a x = b` by Gaussian elimination with partial pivoting.
    #[allow(clippy::needless_range_loop)]
    fn solve(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> [f64; 3] {
        for col in 0..3 {
            let piv = (col..3)
                .max_by(|&i, &k| a[i][col].abs().total_cmp(&a[k][col].abs()))
                .unwrap();
            a.swap(col, piv);
            b.swap(col, piv);
            for row in col + 1..3 {
                let f = a[row][col] / a[col][col];
                for k in col..3 {
                    a[row][k] -= f * a[col][k];
                }
                b[row] -= f * b[col];
            }
        }
        let mut x = [0.0; 3];
        for row in (0..3).rev() {
            let mut s = b[row];
            for k in row + 1..3 {
                s -= a[row][k] * x[k];
            }
            x[row] = s / a[row][row];
        }
        x
    }

    /// The rational map against the matrices it was derived from: `L^T` and `Delta` written
    /// out entry by entry (crate::mv's module docs), `L^T y = m` by elimination, `Delta y`.
    /// The identity holds for any `delta` and `hn` once `alpha = |hn m|^2`.
    #[test]
    fn rational_map_equals_the_solve_it_replaces() {
        let mut rng = Lcg(7);
        let mut worst = 0.0f64;
        let mut compared = 0;
        for _ in 0..2000 {
            let j = [
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
            ];
            let m = [
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
            ];
            let hn = rng.range(-0.3, 0.3);
            let delta = rng.range(-0.05, 0.05);
            let u = [hn * m[0], hn * m[1], hn * m[2]];
            let alpha = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
            let s0 = j[0] + j[1] + j[2];
            let s2_0 = j[0] * j[1] + j[0] * j[2] + j[1] * j[2];
            let s1 = s0 + delta;
            let e = s0 * delta + (delta * delta - alpha) / 2.0;
            let d: [f64; 3] = core::array::from_fn(|i| j[i] * j[i] + s2_0 + e);
            // hat(u) = [[0, -u2, u1], [u2, 0, -u0], [-u1, u0, 0]]
            let hat = [[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]];
            let mut lt = [[0.0; 3]; 3];
            let mut big_delta = [[0.0; 3]; 3];
            for r in 0..3 {
                for k in 0..3 {
                    let diag = if r == k { 1.0 } else { 0.0 };
                    lt[r][k] = u[r] * u[k] + diag * d[r] + s1 * hat[r][k];
                    big_delta[r][k] =
                        diag * (delta * j[r] - e) - u[r] * u[k] + (j[r] - s1) * hat[r][k];
                }
            }
            let y = solve(lt, m);
            let want: [f64; 3] =
                core::array::from_fn(|r| (0..3).map(|k| big_delta[r][k] * y[k]).sum());
            let c0 = Vec3::new(d[0] - e, d[1] - e, d[2] - e);
            let Some(map) = FrozenMap::new(Vec3::new(j[0], j[1], j[2]), c0, s0, delta, hn, alpha)
            else {
                continue;
            };
            let got = map.increment(Vec3::new(m[0], m[1], m[2]), 1.0).to_array();
            let scale = want.iter().map(|x| x.abs()).fold(0.0, f64::max).max(1e-300);
            let cond = lt.iter().flatten().map(|x| x.abs()).fold(0.0, f64::max);
            let err = (0..3).map(|i| (got[i] - want[i]).abs()).fold(0.0, f64::max) / scale;
            // the elimination's own error grows with the system's condition
            if cond < 10.0 {
                worst = worst.max(err);
                compared += 1;
            }
        }
        // the refusal (alpha > min |d_i| / 2) must leave most of the draws to compare
        assert!(compared > 1000, "only {compared} of 2000 draws compared");
        assert!(worst < 1e-11, "worst relative difference {worst:e}");
    }
}
