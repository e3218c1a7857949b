//! `[shape] kind = "pde-tube"`: a Bloor–Wilson PDE tube (docs/method.md §15,
//! §16.3) from its two end curves (`bottom_size`, `bottom_exponent`,
//! `top_size`, `top_exponent`), `height`, the derivative conditions `flare`
//! and `rise`, the PDE's `a`, `modes` and `samples`, into a [`TubeSpec`].
//! The surface is solved when `[shape]` is resolved (every error of the
//! solve names its key); once `[operation]` has given the boss or mould and
//! the tolerance, [`check`] builds the part and refuses a turning spine or
//! an overhang, naming the z, and a flat finishing tool.

use super::resolve::show;
use super::{invalid, limits, CutterShape, Finish, JobError, Operation, OperationKind, RawShape};
use crate::geometry::{ShapeSource, Vec2};
use crate::sources::pde::PdeError;
use crate::sources::pde_tube::spec::{TubeEnd, TubeSpec};
use crate::sources::pde_tube::{TubeError, TubeKind};

/// `shape.kind` of a PDE tube.
pub(crate) const KIND: &str = "pde-tube";

/// Defaults: a = 1 and N = 8 with K = 128 give the vase to 1e-14 mm
/// at the samples (docs/method.md §15).
const DEFAULT_A: f64 = 1.0;
const DEFAULT_MODES: i64 = 8;
const DEFAULT_SAMPLES: i64 = 128;
/// An end curve's exponent by default: an ellipse (a circle for equal sides).
const DEFAULT_EXPONENT: f64 = 2.0;

/// The tube's own keys and whether each is given.
fn tube_keys(s: &RawShape) -> [(&'static str, bool); 10] {
    [
        ("shape.bottom_size", s.bottom_size.is_some()),
        ("shape.bottom_exponent", s.bottom_exponent.is_some()),
        ("shape.top_size", s.top_size.is_some()),
        ("shape.top_exponent", s.top_exponent.is_some()),
        ("shape.flare", s.flare.is_some()),
        ("shape.rise", s.rise.is_some()),
        ("shape.a", s.a.is_some()),
        ("shape.modes", s.modes.is_some()),
        ("shape.samples", s.samples.is_some()),
        ("shape.trim", s.trim.is_some()),
    ]
}

/// Without `shape.kind = "pde-tube"`: no tube key.
pub(super) fn refuse_tube_keys(s: &RawShape) -> Result<(), JobError> {
    match tube_keys(s).iter().find(|k| k.1) {
        Some((key, _)) => Err(invalid(
            key,
            "only applies to shape.kind = \"pde-tube\" (a PDE tube)",
        )),
        None => Ok(()),
    }
}

/// The keys of the other sources, refused with a tube.
fn refuse_other_keys(s: &RawShape) -> Result<(), JobError> {
    let more = [
        ("shape.degree", s.degree.is_some()),
        ("shape.form", s.form.is_some()),
        ("shape.size", s.size.is_some()),
        ("shape.row0", s.row0.is_some()),
        ("shape.row1", s.row1.is_some()),
        ("shape.points", s.points.is_some()),
        ("shape.inside", s.inside.is_some()),
        ("shape.outside", s.outside.is_some()),
        ("shape.points_file", s.points_file.is_some()),
        ("shape.kernel", s.kernel.is_some()),
        ("shape.box", s.box_.is_some()),
        ("shape.elements", s.elements.is_some()),
        ("shape.base", s.base.is_some()),
        ("shape.solid", s.solid.is_some()),
    ];
    super::harmonic::refuse_keys(s, &more, KIND, "a tube is given by shape.bottom_size, shape.top_size and shape.height (and shape.bottom_exponent, shape.top_exponent, shape.flare, shape.rise, shape.a, shape.modes, shape.samples, shape.origin)")
}

/// A required tube key.
fn required<T>(v: Option<T>, key: &str, what: &str) -> Result<T, JobError> {
    super::harmonic::required_with(KIND, v, key, what)
}

/// An integer key within `range`.
fn integer(v: i64, key: &str, range: limits::Range) -> Result<usize, JobError> {
    range.check(key, v as f64)?;
    usize::try_from(v).map_err(|_| invalid(key, format!("must be an integer ≥ 0, got {v}")))
}

/// One end: its size, exponent, flare and rise.
fn end(prefix: &str, size: Option<[f64; 2]>, exponent: Option<f64>) -> Result<TubeEnd, JobError> {
    let key = format!("shape.{prefix}_size");
    let size = required(size, &key, "[X, Y] in mm, the curve's extents")?;
    for v in size {
        limits::TUBE_SIZE.check(&key, v)?;
    }
    let exponent = limits::TUBE_EXPONENT.check(
        &format!("shape.{prefix}_exponent"),
        exponent.unwrap_or(DEFAULT_EXPONENT),
    )?;
    Ok(TubeEnd {
        size,
        exponent,
        flare: 0.0,
        rise: 0.0,
    })
}

/// `[shape]` with `kind = "pde-tube"` and its `height` (mm, if given): the
/// spec, its surface solved once (kind and tolerance are filled in by
/// [`check`]).
pub(super) fn resolve(
    mut s: RawShape,
    origin: Vec2,
    height: Option<f64>,
) -> Result<ShapeSource, JobError> {
    refuse_other_keys(&s)?;
    let height = required(
        height,
        "shape.height",
        "mm, from the bottom curve to the top one",
    )?;
    limits::DEPTH.check("shape.height", height)?;
    let mut bottom = end("bottom", s.bottom_size, s.bottom_exponent)?;
    let mut top = end("top", s.top_size, s.top_exponent)?;
    let flare = s.flare.unwrap_or([0.0, 0.0]);
    let rise = s.rise.unwrap_or([height, height]);
    for (key, pair) in [("shape.flare", flare), ("shape.rise", rise)] {
        for v in pair {
            limits::TUBE_SLOPE.check(key, v)?;
        }
    }
    (bottom.flare, top.flare) = (flare[0], flare[1]);
    (bottom.rise, top.rise) = (rise[0], rise[1]);
    let a = limits::TUBE_A.check("shape.a", s.a.unwrap_or(DEFAULT_A))?;
    let modes = integer(
        s.modes.unwrap_or(DEFAULT_MODES),
        "shape.modes",
        limits::TUBE_MODES,
    )?;
    let samples = integer(
        s.samples.unwrap_or(DEFAULT_SAMPLES),
        "shape.samples",
        limits::TUBE_SAMPLES,
    )?;
    if samples < 2 * modes + 1 {
        return Err(invalid(
            "shape.samples",
            format!(
                "= {samples} is below 2·shape.modes + 1 = {}: mode N would alias",
                2 * modes + 1
            ),
        ));
    }
    let spec = TubeSpec {
        bottom,
        top,
        height,
        a,
        modes,
        samples,
        origin,
        kind: TubeKind::Boss,
        tolerance: crate::job::defaults::TOLERANCE,
        trims: super::tube_trim::resolve(s.trim.take())?,
    };
    spec.surface().map_err(pde_error)?;
    Ok(ShapeSource::PdeTube(spec))
}

/// A [`PdeError`] as a job error naming the key.
fn pde_error(e: PdeError) -> JobError {
    let key = match &e {
        PdeError::Invalid { key: "modes", .. } | PdeError::IllConditioned { key: "modes", .. } => {
            "shape.modes"
        }
        PdeError::Invalid {
            key: "x0" | "x1", ..
        } => "shape.samples",
        PdeError::Invalid {
            key: "xu0" | "xu1", ..
        } => "shape.rise",
        _ => "shape.a",
    };
    invalid(key, e.to_string())
}

/// With the operation known: the tube as a boss or its mould, to the
/// operation's tolerance, built once so that a turning spine or an overhang
/// is refused here (the z named in machine coordinates, `top` the stock
/// top).
pub(super) fn check(
    spec: &mut TubeSpec,
    op: &Operation,
    top: f64,
    finish: Option<&Finish>,
) -> Result<(), JobError> {
    if finish.is_some_and(|f| f.shape == CutterShape::Flat) {
        return Err(invalid(
            "finish.shape",
            "= \"flat\" cannot follow a PDE tube's curved wall along its sections within the tolerance (its edge leaves a stair): use \"ball\" or \"bull\"",
        ));
    }
    spec.kind = match op.kind {
        OperationKind::Cavity => TubeKind::Mould,
        _ => TubeKind::Boss,
    };
    spec.tolerance = op.tolerance;
    super::tube_trim::check(
        &mut spec.trims,
        top,
        spec.height,
        spec.kind == TubeKind::Boss,
    )?;
    match spec.tube() {
        Ok(_) => Ok(()),
        Err(e @ TubeError::Overhang { .. }) if !spec.trims.is_empty() => {
            let plain = TubeSpec {
                trims: Vec::new(),
                ..spec.clone()
            };
            match plain.tube() {
                Ok(_) => Err(trim_overhang(e, spec, top)),
                Err(e) => Err(tube_error(e, spec, top)),
            }
        }
        Err(e) => Err(tube_error(e, spec, top)),
    }
}

/// An overhang that only the trim makes (the untrimmed tube nests): its
/// sides, the rays from the spine to the wall at its angles, lean out of
/// the section below (the wall's polar angle is not quite v).
fn trim_overhang(e: TubeError, spec: &TubeSpec, top: f64) -> JobError {
    let TubeError::Overhang { z, by, .. } = e else {
        return tube_error(e, spec, top);
    };
    invalid(
        "shape.trim[1].angles",
        format!(
            "makes the part overhang at z = {:.4} mm: the trim's sides (rays from the tube's spine to its wall at these angles) reach outside the section below by {by:.2e} mm (tolerance {} mm), and a 3-axis mill cannot reach under them; try other angles, or a larger operation.tolerance",
            top + z,
            show(spec.tolerance)
        ),
    )
}

/// A [`TubeError`] as a job error naming the key (heights in machine z).
fn tube_error(e: TubeError, spec: &TubeSpec, top: f64) -> JobError {
    match e {
        TubeError::Pde(p) => pde_error(p),
        TubeError::NotMonotone { z, u } => invalid(
            "shape.rise",
            format!(
                "makes the tube's spine turn back in z at z = {:.4} mm (u = {u:.4}): its height must change monotonically from the bottom curve to the top one; use rises of the same sign as shape.height, or smaller flares",
                top + z
            ),
        ),
        TubeError::Overhang {
            z,
            lower,
            upper,
            by,
            what,
            ..
        } => {
            let (key, fix) = match spec.kind {
                TubeKind::Boss => ("shape.top_size", "a boss's sections must shrink upward: a top curve inside the bottom one, and flares that do not bulge it"),
                TubeKind::Mould => ("shape.top_size", "a mould's pockets must widen upward (the tube upside down): a top curve inside the bottom one, and flares that do not bulge it"),
            };
            let key = if spec.bottom.flare != 0.0 || spec.top.flare != 0.0 {
                "shape.flare"
            } else {
                key
            };
            invalid(
                key,
                format!(
                    "makes the part overhang at z = {:.4} mm (between z = {:.4} and {:.4}): {what} by {by:.2e} mm (tolerance {} mm), and a 3-axis mill cannot reach under it; {fix}",
                    top + z,
                    top + lower,
                    top + upper,
                    show(spec.tolerance)
                ),
            )
        }
        TubeError::Invalid { key, reason } => invalid(
            match key {
                "tol" => "operation.tolerance",
                "points" => "operation.tolerance",
                _ => "shape.height",
            },
            reason.to_string(),
        ),
    }
}
