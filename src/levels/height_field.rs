//! A height field over a rectangle as a [`Sections`] source: the harmonic
//! patch of a job (`shape.kind = "harmonic-bezier"`) or a polyharmonic
//! solid's top envelope (`shape.kind = "polyharmonic"`), milled from above.
//! The field is any [`Height`]: h and ∇h in the rectangle's own coordinates.
//!
//! The part is {(x, y, z): (x, y) in the rectangle, z ≤ h(x, y)}; its top
//! (z = 0, relative) is max h, its bottom (z = −depth) min h. The section at
//! z is {h ≥ max h + z} over the rectangle: closed polygons, material on the
//! left, the rectangle's border closing them where h ≥ z at the edge.
//!
//! How: h is sampled once on a grid over exactly the rectangle (spacing at
//! most [`SPACING`], its border points on the border), ringed by one row of
//! points outside it that count as below every level. Marching squares on
//! that ring-padded grid (`field::isolines::edge_loops`) gives each loop as a
//! chain of crossed edges; a vertex on an edge between two points of the
//! rectangle is the root of h − level on it (regula falsi to 1e-12 mm), and
//! one on an edge to the ring is the border point itself, so loops run along
//! the border exactly. Chords off the border are then refined: a chord's
//! midpoint is projected onto {h = level} by Newton along ∇h and inserted
//! while it lies more than `CHORD_FRACTION` × tolerance from the chord (as
//! `field::level::refine` does for Γ(s)).

use super::plan::CHORD_FRACTION;
use super::sections::{LevelField, Sections};
use crate::field::isolines::{edge_loops, root_in_unit, Grid};
use crate::geometry::polygon_area;
use crate::geometry::Vec2;
use crate::sources::harmonic_bezier::{HarmonicError, HarmonicPatch, HeightRange, PatchSpec};

/// A height field over a rectangle, (x, y) from its lower-left corner, mm.
pub(crate) trait Height: Send + Sync {
    /// h(x, y), mm.
    fn height(&self, x: f64, y: f64) -> f64;
    /// ∇h = (∂h/∂x, ∂h/∂y) at (x, y).
    fn gradient(&self, x: f64, y: f64) -> [f64; 2];
    /// ∇h at (x, y) where h(x, y) = `h` is already known (a field that finds
    /// h by a search may skip it).
    fn gradient_at(&self, x: f64, y: f64, _h: f64) -> [f64; 2] {
        self.gradient(x, y)
    }
}

impl Height for crate::sources::polyharmonic::Relief {
    fn height(&self, x: f64, y: f64) -> f64 {
        crate::sources::polyharmonic::Relief::height(self, x, y)
    }
    fn gradient(&self, x: f64, y: f64) -> [f64; 2] {
        crate::sources::polyharmonic::Relief::gradient(self, x, y)
    }
    fn gradient_at(&self, x: f64, y: f64, h: f64) -> [f64; 2] {
        crate::sources::polyharmonic::Relief::gradient_at(self, x, y, h)
    }
}

impl Height for HarmonicPatch {
    fn height(&self, x: f64, y: f64) -> f64 {
        HarmonicPatch::height(self, x, y)
    }
    fn gradient(&self, x: f64, y: f64) -> [f64; 2] {
        HarmonicPatch::gradient(self, x, y)
    }
}

/// Largest grid spacing, mm: a component of a section narrower than about
/// this is not seen (h is a polynomial of low degree, so its level sets have
/// few components, each born at the border where h has a local maximum
/// along it).
pub(crate) const SPACING: f64 = 0.2;

/// Most grid points sampled (the spacing grows past [`SPACING`] for
/// rectangles larger than 400 × 400 mm to stay within it).
pub(crate) const MAX_POINTS: usize = 4_000_000;

/// Halvings of a chord at most in the refinement.
const REFINE_DEPTH: usize = 4;

/// A height field's sections (module doc).
pub(crate) struct HeightFieldSections {
    field: Box<dyn Height>,
    origin: Vec2,
    size: [f64; 2],
    /// max h and min h, mm (patch heights).
    top: f64,
    bottom: f64,
    /// Where h is largest, job coordinates (the section at the very top).
    argmax: Vec2,
    /// Points of the grid in x and y, and their spacings, mm.
    nx: usize,
    ny: usize,
    hx: f64,
    hy: f64,
    /// h at (i, j), `values[j * nx + i]`.
    values: Vec<f64>,
    /// Chords stay within this of the level curve, mm.
    chord_tol: f64,
}

impl HeightFieldSections {
    /// The sections of `spec`'s patch, chords within `CHORD_FRACTION` ×
    /// `tol` (mm) of the level curves. Errors only for a spec that does not
    /// build a patch.
    pub(crate) fn new(spec: &PatchSpec, tol: f64) -> Result<HeightFieldSections, HarmonicError> {
        let patch = spec.patch()?;
        let range = patch.height_range();
        Ok(Self::of_height(
            Box::new(patch),
            spec.origin,
            spec.size,
            range,
            tol,
        ))
    }

    /// The sections of any height field over the rectangle `origin`, `size`
    /// whose max and min heights (and where the max is, relative to the
    /// origin) are `range`; chords within `CHORD_FRACTION` × `tol` (mm).
    pub(crate) fn of_height(
        field: Box<dyn Height>,
        origin: Vec2,
        size: [f64; 2],
        range: HeightRange,
        tol: f64,
    ) -> HeightFieldSections {
        let [sx, sy] = size;
        let spacing = SPACING.max((sx * sy / MAX_POINTS as f64).sqrt());
        let nx = ((sx / spacing).ceil() as usize).max(1) + 1;
        let ny = ((sy / spacing).ceil() as usize).max(1) + 1;
        let (hx, hy) = (sx / (nx - 1) as f64, sy / (ny - 1) as f64);
        use rayon::prelude::*;
        let values: Vec<f64> = (0..nx * ny)
            .into_par_iter()
            .map(|k| field.height((k % nx) as f64 * hx, (k / nx) as f64 * hy))
            .collect();
        HeightFieldSections {
            origin,
            size,
            top: range.max,
            bottom: range.min,
            argmax: origin + Vec2::new(range.argmax[0], range.argmax[1]),
            nx,
            ny,
            hx,
            hy,
            values,
            chord_tol: CHORD_FRACTION * tol,
            field,
        }
    }

    /// h at a point in job coordinates, mm (patch heights).
    pub(crate) fn height(&self, p: Vec2) -> f64 {
        self.field.height(p.x - self.origin.x, p.y - self.origin.y)
    }

    /// max h, mm: the part's top, placed at the stock top.
    pub(crate) fn top_height(&self) -> f64 {
        self.top
    }

    /// The rectangle's lower-left corner and its size (job coordinates, mm).
    pub(crate) fn rectangle_box(&self) -> (Vec2, Vec2) {
        (self.origin, Vec2::new(self.size[0], self.size[1]))
    }

    /// The largest |∂h/∂y| on the sampling grid (central differences of the
    /// exact gradient are not needed: ∇h is evaluated at every grid point).
    pub(crate) fn max_slope_y(&self) -> f64 {
        use rayon::prelude::*;
        (0..self.nx * self.ny)
            .into_par_iter()
            .map(|k| {
                let (x, y) = (
                    (k % self.nx) as f64 * self.hx,
                    (k / self.nx) as f64 * self.hy,
                );
                self.field.gradient_at(x, y, self.values[k])[1].abs()
            })
            .reduce(|| 0.0, f64::max)
    }

    /// Grid point (i, j) in job coordinates.
    fn point(&self, i: usize, j: usize) -> Vec2 {
        self.origin + Vec2::new(i as f64 * self.hx, j as f64 * self.hy)
    }

    /// The rectangle, counter-clockwise.
    fn rectangle(&self) -> Vec<Vec2> {
        crate::geometry::rectangle(self.origin, self.size)
    }

    /// The grid ringed by one row of points below every level (−∞).
    fn padded(&self) -> Grid {
        let (px, py) = (self.nx + 2, self.ny + 2);
        let mut values = vec![f64::NEG_INFINITY; px * py];
        for j in 0..self.ny {
            let row = &self.values[j * self.nx..(j + 1) * self.nx];
            values[(j + 1) * px + 1..(j + 1) * px + 1 + self.nx].copy_from_slice(row);
        }
        Grid {
            origin: self.origin,
            h: self.hx,
            nx: px,
            ny: py,
            inside: vec![false; values.len()],
            values,
        }
    }

    /// The vertex of the loop at `level` on the padded grid's edge `e`.
    fn vertex(&self, e: [(usize, usize); 2], level: f64) -> Vec2 {
        let real = |(i, j): (usize, usize)| {
            (i >= 1 && j >= 1 && i <= self.nx && j <= self.ny).then(|| (i - 1, j - 1))
        };
        match (real(e[0]), real(e[1])) {
            (Some(a), Some(b)) => {
                let (pa, pb) = (self.point(a.0, a.1), self.point(b.0, b.1));
                let fa = self.values[a.1 * self.nx + a.0] - level;
                let fb = self.values[b.1 * self.nx + b.0] - level;
                let t = root_in_unit(fa, fb, &|t| self.height(pa.lerp(pb, t)) - level);
                pa.lerp(pb, t)
            }
            (Some(a), None) | (None, Some(a)) => self.point(a.0, a.1),
            // Two ring points are both below every level: never crossed.
            (None, None) => self.origin,
        }
    }

    /// Which sides of the rectangle `p` lies on (bits: bottom, right, top,
    /// left), to 1e-9 mm.
    fn sides(&self, p: Vec2) -> u8 {
        let q = p - self.origin;
        let on = |a: f64, b: f64| (a - b).abs() <= 1e-9;
        u8::from(on(q.y, 0.0))
            | u8::from(on(q.x, self.size[0])) << 1
            | u8::from(on(q.y, self.size[1])) << 2
            | u8::from(on(q.x, 0.0)) << 3
    }

    /// Newton along ∇h from `p` onto {h = level} (a few steps); `None` if it
    /// leaves the rectangle or wanders farther than `limit`.
    fn project(&self, p: Vec2, level: f64, limit: f64) -> Option<Vec2> {
        let mut q = p;
        for _ in 0..8 {
            let r = q - self.origin;
            let g = self.field.gradient(r.x, r.y);
            let g2 = g[0] * g[0] + g[1] * g[1];
            if g2 == 0.0 || !g2.is_finite() {
                return None;
            }
            let f = self.height(q) - level;
            let step = Vec2::new(g[0], g[1]) * (f / g2);
            q -= step;
            if step.norm() < 1e-12 {
                break;
            }
        }
        let r = q - self.origin;
        let inside = r.x >= 0.0 && r.y >= 0.0 && r.x <= self.size[0] && r.y <= self.size[1];
        (inside && q.dist(p) <= limit).then_some(q)
    }

    /// The loop with its chords refined, collinear border points dropped.
    fn refine(&self, lp: &[Vec2], level: f64) -> Vec<Vec2> {
        let n = lp.len();
        let mut out = Vec::with_capacity(2 * n);
        for k in 0..n {
            let (a, b) = (lp[k], lp[(k + 1) % n]);
            out.push(a);
            if self.sides(a) & self.sides(b) == 0 {
                self.refine_chord(a, b, level, REFINE_DEPTH, &mut out);
            }
        }
        drop_collinear_border(&out, |p| self.sides(p))
    }

    fn refine_chord(&self, a: Vec2, b: Vec2, level: f64, depth: usize, out: &mut Vec<Vec2>) {
        if depth == 0 {
            return;
        }
        let m = a.lerp(b, 0.5);
        if let Some(q) = self.project(m, level, a.dist(b)) {
            if q.dist(m) > self.chord_tol {
                self.refine_chord(a, q, level, depth - 1, out);
                out.push(q);
                self.refine_chord(q, b, level, depth - 1, out);
            }
        }
    }

    /// The section at patch height `level`, mm.
    pub(crate) fn section_at_height(&self, level: f64) -> Vec<Vec<Vec2>> {
        if level <= self.bottom {
            return vec![self.rectangle()];
        }
        let grid = self.padded();
        let min_area = self.hx * self.hy;
        let loops: Vec<Vec<Vec2>> = edge_loops(&grid, level)
            .into_iter()
            .map(|lp| {
                let mut pts: Vec<Vec2> = lp.iter().map(|&e| self.vertex(e, level)).collect();
                pts.dedup_by(|a, b| a.dist(*b) <= 1e-12);
                while pts.len() > 1 && pts[0].dist(pts[pts.len() - 1]) <= 1e-12 {
                    pts.pop();
                }
                pts
            })
            .filter(|p| p.len() >= 3 && polygon_area(p).abs() > min_area)
            .map(|p| self.refine(&p, level))
            .collect();
        if loops.is_empty() && level <= self.top + 1e-9 {
            // Narrower than the grid: the section is the point of the maximum.
            return vec![vec![self.argmax]];
        }
        loops
    }
}

/// `poly` without the vertices that lie on one side of the rectangle
/// together with both their neighbours (the border's own grid points).
fn drop_collinear_border(poly: &[Vec2], sides: impl Fn(Vec2) -> u8) -> Vec<Vec2> {
    let n = poly.len();
    if n < 4 {
        return poly.to_vec();
    }
    let s: Vec<u8> = poly.iter().map(|&p| sides(p)).collect();
    (0..n)
        .filter(|&k| {
            let shared = s[(k + n - 1) % n] & s[k] & s[(k + 1) % n];
            // A corner of the rectangle lies on two sides: keep it.
            shared == 0 || s[k].count_ones() > 1
        })
        .map(|k| poly[k])
        .collect()
}

impl Sections for HeightFieldSections {
    fn z_range(&self) -> (f64, f64) {
        (self.bottom - self.top, 0.0)
    }

    fn section(&self, z: f64) -> Vec<Vec<Vec2>> {
        self.section_at_height(self.top + z)
    }

    /// The level's height as a fraction of the part's: (h − min h) / (max h
    /// − min h) at h = max h + z, 1 at the top and 0 at the bottom, as s
    /// runs for the MFS.
    fn level_value(&self, z: f64) -> f64 {
        ((self.top + z - self.bottom) / (self.top - self.bottom)).clamp(0.0, 1.0)
    }

    /// No field of its own: the planner solves the level's MFS problem on
    /// the section.
    fn level_field(&self, _z: f64) -> Option<LevelField> {
        None
    }
}
