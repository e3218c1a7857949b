//! What can be wrong with a harmonic Bézier patch: the input (each variant
//! names the job key it would come from, `shape.degree`, `shape.row0`, …) or,
//! in `Internal`, pfcam itself.

/// An error building a harmonic mould or patch.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum HarmonicError {
    /// The degree is below 1 (a patch needs at least two control points a row).
    #[error("shape.degree: a harmonic Bézier patch needs degree 1 or more, got {degree}")]
    DegreeTooLow {
        /// The degree asked for.
        degree: usize,
    },
    /// The degree is above the cap, where f64 no longer keeps the mould's rows
    /// summing to 1 (a constant must stay a constant).
    #[error(
        "shape.degree: {degree} is above the cap {cap}: at degree {first_bad} the harmonic \
         mould's rows, which must sum to exactly 1, sum to 1 only within {error:.1e} in \
         double precision (the limit is {limit:.0e}), so its inner control points would \
         carry rounding of that order times the heights; use degree {cap} or less"
    )]
    DegreeAboveCap {
        /// The degree asked for.
        degree: usize,
        /// The highest degree allowed.
        cap: usize,
        /// The first degree refused, where the error was measured.
        first_bad: usize,
        /// The row-sum error measured at `first_bad`.
        error: f64,
        /// The largest row-sum error accepted.
        limit: f64,
    },
    /// The (n + 1) × n form was asked for with an odd degree.
    #[error(
        "shape.form: the raised (n + 1) × n patch is for even degrees; degree {degree} is odd, \
         and its n × n patch (form = \"square\") is already unique"
    )]
    RaisedOddDegree {
        /// The degree asked for.
        degree: usize,
    },
    /// A boundary row has the wrong number of heights.
    #[error("{key}: degree {degree} needs {expected} heights (degree + 1), got {got}")]
    RowLength {
        /// `shape.row0` or `shape.row1`.
        key: &'static str,
        /// The degree.
        degree: usize,
        /// degree + 1.
        expected: usize,
        /// The number given.
        got: usize,
    },
    /// A height is NaN or infinite.
    #[error("{key}[{index}]: heights must be finite numbers of mm, got {value}")]
    NotFinite {
        /// `shape.row0` or `shape.row1`.
        key: &'static str,
        /// Index in the row.
        index: usize,
        /// The value.
        value: f64,
    },
    /// The patch size is not two positive finite lengths.
    #[error("shape.size: must be [X, Y], two positive finite lengths in mm, got [{x}, {y}]")]
    Size {
        /// X, mm.
        x: f64,
        /// Y, mm.
        y: f64,
    },
    /// An even degree's n × n patch exists only when the two rows have the
    /// same n-th difference (the coefficient of vⁿ along the rows).
    #[error(
        "shape.row0, shape.row1: an n × n harmonic patch of even degree {degree} exists only \
         when the {degree}-th differences of the two rows agree (Δⁿrow0 = {d0}, Δⁿrow1 = {d1}, \
         tolerance {tolerance:.1e}); change the rows, or use form = \"raised\", the \
         ({degree} + 1) × {degree} patch that takes any two rows"
    )]
    EvenRowsDisagree {
        /// The degree.
        degree: usize,
        /// Δⁿ of row0.
        d0: f64,
        /// Δⁿ of row1.
        d1: f64,
        /// The tolerance they were compared with.
        tolerance: f64,
    },
    /// The mould's linear system did not behave as the theory says: a bug in
    /// pfcam, not in the input.
    #[error(
        "harmonic mould of degree {degree}: {what} (this is a bug in pfcam; please report it)"
    )]
    Internal {
        /// The degree.
        degree: usize,
        /// What went wrong.
        what: MouldFault,
    },
}

/// How the mould's linear system misbehaved ([`HarmonicError::Internal`]).
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum MouldFault {
    /// The mould's rows do not sum to 1 within the limit.
    #[error("its rows sum to 1 only within {error:.1e}")]
    RowSum {
        /// The largest |row sum − 1| (or NaN).
        error: f64,
    },
    /// The inner system's R has a (near) zero on its diagonal.
    #[error("the inner system is rank deficient (|R_kk| from {small:.1e} to {big:.1e})")]
    RankDeficient {
        /// The smallest |R_kk|.
        small: f64,
        /// The largest |R_kk|.
        big: f64,
    },
}
