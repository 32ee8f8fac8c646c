//! The high-precision references of `lab/refs/refs.json` (made by `lab/refs/make_refs.py`
//! with mpmath's Taylor integrator at 40 digits, cross-checked by an independent 60-digit
//! Taylor integrator: see the script's docstring).

use serde::Deserialize;

/// One scene: body, initial state and the reference states at the listed times.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Scene name (`talk`, `hv`, `symmetric_top`, ...).
    pub name: String,
    /// Principal moments of inertia.
    pub inertia: [f64; 3],
    /// The mass matrix, when the scene is given by it (the talk's case).
    pub mass_matrix: Option<[f64; 3]>,
    /// Initial momentum.
    pub m0: [f64; 3],
    /// Initial attitude.
    pub q0: [f64; 4],
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
struct RawScene {
    name: String,
    inertia: Vec<String>,
    #[serde(rename = "mass_matrix_J")]
    mass_matrix: Option<Vec<String>>,
    m0: Vec<String>,
    q0: Vec<String>,
    t: Vec<f64>,
    m: Vec<Vec<String>>,
    q: Vec<Vec<String>>,
}

fn nums<const N: usize>(v: &[String]) -> [f64; N] {
    let mut out = [0.0; N];
    for (o, s) in out.iter_mut().zip(v) {
        *o = s.parse().unwrap_or(f64::NAN);
    }
    out
}

/// All scenes of the stored reference file.
pub fn scenes() -> Vec<Scene> {
    let raw: Raw =
        serde_json::from_str(include_str!("../refs/refs.json")).expect("refs.json parses");
    raw.scenes
        .into_iter()
        .map(|s| Scene {
            name: s.name,
            inertia: nums(&s.inertia),
            mass_matrix: s.mass_matrix.as_deref().map(nums),
            m0: nums(&s.m0),
            q0: nums(&s.q0),
            t: s.t,
            m: s.m.iter().map(|v| nums(v)).collect(),
            q: s.q.iter().map(|v| nums(v)).collect(),
        })
        .collect()
}

/// The scene called `name`.
pub fn scene(name: &str) -> Option<Scene> {
    scenes().into_iter().find(|s| s.name == name)
}

impl Scene {
    /// The body in any `Real` (from the mass matrix when given, so the talk's J is exact).
    pub fn body<T: rigid3::Real>(&self) -> rigid3::Body<T> {
        let b = match self.mass_matrix {
            Some(j) => rigid3::Body::from_mass_matrix(j.map(T::from_f64)),
            None => rigid3::Body::from_inertia(self.inertia.map(T::from_f64)),
        };
        b.expect("reference scenes are valid bodies")
    }

    /// Index of reference time `t`.
    pub fn at(&self, t: f64) -> Option<usize> {
        self.t.iter().position(|&x| x == t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_agree_with_math_md_and_keep_the_invariants() {
        let talk = scene("talk").unwrap();
        let m10 = talk.m[talk.at(10.0).unwrap()];
        assert!((m10[0] - 0.827_172_818_567_906_3).abs() < 1e-16);
        for s in scenes() {
            let b = s.body::<f64>();
            let (c0, e0) = (b.casimir(&s.m0), b.energy(&s.m0));
            let p0 = rigid3::State::new(s.m0, s.q0).spatial_momentum();
            for (m, q) in s.m.iter().zip(&s.q) {
                assert!(
                    (b.casimir(m) - c0).abs() <= 1e-15 * c0.max(1.0),
                    "{}",
                    s.name
                );
                assert!(
                    (b.energy(m) - e0).abs() <= 1e-15 * e0.max(1.0),
                    "{}",
                    s.name
                );
                let p = rigid3::State::new(*m, *q).spatial_momentum();
                for k in 0..3 {
                    assert!(
                        (p[k] - p0[k]).abs() <= 1e-14 * c0.sqrt().max(1.0),
                        "{}",
                        s.name
                    );
                }
            }
        }
    }
}
