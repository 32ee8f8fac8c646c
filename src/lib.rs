//! # rigid3: explicit discrete Moser–Veselov integrators for the free rigid body
//!
//! `#![no_std]`, allocation-free, `f32` and `f64`. Integrates Euler's equations
//! `m' = m x Omega`, `Omega = I^-1 m`, for the body angular momentum `m`, and the attitude
//! quaternion `q' = 1/2 q (x) (0, Omega)` (body to space), with the discrete Moser–Veselov
//! (DMV) rigid body solved explicitly for `N = 3` (Zanna & McLachlan, "An explicit,
//! completely integrable, second-order method for the 3x3 rigid body").
//!
//! ## Conventions (docs/MATH.md §1)
//!
//! - Principal moments `I = (I1, I2, I3)`; mass matrix `J_i = (I_j + I_k - I_i) / 2`.
//! - Energy `E = 1/2 sum m_i^2 / I_i` and Casimir `|m|^2` are conserved by the flow, and so is
//!   the spatial momentum `R(q) m`.
//! - `q = (w, x, y, z)` maps body to space: `x_space = R(q) x_body`.
//! - The body frame is the principal frame of the [`Body`]: `m`, `Omega`, torques and rotor
//!   momentum are given along its principal axes. For a body built from an inertia tensor,
//!   [`Body::from_inertia_tensor`] returns that frame, and [`Frame`] turns sensor-frame vectors
//!   (gyro rates, wheel axes, commanded torques) into it and attitudes back.
//!
//! ## Methods
//!
//! | type | method | order | conserves |
//! |---|---|---|---|
//! | [`Mv`] | closed-form explicit DMV: one 3x3 solve, no sqrt, no trig (flagship) | 2 | `\|m\|^2`, `E`, `R(q) m` |
//! | [`PreMv`] | DMV with modified moments (Hairer–Vilmart), same cost per step as `Mv` | 4–10 | `\|m\|^2`, `E`, `R(q) m` |
//! | [`RetimedMv`] | DMV (or `PreMv`) with its step chosen from the exact solution: `m` exact at `t = n h` | m: exact, q: 2–10 | `\|m\|^2`, `E`, `R(q) m` |
//! | [`SeedMv`] | the talk's explicit DMV (cubic + eigenvectors), as published | 2 | `\|m\|^2`, `E`, `R(q) m` |
//! | [`Splitting`] | McLachlan's symmetric splitting, three axis rotations | 2 | `\|m\|^2`, `R(q) m` |
//! | [`Splitting2`] | McLachlan's splitting with the Casimir split off, two rotations | 2 | `\|m\|^2`, `R(q) m` |
//! | [`Midpoint`] | implicit midpoint, Newton or fixed point | 2 | `\|m\|^2`, `E` |
//! | [`Rk4`] | classical Runge–Kutta | 4 | none |
//! | [`Exact`] | the exact flow: Jacobi elliptic functions and `Pi` ([`elliptic`]) | exact | all |
//!
//! Every method implements [`Integrator`]: `step` advances momentum only, `step_state`
//! momentum and attitude. A step that cannot be taken returns a [`StepError`] and leaves
//! the state as it was; no method panics or returns NaN.
//!
//! The formulas and conventions behind these docs are in `docs/MATH.md` (shipped with the
//! crate; cited as "docs/MATH.md §n"). Costs (counted flops, host time, Cortex-M4F
//! instructions, code size, stack) are measured, with the commands that measure them, in the
//! README's tables: `Mv` takes 78 counted flops per free-running momentum step and 153 with
//! attitude (talk's case, `h = 0.1`; 286–303 with attitude on a step after an outside change,
//! `rigid3-lab flops`).
//!
//! ## Forced motion: torques, reaction wheels, potentials
//!
//! | type | what | order |
//! |---|---|---|
//! | [`Forced`] | kick–turn–drift–turn–kick around any free integrator: a torque model of the attitude and time ([`torque`]: constant, periodic, gravity, gravity gradient, closures) or a torque given per step (`step_state_with`, instead of a model; `step_state_plus`, added to the model: a controller's command), and rotor momentum in the body frame (`set_rotor`, any tick). With `Mv` it is the Lie group variational integrator, explicit | 2 |
//! | [`Composed`] | `new`: compositions of `Forced`'s step (any drift, rotor allowed); `nystrom`: Blanes–Moan Nyström splittings with a near-exact drift (`PreMv` order 10, or `Exact`), for torques without rotor, the cheapest per accuracy on the README's heavy top below `1e-6`; `force_gradient`: Chin's two-drift splitting 4A with the bracket `[B, [A, B]]` in its middle kick, the cheapest rigid3 method at `1e-4` and `1e-5` on the heavy top in counted operations (level with RK4 there: 4 % and 0.3 % more in the table, 2 % and 1 % fewer interpolated to the level; in host time RK4 is faster) | 4, 6 |
//! | [`ForcedRk4`] | classical Runge–Kutta on the full forced equations (baseline) | 4 |
//!
//! The forced step keeps what the torque leaves: `|m|^2` and `R(q) m` with a rotor alone, the
//! vertical spatial momentum of a heavy top (to round-off, or to `O(h^2)` where a fast wheel
//! takes the relative splitting: [`Forced`]'s docs); small f32 torques are not rounded away (each
//! kick's lost rounding is carried into the next). docs/MATH.md §9 has the splittings.
//!
//! ```
//! use rigid3::{Body, Forced, GravityGradient, Integrator, Mv, State};
//!
//! // a small satellite at 200 Hz in a 90-minute orbit, with three reaction wheels
//! let body = Body::<f32>::from_inertia([60.0, 95.0, 120.0]).unwrap();
//! let n = 0.001_163_6f32;
//! let gg = GravityGradient::circular(&body, n); // K = N^2, the body's principal moments
//! let mut f = Forced::new(Mv::new(body, 0.005), gg);
//! let mut s = State::new([0.5, -0.3, 1.2], [1.0, 0.0, 0.0, 0.0]);
//! let mut elapsed = 0.0f64;
//! for tick in 0..200 {
//!     f.set_rotor([0.1, -0.2, 0.05]).unwrap(); // the wheels' momentum, each tick
//!     let dt = 0.005 * (1.0 + 0.01 * (tick % 3) as f32); // the measured dt
//!     f.set_step_size(dt);
//!     f.step_state(&mut s).unwrap();
//!     elapsed += f64::from(dt);
//! }
//! // the clock (a compensated sum) is the sum of the steps taken, for the torque's time
//! assert!((f64::from(f.time()) - elapsed).abs() < 1e-6);
//! // a controller's command added to the gravity gradient, given at both ends of the step
//! // (zero-order hold: the same twice); step_state_with would take it instead of the model
//! f.step_state_plus(&mut s, [1e-3, 0.0, 0.0], [1e-3, 0.0, 0.0]).unwrap();
//! ```
//!
//! ## For analysts and filters
//!
//! [`Orbit`] is the exact trajectory through a state, set up once and evaluated at any `t`;
//! [`Integrator::step_partial`] takes a step of any size without disturbing an integrator's
//! tracked trajectory (output between steps, event location); [`Mv::step_with_jacobian`] and
//! [`PreMv::step_with_jacobian`] return the step's 6x6 tangent map for a multiplicative EKF
//! ([`tangent`]); [`Quaternion`] and [`Frame`] handle attitudes and the principal frame of an
//! inertia tensor, with quaternions `[w, x, y, z]` at every boundary.
//!
//! ## Features
//!
//! - `mint`: `From`/`Into` between [`Quaternion`], [`State`] and `mint`'s `Quaternion` and
//!   `Vector3` (mint's quaternion is `{ v: [x, y, z], s: w }`, i.e. `[x, y, z, w]`; the
//!   conversions map by name), in the module `interop` (present with either feature).
//! - `micromath`: the same for micromath 2's `Quaternion` (`(w, x, y, z)`) and
//!   `vector::F32x3` (`f32` only).
//! - `defmt`: `defmt::Format` on the public types.
//!
//! ## Example
//!
//! ```
//! use rigid3::{Body, Exact, Integrator, Mv, PreMv, State};
//!
//! // the talk's case
//! let body = Body::<f64>::from_mass_matrix([0.9218, 0.7382, 0.1763]).unwrap();
//! let s0 = State::new([0.4165, 0.9072, 0.0588], [1.0, 0.0, 0.0, 0.0]);
//!
//! // the closed-form DMV step: conserves |m|^2, the energy and R(q) m to round-off
//! let mut dmv = Mv::new(body, 0.1);
//! let mut s = s0;
//! for _ in 0..100 {
//!     dmv.step_state(&mut s).unwrap();
//! }
//! assert!((body.energy(&s.m) - body.energy(&s0.m)).abs() < 1e-14);
//!
//! // preprocessed to order 10, the same cost per step is accurate to ~1e-15 at t = 10
//! let mut pre = PreMv::new(body, 0.1, 10).unwrap();
//! let mut p = s0;
//! for _ in 0..100 {
//!     pre.step_state(&mut p).unwrap();
//! }
//! let exact = Exact::at(&body, &s0, 10.0).unwrap();
//! assert!((p.m[0] - exact.m[0]).abs() < 1e-12);
//!
//! // past the existence limit a step is refused and the state left as it was
//! let mut m = s0.m;
//! let too_big = 1.01 * Mv::max_step(&body, &m);
//! assert!(Mv::new(body, too_big).step(&mut m).is_err());
//! assert_eq!(m, s0.m);
//! ```
#![no_std]
// One `asm!` (src/fpu_sqrt.rs, the FPU's square root on hard-float ARM) is the only unsafe code.
#![deny(unsafe_code)]
#![warn(missing_docs)]
// `!(x > 0)` is deliberate throughout: it is true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod asin;
mod body;
mod cbrt;
pub mod cubic;
pub mod elliptic;
mod error;
mod exact;
mod forced;
mod forced_composed;
mod forced_relative;
mod forced_rk4;
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
mod fpu_sqrt;
mod frame;
mod integrator;
#[cfg(any(feature = "mint", feature = "micromath"))]
pub mod interop;
mod linalg;
mod max_step;
mod midpoint;
mod mv;
mod mv_frozen;
mod mv_pre;
mod mv_pre_series;
mod mv_retimed;
mod mv_seed;
mod orbit;
mod quat;
mod real;
mod rk4;
mod sincos;
mod sincos_far;
mod splitting;
pub mod tangent;
#[cfg(test)]
mod test_rng;
pub mod torque;

pub use body::Body;
pub use error::{BodyError, StepError};
pub use exact::Exact;
pub use forced::Forced;
pub use forced_composed::Composed;
pub use forced_rk4::ForcedRk4;
pub use frame::Frame;
pub use integrator::{Integrator, State};
pub use midpoint::{Midpoint, Solver};
pub use mv::Mv;
pub use mv_pre::PreMv;
pub use mv_retimed::RetimedMv;
pub use mv_seed::SeedMv;
pub use orbit::Orbit;
pub use quat::Quaternion;
pub use real::Real;
pub use rk4::Rk4;
pub use sincos::sin_cos;
pub use splitting::{Splitting, Splitting2};
pub use torque::{
    ConstantTorque, FnTorque, Gravity, GravityGradient, NoTorque, PeriodicTorque, Torque,
};
