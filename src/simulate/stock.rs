//! The stock as a height map: a grid of square cells, each holding the height
//! (z, mm) of the material at its centre. Material is removed by lowering a
//! cell; nothing ever raises one, so the height of a cell is the minimum of the
//! stock top and every tool bottom that passed over its centre.

/// A grid of `nx` × `ny` square cells of side `res` (mm) whose lower-left corner
/// is (`x0`, `y0`). Cell (i, j) has its centre at
/// (x0 + (i + ½)·res, y0 + (j + ½)·res) and index j·nx + i.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Lower-left corner, x, mm.
    pub(crate) x0: f64,
    /// Lower-left corner, y, mm.
    pub(crate) y0: f64,
    /// Cell side, mm.
    pub(crate) res: f64,
    /// Columns.
    pub nx: usize,
    /// Rows.
    pub ny: usize,
}

impl Grid {
    /// The grid covering the rectangle `lo`..`hi` (mm) with cells of side at
    /// least `res` and at most `max_cells` cells: when `res` would need more,
    /// the side grows to √(area / max_cells) (rounded up to 1 µm). Returns the
    /// grid; its `res` says whether it was coarsened.
    pub(crate) fn covering(lo: [f64; 2], hi: [f64; 2], res: f64, max_cells: usize) -> Grid {
        let (w, h) = ((hi[0] - lo[0]).max(0.0), (hi[1] - lo[1]).max(0.0));
        let cells = |r: f64| ((w / r).ceil().max(1.0), (h / r).ceil().max(1.0));
        let mut r = res;
        let (mut nx, mut ny) = cells(r);
        if nx * ny > max_cells as f64 {
            r = ((w * h / max_cells as f64).sqrt() * 1e3).ceil() / 1e3;
            (nx, ny) = cells(r);
            // The ceilings can add a row and a column: grow until it fits.
            while nx * ny > max_cells as f64 {
                r *= 1.01;
                (nx, ny) = cells(r);
            }
        }
        Grid {
            x0: lo[0],
            y0: lo[1],
            res: r,
            nx: nx as usize,
            ny: ny as usize,
        }
    }

    /// Centre of column `i`, mm.
    pub fn cx(&self, i: usize) -> f64 {
        self.x0 + (i as f64 + 0.5) * self.res
    }

    /// Centre of row `j`, mm.
    pub fn cy(&self, j: usize) -> f64 {
        self.y0 + (j as f64 + 0.5) * self.res
    }

    /// The columns whose centres lie in [a, b] (mm), clipped to the grid;
    /// `None` when there are none.
    pub fn cols(&self, a: f64, b: f64) -> Option<(usize, usize)> {
        index_range(a - self.x0, b - self.x0, self.res, self.nx)
    }

    /// The rows whose centres lie in [a, b] (mm), clipped to the grid.
    pub fn rows(&self, a: f64, b: f64) -> Option<(usize, usize)> {
        index_range(a - self.y0, b - self.y0, self.res, self.ny)
    }

    /// The cell whose square holds (x, y), if inside the grid.
    #[cfg(test)]
    pub(crate) fn cell_at(&self, x: f64, y: f64) -> Option<(usize, usize)> {
        let i = ((x - self.x0) / self.res).floor();
        let j = ((y - self.y0) / self.res).floor();
        (i >= 0.0 && j >= 0.0 && i < self.nx as f64 && j < self.ny as f64)
            .then_some((i as usize, j as usize))
    }

    /// Upper-right corner, mm.
    pub(crate) fn hi(&self) -> [f64; 2] {
        [
            self.x0 + self.nx as f64 * self.res,
            self.y0 + self.ny as f64 * self.res,
        ]
    }
}

/// Indices k in 0..n with (k + ½)·res ∈ [a, b].
fn index_range(a: f64, b: f64, res: f64, n: usize) -> Option<(usize, usize)> {
    if a.partial_cmp(&b)
        .is_none_or(|o| o == std::cmp::Ordering::Greater)
        || n == 0
    {
        return None;
    }
    // Clamped before rounding, so the casts below are of numbers in range.
    let lo = -floor(-(a / res - 0.5).clamp(-1.0, n as f64));
    let hi = floor((b / res - 0.5).clamp(-1.0, n as f64)).min(n as f64 - 1.0);
    let lo = lo.max(0.0);
    (lo <= hi).then_some((lo as usize, hi as usize))
}

/// ⌊x⌋ for |x| < 2⁶², by an integer cast (`f64::floor` is a library call on
/// baseline x86-64, and this runs for every row of every piece).
fn floor(x: f64) -> f64 {
    let i = x as i64 as f64;
    if i > x {
        i - 1.0
    } else {
        i
    }
}

/// The stock: a [`Grid`], the stock top (mm) and the height of every cell.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightMap {
    /// The cells.
    pub grid: Grid,
    /// The uncut stock's top, mm.
    pub(crate) top: f64,
    /// Height of each cell's centre, mm, row by row from the bottom.
    pub h: Vec<f64>,
    /// The line of the move that last lowered each cell (0: never cut).
    pub(crate) last_cut: Vec<u32>,
}

impl HeightMap {
    /// Uncut stock: every cell at `top`.
    pub(crate) fn new(grid: Grid, top: f64) -> HeightMap {
        let n = grid.nx * grid.ny;
        HeightMap {
            grid,
            top,
            h: vec![top; n],
            last_cut: vec![0; n],
        }
    }

    /// Height at the centre of cell (i, j).
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.h[j * self.grid.nx + i]
    }

    /// Lowest height, mm.
    pub fn min(&self) -> f64 {
        self.h.iter().copied().fold(self.top, f64::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_cells_and_ranges() {
        let g = Grid::covering([0.0, 0.0], [1.0, 0.5], 0.1, 1_000_000);
        assert_eq!((g.nx, g.ny), (10, 5));
        assert!((g.cx(0) - 0.05).abs() < 1e-12);
        // Centres 0.05, 0.15, ..., 0.95: those in [0.1, 0.35] are 0.15, 0.25.
        assert_eq!(g.cols(0.1, 0.35), Some((1, 2)));
        assert_eq!(g.cols(-5.0, 0.04), None);
        assert_eq!(g.cols(0.9, 7.0), Some((9, 9)));
        assert_eq!(g.cell_at(0.99, 0.01), Some((9, 0)));
        assert_eq!(g.cell_at(1.01, 0.01), None);
    }

    #[test]
    fn too_many_cells_coarsen_the_grid() {
        let g = Grid::covering([0.0, 0.0], [100.0, 100.0], 0.01, 10_000);
        assert!(g.nx * g.ny <= 10_000, "{g:?}");
        assert!(g.res >= 1.0 && g.res < 1.05, "{g:?}");
        assert!(g.hi()[0] >= 100.0 && g.hi()[1] >= 100.0);
    }
}
