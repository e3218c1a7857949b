//! What is wrong with one input of a PDE surface ([`PdeError::Invalid`](super::PdeError::Invalid)).

use super::MAX_SAMPLES;

/// Why a parameter or curve of a PDE surface is out of range; the key it
/// concerns is [`PdeError::Invalid`](super::PdeError::Invalid)'s.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PdeFault {
    /// A parameter (`a`) that must be finite and positive.
    #[error("must be finite and > 0, got {value}")]
    NotPositive {
        /// What it was given.
        value: f64,
    },
    /// The first curve's sample count is outside 2N + 1 to [`MAX_SAMPLES`].
    #[error("{samples} samples; need 2·modes + 1 = {need} to {MAX_SAMPLES}")]
    SampleCount {
        /// Its samples K.
        samples: usize,
        /// 2N + 1.
        need: usize,
    },
    /// A curve with another sample count than the first.
    #[error("{samples} samples, but {first} has {first_samples}")]
    SampleMismatch {
        /// Its samples.
        samples: usize,
        /// The first curve's key.
        first: &'static str,
        /// The first curve's samples.
        first_samples: usize,
    },
    /// A sample with a coordinate that is not finite.
    #[error("sample {index} is not finite")]
    SampleNotFinite {
        /// The sample's index, from 0.
        index: usize,
    },
    /// The four-curve `s` outside (0, 1).
    #[error("must lie strictly inside (0, 1), got {s}")]
    SOutside {
        /// What it was given.
        s: f64,
    },
    /// The four-curve `t` outside (s, 1).
    #[error("must lie strictly inside (s, 1) = ({s}, 1), got {t}")]
    TOutside {
        /// The curves' s.
        s: f64,
        /// What it was given.
        t: f64,
    },
    /// A trim-map curve that runs clockwise.
    #[error("must run counter-clockwise in the (u, v) plane")]
    Clockwise,
    /// A trim map whose Jacobian is not positive somewhere.
    #[error("the map folds: its Jacobian is {det:.3e} at ξ = {xi:.4}, η = {eta:.4} (curves crossing, or a trim curve too far from star-shaped for a Laplace map)")]
    Folds {
        /// The smallest sampled Jacobian.
        det: f64,
        /// Where: ξ.
        xi: f64,
        /// Where: η.
        eta: f64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The texts are the ones the causes had as strings, number formats too
    /// (issue 16).
    #[test]
    fn messages_are_the_strings_they_replace() {
        let (a, k, modes, j) = (-0.5, 7, 4, 3);
        let (s, t) = (0.25, 0.125);
        let (det, xi, eta) = (-1.234_567e-3, 0.123_456, 2.718_39);
        let need = 2 * modes + 1;
        let cases = [
            (PdeFault::NotPositive { value: a }, format!("must be finite and > 0, got {a}")),
            (
                PdeFault::SampleCount { samples: k, need },
                format!("{k} samples; need 2·modes + 1 = {need} to {MAX_SAMPLES}"),
            ),
            (
                PdeFault::SampleMismatch { samples: 6, first: "x0", first_samples: k },
                format!("{} samples, but x0 has {k}", 6),
            ),
            (PdeFault::SampleNotFinite { index: j }, format!("sample {j} is not finite")),
            (PdeFault::SOutside { s: 1.5 }, format!("must lie strictly inside (0, 1), got {}", 1.5)),
            (
                PdeFault::TOutside { s, t },
                format!("must lie strictly inside (s, 1) = ({}, 1), got {}", s, t),
            ),
            (PdeFault::Clockwise, "must run counter-clockwise in the (u, v) plane".into()),
            (
                PdeFault::Folds { det, xi, eta },
                format!("the map folds: its Jacobian is {det:.3e} at ξ = {xi:.4}, η = {eta:.4} (curves crossing, or a trim curve too far from star-shaped for a Laplace map)"),
            ),
        ];
        for (fault, text) in cases {
            assert_eq!(fault.to_string(), text);
        }
    }
}
