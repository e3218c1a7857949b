//! The modelled part S2 = {(x, y) ∈ Γ(s), z = φ(s)} (the paper's Section 7) as a
//! closed triangle mesh, written as binary STL (`pfcam surface`).
//!
//! The top of the part is the height field z(x, y) = φ(clamp(u(x, y), s_bottom,
//! s_top)) of the shape's field u (for a cavity, the mould, mirrored: z = −depth −
//! φ(u), relative to the stock top). It is triangulated as *isobands* on a grid
//! over the stock rectangle:
//!
//! - u is sampled at the grid points, with the material pinned to u = 1 as in
//!   `field::isolines` (the MFS sum is meaningless there).
//! - The levels are a fine set of s values from s_bottom to s_top (z steps of at
//!   most [`LEVEL_DZ`], s steps of at most 1/[`LEVEL_DS_DIVISIONS`] of the range),
//!   so s_top and s_bottom, where the wall meets the flat top and the floor, are
//!   levels and the mesh has creases exactly on Γ(s_top) and Γ(s_bottom).
//! - Every grid edge whose end values straddle a level gets one vertex per level,
//!   placed by regula falsi on u along the edge (as `field::isolines` places its
//!   vertices) and kept at least [`T_MIN`] of the edge from its ends and from each
//!   other, in level order. A vertex depends only on its edge, and is keyed by
//!   (edge, level), so the two cells sharing an edge share its vertices exactly.
//! - In every cell, each level's crossings are joined by chords (marching
//!   squares, saddles decided by the cell's mean value like `isolines`). Chords of
//!   different levels never cross, so they cut the square into convex pieces, one
//!   per band; each is triangulated without zero-area triangles.
//! - The solid is closed by four vertical side walls from the top surface's
//!   boundary down to the stock bottom ([`BASE_THICKNESS`] below the deepest cut)
//!   and a flat bottom.
//!
//! The mesh is indexed; [`edge_use_counts`] and [`is_watertight`] check it, and the
//! same checks run on the written file after welding its float vertices
//! ([`read_stl`], [`weld`]).

use crate::field::Field;
use crate::geometry::{polygon_winding_number, Vec2};
use crate::job::{Job, OperationKind};
use crate::levels::plan::GRID_SPACING;
use crate::levels::DepthProfile;
use crate::output::{check_target, OutputError};
use crate::pipeline::{self, PipelineError, Progress, FLATTEN_FRACTION};
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::Path;

/// Stock below the deepest cut, mm: the STL's bottom is at stock.top − depth − this.
pub const BASE_THICKNESS: f64 = 2.0;

/// Default grid spacing, mm: the level planner's grid (`levels::plan::GRID_SPACING`).
pub const DEFAULT_RESOLUTION: f64 = GRID_SPACING;

/// Largest z step between neighbouring levels of the isobands, mm.
pub(crate) const LEVEL_DZ: f64 = 0.1;

/// The levels are at most (s_top − s_bottom)/this apart in s (where φ is flat).
pub(crate) const LEVEL_DS_DIVISIONS: usize = 16;

/// No crossing vertex lies closer than this fraction of its grid edge to the
/// edge's ends or to another crossing on the same edge (so no triangle has zero
/// area, also after rounding to the STL's 32-bit floats).
pub const T_MIN: f64 = 1e-3;

/// Grid points in the material are u = 1; all others are kept just below 1, so
/// that a level at s = 1 (a linear profile's top) is the material's outline.
const ONE_BELOW: f64 = 1.0 - 1e-12;

/// Largest grid the command accepts (points).
pub(crate) const MAX_GRID_POINTS: usize = 40_000_000;

/// Options of `pfcam surface`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceOptions {
    /// Grid spacing, mm.
    pub resolution: f64,
}

impl Default for SurfaceOptions {
    fn default() -> Self {
        SurfaceOptions {
            resolution: DEFAULT_RESOLUTION,
        }
    }
}

/// What can go wrong building a surface.
#[derive(Debug, thiserror::Error)]
pub enum SurfaceError {
    /// The shape or its field.
    #[error(transparent)]
    Pipeline(#[from] PipelineError),
    /// A profile job: it has no modelled surface.
    #[error("surface: {}", PROFILE_MESSAGE)]
    ProfileJob,
    /// A boss or cavity job without its `[profile]` (the job's checks
    /// require one).
    #[error("surface: a boss or cavity needs a [profile]")]
    NoProfile,
    /// The shape has no contour.
    #[error("surface: the shape is empty: nothing to model")]
    EmptyShape,
    /// The profile's lowest level, found as the run's planner finds it.
    #[error("surface: {0}")]
    Plan(#[from] crate::levels::plan::PlanError),
    /// The profile's lowest level has no contour around the shape.
    #[error("surface: the level s = {s} has no contour around the shape")]
    NoBaseContour {
        /// The level's field value.
        s: f64,
    },
    /// The grid spacing is not a positive number of mm.
    #[error("surface: the resolution must be a positive number of mm, got {0}")]
    Resolution(f64),
    /// The grid over the stock would have more than [`MAX_GRID_POINTS`] points.
    #[error("surface: a {resolution} mm grid over the {width:.1} × {height:.1} mm stock has more than {MAX_GRID_POINTS} points; choose a coarser --resolution")]
    GridTooLarge {
        /// The grid spacing asked for, mm.
        resolution: f64,
        /// The stock's width, mm.
        width: f64,
        /// The stock's height (y extent), mm.
        height: f64,
    },
    /// More vertices than one mesh's indices can hold.
    #[error("surface: too many vertices for one mesh; choose a coarser --resolution")]
    TooManyVertices,
    /// A polyharmonic source's closed mesh could not be built.
    #[error("surface: {0}")]
    Poly(#[from] crate::sources::polyharmonic::PolyError),
}

/// An indexed triangle mesh, mm. Triangles are counter-clockwise seen from
/// outside (the right-hand normal points out of the solid).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as vertex indices.
    pub triangles: Vec<[u32; 3]>,
}

fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm3(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// (c₁ − c₀) × (c₂ − c₀): the triangle's normal, twice its area long.
pub(crate) fn triangle_normal(c: &[[f64; 3]; 3]) -> [f64; 3] {
    cross3(sub3(c[1], c[0]), sub3(c[2], c[0]))
}

/// The triangle's area, mm².
pub(crate) fn triangle_area(c: &[[f64; 3]; 3]) -> f64 {
    0.5 * norm3(triangle_normal(c))
}

impl Mesh {
    /// The three corners of triangle `t`.
    pub fn corners(&self, t: usize) -> [[f64; 3]; 3] {
        let [a, b, c] = self.triangles[t];
        [
            self.vertices[a as usize],
            self.vertices[b as usize],
            self.vertices[c as usize],
        ]
    }

    /// The corners of every triangle that faces up ([`up_area`] > 1e-12):
    /// what a cutter lowered from above can touch, for the drop-cutter.
    pub(crate) fn up_triangles(&self) -> Vec<[[f64; 3]; 3]> {
        (0..self.triangles.len())
            .map(|t| self.corners(t))
            .filter(|c| up_area(c) > 1e-12)
            .collect()
    }

    /// Area of triangle `t`, mm².
    pub fn area(&self, t: usize) -> f64 {
        triangle_area(&self.corners(t))
    }

    /// Enclosed volume, mm³ (divergence theorem; positive for outward normals).
    pub fn volume(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                let n = cross3(b, c);
                (a[0] * n[0] + a[1] * n[1] + a[2] * n[2]) / 6.0
            })
            .sum()
    }

    /// Smallest and largest coordinates of the vertices.
    pub fn bbox(&self) -> Option<([f64; 3], [f64; 3])> {
        let first = *self.vertices.first()?;
        Some(self.vertices.iter().fold((first, first), |(lo, hi), v| {
            (
                [lo[0].min(v[0]), lo[1].min(v[1]), lo[2].min(v[2])],
                [hi[0].max(v[0]), hi[1].max(v[1]), hi[2].max(v[2])],
            )
        }))
    }

    /// Triangles with a repeated vertex index or zero area.
    pub fn degenerate_triangles(&self) -> usize {
        (0..self.triangles.len())
            .filter(|&t| {
                let [a, b, c] = self.triangles[t];
                a == b || b == c || a == c || self.area(t) <= 0.0
            })
            .count()
    }

    /// Ok if the mesh is closed and consistently oriented (see [`is_watertight`])
    /// with no degenerate triangle; otherwise what is wrong, in words.
    pub fn check(&self) -> Result<(), String> {
        let counts = edge_use_counts(&self.triangles);
        let mut open = 0;
        let mut doubled = 0;
        for (&(a, b), &n) in &counts {
            if n > 1 {
                doubled += 1;
            }
            if counts.get(&(b, a)).copied().unwrap_or(0) != 1 {
                open += 1;
            }
        }
        let degenerate = self.degenerate_triangles();
        if open + doubled + degenerate > 0 {
            return Err(format!(
                "{open} directed edge(s) without exactly one opposite, {doubled} used more than once, {degenerate} degenerate triangle(s)"
            ));
        }
        Ok(())
    }
}

/// How many triangles use each directed edge (a, b) (a triangle [a, b, c] uses
/// a→b, b→c and c→a).
pub fn edge_use_counts(triangles: &[[u32; 3]]) -> HashMap<(u32, u32), u32> {
    let mut m: HashMap<(u32, u32), u32> = HashMap::with_capacity(triangles.len() * 3);
    for t in triangles {
        for k in 0..3 {
            *m.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    m
}

/// Closed and consistently oriented: every directed edge is used by exactly one
/// triangle and its opposite by exactly one other, so every undirected edge is
/// shared by exactly two triangles that traverse it in opposite directions.
pub fn is_watertight(triangles: &[[u32; 3]]) -> bool {
    let m = edge_use_counts(triangles);
    !triangles.is_empty()
        && m.iter()
            .all(|(&(a, b), &n)| n == 1 && m.get(&(b, a)).copied() == Some(1))
}

/// The part's inputs: the shape's field and outline, φ(s) and the stock.
pub struct SurfaceJob<'a> {
    /// The shape's field (u = 1 on the glyphs).
    pub field: &'a Field,
    /// The glyphs, flattened, material on the left.
    pub glyphs: &'a [Vec<Vec2>],
    /// φ(s).
    pub profile: &'a DepthProfile,
    /// True for a cavity (the mould), false for a boss.
    pub cavity: bool,
    /// Stock top, mm.
    pub top: f64,
    /// Stock margin around the part's largest level, mm.
    pub margin: f64,
    /// The job's tolerance, mm (for the stock rectangle's contour, as the planner).
    pub tol: f64,
    /// The stock rectangle when the caller has it (the level planner's,
    /// `LevelParams::stock_lo`/`stock_hi`), else `None`: [`stock_rectangle`]
    /// computes the same rectangle.
    pub stock: Option<(Vec2, Vec2)>,
}

/// z (absolute, mm) of S2 where u = `s`, with the stock top at `top`: a
/// boss's top + φ(s), a cavity's top − depth − φ(s) (φ clamps s to its
/// range).
pub(crate) fn surface_z(profile: &DepthProfile, cavity: bool, top: f64, s: f64) -> f64 {
    let phi = profile.z(s);
    if cavity {
        top - profile.depth() - phi
    } else {
        top + phi
    }
}

impl SurfaceJob<'_> {
    /// z (absolute, mm) of the surface where u = s: boss top + φ(s), cavity
    /// top − depth − φ(s) (φ clamps s to its range).
    pub(crate) fn z_of(&self, s: f64) -> f64 {
        surface_z(self.profile, self.cavity, self.top, s)
    }

    /// z of the stock bottom: the deepest cut minus [`BASE_THICKNESS`].
    pub(crate) fn z_bottom(&self) -> f64 {
        self.top - self.profile.depth() - BASE_THICKNESS
    }
}

/// Twice the signed XY area of a triangle: positive when its corners run
/// counter-clockwise seen from above, i.e. its normal points up.
pub(crate) fn up_area(c: &[[f64; 3]; 3]) -> f64 {
    (c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1])
}

/// The mesh with what it was built from.
#[derive(Clone, Debug)]
pub struct Surface {
    /// The closed mesh.
    pub mesh: Mesh,
    /// The stock rectangle (as `pfcam run` computes it), mm.
    pub stock_lo: Vec2,
    /// Upper-right corner of the stock rectangle, mm.
    pub stock_hi: Vec2,
    /// z of the STL's bottom face, mm.
    pub z_bottom: f64,
    /// The levels s of the isobands, increasing.
    pub levels: Vec<f64>,
    /// Every vertex placed on a level: (vertex, index into `levels`).
    pub crossings: Vec<(u32, usize)>,
    /// Grid points in x and y.
    pub grid: (usize, usize),
}

/// A job's surface with the shape's field it was built from.
#[derive(Clone, Debug)]
pub struct JobSurface {
    /// The surface.
    pub surface: Surface,
    /// The shape's field.
    pub field: Field,
    /// The glyphs, flattened as for `pfcam run`.
    pub glyphs: Vec<Vec<Vec2>>,
}

/// The message for a profile job, which has no modelled surface.
pub(crate) const PROFILE_MESSAGE: &str =
    "operation.kind = \"profile\" has no modelled surface; use a boss or cavity job";

/// The surface of a boss or cavity job: the shape and its field exactly as
/// `pfcam run` builds them (`pipeline::job_shape`, `pipeline::solve_sections`), the
/// stock as the level planner computes it, then [`build`].
pub fn job_surface(
    job: &Job,
    opts: &SurfaceOptions,
    progress: &mut dyn FnMut(Progress),
) -> Result<JobSurface, SurfaceError> {
    if job.operation.kind == OperationKind::Profile {
        return Err(SurfaceError::ProfileJob);
    }
    let profile = job.profile.as_ref().ok_or(SurfaceError::NoProfile)?;
    let (shape, _) = pipeline::job_shape(job, progress)?;
    let flat_tol = job.operation.tolerance * FLATTEN_FRACTION;
    // As `pfcam run` decides it: a field that misses its target is refused
    // only when its error would move the surface past tolerance/10.
    let (sections, _, _, _) = pipeline::solve_sections(&shape, job, profile, flat_tol, progress)?;
    let glyphs: Vec<Vec<Vec2>> = shape.contours().map(|c| c.flatten(flat_tol)).collect();
    let field = sections.field().clone();
    let sj = SurfaceJob {
        field: &field,
        glyphs: &glyphs,
        profile,
        cavity: job.operation.kind == OperationKind::Cavity,
        top: job.stock.top,
        margin: job.stock.margin,
        tol: job.operation.tolerance,
        stock: None,
    };
    let surface = build(&sj, opts, progress)?;
    Ok(JobSurface {
        surface,
        field,
        glyphs,
    })
}

/// The part of any boss or cavity job as a closed mesh at `opts.resolution`:
/// a closed polyharmonic solid itself (`patch::closed::closed_surface`), a
/// height field's block (`patch::patch_surface`), a PDE tube's part
/// (`tube::tube_surface`), else [`job_surface`]'s.
pub fn job_part_surface(
    job: &Job,
    opts: &SurfaceOptions,
    progress: &mut dyn FnMut(Progress),
) -> Result<Surface, SurfaceError> {
    if let crate::geometry::ShapeSource::Polyharmonic(spec) = &job.shape {
        if let Some(s) = crate::patch::closed::closed_surface(job, spec, opts.resolution) {
            return s;
        }
    }
    if let Some(spec) = job.shape.height_source() {
        return Ok(crate::patch::patch_surface(job, spec, opts.resolution)?);
    }
    if let crate::geometry::ShapeSource::PdeTube(spec) = &job.shape {
        return Ok(crate::tube::tube_surface(job, spec, opts.resolution)?);
    }
    Ok(job_surface(job, opts, progress)?.surface)
}

/// The levels s of the isobands: from s_bottom to s_top, neighbours at most
/// [`LEVEL_DZ`] apart in z and (s_top − s_bottom)/[`LEVEL_DS_DIVISIONS`] in s.
pub(crate) fn level_values(profile: &DepthProfile) -> Vec<f64> {
    let (lo, hi) = profile.s_range();
    let ds = (hi - lo) / LEVEL_DS_DIVISIONS as f64;
    let mut out = vec![lo];
    let mut s = lo;
    for _ in 0..100_000 {
        let next = (s + ds).min(profile.s_at(profile.z(s) + LEVEL_DZ));
        if next >= hi - 1e-6 * (hi - lo) {
            break;
        }
        s = next.max(s + 1e-9);
        out.push(s);
    }
    out.push(hi);
    out
}

/// Which cell sides a point lies on (bits 0–3: bottom, right, top, left; for the
/// stock rectangle: front, right, back, left).
type Sides = u8;
const CORNER_SIDES: [Sides; 4] = [0b1001, 0b0011, 0b0110, 0b1100];

/// Triangulate a convex polygon whose vertices all lie on the sides of a
/// rectangle (`sides` says which), in the polygon's own orientation, with no
/// zero-area triangle. Three vertices are collinear exactly when they share a
/// side, so this is decided from the side bits, never from rounded coordinates.
/// Ear clipping: while some vertex is off a side holding all the others, fan
/// from it; otherwise cut off any vertex whose neighbours do not share a side
/// with it (the rest is still convex and not flat).
fn triangulate_convex(poly: &[(u32, Sides)], out: &mut Vec<[u32; 3]>) {
    let mut v: Vec<(u32, Sides)> = poly.to_vec();
    let mut start = 0;
    while v.len() >= 3 {
        let n = v.len();
        // Fan case: n − 1 vertices on one side.
        let mut apex = None;
        for bit in 0..4 {
            let on = v.iter().filter(|p| p.1 & (1 << bit) != 0).count();
            if on + 1 == n {
                apex = (0..n).find(|&i| v[i].1 & (1 << bit) == 0);
                break;
            }
        }
        if let Some(a) = apex {
            for k in 1..n - 1 {
                out.push([v[a].0, v[(a + k) % n].0, v[(a + k + 1) % n].0]);
            }
            return;
        }
        if n == 3 {
            out.push([v[0].0, v[1].0, v[2].0]);
            return;
        }
        let Some(i) = (0..n)
            .map(|k| (start + k) % n)
            .find(|&i| v[(i + n - 1) % n].1 & v[i].1 & v[(i + 1) % n].1 == 0)
        else {
            // Flat: nothing to triangulate (cannot happen for a piece of a cell).
            return;
        };
        out.push([v[(i + n - 1) % n].0, v[i].0, v[(i + 1) % n].0]);
        v.remove(i);
        start = i % v.len();
    }
}

/// The material along one grid edge: its winding number at the edge's start and
/// where (parameter t) the edge crosses the glyphs' outlines.
struct EdgeMask {
    w0: i32,
    cuts: Vec<(f64, i32)>,
}

impl EdgeMask {
    fn new(a: Vec2, b: Vec2, glyphs: &[Vec<Vec2>], boxes: &[(Vec2, Vec2)]) -> EdgeMask {
        let d = b - a;
        let (elo, ehi) = (
            Vec2::new(a.x.min(b.x), a.y.min(b.y)),
            Vec2::new(a.x.max(b.x), a.y.max(b.y)),
        );
        let mut w0 = 0;
        let mut cuts = Vec::new();
        for (poly, &(lo, hi)) in glyphs.iter().zip(boxes) {
            w0 += polygon_winding_number(poly, a);
            if ehi.x < lo.x || elo.x > hi.x || ehi.y < lo.y || elo.y > hi.y {
                continue;
            }
            let n = poly.len();
            for i in 0..n {
                let (p, q) = (poly[i], poly[(i + 1) % n]);
                let e = q - p;
                let den = d.cross(e);
                if den == 0.0 {
                    continue;
                }
                let ap = p - a;
                let t = ap.cross(e) / den;
                let s = ap.cross(d) / den;
                if (0.0..=1.0).contains(&t) && (0.0..1.0).contains(&s) {
                    // Crossing from the edge's right to its left raises the winding.
                    cuts.push((t, if den < 0.0 { 1 } else { -1 }));
                }
            }
        }
        cuts.sort_by(|x, y| x.0.total_cmp(&y.0));
        EdgeMask { w0, cuts }
    }

    fn inside(&self, t: f64) -> bool {
        let w: i32 = self.w0
            + self
                .cuts
                .iter()
                .take_while(|c| c.0 < t)
                .map(|c| c.1)
                .sum::<i32>();
        w != 0
    }

    /// Where the edge passes between material and free space: the first such
    /// place from the start if `from_start`, else the last.
    fn outline(&self, from_start: bool) -> Option<f64> {
        let mut w = self.w0;
        let mut found = None;
        for &(t, dw) in &self.cuts {
            let before = w != 0;
            w += dw;
            if before != (w != 0) {
                if from_start {
                    return Some(t);
                }
                found = Some(t);
            }
        }
        found
    }
}

/// Keep the crossings of one edge in level order along it (`ascending`: t grows
/// with the level), at least [`T_MIN`] of the edge from its ends and from each
/// other (less only if an edge carries more than 1/T_MIN levels).
fn space_out(ts: &mut [f64], ascending: bool) {
    let n = ts.len();
    if n == 0 {
        return;
    }
    let d = T_MIN.min((1.0 - 2.0 * T_MIN) / n as f64);
    let mut q: Vec<f64> = ts
        .iter()
        .map(|&t| if ascending { t } else { 1.0 - t })
        .collect();
    q[0] = q[0].max(T_MIN);
    for i in 1..n {
        q[i] = q[i].max(q[i - 1] + d);
    }
    q[n - 1] = q[n - 1].min(1.0 - T_MIN);
    for i in (0..n - 1).rev() {
        q[i] = q[i].min(q[i + 1] - d);
    }
    for (t, q) in ts.iter_mut().zip(q) {
        *t = if ascending { q } else { 1.0 - q };
    }
}

/// The stock rectangle as the level planner computes it: the bounding box of
/// the largest level Γ(s_bottom) (a boss's foot, a cavity's rim), from the
/// same grid of u and the same curves (`crate::levels::mfs_sections::job_grid`,
/// `field::level::curves`), plus the margin.
pub(crate) fn stock_rectangle(sj: &SurfaceJob) -> Result<(Vec2, Vec2), SurfaceError> {
    if crate::geometry::polygons_bbox(sj.glyphs).is_none() {
        return Err(SurfaceError::EmptyShape);
    }
    let (s_lo, _) = sj.profile.s_range();
    let (grid, h) = crate::levels::mfs_sections::job_grid(sj.field, sj.glyphs, sj.profile)?;
    let base = crate::field::level::curves(&grid, sj.field, sj.glyphs, s_lo, h, sj.tol);
    let (blo, bhi) =
        crate::geometry::polygons_bbox(&base).ok_or(SurfaceError::NoBaseContour { s: s_lo })?;
    let m = Vec2::new(sj.margin, sj.margin);
    Ok((blo - m, bhi + m))
}

/// Index of the band of value v: how many levels are ≤ v.
fn band(levels: &[f64], v: f64) -> usize {
    levels.partition_point(|&s| s <= v)
}

/// The grid over the stock rectangle, and u sampled on it.
struct StockGrid {
    /// x of the grid columns, mm: the stock's left edge to its right edge.
    xs: Vec<f64>,
    /// y of the grid rows, mm: the stock's front edge to its back edge.
    ys: Vec<f64>,
    /// Grid points in x.
    nx: usize,
    /// Grid points in y.
    ny: usize,
    /// Whether each point (index j·nx + i) lies in the material.
    inside: Vec<bool>,
    /// u at each point, the material pinned to 1, the rest at most `ONE_BELOW`.
    values: Vec<f64>,
}

impl StockGrid {
    /// The grid over exactly the rectangle `slo`–`shi`, spacing at most `res`
    /// mm in each direction (so x and y spacings may differ), not yet sampled.
    fn over(slo: Vec2, shi: Vec2, res: f64) -> Result<StockGrid, SurfaceError> {
        let (w, h) = (shi.x - slo.x, shi.y - slo.y);
        let cx = (w / res).ceil().max(1.0);
        let cy = (h / res).ceil().max(1.0);
        if (cx + 1.0) * (cy + 1.0) > MAX_GRID_POINTS as f64 {
            return Err(SurfaceError::GridTooLarge {
                resolution: res,
                width: w,
                height: h,
            });
        }
        let (nx, ny) = (cx as usize + 1, cy as usize + 1);
        Ok(StockGrid {
            xs: spaced(slo.x, shi.x, nx),
            ys: spaced(slo.y, shi.y, ny),
            nx,
            ny,
            inside: Vec::new(),
            values: Vec::new(),
        })
    }

    /// Samples u at every point, in blocks of rows (one progress step each),
    /// the rows of a block in parallel.
    fn sample(&mut self, sj: &SurfaceJob, progress: &mut dyn FnMut(Progress)) {
        const BLOCK: usize = 16;
        let (nx, ny) = (self.nx, self.ny);
        self.inside = crate::geometry::winding_rows(&self.xs, &self.ys, sj.glyphs);
        progress(Progress::Stage {
            name: "sampling the field".into(),
            total: ny.div_ceil(BLOCK) as u64,
        });
        let (xs, ys, inside) = (&self.xs, &self.ys, &self.inside);
        let mut values = vec![0.0; nx * ny];
        for (b, chunk) in values.chunks_mut(nx * BLOCK).enumerate() {
            chunk.par_chunks_mut(nx).enumerate().for_each(|(r, row)| {
                let j = b * BLOCK + r;
                let inside = &inside[j * nx..(j + 1) * nx];
                sj.field
                    .values_where(row, inside, |i| Vec2::new(xs[i], ys[j]));
                for (v, &m) in row.iter_mut().zip(inside) {
                    *v = if m { 1.0 } else { v.min(ONE_BELOW) };
                }
            });
            progress(Progress::Step);
        }
        self.values = values;
    }

    /// Horizontal edges (i, j)–(i+1, j) are numbered first.
    fn n_horizontal(&self) -> usize {
        (self.nx - 1) * self.ny
    }

    /// All edges: the horizontal ones, then the vertical (i, j)–(i, j+1).
    fn n_edges(&self) -> usize {
        self.n_horizontal() + self.nx * (self.ny - 1)
    }

    /// Edge (i, j)–(i+1, j).
    fn h_edge(&self, i: usize, j: usize) -> usize {
        j * (self.nx - 1) + i
    }

    /// Edge (i, j)–(i, j+1).
    fn v_edge(&self, i: usize, j: usize) -> usize {
        self.n_horizontal() + j * self.nx + i
    }

    /// The grid points at edge `e`'s lower-index end and its other end.
    fn ends(&self, e: usize) -> (usize, usize) {
        let (nx, n_h) = (self.nx, self.n_horizontal());
        if e < n_h {
            let (i, j) = (e % (nx - 1), e / (nx - 1));
            (j * nx + i, j * nx + i + 1)
        } else {
            let e = e - n_h;
            let (i, j) = (e % nx, e / nx);
            (j * nx + i, (j + 1) * nx + i)
        }
    }

    /// Grid point `g`, mm.
    fn point(&self, g: usize) -> Vec2 {
        Vec2::new(self.xs[g % self.nx], self.ys[g / self.nx])
    }

    /// The levels edge `e` crosses: the lowest one k0, and the parameters t
    /// (from the edge's lower-index end) of levels k0, k0+1, ..., by regula
    /// falsi on u along the edge (u = 1 in the glyphs, whose `boxes` bound
    /// them), spaced at least [`T_MIN`] apart.
    fn edge_crossings(
        &self,
        e: usize,
        sj: &SurfaceJob,
        levels: &[f64],
        boxes: &[(Vec2, Vec2)],
    ) -> (usize, Vec<f64>) {
        let (ga, gb) = self.ends(e);
        let (va, vb) = (self.values[ga], self.values[gb]);
        let (ba, bb) = (band(levels, va), band(levels, vb));
        if ba == bb {
            return (0, Vec::new());
        }
        let (k0, k1) = (ba.min(bb), ba.max(bb));
        let (pa, pb) = (self.point(ga), self.point(gb));
        let mask =
            (self.inside[ga] || self.inside[gb]).then(|| EdgeMask::new(pa, pb, sj.glyphs, boxes));
        let u = |t: f64| -> f64 {
            if mask.as_ref().is_some_and(|m| m.inside(t)) {
                1.0
            } else {
                sj.field.value(pa.lerp(pb, t))
            }
        };
        let mut ts: Vec<f64> = (k0..k1)
            .map(|k| {
                let s = levels[k];
                if s >= ONE_BELOW {
                    // The top at s = 1 is the material's outline itself.
                    mask.as_ref()
                        .and_then(|m| m.outline(va < vb))
                        .unwrap_or(0.5)
                } else {
                    crate::field::isolines::root_in_unit(va - s, vb - s, &|t| u(t) - s)
                }
            })
            .collect();
        space_out(&mut ts, va < vb);
        (k0, ts)
    }

    /// Every edge's crossings, edge by edge in parallel, in blocks of
    /// 2¹⁴ edges (one progress step each), collected in edge order.
    fn crossings(
        &self,
        sj: &SurfaceJob,
        levels: &[f64],
        progress: &mut dyn FnMut(Progress),
    ) -> Vec<(usize, Vec<f64>)> {
        const EDGE_BLOCK: usize = 1 << 14;
        let boxes: Vec<(Vec2, Vec2)> = sj
            .glyphs
            .iter()
            .map(|p| {
                crate::geometry::polygons_bbox(std::slice::from_ref(p))
                    .unwrap_or((Vec2::ZERO, Vec2::ZERO))
            })
            .collect();
        let n_edges = self.n_edges();
        let edge_blocks = n_edges.div_ceil(EDGE_BLOCK);
        progress(Progress::Stage {
            name: "placing the level crossings".into(),
            total: edge_blocks as u64,
        });
        let mut edge_x: Vec<(usize, Vec<f64>)> = Vec::with_capacity(n_edges);
        for b in 0..edge_blocks {
            let r = b * EDGE_BLOCK..((b + 1) * EDGE_BLOCK).min(n_edges);
            edge_x.par_extend(
                r.into_par_iter()
                    .map(|e| self.edge_crossings(e, sj, levels, &boxes)),
            );
            progress(Progress::Step);
        }
        edge_x
    }
}

/// `n` ≥ 2 values from `a` to `b` (exactly) in equal steps.
fn spaced(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            if i + 1 == n {
                b
            } else {
                a + (b - a) * i as f64 / (n - 1) as f64
            }
        })
        .collect()
}

/// The mesh's vertices placed so far and where each edge's crossings are.
struct Vertices<'a> {
    /// The grid.
    grid: &'a StockGrid,
    /// Each edge's lowest level and crossing parameters.
    edge_x: Vec<(usize, Vec<f64>)>,
    /// Each edge's first crossing vertex.
    x_base: Vec<u32>,
    /// The vertices: the grid points at z(u), then every crossing, edge by
    /// edge, at its level's z.
    vertices: Vec<[f64; 3]>,
    /// Every crossing vertex with its level's index.
    crossings: Vec<(u32, usize)>,
}

impl<'a> Vertices<'a> {
    /// The grid points and the crossings `edge_x` as vertices; an error if
    /// they are too many for 32-bit indices (with room for the walls).
    fn place(
        grid: &'a StockGrid,
        edge_x: Vec<(usize, Vec<f64>)>,
        sj: &SurfaceJob,
        level_z: &[f64],
    ) -> Result<Vertices<'a>, SurfaceError> {
        let (nx, ny) = (grid.nx, grid.ny);
        let mut vertices: Vec<[f64; 3]> = Vec::with_capacity(nx * ny * 2);
        for g in 0..nx * ny {
            vertices.push([grid.xs[g % nx], grid.ys[g / nx], sj.z_of(grid.values[g])]);
        }
        let mut x_base = vec![0u32; grid.n_edges()];
        let mut crossings = Vec::new();
        for (e, (k0, ts)) in edge_x.iter().enumerate() {
            x_base[e] = vertices.len() as u32;
            let (ga, gb) = grid.ends(e);
            let (pa, pb) = (grid.point(ga), grid.point(gb));
            for (m, &t) in ts.iter().enumerate() {
                // Along the edge only one coordinate changes; the other stays exact.
                let p = if e < grid.n_horizontal() {
                    Vec2::new(pa.x + t * (pb.x - pa.x), pa.y)
                } else {
                    Vec2::new(pa.x, pa.y + t * (pb.y - pa.y))
                };
                crossings.push((vertices.len() as u32, k0 + m));
                vertices.push([p.x, p.y, level_z[k0 + m]]);
            }
        }
        if vertices.len() > u32::MAX as usize / 2 {
            return Err(SurfaceError::TooManyVertices);
        }
        Ok(Vertices {
            grid,
            edge_x,
            x_base,
            vertices,
            crossings,
        })
    }

    /// Appends the crossings of edge `e`, from its start (`forward`) or from
    /// its end, each with its vertex, `sides` and level.
    fn along(&self, e: usize, forward: bool, sides: Sides, out: &mut Vec<(u32, Sides, usize)>) {
        let (k0, ts) = &self.edge_x[e];
        let (ga, gb) = self.grid.ends(e);
        // Levels grow along the edge from the lower value to the higher.
        let up = self.grid.values[ga] < self.grid.values[gb];
        let n = ts.len();
        for m in 0..n {
            let idx = if up == forward { m } else { n - 1 - m };
            out.push((self.x_base[e] + idx as u32, sides, k0 + idx));
        }
    }

    /// The top surface's isobands, cell by cell (rows in parallel, collected
    /// in order).
    fn top(&self, levels: &[f64]) -> Vec<[u32; 3]> {
        let (g, nx, ny) = (self.grid, self.grid.nx, self.grid.ny);
        let rows: Vec<Vec<[u32; 3]>> = (0..ny - 1)
            .into_par_iter()
            .map(|j| {
                let mut tris = Vec::new();
                let mut pts: Vec<(u32, Sides, usize)> = Vec::new();
                for i in 0..nx - 1 {
                    let corners = [
                        j * nx + i,
                        j * nx + i + 1,
                        (j + 1) * nx + i + 1,
                        (j + 1) * nx + i,
                    ];
                    let cv = corners.map(|c| g.values[c]);
                    let edges = [
                        (g.h_edge(i, j), true),
                        (g.v_edge(i + 1, j), true),
                        (g.h_edge(i, j + 1), false),
                        (g.v_edge(i, j), false),
                    ];
                    pts.clear();
                    for m in 0..4 {
                        pts.push((corners[m] as u32, CORNER_SIDES[m], usize::MAX));
                        self.along(edges[m].0, edges[m].1, 1 << m, &mut pts);
                    }
                    cell(&pts, &cv, levels, &mut tris);
                }
                tris
            })
            .collect();
        rows.concat()
    }

    /// The top's boundary counter-clockwise (seen from above) from the
    /// front-left corner: (vertex, stock sides, 0).
    fn boundary(&self) -> Vec<(u32, Sides, usize)> {
        const FRONT: Sides = 1;
        const RIGHT: Sides = 2;
        const BACK: Sides = 4;
        const LEFT: Sides = 8;
        let (g, nx, ny) = (self.grid, self.grid.nx, self.grid.ny);
        let mut ring: Vec<(u32, Sides, usize)> = Vec::new();
        for i in 0..nx - 1 {
            ring.push((i as u32, if i == 0 { FRONT | LEFT } else { FRONT }, 0));
            self.along(g.h_edge(i, 0), true, FRONT, &mut ring);
        }
        for j in 0..ny - 1 {
            let s = if j == 0 { FRONT | RIGHT } else { RIGHT };
            ring.push(((j * nx + nx - 1) as u32, s, 0));
            self.along(g.v_edge(nx - 1, j), true, RIGHT, &mut ring);
        }
        for i in (1..nx).rev() {
            let s = if i == nx - 1 { RIGHT | BACK } else { BACK };
            ring.push((((ny - 1) * nx + i) as u32, s, 0));
            self.along(g.h_edge(i - 1, ny - 1), false, BACK, &mut ring);
        }
        for j in (1..ny).rev() {
            let s = if j == ny - 1 { BACK | LEFT } else { LEFT };
            ring.push(((j * nx) as u32, s, 0));
            self.along(g.v_edge(0, j - 1), false, LEFT, &mut ring);
        }
        ring
    }

    /// Closes the solid: each boundary point gets a vertex straight below it
    /// at `z_bottom`, the walls join the two rings, and the bottom is the lower
    /// ring reversed (clockwise from above: facing down).
    fn close(&mut self, z_bottom: f64, triangles: &mut Vec<[u32; 3]>) {
        let ring = self.boundary();
        let vertices = &mut self.vertices;
        let below: Vec<u32> = ring
            .iter()
            .map(|&(v, _, _)| {
                let p = vertices[v as usize];
                vertices.push([p[0], p[1], z_bottom]);
                (vertices.len() - 1) as u32
            })
            .collect();
        let r = ring.len();
        for a in 0..r {
            let b = (a + 1) % r;
            let (pa, pb) = (ring[a].0, ring[b].0);
            triangles.push([below[a], below[b], pb]);
            triangles.push([below[a], pb, pa]);
        }
        let bottom: Vec<(u32, Sides)> = (0..r).rev().map(|a| (below[a], ring[a].1)).collect();
        triangulate_convex(&bottom, triangles);
    }
}

/// Build the closed mesh of the part: stock rectangle, grid, level crossings,
/// isobands, walls and bottom. Steps are reported through `progress`.
pub fn build(
    sj: &SurfaceJob,
    opts: &SurfaceOptions,
    progress: &mut dyn FnMut(Progress),
) -> Result<Surface, SurfaceError> {
    let res = opts.resolution;
    if !(res > 0.0 && res.is_finite()) {
        return Err(SurfaceError::Resolution(res));
    }
    let (slo, shi) = match sj.stock {
        Some(stock) => stock,
        None => {
            progress(Progress::Stage {
                name: "finding the stock".into(),
                total: 1,
            });
            let stock = stock_rectangle(sj)?;
            progress(Progress::Step);
            stock
        }
    };
    let levels = level_values(sj.profile);
    let level_z: Vec<f64> = levels.iter().map(|&s| sj.z_of(s)).collect();
    let mut grid = StockGrid::over(slo, shi, res)?;
    grid.sample(sj, progress);
    let edge_x = grid.crossings(sj, &levels, progress);
    progress(Progress::Stage {
        name: "triangulating".into(),
        total: 1,
    });
    let mut v = Vertices::place(&grid, edge_x, sj, &level_z)?;
    let mut triangles = v.top(&levels);
    let z_bottom = sj.z_bottom();
    v.close(z_bottom, &mut triangles);
    progress(Progress::Step);
    Ok(Surface {
        mesh: Mesh {
            vertices: v.vertices,
            triangles,
        },
        stock_lo: slo,
        stock_hi: shi,
        z_bottom,
        levels,
        crossings: v.crossings,
        grid: (grid.nx, grid.ny),
    })
}

/// The isobands of one cell. `pts` are the cell's boundary points counter-
/// clockwise from its lower-left corner: (vertex, sides, level) with level
/// `usize::MAX` for the corners; `cv` the corner values.
fn cell(pts: &[(u32, Sides, usize)], cv: &[f64; 4], levels: &[f64], out: &mut Vec<[u32; 3]>) {
    let n = pts.len();
    if n == 4 {
        // No crossing: one band, two triangles.
        out.push([pts[0].0, pts[1].0, pts[2].0]);
        out.push([pts[0].0, pts[2].0, pts[3].0]);
        return;
    }
    // Chords: each level's crossings paired as by marching squares.
    let mut partner = vec![usize::MAX; n];
    let centre = 0.25 * (cv[0] + cv[1] + cv[2] + cv[3]);
    let mut by_level: Vec<(usize, usize)> = (0..n)
        .filter(|&p| pts[p].2 != usize::MAX)
        .map(|p| (pts[p].2, p))
        .collect();
    by_level.sort_unstable();
    let mut a = 0;
    while a < by_level.len() {
        let k = by_level[a].0;
        let mut b = a;
        while b < by_level.len() && by_level[b].0 == k {
            b += 1;
        }
        // Positions of level k's crossings, in boundary order (one per side).
        let mut ps: Vec<usize> = by_level[a..b].iter().map(|x| x.1).collect();
        ps.sort_unstable();
        if ps.len() == 2 {
            partner[ps[0]] = ps[1];
            partner[ps[1]] = ps[0];
        } else if ps.len() == 4 {
            // A saddle: corner m lies between the crossings on sides m−1 and m.
            // Cut off the low corners if the centre is high, else the high ones.
            let s = levels[k];
            for m in 0..4 {
                let high = cv[m] >= s;
                if high == (centre < s) {
                    let (p, q) = (ps[(m + 3) % 4], ps[m]);
                    partner[p] = q;
                    partner[q] = p;
                }
            }
        }
        a = b;
    }
    // Faces: walk the boundary counter-clockwise; at a crossing, follow its chord.
    let mut used = vec![false; n];
    let mut face: Vec<(u32, Sides)> = Vec::new();
    for start in 0..n {
        if used[start] {
            continue;
        }
        face.clear();
        let mut s = start;
        for _ in 0..2 * n {
            used[s] = true;
            face.push((pts[s].0, pts[s].1));
            let mut next = (s + 1) % n;
            if partner[next] != usize::MAX {
                face.push((pts[next].0, pts[next].1));
                next = partner[next];
            }
            if next == start {
                break;
            }
            s = next;
        }
        triangulate_convex(&face, out);
    }
}

/// The STL's 80-byte header: `pfcam <name>`, cut to fit, padded with zeros.
pub(crate) fn stl_header(name: &str) -> [u8; 80] {
    let mut h = [0u8; 80];
    let text = format!("pfcam {name}");
    let mut end = text.len().min(80);
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    h[..end].copy_from_slice(&text.as_bytes()[..end]);
    h
}

/// The mesh as binary STL: header, triangle count (u32), then per triangle the
/// unit normal and the three corners (f32, little-endian) and a zero u16.
pub fn stl_bytes(mesh: &Mesh, name: &str) -> Vec<u8> {
    let mut b = Vec::with_capacity(84 + 50 * mesh.triangles.len());
    b.extend_from_slice(&stl_header(name));
    b.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for t in 0..mesh.triangles.len() {
        let [p, q, r] = mesh.corners(t);
        let n = cross3(sub3(q, p), sub3(r, p));
        let len = norm3(n);
        let n = if len > 0.0 {
            [n[0] / len, n[1] / len, n[2] / len]
        } else {
            [0.0; 3]
        };
        for v in [n, p, q, r] {
            for c in v {
                b.extend_from_slice(&(c as f32).to_le_bytes());
            }
        }
        b.extend_from_slice(&0u16.to_le_bytes());
    }
    b
}

/// One triangle of a binary STL file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StlTriangle {
    /// The stored normal.
    pub normal: [f32; 3],
    /// The corners.
    pub corners: [[f32; 3]; 3],
}

/// Read a binary STL: the header and the triangles (the length must match the
/// count).
pub fn read_stl(bytes: &[u8]) -> Result<([u8; 80], Vec<StlTriangle>), String> {
    if bytes.len() < 84 {
        return Err(format!("{} bytes: too short for a binary STL", bytes.len()));
    }
    let mut header = [0u8; 80];
    header.copy_from_slice(&bytes[..80]);
    let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    if bytes.len() != 84 + 50 * count {
        return Err(format!(
            "{} triangles need {} bytes, the file has {}",
            count,
            84 + 50 * count,
            bytes.len()
        ));
    }
    let f = |o: usize| f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    let v = |o: usize| [f(o), f(o + 4), f(o + 8)];
    let tris = (0..count)
        .map(|t| {
            let o = 84 + 50 * t;
            StlTriangle {
                normal: v(o),
                corners: [v(o + 12), v(o + 24), v(o + 36)],
            }
        })
        .collect();
    Ok((header, tris))
}

/// Weld an STL's triangles into an indexed mesh: corners with the same 32-bit
/// coordinates are one vertex.
pub fn weld(tris: &[StlTriangle]) -> Mesh {
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    let mut mesh = Mesh::default();
    for t in tris {
        let mut tri = [0u32; 3];
        for (k, c) in t.corners.iter().enumerate() {
            // +0.0 folds −0.0 into 0.0.
            let key = c.map(|x| (x + 0.0).to_bits());
            tri[k] = *index.entry(key).or_insert_with(|| {
                mesh.vertices.push(c.map(f64::from));
                (mesh.vertices.len() - 1) as u32
            });
        }
        mesh.triangles.push(tri);
    }
    mesh
}

/// Whether the file at `path` is a binary STL pfcam wrote (its header starts
/// with `pfcam ` and its length matches its triangle count).
pub(crate) fn written_by_pfcam(path: &Path) -> std::io::Result<bool> {
    use std::io::Read;
    let len = std::fs::metadata(path)?.len();
    let mut head = Vec::new();
    std::fs::File::open(path)?.take(84).read_to_end(&mut head)?;
    if head.len() < 84 || !head.starts_with(b"pfcam ") {
        return Ok(false);
    }
    let count = u32::from_le_bytes([head[80], head[81], head[82], head[83]]) as u64;
    Ok(len == 84 + 50 * count)
}

/// As `output::check_target` for an STL: a file may be replaced if pfcam wrote
/// it (see [`written_by_pfcam`]) or with `force`. Returns whether it is pfcam's,
/// to pass on as `force` to `output::write_atomic`, which does not know STL.
pub fn check_stl_target(path: &Path, force: bool) -> Result<bool, OutputError> {
    let own = path.is_file() && written_by_pfcam(path).unwrap_or(false);
    check_target(path, force || own)?;
    Ok(own)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square's sides: 0 bottom, 1 right, 2 top, 3 left.
    fn area2(p: &[[f64; 2]], t: [u32; 3]) -> f64 {
        let [a, b, c] = t.map(|i| p[i as usize]);
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    }

    #[test]
    fn convex_pieces_with_collinear_points_have_no_flat_triangles() {
        // The unit square with points on its sides: every piece's triangles
        // have positive area and add up to the piece.
        let pos = [
            [0.0, 0.0],
            [0.25, 0.0],
            [0.5, 0.0],
            [1.0, 0.0],
            [1.0, 0.5],
            [1.0, 1.0],
            [0.5, 1.0],
            [0.0, 1.0],
            [0.0, 0.3],
        ];
        let sides: [Sides; 9] = [
            0b1001, 0b0001, 0b0001, 0b0011, 0b0010, 0b0110, 0b0100, 0b1100, 0b1000,
        ];
        let cases: Vec<Vec<usize>> = vec![
            (0..9).collect(),
            vec![0, 1, 2, 3, 5],    // a triangle with two points on one side
            vec![2, 3, 4, 5, 6],    // a pentagon
            vec![0, 1, 2, 3, 4, 8], // flat runs on two sides
            vec![1, 2, 3, 4, 5],    // a quad with a flat run
        ];
        for c in cases {
            let poly: Vec<(u32, Sides)> = c.iter().map(|&i| (i as u32, sides[i])).collect();
            let mut out = Vec::new();
            triangulate_convex(&poly, &mut out);
            assert_eq!(out.len(), c.len() - 2, "{c:?}");
            let total: f64 = out.iter().map(|&t| area2(&pos, t)).sum();
            let expect: f64 = (0..c.len())
                .map(|k| {
                    let (a, b) = (pos[c[k]], pos[c[(k + 1) % c.len()]]);
                    a[0] * b[1] - a[1] * b[0]
                })
                .sum();
            assert!((total - expect).abs() < 1e-12, "{c:?}: {total} vs {expect}");
            for &t in &out {
                assert!(area2(&pos, t) > 0.0, "{c:?}: flat or flipped {t:?}");
            }
        }
    }

    #[test]
    fn crossings_keep_level_order_and_distance() {
        let mut ts = vec![0.0, 0.5, 0.4, 1.0];
        space_out(&mut ts, true);
        for w in ts.windows(2) {
            assert!(w[1] - w[0] >= T_MIN * 0.999, "{ts:?}");
        }
        assert!(ts[0] >= T_MIN && ts[3] <= 1.0 - T_MIN, "{ts:?}");
        let mut ts = vec![1.0, 0.9, 0.95];
        space_out(&mut ts, false);
        assert!(
            ts[0] > ts[1] && ts[1] > ts[2] && ts[0] <= 1.0 - T_MIN,
            "{ts:?}"
        );
        // Many levels on one edge: still ordered, inside the edge.
        let mut ts = vec![0.5; 2000];
        space_out(&mut ts, true);
        assert!(ts.windows(2).all(|w| w[1] > w[0]) && ts[1999] < 1.0);
    }

    #[test]
    fn watertight_detects_holes_and_flips() {
        // A tetrahedron, outward.
        let tet = vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        assert!(is_watertight(&tet));
        let mut flipped = tet.clone();
        flipped[1] = [0, 3, 1];
        assert!(!is_watertight(&flipped));
        assert!(!is_watertight(&tet[..3]));
        let m = Mesh {
            vertices: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ],
            triangles: tet,
        };
        assert!(m.check().is_ok());
        assert!((m.volume() - 1.0 / 6.0).abs() < 1e-15);
        let back = weld(&read_stl(&stl_bytes(&m, "tet")).unwrap().1);
        assert_eq!(back.vertices.len(), 4);
        for t in 0..4 {
            assert_eq!(back.corners(t), m.corners(t));
        }
        assert_eq!(&stl_header("tet")[..10], b"pfcam tet\0");
    }

    #[test]
    fn levels_span_the_profile_in_small_steps() {
        let p = DepthProfile::Sigmoid {
            s1: 0.97,
            s2: 0.9,
            steepness: 6.0,
            depth: 3.0,
        };
        let l = level_values(&p);
        assert_eq!(l[0], 0.9);
        assert_eq!(*l.last().unwrap(), 0.97);
        for w in l.windows(2) {
            assert!(w[1] > w[0]);
            assert!(w[1] - w[0] <= 0.07 / 16.0 + 1e-12);
            assert!(p.z(w[1]) - p.z(w[0]) <= LEVEL_DZ + 1e-9);
        }
    }
}
