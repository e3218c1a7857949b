//! Reading a user's drawing whole, with a size cap (`shape.svg_file`,
//! `shape.dxf_file`): the same checks and messages for every file source.

use std::io::Read;
use std::path::Path;

/// The bytes of `path`, refused past `max` bytes (never more than `max` + 1
/// read). `Err` is the message that follows the key: "is a directory, not
/// `kind` file: P", "no such file: P", "cannot be read: E: P" or "is larger
/// than N MiB: P", where `kind` is e.g. "an SVG" or "a DXF".
pub(crate) fn read_capped(path: &Path, kind: &str, max: u64) -> Result<Vec<u8>, String> {
    let shown = path.display();
    if path.is_dir() {
        return Err(format!("is a directory, not {kind} file: {shown}"));
    }
    let file = std::fs::File::open(path).map_err(|e| {
        let why = match e.kind() {
            std::io::ErrorKind::NotFound => "no such file".to_string(),
            _ => e.to_string(),
        };
        format!("{why}: {shown}")
    })?;
    let mut bytes = Vec::new();
    file.take(max + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot be read: {e}: {shown}"))?;
    if bytes.len() as u64 > max {
        return Err(format!("is larger than {} MiB: {shown}", max >> 20));
    }
    Ok(bytes)
}
