//! The outline of what closed polygons fill under a fill rule, as a renderer
//! paints it: SVG's `nonzero` (winding number ≠ 0) or `evenodd` (odd). The
//! polygons may cross themselves and each other.
//!
//! The polygons are cut into a planar graph (`arrangement`). An edge of it is
//! on the outline when one of its sides is filled and the other is not; the
//! winding number of a side is counted exactly on the grid, along a ray from the
//! edge's midpoint. The outline's edges, filled side on the left, are chained
//! into loops; where loops touch at a point (a bow-tie's waist) each keeps to
//! its own side, so every loop is simple. Outlines come out counter-clockwise,
//! holes clockwise.

use super::arrangement::{arrange, orient, Arrangement, TooComplex, P};
use super::Vec2;

/// How a closed path's winding number decides what is inside.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FillRule {
    /// Inside where the winding number is not zero (SVG's default).
    NonZero,
    /// Inside where the winding number is odd.
    EvenOdd,
    /// Inside where the winding number is positive: a region wound
    /// counter-clockwise less those wound clockwise inside it (a set
    /// difference, whatever the overlaps).
    Positive,
}

impl FillRule {
    fn fills(self, w: i32) -> bool {
        match self {
            FillRule::NonZero => w != 0,
            FillRule::EvenOdd => w % 2 != 0,
            FillRule::Positive => w > 0,
        }
    }
}

/// The loops bounding what `polys` fill under `rule`: outlines counter-clockwise,
/// holes clockwise, none crossing another.
pub(crate) fn fill_outlines(
    polys: &[Vec<Vec2>],
    rule: FillRule,
) -> Result<Vec<Vec<Vec2>>, TooComplex> {
    let arr = arrange(polys)?;
    let directed = boundary_edges(&arr, rule)?;
    Ok(chain(&arr, &directed)
        .into_iter()
        .map(|l| l.into_iter().map(|p| arr.at(p)).collect())
        .collect())
}

/// Whether any edge of `polys` crosses or touches another other than at the
/// shared end of two consecutive edges (a polygon that crosses itself).
pub(crate) fn crosses(polys: &[Vec<Vec2>]) -> Result<bool, TooComplex> {
    Ok(arrange(polys)?.crossed)
}

/// At most this many band entries are held (edges × the bands each spans):
/// 400 MB.
const MAX_BAND_ENTRIES: usize = 100_000_000;

/// At most this many edges are looked at by all the rays together (about a
/// second).
const MAX_RAY_TESTS: usize = 400_000_000;

/// The edges with the filled side on the left, as (from, to) point indices.
fn boundary_edges(arr: &Arrangement, rule: FillRule) -> Result<Vec<(usize, usize)>, TooComplex> {
    let rays = Rays::new(arr);
    let work: usize = arr
        .edges
        .iter()
        .enumerate()
        .map(|(k, _)| rays.candidates(k))
        .sum();
    if work > MAX_RAY_TESTS {
        return Err(TooComplex);
    }
    Ok(arr
        .edges
        .iter()
        .enumerate()
        .filter_map(|(k, e)| {
            let (left, right) = rays.sides(k);
            match (rule.fills(left), rule.fills(right)) {
                (true, false) => Some((e.a, e.b)),
                (false, true) => Some((e.b, e.a)),
                _ => None,
            }
        })
        .collect())
}

/// The graph's edges in doubled coordinates, bucketed in bands of y (for rays
/// to +x) and of x (for rays to +y, from horizontal edges).
struct Rays {
    /// (p, q, mult) per edge, doubled.
    segs: Vec<(P, P, i32)>,
    rows: Bands,
    cols: Bands,
}

/// Edges by the band of one coordinate they span.
struct Bands {
    axis: usize,
    lo: i64,
    step: i64,
    bands: Vec<Vec<u32>>,
}

impl Bands {
    fn new(segs: &[(P, P, i32)], axis: usize) -> Bands {
        let lo = segs
            .iter()
            .map(|s| s.0[axis].min(s.1[axis]))
            .min()
            .unwrap_or(0);
        let hi = segs
            .iter()
            .map(|s| s.0[axis].max(s.1[axis]))
            .max()
            .unwrap_or(0);
        // About √E bands, fewer when long edges would fill too many.
        let mut n = ((segs.len() as f64).sqrt() as i64).clamp(1, 4096);
        let entries = |step: i64| -> usize {
            segs.iter()
                .map(|s| {
                    let (a, b) = (s.0[axis].min(s.1[axis]), s.0[axis].max(s.1[axis]));
                    ((b - lo) / step - (a - lo) / step + 1) as usize
                })
                .sum()
        };
        while n > 1 && entries(((hi - lo) / n + 1).max(1)) > MAX_BAND_ENTRIES {
            n /= 2;
        }
        let step = ((hi - lo) / n + 1).max(1);
        let mut bands = vec![Vec::new(); ((hi - lo) / step + 1) as usize];
        for (k, s) in segs.iter().enumerate() {
            let (a, b) = (s.0[axis].min(s.1[axis]), s.0[axis].max(s.1[axis]));
            for band in &mut bands[((a - lo) / step) as usize..=((b - lo) / step) as usize] {
                band.push(k as u32);
            }
        }
        Bands {
            axis,
            lo,
            step,
            bands,
        }
    }

    fn at(&self, c: i64) -> &[u32] {
        let k = (c - self.lo).div_euclid(self.step);
        usize::try_from(k)
            .ok()
            .and_then(|k| self.bands.get(k))
            .map_or(&[], Vec::as_slice)
    }
}

impl Rays {
    fn new(arr: &Arrangement) -> Rays {
        let d = |p: P| [2 * p[0], 2 * p[1]];
        let segs: Vec<(P, P, i32)> = arr
            .edges
            .iter()
            .map(|e| (d(arr.points[e.a]), d(arr.points[e.b]), e.mult))
            .collect();
        let rows = Bands::new(&segs, 1);
        let cols = Bands::new(&segs, 0);
        Rays { segs, rows, cols }
    }

    /// How many edges the ray from edge `k` looks at.
    fn candidates(&self, k: usize) -> usize {
        let (a, b, _) = self.segs[k];
        let m = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
        if a[1] != b[1] {
            self.rows.at(m[1]).len()
        } else {
            self.cols.at(m[0]).len()
        }
    }

    /// Winding numbers (left, right) of edge `k`'s two sides, a → b.
    fn sides(&self, k: usize) -> (i32, i32) {
        let (a, b, mult) = self.segs[k];
        let m = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
        if a[1] != b[1] {
            // The ray to +x: the right side of an upward edge, the left of a
            // downward one.
            let w = self.winding(&self.rows, m, k);
            if b[1] > a[1] {
                (w + mult, w)
            } else {
                (w, w - mult)
            }
        } else {
            // Horizontal: the ray to +y, the left side of an edge to +x.
            let w = self.winding(&self.cols, m, k);
            if b[0] > a[0] {
                (w, w - mult)
            } else {
                (w + mult, w)
            }
        }
    }

    /// Winding number just beside `m` (on edge `skip`) towards +x (rows) or +y
    /// (cols): signed crossings of the ray from `m` that way, half-open in the
    /// other coordinate.
    fn winding(&self, bands: &Bands, m: P, skip: usize) -> i32 {
        // For +y, swap the axes: a reflection, so the count changes sign.
        let (u, v, sign) = if bands.axis == 1 {
            (0, 1, 1)
        } else {
            (1, 0, -1)
        };
        let sw = |p: P| [p[u], p[v]];
        let mm = sw(m);
        let mut w = 0;
        for &k in bands.at(m[bands.axis]) {
            let k = k as usize;
            if k == skip {
                continue;
            }
            let (p, q, mult) = self.segs[k];
            let (p, q) = (sw(p), sw(q));
            if p[1] <= mm[1] && q[1] > mm[1] && orient(p, q, mm) > 0 {
                w += mult;
            } else if q[1] <= mm[1] && p[1] > mm[1] && orient(p, q, mm) < 0 {
                w -= mult;
            }
        }
        sign * w
    }
}

/// The directed edges joined into closed loops of grid points. At a point where
/// several leave, the walk takes the first one clockwise from the way it came
/// (the sharpest left turn), which keeps the filled side on the left to itself.
/// Edges that lead nowhere (a rounding artefact) are dropped.
fn chain(arr: &Arrangement, edges: &[(usize, usize)]) -> Vec<Vec<P>> {
    let mut out_of: Vec<Vec<usize>> = vec![Vec::new(); arr.points.len()];
    for (k, &(a, _)) in edges.iter().enumerate() {
        out_of[a].push(k);
    }
    let dir = |k: usize| {
        let (a, b) = edges[k];
        let (p, q) = (arr.points[a], arr.points[b]);
        Vec2::new((q[0] - p[0]) as f64, (q[1] - p[1]) as f64)
    };
    let mut used = vec![false; edges.len()];
    let mut loops = Vec::new();
    for start in 0..edges.len() {
        if used[start] {
            continue;
        }
        let mut path = vec![start];
        used[start] = true;
        loop {
            let last = *path.last().unwrap_or(&start);
            let v = edges[last].1;
            if v == edges[start].0 {
                loops.push(path.iter().map(|&k| arr.points[edges[k].0]).collect());
                break;
            }
            let back = dir(last) * -1.0;
            let next = out_of[v]
                .iter()
                .copied()
                .filter(|&k| !used[k])
                .min_by(|&x, &y| cw_angle(back, dir(x)).total_cmp(&cw_angle(back, dir(y))));
            let Some(next) = next else { break };
            used[next] = true;
            path.push(next);
        }
    }
    loops
        .into_iter()
        .map(drop_straight_points)
        .filter(|l: &Vec<P>| l.len() >= 3)
        .collect()
}

/// The clockwise angle from `from` to `to`, in (0, 2π].
fn cw_angle(from: Vec2, to: Vec2) -> f64 {
    let a = -from.cross(to).atan2(from.dot(to));
    if a <= 0.0 {
        a + std::f64::consts::TAU
    } else {
        a
    }
}

/// The loop without points where it runs straight on (exactly, on the grid).
fn drop_straight_points(l: Vec<P>) -> Vec<P> {
    let n = l.len();
    let keep: Vec<P> = (0..n)
        .filter(|&i| {
            let (p, q, r) = (l[(i + n - 1) % n], l[i], l[(i + 1) % n]);
            let same_way = (q[0] - p[0]) as i128 * (r[0] - q[0]) as i128
                + (q[1] - p[1]) as i128 * (r[1] - q[1]) as i128
                > 0;
            orient(p, q, r) != 0 || !same_way
        })
        .map(|i| l[i])
        .collect();
    keep
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::polygon_area;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    fn square(x: f64, y: f64, s: f64, ccw: bool) -> Vec<Vec2> {
        let mut p = vec![v(x, y), v(x + s, y), v(x + s, y + s), v(x, y + s)];
        if !ccw {
            p.reverse();
        }
        p
    }

    #[test]
    fn a_bow_tie_fills_two_triangles() {
        let tie = vec![v(0.0, 0.0), v(20.0, 20.0), v(20.0, 0.0), v(0.0, 20.0)];
        for rule in [FillRule::NonZero, FillRule::EvenOdd] {
            let loops = fill_outlines(std::slice::from_ref(&tie), rule).unwrap();
            assert_eq!(loops.len(), 2, "{rule:?}");
            for l in &loops {
                assert_eq!(l.len(), 3);
                assert!(
                    (polygon_area(l) - 100.0).abs() < 1e-6,
                    "{}",
                    polygon_area(l)
                );
            }
        }
    }

    #[test]
    fn nested_squares_under_each_rule() {
        // Same direction: nonzero fills the hole, evenodd does not.
        let outer = square(0.0, 0.0, 10.0, true);
        let inner = square(3.0, 3.0, 4.0, true);
        let both = [outer.clone(), inner.clone()];
        let nz = fill_outlines(&both, FillRule::NonZero).unwrap();
        assert_eq!(nz.len(), 1);
        assert!((polygon_area(&nz[0]) - 100.0).abs() < 1e-6);
        let eo = fill_outlines(&both, FillRule::EvenOdd).unwrap();
        assert_eq!(eo.len(), 2);
        let total: f64 = eo.iter().map(|l| polygon_area(l)).sum();
        assert!((total - 84.0).abs() < 1e-6, "{total}");
        // Opposite directions: a hole under both.
        let both = [outer, square(3.0, 3.0, 4.0, false)];
        let nz = fill_outlines(&both, FillRule::NonZero).unwrap();
        let total: f64 = nz.iter().map(|l| polygon_area(l)).sum();
        assert_eq!(nz.len(), 2);
        assert!((total - 84.0).abs() < 1e-6, "{total}");
    }

    #[test]
    fn overlapping_squares_merge_and_a_clockwise_square_turns() {
        let a = square(0.0, 0.0, 10.0, false);
        let b = square(5.0, 5.0, 10.0, false);
        let loops = fill_outlines(&[a, b], FillRule::NonZero).unwrap();
        assert_eq!(loops.len(), 1);
        assert!(
            (polygon_area(&loops[0]) - 175.0).abs() < 1e-6,
            "{}",
            polygon_area(&loops[0])
        );
        assert_eq!(loops[0].len(), 8);
        // Evenodd: the overlap is a hole, drawn as two L-shapes meeting at corners.
        let a = square(0.0, 0.0, 10.0, true);
        let b = square(5.0, 5.0, 10.0, true);
        let loops = fill_outlines(&[a, b], FillRule::EvenOdd).unwrap();
        let total: f64 = loops.iter().map(|l| polygon_area(l)).sum();
        assert!((total - 150.0).abs() < 1e-6, "{total}");
    }

    /// Positive: a counter-clockwise square less the clockwise ones, an
    /// area by hand; a clockwise square around it leaves nothing, one drawn
    /// twice takes off no more than once.
    #[test]
    fn positive_is_a_difference() {
        let a = square(0.0, 0.0, 10.0, true);
        let corner = square(5.0, 5.0, 10.0, false);
        let inside = square(2.0, 2.0, 2.0, false);
        let loops = fill_outlines(
            &[a.clone(), corner.clone(), corner, inside],
            FillRule::Positive,
        )
        .unwrap();
        let total: f64 = loops.iter().map(|l| polygon_area(l)).sum();
        assert!((total - (100.0 - 25.0 - 4.0)).abs() < 1e-6, "{total}");
        assert_eq!(loops.len(), 2);
        assert_eq!(loops.iter().filter(|l| polygon_area(l) < 0.0).count(), 1);
        let around = square(-1.0, -1.0, 12.0, false);
        assert!(fill_outlines(&[a, around], FillRule::Positive)
            .unwrap()
            .is_empty());
    }

    #[test]
    fn a_pentagram_under_each_rule() {
        let star: Vec<Vec2> = (0..5)
            .map(|k| {
                let a = std::f64::consts::FRAC_PI_2 + 4.0 * std::f64::consts::PI * k as f64 / 5.0;
                v(10.0 * a.cos(), 10.0 * a.sin())
            })
            .collect();
        let nz = fill_outlines(std::slice::from_ref(&star), FillRule::NonZero).unwrap();
        assert_eq!(nz.len(), 1);
        assert_eq!(nz[0].len(), 10);
        assert!(polygon_area(&nz[0]) > 0.0);
        let eo = fill_outlines(std::slice::from_ref(&star), FillRule::EvenOdd).unwrap();
        // Five tips; the pentagon in the middle (winding 2) is empty.
        assert_eq!(eo.len(), 5);
        let tips: f64 = eo.iter().map(|l| polygon_area(l)).sum();
        assert!(tips > 0.0 && tips < polygon_area(&nz[0]));
    }

    #[test]
    fn a_dense_hatch_is_refused_before_it_fills_the_memory() {
        // 1200 thin bars across 1200 others: 5.8 million crossings, past
        // MAX_PIECES, refused as it counts them.
        let bar = |k: usize, across: bool| {
            let (a, b) = (k as f64, k as f64 + 0.5);
            if across {
                vec![v(0.0, a), v(1200.0, a), v(1200.0, b), v(0.0, b)]
            } else {
                vec![v(a, 0.0), v(b, 0.0), v(b, 1200.0), v(a, 1200.0)]
            }
        };
        let polys: Vec<Vec<Vec2>> = (0..1200)
            .flat_map(|k| [bar(k, true), bar(k, false)])
            .collect();
        assert_eq!(fill_outlines(&polys, FillRule::NonZero), Err(TooComplex));
    }

    #[test]
    fn an_edge_drawn_forth_and_back_fills_nothing() {
        let sliver = vec![v(0.0, 0.0), v(10.0, 0.0), v(5.0, 0.0)];
        let loops = fill_outlines(&[sliver], FillRule::NonZero).unwrap();
        assert!(loops.is_empty());
    }
}
