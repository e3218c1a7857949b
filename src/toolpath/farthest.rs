//! The farthest point of the stock from the part, which sizes a boss level's
//! outermost clearing ring.
//!
//! The answer is the largest distance to the part over a grid of the stock
//! rectangle (points inside the part skipped), plus half a cell's diagonal.
//! The distance to the part's edges is 1-Lipschitz, so a block of grid points
//! whose middle point is at distance d holds no point farther than d + ρ, ρ
//! the largest distance from the middle point to the block's corners: blocks
//! are opened best bound first and a block whose bound cannot beat the best
//! point found is never opened. The grid's maximum is the same as when every
//! point is measured (the bound is strict by a margin far above rounding),
//! at a few percent of the distance queries.

use crate::geometry::{DistanceIndex, Vec2};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Blocks whose bound exceeds the best by less than this (mm) are still
/// opened: a margin far above the rounding of a distance, so the result is
/// the grid's maximum exactly.
const SLACK: f64 = 1e-9;

/// An upper bound of the largest distance from a point of the stock rectangle
/// outside the part to the part: the largest on a grid of spacing `step / 2`
/// (at most 2000 cells along the longer side; points inside the part skipped),
/// plus half the cell's diagonal (the distance is 1-Lipschitz). Not the
/// corners alone: above a deep bay of the part (the V of an M) the stock's
/// edge is farther from the part than any corner, and rings sized by the
/// corners left 3 mm wedges of stock uncut there.
pub(crate) fn farthest_stock_point(
    part: &[Vec<Vec2>],
    index: &DistanceIndex,
    lo: Vec2,
    hi: Vec2,
    step: f64,
) -> f64 {
    let g = StockGrid::new(part, lo, hi, step);
    let mut far: f64 = 0.0;
    let mut heap = BinaryHeap::new();
    let whole = Block {
        i0: 0,
        i1: g.nx,
        j0: 0,
        j1: g.ny,
        bound: f64::INFINITY,
    };
    heap.push(whole);
    while let Some(b) = heap.pop() {
        if b.bound + SLACK < far {
            break;
        }
        for child in b.split() {
            let (ci, cj) = child.middle();
            let d = index.distance(g.point(ci, cj));
            if child.i1 - child.i0 == 1 && child.j1 - child.j0 == 1 {
                if !g.inside(ci, cj) {
                    far = far.max(d);
                }
                continue;
            }
            let bound = d + g.h * child.reach(ci, cj);
            if bound + SLACK >= far {
                heap.push(Block { bound, ..child });
            }
        }
    }
    far + g.h * std::f64::consts::FRAC_1_SQRT_2
}

/// The grid over the stock and its inside-the-part mask.
struct StockGrid {
    lo: Vec2,
    h: f64,
    nx: usize,
    ny: usize,
    inside: Vec<bool>,
}

impl StockGrid {
    fn new(part: &[Vec<Vec2>], lo: Vec2, hi: Vec2, step: f64) -> StockGrid {
        let size = hi - lo;
        let h = (0.5 * step).max(size.x.max(size.y) / 2000.0);
        let (nx, ny) = (
            (size.x / h).ceil() as usize + 1,
            (size.y / h).ceil() as usize + 1,
        );
        let inside = crate::field::isolines::fill_rows(lo, h, nx, ny, part);
        StockGrid {
            lo,
            h,
            nx,
            ny,
            inside,
        }
    }

    fn point(&self, i: usize, j: usize) -> Vec2 {
        self.lo + Vec2::new(i as f64 * self.h, j as f64 * self.h)
    }

    fn inside(&self, i: usize, j: usize) -> bool {
        self.inside[j * self.nx + i]
    }
}

/// Grid points i0..i1 × j0..j1 and an upper bound of their distances.
#[derive(Clone, Copy, Debug)]
struct Block {
    i0: usize,
    i1: usize,
    j0: usize,
    j1: usize,
    bound: f64,
}

impl Block {
    /// The block in up to four quarters (halves of each side longer than 1).
    fn split(&self) -> impl Iterator<Item = Block> + '_ {
        let im = (self.i0 + self.i1).div_ceil(2);
        let jm = (self.j0 + self.j1).div_ceil(2);
        let is = [(self.i0, im), (im, self.i1)];
        let js = [(self.j0, jm), (jm, self.j1)];
        js.into_iter()
            .flat_map(move |(j0, j1)| is.into_iter().map(move |(i0, i1)| (i0, i1, j0, j1)))
            .filter(|&(i0, i1, j0, j1)| i0 < i1 && j0 < j1)
            .map(|(i0, i1, j0, j1)| Block {
                i0,
                i1,
                j0,
                j1,
                bound: f64::INFINITY,
            })
    }

    /// The grid point at the block's middle.
    fn middle(&self) -> (usize, usize) {
        ((self.i0 + self.i1 - 1) / 2, (self.j0 + self.j1 - 1) / 2)
    }

    /// Distance, in cells, from grid point (i, j) to the block's farthest point.
    fn reach(&self, i: usize, j: usize) -> f64 {
        let dx = (i - self.i0).max(self.i1 - 1 - i) as f64;
        let dy = (j - self.j0).max(self.j1 - 1 - j) as f64;
        dx.hypot(dy)
    }
}

impl PartialEq for Block {
    fn eq(&self, o: &Block) -> bool {
        self.bound.total_cmp(&o.bound) == Ordering::Equal
    }
}
impl Eq for Block {}
impl PartialOrd for Block {
    fn partial_cmp(&self, o: &Block) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Block {
    fn cmp(&self, o: &Block) -> Ordering {
        self.bound.total_cmp(&o.bound)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every grid point measured: the definition the search must reproduce.
    fn brute(part: &[Vec<Vec2>], index: &DistanceIndex, lo: Vec2, hi: Vec2, step: f64) -> f64 {
        let g = StockGrid::new(part, lo, hi, step);
        let mut far: f64 = 0.0;
        for j in 0..g.ny {
            for i in 0..g.nx {
                if !g.inside(i, j) {
                    far = far.max(index.distance(g.point(i, j)));
                }
            }
        }
        far + g.h * std::f64::consts::FRAC_1_SQRT_2
    }

    fn star(c: Vec2, r0: f64, r1: f64, n: usize, turn: f64) -> Vec<Vec2> {
        (0..2 * n)
            .map(|k| {
                let a = turn + std::f64::consts::PI * k as f64 / n as f64;
                let r = if k % 2 == 0 { r0 } else { r1 };
                c + Vec2::new(r * a.cos(), r * a.sin())
            })
            .collect()
    }

    #[test]
    fn the_search_finds_the_grids_maximum_exactly() {
        let cases = [
            (vec![star(Vec2::new(30.0, 20.0), 15.0, 4.0, 5, 0.1)], 1.27),
            (
                vec![
                    star(Vec2::new(10.0, 10.0), 8.0, 3.0, 7, 0.0),
                    star(Vec2::new(45.0, 28.0), 6.0, 5.0, 3, 1.0),
                ],
                0.8,
            ),
            (vec![star(Vec2::new(30.0, 20.0), 2.0, 1.0, 4, 0.3)], 3.0),
        ];
        for (part, step) in cases {
            let index = DistanceIndex::new(&part);
            let (lo, hi) = (Vec2::new(-2.0, -3.0), Vec2::new(61.0, 41.5));
            let fast = farthest_stock_point(&part, &index, lo, hi, step);
            let all = brute(&part, &index, lo, hi, step);
            assert_eq!(fast, all, "step {step}");
        }
    }

    #[test]
    fn the_farthest_stock_point_can_lie_above_a_bay() {
        // A U open at the top, 40 × 40, its bay 30 wide and 35 deep, in a
        // stock 1 mm larger all round. Every corner of the stock is 1.41 from
        // the U; the bay's points on its axis from (20, 20) up to the stock's
        // edge at (20, 41) are 15 or more from the arms.
        let u = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(40.0, 0.0),
            Vec2::new(40.0, 40.0),
            Vec2::new(35.0, 40.0),
            Vec2::new(35.0, 5.0),
            Vec2::new(5.0, 5.0),
            Vec2::new(5.0, 40.0),
            Vec2::new(0.0, 40.0),
        ];
        let part = vec![u];
        let index = DistanceIndex::new(&part);
        let (lo, hi) = (Vec2::new(-1.0, -1.0), Vec2::new(41.0, 41.0));
        let exact = index.distance(Vec2::new(20.0, 41.0));
        assert!((exact - 226.0f64.sqrt()).abs() < 1e-12);
        let far = farthest_stock_point(&part, &index, lo, hi, 1.27);
        assert!(far >= exact, "{far} < {exact}");
        assert!(far <= exact + 0.5, "{far} far above {exact}");
        assert!(index.distance(lo) < 1.5);
        assert_eq!(far, brute(&part, &index, lo, hi, 1.27));
    }
}
