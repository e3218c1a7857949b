//! `[tool]` into a [`Tool`]: the flat roughing cutter, its feeds (mm/min),
//! spindle (rev/min), stepdown and stepover (mm) and ramp angle (degrees).

use super::resolve::show;
use super::{defaults, invalid, limits, CutterShape, JobError, RawTool, Tool};

/// `[tool]` with defaults applied and every value checked; `tool.diameter` is
/// required (mm).
pub(super) fn resolve(t: RawTool) -> Result<Tool, JobError> {
    let diameter = limits::TOOL_DIAMETER.check(
        "tool.diameter",
        t.diameter
            .ok_or_else(|| invalid("tool.diameter", "is required (mm)"))?,
    )?;
    Ok(Tool {
        shape: CutterShape::Flat,
        corner: 0.0,
        diameter,
        feed: limits::FEED.check("tool.feed", t.feed.unwrap_or(defaults::FEED))?,
        plunge_feed: limits::FEED.check(
            "tool.plunge_feed",
            t.plunge_feed.unwrap_or(defaults::PLUNGE_FEED),
        )?,
        spindle: limits::SPINDLE.check("tool.spindle", t.spindle.unwrap_or(defaults::SPINDLE))?,
        stepdown: limits::STEPDOWN
            .check("tool.stepdown", t.stepdown.unwrap_or(defaults::STEPDOWN))?,
        stepover: resolve_stepover(t.stepover, diameter)?,
        ramp_angle: limits::RAMP_ANGLE.check(
            "tool.ramp_angle",
            t.ramp_angle.unwrap_or(defaults::RAMP_ANGLE),
        )?,
    })
}

/// `tool.stepover` (mm, default `defaults::STEPOVER_FRACTION` of the
/// diameter): at least `limits::MIN_STEPOVER_FRACTION` of the diameter, and
/// at most the radius so that neighbouring clearing rings overlap.
fn resolve_stepover(stepover: Option<f64>, diameter: f64) -> Result<f64, JobError> {
    let so = limits::STEPOVER.check(
        "tool.stepover",
        stepover.unwrap_or(defaults::STEPOVER_FRACTION * diameter),
    )?;
    if so < diameter * limits::MIN_STEPOVER_FRACTION {
        return Err(invalid(
            "tool.stepover",
            format!(
                "must be at least {} of tool.diameter ({} mm): finer steps multiply the clearing rings and the run time, got {}",
                show(limits::MIN_STEPOVER_FRACTION),
                show(diameter * limits::MIN_STEPOVER_FRACTION),
                show(so)
            ),
        ));
    }
    if so > diameter / 2.0 {
        return Err(invalid(
            "tool.stepover",
            format!(
                "must be at most the tool radius ({} mm) so neighbouring rings overlap, got {}",
                show(diameter / 2.0),
                show(so)
            ),
        ));
    }
    Ok(so)
}
