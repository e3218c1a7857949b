//! Reading a job: the file, bounded in size ([`read_bounded`]), its TOML
//! parsed and checked table by table against the schema ([`RawJob`]), and
//! every TOML error placed by line, column and dotted key ([`parse_error`]).
//! Resolution is `resolve.rs`'s.

use super::font::{Fonts, Sources};
use super::{echo, invalid, limits, Job, JobError, RawJob};
use std::path::Path;

/// Read and resolve a job file. The job name defaults to the file stem, and a font
/// path is resolved relative to the file's directory.
pub fn load_job(path: &Path) -> Result<Job, JobError> {
    let text = read_bounded(path)?;
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "job".into());
    let base = path.parent().unwrap_or_else(|| Path::new(""));
    parse_job(&text, &stem, base).map_err(|e| e.in_file(path))
}

/// The tables of a job file.
pub(super) const SECTIONS: &[&str] = &[
    "job",
    "shape",
    "tool",
    "stock",
    "operation",
    "field",
    "machine",
    "output",
    "profile",
    "finish",
];

/// Every section is a table: `[[tool]]` (an array of tables) or `tool = 3`
/// would otherwise reach serde, which reads a struct from an array and says
/// `tool[1]: invalid type: map, expected f64`.
fn check_sections(table: &toml::Table) -> Result<(), JobError> {
    for (key, value) in table.iter().filter(|(k, _)| SECTIONS.contains(&k.as_str())) {
        let what = match value {
            toml::Value::Table(_) => continue,
            toml::Value::Array(a) if a.iter().all(|v| v.is_table()) => {
                format!("an array of tables [[{key}]]")
            }
            v => {
                let t = v.type_str();
                let article = if t.starts_with(['a', 'e', 'i', 'o', 'u']) {
                    "an"
                } else {
                    "a"
                };
                format!("{article} {t}")
            }
        };
        return Err(invalid(
            key,
            format!("must be a table, written [{key}], not {what}"),
        ));
    }
    Ok(())
}

/// The text of a job file, refused past `limits::MAX_JOB_BYTES` without reading
/// further (a device such as `/dev/zero`, a log given by mistake) and when it is
/// not a regular file or not UTF-8.
pub(super) fn read_bounded(path: &Path) -> Result<String, JobError> {
    use std::io::Read;
    let read_error = |error| JobError::Read {
        path: path.to_path_buf(),
        error,
    };
    if path.is_dir() {
        return Err(JobError::NotAJob {
            path: path.to_path_buf(),
            why: "it is a directory".into(),
        });
    }
    let file = std::fs::File::open(path).map_err(read_error)?;
    let mut bytes = Vec::new();
    file.take(limits::MAX_JOB_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(read_error)?;
    if bytes.len() as u64 > limits::MAX_JOB_BYTES {
        return Err(JobError::NotAJob {
            path: path.to_path_buf(),
            why: format!(
                "it is larger than {} KiB; a job file is a few kilobytes of TOML",
                limits::MAX_JOB_BYTES / 1024
            ),
        });
    }
    String::from_utf8(bytes).map_err(|e| JobError::NotAJob {
        path: path.to_path_buf(),
        why: format!(
            "it is not UTF-8 text (byte {} is not valid)",
            e.utf8_error().valid_up_to() + 1
        ),
    })
}

/// Parse and resolve job text. `name_hint` is the name used when `[job] name` is
/// absent; `base_dir` is where relative font paths are looked up; font names
/// are looked up among the system's fonts.
pub fn parse_job(text: &str, name_hint: &str, base_dir: &Path) -> Result<Job, JobError> {
    let src = Sources {
        base_dir,
        fonts: Fonts::System,
    };
    parse_job_with(text, name_hint, &src)
}

/// As [`parse_job`], with font names looked up in `src.fonts`.
pub fn parse_job_with(text: &str, name_hint: &str, src: &Sources<'_>) -> Result<Job, JobError> {
    let table: toml::Table = text.parse().map_err(|e| parse_error(text, e))?;
    check_sections(&table)?;
    let raw: RawJob = toml::from_str(text).map_err(|e| parse_error(text, e))?;
    raw.resolve_with(name_hint, src)
}

/// A TOML error placed in `text`: its line, column and dotted key.
pub(super) fn parse_error(text: &str, e: toml::de::Error) -> JobError {
    let pos = e.span().map_or(0, |s| s.start).min(text.len());
    let (line, column) = line_col(text, pos);
    let key = e.span().and_then(|_| key_at(text, pos));
    // TOML puts every key after `[[shape.part]]` into that part.
    let misplaced = key.as_deref().is_some_and(|k| {
        k.starts_with("shape.part[")
            && ["result", "height", "origin"]
                .iter()
                .any(|f| k.ends_with(&format!("].{f}")))
    }) && e.message().trim().starts_with("unknown field");
    JobError::Parse {
        origin: "job".into(),
        line,
        column,
        key: key.map(|k| echo::clip(&k).into_owned()),
        error: Box::new(e),
        misplaced,
    }
}

/// 1-based line and column (in characters) of byte offset `pos`.
fn line_col(text: &str, pos: usize) -> (usize, usize) {
    let before = text.get(..pos).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}

/// The dotted key at byte offset `pos`: the table header when `pos` is in one,
/// otherwise `<last table>.<key before '='>` on that line. A table of an array
/// of tables gets its number, counted from 1: `shape.part[2].polygon`.
fn key_at(text: &str, pos: usize) -> Option<String> {
    let before = text.get(..pos)?;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[pos..].find('\n').map_or(text.len(), |i| pos + i);
    let line = &text[line_start..line_end];
    // `[name]` or `[[name]]`, nothing after it but a comment; not `[0, 1],` in a
    // multi-line array.
    let header = |l: &str| -> Option<(String, bool)> {
        let t = l.trim();
        let array = t.starts_with("[[");
        let open = if array { 2 } else { 1 };
        let t = t.strip_prefix(&"[["[..open])?;
        let end = t.find(']')?;
        let rest = t[end..].strip_prefix(&"]]"[..open])?.trim_start();
        let name = t[..end].trim();
        let ok = !name.is_empty()
            && (rest.is_empty() || rest.starts_with('#'))
            && name
                .chars()
                .all(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | '.' | '"' | '\'' | ' '));
        ok.then(|| (name.to_string(), array))
    };
    // The header's name, numbered if it is an array's: `lines` end with it.
    let named = |lines: &[&str], h: (String, bool)| -> String {
        if h.1 {
            let n = lines
                .iter()
                .filter(|l| header(l).as_ref() == Some(&h))
                .count();
            format!("{}[{n}]", h.0)
        } else {
            h.0
        }
    };
    let lines: Vec<&str> = text[..line_start].lines().collect();
    if let Some(h) = header(line) {
        let mut upto = lines.clone();
        upto.push(line);
        return Some(named(&upto, h));
    }
    // The line with the key: this one, or, inside a multi-line array, the one
    // that opened it (its `[`s not yet closed at `pos`).
    let mut key_line = lines.len();
    let key_text = if line.contains('=') {
        line
    } else {
        let i = lines
            .iter()
            .rposition(|l| l.contains('=') || header(l).is_some())?;
        let open = |s: &str| s.matches('[').count() as i64 - s.matches(']').count() as i64;
        let from = &lines[i][lines[i].find('=')? + 1..];
        let depth = open(from)
            + lines[i + 1..].iter().map(|l| open(l)).sum::<i64>()
            + open(&text[line_start..pos]);
        if depth <= 0 {
            return None;
        }
        key_line = i;
        lines[i]
    };
    let eq = key_text.find('=')?;
    let key = key_text[..eq].trim().trim_matches('"');
    if key.is_empty() {
        return None;
    }
    let table = lines[..key_line]
        .iter()
        .rposition(|l| header(l).is_some())
        .and_then(|i| header(lines[i]).map(|h| named(&lines[..=i], h)));
    Some(match table {
        Some(t) => format!("{t}.{key}"),
        None => key.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::job::load_machine;
    use crate::job::tests::{err_key, parse, q_with, with, GOOD, Q};

    /// A parse error in a file read from disk names the file, whether the
    /// file is a job or a machine file ([`JobError::in_file`]).
    #[test]
    fn a_parse_error_in_a_file_names_the_file() {
        let dir = std::env::temp_dir().join(format!("pfcam-job-origin-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let machine = dir.join("machine.toml");
        std::fs::write(
            &machine,
            "[machine]
rapid_rat = 3000
",
        )
        .unwrap();
        let job = dir.join("job.toml");
        std::fs::write(&job, with("tool", "diamter = 3")).unwrap();
        let m = load_machine(&machine).unwrap_err();
        let j = load_job(&job).unwrap_err();
        std::fs::remove_dir_all(&dir).unwrap();
        for (e, path, key) in [(m, machine, "machine.rapid_rat"), (j, job, "tool.diamter")] {
            let JobError::Parse { origin, .. } = &e else {
                panic!("{e:?}")
            };
            assert_eq!(origin, &path.display().to_string());
            assert_eq!(e.key(), Some(key), "{e}");
        }
        // Text not read from a file keeps `job` as its origin.
        let text = parse(&with("tool", "diamter = 3")).unwrap_err();
        assert!(text.to_string().starts_with("job:"), "{text}");
    }

    #[test]
    fn syntax_error_has_line_and_column() {
        let e = parse("[shape]\ntext = \"A\"\nheight = = 5\n").unwrap_err();
        match &e {
            JobError::Parse { line, column, .. } => {
                assert_eq!(*line, 3);
                assert!(*column >= 8, "column {column}");
            }
            other => panic!("{other:?}"),
        }
        assert!(e.to_string().starts_with("job:3:"), "{e}");
    }

    #[test]
    fn unknown_key_is_named() {
        let (k, msg) = err_key(&with("tool", "diamter = 3.0"));
        assert_eq!(k, "tool.diamter");
        assert!(
            msg.contains("job:8:1: tool.diamter: unknown field"),
            "{msg}"
        );
        let (k, _) = err_key(&with("spindle", "rpm = 3"));
        assert_eq!(k, "spindle");
    }

    #[test]
    fn wrong_type_is_named() {
        let (k, msg) = err_key(&GOOD.replace("height = 50.0", "height = \"tall\""));
        assert_eq!(k, "shape.height");
        assert!(msg.contains("job:6:"), "{msg}");
    }

    #[test]
    fn part_keys_are_named_in_toml_errors() {
        // A misspelt key, a wrong type, and a [shape] key written after the parts.
        let (k, msg) = err_key(&q_with("level = 0.95", "levle = 0.95"));
        assert_eq!(k, "shape.part[3].levle");
        assert!(msg.contains("unknown field `levle`"), "{msg}");
        let (k, msg) = err_key(&q_with("of = \"m4\"", "of = 4"));
        assert_eq!(k, "shape.part[5].of");
        assert!(msg.contains("a part name or a list of part names"), "{msg}");
        // In a multi-line array, the key that opened it.
        let (k, msg) = err_key(&q_with("[50, 120], [100, 120]", "[50, 120], [100]"));
        assert_eq!(k, "shape.part[4].polygon", "{msg}");
        let (k, msg) = err_key(&format!("{Q}result = \"m6\"\n"));
        assert_eq!(k, "shape.part[7].result");
        assert!(
            msg.contains("belong in [shape], above the first [[shape.part]]"),
            "{msg}"
        );
        let (k, _) = err_key(&q_with(
            "polygon = [[0, 0], [100, 0], [100, 300], [0, 300]]",
            "polygon = [[0, 0], [100, 0], \"x\"]",
        ));
        assert_eq!(k, "shape.part[1].polygon");
    }

    #[test]
    fn load_job_names_the_file() {
        let e = load_job(Path::new("/no/such/job.toml")).unwrap_err();
        assert!(matches!(e, JobError::Read { .. }));
        assert!(e.to_string().contains("/no/such/job.toml"), "{e}");
    }
}
