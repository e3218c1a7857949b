//! A profile job's part as a [`Sections`] source: the shape cut out to
//! `operation.depth`, a prism whose section at every height is the shape
//! itself. It has no field of its own per level (`level_field` is `None`).

use super::sections::{LevelField, Sections};
use crate::geometry::Vec2;

/// The shape's contours, flattened (material on the left), over a depth.
pub(crate) struct PrismSections {
    contours: Vec<Vec<Vec2>>,
    depth: f64,
}

impl PrismSections {
    /// The prism of `contours` (mm, material on the left) from z = −`depth`
    /// to 0.
    pub(crate) fn new(contours: Vec<Vec<Vec2>>, depth: f64) -> PrismSections {
        PrismSections { contours, depth }
    }
}

impl Sections for PrismSections {
    fn z_range(&self) -> (f64, f64) {
        (-self.depth, 0.0)
    }

    fn section(&self, _z: f64) -> Vec<Vec<Vec2>> {
        self.contours.clone()
    }

    /// The prism's sections are all u = 1 of the shape's field: s = 1.
    fn level_value(&self, _z: f64) -> f64 {
        1.0
    }

    fn level_field(&self, _z: f64) -> Option<LevelField> {
        None
    }
}
