//! `shape.dxf_file` and the keys that go with it: `layer`, `join_tolerance`,
//! `origin`. The file must exist (relative to the job's directory, as a font
//! or SVG file is); it is read when the shape is built. The drawing keeps the
//! size its `$INSUNITS` gives it: `scale`, `width`, `height` do not apply.

use std::path::Path;

use super::{defaults, extent, invalid, limits, JobError};
use crate::geometry::dxffile::DxfFileSource;
use crate::geometry::{ShapeSource, Vec2};

/// The `[shape]` keys of a DXF file job, as written.
pub(crate) struct RawDxfFile {
    /// `dxf_file`
    pub(crate) file: String,
    /// `layer`
    pub(crate) layer: Option<String>,
    /// `join_tolerance`, mm
    pub(crate) join_tolerance: Option<f64>,
    /// Keys given that apply to other sources (`font`, `height`, ...).
    pub(crate) others: Vec<&'static str>,
}

/// The shape source, or an error naming the key.
pub(crate) fn resolve(
    raw: RawDxfFile,
    origin: Vec2,
    tool_diameter: f64,
    base_dir: &Path,
) -> Result<ShapeSource, JobError> {
    if let Some(key) = raw.others.first() {
        return Err(invalid(
            key,
            "does not apply to shape.dxf_file (the drawing keeps the size its $INSUNITS gives; shape.layer, shape.join_tolerance and shape.origin apply)",
        ));
    }
    if raw.layer.as_deref().is_some_and(|l| l.trim().is_empty()) {
        return Err(invalid(
            "shape.layer",
            "must not be empty (the name of a layer of shape.dxf_file)",
        ));
    }
    let join_tolerance = limits::JOIN_TOLERANCE.check(
        "shape.join_tolerance",
        raw.join_tolerance.unwrap_or(defaults::JOIN_TOLERANCE),
    )?;
    if raw.file.trim().is_empty() {
        return Err(invalid("shape.dxf_file", "must not be empty"));
    }
    let path = base_dir.join(&raw.file);
    if path.is_dir() {
        return Err(invalid(
            "shape.dxf_file",
            format!("is a directory, not a DXF file: {}", path.display()),
        ));
    }
    if !path.exists() {
        return Err(JobError::FileNotFound {
            key: "shape.dxf_file".into(),
            path,
        });
    }
    Ok(ShapeSource::DxfFile(DxfFileSource {
        path,
        layer: raw.layer,
        join_tolerance,
        origin,
        tolerance: defaults::TOLERANCE,
        max_size: extent::max_side(tool_diameter),
    }))
}
