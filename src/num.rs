//! Small numeric helpers shared by the stages.

/// The larger of `a` and `b`, or NaN when either is NaN. `f64::max` returns the
/// other operand when one is NaN, so a reduction with it reads a NaN error as
/// no error at all; every reduction of an error or a distance that a check
/// relies on uses this instead.
pub fn max_or_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
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
