//! The marker line that starts every SVG pfcam writes, and how pfcam
//! recognises its own files by it.

/// What the first line of every pfcam SVG starts with.
pub(crate) const SVG_MARKER_PREFIX: &str = "<!-- pfcam ";

/// The first line of a pfcam SVG for job `name` (an XML comment before the root
/// element; `--` cannot occur inside a comment, so it is broken up).
pub(crate) fn svg_marker(name: &str) -> String {
    format!(
        "{SVG_MARKER_PREFIX}{} job {} -->",
        env!("CARGO_PKG_VERSION"),
        name.replace("--", "- -").replace('\n', " ")
    )
}

/// Whether `first_line` is the first line of an SVG pfcam wrote.
pub(crate) fn is_pfcam_svg(first_line: &str) -> bool {
    first_line.starts_with(SVG_MARKER_PREFIX) && first_line.trim_end().ends_with("-->")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marker_is_recognised_and_survives_odd_names() {
        let m = svg_marker("a--b");
        assert!(is_pfcam_svg(&m), "{m}");
        assert!(!m[4..m.len() - 3].contains("--"), "{m}");
        assert!(!is_pfcam_svg("<svg xmlns=\"http://www.w3.org/2000/svg\">"));
    }
}
