//! `[operation]` into an [`Operation`], with the tables that only a boss or
//! cavity takes: `[profile]` (the depth profile) and `[finish]`.

use super::finish::{self, RawFinish};
use super::resolve::{one_of, show};
use super::{
    defaults, invalid, limits, Direction, Finish, JobError, Operation, OperationKind, RawOperation,
    RawProfile, Side, Stock, Tool, DIRECTIONS, OPERATION_KINDS, SIDES,
};
use crate::profile::DepthProfile;

/// The resolved `[operation]` and the tables it governs.
pub(super) struct Resolved {
    pub(crate) operation: Operation,
    /// `Some` exactly for a boss or cavity.
    pub(crate) profile: Option<DepthProfile>,
    pub(crate) finish: Option<Finish>,
}

/// `[operation]`, `[profile]` and `[finish]` against the resolved tool and
/// stock: the depth (mm below `stock.top`) in passes of `tool.stepdown`, the
/// tolerance below the tool radius, the clearing rings of a boss's margin.
/// `surface` is a surface source's own depth (a harmonic patch's max h −
/// min h, a PDE tube's height, mm) and whether it is a tube: the depth is
/// then the surface's, the operation a boss by default (a tube may be a
/// cavity, its mould), and `operation.depth` and `[profile]` do not apply.
pub(super) fn resolve(
    o: RawOperation,
    tool: &Tool,
    stock: &Stock,
    tables: (Option<RawProfile>, Option<RawFinish>),
    surface: (Option<f64>, bool),
) -> Result<Resolved, JobError> {
    let (surface_depth, tube) = surface;
    let (profile, finish) = tables;
    let default_kind = if surface_depth.is_some() {
        "boss"
    } else {
        "profile"
    };
    let kind = o.kind.unwrap_or_else(|| default_kind.into());
    one_of("operation.kind", &kind, OPERATION_KINDS)?;
    if let Some(d) = surface_depth {
        check_surface(&kind, o.depth, profile.is_some(), d, tube)?;
    }
    let side = o.side.unwrap_or_else(|| "outside".into());
    one_of("operation.side", &side, SIDES)?;
    let direction = o.direction.unwrap_or_else(|| "climb".into());
    one_of("operation.direction", &direction, DIRECTIONS)?;
    let depth = match surface_depth {
        Some(d) => d,
        None => resolve_depth(o.depth, tool)?,
    };
    let tolerance = resolve_tolerance(o.tolerance, tool.diameter)?;
    let max_scallop = limits::MAX_SCALLOP.check(
        "operation.max_scallop",
        o.max_scallop.unwrap_or(defaults::MAX_SCALLOP),
    )?;
    let op_kind = match kind.as_str() {
        "boss" => OperationKind::Boss,
        "cavity" => OperationKind::Cavity,
        _ => OperationKind::Profile,
    };
    check_margin_rings(op_kind, stock, tool)?;
    check_levels(op_kind, depth, tool)?;
    let profile = match surface_depth {
        Some(_) => None,
        None => resolve_profile_table(op_kind, profile, depth)?,
    };
    let finish = resolve_finish_table(op_kind, finish, tool)?;
    let stock_to_leave = resolve_stock_to_leave(op_kind, o.stock_to_leave, finish.is_some())?;
    let operation = Operation {
        stock_to_leave,
        max_scallop,
        kind: op_kind,
        side: Side::Outside,
        depth,
        tolerance,
        direction: if direction == "climb" {
            Direction::Climb
        } else {
            Direction::Conventional
        },
    };
    Ok(Resolved {
        operation,
        profile,
        finish,
    })
}

/// A surface source is milled as a boss (a PDE tube also as its mould, a
/// cavity): its depth is the surface's own, and its heights are its own
/// depth profile.
fn check_surface(
    kind: &str,
    depth: Option<f64>,
    has_profile: bool,
    surface_depth: f64,
    tube: bool,
) -> Result<(), JobError> {
    let what = if tube {
        "a PDE tube"
    } else {
        "a harmonic patch"
    };
    if kind == "profile" {
        return Err(invalid(
            "operation.kind",
            format!("= \"profile\" cuts a shape's outline with vertical walls; {what} is a surface: use \"boss\" (the default with shape.kind){}", if tube { " or \"cavity\" (its mould)" } else { "" }),
        ));
    }
    if tube {
        return check_surface_keys(depth, has_profile, surface_depth, what);
    }
    if kind == "cavity" {
        return Err(invalid(
            "operation.kind",
            "= \"cavity\" (the patch's mould milled into a slab) is not available for a harmonic patch; for the negative surface as a boss, negate shape.row0 and shape.row1 (the mould of a harmonic patch is linear in its rows, so −h is the patch of the negated rows)",
        ));
    }
    check_surface_keys(depth, has_profile, surface_depth, what)
}

/// `operation.depth` and `[profile]` do not apply to a surface (`what`).
fn check_surface_keys(
    depth: Option<f64>,
    has_profile: bool,
    surface_depth: f64,
    what: &str,
) -> Result<(), JobError> {
    let (range, top, heights) = if what == "a PDE tube" {
        ("its shape.height", "its top curve", "X(u, v) itself")
    } else {
        (
            "the surface's own range, max h − min h",
            "max h",
            "h(x, y) itself",
        )
    };
    if let Some(d) = depth {
        return Err(invalid(
            "operation.depth",
            format!(
                "= {} does not apply to {what}: its depth is {range} = {surface_depth:.3} mm (the stock top is at {top})",
                show(d)
            ),
        ));
    }
    if has_profile {
        return Err(invalid(
            "profile",
            format!("does not apply to {what}: its heights are the surface {heights}"),
        ));
    }
    Ok(())
}

/// `operation.depth` (required, mm below `stock.top`): positive, within
/// `limits::DEPTH`, and at most `limits::MAX_PASSES` passes of `tool.stepdown`.
fn resolve_depth(depth: Option<f64>, tool: &Tool) -> Result<f64, JobError> {
    let depth =
        depth.ok_or_else(|| invalid("operation.depth", "is required (mm below stock.top)"))?;
    if !(depth.is_finite() && depth > 0.0) {
        return Err(invalid(
            "operation.depth",
            format!("must be > 0 (mm below stock.top), got {}", show(depth)),
        ));
    }
    limits::DEPTH.check("operation.depth", depth)?;
    if depth / tool.stepdown > limits::MAX_PASSES {
        return Err(invalid(
            "operation.depth",
            format!(
                "needs {} passes of tool.stepdown = {} mm; at most {} are allowed (raise tool.stepdown)",
                (depth / tool.stepdown).ceil(),
                show(tool.stepdown),
                limits::MAX_PASSES
            ),
        ));
    }
    Ok(depth)
}

/// `operation.tolerance` (mm, default `defaults::TOLERANCE`): smaller than the
/// tool radius, within `limits::TOLERANCE`.
fn resolve_tolerance(given: Option<f64>, diameter: f64) -> Result<f64, JobError> {
    let tolerance = given.unwrap_or(defaults::TOLERANCE);
    if tolerance >= diameter / 2.0 {
        return Err(invalid(
            "operation.tolerance",
            format!(
                "must be smaller than the tool radius ({} mm), got {}{}",
                show(diameter / 2.0),
                show(tolerance),
                if given.is_none() {
                    " (the default): set it for so small a tool"
                } else {
                    ""
                }
            ),
        ));
    }
    limits::TOLERANCE.check("operation.tolerance", tolerance)
}

/// A boss clears `⌈margin / stepover⌉` rings around itself at every level:
/// at most `limits::MAX_MARGIN_RINGS`.
fn check_margin_rings(kind: OperationKind, stock: &Stock, tool: &Tool) -> Result<(), JobError> {
    let rings = (stock.margin / tool.stepover).ceil();
    if kind == OperationKind::Boss && rings > limits::MAX_MARGIN_RINGS {
        return Err(invalid(
            "stock.margin",
            format!(
                "= {} mm is {rings} clearing rings of tool.stepover = {} mm around a boss, at every level; at most {} are allowed (lower the margin or raise tool.stepover)",
                show(stock.margin),
                show(tool.stepover),
                limits::MAX_MARGIN_RINGS
            ),
        ));
    }
    Ok(())
}

/// A boss or cavity has `⌈depth / stepdown⌉` levels: fewer than
/// `limits::MAX_LEVELS`.
fn check_levels(kind: OperationKind, depth: f64, tool: &Tool) -> Result<(), JobError> {
    let levels = (depth / tool.stepdown - 1e-9).ceil();
    if kind != OperationKind::Profile && levels >= limits::MAX_LEVELS as f64 {
        return Err(invalid(
            "operation.depth",
            format!(
                "needs {levels} levels of tool.stepdown = {} mm; a boss or cavity has fewer than {} (raise tool.stepdown)",
                show(tool.stepdown),
                limits::MAX_LEVELS
            ),
        ));
    }
    Ok(())
}

/// `[profile]`: refused for a profile operation, defaulted for a boss or cavity.
fn resolve_profile_table(
    kind: OperationKind,
    profile: Option<RawProfile>,
    depth: f64,
) -> Result<Option<DepthProfile>, JobError> {
    if kind == OperationKind::Profile {
        if profile.is_some() {
            return Err(invalid(
                "profile",
                "only applies to operation.kind = \"boss\" or \"cavity\"",
            ));
        }
        return Ok(None);
    }
    Ok(Some(super::profile::resolve(
        profile.unwrap_or_default(),
        depth,
    )?))
}

/// `[finish]`, if given: only for a boss or cavity.
fn resolve_finish_table(
    kind: OperationKind,
    finish: Option<RawFinish>,
    tool: &Tool,
) -> Result<Option<Finish>, JobError> {
    match finish {
        None => Ok(None),
        Some(_) if kind == OperationKind::Profile => Err(invalid(
            "finish",
            "only applies to operation.kind = \"boss\" or \"cavity\" (a profile's walls are the tool's own)",
        )),
        Some(f) => Ok(Some(f.resolve(tool)?)),
    }
}

/// `operation.stock_to_leave` (mm): defaults to
/// `finish::defaults::STOCK_TO_LEAVE` with a `[finish]`, else 0; only a boss or
/// cavity may leave stock.
fn resolve_stock_to_leave(
    kind: OperationKind,
    given: Option<f64>,
    has_finish: bool,
) -> Result<f64, JobError> {
    let stock_to_leave = limits::STOCK_TO_LEAVE.check(
        "operation.stock_to_leave",
        given.unwrap_or(if has_finish {
            finish::defaults::STOCK_TO_LEAVE
        } else {
            0.0
        }),
    )?;
    if stock_to_leave > 0.0 && kind == OperationKind::Profile {
        return Err(invalid(
            "operation.stock_to_leave",
            "only applies to operation.kind = \"boss\" or \"cavity\"",
        ));
    }
    Ok(stock_to_leave)
}
