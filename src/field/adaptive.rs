//! A field to a required accuracy: the paired layout (`Layout::pairs`) with N
//! grown geometrically until the max boundary error on the check points is at
//! most the target.
//!
//! With pairs at the corners the error hardly depends on the pseudo-boundary
//! distance d between 1.5h and 4h (h = perimeter / N): on the paper's I, H, M
//! and S at N = 800 every d in that range is within 2.5× of the best
//! (`cargo run --release --example dscan -- I 800`). So one solve per N at
//! d = 2h replaces the 17-solve distance search, and the budget goes into N.

use super::{solve_layout, FieldError, Layout, Prepared, Solved, DEFAULT_CORNER_FRACTION};

/// Pseudo-boundary distance of an accurate solve, in units of the spacing h.
pub const DISTANCE_PER_SPACING: f64 = 2.0;

/// Factor by which N grows between two tries.
pub const GROWTH: f64 = 1.5;

/// What an accurate solve should reach, and within what.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Target {
    /// Max boundary error to reach.
    pub max_error: f64,
    /// First N tried.
    pub n_start: usize,
    /// Largest N tried.
    pub n_max: usize,
    /// A fixed pseudo-boundary distance (else `DISTANCE_PER_SPACING` h).
    pub distance: Option<f64>,
}

/// The paired layout for N charges.
fn layout(prep: &Prepared, n_total: usize, distance: Option<f64>) -> Layout {
    let h = prep.perimeter() / n_total as f64;
    Layout {
        n_total,
        distance: distance.unwrap_or(DISTANCE_PER_SPACING * h),
        corner_clusters: true,
        corner_fraction: DEFAULT_CORNER_FRACTION,
        pairs: true,
    }
}

/// Solve with N = n_start, n_start·1.5, … up to n_max, stopping at the first
/// whose max boundary error is at most the target. Returns that solve, or the
/// best one seen when none reaches it (the caller decides whether that is an
/// error: `Solved::solution.max_error` is the figure reached).
pub fn solve_to(prep: &Prepared, target: &Target) -> Result<Solved, FieldError> {
    let mut n = target.n_start.min(target.n_max);
    let mut best: Option<Solved> = None;
    let mut solves = 0;
    let mut last_err = None;
    loop {
        let lay = layout(prep, n, target.distance);
        match solve_layout(prep, &lay) {
            Ok((solution, m)) => {
                solves += 1;
                let solved = Solved {
                    solution,
                    layout: lay,
                    solves,
                    m,
                };
                if solved.solution.max_error <= target.max_error {
                    return Ok(solved);
                }
                if best
                    .as_ref()
                    .is_none_or(|b| solved.solution.better_than(&b.solution))
                {
                    best = Some(solved);
                }
            }
            Err(e) => last_err = Some(e),
        }
        if n >= target.n_max {
            break;
        }
        n = ((n as f64 * GROWTH).ceil() as usize).min(target.n_max);
    }
    match best {
        Some(mut b) => {
            b.solves = solves;
            Ok(b)
        }
        None => Err(last_err.unwrap_or(FieldError::Invalid("no layout could be solved".into()))),
    }
}
