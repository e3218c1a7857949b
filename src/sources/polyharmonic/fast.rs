//! T₁ fast inside a region well away from the box: the box's part of T₁ is
//! sampled once on a grid and interpolated, the loads' part is summed exactly.
//!
//! ```text
//! T₁(x) = B(x) + L(x),  B(x) = Σⱼ (g₁ V₁ⱼ − h₁ T₁ⱼ + h₂ T₂ⱼ − g₂ V₂ⱼ),  L(x) = −Σₖ Sₖ K₂(x, qₖ)
//! ```
//!
//! B is the field of layers on the box faces: harmonic-like and smooth at a
//! distance from them, so a tensor Lagrange interpolant of `order` points a
//! side ([`LagrangeGrid`]) on nodes `spacing` apart approximates it to
//! O(spacing^order); its cost is order³ multiply-adds instead of N element
//! quadratures. L carries all the detail near the given points and costs M
//! kernel evaluations. One evaluation at N = 216, M ≈ 50 falls from about
//! 0.1 ms to a few µs (docs/method.md §17, "Speed").

use super::error::{invalid, PolyError};
use super::fault::PolyFault;
use super::lagrange::LagrangeGrid;
use super::system::Solution;
use nalgebra::Vector3;

/// Most interpolation nodes (8 MB of values).
pub(crate) const MAX_NODES: usize = 1_000_000;

/// T₁ with the box part interpolated over a region (module doc).
#[derive(Debug, Clone)]
pub struct FastField {
    sol: Solution,
    grid: LagrangeGrid,
}

impl FastField {
    /// Samples the box part of `sol` on nodes at most `spacing` apart
    /// covering [lo, hi] (padded by order/2 − 1 nodes so every stencil is
    /// centred), `order` points a side. Errors (`box`): the padded region is
    /// not strictly inside the box, or it needs more than [`MAX_NODES`].
    pub fn new(
        sol: Solution,
        lo: Vector3<f64>,
        hi: Vector3<f64>,
        spacing: f64,
        order: usize,
    ) -> Result<Self, PolyError> {
        let pad = (order / 2).saturating_sub(1) as f64;
        let mut n = [0usize; 3];
        let mut h = Vector3::zeros();
        for k in 0..3 {
            let cells = ((hi[k] - lo[k]) / spacing).ceil().max(1.0);
            n[k] = cells as usize + 1 + 2 * pad as usize;
            h[k] = (hi[k] - lo[k]) / cells;
        }
        let start = lo - h * pad;
        let end = hi + h * pad;
        if !(sol.mesh().contains(start) && sol.mesh().contains(end)) {
            return Err(invalid(
                "box",
                PolyFault::RegionOutsideBox {
                    start,
                    end,
                    lo: sol.mesh().lo,
                    hi: sol.mesh().hi,
                },
            ));
        }
        let nodes = n.iter().map(|&k| k as f64).product::<f64>();
        if nodes > MAX_NODES as f64 {
            return Err(invalid("box", PolyFault::TooManyNodes { nodes }));
        }
        let grid = LagrangeGrid::sample(start, h, n, order, |x| sol.box_value(x));
        Ok(FastField { sol, grid })
    }

    /// T₁(x) (x meant inside the region; outside it the end stencils
    /// extrapolate).
    pub fn value(&self, x: Vector3<f64>) -> f64 {
        self.grid.value(x) + self.sol.load_value(x)
    }

    /// ∇T₁(x).
    pub fn gradient(&self, x: Vector3<f64>) -> Vector3<f64> {
        self.grid.value_gradient(x).1 + self.sol.load_gradient(x)
    }

    /// The solved field (for the exact T₁).
    pub fn solution(&self) -> &Solution {
        &self.sol
    }
}
