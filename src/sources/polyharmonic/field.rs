//! The solved field anywhere in the box: T₁(x), ∇T₁(x) (eqs. (21)–(23)) and
//! the unit normal (28).
//!
//! For x strictly inside the box (c = 1), by (20) with the solved V₁, V₂, S:
//!
//! ```text
//! T₁(x)  = Σⱼ (g₁ V₁ⱼ − h₁ T₁ⱼ + h₂ T₂ⱼ − g₂ V₂ⱼ) − Σₖ Sₖ K₂(x, qₖ)
//! ∇T₁(x) = Σⱼ (∇g₁ V₁ⱼ − ∇h₁ T₁ⱼ + ∇h₂ T₂ⱼ − ∇g₂ V₂ⱼ) − Σₖ Sₖ ∇K₂(x, qₖ)
//! N      = ∇T₁ / |∇T₁|                                               (28)
//! ```
//!
//! T₁ is the same sum as a point's row of the system, so at every given point
//! it equals the asked value to the solve's rounding. The cost is N element
//! quadratures (order² kernel pairs each, more within a few element sizes of
//! the box) plus M load terms per evaluation.

use super::quadrature::{influence, influence_gradient};
use super::system::Solution;
use nalgebra::Vector3;

impl Solution {
    /// T₁(x), or None when x is not strictly inside the box (where (20)
    /// gives c·T₁ with c ≠ 1, not T₁).
    pub fn value(&self, x: Vector3<f64>) -> Option<f64> {
        self.mesh
            .contains(x)
            .then(|| self.box_value(x) + self.load_value(x))
    }

    /// ∇T₁(x), or None when x is not strictly inside the box.
    pub fn gradient(&self, x: Vector3<f64>) -> Option<Vector3<f64>> {
        self.mesh
            .contains(x)
            .then(|| self.box_gradient(x) + self.load_gradient(x))
    }

    /// The box's part of T₁ at x: Σⱼ (g₁ V₁ⱼ − h₁ T₁ⱼ + h₂ T₂ⱼ − g₂ V₂ⱼ),
    /// smooth away from the box faces (no check that x is inside).
    pub(crate) fn box_value(&self, x: Vector3<f64>) -> f64 {
        let mut sum = 0.0;
        for (j, el) in self.mesh.elements.iter().enumerate() {
            let f = influence(el, x, &self.rule);
            sum += f.g1 * self.v1[j] - f.h1 * self.t1[j] + f.h2 * self.t2[j] - f.g2 * self.v2[j];
        }
        sum
    }

    /// The loads' part of T₁ at x: −Σₖ Sₖ K₂(x, qₖ).
    pub(crate) fn load_value(&self, x: Vector3<f64>) -> f64 {
        let mut sum = 0.0;
        for (q, s) in self.centres.iter().zip(&self.s) {
            sum -= s * self.loads.1.value(x - q);
        }
        sum
    }

    /// ∇ of [`Solution::box_value`].
    pub(crate) fn box_gradient(&self, x: Vector3<f64>) -> Vector3<f64> {
        let mut sum = Vector3::zeros();
        for (j, el) in self.mesh.elements.iter().enumerate() {
            let f = influence_gradient(el, x, &self.rule);
            sum += f.g1 * self.v1[j] - f.h1 * self.t1[j] + f.h2 * self.t2[j] - f.g2 * self.v2[j];
        }
        sum
    }

    /// ∇ of [`Solution::load_value`].
    pub(crate) fn load_gradient(&self, x: Vector3<f64>) -> Vector3<f64> {
        let mut sum = Vector3::zeros();
        for (q, s) in self.centres.iter().zip(&self.s) {
            sum -= self.loads.1.gradient(x - q) * *s;
        }
        sum
    }

    /// The outward unit normal ∇T₁/|∇T₁| (28) of the level set through x, or
    /// None outside the box or where ∇T₁ vanishes.
    pub fn normal(&self, x: Vector3<f64>) -> Option<Vector3<f64>> {
        let g = self.gradient(x)?;
        let n = g.norm();
        (n.is_finite() && n > 0.0).then(|| g / n)
    }
}
