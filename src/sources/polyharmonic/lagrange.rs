//! Tensor-product Lagrange interpolation on a regular 3D grid: a smooth
//! function sampled once at the nodes, then evaluated (value and gradient) at
//! any point of the grid's box from the `order`³ nodes around it.
//!
//! Along each axis, with t = (x − lo)/h the position in node units, the
//! stencil is the `order` consecutive nodes i₀ … i₀ + order − 1 centred on t
//! (shifted inwards at the grid's ends), and u = t − i₀:
//!
//! ```text
//! f(x) ≈ Σ_{i,j,k} Lᵢ(u) Lⱼ(v) Lₖ(w) f_{i₀+i, j₀+j, k₀+k}
//! Lᵢ(u) = Π_{m≠i} (u − m)/(i − m)
//! ```
//!
//! The error is O(h^order) times the order-th derivatives: a polynomial of
//! degree < order in each variable is reproduced to rounding (test).

use nalgebra::Vector3;

/// Most points per axis of a stencil.
pub(crate) const MAX_ORDER: usize = 8;

/// Values of a function on the nodes lo + (i, j, k)·h.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LagrangeGrid {
    lo: Vector3<f64>,
    h: Vector3<f64>,
    n: [usize; 3],
    order: usize,
    /// f at node (i, j, k): `values[(k * n[1] + j) * n[0] + i]`.
    values: Vec<f64>,
}

impl LagrangeGrid {
    /// Samples `f` on the `n[0] × n[1] × n[2]` nodes from `lo`, `h` apart
    /// (in parallel: f must be a pure function of the node). `order` is
    /// clamped to 2..=[`MAX_ORDER`] and to the smallest `n`; every n ≥ 2.
    pub(crate) fn sample(
        lo: Vector3<f64>,
        h: Vector3<f64>,
        n: [usize; 3],
        order: usize,
        f: impl Fn(Vector3<f64>) -> f64 + Sync,
    ) -> Self {
        use rayon::prelude::*;
        let n = n.map(|k| k.max(2));
        let order = order.clamp(2, MAX_ORDER).min(n[0].min(n[1]).min(n[2]));
        let values = (0..n[0] * n[1] * n[2])
            .into_par_iter()
            .map(|idx| {
                let (i, j, k) = (idx % n[0], (idx / n[0]) % n[1], idx / (n[0] * n[1]));
                f(lo + Vector3::new(i as f64 * h.x, j as f64 * h.y, k as f64 * h.z))
            })
            .collect();
        LagrangeGrid {
            lo,
            h,
            n,
            order,
            values,
        }
    }

    /// The stencil's first node and the weights and their derivatives (per
    /// unit of x) along `axis` at coordinate `x`.
    fn axis(&self, axis: usize, x: f64) -> (usize, [f64; MAX_ORDER], [f64; MAX_ORDER]) {
        let p = self.order;
        let t = (x - self.lo[axis]) / self.h[axis];
        let last = (self.n[axis] - p) as f64;
        let i0 = (t.floor() - (p / 2 - 1) as f64).clamp(0.0, last);
        let u = t - i0;
        let (mut w, mut dw) = ([0.0; MAX_ORDER], [0.0; MAX_ORDER]);
        for i in 0..p {
            let (mut prod, mut dsum) = (1.0, 0.0);
            for m in (0..p).filter(|&m| m != i) {
                let den = i as f64 - m as f64;
                let mut term = 1.0 / den;
                for q in (0..p).filter(|&q| q != i && q != m) {
                    term *= (u - q as f64) / (i as f64 - q as f64);
                }
                dsum += term;
                prod *= (u - m as f64) / den;
            }
            w[i] = prod;
            dw[i] = dsum / self.h[axis];
        }
        (i0 as usize, w, dw)
    }

    /// The interpolated value and gradient at `x` (extrapolated by the end
    /// stencils outside the grid's box).
    pub(crate) fn value_gradient(&self, x: Vector3<f64>) -> (f64, Vector3<f64>) {
        let p = self.order;
        let (i0, wx, dx) = self.axis(0, x.x);
        let (j0, wy, dy) = self.axis(1, x.y);
        let (k0, wz, dz) = self.axis(2, x.z);
        let (mut f, mut g) = (0.0, Vector3::zeros());
        for k in 0..p {
            for j in 0..p {
                let row = ((k0 + k) * self.n[1] + j0 + j) * self.n[0] + i0;
                let (mut s, mut sx) = (0.0, 0.0);
                for i in 0..p {
                    let v = self.values[row + i];
                    s += wx[i] * v;
                    sx += dx[i] * v;
                }
                f += wz[k] * wy[j] * s;
                g.x += wz[k] * wy[j] * sx;
                g.y += wz[k] * dy[j] * s;
                g.z += dz[k] * wy[j] * s;
            }
        }
        (f, g)
    }

    /// The interpolated value at `x`.
    pub(crate) fn value(&self, x: Vector3<f64>) -> f64 {
        self.value_gradient(x).0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A polynomial of degree order − 1 in each variable is reproduced, value
    /// and gradient, anywhere in the grid's box.
    #[test]
    fn polynomials_of_low_degree_are_reproduced() {
        let f = |x: Vector3<f64>| x.x.powi(3) * x.y - 2.0 * x.y.powi(2) * x.z.powi(3) + x.z;
        let grad = |x: Vector3<f64>| {
            Vector3::new(
                3.0 * x.x.powi(2) * x.y,
                x.x.powi(3) - 4.0 * x.y * x.z.powi(3),
                -6.0 * x.y.powi(2) * x.z.powi(2) + 1.0,
            )
        };
        let g = LagrangeGrid::sample(
            Vector3::new(-1.0, -2.0, 0.5),
            Vector3::new(0.3, 0.25, 0.2),
            [9, 17, 11],
            4,
            f,
        );
        for k in 0..50 {
            let t = k as f64 / 50.0;
            let x = Vector3::new(
                -1.0 + 2.4 * t,
                -2.0 + 4.0 * (1.0 - t),
                0.5 + 2.0 * (t * 7.0).fract(),
            );
            let (v, gr) = g.value_gradient(x);
            assert!((v - f(x)).abs() < 1e-11, "{v} vs {}", f(x));
            assert!((gr - grad(x)).norm() < 1e-10, "{gr:?} vs {:?}", grad(x));
        }
    }

    /// A smooth non-polynomial function converges like h^order.
    #[test]
    fn the_error_falls_like_h_to_the_order() {
        let f = |x: Vector3<f64>| (x.x + 0.5 * x.y).sin() * (0.7 * x.z).exp();
        let err = |n: usize| {
            let h = 2.0 / (n - 1) as f64;
            let g = LagrangeGrid::sample(Vector3::zeros(), Vector3::repeat(h), [n; 3], 4, f);
            (0..200)
                .map(|k| {
                    let t = (k as f64 * 0.618_033_988_7).fract();
                    let x = Vector3::new(2.0 * t, 2.0 * (3.0 * t).fract(), 2.0 * (7.0 * t).fract());
                    (g.value(x) - f(x)).abs()
                })
                .fold(0.0, f64::max)
        };
        let (e1, e2) = (err(11), err(21));
        let order = (e1 / e2).log2();
        assert!(order > 3.5, "errors {e1:.2e}, {e2:.2e}: order {order:.2}");
    }
}
