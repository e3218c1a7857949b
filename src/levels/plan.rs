//! Levels of a boss or cavity: the schedule of z ([`plan_schedule`]), and for
//! every level ([`plan_level`]) its contour Γ(s_k) (the source's section) and
//! its own field: the source's, or a new MFS problem solved on Γ(s_k) (the
//! paper, Section 7: "The corresponding MFS problem is solved at each level to
//! find the offset lines", [`crate::field::section`]). The planner only plans:
//! the paths of each level are traced in its field by `toolpath::zlevel`, which
//! `pipeline` calls level by level.

use super::schedule;
use super::sections::{LevelField, Sections};
use crate::estimate::{check_bound, level_area, levels_bound, GuardError, LowerBound};
use crate::field::{self, FieldError};
use crate::geometry::{polygons_bbox, DistanceIndex, Vec2};

/// Grid spacing for sampling u, mm: fine enough that marching squares finds every
/// component of Γ(s) of the letters; vertices are exact and chords are then refined
/// to the tolerance by `field::level::refine`.
pub(crate) const GRID_SPACING: f64 = 0.4;

/// What the level planner reports for one level.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelInfo {
    /// Z (absolute).
    pub z: f64,
    /// Equipotential value.
    pub s: f64,
    /// Singularities of the level's MFS solve.
    pub n: usize,
    /// Collocation points.
    pub m: usize,
    /// Max boundary error of the level's solve.
    pub max_error: f64,
    /// Pseudo-boundary distance chosen for the level's solve, mm.
    pub(crate) distance: f64,
    /// Cavity: the uncut share of the reachable area (measured on a grid).
    pub uncut: Option<f64>,
    /// Smallest clearance of the level's moves from the gouge check against
    /// Γ(s_k), mm (filled in by the pipeline after linking).
    pub min_clearance: f64,
    /// Seconds spent on this level's MFS solve (wall clock, for benchmarks).
    pub t_solve: f64,
    /// Seconds spent tracing and clearing this level (wall clock).
    pub t_paths: f64,
}

/// Inputs of the level planner.
pub(crate) struct LevelJob<'a> {
    /// The part: its z range, its sections, the level's parameter and,
    /// when it knows one, the level's field ([`Sections`]).
    pub(crate) source: &'a dyn Sections,
    /// True for a cavity (the mould), false for a boss.
    pub(crate) cavity: bool,
    /// Stock top, mm.
    pub(crate) top: f64,
    /// Largest depth per level.
    pub(crate) stepdown: f64,
    /// Largest horizontal step between neighbouring levels.
    pub(crate) max_scallop: f64,
    /// Stock margin around the largest level, mm.
    pub(crate) margin: f64,
    /// Outer radius for the level problems.
    pub(crate) outer_radius: f64,
    /// Chord tolerance, mm: a section's solve flattens within it.
    pub(crate) tol: f64,
    /// The tool's radius, its stepover and its cutting feed (mm, mm, mm/min),
    /// for the lower bound of the machining time.
    pub(crate) tool: ToolFigures,
    /// `machine.max_hours`: the job stops before any level is traced when its
    /// lower bound ([`crate::estimate::levels_bound`]) passes it.
    pub(crate) max_hours: f64,
}

/// What the time bound needs of the tool.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ToolFigures {
    /// Tool radius, mm.
    pub(crate) radius: f64,
    /// Largest distance between neighbouring clearing rings, mm.
    pub(crate) stepover: f64,
    /// Cutting feed, mm/min.
    pub(crate) feed: f64,
}

/// The largest error a level's field may have: a hundredth of 1 − s (issue
/// 12), so that the field places Γ(s) where s says.
pub(crate) fn level_error_bound(s: f64) -> f64 {
    (1.0 - s) / 100.0
}

pub(crate) use crate::field::level::CHORD_FRACTION;

/// The box of nothing: every point extends it.
pub(super) const EMPTY_BOX: (Vec2, Vec2) = (
    Vec2 {
        x: f64::MAX,
        y: f64::MAX,
    },
    Vec2 {
        x: f64::MIN,
        y: f64::MIN,
    },
);

/// The levels to plan, known before any is: the z schedule, the cutting
/// order, the stock rectangle and the time bound.
#[derive(Clone, Debug)]
pub(crate) struct Schedule {
    /// Every level below the top, top down.
    pub(crate) levels: Vec<Level>,
    /// The order in which the levels are cut, as indices into `levels`
    /// ([`super::cutting_order`]).
    pub(crate) order: Vec<usize>,
    /// The stock rectangle (lower-left, upper-right): the largest level (a
    /// boss's base, a cavity's rim) plus the margin, mm.
    pub(crate) stock: (Vec2, Vec2),
    /// Seconds spent extracting contours and choosing the z schedule (wall
    /// clock).
    pub(crate) t_schedule: f64,
    /// The lower bound of the machining time, from the levels' contours.
    pub(crate) bound: LowerBound,
}

/// One level of the schedule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Level {
    /// Its number, from 1 below the top.
    pub(crate) k: usize,
    /// Its z, relative to the stock top (negative).
    pub(crate) z: f64,
    /// The level below, when this one was added for the scallop bound: it
    /// then clears only the band out to that level's contour, which is cut
    /// first. `None` for a level of the plain stepdown schedule.
    pub(crate) z_below: Option<f64>,
}

/// One level planned: what its paths are traced from.
pub(crate) struct PlannedLevel {
    /// Z (absolute).
    pub(crate) z: f64,
    /// Equipotential value (the source's level value).
    pub(crate) s: f64,
    /// The level's name in paths and messages, `level k (z …)`.
    pub(crate) label: String,
    /// The section as the source gives it: the part's material on the left
    /// (a cavity's: the mould's), what the paths are traced along.
    pub(crate) section: Vec<Vec<Vec2>>,
    /// Γ(s_k) with a boss's material on the left (a cavity's section
    /// reversed): what the gouge check measures against.
    pub(crate) part: Vec<Vec<Vec2>>,
    /// The level's own field and its figures.
    pub(crate) field: LevelField,
    /// A level added for the scallop bound: the width of the band it clears,
    /// mm (the gap to the level below).
    pub(crate) reach: Option<f64>,
    /// Warnings about this level.
    pub(crate) warnings: Vec<String>,
    /// Seconds spent on the level's field (wall clock, for benchmarks).
    pub(crate) t_solve: f64,
}

impl PlannedLevel {
    /// What the planner reports for the level, once its paths are traced
    /// (`uncut`: a cavity's uncut share; `t_paths`: the seconds they took).
    pub(crate) fn info(&self, uncut: Option<f64>, t_paths: f64) -> LevelInfo {
        LevelInfo {
            z: self.z,
            s: self.s,
            n: self.field.field.n(),
            m: self.field.figures.m,
            max_error: self.field.figures.max_error,
            distance: self.field.figures.distance,
            uncut,
            min_clearance: f64::NAN,
            t_solve: self.t_solve,
            t_paths,
        }
    }
}

/// The z schedule of `job`, its cutting order, the stock rectangle and the
/// time bound; refused when the bound passes `machine.max_hours`.
pub(crate) fn plan_schedule(job: &LevelJob) -> Result<Schedule, PlanError> {
    let t_start = std::time::Instant::now();
    let c = LevelCurves { job };
    let depth = c.depth();
    let zs = level_schedule(job, &c)?;
    // The levels of the plain stepdown schedule clear everything; the ones added
    // for the scallop bound only the band down to the level below them, which is
    // cut before them ([`super::cutting_order`]).
    let rough_z = stepdown_levels(depth, job.stepdown);
    let is_rough = |z: f64| rough_z.iter().any(|&zr| (zr - z).abs() < 1e-9);
    let t_schedule = t_start.elapsed().as_secs_f64();
    let stock = stock_rectangle(job, &c);
    let bound = time_bound(job, &c, &rough_z, &zs, stock);
    let t = job.tool;
    check_bound(&bound, job.max_hours, 2.0 * t.radius, t.stepover)?;
    let levels: Vec<Level> = (1..zs.len())
        .map(|k| Level {
            k,
            z: zs[k],
            z_below: zs.get(k + 1).copied().filter(|_| !is_rough(zs[k])),
        })
        .collect();
    let rough: Vec<bool> = levels.iter().map(|l| l.z_below.is_none()).collect();
    Ok(Schedule {
        levels,
        order: super::cutting_order(&rough),
        stock,
        t_schedule,
        bound,
    })
}

/// The z of the plain stepdown schedule, 0 down to −depth.
fn stepdown_levels(depth: f64, stepdown: f64) -> Vec<f64> {
    let n_rough = ((depth / stepdown) - 1e-9).ceil().max(1.0) as usize;
    (0..=n_rough)
        .map(|k| -depth * k as f64 / n_rough as f64)
        .collect()
}

/// The lower bound of the machining time ([`levels_bound`]) from the areas
/// of the stepdown levels `rough_z` and of all levels `zs` below the top, a
/// boss's within the stock rectangle.
fn time_bound(
    job: &LevelJob,
    c: &LevelCurves,
    rough_z: &[f64],
    zs: &[f64],
    stock: (Vec2, Vec2),
) -> LowerBound {
    let stock = (!job.cavity).then_some(stock);
    let area_at = |zrel: f64| level_area(&c.at(zrel), stock);
    let t = job.tool;
    levels_bound(
        &rough_z[1..].iter().map(|&z| area_at(z)).collect::<Vec<_>>(),
        &zs[1..].iter().map(|&z| area_at(z)).collect::<Vec<_>>(),
        2.0 * t.radius,
        t.stepover,
        t.feed,
    )
}

/// The curves the planner cuts along, from the job's [`Sections`].
struct LevelCurves<'a> {
    job: &'a LevelJob<'a>,
}

impl LevelCurves<'_> {
    /// The part's depth, mm (top minus bottom of its z range).
    fn depth(&self) -> f64 {
        let (bottom, top) = self.job.source.z_range();
        top - bottom
    }

    /// The curves at `zrel` (relative to the stock top) with the material of
    /// a boss on their left: a boss's section, a cavity's section reversed
    /// (the pocket inside them).
    fn at(&self, zrel: f64) -> Vec<Vec<Vec2>> {
        let section = self.job.source.section(zrel);
        if self.job.cavity {
            reversed(&section)
        } else {
            section
        }
    }

    /// The horizontal step between the contours of the levels at `za` and
    /// `zb`: the largest distance from the wider contour's points to the
    /// narrower one (NaN if a distance is).
    fn gap(&self, za: f64, zb: f64) -> f64 {
        let (ca, cb) = (self.at(za), self.at(zb));
        let (wide, narrow) = if self.job.cavity { (ca, cb) } else { (cb, ca) };
        let idx = DistanceIndex::new(&narrow);
        wide.iter()
            .flatten()
            .map(|&p| idx.distance(p))
            .fold(0.0, crate::num::max_or_nan)
    }
}

/// Every polygon run backwards.
fn reversed(polys: &[Vec<Vec2>]) -> Vec<Vec<Vec2>> {
    polys
        .iter()
        .map(|p| p.iter().rev().copied().collect())
        .collect()
}

/// The z of every level, relative to the stock top, from 0 down
/// ([`schedule`]: the stepdown levels plus those the scallop bound needs).
fn level_schedule(job: &LevelJob, c: &LevelCurves) -> Result<Vec<f64>, PlanError> {
    let gap_nan = std::cell::Cell::new(false);
    let gap = |za: f64, zb: f64| -> f64 {
        let g = c.gap(za, zb);
        if g.is_nan() {
            gap_nan.set(true);
        }
        g
    };
    let max_levels = crate::job::limits::MAX_LEVELS;
    let depth = c.depth();
    let zs = schedule(depth, job.stepdown, job.max_scallop, 0.02, max_levels, &gap).ok_or(
        PlanError::TooManyLevels {
            max_scallop: job.max_scallop,
            max_levels,
        },
    )?;
    if gap_nan.get() {
        return Err(PlanError::GapNotANumber);
    }
    Ok(zs)
}

/// The stock rectangle: the largest level (a boss's base, a cavity's rim)
/// plus the margin.
fn stock_rectangle(job: &LevelJob, c: &LevelCurves) -> (Vec2, Vec2) {
    let base = c.at(if job.cavity { 0.0 } else { -c.depth() });
    let (blo, bhi) = polygons_bbox(&base).unwrap_or(EMPTY_BOX);
    let m = Vec2::new(job.margin, job.margin);
    (blo - m, bhi + m)
}

/// Level `level` of `job`: its section, its own field ([`level_field`]) and,
/// when it was added for the scallop bound, the band it clears.
pub(crate) fn plan_level(job: &LevelJob, level: &Level) -> Result<PlannedLevel, PlanError> {
    use crate::count::{set_stage, Stage};
    let c = LevelCurves { job };
    let (k, z) = (level.k, level.z);
    set_stage(Stage::LevelGrid);
    let s = job.source.level_value(z);
    // Material on the left (for a cavity the mould is outside Γ(s): the
    // section's loops are Γ(s) reversed).
    let section = job.source.section(z);
    let part = if job.cavity {
        reversed(&section)
    } else {
        section.clone()
    };
    if part.is_empty() {
        return Err(PlanError::NoContour {
            level: k,
            z: job.top + z,
            s,
        });
    }
    let t0 = std::time::Instant::now();
    let label = format!("level {k} (z {:.3})", job.top + z);
    let mut warnings = Vec::new();
    set_stage(Stage::LevelSolve);
    let field = level_field(job, &section, z, s, &label, &mut warnings)?;
    let t_solve = t0.elapsed().as_secs_f64();
    set_stage(Stage::LevelGrid);
    let reach = level.z_below.map(|zb| c.gap(z, zb));
    if reach.is_some_and(f64::is_nan) {
        return Err(PlanError::BandNotANumber { level: label });
    }
    Ok(PlannedLevel {
        z: job.top + z,
        s,
        label,
        section,
        part,
        field,
        reach,
        warnings,
        t_solve,
    })
}

/// A level's own field: the source's, when it knows one (the MFS boss: u/s),
/// with its warning under the level's name; else the level's MFS problem
/// solved on its section `oriented` (the MFS cavity, [`section_field`]).
fn level_field(
    job: &LevelJob,
    oriented: &[Vec<Vec2>],
    z: f64,
    s: f64,
    label: &str,
    warnings: &mut Vec<String>,
) -> Result<LevelField, PlanError> {
    match job.source.level_field(z) {
        Some(l) => {
            warnings.extend(l.warning.as_ref().map(|w| format!("{label}, {w}")));
            Ok(l)
        }
        None => section_field(oriented, job.tol, job.outer_radius, s, label),
    }
}

/// One line for every cavity level whose field errs above
/// `level_error_bound` (it was one line per level: ten on q-mould, all saying
/// the same): how many, the worst, and what it means for the part.
pub(crate) fn cavity_error_warning(info: &[LevelInfo]) -> Option<String> {
    let over: Vec<(usize, &LevelInfo)> = info
        .iter()
        .enumerate()
        .filter(|(_, l)| l.max_error > level_error_bound(l.s))
        .collect();
    let (k, worst) = over
        .iter()
        .max_by(|a, b| {
            (a.1.max_error / level_error_bound(a.1.s))
                .total_cmp(&(b.1.max_error / level_error_bound(b.1.s)))
        })
        .copied()?;
    Some(format!(
        "{} of {} levels have fields that err above a hundredth of 1 − s (worst: level {}, z {:.3}, s = {:.6}, {:.2e} against {:.1e}): each cut follows its level's polygon and is checked by geometry, so the part is as modelled; the field only steers the tracer there (every level's error is in the JSON report)",
        over.len(),
        info.len(),
        k + 1,
        worst.z,
        worst.s,
        worst.max_error,
        level_error_bound(worst.s)
    ))
}

/// A level's field solved by MFS on its section (the paper's Section 7): a
/// cavity's, the mould being outside Γ(s), so the level's problem is not the
/// shape's. An error above `level_error_bound` is reported once for all
/// cavity levels ([`cavity_error_warning`]; doubling N twice did not move it:
/// the limit is the level's polygon, whose vertices are kinks the smooth Γ(s)
/// does not have); NaN is an error.
fn section_field(
    oriented: &[Vec<Vec2>],
    tol: f64,
    outer_radius: f64,
    s: f64,
    label: &str,
) -> Result<LevelField, PlanError> {
    let (field, figures) = field::section::solve_section(oriented, tol, outer_radius)?;
    if figures.max_error.is_nan() {
        return Err(PlanError::FieldErrorNotANumber {
            level: label.to_string(),
            s,
        });
    }
    Ok(LevelField {
        field,
        figures,
        warning: None,
    })
}

/// Why planning levels failed.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// A level's field.
    #[error("{0}")]
    Field(#[from] FieldError),
    /// The job's lower bound passes `machine.max_hours`.
    #[error("{0}")]
    Guard(#[from] GuardError),
    /// The profile's lowest level does not close around the shape within the
    /// padding the grid grows to.
    #[error("the level s = {s} does not close within {pad:.0} mm of the shape; raise profile.s_bottom / profile.s2")]
    LevelOpen {
        /// The profile's bottom s.
        s: f64,
        /// The largest padding tried around the shape, mm.
        pad: f64,
    },
    /// The scallop bound needs more levels than a job may have.
    #[error("operation.max_scallop = {max_scallop} mm needs more than {max_levels} levels on this wall: raise it, or tool.stepdown")]
    TooManyLevels {
        /// The job's `operation.max_scallop`, mm.
        max_scallop: f64,
        /// The most levels allowed.
        max_levels: usize,
    },
    /// A level whose section is empty.
    #[error("level {level} (z {z:.3}, s = {s:.4}) has no contour")]
    NoContour {
        /// The level's index.
        level: usize,
        /// Its z, mm (absolute).
        z: f64,
        /// Its field value.
        s: f64,
    },
    /// A broken invariant: the band a level clears came out NaN.
    #[error("{level}: the band it clears is not a number (NaN): this is a pfcam bug, please report it with the job file")]
    BandNotANumber {
        /// The level, as `level k (z …)`.
        level: String,
    },
    /// A broken invariant: the max boundary error of a level's field came
    /// out NaN.
    #[error("{level}, s = {s:.6}: the max boundary error of its field is not a number (NaN): this is a pfcam bug, please report it with the job file")]
    FieldErrorNotANumber {
        /// The level, as `level k (z …)`.
        level: String,
        /// The level's field value.
        s: f64,
    },
    /// A broken invariant: the horizontal step between two levels came out
    /// NaN.
    #[error("the horizontal step between two levels is not a number (NaN): this is a pfcam bug, please report it with the job file")]
    GapNotANumber,
}

#[cfg(test)]
mod tests {
    use super::PlanError;

    /// The texts are the ones the variants had as strings (issue 16).
    #[test]
    fn nan_errors_say_the_strings_they_replace() {
        let (label, s) = ("level 3 (z -2.000)".to_string(), 0.123_456_78);
        let bug = "is not a number (NaN): this is a pfcam bug, please report it with the job file";
        let cases = [
            (
                PlanError::BandNotANumber {
                    level: label.clone(),
                },
                format!("{label}: the band it clears"),
            ),
            (
                PlanError::FieldErrorNotANumber {
                    level: label.clone(),
                    s,
                },
                format!("{label}, s = {s:.6}: the max boundary error of its field"),
            ),
        ];
        for (e, text) in cases {
            assert_eq!(e.to_string(), format!("{text} {bug}"));
        }
    }
}
