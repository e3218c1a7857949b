//! Why a part of a composition could not be modelled, beyond its geometry
//! and its field's solve ([`super::ComposeError::Part`]): one variant per
//! cause, holding the numbers and names its message quotes.

use crate::geometry::Vec2;

/// What went wrong with one part (the part's name is the
/// [`super::ComposeError`]'s).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PartFault {
    /// A hole of the material leaves no room for the sink inside it.
    #[error("a hole of the material has no interior for its sink")]
    HoleWithoutRoom,
    /// A primitive's contours make no region.
    #[error("the primitive encloses no area")]
    PrimitiveNoArea,
    /// `level` not strictly between 0 and 1.
    #[error("level must be strictly between 0 and 1, got {s}")]
    LevelOutOfRange {
        /// The level asked for.
        s: f64,
    },
    /// The part (or the result) has no polygon at all.
    #[error("empty")]
    Empty,
    /// Γ(s) of the part's field has no curve around the part.
    #[error("Γ({s:?}) of its field is empty near the part")]
    LevelEmpty {
        /// The level.
        s: f64,
    },
    /// Γ(s) of the part's field reaches past the largest box searched.
    #[error("Γ({s:?}) of its field does not close within 32 times the part's size; take a level closer to 1")]
    LevelOpen {
        /// The level.
        s: f64,
    },
    /// An extracted curve is not a closed contour.
    #[error("a curve could not be closed")]
    CurveOpen,
    /// The operands of a combination share no boundary.
    #[error("{a} and {b} do not overlap: the result has no boundary")]
    Disjoint {
        /// The first operand's name.
        a: String,
        /// The second operand's name.
        b: String,
    },
    /// `combine` called with another operation (a pfcam bug: its callers
    /// pass only these two).
    #[error("combine takes union or intersect")]
    CombineOp,
    /// The field is NaN at the part's check points (a pfcam bug).
    #[error("its field is not a number (NaN) on its boundary: this is a pfcam bug, please report it with the job file")]
    NanOnBoundary,
    /// The part has no collocation point.
    #[error("no boundary points")]
    NoBoundaryPoints,
    /// The field has no level curve just outside the material.
    #[error(
        "its field has no curve u = {s:.6} near its boundary (max boundary error {max_error:.2e})"
    )]
    NoBoundaryCurve {
        /// The level looked for, 1 − τ.
        s: f64,
        /// The solve's max boundary error.
        max_error: f64,
    },
    /// A vertex of the boundary curve is off the level it was extracted at.
    #[error("its field does not reach u = 1 on the boundary near ({:.3}, {:.3}): u = {u:.4} there (max boundary error {max_error:.2e})", at.x, at.y)]
    Unreached {
        /// The vertex.
        at: Vec2,
        /// The field there.
        u: f64,
        /// The solve's max boundary error.
        max_error: f64,
    },
    /// A polygon primitive's ring is not a closed contour.
    #[error("the polygon is not closed")]
    PolygonOpen,
    /// The result is the void of a part, with no outline of its own.
    #[error("the result is unbounded (the void of a part); use it inside subtract or intersect")]
    Unbounded,
    /// A primitive with no contour.
    #[error("the primitive draws nothing")]
    DrawsNothing,
    /// No part of the composition is a primitive.
    #[error("the composition has no primitive (polygon, svg or text)")]
    NoPrimitive,
    /// An operand named before it is defined (or never).
    #[error("refers to \"{of}\", which is not defined before it")]
    Undefined {
        /// The name referred to.
        of: String,
    },
    /// A part with neither a primitive nor an operation.
    #[error("is neither a primitive nor made of other parts")]
    NoSource,
    /// An operation with an empty operand list.
    #[error("an operation needs operands")]
    NoOperands,
    /// `invert` of other than one part.
    #[error("invert takes exactly one part")]
    InvertArity,
    /// A binary operation with one operand.
    #[error("this operation needs at least two parts")]
    TooFewOperands,
    /// The placed result makes no region.
    #[error("the result encloses no area")]
    ResultNoArea,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The texts are the ones the causes had as strings, number formats too.
    #[test]
    fn messages_are_the_strings_they_replace() {
        let (s, u, e) = (0.999_876_5, 0.912_34, 3.21e-4);
        let at = Vec2::new(1.23456, -7.0);
        let cases = [
            (PartFault::LevelOutOfRange { s: 1e-300 }, format!("level must be strictly between 0 and 1, got {}", 1e-300)),
            (PartFault::LevelEmpty { s }, format!("Γ({s:?}) of its field is empty near the part")),
            (PartFault::LevelOpen { s }, format!("Γ({s:?}) of its field does not close within 32 times the part's size; take a level closer to 1")),
            (PartFault::Disjoint { a: "a".into(), b: "b".into() }, "a and b do not overlap: the result has no boundary".into()),
            (PartFault::NoBoundaryCurve { s, max_error: e }, format!("its field has no curve u = {s:.6} near its boundary (max boundary error {e:.2e})")),
            (PartFault::Unreached { at, u, max_error: e }, format!("its field does not reach u = 1 on the boundary near ({:.3}, {:.3}): u = {u:.4} there (max boundary error {e:.2e})", at.x, at.y)),
            (PartFault::Undefined { of: "q".into() }, "refers to \"q\", which is not defined before it".into()),
        ];
        for (fault, text) in cases {
            assert_eq!(fault.to_string(), text);
        }
    }
}
