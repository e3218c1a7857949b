//! What is wrong with one input of a PDE tube ([`TubeError::Invalid`](super::TubeError::Invalid)).

use super::trim::MAX_TRIM_VERTICES;
use super::MAX_POINTS;

/// Why a curve or parameter does not fit a tube; the key it concerns is
/// [`TubeError::Invalid`](super::TubeError::Invalid)'s.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TubeFault {
    /// A curve whose z (or z component) is not one value.
    #[error("a tube needs it {what}: sample {sample} has z = {z}, sample 0 {z0}")]
    NotFlat {
        /// What the curve must be ("horizontal (one z)", "of constant z
        /// component").
        what: &'static str,
        /// The first sample off sample 0's z, from 0.
        sample: usize,
        /// Its z.
        z: f64,
        /// Sample 0's z.
        z0: f64,
    },
    /// `tol` not finite and > 0.
    #[error("{tol}; must be finite and > 0 (mm)")]
    Tolerance {
        /// What it was given (mm).
        tol: f64,
    },
    /// `points` outside 16 to [`MAX_POINTS`].
    #[error("{points}; must be 16 to {MAX_POINTS}")]
    Points {
        /// What it was given.
        points: usize,
    },
    /// The top curve at the bottom curve's height.
    #[error("at the same height as x0 (z = {z0}): a tube needs depth")]
    NoDepth {
        /// The bottom curve's z.
        z0: f64,
    },
    /// A trim polygon with too few or too many points.
    #[error("trim {trim}: {points} points; a closed polygon needs 3 to {MAX_TRIM_VERTICES}")]
    TrimPoints {
        /// The trim's index, from 0.
        trim: usize,
        /// Its points.
        points: usize,
    },
    /// A trim point with a coordinate that is not finite.
    #[error("trim {trim}: point {point} is not finite")]
    TrimNotFinite {
        /// The trim's index, from 0.
        trim: usize,
        /// The point's index, from 0.
        point: usize,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The texts are the ones the causes had as strings, number formats too
    /// (issue 16).
    #[test]
    fn messages_are_the_strings_they_replace() {
        let (what, j, z, z0) = ("of constant z component", 5, 1.234_567_8, -0.5);
        let (tol, points, i, n) = (-0.01, 12, 2, 100_001);
        let cases = [
            (
                TubeFault::NotFlat {
                    what,
                    sample: j,
                    z,
                    z0,
                },
                format!("a tube needs it {what}: sample {j} has z = {z}, sample 0 {z0}"),
            ),
            (
                TubeFault::Tolerance { tol },
                format!("{tol}; must be finite and > 0 (mm)"),
            ),
            (
                TubeFault::Points { points },
                format!("{points}; must be 16 to {MAX_POINTS}"),
            ),
            (
                TubeFault::NoDepth { z0 },
                format!("at the same height as x0 (z = {z0}): a tube needs depth"),
            ),
            (
                TubeFault::TrimPoints { trim: i, points: n },
                format!("trim {i}: {n} points; a closed polygon needs 3 to {MAX_TRIM_VERTICES}"),
            ),
            (
                TubeFault::TrimNotFinite { trim: i, point: j },
                format!("trim {i}: point {j} is not finite"),
            ),
        ];
        for (fault, text) in cases {
            assert_eq!(fault.to_string(), text);
        }
    }
}
