//! Gauss–Legendre rules on [−1, 1], computed once per order.
//!
//! The nodes are the roots of Pₙ, found by Newton's method from the
//! Tricomi estimate cos(π(k − ¼)/(n + ½)); the weights are
//! 2 / ((1 − x²) Pₙ'(x)²). Hand-written: the `gauss-quad` crate (0.3) needs
//! Rust 1.89, above pfcam's 1.85, and a rule is twenty lines.

use std::f64::consts::PI;

/// Largest order: beyond this the Newton start values crowd and nothing in
/// the box quadrature needs more.
pub(crate) const MAX_ORDER: usize = 64;

/// An n-point Gauss–Legendre rule: exact for polynomials of degree ≤ 2n − 1.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct GaussRule {
    /// Nodes in (−1, 1), ascending.
    pub(crate) nodes: Vec<f64>,
    /// Weights, summing to 2.
    pub(crate) weights: Vec<f64>,
}

impl GaussRule {
    /// The rule of `n` points, 1 ≤ n ≤ `MAX_ORDER` (clamped into that range).
    pub(crate) fn new(n: usize) -> Self {
        let n = n.clamp(1, MAX_ORDER);
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        for k in 0..n {
            let mut x = (PI * (k as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            // Newton converges quadratically from the estimate; 100 caps it.
            for _ in 0..100 {
                let (p, d) = legendre(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre(n, x);
            dp = if d.is_finite() { d } else { dp };
            nodes[n - 1 - k] = x;
            weights[n - 1 - k] = 2.0 / ((1.0 - x * x) * dp * dp);
        }
        GaussRule { nodes, weights }
    }

    /// ∫_{lo}^{hi} f(t) dt by this rule.
    #[cfg(test)]
    pub(crate) fn integrate(&self, lo: f64, hi: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        let mut sum = 0.0;
        for (x, w) in self.nodes.iter().zip(&self.weights) {
            sum += w * f(mid + half * x);
        }
        sum * half
    }
}

/// Pₙ(x) and Pₙ'(x) by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let k = k as f64;
        let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    let p = if n == 0 { 1.0 } else { p1 };
    let dp = n as f64 * (x * p - p0) / (x * x - 1.0);
    (p, dp)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The n-point rule integrates x^k exactly for k ≤ 2n − 1 and not x^{2n}.
    #[test]
    fn exact_to_degree_2n_minus_1() {
        for n in [1, 2, 3, 5, 8, 16, 40] {
            let rule = GaussRule::new(n);
            assert!((rule.weights.iter().sum::<f64>() - 2.0).abs() < 1e-13);
            for k in 0..2 * n {
                let exact = if k % 2 == 1 {
                    0.0
                } else {
                    2.0 / (k as f64 + 1.0)
                };
                let got = rule.integrate(-1.0, 1.0, |x| x.powi(k as i32));
                assert!((got - exact).abs() < 1e-13, "n {n} k {k}: {got} vs {exact}");
            }
            if n <= 5 {
                let k = 2 * n;
                let exact = 2.0 / (k as f64 + 1.0);
                let got = rule.integrate(-1.0, 1.0, |x| x.powi(k as i32));
                assert!(
                    (got - exact).abs() > 1e-3,
                    "n {n}: degree 2n exact by luck?"
                );
            }
        }
    }

    #[test]
    fn integrates_a_smooth_function_on_an_interval() {
        let rule = GaussRule::new(12);
        let got = rule.integrate(0.0, 2.0, f64::exp);
        assert!((got - (2.0f64.exp() - 1.0)).abs() < 1e-13);
    }
}
