//! `[stock]` into a [`Stock`]: the top of the stock, the safe and retract
//! heights above it and the margin cleared around the shape (all mm).

use super::resolve::{finite, show};
use super::{defaults, invalid, limits, JobError, RawStock, Stock};

/// `[stock]` with defaults applied: `safe_z` defaults to
/// `defaults::SAFE_CLEARANCE` above `top`, `retract_z` to `safe_z`.
pub(super) fn resolve(s: RawStock) -> Result<Stock, JobError> {
    let top = limits::STOCK_TOP.check("stock.top", s.top.unwrap_or(defaults::STOCK_TOP))?;
    let safe_z = resolve_safe_z(s.safe_z, top)?;
    let retract_z = resolve_retract(s.retract_z, top, safe_z)?;
    let margin = limits::MARGIN.check("stock.margin", s.margin.unwrap_or(defaults::MARGIN))?;
    Ok(Stock {
        top,
        safe_z,
        retract_z,
        margin,
    })
}

/// `stock.safe_z`: above `top`, by at most `limits::SAFE_CLEARANCE.hi` mm.
fn resolve_safe_z(safe_z: Option<f64>, top: f64) -> Result<f64, JobError> {
    let safe_z = finite(
        "stock.safe_z",
        safe_z.unwrap_or(top + defaults::SAFE_CLEARANCE),
    )?;
    if safe_z > top && !limits::SAFE_CLEARANCE.contains(safe_z - top) {
        return Err(invalid(
            "stock.safe_z",
            format!(
                "must be at most {} mm above stock.top ({}), got {}",
                show(limits::SAFE_CLEARANCE.hi),
                show(top),
                show(safe_z)
            ),
        ));
    }
    if safe_z <= top {
        return Err(invalid(
            "stock.safe_z",
            format!(
                "must be above stock.top ({}), got {}",
                show(top),
                show(safe_z)
            ),
        ));
    }
    Ok(safe_z)
}

/// `stock.retract_z`: above the stock top (nothing is ever higher: the
/// tool may rapid over any of it there), at most `stock.safe_z`; `safe_z` when
/// not given.
fn resolve_retract(retract_z: Option<f64>, top: f64, safe_z: f64) -> Result<f64, JobError> {
    let Some(z) = retract_z else {
        return Ok(safe_z);
    };
    let z = finite("stock.retract_z", z)?;
    if z <= top || z > safe_z {
        return Err(invalid(
            "stock.retract_z",
            format!(
                "must be above stock.top ({}) and at most stock.safe_z ({}), got {}",
                show(top),
                show(safe_z),
                show(z)
            ),
        ));
    }
    Ok(z)
}
