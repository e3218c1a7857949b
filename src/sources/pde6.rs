//! The sixth-order (tri-harmonic) Bloor–Wilson surface of Ugail 2004 §4 (seed 004,
//! eqs. (11)–(14)): (∂²/∂u² + a²∂²/∂v²)³ X = 0 with X, Xᵤ and Xᵤᵤ given at u = 0
//! and u = 1 as curves sampled at vₖ = 2πk/K.
//!
//! ```text
//! X(u, v) = A₀(u) + Σ_{n=1..N} [Aₙ(u) cos nv + Bₙ(u) sin nv] + R(u, v)
//! A₀      = quintic meeting the six conditions' means (the spine, eq. (13)–(14))
//! Aₙ, Bₙ  = (c₁ + c₂u + c₃u²) e^{λ(u−1)} + (c₄ + c₅u + c₆u²) e^{−λu},  λ = a n
//! R       = the same six functions with λ = w = a (N + 1), from the residual
//! ```
//!
//! As in [`super::pde`]: the scaled basis (no overflow), and the remainder carries
//! the samples' DFT modes N < n ≤ K/2 through one 6 × 6 solve, so the conditions
//! hold at every sample to rounding. 004 writes the remainder "of similar form" to
//! its (7); six terms are needed to meet six conditions.

use super::pde::{check_curves, fourier_curve, PdeError, PdeFault};
use nalgebra::{Matrix6, Matrix6x3, RowVector3, RowVector6};

/// The six conditions, each sampled at vₖ = 2πk/K: X(0, v), X(1, v), Xᵤ(0, v),
/// Xᵤ(1, v), Xᵤᵤ(0, v), Xᵤᵤ(1, v) (mm, mm per unit u, mm per unit u²).
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryCurves6 {
    /// X(0, vₖ), X(1, vₖ), Xᵤ(0, vₖ), Xᵤ(1, vₖ), Xᵤᵤ(0, vₖ), Xᵤᵤ(1, vₖ), in this order.
    pub curves: [Vec<[f64; 3]>; 6],
}

const KEYS: [&str; 6] = ["x0", "x1", "xu0", "xu1", "xuu0", "xuu1"];

/// A solved sixth-order surface.
#[derive(Debug, Clone, PartialEq)]
pub struct PdeSurface6 {
    /// (n, λ, cos coefficients, sin coefficients); n = 0 is the spine (λ = 0,
    /// monomial basis 1, u, …, u⁵, sin part zero).
    terms: Vec<(usize, f64, Matrix6x3<f64>, Matrix6x3<f64>)>,
}

/// Basis row and its first two u-derivatives. λ = 0: monomials uʲ, j = 0..6;
/// λ > 0: uʲ e^{λ(u−1)}, j = 0..3, then uʲ e^{−λu}, j = 0..3.
fn basis(lambda: f64, u: f64) -> [RowVector6<f64>; 3] {
    let cols: [[f64; 3]; 6] = std::array::from_fn(|i| {
        let (j, e, sigma) = if lambda == 0.0 {
            (i, 1.0, 0.0)
        } else if i < 3 {
            (i, (lambda * (u - 1.0)).exp(), lambda)
        } else {
            (i - 3, (-lambda * u).exp(), -lambda)
        };
        let jf = j as f64;
        let pw = |m: usize| if m > j { 0.0 } else { u.powi((j - m) as i32) };
        [
            pw(0) * e,
            (jf * pw(1) + sigma * pw(0)) * e,
            (jf * (jf - 1.0) * pw(2) + 2.0 * sigma * jf * pw(1) + sigma * sigma * pw(0)) * e,
        ]
    });
    std::array::from_fn(|d| RowVector6::from_fn(|_, c| cols[c][d]))
}

/// Row scale: the Xᵤ rows grow like λ and the Xᵤᵤ rows like λ², so both are
/// divided by that size (and their right-hand sides with them) before the LU.
fn row_scale(lambda: f64, row: usize) -> f64 {
    1.0 / lambda.max(1.0).powi((row / 2) as i32)
}

/// Rows X(0), X(1), Xᵤ(0), Xᵤ(1), Xᵤᵤ(0), Xᵤᵤ(1), each times [`row_scale`].
fn matrix(lambda: f64) -> Matrix6<f64> {
    let (b0, b1) = (basis(lambda, 0.0), basis(lambda, 1.0));
    let rows = [b0[0], b1[0], b0[1], b1[1], b0[2], b1[2]];
    Matrix6::from_fn(|r, c| rows[r][c] * row_scale(lambda, r))
}

fn check(c: &BoundaryCurves6, a: f64, modes: usize) -> Result<(), PdeError> {
    let bad = |key, reason| Err(PdeError::Invalid { key, reason });
    if !(a.is_finite() && a > 0.0) {
        return bad("a", PdeFault::NotPositive { value: a });
    }
    let curves: Vec<(&'static str, &[[f64; 3]])> = KEYS
        .iter()
        .zip(&c.curves)
        .map(|(&key, curve)| (key, curve.as_slice()))
        .collect();
    check_curves(&curves, modes, |_, _| Ok(()))
}

impl PdeSurface6 {
    /// Solves the surface for the curves, a > 0 and N = `modes` modes in F.
    pub fn solve(c: &BoundaryCurves6, a: f64, modes: usize) -> Result<Self, PdeError> {
        check(c, a, modes)?;
        let k = c.curves[0].len();
        let mut terms = Vec::with_capacity(k / 2 + 1);
        for n in 0..=k / 2 {
            let lambda = if n == 0 {
                0.0
            } else {
                a * n.min(modes + 1) as f64
            };
            let lu = matrix(lambda).lu();
            let (mut cm, mut sm) = (Matrix6x3::zeros(), Matrix6x3::zeros());
            for (row, curve) in c.curves.iter().enumerate() {
                let (cr, sr) = fourier_curve(curve, n);
                cm.set_row(row, &(cr * row_scale(lambda, row)));
                sm.set_row(row, &(sr * row_scale(lambda, row)));
            }
            let solve = |rhs: &Matrix6x3<f64>| match lu.solve(rhs) {
                Some(x) if x.iter().all(|v| v.is_finite()) => Ok(x),
                _ => Err(PdeError::Singular { mode: n, lambda }),
            };
            terms.push((n, lambda, solve(&cm)?, solve(&sm)?));
        }
        Ok(Self { terms })
    }

    /// The `d`-th u-derivative (d ≤ 2) of X at (u, v) (mm per unit uᵈ).
    pub fn eval(&self, d: usize, u: f64, v: f64) -> [f64; 3] {
        let mut x = RowVector3::zeros();
        for (n, lambda, c, s) in &self.terms {
            let phi = basis(*lambda, u)[d.min(2)];
            let (sv, cv) = (*n as f64 * v).sin_cos();
            x += phi * (c * cv + s * sv);
        }
        [x[0], x[1], x[2]]
    }

    /// The spine A₀(u) (004 eq. (13)).
    #[cfg(test)]
    pub(crate) fn spine(&self, u: f64) -> [f64; 3] {
        let x = basis(0.0, u)[0] * self.terms[0].2;
        [x[0], x[1], x[2]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    fn curves(k: usize) -> BoundaryCurves6 {
        type F = fn(f64) -> [f64; 3];
        let fs: [F; 6] = [
            |v| [(10.0 + (5.0 * v).cos()) * v.cos(), 10.0 * v.sin(), 0.0],
            |v| [6.0 * v.cos(), (6.0 + 0.5 * (7.0 * v).sin()) * v.sin(), 12.0],
            |v| [2.0 * v.cos(), 2.0 * v.sin(), 10.0 + (4.0 * v).cos()],
            |v| [-v.cos(), -v.sin() + 0.3 * (9.0 * v).cos(), 10.0],
            |v| [(6.0 * v).sin(), 3.0 * v.sin(), 1.0],
            |v| [-4.0 * v.cos(), 0.2 * (8.0 * v).cos(), -2.0],
        ];
        BoundaryCurves6 {
            curves: fs.map(|f| (0..k).map(|j| f(TAU * j as f64 / k as f64)).collect()),
        }
    }

    /// Largest condition error, the Xᵤ rows divided by w and the Xᵤᵤ rows by w²
    /// (w = a (N + 1) ≥ 1 here): Xᵤᵤ is a sum of terms of size w²·|X| that cancel,
    /// so rounding there is relative to w²·|X|, not to |Xᵤᵤ|.
    fn error(s: &PdeSurface6, c: &BoundaryCurves6, w: f64) -> f64 {
        let k = c.curves[0].len();
        let mut e: f64 = 0.0;
        for j in 0..k {
            let v = TAU * j as f64 / k as f64;
            for (row, curve) in c.curves.iter().enumerate() {
                let got = s.eval(row / 2, (row % 2) as f64, v);
                let d = (0..3)
                    .map(|i| (got[i] - curve[j][i]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                let d = d / w.powi((row / 2) as i32);
                e = crate::num::max_or_nan(e, d);
            }
        }
        e
    }

    #[test]
    fn sixth_order_meets_x_xu_xuu_at_the_samples() {
        for (k, n, a) in [(32, 3, 1.0), (64, 6, 0.5), (64, 20, 5.0)] {
            let c = curves(k);
            let s = PdeSurface6::solve(&c, a, n).unwrap();
            let e = error(&s, &c, a * (n + 1) as f64);
            // Measured: 1.0e-12, 4.3e-12, 1.8e-10/w² (a = 0.5: as λ → 0 the six
            // functions tend to one quintic's span, and the 6 × 6 LU loses digits).
            assert!(e < 1e-11, "K = {k}, N = {n}, a = {a}: {e:e}");
        }
    }

    #[test]
    fn the_quintic_spine_is_the_mean_over_the_samples() {
        let c = curves(40);
        let s = PdeSurface6::solve(&c, 1.0, 4).unwrap();
        for u in [0.0, 0.3, 0.7, 1.0] {
            let mut m = [0.0; 3];
            for j in 0..40 {
                let p = s.eval(0, u, TAU * j as f64 / 40.0);
                (0..3).for_each(|i| m[i] += p[i] / 40.0);
            }
            let sp = s.spine(u);
            assert!(
                (0..3).all(|i| (m[i] - sp[i]).abs() < 1e-12),
                "{m:?} vs {sp:?}"
            );
        }
    }

    #[test]
    fn second_derivative_matches_finite_differences() {
        let s = PdeSurface6::solve(&curves(32), 1.3, 4).unwrap();
        let h = 1e-4;
        for (u, v) in [(0.2, 0.4), (0.5, 2.0), (0.8, 5.5)] {
            let fd: Vec<f64> = (0..3)
                .map(|i| {
                    (s.eval(0, u + h, v)[i] - 2.0 * s.eval(0, u, v)[i] + s.eval(0, u - h, v)[i])
                        / (h * h)
                })
                .collect();
            let d2 = s.eval(2, u, v);
            assert!(
                (0..3).all(|i| (fd[i] - d2[i]).abs() < 1e-4),
                "{fd:?} vs {d2:?}"
            );
        }
    }
}
