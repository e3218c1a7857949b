//! Equipotential curves Γ(s) = {u = s} (the paper's (2.2)) as closed polygons.
//!
//! u is sampled once on a grid, then each level is extracted by marching squares
//! (`field::march`, shared with `field::contour`, its rings turned to have u ≥ s
//! on their left; non-finite values compared as they are) and every vertex is placed on its grid edge by regula falsi on u, so it
//! lies on Γ(s) to 1e-9 of the field's value. Inside the material the MFS sum is
//! meaningless (the singularities live there), so grid points in the material
//! count as u = 1, the value on the generating boundary.
//!
//! Loops are oriented with the region u ≥ s on their left: around the material
//! they run counter-clockwise, around a hole (a counter's sink) clockwise, the same
//! "material on the left" convention as the glyph contours.
//!
//! This is the one sampling and the one extractor of Γ(s): the level planner,
//! compose, the finishing and the surface take its rings ([`isolines`],
//! [`isolines_in`]); the preview draws every piece, the open ones that leave
//! the drawing too ([`pieces`]), on a grid sampled through the guard against
//! a cell size given in the wrong unit ([`Grid::try_sample`]).

use super::march::{self, Edge, Gaps, Level};
use super::Field;
use crate::geometry::{polygon_winding_number, polygons_bbox, Ring, Vec2};
use rayon::prelude::*;

/// Values of u on a regular grid, with the material marked.
#[derive(Clone, Debug)]
pub struct Grid {
    /// Lower-left corner.
    pub origin: Vec2,
    /// Spacing, mm.
    pub h: f64,
    /// Points in x.
    pub nx: usize,
    /// Points in y.
    pub ny: usize,
    /// u at point (i, j) is `values[j * nx + i]`; 1 inside the material.
    pub values: Vec<f64>,
    /// True inside the material.
    pub inside: Vec<bool>,
}

/// Marks grid points inside the closed polygons (non-zero winding): the
/// grid's rows and columns through [`crate::geometry::winding_rows`].
pub(crate) fn fill_rows(
    origin: Vec2,
    h: f64,
    nx: usize,
    ny: usize,
    polys: &[Vec<Vec2>],
) -> Vec<bool> {
    let xs: Vec<f64> = (0..nx).map(|i| origin.x + h * i as f64).collect();
    let ys: Vec<f64> = (0..ny).map(|j| origin.y + h * j as f64).collect();
    crate::geometry::winding_rows(&xs, &ys, polys)
}

/// The most grid points [`Grid::try_sample`] will take (a guard against a
/// cell size given in the wrong unit: 16 M points is a 4000 × 4000 grid).
pub const MAX_GRID_POINTS: usize = 16_000_000;

/// Why a grid cannot be sampled.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ContourError {
    /// A cell size that is not a positive number, or a corner of the box
    /// that is not finite.
    #[error("equipotential grid: cell size must be a positive number, got {h}")]
    CellSize {
        /// The cell size given.
        h: f64,
    },
    /// A box whose `hi` does not exceed its `lo` in x and y.
    #[error("equipotential grid: the rectangle is empty (hi must exceed lo in x and y)")]
    EmptyRect,
    /// More than [`MAX_GRID_POINTS`] points.
    #[error("equipotential grid: {nx} × {ny} cells are too many (at most {MAX_GRID_POINTS} points); use a larger cell")]
    TooManyCells {
        /// Cells across.
        nx: f64,
        /// Cells down.
        ny: f64,
    },
}

impl Grid {
    /// [`Grid::sample`] after checking the box and the spacing: `h` a
    /// positive number, `hi` above and right of `lo`, and at most
    /// [`MAX_GRID_POINTS`] points.
    pub fn try_sample(
        field: &Field,
        lo: Vec2,
        hi: Vec2,
        h: f64,
        material: &[Vec<Vec2>],
    ) -> Result<Grid, ContourError> {
        if !(h > 0.0 && h.is_finite() && lo.is_finite() && hi.is_finite()) {
            return Err(ContourError::CellSize { h });
        }
        if !(hi.x > lo.x && hi.y > lo.y) {
            return Err(ContourError::EmptyRect);
        }
        let nx = ((hi.x - lo.x) / h).ceil();
        let ny = ((hi.y - lo.y) / h).ceil();
        if (nx + 1.0) * (ny + 1.0) > MAX_GRID_POINTS as f64 {
            return Err(ContourError::TooManyCells { nx, ny });
        }
        Ok(Grid::sample(field, lo, hi, h, material))
    }

    /// Sample u over the box [lo, hi] with spacing `h`; `material` are the closed
    /// polygons of the generating boundary (material on the left).
    pub fn sample(field: &Field, lo: Vec2, hi: Vec2, h: f64, material: &[Vec<Vec2>]) -> Grid {
        let mask = |lo: Vec2, h: f64, nx: usize, ny: usize| fill_rows(lo, h, nx, ny, material);
        Grid::sample_masked(field, lo, hi, h, &mask)
    }

    /// As `sample`, with the material given by a membership test.
    /// Sample u over the box [lo, hi] with spacing `h`, where `mask(lo, h, nx,
    /// ny)` marks the grid points inside the material (row-major, index
    /// j·nx + i): u is taken as 1 there and evaluated elsewhere.
    pub fn sample_masked(
        field: &Field,
        lo: Vec2,
        hi: Vec2,
        h: f64,
        mask: &(dyn Fn(Vec2, f64, usize, usize) -> Vec<bool> + Sync),
    ) -> Grid {
        let nx = (((hi.x - lo.x) / h).ceil() as usize + 1).max(2);
        let ny = (((hi.y - lo.y) / h).ceil() as usize + 1).max(2);
        let mut inside = mask(lo, h, nx, ny);
        debug_assert_eq!(inside.len(), nx * ny, "a grid mask has one entry per point");
        inside.resize(nx * ny, false);
        let mut values = vec![0.0; nx * ny];
        values
            .par_chunks_mut(nx)
            .zip(inside.par_chunks(nx))
            .enumerate()
            .for_each(|(j, (row, mrow))| {
                for (v, &m) in row.iter_mut().zip(mrow) {
                    if m {
                        *v = 1.0;
                    }
                }
                let at = |i: usize| Vec2::new(lo.x + h * i as f64, lo.y + h * j as f64);
                field.values_where(row, mrow, at);
            });
        Grid {
            origin: lo,
            h,
            nx,
            ny,
            values,
            inside,
        }
    }

    fn point(&self, i: usize, j: usize) -> Vec2 {
        Vec2::new(
            self.origin.x + self.h * i as f64,
            self.origin.y + self.h * j as f64,
        )
    }

    /// Largest u on the grid's border (levels above it close inside the grid).
    pub fn border_max(&self) -> f64 {
        let mut m = f64::NEG_INFINITY;
        for i in 0..self.nx {
            m = m
                .max(self.values[i])
                .max(self.values[(self.ny - 1) * self.nx + i]);
        }
        for j in 0..self.ny {
            m = m
                .max(self.values[j * self.nx])
                .max(self.values[j * self.nx + self.nx - 1]);
        }
        m
    }
}

/// The rings of {u = s} on the grid (its points are the lattice's, values only),
/// as chains of crossed edges with u ≥ s on their left.
fn trace_loops(grid: &Grid, s: f64) -> Vec<Vec<Edge>> {
    let nx = grid.nx;
    let value = |i: usize, j: usize| grid.values[j * nx + i];
    march::level(nx - 1, grid.ny - 1, value, s, Gaps::Compare).rings()
}

/// The loops of {u = s} on `grid` (values only: `origin`, `h` and `inside`
/// are not read), each a chain of the grid edges it crosses, an edge given by
/// its two end points (i, j), in the order of the loop, u ≥ s on its left.
/// For sources that place the vertices themselves (`levels::height_field`).
pub fn edge_loops(grid: &Grid, s: f64) -> Vec<Vec<[(usize, usize); 2]>> {
    trace_loops(grid, s)
        .into_iter()
        .map(|lp| lp.into_iter().map(Edge::ends).collect())
        .collect()
}

/// The closed curves {u = s} on the grid as rings, material on their left.
/// Vertices are placed on grid edges by regula falsi on u (taken as 1 inside
/// the material on edges that touch it); a loop with fewer than three distinct
/// vertices is no ring and is left out.
pub fn isolines(grid: &Grid, s: f64, field: &Field, material: &[Vec<Vec2>]) -> Vec<Ring> {
    let inside = |p: Vec2| {
        material
            .iter()
            .map(|m| polygon_winding_number(m, p))
            .sum::<i32>()
            != 0
    };
    isolines_in(grid, s, field, &inside)
}

/// As `isolines`, with the material given by a membership test (which must agree
/// with `grid.inside` at the grid points).
pub fn isolines_in(
    grid: &Grid,
    s: f64,
    field: &Field,
    inside: &(dyn Fn(Vec2) -> bool + Sync),
) -> Vec<Ring> {
    trace_loops(grid, s)
        .par_iter()
        .filter_map(|lp| {
            Ring::new(
                lp.iter()
                    .map(|&e| on_edge(grid, e, s, field, inside))
                    .collect(),
            )
        })
        .collect()
}

/// The vertex of {u = s} on the crossed edge `e`: the root of u − s there by
/// regula falsi, with u taken as 1 inside the material when the edge touches
/// it (`inside` agrees with `grid.inside` at the grid points).
fn on_edge(
    grid: &Grid,
    e: Edge,
    s: f64,
    field: &Field,
    inside: &(dyn Fn(Vec2) -> bool + Sync),
) -> Vec2 {
    let [a, b] = e.ends();
    let ((pa, fa), (pb, fb)) = edge_ends(grid, e, s);
    let (ia, ib) = (a.1 * grid.nx + a.0, b.1 * grid.nx + b.0);
    if grid.inside[ia] || grid.inside[ib] {
        let u = |p: Vec2| if inside(p) { 1.0 } else { field.value(p) };
        edge_root(pa, pb, fa, fb, s, &u)
    } else {
        edge_root(pa, pb, fa, fb, s, &|p| field.value(p))
    }
}

/// One piece of Γ(s) on a grid: a ring, or an open curve whose two ends lie
/// on the grid's border.
#[derive(Clone, Debug, PartialEq)]
pub struct Equipotential {
    /// The vertices, in order. For a ring the first vertex is not repeated.
    pub points: Vec<Vec2>,
    /// True for a ring, false for a curve that leaves the grid.
    pub closed: bool,
}

impl Equipotential {
    /// Length of the polyline (including the closing edge of a ring), mm.
    pub fn length(&self) -> f64 {
        let mut l: f64 = self.points.windows(2).map(|w| w[0].dist(w[1])).sum();
        if self.closed && self.points.len() > 1 {
            l += self.points[self.points.len() - 1].dist(self.points[0]);
        }
        l
    }
}

/// Every piece of {u = s} on the grid, rings and open curves alike, in the
/// order of `field::march` (open curves first), each vertex placed as by
/// [`isolines_in`] (`inside` as there); rings are not turned, and pieces of
/// fewer than two vertices are dropped. For drawing the levels.
pub fn pieces(
    grid: &Grid,
    s: f64,
    field: &Field,
    inside: &(dyn Fn(Vec2) -> bool + Sync),
) -> Vec<Equipotential> {
    let value = |i: usize, j: usize| grid.values[j * grid.nx + i];
    let Level { edges, curves } = march::level(grid.nx - 1, grid.ny - 1, value, s, Gaps::Compare);
    let points: Vec<Vec2> = edges
        .par_iter()
        .map(|&e| on_edge(grid, e, s, field, inside))
        .collect();
    curves
        .into_iter()
        .filter(|c| c.crossings.len() >= 2)
        .map(|c| Equipotential {
            points: c.crossings.iter().map(|&k| points[k]).collect(),
            closed: c.closed,
        })
        .collect()
}

/// The material test for closed polygons (outlines counter-clockwise,
/// counters clockwise): the sum of winding numbers is positive inside an
/// outline and outside its counters (Appendix I). Polygons are first tested
/// against their bounding boxes, which keeps sampling fast.
pub fn material_mask(polys: &[Vec<Vec2>]) -> impl Fn(Vec2) -> bool + Sync + '_ {
    let boxes: Vec<Option<(Vec2, Vec2)>> = polys
        .iter()
        .map(|poly| polygons_bbox(std::slice::from_ref(poly)))
        .collect();
    move |p: Vec2| {
        polys
            .iter()
            .zip(&boxes)
            .filter(|(_, b)| {
                b.is_some_and(|(lo, hi)| p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y)
            })
            .map(|(poly, _)| polygon_winding_number(poly, p))
            .sum::<i32>()
            > 0
    }
}

/// Root of u − s on the segment pa–pb (u − s = fa at pa, fb at pb, opposite signs).
fn edge_root(
    pa: Vec2,
    pb: Vec2,
    fa: f64,
    fb: f64,
    s: f64,
    value_at: &(dyn Fn(Vec2) -> f64 + Sync),
) -> Vec2 {
    pa.lerp(pb, root_in_unit(fa, fb, &|t| value_at(pa.lerp(pb, t)) - s))
}

/// Root of f on [0, 1], given f(0) = fa and f(1) = fb of opposite signs, by the
/// Illinois variant of regula falsi (40 steps at most, to |f| < 1e-12).
pub fn root_in_unit(fa: f64, fb: f64, f: &dyn Fn(f64) -> f64) -> f64 {
    let (mut ta, mut tb, mut fa, mut fb) = (0.0_f64, 1.0_f64, fa, fb);
    let mut side = 0;
    let mut t = 0.5;
    for _ in 0..40 {
        t = if (fb - fa).abs() > 0.0 {
            (ta * fb - tb * fa) / (fb - fa)
        } else {
            0.5 * (ta + tb)
        };
        if !(t > ta.min(tb) && t < ta.max(tb)) {
            t = 0.5 * (ta + tb);
        }
        let ft = f(t);
        if ft.abs() < 1e-12 || (tb - ta).abs() < 1e-12 {
            break;
        }
        if (ft < 0.0) == (fa < 0.0) {
            ta = t;
            fa = ft;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            tb = t;
            fb = ft;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    t
}

/// As `isolines`, with every vertex placed by linear interpolation of the grid
/// values (no field evaluations): for searches over many levels.
pub fn isolines_linear(grid: &Grid, s: f64) -> Vec<Vec<Vec2>> {
    trace_loops(grid, s)
        .into_iter()
        .map(|lp| {
            lp.iter()
                .map(|e| {
                    let ((pa, fa), (pb, fb)) = edge_ends(grid, *e, s);
                    let t = if fb != fa { fa / (fa - fb) } else { 0.5 };
                    pa.lerp(pb, t.clamp(0.0, 1.0))
                })
                .collect()
        })
        .collect()
}

fn edge_ends(grid: &Grid, e: Edge, s: f64) -> ((Vec2, f64), (Vec2, f64)) {
    let [a, b] = e.ends();
    let nx = grid.nx;
    (
        (grid.point(a.0, a.1), grid.values[a.1 * nx + a.0] - s),
        (grid.point(b.0, b.1), grid.values[b.1 * nx + b.0] - s),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_charge_equipotentials_are_circles() {
        // u = ln r (one charge of strength −2π at the origin): Γ(s) is the circle r = eˢ.
        let f = Field::new(vec![Vec2::ZERO], vec![-std::f64::consts::TAU]);
        let grid = Grid::sample(&f, Vec2::new(-3.0, -3.0), Vec2::new(3.0, 3.0), 0.1, &[]);
        for s in [-0.5, 0.0, 0.5, 1.0] {
            let loops = isolines(&grid, s, &f, &[]);
            assert_eq!(loops.len(), 1, "s = {s}");
            let r = f64::exp(s);
            let worst = loops[0]
                .points()
                .iter()
                .map(|p| (p.norm() - r).abs())
                .fold(0.0, f64::max);
            assert!(worst < 1e-9, "s = {s}: radius error {worst:e}");
            // u grows outward, so the high side (left) is outside: clockwise.
            assert!(loops[0].signed_area() < 0.0);
            // A vertex on every crossed grid edge: about 4·2r/h of them.
            assert!(loops[0].len() as f64 > 6.0 * r / 0.1);
        }
    }

    #[test]
    fn material_is_pinned_to_one_and_loops_enclose_it() {
        // A square of material with u = distance-like field around it: use the
        // charge at the square's centre with u = 1 − 0.2·ln(r/0.5): the material
        // square [-0.5, 0.5]² is masked; level 0.9 is the circle r = 0.5·e^0.5.
        let f = Field::new(vec![Vec2::ZERO], vec![0.2 * std::f64::consts::TAU]);
        // u = −0.2 ln r = 1 − 0.2 ln(r/ r0) with r0 = e^{-5}: shift by choosing s.
        let sq = vec![
            Vec2::new(-0.5, -0.5),
            Vec2::new(0.5, -0.5),
            Vec2::new(0.5, 0.5),
            Vec2::new(-0.5, 0.5),
        ];
        let grid = Grid::sample(
            &f,
            Vec2::new(-3.0, -3.0),
            Vec2::new(3.0, 3.0),
            0.05,
            std::slice::from_ref(&sq),
        );
        assert!(grid.inside[grid.nx * (grid.ny / 2) + grid.nx / 2]);
        let s = -0.2 * 1.5f64.ln();
        let loops = isolines(&grid, s, &f, std::slice::from_ref(&sq));
        assert_eq!(loops.len(), 1);
        // u decreases outward: high side inside, loop counter-clockwise around the material.
        assert!(loops[0].signed_area() > 0.0);
        let worst = loops[0]
            .points()
            .iter()
            .map(|p| (p.norm() - 1.5).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "radius error {worst:e}");
    }

    #[test]
    fn pieces_leaving_the_grid_are_open_and_on_their_level() {
        // The circle r = eˢ about a charge near the grid's right edge: the part
        // of it inside the grid is one open piece, both ends on the border.
        let f = Field::new(vec![Vec2::new(2.5, 0.0)], vec![-std::f64::consts::TAU]);
        let grid = Grid::try_sample(&f, Vec2::new(-3.0, -3.0), Vec2::new(3.0, 3.0), 0.1, &[])
            .expect("grid");
        let s = 1.0f64.ln();
        let ps = pieces(&grid, s, &f, &|_| false);
        assert_eq!(ps.len(), 1);
        assert!(!ps[0].closed);
        for p in &ps[0].points {
            assert!((f.value(*p) - s).abs() < 1e-12, "{p:?}");
        }
        let hi_x = grid.origin.x + grid.h * (grid.nx - 1) as f64;
        for end in [ps[0].points[0], ps[0].points[ps[0].points.len() - 1]] {
            assert!((end.x - hi_x).abs() < 1e-9, "{end:?}");
        }
        // The closed circle of a charge in the middle is one ring, as from isolines.
        let g0 = Grid::sample(&f, Vec2::new(-1.0, -3.0), Vec2::new(6.0, 3.0), 0.1, &[]);
        let ring = pieces(&g0, s, &f, &|_| false);
        assert_eq!(ring.len(), 1);
        assert!(ring[0].closed);
        let l = ring[0].length();
        assert!(
            l < std::f64::consts::TAU && l > 0.999 * std::f64::consts::TAU,
            "{l}"
        );
    }

    #[test]
    fn bad_grids_are_errors() {
        let f = Field::new(vec![Vec2::ZERO], vec![1.0]);
        let cases = [
            (Vec2::ZERO, Vec2::new(1.0, 1.0), 0.0),
            (Vec2::ZERO, Vec2::new(1.0, 1.0), f64::NAN),
            (Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), 0.1),
            (Vec2::ZERO, Vec2::new(1e6, 1e6), 1e-3),
        ];
        let want = [
            ContourError::CellSize { h: 0.0 },
            ContourError::CellSize { h: f64::NAN },
            ContourError::EmptyRect,
            ContourError::TooManyCells { nx: 1e9, ny: 1e9 },
        ];
        for ((lo, hi, h), want) in cases.into_iter().zip(want) {
            let got = Grid::try_sample(&f, lo, hi, h, &[])
                .map(|_| ())
                .unwrap_err();
            // NaN is not equal to itself: compare the texts.
            assert_eq!(got.to_string(), want.to_string(), "{lo:?} {hi:?} {h}");
        }
    }

    /// The texts are the ones the causes had as strings (issue 16).
    #[test]
    fn grid_errors_say_the_strings_they_replace() {
        let (h, nx, ny) = (-0.25, 4001.0, 4000.0);
        let cases = [
            (ContourError::CellSize { h }, format!("cell size must be a positive number, got {h}")),
            (ContourError::EmptyRect, "the rectangle is empty (hi must exceed lo in x and y)".to_string()),
            (
                ContourError::TooManyCells { nx, ny },
                format!("{nx} × {ny} cells are too many (at most {MAX_GRID_POINTS} points); use a larger cell"),
            ),
        ];
        for (e, text) in cases {
            assert_eq!(e.to_string(), format!("equipotential grid: {text}"));
        }
    }

    #[test]
    fn the_material_mask_is_inside_outlines_and_outside_counters() {
        let square = |r: f64| {
            vec![
                Vec2::new(-r, -r),
                Vec2::new(r, -r),
                Vec2::new(r, r),
                Vec2::new(-r, r),
            ]
        };
        let counter: Vec<Vec2> = square(1.0).into_iter().rev().collect();
        let polys = vec![square(2.0), counter];
        let m = material_mask(&polys);
        assert!(m(Vec2::new(1.5, 0.0)) && !m(Vec2::ZERO) && !m(Vec2::new(3.0, 0.0)));
    }
}
