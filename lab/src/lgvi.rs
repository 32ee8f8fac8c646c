//! The Lie group variational integrator of Lee, Leok and McClamroch (Comput. Methods Appl.
//! Mech. Engrg. 196 (2007) 2907, §3; "Lie group variational integrators for the full body
//! problem"), solved as they solve it: Newton's method on the exponential coordinates of the
//! step's rotation. The lab's independent oracle for `rigid3::Forced<Mv>`, which claims to be
//! the same map solved in closed form.
//!
//! One step from `(Pi_k, R_k)` at time `t_k`, `M_k = tau(t_k, R_k)` the body torque:
//!
//! `h S(Pi_k + h/2 M_k) = F J_d - J_d F^T`,   `J_d = tr(J)/2 I - J`,
//! `R_k+1 = R_k F`,   `Pi_k+1 = F^T (Pi_k + h/2 M_k) + h/2 M_k+1`.
//!
//! With `F = exp(S(f))`, `theta = |f|`, the implicit equation is (their eq. (22))
//!
//! `h g = (sin theta / theta) J f + ((1 - cos theta) / theta^2) f x J f`,  `g = Pi_k + h/2 M_k`,
//!
//! `J = diag(I)` the standard inertia. Newton from `f = h J^-1 g`, the Jacobian written out
//! (the derivatives of the two scalar functions by their series below `theta = 1e-3`), stopped
//! when the update is below `1e-15 |f|`; at most 30 iterations. Only rigid3's `Body`, `State`
//! and `Torque` are used: no part of its DMV solution.

use rigid3::{Body, State, Torque};

/// Newton iterations after which a step gives up.
pub const MAX_NEWTON: u32 = 30;

/// The LGVI of the heavy body (no rotor) in f64.
#[derive(Clone, Debug)]
pub struct Lgvi<F> {
    inertia: [f64; 3],
    h: f64,
    t: f64,
    torque: F,
    /// Newton iterations of the last step.
    pub iterations: u32,
}

type V3 = [f64; 3];

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: V3) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// `x` with `A x = b` by Gaussian elimination with partial pivoting.
fn solve3(mut a: [[f64; 3]; 3], mut b: V3) -> Option<V3> {
    for col in 0..3 {
        let p = (col..3).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[p][col] == 0.0 {
            return None;
        }
        a.swap(col, p);
        b.swap(col, p);
        for r in col + 1..3 {
            let f = a[r][col] / a[col][col];
            for c in col..3 {
                a[r][c] -= f * a[col][c];
            }
            b[r] -= f * b[col];
        }
    }
    let mut x = [0.0; 3];
    for r in (0..3).rev() {
        let s: f64 = (r + 1..3).map(|c| a[r][c] * x[c]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    Some(x)
}

/// `(sin t / t, (1 - cos t) / t^2, (d/dt (sin t / t)) / t, (d/dt ((1 - cos t) / t^2)) / t)`.
fn scalars(t: f64) -> (f64, f64, f64, f64) {
    let t2 = t * t;
    if t < 1e-3 {
        (
            1.0 - t2 / 6.0 + t2 * t2 / 120.0,
            0.5 - t2 / 24.0 + t2 * t2 / 720.0,
            -1.0 / 3.0 + t2 / 30.0,
            -1.0 / 12.0 + t2 / 180.0,
        )
    } else {
        let (s, c) = t.sin_cos();
        let half = (0.5 * t).sin();
        let b = 2.0 * half * half / t2;
        (
            s / t,
            b,
            (t * c - s) / (t2 * t),
            (t * s - 2.0 * (1.0 - c)) / (t2 * t2),
        )
    }
}

/// `R(q)^T v`.
fn unrotate(q: [f64; 4], v: V3) -> V3 {
    rotate([q[0], -q[1], -q[2], -q[3]], v)
}

/// `R(q) v = q (0, v) q*`.
fn rotate(q: [f64; 4], v: V3) -> V3 {
    let u = [q[1], q[2], q[3]];
    let t = cross(u, v).map(|x| 2.0 * x);
    let ut = cross(u, t);
    [
        v[0] + q[0] * t[0] + ut[0],
        v[1] + q[0] * t[1] + ut[1],
        v[2] + q[0] * t[2] + ut[2],
    ]
}

fn qmul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

impl<F: Torque<f64>> Lgvi<F> {
    /// An LGVI for `body` with step `h` under `torque`, starting at `t = 0`.
    pub fn new(body: &Body<f64>, h: f64, torque: F) -> Self {
        Self {
            inertia: body.inertia(),
            h,
            t: 0.0,
            torque,
            iterations: 0,
        }
    }

    /// `f` with `h g = a(|f|) J f + b(|f|) f x J f`, by Newton; `None` if it does not converge.
    fn rotation_vector(&mut self, hg: V3) -> Option<V3> {
        let i = self.inertia;
        let mut f = [hg[0] / i[0], hg[1] / i[1], hg[2] / i[2]];
        for k in 1..=MAX_NEWTON {
            let t = norm(f);
            let (a, b, da, db) = scalars(t);
            let jf = [i[0] * f[0], i[1] * f[1], i[2] * f[2]];
            let fxjf = cross(f, jf);
            let g = [0, 1, 2].map(|r| a * jf[r] + b * fxjf[r] - hg[r]);
            // dG = a J + b (S(f) J - S(J f)) + da (J f) f^T + db (f x J f) f^T
            let mut d = [[0.0; 3]; 3];
            for r in 0..3 {
                for c in 0..3 {
                    // (S(f) J)_rc = S(f)_rc I_c ; S(J f)_rc
                    let sf = skew(f)[r][c] * i[c];
                    let sjf = skew(jf)[r][c];
                    d[r][c] = b * (sf - sjf) + da * jf[r] * f[c] + db * fxjf[r] * f[c];
                }
                d[r][r] += a * i[r];
            }
            let step = solve3(d, g)?;
            f = [f[0] - step[0], f[1] - step[1], f[2] - step[2]];
            if norm(step) <= 1e-15 * norm(f) + f64::MIN_POSITIVE {
                self.iterations = k;
                return Some(f);
            }
        }
        None
    }

    /// One step; `None` (state untouched) if Newton does not converge.
    pub fn step(&mut self, s: &mut State<f64>) -> Option<()> {
        let h = self.h;
        let m_k = self.torque.torque(self.t, &s.q);
        let g = [0, 1, 2].map(|r| s.m[r] + 0.5 * h * m_k[r]);
        let f = self.rotation_vector(g.map(|x| h * x))?;
        let theta = norm(f);
        let (sh, ch) = (0.5 * theta).sin_cos();
        let axis = if theta > 0.0 {
            f.map(|x| x / theta)
        } else {
            [0.0; 3]
        };
        let p = [ch, sh * axis[0], sh * axis[1], sh * axis[2]];
        let q = qmul(s.q, p);
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        let q = q.map(|x| x / n);
        let t1 = self.t + h;
        let m_next_torque = self.torque.torque(t1, &q);
        // F^T g = R(p)^T g
        let fg = unrotate(p, g);
        s.m = [0, 1, 2].map(|r| fg[r] + 0.5 * h * m_next_torque[r]);
        s.q = q;
        self.t = t1;
        Some(())
    }
}

fn skew(v: V3) -> [[f64; 3]; 3] {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}
