//! Token-wise comparison of G-code files within a numeric tolerance, for golden
//! files (`gcode-samples/*.nc`, as svg2gcode's `tests/*.gcode`).
//!
//! Rules:
//! - comments (`( ... )` and `; ...`) are ignored, so the version line, labels,
//!   and estimates may change freely; blank lines are ignored;
//! - each remaining line is compared word by word: the same letters in the same
//!   order, and numbers within `tol` of each other;
//! - the axis words X, Y, Z and the feed F are modal in the program, so they are
//!   compared as the machine would see them: after every line, the current X, Y,
//!   Z and F of both files must agree within `tol` (a value that rounds to the
//!   same text in one file and not the other then does not count as a change).

/// Tolerance of the golden-file comparison, mm (and mm/min for F): one unit of
/// the last written decimal, so that a rounding flip is not a difference.
pub const GOLDEN_TOLERANCE: f64 = 1e-3;

/// Slack added to the tolerance so that the decimal rounding of two written
/// numbers one unit apart (e.g. `0.001` vs `0.002`) still counts as within it.
const ROUNDING_SLACK: f64 = 1e-9;

/// The first difference between two programs.
#[derive(Debug, Clone, PartialEq)]
pub struct GcodeDiff {
    /// 1-based line in the expected file (0 when it has run out).
    pub(crate) expected_line: usize,
    /// 1-based line in the actual file (0 when it has run out).
    pub(crate) actual_line: usize,
    /// What differs.
    pub(crate) what: String,
}

impl std::fmt::Display for GcodeDiff {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "expected line {}, actual line {}: {}",
            self.expected_line, self.actual_line, self.what
        )
    }
}

/// A program line without comments: its words, and its 1-based line number.
struct CodeLine {
    no: usize,
    text: String,
    words: Vec<(char, f64)>,
}

fn strip_comments(line: &str) -> String {
    let mut out = String::new();
    let mut depth = 0;
    for c in line.chars() {
        match c {
            ';' if depth == 0 => break,
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            c if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out
}

fn code_lines(text: &str) -> Result<Vec<CodeLine>, String> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let code = strip_comments(raw);
        let compact: String = code.chars().filter(|c| !c.is_whitespace()).collect();
        if compact.is_empty() {
            continue;
        }
        let mut words = Vec::new();
        let mut chars = compact.char_indices().peekable();
        while let Some((start, c)) = chars.next() {
            if !c.is_ascii_alphabetic() {
                return Err(format!("line {}: unexpected {c:?} in {raw:?}", i + 1));
            }
            let mut end = start + 1;
            while let Some(&(j, d)) = chars.peek() {
                if d.is_ascii_alphabetic() {
                    break;
                }
                end = j + d.len_utf8();
                chars.next();
            }
            let num = &compact[start + 1..end];
            let v: f64 = num
                .parse()
                .map_err(|_| format!("line {}: bad number {num:?} in {raw:?}", i + 1))?;
            words.push((c.to_ascii_uppercase(), v));
        }
        out.push(CodeLine {
            no: i + 1,
            text: raw.trim().to_string(),
            words,
        });
    }
    Ok(out)
}

const MODAL: [char; 4] = ['X', 'Y', 'Z', 'F'];

/// Compare `actual` with `expected` under the rules of this module; `Ok` when
/// they agree within `tol`, otherwise the first difference.
pub fn compare_gcode(expected: &str, actual: &str, tol: f64) -> Result<(), GcodeDiff> {
    let diff = |e: usize, a: usize, what: String| GcodeDiff {
        expected_line: e,
        actual_line: a,
        what,
    };
    let exp = code_lines(expected).map_err(|w| diff(0, 0, format!("expected file: {w}")))?;
    let act = code_lines(actual).map_err(|w| diff(0, 0, format!("actual file: {w}")))?;
    let close = |a: f64, b: f64| (a - b).abs() <= tol + ROUNDING_SLACK;
    let mut modal_e = [None::<f64>; 4];
    let mut modal_a = [None::<f64>; 4];
    for (e, a) in exp.iter().zip(act.iter()) {
        let plain = |l: &CodeLine| -> Vec<(char, f64)> {
            l.words
                .iter()
                .copied()
                .filter(|(c, _)| !MODAL.contains(c))
                .collect()
        };
        let (pe, pa) = (plain(e), plain(a));
        let same = pe.len() == pa.len()
            && pe
                .iter()
                .zip(pa.iter())
                .all(|((c1, v1), (c2, v2))| c1 == c2 && close(*v1, *v2));
        if !same {
            return Err(diff(e.no, a.no, format!("`{}` vs `{}`", e.text, a.text)));
        }
        for (l, m) in [(e, &mut modal_e), (a, &mut modal_a)] {
            for &(c, v) in &l.words {
                if let Some(i) = MODAL.iter().position(|&x| x == c) {
                    m[i] = Some(v);
                }
            }
        }
        for (i, c) in MODAL.iter().enumerate() {
            let ok = match (modal_e[i], modal_a[i]) {
                (None, None) => true,
                (Some(x), Some(y)) => close(x, y),
                _ => false,
            };
            if !ok {
                return Err(diff(
                    e.no,
                    a.no,
                    format!(
                        "{c} is {:?} vs {:?} after `{}` vs `{}`",
                        modal_e[i], modal_a[i], e.text, a.text
                    ),
                ));
            }
        }
    }
    if exp.len() != act.len() {
        let (e, a) = (exp.get(act.len()), act.get(exp.len()));
        return Err(diff(
            e.map_or(0, |l| l.no),
            a.map_or(0, |l| l.no),
            format!(
                "{} code lines expected, {} found (first extra: `{}`)",
                exp.len(),
                act.len(),
                e.or(a).map_or("", |l| l.text.as_str())
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: &str = "(pfcam 0.1.0 job x)\nG21 G90\nG0 Z5\nG0 X0 Y0\nM3 S1000\nG1 X10 Y0.5 F800\nG2 X20 Y0.5 I5 J0\nM5\nM2\n";

    #[test]
    fn identical_and_comment_changes_pass() {
        assert_eq!(compare_gcode(A, A, GOLDEN_TOLERANCE), Ok(()));
        let b = A.replace(
            "(pfcam 0.1.0 job x)",
            "(pfcam 9.9.9 job x)\n(new comment)\n",
        );
        assert_eq!(compare_gcode(A, &b, GOLDEN_TOLERANCE), Ok(()));
    }

    #[test]
    fn change_within_tolerance_passes() {
        let b = A.replace("Y0.5 F800", "Y0.501 F800");
        assert_eq!(compare_gcode(A, &b, GOLDEN_TOLERANCE), Ok(()));
        let b = A.replace("I5 J0", "I5.001 J-0.001");
        assert_eq!(compare_gcode(A, &b, GOLDEN_TOLERANCE), Ok(()));
    }

    #[test]
    fn change_beyond_tolerance_is_caught() {
        let b = A.replace("G1 X10 Y0.5", "G1 X10.002 Y0.5");
        let d = compare_gcode(A, &b, GOLDEN_TOLERANCE).unwrap_err();
        assert_eq!((d.expected_line, d.actual_line), (6, 6));
        assert!(d.what.contains('X'), "{d}");
        let b = A.replace("I5 J0", "I5 J0.01");
        assert_eq!(
            compare_gcode(A, &b, GOLDEN_TOLERANCE)
                .unwrap_err()
                .expected_line,
            7
        );
    }

    #[test]
    fn different_words_are_caught() {
        let b = A.replace("G2 X20", "G3 X20");
        assert!(compare_gcode(A, &b, GOLDEN_TOLERANCE).is_err());
        let b = A.replace("M5\n", "");
        let d = compare_gcode(A, &b, GOLDEN_TOLERANCE).unwrap_err();
        assert!(d.what.contains("M5") || d.what.contains("M2"), "{d}");
        let b = format!("{A}G0 Z5\n");
        let d = compare_gcode(A, &b, GOLDEN_TOLERANCE).unwrap_err();
        assert!(d.what.contains("8 code lines expected, 9 found"), "{d}");
    }

    #[test]
    fn modal_words_compare_as_state() {
        // The same position written once or twice is the same program.
        let b = A.replace("G2 X20 Y0.5", "G2 X20 Y0.5 Z5");
        assert_eq!(compare_gcode(A, &b, GOLDEN_TOLERANCE), Ok(()));
        // A feed that is dropped changes the state only if its value differs.
        let b = A.replace("I5 J0", "I5 J0 F800");
        assert_eq!(compare_gcode(A, &b, GOLDEN_TOLERANCE), Ok(()));
        let b = A.replace("I5 J0", "I5 J0 F900");
        assert!(compare_gcode(A, &b, GOLDEN_TOLERANCE).is_err());
    }

    #[test]
    fn garbage_is_an_error() {
        assert!(compare_gcode(A, "G1 X1..2\n", GOLDEN_TOLERANCE).is_err());
        assert!(compare_gcode("G1 X1\n", "G1 X1\n#\n", GOLDEN_TOLERANCE).is_err());
    }
}
