//! Marching squares: the level curve {u = s} of a function sampled on a lattice,
//! as chains of the lattice edges it crosses.
//!
//! The lattice has points (i, j), 0 ≤ i ≤ nx, 0 ≤ j ≤ ny, and nx × ny cells; cell
//! (i, j) has corners 0 (i, j), 1 (i+1, j), 2 (i+1, j+1), 3 (i, j+1),
//! counter-clockwise, and sides k = 0 (bottom), 1 (right), 2 (top), 3 (left), side
//! k running from corner k to corner k+1. A corner is *above* when u ≥ s. A side
//! whose two corners differ is *crossed*: the curve meets it once. Each cell
//! joins its crossed sides in pairs by segments:
//!
//! - two crossed sides (one corner cut off, or the cell split across): one
//!   segment;
//! - four (a *saddle*: corners 0 and 2 on one side of s, 1 and 3 on the other):
//!   the bilinear interpolant's value at the centre, the mean of the four
//!   corners, decides which diagonal pair is connected through the middle; the
//!   other two corners are cut off, two segments.
//!
//! A crossing belongs to at most two segments (the two cells on either side of
//! its edge), so the segments chain into curves: *open* ones from an end (a
//! crossing on the lattice's border or next to a skipped cell, see [`Gaps`]) to
//! the other, and *closed* ones (rings). Along a segment from side a to side b,
//! u ≥ s lies on the left exactly when corner a is above, and this orientation
//! agrees along a whole curve.
//!
//! Placing a vertex on its crossed edge (linear interpolation, root finding,
//! Newton steps on the field) is the caller's: here a curve is the sequence of
//! its edges.

use std::collections::HashMap;

/// Edge of the lattice, by its lower/left point: horizontal (i, j)–(i+1, j) or
/// vertical (i, j)–(i, j+1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Edge {
    H(usize, usize),
    V(usize, usize),
}

impl Edge {
    /// The lattice points at the two ends of the edge, lower/left first.
    pub(super) fn ends(self) -> [(usize, usize); 2] {
        match self {
            Edge::H(i, j) => [(i, j), (i + 1, j)],
            Edge::V(i, j) => [(i, j), (i, j + 1)],
        }
    }
}

/// What a cell with a non-finite corner value means.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Gaps {
    /// The cell is skipped: the curve ends, open, at its crossed sides (a NaN
    /// marks a point where u is not to be evaluated).
    Skip,
    /// The values are compared as they are: −∞ and NaN are below every level,
    /// +∞ above (a border padded with −∞ closes every curve above it).
    Compare,
}

/// One connected piece of {u = s}.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Curve {
    /// Indices into [`Level::edges`], in order along the curve; for a closed
    /// curve the first is not repeated.
    pub crossings: Vec<usize>,
    /// True for a ring, false for a curve between two ends.
    pub closed: bool,
    /// Whether u ≥ s lies on the left in the order of `crossings`.
    high_left: bool,
}

/// {u = s} on the lattice.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Level {
    /// The crossed edges, in the order the scan of the cells (rows j upward,
    /// each from i = 0) first meets them.
    pub edges: Vec<Edge>,
    /// Open curves first, each from its end met first by the scan; then the
    /// rings, in the scan order of their first cell (lowest, then leftmost),
    /// each from that cell's right side toward its top: clockwise.
    pub curves: Vec<Curve>,
}

impl Level {
    /// The rings as chains of edges, each turned (from the same first edge) so
    /// that u ≥ s lies on its left: counter-clockwise around a region above s,
    /// clockwise around one below. A ring crosses at least four edges (the
    /// smallest closes around one lattice point).
    pub(super) fn rings(self) -> Vec<Vec<Edge>> {
        let edges = self.edges;
        self.curves
            .into_iter()
            .filter(|c| c.closed)
            .map(|mut c| {
                if !c.high_left {
                    c.crossings[1..].reverse();
                }
                c.crossings.into_iter().map(|k| edges[k]).collect()
            })
            .collect()
    }
}

/// {u = s} on the lattice of `nx` × `ny` cells whose point (i, j) has the value
/// `value(i, j)` (see the module docs). Deterministic: the same values give the
/// same edges and curves, in the same order.
pub(super) fn level(
    nx: usize,
    ny: usize,
    value: impl Fn(usize, usize) -> f64,
    s: f64,
    gaps: Gaps,
) -> Level {
    let (edges, segs) = segments(nx, ny, value, s, gaps);
    let curves = chain(&segs, edges.len());
    Level { edges, curves }
}

/// A segment between two crossings (indices into the edges), and whether u ≥ s
/// lies on its left going from the first to the second.
type Segment = ((usize, usize), bool);

/// The crossed edges and the segments of every cell, cells in scan order.
fn segments(
    nx: usize,
    ny: usize,
    value: impl Fn(usize, usize) -> f64,
    s: f64,
    gaps: Gaps,
) -> (Vec<Edge>, Vec<Segment>) {
    let mut ids: HashMap<Edge, usize> = HashMap::new();
    let mut edges: Vec<Edge> = Vec::new();
    let mut crossing = |e: Edge| -> usize {
        *ids.entry(e).or_insert_with(|| {
            edges.push(e);
            edges.len() - 1
        })
    };
    let mut segs = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let v = [
                value(i, j),
                value(i + 1, j),
                value(i + 1, j + 1),
                value(i, j + 1),
            ];
            if gaps == Gaps::Skip && v.iter().any(|x| !x.is_finite()) {
                continue;
            }
            let above = v.map(|x| x >= s);
            let side = [
                Edge::H(i, j),
                Edge::V(i + 1, j),
                Edge::H(i, j + 1),
                Edge::V(i, j),
            ];
            for &(a, b) in cell_pairs(v, s) {
                let ka = crossing(side[a]);
                let kb = crossing(side[b]);
                segs.push(((ka, kb), above[a]));
            }
        }
    }
    (edges, segs)
}

/// The pairs of sides a cell with corner values `v` joins at level `s` (see the
/// module docs; a pair's order fixes the order in which the scan meets its
/// crossings). None when all four corners are on one side.
fn cell_pairs(v: [f64; 4], s: f64) -> &'static [(usize, usize)] {
    let case = v
        .iter()
        .enumerate()
        .fold(0u8, |c, (k, &x)| c | (u8::from(x >= s) << k));
    match case {
        1 | 14 => &[(3, 0)],
        2 | 13 => &[(0, 1)],
        3 | 12 => &[(3, 1)],
        4 | 11 => &[(1, 2)],
        6 | 9 => &[(0, 2)],
        7 | 8 => &[(3, 2)],
        5 | 10 => {
            let centre_above = 0.25 * (v[0] + v[1] + v[2] + v[3]) >= s;
            // Case 5: 0 and 2 above. If the centre is above too, 0 and 2
            // connect through the middle: cut off corners 1 and 3.
            if (case == 5) == centre_above {
                &[(0, 1), (2, 3)]
            } else {
                &[(3, 0), (1, 2)]
            }
        }
        _ => &[],
    }
}

/// Join segments into curves (see [`Level::curves`] for the order). Each
/// crossing is shared by at most two segments.
fn chain(segs: &[Segment], n_points: usize) -> Vec<Curve> {
    let mut adj: Vec<[usize; 2]> = vec![[usize::MAX; 2]; n_points];
    for (k, &((a, b), _)) in segs.iter().enumerate() {
        for p in [a, b] {
            let slot = usize::from(adj[p][0] != usize::MAX);
            adj[p][slot] = k;
        }
    }
    let mut used = vec![false; segs.len()];
    let mut curves = Vec::new();
    // Open curves first: start at every end (a crossing with one segment).
    for (a, nb) in adj.iter().enumerate() {
        if nb[0] != usize::MAX && nb[1] == usize::MAX && !used[nb[0]] {
            curves.push(walk(segs, &adj, a, nb[0], &mut used));
        }
    }
    // What is left are rings.
    for k in 0..segs.len() {
        if !used[k] {
            let mut ring = walk(segs, &adj, segs[k].0 .0, k, &mut used);
            if ring.crossings.len() > 1 && ring.crossings.first() == ring.crossings.last() {
                ring.crossings.pop();
            }
            ring.closed = true;
            curves.push(ring);
        }
    }
    curves
}

/// The curve from crossing `start` along segment `first`, on through unused
/// segments until none is left (at an end, or back at `start`); marks the
/// segments used. Returned as open.
fn walk(
    segs: &[Segment],
    adj: &[[usize; 2]],
    start: usize,
    first: usize,
    used: &mut [bool],
) -> Curve {
    let ((a, _), forward) = segs[first];
    let mut crossings = vec![start];
    let (mut at, mut k) = (start, first);
    loop {
        used[k] = true;
        let (p, q) = segs[k].0;
        at = if p == at { q } else { p };
        crossings.push(at);
        match adj[at].into_iter().find(|&n| n != usize::MAX && !used[n]) {
            Some(n) => k = n,
            None => break,
        }
    }
    Curve {
        crossings,
        closed: false,
        high_left: forward == (a == start),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use Edge::{H, V};

    /// A lattice of `n` × `n` points, row-major values.
    fn lattice(n: usize, values: &[f64], s: f64, gaps: Gaps) -> Level {
        level(n - 1, n - 1, |i, j| values[j * n + i], s, gaps)
    }

    /// 5 × 5 points, 0 except 1 at (2, 2), and `right` at (3, 2).
    fn bump(right: f64) -> Vec<f64> {
        let mut v = vec![0.0; 25];
        v[2 * 5 + 2] = 1.0;
        v[2 * 5 + 3] = right;
        v
    }

    #[test]
    fn a_peak_gives_one_ring_clockwise_then_turned_high_left() {
        let l = lattice(5, &bump(0.0), 0.5, Gaps::Compare);
        // In the order the scan meets them: cell (1, 1)'s right side and top,
        // then (2, 1)'s top, then (1, 2)'s right side.
        assert_eq!(l.edges, [V(2, 1), H(1, 2), H(2, 2), V(2, 2)]);
        assert_eq!(l.curves.len(), 1);
        assert!(l.curves[0].closed);
        // From the first cell's right side toward its top, around (2, 2).
        assert_eq!(l.curves[0].crossings, [0, 1, 3, 2]);
        // Below, left, above, right of the peak: clockwise, the high side on the
        // right; turned from the same first edge, counter-clockwise.
        assert!(!l.curves[0].high_left);
        assert_eq!(l.rings(), [[V(2, 1), H(2, 2), V(2, 2), H(1, 2)]]);
        // A pit: the low side is inside, and clockwise already has it on the right.
        let pit: Vec<f64> = bump(0.0).into_iter().map(|x| 1.0 - x).collect();
        let l = lattice(5, &pit, 0.5, Gaps::Compare);
        assert!(l.curves[0].high_left);
        assert_eq!(l.rings(), [[V(2, 1), H(1, 2), V(2, 2), H(2, 2)]]);
    }

    #[test]
    fn gaps_skip_opens_the_curve_and_compare_reads_nan_as_below() {
        // NaN right of the peak: skipped, the four cells around it leave the
        // curve open from the crossing below the peak to the one above.
        let l = lattice(5, &bump(f64::NAN), 0.5, Gaps::Skip);
        assert_eq!(l.edges, [V(2, 1), H(1, 2), V(2, 2)]);
        assert_eq!(l.curves.len(), 1);
        assert!(!l.curves[0].closed);
        assert_eq!(l.curves[0].crossings, [0, 1, 2]);
        assert!(l.rings().is_empty());
        // Compared, NaN is below 0.5 like the zeros: the full ring.
        let l = lattice(5, &bump(f64::NAN), 0.5, Gaps::Compare);
        assert_eq!(l, lattice(5, &bump(0.0), 0.5, Gaps::Compare));
    }

    #[test]
    fn gaps_compare_closes_a_plateau_on_a_border_of_minus_infinity() {
        // 3 × 3 points at 1 inside a border of −∞.
        let mut v = vec![f64::NEG_INFINITY; 25];
        for j in 1..4 {
            for i in 1..4 {
                v[j * 5 + i] = 1.0;
            }
        }
        // Skipped, every cell that crosses touches the border: nothing.
        let l = lattice(5, &v, 0.5, Gaps::Skip);
        assert!(l.edges.is_empty() && l.curves.is_empty());
        // Compared: one ring through the 12 edges from the plateau to the border,
        // counter-clockwise once turned (the plateau on the left).
        let rings = lattice(5, &v, 0.5, Gaps::Compare).rings();
        assert_eq!(rings.len(), 1);
        assert_eq!(rings[0].len(), 12);
        assert_eq!(rings[0][..4], [V(1, 0), V(2, 0), V(3, 0), H(3, 1)]);
    }

    #[test]
    fn a_saddle_follows_the_mean_of_its_corners() {
        // Corners 0 and 2 at 1, 1 and 3 at 0: the mean is 0.5. At 0.5 the centre
        // is above: 0 and 2 connect, 1 and 3 are cut off. At 0.6 it is below: 0
        // and 2 are cut off. Either way two open pieces, one per cut corner.
        let v = [1.0, 0.0, 0.0, 1.0];
        for (s, edges) in [
            (0.5, [H(0, 0), V(1, 0), H(0, 1), V(0, 0)]),
            (0.6, [V(0, 0), H(0, 0), V(1, 0), H(0, 1)]),
        ] {
            let l = lattice(2, &v, s, Gaps::Compare);
            assert_eq!(l.edges, edges, "s = {s}");
            let pieces: Vec<_> = l
                .curves
                .iter()
                .map(|c| (&c.crossings[..], c.closed))
                .collect();
            assert_eq!(pieces, [(&[0, 1][..], false), (&[2, 3][..], false)]);
        }
    }
}
