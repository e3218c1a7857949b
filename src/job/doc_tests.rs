//! docs/job-format.md against the code: its examples parse, every key and
//! range is documented, and mangled jobs never panic.

use super::load::SECTIONS;
use super::*;

const DOC: &str = include_str!("../../docs/job-format.md");

#[test]
fn the_example_is_the_shipped_job() {
    let job = include_str!("../../jobs/mfs-sign.toml");
    let example = DOC
        .split("`jobs/mfs-sign.toml` as shipped")
        .nth(1)
        .and_then(|rest| rest.split("```toml\n").nth(1))
        .and_then(|block| block.split("```").next())
        .expect("docs/job-format.md has the mfs-sign example");
    assert_eq!(example, job, "docs/job-format.md's example is stale");
}

/// (Over 120 lines because it is a list: one line per key of the job
/// format, which is what it checks.)
#[test]
fn every_key_is_documented() {
    let keys = [
        "name",
        "text",
        "shape.lines",
        "shape.line_spacing",
        "shape.align",
        "font",
        "height",
        "letter_spacing",
        "origin",
        "svg_path",
        "svg_file",
        "id",
        "scale",
        "width",
        "dxf_file",
        "layer",
        "join_tolerance",
        "diameter",
        "feed",
        "plunge_feed",
        "spindle",
        "stepdown",
        "top",
        "safe_z",
        "retract_z",
        "kind",
        "side",
        "depth",
        "tolerance",
        "direction",
        "singularities",
        "pseudo_boundary",
        "rapid_rate",
        "spindle_dwell",
        "coolant",
        "arcs",
        "max_arc_radius",
        "travel",
        "work_offset",
        "max_hours",
        "max_file_mb",
        "stepover",
        "ramp_angle",
        "margin",
        "max_scallop",
        "scallop",
        "pattern",
        "corner_radius",
        "s_bottom",
        "s1",
        "s2",
        "steepness",
        "exponent",
        "points",
        "shape.result",
        "shape.kind",
        "shape.degree",
        "shape.form",
        "shape.size",
        "shape.row0",
        "shape.row1",
        "shape.points",
        "shape.inside",
        "shape.outside",
        "shape.points_file",
        "shape.kernel",
        "shape.a",
        "shape.box",
        "shape.elements",
        "shape.base",
        "shape.solid",
        "shape.bottom_size",
        "shape.bottom_exponent",
        "shape.top_size",
        "shape.top_exponent",
        "shape.flare",
        "shape.rise",
        "shape.modes",
        "shape.samples",
        "shape.part.name",
        "shape.part.polygon",
        "shape.part.svg",
        "shape.part.text",
        "shape.part.font",
        "shape.part.size",
        "shape.part.of",
        "shape.part.op",
        "shape.part.level",
        "shape.part.singularities",
        "shape.trim.angles",
        "shape.trim.z",
    ];
    // The text of the section `## `heading``, up to the next `## `.
    let section = |heading: &str| -> &str {
        let h = format!("## `{heading}`");
        let from = DOC
            .find(&h)
            .unwrap_or_else(|| panic!("{heading} is not documented"));
        let rest = &DOC[from + h.len()..];
        &rest[..rest.find("\n## ").unwrap_or(rest.len())]
    };
    for k in keys {
        // `shape.part.level` in `[[shape.part]]`, `shape.result` in `[shape]`.
        let (text, key) = match k.rsplit_once('.') {
            Some(("shape.part", key)) => (section("[[shape.part]]"), key),
            Some(("shape.trim", key)) => (section("[[shape.trim]]"), key),
            Some((table, key)) => (section(&format!("[{table}]")), key),
            None => (DOC, k),
        };
        assert!(
            text.contains(&format!("| `{key}` |")),
            "{k} is not in docs/job-format.md"
        );
    }
    for t in SECTIONS
        .iter()
        .copied()
        .chain(["[shape.part]", "[shape.trim]"])
    {
        assert!(
            DOC.contains(&format!("## `[{t}]`")),
            "[{t}] is not documented"
        );
    }
}

/// Mangled job files (the shipped jobs with bytes dropped, repeated or
/// swapped, numbers replaced by extremes, lines shuffled) always give a job
/// or an error, never a panic; every job that resolves has every numeric
/// key within its documented range. A fixed seed, so a failure repeats.
#[test]
fn mangled_jobs_never_panic() {
    let jobs: Vec<String> = std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/jobs"))
        .expect("jobs/")
        .filter_map(|e| std::fs::read_to_string(e.ok()?.path()).ok())
        .collect();
    assert!(jobs.len() >= 5);
    let mut g = crate::num::testing::Lcg(0x6a6f62);
    let mut next = |n: usize| g.below(n);
    let extremes = [
        "1e300",
        "-1e300",
        "nan",
        "inf",
        "-inf",
        "0",
        "-0.0",
        "1e-320",
        "99999999999999999999",
        "-9223372036854775808",
        "\"\"",
        "[]",
        "[[]]",
        "{}",
        "true",
        "\"auto\"",
        "1.5",
        "-3",
    ];
    let (mut ok, mut refused) = (0, 0);
    for round in 0..3000 {
        let mut text = jobs[round % jobs.len()].clone().into_bytes();
        for _ in 0..1 + next(4) {
            let at = next(text.len());
            match next(5) {
                0 => {
                    let len = next(8).min(text.len() - at);
                    text.drain(at..at + len);
                }
                1 => {
                    let piece: Vec<u8> = text[at..(at + next(40)).min(text.len())].to_vec();
                    let to = next(text.len());
                    text.splice(to..to, piece);
                }
                2 => {
                    let junk = b"=[]{}\"#.,-\n\x00\xff";
                    text.insert(at, junk[next(junk.len())]);
                }
                _ => {
                    // Replace the number after the next `=` by an extreme.
                    let s = String::from_utf8_lossy(&text).into_owned();
                    let from = (at.min(s.len())..=s.len())
                        .find(|&i| s.is_char_boundary(i))
                        .unwrap_or(s.len());
                    if let Some(eq) = s[from..].find('=').map(|i| i + from) {
                        let end = s[eq..].find('\n').map_or(s.len(), |i| eq + i);
                        let new = format!(
                            "{}= {}{}",
                            &s[..eq],
                            extremes[next(extremes.len())],
                            &s[end..]
                        );
                        text = new.into_bytes();
                    }
                }
            }
        }
        let text = String::from_utf8_lossy(&text);
        match parse_job(&text, "fuzz", Path::new(".")) {
            Ok(job) => {
                ok += 1;
                let t = &job.tool;
                for (key, x) in [
                    ("tool.diameter", t.diameter),
                    ("tool.feed", t.feed),
                    ("tool.plunge_feed", t.plunge_feed),
                    ("tool.spindle", t.spindle),
                    ("operation.depth", job.operation.depth),
                    ("stock.margin", job.stock.margin),
                ] {
                    let r = limits::KEYS.iter().find(|(k, _)| *k == key).unwrap().1;
                    assert!(
                        r.contains(x),
                        "round {round}: {key} = {x} resolved from\n{text}"
                    );
                }
            }
            Err(e) => {
                refused += 1;
                assert!(!e.to_string().is_empty());
            }
        }
    }
    // The mutations are neither all harmless nor all fatal.
    assert!(ok > 100 && refused > 100, "ok {ok}, refused {refused}");
}

/// Every range in `limits::KEYS` is the one docs/job-format.md gives on
/// that key's row.
#[test]
fn every_range_is_documented() {
    for (k, range) in limits::KEYS {
        let (table, key) = k.rsplit_once('.').unwrap_or(("", k));
        let heading = if table == "shape.part" {
            "## `[[shape.part]]`".to_string()
        } else {
            format!("## `[{table}]`")
        };
        let from = DOC.find(&heading).unwrap_or_else(|| panic!("{heading}"));
        let rest = &DOC[from + heading.len()..];
        let text = &rest[..rest.find("\n## ").unwrap_or(rest.len())];
        let row = text
            .lines()
            .find(|l| l.starts_with(&format!("| `{key}` |")))
            .unwrap_or_else(|| panic!("{k} has no row"));
        assert!(
            row.contains(&range.interval()),
            "{k}: the row does not say {}: {row}",
            range.interval()
        );
    }
}

/// The first TOML block after `after` in the doc.
fn toml_block(after: &str) -> &'static str {
    let from = DOC
        .find(after)
        .unwrap_or_else(|| panic!("no {after:?} in docs/job-format.md"));
    let start = DOC[from..].find("```toml\n").map(|i| from + i + 8);
    let block = start.and_then(|s| DOC[s..].find("```").map(|e| &DOC[s..s + e]));
    block.unwrap_or_else(|| panic!("no toml example after {after:?} in docs/job-format.md"))
}

#[test]
fn the_documented_example_is_valid() {
    match parse_job(toml_block("\n## Example\n"), "x", Path::new(".")) {
        Ok(j) => assert_eq!(j.name, "mfs-sign"),
        Err(e) => panic!("docs example: {e}"),
    }
}

#[test]
fn the_documented_letter_q_is_the_papers() {
    let doc = parse_job(
        toml_block("### Example: the paper's letter Q"),
        "x",
        Path::new("."),
    )
    .unwrap_or_else(|e| panic!("docs example: {e}"));
    assert_eq!(doc.name, "letter-q");
    let ShapeSource::Composite(mut doc) = doc.shape else {
        panic!("{:?}", doc.shape)
    };
    let ShapeSource::Composite(test) = parse_job(super::tests::Q, "x", Path::new("."))
        .unwrap()
        .shape
    else {
        panic!()
    };
    // The test's m5 sets its singularities; the doc's leaves them to pfcam.
    assert_eq!(doc.parts[4].singularities, None);
    doc.parts[4].singularities = test.parts[4].singularities;
    assert_eq!(doc, test);
}
