//! Potential fields by the method of fundamental solutions (the paper's Sections 2–4).

pub mod adaptive;
pub mod blocks;
pub mod fast;
pub mod inverse;
pub mod isolines;
pub(crate) mod level;
mod march;
pub mod mfs;
pub mod refine;
pub mod section;
pub mod setup;

pub use mfs::{kernel, Condition, Field, Problem, Solution};
pub use setup::{Boundary, Layout, Prepared, Sink};

use crate::geometry::{glyphs, polygon_winding_number, Contour, GeometryError, Vec2};
use rayon::prelude::*;
use serde::Serialize;

/// Default share of the free singularities given to corner clusters (measured on
/// the convergence study of the letter I; see docs/method.md).
pub const DEFAULT_CORNER_FRACTION: f64 = 0.4;

/// Corner fractions tried by `solve_best`: the error depends on how the integer
/// number of charges per corner falls, so the best of three is kept.
pub const CORNER_FRACTIONS: [f64; 3] = [0.3, 0.4, 0.5];

/// Number of distances tried in the coarse scan of the pseudo-boundary distance.
pub const DISTANCE_SCAN: usize = 8;

/// Golden-section steps after the scan.
pub const DISTANCE_REFINE: usize = 8;

/// A solve with the layout that was chosen.
#[derive(Clone, Debug)]
pub struct Solved {
    /// The solution.
    pub solution: Solution,
    /// The layout used (with the chosen distance).
    pub layout: Layout,
    /// Number of solves spent choosing the distance.
    pub solves: usize,
    /// Collocation points M.
    pub m: usize,
}

impl Solved {
    /// The solve's figures: M, the chosen distance and the max boundary error.
    pub fn figures(&self) -> FieldFigures {
        FieldFigures {
            m: self.m,
            distance: self.layout.distance,
            max_error: self.solution.max_error,
        }
    }
}

/// One solve's figures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldFigures {
    /// Collocation points M.
    pub m: usize,
    /// Pseudo-boundary distance, mm.
    pub distance: f64,
    /// Max boundary error over the check points.
    pub max_error: f64,
}

/// Solve one layout.
pub fn solve_layout(prep: &Prepared, layout: &Layout) -> Result<(Solution, usize), FieldError> {
    let problem = prep.problem(layout)?;
    let sol = mfs::solve(&problem)?;
    Ok((sol, problem.colloc.len()))
}

/// Solve with N singularities, the pseudo-boundary distance either given or chosen
/// to minimise the max boundary error: a log-spaced scan of `DISTANCE_SCAN` values
/// in [h/4, 8h] (h the mean spacing of the uniform singularities), in parallel,
/// then `DISTANCE_REFINE` golden-section steps in log d around the best. The paper
/// scanned 200 values of d; this takes 16 solves.
pub fn solve_auto(
    prep: &Prepared,
    n_total: usize,
    distance: Option<f64>,
    corner_clusters: bool,
) -> Result<Solved, FieldError> {
    let base = Layout {
        corner_clusters,
        ..Layout::auto(n_total)
    };
    solve_with(prep, base, distance)
}

/// As `solve_auto` with the distance chosen, trying each of `CORNER_FRACTIONS` and
/// keeping the layout with the smallest max boundary error.
pub fn solve_best(prep: &Prepared, n_total: usize, pairs: bool) -> Result<Solved, FieldError> {
    let mut best = BestSolve::default();
    for f in CORNER_FRACTIONS {
        let base = Layout {
            n_total,
            distance: 1.0,
            corner_clusters: true,
            corner_fraction: f,
            pairs,
        };
        best.add(solve_with(prep, base, None));
    }
    best.into_result()
}

/// The best of several solves ([`Solution::better_than`]) with the count of
/// solves they all took, or the last error when none succeeded.
#[derive(Default)]
pub(crate) struct BestSolve {
    best: Option<Solved>,
    solves: usize,
    last_err: Option<FieldError>,
}

impl BestSolve {
    /// Count a solve's work and keep it if it beats the best so far; keep an
    /// error as the last one.
    pub(crate) fn add(&mut self, r: Result<Solved, FieldError>) {
        match r {
            Ok(s) => {
                self.solves += s.solves;
                if self
                    .best
                    .as_ref()
                    .is_none_or(|b| s.solution.better_than(&b.solution))
                {
                    self.best = Some(s);
                }
            }
            Err(e) => self.last_err = Some(e),
        }
    }

    /// Solves counted so far.
    pub(crate) fn solves(&self) -> usize {
        self.solves
    }

    /// The best solve, its `solves` the count of all, or the last error.
    pub(crate) fn into_result(self) -> Result<Solved, FieldError> {
        match self.best {
            Some(mut b) => {
                b.solves = self.solves;
                Ok(b)
            }
            None => Err(self.last_err.unwrap_or(FieldError::NoLayoutSolved)),
        }
    }
}

/// As `solve_auto`, for a given layout (its `distance` is ignored unless fixed).
pub fn solve_with(
    prep: &Prepared,
    base: Layout,
    distance: Option<f64>,
) -> Result<Solved, FieldError> {
    let n_total = base.n_total;
    if let Some(d) = distance {
        let layout = Layout {
            distance: d,
            ..base
        };
        let (solution, m) = solve_layout(prep, &layout)?;
        return Ok(Solved {
            solution,
            layout,
            solves: 1,
            m,
        });
    }
    let h = prep.perimeter() / n_total as f64;
    let (lo, hi) = ((h / 4.0).ln(), (8.0 * h).ln());
    let xs: Vec<f64> = (0..DISTANCE_SCAN)
        .map(|i| lo + (hi - lo) * i as f64 / (DISTANCE_SCAN - 1) as f64)
        .collect();
    let eval = |x: f64| -> Result<(f64, Solution, usize), FieldError> {
        let layout = Layout {
            distance: x.exp(),
            ..base
        };
        let (sol, m) = solve_layout(prep, &layout)?;
        Ok((sol.max_error, sol, m))
    };
    let scan: Vec<Result<(f64, Solution, usize), FieldError>> =
        xs.par_iter().map(|&x| eval(x)).collect();
    let mut best: Option<(f64, f64, Solution, usize)> = None;
    let mut errors = vec![f64::INFINITY; xs.len()];
    let mut first_err = None;
    for (i, r) in scan.into_iter().enumerate() {
        match r {
            Ok((e, sol, m)) => {
                errors[i] = e;
                if best.as_ref().is_none_or(|b| sol.better_than(&b.2)) {
                    best = Some((e, xs[i], sol, m));
                }
            }
            Err(e) => {
                first_err.get_or_insert(e);
            }
        }
    }
    let Some(mut best) = best else {
        return Err(first_err.unwrap_or(FieldError::NoDistanceSolved));
    };
    // The refinement stays among well-conditioned solutions when the best is one
    // (those from the fallback count as not solved, as when they were refused).
    let wc = best.2.well_conditioned;
    let key = |r: Result<(f64, Solution, usize), FieldError>| match r {
        Ok((e, sol, _)) if !wc || sol.well_conditioned => e,
        _ => f64::INFINITY,
    };
    let ib = xs.iter().position(|&x| x == best.1).unwrap_or(0);
    let (mut a, mut b) = (xs[ib.saturating_sub(1)], xs[(ib + 1).min(xs.len() - 1)]);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let mut solves = DISTANCE_SCAN;
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let mut fc = key(eval(c));
    let mut fd = key(eval(d));
    solves += 2;
    for _ in 2..DISTANCE_REFINE {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = key(eval(c));
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = key(eval(d));
        }
        solves += 1;
    }
    let x = if fc < fd { c } else { d };
    if fc.min(fd) < best.0 {
        if let Ok((e, sol, m)) = eval(x) {
            solves += 1;
            if sol.better_than(&best.2) {
                best = (e, x, sol, m);
            }
        }
    }
    Ok(Solved {
        solution: best.2,
        layout: Layout {
            distance: best.1.exp(),
            ..base
        },
        solves,
        m: best.3,
    })
}

/// A quick solve for the fields of z-levels, whose generating boundaries Γ(s) are
/// smooth: four distances in [h/2, 4h], in parallel, and the best kept.
pub fn solve_quick(prep: &Prepared, base: Layout) -> Result<Solved, FieldError> {
    let h = prep.perimeter() / base.n_total as f64;
    let ds: Vec<f64> = (0..4).map(|i| h * 0.5 * 2f64.powf(i as f64)).collect();
    let res: Vec<Result<(Solution, usize, f64), FieldError>> = ds
        .par_iter()
        .map(|&d| {
            solve_layout(
                prep,
                &Layout {
                    distance: d,
                    ..base
                },
            )
            .map(|(s, m)| (s, m, d))
        })
        .collect();
    let mut best: Option<(Solution, usize, f64)> = None;
    let mut err = None;
    for r in res {
        match r {
            Ok(t) => {
                if best.as_ref().is_none_or(|b| t.0.better_than(&b.0)) {
                    best = Some(t);
                }
            }
            Err(e) => err = Some(e),
        }
    }
    match best {
        Some((solution, m, d)) => Ok(Solved {
            solution,
            layout: Layout {
                distance: d,
                ..base
            },
            solves: 4,
            m,
        }),
        None => Err(err.unwrap_or(FieldError::NoDistanceSolved)),
    }
}

/// Area centroid of the material bounded by the contours (outlines counter-clockwise
/// count positive, counters clockwise negative), from their flattenings.
pub fn centroid(contours: &[Contour], tol: f64) -> Vec2 {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for c in contours {
        let p = c.flatten(tol);
        let n = p.len();
        for i in 0..n {
            let (u, v) = (p[i], p[(i + 1) % n]);
            let w = u.cross(v);
            a += w;
            cx += (u.x + v.x) * w;
            cy += (u.y + v.y) * w;
        }
    }
    if a.abs() > 0.0 {
        Vec2::new(cx / (3.0 * a), cy / (3.0 * a))
    } else {
        Vec2::ZERO
    }
}

/// The boundary of a built-in glyph in font units as in the paper's Section 3:
/// outer circle of radius 1e4 about the barycentre.
pub fn paper_boundary(ch: char) -> Result<Boundary, FieldError> {
    let g = glyphs::paper_glyph(ch)?;
    let mut contours = g.outlines.clone();
    let mut is_counter = vec![false; contours.len()];
    for c in &g.counters {
        contours.push(c.clone());
        is_counter.push(true);
    }
    Ok(Boundary::about_centroid(contours, is_counter, 1e4, 0.01))
}

/// Is `p` inside the closed polygon? (winding number ≠ 0, Appendix I)
pub fn inside(poly: &[Vec2], p: Vec2) -> bool {
    polygon_winding_number(poly, p) != 0
}

/// What can go wrong building or solving a field.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum FieldError {
    /// The built-in glyph could not be had (not in the paper's font, or the
    /// font unreadable).
    #[error(transparent)]
    Glyph(#[from] GeometryError),
    /// A boundary with no contours at all.
    #[error("the shape has no contours")]
    NoContours,
    /// A counter with no room inside it for a sink.
    #[error("a counter has no interior")]
    EmptyCounter,
    /// A layout asking for fewer singularities than the shape's contours need.
    #[error("{n} singularities are too few for this shape (at least {needed} needed)")]
    TooFewSingularities {
        /// Singularities asked for.
        n: usize,
        /// The fewest this shape takes.
        needed: usize,
    },
    /// An MFS problem with fewer collocation points than singularities (or none).
    #[error(
        "an MFS problem needs at least as many collocation points as singularities (M = {m}, N = {n})"
    )]
    TooFewCollocationPoints {
        /// Collocation points.
        m: usize,
        /// Singularities.
        n: usize,
    },
    /// The least-squares solve gave a coefficient that is NaN or infinite.
    #[error("the MFS solve gave coefficients that are not numbers")]
    NonFiniteCoefficients,
    /// The solved field is NaN at a check point.
    #[error("the field is not a finite number at a check point (a check point on a singularity?)")]
    NotANumberAtCheck,
    /// No candidate layout was tried, so none was solved.
    #[error("no layout could be solved")]
    NoLayoutSolved,
    /// No candidate pseudo-boundary distance was tried, so none was solved.
    #[error("no distance could be solved")]
    NoDistanceSolved,
}

/// One row of the convergence study (the paper's Table 3.2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ConvergenceRow {
    /// Singularities N, counting every one.
    pub n: usize,
    /// Collocation points M = 2N.
    pub m: usize,
    /// Pseudo-boundary distance chosen, font units.
    pub distance: f64,
    /// Max boundary error over the check points.
    pub max_error: f64,
}

/// Solve the paper's problem for a built-in glyph (font units, outer circle of
/// radius 1e4 about the barycentre) for each N, M = 2N, the distance chosen to
/// minimise the max boundary error.
pub fn convergence_table(glyph: char, ns: &[usize]) -> Result<Vec<ConvergenceRow>, FieldError> {
    let prep = Prepared::new(paper_boundary(glyph)?)?;
    ns.iter()
        .map(|&n| {
            let s = solve_best(&prep, n, true)?;
            Ok(ConvergenceRow {
                n,
                m: s.m,
                distance: s.layout.distance,
                max_error: s.solution.max_error,
            })
        })
        .collect()
}
