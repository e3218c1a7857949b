//! `[[shape.part]]` and `shape.result` into a [`Composition`]: each part a
//! primitive (`polygon`, `svg`, `text`) or derived from earlier parts (`of`,
//! with `op` or `level`), and the result a bounded part. Parts are numbered
//! from 1 in messages, in the order of the file: `shape.part[2].level`.

use super::font::{resolve_font, Sources};
use super::resolve::{at_most_one, one_of, show};
use super::text::{check_line, check_text};
use super::{defaults, echo, field, invalid, limits, JobError, RawPart};
use crate::geometry::{BoolOp, Composition, Part, PartSource, Vec2};

/// The accepted values of `shape.part.op`.
pub(crate) const PART_OPS: &[&str] = &["union", "intersect", "subtract", "invert"];

/// `[[shape.part]]` and `shape.result` into a composition (its `height` and
/// `origin` are left for the caller).
pub(super) fn resolve(
    raw: Vec<RawPart>,
    result: Option<String>,
    src: &Sources<'_>,
) -> Result<Composition, JobError> {
    check_part_count(raw.len())?;
    // Every name first, so that a reference to a later part can say so.
    let names = part_names(&raw)?;
    let mut parts: Vec<Part> = Vec::with_capacity(raw.len());
    for (i, p) in raw.into_iter().enumerate() {
        let k = format!("shape.part[{}]", i + 1);
        let key = |field: &str| format!("{k}.{field}");
        let source = resolve_part_source(&k, &names[..i], &names[i..], &p, src)?;
        let level = resolve_level(&key("level"), p.level)?;
        let singularities = field::resolve_singularities(&key("singularities"), p.singularities)?;
        parts.push(Part {
            name: names[i].clone(),
            source,
            level,
            singularities,
        });
    }
    let explicit = result.is_some();
    let result = resolve_result(result, &names)?;
    check_result_bounded(&parts, &names, &result, explicit)?;
    Ok(Composition {
        parts,
        result,
        height: None,
        origin: Vec2::ZERO,
    })
}

/// At least one part, at most `limits::MAX_PARTS` (each may need a field solve).
fn check_part_count(n: usize) -> Result<(), JobError> {
    if n == 0 {
        return Err(invalid(
            "shape.part",
            "must have at least one part ([[shape.part]] tables)",
        ));
    }
    if n > limits::MAX_PARTS {
        return Err(invalid(
            "shape.part",
            format!(
                "has {} parts; at most {} are allowed (each may need a field solve)",
                n,
                limits::MAX_PARTS
            ),
        ));
    }
    Ok(())
}

/// Every part's `name`: required, not blank, unique.
fn part_names(raw: &[RawPart]) -> Result<Vec<String>, JobError> {
    let mut names: Vec<String> = Vec::with_capacity(raw.len());
    for (i, p) in raw.iter().enumerate() {
        let key = format!("shape.part[{}].name", i + 1);
        let name = p.name.as_deref().ok_or_else(|| {
            invalid(
                &key,
                "is required: parts refer to each other, and shape.result to a part, by name",
            )
        })?;
        if name.trim().is_empty() {
            return Err(invalid(&key, format!("must not be empty, got {name:?}")));
        }
        if let Some(j) = names.iter().position(|n| n == name) {
            return Err(invalid(
                &key,
                format!("{name:?} is already the name of shape.part[{}]", j + 1),
            ));
        }
        names.push(name.to_string());
    }
    Ok(names)
}

/// A part's `level`: an equipotential value strictly in (0, 1).
fn resolve_level(key: &str, level: Option<f64>) -> Result<Option<f64>, JobError> {
    match level {
        None => Ok(None),
        Some(l) if l.is_finite() && l > 0.0 && l < 1.0 => Ok(Some(l)),
        Some(l) => Err(invalid(
            key,
            format!("must be strictly between 0 and 1, got {}", show(l)),
        )),
    }
}

/// `shape.result`: a part's name; the last part when not given.
fn resolve_result(result: Option<String>, names: &[String]) -> Result<String, JobError> {
    match result {
        None => Ok(names[names.len() - 1].clone()),
        Some(r) if names.contains(&r) => Ok(r),
        Some(r) => Err(invalid(
            "shape.result",
            format!(
                "names an unknown part {:?} (the parts: {})",
                echo::clip(&r),
                names.join(", ")
            ),
        )),
    }
}

/// Bounded or not, part by part: an inversion is the unbounded R² − Ω, and
/// what is built from one may be too (a union if all its parts are, an
/// intersection if any is, a difference if its first is).
fn bounded_parts(parts: &[Part], names: &[String]) -> Vec<bool> {
    let mut bounded: Vec<bool> = Vec::with_capacity(parts.len());
    for p in parts {
        let b = |n: &String| bounded[names.iter().position(|m| m == n).unwrap_or(0)];
        let is_bounded = match &p.source {
            PartSource::Polygon(_) | PartSource::Svg(_) | PartSource::Text { .. } => true,
            PartSource::Ref(n) => b(n),
            PartSource::Op { op, of } => match op {
                BoolOp::Invert => false,
                BoolOp::Union => of.iter().all(b),
                BoolOp::Intersect => of.iter().any(b),
                BoolOp::Subtract => of.first().is_some_and(b),
            },
        };
        bounded.push(is_bounded);
    }
    bounded
}

/// The result must be bounded: the void of a part cannot be cut. `explicit`
/// says whether `shape.result` was given (else the last part is the result).
fn check_result_bounded(
    parts: &[Part],
    names: &[String],
    result: &str,
    explicit: bool,
) -> Result<(), JobError> {
    let bounded = bounded_parts(parts, names);
    let r = names.iter().position(|n| *n == result).unwrap_or(0);
    if bounded[r] {
        return Ok(());
    }
    let why = if matches!(
        parts[r].source,
        PartSource::Op {
            op: BoolOp::Invert,
            ..
        }
    ) {
        "an invert".to_string()
    } else {
        "built from an invert so that it is unbounded too".to_string()
    };
    let which = if explicit {
        format!("shape.part[{}]", r + 1)
    } else {
        format!(
            "shape.part[{}]; without shape.result the last part is the result",
            r + 1
        )
    };
    Err(invalid(
        "shape.result",
        format!(
            "names {result:?}, which is {why} ({which}): the void R² − Ω of a part is unbounded and cannot be cut; use an invert only inside another operation, e.g. intersect"
        ),
    ))
}

/// What part `k` is made of. `earlier` are the names of the parts before it,
/// `this_and_later` its own name and those after it.
fn resolve_part_source(
    k: &str,
    earlier: &[String],
    this_and_later: &[String],
    p: &RawPart,
    src: &Sources<'_>,
) -> Result<PartSource, JobError> {
    check_part_keys(k, p)?;
    if let Some(source) = resolve_primitive(k, p, src)? {
        return Ok(source);
    }
    resolve_derived(k, earlier, this_and_later, p)
}

/// The key exclusivity of a part: at most one primitive, a primitive without
/// `of` or `op`, and `font`, `size` only with `text`.
fn check_part_keys(k: &str, p: &RawPart) -> Result<(), JobError> {
    let key = |field: &str| format!("{k}.{field}");
    let names = [key("polygon"), key("svg"), key("text")];
    let primitive = at_most_one(
        &[
            (&names[0], p.polygon.is_some()),
            (&names[1], p.svg.is_some()),
            (&names[2], p.text.is_some()),
        ],
        "a primitive part is exactly one of polygon, svg, text",
    )?;
    if let Some(prim) = primitive {
        for (field, given) in [("of", p.of.is_some()), ("op", p.op.is_some())] {
            if given {
                return Err(invalid(
                    &key(field),
                    format!(
                        "cannot be combined with {prim}: a part is either a primitive (polygon, svg or text) or derived from earlier parts (of, with op)"
                    ),
                ));
            }
        }
    }
    if p.text.is_none() {
        for (field, given) in [("font", p.font.is_some()), ("size", p.size.is_some())] {
            if given {
                return Err(invalid(
                    &key(field),
                    format!("only applies to a text part ({})", key("text")),
                ));
            }
        }
    }
    Ok(())
}

/// A primitive part (`polygon`, `svg` or `text` with its `font` and `size` in
/// mm), or `None` for a derived one.
fn resolve_primitive(
    k: &str,
    p: &RawPart,
    src: &Sources<'_>,
) -> Result<Option<PartSource>, JobError> {
    let key = |field: &str| format!("{k}.{field}");
    if let Some(points) = &p.polygon {
        return resolve_polygon(&key("polygon"), points).map(|v| Some(PartSource::Polygon(v)));
    }
    if let Some(d) = &p.svg {
        if d.trim().is_empty() {
            return Err(invalid(&key("svg"), "must not be empty (SVG path data)"));
        }
        return Ok(Some(PartSource::Svg(d.clone())));
    }
    let Some(text) = &p.text else {
        return Ok(None);
    };
    check_line(&key("text"), text, "a text part is one line")?;
    check_text(&key("text"), text)?;
    let font = resolve_font(&key("font"), &key("text"), p.font.as_deref(), text, src)?;
    let size = match p.size {
        None => defaults::PART_TEXT_SIZE,
        Some(s) => limits::PART_SIZE.check(&key("size"), s)?,
    };
    Ok(Some(PartSource::Text {
        text: text.clone(),
        font,
        size,
    }))
}

/// A part derived from earlier parts: `of` (checked by [`check_of`]) with
/// `op`, or a single part with `level` (a [`PartSource::Ref`]).
fn resolve_derived(
    k: &str,
    earlier: &[String],
    this_and_later: &[String],
    p: &RawPart,
) -> Result<PartSource, JobError> {
    let key = |field: &str| format!("{k}.{field}");
    let Some(of) = &p.of else {
        if p.op.is_some() {
            return Err(invalid(
                &key("op"),
                format!(
                    "needs {}: the names of the earlier parts it combines",
                    key("of")
                ),
            ));
        }
        return Err(invalid(
            k,
            "has no source: a part is a primitive (polygon, svg or text) or is derived from earlier parts (of, with op; or of one part with level)",
        ));
    };
    let of = &of.0;
    check_of(&key("of"), of, earlier, this_and_later)?;
    let Some(op) = &p.op else {
        if of.len() > 1 {
            return Err(invalid(
                &key("op"),
                format!(
                    "is required when {} names several parts: one of union, intersect, subtract",
                    key("of")
                ),
            ));
        }
        if p.level.is_none() {
            return Err(invalid(
                &key("level"),
                format!(
                    "is required when {} names a single part without op: without it the part is a plain copy of {:?}",
                    key("of"),
                    of[0]
                ),
            ));
        }
        return Ok(PartSource::Ref(of[0].clone()));
    };
    resolve_op(k, op, of)
}

/// `of` at `key`: not empty, each name an earlier part, none twice.
fn check_of(
    key: &str,
    of: &[String],
    earlier: &[String],
    this_and_later: &[String],
) -> Result<(), JobError> {
    if of.is_empty() {
        return Err(invalid(key, "must name at least one earlier part, got []"));
    }
    for (j, name) in of.iter().enumerate() {
        if earlier.contains(name) {
            if of[..j].contains(name) {
                return Err(invalid(key, format!("names {name:?} twice")));
            }
            continue;
        }
        let before = if earlier.is_empty() {
            "no part is defined before it".to_string()
        } else {
            format!("defined before it: {}", earlier.join(", "))
        };
        let message = match this_and_later.iter().position(|n| n == name) {
            Some(0) => format!("names the part itself, {name:?} (a part may only use parts defined before it; {before})"),
            Some(_) => format!("names {name:?}, which is defined after it (a part may only use parts defined before it; {before})"),
            None => format!("names an unknown part {:?} ({before})", echo::clip(name)),
        };
        return Err(invalid(key, message));
    }
    Ok(())
}

/// `op` of part `k` over the parts `of`: union, intersect and subtract take
/// at least 2 parts, invert exactly 1.
fn resolve_op(k: &str, op: &str, of: &[String]) -> Result<PartSource, JobError> {
    let key = |field: &str| format!("{k}.{field}");
    one_of(&key("op"), op, PART_OPS)?;
    let (bool_op, count_ok, needs) = match op {
        "union" => (BoolOp::Union, of.len() >= 2, "at least 2 parts"),
        "intersect" => (BoolOp::Intersect, of.len() >= 2, "at least 2 parts"),
        "subtract" => (
            BoolOp::Subtract,
            of.len() >= 2,
            "at least 2 parts (the first minus the others)",
        ),
        _ => (BoolOp::Invert, of.len() == 1, "exactly 1 part"),
    };
    if !count_ok {
        return Err(invalid(
            &key("of"),
            format!(
                "must name {needs} for op = {op:?}, got {} ({})",
                of.len(),
                of.iter()
                    .map(|n| format!("{n:?}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    Ok(PartSource::Op {
        op: bool_op,
        of: of.to_vec(),
    })
}

/// A polygon: at least 3 finite points, not all on one line.
fn resolve_polygon(key: &str, points: &[[f64; 2]]) -> Result<Vec<Vec2>, JobError> {
    if points.len() < 3 || points.len() > limits::MAX_POLYGON_POINTS {
        return Err(invalid(
            key,
            format!(
                "must have 3 to {} points [x, y], got {}",
                limits::MAX_POLYGON_POINTS,
                points.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(points.len());
    for (j, [x, y]) in points.iter().enumerate() {
        if !(limits::DESIGN.contains(*x) && limits::DESIGN.contains(*y)) {
            return Err(invalid(
                key,
                format!(
                    "point {} must be finite numbers in {}, got [{}, {}]",
                    j + 1,
                    limits::DESIGN.describe(),
                    show(*x),
                    show(*y)
                ),
            ));
        }
        out.push(Vec2::new(*x, *y));
    }
    // Not all on one line: some point is off the line from the first point to the
    // one farthest from it.
    let p0 = out[0];
    let far = out
        .iter()
        .copied()
        .max_by(|a, b| (*a - p0).dot(*a - p0).total_cmp(&(*b - p0).dot(*b - p0)))
        .unwrap_or(p0);
    let d = far - p0;
    let len2 = d.dot(d);
    let flat = len2 == 0.0 || out.iter().all(|&q| (d.cross(q - p0)).abs() <= 1e-12 * len2);
    if flat {
        return Err(invalid(
            key,
            "has all its points on one line: it encloses no area",
        ));
    }
    Ok(out)
}
