//! `pfcam check`: a G-code file against GRBL 1.1's rules, with totals.
//!
//! Every line goes through the same tokenizer and modal-state tracker the
//! streamer uses ([`super::parse`]), so a finding carries GRBL's own error number
//! (`error:N`) wherever GRBL has one: unsupported words (20), two words of one
//! modal group (21), no feed rate (22), a repeated letter (25), an arc off its
//! circle (33) or with too small an R (34), a line too long for GRBL's line
//! buffer (11), and the rest of [`ModalState::execute`]'s checks. On top of that
//! the checker
//! - warns about what GRBL accepts but is likely a mistake: `G0`/`G1` without axis
//!   words, arcs whose start is unknown (GRBL checks them against wherever the
//!   machine stands), `$` lines, a program without `M2`/`M30`;
//! - checks the moves against the machine's travel when it is known
//!   ([`Limits`]);
//! - adds up the program: bounding boxes, cutting and rapid length, estimated time
//!   ([`Totals`]).
//!
//! Lengths and times are those of the moves as GRBL would run them (arcs by their
//! true, possibly helical, length); a move that starts where the position is not
//! yet known (the first `G0 Z` of a program, or anything after `G28`/`G30`/`G53`)
//! cannot be measured and is counted in [`Totals::unmeasured_moves`].

use super::motion;
use super::parse::{clean_line, has_block_delete, tokenize, FeedMode, ModalState, Motion, Word};
use serde::Serialize;
use std::fmt;

/// GRBL 1.1's line buffer, characters: a block (comments and spaces removed)
/// must be shorter, as the newline takes the last place; GRBL answers `error:11`
/// otherwise.
pub(crate) const GRBL_LINE_BUFFER: usize = 80;

/// Longest raw line (comments included) before the checker warns; pfcam's own
/// writer stays within it ([`super::writer::MAX_LINE_LEN`]).
pub(crate) const MAX_RAW_LINE: usize = 80;

/// Slack for the travel comparisons, mm: far below a step, only absorbs the
/// binary rounding of coordinates read from text.
const TRAVEL_EPS: f64 = 1e-6;

/// How bad a finding is: errors make `pfcam check` fail, warnings do not.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// GRBL would reject the line, or the program does not fit the machine.
    Error,
    /// GRBL accepts it, but it is probably not what was meant.
    Warning,
}

/// One thing found on one line.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Finding {
    /// 1-based line number in the file.
    pub line: usize,
    /// Error or warning.
    pub severity: Severity,
    /// GRBL 1.1's error number (`error:N`) when GRBL has one for it.
    pub(crate) code: Option<u8>,
    /// What is wrong, in pfcam's words.
    pub message: String,
}

impl fmt::Display for Finding {
    /// `error 33: message`, `error: message` (no GRBL number) or
    /// `warning: message`; the caller puts `FILE:LINE: ` in front.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.severity, self.code) {
            (Severity::Error, Some(c)) => write!(f, "error {c}: {}", self.message),
            (Severity::Error, None) => write!(f, "error: {}", self.message),
            (Severity::Warning, Some(c)) => write!(f, "warning {c}: {}", self.message),
            (Severity::Warning, None) => write!(f, "warning: {}", self.message),
        }
    }
}

/// The machine's travel, for the limit checks.
///
/// GRBL's convention (default `$23`, homing to the positive end): after homing,
/// machine coordinates run from 0 down to −`travel` on each axis. Work
/// coordinates are machine coordinates minus `work_offset` (G54's offset).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Limits {
    /// X, Y, Z travel in mm (GRBL's `$130`, `$131`, `$132`), each > 0.
    pub travel: [f64; 3],
    /// Machine position of the work origin, mm. Known: every move is checked
    /// against [−travel, 0] in machine coordinates. Unknown: only the size of the
    /// program (max − min of every axis) is checked against the travel, since no
    /// choice of work origin can make a larger program fit.
    pub work_offset: Option<[f64; 3]>,
}

/// What the checker needs to know about the machine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CheckOptions {
    /// Rate assumed for `G0` in the time estimate, mm/min.
    pub rapid_rate: f64,
    /// Travel limits, if known.
    pub limits: Option<Limits>,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            rapid_rate: crate::job::defaults::RAPID_RATE,
            limits: None,
        }
    }
}

/// Per-axis minimum and maximum, mm; `None` for an axis never known.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub(crate) struct Extent {
    /// Smallest X, Y, Z.
    pub(crate) min: [Option<f64>; 3],
    /// Largest X, Y, Z.
    pub(crate) max: [Option<f64>; 3],
}

impl Extent {
    fn add(&mut self, k: usize, v: f64) {
        self.min[k] = Some(self.min[k].map_or(v, |m| m.min(v)));
        self.max[k] = Some(self.max[k].map_or(v, |m| m.max(v)));
    }

    fn add_point(&mut self, p: &[Option<f64>; 3]) {
        for (k, v) in p.iter().enumerate() {
            if let Some(v) = v {
                self.add(k, *v);
            }
        }
    }

    /// `X 0 .. 30, Y 0 .. 20, Z -2 .. 5` (`?` for an axis never known).
    fn show(&self) -> String {
        let mut s = Vec::new();
        for (k, letter) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            s.push(match (self.min[k], self.max[k]) {
                (Some(a), Some(b)) => format!("{letter} {} .. {}", num(a), num(b)),
                _ => format!("{letter} ?"),
            });
        }
        s.join(", ")
    }
}

/// What the program adds up to.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Totals {
    /// Lines in the file.
    pub(crate) lines: usize,
    /// Lines with a block to send (not blank, not only a comment).
    pub(crate) blocks: usize,
    /// Every position the program reaches (work coordinates, mm).
    pub(crate) bounds: Extent,
    /// Where feed moves (`G1`/`G2`/`G3`/`G38.x`) go, starts included, arcs by their
    /// true extent: the same as the `cut min`/`cut max` pfcam writes in its header.
    pub(crate) cut_bounds: Extent,
    /// Length of feed moves, mm.
    pub cut_length: f64,
    /// Length of rapid moves, mm.
    pub rapid_length: f64,
    /// Total of `G4` dwells, s.
    pub dwell_s: f64,
    /// Estimated time, s: feed moves at their feed, rapids at the rapid rate,
    /// dwells; acceleration ignored.
    pub time_s: f64,
    /// The rapid rate used, mm/min.
    pub(crate) rapid_rate: f64,
    /// Moves not measured because they start where the position is unknown.
    pub(crate) unmeasured_moves: usize,
}

impl fmt::Display for Totals {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "lines: {} ({} blocks)", self.lines, self.blocks)?;
        writeln!(f, "bounds: {} mm", self.bounds.show())?;
        writeln!(f, "cut bounds: {} mm", self.cut_bounds.show())?;
        write!(
            f,
            "length: cut {:.1} mm, rapid {:.1} mm",
            self.cut_length, self.rapid_length
        )?;
        if self.unmeasured_moves > 0 {
            write!(
                f,
                " ({} move(s) from an unknown position not measured)",
                self.unmeasured_moves
            )?;
        }
        write!(
            f,
            "\nestimated time: {} (rapids at {} mm/min, dwells {} s, acceleration ignored)",
            super::format_duration(self.time_s),
            num(self.rapid_rate),
            num(self.dwell_s)
        )
    }
}

/// The findings, in line order, and the totals.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Report {
    /// Errors and warnings, by line.
    pub findings: Vec<Finding>,
    /// What the program adds up to.
    pub totals: Totals,
}

impl Report {
    /// Number of errors.
    pub fn errors(&self) -> usize {
        self.findings
            .iter()
            .filter(|f| f.severity == Severity::Error)
            .count()
    }

    /// Number of warnings.
    pub fn warnings(&self) -> usize {
        self.findings.len() - self.errors()
    }
}

fn num(x: f64) -> String {
    super::writer::fmt_num(x)
}

const AXES: [char; 3] = ['X', 'Y', 'Z'];

/// The first move past one side of one axis's travel, and how many there are.
#[derive(Clone, Debug)]
struct Overrun {
    line: usize,
    message: String,
    count: usize,
}

struct Checker {
    opts: CheckOptions,
    state: ModalState,
    report: Report,
    /// Index: axis × 2 + (0 below, 1 above), for [`Limits::work_offset`] checks.
    overruns: [Option<Overrun>; 6],
    /// Axes already reported as larger than the travel.
    too_big: [bool; 3],
}

/// Checks a G-code program (the text of a `.nc` file).
pub fn check_gcode(text: &str, opts: &CheckOptions) -> Report {
    let mut c = Checker {
        opts: *opts,
        state: ModalState::default(),
        report: Report::default(),
        overruns: Default::default(),
        too_big: [false; 3],
    };
    c.report.totals.rapid_rate = opts.rapid_rate;
    let mut last_block = 0;
    for (i, raw) in text.lines().enumerate() {
        let n = i + 1;
        c.report.totals.lines = n;
        let block = clean_line(raw);
        if !block.is_empty() {
            last_block = n;
        }
        c.line(n, raw, &block);
    }
    if last_block > 0 && !c.state.ended {
        c.warn(
            last_block,
            "the program does not end with M2 or M30 (GRBL keeps the spindle and modes as they are)",
        );
    }
    for o in c.overruns.iter().flatten() {
        let more = match o.count {
            1 => String::new(),
            n => format!(" ({} more move(s) past this limit)", n - 1),
        };
        c.report.findings.push(Finding {
            line: o.line,
            severity: Severity::Error,
            code: None,
            message: format!("{}{more}", o.message),
        });
    }
    c.report.findings.sort_by_key(|f| f.line);
    c.report
}

impl Checker {
    fn push(&mut self, line: usize, severity: Severity, code: Option<u8>, message: String) {
        self.report.findings.push(Finding {
            line,
            severity,
            code,
            message,
        });
    }

    fn warn(&mut self, line: usize, message: impl Into<String>) {
        self.push(line, Severity::Warning, None, message.into());
    }

    fn line(&mut self, n: usize, raw: &str, block: &str) {
        let block_len = block.chars().count();
        if block_len >= GRBL_LINE_BUFFER {
            // GRBL drops the whole line: nothing of it runs.
            self.push(
                n,
                Severity::Error,
                Some(11),
                format!(
                    "the block is {block_len} characters without comments and spaces; \
                     GRBL's line buffer holds {}",
                    GRBL_LINE_BUFFER - 1
                ),
            );
            return;
        }
        let raw_len = raw.trim_end_matches('\r').chars().count();
        if raw_len > MAX_RAW_LINE {
            self.warn(
                n,
                format!(
                    "the line is {raw_len} characters, over {MAX_RAW_LINE}; GRBL gets \
                     {block_len} once comments and spaces are removed, which fits"
                ),
            );
        }
        if block.is_empty() {
            return;
        }
        if has_block_delete(raw) {
            self.warn(
                n,
                "GRBL ignores the block-delete `/`: this block runs every time",
            );
        }
        self.report.totals.blocks += 1;
        if block.starts_with('$') {
            self.warn(
                n,
                "a `$` system command is not G-code: not checked (send it by hand)",
            );
            return;
        }
        let before = self.state.clone();
        if let Err(e) = self.state.execute(block) {
            self.push(n, Severity::Error, Some(e.code), e.detail);
            return;
        }
        // `execute` accepted the block, so it tokenizes.
        let Ok(words) = tokenize(block) else { return };
        self.block(n, &before, &words);
    }

    /// Totals, limits and warnings for a block GRBL accepts; `before` is the state
    /// before it, `self.state` after it.
    fn block(&mut self, n: usize, before: &ModalState, words: &[Word]) {
        self.warn_build_options(n, words);
        self.non_motion(n, words);
        let Some(motion) = motion::block_motion(words, before) else {
            return;
        };
        if motion == Motion::None {
            return;
        }
        let from = before.position;
        let after = self.state.clone();
        let (extremes, length) = self.extent(n, motion, from, &after, words);
        let feed_move = motion != Motion::Rapid;
        let t = &mut self.report.totals;
        for p in &extremes {
            t.bounds.add_point(p);
            if feed_move {
                t.cut_bounds.add_point(p);
            }
        }
        if feed_move {
            t.cut_bounds.add_point(&from);
        }
        let inverse_f = words.iter().find(|w| w.letter == 'F').map(|w| w.value);
        match length {
            None => t.unmeasured_moves += 1,
            Some(l) if feed_move => {
                t.cut_length += l;
                t.time_s += match after.feed_mode {
                    // G93: F is the inverse of the move's time in minutes.
                    FeedMode::InverseTime => inverse_f.map_or(0.0, |f| 60.0 / f),
                    FeedMode::UnitsPerMinute => {
                        after
                            .feed
                            .map_or(0.0, |f| if f > 0.0 { l / f * 60.0 } else { 0.0 })
                    }
                };
            }
            Some(l) => {
                t.rapid_length += l;
                t.time_s += l / self.opts.rapid_rate * 60.0;
            }
        }
        self.limits(n, &extremes);
    }

    /// Warns of M7 and M56, which a stock GRBL 1.1 build rejects.
    fn warn_build_options(&mut self, n: usize, words: &[Word]) {
        for (m, build) in [
            (7.0, "ENABLE_M7"),
            (56.0, "ENABLE_PARKING_OVERRIDE_CONTROL"),
        ] {
            if words.iter().any(|w| w.letter == 'M' && w.value == m) {
                self.warn(
                    n,
                    format!(
                        "M{m} works only in GRBL built with {build}; a stock GRBL 1.1 answers \
                         error 20"
                    ),
                );
            }
        }
    }

    /// What a block does besides its motion: a G4 dwell's time, a warning for
    /// G0/G1 without axis words, and G28/G30/G53 moves counted as unmeasured.
    fn non_motion(&mut self, n: usize, words: &[Word]) {
        let value = |c: char| words.iter().find(|w| w.letter == c).map(|w| w.value);
        let gcodes = motion::gcodes(words);
        let has_axes = AXES.iter().any(|&c| value(c).is_some());
        let axis_command = motion::is_axis_command(&gcodes);
        if gcodes.contains(&40) {
            let p = value('P').unwrap_or(0.0);
            self.report.totals.dwell_s += p;
            self.report.totals.time_s += p;
        }
        let explicit = motion::explicit_motion(&gcodes);
        if matches!(explicit, Some(0) | Some(10)) && !has_axes && !axis_command {
            self.warn(
                n,
                format!(
                    "G{} without axis words: nothing moves",
                    explicit.unwrap_or(0) / 10
                ),
            );
        }
        // G28/G30 go home (through the axis words, if any); G53 moves in machine
        // coordinates: real moves, to places only the machine knows.
        if gcodes.iter().any(|g| matches!(g, 280 | 300)) || (gcodes.contains(&530) && has_axes) {
            self.report.totals.unmeasured_moves += 1;
        }
    }

    /// The points a move from `from` to `after.position` reaches at its
    /// extremes (the end, and an arc's extremes in its plane), and its length
    /// where both ends are known. An arc from an unknown position is warned of.
    fn extent(
        &mut self,
        n: usize,
        motion: Motion,
        from: [Option<f64>; 3],
        after: &ModalState,
        words: &[Word],
    ) -> (Vec<[Option<f64>; 3]>, Option<f64>) {
        let to = after.position;
        let mut extremes: Vec<[Option<f64>; 3]> = vec![to];
        let known = |p: &[Option<f64>; 3]| p.iter().all(Option::is_some);
        let mut length = None;
        if !matches!(motion, Motion::ArcCw | Motion::ArcCcw) {
            if known(&from) && known(&to) {
                let d: f64 = (0..3)
                    .map(|k| (to[k].unwrap_or(0.0) - from[k].unwrap_or(0.0)).powi(2))
                    .sum();
                length = Some(d.sqrt());
            }
            return (extremes, length);
        }
        let ccw = motion == Motion::ArcCcw;
        let [a0, a1] = after.plane.axes();
        let (Some(s0), Some(s1), Some(t0), Some(t1)) = (from[a0], from[a1], to[a0], to[a1]) else {
            self.warn(
                n,
                "arc from an unknown position: GRBL checks it against wherever the \
                 machine stands, pfcam cannot",
            );
            return (extremes, length);
        };
        let (arc, _) = motion::block_arc(words, after, [s0, s1], [t0, t1], ccw);
        // The linear axis is covered by `from` and `to`.
        let lin = 3 - a0 - a1;
        for [u, v] in arc.extremes() {
            let mut p = to;
            p[a0] = Some(u);
            p[a1] = Some(v);
            p[lin] = None;
            extremes.push(p);
        }
        if known(&from) && known(&to) {
            let dz = to[lin].unwrap_or(0.0) - from[lin].unwrap_or(0.0);
            length = Some(arc.length(dz));
        }
        (extremes, length)
    }

    fn limits(&mut self, n: usize, points: &[[Option<f64>; 3]]) {
        let Some(limits) = self.opts.limits else {
            return;
        };
        match limits.work_offset {
            Some(offset) => {
                for p in points {
                    for (k, w) in p.iter().enumerate() {
                        let Some(w) = *w else { continue };
                        let m = w + offset[k];
                        let (side, bound) = if m > TRAVEL_EPS {
                            (1, 0.0)
                        } else if m < -limits.travel[k] - TRAVEL_EPS {
                            (0, -limits.travel[k])
                        } else {
                            continue;
                        };
                        let slot = &mut self.overruns[k * 2 + side];
                        match slot {
                            Some(o) => {
                                if o.line != n {
                                    o.count += 1;
                                }
                            }
                            None => {
                                *slot = Some(Overrun {
                                    line: n,
                                    count: 1,
                                    message: format!(
                                        "{} {} is machine {} {}, past the travel limit {} \
                                         (machine {} runs from {} to 0; GRBL: soft-limit \
                                         ALARM:2 or a crash)",
                                        AXES[k],
                                        num(w),
                                        AXES[k],
                                        num(m),
                                        num(bound),
                                        AXES[k],
                                        num(-limits.travel[k]),
                                    ),
                                })
                            }
                        }
                    }
                }
            }
            None => {
                let b = self.report.totals.bounds;
                for (k, (lo, hi)) in b.min.into_iter().zip(b.max).enumerate() {
                    if let (Some(lo), Some(hi)) = (lo, hi) {
                        if !self.too_big[k] && hi - lo > limits.travel[k] + TRAVEL_EPS {
                            self.too_big[k] = true;
                            self.push(
                                n,
                                Severity::Error,
                                None,
                                format!(
                                    "the program now spans {} {} .. {} ({} mm), more than \
                                     the machine's {} mm of {} travel: no work origin fits it",
                                    AXES[k],
                                    num(lo),
                                    num(hi),
                                    num(hi - lo),
                                    num(limits.travel[k]),
                                    AXES[k]
                                ),
                            );
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, TAU};

    fn check(text: &str) -> Report {
        check_gcode(text, &CheckOptions::default())
    }

    fn codes(r: &Report) -> Vec<(usize, Option<u8>, Severity)> {
        r.findings
            .iter()
            .map(|f| (f.line, f.code, f.severity))
            .collect()
    }

    #[test]
    fn a_clean_program_has_no_findings() {
        let r = check("G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG2 X10 Y0 I5 J0\nM2\n");
        assert!(r.findings.is_empty(), "{:?}", r.findings);
        // Plunge 6 mm, half circle of radius 5.
        let want = 6.0 + 5.0 * std::f64::consts::PI;
        assert!((r.totals.cut_length - want).abs() < 1e-9);
        assert_eq!(r.totals.unmeasured_moves, 1);
        // G2 (clockwise) from the left of the centre goes over the top.
        assert_eq!(r.totals.cut_bounds.min, [Some(0.0), Some(0.0), Some(-1.0)]);
        assert_eq!(r.totals.cut_bounds.max, [Some(10.0), Some(5.0), Some(5.0)]);
    }

    #[test]
    fn errors_carry_grbl_numbers_and_lines() {
        let r = check("G0 X0 Y0\nG41 X1\nG1 X2\nG0 X1 X2\nM2\n");
        assert_eq!(
            codes(&r),
            vec![
                (2, Some(20), Severity::Error),
                (3, Some(22), Severity::Error),
                (4, Some(25), Severity::Error)
            ]
        );
        assert_eq!(r.errors(), 3);
        let long = format!("G1 X1 F100 {}\nM2\n", "Y1.0000000".repeat(8));
        let r = check(&long);
        assert_eq!(codes(&r), vec![(1, Some(11), Severity::Error)]);
    }

    #[test]
    fn warnings_do_not_count_as_errors() {
        let r = check("G0 X0 Y0 Z0\nG1 F100\nG0\n");
        assert_eq!(r.errors(), 0);
        assert_eq!(r.warnings(), 3, "{:?}", r.findings);
    }

    #[test]
    fn r_arcs_long_and_short_way() {
        // Quarter circle of radius 10 the short way, three quarters the long way.
        let short = check("G0 X0 Y0 Z0\nG2 X10 Y10 R10 F100\nM2\n");
        let long = check("G0 X0 Y0 Z0\nG2 X10 Y10 R-10 F100\nM2\n");
        let q = 10.0 * FRAC_PI_2;
        assert!((short.totals.cut_length - q).abs() < 1e-9);
        assert!((long.totals.cut_length - 3.0 * q).abs() < 1e-9);
        // G2 from (0,0) to (10,10) the short way: centre (10, 0), through (0, 0)
        // and up; the long way's centre is (0, 10), reaching y = 20 and x = -10.
        assert_eq!(short.totals.cut_bounds.max[1], Some(10.0));
        assert_eq!(long.totals.cut_bounds.min[0], Some(-10.0));
        assert_eq!(long.totals.cut_bounds.max[1], Some(20.0));
    }

    #[test]
    fn incremental_and_inch_moves() {
        let r = check("G20 G90 G0 X0 Y0 Z0\nG91 G1 X1 F10\nG1 Y1\nM2\n");
        assert!((r.totals.cut_length - 50.8).abs() < 1e-9);
        // 50.8 mm at 10 in/min = 254 mm/min: 12 s.
        assert!((r.totals.time_s - 12.0).abs() < 1e-9);
        assert_eq!(r.totals.bounds.max, [Some(25.4), Some(25.4), Some(0.0)]);
    }

    #[test]
    fn travel_limits() {
        let text = "G0 X0 Y0 Z0\nG1 X100 F100\nG1 X350\nG1 X360\nM2\n";
        let size_only = CheckOptions {
            limits: Some(Limits {
                travel: [300.0, 200.0, 50.0],
                work_offset: None,
            }),
            ..CheckOptions::default()
        };
        let r = check_gcode(text, &size_only);
        assert_eq!(codes(&r), vec![(3, None, Severity::Error)]);
        let placed = CheckOptions {
            limits: Some(Limits {
                travel: [300.0, 200.0, 50.0],
                work_offset: Some([-250.0, -100.0, -10.0]),
            }),
            ..CheckOptions::default()
        };
        // Machine X = work X − 250: X100 is −150, X350 is +100 (past 0).
        let r = check_gcode(text, &placed);
        assert_eq!(codes(&r), vec![(3, None, Severity::Error)]);
        assert!(r.findings[0].message.contains("1 more"), "{:?}", r.findings);
    }

    #[test]
    fn home_and_machine_moves_are_unmeasured() {
        let r = check("G0 X0 Y0 Z0\nG28\nG0 X1 Y1 Z1\nG53 G0 Z-1\nG0 X2\nM2\n");
        assert!(r.findings.is_empty(), "{:?}", r.findings);
        // The first move, G28, the move after it, G53, and the move after that.
        assert_eq!(r.totals.unmeasured_moves, 5);
        assert_eq!(r.totals.rapid_length, 0.0);
    }

    #[test]
    fn optional_m_codes_are_warnings() {
        let r = check("M7\nM9\nM2\n");
        assert_eq!(codes(&r), vec![(1, None, Severity::Warning)]);
        let r = check("G0 X0\n/G0 X1\nM2\n");
        assert_eq!(codes(&r), vec![(2, None, Severity::Warning)]);
    }

    /// Garbage and mangled G-code give findings, never a panic (a fixed-seed
    /// generator, so a failure is reproducible).
    #[test]
    fn never_panics_on_garbage() {
        let mut g = crate::num::testing::Lcg(0x5eed);
        let mut next = move || g.word();
        let alphabet: Vec<char> = "GMXYZIJKRFPSTNL0123456789.-+ ()%;$#E\té\r"
            .chars()
            .collect();
        let mut lines = vec![
            "G0 X0 Y0 Z0".to_string(),
            "G20".into(),
            "G91".into(),
            "G93".into(),
            "G18".into(),
            "G19".into(),
            format!("X{}", "9".repeat(400)),
            "G2 X0 Y0 R0 F1".into(),
            "G2 X1 Y0 I0 J0 F1".into(),
            "G3 X0 Y0 I0 J0 F1".into(),
            "G28".into(),
            "G53 G0 X1".into(),
        ];
        for _ in 0..3000 {
            let len = next() % 30;
            lines.push(
                (0..len)
                    .map(|_| alphabet[next() % alphabet.len()])
                    .collect(),
            );
        }
        for _ in 0..50 {
            let mut text = String::new();
            for _ in 0..200 {
                text += &lines[next() % lines.len()];
                text.push('\n');
            }
            let limits = Some(Limits {
                travel: [100.0, 100.0, 50.0],
                work_offset: (next() % 2 == 0).then_some([-50.0, -50.0, -10.0]),
            });
            let r = check_gcode(
                &text,
                &CheckOptions {
                    limits,
                    ..CheckOptions::default()
                },
            );
            assert!(r.findings.windows(2).all(|w| w[0].line <= w[1].line));
        }
    }

    #[test]
    fn full_circle_and_helix() {
        let r = check("G0 X0 Y0 Z0\nG3 X0 Y0 Z-2 I5 J0 F100\nM2\n");
        let want = (TAU * 5.0).hypot(2.0);
        assert!((r.totals.cut_length - want).abs() < 1e-9);
        assert_eq!(r.totals.cut_bounds.max[0], Some(10.0));
    }
}
