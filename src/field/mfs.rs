//! The method of fundamental solutions: u_N(P) = Σ cₙ k(P, Qₙ) with the kernel
//! k(P, Q) = −(1/2π) log|P − Q| (the paper's (2.3)–(2.4)), coefficients from an
//! overdetermined least-squares fit at collocation points.

use super::FieldError;
use crate::geometry::Vec2;
use faer::linalg::solvers::SolveLstsq;
use faer::Mat;

const INV_2PI: f64 = 1.0 / std::f64::consts::TAU;

/// Estimated condition number (ratio of the largest to smallest |Rᵢᵢ| of the
/// Householder QR of the column-scaled matrix, a lower bound of the true one)
/// up to which the plain least-squares solution is used. Past it (or with a
/// non-finite column: a charge on a collocation point) the solve does not
/// refuse: it falls back to the ridge QR ([`RIDGE_PER_ROW`]), then to a
/// rank-revealing QR truncated at [`RANK_CUTOFF`], and marks the solution
/// as not well-conditioned, which the distance and
/// layout searches take only when nothing better is found. The measured
/// boundary error on the check points is the guard, never this estimate.
pub const MAX_CONDITION: f64 = 1e15;

/// Relative cut-off of the fallback's column-pivoted QR: columns whose |Rₖₖ|
/// falls below this fraction of |R₀₀| are left out of the fit (coefficient 0):
/// what they would add is already in the span of the others to working
/// precision, and solving for them would turn rounding into huge coefficients.
pub const RANK_CUTOFF: f64 = 1e-15;

/// The fundamental solution k(P, Q) = −(1/2π) log|P − Q| (paper (2.3)).
#[inline]
pub fn kernel(p: Vec2, q: Vec2) -> f64 {
    -INV_2PI * 0.5 * (p - q).norm2().ln()
}

/// A point where a boundary value is imposed (or checked).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Condition {
    /// The point.
    pub p: Vec2,
    /// The value u must take there.
    pub value: f64,
}

/// A discretised MFS problem: singularities, collocation points, check points.
#[derive(Clone, Debug, Default)]
pub struct Problem {
    /// Singularities Qₙ, outside the domain.
    pub charges: Vec<Vec2>,
    /// Collocation points Pₘ with their boundary values.
    pub colloc: Vec<Condition>,
    /// Check points (between collocation points, and every corner) on which the
    /// max boundary error is measured; never used in the fit.
    pub checks: Vec<Condition>,
    /// Charges the layout's guard moved off a collocation or check point
    /// (`setup::MIN_SEPARATION`); 0 when the layout kept them apart itself.
    pub moved: usize,
}

/// A solved potential field u(P) = gain · Σ cₙ k(P, Qₙ), optionally with
/// local expansions for fast evaluation ([`Field::accelerated`]).
#[derive(Clone, Debug)]
pub struct Field {
    charges: Vec<Vec2>,
    coef: Vec<f64>,
    gain: f64,
    accel: Option<std::sync::Arc<super::fast::Accel>>,
}

impl PartialEq for Field {
    /// The same field: same charges, coefficients and gain (how it is
    /// evaluated does not matter).
    fn eq(&self, o: &Field) -> bool {
        self.charges == o.charges && self.coef == o.coef && self.gain == o.gain
    }
}

/// The result of a solve.
#[derive(Clone, Debug)]
pub struct Solution {
    /// The field.
    pub field: Field,
    /// max |u − g| over the check points.
    pub max_error: f64,
    /// The estimated condition number of the scaled system.
    pub condition: f64,
    /// Whether the plain least-squares solution was used (condition below
    /// [`MAX_CONDITION`]); false for the truncated fallback.
    pub well_conditioned: bool,
    /// Charges the layout's guard moved off a collocation or check point
    /// ([`Problem::moved`]).
    pub moved: usize,
    /// The check points `max_error` was measured on, and the error at each
    /// (where the error is mapped, `levels::accuracy`).
    pub checks: Vec<Condition>,
    /// |u − g| at each of `checks`.
    pub errors: Vec<f64>,
}

impl Solution {
    /// Whether `self` is a better fit than `other`: a well-conditioned solution
    /// before one from the fallback, then the smaller max boundary error.
    pub fn better_than(&self, other: &Solution) -> bool {
        match (self.well_conditioned, other.well_conditioned) {
            (true, false) => true,
            (false, true) => false,
            _ => self.max_error < other.max_error,
        }
    }
}

impl Field {
    /// A field from charges and coefficients (tests build analytic fields this way).
    pub fn new(charges: Vec<Vec2>, coef: Vec<f64>) -> Field {
        Field {
            charges,
            coef,
            gain: 1.0,
            accel: None,
        }
    }

    /// The field times `k` (the same charges and expansions, a gain of k).
    pub fn scaled(&self, k: f64) -> Field {
        Field {
            gain: self.gain * k,
            ..self.clone()
        }
    }

    /// The same field, evaluated inside [lo, hi] from local expansions in
    /// boxes of side `box_size` (mm), built as they are first needed, plus
    /// direct sums over the charges near each box (`field::fast`); outside
    /// it, directly. Within 1e-15 of the direct sums before rounding.
    pub fn accelerated(&self, lo: Vec2, hi: Vec2, box_size: f64) -> Field {
        Field {
            accel: Some(std::sync::Arc::new(super::fast::Accel::new(
                lo, hi, box_size,
            ))),
            ..self.clone()
        }
    }

    /// [`accelerated`](Self::accelerated) over the box `lo`–`hi` grown by half
    /// its diagonal on every side (where levels, stock and previews look), in
    /// boxes of 1/[`BOXES_PER_DIAGONAL`](super::fast::BOXES_PER_DIAGONAL) of
    /// the diagonal.
    pub fn accelerated_around(&self, lo: Vec2, hi: Vec2) -> Field {
        let diag = (hi - lo).norm();
        if !(diag.is_finite() && diag > 0.0) {
            return self.clone();
        }
        let pad = Vec2::new(0.5 * diag, 0.5 * diag);
        self.accelerated(lo - pad, hi + pad, diag / super::fast::BOXES_PER_DIAGONAL)
    }

    /// The same field without expansions (every evaluation a direct sum).
    pub fn direct(&self) -> Field {
        Field {
            accel: None,
            ..self.clone()
        }
    }

    /// Σ c log|P − Q| and Σ c (P − Q)/|P − Q|², by the expansions when there
    /// are some for P.
    fn sums(&self, p: Vec2) -> (f64, Vec2) {
        if let Some(r) = self
            .accel
            .as_ref()
            .and_then(|a| a.sums(&self.charges, &self.coef, p))
        {
            return r;
        }
        crate::count::eval(self.charges.len(), 0);
        let (mut s, mut gx, mut gy) = (0.0, 0.0, 0.0);
        for (q, c) in self.charges.iter().zip(&self.coef) {
            let d = p - *q;
            let r2 = d.norm2();
            s += c * r2.ln();
            let w = c / r2;
            gx += w * d.x;
            gy += w * d.y;
        }
        (0.5 * s, Vec2::new(gx, gy))
    }

    /// Number of singularities N.
    pub fn n(&self) -> usize {
        self.charges.len()
    }

    /// The singularities.
    pub fn charges(&self) -> &[Vec2] {
        &self.charges
    }

    /// u(P).
    pub fn value(&self, p: Vec2) -> f64 {
        if self.accel.is_some() {
            return -INV_2PI * self.gain * self.sums(p).0;
        }
        crate::count::eval(self.charges.len(), 0);
        let mut s = 0.0;
        for (q, c) in self.charges.iter().zip(&self.coef) {
            s += c * (p - *q).norm2().ln();
        }
        -INV_2PI * 0.5 * self.gain * s
    }

    /// ∇u(P) = −(1/2π) Σ cₙ (P − Qₙ)/|P − Qₙ|²: in complex form the conjugate of
    /// −(1/2π) Σ cₙ/(z − qₙ), which needs no logarithm.
    pub fn grad(&self, p: Vec2) -> Vec2 {
        if self.accel.is_some() {
            return self.sums(p).1 * (-INV_2PI * self.gain);
        }
        crate::count::eval(self.charges.len(), 0);
        let (mut gx, mut gy) = (0.0, 0.0);
        for (q, c) in self.charges.iter().zip(&self.coef) {
            let d = p - *q;
            let w = c / d.norm2();
            gx += w * d.x;
            gy += w * d.y;
        }
        Vec2::new(-INV_2PI * self.gain * gx, -INV_2PI * self.gain * gy)
    }

    /// u at each of `ps`, into `out` (as far as the shorter of the two
    /// goes): [`Field::value`]'s bits, faster for
    /// runs of nearby points (a grid's row): their expansions are summed side
    /// by side ([`super::fast::Accel::sums_many`]).
    pub fn values(&self, ps: &[Vec2], out: &mut [f64]) {
        let Some(accel) = &self.accel else {
            for (o, &p) in out.iter_mut().zip(ps) {
                *o = self.value(p);
            }
            return;
        };
        let mut sums = vec![None; ps.len()];
        accel.sums_many(&self.charges, &self.coef, ps, &mut sums);
        for ((o, &p), r) in out.iter_mut().zip(ps).zip(sums) {
            // As `value`: the direct sums where the expansions have none.
            let s = r.map_or_else(|| self.sums(p).0, |r| r.0);
            *o = -INV_2PI * self.gain * s;
        }
    }

    /// u at `at(i)` into `out[i]` for every i where `skip[i]` is false (a
    /// row of a grid, without its points in the material); the others, and
    /// any i past `skip`'s end, are left as they are. The bits of
    /// [`Field::value`], by [`Field::values`].
    pub fn values_where(&self, out: &mut [f64], skip: &[bool], at: impl Fn(usize) -> Vec2) {
        let (idx, ps): (Vec<usize>, Vec<Vec2>) = (0..out.len().min(skip.len()))
            .filter(|&i| !skip[i])
            .map(|i| (i, at(i)))
            .unzip();
        let mut vs = vec![0.0; ps.len()];
        self.values(&ps, &mut vs);
        for (i, v) in idx.into_iter().zip(vs) {
            out[i] = v;
        }
    }

    /// u(P) and ∇u(P) together.
    pub fn value_grad(&self, p: Vec2) -> (f64, Vec2) {
        let (s, g) = self.sums(p);
        let k = -INV_2PI * self.gain;
        (k * s, g * k)
    }

    /// The Hessian [[u_xx, u_xy], [u_xy, u_yy]] (u_yy = −u_xx: u is harmonic).
    pub fn hessian(&self, p: Vec2) -> [[f64; 2]; 2] {
        crate::count::eval(self.charges.len(), 0);
        let (mut hxx, mut hxy) = (0.0, 0.0);
        for (q, c) in self.charges.iter().zip(&self.coef) {
            let d = p - *q;
            let r2 = d.norm2();
            let r4 = r2 * r2;
            hxx += c * (d.y * d.y - d.x * d.x) / r4;
            hxy += c * (-2.0 * d.x * d.y) / r4;
        }
        let hxx = -INV_2PI * self.gain * hxx;
        let hxy = -INV_2PI * self.gain * hxy;
        [[hxx, hxy], [hxy, -hxx]]
    }
}

/// Solve the problem in the least-squares sense (paper, Section 2: M > N).
///
/// The columns are scaled to unit Euclidean norm before a Householder QR (faer),
/// which makes the |Rᵢᵢ| ratio a fair condition estimate and keeps charges at very
/// different distances on an equal footing.
pub fn solve(problem: &Problem) -> Result<Solution, FieldError> {
    let points: Vec<Vec2> = problem.colloc.iter().map(|c| c.p).collect();
    let rhs: Vec<f64> = problem.colloc.iter().map(|c| c.value).collect();
    let (factor, coef) = Factor::new(&problem.charges, &points, &rhs)?;
    let field = Field::new(problem.charges.clone(), coef);
    let errors = check_errors(&field, &problem.checks);
    let max_error = largest(&errors);
    if !max_error.is_finite() {
        return Err(FieldError::NotANumberAtCheck);
    }
    Ok(Solution {
        field,
        max_error,
        condition: factor.condition,
        well_conditioned: factor.well_conditioned,
        moved: problem.moved,
        checks: problem.checks.clone(),
        errors,
    })
}

/// The least-squares factorisation of the column-scaled kernel matrix of
/// charges × points, kept for more right-hand sides (the letter blocks of
/// `field::blocks` solve their own block many times).
pub(crate) struct Factor {
    kind: FactorKind,
    scale: Vec<f64>,
    /// The estimated condition number of the scaled system.
    pub(crate) condition: f64,
    /// Whether the plain least-squares solution is used.
    pub(crate) well_conditioned: bool,
}

enum FactorKind {
    Plain(faer::linalg::solvers::Qr<f64>),
    Truncated(faer::linalg::solvers::ColPivQr<f64>, usize),
    /// The QR of the kernel matrix over λI ([`ridge`]), and the kernel
    /// matrix's row count (the right-hand side is padded with zeros).
    Ridge(faer::linalg::solvers::Qr<f64>, usize),
}

impl Factor {
    /// Factor the kernel matrix and solve it for `rhs`: the plain QR when its
    /// condition estimate is below [`MAX_CONDITION`] and its solution finite,
    /// else the ridge QR ([`ridge`]), and only if that too gives a
    /// non-finite solution, the truncated column-pivoted QR. Returns the
    /// factor and the coefficients.
    pub(crate) fn new(
        charges: &[Vec2],
        points: &[Vec2],
        rhs: &[f64],
    ) -> Result<(Factor, Vec<f64>), FieldError> {
        let (m, n) = (points.len(), charges.len());
        if n == 0 || m < n {
            return Err(FieldError::TooFewCollocationPoints { m, n });
        }
        let (a, scale) = scaled_matrix(charges, points);
        // Sequential QR: the result must not depend on the thread count (same job,
        // same G-code); pfcam parallelises over whole solves and loops instead.
        faer::set_global_parallelism(faer::Par::Seq);
        let qr = a.qr();
        let condition = crate::num::triangular_condition(qr.thin_R());
        if condition < MAX_CONDITION {
            let factor = Factor {
                kind: FactorKind::Plain(qr),
                scale: scale.clone(),
                condition,
                well_conditioned: true,
            };
            let coef = factor.solve(rhs);
            if coef.iter().all(|c| c.is_finite()) {
                return Ok((factor, coef));
            }
        } else {
            drop(qr);
        }
        let (qr, condition) = ridge(&a);
        let mut factor = Factor {
            kind: FactorKind::Ridge(qr, m),
            scale,
            condition,
            well_conditioned: false,
        };
        let coef = factor.solve(rhs);
        if coef.iter().all(|c| c.is_finite()) {
            return Ok((factor, coef));
        }
        let qr = a.col_piv_qr();
        let (rank, cond) = truncated_rank(&qr);
        factor.kind = FactorKind::Truncated(qr, rank);
        factor.condition = cond;
        let coef = factor.solve(rhs);
        if coef.iter().any(|c| !c.is_finite()) {
            return Err(FieldError::NonFiniteCoefficients);
        }
        Ok((factor, coef))
    }

    /// The coefficients (in the charges' own scale) that fit `rhs` best.
    pub(crate) fn solve(&self, rhs: &[f64]) -> Vec<f64> {
        let rhs = Mat::<f64>::from_fn(rhs.len(), 1, |i, _| rhs[i]);
        let x: Vec<f64> = match &self.kind {
            FactorKind::Plain(qr) => {
                let x = qr.solve_lstsq(&rhs);
                (0..self.scale.len()).map(|j| x[(j, 0)]).collect()
            }
            FactorKind::Truncated(qr, rank) => truncated_apply(qr, *rank, rhs),
            FactorKind::Ridge(qr, m) => {
                let n = self.scale.len();
                let padded =
                    Mat::<f64>::from_fn(m + n, 1, |i, _| if i < *m { rhs[(i, 0)] } else { 0.0 });
                let x = qr.solve_lstsq(&padded);
                (0..n).map(|j| x[(j, 0)]).collect()
            }
        };
        x.iter().zip(&self.scale).map(|(x, s)| x * s).collect()
    }
}

/// Ridge factor: λ over the machine epsilon per row of the augmented
/// matrix (see [`ridge`]).
pub const RIDGE_PER_ROW: f64 = 128.0;

/// The Householder QR of the column-scaled kernel matrix `a` (M × N) stacked
/// on λI, λ = [`RIDGE_PER_ROW`]·(M + N)·ε: the least-squares solution of
/// min ‖a x − b‖² + λ²‖x‖², Tikhonov's regularisation. faer's QR does not
/// advance its row past a column whose remainder falls under 16·(M + N)·ε
/// of its norm, so the R of an ill-conditioned MFS matrix (a cluster's
/// deepest charges, a sink's ring) has exact zeros on its diagonal and the
/// plain solution is not a number; the λ rows keep every remainder above
/// that threshold. λ ≈ 9e-11 at M + N = 3 137 (DejaVu Serif "e" at 50 mm);
/// 3e-11 and 1e-10 reach the same errors on B H P R a e x (docs/method.md
/// §3d), in a third to a half of the column-pivoted QR's time. Returns the
/// factor and its condition estimate.
fn ridge(a: &Mat<f64>) -> (faer::linalg::solvers::Qr<f64>, f64) {
    let (m, n) = (a.nrows(), a.ncols());
    let lambda = RIDGE_PER_ROW * (m + n) as f64 * f64::EPSILON;
    let aug = Mat::<f64>::from_fn(m + n, n, |i, j| {
        if i < m {
            a[(i, j)]
        } else if i - m == j {
            lambda
        } else {
            0.0
        }
    });
    let qr = aug.qr();
    let cond = crate::num::triangular_condition(qr.thin_R());
    (qr, cond)
}

/// The kernel matrix k(P_m, Q_n) with its columns scaled to unit norm, and
/// the scales (0 for a non-finite or zero column, which is zeroed: a charge
/// on a collocation point, left out by the truncated solve).
fn scaled_matrix(charges: &[Vec2], points: &[Vec2]) -> (Mat<f64>, Vec<f64>) {
    let (m, n) = (points.len(), charges.len());
    crate::count::pairs(m * n);
    // The kernel matrix column by column in parallel (each entry is the same
    // `kernel` call whichever thread makes it, so the matrix does not depend
    // on the thread count): its M·N logarithms were a third of the shape
    // solve on one thread (issue 13).
    let cols = {
        use rayon::prelude::*;
        let mut cols = vec![0.0; m * n];
        cols.par_chunks_mut(m.max(1))
            .zip(charges.par_iter())
            .for_each(|(col, &q)| {
                for (v, &p) in col.iter_mut().zip(points) {
                    *v = kernel(p, q);
                }
            });
        cols
    };
    let mut a = Mat::<f64>::from_fn(m, n, |i, j| cols[j * m + i]);
    drop(cols);
    let mut scale = vec![0.0; n];
    for (j, s) in scale.iter_mut().enumerate() {
        let norm = a.col(j).norm_l2();
        *s = if norm.is_finite() && norm > 0.0 {
            1.0 / norm
        } else {
            0.0
        };
        let sj = *s;
        for i in 0..m {
            a[(i, j)] = if sj > 0.0 { a[(i, j)] * sj } else { 0.0 };
        }
    }
    (a, scale)
}

/// The rank a column-pivoted QR keeps (|R_kk| above [`RANK_CUTOFF`] |R₀₀|)
/// and |R₀₀| / |R_kk| over the kept columns.
fn truncated_rank(qr: &faer::linalg::solvers::ColPivQr<f64>) -> (usize, f64) {
    let r = qr.R();
    let n = r.ncols().min(r.nrows());
    if n == 0 {
        return (0, f64::INFINITY);
    }
    let r00 = r[(0, 0)].abs();
    let rank = (0..n)
        .take_while(|&k| r[(k, k)].abs() > RANK_CUTOFF * r00 && r[(k, k)].is_finite())
        .count();
    let condition = if rank > 0 {
        r00 / r[(rank - 1, rank - 1)].abs()
    } else {
        f64::INFINITY
    };
    (rank, condition)
}

/// The basic least-squares solution from a column-pivoted QR truncated at
/// `rank`: x over the kept columns solves Rₖₖ xₖ = (Qᵀb)ₖ, the rest are 0
/// (in the original column order).
fn truncated_apply(
    qr: &faer::linalg::solvers::ColPivQr<f64>,
    rank: usize,
    mut rhs: Mat<f64>,
) -> Vec<f64> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::householder;
    let r = qr.R();
    let n = r.ncols();
    let (basis, coeff) = (qr.Q_basis(), qr.Q_coeff());
    let mut buf =
        MemBuffer::new(
            householder::apply_block_householder_sequence_transpose_on_the_left_in_place_scratch::<
                f64,
            >(basis.nrows(), coeff.nrows(), 1),
        );
    householder::apply_block_householder_sequence_transpose_on_the_left_in_place_with_conj(
        basis,
        coeff,
        faer::Conj::No,
        rhs.as_mut(),
        faer::Par::Seq,
        MemStack::new(&mut buf),
    );
    // Back substitution on the leading rank × rank block of R.
    let mut y = vec![0.0; n];
    for k in (0..rank).rev() {
        let mut s = rhs[(k, 0)];
        for (j, yj) in y.iter().enumerate().take(rank).skip(k + 1) {
            s -= r[(k, j)] * yj;
        }
        y[k] = s / r[(k, k)];
    }
    let (forward, _) = qr.P().arrays();
    let mut x = vec![0.0; n];
    for (k, &col) in forward.iter().enumerate() {
        x[col] = y[k];
    }
    x
}

/// The truncated solve of `a` x ≈ `rhs` ([`truncated_rank`],
/// [`truncated_apply`]): x, the rank kept and the condition over it.
#[cfg(test)]
fn truncated_lstsq(a: &Mat<f64>, rhs: Mat<f64>) -> (Vec<f64>, usize, f64) {
    faer::set_global_parallelism(faer::Par::Seq);
    let qr = a.col_piv_qr();
    let (rank, condition) = truncated_rank(&qr);
    (truncated_apply(&qr, rank, rhs), rank, condition)
}

/// max |u(P) − g(P)| over the given points, the field evaluated through local
/// expansions over the points' cluster (`dense_box`): within 1e-14 of the
/// direct sums (§12 of docs/method.md), far below any boundary error worth
/// measuring; the check points were most of the shape solves' kernel pairs
/// (issue 13). Points outside the box are summed directly.
pub fn max_error(field: &Field, checks: &[Condition]) -> f64 {
    largest(&check_errors(field, checks))
}

/// |u(P) − g(P)| at each of the given points, evaluated as [`max_error`]
/// says.
pub fn check_errors(field: &Field, checks: &[Condition]) -> Vec<f64> {
    use rayon::prelude::*;
    let field = match dense_box(checks) {
        Some((lo, hi)) => field.accelerated_around(lo, hi),
        None => field.clone(),
    };
    checks
        .par_iter()
        .with_min_len(256)
        .map(|c| (field.value(c.p) - c.value).abs())
        .collect()
}

/// The largest of `errors`, NaN if one is.
pub(crate) fn largest(errors: &[f64]) -> f64 {
    errors.iter().copied().fold(0.0, crate::num::max_or_nan)
}

/// The box of the points within 4 times the median distance of the
/// coordinate-wise median point: the glyph's check points without the outer
/// circle's, 14 times farther out, whose box would make every expansion box
/// hold most charges. Only the speed of [`max_error`] depends on this choice.
fn dense_box(checks: &[Condition]) -> Option<(Vec2, Vec2)> {
    let median = |mut v: Vec<f64>| -> Option<f64> {
        v.retain(|x| x.is_finite());
        if v.is_empty() {
            return None;
        }
        let k = v.len() / 2;
        Some(*v.select_nth_unstable_by(k, f64::total_cmp).1)
    };
    let c = Vec2::new(
        median(checks.iter().map(|c| c.p.x).collect())?,
        median(checks.iter().map(|c| c.p.y).collect())?,
    );
    let reach = 4.0 * median(checks.iter().map(|q| q.p.dist(c)).collect())?;
    let mut lo = Vec2::new(f64::INFINITY, f64::INFINITY);
    let mut hi = Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    for q in checks.iter().filter(|q| q.p.dist(c) <= reach) {
        lo = Vec2::new(lo.x.min(q.p.x), lo.y.min(q.p.y));
        hi = Vec2::new(hi.x.max(q.p.x), hi.y.max(q.p.y));
    }
    (lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::linalg::solvers::SolveLstsq;

    fn pseudo_random(m: usize, n: usize) -> Mat<f64> {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        Mat::from_fn(m, n, |_, _| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
    }

    /// A repeated charge makes two equal columns: faer's plain QR then has
    /// an exact zero on R's diagonal and no finite solution, and the ridge
    /// QR takes over. Its field meets u = 1 on the circle of radius 2, at
    /// points between the collocation points, within 1e-8, and agrees with
    /// the solve that has each charge once within 1e-8 between the ring of
    /// 40 charges (radius 1.2) and the boundary. (On the unit circle the
    /// ring's logarithms sum to about 0, and u = 1 is out of reach.)
    #[test]
    fn the_ridge_qr_solves_a_repeated_charge() {
        let tau = std::f64::consts::TAU;
        let on = |r: f64, a: f64| Vec2::new(3.0 + r * a.cos(), -2.0 + r * a.sin());
        let once: Vec<Vec2> = (0..40).map(|k| on(1.2, tau * k as f64 / 40.0)).collect();
        let mut twice = once.clone();
        twice.insert(7, once[7]);
        let points: Vec<Vec2> = (0..160).map(|k| on(2.0, tau * k as f64 / 160.0)).collect();
        let rhs = vec![1.0; points.len()];
        let (f1, c1) = Factor::new(&once, &points, &rhs).expect("distinct charges");
        assert!(f1.well_conditioned, "the distinct charges need no fallback");
        let (f2, c2) = Factor::new(&twice, &points, &rhs).expect("a repeated charge");
        assert!(
            !f2.well_conditioned,
            "a repeated charge is past the estimate"
        );
        assert!(
            matches!(f2.kind, FactorKind::Ridge(..)),
            "the ridge QR solved it"
        );
        let u1 = Field::new(once, c1);
        let u2 = Field::new(twice, c2);
        for k in 0..500 {
            let p = on(2.0, tau * (k as f64 + 0.37) / 500.0);
            assert!(
                (u2.value(p) - 1.0).abs() < 1e-8,
                "u = {} at {p:?}",
                u2.value(p)
            );
            let q = on(1.6 + 0.38 * (k % 7) as f64 / 7.0, tau * k as f64 / 500.0);
            assert!((u2.value(q) - u1.value(q)).abs() < 1e-8, "at {q:?}");
        }
    }

    /// The max error through local expansions equals the direct sums' to
    /// 1e-13 of max |u|, and the box it expands over is the dense cluster
    /// (without the outer ring 14 times farther out).
    #[test]
    fn max_error_through_expansions_matches_the_direct_sums() {
        let tau = std::f64::consts::TAU;
        let ring = |r: f64, n: usize, phase: f64| -> Vec<Vec2> {
            (0..n)
                .map(|k| {
                    let a = tau * (k as f64 + phase) / n as f64;
                    Vec2::new(20.0 + r * a.cos(), 5.0 + r * a.sin())
                })
                .collect()
        };
        let mut charges = ring(8.0, 400, 0.0);
        charges.extend(ring(140.0, 40, 0.0));
        let coef: Vec<f64> = (0..charges.len())
            .map(|k| ((k * 7919) % 101) as f64 / 50.0 - 1.0)
            .collect();
        let field = Field::new(charges, coef);
        let mut checks: Vec<Condition> = ring(10.0, 3000, 0.25)
            .into_iter()
            .map(|p| Condition { p, value: 1.0 })
            .collect();
        checks.extend(
            ring(100.0, 200, 0.5)
                .into_iter()
                .map(|p| Condition { p, value: 0.0 }),
        );
        let direct = checks
            .iter()
            .map(|c| (field.value(c.p) - c.value).abs())
            .fold(0.0, f64::max);
        let scale = checks
            .iter()
            .map(|c| field.value(c.p).abs())
            .fold(0.0, f64::max);
        let fast = max_error(&field, &checks);
        assert!((fast - direct).abs() <= 1e-13 * scale, "{fast} vs {direct}");
        let (lo, hi) = dense_box(&checks).unwrap();
        assert!(
            lo.x > 9.0 && hi.x < 31.0 && lo.y > -6.0 && hi.y < 16.0,
            "{lo:?} {hi:?}"
        );
    }

    /// On a well-conditioned matrix the truncated solve keeps every column and
    /// gives the ordinary least-squares solution.
    #[test]
    fn full_rank_matches_the_plain_least_squares_solution() {
        let a = pseudo_random(40, 12);
        let b = pseudo_random(40, 1);
        let (x, rank, _) = truncated_lstsq(&a, b.clone());
        let plain = a.qr().solve_lstsq(&b);
        assert_eq!(rank, 12);
        for (j, xj) in x.iter().enumerate() {
            assert!(
                (xj - plain[(j, 0)]).abs() < 1e-12,
                "x[{j}] {xj} vs {}",
                plain[(j, 0)]
            );
        }
    }

    /// A repeated column (two charges in one place) is dropped, and the fit is
    /// as good as without it.
    #[test]
    fn a_repeated_column_is_dropped_without_losing_the_fit() {
        let a = pseudo_random(40, 12);
        let mut twice = Mat::<f64>::zeros(40, 13);
        for i in 0..40 {
            for j in 0..12 {
                twice[(i, j)] = a[(i, j)];
            }
            twice[(i, 12)] = a[(i, 3)];
        }
        let b = pseudo_random(40, 1);
        let (x, rank, _) = truncated_lstsq(&twice, b.clone());
        assert_eq!(rank, 12);
        let plain = a.qr().solve_lstsq(&b);
        let residual = |y: &dyn Fn(usize) -> f64, m: &Mat<f64>| {
            (0..40)
                .map(|i| {
                    let r: f64 = (0..m.ncols()).map(|j| m[(i, j)] * y(j)).sum::<f64>() - b[(i, 0)];
                    r * r
                })
                .sum::<f64>()
        };
        let r_trunc = residual(&|j| x[j], &twice);
        let r_plain = residual(&|j| plain[(j, 0)], &a);
        assert!(
            (r_trunc - r_plain).abs() < 1e-12 * r_plain.max(1.0),
            "{r_trunc} vs {r_plain}"
        );
    }
}
