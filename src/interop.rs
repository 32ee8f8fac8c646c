//! Conversions to and from other crates' vector and quaternion types (features `mint` and
//! `micromath`). Every conversion is a move of named fields: no arithmetic, nothing rounded.
//!
//! **Quaternion order.** This crate's arrays are `[w, x, y, z]` ([`crate::State::q`],
//! [`Quaternion::to_array`]). `mint::Quaternion` is `{ v: [x, y, z], s: w }` (the layout of
//! glam and nalgebra, `[x, y, z, w]`); micromath's `Quaternion` is `(w, x, y, z)` with
//! accessors `w()`, `x()`, `y()`, `z()`. The impls below map by name, so the rotation is the
//! same on both sides (tests/interop.rs checks it by rotating a vector on each side).
//!
//! With `mint` (any `T`):
//! - [`Quaternion<T>`] `<->` `mint::Quaternion<T>`, and `IntoMint` for `Quaternion<T>`;
//! - [`State<T>`] `<->` `(mint::Vector3<T>, mint::Quaternion<T>)` (momentum, attitude);
//! - vectors are `[T; 3]` here, which mint converts itself (`mint::Vector3::from([x, y, z])`,
//!   `<[T; 3]>::from(v)`).
//!
//! With `micromath` (`f32`; enables micromath's `vector` and `quaternion` features):
//! - [`Quaternion<f32>`] `<->` `micromath::Quaternion`;
//! - [`State<f32>`] `<->` `(micromath::vector::F32x3, micromath::Quaternion)`;
//! - vectors: [`from_f32x3`] and [`to_f32x3`] (a `From` between `[f32; 3]` and `F32x3` would
//!   be between two foreign types, which Rust does not allow here).

use crate::integrator::State;
use crate::quat::Quaternion;

#[cfg(feature = "mint")]
mod with_mint {
    use super::{Quaternion, State};

    impl<T> From<mint::Quaternion<T>> for Quaternion<T> {
        /// `{ v: [x, y, z], s: w }` to `[w, x, y, z]`.
        fn from(q: mint::Quaternion<T>) -> Self {
            Quaternion {
                w: q.s,
                x: q.v.x,
                y: q.v.y,
                z: q.v.z,
            }
        }
    }

    impl<T> From<Quaternion<T>> for mint::Quaternion<T> {
        /// `[w, x, y, z]` to `{ v: [x, y, z], s: w }`.
        fn from(q: Quaternion<T>) -> Self {
            mint::Quaternion {
                v: mint::Vector3 {
                    x: q.x,
                    y: q.y,
                    z: q.z,
                },
                s: q.w,
            }
        }
    }

    impl<T> mint::IntoMint for Quaternion<T> {
        type MintType = mint::Quaternion<T>;
    }

    impl<T> From<(mint::Vector3<T>, mint::Quaternion<T>)> for State<T> {
        /// Body momentum and attitude (body to space) to a state.
        fn from((m, q): (mint::Vector3<T>, mint::Quaternion<T>)) -> Self {
            State {
                m: [m.x, m.y, m.z],
                q: [q.s, q.v.x, q.v.y, q.v.z],
            }
        }
    }

    impl<T> From<State<T>> for (mint::Vector3<T>, mint::Quaternion<T>) {
        /// A state as body momentum and attitude (body to space).
        fn from(s: State<T>) -> Self {
            let [mx, my, mz] = s.m;
            let [w, x, y, z] = s.q;
            (
                mint::Vector3 {
                    x: mx,
                    y: my,
                    z: mz,
                },
                mint::Quaternion {
                    v: mint::Vector3 { x, y, z },
                    s: w,
                },
            )
        }
    }
}

#[cfg(feature = "micromath")]
mod with_micromath {
    use super::{Quaternion, State};
    use micromath::vector::F32x3;

    impl From<micromath::Quaternion> for Quaternion<f32> {
        /// micromath's `(w, x, y, z)` to `[w, x, y, z]`.
        fn from(q: micromath::Quaternion) -> Self {
            Quaternion {
                w: q.w(),
                x: q.x(),
                y: q.y(),
                z: q.z(),
            }
        }
    }

    impl From<Quaternion<f32>> for micromath::Quaternion {
        /// `[w, x, y, z]` to micromath's `(w, x, y, z)`.
        fn from(q: Quaternion<f32>) -> Self {
            micromath::Quaternion::new(q.w, q.x, q.y, q.z)
        }
    }

    impl From<(F32x3, micromath::Quaternion)> for State<f32> {
        /// Body momentum and attitude (body to space) to a state.
        fn from((m, q): (F32x3, micromath::Quaternion)) -> Self {
            State {
                m: [m.x, m.y, m.z],
                q: [q.w(), q.x(), q.y(), q.z()],
            }
        }
    }

    impl From<State<f32>> for (F32x3, micromath::Quaternion) {
        /// A state as body momentum and attitude (body to space).
        fn from(s: State<f32>) -> Self {
            let [w, x, y, z] = s.q;
            (to_f32x3(s.m), micromath::Quaternion::new(w, x, y, z))
        }
    }

    /// micromath's 3-vector as this crate's `[x, y, z]`.
    #[must_use]
    pub fn from_f32x3(v: F32x3) -> [f32; 3] {
        [v.x, v.y, v.z]
    }

    /// `[x, y, z]` as micromath's 3-vector.
    #[must_use]
    pub fn to_f32x3(v: [f32; 3]) -> F32x3 {
        F32x3 {
            x: v[0],
            y: v[1],
            z: v[2],
        }
    }
}

#[cfg(feature = "micromath")]
pub use with_micromath::{from_f32x3, to_f32x3};
