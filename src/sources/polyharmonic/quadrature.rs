//! Integrals of the box kernels over one constant element, seen from a point
//! P (Ochiai eqs. (34)–(38)):
//!
//! ```text
//! g₁ = ∫ T*₁ dA    g₂ = ∫ T*₂ dA    h₁ = ∫ ∂T*₁/∂n_Q dA    h₂ = ∫ ∂T*₂/∂n_Q dA
//! ```
//!
//! and their gradients in P (with d = P − Q, ∂T*/∂n_Q = −g(r) d·n and
//! ∇_P ∂T*/∂n_Q = −(h(r)(d·n) d + g(r) n), see [`Radial`](super::kernels::Radial)).
//!
//! From the element's own centre the integrals are exact (`elements`:
//! g₁ = ∫dA/r / 4π, g₂ = ∫r dA / 8π, h₁ = h₂ = 0). Otherwise the element is
//! split into four, recursively, until each piece is at least `ratio` times its
//! diameter away from P (or `max_depth` splits deep), and each piece takes an
//! `order` × `order` Gauss–Legendre product rule. The error of a piece falls
//! like (1/(2·ratio))^{2·order}, so the near-singular neighbours (across a
//! box edge, h/2 from the collocation point) cost a few levels, not a finer
//! rule everywhere.

use super::elements::{self_inv_r, self_r, Element};
use super::error::{invalid, PolyError};
use super::fault::PolyFault;
use super::gauss::{GaussRule, MAX_ORDER};
use super::kernels::Kernel;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Deepest subdivision allowed: 2⁻¹⁶ of an element is below any distance a
/// job's points come to the box; it bounds the work for a point on the box.
pub(crate) const MAX_DEPTH: u32 = 16;

/// The quadrature's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quadrature {
    /// Gauss points per side of a piece (1..=64).
    pub order: usize,
    /// A piece is integrated once its distance to P is ≥ ratio × its diameter
    /// (> 0; 1 to 2 is usual).
    pub ratio: f64,
    /// Most subdivisions (≤ [`MAX_DEPTH`]).
    pub max_depth: u32,
}

impl Default for Quadrature {
    /// 6 × 6 points, ratio 1.5, depth 12: the double-layer rows sum to −½
    /// within 1e-9 (`cargo test --release --lib polyharmonic::quadrature`).
    fn default() -> Self {
        Quadrature {
            order: 6,
            ratio: 1.5,
            max_depth: 12,
        }
    }
}

/// A [`Quadrature`] with its Gauss rule built.
#[derive(Debug, Clone, PartialEq)]
pub struct QuadRule {
    rule: GaussRule,
    ratio: f64,
    max_depth: u32,
}

impl QuadRule {
    /// Checks the settings (`quadrature.order`, `.ratio`, `.max_depth`).
    pub fn new(q: Quadrature) -> Result<Self, PolyError> {
        if !(1..=MAX_ORDER).contains(&q.order) {
            return Err(invalid("quadrature", PolyFault::Order { order: q.order }));
        }
        if !(q.ratio.is_finite() && q.ratio > 0.0) {
            return Err(invalid("quadrature", PolyFault::Ratio { ratio: q.ratio }));
        }
        if q.max_depth > MAX_DEPTH {
            return Err(invalid(
                "quadrature",
                PolyFault::Depth {
                    max_depth: q.max_depth,
                },
            ));
        }
        Ok(QuadRule {
            rule: GaussRule::new(q.order),
            ratio: q.ratio,
            max_depth: q.max_depth,
        })
    }

    /// Calls `f(Q, w)` for every quadrature point Q on the element with its
    /// area weight w, refined towards `p` as the module doc says.
    pub(crate) fn visit(
        &self,
        el: &Element,
        p: Vector3<f64>,
        f: &mut impl FnMut(Vector3<f64>, f64),
    ) {
        self.piece(el, el.centre, el.a, el.b, p, 0, f);
    }

    #[allow(clippy::too_many_arguments)]
    fn piece(
        &self,
        el: &Element,
        c: Vector3<f64>,
        a: f64,
        b: f64,
        p: Vector3<f64>,
        depth: u32,
        f: &mut impl FnMut(Vector3<f64>, f64),
    ) {
        let rel = p - c;
        let (du, dv) = (rel.dot(&el.u), rel.dot(&el.v));
        let dn = rel.dot(&el.normal);
        let (eu, ev) = ((du.abs() - a).max(0.0), (dv.abs() - b).max(0.0));
        let dist = (eu * eu + ev * ev + dn * dn).sqrt();
        if depth >= self.max_depth || dist >= self.ratio * 2.0 * a.hypot(b) {
            let (nodes, weights) = (&self.rule.nodes, &self.rule.weights);
            for (x, wx) in nodes.iter().zip(weights) {
                for (y, wy) in nodes.iter().zip(weights) {
                    f(c + el.u * (a * x) + el.v * (b * y), wx * wy * a * b);
                }
            }
            return;
        }
        let (ha, hb) = (0.5 * a, 0.5 * b);
        for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
            let cc = c + el.u * (su * ha) + el.v * (sv * hb);
            self.piece(el, cc, ha, hb, p, depth + 1, f);
        }
    }
}

/// g₁, g₂, h₁, h₂ of one element seen from P.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Influence {
    /// ∫ T*₁ dA.
    pub(crate) g1: f64,
    /// ∫ T*₂ dA.
    pub(crate) g2: f64,
    /// ∫ ∂T*₁/∂n dA.
    pub h1: f64,
    /// ∫ ∂T*₂/∂n dA.
    pub(crate) h2: f64,
}

/// ∇_P of g₁, g₂, h₁, h₂.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct InfluenceGradient {
    /// ∇ ∫ T*₁ dA.
    pub(crate) g1: Vector3<f64>,
    /// ∇ ∫ T*₂ dA.
    pub(crate) g2: Vector3<f64>,
    /// ∇ ∫ ∂T*₁/∂n dA.
    pub(crate) h1: Vector3<f64>,
    /// ∇ ∫ ∂T*₂/∂n dA.
    pub(crate) h2: Vector3<f64>,
}

/// Whether `p` is the element's own centre (to rounding of the box size).
fn is_own_centre(el: &Element, p: Vector3<f64>) -> bool {
    (p - el.centre).norm() <= 1e-12 * (el.a + el.b + el.centre.norm())
}

/// The element's g₁, g₂, h₁, h₂ seen from `p` (exact from its own centre).
pub fn influence(el: &Element, p: Vector3<f64>, q: &QuadRule) -> Influence {
    if is_own_centre(el, p) {
        return Influence {
            g1: self_inv_r(el.a, el.b) / (4.0 * PI),
            g2: self_r(el.a, el.b) / (8.0 * PI),
            h1: 0.0,
            h2: 0.0,
        };
    }
    let mut s = Influence::default();
    q.visit(el, p, &mut |x, w| {
        let d = p - x;
        let r = d.norm();
        let (k1, k2) = (Kernel::T1.radial(r), Kernel::T2.radial(r));
        let dn = d.dot(&el.normal);
        s.g1 += w * k1.f;
        s.g2 += w * k2.f;
        s.h1 -= w * k1.g * dn;
        s.h2 -= w * k2.g * dn;
    });
    s
}

/// ∇_P of the element's g₁, g₂, h₁, h₂ at `p` (not on the element).
pub(crate) fn influence_gradient(el: &Element, p: Vector3<f64>, q: &QuadRule) -> InfluenceGradient {
    let z = Vector3::zeros();
    let mut s = InfluenceGradient {
        g1: z,
        g2: z,
        h1: z,
        h2: z,
    };
    q.visit(el, p, &mut |x, w| {
        let d = p - x;
        let r = d.norm();
        let (k1, k2) = (Kernel::T1.radial(r), Kernel::T2.radial(r));
        let dn = d.dot(&el.normal);
        s.g1 += d * (w * k1.g);
        s.g2 += d * (w * k2.g);
        s.h1 -= (d * (k1.h * dn) + el.normal * k1.g) * w;
        s.h2 -= (d * (k2.h * dn) + el.normal * k2.g) * w;
    });
    s
}

#[cfg(test)]
mod tests;
