//! `[shape] kind = "polyharmonic"`: a solid from scattered points (Ochiai,
//! docs/method.md §17) milled from above as its top envelope over the `size`
//! rectangle. Points inline (`points`, `inside`, `outside`) or from
//! `points_file` (CSV or XYZ); `kernel`, `a`, `box`, `elements`, `base`,
//! `solid` (`"relief"` or `"closed"`: whether `pfcam surface` meshes the
//! closed solid itself, checked closed here).
//! The relief is solved and built here (`PolySpec::build_cached`), so the
//! job's depth, max h − base, is known when the job is.

use super::resolve::{one_of, show};
use super::{invalid, limits, JobError, RawShape};
use crate::geometry::{ShapeSource, Vec2};
use crate::sources::polyharmonic::{GivenPoint, Kernel, PointKind, PolyInputs, PolySpec, Solid};
use nalgebra::Vector3;
use std::path::Path;

/// Most elements per box edge a job may ask for (N = 6·12² = 864 elements,
/// a solve of about 2 s).
pub(crate) const MAX_ELEMENTS: i64 = 12;

/// Most bytes of a points file.
pub(crate) const MAX_FILE_BYTES: u64 = 4_000_000;

/// The polyharmonic keys and whether each is given.
pub(super) fn poly_keys(s: &RawShape) -> [(&'static str, bool); 9] {
    [
        ("shape.points", s.points.is_some()),
        ("shape.inside", s.inside.is_some()),
        ("shape.outside", s.outside.is_some()),
        ("shape.points_file", s.points_file.is_some()),
        ("shape.kernel", s.kernel.is_some()),
        ("shape.a", s.a.is_some()),
        ("shape.box", s.box_.is_some()),
        ("shape.elements", s.elements.is_some()),
        ("shape.solid", s.solid.is_some()),
    ]
}

/// Keys of the other sources, refused with `kind = "polyharmonic"`.
fn refuse_other_keys(s: &RawShape) -> Result<(), JobError> {
    let more = [
        ("shape.height", s.height.is_some()),
        ("shape.degree", s.degree.is_some()),
        ("shape.form", s.form.is_some()),
        ("shape.row0", s.row0.is_some()),
        ("shape.row1", s.row1.is_some()),
        ("shape.bottom_size", s.bottom_size.is_some()),
        ("shape.bottom_exponent", s.bottom_exponent.is_some()),
        ("shape.top_size", s.top_size.is_some()),
        ("shape.top_exponent", s.top_exponent.is_some()),
        ("shape.flare", s.flare.is_some()),
        ("shape.rise", s.rise.is_some()),
        ("shape.modes", s.modes.is_some()),
        ("shape.samples", s.samples.is_some()),
    ];
    super::harmonic::refuse_keys(s, &more, "polyharmonic", "the solid is given by shape.points (or shape.points_file), shape.box, shape.size and shape.base (and shape.inside, shape.outside, shape.kernel, shape.a, shape.elements, shape.solid, shape.origin)")
}

/// A required key.
fn required<T>(v: Option<T>, key: &str, what: &str) -> Result<T, JobError> {
    super::harmonic::required_with("polyharmonic", v, key, what)
}

/// `[shape]` with `kind = "polyharmonic"`: solved and built once.
pub(super) fn resolve(s: RawShape, origin: Vec2, base_dir: &Path) -> Result<ShapeSource, JobError> {
    refuse_other_keys(&s)?;
    let points = given_points(&s, base_dir)?;
    let kernel = kernel(&s)?;
    let corners = required(
        s.box_.clone(),
        "shape.box",
        "[[x0, y0, z0], [x1, y1, z1]] in mm",
    )?;
    let [lo, hi] = <[[f64; 3]; 2]>::try_from(corners.as_slice()).map_err(|_| {
        invalid(
            "shape.box",
            format!(
                "needs 2 corners [[x0, y0, z0], [x1, y1, z1]], got {}",
                corners.len()
            ),
        )
    })?;
    for c in lo.iter().chain(&hi) {
        limits::ORIGIN.check("shape.box", *c)?;
    }
    let (lo, hi) = (Vector3::from(lo), Vector3::from(hi));
    let elements = s.elements.unwrap_or(6);
    if !(1..=MAX_ELEMENTS).contains(&elements) {
        return Err(invalid(
            "shape.elements",
            format!("must be an integer from 1 to {MAX_ELEMENTS} (elements per box edge), got {elements}"),
        ));
    }
    let size = required(s.size, "shape.size", "[X, Y] of the rectangle milled, mm")?;
    for v in size {
        limits::PATCH_SIZE.check("shape.size", v)?;
    }
    let base = required(s.base, "shape.base", "the height of the block's foot, mm")?;
    limits::ORIGIN.check("shape.base", base)?;
    check_inside_box(&points, lo, hi, origin, size, base)?;
    let solid = solid(&s)?;
    PolySpec::build_cached(PolyInputs {
        points: points.into_iter().map(|p| p.1).collect(),
        kernel,
        lo,
        hi,
        per_edge: elements as usize,
        origin: [origin.x, origin.y],
        size,
        base,
        solid,
    })
    .map(ShapeSource::Polyharmonic)
    .map_err(poly_error)
}

/// `solid`: `"relief"` (default) or `"closed"`.
fn solid(s: &RawShape) -> Result<Solid, JobError> {
    let name = s.solid.as_deref().unwrap_or("relief");
    one_of("shape.solid", name, &["relief", "closed"])?;
    Ok(if name == "closed" {
        Solid::Closed
    } else {
        Solid::Relief
    })
}

/// `kernel` (default `T2A`) and `a`.
fn kernel(s: &RawShape) -> Result<Kernel, JobError> {
    let name = s.kernel.as_deref().unwrap_or("T2A");
    one_of("shape.kernel", name, &["T1", "T2", "T3", "T1A", "T2A"])?;
    match name {
        "T2" => match s.a {
            Some(_) => Err(invalid("shape.a", "only applies to shape.kernel = \"T2A\" (the ball radius A)")),
            None => Ok(Kernel::T2),
        },
        "T2A" => {
            let a = required(s.a, "shape.a", "the ball radius A of the T2A kernel, mm")?;
            if !(a.is_finite() && a > 0.0 && a <= 1000.0) {
                return Err(invalid("shape.a", format!("must be > 0 and at most 1000 mm, got {}", show(a))));
            }
            Ok(Kernel::T2A { a })
        }
        k => Err(invalid(
            "shape.kernel",
            format!("= \"{k}\" needs the l = 1 (T1, T1A) or l = 3 (T3) system of Ochiai's (20), which is not implemented: use \"T2A\" (the paper's choice) or \"T2\""),
        )),
    }
}

/// The points with the key each came from (`shape.points[3]`, or the file's
/// line).
fn given_points(s: &RawShape, base_dir: &Path) -> Result<Vec<(String, GivenPoint)>, JobError> {
    let inline = s.points.is_some() || s.inside.is_some() || s.outside.is_some();
    if let Some(file) = &s.points_file {
        if inline {
            return Err(invalid(
                "shape.points_file",
                "cannot be combined with shape.points, shape.inside or shape.outside: give the points in one place",
            ));
        }
        return super::polyharmonic_file::read_points(base_dir, file);
    }
    let points = required(
        s.points.as_ref(),
        "shape.points",
        "[[x, y, z], ...] on the surface, mm",
    )?;
    let mut out = Vec::new();
    for (key, list, kind) in [
        ("shape.points", Some(points), PointKind::Surface),
        ("shape.inside", s.inside.as_ref(), PointKind::Inside),
        ("shape.outside", s.outside.as_ref(), PointKind::Outside),
    ] {
        for (i, p) in list.into_iter().flatten().enumerate() {
            out.push((
                format!("{key}[{i}]"),
                GivenPoint {
                    p: Vector3::from(*p),
                    kind,
                },
            ));
        }
    }
    Ok(out)
}

/// Every point finite and strictly inside the box; the rectangle and the
/// base inside it too; at most `system::MAX_POINTS` points.
fn check_inside_box(
    points: &[(String, GivenPoint)],
    lo: Vector3<f64>,
    hi: Vector3<f64>,
    origin: Vec2,
    size: [f64; 2],
    base: f64,
) -> Result<(), JobError> {
    if (0..3).any(|k| lo[k] >= hi[k]) {
        return Err(invalid("shape.box", "needs x0 < x1, y0 < y1 and z0 < z1"));
    }
    let max = crate::sources::polyharmonic::system::MAX_POINTS;
    if points.is_empty() || points.len() > max {
        return Err(invalid(
            "shape.points",
            format!("needs 1 to {max} points in all, got {}", points.len()),
        ));
    }
    let inside = |p: Vector3<f64>| (0..3).all(|k| p[k] > lo[k] && p[k] < hi[k]);
    for (key, g) in points {
        if !inside(g.p) {
            return Err(invalid(
                key.split('[').next().unwrap_or(key),
                format!(
                    "{key} = [{}, {}, {}] is not strictly inside shape.box",
                    show(g.p.x),
                    show(g.p.y),
                    show(g.p.z)
                ),
            ));
        }
    }
    let far = Vector3::new(origin.x + size[0], origin.y + size[1], base);
    if !(inside(Vector3::new(origin.x, origin.y, base)) && inside(far)) {
        return Err(invalid(
            "shape.box",
            "must hold the rectangle (shape.origin, shape.size) at the height shape.base strictly inside it",
        ));
    }
    Ok(())
}

/// A polyharmonic error as a job error: its key as a job key.
fn poly_error(e: crate::sources::polyharmonic::PolyError) -> JobError {
    use crate::sources::polyharmonic::PolyError;
    // An input's own fault names its key; the zero set and the singular
    // system are the points' ("points: ..." in their text).
    let (key, message) = match &e {
        PolyError::Invalid { key, reason } => (*key, reason.to_string()),
        other => {
            let text = other.to_string();
            let message = text.strip_prefix("points: ").unwrap_or(&text).to_string();
            ("points", message)
        }
    };
    let key = match key {
        k if k.starts_with("shape.") => k,
        "kernel" => "shape.kernel",
        "kernel.a" => "shape.a",
        "box" => "shape.box",
        "elements" => "shape.elements",
        _ => "shape.points",
    };
    invalid(key, message)
}

/// The part's depth, mm: max h − base, at least 0.01 mm and within
/// `limits::DEPTH`.
pub(super) fn relief_depth(spec: &PolySpec) -> Result<f64, JobError> {
    let r = spec.range();
    let depth = r.max - r.min;
    if depth.is_nan() || depth < super::harmonic::MIN_PATCH_DEPTH {
        return Err(invalid(
            "shape.base",
            format!("the solid does not rise above shape.base = {} over the rectangle (max h − base = {} mm): nothing to mill", show(spec.base), show(depth)),
        ));
    }
    limits::DEPTH.check("shape.base", depth).map_err(|_| {
        invalid(
            "shape.base",
            format!(
                "the relief is {} mm deep (max h − base), more than the {} mm a part may be",
                show(depth),
                show(limits::DEPTH.hi)
            ),
        )
    })
}
