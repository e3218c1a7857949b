//! Typed errors of the polyharmonic solid (`sources::polyharmonic`).

/// Bad input to the polyharmonic solid, or a system that cannot be solved.
/// `key` names the input at fault, as the job keys will when the source is
/// wired into jobs (`points`, `kernel.a`, `box`, `elements`, `quadrature`,
/// `envelope`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolyError {
    /// A parameter or point is out of range; the message says how.
    #[error("{key}: {reason}")]
    Invalid {
        /// The input at fault.
        key: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// The dense system (20) is singular to working precision.
    #[error("points: the system of {size} unknowns is singular (condition estimate {condition:.3e}); spread the points or use a larger kernel.a")]
    Singular {
        /// The number of unknowns 2N + M.
        size: usize,
        /// max |Uᵢᵢ| / min |Uᵢᵢ| of the fully pivoted LU.
        condition: f64,
    },
}

/// Shorthand for [`PolyError::Invalid`].
pub(crate) fn invalid(key: &'static str, reason: impl Into<String>) -> PolyError {
    PolyError::Invalid {
        key,
        reason: reason.into(),
    }
}
