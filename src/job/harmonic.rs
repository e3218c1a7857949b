//! `[shape] kind = "harmonic-bezier"`: a harmonic tensor-product Bézier patch
//! (docs/method.md §14) from `degree`, `form`, `size`, `row0`, `row1` and
//! `origin`, into a [`PatchSpec`] whose patch is known to build. The patch's
//! height range (by the maximum principle, on its edges) is the part's depth.

use super::resolve::{one_of, show};
use super::{invalid, limits, JobError, RawShape};
use crate::geometry::{ShapeSource, Vec2};
use crate::sources::harmonic_bezier::{default_form, Form, HarmonicError, PatchSpec};

/// The accepted values of `shape.kind`.
pub(crate) const SHAPE_KINDS: &[&str] = &["harmonic-bezier", "polyharmonic", super::tube::KIND];

/// The patch keys and whether each is given.
fn patch_keys(s: &RawShape) -> [(&'static str, bool); 5] {
    [
        ("shape.degree", s.degree.is_some()),
        ("shape.form", s.form.is_some()),
        ("shape.size", s.size.is_some()),
        ("shape.row0", s.row0.is_some()),
        ("shape.row1", s.row1.is_some()),
    ]
}

/// Without `shape.kind = "harmonic-bezier"`: no patch key.
pub(super) fn refuse_patch_keys(s: &RawShape) -> Result<(), JobError> {
    if let Some((key, _)) = patch_keys(s).iter().find(|k| k.1) {
        return Err(invalid(
            key,
            "only applies to shape.kind = \"harmonic-bezier\" (a harmonic patch)",
        ));
    }
    refuse_poly_keys(s, "without shape.kind")
}

/// No polyharmonic key (`base` included) outside `kind = "polyharmonic"`.
fn refuse_poly_keys(s: &RawShape, context: &str) -> Result<(), JobError> {
    let keys = super::polyharmonic::poly_keys(s);
    match keys
        .iter()
        .chain(&[("shape.base", s.base.is_some())])
        .find(|k| k.1)
    {
        Some((key, _)) => Err(invalid(
            key,
            format!("only applies to shape.kind = \"polyharmonic\" (a solid from points), not {context}"),
        )),
        None => Ok(()),
    }
}

/// The keys of the glyph sources (text, SVG, DXF, a composition), which
/// every surface kind refuses.
pub(super) fn glyph_keys(s: &RawShape) -> [(&'static str, bool); 16] {
    [
        ("shape.text", s.text.is_some()),
        ("shape.lines", s.lines.is_some()),
        ("shape.svg_path", s.svg_path.is_some()),
        ("shape.svg_file", s.svg_file.is_some()),
        ("shape.dxf_file", s.dxf_file.is_some()),
        ("shape.part", s.part.is_some()),
        ("shape.result", s.result.is_some()),
        ("shape.font", s.font.is_some()),
        ("shape.letter_spacing", s.letter_spacing.is_some()),
        ("shape.line_spacing", s.line_spacing.is_some()),
        ("shape.align", s.align.is_some()),
        ("shape.id", s.id.is_some()),
        ("shape.scale", s.scale.is_some()),
        ("shape.width", s.width.is_some()),
        ("shape.layer", s.layer.is_some()),
        ("shape.join_tolerance", s.join_tolerance.is_some()),
    ]
}

/// The keys of the other sources, refused with a patch.
fn refuse_other_keys(s: &RawShape) -> Result<(), JobError> {
    refuse_keys(
        s,
        &[("shape.height", s.height.is_some())],
        "harmonic-bezier",
        "a patch is given by shape.degree, shape.size, shape.row0 and shape.row1 (and shape.form, shape.origin)",
    )
}

/// With `shape.kind = kind`: the first given key among the glyph sources'
/// ([`glyph_keys`]) and `more` is refused, the message saying what the kind
/// is `given_by`.
pub(super) fn refuse_keys(
    s: &RawShape,
    more: &[(&'static str, bool)],
    kind: &str,
    given_by: &str,
) -> Result<(), JobError> {
    match glyph_keys(s).iter().chain(more).find(|k| k.1) {
        Some((key, _)) => Err(invalid(
            key,
            format!("does not apply to shape.kind = \"{kind}\": {given_by}"),
        )),
        None => Ok(()),
    }
}

/// A key that `shape.kind = kind` requires: its value, or the error naming
/// it and `what` it is.
pub(super) fn required_with<T>(
    kind: &str,
    v: Option<T>,
    key: &str,
    what: &str,
) -> Result<T, JobError> {
    v.ok_or_else(|| {
        invalid(
            key,
            format!("is required with shape.kind = \"{kind}\" ({what})"),
        )
    })
}

/// A required patch key.
fn required<T>(v: Option<T>, key: &str, what: &str) -> Result<T, JobError> {
    required_with("harmonic-bezier", v, key, what)
}

/// `[shape]` with `kind`: the patch, checked by building it once.
pub(super) fn resolve(s: RawShape, origin: Vec2) -> Result<ShapeSource, JobError> {
    let kind = s.kind.clone().unwrap_or_default();
    one_of("shape.kind", &kind, SHAPE_KINDS)?;
    refuse_other_keys(&s)?;
    refuse_poly_keys(&s, "with a harmonic patch")?;
    let degree = required(s.degree, "shape.degree", "n, the degree along the rows")?;
    let degree = usize::try_from(degree)
        .ok()
        .filter(|&d| d >= 1)
        .ok_or_else(|| {
            invalid(
                "shape.degree",
                format!("must be an integer ≥ 1, got {degree}"),
            )
        })?;
    let size = required(s.size, "shape.size", "[X, Y] in mm")?;
    for v in size {
        limits::PATCH_SIZE.check("shape.size", v)?;
    }
    let row0 = required(s.row0, "shape.row0", "degree + 1 heights in mm")?;
    let row1 = required(s.row1, "shape.row1", "degree + 1 heights in mm")?;
    for (key, row) in [("shape.row0", &row0), ("shape.row1", &row1)] {
        for (j, &h) in row.iter().enumerate() {
            limits::PATCH_HEIGHT.check(&format!("{key}[{j}]"), h)?;
        }
    }
    let form = match s.form.as_deref() {
        None => default_form(degree),
        Some(f) => {
            one_of("shape.form", f, &["square", "raised"])?;
            if f == "square" {
                Form::Square
            } else {
                Form::Raised
            }
        }
    };
    let spec = PatchSpec {
        degree,
        form,
        size,
        row0,
        row1,
        origin,
    };
    spec.patch().map_err(harmonic_error)?;
    Ok(ShapeSource::HarmonicBezier(spec))
}

/// A [`HarmonicError`] as a job error: its text starts with the key.
pub(super) fn harmonic_error(e: HarmonicError) -> JobError {
    let text = e.to_string();
    match text.split_once(": ") {
        Some((key, message)) if key.starts_with("shape.") => invalid(key, message),
        _ => invalid("shape.kind", text),
    }
}

/// The part's depth, mm: max h − min h over the rectangle, which must be at
/// least [`MIN_PATCH_DEPTH`] and within `limits::DEPTH`.
pub(super) fn patch_depth(spec: &PatchSpec) -> Result<f64, JobError> {
    let patch = spec.patch().map_err(harmonic_error)?;
    let r = patch.height_range();
    let depth = r.max - r.min;
    if depth.is_nan() || depth < MIN_PATCH_DEPTH {
        return Err(invalid(
            "shape.row0",
            format!(
                "and shape.row1 make a flat patch (max h − min h = {} mm, under {MIN_PATCH_DEPTH} mm): nothing to mill",
                show(depth)
            ),
        ));
    }
    limits::DEPTH
        .check("shape.row0", depth)
        .map_err(|_| {
            invalid(
                "shape.row0",
                format!(
                    "and shape.row1 make a patch {} mm deep (max h − min h, the surface's own range), more than the {} mm a part may be",
                    show(depth),
                    show(limits::DEPTH.hi)
                ),
            )
        })
}

/// The shallowest patch accepted, mm: below a hundredth of a millimetre the
/// part is a flat block, and its levels would be the tolerance apart.
pub(crate) const MIN_PATCH_DEPTH: f64 = 0.01;
