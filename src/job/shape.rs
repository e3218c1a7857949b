//! `[shape]` into a [`ShapeSource`]: exactly one source (`text`, `lines`,
//! `svg_path`, `svg_file`, `dxf_file` or `[[shape.part]]`), each with only the
//! keys that apply to it; `origin` and `height` in mm.

use super::font::Sources;
use super::resolve::at_most_one;
use super::{
    composition, dxffile, harmonic, invalid, limits, polyharmonic, svgfile, text, tube, JobError,
    RawShape,
};
use crate::geometry::{Composition, ShapeSource, Vec2};

/// `[shape]` with the tool's diameter (mm), which the text's letter spacing
/// and the files' checks use.
pub(super) fn resolve(
    mut s: RawShape,
    tool_diameter: f64,
    src: &Sources<'_>,
) -> Result<ShapeSource, JobError> {
    let origin = match s.origin {
        Some([x, y]) => Vec2::new(
            limits::ORIGIN.check("shape.origin", x)?,
            limits::ORIGIN.check("shape.origin", y)?,
        ),
        None => Vec2::ZERO,
    };
    let height = s
        .height
        .map(|h| limits::SHAPE_HEIGHT.check("shape.height", h))
        .transpose()?;
    if s.kind.as_deref() == Some("polyharmonic") {
        return polyharmonic::resolve(s, origin, src.base_dir);
    }
    if s.kind.as_deref() == Some(tube::KIND) {
        return tube::resolve(s, origin, height);
    }
    tube::refuse_tube_keys(&s)?;
    if s.kind.is_some() {
        return harmonic::resolve(s, origin);
    }
    harmonic::refuse_patch_keys(&s)?;
    if let Some(parts) = s.part.take() {
        check_composite_keys(&s)?;
        let composition = composition::resolve(parts, s.result, src)?;
        return Ok(ShapeSource::Composite(Composition {
            height,
            origin,
            ..composition
        }));
    }
    check_single_source_keys(&s)?;
    if let Some(file) = s.dxf_file {
        let others = [
            ("shape.font", s.font.is_some()),
            ("shape.letter_spacing", s.letter_spacing.is_some()),
            ("shape.height", height.is_some()),
            ("shape.id", s.id.is_some()),
            ("shape.scale", s.scale.is_some()),
            ("shape.width", s.width.is_some()),
        ];
        return dxffile::resolve(
            dxffile::RawDxfFile {
                file,
                layer: s.layer,
                join_tolerance: s.join_tolerance,
                others: others.iter().filter(|k| k.1).map(|k| k.0).collect(),
            },
            origin,
            tool_diameter,
            src.base_dir,
        );
    }
    check_svg_file_keys(&s)?;
    if let Some(file) = s.svg_file {
        return svgfile::resolve(
            svgfile::RawSvgFile {
                file,
                id: s.id,
                scale: s.scale,
                width: s.width,
                height,
                font: s.font.is_some(),
                letter_spacing: s.letter_spacing.is_some(),
            },
            origin,
            tool_diameter,
            src.base_dir,
        );
    }
    // Two sources given were refused above (`at_most_one`).
    if s.text.is_some() || s.lines.is_some() {
        let raw = text::RawText {
            text: s.text,
            lines: s.lines,
            font: s.font,
            letter_spacing: s.letter_spacing,
            line_spacing: s.line_spacing,
            align: s.align,
        };
        return text::resolve(raw, height, origin, tool_diameter, src);
    }
    resolve_svg_path(s, height, origin)
}

/// With `[[shape.part]]`: no other source, and no text layout key (a text
/// part has its own font).
fn check_composite_keys(s: &RawShape) -> Result<(), JobError> {
    for (key, given) in [
        ("shape.text", s.text.is_some()),
        ("shape.lines", s.lines.is_some()),
        ("shape.svg_path", s.svg_path.is_some()),
        ("shape.svg_file", s.svg_file.is_some()),
        ("shape.dxf_file", s.dxf_file.is_some()),
    ] {
        if given {
            return Err(invalid(
                "shape.part",
                format!(
                    "cannot be combined with {key}: a job has one shape source (a part may itself be text or svg: shape.part[i].text, shape.part[i].svg)"
                ),
            ));
        }
    }
    for (key, given) in [
        ("shape.font", s.font.is_some()),
        ("shape.letter_spacing", s.letter_spacing.is_some()),
        ("shape.align", s.align.is_some()),
        ("shape.line_spacing", s.line_spacing.is_some()),
    ] {
        if given {
            return Err(invalid(
                key,
                "only applies to shape.text, not to [[shape.part]] (a text part has its own font: shape.part[i].font)",
            ));
        }
    }
    Ok(())
}

/// Without `[[shape.part]]`: no `result`, at most one source, the line layout
/// keys only with text or lines, the DXF keys only with `dxf_file`.
fn check_single_source_keys(s: &RawShape) -> Result<(), JobError> {
    if s.result.is_some() {
        return Err(invalid(
            "shape.result",
            "only applies to a composition: it names one of the [[shape.part]] tables",
        ));
    }
    at_most_one(
        &[
            ("shape.text", s.text.is_some()),
            ("shape.lines", s.lines.is_some()),
            ("shape.svg_path", s.svg_path.is_some()),
            ("shape.svg_file", s.svg_file.is_some()),
            ("shape.dxf_file", s.dxf_file.is_some()),
        ],
        "give exactly one",
    )?;
    if s.text.is_none() && s.lines.is_none() {
        for (key, given) in [
            ("shape.align", s.align.is_some()),
            ("shape.line_spacing", s.line_spacing.is_some()),
        ] {
            if given {
                return Err(invalid(key, "only applies to shape.text or shape.lines"));
            }
        }
    }
    if s.dxf_file.is_none() {
        for (key, given) in [
            ("shape.layer", s.layer.is_some()),
            ("shape.join_tolerance", s.join_tolerance.is_some()),
        ] {
            if given {
                return Err(invalid(key, "only applies to shape.dxf_file"));
            }
        }
    }
    Ok(())
}

/// `id`, `scale` and `width` only with `svg_file`.
fn check_svg_file_keys(s: &RawShape) -> Result<(), JobError> {
    if s.svg_file.is_none() {
        for (key, given) in [
            ("shape.id", s.id.is_some()),
            ("shape.scale", s.scale.is_some()),
            ("shape.width", s.width.is_some()),
        ] {
            if given {
                return Err(invalid(key, "only applies to shape.svg_file"));
            }
        }
    }
    Ok(())
}

/// The last source left, `svg_path`: required when nothing else is given, not
/// blank, without the text keys.
fn resolve_svg_path(
    s: RawShape,
    height: Option<f64>,
    origin: Vec2,
) -> Result<ShapeSource, JobError> {
    let Some(d) = s.svg_path else {
        return Err(invalid(
            "shape.text",
            "or shape.lines or shape.svg_path or shape.svg_file or shape.dxf_file or [[shape.part]] is required (exactly one of them)",
        ));
    };
    for (key, given) in [
        ("shape.font", s.font.is_some()),
        ("shape.letter_spacing", s.letter_spacing.is_some()),
    ] {
        if given {
            return Err(invalid(
                key,
                "only applies to shape.text, not shape.svg_path",
            ));
        }
    }
    if d.trim().is_empty() {
        return Err(invalid("shape.svg_path", "must not be empty"));
    }
    Ok(ShapeSource::SvgPath { d, height, origin })
}
