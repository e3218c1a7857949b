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
    let off = offsets(grid, tool);
    let (nx, ny) = (grid.nx as i64, grid.ny as i64);
    let at = |v: &[f64], i: i64, j: i64| -> Option<f64> {
        (i >= 0 && j >= 0 && i < nx && j < ny).then(|| v[(j * nx + i) as usize])
    };
    let drop: Vec<f64> = (0..grid.nx * grid.ny)
        .into_par_iter()
        .map(|k| {
            let (i, j) = ((k % grid.nx) as i64, (k / grid.nx) as i64);
            off.iter()
                .filter_map(|&(di, dj, l)| at(part, i + di, j + dj).map(|p| p - l))
                .fold(f64::NEG_INFINITY, f64::max)
        })
        .collect();
    (0..grid.nx * grid.ny)
        .into_par_iter()
        .map(|k| {
            let (i, j) = ((k % grid.nx) as i64, (k / grid.nx) as i64);
            let m = off
                .iter()
                .filter_map(|&(di, dj, l)| at(&drop, i - di, j - dj).map(|d| d + l))
                .filter(|v| v.is_finite())
                .fold(f64::INFINITY, f64::min);
            if m.is_finite() {
                m
            } else {
                f64::NEG_INFINITY
            }
        })
        .collect()
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
}
