//! Output files on disk: written atomically, and never over someone else's file.
//!
//! A file is first written in full to a temporary file in the same directory
//! (`.<name>.tmp-<pid>-<k>`), flushed to disk, then renamed over the final name,
//! so the final name holds either the old file or the whole new one: an error at
//! any point leaves nothing under the final name. An existing file is replaced
//! only if pfcam wrote it (G-code, SVG, JSON or PNG with pfcam's marker, see
//! [`is_pfcam_file`]) or if the caller forces it.

use crate::gcode::is_pfcam_output;
use std::fs;
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

/// What can go wrong writing an output file.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// An existing file that pfcam did not write.
    #[error("refusing to overwrite {}: it was not written by pfcam (use --force to replace it)", path.display())]
    Foreign {
        /// the file
        path: PathBuf,
    },
    /// Something that is not a regular file is in the way.
    #[error("{} exists and is not a regular file", path.display())]
    NotAFile {
        /// the path
        path: PathBuf,
    },
    /// A symbolic link is in the way (replaced only with `--force`).
    #[error("{} is a symbolic link; use --force to replace the link itself (what it points to is left alone)", path.display())]
    Symlink {
        /// the path
        path: PathBuf,
    },
    /// The output directory cannot be written (checked before a long run).
    #[error("cannot write into {}: {source}", path.display())]
    Unwritable {
        /// the directory
        path: PathBuf,
        /// why
        source: io::Error,
    },
    /// The output directory cannot be created.
    #[error("cannot create directory {}: {source}", path.display())]
    CreateDir {
        /// the directory
        path: PathBuf,
        /// why
        source: io::Error,
    },
    /// Reading, writing or renaming failed.
    #[error("cannot write {}: {source}", path.display())]
    Io {
        /// the file
        path: PathBuf,
        /// why
        source: io::Error,
    },
}

/// Whether the existing file at `path` was written by pfcam (see [`is_pfcam_file`]).
pub(crate) fn written_by_pfcam(path: &Path) -> io::Result<bool> {
    let f = fs::File::open(path)?;
    let mut prefix = Vec::new();
    // The markers are near the start; reading a bounded prefix keeps a huge
    // foreign file from being read whole.
    f.take(PREFIX_LEN).read_to_end(&mut prefix)?;
    Ok(is_pfcam_file(&prefix))
}

/// How much of an existing file [`written_by_pfcam`] reads.
pub(crate) const PREFIX_LEN: u64 = 4096;

/// The PNG signature.
const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// Whether a file starting with `prefix` is one pfcam wrote:
/// - G-code: its first line is `(pfcam <version> job <name>)`;
/// - SVG: its first line is the comment `<!-- pfcam <version> job <name> -->`;
/// - JSON: its first line is `{` and its second the key `"generator": "pfcam <version>"`;
/// - PNG: a `tEXt` chunk `Software` = `pfcam <version>` (written right after the
///   image header).
pub fn is_pfcam_file(prefix: &[u8]) -> bool {
    if prefix.starts_with(PNG_SIGNATURE) {
        let needle = b"tEXtSoftware\0pfcam ";
        return prefix.windows(needle.len()).any(|w| w == needle);
    }
    let text = String::from_utf8_lossy(prefix);
    let mut lines = text.split('\n');
    let first = lines.next().unwrap_or("");
    if is_pfcam_output(first) || crate::preview::is_pfcam_svg(first) {
        return true;
    }
    first.trim_end() == "{"
        && lines
            .next()
            .is_some_and(|l| l.trim_start().starts_with("\"generator\": \"pfcam "))
}

/// Check that `path` may be written: it does not exist, or it is a regular file
/// that pfcam wrote, or `force` is set. A symbolic link is replaced (the link
/// itself, not what it points to) only with `force`.
pub fn check_target(path: &Path, force: bool) -> Result<(), OutputError> {
    match fs::symlink_metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(()),
        Err(source) => Err(OutputError::Io {
            path: path.into(),
            source,
        }),
        Ok(m) if m.file_type().is_symlink() && force => Ok(()),
        Ok(m) if m.file_type().is_symlink() => Err(OutputError::Symlink { path: path.into() }),
        Ok(m) if !m.is_file() => Err(OutputError::NotAFile { path: path.into() }),
        Ok(_) if force => Ok(()),
        Ok(_) => match written_by_pfcam(path) {
            Ok(true) => Ok(()),
            Ok(false) => Err(OutputError::Foreign { path: path.into() }),
            Err(source) => Err(OutputError::Io {
                path: path.into(),
                source,
            }),
        },
    }
}

/// Write `contents` to `path` atomically (see the module docs), creating the
/// parent directory if needed, after [`check_target`].
pub fn write_atomic(path: &Path, contents: &[u8], force: bool) -> Result<(), OutputError> {
    check_target(path, force)?;
    let dir = parent_dir(path)?;
    let io_err = |source| OutputError::Io {
        path: path.into(),
        source,
    };
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    let (tmp, mut file) = create_temp(&dir, &file_name).map_err(io_err)?;
    let written = file
        .write_all(contents)
        .and_then(|()| file.sync_all())
        .and_then(|()| {
            drop(file);
            fs::rename(&tmp, path)
        });
    if let Err(e) = written {
        let _ = fs::remove_file(&tmp);
        return Err(io_err(e));
    }
    Ok(())
}

/// Check, before a long computation, that files can be created in the
/// directory of `path`: the directory is created if missing and a probe file
/// is created there and removed again.
pub fn check_writable(path: &Path) -> Result<(), OutputError> {
    let dir = parent_dir(path)?;
    let (probe, file) =
        create_temp(&dir, "pfcam-probe").map_err(|source| OutputError::Unwritable {
            path: dir.clone(),
            source,
        })?;
    drop(file);
    fs::remove_file(&probe).map_err(|source| OutputError::Unwritable { path: dir, source })
}

/// The directory `path` goes in (`.` for a bare name), created if missing.
fn parent_dir(path: &Path) -> Result<PathBuf, OutputError> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    fs::create_dir_all(&dir).map_err(|source| OutputError::CreateDir {
        path: dir.clone(),
        source,
    })?;
    Ok(dir)
}

/// A new temporary file next to the target, never one that exists already.
fn create_temp(dir: &Path, file_name: &str) -> io::Result<(PathBuf, fs::File)> {
    let pid = std::process::id();
    let mut k = 0u32;
    loop {
        let tmp = dir.join(format!(".{file_name}.tmp-{pid}-{k}"));
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
        {
            Ok(f) => return Ok((tmp, f)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists && k < 100 => k += 1,
            Err(e) => return Err(e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh empty directory under the target dir (no tempfile crate needed).
    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("pfcam-output-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        d
    }

    fn entries(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[cfg(unix)]
    #[test]
    fn a_symlink_is_replaced_only_with_force_and_its_target_kept() {
        let d = scratch("symlink");
        let target = d.join("user-file.nc");
        fs::write(&target, "(pfcam 0.0.1 job x)\n").unwrap();
        let link = d.join("x.nc");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let e = write_atomic(&link, b"(pfcam 0.1.0 job x)\nM2\n", false).unwrap_err();
        assert!(matches!(e, OutputError::Symlink { .. }), "{e}");
        write_atomic(&link, b"(pfcam 0.1.0 job x)\nM2\n", true).unwrap();
        assert!(!fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(
            fs::read_to_string(&target).unwrap(),
            "(pfcam 0.0.1 job x)\n"
        );
        fs::remove_dir_all(&d).unwrap();
    }

    /// /proc takes no new files even from root, so this holds whoever runs it.
    #[cfg(target_os = "linux")]
    #[test]
    fn an_unwritable_directory_is_found_before_the_work() {
        let r = check_writable(Path::new("/proc/pfcam-x.nc"));
        assert!(matches!(r, Err(OutputError::Unwritable { .. })), "{r:?}");
        let d = scratch("writable");
        let file = d.join("a-file");
        fs::write(&file, b"").unwrap();
        let r = check_writable(&file.join("x.nc"));
        assert!(matches!(r, Err(OutputError::CreateDir { .. })), "{r:?}");
        assert!(check_writable(&d.join("new/sub/x.nc")).is_ok());
        assert_eq!(entries(&d.join("new/sub")), Vec::<String>::new());
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn writes_new_file_and_creates_dir() {
        let d = scratch("new");
        let p = d.join("sub/x.nc");
        write_atomic(&p, b"(pfcam 0.1.0 job x)\nM2\n", false).unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "(pfcam 0.1.0 job x)\nM2\n");
        assert_eq!(entries(&d.join("sub")), ["x.nc"]);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn replaces_own_file_but_not_foreign_one() {
        let d = scratch("replace");
        let p = d.join("x.nc");
        fs::write(&p, "(pfcam 0.0.1 job x)\nG0 X1\n").unwrap();
        write_atomic(&p, b"(pfcam 0.1.0 job x)\nM2\n", false).unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "(pfcam 0.1.0 job x)\nM2\n");

        fs::write(&p, "G0 X1 (hand made)\n").unwrap();
        let e = write_atomic(&p, b"(pfcam 0.1.0 job x)\n", false).unwrap_err();
        assert!(matches!(e, OutputError::Foreign { .. }));
        assert!(
            e.to_string().contains("x.nc") && e.to_string().contains("--force"),
            "{e}"
        );
        assert_eq!(fs::read_to_string(&p).unwrap(), "G0 X1 (hand made)\n");
        assert_eq!(entries(&d), ["x.nc"]);

        write_atomic(&p, b"(pfcam 0.1.0 job x)\n", true).unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "(pfcam 0.1.0 job x)\n");
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn recognises_each_kind_of_pfcam_file() {
        for own in [
            "(pfcam 0.1.0 job x)\nM2\n",
            "<!-- pfcam 0.1.0 job x -->\n<svg xmlns=\"http://www.w3.org/2000/svg\"/>\n",
            "{\n  \"generator\": \"pfcam 0.1.0\",\n  \"job\": \"x\"\n}\n",
        ] {
            assert!(is_pfcam_file(own.as_bytes()), "{own}");
        }
        for foreign in [
            "G0 X1\n",
            "<svg xmlns=\"http://www.w3.org/2000/svg\"/>\n<!-- pfcam 0.1.0 job x -->\n",
            "{\"generator\": \"pfcam 0.1.0\"}\n",
            "{\n  \"job\": \"x\",\n  \"generator\": \"pfcam 0.1.0\"\n}\n",
            "",
        ] {
            assert!(!is_pfcam_file(foreign.as_bytes()), "{foreign}");
        }
        let img = crate::preview::colormap::Rgb8 {
            width: 1,
            height: 1,
            data: vec![0, 0, 0],
        };
        let png = crate::preview::colormap::encode_png(&img, "x").unwrap();
        assert!(is_pfcam_file(&png));
        let mut other = png.clone();
        let at = other.windows(8).position(|w| w == b"Software").unwrap();
        other[at..at + 8].copy_from_slice(b"Comment_");
        assert!(!is_pfcam_file(&other));
    }

    #[test]
    fn directory_in_the_way() {
        let d = scratch("dir");
        fs::create_dir(d.join("x.nc")).unwrap();
        let e = write_atomic(&d.join("x.nc"), b"M2\n", true).unwrap_err();
        assert!(matches!(e, OutputError::NotAFile { .. }), "{e}");
        assert_eq!(entries(&d), ["x.nc"]);
        fs::remove_dir_all(&d).unwrap();
    }
}
