//! Bernstein polynomials B_i^n(t) = C(n, i) tᵢ (1 − t)^(n−i) on [0, 1]: the
//! few operations the harmonic patch needs (de Casteljau evaluation, the
//! control points of a derivative, forward differences).

/// The binomial coefficient C(n, k) as f64 (exact for the degrees used here:
/// C(30, 15) < 2⁵³).
pub(crate) fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let k = k.min(n - k);
    (0..k).fold(1.0, |c, i| c * (n - i) as f64 / (i + 1) as f64)
}

/// Σ_i c_i B_i^n(t), n = c.len() − 1, by de Casteljau's algorithm (convex
/// combinations only, so stable for t in [0, 1]). An empty slice is 0.
pub(crate) fn de_casteljau(c: &[f64], t: f64) -> f64 {
    let mut w = c.to_vec();
    for r in 1..w.len() {
        for i in 0..w.len() - r {
            w[i] = (1.0 - t) * w[i] + t * w[i + 1];
        }
    }
    w.first().copied().unwrap_or(0.0)
}

/// The control points of the derivative: d/dt Σ c_i B_i^n = Σ n (c_{i+1} − c_i)
/// B_i^{n−1}. A constant (one point) gives an empty slice (the zero polynomial).
pub(crate) fn derivative(c: &[f64]) -> Vec<f64> {
    let n = c.len().saturating_sub(1) as f64;
    c.windows(2).map(|w| n * (w[1] - w[0])).collect()
}

/// The k-th forward difference Δᵏc_0 = Σ_j (−1)^(k−j) C(k, j) c_j of the first
/// k + 1 points. In the power basis Σ_i c_i B_i^n(t) = Σ_k C(n, k) Δᵏc_0 tᵏ,
/// so Δⁿc_0 is the coefficient of tⁿ.
pub(crate) fn forward_difference(c: &[f64], k: usize) -> f64 {
    (0..=k.min(c.len().saturating_sub(1)))
        .map(|j| {
            let sign = if (k - j) % 2 == 0 { 1.0 } else { -1.0 };
            sign * binomial(k, j) * c[j]
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binomials_are_exact() {
        assert_eq!(binomial(5, 2), 10.0);
        assert_eq!(binomial(30, 15), 155_117_520.0);
        assert_eq!(binomial(3, 4), 0.0);
        assert_eq!(binomial(0, 0), 1.0);
    }

    /// de Casteljau against the Bernstein sum written out.
    #[test]
    fn de_casteljau_is_the_bernstein_sum() {
        let c = [0.3, -1.0, 2.5, 0.7, 4.0];
        for t in [0.0_f64, 0.17, 0.5, 0.93, 1.0] {
            let direct: f64 = (0..5)
                .map(|i| c[i] * binomial(4, i) * t.powi(i as i32) * (1.0 - t).powi(4 - i as i32))
                .sum();
            assert!((de_casteljau(&c, t) - direct).abs() < 1e-14);
        }
    }

    /// The derivative's control points against a central difference.
    #[test]
    fn derivative_matches_finite_differences() {
        let c = [0.3, -1.0, 2.5, 0.7, 4.0];
        let d = derivative(&c);
        let h = 1e-6;
        for t in [0.1, 0.5, 0.8] {
            let fd = (de_casteljau(&c, t + h) - de_casteljau(&c, t - h)) / (2.0 * h);
            assert!((de_casteljau(&d, t) - fd).abs() < 1e-8);
        }
    }

    /// The n-th difference is the coefficient of tⁿ: for tⁿ itself (control
    /// points 0, …, 0, 1) it is 1, and for any lower degree 0.
    #[test]
    fn nth_difference_is_the_leading_coefficient() {
        // tⁿ has Bernstein coefficients δ_{i,n}.
        assert_eq!(forward_difference(&[0.0, 0.0, 0.0, 1.0], 3), 1.0);
        // t (degree 1) raised to degree 3: coefficients i/3.
        let t = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0];
        assert!(forward_difference(&t, 3).abs() < 1e-15);
    }
}
