//! The library's unit tests' deterministic generator (the crate itself has no RNG; the
//! integration tests and the lab have their own).

/// A 64-bit linear congruential generator (Knuth's MMIX constants), uniform in `[0, 1)` from
/// its top 53 bits.
pub(crate) struct Lcg(pub(crate) u64);

impl Lcg {
    pub(crate) fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}
