//! `Frame`: the principal frame of a body given by a full inertia tensor, so sensor vectors
//! and attitudes can be moved between the tensor's frame and the principal frame.

use crate::body::Body;
use crate::error::BodyError;
use crate::integrator::State;
use crate::quat::Quaternion;
use crate::real::Real;

/// The principal frame of a body, relative to the frame its inertia tensor was given in (the
/// "tensor frame": the structure's, the IMU's, the CAD model's).
///
/// `x_tensor = R(f) x_principal`, with `f` the unit quaternion `[w, x, y, z]` that
/// [`Body::from_inertia_tensor`] returns; [`Frame::from_inertia_tensor`] wraps it. The
/// integrators work in the principal frame: a gyro or magnetometer reading in the tensor frame
/// goes in through [`to_principal`](Frame::to_principal), a state comes out through
/// [`state_from_principal`](Frame::state_from_principal). For attitudes (body to space):
/// `q_principal = q_tensor (x) f` and `q_tensor = q_principal (x) f^*`.
///
/// Accuracy: each map is one quaternion rotation or product (a few ulps); the frame itself is
/// that of [`Body::from_inertia_tensor`] (the recomposed tensor matches the input to about
/// `8 eps |A|`; axes of a repeated moment are any orthonormal basis of its eigenspace).
///
/// ```
/// use rigid3::{Body, Frame, State};
///
/// // a tensor with products of inertia, in the structure's frame
/// let tensor = [[2.0, 0.1, 0.0], [0.1, 3.0, -0.2], [0.0, -0.2, 4.0]];
/// let (body, frame) = Frame::<f64>::from_inertia_tensor(tensor).unwrap();
/// // angular velocity measured in the structure's frame -> momentum in the principal frame
/// let omega = [0.1, -0.2, 0.3];
/// let w_p = frame.to_principal(omega);
/// let i = body.inertia();
/// let m_p = [i[0] * w_p[0], i[1] * w_p[1], i[2] * w_p[2]];
/// // and back: the tensor times omega
/// let m = frame.from_principal(m_p);
/// let expect = [
///     2.0 * 0.1 + 0.1 * -0.2,
///     0.1 * 0.1 + 3.0 * -0.2 - 0.2 * 0.3,
///     -0.2 * -0.2 + 4.0 * 0.3,
/// ];
/// for k in 0..3 {
///     assert!((m[k] - expect[k]).abs() < 1e-14);
/// }
/// // a state of the structure (attitude structure -> space) in the principal frame
/// let s = frame.state_to_principal(m, [1.0, 0.0, 0.0, 0.0]);
/// let (m_back, q_back) = frame.state_from_principal(&s);
/// assert!((m_back[1] - m[1]).abs() < 1e-14 && (q_back[0] - 1.0).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Frame<T> {
    /// `f`: principal to tensor frame.
    f: Quaternion<T>,
}

impl<T: Real> Frame<T> {
    /// The body in its principal frame and that frame, from a symmetric inertia tensor
    /// (row-major) given in some frame: [`Body::from_inertia_tensor`], with the frame wrapped.
    ///
    /// # Errors
    ///
    /// Those of [`Body::from_inertia_tensor`]: `NonFinite`, `NotSymmetric`, and those of
    /// [`Body::from_inertia`].
    pub fn from_inertia_tensor(tensor: [[T; 3]; 3]) -> Result<(Body<T>, Self), BodyError> {
        let (body, f) = Body::from_inertia_tensor(tensor)?;
        Ok((body, Self::from_quaternion(Quaternion::from_array(f))))
    }

    /// A frame from the unit quaternion `f` (`[w, x, y, z]`, principal to tensor frame:
    /// `x_tensor = R(f) x_principal`); not normalised here.
    #[must_use]
    pub fn from_quaternion(f: Quaternion<T>) -> Self {
        Self { f }
    }

    /// The quaternion `f` (`x_tensor = R(f) x_principal`).
    #[must_use]
    pub fn quaternion(&self) -> Quaternion<T> {
        self.f
    }

    /// A vector in the tensor frame (a sensor reading) in the principal frame: `R(f)^T v`.
    #[must_use]
    pub fn to_principal(&self, v: [T; 3]) -> [T; 3] {
        self.f.inverse_rotate(v)
    }

    /// A vector in the principal frame in the tensor frame: `R(f) v`.
    #[must_use]
    pub fn from_principal(&self, v: [T; 3]) -> [T; 3] {
        self.f.rotate(v)
    }

    /// An attitude of the tensor frame (`[w, x, y, z]`, tensor frame to space) as the attitude
    /// of the principal frame: `q (x) f`.
    #[must_use]
    pub fn attitude_to_principal(&self, q: [T; 4]) -> [T; 4] {
        Quaternion::from_array(q).compose(self.f).to_array()
    }

    /// An attitude of the principal frame (`[w, x, y, z]`, principal frame to space) as the
    /// attitude of the tensor frame: `q (x) f^*`.
    #[must_use]
    pub fn attitude_from_principal(&self, q: [T; 4]) -> [T; 4] {
        Quaternion::from_array(q)
            .compose(self.f.conjugate())
            .to_array()
    }

    /// The integrators' state from momentum `m` in the tensor frame and the tensor frame's
    /// attitude `q` (`[w, x, y, z]`, to space): `State { m: R(f)^T m, q: q (x) f }`. The spatial
    /// momentum `R(q) m` is the same in both.
    #[must_use]
    pub fn state_to_principal(&self, m: [T; 3], q: [T; 4]) -> State<T> {
        State::new(self.to_principal(m), self.attitude_to_principal(q))
    }

    /// A state of the integrators as momentum and attitude of the tensor frame: the inverse of
    /// [`state_to_principal`](Frame::state_to_principal).
    #[must_use]
    pub fn state_from_principal(&self, s: &State<T>) -> ([T; 3], [T; 4]) {
        (self.from_principal(s.m), self.attitude_from_principal(s.q))
    }
}
