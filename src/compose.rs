//! Modelling with potential fields: the paper's Boolean operations on MFS problems
//! (Section 4) and its modelling sequence (Section 5), which builds the letter Q
//! from a rectangle and a polygon.
//!
//! Every part is a *model*: its MFS point set by role (singularities in the
//! material with the collocation points of u = 1 on its boundary, the outer circle
//! ∂Ω_E and the sinks ∂Ω_O with u = 0), the solved field, an exact membership test
//! (the primitives' polygons combined as a Boolean expression, Appendix I's index
//! for each), and an explicit boundary:
//! - a primitive (polygon, SVG path, text) solves the direct problem (2.1);
//! - `level = s` takes Γ(s) of a part's field as a new primitive (model set 1);
//! - `invert` solves the inverse problem: u = 1 on the same boundary, singularities
//!   on the other side of it, u = 0 on a sink inside every piece of material;
//! - `union` keeps every point of both operands (the paper: "equivalent to solving
//!   (2.5) with ℓ = 2"), except sinks that fall in the other operand's material;
//! - `intersect` keeps the points of each operand inside the other;
//! - `subtract` A − B is the intersection of A with the inverse problem of B: the
//!   points of A outside B, the points of B and its outside singularities R_I inside
//!   A, and the sinks of B (the paper's P̂_I1 ∪ P̂_I2, Q̂_I1 ∪ R̂_I2, P_O2, R_O2).
//!
//! The measured refinements of the paper's recipe (docs/method.md §10): points of
//! a union inside the other operand are kept as interior points of u = 1, and
//! dropped where an intersection brings them next to a new boundary; singularities
//! that would sit almost on the new boundary are dropped; sinks stay only where the
//! result's material shuts them in; crossings that are convex corners of the
//! result get a cluster of singularities.
//!
//! The combined problem is solved afresh, and the explicit boundary of the result
//! is {u = 1} of its own field: Γ(1 − τ) just outside the material (τ 1.5 times the
//! largest deficit 1 − u at its check points), every vertex checked to lie on that
//! level of the raw field, so a composite whose field does not reach 1 on some
//! piece of its boundary is an error, not a curve copied from the membership test;
//! then each vertex is carried onto u = 1 by Newton's method.

use crate::field::isolines::{isolines_in, Grid};
use crate::field::level::{self, Limits};
use crate::field::setup::{Boundary, Layout, Prepared, Sink, OUTER_CHARGES, SINK_CHARGES};
use crate::field::{self, mfs, Field, FieldError, Problem};
use crate::geometry::polygon_area;
use crate::geometry::{
    build_shape, deepest_point_in, line_crossing, polygon_winding_number, polygons_bbox,
    regions_from_contours, svgpath, BoolOp, Composition, Contour, DistanceIndex, GeometryError,
    Part, PartSource, Ring, Shape, ShapeSource, Vec2,
};
use std::collections::HashMap;
use std::time::Instant;

mod fault;
mod mask;
mod order;

pub use fault::PartFault;

/// The models a part may refer to, by name.
type Models<'a> = HashMap<&'a str, &'a Model>;

/// Singularities per region of a primitive when a part does not set them.
pub const AUTO_N_PER_REGION: usize = 120;

/// The outer circle (shared by every part, the paper's Ω_E1 = Ω_E2) has this many
/// times the diagonal of the primitives' bounding box as radius, about the box's
/// centre (as `pipeline::OUTER_RADIUS_FACTOR` for a single shape).
pub const OUTER_RADIUS_FACTOR: f64 = 14.0;

/// Grid points across the longer side of the box in which a curve is extracted.
pub const EXTRACT_GRID: f64 = 400.0;

/// Chords of extracted curves are refined until they are within this fraction of
/// the primitives' diagonal of the level (Newton onto Γ(s)).
pub const CURVE_TOL: f64 = 2e-5;

/// Smallest τ for the boundary Γ(1 − τ) of a composite.
pub const MIN_TAU: f64 = 1e-5;

/// What went wrong modelling a part.
#[derive(Debug, thiserror::Error)]
pub enum ComposeError {
    /// A part's geometry is bad.
    #[error("shape.part \"{part}\": {source}")]
    Geometry {
        /// the part
        part: String,
        /// why
        source: GeometryError,
    },
    /// A part's field could not be built or solved.
    #[error("shape.part \"{part}\": field: {source}")]
    Field {
        /// the part
        part: String,
        /// why
        source: FieldError,
    },
    /// A part's field could not be solved or used.
    #[error("shape.part \"{part}\": {source}")]
    Part {
        /// the part
        part: String,
        /// why
        source: PartFault,
    },
}

impl ComposeError {
    /// The name of the part (or operation) that failed, as the composition
    /// gave it.
    pub fn part(&self) -> &str {
        match self {
            ComposeError::Geometry { part, .. }
            | ComposeError::Field { part, .. }
            | ComposeError::Part { part, .. } => part,
        }
    }

    /// What went wrong there, without the part's name.
    pub fn detail(&self) -> String {
        match self {
            ComposeError::Geometry { source, .. } => source.to_string(),
            ComposeError::Field { source, .. } => format!("field: {source}"),
            ComposeError::Part { source, .. } => source.to_string(),
        }
    }
}

fn part_err(part: &str, fault: PartFault) -> ComposeError {
    ComposeError::Part {
        part: part.to_string(),
        source: fault,
    }
}

fn field_err(part: &str, e: FieldError) -> ComposeError {
    ComposeError::Field {
        part: part.to_string(),
        source: e,
    }
}

/// Exact membership: the primitives' polygons (non-zero winding, Appendix I)
/// combined by the Boolean expression of the part.
#[derive(Clone, Debug)]
pub enum Csg {
    /// Inside closed polygons (or outside them, for the material of an inverse problem).
    Leaf {
        /// polygons, material on the left
        polys: Vec<Vec<Vec2>>,
        /// the material is the outside of the polygons
        complement: bool,
    },
    /// Complement.
    Not(Box<Csg>),
    /// Intersection.
    And(Box<Csg>, Box<Csg>),
    /// Union.
    Or(Box<Csg>, Box<Csg>),
}

impl Csg {
    /// True when `p` is in the material.
    pub fn contains(&self, p: Vec2) -> bool {
        match self {
            Csg::Leaf { polys, complement } => {
                let w: i32 = polys.iter().map(|q| polygon_winding_number(q, p)).sum();
                (w != 0) != *complement
            }
            Csg::Not(a) => !a.contains(p),
            Csg::And(a, b) => a.contains(p) && b.contains(p),
            Csg::Or(a, b) => a.contains(p) || b.contains(p),
        }
    }
}

/// The MFS points of a model by role (the paper's sets of Section 4).
#[derive(Clone, Debug, Default)]
pub struct PointSet {
    /// Singularities in the material (Q_I, or R_I of an inverse problem), with the
    /// collocation and check points of u = 1 on the boundary (P_I).
    pub material: Problem,
    /// Collocation points of u = 1 inside the material: a union keeps the points
    /// of each operand inside the other, as the paper does.
    pub interior: Vec<Vec2>,
    /// The outer circle ∂Ω_E with its singularities, when the material is bounded.
    pub outer: Option<Problem>,
    /// Sinks ∂Ω_O with their singularities, u = 0.
    pub sinks: Vec<(Sink, Problem)>,
}

impl PointSet {
    fn problem(&self) -> Problem {
        let mut pr = self.material.clone();
        pr.colloc.extend(
            self.interior
                .iter()
                .map(|&p| crate::field::Condition { p, value: 1.0 }),
        );
        for g in self.outer.iter().chain(self.sinks.iter().map(|(_, p)| p)) {
            pr.charges.extend_from_slice(&g.charges);
            pr.colloc.extend_from_slice(&g.colloc);
            pr.checks.extend_from_slice(&g.checks);
        }
        pr
    }
}

/// A modelled part.
#[derive(Clone, Debug)]
pub struct Model {
    /// The part's name.
    pub name: String,
    /// Its MFS points.
    pub set: PointSet,
    /// Its solved field.
    pub field: Field,
    /// Max boundary error |u − g| over its check points.
    pub max_error: f64,
    /// The explicit boundary, material on the left.
    pub contours: Vec<Contour>,
    /// For each contour, whether it bounds a hole of the material.
    pub is_counter: Vec<bool>,
    /// Exact membership.
    pub csg: Csg,
}

impl Model {
    /// True when the material is bounded (the outer circle is in the void).
    pub fn bounded(&self) -> bool {
        self.set.outer.is_some()
    }

    /// The boundary polygons (flattened contours).
    pub fn polygons(&self, tol: f64) -> Vec<Vec<Vec2>> {
        self.contours.iter().map(|c| c.flatten(tol)).collect()
    }
}

/// One MFS solve spent modelling, as reported to the user.
#[derive(Clone, Debug, PartialEq)]
pub struct PartReport {
    /// What was solved, e.g. `m2 = Γ(0.85) of m1` or `Q: subtract`.
    pub label: String,
    /// Singularities N.
    pub n: usize,
    /// Collocation points M.
    pub m: usize,
    /// Pseudo-boundary distance, design units (0 for a composite: its points are kept).
    pub distance: f64,
    /// Max boundary error over the check points.
    pub max_error: f64,
    /// Seconds spent (wall clock).
    pub seconds: f64,
}

/// The frame shared by all parts: the outer circle and the flattening tolerance.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// Centre of the outer circle.
    pub centre: Vec2,
    /// Its radius.
    pub radius: f64,
    /// Diagonal of the primitives' bounding box (the length scale).
    pub size: f64,
}

impl Frame {
    /// The frame for primitives with this bounding box.
    pub fn around(lo: Vec2, hi: Vec2) -> Frame {
        let size = (hi - lo).norm();
        Frame {
            centre: (lo + hi) * 0.5,
            radius: OUTER_RADIUS_FACTOR * size,
            size,
        }
    }

    fn flat_tol(&self) -> f64 {
        1e-5 * self.size
    }
}

/// Solve the problem of a boundary: `outer` says whether the outer circle is in the
/// void; a sink goes inside every contour flagged as a counter, at the point of
/// the void inside it farthest from the boundary. The pseudo-boundary distance is
/// chosen (`field::solve_with`).
#[allow(clippy::too_many_arguments)]
fn solve_boundary(
    name: &str,
    contours: Vec<Contour>,
    is_counter: Vec<bool>,
    outer: bool,
    csg: Csg,
    frame: &Frame,
    n: Option<usize>,
    label: String,
) -> Result<(Model, PartReport), ComposeError> {
    let t0 = Instant::now();
    let flat_tol = frame.flat_tol();
    let polys: Vec<Vec<Vec2>> = contours.iter().map(|c| c.flatten(flat_tol)).collect();
    let index = DistanceIndex::new(&polys);
    let mut sinks = Vec::new();
    for (ci, poly) in polys.iter().enumerate() {
        if !is_counter[ci] {
            continue;
        }
        let Some((lo, hi)) = polygons_bbox(std::slice::from_ref(poly)) else {
            continue;
        };
        let inside = |p: Vec2| polygon_winding_number(poly, p) != 0 && !csg.contains(p);
        let (centre, room) = deepest_point_in(lo, hi, &inside, &index);
        if room <= 0.0 {
            return Err(part_err(name, PartFault::HoleWithoutRoom));
        }
        sinks.push(Sink {
            centre,
            radius: 0.25 * room,
        });
    }
    let boundary = Boundary::new(
        contours.clone(),
        is_counter.clone(),
        frame.centre,
        frame.radius,
        flat_tol,
    );
    let mut prep = Prepared::with_sinks(boundary, sinks).map_err(|e| field_err(name, e))?;
    prep.outer = outer;
    let regions = is_counter.iter().filter(|c| !**c).count().max(1);
    let n_total = n.unwrap_or(
        AUTO_N_PER_REGION * regions
            + if outer { OUTER_CHARGES } else { 0 }
            + prep.sinks.len() * SINK_CHARGES,
    );
    let solved =
        field::solve_with(&prep, Layout::auto(n_total), None).map_err(|e| field_err(name, e))?;
    let groups = prep
        .groups(&solved.layout)
        .map_err(|e| field_err(name, e))?;
    let report = PartReport {
        label,
        n: solved.layout.n_total,
        m: solved.m,
        distance: solved.layout.distance,
        max_error: solved.solution.max_error,
        seconds: t0.elapsed().as_secs_f64(),
    };
    Ok((
        Model {
            name: name.to_string(),
            set: PointSet {
                material: groups.material,
                interior: Vec::new(),
                outer: groups.outer,
                sinks: groups.sinks,
            },
            field: sampled_fast(solved.solution.field, &polys),
            max_error: solved.solution.max_error,
            contours,
            is_counter,
            csg,
        },
        report,
    ))
}

/// The direct problem (2.1) of a primitive: contours oriented and nested first.
pub fn primitive(
    name: &str,
    contours: Vec<Contour>,
    frame: &Frame,
    n: Option<usize>,
) -> Result<(Model, PartReport), ComposeError> {
    let regions = regions_from_contours(name, contours);
    if regions.is_empty() {
        return Err(part_err(name, PartFault::PrimitiveNoArea));
    }
    let mut cs = Vec::new();
    let mut flags = Vec::new();
    for r in regions {
        cs.push(r.outline);
        flags.push(false);
        for c in r.counters {
            cs.push(c);
            flags.push(true);
        }
    }
    let polys: Vec<Vec<Vec2>> = cs.iter().map(|c| c.flatten(frame.flat_tol())).collect();
    let csg = Csg::Leaf {
        polys,
        complement: false,
    };
    solve_boundary(
        name,
        cs,
        flags,
        true,
        csg,
        frame,
        n,
        format!("{name}: primitive"),
    )
}

/// The inverse problem of a model: the same boundary, material and void swapped.
/// Applied twice it gives back the direct problem.
pub fn invert(
    name: &str,
    m: &Model,
    frame: &Frame,
    n: Option<usize>,
) -> Result<(Model, PartReport), ComposeError> {
    let contours: Vec<Contour> = m.contours.iter().map(Contour::reversed).collect();
    let flags: Vec<bool> = m.is_counter.iter().map(|c| !c).collect();
    let csg = match &m.csg {
        Csg::Not(inner) => (**inner).clone(),
        other => Csg::Not(Box::new(other.clone())),
    };
    solve_boundary(
        name,
        contours,
        flags,
        !m.bounded(),
        csg,
        frame,
        n,
        format!("{name}: inverse problem of {}", m.name),
    )
}

/// Γ(s) of a model's field as rings, material (u ≥ s) on the left.
pub fn level_curves(m: &Model, s: f64, frame: &Frame) -> Result<Vec<Ring>, ComposeError> {
    if !(s > 0.0 && s < 1.0) {
        return Err(part_err(&m.name, PartFault::LevelOutOfRange { s }));
    }
    let polys = m.polygons(frame.flat_tol());
    let (lo0, hi0) = polygons_bbox(&polys).ok_or_else(|| part_err(&m.name, PartFault::Empty))?;
    let inside = |p: Vec2| m.csg.contains(p);
    let mask = |o: Vec2, h: f64, nx: usize, ny: usize| m.csg.grid_mask(o, h, nx, ny);
    // The box grows by half the part's size on each side, doubling each try.
    let sample = |k: usize| {
        let pad = (hi0 - lo0) * (0.5 * f64::powi(2.0, k as i32))
            + Vec2::new(1.0, 1.0) * (0.01 * frame.size);
        let (lo, hi) = (lo0 - pad, hi0 + pad);
        let h = (hi.x - lo.x).max(hi.y - lo.y) / EXTRACT_GRID;
        Grid::sample_masked(&m.field, lo, hi, h, &mask)
    };
    let open = || part_err(&m.name, PartFault::LevelOpen { s });
    let grid = if m.bounded() {
        level::closing_grid(s, 6, sample).ok_or_else(open)?
    } else {
        sample(0)
    };
    let tol = CURVE_TOL * frame.size;
    let rings = level::drop_slivers(isolines_in(&grid, s, &m.field, &inside), grid.h);
    let out: Vec<Ring> = rings
        .into_iter()
        .map(|l| level::refine(&l, &m.field, s, tol))
        .collect();
    if out.is_empty() {
        return Err(part_err(&m.name, PartFault::LevelEmpty { s }));
    }
    Ok(out)
}

/// A part's boundary loops (material on their left) as contours, each with
/// whether it bounds a hole (clockwise: negative area).
fn loop_contours(name: &str, loops: &[Ring]) -> Result<(Vec<Contour>, Vec<bool>), ComposeError> {
    let mut cs = Vec::new();
    let mut flags = Vec::new();
    for l in loops {
        let c = Contour::polygon(l.points()).map_err(|_| part_err(name, PartFault::CurveOpen))?;
        flags.push(l.signed_area() < 0.0);
        cs.push(c);
    }
    Ok((cs, flags))
}

/// A new primitive from closed polygons with the material on their left: the
/// loops around material (counter-clockwise) are outlines, the others counters.
fn from_loops(
    name: &str,
    loops: Vec<Ring>,
    bounded: bool,
    frame: &Frame,
    n: Option<usize>,
    label: String,
) -> Result<(Model, PartReport), ComposeError> {
    let (cs, flags) = loop_contours(name, &loops)?;
    let csg = Csg::Leaf {
        polys: loops.into_iter().map(Ring::into_points).collect(),
        complement: !bounded,
    };
    solve_boundary(name, cs, flags, bounded, csg, frame, n, label)
}

/// Union or intersection of two models by their point sets, solved afresh.
pub fn combine(
    name: &str,
    a: &Model,
    b: &Model,
    op: BoolOp,
    frame: &Frame,
) -> Result<(Model, PartReport), ComposeError> {
    let t0 = Instant::now();
    let (csg, outer) = combined_csg(name, a, b, op)?;
    let (mut material, edges) = boundary_points(a, b, op);
    let mut interior = Vec::new();
    for (k, (me, other)) in [(a, b), (b, a)].into_iter().enumerate() {
        carry_operand(me, other, &edges[1 - k], op, &mut material, &mut interior);
    }
    if material.colloc.is_empty() || material.charges.is_empty() {
        let (a, b) = (a.name.clone(), b.name.clone());
        return Err(part_err(name, PartFault::Disjoint { a, b }));
    }
    add_crossing_clusters(&mut material, a, b, &csg, frame);
    let sinks = enclosed_sinks(a, b, &material, &csg, frame);
    let set = PointSet {
        material,
        interior,
        outer,
        sinks,
    };
    let problem = set.problem();
    let sol = mfs::solve(&problem).map_err(|e| field_err(name, e))?;
    let pts: Vec<Vec<Vec2>> = vec![set.material.colloc.iter().map(|c| c.p).collect()];
    let mut model = Model {
        name: name.to_string(),
        set,
        field: sampled_fast(sol.field, &pts),
        max_error: sol.max_error,
        contours: Vec::new(),
        is_counter: Vec::new(),
        csg,
    };
    let loops = boundary_curve(&model, frame)?;
    (model.contours, model.is_counter) = loop_contours(name, &loops)?;
    let label = match op {
        BoolOp::Union => format!("{name} = {} ∪ {}", a.name, b.name),
        _ => format!("{name} = {} ∩ {}", a.name, b.name),
    };
    let report = PartReport {
        label,
        n: problem.charges.len(),
        m: problem.colloc.len(),
        distance: 0.0,
        max_error: sol.max_error,
        seconds: t0.elapsed().as_secs_f64(),
    };
    Ok((model, report))
}

/// A part's field for sampling: evaluated from local expansions
/// (`Field::accelerated_around`) over the box of `near` grown by half its
/// diagonal, where its level curves and boundary are extracted (grids of
/// 400² points each), and directly beyond.
fn sampled_fast(field: Field, near: &[Vec<Vec2>]) -> Field {
    match polygons_bbox(near) {
        Some((lo, hi)) => field.accelerated_around(lo, hi),
        None => field,
    }
}

/// The exact membership of `a` op `b` and the result's outer circle: a
/// union's only if both operands are bounded, an intersection's if either is.
fn combined_csg(
    name: &str,
    a: &Model,
    b: &Model,
    op: BoolOp,
) -> Result<(Csg, Option<Problem>), ComposeError> {
    Ok(match op {
        BoolOp::Union => (
            Csg::Or(Box::new(a.csg.clone()), Box::new(b.csg.clone())),
            if a.bounded() && b.bounded() {
                a.set.outer.clone()
            } else {
                None
            },
        ),
        BoolOp::Intersect => (
            Csg::And(Box::new(a.csg.clone()), Box::new(b.csg.clone())),
            a.set.outer.clone().or_else(|| b.set.outer.clone()),
        ),
        _ => return Err(part_err(name, PartFault::CombineOp)),
    })
}

/// The collocation and check points of each operand that lie on the result's
/// boundary (a union's outside the other operand, an intersection's inside
/// it), as a problem without charges; and each operand's piece of the
/// boundary (`a`'s first).
fn boundary_points(a: &Model, b: &Model, op: BoolOp) -> (Problem, Vec<Vec<Vec2>>) {
    let on_boundary = |other: &Model, p: Vec2| match op {
        BoolOp::Intersect => other.csg.contains(p),
        _ => !other.csg.contains(p),
    };
    let mut material = Problem::default();
    let mut edges: Vec<Vec<Vec2>> = Vec::new();
    for (me, other) in [(a, b), (b, a)] {
        let m = &me.set.material;
        let kept: Vec<_> = m
            .colloc
            .iter()
            .copied()
            .filter(|c| on_boundary(other, c.p))
            .collect();
        edges.push(kept.iter().map(|c| c.p).collect());
        material.colloc.extend(kept);
        material
            .checks
            .extend(m.checks.iter().copied().filter(|c| on_boundary(other, c.p)));
    }
    (material, edges)
}

/// Distance from `q` to the nearest of `pts` (∞ for none).
fn nearest(q: Vec2, pts: &[Vec2]) -> f64 {
    pts.iter().map(|p| p.dist(q)).fold(f64::INFINITY, f64::min)
}

/// Adds to the result the singularities of operand `me` (combined with
/// `other` by `op`) that it keeps, and its points inside the material;
/// `edge` is `other`'s piece of the result's boundary.
fn carry_operand(
    me: &Model,
    other: &Model,
    edge: &[Vec2],
    op: BoolOp,
    material: &mut Problem,
    interior: &mut Vec<Vec2>,
) {
    let own: Vec<Vec2> = me.set.material.colloc.iter().map(|c| c.p).collect();
    // Singularities: a union keeps all (each lies in its operand's
    // material), an intersection those inside the other operand; but one
    // nearer to the other operand's piece of the result's boundary than
    // half its distance to its own boundary would sit almost on the new
    // boundary, and is dropped.
    material
        .charges
        .extend(me.set.material.charges.iter().copied().filter(|&q| {
            let keep = match op {
                BoolOp::Intersect => other.csg.contains(q),
                _ => true,
            };
            keep && nearest(q, edge) >= 0.5 * nearest(q, &own)
        }));
    // Points inside the material: the paper's union keeps the points of
    // each operand inside the other (u = 1 there); they and those carried
    // from earlier unions stay while inside the result.
    if op == BoolOp::Union {
        interior.extend(
            me.set
                .material
                .colloc
                .iter()
                .map(|c| c.p)
                .filter(|&p| other.csg.contains(p)),
        );
    }
    // An interior point of u = 1 next to a piece of boundary that this
    // intersection or subtraction creates would contradict the field
    // rising above 1 into the material there (the Q's tail m5 inside the
    // ring, next to the counter m3: a max error of 7.8e-3 with them). Those
    // nearer to the other operand's piece of the result's boundary than
    // twice the operand's typical singularity distance are dropped. (Near
    // the old boundary, at a union's notch, they stay: there u − 1 ~ r² is
    // flat and they agree with it.)
    let typical = {
        let mut ds: Vec<f64> = own
            .iter()
            .map(|&p| nearest(p, &me.set.material.charges))
            .collect();
        ds.sort_by(f64::total_cmp);
        ds.get(ds.len() / 2).copied().unwrap_or(0.0)
    };
    interior.extend(me.set.interior.iter().copied().filter(|&p| {
        op == BoolOp::Union || (other.csg.contains(p) && nearest(p, edge) >= 2.0 * typical)
    }));
}

/// The operands' sinks that stay: only those in a hole of the result, in its
/// void and shut in by its material (`csg`) in each of 32 directions within
/// the reach of the result's boundary points. A sink of B where B sticks out
/// of A (A − B opens onto the outside there) would put u = 0 in the void that
/// belongs to the outer circle (measured on two rectangles: max error 6.1e-3
/// with it, 5.8e-4 without).
fn enclosed_sinks(
    a: &Model,
    b: &Model,
    material: &Problem,
    csg: &Csg,
    frame: &Frame,
) -> Vec<(Sink, Problem)> {
    let pts: Vec<Vec2> = material.colloc.iter().map(|c| c.p).collect();
    let (lo, hi) = polygons_bbox(&[pts]).unwrap_or((Vec2::ZERO, Vec2::ZERO));
    let reach = (hi - lo).norm();
    let enclosed = |c: Vec2| {
        let step = 1e-3 * frame.size;
        (0..32).all(|k| {
            let t = std::f64::consts::TAU * k as f64 / 32.0;
            let d = Vec2::new(t.cos(), t.sin());
            let mut r = 0.0;
            while r < reach {
                r += step;
                if csg.contains(c + d * r) {
                    return true;
                }
            }
            false
        })
    };
    a.set
        .sinks
        .iter()
        .chain(&b.set.sinks)
        .filter(|(s, _)| !csg.contains(s.centre) && enclosed(s.centre))
        .cloned()
        .collect()
}

/// Singularities clustered at each crossing of the operands' boundaries that is a
/// convex corner of the result (β < π: an intersection's or a subtraction's
/// corners), where u − 1 ~ r^(π/α), α = 2π − β > π, is singular in its gradient.
/// The operands' own pseudo-boundaries leave a gap there: their singularities
/// within about d of the corner fall outside the result and are dropped. As for a
/// glyph's corners (`field::setup`), charges go along the bisector at
/// δⱼ = δ_max exp(−σ(√n − √j)), each with two collocation points on the result's
/// boundary at distance δⱼ from the corner, one on each side.
fn add_crossing_clusters(pr: &mut Problem, a: &Model, b: &Model, csg: &Csg, frame: &Frame) {
    use crate::field::setup::CLUSTER_SIGMA;
    use crate::field::Condition;
    let tol = frame.flat_tol();
    let pa = a.polygons(tol);
    let pb = b.polygons(tol);
    let edges = |ps: &[Vec<Vec2>]| -> Vec<(Vec2, Vec2)> {
        ps.iter()
            .flat_map(|p| (0..p.len()).map(move |i| (p[i], p[(i + 1) % p.len()])))
            .collect()
    };
    let (ea, eb) = (edges(&pa), edges(&pb));
    let mut crossings: Vec<Vec2> = Vec::new();
    for &(p, q) in &ea {
        for &(r, t) in &eb {
            let Some((u, v)) = line_crossing(p, q - p, r, t - r) else {
                continue;
            };
            if (0.0..1.0).contains(&u) && (0.0..1.0).contains(&v) {
                let x = p + (q - p) * u;
                if crossings.iter().all(|c| c.dist(x) > 1e-6 * frame.size) {
                    crossings.push(x);
                }
            }
        }
    }
    let all: Vec<(Vec2, Vec2)> = ea.iter().chain(&eb).copied().collect();
    let nearest_on_boundary = |p: Vec2| -> Vec2 {
        let mut best = (f64::INFINITY, p);
        for &(s, e) in &all {
            let d = e - s;
            let t = ((p - s).dot(d) / d.norm2().max(1e-300)).clamp(0.0, 1.0);
            let q = s + d * t;
            let dd = q.dist(p);
            if dd < best.0 {
                best = (dd, q);
            }
        }
        best.1
    };
    const DIRS: usize = 144;
    const N_EACH: usize = 12;
    for &x in &crossings {
        let r0 = 1e-4 * frame.size;
        let dir = |k: f64| {
            let t = std::f64::consts::TAU * k / DIRS as f64;
            Vec2::new(t.cos(), t.sin())
        };
        let inside: Vec<bool> = (0..DIRS)
            .map(|k| csg.contains(x + dir(k as f64) * r0))
            .collect();
        let n_in = inside.iter().filter(|b| **b).count();
        if n_in == 0 || n_in == DIRS {
            continue;
        }
        // One run of material around the crossing, narrower than a half-turn.
        let starts: Vec<usize> = (0..DIRS)
            .filter(|&k| inside[k] && !inside[(k + DIRS - 1) % DIRS])
            .collect();
        if starts.len() != 1 || 2 * n_in >= DIRS {
            continue;
        }
        let k0 = starts[0] as f64;
        let mid = dir(k0 + (n_in as f64 - 1.0) / 2.0);
        let e1 = dir(k0 - 0.5);
        let e2 = dir(k0 + n_in as f64 - 0.5);
        // Room along the bisector: to the result's boundary, capped by the size.
        let mut room = 0.0;
        let step = 1e-3 * frame.size;
        while room < 0.25 * frame.size && csg.contains(x + mid * (room + step)) {
            room += step;
        }
        let dmax = 0.4 * room;
        if dmax <= 0.0 {
            continue;
        }
        let nn = N_EACH as f64;
        for j in 1..=N_EACH {
            let delta = dmax * (-CLUSTER_SIGMA * (nn.sqrt() - (j as f64).sqrt())).exp();
            pr.charges.push(x + mid * delta);
            for e in [e1, e2] {
                let p = nearest_on_boundary(x + e * delta);
                pr.colloc.push(Condition { p, value: 1.0 });
                let c = nearest_on_boundary(x + e * (0.7 * delta));
                pr.checks.push(Condition { p: c, value: 1.0 });
            }
        }
        pr.checks.push(Condition { p: x, value: 1.0 });
    }
}

/// The boundary of a composite, {u = 1} of its own field: Γ(1 − τ), τ 1.5 times
/// the largest deficit 1 − u over its check points, just outside the material, with every vertex checked to lie on
/// that level of the raw field (not on the edge of the membership mask), then
/// each vertex carried onto u = 1 by Newton's method.
fn boundary_curve(m: &Model, frame: &Frame) -> Result<Vec<Ring>, ComposeError> {
    // u falls short of 1 on the boundary by at most the largest deficit over the
    // check points; Γ(1 − τ) must stay outside the material, so τ exceeds it.
    let deficit = m
        .set
        .material
        .checks
        .iter()
        .map(|c| c.value - m.field.value(c.p))
        .fold(0.0, crate::num::max_or_nan);
    if deficit.is_nan() {
        return Err(part_err(&m.name, PartFault::NanOnBoundary));
    }
    let tau = (1.5 * deficit).max(MIN_TAU);
    let s = 1.0 - tau;
    let pts: Vec<Vec2> = m.set.material.colloc.iter().map(|c| c.p).collect();
    let (lo0, hi0) =
        polygons_bbox(&[pts]).ok_or_else(|| part_err(&m.name, PartFault::NoBoundaryPoints))?;
    let pad = (hi0 - lo0) * 0.05 + Vec2::new(1.0, 1.0) * (0.01 * frame.size);
    let (lo, hi) = (lo0 - pad, hi0 + pad);
    let h = (hi.x - lo.x).max(hi.y - lo.y) / EXTRACT_GRID;
    let inside = |p: Vec2| m.csg.contains(p);
    let mask = |o: Vec2, h: f64, nx: usize, ny: usize| m.csg.grid_mask(o, h, nx, ny);
    let grid = Grid::sample_masked(&m.field, lo, hi, h, &mask);
    let loops = level::drop_slivers(isolines_in(&grid, s, &m.field, &inside), h);
    if loops.is_empty() {
        let max_error = m.max_error;
        return Err(part_err(
            &m.name,
            PartFault::NoBoundaryCurve { s, max_error },
        ));
    }
    for l in &loops {
        for &p in l.points() {
            let u = m.field.value(p);
            if (u - s).abs() > 1e-6 {
                let (at, max_error) = (p, m.max_error);
                return Err(part_err(&m.name, PartFault::Unreached { at, u, max_error }));
            }
        }
    }
    // Onto u = 1 itself: Newton along ∇u from each vertex of Γ(1 − τ), steps at
    // most one grid spacing, kept only if it lands within 60 spacings and where u
    // is 1 to τ/2. Where the material has a re-entrant corner (a union's notch)
    // u − 1 ~ r² and Γ(1 − τ) cuts the corner by about √τ of the size: there the
    // vertices slide onto the walls and the chord refinement puts the corner back.
    let limits = Limits {
        eps: 1e-12,
        max_step: h,
        ..Limits::steps(100, 60.0 * h)
    };
    let onto_one = |p: Vec2| -> Vec2 {
        level::project(&m.field, p, 1.0, &limits)
            .filter(|&q| (m.field.value(q) - 1.0).abs() <= 0.5 * tau)
            .unwrap_or(p)
    };
    let tol = CURVE_TOL * frame.size;
    // A ring whose vertices all but meet on u = 1 bounds nothing: not a curve.
    loops
        .into_iter()
        .map(|l| {
            let on = Ring::new(l.points().iter().map(|&p| onto_one(p)).collect())
                .ok_or_else(|| part_err(&m.name, PartFault::CurveOpen))?;
            Ok(level::refine(&on, &m.field, 1.0, tol))
        })
        .collect()
}

/// A polygon that crosses itself, split at each crossing into simple loops (the
/// paper's tail m4 crosses itself near its tip: (100, 120)–(280, 20) and
/// (300, 50)–(270, 20)). Each loop is then taken as material (non-zero winding);
/// with a loop's boundary running the wrong way the MFS singularities would sit
/// outside it (measured: max boundary error 0.2 for m4 as given).
pub fn split_at_crossings(poly: Vec<Vec2>) -> Vec<Vec<Vec2>> {
    let n = poly.len();
    for i in 0..n {
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (p, q) = (poly[i], poly[(i + 1) % n]);
            let (r, t) = (poly[j], poly[(j + 1) % n]);
            let Some((u, v)) = line_crossing(p, q - p, r, t - r) else {
                continue;
            };
            if u > 0.0 && u < 1.0 && v > 0.0 && v < 1.0 {
                let x = p + (q - p) * u;
                let mut a: Vec<Vec2> = poly[..=i].to_vec();
                a.push(x);
                a.extend_from_slice(&poly[j + 1..]);
                let mut b = vec![x];
                b.extend_from_slice(&poly[i + 1..=j]);
                let mut out = split_at_crossings(a);
                out.extend(split_at_crossings(b));
                return out;
            }
        }
    }
    vec![poly]
}

/// The contours of a primitive part in design units.
fn primitive_contours(part: &Part) -> Result<Option<Vec<Contour>>, ComposeError> {
    let geo = |e: GeometryError| ComposeError::Geometry {
        part: part.name.clone(),
        source: e,
    };
    Ok(match &part.source {
        PartSource::Polygon(pts) => {
            let mut cs = Vec::new();
            for mut l in split_at_crossings(pts.clone()) {
                if polygon_area(&l) < 0.0 {
                    l.reverse();
                }
                if polygon_area(&l).abs() > 0.0 {
                    cs.push(
                        Contour::polygon(&l)
                            .map_err(|_| part_err(&part.name, PartFault::PolygonOpen))?,
                    );
                }
            }
            Some(cs)
        }
        PartSource::Svg(d) => Some(svgpath::path_contours(d).map_err(geo)?),
        PartSource::Text { text, font, size } => {
            let shape = build_shape(&ShapeSource::Text {
                text: text.clone(),
                font: font.clone(),
                height: *size,
                letter_spacing: 0.0,
                line_spacing: None,
                align: crate::geometry::Align::Left,
                origin: Vec2::ZERO,
                as_lines: false,
            })
            .map_err(geo)?;
            Some(shape.contours().cloned().collect())
        }
        PartSource::Ref(_) | PartSource::Op { .. } => None,
    })
}

/// Everything a composition produced.
#[derive(Clone, Debug)]
pub struct Built {
    /// The result in mm, placed and scaled.
    pub shape: Shape,
    /// The result's model in design units.
    pub model: Model,
    /// One report per MFS solve.
    pub reports: Vec<PartReport>,
    /// The frame.
    pub frame: Frame,
    /// Design units → mm: p ↦ origin + (p − lo)·scale.
    pub scale: f64,
}

/// Build the models of a composition and place the result. Parts that do
/// not depend on each other are built in parallel (`order::waves`); each
/// part's model and reports are those of building them one by one in order,
/// and an error is the one the first failing part in order gives.
pub fn build(
    comp: &Composition,
    on_part: &mut dyn FnMut(usize, usize),
) -> Result<Built, ComposeError> {
    let (prims, frame) = primitives_and_frame(comp)?;
    let built = order::build_parts(comp, prims, &frame, on_part)?;
    let (model, reports) = built.result(&comp.result)?;
    if !model.bounded() {
        return Err(part_err(&comp.result, PartFault::Unbounded));
    }
    let (shape, scale) = place(comp, &model, &frame)?;
    Ok(Built {
        shape,
        model,
        reports,
        frame,
        scale,
    })
}

/// Part `part`'s model and the reports of its solves, given the models it
/// may refer to (`models`: the latest earlier part of each name it names).
fn build_part(
    part: &Part,
    prim: Option<Vec<Contour>>,
    models: &Models,
    frame: &Frame,
) -> Result<(Model, Vec<PartReport>), ComposeError> {
    let mut reports = Vec::new();
    let base = part_base(part, prim, models, frame, &mut reports)?;
    let model = at_level(part, base, frame, &mut reports)?;
    Ok((model, reports))
}

/// Every primitive part's contours by name, and the frame from their
/// bounding box.
fn primitives_and_frame(
    comp: &Composition,
) -> Result<(HashMap<&str, Vec<Contour>>, Frame), ComposeError> {
    let mut prims: HashMap<&str, Vec<Contour>> = HashMap::new();
    let mut all: Vec<Vec<Vec2>> = Vec::new();
    for p in &comp.parts {
        if let Some(cs) = primitive_contours(p)? {
            if cs.is_empty() {
                return Err(part_err(&p.name, PartFault::DrawsNothing));
            }
            all.extend(cs.iter().map(|c| c.flatten(1e-3)));
            prims.insert(&p.name, cs);
        }
    }
    let (lo, hi) =
        polygons_bbox(&all).ok_or_else(|| part_err(&comp.result, PartFault::NoPrimitive))?;
    Ok((prims, Frame::around(lo, hi)))
}

/// The model of the part named `of`, which part `who` refers to: an error
/// if it is not defined yet.
fn model_of(models: &Models, of: &str, who: &str) -> Result<Model, ComposeError> {
    models.get(of).map(|m| (*m).clone()).ok_or_else(|| {
        let of = of.to_string();
        part_err(who, PartFault::Undefined { of })
    })
}

/// A part's model before its `level`: its primitive (`prim`, solved here),
/// the part it refers to, or its operation on earlier parts. Each solve's
/// report goes to `reports`.
fn part_base(
    part: &Part,
    prim: Option<Vec<Contour>>,
    models: &Models,
    frame: &Frame,
    reports: &mut Vec<PartReport>,
) -> Result<Model, ComposeError> {
    let name = part.name.as_str();
    if let Some(cs) = prim {
        let (m, r) = primitive(name, cs, frame, part.singularities)?;
        reports.push(r);
        return Ok(m);
    }
    match &part.source {
        PartSource::Ref(of) => {
            let mut m = model_of(models, of, name)?;
            m.name = name.to_string();
            Ok(m)
        }
        PartSource::Op { op, of } => {
            let mut acc = operate(part, *op, of, models, frame, reports)?;
            acc.name = name.to_string();
            Ok(acc)
        }
        _ => Err(part_err(name, PartFault::NoSource)),
    }
}

/// Operation `op` of `part` on the earlier parts `of`, left to right: invert
/// one part; or union, intersect or subtract each further part (subtraction
/// being intersection with the inverse problem of the part taken away).
fn operate(
    part: &Part,
    op: BoolOp,
    of: &[String],
    models: &Models,
    frame: &Frame,
    reports: &mut Vec<PartReport>,
) -> Result<Model, ComposeError> {
    let name = part.name.as_str();
    let first = of
        .first()
        .ok_or_else(|| part_err(name, PartFault::NoOperands))?;
    let mut acc = model_of(models, first, name)?;
    if op == BoolOp::Invert {
        if of.len() != 1 {
            return Err(part_err(name, PartFault::InvertArity));
        }
        let (m, r) = invert(name, &acc, frame, part.singularities)?;
        reports.push(r);
        return Ok(m);
    }
    if of.len() < 2 {
        return Err(part_err(name, PartFault::TooFewOperands));
    }
    for other in &of[1..] {
        let b = model_of(models, other, name)?;
        let (b, kind) = if op == BoolOp::Subtract {
            let iname = format!("{name}: void of {other}");
            let (inv, r) = invert(&iname, &b, frame, None)?;
            reports.push(r);
            (inv, BoolOp::Intersect)
        } else {
            (b, op)
        };
        let (m, mut r) = combine(name, &acc, &b, kind, frame)?;
        if op == BoolOp::Subtract {
            r.label = format!("{name} = {} − {other}", acc.name);
        }
        reports.push(r);
        acc = m;
    }
    Ok(acc)
}

/// A part with a `level` s is the equipotential Γ(s) of its base, solved
/// afresh as a new boundary; without one, the base itself.
fn at_level(
    part: &Part,
    base: Model,
    frame: &Frame,
    reports: &mut Vec<PartReport>,
) -> Result<Model, ComposeError> {
    let Some(s) = part.level else {
        return Ok(base);
    };
    let name = part.name.as_str();
    let loops = level_curves(&base, s, frame)?;
    let (m, r) = from_loops(
        name,
        loops,
        base.bounded(),
        frame,
        part.singularities,
        match &part.source {
            PartSource::Ref(of) => format!("{name} = Γ({s:?}) of {of}"),
            _ => format!("{name} = Γ({s:?}) of its field"),
        },
    )?;
    reports.push(r);
    Ok(m)
}

/// The result placed in mm: its box's lower-left at `comp.origin`, scaled to
/// `comp.height` (else 1:1); and the scale.
fn place(comp: &Composition, model: &Model, frame: &Frame) -> Result<(Shape, f64), ComposeError> {
    let polys = model.polygons(frame.flat_tol());
    let (lo, hi) = polygons_bbox(&polys).ok_or_else(|| part_err(&comp.result, PartFault::Empty))?;
    let scale = match comp.height {
        Some(h) => h / (hi.y - lo.y),
        None => 1.0,
    };
    let origin = comp.origin;
    let placed: Vec<Contour> = model
        .contours
        .iter()
        .map(|c| c.map(|p| origin + (p - lo) * scale))
        .collect();
    let regions = regions_from_contours(&comp.result, placed);
    if regions.is_empty() {
        return Err(part_err(&comp.result, PartFault::ResultNoArea));
    }
    Ok((Shape { regions }, scale))
}
