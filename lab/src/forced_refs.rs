//! The high-precision references of the forced scenes, `lab/refs/forced_refs.json`, made by
//! `lab/refs/make_forced_refs.py`: mpmath's Taylor solver (40 digits) and an 8-stage
//! Gauss–Legendre collocation of our own (60 digits), which must agree to 25 digits for the
//! file to be written (see the script's docstring and `forced_refs.txt`).

use crate::forced_methods::ForceSpec;
use crate::forced_work::ForcedScene;
use serde::Deserialize;

/// The scenes of the forced work-precision chart (figure 9, `forced-work`).
pub const CHARTED: [&str; 3] = ["heavy_top", "satellite", "gyrostat"];

/// Every forced scene with a reference.
pub const ALL: [&str; 6] = [
    "heavy_top",
    "lagrange_top",
    "gravity_gradient",
    "body_torque",
    "gyrostat",
    "satellite",
];

#[derive(Deserialize)]
struct Raw {
    scenes: Vec<RawScene>,
}

#[derive(Deserialize, Default)]
struct RawSpec {
    rotor: Option<Vec<String>>,
    gravity: Option<(String, Vec<String>)>,
    gravity_gradient: Option<(String, String)>,
    body_torque: Option<(Vec<String>, Vec<String>, Vec<String>)>,
}

#[derive(Deserialize)]
struct RawState {
    t: f64,
    m: Vec<String>,
    q: Vec<String>,
}

#[derive(Deserialize)]
struct RawScene {
    name: String,
    inertia: Vec<String>,
    m0: Vec<String>,
    q0: Vec<String>,
    spec: RawSpec,
    agreement_digits: f64,
    states: Vec<RawState>,
}

fn num(s: &str) -> f64 {
    s.parse().unwrap_or(f64::NAN)
}

fn nums<const N: usize>(v: &[String]) -> [f64; N] {
    let mut out = [f64::NAN; N];
    for (o, s) in out.iter_mut().zip(v) {
        *o = num(s);
    }
    out
}

fn spec(r: &RawSpec) -> ForceSpec {
    ForceSpec {
        rotor: r.rotor.as_deref().map(nums),
        gravity: r.gravity.as_ref().map(|(mg, c)| (num(mg), nums(c))),
        gravity_gradient: r.gravity_gradient.as_ref().map(|(k, n)| (num(k), num(n))),
        body_torque: r
            .body_torque
            .as_ref()
            .map(|(a, w, p)| (nums(a), nums(w), nums(p))),
    }
}

/// The agreement (digits) of the two reference integrators, per scene.
pub fn agreement() -> Vec<(String, f64)> {
    raw()
        .scenes
        .into_iter()
        .map(|s| (s.name, s.agreement_digits))
        .collect()
}

fn raw() -> Raw {
    serde_json::from_str(include_str!("../refs/forced_refs.json")).expect("forced_refs.json parses")
}

/// The scene `name` with its reference at `t_end` (1 or 10).
pub fn scene(name: &str, t_end: f64) -> Option<ForcedScene> {
    let s = raw().scenes.into_iter().find(|s| s.name == name)?;
    let st = s.states.iter().find(|st| st.t == t_end)?;
    Some(ForcedScene {
        name: s.name.clone(),
        inertia: nums(&s.inertia),
        m0: nums(&s.m0),
        q0: nums(&s.q0),
        spec: spec(&s.spec),
        t_end,
        m_ref: nums(&st.m),
        q_ref: nums(&st.q),
    })
}

/// The charted scenes at `T = 10`.
pub fn charted() -> Vec<ForcedScene> {
    CHARTED.iter().filter_map(|n| scene(n, 10.0)).collect()
}
