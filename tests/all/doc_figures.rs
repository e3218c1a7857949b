//! The figures the docs quote, read back from the docs so that a test can hold
//! each one to the value it computes (issue 15: docs that stay true). A test
//! finds the figure in the doc (a table row by its first cell, or the text
//! after a marker), computes the value, and asserts that the value written the
//! way the doc writes it (same decimals, or same digits in e-notation) is the
//! figure. Nothing here knows an expected value: the doc is the expectation.

/// The text of a doc, `path` relative to the crate root (`docs/method.md`).
pub fn read(path: &str) -> String {
    // The crate root (not `common::root`: the `grbl` test binary includes
    // this file without `common`).
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// `doc` from the first occurrence of `marker` on (to find a table row in the
/// right one of two tables with the same first cells).
pub fn after<'a>(doc: &'a str, doc_name: &str, marker: &str) -> &'a str {
    let at = doc
        .find(marker)
        .unwrap_or_else(|| panic!("{doc_name} no longer says `{marker}`"));
    &doc[at..]
}

/// The cells of the Markdown table row whose first cell is `first` (trimmed,
/// backticks kept), without the row's outer pipes. Panics naming the doc when
/// there is no such row, so a renamed row fails rather than checks nothing.
pub fn table_row<'a>(doc: &'a str, doc_name: &str, first: &str) -> Vec<&'a str> {
    doc.lines()
        .filter_map(|l| l.trim().strip_prefix('|')?.strip_suffix('|'))
        .map(|l| l.split('|').map(str::trim).collect::<Vec<_>>())
        .find(|cells| cells[0] == first)
        .unwrap_or_else(|| panic!("{doc_name} has no table row starting `| {first} |`"))
}

/// `text` with every run of white space (line breaks too) one space, so that a
/// marker may span a line break of the doc.
fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The first number in `doc` after the first occurrence of `marker` (with
/// `·10⁻⁵` read as `e-5` and spaces between digit groups joined), as written.
pub fn number_after(doc: &str, doc_name: &str, marker: &str) -> String {
    let doc = one_line(doc);
    let at = doc
        .find(marker)
        .unwrap_or_else(|| panic!("{doc_name} no longer says `{marker}`"));
    first_number(&doc[at + marker.len()..])
        .unwrap_or_else(|| panic!("{doc_name}: no number after `{marker}`"))
}

/// The first `count` numbers in `doc` after the first occurrence of `marker`,
/// as `number_after` reads them.
pub fn numbers_after(doc: &str, doc_name: &str, marker: &str, count: usize) -> Vec<String> {
    let doc = one_line(doc);
    let at = doc
        .find(marker)
        .unwrap_or_else(|| panic!("{doc_name} no longer says `{marker}`"));
    let mut rest = normalise(&doc[at + marker.len()..]);
    let mut out = Vec::new();
    while out.len() < count {
        let n = first_number(&rest)
            .unwrap_or_else(|| panic!("{doc_name}: fewer than {count} numbers after `{marker}`"));
        let digits = n.trim_start_matches('-');
        let from = rest.find(digits).expect("the number just read") + digits.len();
        rest = rest[from..].to_string();
        out.push(n);
    }
    out
}

/// The first number in `text`, normalised as `number_after` describes.
pub fn first_number(text: &str) -> Option<String> {
    let plain = normalise(text);
    let start = plain.find(|c: char| c.is_ascii_digit())?;
    let neg = plain[..start].ends_with(['-', '−']);
    let rest = &plain[start..];
    let mut end = 0;
    let b = rest.as_bytes();
    while end < b.len() {
        let c = b[end] as char;
        let exp_here = c == 'e'
            && end + 1 < b.len()
            && (b[end + 1].is_ascii_digit() || (b[end + 1] == b'-' && end + 2 < b.len()));
        if c.is_ascii_digit() || (c == '.' && end + 1 < b.len() && b[end + 1].is_ascii_digit()) {
            end += 1;
        } else if exp_here {
            end += if b[end + 1] == b'-' { 2 } else { 1 };
        } else {
            break;
        }
    }
    Some(format!("{}{}", if neg { "-" } else { "" }, &rest[..end]))
}

/// `·10⁻⁵` as `e-5`, `−` as `-`, and a space between digit groups
/// (`301 632`, `45 858.0`) dropped.
fn normalise(text: &str) -> String {
    let sup = |c: char| "⁰¹²³⁴⁵⁶⁷⁸⁹".chars().position(|s| s == c);
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let digit_group = |j: usize| {
            j + 3 <= chars.len()
                && chars[j..j + 3].iter().all(char::is_ascii_digit)
                && chars.get(j + 3).is_none_or(|c| !c.is_ascii_digit())
        };
        if c == '·' && chars.get(i + 1) == Some(&'1') && chars.get(i + 2) == Some(&'0') {
            out.push('e');
            i += 3;
        } else if c == '⁻' {
            out.push('-');
            i += 1;
        } else if let Some(d) = sup(c) {
            out.push(char::from(b'0' + d as u8));
            i += 1;
        } else if c == '−' {
            out.push('-');
            i += 1;
        } else if (c == ' ' || c == '\u{202f}')
            && out.ends_with(|p: char| p.is_ascii_digit())
            && digit_group(i + 1)
        {
            i += 1;
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// `value` written as `figure` is: the same number of decimals, or in
/// e-notation with the same number of mantissa decimals.
pub fn as_written(figure: &str, value: f64) -> String {
    let figure = normalise(figure);
    if let Some((mantissa, _)) = figure.split_once('e') {
        let d = mantissa.split_once('.').map_or(0, |(_, f)| f.len());
        format!("{value:.d$e}")
    } else {
        let d = figure.split_once('.').map_or(0, |(_, f)| f.len());
        format!("{value:.d$}")
    }
}

/// The doc's `figure` is `value` as the doc writes it.
pub fn assert_figure(what: &str, figure: &str, value: f64) {
    let figure = normalise(figure);
    let computed = as_written(&figure, value);
    // `-0.0000` is written `0.0000`.
    let unsigned_zero = |s: &str| {
        s.trim_start_matches('-')
            .chars()
            .all(|c| c == '0' || c == '.')
    };
    let same = computed == figure || (unsigned_zero(&computed) && unsigned_zero(&figure));
    assert!(
        same,
        "{what}: the doc says {figure}, the command now gives {computed} ({value:e}); re-measure and correct the doc"
    );
}
