//! Reading a user's drawing whole, with a size cap (`shape.svg_file`,
//! `shape.dxf_file`): the same checks and messages for every file source.

use std::io::Read;
use std::path::{Path, PathBuf};

use super::Cause;

/// Why a drawing's file cannot be read; the text follows the key (see
/// [`GeometryError::FileRead`](super::GeometryError::FileRead)).
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ReadFault {
    /// The path is a directory.
    #[error("is a directory, not {kind} file: {}", .path.display())]
    Directory {
        /// What the file should be: "an SVG", "a DXF".
        kind: &'static str,
        /// The path.
        path: PathBuf,
    },
    /// No file at the path.
    #[error("no such file: {}", .path.display())]
    NotFound {
        /// The path.
        path: PathBuf,
    },
    /// The file cannot be opened.
    #[error("{source}: {}", .path.display())]
    Open {
        /// The path.
        path: PathBuf,
        /// The system's refusal.
        source: Cause<std::io::Error>,
    },
    /// The file cannot be read to its end.
    #[error("cannot be read: {source}: {}", .path.display())]
    Read {
        /// The path.
        path: PathBuf,
        /// The system's refusal.
        source: Cause<std::io::Error>,
    },
    /// The file is larger than the cap.
    #[error("is larger than {} MiB: {}", .max >> 20, .path.display())]
    TooLarge {
        /// The cap, bytes.
        max: u64,
        /// The path.
        path: PathBuf,
    },
}

/// The bytes of `path`, refused past `max` bytes (never more than `max` + 1
/// read). `kind` is what the file should be, e.g. "an SVG" or "a DXF".
pub(crate) fn read_capped(path: &Path, kind: &'static str, max: u64) -> Result<Vec<u8>, ReadFault> {
    let path_buf = || path.to_path_buf();
    if path.is_dir() {
        return Err(ReadFault::Directory {
            kind,
            path: path_buf(),
        });
    }
    let file = std::fs::File::open(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => ReadFault::NotFound { path: path_buf() },
        _ => ReadFault::Open {
            path: path_buf(),
            source: Cause::new(e),
        },
    })?;
    let mut bytes = Vec::new();
    file.take(max + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| ReadFault::Read {
            path: path_buf(),
            source: Cause::new(e),
        })?;
    if bytes.len() as u64 > max {
        return Err(ReadFault::TooLarge {
            max,
            path: path_buf(),
        });
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The texts are the ones the faults had as strings (issue 16).
    #[test]
    fn faults_say_the_strings_they_replace() {
        let path = PathBuf::from("/drawings/a b.svg");
        let shown = path.display();
        let io = || std::io::Error::new(std::io::ErrorKind::PermissionDenied, "Permission denied");
        let e = io();
        let cases = [
            (
                ReadFault::Directory {
                    kind: "an SVG",
                    path: path.clone(),
                },
                format!("is a directory, not an SVG file: {shown}"),
            ),
            (
                ReadFault::NotFound { path: path.clone() },
                format!("no such file: {shown}"),
            ),
            (
                ReadFault::Open {
                    path: path.clone(),
                    source: Cause::new(io()),
                },
                format!("{e}: {shown}"),
            ),
            (
                ReadFault::Read {
                    path: path.clone(),
                    source: Cause::new(io()),
                },
                format!("cannot be read: {e}: {shown}"),
            ),
            (
                ReadFault::TooLarge {
                    max: 32 << 20,
                    path: path.clone(),
                },
                format!("is larger than {} MiB: {shown}", 32),
            ),
        ];
        for (fault, text) in cases {
            assert_eq!(fault.to_string(), text);
        }
    }

    #[test]
    fn a_missing_file_and_a_directory_are_told_apart() {
        let dir = std::env::temp_dir();
        assert!(matches!(
            read_capped(&dir, "a DXF", 1),
            Err(ReadFault::Directory { kind: "a DXF", .. })
        ));
        let missing = dir.join("pfcam-no-such-drawing.dxf");
        assert_eq!(
            read_capped(&missing, "a DXF", 1),
            Err(ReadFault::NotFound { path: missing })
        );
    }
}
