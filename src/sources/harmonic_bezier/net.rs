//! A tensor-product Bézier net of scalars, Σ_i Σ_j P_ij B_i^m(u) B_j^n(v), its
//! evaluation and the nets of its partial derivatives.

use super::bernstein::de_casteljau;

/// (m + 1) × (n + 1) control values, row-major: `p[i * (n + 1) + j]` = P_ij.
/// A net with no rows or columns is the zero polynomial.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Net {
    /// m + 1, the number of rows (index i, parameter u).
    pub(crate) rows: usize,
    /// n + 1, the number of columns (index j, parameter v).
    pub(crate) cols: usize,
    /// The values.
    pub(crate) p: Vec<f64>,
}

impl Net {
    /// The value at (u, v): each row's Bézier in v by de Casteljau, then the
    /// column of those in u.
    pub(crate) fn eval(&self, u: f64, v: f64) -> f64 {
        if self.cols == 0 {
            return 0.0;
        }
        let column: Vec<f64> = self
            .p
            .chunks(self.cols)
            .map(|row| de_casteljau(row, v))
            .collect();
        de_casteljau(&column, u)
    }

    /// Row i (the Bézier in v at u = i/m's control points).
    pub(crate) fn row(&self, i: usize) -> &[f64] {
        &self.p[i * self.cols..(i + 1) * self.cols]
    }

    /// Column j.
    pub(crate) fn column(&self, j: usize) -> Vec<f64> {
        (0..self.rows).map(|i| self.p[i * self.cols + j]).collect()
    }

    /// ∂/∂u: m (P_{i+1,j} − P_ij), an m × (n + 1) net.
    pub(crate) fn d_u(&self) -> Net {
        let m = self.rows.saturating_sub(1);
        let p = (0..m)
            .flat_map(|i| (0..self.cols).map(move |j| (i, j)))
            .map(|(i, j)| m as f64 * (self.p[(i + 1) * self.cols + j] - self.p[i * self.cols + j]))
            .collect();
        Net {
            rows: m,
            cols: if m == 0 { 0 } else { self.cols },
            p,
        }
    }

    /// ∂/∂v: n (P_{i,j+1} − P_ij), an (m + 1) × n net.
    pub(crate) fn d_v(&self) -> Net {
        let n = self.cols.saturating_sub(1);
        let p = (0..self.rows)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, j)| n as f64 * (self.p[i * self.cols + j + 1] - self.p[i * self.cols + j]))
            .collect();
        Net {
            rows: if n == 0 { 0 } else { self.rows },
            cols: n,
            p,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 × 3 net's value and derivatives against its polynomial, written out
    /// in the power basis: P_ij = i·j gives u·v exactly (linear precision in
    /// each direction: Σ (i/m) B_i^m = u), so P_ij = m·n·(i/m)(j/n).
    #[test]
    fn the_product_uv_and_its_derivatives() {
        let (m, n) = (2, 3);
        let p = (0..=m)
            .flat_map(|i| (0..=n).map(move |j| (i as f64 / m as f64) * (j as f64 / n as f64)))
            .collect();
        let net = Net {
            rows: m + 1,
            cols: n + 1,
            p,
        };
        for (u, v) in [(0.2, 0.7), (0.9, 0.1), (0.5, 0.5)] {
            assert!((net.eval(u, v) - u * v).abs() < 1e-15);
            assert!((net.d_u().eval(u, v) - v).abs() < 1e-14);
            assert!((net.d_v().eval(u, v) - u).abs() < 1e-14);
            assert!((net.d_u().d_v().eval(u, v) - 1.0).abs() < 1e-14);
            assert!(net.d_u().d_u().eval(u, v).abs() < 1e-14);
        }
    }

    /// A net of one column has a zero v-derivative.
    #[test]
    fn degree_zero_derivative_is_zero() {
        let net = Net {
            rows: 2,
            cols: 1,
            p: vec![1.0, 3.0],
        };
        assert_eq!(net.d_v().eval(0.3, 0.3), 0.0);
        assert!((net.d_u().eval(0.3, 0.3) - 2.0).abs() < 1e-15);
    }
}
