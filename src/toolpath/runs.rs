//! The order of a boss level's clearing rings: closed rings and the runs of
//! rings that cross the stock's edge (each starting and ending in the air
//! beside it).
//!
//! Ring j + 1 lies a stepover outside ring j, so a piece of ring j may be cut
//! only once every piece of ring j + 1 beside it is (otherwise the tool would
//! bury itself in the full width of both). Among the pieces free to go, the
//! next is the one nearest to where the tool is: an open run by the route to
//! its start (around the stock, [`Keepout::route_length`], when both ends are
//! beside it), a closed ring by its nearest point, where it will be entered.
//! The runs of one corner follow each other, outermost first, instead of the
//! tool crossing the stock between corners for every ring, and a level starts
//! near where the level before it ended.

use super::air::Keepout;
use crate::geometry::{densify, Vec2};
use std::collections::HashMap;

/// One piece to order.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Piece<'a> {
    /// Its ring's index (0 = the finishing ring at the wall radius).
    pub(crate) ring: usize,
    /// Its points (a closed ring's last equals its first).
    pub(crate) points: &'a [Vec2],
    /// A closed ring, entered anywhere, or an open run, entered at its start.
    pub(crate) closed: bool,
}

/// A hash of points in square cells of side `d`: which of them lie within
/// `d` of a point.
struct Cells {
    d: f64,
    map: HashMap<(i64, i64), Vec<Vec2>>,
}

impl Cells {
    fn new(pts: &[Vec2], d: f64) -> Cells {
        let mut map: HashMap<(i64, i64), Vec<Vec2>> = HashMap::new();
        for &p in pts {
            map.entry(Self::key(p, d)).or_default().push(p);
        }
        Cells { d, map }
    }

    fn key(p: Vec2, d: f64) -> (i64, i64) {
        ((p.x / d).floor() as i64, (p.y / d).floor() as i64)
    }

    fn near(&self, p: Vec2) -> bool {
        let (i, j) = Self::key(p, self.d);
        (i - 1..=i + 1).any(|a| {
            (j - 1..=j + 1).any(|b| {
                self.map
                    .get(&(a, b))
                    .is_some_and(|v| v.iter().any(|q| q.dist(p) <= self.d))
            })
        })
    }
}

/// Where the tool enters `piece` coming from `at`, and the length of the way
/// there.
fn approach(piece: &Piece, at: Vec2, keep: &Keepout) -> (Vec2, f64) {
    if piece.closed {
        let n = piece.points.len().saturating_sub(1).max(1);
        piece.points[..n]
            .iter()
            .map(|&q| (q, at.dist(q)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((at, 0.0))
    } else {
        let q = piece.points[0];
        if keep.clear(at) && keep.clear(q) {
            (q, keep.route_length(at, q))
        } else {
            (q, at.dist(q))
        }
    }
}

/// The order to cut `pieces` in (indices): each after the pieces of the ring
/// outside it that come within `reach` of it, and otherwise the nearest to
/// where the tool is, starting at `from`.
pub(crate) fn order(pieces: &[Piece], reach: f64, keep: &Keepout, from: Vec2) -> Vec<usize> {
    let n = pieces.len();
    let pts: Vec<Vec<Vec2>> = pieces
        .iter()
        .map(|p| densify(p.points, 0.5 * reach, false))
        .collect();
    let cells: Vec<Cells> = pts.iter().map(|p| Cells::new(p, reach)).collect();
    // waits[i]: how many uncut pieces of the next ring out lie beside piece i.
    let mut waits = vec![0usize; n];
    let mut frees: Vec<Vec<usize>> = vec![Vec::new(); n];
    for i in 0..n {
        for k in 0..n {
            if pieces[k].ring == pieces[i].ring + 1 && pts[i].iter().any(|&q| cells[k].near(q)) {
                waits[i] += 1;
                frees[k].push(i);
            }
        }
    }
    let mut done = vec![false; n];
    let mut out = Vec::with_capacity(n);
    let mut at = from;
    for _ in 0..n {
        // Some piece is always free: those of the largest ring wait for none.
        let next = (0..n)
            .filter(|&i| !done[i] && waits[i] == 0)
            .map(|i| (i, approach(&pieces[i], at, keep)))
            .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1));
        let Some((i, (entry, _))) = next else { break };
        done[i] = true;
        for &k in &frees[i] {
            waits[k] -= 1;
        }
        at = if pieces[i].closed {
            entry
        } else {
            *pieces[i].points.last().unwrap_or(&entry)
        };
        out.push(i);
    }
    // A cycle cannot happen (a piece waits only for a larger ring); anything
    // left keeps its place after the rest.
    out.extend((0..n).filter(|&i| !done[i]));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pieces of the given rings and points, all open or all closed.
    fn pieces(rings: &[(usize, Vec<Vec2>)], closed: bool) -> Vec<Piece<'_>> {
        rings
            .iter()
            .map(|(j, p)| Piece {
                ring: *j,
                points: p,
                closed,
            })
            .collect()
    }

    fn seg(a: Vec2, b: Vec2) -> Vec<Vec2> {
        (0..=10).map(|k| a + (b - a) * (k as f64 / 10.0)).collect()
    }

    /// Two corners of a 100 × 50 stock, two rings each, cutting each corner
    /// along a diagonal, ring 2 1.2 mm inside ring 3: the runs of a corner
    /// follow each other, outer ring first.
    #[test]
    fn runs_of_a_corner_follow_each_other_outer_first() {
        let keep = Keepout::around_stock(Vec2::new(0.0, 0.0), Vec2::new(100.0, 50.0), 1.0);
        let ll = |c: f64| seg(Vec2::new(-2.0, c + 2.0), Vec2::new(c + 2.0, -2.0));
        let ur = |c: f64| seg(Vec2::new(102.0, 48.0 - c), Vec2::new(98.0 - c, 52.0));
        let runs = [(3, ll(6.0)), (2, ur(7.7)), (2, ll(7.7)), (3, ur(6.0))];
        let pieces = pieces(&runs, false);
        let o = order(&pieces, 2.0, &keep, Vec2::new(-5.0, -5.0));
        assert_eq!(o, vec![0, 2, 3, 1]);
    }

    /// Closed rings: an inner ring never before the ring around it, and two
    /// letters' rings taken letter by letter from where the tool is.
    #[test]
    fn closed_rings_wait_for_the_ring_outside_and_go_nearest_first() {
        let keep = Keepout::around_stock(Vec2::new(-50.0, -50.0), Vec2::new(150.0, 50.0), 1.0);
        let circle = |c: Vec2, r: f64| -> Vec<Vec2> {
            (0..=40)
                .map(|k| {
                    let t = std::f64::consts::TAU * k as f64 / 40.0;
                    c + Vec2::new(r * t.cos(), r * t.sin())
                })
                .collect()
        };
        let (a, b) = (Vec2::new(0.0, 0.0), Vec2::new(100.0, 0.0));
        let rings = [
            (1, circle(a, 10.0)),
            (2, circle(b, 11.2)),
            (2, circle(a, 11.2)),
            (1, circle(b, 10.0)),
        ];
        let pieces = pieces(&rings, true);
        // From beside b: b's rings first, outer then inner, then a's.
        let o = order(&pieces, 2.0, &keep, Vec2::new(120.0, 0.0));
        assert_eq!(o, vec![1, 3, 2, 0]);
        // From beside a, the other way round.
        let o = order(&pieces, 2.0, &keep, Vec2::new(-20.0, 0.0));
        assert_eq!(o, vec![2, 0, 1, 3]);
    }
}
