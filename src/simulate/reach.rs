//! What a cutter can reach of the part: the lowest surface a tool of its
//! shape can leave over every cell without entering the part, as a machinist
//! separates "material the tool cannot reach" (a valley narrower than a ball,
//! a corner rounder than the radius) from "material the program left".
//!
//! On the cells, with the tool's lift p(ρ) (0 on its flat, rising on its
//! corner) over the offsets within its radius: the lowest tip over cell c is
//! drop(c) = max over offsets δ of part(c + δ) − p(|δ|) (the drop-cutter on the
//! part's heights), and the envelope over cell x is
//! reach(x) = min over δ of drop(x − δ) + p(|δ|): the lowest any placement of
//! the tool leaves there. reach ≥ part everywhere, equal where the tool fits;
//! the material above reach is what the programs left.

use super::stock::Grid;
use super::tool::Tool;
use rayon::prelude::*;

/// The offsets (di, dj) of the cells within the tool's radius with the lift
/// there.
fn offsets(grid: &Grid, tool: &Tool) -> Vec<(i64, i64, f64)> {
    let h = grid.res;
    let n = (tool.radius() / h).floor() as i64;
    let mut out = Vec::new();
    for dj in -n..=n {
        for di in -n..=n {
            let rho = ((di * di + dj * dj) as f64).sqrt() * h;
            if let Some(l) = tool.lift(rho) {
                out.push((di, dj, l));
            }
        }
    }
    out
}

/// The envelope (see the module docs) of `part` (row-major on `grid`, −∞
/// where there is no part) for `tool`; −∞ where no placement covers a cell.
pub fn envelope(grid: &Grid, part: &[f64], tool: &Tool) -> Vec<f64> {
    envelope_of_drops(grid, &drops(grid, part, tool), tool)
}

/// The drop of `tool` over every cell on the heights `part` (drop(c) in the
/// module docs: the lowest tip there without entering a cell's height).
pub(crate) fn drops(grid: &Grid, part: &[f64], tool: &Tool) -> Vec<f64> {
    let off = offsets(grid, tool);
    let (nx, ny) = (grid.nx as i64, grid.ny as i64);
    let at = |v: &[f64], i: i64, j: i64| -> Option<f64> {
        (i >= 0 && j >= 0 && i < nx && j < ny).then(|| v[(j * nx + i) as usize])
    };
    (0..grid.nx * grid.ny)
        .into_par_iter()
        .map(|k| {
            let (i, j) = ((k % grid.nx) as i64, (k / grid.nx) as i64);
            off.iter()
                .filter_map(|&(di, dj, l)| at(part, i + di, j + dj).map(|p| p - l))
                .fold(f64::NEG_INFINITY, f64::max)
        })
        .collect()
}

/// The envelope over every cell of the tips `drop` (from [`drops`]).
pub(crate) fn envelope_of_drops(grid: &Grid, drop: &[f64], tool: &Tool) -> Vec<f64> {
    let off = offsets(grid, tool);
    let (nx, ny) = (grid.nx as i64, grid.ny as i64);
    let at = |i: i64, j: i64| -> Option<f64> {
        (i >= 0 && j >= 0 && i < nx && j < ny).then(|| drop[(j * nx + i) as usize])
    };
    (0..grid.nx * grid.ny)
        .into_par_iter()
        .map(|k| lowest(grid, &off, k, &at))
        .collect()
}

/// The lowest surface any placement leaves over cell `k`: min over the
/// offsets of the tip `drop_of` the placement gives (`None`: none there)
/// plus the lift; −∞ where no placement covers it.
fn lowest(
    grid: &Grid,
    off: &[(i64, i64, f64)],
    k: usize,
    drop_of: &dyn Fn(i64, i64) -> Option<f64>,
) -> f64 {
    let (i, j) = ((k % grid.nx) as i64, (k / grid.nx) as i64);
    let m = off
        .iter()
        .filter_map(|&(di, dj, l)| drop_of(i - di, j - dj).map(|d| d + l))
        .filter(|v| v.is_finite())
        .fold(f64::INFINITY, f64::min);
    if m.is_finite() {
        m
    } else {
        f64::NEG_INFINITY
    }
}

/// The envelope `env` (from [`envelope_of_drops`] of `drop`) raised at the cells `cells` to
/// what the tool's drops onto the part itself give there: each placement
/// within the tool's radius of such a cell takes the higher of its drop on
/// the cells' heights (`drop`, from [`drops`], not recomputed) and `drop_at(x, y, floor)` (the drop onto the part's
/// triangles at the placement's centre; it may skip what cannot lift the
/// tool over `floor`, the drop on the cells; `None`: nothing under it). On a near-vertical wall
/// the cells' heights let the tool sink between two cell centres (up to
/// √(2·r·δ) for a ball grazing a wall δ from a centre), so the envelope lay
/// under the part's foot and read material the programs could not remove
/// as left (docs/simulate.md). Drops onto a subset of the part are never
/// above the true drop, so neither is the result.
pub(crate) fn refine(
    grid: &Grid,
    drop: &[f64],
    tool: &Tool,
    env: &mut [f64],
    cells: &[usize],
    drop_at: &(dyn Fn(f64, f64, f64) -> Option<f64> + Sync),
) {
    use std::collections::HashMap;
    let off = offsets(grid, tool);
    let (nx, ny) = (grid.nx as i64, grid.ny as i64);
    let inside = |i: i64, j: i64| i >= 0 && j >= 0 && i < nx && j < ny;
    let mut places: Vec<(i64, i64)> = cells
        .iter()
        .flat_map(|&k| {
            let (i, j) = ((k % grid.nx) as i64, (k / grid.nx) as i64);
            off.iter()
                .map(move |&(di, dj, _)| (i - di, j - dj))
                .filter(|&(a, b)| inside(a, b))
        })
        .collect();
    places.sort_unstable();
    places.dedup();
    let drops: HashMap<(i64, i64), f64> = places
        .par_iter()
        .map(|&(i, j)| {
            let on_cells = drop[(j * nx + i) as usize];
            let exact = drop_at(grid.cx(i as usize), grid.cy(j as usize), on_cells);
            ((i, j), exact.map_or(on_cells, |e| e.max(on_cells)))
        })
        .collect();
    let refined = |i: i64, j: i64| drops.get(&(i, j)).copied();
    for &k in cells {
        env[k] = env[k].max(lowest(grid, &off, k, &refined));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::tool::ToolShape;

    fn grid(n: usize, h: f64) -> Grid {
        Grid::covering([0.0, 0.0], [n as f64 * h, n as f64 * h], h, usize::MAX)
    }

    #[test]
    fn a_ball_reaches_a_wide_valley_but_not_a_narrow_one() {
        let h = 0.05;
        let g = grid(120, h);
        let ball = Tool::new(ToolShape::Ball, 2.0, None).unwrap();
        // A V valley along y: part = |x − 3| · slope; a ball of radius 1 sits
        // in a 90° V (slope 1) with its tip sin(45°)-offset: the envelope at
        // the bottom is r(√2 − 1) = 0.414 above the part.
        let part: Vec<f64> = (0..g.nx * g.ny)
            .map(|k| (g.cx(k % g.nx) - 3.0).abs())
            .collect();
        let env = envelope(&g, &part, &ball);
        let mid = (g.ny / 2) * g.nx + ((3.0 - g.cx(0)) / h).round() as usize;
        let expect = 2.0f64.sqrt() - 1.0;
        assert!(
            (env[mid] - part[mid] - expect).abs() < 0.03,
            "{}",
            env[mid] - part[mid]
        );
        // On the flanks, well inside, the ball touches the plane: reach = part.
        let flank = (g.ny / 2) * g.nx + ((4.5 - g.cx(0)) / h).round() as usize;
        assert!(
            (env[flank] - part[flank]).abs() < 0.01,
            "{}",
            env[flank] - part[flank]
        );
        // A flat plane is reached everywhere by every shape.
        let plane = vec![-1.0; g.nx * g.ny];
        for t in [
            ball,
            Tool::new(ToolShape::Flat, 2.0, None).unwrap(),
            Tool::new(ToolShape::Bull, 2.0, Some(0.3)).unwrap(),
        ] {
            let e = envelope(&g, &plane, &t);
            assert!(e.iter().all(|&v| (v + 1.0).abs() < 1e-12));
        }
        // Never below the part.
        assert!(env.iter().zip(&part).all(|(e, p)| e >= &(p - 1e-12)));
    }

    /// A steep wall along y (84°): the top z = 0 for x < 1, down to z = −1
    /// at x = 1.1, the floor beyond, and a ball of radius 1 on 0.1 mm cells.
    /// On the cells' heights a ball near the wall misses its top edge,
    /// which lies between two cell centres, and sinks (0.31 mm at x = 1.95),
    /// so the envelope over the foot lies too low; refined by the exact drops
    /// onto the wall's triangles it equals the envelope of those exact tips
    /// over the same placements.
    #[test]
    fn refined_by_exact_drops_the_envelope_stands_on_a_steep_wall() {
        let h = 0.1;
        let g = Grid::covering([0.0, 0.0], [4.0, 1.0], h, usize::MAX);
        let ball = Tool::new(ToolShape::Ball, 2.0, None).unwrap();
        let height = |x: f64| (-(x - 1.0) * 10.0).clamp(-1.0, 0.0);
        let part: Vec<f64> = (0..g.nx * g.ny).map(|k| height(g.cx(k % g.nx))).collect();
        // Strips x0..x1 along y of the plane z = height, two triangles each.
        let strip = |x0: f64, x1: f64| {
            let (z0, z1) = (height(x0), height(x1));
            [
                [[x0, -3.0, z0], [x1, -3.0, z1], [x1, 4.0, z1]],
                [[x0, -3.0, z0], [x1, 4.0, z1], [x0, 4.0, z0]],
            ]
        };
        let tris: Vec<[[f64; 3]; 3]> = [strip(-3.0, 1.0), strip(1.0, 1.1), strip(1.1, 7.0)]
            .into_iter()
            .flatten()
            .collect();
        let drop_at = |x: f64, y: f64, _floor: f64| -> Option<f64> {
            let z = tris
                .iter()
                .map(|t| super::super::balldrop::ball_on_triangle(t, x, y, 1.0))
                .fold(f64::NEG_INFINITY, f64::max);
            z.is_finite().then_some(z - 1.0)
        };
        // The exact tip of a placement at x, and the envelope of those tips
        // over the cell centres within the radius along the row.
        let tip = |x: f64| drop_at(x, 0.5, f64::NEG_INFINITY).unwrap();
        let want = |i: usize| {
            (0..g.nx)
                .filter(|&c| c.abs_diff(i) <= 10)
                .map(|c| tip(g.cx(c)) + ball.lift(c.abs_diff(i) as f64 * h).unwrap())
                .fold(f64::INFINITY, f64::min)
        };
        // At x = 1.95 the ball rests on the top edge, 0.95 off.
        assert!((tip(1.95) - ((1.0f64 - 0.95 * 0.95).sqrt() - 1.0)).abs() < 1e-12);
        let mut env = envelope(&g, &part, &ball);
        let row = (g.ny / 2) * g.nx;
        let foot: Vec<usize> = (0..g.nx)
            .filter(|&i| g.cx(i) > 1.1 && g.cx(i) < 2.1)
            .map(|i| row + i)
            .collect();
        // Before: under the exact envelope by far more than a scallop.
        let sunk = foot
            .iter()
            .map(|&k| want(k % g.nx) - env[k])
            .fold(0.0, f64::max);
        assert!(sunk > 0.02, "{sunk}");
        refine(
            &g,
            &drops(&g, &part, &ball),
            &ball,
            &mut env,
            &foot,
            &drop_at,
        );
        for &k in &foot {
            let i = k % g.nx;
            assert!(
                (env[k] - want(i)).abs() < 1e-9,
                "x {}: {} vs {}",
                g.cx(i),
                env[k],
                want(i)
            );
        }
    }
}
