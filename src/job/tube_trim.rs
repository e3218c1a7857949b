//! `[[shape.trim]]` of a PDE tube: a slot cut into the tube from its top,
//! given by two angles (degrees) and two heights (mm, machine z), the
//! rectangle u ∈ [u(z₀), u(z₁)], v ∈ [a₀, a₁] in the surface's parameter
//! plane (docs/method.md §16.3). What the part's mesh and its finishing can
//! carry decides the limits: one trim, reaching the part's top (a trim closed
//! inside the wall is a window, overhung by the wall above it), its floor
//! above the foot, narrower than 180°, on a boss.

use super::resolve::show;
use super::{invalid, JobError, RawTrim};
use crate::sources::pde_tube::spec::TrimRect;

/// Most trims of a tube: two trims meeting one section would leave pie
/// pieces touching only at the spine (a solid joined along a line).
pub(crate) const MAX_TRIMS: usize = 1;

/// The widest trim, degrees: a wider one makes the spine an outside corner of
/// the kept pie, round which the finishing rings do not turn.
pub(crate) const MAX_TRIM_DEGREES: f64 = 180.0;

/// The key of trim `i` (0-based) and field `f`, as TOML errors name it.
fn key(i: usize, f: &str) -> String {
    format!("shape.trim[{}].{f}", i + 1)
}

/// The trims as written: angles in radians, z still machine z (made
/// relative to the part's top by [`check`]).
pub(super) fn resolve(raw: Option<Vec<RawTrim>>) -> Result<Vec<TrimRect>, JobError> {
    let raw = raw.unwrap_or_default();
    if raw.len() > MAX_TRIMS {
        return Err(invalid(
            "shape.trim",
            format!("{} [[shape.trim]] tables; a tube takes at most {MAX_TRIMS}: two trims meeting one section would leave its pieces joined only at the spine", raw.len()),
        ));
    }
    raw.iter()
        .enumerate()
        .map(|(i, t)| {
            let angles = t.angles.ok_or_else(|| {
                invalid(
                    &key(i, "angles"),
                    "is required: [from, to] in degrees, counter-clockwise from +x",
                )
            })?;
            let z = t.z.ok_or_else(|| {
                invalid(
                    &key(i, "z"),
                    "is required: [bottom, top] in mm (machine z), top at the part's top",
                )
            })?;
            let [a0, a1] = angles;
            if !angles.iter().all(|a| a.is_finite() && a.abs() <= 360.0) {
                return Err(invalid(&key(i, "angles"), format!("= [{}, {}]: each must be a number in [-360, 360] (degrees)", show(a0), show(a1))));
            }
            if !(a1 > a0 && a1 - a0 < MAX_TRIM_DEGREES) {
                return Err(invalid(&key(i, "angles"), format!("= [{}, {}]: the second must be above the first by less than {MAX_TRIM_DEGREES}° (the trim runs counter-clockwise from the first to the second)", show(a0), show(a1))));
            }
            if !z.iter().all(|v| v.is_finite()) || z[1] <= z[0] {
                return Err(invalid(&key(i, "z"), format!("= [{}, {}]: must be [bottom, top] (mm), bottom below top", show(z[0]), show(z[1]))));
            }
            Ok(TrimRect {
                angles: [a0.to_radians(), a1.to_radians()],
                z,
            })
        })
        .collect()
}

/// With the stock top and the part's depth known: each trim within the
/// part, reaching its top, on a boss; its z made relative to the top.
pub(super) fn check(
    trims: &mut [TrimRect],
    top: f64,
    depth: f64,
    boss: bool,
) -> Result<(), JobError> {
    for (i, t) in trims.iter_mut().enumerate() {
        if !boss {
            return Err(invalid(
                "shape.trim",
                "applies to a boss only (operation.kind = \"boss\"): a mould's trims are not implemented",
            ));
        }
        let foot = top - depth;
        let [z0, z1] = t.z;
        if z1 < top {
            return Err(invalid(
                &key(i, "z"),
                format!(
                    "= [{}, {}] ends below the part's top z = {}: the trim would be a window in the wall, and the wall above it overhangs the opening at z = {} (a 3-axis mill cannot reach under it); a trim must reach the top: z = [{}, {}]",
                    show(z0), show(z1), show(top), show(z1), show(z0), show(top)
                ),
            ));
        }
        if z0 <= foot || z0 >= top {
            return Err(invalid(
                &key(i, "z"),
                format!(
                    "= [{}, {}]: its bottom must be above the part's foot z = {} and below its top z = {} (a trim down to the foot is not implemented: the part's mesh joins the whole foot curve to the floor)",
                    show(z0), show(z1), show(foot), show(top)
                ),
            ));
        }
        t.z = [z0 - top, 0.0];
    }
    Ok(())
}
