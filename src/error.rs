//! Error types: small, `Copy`, and `#[non_exhaustive]` so variants can be added.

use core::fmt;

/// Why a set of moments of inertia (or a mass matrix, or an inertia tensor) was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum BodyError {
    /// An entry is NaN or infinite.
    NonFinite,
    /// A principal moment of inertia is zero or negative.
    NonPositiveMoment,
    /// A moment is larger than the sum of the other two (`I_i > I_j + I_k`): no real mass
    /// distribution has it, and the mass matrix `J` would have a negative entry.
    TriangleInequality,
    /// A mass-matrix entry `J_i` is negative.
    NegativeMassMatrix,
    /// The inertia tensor is not symmetric (to a relative tolerance of `64 eps`).
    NotSymmetric,
    /// A principal moment of inertia is positive but subnormal (below `MIN_POSITIVE`, about
    /// `1.2e-38` in f32 and `2.2e-308` in f64): the mass matrix and the step's products of
    /// moments underflow to zero there, so no method could step the body correctly. Rescale
    /// the units (a gram-centimetre body in kilogram-metres is still far above this).
    SubnormalMoment,
}

impl fmt::Display for BodyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BodyError::NonFinite => "inertia has a NaN or infinite entry",
            BodyError::NonPositiveMoment => "a principal moment of inertia is not positive",
            BodyError::TriangleInequality => {
                "moments of inertia break the triangle inequality I_i <= I_j + I_k"
            }
            BodyError::NegativeMassMatrix => "a mass-matrix entry J_i is negative",
            BodyError::NotSymmetric => "the inertia tensor is not symmetric",
            BodyError::SubnormalMoment => {
                "a principal moment of inertia is subnormal (rescale the units)"
            }
        })
    }
}

/// Why a step was not taken. The state is always left as it was.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum StepError {
    /// The state or the step size has a NaN or infinite entry, or the quaternion is zero.
    NonFinite,
    /// The step size is past the method's limit for this state (for DMV: the cubic of
    /// docs/MATH.md §2 has a negative real root, so no real orthogonal solution exists:
    /// docs/MATH.md §3).
    StepTooLarge,
    /// An iterative solve (implicit midpoint) did not converge.
    NoConvergence,
    /// The method's linear algebra broke down on a degenerate input (a singular eigenvector
    /// system, a repeated root the method cannot separate, a singular mass matrix) or its
    /// result failed a validity check (not orthogonal, not finite).
    Degenerate,
    /// The result would overflow the floating-point range.
    Overflow,
    /// A momentum-only step was asked of a forced integrator whose torque depends on the
    /// attitude (use `step_state`).
    NeedsAttitude,
    /// A method was built with an order it does not provide.
    InvalidOrder,
    /// A rotor was given to a forced scheme whose order assumes the torque is the only
    /// addition to the free body (the Nyström splittings of `Composed`).
    RotorUnsupported,
}

impl fmt::Display for StepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            StepError::NonFinite => "state or step size is not finite",
            StepError::StepTooLarge => "step size is past the method's limit for this state",
            StepError::NoConvergence => "the iteration did not converge",
            StepError::Degenerate => "the method broke down on a degenerate input",
            StepError::Overflow => "the result would overflow",
            StepError::NeedsAttitude => "the torque depends on the attitude: step the full state",
            StepError::InvalidOrder => "the method does not provide that order",
            StepError::RotorUnsupported => "this forced scheme takes no rotor",
        })
    }
}

// `core::error::Error` (stable since Rust 1.81): no `std` feature needed, the types work as
// `Box<dyn Error>` and with `?` in std applications and as `dyn core::error::Error` without std.
impl core::error::Error for BodyError {}

impl core::error::Error for StepError {}
