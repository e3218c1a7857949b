//! Typed errors of the polyharmonic solid (`sources::polyharmonic`).

use super::fault::PolyFault;

/// Bad input to the polyharmonic solid, or a system that cannot be solved.
/// `key` names the input at fault, as the job keys will when the source is
/// wired into jobs (`points`, `kernel.a`, `box`, `elements`, `quadrature`,
/// `envelope`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolyError {
    /// A parameter or point is out of range; `reason` says how.
    #[error("{key}: {reason}")]
    Invalid {
        /// The input at fault.
        key: &'static str,
        /// What is wrong with it.
        #[source]
        reason: PolyFault,
    },
    /// The closed solid's zero set could not be extracted: the field is not
    /// finite at a node of its grid (key `points`).
    #[error("points: {source}")]
    ZeroSet {
        /// The extraction's refusal.
        source: super::iso::IsoError,
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
pub(crate) fn invalid(key: &'static str, reason: PolyFault) -> PolyError {
    PolyError::Invalid { key, reason }
}

#[cfg(test)]
mod tests {
    use super::super::iso::IsoError;
    use super::PolyError;

    /// The text is the one the cause had as a string (`invalid("points",
    /// e.to_string())`), and the cause stays the error's source (issue 16).
    #[test]
    fn a_zero_set_error_says_the_string_it_replaces() {
        let iso = IsoError::NotFinite {
            at: [1.234_56, -2.0, 0.5],
        };
        let old = iso.to_string();
        let e = PolyError::ZeroSet {
            source: iso.clone(),
        };
        assert_eq!(e.to_string(), format!("points: {old}"));
        let source = std::error::Error::source(&e).expect("a source");
        assert_eq!(source.downcast_ref::<IsoError>(), Some(&iso));
    }
}
