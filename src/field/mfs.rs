//! The method of fundamental solutions: u_N(P) = Σ cₙ k(P, Qₙ) with the kernel
//! k(P, Q) = −(1/2π) log|P − Q| (the paper's (2.3)–(2.4)), coefficients from an
//! overdetermined least-squares fit at collocation points.

use super::FieldError;
use crate::geometry::Vec2;
use faer::linalg::solvers::SolveLstsq;
use faer::Mat;

const INV_2PI: f64 = 1.0 / std::f64::consts::TAU;

/// Estimated condition number (ratio of the largest to smallest |Rᵢᵢ| of the
/// Householder QR of the column-scaled matrix, a lower bound of the true one) above which the solve is refused.
/// Exponentially clustered corner charges make the matrix ill-conditioned by design
/// (as in the "lightning" solvers), and least squares still gives a small residual
/// up to ~1e15; past that the coefficients are noise and the boundary error check
/// would be the only guard, so we stop with a typed error first.
pub const MAX_CONDITION: f64 = 1e15;

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
}

/// A solved potential field u(P) = Σ cₙ k(P, Qₙ).
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    charges: Vec<Vec2>,
    coef: Vec<f64>,
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
}

impl Field {
    /// A field from charges and coefficients (tests build analytic fields this way).
    pub fn new(charges: Vec<Vec2>, coef: Vec<f64>) -> Field {
        Field { charges, coef }
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
        let mut s = 0.0;
        for (q, c) in self.charges.iter().zip(&self.coef) {
            s += c * (p - *q).norm2().ln();
        }
        -INV_2PI * 0.5 * s
    }

    /// ∇u(P) = −(1/2π) Σ cₙ (P − Qₙ)/|P − Qₙ|²: in complex form the conjugate of
    /// −(1/2π) Σ cₙ/(z − qₙ), which needs no logarithm.
    pub fn grad(&self, p: Vec2) -> Vec2 {
        let (mut gx, mut gy) = (0.0, 0.0);
        for (q, c) in self.charges.iter().zip(&self.coef) {
            let d = p - *q;
            let w = c / d.norm2();
            gx += w * d.x;
            gy += w * d.y;
        }
        Vec2::new(-INV_2PI * gx, -INV_2PI * gy)
    }

    /// u(P) and ∇u(P) together.
    pub fn value_grad(&self, p: Vec2) -> (f64, Vec2) {
        let (mut s, mut gx, mut gy) = (0.0, 0.0, 0.0);
        for (q, c) in self.charges.iter().zip(&self.coef) {
            let d = p - *q;
            let r2 = d.norm2();
            s += c * r2.ln();
            let w = c / r2;
            gx += w * d.x;
            gy += w * d.y;
        }
        (-INV_2PI * 0.5 * s, Vec2::new(-INV_2PI * gx, -INV_2PI * gy))
    }

    /// The Hessian [[u_xx, u_xy], [u_xy, u_yy]] (u_yy = −u_xx: u is harmonic).
    pub fn hessian(&self, p: Vec2) -> [[f64; 2]; 2] {
        let (mut hxx, mut hxy) = (0.0, 0.0);
        for (q, c) in self.charges.iter().zip(&self.coef) {
            let d = p - *q;
            let r2 = d.norm2();
            let r4 = r2 * r2;
            hxx += c * (d.y * d.y - d.x * d.x) / r4;
            hxy += c * (-2.0 * d.x * d.y) / r4;
        }
        let hxx = -INV_2PI * hxx;
        let hxy = -INV_2PI * hxy;
        [[hxx, hxy], [hxy, -hxx]]
    }
}

/// Solve the problem in the least-squares sense (paper, Section 2: M > N).
///
/// The columns are scaled to unit Euclidean norm before a Householder QR (faer),
/// which makes the |Rᵢᵢ| ratio a fair condition estimate and keeps charges at very
/// different distances on an equal footing.
pub fn solve(problem: &Problem) -> Result<Solution, FieldError> {
    let m = problem.colloc.len();
    let n = problem.charges.len();
    if n == 0 || m < n {
        return Err(FieldError::Invalid(format!(
            "an MFS problem needs at least as many collocation points as singularities (M = {m}, N = {n})"
        )));
    }
    let mut a = Mat::<f64>::from_fn(m, n, |i, j| kernel(problem.colloc[i].p, problem.charges[j]));
    let mut scale = vec![0.0; n];
    for (j, s) in scale.iter_mut().enumerate() {
        let norm = a.col(j).norm_l2();
        *s = if norm > 0.0 { 1.0 / norm } else { 1.0 };
        let sj = *s;
        for i in 0..m {
            a[(i, j)] *= sj;
        }
    }
    // Sequential QR: the result must not depend on the thread count (same job,
    // same G-code); pfcam parallelises over whole solves and loops instead.
    faer::set_global_parallelism(faer::Par::Seq);
    let qr = a.qr();
    let r = qr.thin_R();
    let (mut rmax, mut rmin) = (0.0_f64, f64::INFINITY);
    for k in 0..n {
        let v = r[(k, k)].abs();
        rmax = rmax.max(v);
        rmin = rmin.min(v);
    }
    let condition = if rmin > 0.0 {
        rmax / rmin
    } else {
        f64::INFINITY
    };
    if condition.is_nan() || condition >= MAX_CONDITION {
        return Err(FieldError::IllConditioned { cond: condition });
    }
    let rhs = Mat::<f64>::from_fn(m, 1, |i, _| problem.colloc[i].value);
    let x = qr.solve_lstsq(&rhs);
    let coef: Vec<f64> = (0..n).map(|j| x[(j, 0)] * scale[j]).collect();
    if coef.iter().any(|c| !c.is_finite()) {
        return Err(FieldError::IllConditioned { cond: condition });
    }
    let field = Field {
        charges: problem.charges.clone(),
        coef,
    };
    let max_error = max_error(&field, &problem.checks);
    if max_error.is_nan() {
        return Err(FieldError::Invalid(
            "the field is not a number at a check point (a check point on a singularity?)".into(),
        ));
    }
    Ok(Solution {
        field,
        max_error,
        condition,
    })
}

/// max |u(P) − g(P)| over the given points.
pub fn max_error(field: &Field, checks: &[Condition]) -> f64 {
    use rayon::prelude::*;
    checks
        .par_iter()
        .with_min_len(256)
        .map(|c| (field.value(c.p) - c.value).abs())
        .reduce(|| 0.0, crate::num::max_or_nan)
}
