//! The mould (Arnal and Monterde 2014): the inner control points of a harmonic
//! tensor-product Bézier patch as one fixed linear combination of two opposite
//! boundary rows, computed once per degree by a linear solve.
//!
//! Index convention (the one for which the paper's n = 3 values hold, checked
//! in the tests): the patch is x(u, v) = Σ_{i=0}^{m} Σ_{j=0}^{n} P_ij
//! B_i^m(u) B_j^n(v); the prescribed rows are P_{0,j} (u = 0) and P_{m,j}
//! (u = 1), j = 0…n; the unknowns are P_ij for i = 1…m − 1. m = n (square)
//! or m = n + 1 (raised, for even n).
//!
//! The harmonic condition Δx = x_uu + x_vv = 0 in the Bernstein basis: x_uu
//! has bidegree (m − 2, n), x_vv (m, n − 2); raised to (m, n), the coefficient
//! of B_k^m(u) B_l^n(v) in Δx is
//!
//! E_kl = (m−k)(m−k−1) Δ²_u P_{k,l} + 2k(m−k) Δ²_u P_{k−1,l} + k(k−1) Δ²_u P_{k−2,l}
//!      + (n−l)(n−l−1) Δ²_v P_{k,l} + 2l(n−l) Δ²_v P_{k,l−1} + l(l−1) Δ²_v P_{k,l−2},
//!
//! with Δ²_u P_{a,l} = P_{a,l} − 2P_{a+1,l} + P_{a+2,l} (and Δ²_v likewise in
//! the second index); terms whose index leaves [0, m − 2] (or [0, n − 2]) have
//! weight 0. (The weights are m(m−1) C(m−2, a) C(2, k−a) / C(m, k), the degree
//! elevation of B_a^{m−2}.) Δx = 0 is E_kl = 0 for all (m + 1)(n + 1) pairs.
//! Split into inner and boundary unknowns, A_in X = −A_bd B; the mould is
//! M = −A_in⁺ A_bd, solved by Householder QR (faer) in the least-squares sense.
//! For odd n (m = n) and for m = n + 1 the system is consistent for every B
//! and has full column rank, so M is unique. For even n with m = n it is
//! consistent only when Δⁿ row0 = Δⁿ row1; there M is the least-squares
//! mould, exact on every pair of rows that satisfies the condition.

use super::error::{HarmonicError, MouldFault};
use faer::linalg::solvers::SolveLstsq;
use faer::Mat;

/// The largest degree accepted: above it f64 loses the mould's row sums
/// (measured with `cargo run --release --example harmonic_rowsums`;
/// docs/method.md §14).
pub const MAX_DEGREE: usize = 10;

/// The largest accepted |Σ_c M_rc − 1| over the rows of a mould. Every row
/// must sum to 1 exactly (a constant is harmonic, so equal heights must give
/// equal heights); 1e-9 of the heights is far below a machine's resolution.
pub const ROW_SUM_LIMIT: f64 = 1e-9;

/// Which harmonic patch a degree n gives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// n × n: unique for odd n; for even n only when the rows' n-th
    /// differences agree.
    Square,
    /// (n + 1) × n: degree n + 1 across the rows (even n only); takes any
    /// two rows.
    Raised,
}

impl Form {
    /// The degree across the rows (m) for row degree n.
    pub(crate) fn across(self, degree: usize) -> usize {
        match self {
            Form::Square => degree,
            Form::Raised => degree + 1,
        }
    }

    /// The form's name as in a job file.
    pub fn name(self) -> &'static str {
        match self {
            Form::Square => "square",
            Form::Raised => "raised",
        }
    }
}

/// The mould of one degree and form: `rows()` = (m − 1)(n + 1) inner control
/// points, each a combination of the `columns()` = 2(n + 1) boundary points
/// (P_00 … P_0n | P_m0 … P_mn).
#[derive(Clone, Debug, PartialEq)]
pub struct Mould {
    /// n, the degree along the rows.
    pub degree: usize,
    /// m, the degree across the rows.
    pub across: usize,
    /// The form.
    pub form: Form,
    /// Row-major coefficients.
    coefficients: Vec<f64>,
    /// max over rows of |Σ_c M_rc − 1|.
    pub row_sum_error: f64,
    /// max |A_in M + A_bd| / max |A| (None for an even square mould, whose
    /// system is consistent only on part of the rows' space).
    pub residual: Option<f64>,
}

impl Mould {
    /// Number of inner control points, (m − 1)(n + 1).
    pub fn rows(&self) -> usize {
        (self.across - 1) * (self.degree + 1)
    }

    /// Number of boundary control points, 2(n + 1).
    pub(crate) fn columns(&self) -> usize {
        2 * (self.degree + 1)
    }

    /// The coefficients of inner point number `r` (see [`Mould::inner_index`]).
    pub fn row(&self, r: usize) -> &[f64] {
        let c = self.columns();
        &self.coefficients[r * c..(r + 1) * c]
    }

    /// The (i, j) of inner point number r: i = 1 + r / (n + 1), j = r mod (n + 1).
    pub fn inner_index(&self, r: usize) -> (usize, usize) {
        (1 + r / (self.degree + 1), r % (self.degree + 1))
    }

    /// The coefficients of P_ij for 1 ≤ i ≤ m − 1, j ≤ n.
    pub fn point(&self, i: usize, j: usize) -> Option<&[f64]> {
        (i >= 1 && i < self.across && j <= self.degree)
            .then(|| self.row((i - 1) * (self.degree + 1) + j))
    }

    /// The full control net, row-major (m + 1) × (n + 1), from the two rows
    /// (each of length n + 1; the caller checks the lengths).
    pub fn net(&self, row0: &[f64], row1: &[f64]) -> Vec<f64> {
        let boundary: Vec<f64> = row0.iter().chain(row1).copied().collect();
        let mut net = row0.to_vec();
        for r in 0..self.rows() {
            net.push(self.row(r).iter().zip(&boundary).map(|(a, b)| a * b).sum());
        }
        net.extend_from_slice(row1);
        net
    }
}

/// The mould of `degree` and `form`, refused above [`MAX_DEGREE`] (with the
/// row-sum error measured at MAX_DEGREE + 1 as the reason) and checked: rows
/// summing to 1 within [`ROW_SUM_LIMIT`].
pub fn mould(degree: usize, form: Form) -> Result<Mould, HarmonicError> {
    if degree == 0 {
        return Err(HarmonicError::DegreeTooLow { degree });
    }
    if form == Form::Raised && degree % 2 == 1 {
        return Err(HarmonicError::RaisedOddDegree { degree });
    }
    if degree > MAX_DEGREE {
        let first_bad = MAX_DEGREE + 1;
        let error = solve_mould(first_bad, Form::Square)?.row_sum_error;
        return Err(HarmonicError::DegreeAboveCap {
            degree,
            cap: MAX_DEGREE,
            first_bad,
            error,
            limit: ROW_SUM_LIMIT,
        });
    }
    let m = solve_mould(degree, form)?;
    if m.row_sum_error.is_nan() || m.row_sum_error > ROW_SUM_LIMIT {
        return Err(HarmonicError::Internal {
            degree,
            what: MouldFault::RowSum {
                error: m.row_sum_error,
            },
        });
    }
    Ok(m)
}

/// The mould without the cap or the row-sum check (for measuring them):
/// builds E_kl = 0, solves A_in M = −A_bd by QR. Errors only if A_in is
/// rank deficient (a bug). `degree` must be ≥ 1; keep it small (the system
/// has (m + 1)² (n + 1)² entries).
pub fn solve_mould(degree: usize, form: Form) -> Result<Mould, HarmonicError> {
    let (n, m) = (degree, form.across(degree));
    let a = laplacian_system(m, n);
    let w = n + 1;
    let inner: Vec<usize> = (w..m * w).collect();
    let boundary: Vec<usize> = (0..w).chain(m * w..(m + 1) * w).collect();
    let eqs = a.nrows();
    let a_in = Mat::<f64>::from_fn(eqs, inner.len(), |r, c| a[(r, inner[c])]);
    let rhs = Mat::<f64>::from_fn(eqs, boundary.len(), |r, c| -a[(r, boundary[c])]);
    let x = if inner.is_empty() {
        Mat::<f64>::zeros(0, boundary.len())
    } else {
        solve_full_rank(&a_in, &rhs, degree)?
    };
    let coefficients: Vec<f64> = (0..x.nrows())
        .flat_map(|r| (0..x.ncols()).map(move |c| (r, c)))
        .map(|(r, c)| x[(r, c)])
        .collect();
    let row_sum_error = (0..x.nrows())
        .map(|r| ((0..x.ncols()).map(|c| x[(r, c)]).sum::<f64>() - 1.0).abs())
        .fold(0.0, crate::num::max_or_nan);
    let unique = !(form == Form::Square && n % 2 == 0);
    let residual = unique.then(|| relative_residual(&a_in, &x, &rhs));
    Ok(Mould {
        degree: n,
        across: m,
        form,
        coefficients,
        row_sum_error,
        residual,
    })
}

/// QR least squares of A X = B, refusing a rank-deficient A (|R_kk| below
/// 1e-12 of the largest: the theory says A_in has full column rank).
fn solve_full_rank(a: &Mat<f64>, b: &Mat<f64>, degree: usize) -> Result<Mat<f64>, HarmonicError> {
    faer::set_global_parallelism(faer::Par::Seq);
    let qr = a.qr();
    let r = qr.thin_R();
    let diag: Vec<f64> = (0..r.ncols()).map(|k| r[(k, k)].abs()).collect();
    let big = diag.iter().copied().fold(0.0, f64::max);
    let small = diag.iter().copied().fold(f64::INFINITY, f64::min);
    if small.is_nan() || big.is_nan() || small <= 1e-12 * big {
        return Err(HarmonicError::Internal {
            degree,
            what: MouldFault::RankDeficient { small, big },
        });
    }
    Ok(qr.solve_lstsq(b))
}

/// max |A X − B| / (max |A| · max(1, max |X|)).
fn relative_residual(a: &Mat<f64>, x: &Mat<f64>, b: &Mat<f64>) -> f64 {
    let ax = a * x;
    let mut worst = 0.0_f64;
    for r in 0..b.nrows() {
        for c in 0..b.ncols() {
            worst = crate::num::max_or_nan(worst, (ax[(r, c)] - b[(r, c)]).abs());
        }
    }
    let amax = (0..a.nrows())
        .flat_map(|r| (0..a.ncols()).map(move |c| (r, c)))
        .fold(0.0_f64, |s, (r, c)| s.max(a[(r, c)].abs()));
    let xmax = (0..x.nrows())
        .flat_map(|r| (0..x.ncols()).map(move |c| (r, c)))
        .fold(1.0_f64, |s, (r, c)| s.max(x[(r, c)].abs()));
    worst / (amax.max(1.0) * xmax)
}

/// The matrix of E_kl (rows k(n + 1) + l) on all control points (columns
/// i(n + 1) + j), bidegree (m, n): the module doc's formula, integer entries.
pub(crate) fn laplacian_system(m: usize, n: usize) -> Mat<f64> {
    let w = n + 1;
    let mut a = Mat::<f64>::zeros((m + 1) * w, (m + 1) * w);
    for k in 0..=m {
        for l in 0..=n {
            let row = k * w + l;
            for (a_idx, weight) in elevation_weights(m, k) {
                for (d, c) in [(0, 1.0), (1, -2.0), (2, 1.0)] {
                    a[(row, (a_idx + d) * w + l)] += weight * c;
                }
            }
            for (b_idx, weight) in elevation_weights(n, l) {
                for (d, c) in [(0, 1.0), (1, -2.0), (2, 1.0)] {
                    a[(row, k * w + b_idx + d)] += weight * c;
                }
            }
        }
    }
    a
}

/// The second differences a (0 ≤ a ≤ p − 2) that enter the coefficient of
/// B_k^p in p(p−1) Σ_a Δ²c_a B_a^{p−2} raised to degree p, with their weights
/// (a = k: (p−k)(p−k−1); a = k − 1: 2k(p−k); a = k − 2: k(k−1)).
fn elevation_weights(p: usize, k: usize) -> Vec<(usize, f64)> {
    if p < 2 {
        return Vec::new();
    }
    let (pf, kf) = (p as f64, k as f64);
    let mut out = Vec::with_capacity(3);
    if k <= p - 2 {
        out.push((k, (pf - kf) * (pf - kf - 1.0)));
    }
    if k >= 1 && k - 1 <= p - 2 {
        out.push((k - 1, 2.0 * kf * (pf - kf)));
    }
    if k >= 2 {
        out.push((k - 2, kf * (kf - 1.0)));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::polynomials::{bernstein_net, re_im_power};
    use super::*;

    /// A bug report's cause reads as the string it was.
    #[test]
    fn mould_faults_say_what_the_strings_said() {
        let (small, big) = (1.5e-14, 2.0);
        let e = HarmonicError::Internal {
            degree: 7,
            what: MouldFault::RankDeficient { small, big },
        };
        assert_eq!(
            e.to_string(),
            format!("harmonic mould of degree 7: the inner system is rank deficient (|R_kk| from {small:.1e} to {big:.1e}) (this is a bug in pfcam; please report it)")
        );
    }

    /// A p for the net p of a polynomial.
    fn laplacian_coefficients(m: usize, n: usize, poly: &[(usize, usize, f64)]) -> Vec<f64> {
        let a = laplacian_system(m, n);
        let p = bernstein_net(poly, m, n);
        (0..a.nrows())
            .map(|r| (0..a.ncols()).map(|c| a[(r, c)] * p[c]).sum())
            .collect()
    }

    /// E_kl, checked on its own (no solve): the E_kl are the Bernstein
    /// coefficients of Δx itself, so they vanish on harmonic nets, are 2
    /// everywhere for u² (Δ = 2), and 2k/m for u v² (Δ = 2u).
    #[test]
    fn the_equations_are_the_bernstein_coefficients_of_the_laplacian() {
        for (m, n) in [(3, 3), (5, 4), (4, 4), (2, 5)] {
            for k in 0..=m.min(n) {
                for imag in [false, true] {
                    let e = laplacian_coefficients(m, n, &re_im_power(k, imag));
                    assert!(e.iter().all(|x| x.abs() < 1e-12), "{m} {n} {k} {imag}");
                }
            }
            let e = laplacian_coefficients(m, n, &[(2, 0, 1.0)]);
            assert!(e.iter().all(|x| (x - 2.0).abs() < 1e-12), "{m} {n}: {e:?}");
            let e = laplacian_coefficients(m, n, &[(1, 2, 1.0)]);
            // Δ(u v²) = 2u: coefficients 2k/m in the k index.
            let w = n + 1;
            for (r, x) in e.iter().enumerate() {
                assert!((x - 2.0 * (r / w) as f64 / m as f64).abs() < 1e-12);
            }
        }
    }
}
