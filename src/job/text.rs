//! `shape.text` or `shape.lines` with their layout keys (`font`, `height`,
//! `letter_spacing`, `line_spacing`, `align`) into a `ShapeSource::Text`.
//!
//! Several lines are written as an array, `lines = ["ONE", "TWO"]`, one
//! string per line, top to bottom: a TOML multi-line string would carry the
//! file's line endings and a trailing newline into the text. `text` is one
//! line and refuses a line break, pointing at `lines`.

use super::font::{resolve_font, Sources};
use super::{defaults, invalid, limits, JobError};
use crate::geometry::{Align, ShapeSource, Vec2};

/// The text keys of `[shape]` as written.
pub(crate) struct RawText {
    pub(crate) text: Option<String>,
    pub(crate) lines: Option<Vec<String>>,
    pub(crate) font: Option<String>,
    pub(crate) letter_spacing: Option<f64>,
    pub(crate) line_spacing: Option<f64>,
    pub(crate) align: Option<String>,
}

/// The accepted values of `shape.align`.
pub(crate) const ALIGNS: &[&str] = &["left", "centre", "center", "right"];

/// The text source: `height` (already checked) defaults to
/// `defaults::TEXT_HEIGHT`, `letter_spacing` to the tool's diameter.
pub(crate) fn resolve(
    t: RawText,
    height: Option<f64>,
    origin: Vec2,
    tool_diameter: f64,
    src: &Sources<'_>,
) -> Result<ShapeSource, JobError> {
    let (key, text, as_lines) = match (t.text, t.lines) {
        (Some(text), _) => {
            check_line(
                "shape.text",
                &text,
                "write several lines as shape.lines = [\"...\", \"...\"]",
            )?;
            check_text("shape.text", &text)?;
            ("shape.text", text, false)
        }
        (None, Some(lines)) => ("shape.lines", join_lines(&lines)?, true),
        (None, None) => return Err(invalid("shape.text", "or shape.lines is required")),
    };
    let font = resolve_font("shape.font", key, t.font.as_deref(), &text, src)?;
    let letter_spacing = limits::LETTER_SPACING.check(
        "shape.letter_spacing",
        t.letter_spacing.unwrap_or(tool_diameter),
    )?;
    let line_spacing = t
        .line_spacing
        .map(|s| limits::LINE_SPACING.check("shape.line_spacing", s))
        .transpose()?;
    Ok(ShapeSource::Text {
        text,
        font,
        height: height.unwrap_or(defaults::TEXT_HEIGHT),
        letter_spacing,
        line_spacing,
        align: resolve_align(t.align.as_deref())?,
        origin,
        as_lines,
    })
}

/// `shape.align`: `left` (the default), `centre` or `center`, `right`.
fn resolve_align(align: Option<&str>) -> Result<Align, JobError> {
    match align {
        None | Some("left") => Ok(Align::Left),
        Some("centre" | "center") => Ok(Align::Centre),
        Some("right") => Ok(Align::Right),
        Some(other) => Err(invalid(
            "shape.align",
            format!(
                "must be one of {}, got {other:?}",
                ALIGNS
                    .iter()
                    .map(|a| format!("\"{a}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
    }
}

/// `shape.lines` joined by `\n`: 1 to [`limits::MAX_TEXT_LINES`] lines, none
/// with a line break of its own, not all blank, at most
/// [`limits::MAX_TEXT_CHARS`] characters in all. Blank lines are kept (they
/// take their line's space).
fn join_lines(lines: &[String]) -> Result<String, JobError> {
    if lines.is_empty() {
        return Err(invalid("shape.lines", "must have at least one line"));
    }
    if lines.len() > limits::MAX_TEXT_LINES {
        return Err(invalid(
            "shape.lines",
            format!(
                "has {} lines; at most {} are allowed",
                lines.len(),
                limits::MAX_TEXT_LINES
            ),
        ));
    }
    for (i, line) in lines.iter().enumerate() {
        check_line(
            &format!("shape.lines[{}]", i + 1),
            line,
            "give each line as its own string",
        )?;
    }
    let text = lines.join("\n");
    check_text("shape.lines", &text.replace('\n', ""))?;
    Ok(text)
}

/// One line: no line break (`\n`, `\r`, U+2028, U+2029).
pub(crate) fn check_line(key: &str, line: &str, advice: &str) -> Result<(), JobError> {
    match line
        .chars()
        .find(|c| matches!(c, '\n' | '\r' | '\u{2028}' | '\u{2029}'))
    {
        Some(c) => Err(invalid(key, format!("has a line break ({c:?}); {advice}"))),
        None => Ok(()),
    }
}

/// Text to lay out: not blank, and at most `limits::MAX_TEXT_CHARS` characters.
pub(crate) fn check_text(key: &str, text: &str) -> Result<(), JobError> {
    if text.trim().is_empty() {
        return Err(invalid(key, "must not be empty"));
    }
    let n = text.chars().count();
    if n > limits::MAX_TEXT_CHARS {
        return Err(invalid(
            key,
            format!(
                "has {n} characters; at most {} are allowed",
                limits::MAX_TEXT_CHARS
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::geometry::{Align, ShapeSource};
    use crate::job::{parse_job, Job, JobError};
    use std::path::Path;

    fn job(shape: &str) -> Result<Job, JobError> {
        let text =
            format!("[shape]\n{shape}\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n");
        parse_job(&text, "t", Path::new("."))
    }

    fn err(shape: &str) -> String {
        match job(shape) {
            Ok(j) => panic!("expected an error, got {:?}", j.shape),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn lines_align_and_line_spacing() {
        let j = job("lines = [\"MFS\", \"\", \"AH\"]\nalign = \"centre\"\nline_spacing = 1.5")
            .expect("job");
        let ShapeSource::Text {
            text,
            align,
            line_spacing,
            as_lines,
            ..
        } = j.shape
        else {
            panic!("{:?}", j.shape)
        };
        assert_eq!(text, "MFS\n\nAH");
        assert_eq!(
            (align, line_spacing, as_lines),
            (Align::Centre, Some(1.5), true)
        );
        for (word, want) in [
            ("center", Align::Centre),
            ("right", Align::Right),
            ("left", Align::Left),
        ] {
            let j = job(&format!("text = \"MFS\"\nalign = \"{word}\"")).expect("job");
            assert!(
                matches!(j.shape, ShapeSource::Text { align, line_spacing: None, as_lines: false, .. } if align == want)
            );
        }
    }

    #[test]
    fn text_and_lines_errors_name_their_key() {
        let cases = [
            ("text = \"MF\\nS\"", "shape.text has a line break ('\\n'); write several lines as shape.lines"),
            ("lines = []", "shape.lines must have at least one line"),
            ("lines = [\"MF\", \"A\\r\"]", "shape.lines[2] has a line break ('\\r')"),
            ("lines = [\"\", \" \"]", "shape.lines must not be empty"),
            ("lines = [\"MZ\"]", "shape.lines has 'Z', but the font `paper` has no glyph"),
            ("text = \"A\"\nlines = [\"A\"]", "shape.text"),
            ("text = \"A\"\nalign = \"middle\"", "shape.align must be one of \"left\", \"centre\", \"center\", \"right\", got \"middle\""),
            ("text = \"A\"\nline_spacing = 0", "shape.line_spacing"),
            ("text = \"A\"\nline_spacing = 11", "shape.line_spacing"),
            ("svg_path = \"M0 0 H1 V1 Z\"\nalign = \"left\"", "shape.align only applies to shape.text or shape.lines"),
            ("svg_path = \"M0 0 H1 V1 Z\"\nline_spacing = 1", "shape.line_spacing only applies"),
        ];
        for (shape, want) in cases {
            let e = err(shape);
            assert!(e.starts_with(want), "{shape}: {e}");
        }
        let many = format!("lines = [{}]", vec!["\"I\""; 51].join(", "));
        assert!(err(&many).starts_with("shape.lines has 51 lines; at most 50"));
        let long = format!("lines = [\"{}\", \"{}\"]", "I".repeat(100), "I".repeat(101));
        assert!(err(&long).starts_with("shape.lines has 201 characters"));
    }
}
