//! Small numeric helpers shared by the stages.

mod condition;

pub(crate) use condition::triangular_condition;

/// The larger of `a` and `b`, or NaN when either is NaN. `f64::max` returns the
/// other operand when one is NaN, so a reduction with it reads a NaN error as
/// no error at all; every reduction of an error or a distance that a check
/// relies on uses this instead.
pub(crate) fn max_or_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// Fixed-seed random numbers for the unit tests (no rand dependency): a
/// 64-bit LCG (Knuth's MMIX constants), each draw its top 53 bits.
#[cfg(test)]
pub(crate) mod testing {
    /// The generator; its state is the seed.
    pub(crate) struct Lcg(pub(crate) u64);

    impl Lcg {
        /// One step of the generator: the new state.
        fn step(&mut self) -> u64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            self.0
        }

        /// Uniform in [0, 1).
        pub(crate) fn next(&mut self) -> f64 {
            (self.step() >> 11) as f64 / (1u64 << 53) as f64
        }

        /// Uniform in [a, b).
        pub(crate) fn range(&mut self, a: f64, b: f64) -> f64 {
            a + (b - a) * self.next()
        }

        /// The state's top 31 bits after a step (for picking indices).
        pub(crate) fn word(&mut self) -> usize {
            (self.step() >> 33) as usize
        }

        /// [`Lcg::word`] modulo `n` (0 when n is 0).
        pub(crate) fn below(&mut self, n: usize) -> usize {
            self.word() % n.max(1)
        }
    }

    /// `count` draws of [`Lcg`] from `seed`.
    pub(crate) fn uniforms(seed: u64, count: usize) -> Vec<f64> {
        let mut g = Lcg(seed);
        (0..count).map(|_| g.next()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nan_anywhere_is_the_result() {
        assert_eq!(max_or_nan(1.0, 2.0), 2.0);
        assert!(max_or_nan(f64::NAN, 2.0).is_nan());
        assert!(max_or_nan(2.0, f64::NAN).is_nan());
        let xs = [0.5, f64::NAN, 3.0];
        assert!(xs.iter().copied().fold(0.0, max_or_nan).is_nan());
        // What f64::max does with the same values: the NaN is lost.
        assert_eq!(xs.iter().copied().fold(0.0, f64::max), 3.0);
    }
}
