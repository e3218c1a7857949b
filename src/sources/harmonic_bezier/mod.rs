//! Harmonic tensor-product Bézier patches (Arnal and Monterde, "Generating
//! harmonic surfaces for interactive design", Comput. Math. Appl. 2014; the
//! seed paper 003, issue 18): a height field whose inner control points are
//! fixed by two opposite boundary rows through the harmonic condition Δx = 0.
//! docs/method.md §14 has the equations as implemented and the measured
//! figures.

mod bernstein;
mod error;
pub mod mould;
mod net;
mod patch;
pub mod polynomials;
mod range;
mod spec;

pub use error::HarmonicError;
pub use mould::mould;
pub use mould::solve_mould;
pub use mould::Form;
pub use mould::Mould;
pub use mould::MAX_DEGREE;
pub use mould::ROW_SUM_LIMIT;
pub use patch::HarmonicPatch;
pub(crate) use range::HeightRange;
pub(crate) use spec::default_form;
pub(crate) use spec::PatchSpec;
