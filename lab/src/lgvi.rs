//! The Lie group variational integrator of Lee, Leok and McClamroch (Comput. Methods Appl.
//! Mech. Engrg. 196 (2007) 2907, §3; "Lie group variational integrators for the full body
//! problem"), solved as they solve it: Newton's method on a three-parameter chart of the
//! step's rotation. The lab's independent oracle for `rigid3::Forced<Mv>`, which claims to be
//! the same map solved in closed form.
//!
//! One step from `(Pi_k, R_k)` at time `t_k`, `M_k = tau(t_k, R_k)` the body torque:
//!
//! `h S(Pi_k + h/2 M_k) = F J_d - J_d F^T`,   `J_d = tr(J)/2 I - J`,
//! `R_k+1 = R_k F`,   `Pi_k+1 = F^T (Pi_k + h/2 M_k) + h/2 M_k+1`,
//!
//! `J = diag(I)` the standard inertia, `J_d` rigid3's mass matrix, `S = hat`. In rigid3's
//! conventions (`q` body to space, `R_k+1 = R_k F` is `q_k+1 = q_k (x) quat(F)`) this is
//! docs/MATH.md §2's DMV equation for the kicked momentum. For any `F = I + a S(f) + b S(f)^2`
//! the implicit equation reads `h g = a J f + b f x J f`, `g = Pi_k + h/2 M_k`:
//!
//! - Cayley (the default): `F = (I + S(c)) (I - S(c))^-1`, `a = b = 2 / (1 + |c|^2)`, i.e.
//!   the polynomial equation `G(c) = 2 (J c + c x J c) - (1 + |c|^2) h g = 0`, Jacobian
//!   `2 (J + S(c) J - S(J c)) - 2 h g c^T`; `quat(F) = (1, c) / sqrt(1 + |c|^2)`.
//! - exponential coordinates (their eq. (22)): `F = exp(S(f))`, `theta = |f|`,
//!   `a = sin theta / theta`, `b = (1 - cos theta) / theta^2` (the derivatives of the two
//!   scalar functions by their series below `theta = 1e-3`).
//!
//! Newton starts from the first-order solution (`c = h J^-1 g / 2`, `f = h J^-1 g`), solves
//! each 3x3 system by Gaussian elimination with partial pivoting, and stops when the update is
//! at most `1e-15` times the iterate; after [`MAX_NEWTON`] iterations, or on a singular
//! Jacobian or a non-finite iterate, the step returns an [`LgviError`] and leaves the state
//! untouched. Only rigid3's `Body`, `State` and `Torque` are used: no part of its DMV solution.

use rigid3::{Body, State, Torque};

/// Newton iterations after which a step gives up.
pub const MAX_NEWTON: u32 = 30;

/// Newton stops when the update is at most this times the iterate.
pub const NEWTON_TOL: f64 = 1e-15;

/// The chart of the step's rotation Newton iterates on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Coordinates {
    /// The Cayley vector `c`, `F = (I + S(c)) (I - S(c))^-1`: a polynomial equation.
    #[default]
    Cayley,
    /// The rotation vector `f`, `F = exp(S(f))` (Lee–Leok–McClamroch's eq. (22)).
    Exponential,
}

/// Why an LGVI step was not taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LgviError {
    /// Newton's update was still above the tolerance after [`MAX_NEWTON`] iterations.
    NoConvergence {
        /// The last update relative to the iterate.
        last_update: f64,
    },
    /// A Newton Jacobian was singular.
    Singular,
    /// A non-finite state, torque or iterate.
    NonFinite,
}

impl core::fmt::Display for LgviError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::NoConvergence { last_update } => write!(
                f,
                "Newton did not converge in {MAX_NEWTON} iterations (last relative update {last_update:e})"
            ),
            Self::Singular => write!(f, "singular Newton Jacobian"),
            Self::NonFinite => write!(f, "non-finite state, torque or iterate"),
        }
    }
}

impl std::error::Error for LgviError {}

/// The LGVI of the heavy body (no rotor) in f64.
#[derive(Clone, Debug)]
pub struct Lgvi<F> {
    inertia: [f64; 3],
    h: f64,
    t: f64,
    torque: F,
    coordinates: Coordinates,
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
    /// An LGVI for `body` with step `h` under `torque`, starting at `t = 0`, Newton on the
    /// Cayley vector.
    pub fn new(body: &Body<f64>, h: f64, torque: F) -> Self {
        Self::with_coordinates(body, h, torque, Coordinates::Cayley)
    }

    /// The same with Newton on the given chart.
    pub fn with_coordinates(body: &Body<f64>, h: f64, torque: F, coordinates: Coordinates) -> Self {
        Self {
            inertia: body.inertia(),
            h,
            t: 0.0,
            torque,
            coordinates,
            iterations: 0,
        }
    }

    /// Newton on `G`, whose value and Jacobian at `x` are `residual(x)`, from `x`.
    fn newton(
        &mut self,
        mut x: V3,
        residual: impl Fn(V3) -> (V3, [[f64; 3]; 3]),
    ) -> Result<V3, LgviError> {
        let mut last_update = f64::INFINITY;
        for k in 1..=MAX_NEWTON {
            let (g, d) = residual(x);
            let step = solve3(d, g).ok_or(LgviError::Singular)?;
            x = [x[0] - step[0], x[1] - step[1], x[2] - step[2]];
            if !x.iter().all(|v| v.is_finite()) {
                return Err(LgviError::NonFinite);
            }
            let nx = norm(x);
            if norm(step) <= NEWTON_TOL * nx + f64::MIN_POSITIVE {
                self.iterations = k;
                return Ok(x);
            }
            last_update = norm(step) / nx;
        }
        Err(LgviError::NoConvergence { last_update })
    }

    /// The quaternion of `F` with `h g = vee(F J_d - J_d F^T)`, by Newton in the chosen chart.
    fn step_rotation(&mut self, hg: V3) -> Result<[f64; 4], LgviError> {
        let i = self.inertia;
        match self.coordinates {
            Coordinates::Cayley => {
                let c0 = [0, 1, 2].map(|r| 0.5 * hg[r] / i[r]);
                let c = self.newton(c0, |c| {
                    let jc = [i[0] * c[0], i[1] * c[1], i[2] * c[2]];
                    let cxjc = cross(c, jc);
                    let n1 = 1.0 + c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
                    let g = [0, 1, 2].map(|r| 2.0 * (jc[r] + cxjc[r]) - n1 * hg[r]);
                    // dG = 2 (J + S(c) J - S(J c)) - 2 (h g) c^T
                    let (sc, sjc) = (skew(c), skew(jc));
                    let mut d = [[0.0; 3]; 3];
                    for r in 0..3 {
                        for k in 0..3 {
                            d[r][k] = 2.0 * (sc[r][k] * i[k] - sjc[r][k]) - 2.0 * hg[r] * c[k];
                        }
                        d[r][r] += 2.0 * i[r];
                    }
                    (g, d)
                })?;
                let n = (1.0 + c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
                Ok([1.0 / n, c[0] / n, c[1] / n, c[2] / n])
            }
            Coordinates::Exponential => {
                let f0 = [0, 1, 2].map(|r| hg[r] / i[r]);
                let f = self.newton(f0, |f| {
                    let t = norm(f);
                    let (a, b, da, db) = scalars(t);
                    let jf = [i[0] * f[0], i[1] * f[1], i[2] * f[2]];
                    let fxjf = cross(f, jf);
                    let g = [0, 1, 2].map(|r| a * jf[r] + b * fxjf[r] - hg[r]);
                    // dG = a J + b (S(f) J - S(J f)) + da (J f) f^T + db (f x J f) f^T
                    let (sf, sjf) = (skew(f), skew(jf));
                    let mut d = [[0.0; 3]; 3];
                    for r in 0..3 {
                        for k in 0..3 {
                            d[r][k] = b * (sf[r][k] * i[k] - sjf[r][k])
                                + da * jf[r] * f[k]
                                + db * fxjf[r] * f[k];
                        }
                        d[r][r] += a * i[r];
                    }
                    (g, d)
                })?;
                let theta = norm(f);
                let (sh, ch) = (0.5 * theta).sin_cos();
                let axis = if theta > 0.0 {
                    f.map(|x| x / theta)
                } else {
                    [0.0; 3]
                };
                Ok([ch, sh * axis[0], sh * axis[1], sh * axis[2]])
            }
        }
    }

    /// One step.
    ///
    /// # Errors
    ///
    /// [`LgviError`] when Newton does not converge, meets a singular Jacobian or a non-finite
    /// value; the state and the time are then untouched.
    pub fn step(&mut self, s: &mut State<f64>) -> Result<(), LgviError> {
        let h = self.h;
        let m_k = self.torque.torque(self.t, &s.q);
        let g = [0, 1, 2].map(|r| s.m[r] + 0.5 * h * m_k[r]);
        if !g.iter().chain(&s.q).all(|x| x.is_finite()) {
            return Err(LgviError::NonFinite);
        }
        let p = self.step_rotation(g.map(|x| h * x))?;
        let q = qmul(s.q, p);
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        let q = q.map(|x| x / n);
        let t1 = self.t + h;
        let m_next_torque = self.torque.torque(t1, &q);
        // F^T g = R(p)^T g
        let fg = unrotate(p, g);
        let m = [0, 1, 2].map(|r| fg[r] + 0.5 * h * m_next_torque[r]);
        if !m.iter().all(|x| x.is_finite()) {
            return Err(LgviError::NonFinite);
        }
        s.m = m;
        s.q = q;
        self.t = t1;
        Ok(())
    }
}

fn skew(v: V3) -> [[f64; 3]; 3] {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}
