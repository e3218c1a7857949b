//! Potential fields by the method of fundamental solutions (the paper's Sections 2–4).

use serde::Serialize;

/// What can go wrong building or solving a field.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum FieldError {
    /// The least-squares system is too ill-conditioned to trust.
    #[error("the MFS system is ill-conditioned (estimated condition number {cond:.2e}); try fewer singularities or a larger pseudo-boundary distance")]
    IllConditioned {
        /// estimated condition number
        cond: f64,
    },
    /// A glyph name or shape the field cannot be built for.
    #[error("{0}")]
    Invalid(String),
}

/// One row of the convergence study (the paper's Table 3.2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ConvergenceRow {
    /// Singularities N, counting every one.
    pub n: usize,
    /// Collocation points M = 2N.
    pub m: usize,
    /// Pseudo-boundary distance chosen, font units.
    pub distance: f64,
    /// Max boundary error over the check points.
    pub max_error: f64,
}

/// Solve the paper's problem for a built-in glyph (font units, outer circle of
/// radius 1e4 about the barycentre) for each N, M = 2N, the distance chosen to
/// minimise the max boundary error.
pub fn convergence_table(glyph: char, ns: &[usize]) -> Result<Vec<ConvergenceRow>, FieldError> {
    let _ = (glyph, ns);
    Err(FieldError::Invalid("the MFS solver is being built".into()))
}
