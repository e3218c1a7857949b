//! `shape.svg_file` and the keys that go with it: `id`, `scale`, `width`,
//! `height`, `origin`. The file must exist (relative to the job's directory,
//! as a font file is); it is read when the shape is built.

use std::path::Path;

use super::resolve::at_most_one;
use super::{defaults, extent, invalid, limits, JobError};
use crate::geometry::svgfile::{SvgFileSource, SvgSize};
use crate::geometry::{ShapeSource, Vec2};

/// The `[shape]` keys of an SVG file job, as written.
pub(crate) struct RawSvgFile {
    /// `svg_file`
    pub(crate) file: String,
    /// `id`
    pub(crate) id: Option<String>,
    /// `scale`
    pub(crate) scale: Option<f64>,
    /// `width`, mm
    pub(crate) width: Option<f64>,
    /// `height`, mm (already range-checked)
    pub(crate) height: Option<f64>,
    /// whether `font` was given (it does not apply)
    pub(crate) font: bool,
    /// whether `letter_spacing` was given (it does not apply)
    pub(crate) letter_spacing: bool,
}

/// The shape source, or an error naming the key.
pub(crate) fn resolve(
    raw: RawSvgFile,
    origin: Vec2,
    tool_diameter: f64,
    base_dir: &Path,
) -> Result<ShapeSource, JobError> {
    for (key, given) in [
        ("shape.font", raw.font),
        ("shape.letter_spacing", raw.letter_spacing),
    ] {
        if given {
            return Err(invalid(
                key,
                "only applies to shape.text, not shape.svg_file",
            ));
        }
    }
    let size = size(&raw)?;
    if raw.id.as_deref().is_some_and(|id| id.trim().is_empty()) {
        return Err(invalid(
            "shape.id",
            "must not be empty (the id of an element of shape.svg_file)",
        ));
    }
    if raw.file.trim().is_empty() {
        return Err(invalid("shape.svg_file", "must not be empty"));
    }
    let path = base_dir.join(&raw.file);
    if path.is_dir() {
        return Err(invalid(
            "shape.svg_file",
            format!("is a directory, not an SVG file: {}", path.display()),
        ));
    }
    if !path.exists() {
        return Err(JobError::FileNotFound {
            key: "shape.svg_file".into(),
            path,
        });
    }
    Ok(ShapeSource::SvgFile(SvgFileSource {
        path,
        id: raw.id,
        size,
        origin,
        tolerance: defaults::TOLERANCE,
        max_size: extent::max_side(tool_diameter),
    }))
}

/// At most one of `scale`, `width`, `height`.
fn size(raw: &RawSvgFile) -> Result<SvgSize, JobError> {
    at_most_one(
        &[
            ("shape.scale", raw.scale.is_some()),
            ("shape.width", raw.width.is_some()),
            ("shape.height", raw.height.is_some()),
        ],
        "give at most one (the drawing keeps its proportions)",
    )?;
    Ok(match (raw.scale, raw.width, raw.height) {
        (Some(s), _, _) => SvgSize::Scale(limits::SVG_SCALE.check("shape.scale", s)?),
        (_, Some(w), _) => SvgSize::Width(limits::SHAPE_WIDTH.check("shape.width", w)?),
        (_, _, Some(h)) => SvgSize::Height(h),
        _ => SvgSize::Natural,
    })
}
