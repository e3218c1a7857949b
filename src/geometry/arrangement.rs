//! Closed polygons cut into a planar graph: every edge split wherever another
//! edge crosses or touches it, coincident pieces merged. The fill rules
//! (`fill.rs`) work on this graph.
//!
//! Points are snapped to an integer grid of [`GRID`] steps across the larger
//! side of the input's box (a 100 mm logo: steps of 0.1 nm), so every
//! orientation test is exact (in `i128`); only a crossing point is rounded,
//! to the nearest grid point.

use std::collections::HashMap;

use super::Vec2;

/// Grid steps across the larger side of the input's bounding box. Coordinates
/// stay below 2³⁰, doubled midpoints below 2³¹: their products fit `i128` with
/// room to spare.
const GRID: f64 = (1u64 << 30) as f64;

/// At most this many edges go in.
pub(crate) const MAX_EDGES: usize = 1_000_000;

/// At most this many pieces come out (edges plus split points): a few long
/// edges crossing each other n² times cannot fill the memory.
pub(crate) const MAX_PIECES: usize = 4_000_000;

/// At most this many pairs of edges whose x-ranges overlap are tested for a
/// crossing (about a second): thousands of long edges side by side would
/// otherwise take hours.
pub(crate) const MAX_PAIR_TESTS: u64 = 400_000_000;

/// A point on the grid.
pub(crate) type P = [i64; 2];

/// One edge of the graph, from point `a` to point `b`, drawn `mult` times in that
/// direction (net: a piece drawn once each way has `mult` 0 and is dropped).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Edge {
    /// start (index into `points`)
    pub(crate) a: usize,
    /// end
    pub(crate) b: usize,
    /// net count of input edges along a → b
    pub(crate) mult: i32,
}

/// The planar graph of some closed polygons.
#[derive(Clone, Debug, Default)]
pub(crate) struct Arrangement {
    /// Grid point (i, j) is `origin + unit · (i, j)`.
    pub(crate) origin: Vec2,
    /// Size of a grid step.
    pub(crate) unit: f64,
    /// The vertices.
    pub(crate) points: Vec<P>,
    /// The edges; no two share both ends, none crosses another.
    pub(crate) edges: Vec<Edge>,
    /// Whether any two input edges crossed or touched other than end to end,
    /// or more than two edges meet at a point.
    pub(crate) crossed: bool,
}

/// Too many edges, pieces or tests (see [`MAX_EDGES`], [`MAX_PIECES`],
/// [`MAX_PAIR_TESTS`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct TooComplex;

impl Arrangement {
    /// A grid point in the input's coordinates.
    pub(crate) fn at(&self, p: P) -> Vec2 {
        self.origin + Vec2::new(p[0] as f64, p[1] as f64) * self.unit
    }
}

/// Twice the signed area of the triangle a, b, c: > 0 when c is left of a → b.
pub(crate) fn orient(a: P, b: P, c: P) -> i128 {
    let (abx, aby) = ((b[0] - a[0]) as i128, (b[1] - a[1]) as i128);
    let (acx, acy) = ((c[0] - a[0]) as i128, (c[1] - a[1]) as i128);
    abx * acy - aby * acx
}

/// The graph of `polys`, each a closed polygon (the last point joins the first).
pub(crate) fn arrange(polys: &[Vec<Vec2>]) -> Result<Arrangement, TooComplex> {
    let n_in: usize = polys.iter().map(Vec::len).sum();
    if n_in > MAX_EDGES {
        return Err(TooComplex);
    }
    let Some((lo, hi)) = super::polygons_bbox(polys) else {
        return Ok(Arrangement::default());
    };
    let span = (hi.x - lo.x).max(hi.y - lo.y);
    if !(span > 0.0 && span.is_finite()) {
        return Ok(Arrangement::default());
    }
    let unit = span / GRID;
    let snap = |p: Vec2| -> P {
        [
            ((p.x - lo.x) / unit).round() as i64,
            ((p.y - lo.y) / unit).round() as i64,
        ]
    };
    let mut raw: Vec<(P, P)> = Vec::with_capacity(n_in);
    for poly in polys {
        let pts: Vec<P> = poly.iter().map(|&p| snap(p)).collect();
        let n = pts.len();
        for k in 0..n {
            let (a, b) = (pts[k], pts[(k + 1) % n]);
            if a != b {
                raw.push((a, b));
            }
        }
    }
    let (splits, crossed) = split_points(&raw)?;
    let mut arr = merge(&raw, splits)?;
    arr.origin = lo;
    arr.unit = unit;
    // A point where more than two edges meet: a polygon passing through one of
    // its vertices again (a figure eight crossing at a joint) or touching itself.
    let mut degree = vec![0u32; arr.points.len()];
    for e in &arr.edges {
        degree[e.a] += 1;
        degree[e.b] += 1;
    }
    arr.crossed = crossed || degree.iter().any(|&d| d > 2);
    Ok(arr)
}

/// For every edge, the points where others cross or touch it; and whether any
/// did other than at a shared end.
fn split_points(raw: &[(P, P)]) -> Result<(Vec<Vec<P>>, bool), TooComplex> {
    let mut order: Vec<usize> = (0..raw.len()).collect();
    let xmin = |i: usize| raw[i].0[0].min(raw[i].1[0]);
    let xmax = |i: usize| raw[i].0[0].max(raw[i].1[0]);
    order.sort_by_key(|&i| xmin(i));
    let mut splits: Vec<Vec<P>> = vec![Vec::new(); raw.len()];
    let mut pieces = raw.len();
    let mut tests = 0u64;
    let mut crossed = false;
    for (k, &i) in order.iter().enumerate() {
        let (a, b) = raw[i];
        let (ylo, yhi) = (a[1].min(b[1]), a[1].max(b[1]));
        for &j in &order[k + 1..] {
            if xmin(j) > xmax(i) {
                break;
            }
            tests += 1;
            if tests > MAX_PAIR_TESTS {
                return Err(TooComplex);
            }
            let (c, d) = raw[j];
            if c[1].max(d[1]) < ylo || c[1].min(d[1]) > yhi {
                continue;
            }
            let found = meet(a, b, c, d);
            for (on_i, p) in found.into_iter().flatten() {
                let shared_end = (p == a || p == b) && (p == c || p == d);
                if shared_end {
                    continue;
                }
                crossed = true;
                let list = if on_i { &mut splits[i] } else { &mut splits[j] };
                list.push(p);
                pieces += 1;
                if pieces > MAX_PIECES {
                    return Err(TooComplex);
                }
            }
        }
    }
    Ok((splits, crossed))
}

/// Where segments ab and cd meet: up to four points, each with the segment
/// (`true`: ab) whose inside it splits. A proper crossing splits both.
fn meet(a: P, b: P, c: P, d: P) -> [Option<(bool, P)>; 4] {
    let (o1, o2) = (orient(c, d, a), orient(c, d, b));
    let (o3, o4) = (orient(a, b, c), orient(a, b, d));
    let mut out = [None; 4];
    if o1.signum() * o2.signum() < 0 && o3.signum() * o4.signum() < 0 {
        // a + (b − a)·o1/(o1 − o2), rounded to the grid.
        let den = o1 - o2;
        let x = a[0] + div_round((b[0] - a[0]) as i128 * o1, den);
        let y = a[1] + div_round((b[1] - a[1]) as i128 * o1, den);
        let p = [x, y];
        out[0] = (p != a && p != b).then_some((true, p));
        out[1] = (p != c && p != d).then_some((false, p));
        return out;
    }
    // An end of one on the inside of the other (touching or collinear overlap).
    let inside = |p: P, s: P, e: P, o: i128| o == 0 && strictly_between(p, s, e);
    out[0] = inside(c, a, b, o3).then_some((true, c));
    out[1] = inside(d, a, b, o4).then_some((true, d));
    out[2] = inside(a, c, d, o1).then_some((false, a));
    out[3] = inside(b, c, d, o2).then_some((false, b));
    out
}

/// Whether p, on the line through s and e, lies strictly between them.
fn strictly_between(p: P, s: P, e: P) -> bool {
    let t = (p[0] - s[0]) as i128 * (e[0] - s[0]) as i128
        + (p[1] - s[1]) as i128 * (e[1] - s[1]) as i128;
    let len2 = (e[0] - s[0]) as i128 * (e[0] - s[0]) as i128
        + (e[1] - s[1]) as i128 * (e[1] - s[1]) as i128;
    t > 0 && t < len2
}

/// n / d rounded to the nearest integer (d ≠ 0).
fn div_round(n: i128, d: i128) -> i64 {
    let (n, d) = if d < 0 { (-n, -d) } else { (n, d) };
    let q = if n >= 0 {
        (2 * n + d) / (2 * d)
    } else {
        -((-2 * n + d) / (2 * d))
    };
    q as i64
}

/// The edges cut at their split points, coincident pieces merged by their ends.
fn merge(raw: &[(P, P)], splits: Vec<Vec<P>>) -> Result<Arrangement, TooComplex> {
    let mut index: HashMap<P, usize> = HashMap::new();
    let mut points: Vec<P> = Vec::new();
    let mut id = |p: P| -> usize {
        *index.entry(p).or_insert_with(|| {
            points.push(p);
            points.len() - 1
        })
    };
    let mut count: HashMap<(usize, usize), i32> = HashMap::new();
    let mut keys: Vec<(usize, usize)> = Vec::new();
    for (&(a, b), mut cuts) in raw.iter().zip(splits) {
        let along = |p: &P| {
            (p[0] - a[0]) as i128 * (b[0] - a[0]) as i128
                + (p[1] - a[1]) as i128 * (b[1] - a[1]) as i128
        };
        cuts.sort_by_key(along);
        cuts.dedup();
        let chain: Vec<P> = std::iter::once(a)
            .chain(cuts)
            .chain(std::iter::once(b))
            .collect();
        for w in chain.windows(2) {
            if w[0] == w[1] {
                continue;
            }
            let (i, j) = (id(w[0]), id(w[1]));
            let (key, sign) = if i < j { ((i, j), 1) } else { ((j, i), -1) };
            let c = count.entry(key).or_insert_with(|| {
                keys.push(key);
                0
            });
            *c += sign;
        }
    }
    if keys.len() > MAX_PIECES {
        return Err(TooComplex);
    }
    let edges = keys
        .into_iter()
        .filter_map(|k| {
            let mult = count[&k];
            (mult != 0).then_some(Edge {
                a: k.0,
                b: k.1,
                mult,
            })
        })
        .collect();
    Ok(Arrangement {
        points,
        edges,
        ..Arrangement::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    #[test]
    fn a_bow_tie_is_cut_at_its_crossing() {
        let arr = arrange(&[vec![v(0.0, 0.0), v(20.0, 20.0), v(20.0, 0.0), v(0.0, 20.0)]]).unwrap();
        assert!(arr.crossed);
        assert_eq!(arr.points.len(), 5);
        assert_eq!(arr.edges.len(), 6);
        let centre = arr
            .points
            .iter()
            .map(|&p| arr.at(p))
            .any(|p| p.dist(v(10.0, 10.0)) < 1e-12);
        assert!(centre);
    }

    #[test]
    fn a_square_is_not_crossed_and_overlaps_cancel() {
        let sq = vec![v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)];
        let arr = arrange(std::slice::from_ref(&sq)).unwrap();
        assert!(!arr.crossed);
        assert_eq!(arr.edges.len(), 4);
        // The same square drawn back the other way cancels edge by edge.
        let mut back = sq.clone();
        back.reverse();
        let arr = arrange(&[sq, back]).unwrap();
        assert!(arr.edges.is_empty());
    }

    #[test]
    fn a_t_junction_and_a_collinear_overlap_split_the_other_edge() {
        // Two squares sharing part of a side: the shared piece is counted twice.
        let a = vec![v(0.0, 0.0), v(2.0, 0.0), v(2.0, 2.0), v(0.0, 2.0)];
        let b = vec![v(2.0, 1.0), v(3.0, 1.0), v(3.0, 3.0), v(2.0, 3.0)];
        let arr = arrange(&[a, b]).unwrap();
        assert!(arr.crossed);
        // a's right side is cut at (2, 1); b's left side at (2, 2).
        assert_eq!(arr.points.len(), 8);
        // The shared piece runs up in a and down in b: it cancels, 10 − 2 pieces.
        assert_eq!(arr.edges.len(), 8);
    }

    #[test]
    fn rounding_a_crossing_is_to_the_nearest_grid_point() {
        assert_eq!(div_round(7, 2), 4);
        assert_eq!(div_round(-7, 2), -4);
        assert_eq!(div_round(5, -3), -2);
        assert_eq!(div_round(1, 3), 0);
    }
}
