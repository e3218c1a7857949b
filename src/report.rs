//! The run report: per z-level and total figures of a run, as JSON
//! (`DIR/<job name>.json`) and as a short human table.
//!
//! A *level* is one cutting depth z: every feed move that ends at that z (the
//! plunge into it, the horizontal pass, any ramp down to it). For the profile
//! operation every level follows the same field, the part's own (s = 1 on the
//! part's boundary, Γ(1) offset by the tool radius), so every level reports that
//! solve's N and max boundary error; with z-levels of their own (s_k < 1) the
//! level's own solve goes there.

use crate::geometry::DistanceIndex;
use crate::job::Job;
use crate::pipeline::{RunOutput, SolveReport, FLATTEN_FRACTION};
use crate::toolpath::{gouge, Move, Section, Toolpath, Vec3};
use serde::Serialize;

/// What the first key of every pfcam JSON file says: `"generator": "pfcam <version>"`.
pub(crate) fn generator() -> String {
    format!("pfcam {}", env!("CARGO_PKG_VERSION"))
}

/// Two depths closer than this (mm) are the same level.
pub(crate) const Z_EPS: f64 = 1e-6;

/// The feed moves of one level, each with the point it starts from.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelMoves {
    /// The depth, mm.
    pub z: f64,
    /// (start point, move), in cutting order.
    pub moves: Vec<(Vec3, Move)>,
}

/// The levels of a run as its G-code header and report count them: for a boss
/// or cavity one per planned level (a section of the tool path each, whatever
/// depths its links and ramps pass through), shallowest first; for a profile,
/// [`split_levels`].
pub(crate) fn run_levels(out: &RunOutput) -> Vec<LevelMoves> {
    if out.levels.is_empty() || out.levels.len() != out.toolpath.sections.len() {
        return split_levels(&out.toolpath);
    }
    let mut at = out.toolpath.start;
    let mut levels = Vec::with_capacity(out.toolpath.sections.len());
    for sec in &out.toolpath.sections {
        let mut moves = Vec::new();
        for m in &sec.moves {
            if !matches!(m, Move::Rapid { .. }) {
                moves.push((at, *m));
            }
            at = m.to();
        }
        levels.push(LevelMoves { z: sec.z, moves });
    }
    // Shallowest first, as split_levels gives them: the sections are in
    // cutting order (levels::cutting_order), which is not z order.
    levels.sort_by(|a, b| b.z.total_cmp(&a.z));
    levels
}

/// Split a tool path's feed moves by level, shallowest level first. The levels
/// are the depths of the horizontal feed moves; a move that changes depth (a
/// plunge, or a ramp of a boss or cavity) belongs to the level it descends into,
/// the highest level at or below where it ends. Rapids belong to no level.
pub fn split_levels(tp: &Toolpath) -> Vec<LevelMoves> {
    let mut zs: Vec<f64> = Vec::new();
    let mut at = tp.start;
    for m in tp.moves() {
        let to = m.to();
        if !matches!(m, Move::Rapid { .. })
            && (to.z - at.z).abs() <= Z_EPS
            && !zs.iter().any(|z| (z - to.z).abs() <= Z_EPS)
        {
            zs.push(to.z);
        }
        at = to;
    }
    zs.sort_by(|a, b| b.total_cmp(a));
    let mut levels: Vec<LevelMoves> = zs
        .iter()
        .map(|&z| LevelMoves {
            z,
            moves: Vec::new(),
        })
        .collect();
    for (at, m) in tp.feed_moves() {
        let to = m.to();
        let k = zs
            .iter()
            .position(|&z| z <= to.z + Z_EPS)
            .unwrap_or(zs.len().saturating_sub(1));
        if let Some(l) = levels.get_mut(k) {
            l.moves.push((at, m));
        } else {
            levels.push(LevelMoves {
                z: to.z,
                moves: vec![(at, m)],
            });
        }
    }
    levels
}

pub(crate) use crate::toolpath::feed_length_time;

/// One level of the report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LevelReport {
    /// Depth, mm.
    pub(crate) z: f64,
    /// The equipotential value the level's path offsets (1 for a profile: the
    /// part's boundary).
    pub(crate) s: f64,
    /// Singularities N of the level's field.
    pub(crate) n: usize,
    /// Max boundary error of the level's field.
    pub(crate) max_boundary_error: f64,
    /// Feed length at this level (plunge and pass), mm.
    pub(crate) path_length_mm: f64,
    /// Smallest clearance (distance to the part − tool radius) of this level's
    /// moves from the independent gouge check, mm; null if none is below the
    /// stock top.
    pub(crate) min_clearance_mm: Option<f64>,
    /// Feed time at this level, seconds (acceleration ignored).
    pub(crate) time_s: f64,
    /// Cavity levels: the uncut share of the reachable area, measured on a grid
    /// of a tenth of the tool radius (null for other operations).
    pub(crate) uncut_share: Option<f64>,
}

/// Totals of the run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct Totals {
    /// Number of levels.
    pub(crate) levels: usize,
    /// Feed length, mm.
    pub(crate) cut_length_mm: f64,
    /// Rapid length, mm.
    pub(crate) rapid_length_mm: f64,
    /// Estimated time, seconds, rapids at the machine's rapid rate, acceleration
    /// ignored (as in the G-code header).
    pub(crate) time_s: f64,
    /// Smallest clearance over the whole path, mm (null if nothing is cut).
    pub(crate) min_clearance_mm: Option<f64>,
    /// Largest max boundary error over every solve.
    pub(crate) max_boundary_error: f64,
    /// Tracing steps that fell back to the geometric normal.
    pub(crate) fallbacks: usize,
}

/// One MFS solve in the report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct SolveEntry {
    /// What was solved.
    pub(crate) label: String,
    /// Singularities N.
    pub(crate) n: usize,
    /// Collocation points M.
    pub(crate) m: usize,
    /// Pseudo-boundary distance, mm.
    pub(crate) pseudo_boundary_mm: f64,
    /// Max boundary error.
    pub(crate) max_boundary_error: f64,
}

impl From<&SolveReport> for SolveEntry {
    fn from(r: &SolveReport) -> Self {
        SolveEntry {
            label: r.label.clone(),
            n: r.n,
            m: r.m,
            pseudo_boundary_mm: r.distance,
            max_boundary_error: r.max_error,
        }
    }
}

/// The whole report; `generator` is its first key, which is how pfcam recognises
/// its own JSON files (see `output`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RunReport {
    /// `pfcam <version>`.
    pub(crate) generator: String,
    /// The job's name.
    pub(crate) job: String,
    /// Operation, e.g. `profile outside`.
    pub(crate) operation: String,
    /// Tool diameter, mm.
    pub(crate) tool_diameter_mm: f64,
    /// Chord / gouge tolerance, mm.
    pub(crate) tolerance_mm: f64,
    /// Glyphs (regions) of the shape.
    pub(crate) glyphs: Vec<String>,
    /// The stock and where the work zero sits on it (as in the G-code header).
    pub stock: Option<StockReport>,
    /// Every MFS solve.
    pub(crate) solves: Vec<SolveEntry>,
    /// Per level, shallowest first.
    pub levels: Vec<LevelReport>,
    /// Totals.
    pub(crate) totals: Totals,
    /// Each G-code program of the run (one today: `<name>.nc`) with its
    /// header's lengths and time, and the job's lower bound.
    pub programs: Vec<ProgramReport>,
    /// Warnings of the run.
    pub(crate) warnings: Vec<String>,
}

/// One G-code program: the lengths and estimated time its header gives, the
/// lower bound of its machining time and the ratio of the two.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ProgramReport {
    /// The file, `<name>.nc`.
    pub file: String,
    /// Its tool's diameter, mm.
    pub(crate) tool_diameter_mm: f64,
    /// Feed length, mm (the header's `length: cut`).
    pub cut_length_mm: f64,
    /// Rapid length, mm (the header's `rapid`).
    pub rapid_length_mm: f64,
    /// Estimated time, s (the header's `estimated time`).
    pub time_s: f64,
    /// Lower bound of the machining time, s (docs/job-format.md, `max_hours`).
    pub lower_bound_s: f64,
    /// Its clearing part, s.
    pub lower_bound_clearing_s: f64,
    /// Its outline part, s.
    pub lower_bound_outline_s: f64,
    /// `time_s / lower_bound_s` (null when the bound is 0).
    pub time_over_bound: Option<f64>,
}

/// The G-code files of a job: `<name>.nc`, or with a `[finish]` tool
/// `<name>.rough.nc` and `<name>.finish.nc` (GRBL has no tool changer).
pub fn program_files(job: &Job) -> Vec<String> {
    if job.finish.is_some() {
        vec![
            format!("{}.rough.nc", job.name),
            format!("{}.finish.nc", job.name),
        ]
    } else {
        vec![format!("{}.nc", job.name)]
    }
}

impl ProgramReport {
    /// Every program of the run, roughing first.
    pub fn all(job: &Job, out: &RunOutput) -> Vec<ProgramReport> {
        let mut v = vec![ProgramReport::new(job, out)];
        if let (Some(f), Some(fj)) = (&out.finish, job.finishing()) {
            let st = crate::gcode::writer::program_stats(&f.toolpath, &fj);
            v.push(ProgramReport {
                file: program_files(job)[1].clone(),
                tool_diameter_mm: fj.tool.diameter,
                cut_length_mm: st.cut_length,
                rapid_length_mm: st.rapid_length,
                time_s: st.time_s,
                lower_bound_s: f.lower_bound_s,
                lower_bound_clearing_s: 0.0,
                lower_bound_outline_s: f.lower_bound_s,
                time_over_bound: (f.lower_bound_s > 0.0).then(|| st.time_s / f.lower_bound_s),
            });
        }
        v
    }

    /// The (roughing) program of `job` for the finished run `out`.
    pub(crate) fn new(job: &Job, out: &RunOutput) -> ProgramReport {
        let st = crate::gcode::writer::program_stats(&out.toolpath, job);
        let b = out.lower_bound;
        ProgramReport {
            file: program_files(job)[0].clone(),
            tool_diameter_mm: job.tool.diameter,
            cut_length_mm: st.cut_length,
            rapid_length_mm: st.rapid_length,
            time_s: st.time_s,
            lower_bound_s: b.total_s(),
            lower_bound_clearing_s: b.clearing_s,
            lower_bound_outline_s: b.outline_s,
            time_over_bound: (b.total_s() > 0.0).then(|| st.time_s / b.total_s()),
        }
    }
}

/// The stock of a run, in work coordinates (mm): the rectangle, its top and
/// safe Z, and how far the work zero X0 Y0 is from its left and front edges.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct StockReport {
    /// `"stock"` (a boss's or cavity's own stock rectangle) or `"sheet"` (a
    /// profile: the least sheet the tool sweeps).
    pub kind: String,
    /// Lower-left corner, X.
    pub x_min: f64,
    /// Lower-left corner, Y.
    pub y_min: f64,
    /// Upper-right corner, X.
    pub(crate) x_max: f64,
    /// Upper-right corner, Y.
    pub(crate) y_max: f64,
    /// Z of the stock's top.
    pub(crate) top: f64,
    /// Z of rapid moves.
    pub(crate) safe_z: f64,
    /// X0 measured from the stock's left edge.
    pub zero_from_left: f64,
    /// Y0 measured from the stock's front (low-Y) edge.
    pub zero_from_front: f64,
}

impl StockReport {
    fn new(job: &Job, out: &RunOutput) -> Option<StockReport> {
        let e = crate::gcode::stock_extent(&out.toolpath, job.tool.diameter / 2.0, out.stock)?;
        Some(StockReport {
            kind: if e.known { "stock" } else { "sheet" }.into(),
            x_min: e.lo.x,
            y_min: e.lo.y,
            x_max: e.hi.x,
            y_max: e.hi.y,
            top: job.stock.top,
            safe_z: job.stock.safe_z,
            zero_from_left: -e.lo.x,
            zero_from_front: -e.lo.y,
        })
    }
}

/// The field a level at depth `z` follows: (s, N, max boundary error). For the
/// profile every pass follows the shape's own field, s = 1 on the part, so this
/// is the first solve for every z. Operations with a solve per level (boss,
/// cavity) look their level up here by z.
pub(crate) fn level_field(out: &RunOutput, z: f64) -> (f64, usize, f64) {
    let _ = z;
    out.solves
        .first()
        .map_or((1.0, 0, f64::NAN), |r| (1.0, r.n, r.max_error))
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl Totals {
    /// The run's totals over its `levels` levels: lengths and time of the
    /// whole tool path, its least clearance, the worst boundary error of any
    /// solve (NaN if any is NaN or there is none) and the fallbacks.
    fn new(job: &Job, out: &RunOutput, levels: usize) -> Totals {
        let st = out.toolpath.stats(job.machine.rapid_rate);
        Totals {
            levels,
            cut_length_mm: st.cut_length,
            rapid_length_mm: st.rapid_length,
            time_s: st.time_s,
            min_clearance_mm: finite(out.min_clearance),
            max_boundary_error: out
                .solves
                .iter()
                .map(|r| r.max_error)
                .reduce(crate::num::max_or_nan)
                .unwrap_or(f64::NAN),
            fallbacks: out.fallbacks,
        }
    }
}

/// A boss's or cavity's levels: one section per level, with its own field,
/// and the gouge check already run against that level's Γ(s_k) by the
/// pipeline. Time is the feed moves' only.
fn planned_levels(job: &Job, out: &RunOutput) -> Vec<LevelReport> {
    out.toolpath
        .sections
        .iter()
        .zip(&out.levels)
        .map(|(sec, li)| {
            let one = Toolpath {
                start: out.toolpath.start,
                sections: vec![sec.clone()],
            };
            let st = one.stats(job.machine.rapid_rate);
            let feed_time = {
                let mut t = 0.0;
                let mut at = one.start;
                for m in &sec.moves {
                    t += feed_length_time(at, m).1;
                    at = m.to();
                }
                t
            };
            LevelReport {
                z: li.z,
                s: li.s,
                n: li.n,
                max_boundary_error: li.max_error,
                path_length_mm: st.cut_length,
                min_clearance_mm: finite(li.min_clearance),
                time_s: feed_time,
                uncut_share: li.uncut,
            }
        })
        .collect()
}

/// A profile's levels ([`split_levels`]), each gouge-checked here against
/// the part (flattened as the pipeline flattens it), with the shape's field.
fn profile_levels(job: &Job, out: &RunOutput) -> Vec<LevelReport> {
    let radius = job.tool.diameter / 2.0;
    let top = job.stock.top;
    let polys: Vec<Vec<_>> = out
        .shape
        .contours()
        .map(|c| c.flatten(job.operation.tolerance * FLATTEN_FRACTION))
        .collect();
    let part = DistanceIndex::new(&polys);
    split_levels(&out.toolpath)
        .into_iter()
        .map(|lv| {
            let (mut len, mut time) = (0.0, 0.0);
            let mut moves = Vec::with_capacity(2 * lv.moves.len());
            for (from, m) in &lv.moves {
                let (l, t) = feed_length_time(*from, m);
                len += l;
                time += t;
                // A rapid to the start point makes each move checkable alone
                // (the gouge check skips rapids).
                moves.push(Move::Rapid { to: *from });
                moves.push(*m);
            }
            let sub = Toolpath {
                start: lv.moves.first().map(|(f, _)| *f).unwrap_or_default(),
                sections: vec![Section {
                    label: String::new(),
                    z: lv.z,
                    moves,
                }],
            };
            let g = gouge::check(&sub, &part, radius, top);
            let (s, n, max_err) = level_field(out, lv.z);
            LevelReport {
                z: lv.z,
                s,
                n,
                max_boundary_error: max_err,
                path_length_mm: len,
                min_clearance_mm: (g.moves_checked > 0)
                    .then_some(g.min_clearance)
                    .and_then(finite),
                time_s: time,
                uncut_share: None,
            }
        })
        .collect()
}

impl RunReport {
    /// The report of a finished run.
    pub fn new(job: &Job, out: &RunOutput) -> RunReport {
        let levels = if !out.levels.is_empty() {
            planned_levels(job, out)
        } else {
            profile_levels(job, out)
        };
        let totals = Totals::new(job, out, levels.len());
        RunReport {
            generator: generator(),
            job: job.name.clone(),
            operation: format!("{:?} {:?}", job.operation.kind, job.operation.side).to_lowercase(),
            tool_diameter_mm: job.tool.diameter,
            tolerance_mm: job.operation.tolerance,
            glyphs: out.glyphs.clone(),
            stock: StockReport::new(job, out),
            solves: out.solves.iter().map(SolveEntry::from).collect(),
            levels,
            totals,
            programs: ProgramReport::all(job, out),
            warnings: out.warnings.clone(),
        }
    }

    /// Pretty JSON, ending with a newline; `"generator"` is on the second line.
    pub fn to_json(&self) -> String {
        // Serialising plain numbers, strings and options cannot fail; NaN and
        // infinities become null.
        let mut s = serde_json::to_string_pretty(self).unwrap_or_else(|_| "{}".into());
        s.push('\n');
        s
    }

    /// A short human table: one row per level, then the totals.
    pub fn table(&self) -> String {
        let mut s = format!(
            "{:>9} {:>8} {:>5} {:>10} {:>11} {:>13} {:>9}\n",
            "z (mm)", "s", "N", "max error", "length (mm)", "clearance (mm)", "time"
        );
        let clear = |c: Option<f64>| c.map_or("-".to_string(), |c| format!("{c:.4}"));
        for l in &self.levels {
            s += &format!(
                "{:>9.3} {:>8.5} {:>5} {:>10.2e} {:>11.1} {:>14} {:>9}\n",
                l.z,
                l.s,
                l.n,
                l.max_boundary_error,
                l.path_length_mm,
                clear(l.min_clearance_mm),
                crate::gcode::format_duration(l.time_s)
            );
        }
        let t = &self.totals;
        s += &format!(
            "{:>9} {:>8} {:>5} {:>10.2e} {:>11.1} {:>14} {:>9}",
            "total",
            t.levels,
            "",
            t.max_boundary_error,
            t.cut_length_mm,
            clear(t.min_clearance_mm),
            crate::gcode::format_duration(t.time_s)
        );
        s
    }
}

#[cfg(test)]
mod tests {

    #[test]
    fn ramps_belong_to_the_level_they_enter() {
        use crate::toolpath::{Move, Section, Toolpath, Vec3};
        let lin = |x: f64, z: f64| Move::Linear {
            to: Vec3::new(x, 0.0, z),
            feed: 100.0,
        };
        let tp = Toolpath {
            start: Vec3::new(0.0, 0.0, 5.0),
            sections: vec![Section {
                label: String::new(),
                z: -2.0,
                moves: vec![
                    Move::Rapid {
                        to: Vec3::new(0.0, 0.0, 1.0),
                    },
                    lin(0.0, -1.0), // plunge into level -1
                    lin(10.0, -1.0),
                    lin(20.0, -1.3), // a ramp down to level -2
                    lin(30.0, -1.6),
                    lin(40.0, -2.0),
                    lin(50.0, -2.0),
                ],
            }],
        };
        let lv = split_levels(&tp);
        assert_eq!(lv.len(), 2, "{lv:?}");
        assert_eq!((lv[0].z, lv[0].moves.len()), (-1.0, 2));
        assert_eq!((lv[1].z, lv[1].moves.len()), (-2.0, 4));
    }

    use super::*;

    fn lin(x: f64, y: f64, z: f64) -> Move {
        Move::Linear {
            to: Vec3::new(x, y, z),
            feed: 600.0,
        }
    }

    #[test]
    fn levels_split_by_end_z_shallowest_first() {
        let tp = Toolpath {
            start: Vec3::new(0.0, 0.0, 5.0),
            sections: vec![Section {
                label: "a".into(),
                z: -2.0,
                moves: vec![
                    Move::Rapid {
                        to: Vec3::new(0.0, 0.0, 1.0),
                    },
                    lin(0.0, 0.0, -1.0),
                    lin(10.0, 0.0, -1.0),
                    lin(10.0, 0.0, -2.0),
                    lin(0.0, 0.0, -2.0),
                    Move::Rapid {
                        to: Vec3::new(0.0, 0.0, 5.0),
                    },
                ],
            }],
        };
        let lv = split_levels(&tp);
        assert_eq!(lv.len(), 2);
        assert_eq!((lv[0].z, lv[0].moves.len()), (-1.0, 2));
        assert_eq!((lv[1].z, lv[1].moves.len()), (-2.0, 2));
        let len: f64 = lv[0]
            .moves
            .iter()
            .map(|(f, m)| feed_length_time(*f, m).0)
            .sum();
        assert!((len - 12.0).abs() < 1e-12);
        let (_, t) = feed_length_time(Vec3::new(0.0, 0.0, -1.0), &lv[0].moves[1].1);
        assert!((t - 1.0).abs() < 1e-12, "10 mm at 600 mm/min is one second");
    }
}
