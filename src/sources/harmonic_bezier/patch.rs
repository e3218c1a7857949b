//! A harmonic Bézier patch as a height field over a rectangle in mm.
//!
//! Coordinates: the patch covers 0 ≤ x ≤ X, 0 ≤ y ≤ Y (`size = [X, Y]`). The
//! rows run along x: `row0` is the edge y = 0 and `row1` the edge y = Y, each
//! n + 1 heights at x = jX/n. In the mould's parameters u = y/Y (across the
//! rows, index i, degree m) and v = x/X (along them, index j, degree n):
//!
//! h(x, y) = Σ_{i=0}^{m} Σ_{j=0}^{n} P_ij B_i^m(y/Y) B_j^n(x/X),
//!
//! with P_{0,j} = `row0[j]`, P_{m,j} = `row1[j]` and the inner P_ij from the
//! mould. The patch is harmonic in the parameter plane, h_uu + h_vv = 0; in
//! mm, h_yy Y² + h_xx X² = 0 (harmonic in (x, y) itself only when X = Y).
//! Because Bézier nets have linear precision, the 3D points (jX/n, iY/m,
//! P_ij) are the control net of the same surface as a parametric patch.

use super::bernstein::forward_difference;
use super::error::HarmonicError;
use super::mould::{mould, Form};
use super::net::Net;

/// The heights and derivatives at one point of the parameter square.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamDerivatives {
    /// h, mm.
    pub h: f64,
    /// ∂h/∂u (mm per unit parameter; u = y/Y).
    pub h_u: f64,
    /// ∂h/∂v (v = x/X).
    pub h_v: f64,
    /// ∂²h/∂u².
    pub h_uu: f64,
    /// ∂²h/∂v².
    pub h_vv: f64,
    /// ∂²h/∂u∂v.
    pub h_uv: f64,
}

/// The relative tolerance of the even square patch's condition Δⁿrow0 =
/// Δⁿrow1: |Δⁿrow0 − Δⁿrow1| ≤ 1e-9 · 2ⁿ · max(1, max |height|) (the n-th
/// difference sums 2ⁿ weighted heights, so its rounding scales with 2ⁿ).
pub(crate) const EVEN_DIFFERENCE_TOL: f64 = 1e-9;

/// A harmonic patch: its net and the nets of its derivatives.
#[derive(Clone, Debug, PartialEq)]
pub struct HarmonicPatch {
    /// n, the degree along the rows.
    pub degree: usize,
    /// The form (m = n or n + 1 across the rows).
    pub form: Form,
    /// [X, Y], mm.
    pub size: [f64; 2],
    net: Net,
    d_u: Net,
    d_v: Net,
    d_uu: Net,
    d_vv: Net,
    d_uv: Net,
}

impl HarmonicPatch {
    /// The patch through `row0` (y = 0) and `row1` (y = Y), each degree + 1
    /// heights in mm, over `size` = [X, Y] mm. Errors name the job key.
    pub fn new(
        degree: usize,
        form: Form,
        size: [f64; 2],
        row0: &[f64],
        row1: &[f64],
    ) -> Result<HarmonicPatch, HarmonicError> {
        let [x, y] = size;
        if !(x.is_finite() && y.is_finite() && x > 0.0 && y > 0.0) {
            return Err(HarmonicError::Size { x, y });
        }
        // The degree first: it bounds degree + 1 below.
        let mould = mould(degree, form)?;
        check_row("shape.row0", degree, row0)?;
        check_row("shape.row1", degree, row1)?;
        if form == Form::Square && degree % 2 == 0 {
            check_even_rows(degree, row0, row1)?;
        }
        let net = Net {
            rows: mould.across + 1,
            cols: degree + 1,
            p: mould.net(row0, row1),
        };
        Ok(Self::from_net(degree, form, size, net))
    }

    fn from_net(degree: usize, form: Form, size: [f64; 2], net: Net) -> HarmonicPatch {
        let (d_u, d_v) = (net.d_u(), net.d_v());
        HarmonicPatch {
            degree,
            form,
            size,
            d_uu: d_u.d_u(),
            d_vv: d_v.d_v(),
            d_uv: d_u.d_v(),
            d_u,
            d_v,
            net,
        }
    }

    /// m, the degree across the rows.
    pub fn across(&self) -> usize {
        self.net.rows - 1
    }

    /// The control net as heights, row-major (m + 1) × (n + 1): P_ij at
    /// `[i * (n + 1) + j]`.
    pub fn heights(&self) -> &[f64] {
        &self.net.p
    }

    /// The control net in mm: (jX/n, iY/m, P_ij), row-major as [`heights`](Self::heights).
    pub fn control_points(&self) -> Vec<[f64; 3]> {
        let (m, n) = (self.across() as f64, self.degree as f64);
        let [sx, sy] = self.size;
        let w = self.degree + 1;
        (0..self.net.p.len())
            .map(|k| {
                let (i, j) = ((k / w) as f64, (k % w) as f64);
                [sx * j / n, sy * i / m, self.net.p[k]]
            })
            .collect()
    }

    /// h at (x, y) mm. Outside the rectangle this is the polynomial continued.
    pub fn height(&self, x: f64, y: f64) -> f64 {
        self.net.eval(y / self.size[1], x / self.size[0])
    }

    /// ∇h = (∂h/∂x, ∂h/∂y) at (x, y), mm per mm.
    pub fn gradient(&self, x: f64, y: f64) -> [f64; 2] {
        let (u, v) = (y / self.size[1], x / self.size[0]);
        [
            self.d_v.eval(u, v) / self.size[0],
            self.d_u.eval(u, v) / self.size[1],
        ]
    }

    /// h and its derivatives in the parameters (u, v) = (y/Y, x/X).
    pub fn param_derivatives(&self, u: f64, v: f64) -> ParamDerivatives {
        ParamDerivatives {
            h: self.net.eval(u, v),
            h_u: self.d_u.eval(u, v),
            h_v: self.d_v.eval(u, v),
            h_uu: self.d_uu.eval(u, v),
            h_vv: self.d_vv.eval(u, v),
            h_uv: self.d_uv.eval(u, v),
        }
    }

    /// The net, for the range search.
    pub(super) fn net(&self) -> &Net {
        &self.net
    }
}

/// A row must have degree + 1 finite heights.
fn check_row(key: &'static str, degree: usize, row: &[f64]) -> Result<(), HarmonicError> {
    if row.len() != degree + 1 {
        return Err(HarmonicError::RowLength {
            key,
            degree,
            expected: degree + 1,
            got: row.len(),
        });
    }
    match row.iter().position(|h| !h.is_finite()) {
        Some(index) => Err(HarmonicError::NotFinite {
            key,
            index,
            value: row[index],
        }),
        None => Ok(()),
    }
}

/// An even square patch needs Δⁿrow0 = Δⁿrow1 (the coefficient of vⁿ is the
/// same along both rows: a harmonic polynomial of bidegree (n, n), n even,
/// has no u·vⁿ term), within [`EVEN_DIFFERENCE_TOL`].
fn check_even_rows(degree: usize, row0: &[f64], row1: &[f64]) -> Result<(), HarmonicError> {
    let (d0, d1) = (
        forward_difference(row0, degree),
        forward_difference(row1, degree),
    );
    let scale = row0.iter().chain(row1).fold(1.0_f64, |a, h| a.max(h.abs()));
    let tolerance = EVEN_DIFFERENCE_TOL * 2f64.powi(degree as i32) * scale;
    if (d0 - d1).abs() <= tolerance {
        Ok(())
    } else {
        Err(HarmonicError::EvenRowsDisagree {
            degree,
            d0,
            d1,
            tolerance,
        })
    }
}
