//! The public scenes' reference constants (docs/MATH.md §8): the one definition, used by the
//! library's tests (`tests/common`), its benches (`benches/steps.rs`) and the lab
//! (`lab/src/scenes.rs`), each through `#[path]` (none of them can depend on another).
#![allow(dead_code)]
// the references keep every digit the high-precision solver gave
#![allow(clippy::excessive_precision, clippy::unreadable_literal)]

/// The talk's case: mass matrix `J`.
pub const TALK_J: [f64; 3] = [0.9218, 0.7382, 0.1763];
/// The talk's case: principal moments `I_i = J_j + J_k`.
pub const TALK_I: [f64; 3] = [0.9145, 1.0981, 1.66];
/// The talk's case: initial body momentum.
pub const TALK_M0: [f64; 3] = [0.4165, 0.9072, 0.0588];
/// Reference `m(1)` of the talk's case (docs/MATH.md §8, independent high precision).
pub const TALK_M1: [f64; 3] = [
    0.40963676823852457273,
    0.91216486689156377454,
    -0.0097213021655047406612,
];
/// Reference `m(10)` of the talk's case.
pub const TALK_M10: [f64; 3] = [
    0.82717281856790628525,
    -0.096647426825883589630,
    -0.55352139354352065378,
];
/// Reference `m(100)` of the talk's case.
pub const TALK_M100: [f64; 3] = [
    0.66653809997201721994,
    0.62577581339461293974,
    0.40505940632949599801,
];
/// Existence limit of the DMV step at the talk's initial state (docs/MATH.md §3).
pub const TALK_MAX_STEP: f64 = 1.060273597;

/// Hairer–Vilmart's driver case: principal moments.
pub const HV_I: [f64; 3] = [0.6, 0.8, 1.0];
/// Hairer–Vilmart's driver case: initial momentum.
pub const HV_M0: [f64; 3] = [1.8, 0.4, -0.9];

/// Reference attitude q(10) of the talk's case from q0 = 1 (mpmath, lab/refs/refs.json).
pub const TALK_Q10: [f64; 4] = [
    0.05848376704928084885,
    -0.7688612700282374779,
    -0.5298928566545770041,
    0.35305177652681915446,
];
/// Reference `m(10)` of Hairer–Vilmart's driver case from `q0 = 1`.
pub const HV_M10: [f64; 3] = [
    1.76596250851820753572,
    -0.6954641970330891194,
    0.77955498148187108610,
];
/// Reference `q(10)` of Hairer–Vilmart's driver case from `q0 = 1`.
pub const HV_Q10: [f64; 4] = [
    -0.7360613641607939361,
    -0.5707869512403507332,
    -0.2993885718307900937,
    -0.2068390861046731924,
];
