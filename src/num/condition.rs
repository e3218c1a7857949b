//! The condition estimate of a triangular factor.

use faer::MatRef;

/// The condition estimate of a square system from the triangular factor T of
/// its factorization (R of a QR, U of an LU):
///
/// κ ≈ maxₖ |Tₖₖ| / minₖ |Tₖₖ|, k over the diagonal,
///
/// and +∞ when the smallest |Tₖₖ| is 0. The diagonal of a triangular T holds
/// its eigenvalues, so this is a lower bound on T's 2-norm condition number
/// σ_max / σ_min: cheap and, with the columns scaled to unit norm (QR) or the
/// pivots chosen (LU), a fair estimate of the system's. A NaN on the diagonal
/// is skipped (`f64::max`, `f64::min`).
pub(crate) fn triangular_condition(t: MatRef<'_, f64>) -> f64 {
    let (mut max, mut min) = (0.0_f64, f64::INFINITY);
    for k in 0..t.nrows().min(t.ncols()) {
        let d = t[(k, k)].abs();
        max = max.max(d);
        min = min.min(d);
    }
    if min > 0.0 {
        max / min
    } else {
        f64::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    #[test]
    fn the_ratio_of_the_largest_to_the_smallest_diagonal_magnitude() {
        let t = Mat::<f64>::from_fn(3, 3, |i, j| match (i, j) {
            (0, 0) => -4.0,
            (1, 1) => 0.5,
            (2, 2) => 2.0,
            _ if j > i => 100.0,
            _ => 0.0,
        });
        assert_eq!(triangular_condition(t.as_ref()), 8.0);
    }

    #[test]
    fn a_zero_on_the_diagonal_is_infinite() {
        let t = Mat::<f64>::from_fn(2, 2, |i, j| if i == 0 && j == 0 { 1.0 } else { 0.0 });
        assert_eq!(triangular_condition(t.as_ref()), f64::INFINITY);
    }
}
