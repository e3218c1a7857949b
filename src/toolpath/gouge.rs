//! The independent gouge check: plain geometry on the flattened part, never the
//! field. Every move below the stock top, rapid or feed, is a straight segment
//! in XY (arcs are checked on their flattening); its smallest distance to the
//! part must be at least r − tolerance. (Whether a rapid also stays clear of the
//! material not yet cut is the stock simulation's question, not this one.)

use super::{Move, Toolpath, Vec3};
use crate::geometry::{arc, DistanceIndex, Vec2};

/// The result of a gouge check.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GougeReport {
    /// Smallest (distance to the part − r) over every move below the top, mm.
    pub min_clearance: f64,
    /// Where it was found (XY of the closest move's nearer end, and its Z).
    pub(crate) at: Vec3,
    /// Number of moves checked.
    pub(crate) moves_checked: usize,
}

impl GougeReport {
    /// True when no move comes closer to the part than r − `tol`.
    pub fn passes(&self, tol: f64) -> bool {
        self.min_clearance >= -tol
    }
}

/// Check every move below `top`, rapids included, against the part. Moves
/// above `top` are in air and not checked.
pub fn check(path: &Toolpath, part: &DistanceIndex, radius: f64, top: f64) -> GougeReport {
    let mut rep = GougeReport {
        min_clearance: f64::INFINITY,
        at: path.start,
        moves_checked: 0,
    };
    let mut at = path.start;
    for m in path.moves() {
        let to = m.to();
        let below = at.z.min(to.z) < top - 1e-9;
        match *m {
            Move::Linear { .. } | Move::Rapid { .. } if below => {
                let d = part.segment_distance(
                    Vec2::new(at.x, at.y),
                    Vec2::new(to.x, to.y),
                    radius * 2.0,
                );
                let c = d.min(2.0 * radius) - radius;
                rep.moves_checked += 1;
                if c < rep.min_clearance {
                    rep.min_clearance = c;
                    rep.at = to;
                }
            }
            Move::Arc { cx, cy, ccw, .. } if below => {
                let mut a = at.xy();
                for b in arc::flatten(a, to.xy(), Vec2::new(cx, cy), ccw, 1e-4) {
                    let d = part.segment_distance(a, b, radius * 2.0);
                    let c = d.min(2.0 * radius) - radius;
                    if c < rep.min_clearance {
                        rep.min_clearance = c;
                        rep.at = to;
                    }
                    a = b;
                }
                rep.moves_checked += 1;
            }
            _ => {}
        }
        at = to;
    }
    rep
}
