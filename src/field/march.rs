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
