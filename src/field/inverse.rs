//! The inverse problem of a cavity level (the paper's Section 4): u = 1 on
//! the boundary ∂V of the region V the tool centre may reach, u = 0 on small
//! sink circles deep inside V. Its equipotentials are smooth nested rings from
//! the wall in to the sinks, which `toolpath::inverse` cuts as clearing rings
//! where offset rings could not be built.
//!
//! - Sinks ([`sinks`]): the points of V farthest from ∂V (on a grid of
//!   spacing h), only those at least half as deep as the deepest, each at
//!   least 2.5 × its depth (and 4 sink radii) from the others, at most
//!   [`MAX_SINKS`]; a sink's radius is a quarter of its depth. A sink near ∂V
//!   would force u from 1 to 0 over a short distance there and crowd the
//!   rings against the wall.
//! - Solve ([`solve`]): one quick MFS solve ([`super::solve_quick`]) with the
//!   outer charges, [`super::setup::SINK_CHARGES`] per sink and one charge per
//!   half stepover of ∂V (at least 60), pseudo-boundary at 1 mm.

use super::isolines::Grid;
use super::{Boundary, Field, FieldError, Layout, Prepared, Sink};
use crate::geometry::{Contour, DistanceIndex, Segment, Vec2};

/// Most sinks of one inverse problem.
pub const MAX_SINKS: usize = 80;

/// The sinks of the region bounded by `v` (indexed by `vindex`), searched on
/// a grid of spacing `h` over `lo`..`hi` whose points outside V are those
/// inside `mask` (see the module docs).
pub fn sinks(vindex: &DistanceIndex, lo: Vec2, hi: Vec2, h: f64, mask: &[Vec<Vec2>]) -> Vec<Sink> {
    let probe = Grid::sample(&Field::new(vec![], vec![]), lo, hi, h, mask);
    let mut cand: Vec<(f64, Vec2)> = Vec::new();
    for j in 0..probe.ny {
        for i in 0..probe.nx {
            if !probe.inside[j * probe.nx + i] {
                let q = Vec2::new(probe.origin.x + h * i as f64, probe.origin.y + h * j as f64);
                cand.push((vindex.distance(q), q));
            }
        }
    }
    cand.sort_by(|a, b| {
        b.0.total_cmp(&a.0)
            .then(a.1.x.total_cmp(&b.1.x))
            .then(a.1.y.total_cmp(&b.1.y))
    });
    let dmax = cand.first().map_or(0.0, |c| c.0);
    let mut sinks: Vec<Sink> = Vec::new();
    for &(d, q) in &cand {
        if d < 0.5 * dmax || d < 0.5 * h {
            break;
        }
        if sinks
            .iter()
            .all(|s| s.centre.dist(q) >= 2.5 * d.max(4.0 * s.radius))
        {
            sinks.push(Sink {
                centre: q,
                radius: 0.25 * d,
            });
            if sinks.len() >= MAX_SINKS {
                break;
            }
        }
    }
    sinks
}

/// The field of the inverse problem on the closed loops `v` (oriented:
/// outside V on their left) with `sinks`, its charges spaced for rings a
/// `stepover` apart; `lo`..`hi` is the box of `v`, `tol` the chord tolerance.
pub fn solve(
    v: &[Vec<Vec2>],
    sinks: &[Sink],
    lo: Vec2,
    hi: Vec2,
    stepover: f64,
    tol: f64,
) -> Result<Field, FieldError> {
    let contours: Vec<Contour> = v
        .iter()
        .filter_map(|l| {
            let n = l.len();
            Contour::new(
                (0..n)
                    .map(|i| Segment::Line {
                        a: l[i],
                        b: l[(i + 1) % n],
                    })
                    .collect(),
            )
            .ok()
        })
        .collect();
    let is_counter = vec![false; contours.len()];
    let b = Boundary::about_centroid(contours, is_counter, 20.0 * (hi - lo).norm().max(1.0), tol);
    let prep = Prepared::with_sinks(b, sinks.to_vec())?;
    let n_total = super::setup::OUTER_CHARGES
        + sinks.len() * super::setup::SINK_CHARGES
        + (prep.perimeter() / (0.5 * stepover)).ceil().max(60.0) as usize;
    let solved = super::solve_quick(
        &prep,
        Layout {
            n_total,
            distance: 1.0,
            corner_clusters: false,
            corner_fraction: 0.0,
            pairs: false,
        },
    )?;
    Ok(solved.solution.field)
}
