//! Turns raw bytes into bodies, states and steps for every integrator, and checks the one
//! promise that holds for any input: a step is `Ok` with finite values, or `Err` with the state
//! untouched; constructors are `Ok` with valid values or `Err`. A panic anywhere is a failure.
//! Shared by the libFuzzer targets (`cargo +nightly fuzz run steps`) and the stable smoke test
//! `tests/fuzz_smoke.rs`.

use rigid3::{
    Body, Exact, Integrator, Midpoint, Mv, PreMv, Real, RetimedMv, Rk4, SeedMv, Solver, Splitting,
    Splitting2, State, StepError,
};

/// Outcomes by kind: `Ok`, then the `StepError` variants, then any other.
pub const OUTCOMES: [&str; 7] = [
    "Ok",
    "NonFinite",
    "StepTooLarge",
    "NoConvergence",
    "Degenerate",
    "Overflow",
    "other",
];

/// Method names by selector (`method % 11`).
pub const METHODS: [&str; 11] = [
    "mv",
    "seed-mv",
    "pre-mv",
    "retimed-mv",
    "splitting",
    "splitting2",
    "midpoint",
    "midpoint-fp",
    "rk4",
    "exact",
    "mv x8",
];

/// Counts of outcomes, indexed like [`OUTCOMES`].
pub type Tally = [u32; 7];

/// The column of an outcome in a [`Tally`].
pub fn kind(r: &Result<(), StepError>) -> usize {
    match r {
        Ok(()) => 0,
        Err(StepError::NonFinite) => 1,
        Err(StepError::StepTooLarge) => 2,
        Err(StepError::NoConvergence) => 3,
        Err(StepError::Degenerate) => 4,
        Err(StepError::Overflow) => 5,
        Err(_) => 6,
    }
}

/// Reads numbers from the bytes: mode 0 takes raw bit patterns (NaN, infinities, subnormals,
/// extremes), otherwise a moderate value `i16 / 1000 * 10^(mode - 4)`.
pub struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Self { data, pos: 0 }
    }
    fn byte(&mut self) -> u8 {
        let b = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos += 1;
        b
    }
    pub fn number(&mut self) -> f64 {
        let mode = self.byte() % 9;
        if mode == 0 {
            let mut b = [0u8; 8];
            for x in &mut b {
                *x = self.byte();
            }
            f64::from_le_bytes(b)
        } else {
            let v = i16::from_le_bytes([self.byte(), self.byte()]) as f64 / 1000.0;
            v * 10f64.powi(mode as i32 - 4)
        }
    }
    pub fn pick(&mut self) -> u8 {
        self.byte()
    }
}

/// Bitwise equality (NaN equals NaN): "untouched" means not a bit changed.
pub fn same<T: Real>(a: &[T], b: &[T]) -> bool {
    a.iter()
        .zip(b.iter())
        .all(|(x, y)| x == y || (x != x && y != y))
}

fn run<T: Real, I: Integrator<T>>(mut a: I, m: [T; 3], q: [T; 4]) -> Tally {
    let mut tally = [0u32; 7];
    let mut mm = m;
    let r = a.step(&mut mm);
    tally[kind(&r)] += 1;
    match r {
        Ok(()) => assert!(
            mm.iter().all(|x| x.is_finite()),
            "non-finite momentum from Ok"
        ),
        Err(_) => assert!(same(&mm, &m), "state changed on Err"),
    }
    let s0 = State::new(m, q);
    let mut s = s0;
    let r = a.step_state(&mut s);
    tally[kind(&r)] += 1;
    match r {
        Ok(()) => assert!(
            s.m.iter().chain(s.q.iter()).all(|x| x.is_finite()),
            "non-finite state from Ok"
        ),
        Err(_) => assert!(
            same(&s.m, &s0.m) && same(&s.q, &s0.q),
            "state changed on Err"
        ),
    }
    tally
}

fn all<T: Real>(r: &mut Reader, method: u8) -> Option<Tally> {
    let c = |x: f64| T::from_f64(x);
    let i = [c(r.number()), c(r.number()), c(r.number())];
    // half the inputs through the mass matrix with |J|: most of those are valid bodies, so the
    // integrators (not only the validation) see most inputs
    let body = if r.pick() % 2 == 0 {
        Body::from_inertia(i)
    } else {
        Body::from_mass_matrix(i.map(|x| x.abs()))
    };
    let Ok(body) = body else { return None };
    for x in body.inertia().iter().chain(body.mass_matrix().iter()) {
        assert!(x.is_finite() && *x >= T::ZERO, "invalid body accepted");
    }
    let m = [c(r.number()), c(r.number()), c(r.number())];
    let q = [c(r.number()), c(r.number()), c(r.number()), c(r.number())];
    let h = c(r.number());
    let ms = Mv::max_step(&body, &m);
    assert!(!(ms < T::ZERO) && ms == ms, "max_step is NaN or negative");
    Some(match method % 11 {
        0 => run(Mv::new(body, h), m, q),
        1 => run(SeedMv::new(body, h), m, q),
        2 => run(PreMv::new(body, h, 4 + 2 * (r.pick() % 4)).ok()?, m, q),
        3 => run(RetimedMv::new(body, h, 2).ok()?, m, q),
        4 => run(Splitting::new(body, h), m, q),
        5 => run(Splitting2::new(body, h), m, q),
        6 => run(Midpoint::new(body, h), m, q),
        7 => run(Midpoint::with_solver(body, h, Solver::FixedPoint), m, q),
        8 => run(Rk4::new(body, h), m, q),
        9 => run(Exact::new(body, h), m, q),
        _ => {
            let mut a = Mv::new(body, h);
            let mut mm = m;
            // several steps: the tracking path after the first
            let mut tally = [0u32; 7];
            for _ in 0..8 {
                let r = a.step(&mut mm);
                tally[kind(&r)] += 1;
                if r.is_err() {
                    break;
                }
                assert!(mm.iter().all(|x| x.is_finite()));
            }
            tally
        }
    })
}

/// One input for the `steps` target: any method, f32 or f64. Returns the method selector and
/// the outcomes, or `None` when the bytes make no valid body (refused with a `BodyError`).
pub fn check_steps(data: &[u8]) -> Option<(usize, Tally)> {
    by_precision(data, METHODS.len(), all::<f64>, all::<f32>)
}

/// Reads the method selector and the precision from the first two bytes and runs the check
/// in f64 or f32; returns the method's index (`selector % methods`) and its outcomes.
pub fn by_precision(
    data: &[u8],
    methods: usize,
    in_f64: fn(&mut Reader, u8) -> Option<Tally>,
    in_f32: fn(&mut Reader, u8) -> Option<Tally>,
) -> Option<(usize, Tally)> {
    let mut r = Reader::new(data);
    let method = r.pick();
    let t = if r.pick() % 2 == 0 {
        in_f64(&mut r, method)
    } else {
        in_f32(&mut r, method)
    };
    t.map(|t| (method as usize % methods, t))
}

/// One input for the `inertia_tensor` target.
pub fn check_tensor(data: &[u8]) -> bool {
    let mut r = Reader::new(data);
    let mut t = [[0.0f64; 3]; 3];
    let symmetric = r.pick() % 4 != 0;
    for row in 0..3 {
        for col in 0..3 {
            t[row][col] = r.number();
        }
    }
    if symmetric {
        t[1][0] = t[0][1];
        t[2][0] = t[0][2];
        t[2][1] = t[1][2];
    }
    match Body::from_inertia_tensor(t) {
        Ok((b, q)) => {
            let i = b.inertia();
            assert!(
                i.iter().all(|x| x.is_finite() && *x > 0.0),
                "invalid moments accepted"
            );
            assert!(i[0] <= i[1] && i[1] <= i[2], "moments not ascending");
            let n = q.iter().map(|x| x * x).sum::<f64>();
            assert!(
                (n - 1.0).abs() < 1e-12 && q[0] >= 0.0,
                "frame not a unit quaternion with w >= 0"
            );
            true
        }
        Err(_) => false,
    }
}
