//! The public scenes of MATH.md §8 with their reference values.

/// The talk's case: mass matrix `J`.
pub const TALK_J: [f64; 3] = [0.9218, 0.7382, 0.1763];
/// The talk's case: initial body momentum.
pub const TALK_M0: [f64; 3] = [0.4165, 0.9072, 0.0588];
/// Reference `m(1)` of the talk's case (independent high precision).
pub const TALK_M1: [f64; 3] = [
    0.409_636_768_238_524_6,
    0.912_164_866_891_563_8,
    -0.009_721_302_165_504_741,
];
/// Reference `m(10)` of the talk's case.
pub const TALK_M10: [f64; 3] = [
    0.827_172_818_567_906_3,
    -0.096_647_426_825_883_59,
    -0.553_521_393_543_520_7,
];
/// Reference `m(100)` of the talk's case.
pub const TALK_M100: [f64; 3] = [
    0.666_538_099_972_017_2,
    0.625_775_813_394_612_9,
    0.405_059_406_329_496,
];
/// Hairer–Vilmart's driver case: principal moments.
pub const HV_I: [f64; 3] = [0.6, 0.8, 1.0];
/// Hairer–Vilmart's driver case: initial momentum.
pub const HV_M0: [f64; 3] = [1.8, 0.4, -0.9];
