//! `Mv::step_with_jacobian` and `PreMv::step_with_jacobian` against independent oracles:
//! forward-mode dual numbers (a `Real` written here, six tangent directions at once, run
//! through the generic step of a fresh integrator) and Richardson-extrapolated central
//! differences of the f64 step.

// index loops over 6x6 matrices read as the math does
#![allow(clippy::needless_range_loop)]

mod common;

use common::Rng;
use core::cmp::Ordering;
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};
use rigid3::{Body, Integrator, Mv, PreMv, Real, State};

const N: usize = 6;

/// `v + sum d_i eps_i` with `eps_i eps_j = 0`.
#[derive(Clone, Copy, Debug)]
struct Dual {
    v: f64,
    d: [f64; N],
}

impl Dual {
    fn constant(v: f64) -> Self {
        Dual { v, d: [0.0; N] }
    }
    fn var(v: f64, i: usize) -> Self {
        let mut d = [0.0; N];
        d[i] = 1.0;
        Dual { v, d }
    }
    /// `f(self)` with `f'(v) = df`.
    fn chain(self, v: f64, df: f64) -> Self {
        Dual {
            v,
            d: self.d.map(|x| x * df),
        }
    }
}

impl PartialEq for Dual {
    fn eq(&self, o: &Self) -> bool {
        self.v == o.v
    }
}
impl PartialOrd for Dual {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        self.v.partial_cmp(&o.v)
    }
}
impl Add for Dual {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        let mut d = self.d;
        for (a, b) in d.iter_mut().zip(o.d) {
            *a += b;
        }
        Dual { v: self.v + o.v, d }
    }
}
impl Sub for Dual {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        self + (-o)
    }
}
impl Neg for Dual {
    type Output = Self;
    fn neg(self) -> Self {
        Dual {
            v: -self.v,
            d: self.d.map(|x| -x),
        }
    }
}
impl Mul for Dual {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let mut d = [0.0; N];
        for (i, x) in d.iter_mut().enumerate() {
            *x = self.d[i] * o.v + self.v * o.d[i];
        }
        Dual { v: self.v * o.v, d }
    }
}
impl Div for Dual {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        let v = self.v / o.v;
        let mut d = [0.0; N];
        for (i, x) in d.iter_mut().enumerate() {
            *x = (self.d[i] - v * o.d[i]) / o.v;
        }
        Dual { v, d }
    }
}
impl AddAssign for Dual {
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}
impl SubAssign for Dual {
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}
impl MulAssign for Dual {
    fn mul_assign(&mut self, o: Self) {
        *self = *self * o;
    }
}

impl Real for Dual {
    const EPSILON: Self = Dual {
        v: f64::EPSILON,
        d: [0.0; N],
    };
    const MIN_POSITIVE: Self = Dual {
        v: f64::MIN_POSITIVE,
        d: [0.0; N],
    };
    const MAX: Self = Dual {
        v: f64::MAX,
        d: [0.0; N],
    };
    const ZERO: Self = Dual {
        v: 0.0,
        d: [0.0; N],
    };
    const ONE: Self = Dual {
        v: 1.0,
        d: [0.0; N],
    };
    fn from_f64(x: f64) -> Self {
        Dual::constant(x)
    }
    fn to_f64(self) -> f64 {
        self.v
    }
    fn sqrt(self) -> Self {
        let r = self.v.sqrt();
        self.chain(r, if r > 0.0 { 0.5 / r } else { 0.0 })
    }
    fn abs(self) -> Self {
        if self.v < 0.0 {
            -self
        } else {
            self
        }
    }
    fn sin(self) -> Self {
        self.chain(self.v.sin(), self.v.cos())
    }
    fn cos(self) -> Self {
        self.chain(self.v.cos(), -self.v.sin())
    }
    fn acos(self) -> Self {
        self.chain(self.v.acos(), -1.0 / (1.0 - self.v * self.v).sqrt())
    }
    fn atan2(self, x: Self) -> Self {
        let r2 = self.v * self.v + x.v * x.v;
        let mut d = [0.0; N];
        for (i, o) in d.iter_mut().enumerate() {
            *o = (x.v * self.d[i] - self.v * x.d[i]) / r2;
        }
        Dual {
            v: self.v.atan2(x.v),
            d,
        }
    }
    fn cbrt(self) -> Self {
        let r = self.v.cbrt();
        self.chain(r, if r != 0.0 { 1.0 / (3.0 * r * r) } else { 0.0 })
    }
    fn ln(self) -> Self {
        self.chain(self.v.ln(), 1.0 / self.v)
    }
    fn exp(self) -> Self {
        let e = self.v.exp();
        self.chain(e, e)
    }
    fn is_finite(self) -> bool {
        self.v.is_finite() && self.d.iter().all(|x| x.is_finite())
    }
}

fn qmul<T: Real>(a: [T; 4], b: [T; 4]) -> [T; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

fn conj<T: Real>(q: [T; 4]) -> [T; 4] {
    [q[0], -q[1], -q[2], -q[3]]
}

/// The body-frame attitude error of `q` relative to the unit `q_ref`: `2 vec(q_ref^* q / |q|)`
/// with the sign that makes the scalar part positive (first order in the error).
fn attitude_error<T: Real>(q_ref: [T; 4], q: [T; 4]) -> [T; 3] {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let q = q.map(|x| x / n);
    let r = qmul(conj(q_ref), q);
    let two = T::from_f64(if r[0] < T::ZERO { -2.0 } else { 2.0 });
    [r[1] * two, r[2] * two, r[3] * two]
}

/// `exp(dtheta / 2)` to first order and normalised: exact in the dual part.
fn turned<T: Real>(q: [T; 4], dtheta: [T; 3]) -> [T; 4] {
    let half = T::from_f64(0.5);
    let (a, b, c) = (dtheta[0] * half, dtheta[1] * half, dtheta[2] * half);
    let n2 = a * a + b * b + c * c;
    let w = if n2 == T::ZERO {
        T::ONE
    } else {
        (T::ONE - n2).sqrt()
    };
    qmul(q, [w, a, b, c])
}

#[derive(Clone, Copy)]
enum Method {
    Mv,
    Pre(u8),
}

/// One fresh step of `method` in any precision.
fn fresh_step<T: Real>(
    method: Method,
    inertia: [f64; 3],
    h: f64,
    s: State<T>,
) -> Result<State<T>, rigid3::StepError> {
    let body = Body::from_inertia(inertia.map(T::from_f64)).unwrap();
    let mut s = s;
    match method {
        Method::Mv => Mv::new(body, T::from_f64(h)).step_state(&mut s)?,
        Method::Pre(order) => PreMv::new(body, T::from_f64(h), order)?.step_state(&mut s)?,
    }
    Ok(s)
}

/// The Jacobian by dual numbers: all six directions in one step.
fn dual_jacobian(method: Method, inertia: [f64; 3], h: f64, s: &State<f64>) -> [[f64; 6]; 6] {
    let m = [0, 1, 2].map(|i| Dual::var(s.m[i], i));
    let q = turned(
        s.q.map(Dual::constant),
        [3, 4, 5].map(|i| Dual::var(0.0, i)),
    );
    let out = fresh_step(method, inertia, h, State::new(m, q)).unwrap();
    let q_ref = out.q.map(|x| Dual::constant(x.v));
    let dq = attitude_error(q_ref, out.q);
    let mut f = [[0.0; 6]; 6];
    for j in 0..6 {
        for i in 0..3 {
            f[i][j] = out.m[i].d[j];
            f[i + 3][j] = dq[i].d[j];
        }
    }
    f
}

/// The Jacobian by central differences at `eps` and `eps / 2`, Richardson-extrapolated
/// (truncation `O(eps^4)`).
fn fd_jacobian(method: Method, inertia: [f64; 3], h: f64, s: &State<f64>) -> [[f64; 6]; 6] {
    let base = fresh_step(method, inertia, h, *s).unwrap();
    let eval = |j: usize, e: f64| -> [f64; 6] {
        let mut m = s.m;
        let mut dth = [0.0; 3];
        if j < 3 {
            m[j] += e;
        } else {
            dth[j - 3] = e;
        }
        let q = turned(s.q, dth);
        let out = fresh_step(method, inertia, h, State::new(m, q)).unwrap();
        let d = attitude_error(base.q, out.q);
        [out.m[0], out.m[1], out.m[2], d[0], d[1], d[2]]
    };
    let mut f = [[0.0; 6]; 6];
    let eps = 1e-3;
    for j in 0..6 {
        let central = |e: f64| {
            let (p, n) = (eval(j, e), eval(j, -e));
            [0, 1, 2, 3, 4, 5].map(|i| (p[i] - n[i]) / (2.0 * e))
        };
        let (d1, d2) = (central(eps), central(eps / 2.0));
        for i in 0..6 {
            f[i][j] = (4.0 * d2[i] - d1[i]) / 3.0;
        }
    }
    f
}

fn analytic(
    method: Method,
    inertia: [f64; 3],
    h: f64,
    s: &State<f64>,
    warm: usize,
) -> (State<f64>, State<f64>, [[f64; 6]; 6]) {
    let body = Body::from_inertia(inertia).unwrap();
    // `warm` ordinary steps first: the Jacobian of an integrator along its trajectory (with
    // its tracking data and invariant anchors) is that of the same map; returns the state the
    // Jacobian was taken at, the state after and the Jacobian
    let mut x = *s;
    match method {
        Method::Mv => {
            let mut a = Mv::new(body, h);
            for _ in 0..warm {
                a.step_state(&mut x).unwrap();
            }
            let before = x;
            let f = a.step_with_jacobian(&mut x).unwrap();
            (before, x, f)
        }
        Method::Pre(order) => {
            let mut a = PreMv::new(body, h, order).unwrap();
            for _ in 0..warm {
                a.step_state(&mut x).unwrap();
            }
            let before = x;
            let f = a.step_with_jacobian(&mut x).unwrap();
            (before, x, f)
        }
    }
}

fn max_diff(a: &[[f64; 6]; 6], b: &[[f64; 6]; 6]) -> (f64, f64) {
    let mut d = 0.0f64;
    let mut scale = 0.0f64;
    for i in 0..6 {
        for j in 0..6 {
            d = d.max((a[i][j] - b[i][j]).abs());
            scale = scale.max(b[i][j].abs());
        }
    }
    (d, scale)
}

/// A random valid body, momentum, attitude and step (a fraction of the existence limit).
fn scene(rng: &mut Rng) -> ([f64; 3], State<f64>, f64) {
    let j = [
        rng.range(0.05, 1.0),
        rng.range(0.05, 1.0),
        rng.range(0.05, 1.0),
    ];
    let inertia = [j[1] + j[2], j[0] + j[2], j[0] + j[1]];
    let dir = rng.direction();
    let r = rng.range(0.3, 3.0);
    let m = dir.map(|x| x * r);
    let q = [
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    ];
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    let q = q.map(|x| x / n);
    let body = Body::from_inertia(inertia).unwrap();
    let hmax = Mv::max_step(&body, &m).min(1e3);
    // |Omega| h up to about one radian, and below 0.9 of the existence limit
    let w = body.angular_velocity(&m);
    let wn = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    let h = rng.range(0.01, 0.9) * hmax.min(1.0 / wn);
    (inertia, State::new(m, q), h)
}

#[test]
fn mv_and_pre_mv_jacobians_match_dual_numbers_on_1000_random_states() {
    let mut rng = Rng::new(0x1313);
    let orders = [2u8, 4, 6, 8, 10];
    let (mut worst_mv, mut worst_pre) = (0.0f64, 0.0f64);
    let mut pre_done = 0;
    for k in 0..1000 {
        let (inertia, s, h) = scene(&mut rng);
        let warm = k % 3;
        // Mv
        let (s, after, f) = analytic(Method::Mv, inertia, h, &s, warm);
        let fresh = fresh_step(Method::Mv, inertia, h, s).unwrap();
        for i in 0..3 {
            assert!((after.m[i] - fresh.m[i]).abs() <= 1e-13 * (1.0 + fresh.m[i].abs()));
        }
        let oracle = dual_jacobian(Method::Mv, inertia, h, &s);
        let (d, scale) = max_diff(&f, &oracle);
        let rel = d / scale.max(1.0);
        worst_mv = worst_mv.max(rel);
        assert!(rel <= 1e-10, "Mv state {k}: {d:e} (scale {scale:e}), h {h}");
        // PreMv at a smaller step (its modified body must exist)
        let method = Method::Pre(orders[k % 5]);
        let hp = 0.3 * h;
        if fresh_step(method, inertia, hp, s).is_err() {
            continue;
        }
        let (s, _, f) = analytic(method, inertia, hp, &s, warm);
        let oracle = dual_jacobian(method, inertia, hp, &s);
        let (d, scale) = max_diff(&f, &oracle);
        let rel = d / scale.max(1.0);
        worst_pre = worst_pre.max(rel);
        pre_done += 1;
        assert!(
            rel <= 1e-10,
            "PreMv state {k}: {d:e} (scale {scale:e}), h {hp}"
        );
    }
    println!(
        "max |F - F_dual| / max(1, |F|): Mv {worst_mv:.2e}, PreMv {worst_pre:.2e} ({pre_done} states)"
    );
    assert!(pre_done > 900);
}

#[test]
fn jacobians_match_richardson_central_differences() {
    let mut rng = Rng::new(0x005e_ed13);
    let mut worst = 0.0f64;
    for k in 0..100 {
        let (inertia, s, h) = scene(&mut rng);
        let method = if k % 2 == 0 {
            Method::Mv
        } else {
            Method::Pre(4 + 2 * ((k / 2) % 4) as u8)
        };
        let h = if k % 2 == 0 { h } else { 0.3 * h };
        if fresh_step(method, inertia, h, s).is_err() {
            continue;
        }
        let (_, _, f) = analytic(method, inertia, h, &s, 0);
        let oracle = fd_jacobian(method, inertia, h, &s);
        let (d, scale) = max_diff(&f, &oracle);
        let rel = d / scale.max(1.0);
        worst = worst.max(rel);
        assert!(rel <= 1e-7, "state {k}: {d:e}");
    }
    println!("max |F - F_fd| / max(1, |F|): {worst:.2e}");
}

#[test]
fn jacobian_step_is_the_plain_step_and_keeps_the_state_on_error() {
    let body = Body::<f64>::from_mass_matrix([0.9218, 0.7382, 0.1763]).unwrap();
    let s0 = State::new([0.4165, 0.9072, 0.0588], [1.0, 0.0, 0.0, 0.0]);
    let (mut a, mut b) = (Mv::new(body, 0.1), Mv::new(body, 0.1));
    let (mut sa, mut sb) = (s0, s0);
    for _ in 0..50 {
        a.step_state(&mut sa).unwrap();
        b.step_with_jacobian(&mut sb).unwrap();
        assert_eq!(sa, sb);
    }
    let (mut a, mut b) = (
        PreMv::new(body, 0.1, 6).unwrap(),
        PreMv::new(body, 0.1, 6).unwrap(),
    );
    let (mut sa, mut sb) = (s0, s0);
    for _ in 0..50 {
        a.step_state(&mut sa).unwrap();
        b.step_with_jacobian(&mut sb).unwrap();
        assert_eq!(sa, sb);
    }
    // too large a step: Err, state untouched
    let h = 1.01 * Mv::max_step(&body, &s0.m);
    let mut s = s0;
    assert!(Mv::new(body, h).step_with_jacobian(&mut s).is_err());
    assert_eq!(s, s0);
    let nan = State::new([f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]);
    let zero_q = State::new([1.0, 0.0, 0.0], [0.0; 4]);
    for bad in [nan, zero_q] {
        let mut s = bad;
        let e = Some(rigid3::StepError::NonFinite);
        assert_eq!(Mv::new(body, 0.1).step_with_jacobian(&mut s).err(), e);
        for order in [2u8, 4, 10] {
            let mut pre = PreMv::new(body, 0.1, order).unwrap();
            assert_eq!(pre.step_with_jacobian(&mut s).err(), e);
        }
        assert_eq!(s.m[1..], bad.m[1..]);
    }
    let mut s = s0;
    let e = Some(rigid3::StepError::NonFinite);
    assert_eq!(Mv::new(body, f64::NAN).step_with_jacobian(&mut s).err(), e);
    let mut pre = PreMv::new(body, f64::INFINITY, 6).unwrap();
    assert_eq!(pre.step_with_jacobian(&mut s).err(), e);
    assert_eq!(s, s0);
}

#[test]
fn f32_jacobian_is_the_f64_one_to_single_precision() {
    let mut rng = Rng::new(32);
    for _ in 0..200 {
        let (inertia, s, h) = scene(&mut rng);
        let (_, _, f64_jac) = analytic(Method::Mv, inertia, h, &s, 0);
        let body = Body::<f32>::from_inertia(inertia.map(|x| x as f32)).unwrap();
        let mut x = State::new(s.m.map(|v| v as f32), s.q.map(|v| v as f32));
        let f = Mv::new(body, h as f32).step_with_jacobian(&mut x).unwrap();
        let f = f.map(|r| r.map(f64::from));
        let (d, scale) = max_diff(&f, &f64_jac);
        assert!(d <= 2e-4 * scale.max(1.0), "{d:e} (scale {scale:e})");
    }
}
