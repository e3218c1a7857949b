//! `[profile]` into a [`DepthProfile`]: the depth z = φ(s) (mm below
//! `stock.top`) of the equipotential s ∈ (0, 1) for a boss or cavity. Each
//! kind takes only its own keys.

use super::resolve::{one_of, show};
use super::{defaults, invalid, limits, JobError, RawProfile, PROFILE_KINDS};
use crate::profile::DepthProfile;

/// `[profile]` with `depth` = `operation.depth`, which spline and table
/// points must agree with (their lowest z is −depth).
pub(super) fn resolve(p: RawProfile, depth: f64) -> Result<DepthProfile, JobError> {
    let kind = p
        .kind
        .clone()
        .unwrap_or_else(|| defaults::PROFILE_KIND.into());
    one_of("profile.kind", &kind, PROFILE_KINDS)?;
    match kind.as_str() {
        "linear" => resolve_linear(&p, &kind, depth),
        "sigmoid" | "power" => resolve_sigmoid_or_power(&p, &kind, depth),
        _ => resolve_points(p, &kind, depth),
    }
}

/// An equipotential value at `key`: strictly inside (0, 1).
fn unit(key: &str, v: f64) -> Result<f64, JobError> {
    if v.is_finite() && v > 0.0 && v < 1.0 {
        Ok(v)
    } else {
        Err(invalid(
            key,
            format!("must be an equipotential value in (0, 1), got {}", show(v)),
        ))
    }
}

/// Refuses `key` when `present`: it belongs to another `profile.kind`.
fn unused(kind: &str, key: &str, present: bool) -> Result<(), JobError> {
    if present {
        Err(invalid(
            key,
            format!("does not apply to profile.kind = {kind:?}"),
        ))
    } else {
        Ok(())
    }
}

/// `linear`: depth falls linearly to the floor at `s_bottom`.
fn resolve_linear(p: &RawProfile, kind: &str, depth: f64) -> Result<DepthProfile, JobError> {
    unused(kind, "profile.s1", p.s1.is_some())?;
    unused(kind, "profile.s2", p.s2.is_some())?;
    unused(kind, "profile.steepness", p.steepness.is_some())?;
    unused(kind, "profile.exponent", p.exponent.is_some())?;
    unused(kind, "profile.points", p.points.is_some())?;
    let s_bottom = unit("profile.s_bottom", p.s_bottom.unwrap_or(defaults::S_BOTTOM))?;
    Ok(DepthProfile::Linear { s_bottom, depth })
}

/// `sigmoid` (with `steepness`) or `power` (with `exponent`) between the
/// equipotentials s2 < s1.
fn resolve_sigmoid_or_power(
    p: &RawProfile,
    kind: &str,
    depth: f64,
) -> Result<DepthProfile, JobError> {
    unused(kind, "profile.s_bottom", p.s_bottom.is_some())?;
    unused(kind, "profile.points", p.points.is_some())?;
    let sigmoid = kind == "sigmoid";
    if sigmoid {
        unused(kind, "profile.exponent", p.exponent.is_some())?;
    } else {
        unused(kind, "profile.steepness", p.steepness.is_some())?;
    }
    let (d1, d2, dk) = if sigmoid {
        defaults::SIGMOID
    } else {
        defaults::POWER
    };
    let s1 = unit("profile.s1", p.s1.unwrap_or(d1))?;
    let s2 = unit("profile.s2", p.s2.unwrap_or(d2))?;
    if s2 >= s1 {
        return Err(invalid(
            "profile.s2",
            format!("must be below profile.s1 ({}), got {}", show(s1), show(s2)),
        ));
    }
    Ok(if sigmoid {
        let steepness = limits::STEEPNESS.check("profile.steepness", p.steepness.unwrap_or(dk))?;
        DepthProfile::Sigmoid {
            s1,
            s2,
            steepness,
            depth,
        }
    } else {
        let exponent = limits::EXPONENT.check("profile.exponent", p.exponent.unwrap_or(dk))?;
        DepthProfile::Power {
            s1,
            s2,
            exponent,
            depth,
        }
    })
}

/// `spline` or `table` through `points` [[s, z], ...] (z in mm relative to
/// `stock.top`), at most `limits::MAX_PROFILE_POINTS`, reaching −depth.
fn resolve_points(p: RawProfile, kind: &str, depth: f64) -> Result<DepthProfile, JobError> {
    unused(kind, "profile.s_bottom", p.s_bottom.is_some())?;
    unused(kind, "profile.s1", p.s1.is_some())?;
    unused(kind, "profile.s2", p.s2.is_some())?;
    unused(kind, "profile.steepness", p.steepness.is_some())?;
    unused(kind, "profile.exponent", p.exponent.is_some())?;
    let points = p.points.ok_or_else(|| {
        invalid(
            "profile.points",
            "is required for a spline or table: [[s, z], ...] with z in mm relative to stock.top",
        )
    })?;
    if points.len() > limits::MAX_PROFILE_POINTS {
        return Err(invalid(
            "profile.points",
            format!(
                "has {} points; at most {} are allowed",
                points.len(),
                limits::MAX_PROFILE_POINTS
            ),
        ));
    }
    let prof = DepthProfile::from_points(&points, kind == "spline")
        .map_err(|e| invalid("profile.points", e.to_string()))?;
    if (prof.depth() - depth).abs() > 1e-9 {
        return Err(invalid(
            "profile.points",
            format!(
                "the lowest point is at z = {} but operation.depth is {}: they must agree",
                show(-prof.depth()),
                show(depth)
            ),
        ));
    }
    Ok(prof)
}
