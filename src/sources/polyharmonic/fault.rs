//! What is wrong with one input of the polyharmonic solid
//! ([`PolyError::Invalid`](super::PolyError::Invalid)): one variant per
//! cause, holding the numbers its message quotes.

use super::closed::Region;
use super::elements::MAX_PER_EDGE;
use super::envelope::MAX_SAMPLES;
use super::gauss::MAX_ORDER;
use super::kernels::Kernel;
use super::quadrature::MAX_DEPTH;
use super::spec::RAY_STEP;
use super::system::{MAX_POINTS, MAX_UNKNOWNS};
use nalgebra::Vector3;

/// Why an input of the polyharmonic solid is out of range; the key it
/// concerns is [`PolyError::Invalid`](super::PolyError::Invalid)'s.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolyFault {
    /// The box leaves no region for the closed solid round the points.
    #[error("leaves no room for the closed solid: the given points must lie more than one element side inside it")]
    NoRoom,
    /// The closed solid reaches the region searched round the points.
    #[error("= \"closed\", but the solid {{T1 < 0}} reaches the boundary of the region searched round the points, [{:.3}, {:.3}, {:.3}]..[{:.3}, {:.3}, {:.3}] mm (T1 = {t1:.3e} at ({:.3}, {:.3}, {:.3})): it is not closed there; add outside points, or use shape.solid = \"relief\"", region.lo.x, region.lo.y, region.lo.z, region.hi.x, region.hi.y, region.hi.z, at.x, at.y, at.z)]
    NotClosed {
        /// The region searched.
        region: Region,
        /// Where the solid reaches its boundary.
        at: Vector3<f64>,
        /// T₁ there.
        t1: f64,
    },
    /// No node of the coarse grid is inside the closed solid.
    #[error("= \"closed\", but no node of a {step:.3} mm grid round the points is inside the solid (T1 < 0): the solid is empty or thinner than that")]
    EmptySolid {
        /// The coarse grid's spacing (mm).
        step: f64,
    },
    /// A grid over the closed solid's region with too many nodes.
    #[error("{spacing} mm makes more than {} grid nodes over the closed solid's region [{:.3}, {:.3}, {:.3}]..[{:.3}, {:.3}, {:.3}] mm: use a coarser one", super::iso::MAX_NODES, region.lo.x, region.lo.y, region.lo.z, region.hi.x, region.hi.y, region.hi.z)]
    TooFine {
        /// The grid's spacing (mm).
        spacing: f64,
        /// The region it covers.
        region: Region,
    },
    /// The fast field's work region, with its margin, is not inside the box.
    #[error("the work region {:?}..{:?} (with its interpolation margin) must lie strictly inside the box {:?}..{:?}", start.as_slice(), end.as_slice(), lo.as_slice(), hi.as_slice())]
    RegionOutsideBox {
        /// The work region's lower corner, margin included.
        start: Vector3<f64>,
        /// Its upper corner.
        end: Vector3<f64>,
        /// The box's lower corner.
        lo: Vector3<f64>,
        /// The box's upper corner.
        hi: Vector3<f64>,
    },
    /// The fast field's work region needs too many interpolation nodes.
    #[error(
        "the work region needs {nodes} interpolation nodes, more than {}",
        super::fast::MAX_NODES
    )]
    TooManyNodes {
        /// Its nodes (a product of counts, as f64).
        nodes: f64,
    },
    /// `shape.base` not far enough below the highest point.
    #[error("must lie below the highest given point ({zmax}) by more than {RAY_STEP} mm")]
    BaseTooHigh {
        /// The highest point's z.
        zmax: f64,
    },
    /// The relief's ray step, coarse spacing or start out of range.
    #[error("the ray step and the coarse spacing must be finite and > 0, the rays' start above the base")]
    RaySettings,
    /// The relief's rays too many or too long.
    #[error("too many coarse rays or steps along a ray: a smaller rectangle or box")]
    TooManyRays,
    /// The solid reaches where the relief's rays start.
    #[error("the solid reaches the rays' start z = {z:.3} at ({x:.3}, {y:.3}): raise the box top")]
    ReachesStart {
        /// The rays' start z.
        z: f64,
        /// Where: x.
        x: f64,
        /// Where: y.
        y: f64,
    },
    /// No points.
    #[error("no points given: the solid needs at least one")]
    NoPoints,
    /// More unknowns than [`MAX_UNKNOWNS`].
    #[error("{elements} box elements and {points} points make {} unknowns, more than {MAX_UNKNOWNS}: use fewer elements per edge", 2 * elements + points)]
    TooManyUnknowns {
        /// The box elements N.
        elements: usize,
        /// The points M.
        points: usize,
    },
    /// Box data of another length than the elements.
    #[error("box data needs one value per element ({elements})")]
    BoxData {
        /// The box elements.
        elements: usize,
    },
    /// A kernel whose system is not implemented.
    #[error("{kernel:?} needs the l = 1 or l = 3 system, not implemented: use T2 or T2A")]
    KernelUnsupported {
        /// The kernel.
        kernel: Kernel,
    },
    /// More points than [`MAX_POINTS`].
    #[error("at most {MAX_POINTS} points (got {points})")]
    TooManyPoints {
        /// The points given.
        points: usize,
    },
    /// A point not finite or not strictly inside the box.
    #[error("point {number} at {:?} is not strictly inside the box {:?}..{:?}", at.as_slice(), lo.as_slice(), hi.as_slice())]
    PointOutside {
        /// The point's number, from 1.
        number: usize,
        /// The point.
        at: Vector3<f64>,
        /// The box's lower corner.
        lo: Vector3<f64>,
        /// The box's upper corner.
        hi: Vector3<f64>,
    },
    /// Two points closer than the tolerance.
    #[error("points {first} and {second} coincide (within {tol:.1e}); give each point once")]
    Coincide {
        /// The lower number, from 1.
        first: usize,
        /// The higher number, from 1.
        second: usize,
        /// The distance below which points coincide.
        tol: f64,
    },
    /// A box corner not finite, or lo ≥ hi on an axis.
    #[error("needs finite corners with lo < hi on every axis (lo {lo:?}, hi {hi:?})")]
    BadBox {
        /// The lower corner.
        lo: Vector3<f64>,
        /// The upper corner.
        hi: Vector3<f64>,
    },
    /// Elements per face edge outside 1 to [`MAX_PER_EDGE`].
    #[error("elements per face edge must be 1 to {MAX_PER_EDGE} (got {per_edge})")]
    PerEdge {
        /// What was given.
        per_edge: usize,
    },
    /// `kernel.a` not finite and > 0.
    #[error("the ball radius A must be finite and > 0 (got {a})")]
    Radius {
        /// What was given.
        a: f64,
    },
    /// Quadrature order outside 1 to [`MAX_ORDER`].
    #[error("order must be 1 to {MAX_ORDER} (got {order})")]
    Order {
        /// What was given.
        order: usize,
    },
    /// Quadrature ratio not finite and > 0.
    #[error("ratio must be finite and > 0 (got {ratio})")]
    Ratio {
        /// What was given.
        ratio: f64,
    },
    /// Quadrature depth above [`MAX_DEPTH`].
    #[error("max_depth must be ≤ {MAX_DEPTH} (got {max_depth})")]
    Depth {
        /// What was given.
        max_depth: u32,
    },
    /// The envelope's step or tol not finite and > 0.
    #[error("step and tol must be finite and > 0 (got {step}, {tol})")]
    EnvelopeSettings {
        /// The step given.
        step: f64,
        /// The tol given.
        tol: f64,
    },
    /// The envelope's step makes too many samples.
    #[error("step {step} makes more than {MAX_SAMPLES} samples down the box")]
    EnvelopeSamples {
        /// The step given.
        step: f64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The texts are the ones the causes had as strings (the `format!`s
    /// below are the old call sites'), number formats too (issue 16).
    #[test]
    fn messages_are_the_strings_they_replace() {
        let r = Region {
            lo: Vector3::new(-1.234_56, 0.5, -7.0),
            hi: Vector3::new(10.0, 20.000_49, 3.333_3),
        };
        let p = Vector3::new(0.123_45, -9.876_5, 1.0);
        let (v, step, spacing, nodes, zmax) = (-3.2e-5, 0.456_7, 0.01, 1.5e6, 12.5);
        let (n, m, k, tol) = (600, 3, Kernel::T1, 1.0e-9);
        let (s, e) = (Vector3::new(0.0, 0.0, -1.0), Vector3::new(1.0, 2.0, 3.0));
        let cases = [
            (PolyFault::NoRoom, "leaves no room for the closed solid: the given points must lie more than one element side inside it".to_string()),
            (
                PolyFault::NotClosed { region: r, at: p, t1: v },
                format!(
                    "= \"closed\", but the solid {{T1 < 0}} reaches the boundary of the region searched round the points, [{:.3}, {:.3}, {:.3}]..[{:.3}, {:.3}, {:.3}] mm (T1 = {v:.3e} at ({:.3}, {:.3}, {:.3})): it is not closed there; add outside points, or use shape.solid = \"relief\"",
                    r.lo.x, r.lo.y, r.lo.z, r.hi.x, r.hi.y, r.hi.z, p.x, p.y, p.z
                ),
            ),
            (
                PolyFault::EmptySolid { step },
                format!("= \"closed\", but no node of a {step:.3} mm grid round the points is inside the solid (T1 < 0): the solid is empty or thinner than that"),
            ),
            (
                PolyFault::TooFine { spacing, region: r },
                format!(
                    "{spacing} mm makes more than {} grid nodes over the closed solid's region [{:.3}, {:.3}, {:.3}]..[{:.3}, {:.3}, {:.3}] mm: use a coarser one",
                    super::super::iso::MAX_NODES,
                    r.lo.x, r.lo.y, r.lo.z, r.hi.x, r.hi.y, r.hi.z
                ),
            ),
            (
                PolyFault::RegionOutsideBox { start: s, end: e, lo: r.lo, hi: r.hi },
                format!(
                    "the work region {:?}..{:?} (with its interpolation margin) must lie strictly inside the box {:?}..{:?}",
                    s.as_slice(),
                    e.as_slice(),
                    r.lo.as_slice(),
                    r.hi.as_slice()
                ),
            ),
            (
                PolyFault::TooManyNodes { nodes },
                format!("the work region needs {nodes} interpolation nodes, more than {}", super::super::fast::MAX_NODES),
            ),
            (
                PolyFault::BaseTooHigh { zmax },
                format!("must lie below the highest given point ({zmax}) by more than {RAY_STEP} mm"),
            ),
            (PolyFault::RaySettings, "the ray step and the coarse spacing must be finite and > 0, the rays' start above the base".into()),
            (PolyFault::TooManyRays, "too many coarse rays or steps along a ray: a smaller rectangle or box".into()),
            (
                PolyFault::ReachesStart { z: zmax, x: p.x, y: p.y },
                format!("the solid reaches the rays' start z = {:.3} at ({:.3}, {:.3}): raise the box top", zmax, p.x, p.y),
            ),
            (PolyFault::NoPoints, "no points given: the solid needs at least one".into()),
            (
                PolyFault::TooManyUnknowns { elements: n, points: m },
                format!(
                    "{n} box elements and {} points make {} unknowns, more than {MAX_UNKNOWNS}: use fewer elements per edge",
                    m,
                    2 * n + m
                ),
            ),
            (PolyFault::BoxData { elements: n }, format!("box data needs one value per element ({n})")),
            (
                PolyFault::KernelUnsupported { kernel: k },
                format!("{k:?} needs the l = 1 or l = 3 system, not implemented: use T2 or T2A"),
            ),
            (PolyFault::TooManyPoints { points: n }, format!("at most {MAX_POINTS} points (got {})", n)),
            (
                PolyFault::PointOutside { number: m, at: p, lo: r.lo, hi: r.hi },
                format!(
                    "point {} at {:?} is not strictly inside the box {:?}..{:?}",
                    m,
                    p.as_slice(),
                    r.lo.as_slice(),
                    r.hi.as_slice()
                ),
            ),
            (
                PolyFault::Coincide { first: 2, second: m, tol },
                format!("points {} and {} coincide (within {tol:.1e}); give each point once", 2, m),
            ),
            (
                PolyFault::BadBox { lo: r.lo, hi: r.hi },
                format!("needs finite corners with lo < hi on every axis (lo {:?}, hi {:?})", r.lo, r.hi),
            ),
            (
                PolyFault::PerEdge { per_edge: 0 },
                format!("elements per face edge must be 1 to {MAX_PER_EDGE} (got {})", 0),
            ),
            (PolyFault::Radius { a: v }, format!("the ball radius A must be finite and > 0 (got {v})")),
            (PolyFault::Order { order: 65 }, format!("order must be 1 to {MAX_ORDER} (got {})", 65)),
            (PolyFault::Ratio { ratio: f64::NAN }, format!("ratio must be finite and > 0 (got {})", f64::NAN)),
            (PolyFault::Depth { max_depth: 17 }, format!("max_depth must be ≤ {MAX_DEPTH} (got {})", 17)),
            (
                PolyFault::EnvelopeSettings { step, tol: v },
                format!("step and tol must be finite and > 0 (got {}, {})", step, v),
            ),
            (
                PolyFault::EnvelopeSamples { step: spacing },
                format!("step {} makes more than {MAX_SAMPLES} samples down the box", spacing),
            ),
        ];
        for (fault, text) in cases {
            assert_eq!(fault.to_string(), text);
        }
    }
}
