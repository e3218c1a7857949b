//! The l = 2 system (Ochiai eqs. (20), (29)–(47)) and its dense solve.
//!
//! With ΔT₁ = −T₂ and ΔT₂ = −Σₖ Sₖ χ_k in the box Ω (χ_k the ball of radius A
//! about the k-th given point qₖ; a point load δ for the kernel `T2`), Green's
//! second identity with T*₁ (ΔT*₁ = −δ) and T*₂ (ΔT*₂ = T*₁), n outward, gives
//! (20) for l = 2:
//!
//! ```text
//! c T₁(P) = ∮ (T*₁ V₁ − ∂T*₁/∂n T₁) − ∮ (T*₂ V₂ − ∂T*₂/∂n T₂) − Σₖ Sₖ K₂(P, qₖ)
//! c T₂(P) = ∮ (T*₁ V₂ − ∂T*₁/∂n T₂) + Σₖ Sₖ K₁(P, qₖ)
//! ```
//!
//! with Vᵢ = ∂Tᵢ/∂n on the box, c = ½ at an element centre and 1 inside,
//! (K₁, K₂) = (T*₁A, T*₂A) for `T2A` and (T*₁, T*₂) for `T2`. Constant
//! elements collocated at their centres (eqs. (33)–(46)) give 2N + M equations
//! for V₁, V₂ (N each) and S (M):
//!
//! ```text
//! box e, T₁:  Σⱼ g₁ V₁ − g₂ V₂ − Σₖ K₂ Sₖ = ½T₁ₑ + Σⱼ (h₁ T₁ⱼ − h₂ T₂ⱼ)
//! box e, T₂:  Σⱼ g₁ V₂        + Σₖ K₁ Sₖ = ½T₂ₑ + Σⱼ h₁ T₂ⱼ
//! point p:    Σⱼ g₁ V₁ − g₂ V₂ − Σₖ K₂ Sₖ = τₚ  + Σⱼ (h₁ T₁ⱼ − h₂ T₂ⱼ)
//! ```
//!
//! (gᵢ, hᵢ the element integrals of [`super::quadrature`] from the row's
//! point). Ochiai's solid has T₁ = 1, T₂ = 0 on the box and τ = 0, −1, +1 for
//! surface, inside and outside points; [`solve_dirichlet`] takes any box data
//! (the Green's identity test uses T₁ = |x − c|², T₂ = −6).

use super::elements::BoxMesh;
use super::error::{invalid, PolyError};
use super::fault::PolyFault;
use super::kernels::Kernel;
use super::quadrature::{influence, QuadRule, Quadrature};
use faer::Mat;
use nalgebra::Vector3;

/// Most given points.
pub(crate) const MAX_POINTS: usize = 4000;

/// Most unknowns 2N + M: the dense matrix is (2N + M)² doubles, held twice
/// while it is copied into faer (5000 unknowns: 2 × 200 MB).
pub(crate) const MAX_UNKNOWNS: usize = 5000;

/// Largest condition estimate (max |Uᵢᵢ| / min |Uᵢᵢ| of the pivoted LU)
/// accepted: beyond it the loads carry fewer than ~3 significant digits.
pub(crate) const MAX_CONDITION: f64 = 1e13;

/// What a given point is: T₁ = 0, −1 or +1 there (eq. (47)'s right side).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointKind {
    /// On the surface: T₁ = 0.
    Surface,
    /// Inside the solid: T₁ = −1.
    Inside,
    /// Outside the solid (a separator): T₁ = +1.
    Outside,
}

impl PointKind {
    /// The value of T₁ asked for at a point of this kind.
    pub(crate) fn target(self) -> f64 {
        match self {
            PointKind::Surface => 0.0,
            PointKind::Inside => -1.0,
            PointKind::Outside => 1.0,
        }
    }
}

/// A given point and its kind.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GivenPoint {
    /// Position, strictly inside the box.
    pub p: Vector3<f64>,
    /// Surface, inside or outside.
    pub kind: PointKind,
}

/// Ochiai's problem: the box, its elements, the load kernel and the points.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// Lowest corner of the fictitious box.
    pub lo: Vector3<f64>,
    /// Highest corner.
    pub hi: Vector3<f64>,
    /// Elements per face edge.
    pub per_edge: usize,
    /// `Kernel::T2A { a }` (the paper's choice) or `Kernel::T2`.
    pub kernel: Kernel,
    /// The given points.
    pub points: Vec<GivenPoint>,
    /// The element quadrature.
    pub quadrature: Quadrature,
}

/// The solved field: box data, box unknowns and loads.
#[derive(Debug, Clone)]
pub struct Solution {
    pub(super) mesh: BoxMesh,
    pub(super) rule: QuadRule,
    /// (K₁, K₂): the kernels of the loads in the T₂ and T₁ equations.
    pub(super) loads: (Kernel, Kernel),
    pub(super) t1: Vec<f64>,
    pub(super) t2: Vec<f64>,
    /// V₁ = ∂T₁/∂n per element.
    pub v1: Vec<f64>,
    /// V₂ = ∂T₂/∂n per element.
    pub v2: Vec<f64>,
    /// The load points qₖ.
    pub(crate) centres: Vec<Vector3<f64>>,
    /// The loads Sₖ.
    pub(crate) s: Vec<f64>,
    /// max |Uᵢᵢ| / min |Uᵢᵢ| of the system's fully pivoted LU.
    pub condition: f64,
}

impl Solution {
    /// The box mesh.
    pub fn mesh(&self) -> &BoxMesh {
        &self.mesh
    }
}

/// Solves Ochiai's solid: T₁ = 1, T₂ = 0 on the box, τ from each point's kind.
/// Errors: no points, coincident points (closer than 1e-9 of the box size), a
/// point not strictly inside the box (`points`), a bad kernel (`kernel`,
/// `kernel.a`), box, elements or quadrature, a singular system.
pub fn solve(model: &Model) -> Result<Solution, PolyError> {
    if model.points.is_empty() {
        return Err(invalid("points", PolyFault::NoPoints));
    }
    let mesh = BoxMesh::new(model.lo, model.hi, model.per_edge)?;
    let n = mesh.elements.len();
    let points: Vec<(Vector3<f64>, f64)> = model
        .points
        .iter()
        .map(|g| (g.p, g.kind.target()))
        .collect();
    solve_dirichlet(
        mesh,
        &vec![1.0; n],
        &vec![0.0; n],
        &points,
        model.kernel,
        model.quadrature,
    )
}

/// Solves the l = 2 system for any box data `t1`, `t2` (one value per
/// element) and points (position, T₁ there) that also carry the loads.
pub fn solve_dirichlet(
    mesh: BoxMesh,
    t1: &[f64],
    t2: &[f64],
    points: &[(Vector3<f64>, f64)],
    kernel: Kernel,
    quadrature: Quadrature,
) -> Result<Solution, PolyError> {
    let rule = QuadRule::new(quadrature)?;
    let loads = load_kernels(kernel)?;
    check_points(&mesh, points)?;
    let n = mesh.elements.len();
    if 2 * n + points.len() > MAX_UNKNOWNS {
        return Err(invalid(
            "elements",
            PolyFault::TooManyUnknowns {
                elements: n,
                points: points.len(),
            },
        ));
    }
    if t1.len() != n || t2.len() != n {
        return Err(invalid("box", PolyFault::BoxData { elements: n }));
    }
    let centres: Vec<Vector3<f64>> = points.iter().map(|p| p.0).collect();
    let (a, b) = assemble(&mesh, &rule, loads, t1, t2, points);
    let (x, condition) = dense_solve(a, &b)?;
    Ok(Solution {
        v1: x[..n].to_vec(),
        v2: x[n..2 * n].to_vec(),
        s: x[2 * n..].to_vec(),
        mesh,
        rule,
        loads,
        t1: t1.to_vec(),
        t2: t2.to_vec(),
        centres,
        condition,
    })
}

/// (K₁, K₂) for the l = 2 system; the other kernels need l = 1 or 3.
fn load_kernels(kernel: Kernel) -> Result<(Kernel, Kernel), PolyError> {
    match kernel.validated()? {
        Kernel::T2 => Ok((Kernel::T1, Kernel::T2)),
        Kernel::T2A { a } => Ok((Kernel::T1A { a }, Kernel::T2A { a })),
        kernel => Err(invalid("kernel", PolyFault::KernelUnsupported { kernel })),
    }
}

/// Points: 1..=MAX_POINTS, finite, strictly inside the box, pairwise apart.
fn check_points(mesh: &BoxMesh, points: &[(Vector3<f64>, f64)]) -> Result<(), PolyError> {
    if points.len() > MAX_POINTS {
        return Err(invalid(
            "points",
            PolyFault::TooManyPoints {
                points: points.len(),
            },
        ));
    }
    for (i, (p, t)) in points.iter().enumerate() {
        if !t.is_finite() || !mesh.contains(*p) {
            return Err(invalid(
                "points",
                PolyFault::PointOutside {
                    number: i + 1,
                    at: *p,
                    lo: mesh.lo,
                    hi: mesh.hi,
                },
            ));
        }
    }
    // Sorted by x, each point is compared with those within `tol` in x only.
    let tol = 1e-9 * mesh.size();
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&i, &j| points[i].0.x.total_cmp(&points[j].0.x));
    for (k, &i) in order.iter().enumerate() {
        for &j in order[k + 1..]
            .iter()
            .take_while(|&&j| points[j].0.x - points[i].0.x <= tol)
        {
            if (points[i].0 - points[j].0).norm() <= tol {
                return Err(invalid(
                    "points",
                    PolyFault::Coincide {
                        first: i.min(j) + 1,
                        second: i.max(j) + 1,
                        tol,
                    },
                ));
            }
        }
    }
    Ok(())
}

/// The (2N + M)² matrix, row-major, and the right side; rows in parallel
/// (each row is the same sums whichever thread makes it).
fn assemble(
    mesh: &BoxMesh,
    rule: &QuadRule,
    (k1, k2): (Kernel, Kernel),
    t1: &[f64],
    t2: &[f64],
    points: &[(Vector3<f64>, f64)],
) -> (Vec<f64>, Vec<f64>) {
    use rayon::prelude::*;
    let (n, m) = (mesh.elements.len(), points.len());
    let size = 2 * n + m;
    let mut a = vec![0.0; size * size];
    let mut rhs = vec![0.0; size];
    // Row pairs (T₁, T₂) per element, then one T₁ row per point.
    let (box_rows, point_rows) = a.split_at_mut(2 * n * size);
    let (box_rhs, point_rhs) = rhs.split_at_mut(2 * n);
    box_rows
        .par_chunks_mut(2 * size)
        .zip(box_rhs.par_chunks_mut(2))
        .enumerate()
        .for_each(|(e, (rows, b))| {
            let x = mesh.elements[e].centre;
            let (r1, r2) = rows.split_at_mut(size);
            let (d1, d2) = t1_row(mesh, rule, x, t1, t2, r1);
            b[0] = 0.5 * t1[e] + d1;
            b[1] = 0.5 * t2[e] + d2;
            r2[n..2 * n].copy_from_slice(&r1[..n]);
            for (k, q) in points.iter().enumerate() {
                r1[2 * n + k] = -k2.value(x - q.0);
                r2[2 * n + k] = k1.value(x - q.0);
            }
        });
    point_rows
        .par_chunks_mut(size)
        .zip(point_rhs.par_iter_mut())
        .zip(points.par_iter())
        .for_each(|((row, b), &(x, target))| {
            let (d1, _) = t1_row(mesh, rule, x, t1, t2, row);
            *b = target + d1;
            for (k, q) in points.iter().enumerate() {
                row[2 * n + k] = -k2.value(x - q.0);
            }
        });
    (a, rhs)
}

/// Fills the box part of a T₁ row at `x` (g₁ for V₁, −g₂ for V₂) and returns
/// Σⱼ (h₁ T₁ⱼ − h₂ T₂ⱼ) and Σⱼ h₁ T₂ⱼ.
fn t1_row(
    mesh: &BoxMesh,
    rule: &QuadRule,
    x: Vector3<f64>,
    t1: &[f64],
    t2: &[f64],
    row: &mut [f64],
) -> (f64, f64) {
    let n = mesh.elements.len();
    let (mut d1, mut d2) = (0.0, 0.0);
    for (j, el) in mesh.elements.iter().enumerate() {
        let f = influence(el, x, rule);
        row[j] = f.g1;
        row[n + j] = -f.g2;
        d1 += f.h1 * t1[j] - f.h2 * t2[j];
        d2 += f.h1 * t2[j];
    }
    (d1, d2)
}

/// Solves the row-major system by a fully pivoted LU (faer, sequential: the
/// result must not depend on the thread count). Returns x and the condition
/// estimate; a singular or ill-conditioned system is [`PolyError::Singular`].
fn dense_solve(a: Vec<f64>, b: &[f64]) -> Result<(Vec<f64>, f64), PolyError> {
    use faer::linalg::solvers::Solve;
    let size = b.len();
    faer::set_global_parallelism(faer::Par::Seq);
    let mat = Mat::<f64>::from_fn(size, size, |i, j| a[i * size + j]);
    drop(a);
    let lu = mat.full_piv_lu();
    let condition = crate::num::triangular_condition(lu.U());
    if !(condition.is_finite() && condition <= MAX_CONDITION) {
        return Err(PolyError::Singular { size, condition });
    }
    let rhs = Mat::<f64>::from_fn(size, 1, |i, _| b[i]);
    let x = lu.solve(&rhs);
    let x: Vec<f64> = (0..size).map(|i| x[(i, 0)]).collect();
    if x.iter().any(|v| !v.is_finite()) {
        return Err(PolyError::Singular { size, condition });
    }
    Ok((x, condition))
}

#[cfg(test)]
pub(crate) mod tests;
