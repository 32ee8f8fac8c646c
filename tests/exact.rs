//! The exact solution against independent 34-digit references (lab/refs/refs.json, made by
//! lab/refs/make_refs.py with mpmath Taylor integration), and its invariants.

use rigid3::{Body, Exact, Integrator, State, StepError};

// ---- a minimal JSON reader (objects, arrays, strings, numbers, literals) -----------------

#[derive(Debug, Clone)]
enum Json {
    Obj(Vec<(String, Json)>),
    Arr(Vec<Json>),
    Str(String),
    Num(f64),
    Lit,
}

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
}

impl Parser<'_> {
    fn ws(&mut self) {
        while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
            self.i += 1;
        }
    }
    fn value(&mut self) -> Json {
        self.ws();
        match self.s[self.i] {
            b'{' => {
                self.i += 1;
                let mut v = Vec::new();
                loop {
                    self.ws();
                    if self.s[self.i] == b'}' {
                        self.i += 1;
                        return Json::Obj(v);
                    }
                    let Json::Str(k) = self.value() else {
                        panic!("key")
                    };
                    self.ws();
                    assert_eq!(self.s[self.i], b':');
                    self.i += 1;
                    let x = self.value();
                    v.push((k, x));
                    self.ws();
                    if self.s[self.i] == b',' {
                        self.i += 1;
                    }
                }
            }
            b'[' => {
                self.i += 1;
                let mut v = Vec::new();
                loop {
                    self.ws();
                    if self.s[self.i] == b']' {
                        self.i += 1;
                        return Json::Arr(v);
                    }
                    v.push(self.value());
                    self.ws();
                    if self.s[self.i] == b',' {
                        self.i += 1;
                    }
                }
            }
            b'"' => {
                self.i += 1;
                let start = self.i;
                while self.s[self.i] != b'"' {
                    self.i += 1;
                }
                let out = String::from_utf8(self.s[start..self.i].to_vec()).unwrap();
                self.i += 1;
                Json::Str(out)
            }
            b't' | b'f' | b'n' => {
                while self.i < self.s.len() && self.s[self.i].is_ascii_alphabetic() {
                    self.i += 1;
                }
                Json::Lit
            }
            _ => {
                let start = self.i;
                while self.i < self.s.len() && b"+-.eE0123456789".contains(&self.s[self.i]) {
                    self.i += 1;
                }
                let t = std::str::from_utf8(&self.s[start..self.i]).unwrap();
                Json::Num(t.parse().unwrap())
            }
        }
    }
}

impl Json {
    fn get(&self, key: &str) -> &Json {
        match self {
            Json::Obj(v) => &v.iter().find(|(k, _)| k == key).expect(key).1,
            _ => panic!("not an object"),
        }
    }
    fn arr(&self) -> &[Json] {
        match self {
            Json::Arr(v) => v,
            _ => panic!("not an array"),
        }
    }
    fn num(&self) -> f64 {
        match self {
            Json::Num(x) => *x,
            Json::Str(s) => s.parse().unwrap(),
            _ => panic!("not a number"),
        }
    }
    fn str(&self) -> &str {
        match self {
            Json::Str(s) => s,
            _ => panic!("not a string"),
        }
    }
    fn vec<const N: usize>(&self) -> [f64; N] {
        let a = self.arr();
        assert_eq!(a.len(), N);
        std::array::from_fn(|i| a[i].num())
    }
}

struct Scene {
    name: String,
    inertia: [f64; 3],
    mass_matrix: Option<[f64; 3]>,
    m0: [f64; 3],
    q0: [f64; 4],
    t: Vec<f64>,
    m: Vec<[f64; 3]>,
    q: Vec<[f64; 4]>,
}

fn scenes() -> Vec<Scene> {
    let text = include_str!("../lab/refs/refs.json");
    let root = Parser {
        s: text.as_bytes(),
        i: 0,
    }
    .value();
    root.get("scenes")
        .arr()
        .iter()
        .map(|s| Scene {
            name: s.get("name").str().to_string(),
            inertia: s.get("inertia").vec(),
            mass_matrix: match s {
                Json::Obj(v) => v
                    .iter()
                    .find(|(k, _)| k == "mass_matrix_J")
                    .map(|x| x.1.vec()),
                _ => None,
            },
            m0: s.get("m0").vec(),
            q0: s.get("q0").vec(),
            t: s.get("t").arr().iter().map(Json::num).collect(),
            m: s.get("m").arr().iter().map(Json::vec).collect(),
            q: s.get("q").arr().iter().map(Json::vec).collect(),
        })
        .collect()
}

fn body64(s: &Scene) -> Body<f64> {
    match s.mass_matrix {
        // the talk's case is defined by J (I_i = J_j + J_k)
        Some(j) => Body::from_mass_matrix(j).unwrap(),
        None => Body::from_inertia(s.inertia).unwrap(),
    }
}

fn body32(s: &Scene) -> Body<f32> {
    match s.mass_matrix {
        Some(j) => Body::from_mass_matrix(j.map(|x| x as f32)).unwrap(),
        None => Body::from_inertia(s.inertia.map(|x| x as f32)).unwrap(),
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn m_err(m: &[f64; 3], r: &[f64; 3]) -> f64 {
    norm(&[m[0] - r[0], m[1] - r[1], m[2] - r[2]]) / norm(r).max(1.0)
}

fn q_err(q: &[f64; 4], r: &[f64; 4]) -> f64 {
    let d: Vec<f64> = q.iter().zip(r).map(|(a, b)| a - b).collect();
    let s: Vec<f64> = q.iter().zip(r).map(|(a, b)| a + b).collect();
    norm(&d).min(norm(&s))
}

#[test]
fn matches_references_f64() {
    let mut worst = (0.0f64, 0.0f64);
    for s in scenes() {
        let body = body64(&s);
        let s0 = State::new(s.m0, s.q0);
        let (mut em, mut eq) = (0.0f64, 0.0f64);
        for (k, &t) in s.t.iter().enumerate() {
            let st = Exact::at(&body, &s0, t).unwrap();
            let mo = Exact::momentum_at(&body, &s.m0, t).unwrap();
            assert_eq!(mo, st.m);
            em = em.max(m_err(&st.m, &s.m[k]));
            eq = eq.max(q_err(&st.q, &s.q[k]));
        }
        println!(
            "{:16} f64: max |m err| {:.1e}  max |q err| {:.1e}",
            s.name, em, eq
        );
        assert!(em <= 1e-12, "{}: m error {em:e}", s.name);
        assert!(eq <= 1e-11, "{}: q error {eq:e}", s.name);
        worst = (worst.0.max(em), worst.1.max(eq));
    }
    println!("worst f64: m {:.1e} q {:.1e}", worst.0, worst.1);
}

/// The f32 tolerance: `1e-5`, widened in proportion to the rotation angle past 200 rad
/// (`|m| t / I_min`), because any f32 computation of a phase `phi` is off by about
/// `eps_f32 phi / 2` (the fast spinner turns by about 2000 rad by t = 100).
fn tol32(s: &Scene, t: f64) -> f64 {
    let imin = s.inertia.iter().cloned().fold(f64::MAX, f64::min);
    1e-5 * (norm(&s.m0) * t.abs() / imin / 200.0).max(1.0)
}

fn rounded64(s: &Scene) -> (Body<f64>, State<f64>) {
    let body = match s.mass_matrix {
        Some(j) => Body::from_mass_matrix(j.map(|x| x as f32 as f64)).unwrap(),
        None => Body::from_inertia(s.inertia.map(|x| x as f32 as f64)).unwrap(),
    };
    let st = State::new(s.m0.map(|x| x as f32 as f64), s.q0.map(|x| x as f32 as f64));
    (body, st)
}

#[test]
fn matches_references_f32() {
    for s in scenes() {
        let body = body32(&s);
        let s0 = State::new(s.m0.map(|x| x as f32), s.q0.map(|x| x as f32));
        let (b64, s064) = rounded64(&s);
        for (k, &t) in s.t.iter().enumerate() {
            let st = Exact::at(&body, &s0, t as f32).unwrap();
            let (m32, q32) = (st.m.map(f64::from), st.q.map(f64::from));
            let em = m_err(&m32, &s.m[k]);
            let eq = q_err(&q32, &s.q[k]);
            // the same f32-rounded inputs in f64: what f32 arithmetic alone costs
            let same = Exact::at(&b64, &s064, t).unwrap();
            let am = m_err(&m32, &same.m);
            let aq = q_err(&q32, &same.q);
            println!(
                "{:16} t={t:5} f32: vs ref m {em:.1e} q {eq:.1e} | vs f64 on f32 inputs m {am:.1e} q {aq:.1e}",
                s.name
            );
            let tol = tol32(&s, t);
            assert!(
                em <= tol && eq <= tol,
                "{} t={t}: {em:e} {eq:e} > {tol:e}",
                s.name
            );
            assert!(
                am <= tol && aq <= tol,
                "{} t={t}: {am:e} {aq:e} > {tol:e}",
                s.name
            );
        }
    }
}

// ---- an independent check: classical RK4 with a small step --------------------------------

fn rhs(i: &[f64; 3], y: &[f64; 7]) -> [f64; 7] {
    let (m, q) = ([y[0], y[1], y[2]], [y[3], y[4], y[5], y[6]]);
    let o = [m[0] / i[0], m[1] / i[1], m[2] / i[2]];
    let (w, x, yy, z) = (q[0], q[1], q[2], q[3]);
    // m x Omega with each component's difference of moments formed exactly (the two
    // products m_j m_k / I_k and m_k m_j / I_j cancel to round-off on a nearly symmetric body)
    let d = |a: f64, b: f64| (a - b) / (a * b);
    [
        m[1] * m[2] * d(i[1], i[2]),
        m[2] * m[0] * d(i[2], i[0]),
        m[0] * m[1] * d(i[0], i[1]),
        0.5 * (-x * o[0] - yy * o[1] - z * o[2]),
        0.5 * (w * o[0] + yy * o[2] - z * o[1]),
        0.5 * (w * o[1] + z * o[0] - x * o[2]),
        0.5 * (w * o[2] + x * o[1] - yy * o[0]),
    ]
}

fn rk4(i: [f64; 3], s0: &State<f64>, t: f64, n: usize) -> State<f64> {
    let mut y = [
        s0.m[0], s0.m[1], s0.m[2], s0.q[0], s0.q[1], s0.q[2], s0.q[3],
    ];
    let h = t / n as f64;
    let add =
        |a: &[f64; 7], b: &[f64; 7], s: f64| std::array::from_fn::<f64, 7, _>(|k| a[k] + s * b[k]);
    for _ in 0..n {
        let k1 = rhs(&i, &y);
        let k2 = rhs(&i, &add(&y, &k1, h / 2.0));
        let k3 = rhs(&i, &add(&y, &k2, h / 2.0));
        let k4 = rhs(&i, &add(&y, &k3, h));
        y = std::array::from_fn(|k| y[k] + h / 6.0 * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k]));
    }
    State::new([y[0], y[1], y[2]], [y[3], y[4], y[5], y[6]])
}

fn q_of(a: f64, b: f64, c: f64) -> [f64; 4] {
    let n = (1.0f64 + a * a + b * b + c * c).sqrt();
    [1.0 / n, a / n, b / n, c / n]
}

#[test]
fn special_cases_agree_with_rk4() {
    let q0 = q_of(0.3, -0.2, 0.5);
    let cases: &[([f64; 3], [f64; 3])] = &[
        // exactly on the separatrix: D_b evaluates to 0 (the k = 1, tanh/sech branch)
        ([2.0, 3.0, 4.0], [1.0, 0.5, std::f64::consts::SQRT_2]),
        ([2.0, 3.0, 4.0], [-1.0, 0.5, std::f64::consts::SQRT_2]), // other branches
        ([2.0, 3.0, 4.0], [1.0, -0.5, -std::f64::consts::SQRT_2]),
        ([2.0, 3.0, 4.0], [0.0, 1.3, 0.0]), // unstable equilibrium: middle axis
        ([2.0, 3.0, 4.0], [0.0, 0.0, -2.0]), // steady about the largest axis
        ([2.0, 3.0, 4.0], [0.8, 0.0, 0.0]), // steady about the smallest axis
        ([2.0, 2.0, 3.0], [0.3, -0.4, 0.9]), // symmetric (oblate)
        ([2.0, 3.0, 3.0], [0.3, -0.4, 0.9]), // symmetric (prolate)
        ([2.0, 2.0, 3.0], [0.3, -0.4, 0.0]), // symmetric, m in the equal plane
        ([1.2, 1.2, 1.2], [0.3, -0.4, 0.9]), // sphere
        ([3.0, 1.0, 2.0], [0.5, 0.6, -0.7]), // unsorted axes (odd permutation)
        ([2.0, 3.0, 1.0], [0.5, 0.6, -0.7]), // unsorted axes (even permutation)
        ([1.0, 2.0, 3.0], [0.0, 0.0, 0.0]), // m = 0
        ([1.0, 2.0, 3.0], [1e-9, 1.0, 1e-9]), // very near the middle axis
        ([1.0, 1.0 + 1e-9, 2.0], [0.6, 0.3, 0.2]), // nearly symmetric
    ];
    for (inertia, m0) in cases {
        let body = Body::from_inertia(*inertia).unwrap();
        let s0 = State::new(*m0, q0);
        for t in [0.7, -2.3, 6.0] {
            let ex = Exact::at(&body, &s0, t).unwrap();
            let rk = rk4(*inertia, &s0, t, 20000);
            let em = m_err(&ex.m, &rk.m);
            let eq = q_err(&ex.q, &rk.q);
            assert!(
                em < 1e-11 && eq < 1e-11,
                "{inertia:?} {m0:?} t={t}: {em:e} {eq:e}"
            );
        }
    }
}

#[test]
fn stepping_equals_at_and_conserves() {
    for s in scenes() {
        let body = body64(&s);
        let s0 = State::new(s.m0, s.q0);
        let mut ex = Exact::new(body, 0.1);
        let mut st = s0;
        let mut mo = s.m0;
        let pi0 = s0.spatial_momentum();
        let (e0, c0) = (body.energy(&s.m0), body.casimir(&s.m0));
        for _ in 0..100 {
            ex.step_state(&mut st).unwrap();
            ex.step(&mut mo).unwrap();
            let pi = st.spatial_momentum();
            let dpi = norm(&[pi[0] - pi0[0], pi[1] - pi0[1], pi[2] - pi0[2]]);
            assert!(dpi <= 1e-13 * norm(&pi0).max(1.0), "{} pi {dpi:e}", s.name);
            assert!(
                (body.energy(&st.m) - e0).abs() <= 1e-14 * e0.max(1.0),
                "{}",
                s.name
            );
            assert!(
                (body.casimir(&st.m) - c0).abs() <= 1e-14 * c0.max(1.0),
                "{}",
                s.name
            );
        }
        let at = Exact::at(&body, &s0, 10.0).unwrap();
        // same trajectory, n h = 100 x 0.1 vs 10: round-off of the time only
        assert!(m_err(&st.m, &at.m) < 1e-13, "{}", s.name);
        assert!(q_err(&st.q, &at.q) < 1e-13, "{}", s.name);
        assert_eq!(mo, st.m);
        // the quaternion is continuous in t: the same sign, not only the same rotation
        let d: f64 = st.q.iter().zip(&at.q).map(|(a, b)| (a - b).abs()).sum();
        assert!(d < 1e-12, "{}", s.name);
        // a changed state starts a new trajectory
        let mut moved = State::new([st.m[0] * 1.01, st.m[1], st.m[2]], st.q);
        let expect = Exact::at(&body, &moved, 0.1).unwrap();
        ex.step_state(&mut moved).unwrap();
        assert!(m_err(&moved.m, &expect.m) < 1e-15 && q_err(&moved.q, &expect.q) < 1e-15);
    }
}

#[test]
fn stepping_f32() {
    let body = Body::<f32>::from_mass_matrix([0.9218, 0.7382, 0.1763]).unwrap();
    let s0 = State::new([0.4165f32, 0.9072, 0.0588], [1.0, 0.0, 0.0, 0.0]);
    let mut ex = Exact::new(body, 0.1f32);
    let mut st = s0;
    for _ in 0..100 {
        ex.step_state(&mut st).unwrap();
    }
    let s = scenes().into_iter().find(|s| s.name == "talk").unwrap();
    let k = s.t.iter().position(|&t| t == 10.0).unwrap();
    assert!(m_err(&st.m.map(f64::from), &s.m[k]) < 1e-5);
    assert!(q_err(&st.q.map(f64::from), &s.q[k]) < 1e-5);
}

#[test]
fn backwards_inverts_forwards() {
    for s in scenes() {
        let body = body64(&s);
        let s0 = State::new(s.m0, s.q0);
        for t in [1.0, 10.0, 100.0] {
            let fwd = Exact::at(&body, &s0, t).unwrap();
            let back = Exact::at(&body, &fwd, -t).unwrap();
            let tol = 1e-13 * (1.0 + t);
            assert!(m_err(&back.m, &s0.m) < tol, "{} {t}", s.name);
            assert!(q_err(&back.q, &s0.q) < tol, "{} {t}", s.name);
        }
        let zero = Exact::at(&body, &s0, 0.0).unwrap();
        assert!(m_err(&zero.m, &s0.m) < 1e-15 && q_err(&zero.q, &s0.q) < 1e-15);
    }
}

#[test]
fn bad_inputs_are_refused() {
    let body = Body::from_inertia([1.0, 2.0, 3.0]).unwrap();
    let good = State::new([0.3, 0.4, 0.5], [1.0, 0.0, 0.0, 0.0]);
    let nan = f64::NAN;
    assert_eq!(Exact::at(&body, &good, nan), Err(StepError::NonFinite));
    assert_eq!(
        Exact::at(&body, &good, f64::INFINITY),
        Err(StepError::NonFinite)
    );
    let bad_m = State::new([nan, 0.4, 0.5], good.q);
    assert_eq!(Exact::at(&body, &bad_m, 1.0), Err(StepError::NonFinite));
    let bad_q = State::new(good.m, [0.0; 4]);
    assert_eq!(Exact::at(&body, &bad_q, 1.0), Err(StepError::NonFinite));
    assert_eq!(
        Exact::momentum_at(&body, &[0.1, f64::INFINITY, 0.0], 1.0),
        Err(StepError::NonFinite)
    );
    // a phase beyond 1 / eps periods: refused, not garbage
    assert!(Exact::at(&body, &good, 1e300).is_err());
    assert!(Exact::momentum_at(&body, &[1e300, 1e300, 1e300], 1e10).is_err());
    // the integrator leaves the state untouched on error
    let mut ex = Exact::new(body, nan);
    let mut st = good;
    assert!(ex.step_state(&mut st).is_err());
    assert_eq!(st, good);
    let mut m = [0.3, nan, 0.5];
    let mut ex = Exact::new(body, 0.1);
    assert!(ex.step(&mut m).is_err());
    assert!(m[1].is_nan() && m[0] == 0.3);
    // huge and tiny momenta are fine
    for scale in [1e-150, 1e150] {
        let m0 = [0.3 * scale, 0.4 * scale, 0.5 * scale];
        let m = Exact::momentum_at(&body, &m0, 1.0 / scale).unwrap();
        let r = Exact::momentum_at(&body, &[0.3, 0.4, 0.5], 1.0).unwrap();
        assert!((0..3).all(|k| (m[k] / scale - r[k]).abs() < 1e-14));
    }
}

/// Setting the step size it already has changes nothing, bit for bit (a loop that sets a
/// measured `dt` every tick; before, the cache was dropped and the next step differed by an
/// ulp, found in review). Also through `Composed` over `Exact` (the force-gradient splitting).
#[test]
fn the_same_step_size_set_again_changes_nothing() {
    /// The step after `set_step_size(0.01)` (the step it has) against a clone's without it.
    fn same_h_is_no_change<I: Integrator<f64> + Clone>(mut a: I) {
        let mut s = State::new([0.4165, 0.9072, 0.0588], [1.0, 0.0, 0.0, 0.0]);
        for _ in 0..5 {
            a.step_state(&mut s).unwrap();
        }
        let mut b = a.clone();
        b.set_step_size(0.01);
        let (mut sa, mut sb) = (s, s);
        a.step_state(&mut sa).unwrap();
        b.step_state(&mut sb).unwrap();
        assert_eq!(sa, sb);
    }
    let body = Body::<f64>::from_inertia([0.9145, 1.0981, 1.66]).unwrap();
    same_h_is_no_change(Exact::new(body, 0.01));
    let g = rigid3::Gravity {
        mg: 1.0,
        com: [0.0, 0.0, 0.1],
    };
    same_h_is_no_change(rigid3::Composed::force_gradient(Exact::new(body, 0.01), g).unwrap());
}

/// A step size that changes every step rebuilds the trajectory from the state each time:
/// `|q|` stays at round-off and the attitude with a fine RK4 (measured 1.1e-15 and 2.8e-11
/// rad). A first-use trial found a spacecraft tumbling at 5-6 rad a step, `h` alternating 1/60
/// and 1/50 s, growing `|q| - 1` 1.8x a step (this test on that code: 8.2e-4 and 5.1e-4 rad
/// off RK4 after 200 steps): each rebuilt trajectory took the last output's `|q|` as it was.
/// Oracles: unit length, and RK4 at 25000 steps per step of `Exact`.
#[test]
fn a_changing_step_keeps_the_attitude_unit_and_exact() {
    let i = [60.0, 95.0, 120.0];
    let body = Body::<f64>::from_inertia(i).unwrap();
    let q0 = [
        0.2598598862144856,
        -0.6826427302373264,
        0.16372937159837542,
        -0.6630719684415669,
    ];
    let n = norm(&q0);
    let s0 = State::new(
        [15188.351694666333, -12801.821570916065, -16268.652896356856],
        q0.map(|x| x / n),
    );
    let mut ex = Exact::new(body, 1.0 / 60.0);
    let mut s = s0;
    let (mut t, mut worst) = (0.0, 0.0f64);
    for k in 1..=200 {
        let h = if k % 2 == 0 { 1.0 / 60.0 } else { 1.0 / 50.0 };
        ex.set_step_size(h);
        ex.step_state(&mut s).unwrap();
        t += h;
        worst = worst.max((norm(&s.q) - 1.0).abs());
    }
    let r = rk4(i, &s0, t, 200 * 25_000);
    let (dq, dm) = (q_err(&s.q, &r.q), m_err(&s.m, &r.m));
    println!("Exact with h alternating 1/60, 1/50 s, 200 steps: |q| - 1 {worst:.1e}, attitude {dq:.1e}, momentum {dm:.1e} from RK4");
    assert!(worst <= 1e-14, "{worst:e}");
    assert!(dq <= 1e-9 && dm <= 1e-9, "{dq:e} {dm:e}");
}

/// Nearly symmetric bodies: the attitude's angle has a large part linear in time, which the
/// old evaluation took from the rounded phase and a rounded `R_J` and cancelled against the
/// exact one (found in review: `1e-3` off for `I = (1e-8, 2, 2 + 1 ulp)` at every `t`, `3e-4`
/// already at `t = 1e-6`; `1.6e-4` in f32 for `I = (1, 2, 2.0001)` at `t = 0.01`). Oracle:
/// RK4 at two step sizes (their difference bounds its own error), from the same inputs
/// (the f32 cases rounded to f32 first). Each case's worst error against the bound on it.
#[test]
fn nearly_symmetric_bodies_keep_their_attitude() {
    let ulp2 = 2.0 * f64::EPSILON;
    let q0 = {
        let q = [0.8, -0.1, 0.3, 0.5];
        let n = norm(&q);
        q.map(|x| x / n)
    };
    // (inertia, m0, times)
    let cases: &[([f64; 3], [f64; 3], &[f64])] = &[
        (
            [1e-8, 2.0, 2.0 + ulp2],
            [0.0, 0.9999499987499375, 0.01],
            &[1e-6, 1e-3, 1.0],
        ),
        (
            [1e-4, 2.0, 2.0 + ulp2],
            [1e-10, 0.9999499987, 1e-3],
            &[1.0, 10.0],
        ),
        ([0.1, 2.0, 2.0 + ulp2], [1e-10, 0.995, 0.1], &[1.0, 10.0]),
        ([1.0, 2.0, 2.0 + 1e-15], [0.0, 0.6, 0.8], &[7.0]),
        ([1.0, 2.0 - 1e-8, 2.0], [1e-5, 1.0, 1.0], &[3.0]),
        // about the smallest axis, nearly symmetric about it
        ([1.0, 1.0 + 1e-9, 2.0], [0.6, 0.3, 0.2], &[0.5, 6.0]),
        ([1.0, 1.0 + 4.0 * ulp2, 1.5], [0.9, 0.1, 0.05], &[2.0]),
    ];
    for &(inertia, m0, times) in cases {
        let body = Body::from_inertia(inertia).unwrap();
        let s0 = State::new(m0, q0);
        for &t in times {
            let ex = Exact::at(&body, &s0, t).unwrap();
            let n = ((t.abs() * 4000.0) as usize).max(200);
            // the stored body's moments (from its mass matrix: an ulp apart from the input's)
            let stored = body.inertia();
            let (fine, coarse) = (rk4(stored, &s0, t, 2 * n), rk4(stored, &s0, t, n));
            let own = q_err(&fine.q, &coarse.q).max(m_err(&fine.m, &coarse.m));
            let (eq, em) = (q_err(&ex.q, &fine.q), m_err(&ex.m, &fine.m));
            println!("{inertia:?} {m0:?} t = {t:e}: attitude {eq:.1e}, momentum {em:.1e} (RK4's own {own:.0e})");
            assert!(own <= 1e-13, "the oracle: {own:e}");
            assert!(
                eq <= 1e-12 && em <= 1e-12,
                "{inertia:?} {m0:?} t={t}: {eq:e} {em:e}"
            );
        }
    }
    // f32, from the f32-rounded inputs; the attitude within a few f32 ulps of one
    let f32_cases: &[([f32; 3], [f32; 3], &[f32])] = &[
        ([1.0, 2.0, 2.0001], [0.0, 0.99995, 0.01], &[0.01, 1.0, 10.0]),
        ([0.5, 1.0, 1.0001], [1e-4, 0.99995, 0.01], &[0.01, 1.0]),
        ([1.0, 1.0001, 1.5], [0.1, 0.995, 0.0], &[10.0]),
    ];
    let q32 = q0.map(|x| x as f32);
    for &(inertia, m0, times) in f32_cases {
        let body = Body::<f32>::from_inertia(inertia).unwrap();
        let s0 = State::new(m0, q32);
        let s64 = State::new(m0.map(f64::from), q32.map(f64::from));
        for &t in times {
            let ex = Exact::at(&body, &s0, t).unwrap();
            let n = ((t.abs() * 4000.0) as usize).max(200);
            let r = rk4(body.inertia().map(f64::from), &s64, f64::from(t), n);
            let eq = q_err(&ex.q.map(f64::from), &r.q);
            println!("f32 {inertia:?} {m0:?} t = {t:e}: attitude {eq:.1e}");
            assert!(eq <= 1e-6, "f32 {inertia:?} t={t}: {eq:e}");
        }
    }
}

/// Thin rods (one moment far below the others), against RK4 at two step sizes from the
/// stored body's moments, and against the rod's own sensitivity: the same solution from the
/// largest moment one ulp up.
#[test]
fn thin_rods_keep_their_attitude() {
    let q0 = q_of(0.3, -0.2, 0.5);
    let cases: &[([f64; 3], [f64; 3])] = &[
        ([1e-6, 1.0 - 1e-6, 1.0], [1e-7, 0.8, 0.6]),
        ([1e-6, 1.0 - 1e-12, 1.0], [0.0, 0.8, 0.6]),
        ([3e-6, 1.0, 1.0 + 2e-6], [2e-7, 0.6, -0.8]),
        ([1e-4, 0.99995, 1.0], [3e-5, 0.5, 0.5]),
    ];
    for &(inertia, m0) in cases {
        let body = Body::from_inertia(inertia).unwrap();
        let s0 = State::new(m0, q0);
        let t = 10.0;
        let ex = Exact::at(&body, &s0, t).unwrap();
        let stored = body.inertia();
        let n = 80_000;
        let (fine, coarse) = (rk4(stored, &s0, t, 2 * n), rk4(stored, &s0, t, n));
        let own = q_err(&fine.q, &coarse.q).max(m_err(&fine.m, &coarse.m));
        let mut up = inertia;
        up[2] = f64::from_bits(up[2].to_bits() + 1);
        let nudged = Exact::at(&Body::from_inertia(up).unwrap(), &s0, t).unwrap();
        let (ulp, ulp_m) = (q_err(&nudged.q, &ex.q), m_err(&nudged.m, &ex.m));
        let (eq, em) = (q_err(&ex.q, &fine.q), m_err(&ex.m, &fine.m));
        println!("rod {inertia:?} {m0:?} t = {t}: attitude {eq:.1e}, momentum {em:.1e} (RK4's own {own:.0e}; one ulp of I_max moves them {ulp:.0e}, {ulp_m:.0e})");
        assert!(own <= 1e-13, "the oracle: {own:e}");
        // within the rod's own sensitivity, or round-off
        assert!(
            eq <= ulp.max(1e-12) && em <= ulp_m.max(1e-12),
            "{inertia:?}: {eq:e} {em:e}"
        );
    }
}
