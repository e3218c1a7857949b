//! G-code for GRBL 1.1: the writer, a tokenizer with GRBL's modal state (shared by
//! the streamer's resume), the checker behind `pfcam check`, and a token-wise
//! comparator for golden files.
//!
//! Every file pfcam writes starts with the line `(pfcam <version> job <name>)`
//! ([`header_line`]); [`is_pfcam_output`] recognises it, so that a re-run may
//! replace pfcam's own files but never anyone else's.

pub mod check;
pub(crate) mod compare;
pub(crate) mod motion;
pub mod parse;
pub mod writer;

pub use compare::compare_gcode;
pub use compare::GOLDEN_TOLERANCE;
pub use writer::format_duration;
pub(crate) use writer::stock_extent;
pub use writer::write_gcode;
pub use writer::write_gcode_on;
pub use writer::GcodeError;

/// What every pfcam G-code file's first line starts with.
pub(crate) const HEADER_PREFIX: &str = "(pfcam ";

/// The first line of a G-code file for job `name`.
pub(crate) fn header_line(name: &str) -> String {
    format!(
        "{HEADER_PREFIX}{} job {})",
        env!("CARGO_PKG_VERSION"),
        writer::comment_text(name)
    )
}

/// Whether `first_line` is the first line of a file pfcam wrote.
pub(crate) fn is_pfcam_output(first_line: &str) -> bool {
    first_line.starts_with(HEADER_PREFIX) && first_line.trim_end().ends_with(')')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_is_recognised() {
        let h = header_line("mfs-sign");
        assert!(
            h.starts_with("(pfcam ") && h.ends_with(" job mfs-sign)"),
            "{h}"
        );
        assert!(is_pfcam_output(&h));
        assert!(!is_pfcam_output("G21 G90"));
        assert!(!is_pfcam_output("(made by hand)"));
    }
}
