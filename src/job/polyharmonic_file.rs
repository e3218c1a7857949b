//! `shape.points_file`: the given points of a polyharmonic solid from a CSV
//! or XYZ text file, relative to the job file's directory.
//!
//! One point a line: `x y z` or `x, y, z` (commas, spaces or tabs between
//! fields), optionally a fourth field `surface`, `inside` or `outside` (or
//! `s`, `i`, `o`; surface when absent). Empty lines and lines starting with
//! `#` are skipped, and so is the first other line if its first field is not
//! a number (a CSV header). Errors name `shape.points_file` and the line.

use super::{invalid, JobError};
use crate::sources::polyharmonic::{GivenPoint, PointKind};
use nalgebra::Vector3;
use std::path::Path;

/// Reads the points (with their line as the key, for errors later).
pub(super) fn read_points(
    base_dir: &Path,
    file: &str,
) -> Result<Vec<(String, GivenPoint)>, JobError> {
    const KEY: &str = "shape.points_file";
    if file.trim().is_empty() {
        return Err(invalid(KEY, "must not be empty"));
    }
    let path = base_dir.join(file);
    let meta = std::fs::metadata(&path).map_err(|_| JobError::FileNotFound {
        key: KEY.into(),
        path: path.clone(),
    })?;
    if !meta.is_file() {
        return Err(invalid(KEY, format!("is not a file: {}", path.display())));
    }
    if meta.len() > super::polyharmonic::MAX_FILE_BYTES {
        return Err(invalid(
            KEY,
            format!(
                "is {} bytes, more than the {} a points file may be",
                meta.len(),
                super::polyharmonic::MAX_FILE_BYTES
            ),
        ));
    }
    let text = std::fs::read(&path).map_err(|e| invalid(KEY, format!("cannot be read: {e}")))?;
    let text = String::from_utf8(text).map_err(|_| invalid(KEY, "is not UTF-8 text"))?;
    parse_points(&text)
}

/// The points of a file's text (module doc).
pub(super) fn parse_points(text: &str) -> Result<Vec<(String, GivenPoint)>, JobError> {
    const KEY: &str = "shape.points_file";
    let mut out = Vec::new();
    let mut first = true;
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let numbers: Vec<Option<f64>> = fields.iter().take(3).map(|f| f.parse().ok()).collect();
        if std::mem::take(&mut first) && numbers.first().copied().flatten().is_none() {
            continue;
        }
        let bad = |why: String| invalid(KEY, format!("line {}: {why}", n + 1));
        if !(3..=4).contains(&fields.len()) {
            return Err(bad(format!(
                "needs x, y, z and optionally surface/inside/outside, got {} fields",
                fields.len()
            )));
        }
        let mut p = [0.0; 3];
        for (k, v) in numbers.iter().enumerate() {
            p[k] = v
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(format!("{:?} is not a finite number", fields[k])))?;
        }
        let kind = match fields.get(3).map(|s| s.to_ascii_lowercase()).as_deref() {
            None | Some("surface") | Some("s") => PointKind::Surface,
            Some("inside") | Some("i") => PointKind::Inside,
            Some("outside") | Some("o") => PointKind::Outside,
            Some(k) => return Err(bad(format!("kind {k:?} is not surface, inside or outside"))),
        };
        if out.len() >= crate::sources::polyharmonic::system::MAX_POINTS {
            return Err(bad("too many points".into()));
        }
        out.push((
            format!("{KEY} line {}", n + 1),
            GivenPoint {
                p: Vector3::from(p),
                kind,
            },
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_and_xyz_lines_with_kinds_and_a_header() {
        let pts =
            parse_points("# c\nx,y,z,kind\n1, 2, 3\n# note\n\n4 5 6 inside\n7\t8\t9\to\n").unwrap();
        let kinds: Vec<PointKind> = pts.iter().map(|p| p.1.kind).collect();
        assert_eq!(
            kinds,
            [PointKind::Surface, PointKind::Inside, PointKind::Outside]
        );
        assert_eq!(pts[1].1.p, Vector3::new(4.0, 5.0, 6.0));
        assert_eq!(pts[2].0, "shape.points_file line 7");
    }

    #[test]
    fn bad_lines_name_the_key_and_line() {
        for (text, want) in [
            ("1 2\n", "line 1"),
            ("1 2 3\n1 2 x\n", "line 2"),
            ("1 2 3 middle\n", "kind"),
            ("1 2 nan\n", "finite"),
            ("1 2 3 4 5\n", "fields"),
        ] {
            let e = parse_points(text).unwrap_err().to_string();
            assert!(
                e.contains("shape.points_file") && e.contains(want),
                "{text:?}: {e}"
            );
        }
    }
}
