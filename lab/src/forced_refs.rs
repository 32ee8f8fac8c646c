//! The high-precision references of the forced scenes, `lab/refs/forced_refs.json` (made by
//! `lab/refs/make_forced_refs.py`: a 10-stage Gauss–Legendre collocation at 45 digits with a
//! Richardson check, cross-checked by mpmath's Taylor `odefun` at 40 digits; see the script's
//! docstring and `lab/refs/forced_refs.txt` for the agreement).
//!
//! Equations (src/forced.rs): `m' = m x Omega + tau(t, q)`, `Omega = I^-1 (m - h_r)`,
//! `q' = 1/2 q (x) (0, Omega)`, with the torques of `rigid3::torque` (written from their
//! definitions in the script, not from the Rust code).

use crate::forced_methods::ForceSpec;
use serde::Deserialize;

/// The scenes of the file, in file order.
pub const FORCED_REF_SCENES: [&str; 6] = [
    "heavy_top",
    "lagrange_top",
    "gravity_gradient",
    "body_torque",
    "gyrostat",
    "satellite",
];

/// One forced scene: body, initial state, forcing and the reference states at the listed times.
#[derive(Clone, Debug)]
pub struct ForcedRef {
    /// Scene name (see [`FORCED_REF_SCENES`]).
    pub name: String,
    /// Principal moments of inertia.
    pub inertia: [f64; 3],
    /// Initial momentum.
    pub m0: [f64; 3],
    /// Initial attitude `(w, x, y, z)` (unit to 40 digits before rounding to f64).
    pub q0: [f64; 4],
    /// Torques and rotor.
    pub spec: ForceSpec,
    /// Reference times.
    pub t: Vec<f64>,
    /// Reference momenta at `t`.
    pub m: Vec<[f64; 3]>,
    /// Reference attitudes at `t`.
    pub q: Vec<[f64; 4]>,
}

#[derive(Deserialize)]
struct Raw {
    scenes: Vec<RawScene>,
}

#[derive(Deserialize)]
struct RawGravity {
    mg: String,
    com: Vec<String>,
}

#[derive(Deserialize)]
struct RawGradient {
    k: String,
    n: String,
}

#[derive(Deserialize)]
struct RawPeriodic {
    amplitude: Vec<String>,
    freq: Vec<String>,
    phase: Vec<String>,
}

#[derive(Deserialize)]
struct RawForcing {
    rotor: Option<Vec<String>>,
    gravity: Option<RawGravity>,
    gravity_gradient: Option<RawGradient>,
    body_torque: Option<RawPeriodic>,
}

#[derive(Deserialize)]
struct RawScene {
    name: String,
    inertia: Vec<String>,
    m0: Vec<String>,
    q0: Vec<String>,
    forcing: RawForcing,
    t: Vec<f64>,
    m: Vec<Vec<String>>,
    q: Vec<Vec<String>>,
}

fn num(s: &str) -> f64 {
    s.parse().unwrap_or(f64::NAN)
}

fn nums<const N: usize>(v: &[String]) -> [f64; N] {
    let mut out = [f64::NAN; N];
    if v.len() == N {
        for (o, s) in out.iter_mut().zip(v) {
            *o = num(s);
        }
    }
    out
}

fn spec(f: &RawForcing) -> ForceSpec {
    ForceSpec {
        rotor: f.rotor.as_deref().map(nums),
        gravity: f.gravity.as_ref().map(|g| (num(&g.mg), nums(&g.com))),
        gravity_gradient: f.gravity_gradient.as_ref().map(|g| (num(&g.k), num(&g.n))),
        body_torque: f
            .body_torque
            .as_ref()
            .map(|p| (nums(&p.amplitude), nums(&p.freq), nums(&p.phase))),
    }
}

/// All scenes of the stored reference file.
pub fn scenes() -> Vec<ForcedRef> {
    let raw: Raw = serde_json::from_str(include_str!("../refs/forced_refs.json"))
        .expect("forced_refs.json parses");
    raw.scenes
        .into_iter()
        .map(|s| ForcedRef {
            spec: spec(&s.forcing),
            name: s.name,
            inertia: nums(&s.inertia),
            m0: nums(&s.m0),
            q0: nums(&s.q0),
            t: s.t,
            m: s.m.iter().map(|v| nums(v)).collect(),
            q: s.q.iter().map(|v| nums(v)).collect(),
        })
        .collect()
}

/// The scene called `name`.
pub fn scene(name: &str) -> Option<ForcedRef> {
    scenes().into_iter().find(|s| s.name == name)
}

impl ForcedRef {
    /// The body in any `Real`.
    pub fn body<T: rigid3::Real>(&self) -> rigid3::Body<T> {
        rigid3::Body::from_inertia(self.inertia.map(T::from_f64))
            .expect("reference scenes are valid bodies")
    }

    /// The initial state in any `Real`.
    pub fn state0<T: rigid3::Real>(&self) -> rigid3::State<T> {
        rigid3::State::new(self.m0.map(T::from_f64), self.q0.map(T::from_f64))
    }

    /// Index of reference time `t`.
    pub fn at(&self, t: f64) -> Option<usize> {
        self.t.iter().position(|&x| x == t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forced_methods::make_forced;

    fn qdist(a: [f64; 4], b: [f64; 4]) -> f64 {
        let d: f64 = (0..4).map(|k| (a[k] - b[k]).powi(2)).sum();
        let s: f64 = (0..4).map(|k| (a[k] + b[k]).powi(2)).sum();
        d.min(s).sqrt()
    }

    #[test]
    fn every_scene_is_there_with_its_forcing() {
        let all = scenes();
        let names: Vec<&str> = all.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, FORCED_REF_SCENES);
        for s in &all {
            assert!(s.at(1.0).is_some() && s.at(10.0).is_some(), "{}", s.name);
            assert_eq!(s.m.len(), s.t.len());
            assert_eq!(s.q.len(), s.t.len());
            let finite = s
                .inertia
                .iter()
                .chain(&s.m0)
                .chain(&s.q0)
                .all(|x| x.is_finite());
            assert!(finite, "{}", s.name);
            for q in &s.q {
                let n: f64 = q.iter().map(|x| x * x).sum();
                assert!((n - 1.0).abs() < 1e-15, "{}", s.name);
            }
        }
        let top = scene("heavy_top").unwrap();
        assert_eq!(top.spec.gravity, Some((1.0, [0.2, -0.1, 0.5])));
        assert_eq!(
            scene("satellite").unwrap().spec.rotor,
            Some([0.0, 0.3, 0.0])
        );
        assert_eq!(
            scene("body_torque").unwrap().spec.body_torque,
            Some(([0.1, -0.05, 0.08], [1.3, 0.7, 2.1], [0.0, 0.5, 1.0]))
        );
    }

    #[test]
    fn heavy_top_and_gyrostat_references_keep_their_invariants() {
        for name in ["heavy_top", "lagrange_top", "gyrostat"] {
            let s = scene(name).unwrap();
            let e0 = s
                .spec
                .total_energy(s.inertia, 0.0, s.m0, s.q0)
                .expect("conservative");
            let p0 = rigid3::State::new(s.m0, s.q0).spatial_momentum();
            for (i, (&m, &q)) in s.m.iter().zip(&s.q).enumerate() {
                let e = s.spec.total_energy(s.inertia, s.t[i], m, q).unwrap();
                assert!(
                    (e - e0).abs() <= 1e-14 * e0.abs().max(1.0),
                    "{name}: {e} {e0}"
                );
                let p = rigid3::State::new(m, q).spatial_momentum();
                assert!((p[2] - p0[2]).abs() <= 1e-14, "{name}: {p:?} {p0:?}");
                if name == "gyrostat" {
                    for k in 0..3 {
                        assert!((p[k] - p0[k]).abs() <= 1e-14, "{name}: {p:?} {p0:?}");
                    }
                }
            }
        }
    }

    /// In a gravity gradient the potential turns about `e_z` at the orbit rate `N`, so
    /// `H - N e_z . R(q) m` is conserved: the references keep it to round-off, so the
    /// torque integrated is the one of the potential rigid3 reports (same sign, same frame).
    #[test]
    fn gravity_gradient_references_keep_the_jacobi_integral() {
        for name in ["gravity_gradient", "satellite"] {
            let s = scene(name).unwrap();
            let n = s.spec.gravity_gradient.unwrap().1;
            let jacobi = |t: f64, m: [f64; 3], q: [f64; 4]| {
                let p = rigid3::State::new(m, q).spatial_momentum();
                s.spec.total_energy(s.inertia, t, m, q).unwrap() - n * p[2]
            };
            let j0 = jacobi(0.0, s.m0, s.q0);
            for (i, (&m, &q)) in s.m.iter().zip(&s.q).enumerate() {
                let j = jacobi(s.t[i], m, q);
                assert!(
                    (j - j0).abs() <= 1e-14 * j0.abs().max(1.0),
                    "{name}: {j} {j0}"
                );
            }
        }
    }

    /// The references and rigid3 agree on every convention (frames, signs, the torques'
    /// definitions): the order-6 composition at `h = 1/256` lands on them at `t = 10`
    /// (measured: at most 6.0e-13, the satellite's momentum; a wrong sign or frame would be
    /// off by O(1)).
    #[test]
    fn forced6_at_a_fine_step_lands_on_the_references() {
        let h = 1.0 / 256.0;
        for s in scenes() {
            let mut a = make_forced("forced6", s.body::<f64>(), h, &s.spec).unwrap();
            let mut st = s.state0::<f64>();
            let i = s.at(10.0).unwrap();
            for _ in 0..2560 {
                a.step_state(&mut st).unwrap();
            }
            let r = s.m[i];
            let dm = (0..3).map(|k| (st.m[k] - r[k]).abs()).fold(0.0, f64::max);
            let dq = qdist(st.q, s.q[i]);
            println!(
                "{}: forced6 h = 1/256 at t = 10: |dm| {dm:.1e}, |dq| {dq:.1e}",
                s.name
            );
            assert!(dm.max(dq) <= 1e-11, "{}: {dm:e} {dq:e}", s.name);
        }
    }
}
