//! Resolution: [`RawJob::resolve_with`] applies the defaults and checks every
//! value, one resolver per table (`tool.rs`, `shape.rs`, `stock.rs`,
//! `operation.rs`, `field.rs`, `machine.rs`), and the small checkers they
//! share (`finite`, `one_of`, `at_most_one`, `show`, ...).

use super::font::Sources;
use super::{
    defaults, echo, field, harmonic, invalid, limits, operation, polyharmonic, shape, stock, tool,
    tube, Job, JobError, Output, RawJob, RawOutput,
};
use crate::geometry::svgfile::SvgSize;
use crate::geometry::ShapeSource;

/// Of `keys`, each with whether the job gives it, at most one: the error
/// names the first two given (keyed on the first) and says `rule`; else the
/// one given, if any.
pub(super) fn at_most_one<'a>(
    keys: &[(&'a str, bool)],
    rule: &str,
) -> Result<Option<&'a str>, JobError> {
    let mut given = keys.iter().filter(|k| k.1).map(|k| k.0);
    match (given.next(), given.next()) {
        (Some(first), Some(second)) => Err(invalid(
            first,
            format!("and {second} are both given; {rule}"),
        )),
        (first, _) => Ok(first),
    }
}

/// `x` as the user wrote it, short: `-3`, `0.5`, `1e300` (never 300 digits).
pub(super) fn show(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{x}")
    } else {
        format!("{x:?}")
    }
}

pub(super) fn finite(key: &str, x: f64) -> Result<f64, JobError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(invalid(
            key,
            format!("must be a finite number, got {}", show(x)),
        ))
    }
}

pub(super) fn one_of(key: &str, value: &str, accepted: &[&str]) -> Result<(), JobError> {
    if accepted.contains(&value) {
        Ok(())
    } else {
        Err(invalid(
            key,
            format!(
                "has no value `{}`; accepted: {}",
                echo::clip(value),
                accepted
                    .iter()
                    .map(|a| format!("`{a}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ))
    }
}

/// A job name must make a safe file name: letters, digits, `-`, `_`, `.`, not
/// starting with `.`.
fn check_name(key: &str, name: &str) -> Result<(), JobError> {
    let ok = !name.is_empty()
        && !name.starts_with('.')
        && name.len() <= 64
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'));
    if ok {
        Ok(())
    } else {
        Err(invalid(
            key,
            format!(
                "must be 1 to 64 of the characters A-Z a-z 0-9 - _ . (not starting with .), got {:?}",
                echo::clip(name)
            ),
        ))
    }
}

impl RawJob {
    /// Apply defaults and check every value (see `docs/job-format.md`), with
    /// files and font names found through `src`. The tables in the order their checks run: the tool
    /// first (the letter spacing defaults to its diameter), then the shape,
    /// the stock, the operation with `[profile]` and `[finish]`, the field,
    /// the machine and the output.
    pub(crate) fn resolve_with(self, name_hint: &str, src: &Sources<'_>) -> Result<Job, JobError> {
        let name = resolve_job_name(self.job.and_then(|j| j.name), name_hint)?;
        let tool = tool::resolve(self.tool.unwrap_or_default())?;
        let mut shape = shape::resolve(self.shape.unwrap_or_default(), tool.diameter, src)?;
        check_height_per_tool(&shape, tool.diameter)?;
        let stock = stock::resolve(self.stock.unwrap_or_default())?;
        let surface_depth = match &shape {
            ShapeSource::HarmonicBezier(spec) => Some(harmonic::patch_depth(spec)?),
            ShapeSource::Polyharmonic(spec) => Some(polyharmonic::relief_depth(spec)?),
            ShapeSource::PdeTube(spec) => Some(spec.height),
            _ => None,
        };
        let operation::Resolved {
            operation,
            profile,
            finish,
        } = operation::resolve(
            self.operation.unwrap_or_default(),
            &tool,
            &stock,
            (self.profile, self.finish),
            (surface_depth, matches!(shape, ShapeSource::PdeTube(_))),
        )?;
        set_file_tolerance(&mut shape, operation.tolerance);
        if let ShapeSource::PdeTube(spec) = &mut shape {
            tube::check(spec, &operation, stock.top, finish.as_ref())?;
        }
        let field = field::resolve(self.field.unwrap_or_default())?;
        let machine = self.machine.unwrap_or_default().resolve()?;
        let output = resolve_output(self.output.unwrap_or_default())?;
        Ok(Job {
            name,
            shape,
            tool,
            stock,
            operation,
            field,
            machine,
            profile,
            output,
            finish,
        })
    }
}

/// `job.name`, or else the file name `name_hint`: either must make a safe
/// output file name ([`check_name`]).
fn resolve_job_name(given: Option<String>, name_hint: &str) -> Result<String, JobError> {
    match given {
        Some(n) => {
            check_name("job.name", &n)?;
            Ok(n)
        }
        None => {
            check_name("job.name", name_hint).map_err(|_| {
                invalid(
                    "job.name",
                    format!(
                        "is needed: the file name {name_hint:?} does not make a safe output name"
                    ),
                )
            })?;
            Ok(name_hint.to_string())
        }
    }
}

/// An SVG or DXF file's curves are flattened to `operation.tolerance` (mm).
fn set_file_tolerance(shape: &mut ShapeSource, tolerance: f64) {
    match shape {
        ShapeSource::SvgFile(f) => f.tolerance = tolerance,
        ShapeSource::DxfFile(f) => f.tolerance = tolerance,
        _ => {}
    }
}

/// `[output]`: whether arcs are written, and the largest arc radius (mm).
fn resolve_output(o: RawOutput) -> Result<Output, JobError> {
    Ok(Output {
        arcs: o.arcs.unwrap_or(defaults::ARCS),
        max_arc_radius: limits::MAX_ARC_RADIUS.check(
            "output.max_arc_radius",
            o.max_arc_radius.unwrap_or(defaults::MAX_ARC_RADIUS),
        )?,
    })
}

/// The shape's height against the tool: a sign thousands of tool diameters
/// tall has kilometres of tool path (`limits::MAX_HEIGHT_PER_DIAMETER`).
fn check_height_per_tool(shape: &ShapeSource, diameter: f64) -> Result<(), JobError> {
    let height = match shape {
        ShapeSource::Text { height, .. } => Some(*height),
        ShapeSource::SvgPath { height, .. } => *height,
        ShapeSource::SvgFile(f) => match f.size {
            SvgSize::Height(h) => Some(h),
            _ => None,
        },
        ShapeSource::DxfFile(_) => None,
        ShapeSource::Composite(c) => c.height,
        // Its size is bounded by limits::PATCH_SIZE and check_extent.
        ShapeSource::HarmonicBezier(_) | ShapeSource::Polyharmonic(_) => None,
        // Its sizes by limits::TUBE_SIZE, its height by limits::DEPTH.
        ShapeSource::PdeTube(_) => None,
    };
    match height {
        Some(h) if h / diameter > limits::MAX_HEIGHT_PER_DIAMETER => Err(invalid(
            "shape.height",
            format!(
                "is {} mm, more than {} times tool.diameter ({} mm): the tool path would run to kilometres; use a larger tool or a smaller shape",
                show(h),
                limits::MAX_HEIGHT_PER_DIAMETER,
                show(diameter)
            ),
        )),
        _ => Ok(()),
    }
}

pub(super) fn auto_word(key: &str, word: &str, what: &str) -> Result<(), JobError> {
    if word == "auto" {
        Ok(())
    } else {
        Err(invalid(
            key,
            format!("must be \"auto\" or {what}, got {word:?}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use crate::job::parse_job;
    use crate::job::tests::{err_key, parse, with, GOOD};
    use std::path::Path;

    #[test]
    fn name_defaults_to_hint_and_must_be_safe() {
        let text = GOOD.replace("name = \"letter-a\"\n", "");
        assert_eq!(parse(&text).unwrap().name, "hint");
        let (k, _) = err_key(&GOOD.replace("letter-a", "../evil"));
        assert_eq!(k, "job.name");
        let e = parse_job(&text, "a b", Path::new(".")).unwrap_err();
        assert_eq!(e.key(), Some("job.name"));
    }

    #[test]
    fn output_and_coolant() {
        let j = parse(&with("output", "arcs = false\nmax_arc_radius = 250")).unwrap();
        assert!(!j.output.arcs);
        assert_eq!(j.output.max_arc_radius, 250.0);
        assert!(
            parse(&with("machine", "coolant = true"))
                .unwrap()
                .machine
                .coolant
        );
        assert_eq!(
            err_key(&with("output", "max_arc_radius = 0")).0,
            "output.max_arc_radius"
        );
        assert_eq!(err_key(&with("output", "arcs = 1")).0, "output.arcs");
        assert_eq!(err_key(&with("output", "helix = true")).0, "output.helix");
    }
}
