//! `Counted`: an `f64` that counts every arithmetic operation done on it, so that running an
//! integrator with `T = Counted` measures its flops exactly.
//!
//! Counted: `+`, `-`, `*`, `/` (the flops), `sqrt`, and the transcendental functions (sin,
//! cos, acos, atan2, cbrt, ln, exp) apart. Not counted: negation, `abs`, comparisons and
//! `copysign` (sign manipulation, free on every FPU), and constants (`from_f64`).

// the operator impls bump a counter with `+=`, which is not the operation they implement
#![allow(clippy::suspicious_arithmetic_impl)]

use rigid3::Real;
use std::cell::Cell;
use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// Operation counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Counts {
    /// Additions.
    pub add: u64,
    /// Subtractions.
    pub sub: u64,
    /// Multiplications.
    pub mul: u64,
    /// Divisions.
    pub div: u64,
    /// Square roots.
    pub sqrt: u64,
    /// Transcendental calls (sin, cos, acos, atan2, cbrt, ln, exp).
    pub trans: u64,
}

impl Counts {
    /// `+ - * /`: the flops.
    pub fn flops(&self) -> u64 {
        self.add + self.sub + self.mul + self.div
    }
}

thread_local! {
    static COUNTS: Cell<Counts> = Cell::new(Counts::default());
}

fn bump(f: impl FnOnce(&mut Counts)) {
    COUNTS.with(|c| {
        let mut v = c.get();
        f(&mut v);
        c.set(v);
    });
}

/// The counts since the last [`reset`] on this thread.
pub fn counts() -> Counts {
    COUNTS.with(|c| c.get())
}

/// Zeroes this thread's counts.
pub fn reset() {
    COUNTS.with(|c| c.set(Counts::default()));
}

/// Runs `f` and returns its result with the operations it did.
pub fn count<R>(f: impl FnOnce() -> R) -> (R, Counts) {
    let before = counts();
    let r = f();
    let after = counts();
    (
        r,
        Counts {
            add: after.add - before.add,
            sub: after.sub - before.sub,
            mul: after.mul - before.mul,
            div: after.div - before.div,
            sqrt: after.sqrt - before.sqrt,
            trans: after.trans - before.trans,
        },
    )
}

/// An `f64` that counts the operations done on it.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct Counted(pub f64);

macro_rules! binop {
    ($tr:ident, $f:ident, $field:ident, $op:tt, $tra:ident, $fa:ident) => {
        impl $tr for Counted {
            type Output = Counted;
            #[inline]
            fn $f(self, o: Counted) -> Counted {
                bump(|c| c.$field += 1);
                Counted(self.0 $op o.0)
            }
        }
        impl $tra for Counted {
            #[inline]
            fn $fa(&mut self, o: Counted) {
                *self = $tr::$f(*self, o);
            }
        }
    };
}

binop!(Add, add, add, +, AddAssign, add_assign);
binop!(Sub, sub, sub, -, SubAssign, sub_assign);
binop!(Mul, mul, mul, *, MulAssign, mul_assign);

impl Div for Counted {
    type Output = Counted;
    #[inline]
    fn div(self, o: Counted) -> Counted {
        bump(|c| c.div += 1);
        Counted(self.0 / o.0)
    }
}

impl Neg for Counted {
    type Output = Counted;
    #[inline]
    fn neg(self) -> Counted {
        Counted(-self.0)
    }
}

fn trans(f: impl FnOnce() -> f64) -> Counted {
    bump(|c| c.trans += 1);
    Counted(f())
}

impl Real for Counted {
    const EPSILON: Self = Counted(f64::EPSILON);
    const MIN_POSITIVE: Self = Counted(f64::MIN_POSITIVE);
    const MAX: Self = Counted(f64::MAX);
    const ZERO: Self = Counted(0.0);
    const ONE: Self = Counted(1.0);

    fn from_f64(x: f64) -> Self {
        Counted(x)
    }
    fn to_f64(self) -> f64 {
        self.0
    }
    fn sqrt(self) -> Self {
        bump(|c| c.sqrt += 1);
        Counted(self.0.sqrt())
    }
    fn abs(self) -> Self {
        Counted(self.0.abs())
    }
    fn sin(self) -> Self {
        trans(|| self.0.sin())
    }
    fn cos(self) -> Self {
        trans(|| self.0.cos())
    }
    fn acos(self) -> Self {
        trans(|| self.0.acos())
    }
    fn atan2(self, x: Self) -> Self {
        trans(|| self.0.atan2(x.0))
    }
    fn cbrt(self) -> Self {
        trans(|| self.0.cbrt())
    }
    fn ln(self) -> Self {
        trans(|| self.0.ln())
    }
    fn exp(self) -> Self {
        trans(|| self.0.exp())
    }
    fn is_finite(self) -> bool {
        self.0.is_finite()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_a_known_kernel_exactly() {
        // Horner for a cubic: 3 mul + 3 add; a dot product: 3 mul + 2 add; one sqrt
        let x = Counted(0.5);
        let ((), c) = count(|| {
            let p = ((Counted(1.0) * x + Counted(2.0)) * x + Counted(3.0)) * x + Counted(4.0);
            let d = x * x + x * x + x * x;
            let r = (p - d).sqrt() / Counted(2.0);
            assert_eq!(
                r.0,
                ((((0.5f64 + 2.0) * 0.5 + 3.0) * 0.5 + 4.0) - 0.75).sqrt() / 2.0
            );
            let _ = -r;
            let _ = r.abs();
            let _ = r < x;
        });
        assert_eq!(
            c,
            Counts {
                add: 5,
                sub: 1,
                mul: 6,
                div: 1,
                sqrt: 1,
                trans: 0
            }
        );
        assert_eq!(c.flops(), 13);
    }

    #[test]
    fn counts_the_transcendentals_apart() {
        let ((), c) = count(|| {
            let x = Counted(0.3);
            let _ = x.sin() + x.cos() * x.acos();
            let _ = x.cbrt();
        });
        assert_eq!((c.trans, c.add, c.mul), (4, 1, 1));
    }
}
