//! Jobs: the TOML schema (raw), and the resolved, validated job the pipeline reads.

use crate::geometry::ShapeSource;

/// A resolved job: units in mm, mm/min and rev/min, defaults applied, validated.
#[derive(Clone, Debug, PartialEq)]
pub struct Job {
    /// Job name: output files are `<name>.nc` etc.
    pub name: String,
    /// What to cut.
    pub shape: ShapeSource,
    /// The cutter.
    pub tool: Tool,
    /// The stock.
    pub stock: Stock,
    /// What to do.
    pub operation: Operation,
    /// How to build the potential field.
    pub field: FieldSpec,
}

/// A flat end mill.
#[derive(Clone, Debug, PartialEq)]
pub struct Tool {
    /// Diameter, mm (> 0).
    pub diameter: f64,
    /// Cutting feed, mm/min.
    pub feed: f64,
    /// Plunge feed, mm/min.
    pub plunge_feed: f64,
    /// Spindle speed, rev/min.
    pub spindle: f64,
    /// Largest depth of one pass, mm.
    pub stepdown: f64,
}

/// The stock.
#[derive(Clone, Debug, PartialEq)]
pub struct Stock {
    /// Z of the stock's top surface, mm.
    pub top: f64,
    /// Z for rapid moves, mm (above `top`).
    pub safe_z: f64,
}

/// Operation kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OperationKind {
    /// Cut along the shape's boundary with vertical walls.
    Profile,
}

/// Which side of the material the tool runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Outside the material: outside every outline, inside every counter.
    Outside,
}

/// Milling direction (with a clockwise spindle, M3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Climb: the material on the tool's right (outlines clockwise, counters counter-clockwise).
    Climb,
    /// Conventional: the material on the tool's left.
    Conventional,
}

/// The operation.
#[derive(Clone, Debug, PartialEq)]
pub struct Operation {
    /// Kind.
    pub kind: OperationKind,
    /// Side.
    pub side: Side,
    /// Depth of cut below `stock.top`, mm (> 0).
    pub depth: f64,
    /// Chord and fitting tolerance, mm (> 0).
    pub tolerance: f64,
    /// Climb or conventional.
    pub direction: Direction,
}

/// How the MFS field is set up.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct FieldSpec {
    /// Total number of singularities N; `None` chooses from the shape.
    pub singularities: Option<usize>,
    /// Pseudo-boundary distance in mm; `None` chooses it to minimise the max boundary error.
    pub pseudo_boundary: Option<f64>,
}
