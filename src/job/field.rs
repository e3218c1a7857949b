//! `[field]` into a [`FieldSpec`], and the `"auto"`-or-number keys it shares
//! with `shape.part[i].singularities`.

use super::resolve::auto_word;
use super::{invalid, limits, AutoOr, FieldSpec, JobError, RawField};

/// `[field]`: each key `"auto"` (chosen by the solver, `None`) or a value.
pub(super) fn resolve(f: RawField) -> Result<FieldSpec, JobError> {
    let singularities = resolve_singularities("field.singularities", f.singularities)?;
    let pseudo_boundary = match f.pseudo_boundary {
        None => None,
        Some(AutoOr::Word(w)) => {
            auto_word("field.pseudo_boundary", &w, "a distance in mm")?;
            None
        }
        Some(AutoOr::Int(d)) => {
            Some(limits::PSEUDO_BOUNDARY.check("field.pseudo_boundary", d as f64)?)
        }
        Some(AutoOr::Float(d)) => Some(limits::PSEUDO_BOUNDARY.check("field.pseudo_boundary", d)?),
    };
    Ok(FieldSpec {
        singularities,
        pseudo_boundary,
    })
}

/// A singularity count at `key`: `"auto"` (`None`) or a whole number up to
/// `limits::MAX_SINGULARITIES`.
pub(super) fn resolve_singularities(
    key: &str,
    value: Option<AutoOr>,
) -> Result<Option<usize>, JobError> {
    Ok(match value {
        None => None,
        Some(AutoOr::Word(w)) => {
            auto_word(key, &w, "a whole number of singularities")?;
            None
        }
        Some(AutoOr::Float(x)) => {
            return Err(invalid(
                key,
                format!("must be \"auto\" or a whole number, got {x:?}"),
            ))
        }
        Some(AutoOr::Int(n)) => Some(limits::count(
            key,
            n,
            limits::MAX_SINGULARITIES,
            "singularities",
        )?),
    })
}
