//! The profile operation: the tool centre traced around every outline (outside)
//! and inside every counter the tool fits into, cut in passes of at most
//! `stepdown` from the stock top to the depth.

use super::trace::{trace, Navigator, TraceError, TraceParams};
use super::{Move, Section, Toolpath, Vec3};
pub use crate::geometry::deepest_point;
use crate::geometry::{DistanceIndex, Shape, Vec2};

/// Settings of a profile, mm and mm/min.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProfileParams {
    /// Tool radius.
    pub radius: f64,
    /// Chord tolerance.
    pub tol: f64,
    /// Climb milling (material on the tool's right with an M3 spindle).
    pub climb: bool,
    /// Stock top Z.
    pub top: f64,
    /// Depth below the top.
    pub depth: f64,
    /// Largest depth per pass.
    pub stepdown: f64,
    /// Safe Z for rapids.
    pub safe_z: f64,
    /// Cutting feed.
    pub feed: f64,
    /// Plunge feed.
    pub plunge_feed: f64,
}

/// One traced loop.
#[derive(Clone, Debug, PartialEq)]
pub struct Loop {
    /// e.g. `outside A (1)` or `counter 1 of A (1)`.
    pub label: String,
    /// Centre positions, closed (last = first).
    pub points: Vec<Vec2>,
    /// Field fallbacks (see `Traced::fallbacks`).
    pub fallbacks: usize,
}

/// Why a profile failed.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ProfileError {
    /// Tracing one loop failed.
    #[error("tracing {label}: {source}")]
    Trace {
        /// which loop
        label: String,
        /// why
        source: TraceError,
    },
    /// A field solved for a path (a cavity's inverse problem) failed.
    #[error("{0}")]
    Field(#[from] crate::field::FieldError),
}

/// Z of every pass: equal steps of at most `stepdown`, the last exactly at the depth.
pub fn pass_depths(top: f64, depth: f64, stepdown: f64) -> Vec<f64> {
    let n = ((depth / stepdown) - 1e-9).ceil().max(1.0) as usize;
    (1..=n).map(|k| top - depth * k as f64 / n as f64).collect()
}

/// Trace every loop of the shape: for each region, its counters (inside first, so
/// the part is still held while its holes are cut), then its outline.
/// `polys[i]` is the flattening of the i-th contour of `shape.contours()`.
pub fn trace_loops<N: Navigator + Sync>(
    shape: &Shape,
    polys: &[Vec<Vec2>],
    part: &DistanceIndex,
    nav: &N,
    p: &ProfileParams,
    warnings: &mut Vec<String>,
) -> Result<Vec<Loop>, ProfileError> {
    use rayon::prelude::*;
    let r = p.radius;
    let tp = TraceParams {
        radius: r,
        tol: p.tol,
        part_on_left: !p.climb,
    };
    // (label, start point) for every loop, in cutting order.
    let mut jobs: Vec<(String, Vec2)> = Vec::new();
    let mut k = 0;
    for region in &shape.regions {
        let outline_poly = &polys[k];
        k += 1;
        for (ci, _) in region.counters.iter().enumerate() {
            let poly = &polys[k];
            k += 1;
            let label = format!("counter {} of {}", ci + 1, region.name);
            let (deep, room) = deepest_point(poly, part);
            if room < r + p.tol {
                warnings.push(format!(
                    "{label} is too small for the tool (largest inscribed radius {room:.3} mm, tool radius {r:.3} mm): not cut"
                ));
                continue;
            }
            jobs.push((label, deep));
        }
        // Outside: start below the lowest point of the outline.
        let low = outline_poly.iter().copied().fold(outline_poly[0], |a, b| {
            if b.y < a.y || (b.y == a.y && b.x < a.x) {
                b
            } else {
                a
            }
        });
        jobs.push((
            format!("outside {}", region.name),
            low - Vec2::new(0.0, 2.0 * r + 1.0),
        ));
    }
    jobs.par_iter()
        .map(|(label, start)| {
            trace(nav, part, *start, tp)
                .map(|t| Loop {
                    label: label.clone(),
                    points: t.points,
                    fallbacks: t.fallbacks,
                })
                .map_err(|source| ProfileError::Trace {
                    label: label.clone(),
                    source,
                })
        })
        .collect()
}

/// Link the loops into a tool path: for each loop, rapid above its start at safe Z,
/// rapid down to 1 mm above the stock, plunge to each pass depth at the plunge feed
/// and cut the loop at the feed (the loop closes at its start, so the next pass
/// plunges in place), then retract to safe Z.
pub fn link(loops: &[Loop], p: &ProfileParams) -> Toolpath {
    let depths = pass_depths(p.top, p.depth, p.stepdown);
    let start = Vec3::new(0.0, 0.0, p.safe_z);
    let approach = (p.top + 1.0).min(p.safe_z);
    let mut sections = Vec::new();
    for lp in loops {
        let s0 = lp.points[0];
        let mut moves = vec![
            Move::Rapid {
                to: Vec3::new(s0.x, s0.y, p.safe_z),
            },
            Move::Rapid {
                to: Vec3::new(s0.x, s0.y, approach),
            },
        ];
        for &z in &depths {
            moves.push(Move::Linear {
                to: Vec3::new(s0.x, s0.y, z),
                feed: p.plunge_feed,
            });
            for q in &lp.points[1..] {
                moves.push(Move::Linear {
                    to: Vec3::new(q.x, q.y, z),
                    feed: p.feed,
                });
            }
        }
        moves.push(Move::Rapid {
            to: Vec3::new(s0.x, s0.y, p.safe_z),
        });
        sections.push(Section {
            label: lp.label.clone(),
            z: p.top - p.depth,
            moves,
        });
    }
    Toolpath { start, sections }
}
