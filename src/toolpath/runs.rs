//! The order of a boss level's ring runs: the pieces of the clearing rings
//! that cross the stock, each starting and ending in the air beside it.
//!
//! Ring j + 1 lies a stepover outside ring j, so a run of ring j may be cut
//! only once every run of ring j + 1 beside it is (otherwise the tool would
//! bury itself in the full width of both). Among the runs free to go, the
//! next is the one whose start is the shortest route away around the stock
//! ([`Keepout::route_length`]): the runs of one corner follow each other,
//! outermost first, instead of the tool crossing the stock between corners
//! for every ring.

use super::air::Keepout;
use crate::geometry::Vec2;

/// One run: its ring's index and its points.
pub type Run = (usize, Vec<Vec2>);

/// Whether two polylines come within `d` of each other (vertex to vertex, the
/// rings' points being far closer than a stepover).
fn near(a: &[Vec2], b: &[Vec2], d: f64) -> bool {
    let bbox = |p: &[Vec2]| {
        p.iter().fold(
            (Vec2::new(f64::MAX, f64::MAX), Vec2::new(f64::MIN, f64::MIN)),
            |(lo, hi), q| {
                (
                    Vec2::new(lo.x.min(q.x), lo.y.min(q.y)),
                    Vec2::new(hi.x.max(q.x), hi.y.max(q.y)),
                )
            },
        )
    };
    let ((alo, ahi), (blo, bhi)) = (bbox(a), bbox(b));
    if alo.x > bhi.x + d || blo.x > ahi.x + d || alo.y > bhi.y + d || blo.y > ahi.y + d {
        return false;
    }
    let d2 = d * d;
    a.iter().any(|p| {
        b.iter()
            .any(|q| (p.x - q.x).powi(2) + (p.y - q.y).powi(2) <= d2)
    })
}

/// The runs reordered: each after the runs of the ring outside it that come
/// within `reach` of it, and otherwise the nearest around the stock from where
/// the last ended, starting from `from`.
pub fn order_runs(runs: Vec<Run>, reach: f64, keep: &Keepout, from: Vec2) -> Vec<Run> {
    let n = runs.len();
    // waits[i]: how many runs of the next ring out, beside run i, are uncut.
    let mut waits = vec![0usize; n];
    let mut frees: Vec<Vec<usize>> = vec![Vec::new(); n];
    for i in 0..n {
        for k in 0..n {
            if runs[k].0 == runs[i].0 + 1 && near(&runs[i].1, &runs[k].1, reach) {
                waits[i] += 1;
                frees[k].push(i);
            }
        }
    }
    let mut done = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let mut at = from;
    for _ in 0..n {
        // A run with nothing to wait for always exists: the largest ring's.
        let next = (0..n)
            .filter(|&i| !done[i] && waits[i] == 0)
            .min_by(|&a, &b| {
                keep.route_length(at, runs[a].1[0])
                    .total_cmp(&keep.route_length(at, runs[b].1[0]))
            });
        let Some(i) = next else { break };
        done[i] = true;
        for &k in &frees[i] {
            waits[k] -= 1;
        }
        at = *runs[i].1.last().unwrap_or(&at);
        order.push(i);
    }
    // Anything left by a cycle (impossible: ring indices only grow) keeps its
    // place after the rest.
    order.extend((0..n).filter(|&i| !done[i]));
    let mut slots: Vec<Option<Run>> = runs.into_iter().map(Some).collect();
    order.into_iter().filter_map(|i| slots[i].take()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two corners of a 100 × 50 stock, two rings each: the runs of a corner
    /// follow each other, outer ring first.
    #[test]
    fn runs_of_a_corner_follow_each_other_outer_first() {
        let keep = Keepout::around_stock(Vec2::new(0.0, 0.0), Vec2::new(100.0, 50.0), 1.0);
        // Ring j cuts the corner along a diagonal; ring j - 1 is 1.2 mm
        // further in.
        let seg = |a: Vec2, b: Vec2| -> Vec<Vec2> {
            (0..=10).map(|k| a + (b - a) * (k as f64 / 10.0)).collect()
        };
        let ll = |c: f64| seg(Vec2::new(-2.0, c + 2.0), Vec2::new(c + 2.0, -2.0));
        let ur = |c: f64| seg(Vec2::new(102.0, 48.0 - c), Vec2::new(98.0 - c, 52.0));
        let (ll, ur) = (
            |j: usize| ll(if j == 3 { 6.0 } else { 7.7 }),
            |j: usize| ur(if j == 3 { 6.0 } else { 7.7 }),
        );
        let runs = vec![(3, ll(3)), (2, ur(2)), (2, ll(2)), (3, ur(3))];
        let order = order_runs(runs, 2.0, &keep, Vec2::new(-5.0, -5.0));
        let js: Vec<usize> = order.iter().map(|r| r.0).collect();
        assert_eq!(js, vec![3, 2, 3, 2]);
        // The first two are the lower-left corner's.
        assert!(order[0].1[0].x < 50.0 && order[1].1[0].x < 50.0);
        assert!(order[2].1[0].x > 50.0 && order[3].1[0].x > 50.0);
    }
}
