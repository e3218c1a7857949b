//! A harmonic patch as a job describes it (`[shape] kind = "harmonic-bezier"`):
//! the degree, the form, the rectangle and the two rows, placed at an origin.
//! The patch's own coordinates run over [0, X] × [0, Y]; the job's are those
//! plus `origin` (mm).

use super::{Form, HarmonicError, HarmonicPatch};
use crate::geometry::Vec2;

/// The job's description of a harmonic patch (validated when the job is
/// resolved: [`PatchSpec::patch`] succeeds on every resolved spec).
#[derive(Clone, Debug, PartialEq)]
pub struct PatchSpec {
    /// n, the degree along the rows.
    pub(crate) degree: usize,
    /// Square (n × n) or raised ((n + 1) × n, even n).
    pub(crate) form: Form,
    /// [X, Y], mm.
    pub(crate) size: [f64; 2],
    /// Heights of the edge y = 0 at x = jX/n, mm.
    pub(crate) row0: Vec<f64>,
    /// Heights of the edge y = Y, mm.
    pub(crate) row1: Vec<f64>,
    /// Where the patch's corner (0, 0) goes, mm.
    pub(crate) origin: Vec2,
}

impl PatchSpec {
    /// The patch in its own coordinates (errors name the job key).
    pub fn patch(&self) -> Result<HarmonicPatch, HarmonicError> {
        HarmonicPatch::new(self.degree, self.form, self.size, &self.row0, &self.row1)
    }

    /// The rectangle in job coordinates, counter-clockwise from the origin.
    pub(crate) fn rectangle(&self) -> Vec<Vec2> {
        crate::geometry::rectangle(self.origin, self.size)
    }
}

/// The default form of a degree: square for odd n (unique), raised for even
/// n (the form that takes any two rows), as `pfcam harmonic-mould` chooses.
pub(crate) fn default_form(degree: usize) -> Form {
    if degree % 2 == 1 {
        Form::Square
    } else {
        Form::Raised
    }
}
