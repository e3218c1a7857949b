//! Exact distance from a point to a set of closed polygons, through a uniform grid
//! of segment buckets. This is the plain-geometry oracle: the gouge check and the
//! tracer's contact test use it, never the potential field.

use super::Vec2;

/// Closed polygons with a bucket grid over their edges.
#[derive(Clone, Debug)]
pub struct DistanceIndex {
    edges: Vec<(Vec2, Vec2)>,
    /// The bucket grid `segment_distance` scans, built the first time it is
    /// asked: most indexes (ring gaps, coverage, the tracer) only ever answer
    /// point queries, which the hierarchy serves (issue 13: building the
    /// grid was 5 % of a mould's run for nothing).
    buckets: std::sync::OnceLock<Buckets>,
    /// The hierarchy `nearest` searches (the grid serves `segment_distance`).
    bvh: super::bvh::Bvh,
}

/// A uniform grid of edge buckets.
#[derive(Clone, Debug)]
struct Buckets {
    origin: Vec2,
    cell: f64,
    nx: usize,
    ny: usize,
    /// Edge indices per cell, row-major; `starts[c]..starts[c+1]` index into `items`.
    starts: Vec<u32>,
    items: Vec<u32>,
}

fn seg_dist2(p: Vec2, a: Vec2, b: Vec2) -> (f64, Vec2) {
    let ab = b - a;
    let l2 = ab.norm2();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = a + ab * t;
    ((p - q).norm2(), q)
}

impl DistanceIndex {
    /// Index over the edges of the given closed polygons (each joins last to
    /// first): rings, or vertex lists under the same convention.
    pub fn new<P: AsRef<[Vec2]>>(polys: &[P]) -> DistanceIndex {
        let mut edges = Vec::new();
        for poly in polys {
            edges.extend(super::ring::edges(poly.as_ref()));
        }
        let bvh = super::bvh::Bvh::new(&edges);
        DistanceIndex {
            bvh,
            edges,
            buckets: std::sync::OnceLock::new(),
        }
    }

    fn buckets(&self) -> &Buckets {
        self.buckets.get_or_init(|| Buckets::new(&self.edges))
    }
}

impl Buckets {
    fn new(edges: &[(Vec2, Vec2)]) -> Buckets {
        let (mut lo, mut hi) = (Vec2::new(f64::MAX, f64::MAX), Vec2::new(f64::MIN, f64::MIN));
        for &(a, _) in edges {
            lo = Vec2::new(lo.x.min(a.x), lo.y.min(a.y));
            hi = Vec2::new(hi.x.max(a.x), hi.y.max(a.y));
        }
        if edges.is_empty() {
            lo = Vec2::ZERO;
            hi = Vec2::new(1.0, 1.0);
        }
        let ext = hi - lo;
        // About two edges per cell on average keeps both the scan and the ring search short.
        let area = (ext.x.max(1e-9)) * (ext.y.max(1e-9));
        let cell = (area / (edges.len().max(1) as f64 / 2.0))
            .sqrt()
            .max(ext.x.max(ext.y) / 2048.0)
            .max(1e-9);
        let nx = ((ext.x / cell).floor() as usize + 1).max(1);
        let ny = ((ext.y / cell).floor() as usize + 1).max(1);
        let mut counts = vec![0u32; nx * ny + 1];
        // The cells an edge passes through: row by row, the x-range of the part of
        // the edge inside the row, padded by a hair against rounding (a superset is
        // harmless, a missed cell would not be). Registering the bounding box of the
        // edge instead put a long diagonal into O(n²) cells.
        let cells_of = |a: Vec2, b: Vec2, out: &mut Vec<usize>| {
            out.clear();
            let col = |x: f64| (((x - lo.x) / cell).floor().max(0.0) as usize).min(nx - 1);
            let row = |y: f64| (((y - lo.y) / cell).floor().max(0.0) as usize).min(ny - 1);
            let (ymin, ymax) = (a.y.min(b.y), a.y.max(b.y));
            let pad = 1e-9 * cell;
            for j in row(ymin)..=row(ymax) {
                let y0 = lo.y + j as f64 * cell;
                let (y1, y2) = (ymin.max(y0 - pad), ymax.min(y0 + cell + pad));
                let (y1, y2) = (y1.min(y2), y1.max(y2));
                let (x1, x2) = if b.y == a.y {
                    (a.x.min(b.x), a.x.max(b.x))
                } else {
                    let x_at = |y: f64| a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y);
                    let (u, w) = (x_at(y1), x_at(y2));
                    (u.min(w), u.max(w))
                };
                for i in col(x1 - pad)..=col(x2 + pad) {
                    out.push(j * nx + i);
                }
            }
        };
        let mut cells = Vec::new();
        for &(a, b) in edges {
            cells_of(a, b, &mut cells);
            for &c in &cells {
                counts[c + 1] += 1;
            }
        }
        for c in 1..counts.len() {
            counts[c] += counts[c - 1];
        }
        let starts = counts.clone();
        let mut fill = counts;
        let mut items = vec![0u32; *starts.last().unwrap_or(&0) as usize];
        for (e, &(a, b)) in edges.iter().enumerate() {
            cells_of(a, b, &mut cells);
            for &c in &cells {
                items[fill[c] as usize] = e as u32;
                fill[c] += 1;
            }
        }
        Buckets {
            origin: lo,
            cell,
            nx,
            ny,
            starts,
            items,
        }
    }
}

impl DistanceIndex {
    /// Number of edges indexed.
    #[cfg(test)]
    pub(crate) fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// Total length of the indexed edges.
    pub(crate) fn perimeter(&self) -> f64 {
        self.edges.iter().map(|(a, b)| a.dist(*b)).sum()
    }

    /// Distance from `p` to the nearest edge and the nearest point on it.
    /// A point that is not finite is at distance NaN, never a number that
    /// could pass for a measure.
    pub(crate) fn nearest(&self, p: Vec2) -> (f64, Vec2) {
        let (d, q, _) = self.nearest_from(p, None);
        (d, q)
    }

    /// Distance from `p` to the nearest edge and that edge's index (edges
    /// are numbered polygon after polygon, each polygon's as
    /// `ring::edges` gives them); `None` for an empty index.
    pub(crate) fn nearest_edge(&self, p: Vec2) -> (f64, Option<usize>) {
        let (d, _, e) = self.nearest_from(p, None);
        (d, e.map(|e| e as usize))
    }

    /// [`nearest`](Self::nearest) for a walk of nearby queries: `hint` holds
    /// the edge that answered the last one, which seeds the search's bound
    /// (most of the tree is then pruned at once), and is updated.
    pub(crate) fn nearest_hinted(&self, p: Vec2, hint: &std::cell::Cell<u32>) -> (f64, Vec2) {
        let (d, q, e) = self.nearest_from(p, Some(hint.get()));
        if let Some(e) = e {
            hint.set(e);
        }
        (d, q)
    }

    /// The search behind both: distance, nearest point and the edge found.
    fn nearest_from(&self, p: Vec2, hint: Option<u32>) -> (f64, Vec2, Option<u32>) {
        crate::count::query();
        if !(p.x.is_finite() && p.y.is_finite()) {
            return (f64::NAN, p, None);
        }
        match self.bvh.nearest(&self.edges, p, hint, seg_dist2) {
            Some((d2, q, e)) => (d2.sqrt(), q, Some(e)),
            None => (f64::INFINITY, p, None),
        }
    }

    /// Whether some edge is closer to `p` than `r`: exactly whether the
    /// minimum over every edge of the distance (the same `sqrt` of the same
    /// squared distances as [`nearest`](Self::nearest), which may differ from
    /// that minimum by rounding where two edges tie) is below `r`. The search
    /// stops at the first such edge. `hint` is
    /// tried first and updated, as in [`nearest_hinted`](Self::nearest_hinted).
    pub(crate) fn closer_than(&self, p: Vec2, r: f64, hint: &std::cell::Cell<u32>) -> bool {
        crate::count::query();
        // Boxes are pruned with a relative margin far above the rounding of
        // their bound, so no edge that passes the exact test is skipped.
        let reach2 = r * r * (1.0 + 1e-9) + 1e-300;
        let hit = |a: Vec2, b: Vec2| seg_dist2(p, a, b).0.sqrt() < r;
        match self
            .bvh
            .any_near(&self.edges, p, reach2, Some(hint.get()), hit)
        {
            Some(e) => {
                hint.set(e);
                true
            }
            None => false,
        }
    }

    /// Distance from `p` to the nearest edge.
    pub fn distance(&self, p: Vec2) -> f64 {
        self.nearest(p).0
    }

    /// Distance by scanning every edge (for tests of the grid search).
    #[cfg(test)]
    pub(crate) fn distance_brute(&self, p: Vec2) -> f64 {
        self.edges
            .iter()
            .map(|&(a, b)| seg_dist2(p, a, b).0)
            .fold(f64::INFINITY, f64::min)
            .sqrt()
    }

    /// Smallest distance between the segment `a`–`b` and any indexed edge (exact:
    /// segment–segment distances over the edges in the cells the segment's box,
    /// grown by `reach`, overlaps; edges further than `reach` may be missed, so the
    /// result is exact whenever it is below `reach`).
    pub(crate) fn segment_distance(&self, a: Vec2, b: Vec2, reach: f64) -> f64 {
        crate::count::query();
        if self.edges.is_empty() {
            return f64::INFINITY;
        }
        let g = self.buckets();
        let cell_of =
            |v: f64, o: f64, n: usize| (((v - o) / g.cell).floor().max(0.0) as usize).min(n - 1);
        let i0 = cell_of(a.x.min(b.x) - reach, g.origin.x, g.nx);
        let i1 = cell_of(a.x.max(b.x) + reach, g.origin.x, g.nx);
        let j0 = cell_of(a.y.min(b.y) - reach, g.origin.y, g.ny);
        let j1 = cell_of(a.y.max(b.y) + reach, g.origin.y, g.ny);
        let mut best = f64::INFINITY;
        for j in j0..=j1 {
            for i in i0..=i1 {
                let c = j * g.nx + i;
                for &e in &g.items[g.starts[c] as usize..g.starts[c + 1] as usize] {
                    let (p, q) = self.edges[e as usize];
                    best = best.min(seg_seg_dist(a, b, p, q));
                }
            }
        }
        best
    }
}

/// Distance between segments `a`–`b` and `p`–`q` (0 when they cross).
pub fn seg_seg_dist(a: Vec2, b: Vec2, p: Vec2, q: Vec2) -> f64 {
    let d1 = b - a;
    let d2 = q - p;
    let den = d1.cross(d2);
    if den != 0.0 {
        let t = (p - a).cross(d2) / den;
        let u = (p - a).cross(d1) / den;
        if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
            return 0.0;
        }
    }
    seg_dist2(a, p, q)
        .0
        .min(seg_dist2(b, p, q).0)
        .min(seg_dist2(p, a, b).0)
        .min(seg_dist2(q, a, b).0)
        .sqrt()
}

/// The point inside a closed polygon farthest from `part` (a 48×48 grid search,
/// then pattern search down to 1e-6), with that distance: where a counter's sink
/// goes, and where the tool starts inside a hole. A distance below 0 means the
/// polygon has no interior on the grid.
pub fn deepest_point(poly: &[Vec2], part: &DistanceIndex) -> (Vec2, f64) {
    let (mut lo, mut hi) = (poly[0], poly[0]);
    for p in poly {
        lo = Vec2::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Vec2::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    deepest_point_in(
        lo,
        hi,
        &|p| super::polygon_winding_number(poly, p) != 0,
        part,
    )
}

/// As `deepest_point`, for the region `inside` within the box [lo, hi].
pub(crate) fn deepest_point_in(
    lo: Vec2,
    hi: Vec2,
    inside: &dyn Fn(Vec2) -> bool,
    part: &DistanceIndex,
) -> (Vec2, f64) {
    let mut best = (lo, -1.0);
    let g = 48;
    for i in 0..=g {
        for j in 0..=g {
            let p = Vec2::new(
                lo.x + (hi.x - lo.x) * i as f64 / g as f64,
                lo.y + (hi.y - lo.y) * j as f64 / g as f64,
            );
            if inside(p) {
                let d = part.distance(p);
                if d > best.1 {
                    best = (p, d);
                }
            }
        }
    }
    if best.1 < 0.0 {
        return best;
    }
    let mut step = (hi - lo).norm() / g as f64;
    while step > 1e-6 {
        let mut moved = false;
        for dir in [
            Vec2::new(1.0, 0.0),
            Vec2::new(-1.0, 0.0),
            Vec2::new(0.0, 1.0),
            Vec2::new(0.0, -1.0),
        ] {
            let p = best.0 + dir * step;
            if inside(p) {
                let d = part.distance(p);
                if d > best.1 {
                    best = (p, d);
                    moved = true;
                }
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::num::testing::Lcg;

    fn star(c: Vec2, r0: f64, r1: f64, n: usize) -> Vec<Vec2> {
        (0..2 * n)
            .map(|k| {
                let a = std::f64::consts::PI * k as f64 / n as f64;
                let r = if k % 2 == 0 { r0 } else { r1 };
                c + Vec2::new(a.cos(), a.sin()) * r
            })
            .collect()
    }

    #[test]
    fn nearest_equals_brute_force() {
        let mut rng = Lcg(42);
        let polys = vec![
            star(Vec2::new(0.0, 0.0), 30.0, 12.0, 7),
            star(Vec2::new(80.0, 10.0), 5.0, 2.0, 40),
            vec![
                Vec2::new(-50.0, -50.0),
                Vec2::new(-49.0, -50.0),
                Vec2::new(-49.5, -45.0),
            ],
        ];
        let idx = DistanceIndex::new(&polys);
        assert_eq!(idx.edge_count(), 14 + 80 + 3);
        let mut worst: f64 = 0.0;
        for k in 0..20_000 {
            // Three quarters inside the grid's extent, the rest up to 1e4 away.
            let spread = if k % 4 == 3 { 2e4 } else { 160.0 };
            let p = Vec2::new(
                20.0 + (rng.next() - 0.5) * spread,
                (rng.next() - 0.5) * spread,
            );
            let (d, q) = idx.nearest(p);
            let b = idx.distance_brute(p);
            worst = worst.max((d - b).abs());
            assert!((p.dist(q) - d).abs() <= 1e-9 * d.max(1.0));
        }
        assert!(worst <= 1e-12, "grid vs brute force: {worst:e}");
    }

    /// The tracer's two walk queries, from any hint: `nearest_hinted` gives
    /// the distance to within rounding, and `closer_than` exactly the verdict
    /// of the brute-force distance (the min over every edge) compared with r,
    /// also for radii right at the distance.
    #[test]
    fn hinted_queries_agree_with_the_plain_ones() {
        let mut rng = Lcg(7);
        let polys = vec![
            star(Vec2::new(0.0, 0.0), 30.0, 12.0, 7),
            star(Vec2::new(80.0, 10.0), 5.0, 2.0, 40),
        ];
        let idx = DistanceIndex::new(&polys);
        let hint = std::cell::Cell::new(0);
        let (mut hits, mut misses) = (0, 0);
        for k in 0..20_000 {
            let p = Vec2::new(
                20.0 + (rng.next() - 0.5) * 160.0,
                (rng.next() - 0.5) * 160.0,
            );
            if k % 5 == 0 {
                // A hint that is anywhere, or out of range.
                hint.set((rng.next() * 200.0) as u32);
            }
            let d = idx.distance_brute(p);
            assert!((idx.nearest_hinted(p, &hint).0 - d).abs() <= 1e-12);
            // Radii below, at and just around the distance itself.
            for r in [
                d * 0.5,
                d,
                d * (1.0 + 1e-15),
                d * (1.0 - 1e-15),
                rng.next() * 40.0,
            ] {
                let want = d < r;
                assert_eq!(idx.closer_than(p, r, &hint), want, "p {p:?} r {r} d {d}");
                if want {
                    hits += 1;
                } else {
                    misses += 1;
                }
            }
        }
        assert!(hits > 10_000 && misses > 10_000, "{hits} {misses}");
    }

    #[test]
    fn long_diagonals_and_many_short_edges() {
        // A thin sliver triangle with two long diagonals plus a fine circle: the
        // grid is fine, the diagonals cross many cells.
        let mut circle: Vec<Vec2> = (0..2000)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 2000.0;
                Vec2::new(50.0 + 3.0 * a.cos(), 50.0 + 3.0 * a.sin())
            })
            .collect();
        circle.reverse();
        let sliver = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(100.0, 97.0),
            Vec2::new(99.0, 100.0),
        ];
        let idx = DistanceIndex::new(&[sliver, circle]);
        let mut rng = Lcg(9);
        let mut worst: f64 = 0.0;
        for _ in 0..20_000 {
            let p = Vec2::new(rng.next() * 120.0 - 10.0, rng.next() * 120.0 - 10.0);
            worst = worst.max((idx.distance(p) - idx.distance_brute(p)).abs());
        }
        assert!(worst <= 1e-12, "{worst:e}");
        // Only the cells along the diagonals hold them: far fewer than their boxes.
        let items = idx.buckets().items.len();
        assert!(items < 20 * idx.edges.len(), "{items} items");
    }

    #[test]
    fn degenerate_inputs() {
        let empty = DistanceIndex::new::<Vec<Vec2>>(&[]);
        assert_eq!(empty.distance(Vec2::new(1.0, 1.0)), f64::INFINITY);
        // A flat polygon (zero height) and a single point.
        let flat = DistanceIndex::new(&[vec![Vec2::new(0.0, 0.0), Vec2::new(10.0, 0.0)]]);
        assert_eq!(flat.distance(Vec2::new(5.0, 3.0)), 3.0);
        assert_eq!(flat.distance(Vec2::new(13.0, -4.0)), 5.0);
        let dot = DistanceIndex::new(&[vec![Vec2::new(2.0, 2.0)]]);
        assert_eq!(dot.distance(Vec2::new(5.0, 6.0)), 5.0);
    }
}
