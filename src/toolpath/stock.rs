//! The linker's model of the stock: how far down material has been removed at
//! every point, so that an entry comes down by rapid only to a clearance above the
//! material actually left and ramps in from there.
//!
//! A height map: one height per square cell, the height of the material at the
//! cell's centre. A flat end mill of radius r whose tip moves from `a` to `b`
//! lowers every cell whose centre comes within r of its axis to the lowest tip Z
//! while it does. Along a straight move Z is linear in the parameter t ∈ [0, 1]
//! and the t where the centre is within r form one interval (the roots of
//! |a + t·(b − a) − p|² = r² in the XY plane), so that lowest Z is the smaller of
//! the Z at the interval's ends: the cut is exact at the centres.
//!
//! Questions ("how high is the material under the tool here?") are answered
//! conservatively: every cell whose centre lies within r + half a cell diagonal
//! counts, so that a wall between centres is not missed.
//!
//! This model serves the linker only. The check of a finished program is
//! `pfcam simulate`, which reads the G-code and keeps its own stock.

use super::{Move, Vec3};
use crate::geometry::Vec2;

/// Most cells a map may have: at 8 bytes a cell, 128 MB. Larger stocks get
/// coarser cells (and so more conservative answers), never more memory.
pub(crate) const MAX_CELLS: usize = 16_000_000;

/// Finest and coarsest cell side, mm, before [`MAX_CELLS`] forces coarser.
const CELL_RANGE: (f64, f64) = (0.02, 0.1);

/// Written G-code is not the linker's path: it is fitted with arcs (within
/// half the tolerance) and rounded to 1 µm. The linker cuts its map with a
/// disk this much (plus the tolerance) narrower than the tool, so that it never
/// counts on a cut the written program may miss by a hair: an entry next to
/// such a rim ramps from the material there instead of plunging onto it.
pub(crate) const ROUNDING_SLACK: f64 = 0.001;

/// The radius the linker cuts its map with for a tool of `radius` and a job of
/// tolerance `tol` (see [`ROUNDING_SLACK`]); never below half the tool.
pub(crate) fn model_radius(radius: f64, tol: f64) -> f64 {
    (radius - tol.max(0.0) - ROUNDING_SLACK).max(0.5 * radius)
}

/// A height map of the stock over a rectangle; outside it there is no material.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct StockMap {
    lo: Vec2,
    cell: f64,
    nx: usize,
    ny: usize,
    h: Vec<f64>,
}

impl StockMap {
    /// A block of stock over `lo`..`hi` with its top at `top`, with cells fine
    /// enough for a tool of radius `radius` (an eighth of it, within 0.02 to
    /// 0.1 mm, coarser only when the rectangle would need more than
    /// [`MAX_CELLS`]).
    pub(crate) fn new(lo: Vec2, hi: Vec2, top: f64, radius: f64) -> StockMap {
        let (w, h) = ((hi.x - lo.x).max(0.0), (hi.y - lo.y).max(0.0));
        let mut cell = (radius / 8.0).clamp(CELL_RANGE.0, CELL_RANGE.1);
        if !(cell.is_finite() && w.is_finite() && h.is_finite()) {
            cell = CELL_RANGE.1;
        }
        let count = |c: f64| ((w / c).ceil().max(1.0), (h / c).ceil().max(1.0));
        let (fx, fy) = count(cell);
        if fx * fy > MAX_CELLS as f64 {
            cell *= (fx * fy / MAX_CELLS as f64).sqrt() * 1.01;
        }
        let (fx, fy) = count(cell);
        let (nx, ny) = (fx.min(1e7) as usize, fy.min(1e7) as usize);
        let (nx, ny) = if nx * ny > MAX_CELLS {
            (1, 1)
        } else {
            (nx, ny)
        };
        StockMap {
            lo,
            cell,
            nx,
            ny,
            h: vec![top; nx * ny],
        }
    }

    /// Side of a cell, mm.
    #[cfg(test)]
    pub(crate) fn cell(&self) -> f64 {
        self.cell
    }

    fn centre(&self, i: usize, j: usize) -> Vec2 {
        Vec2::new(
            self.lo.x + (i as f64 + 0.5) * self.cell,
            self.lo.y + (j as f64 + 0.5) * self.cell,
        )
    }

    /// Index ranges of the cells whose centres may lie within `r` of the
    /// rectangle spanned by `a` and `b`.
    fn cells_near(
        &self,
        a: Vec2,
        b: Vec2,
        r: f64,
    ) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
        let span = |lo: f64, hi: f64, origin: f64, n: usize| {
            let first = ((lo - r - origin) / self.cell - 0.5).floor().max(0.0);
            let last = ((hi + r - origin) / self.cell - 0.5).ceil() + 1.0;
            if !(first.is_finite() && last.is_finite()) || last <= 0.0 {
                return 0..0;
            }
            (first.min(n as f64) as usize)..(last.min(n as f64) as usize)
        };
        (
            span(a.x.min(b.x), a.x.max(b.x), self.lo.x, self.nx),
            span(a.y.min(b.y), a.y.max(b.y), self.lo.y, self.ny),
        )
    }

    /// In row `j`, the cells whose centres may lie within `r` of the segment
    /// `a`–`b`: those within `r` in x of the part of the segment inside the
    /// slab |y − y_j| ≤ r. A long diagonal move touches a band two radii wide,
    /// not its whole bounding box (which cost a quarter of mfs-sign's run).
    fn row_cells(&self, a: Vec2, b: Vec2, r: f64, j: usize) -> std::ops::Range<usize> {
        let yc = self.lo.y + (j as f64 + 0.5) * self.cell;
        let (y0, y1) = (yc - r, yc + r);
        let (t0, t1) = if (b.y - a.y).abs() < 1e-300 {
            if a.y < y0 || a.y > y1 {
                return 0..0;
            }
            (0.0, 1.0)
        } else {
            let ta = (y0 - a.y) / (b.y - a.y);
            let tb = (y1 - a.y) / (b.y - a.y);
            (ta.min(tb).max(0.0), ta.max(tb).min(1.0))
        };
        if t0 > t1 {
            return 0..0;
        }
        let (xa, xb) = (a.x + (b.x - a.x) * t0, a.x + (b.x - a.x) * t1);
        let first = ((xa.min(xb) - r - self.lo.x) / self.cell - 0.5)
            .floor()
            .max(0.0);
        let last = ((xa.max(xb) + r - self.lo.x) / self.cell - 0.5).ceil() + 1.0;
        if !(first.is_finite() && last.is_finite()) || last <= 0.0 {
            return 0..0;
        }
        (first.min(self.nx as f64) as usize)..(last.min(self.nx as f64) as usize)
    }

    /// Highest material within `r` of the segment `a`–`b` (the footprint of a
    /// tool moving along it), conservatively: `-∞` where there is none.
    pub(crate) fn top_near_segment(&self, a: Vec2, b: Vec2, r: f64) -> f64 {
        let reach = r + self.cell * std::f64::consts::FRAC_1_SQRT_2;
        let (_, js) = self.cells_near(a, b, reach);
        let mut top = f64::NEG_INFINITY;
        for j in js {
            for i in self.row_cells(a, b, reach, j) {
                let h = self.h[j * self.nx + i];
                if h > top && segment_distance(self.centre(i, j), a, b) <= reach {
                    top = h;
                }
            }
        }
        top
    }

    /// Highest material under a tool disk of radius `r` centred at `p`.
    pub(crate) fn top_near(&self, p: Vec2, r: f64) -> f64 {
        self.top_near_segment(p, p, r)
    }

    /// Highest material within `r` of the polyline `pts`.
    pub(crate) fn top_near_path(&self, pts: &[Vec2], r: f64) -> f64 {
        match pts {
            [] => f64::NEG_INFINITY,
            [p] => self.top_near(*p, r),
            _ => pts
                .windows(2)
                .map(|w| self.top_near_segment(w[0], w[1], r))
                .fold(f64::NEG_INFINITY, f64::max),
        }
    }

    /// Remove what a flat end mill of radius `r` cuts when its tip moves
    /// straight from `a` to `b`.
    pub(crate) fn cut_segment(&mut self, a: Vec3, b: Vec3, r: f64) {
        let (pa, pb) = (Vec2::new(a.x, a.y), Vec2::new(b.x, b.y));
        let (_, js) = self.cells_near(pa, pb, r);
        let d = pb - pa;
        let dd = d.dot(d);
        let zmin = a.z.min(b.z);
        for j in js {
            for i in self.row_cells(pa, pb, r, j) {
                // Already as low as this move reaches: most of a move's
                // footprint was cut by the move before it.
                if self.h[j * self.nx + i] <= zmin {
                    continue;
                }
                let w = pa - self.centre(i, j);
                let c = w.dot(w) - r * r;
                let (t0, t1) = if dd < 1e-18 {
                    if c > 0.0 {
                        continue;
                    }
                    (0.0, 1.0)
                } else {
                    let bq = w.dot(d);
                    let disc = bq * bq - dd * c;
                    if disc < 0.0 {
                        continue;
                    }
                    let sq = disc.sqrt();
                    ((-bq - sq) / dd, (-bq + sq) / dd)
                };
                if t1 < 0.0 || t0 > 1.0 {
                    continue;
                }
                let z = |t: f64| a.z + (b.z - a.z) * t.clamp(0.0, 1.0);
                let low = z(t0).min(z(t1));
                let h = &mut self.h[j * self.nx + i];
                if low < *h {
                    *h = low;
                }
            }
        }
    }

    /// Remove what the feed moves of `moves` cut, starting from `from`; rapids
    /// cut nothing (the linker keeps them in air). Returns where the moves end.
    pub(crate) fn cut_moves(&mut self, from: Vec3, moves: &[Move], r: f64) -> Vec3 {
        let mut at = from;
        for m in moves {
            match *m {
                Move::Rapid { to } => at = to,
                Move::Linear { to, .. } => {
                    self.cut_segment(at, to, r);
                    at = to;
                }
                Move::Arc {
                    to, cx, cy, ccw, ..
                } => {
                    let mut p = at;
                    for q in super::arc_flatten(at, to, cx, cy, ccw, 0.25 * self.cell) {
                        self.cut_segment(p, q, r);
                        p = q;
                    }
                    at = to;
                }
            }
        }
        at
    }

    /// Height of the cell containing `p`, `None` outside the map.
    #[cfg(test)]
    pub(crate) fn height_at(&self, p: Vec2) -> Option<f64> {
        let fi = ((p.x - self.lo.x) / self.cell).floor();
        let fj = ((p.y - self.lo.y) / self.cell).floor();
        if fi < 0.0 || fj < 0.0 || fi >= self.nx as f64 || fj >= self.ny as f64 {
            return None;
        }
        Some(self.h[fj as usize * self.nx + fi as usize])
    }
}

/// Distance from `p` to the segment `a`–`b`.
fn segment_distance(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let d = b - a;
    let dd = d.dot(d);
    let t = if dd > 0.0 {
        ((p - a).dot(d) / dd).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.dist(a + d * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map() -> StockMap {
        StockMap::new(Vec2::new(0.0, 0.0), Vec2::new(20.0, 10.0), 0.0, 1.0)
    }

    #[test]
    fn a_straight_cut_lowers_exactly_the_cells_within_the_radius() {
        let mut m = map();
        assert_eq!(m.cell(), 0.1);
        m.cut_segment(Vec3::new(5.0, 5.0, -1.0), Vec3::new(15.0, 5.0, -1.0), 1.0);
        for j in 0..m.ny {
            for i in 0..m.nx {
                let c = m.centre(i, j);
                let inside = segment_distance(c, Vec2::new(5.0, 5.0), Vec2::new(15.0, 5.0)) <= 1.0;
                let want = if inside { -1.0 } else { 0.0 };
                assert_eq!(m.h[j * m.nx + i], want, "cell at {c:?}");
            }
        }
    }

    #[test]
    fn a_ramp_leaves_the_lowest_tip_height_seen_by_each_cell() {
        let mut m = map();
        // Down from z 0 at x 5 to z −2 at x 15: a cell at x sees the tip at
        // x + 1 at the latest, so its height is −(x + 1 − 5)/5, clamped.
        m.cut_segment(Vec3::new(5.0, 5.0, 0.0), Vec3::new(15.0, 5.0, -2.0), 1.0);
        for x in [4.55, 7.05, 10.05, 13.95, 15.95] {
            let want = (-(x + 1.0 - 5.0) / 5.0_f64).clamp(-2.0, 0.0);
            let got = m.height_at(Vec2::new(x, 5.02)).unwrap();
            assert!((got - want).abs() < 1e-3, "x {x}: {got} vs {want}");
        }
    }

    #[test]
    fn questions_are_conservative_near_a_wall() {
        let mut m = map();
        m.cut_segment(Vec3::new(2.0, 5.0, -1.0), Vec3::new(18.0, 5.0, -1.0), 2.0);
        // On the axis, the whole 1 mm disk is cut; 1 mm off axis its edge
        // reaches the uncut wall at 2 mm.
        assert_eq!(m.top_near(Vec2::new(10.0, 5.0), 1.0), -1.0);
        assert_eq!(m.top_near(Vec2::new(10.0, 6.0), 1.0), 0.0);
        assert_eq!(m.top_near(Vec2::new(-5.0, 5.0), 1.0), f64::NEG_INFINITY);
        let path = [Vec2::new(10.0, 5.0), Vec2::new(10.0, 9.0)];
        assert_eq!(m.top_near_path(&path, 0.5), 0.0);
    }

    #[test]
    fn arcs_cut_like_their_chords() {
        let mut a = map();
        let mut b = map();
        let start = Vec3::new(13.0, 5.0, -1.0);
        let arc = [Move::Arc {
            to: Vec3::new(7.0, 5.0, -1.0),
            cx: 10.0,
            cy: 5.0,
            ccw: true,
            feed: 100.0,
        }];
        a.cut_moves(start, &arc, 0.5);
        let n = 400;
        let pts: Vec<Vec3> = (0..=n)
            .map(|k| {
                let t = std::f64::consts::PI * k as f64 / n as f64;
                Vec3::new(10.0 + 3.0 * t.cos(), 5.0 + 3.0 * t.sin(), -1.0)
            })
            .collect();
        for w in pts.windows(2) {
            b.cut_segment(w[0], w[1], 0.5);
        }
        // The chords lie within a quarter cell of the arc, so the two cuts may
        // disagree only at cells whose centres are that close to the edge of
        // the exact swept band (distance 0.5 from the half circle).
        let arc_distance = |p: Vec2| {
            let (dx, dy) = (p.x - 10.0, p.y - 5.0);
            if dy >= 0.0 {
                (dx.hypot(dy) - 3.0).abs()
            } else {
                p.dist(Vec2::new(13.0, 5.0))
                    .min(p.dist(Vec2::new(7.0, 5.0)))
            }
        };
        let mut differ = 0;
        for j in 0..a.ny {
            for i in 0..a.nx {
                if a.h[j * a.nx + i] != b.h[j * b.nx + i] {
                    let edge = (arc_distance(a.centre(i, j)) - 0.5).abs();
                    assert!(
                        edge <= 0.25 * a.cell() + 1e-3,
                        "cell {i},{j}: {edge} from the edge"
                    );
                    differ += 1;
                }
            }
        }
        assert!(differ < 100, "{differ} cells differ");
        assert_eq!(a.height_at(Vec2::new(10.0, 8.0)), Some(-1.0));
        assert_eq!(a.height_at(Vec2::new(10.0, 2.0)), Some(0.0));
    }

    #[test]
    fn a_huge_stock_gets_coarser_cells_not_more_memory() {
        let m = StockMap::new(Vec2::new(0.0, 0.0), Vec2::new(5000.0, 5000.0), 0.0, 1.0);
        assert!(m.nx * m.ny <= MAX_CELLS);
        assert!(m.cell() > 0.1);
        let m = StockMap::new(Vec2::new(0.0, 0.0), Vec2::new(f64::INFINITY, 1.0), 0.0, 1.0);
        assert!(m.nx * m.ny <= MAX_CELLS);
    }
}
