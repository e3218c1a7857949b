//! The refined layout (issue 46): charges added where the boundary errs, not
//! everywhere. Gopal and Trefethen's lightning solvers grow the poles at a
//! corner when the error near it is large; this does the same for log
//! charges. A layout is a count of uniform charges per contour and of pairs
//! per cluster (every convex material corner and every notch of the void,
//! [`super::setup::NOTCH_TURN`]); after each solve the check points' errors
//! are put to the clusters within two spacings of them and to the contours
//! beyond half a spacing from every cluster, and each part over the target
//! grows: a cluster by a third (at most [`MAX_PAIRS`], then its contour
//! grows instead), a contour's uniform charges by half.
//!
//! So a serif's corners get the pairs a round stem does not need, and a
//! letter with one bad notch does not pay for it on all its length: DejaVu
//! Serif "H" at 50 mm, whose error sat at its serifs' corners (1.2e-5 at
//! N = 2 000 in the fixed split of the paired layout), docs/method.md §3d.

use super::mfs::Problem;
use super::setup::{Groups, PAIRED_OUTER_CHARGES, PAIRED_SINK_CHARGES};
use super::{FieldError, Prepared};
use crate::geometry::Vec2;

/// Pairs a cluster starts with.
pub const START_PAIRS: usize = 3;

/// Fewest uniform charges on a contour.
pub const MIN_CONTOUR: usize = 4;

/// Most solves of one refinement.
pub const MAX_ROUNDS: usize = 24;

/// Most pairs in a cluster: past [`super::setup::refined_cap`] (62) they fill the same
/// range of distances more densely.
pub const MAX_PAIRS: usize = 90;

/// Factor by which a contour's uniform charges grow in a round.
pub const CONTOUR_GROWTH: f64 = 1.5;

/// Factor by which a cluster's pairs grow in a round (at least by two).
pub const CLUSTER_GROWTH: f64 = 1.35;

/// A check point within this many spacings of a cluster's corner is its.
pub const CLUSTER_REACH: f64 = 2.0;

/// A check point farther than this many spacings from every cluster's
/// corner is its contour's (between this and the reach, it is both's).
pub const CONTOUR_REACH: f64 = 0.5;

/// Charges a sink gains in a round whose sink errs over the target.
pub const SINK_STEP: usize = 4;

/// Most charges in a sink: (1/4)ⁿ/n, the ring's aliasing, is far below
/// any target by then.
pub const MAX_SINK: usize = 32;

/// How many singularities go where in a refined layout.
#[derive(Clone, Debug, PartialEq)]
pub struct Refinement {
    /// Uniform charges on each glyph contour.
    pub contour: Vec<usize>,
    /// Pairs at each cluster ([`Prepared::refined_corners`], in order).
    pub pairs: Vec<usize>,
    /// Charges on the outer circle (0 without one).
    pub outer: usize,
    /// Charges in each sink.
    pub sink: usize,
}

/// A refined solve: what the caller's solve made of the best layout, its
/// refinement, its max error and the count of solves.
pub struct Refined<T> {
    /// The caller's result for the best layout.
    pub out: T,
    /// That layout.
    pub refinement: Refinement,
    /// Its problem.
    pub problem: Problem,
    /// Its max boundary error.
    pub max_error: f64,
    /// Solves made.
    pub solves: usize,
}

impl Refinement {
    /// The first layout: `n_uniform` uniform charges shared by length (at
    /// least [`MIN_CONTOUR`] a contour), [`START_PAIRS`] at every cluster,
    /// the paired layout's largest outer ring.
    pub fn initial(prep: &Prepared, n_uniform: usize) -> Refinement {
        let total: f64 = prep.lengths().iter().sum();
        let contour = prep
            .lengths()
            .iter()
            .map(|l| {
                ((l / total) * n_uniform as f64)
                    .ceil()
                    .max(MIN_CONTOUR as f64) as usize
            })
            .collect();
        Refinement {
            contour,
            pairs: vec![START_PAIRS; prep.refined_corners().count()],
            outer: if prep.outer {
                PAIRED_OUTER_CHARGES.1
            } else {
                0
            },
            sink: PAIRED_SINK_CHARGES,
        }
    }

    /// The layout this stands for in reports: N, and the mean
    /// pseudo-boundary distance over the contours' length.
    pub fn layout(&self, prep: &Prepared) -> super::Layout {
        let n = self.total(prep);
        let uniform: usize = self.contour.iter().sum();
        let clustered = n - uniform - self.outer - prep.sinks.len() * self.sink;
        super::Layout {
            n_total: n,
            distance: super::adaptive::DISTANCE_PER_SPACING * prep.perimeter()
                / uniform.max(1) as f64,
            corner_clusters: true,
            corner_fraction: clustered as f64 / (uniform + clustered).max(1) as f64,
            pairs: true,
        }
    }

    /// Singularities in all (uniform, clusters, outer ring and sinks).
    pub fn total(&self, prep: &Prepared) -> usize {
        self.contour.iter().sum::<usize>()
            + 2 * self.pairs.iter().sum::<usize>()
            + self.outer
            + prep.sinks.len() * self.sink
    }

    /// The next layout from the errors at the material's check points
    /// (`checks`, with `owner` their contours), or None when no part over
    /// `target` can grow.
    /// A sink whose error (`sinks`, the largest at each) is over the
    /// target gets [`SINK_STEP`] more charges, every sink alike.
    pub fn grown(
        &self,
        prep: &Prepared,
        checks: &[(Vec2, usize, f64)],
        sinks: &[f64],
        target: f64,
    ) -> Option<Refinement> {
        let spacing: Vec<f64> = prep
            .lengths()
            .iter()
            .zip(&self.contour)
            .map(|(l, &n)| l / n.max(1) as f64)
            .collect();
        let corners: Vec<(usize, Vec2)> = prep.refined_corners().collect();
        let mut corner_err = vec![0.0_f64; corners.len()];
        let mut contour_err = vec![0.0_f64; self.contour.len()];
        for &(p, ci, e) in checks {
            let h = spacing[ci];
            let mut near_any = false;
            for (k, &(ck, q)) in corners.iter().enumerate() {
                if ck != ci {
                    continue;
                }
                let d = p.dist(q);
                if d <= CLUSTER_REACH * h {
                    corner_err[k] = corner_err[k].max(e);
                }
                near_any |= d <= CONTOUR_REACH * h;
            }
            if !near_any {
                contour_err[ci] = contour_err[ci].max(e);
            }
        }
        let mut next = self.clone();
        if sinks.iter().any(|&e| e > target) && self.sink < MAX_SINK {
            next.sink = self.sink + SINK_STEP;
        }
        let mut grow_contour: Vec<bool> = contour_err.iter().map(|&e| e > target).collect();
        for (k, &e) in corner_err.iter().enumerate() {
            if e <= target {
                continue;
            }
            let n = self.pairs[k];
            if n >= MAX_PAIRS {
                grow_contour[corners[k].0] = true;
            } else {
                let grown = ((n as f64 * CLUSTER_GROWTH).ceil() as usize).max(n + 2);
                next.pairs[k] = grown.min(MAX_PAIRS);
            }
        }
        for (ci, grow) in grow_contour.into_iter().enumerate() {
            if grow {
                next.contour[ci] = (self.contour[ci] as f64 * CONTOUR_GROWTH).ceil() as usize;
            }
        }
        (next != *self).then_some(next)
    }
}

/// Refine from `n_uniform` uniform charges until the max boundary error is at
/// most `target` or the next layout would pass `n_max` singularities (or
/// [`MAX_ROUNDS`] solves). `solve` makes the caller's result of a problem
/// and the errors at its check points (in the problem's order). Returns the
/// first layout that meets the target, else the one of least error.
pub fn refine<T>(
    prep: &Prepared,
    n_uniform: usize,
    target: f64,
    n_max: usize,
    solve: impl Fn(&Problem) -> Result<(T, Vec<f64>), FieldError>,
) -> Result<Refined<T>, FieldError> {
    let mut r = Refinement::initial(prep, n_uniform);
    let mut best: Option<Refined<T>> = None;
    let mut last_err = None;
    let mut solves = 0;
    for _ in 0..MAX_ROUNDS {
        let (groups, owner) = prep.groups_refined(&r);
        let problem = groups.concat();
        solves += 1;
        let (out, errors) = match solve(&problem) {
            Ok(x) => x,
            Err(e) => {
                last_err = Some(e);
                break;
            }
        };
        let max_error = super::mfs::largest(&errors);
        if !max_error.is_finite() {
            last_err = Some(FieldError::NotANumberAtCheck);
            break;
        }
        if best.as_ref().is_none_or(|b| max_error < b.max_error) {
            best = Some(Refined {
                out,
                refinement: r.clone(),
                problem,
                max_error,
                solves,
            });
        }
        if max_error <= target {
            break;
        }
        let checks = material_checks(&groups, &owner, &errors);
        match r.grown(prep, &checks, &sink_errors(&groups, &errors), target) {
            Some(n) if n.total(prep) <= n_max => r = n,
            _ => break,
        }
    }
    match best {
        Some(b) => Ok(Refined { solves, ..b }),
        None => Err(last_err.unwrap_or(FieldError::NoLayoutSolved)),
    }
}

/// The material's check points with their contours and errors (the
/// problem's checks start with the material's).
fn material_checks(groups: &Groups, owner: &[usize], errors: &[f64]) -> Vec<(Vec2, usize, f64)> {
    groups
        .material
        .checks
        .iter()
        .zip(owner)
        .zip(errors)
        .map(|((c, &ci), &e)| (c.p, ci, e))
        .collect()
}

/// The largest error at each sink's check points (the problem's checks end
/// with the sinks', in order).
fn sink_errors(groups: &Groups, errors: &[f64]) -> Vec<f64> {
    let sizes: Vec<usize> = groups.sinks.iter().map(|(_, g)| g.checks.len()).collect();
    let mut end = errors.len();
    let mut out: Vec<f64> = sizes
        .iter()
        .rev()
        .map(|&n| {
            let start = end.saturating_sub(n);
            let e = super::mfs::largest(&errors[start..end]);
            end = start;
            e
        })
        .collect();
    out.reverse();
    out
}
