//! Entries into material: how the tool comes down from safe Z to the start of a
//! path, knowing the stock ([`StockMap`]).
//!
//! The rapid stops [`CLEARANCE`] above the highest material under the tool disk
//! (or above the path's own depth where nothing is left there). From the
//! material top the tool goes on at the ramp angle: around a closed loop (several
//! laps if it is short) or back and forth along the start of an open run. The
//! ramp starts as high as the highest material anywhere under its own trail, so
//! it never meets a wall steeper than the ramp. A straight feed down happens only
//! through air.

use super::stock::StockMap;
use super::{Move, Vec3};
use crate::geometry::Vec2;

/// Height above the material left where an entry's rapid stops, mm.
pub(crate) const CLEARANCE: f64 = 0.5;

/// Slack for comparing heights, mm: far below any cut.
const EPS: f64 = 1e-6;

/// Longest walk of a ramp, in path points (bounds the loop for a degenerate
/// path of zero length).
const MAX_RAMP_STEPS: usize = 1_000_000;

/// What an entry needs to know about the tool and the set-up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Entry {
    /// Tool radius, mm.
    pub(crate) radius: f64,
    /// Ramp angle, degrees.
    pub(crate) ramp_angle: f64,
    /// Feed for ramps and plunges in air, mm/min.
    pub(crate) plunge_feed: f64,
    /// Cutting feed, mm/min.
    pub(crate) feed: f64,
    /// Safe Z for rapids.
    pub(crate) safe_z: f64,
    /// Stock top Z.
    pub(crate) top: f64,
}

impl Entry {
    fn ramp_len(&self, drop: f64) -> f64 {
        drop.max(0.0) / self.ramp_angle.to_radians().tan()
    }

    /// Feed along a ramp, mm/min ([`ramp_feed`]).
    pub(crate) fn ramp_feed(&self) -> f64 {
        ramp_feed(self.feed, self.plunge_feed, self.ramp_angle)
    }
}

/// Feed along a ramp at `ramp_angle` degrees, mm/min: the cutting `feed`,
/// slowed only as far as needed for the tool to go down no faster than
/// `plunge_feed` (F·sin(angle) ≤ plunge feed). The roughing's entries and the
/// finisher's both ramp at it.
pub(crate) fn ramp_feed(feed: f64, plunge_feed: f64, ramp_angle: f64) -> f64 {
    let sin = ramp_angle.to_radians().sin();
    if sin > 0.0 {
        feed.min(plunge_feed / sin)
    } else {
        feed
    }
}

/// The points a ramp walks after `pts[0]`: round a closed loop (last = first)
/// again and again, or forth and back along an open run.
fn ramp_points(pts: &[Vec2], closed: bool) -> impl Iterator<Item = Vec2> + '_ {
    let n = pts.len().saturating_sub(1).max(1);
    let period = 2 * n;
    (1..=MAX_RAMP_STEPS).map(move |i| {
        let j = if closed {
            i % n
        } else {
            let j = i % period;
            if j <= n {
                j
            } else {
                period - j
            }
        };
        pts[j.min(pts.len() - 1)]
    })
}

/// Ramp moves from `start` at `z_from` down to `z`, over the points of `seq` in
/// turn, descending with the distance walked until `ramp_len` is reached (the
/// last move ends part-way along a segment, at `z`). Returns the points walked
/// (from `start` to where the ramp ended) and the number of whole segments.
fn descend(
    seq: impl Iterator<Item = Vec2>,
    start: Vec2,
    (z_from, z): (f64, f64),
    ramp_len: f64,
    ramp_feed: f64,
    out: &mut Vec<Move>,
) -> (Vec<Vec2>, usize) {
    let drop = z_from - z;
    let mut walked = 0.0;
    let mut trail = vec![start];
    let mut at = start;
    for (steps, next) in seq.enumerate() {
        let seg = at.dist(next);
        if walked + seg >= ramp_len {
            let t = if seg > 0.0 {
                (ramp_len - walked) / seg
            } else {
                1.0
            };
            let q = at.lerp(next, t);
            out.push(Move::Linear {
                to: Vec3::new(q.x, q.y, z),
                feed: ramp_feed,
            });
            trail.push(q);
            return (trail, steps);
        }
        walked += seg;
        out.push(Move::Linear {
            to: Vec3::new(next.x, next.y, z_from - drop * walked / ramp_len),
            feed: ramp_feed,
        });
        trail.push(next);
        at = next;
    }
    let steps = trail.len() - 1;
    (trail, steps)
}

/// The XY trail of a ramp dropping `drop` into `pts`.
fn ramp_trail(pts: &[Vec2], closed: bool, drop: f64, e: &Entry) -> Vec<Vec2> {
    let mut scratch = Vec::new();
    let len = e.ramp_len(drop);
    let seq = ramp_points(pts, closed);
    descend(seq, pts[0], (drop, 0.0), len, 1.0, &mut scratch).0
}

/// Moves that enter a closed loop by ramping down along it from `z_from` to `z`
/// at the ramp angle (several laps if the loop is short), then cut one full lap
/// at `z` from where the ramp ended.
pub(crate) fn ramp_loop(lp: &[Vec2], z_from: f64, z: f64, e: &Entry, out: &mut Vec<Move>) {
    let n = lp.len() - 1;
    let drop = (z_from - z).max(0.0);
    let (mut k, mut at) = (0, lp[0]);
    if drop > 0.0 {
        let seq = ramp_points(lp, true);
        let len = e.ramp_len(drop);
        let (trail, steps) = descend(seq, lp[0], (z_from, z), len, e.ramp_feed(), out);
        k = steps % n.max(1);
        at = *trail.last().unwrap_or(&lp[0]);
    }
    // One full lap at z from `at` (which lies on segment k → k+1).
    for step in 1..=n {
        let q = lp[(k + step) % n];
        out.push(Move::Linear {
            to: Vec3::new(q.x, q.y, z),
            feed: e.feed,
        });
    }
    out.push(Move::Linear {
        to: Vec3::new(at.x, at.y, z),
        feed: e.feed,
    });
}

/// Moves that enter an open path by ramping from `z_from` to `z` at the ramp
/// angle back and forth along its start, ending at its first point at `z`.
pub(crate) fn ramp_open(pts: &[Vec2], z_from: f64, z: f64, e: &Entry, out: &mut Vec<Move>) {
    let drop = (z_from - z).max(0.0);
    if drop <= 0.0 || pts.len() < 2 {
        out.push(Move::Linear {
            to: Vec3::new(pts[0].x, pts[0].y, z),
            feed: e.plunge_feed,
        });
        return;
    }
    let seq = ramp_points(pts, false);
    let len = e.ramp_len(drop);
    let (trail, _) = descend(seq, pts[0], (z_from, z), len, e.ramp_feed(), out);
    // Back to the start at depth, along the trail just ramped.
    for q in trail.iter().rev().skip(1) {
        out.push(Move::Linear {
            to: Vec3::new(q.x, q.y, z),
            feed: e.feed,
        });
    }
}

/// Rotate a closed loop (last = first) so it starts at the vertex nearest to `p`.
pub(crate) fn start_near(lp: &[Vec2], p: Vec2) -> Vec<Vec2> {
    let n = lp.len() - 1;
    let k = (0..n)
        .min_by(|&a, &b| lp[a].dist(p).total_cmp(&lp[b].dist(p)))
        .unwrap_or(0);
    let mut out: Vec<Vec2> = (0..n).map(|i| lp[(k + i) % n]).collect();
    out.push(out[0]);
    out
}

/// The Z a ramp into `pts` down to `z` must start from: the highest material
/// under the tool anywhere along the ramp's own trail (whose length depends on
/// that height, hence the few rounds; if they do not settle, the trail of a
/// ramp from the stock top, which covers every shorter one). `-∞` or a value
/// ≤ `z` when the start is in air.
pub(crate) fn ramp_start(stock: &StockMap, pts: &[Vec2], closed: bool, z: f64, e: &Entry) -> f64 {
    let mut z_from = stock.top_near(pts[0], e.radius);
    if z_from <= z + EPS {
        return z_from;
    }
    for _ in 0..6 {
        let trail = ramp_trail(pts, closed, z_from - z, e);
        let top = stock.top_near_path(&trail, e.radius);
        if top <= z_from + EPS {
            return z_from;
        }
        z_from = top;
    }
    let trail = ramp_trail(pts, closed, e.top - z, e);
    stock.top_near_path(&trail, e.radius).max(z_from)
}

/// Come down from safe Z over `pts[0]` (where the tool already is) and enter
/// the path at `z`: rapid to [`CLEARANCE`] above the material left under the
/// tool, then ramp from the material top ([`ramp_start`]); where there is none,
/// straight down through air. A closed loop is then cut one full lap; an open
/// run is left at its first point at `z` for the caller to cut.
pub(crate) fn enter(
    stock: &StockMap,
    pts: &[Vec2],
    closed: bool,
    z: f64,
    e: &Entry,
    out: &mut Vec<Move>,
) {
    let first = pts[0];
    let z_from = ramp_start(stock, pts, closed, z, e);
    let floor = z_from.max(z);
    out.push(Move::Rapid {
        to: Vec3::new(first.x, first.y, (floor + CLEARANCE).min(e.safe_z)),
    });
    out.push(Move::Linear {
        to: Vec3::new(first.x, first.y, floor),
        feed: e.plunge_feed,
    });
    match closed {
        true => ramp_loop(pts, floor, z, e, out),
        false => ramp_open(pts, floor, z, e, out),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ramp into an open path shorter than the ramp goes back and forth along
    /// it, never straight down, reaches the depth at the ramp angle, and ends at
    /// the path's start at depth.
    #[test]
    fn an_open_path_is_entered_back_and_forth_at_the_ramp_angle() {
        let pts = [
            Vec2::new(0.0, 0.0),
            Vec2::new(3.0, 0.0),
            Vec2::new(3.0, 2.0),
        ];
        let (z_from, z, angle) = (-1.0, -2.0, 3.0);
        let mut out = Vec::new();
        let e = Entry {
            radius: 1.0,
            ramp_angle: angle,
            plunge_feed: 100.0,
            feed: 500.0,
            safe_z: 5.0,
            top: 0.0,
        };
        ramp_open(&pts, z_from, z, &e, &mut out);
        let mut at = Vec3::new(0.0, 0.0, z_from);
        let mut walked = 0.0;
        for m in &out {
            let to = m.to();
            let d = ((to.x - at.x).powi(2) + (to.y - at.y).powi(2)).sqrt();
            assert!(d > 1e-9, "a vertical move to {to:?}");
            assert!(to.z >= z - 1e-12 && to.z <= at.z + 1e-12);
            if to.z < at.z {
                walked += d;
                let slope = (at.z - to.z) / d;
                assert!((slope - angle.to_radians().tan()).abs() < 1e-9);
            }
            at = to;
        }
        // 1 mm at 3° is about 19 mm of ramp on a 5 mm path: several passes.
        assert!((walked - 1.0 / angle.to_radians().tan()).abs() < 1e-9);
        assert_eq!((at.x, at.y, at.z), (0.0, 0.0, z));
    }
}
