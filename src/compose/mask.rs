//! [`Csg::contains`] at every point of a grid at once, row by row.
//!
//! A leaf's winding number at p is a sum over the edges a→b that straddle
//! p's row (a.y ≤ y < b.y upward, b.y ≤ y < a.y downward) of ±1 where the
//! cross product c(p) = (b − a) × (p − a) = dx·(y − a.y) − dy·(x − a.x) has
//! the right sign (`geometry::polygon_winding_number`). Along a row only x
//! changes, and in floating point x − a.x is a non-decreasing function of x,
//! so c computed in floating point is monotone in x (non-increasing for an
//! upward edge, non-decreasing for a downward one): the points an edge counts
//! are a prefix of the row, found by bisection on the same expression. The
//! grid's answers are therefore those of `contains` at each point, bit for
//! bit, for O(edges · log nx + nx) per row instead of O(edges · nx).

use super::Csg;
use crate::geometry::{polygon_winding_number, Vec2};
use rayon::prelude::*;

impl Csg {
    /// `contains(p)` at the grid points p = (origin.x + h·i, origin.y + h·j),
    /// i < nx, j < ny, row-major (index j·nx + i): the same answers as
    /// [`Csg::contains`] at every point.
    pub fn grid_mask(&self, origin: Vec2, h: f64, nx: usize, ny: usize) -> Vec<bool> {
        let xs: Vec<f64> = (0..nx).map(|i| origin.x + h * i as f64).collect();
        let mut mask = vec![false; nx * ny];
        mask.par_chunks_mut(nx.max(1))
            .enumerate()
            .for_each(|(j, row)| {
                let y = origin.y + h * j as f64;
                row.copy_from_slice(&self.row(y, &xs));
            });
        mask
    }

    /// Membership of the points (x, y), x in `xs` (non-decreasing).
    fn row(&self, y: f64, xs: &[f64]) -> Vec<bool> {
        match self {
            Csg::Leaf { polys, complement } => {
                let w = winding_row(polys, y, xs);
                w.into_iter().map(|w| (w != 0) != *complement).collect()
            }
            Csg::Not(a) => a.row(y, xs).into_iter().map(|b| !b).collect(),
            Csg::And(a, b) => zip_with(a.row(y, xs), b.row(y, xs), |p, q| p && q),
            Csg::Or(a, b) => zip_with(a.row(y, xs), b.row(y, xs), |p, q| p || q),
        }
    }
}

fn zip_with(a: Vec<bool>, b: Vec<bool>, f: impl Fn(bool, bool) -> bool) -> Vec<bool> {
    a.into_iter().zip(b).map(|(p, q)| f(p, q)).collect()
}

/// The winding number of `polys` at every (x, y), x in `xs`.
fn winding_row(polys: &[Vec<Vec2>], y: f64, xs: &[f64]) -> Vec<i32> {
    let finite = polys
        .iter()
        .flatten()
        .all(|p| p.x.is_finite() && p.y.is_finite());
    if !finite || !y.is_finite() || xs.iter().any(|x| !x.is_finite()) {
        // Monotonicity needs numbers; point by point is the definition.
        return xs
            .iter()
            .map(|&x| {
                polys
                    .iter()
                    .map(|q| polygon_winding_number(q, Vec2::new(x, y)))
                    .sum()
            })
            .collect();
    }
    // diff[k] − diff[k+1] … : +w over a prefix [0, k) is diff[0] += w, diff[k] −= w.
    let mut diff = vec![0i32; xs.len() + 1];
    for poly in polys {
        let n = poly.len();
        for i in 0..n {
            let a = poly[i];
            let b = poly[(i + 1) % n];
            let c = |x: f64| (b - a).cross(Vec2::new(x, y) - a);
            if a.y <= y {
                if b.y > y {
                    let k = xs.partition_point(|&x| c(x) > 0.0);
                    diff[0] += 1;
                    diff[k] -= 1;
                }
            } else if b.y <= y {
                let k = xs.partition_point(|&x| c(x) < 0.0);
                diff[0] -= 1;
                diff[k] += 1;
            }
        }
    }
    let mut w = 0;
    xs.iter()
        .enumerate()
        .map(|(i, _)| {
            w += diff[i];
            w
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num::testing::Lcg;

    fn star(c: Vec2, r: f64, k: usize, turns: usize) -> Vec<Vec2> {
        // A star polygon {k/turns}: winding numbers up to `turns` inside.
        (0..k)
            .map(|i| {
                let t = std::f64::consts::TAU * (i * turns) as f64 / k as f64;
                c + Vec2::new(t.cos(), t.sin()) * r
            })
            .collect()
    }

    /// Every grid point, against `contains` point by point: self-crossing
    /// stars (winding 2), a rectangle whose edges lie on grid rows and
    /// columns, holes by complement, and every Boolean node.
    #[test]
    fn grid_mask_equals_contains_at_every_point() {
        let rect = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(2.0, 0.0),
            Vec2::new(2.0, 1.5),
            Vec2::new(0.0, 1.5),
        ];
        let leaf = |polys: Vec<Vec<Vec2>>, complement| Csg::Leaf { polys, complement };
        let a = leaf(vec![star(Vec2::new(1.0, 1.0), 1.2, 7, 3)], false);
        let b = leaf(vec![rect.clone()], false);
        let hole = leaf(vec![star(Vec2::new(1.5, 0.5), 0.6, 5, 2)], true);
        let trees = [
            a.clone(),
            b.clone(),
            hole.clone(),
            Csg::Not(Box::new(a.clone())),
            Csg::And(Box::new(a.clone()), Box::new(hole.clone())),
            Csg::Or(Box::new(b.clone()), Box::new(Csg::Not(Box::new(hole)))),
        ];
        let mut g = Lcg(7);
        let mut checked = 0;
        for t in &trees {
            // The grid through the rectangle's corners (h = 0.25), then
            // random origins and spacings.
            let mut grids = vec![(Vec2::new(-0.5, -0.5), 0.25, 17, 15)];
            for _ in 0..6 {
                let o = Vec2::new(g.range(-1.0, 0.5), g.range(-1.0, 0.5));
                grids.push((o, g.range(0.01, 0.2), 41, 37));
            }
            for (o, h, nx, ny) in grids {
                let mask = t.grid_mask(o, h, nx, ny);
                for j in 0..ny {
                    for i in 0..nx {
                        let p = Vec2::new(o.x + h * i as f64, o.y + h * j as f64);
                        assert_eq!(mask[j * nx + i], t.contains(p), "at {p:?}");
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 50_000);
        // Some points of the test grid are inside and some outside.
        let m = trees[0].grid_mask(Vec2::new(-0.5, -0.5), 0.05, 80, 80);
        assert!(m.iter().any(|&b| b) && m.iter().any(|&b| !b));
    }
}
