//! The GRBL 1.1 G-code writer: a [`Toolpath`] and its [`Job`] to program text.
//!
//! Output, line by line:
//! 1. `(pfcam <version> job <name>)`, then comments: tool, stock and operation,
//!    cut bounds (min..max of X, Y, Z over every feed move, arcs included), the
//!    levels (distinct depths cut), the number of lines and arcs, path lengths and
//!    the estimated time (feed moves at their feed, rapids at
//!    `machine.rapid_rate`, acceleration ignored);
//! 2. `G21 G90 G17 G94` (mm, absolute, XY plane, feed per minute);
//! 3. `G0 Z<safe>`, `G0 X<start> Y<start>`, `M3 S<spindle>`, `M8` when
//!    `machine.coolant`, `G4 P<dwell>` when `machine.spindle_dwell` > 0 and the
//!    spindle turns;
//! 4. per section a `(label)` comment, then `G0`/`G1`/`G2`/`G3` moves: an axis word
//!    only when its written value changes (always X and Y on arcs, which GRBL
//!    requires), arc centres as `I`/`J` offsets from the arc's start as written
//!    (GRBL's only arc distance mode), chosen on the 0.001 mm grid so that the
//!    written start and end are as nearly equidistant from the written centre
//!    as the grid allows (see `CENTRE_SEARCH`), `F` only when the feed changes;
//! 5. a retract to safe Z if the tool is below it, `M9` with coolant, `M5`, `M2`.
//!
//! Arcs reach the program only as [`arcfit::legalize`] lets them: none with
//! `output.arcs = false`, none flatter than `output.max_arc_radius` or shorter
//! than [`MIN_ARC_CHORD`] (lines within half the tolerance instead), none over
//! half a turn (split).
//!
//! Numbers have [`DECIMALS`] decimals with trailing zeros removed and never read
//! `-0`; every line is at most [`MAX_LINE_LEN`] characters (GRBL's line buffer);
//! only words GRBL 1.1 accepts are written. The output depends on nothing but the
//! input, so the same job gives byte-identical files.

use crate::geometry::{arc, Vec2};
use crate::job::{Direction, Job, OperationKind, Side};
use crate::toolpath::arcfit::{self, ArcLimits, MIN_ARC_CHORD};
use crate::toolpath::{Move, Toolpath, Vec3};
use std::fmt::Write as _;

/// Decimals written for coordinates and feeds (mm, mm/min): 0.001 mm, finer than
/// any hobby machine's step.
pub(crate) const DECIMALS: usize = 3;

/// The longest line written: GRBL 1.1's line buffer holds 80 characters.
pub(crate) const MAX_LINE_LEN: usize = 80;

/// 10^[`DECIMALS`]: written numbers are whole multiples of 1/`SCALE` mm.
const SCALE: f64 = 1000.0;

/// How far (in units of the last decimal, each way) the writer may move an arc's
/// written centre from the rounded true centre to make the written start and end
/// equidistant from it (GRBL's error 33 when their radii differ by more than
/// 0.005 mm and 0.1 %). Plain rounding of the start, end and centre (each within
/// 0.0005 mm per axis) already bounds the difference by 2 · 2 · 0.0007 ≈
/// 0.0028 mm; of the 25 grid centres within ±2 units the writer takes the
/// nearest to the true centre among those whose radii differ by at most
/// [`RADIUS_SLACK`] units, else the one with the smallest difference. Measured on
/// every sample in `gcode-samples/`: at most 0.0006 mm (`tests/all/arcs.rs` asserts
/// < 0.002 mm on every job).
const CENTRE_SEARCH: i128 = 2;

/// Radii that differ by no more than this many units of the last decimal count as
/// equal when choosing an arc's written centre (then the centre nearest the true
/// one wins).
const RADIUS_SLACK: f64 = 0.5;

/// A tool path that cannot be written. These are bugs in pfcam (the pipeline
/// must produce finite coordinates and positive feeds), not input errors.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum GcodeError {
    /// A coordinate or arc centre is NaN or infinite.
    #[error("internal error: non-finite coordinate in section `{section}` (please report this pfcam bug)")]
    NonFinite {
        /// the section's label
        section: String,
    },
    /// A feed rate that is not a positive number.
    #[error("internal error: feed {feed} mm/min in section `{section}` is not positive (please report this pfcam bug)")]
    BadFeed {
        /// the section's label
        section: String,
        /// the feed
        feed: f64,
    },
    /// A line longer than GRBL accepts (coordinates of absurd size).
    #[error("a G-code line would be {len} characters, more than GRBL's {MAX_LINE_LEN}: {line}")]
    LineTooLong {
        /// the line
        line: String,
        /// its length
        len: usize,
    },
}

/// `x` with [`DECIMALS`] decimals, trailing zeros and a trailing point removed,
/// and `-0` written as `0`: `1.5`, `-0.001`, `12`.
pub(crate) fn fmt_num(x: f64) -> String {
    let s = format!("{x:.DECIMALS$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s.as_str()
    };
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// Text made safe inside a G-code comment: GRBL ends a comment at the first `)`
/// and has no nesting, so `(`/`)` become `[`/`]`, `;` becomes `,`, and anything
/// outside printable ASCII becomes `?`.
pub(crate) fn comment_text(s: &str) -> String {
    s.chars()
        .map(|c| match c {
            '(' => '[',
            ')' => ']',
            ';' => ',',
            c if c.is_ascii_graphic() || c == ' ' => c,
            _ => '?',
        })
        .collect()
}

/// A whole comment line, cut to fit [`MAX_LINE_LEN`].
fn comment(s: &str) -> String {
    let t: String = comment_text(s).chars().take(MAX_LINE_LEN - 2).collect();
    format!("({t})")
}

/// `754.2` seconds as `12 min 34 s`; `3725` as `1 h 2 min 5 s`.
pub fn format_duration(seconds: f64) -> String {
    let s = if seconds.is_finite() && seconds > 0.0 {
        seconds.round() as u64
    } else {
        0
    };
    let (h, m, s) = (s / 3600, (s / 60) % 60, s % 60);
    if h > 0 {
        format!("{h} h {m} min {s} s")
    } else if m > 0 {
        format!("{m} min {s} s")
    } else {
        format!("{s} s")
    }
}

/// Min and max corners of every feed move (arcs by their true extent), or `None`
/// when the path has no feed move.
pub(crate) fn cut_bounds(tp: &Toolpath) -> Option<(Vec3, Vec3)> {
    let mut lo = Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let mut hi = Vec3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut add = |p: Vec3| {
        lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
        hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
    };
    let mut any = false;
    let mut at = tp.start;
    for m in tp.moves() {
        match *m {
            Move::Rapid { .. } => {}
            Move::Linear { to, .. } => {
                add(at);
                add(to);
                any = true;
            }
            Move::Arc {
                to, cx, cy, ccw, ..
            } => {
                add(at);
                add(to);
                any = true;
                let c = Vec2::new(cx, cy);
                let sweep = arc::sweep(at.xy(), to.xy(), c, ccw);
                let (r, a0) = (arc::radius(at.xy(), c), arc::angle(at.xy(), c));
                for p in arc::extremes(c, r, a0, sweep, ccw) {
                    add(Vec3::new(p.x, p.y, at.z.min(to.z)));
                }
            }
        }
        at = m.to();
    }
    any.then_some((lo, hi))
}

fn check_finite(tp: &Toolpath) -> Result<(), GcodeError> {
    let fin = |p: Vec3| p.x.is_finite() && p.y.is_finite() && p.z.is_finite();
    if !fin(tp.start) {
        return Err(GcodeError::NonFinite {
            section: "start".into(),
        });
    }
    for s in &tp.sections {
        for m in &s.moves {
            let (ok, feed) = match *m {
                Move::Rapid { to } => (fin(to), None),
                Move::Linear { to, feed } => (fin(to), Some(feed)),
                Move::Arc {
                    to, cx, cy, feed, ..
                } => (fin(to) && cx.is_finite() && cy.is_finite(), Some(feed)),
            };
            if !ok {
                return Err(GcodeError::NonFinite {
                    section: s.label.clone(),
                });
            }
            if let Some(f) = feed {
                if !(f.is_finite() && f > 0.0) {
                    return Err(GcodeError::BadFeed {
                        section: s.label.clone(),
                        feed: f,
                    });
                }
            }
        }
    }
    Ok(())
}

/// The modal state of the program as written: each axis's last written value
/// (as text, so that "changed" means "writes differently"), and the feed.
struct Modal {
    axis: [Option<String>; 3],
    feed: Option<String>,
    lines: Vec<String>,
}

impl Modal {
    /// The program's start: modes set, up to `safe_z` first (where the
    /// machine is is unknown), then over the path's `start`; spindle on,
    /// coolant and the spindle's dwell as the job's machine asks.
    fn start(&mut self, job: &Job, start: Vec3, safe_z: f64) {
        self.lines.push("G21 G90 G17 G94".into());
        let z = fmt_num(safe_z);
        self.lines.push(format!("G0 Z{z}"));
        self.axis[2] = Some(z);
        self.rapid(Vec3::new(start.x, start.y, safe_z));
        let spindle = job.tool.spindle.round();
        self.lines.push(format!("M3 S{}", fmt_num(spindle)));
        if job.machine.coolant {
            self.lines.push("M8".into());
        }
        if job.machine.spindle_dwell > 0.0 && spindle > 0.0 {
            self.lines
                .push(format!("G4 P{}", fmt_num(job.machine.spindle_dwell)));
        }
    }

    /// Every section, its label as a comment before its moves; returns where
    /// the tool ends (over the start at `safe_z` for an empty path).
    fn sections(&mut self, tp: &Toolpath, safe_z: f64) -> Vec3 {
        let mut at = Vec3::new(tp.start.x, tp.start.y, safe_z);
        for s in &tp.sections {
            self.lines.push(comment(&s.label));
            for m in &s.moves {
                match *m {
                    Move::Rapid { to } => self.rapid(to),
                    Move::Linear { to, feed } => self.linear(to, feed),
                    Move::Arc {
                        to,
                        cx,
                        cy,
                        ccw,
                        feed,
                    } => self.arc(to, cx, cy, ccw, feed),
                }
                at = m.to();
            }
        }
        at
    }

    /// The program's end: up to `safe_z` from `at` if below it, coolant and
    /// spindle off, M2.
    fn end(&mut self, job: &Job, at: Vec3, safe_z: f64) {
        if at.z < safe_z {
            self.rapid(Vec3::new(at.x, at.y, safe_z));
        }
        if job.machine.coolant {
            self.lines.push("M9".into());
        }
        self.lines.push("M5".into());
        self.lines.push("M2".into());
    }

    /// The written position as numbers (0 for an axis not yet written).
    fn pos(&self, k: usize) -> f64 {
        self.axis[k]
            .as_deref()
            .and_then(|s| s.parse().ok())
            .unwrap_or(0.0)
    }

    /// Axis words of `to` that differ from the written position; `force_xy` always
    /// writes X and Y. Updates the position.
    fn axis_words(&mut self, to: Vec3, force_xy: bool) -> String {
        let mut w = String::new();
        for (k, (letter, v)) in [('X', to.x), ('Y', to.y), ('Z', to.z)]
            .into_iter()
            .enumerate()
        {
            let s = fmt_num(v);
            if self.axis[k].as_deref() != Some(s.as_str()) || (force_xy && k < 2) {
                let _ = write!(w, " {letter}{s}");
                self.axis[k] = Some(s);
            }
        }
        w
    }

    fn feed_word(&mut self, feed: f64) -> String {
        let s = fmt_num(feed);
        if self.feed.as_deref() == Some(s.as_str()) {
            String::new()
        } else {
            let w = format!(" F{s}");
            self.feed = Some(s);
            w
        }
    }

    fn rapid(&mut self, to: Vec3) {
        let w = self.axis_words(to, false);
        if !w.is_empty() {
            self.lines.push(format!("G0{w}"));
        }
    }

    fn linear(&mut self, to: Vec3, feed: f64) {
        let w = self.axis_words(to, false);
        if !w.is_empty() {
            let f = self.feed_word(feed);
            self.lines.push(format!("G1{w}{f}"));
        }
    }

    fn arc(&mut self, to: Vec3, cx: f64, cy: f64, ccw: bool, feed: f64) {
        // Offsets from the start as written, chosen on the written grid so that
        // the written start and end are as equidistant from the written centre as
        // the grid allows (GRBL's error 33 when they differ by more than
        // 0.005 mm): all in whole units of the last decimal, exactly.
        let (sx, sy) = (self.pos(0), self.pos(1));
        let unit = |v: f64| (v * SCALE).round() as i128;
        let written = |v: f64| fmt_num(v).parse::<f64>().unwrap_or(v);
        let (s0, s1) = (unit(sx), unit(sy));
        let (e0, e1) = (unit(written(to.x)), unit(written(to.y)));
        let (ti, tj) = ((cx - sx) * SCALE, (cy - sy) * SCALE);
        let (i0, j0) = (ti.round() as i128, tj.round() as i128);
        // (radius difference, distance to the true centre, i, j), in units.
        let mut best: Option<(f64, f64, i128, i128)> = None;
        for di in -CENTRE_SEARCH..=CENTRE_SEARCH {
            for dj in -CENTRE_SEARCH..=CENTRE_SEARCH {
                let (i, j) = (i0 + di, j0 + dj);
                let (u, v) = (e0 - s0 - i, e1 - s1 - j);
                let dr = ((i * i + j * j) as f64).sqrt() - ((u * u + v * v) as f64).sqrt();
                let dr = dr.abs();
                let off = (i as f64 - ti).hypot(j as f64 - tj);
                let better = match best {
                    None => true,
                    Some((bdr, boff, ..)) => {
                        let (ok, bok) = (dr <= RADIUS_SLACK, bdr <= RADIUS_SLACK);
                        match (ok, bok) {
                            (true, true) => off < boff,
                            (true, false) => true,
                            (false, true) => false,
                            (false, false) => dr < bdr || (dr == bdr && off < boff),
                        }
                    }
                };
                if better {
                    best = Some((dr, off, i, j));
                }
            }
        }
        let (bi, bj) = best.map_or((i0, j0), |b| (b.2, b.3));
        let (i, j) = (fmt_num(bi as f64 / SCALE), fmt_num(bj as f64 / SCALE));
        if i == "0" && j == "0" {
            // No radius at the written precision: a straight move does the same.
            return self.linear(to, feed);
        }
        let w = self.axis_words(to, true);
        let f = self.feed_word(feed);
        let g = if ccw { "G3" } else { "G2" };
        self.lines.push(format!("{g}{w} I{i} J{j}{f}"));
    }
}

/// The depths cut: every distinct written Z of a level feed move (start and end
/// at the same Z), highest first.
pub fn levels(tp: &Toolpath) -> Vec<f64> {
    let mut zs: Vec<f64> = Vec::new();
    let mut at = tp.start;
    for m in tp.moves() {
        if let Move::Linear { to, .. } | Move::Arc { to, .. } = *m {
            if to.z == at.z {
                let z = (to.z * SCALE).round() / SCALE;
                if !zs.contains(&z) {
                    zs.push(z);
                }
            }
        }
        at = m.to();
    }
    zs.sort_by(|a, b| b.total_cmp(a));
    zs
}

/// The header's line on the program's depths: its z-levels, or for a
/// finishing program (every section a [`FINISH_PASS`](crate::toolpath::FINISH_PASS))
/// its passes along the surface, whose z changes along each.
fn levels_line(tp: &Toolpath) -> String {
    let finishing = !tp.sections.is_empty()
        && tp
            .sections
            .iter()
            .all(|s| s.label.starts_with(crate::toolpath::FINISH_PASS));
    if finishing {
        let passes = tp
            .sections
            .iter()
            .filter_map(|s| s.label.split_whitespace().nth(2))
            .collect::<std::collections::BTreeSet<_>>()
            .len();
        // Each section's z is its pass's lowest tip.
        let (lo, hi) = tp
            .sections
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                (lo.min(s.z), hi.max(s.z))
            });
        let raster = tp
            .sections
            .iter()
            .all(|s| s.label.ends_with(crate::toolpath::RASTER_PASS));
        let how = if raster {
            "parallel along x, stepped over in y"
        } else {
            "along the surface from the floor up"
        };
        return format!(
            "passes: {passes} {how}, lowest z {} to {}",
            fmt_num(lo),
            fmt_num(hi)
        );
    }
    let zs = levels(tp);
    let shown: Vec<String> = zs.iter().map(|&z| fmt_num(z)).collect();
    match zs.len() {
        0 => "levels: none".to_string(),
        n if n <= 8 => format!("levels: {n}, z {}", shown.join(" ")),
        n => format!("levels: {n}, z {} to {}", shown[0], shown[n - 1]),
    }
}

/// Lengths and estimated time of the program [`write_gcode_on`] writes for
/// `tp`: its arcs legalised as the writer does, so these are the header's
/// figures.
pub(crate) fn program_stats(tp: &Toolpath, job: &Job) -> crate::toolpath::PathStats {
    arcfit::legalize(tp, &arc_limits(job)).stats(job.machine.rapid_rate)
}

/// The arc limits the writer applies for `job`: `output.arcs`,
/// `output.max_arc_radius`, arcs at least [`MIN_ARC_CHORD`] long, and arcs
/// turned into lines within half the job tolerance.
pub fn arc_limits(job: &Job) -> ArcLimits {
    ArcLimits {
        arcs: job.output.arcs,
        max_radius: job.output.max_arc_radius,
        min_length: MIN_ARC_CHORD,
        tol: job.operation.tolerance / 2.0,
    }
}

/// The stock as the machinist sets it up: the rectangle (lower-left `lo`,
/// upper-right `hi`, mm in work coordinates), and whether it is the job's own
/// stock (`known`) or, for a profile cut from a sheet, the least sheet the tool
/// sweeps (the cut bounds grown by the tool radius `r`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct StockExtent {
    /// Lower-left corner.
    pub(crate) lo: Vec2,
    /// Upper-right corner.
    pub(crate) hi: Vec2,
    /// The job's stock rectangle, not a sheet bound derived from the cut.
    pub(crate) known: bool,
}

/// The [`StockExtent`] of a program: `stock` when given, else the cut bounds
/// grown by `r`; `None` for a program with no feed move and no stock.
pub(crate) fn stock_extent(
    tp: &Toolpath,
    r: f64,
    stock: Option<(Vec2, Vec2)>,
) -> Option<StockExtent> {
    match (stock, cut_bounds(tp)) {
        (Some((lo, hi)), _) => Some(StockExtent {
            lo,
            hi,
            known: true,
        }),
        (None, Some((lo, hi))) => Some(StockExtent {
            lo: Vec2::new(lo.x - r, lo.y - r),
            hi: Vec2::new(hi.x + r, hi.y + r),
            known: false,
        }),
        (None, None) => None,
    }
}

/// The header's stock comments: the stock rectangle (or, for a sheet, the area
/// the tool sweeps: the cut bounds grown by the tool radius), its top and safe
/// Z, and where the work zero X0 Y0 Z0 sits on the stock, which is what the
/// machinist needs to set up the job.
fn stock_lines(tp: &Toolpath, job: &Job, stock: Option<(Vec2, Vec2)>) -> Vec<String> {
    let top = fmt_num(job.stock.top);
    let safe = fmt_num(job.stock.safe_z);
    let Some(extent) = stock_extent(tp, job.tool.diameter / 2.0, stock) else {
        return vec![format!("stock: top {top}, safe z {safe} mm")];
    };
    let (lo, hi) = (extent.lo, extent.hi);
    let what = if extent.known {
        "stock"
    } else {
        "sheet at least"
    };
    let t = job.stock.top;
    let z0 = if t == 0.0 {
        "Z0 on the stock top".to_string()
    } else if t > 0.0 {
        format!("Z0 {} mm below the stock top", fmt_num(t))
    } else {
        format!("Z0 {} mm above the stock top", fmt_num(-t))
    };
    vec![
        format!(
            "{what}: X{}..{} Y{}..{}, top {top}, safe z {safe} mm",
            fmt_num(lo.x),
            fmt_num(hi.x),
            fmt_num(lo.y),
            fmt_num(hi.y)
        ),
        format!(
            "work zero: X0 {} mm from its left, Y0 {} from its front",
            fmt_num(-lo.x),
            fmt_num(-lo.y)
        ),
        format!("work zero: {z0}"),
    ]
}

/// The G-code program for `tp`, cut with `job`'s tool, stock and machine settings.
///
/// Arcs are first made fit to write ([`arcfit::legalize`] with [`arc_limits`]):
/// with `output.arcs = false`, or flatter than `output.max_arc_radius`, or
/// shorter than [`MIN_ARC_CHORD`], an arc is written as lines within half the
/// tolerance; an arc of more than half a turn is split.
pub fn write_gcode(tp: &Toolpath, job: &Job) -> Result<String, GcodeError> {
    write_gcode_on(tp, job, None)
}

/// As [`write_gcode`], on a known stock rectangle (lower-left and upper-right
/// corner, mm; a boss's or cavity's stock, `RunOutput::stock`): the header says
/// where the stock is and where the work zero sits on it. Without one (a
/// profile cut from a sheet) it gives the area the tool sweeps.
pub fn write_gcode_on(
    tp: &Toolpath,
    job: &Job,
    stock: Option<(Vec2, Vec2)>,
) -> Result<String, GcodeError> {
    check_finite(tp)?;
    let legal = arcfit::legalize(tp, &arc_limits(job));
    let tp = &legal;
    let safe_z = job.stock.safe_z.max(tp.start.z);
    let mut out = Modal {
        axis: [None, None, None],
        feed: None,
        lines: header_lines(tp, job, stock),
    };
    out.start(job, tp.start, safe_z);
    let at = out.sections(tp, safe_z);
    out.end(job, at, safe_z);
    join_lines(out.lines)
}

/// The header comments: pfcam's marker line, the tool, the stock and work
/// zero, the operation, the cut's bounds, the levels, the moves, the lengths
/// and the estimated time.
fn header_lines(tp: &Toolpath, job: &Job, stock: Option<(Vec2, Vec2)>) -> Vec<String> {
    let stats = tp.stats(job.machine.rapid_rate);
    let mut l = vec![super::header_line(&job.name), comment(&tool_line(job))];
    l.extend(stock_lines(tp, job, stock).iter().map(|c| comment(c)));
    l.push(comment(&operation_line(job)));
    if let Some((lo, hi)) = cut_bounds(tp) {
        l.push(comment(&format!(
            "cut min: X{} Y{} Z{}",
            fmt_num(lo.x),
            fmt_num(lo.y),
            fmt_num(lo.z)
        )));
        l.push(comment(&format!(
            "cut max: X{} Y{} Z{}",
            fmt_num(hi.x),
            fmt_num(hi.y),
            fmt_num(hi.z)
        )));
    }
    l.push(comment(&levels_line(tp)));
    l.push(comment(&moves_line(tp, job)));
    l.push(comment(&format!(
        "length: cut {} mm, rapid {} mm",
        fmt_num((stats.cut_length * 10.0).round() / 10.0),
        fmt_num((stats.rapid_length * 10.0).round() / 10.0)
    )));
    l.push(comment(&format!(
        "estimated time: {}, rapids at {} mm/min, acceleration ignored",
        format_duration(stats.time_s),
        fmt_num(job.machine.rapid_rate)
    )));
    l
}

/// The header's tool: diameter, shape (and a bull nose's corner), feeds and
/// spindle speed.
fn tool_line(job: &Job) -> String {
    let corner = if job.tool.shape == crate::job::CutterShape::Bull {
        format!(", corner {} mm", fmt_num(job.tool.corner))
    } else {
        String::new()
    };
    format!(
        "tool: {} mm {}{corner}, feed {}, plunge {} mm/min, spindle {} rpm",
        fmt_num(job.tool.diameter),
        job.tool.shape.header_words(),
        fmt_num(job.tool.feed),
        fmt_num(job.tool.plunge_feed),
        fmt_num(job.tool.spindle.round()),
    )
}

/// The header's operation: kind, side, direction, depth, stepdown, tolerance.
fn operation_line(job: &Job) -> String {
    let kind = match job.operation.kind {
        OperationKind::Profile => "profile",
        OperationKind::Boss => "boss",
        OperationKind::Cavity => "cavity",
    };
    let side = match job.operation.side {
        Side::Outside => "outside",
    };
    let direction = match job.operation.direction {
        Direction::Climb => "climb",
        Direction::Conventional => "conventional",
    };
    format!(
        "operation: {kind} {side} {direction}, depth {}, stepdown {}, tol {} mm",
        fmt_num(job.operation.depth),
        fmt_num(job.tool.stepdown),
        fmt_num(job.operation.tolerance)
    )
}

/// The header's count of line and arc moves (and the arcs' largest radius).
fn moves_line(tp: &Toolpath, job: &Job) -> String {
    let (arcs, lines) = tp.moves().fold((0, 0), |(a, b), m| match m {
        Move::Arc { .. } => (a + 1, b),
        Move::Linear { .. } => (a, b + 1),
        Move::Rapid { .. } => (a, b),
    });
    if job.output.arcs {
        format!(
            "moves: {lines} lines, {arcs} arcs of radius <= {} mm",
            fmt_num(job.output.max_arc_radius)
        )
    } else {
        format!("moves: {lines} lines, arcs off")
    }
}

/// The lines joined, each ending in a newline; an error for a line longer
/// than GRBL's [`MAX_LINE_LEN`].
fn join_lines(lines: Vec<String>) -> Result<String, GcodeError> {
    let mut text = String::new();
    for line in lines {
        let len = line.chars().count();
        if len > MAX_LINE_LEN {
            return Err(GcodeError::LineTooLong { line, len });
        }
        text.push_str(&line);
        text.push('\n');
    }
    Ok(text)
}

#[cfg(test)]
mod tests {

    #[test]
    fn the_header_places_the_stock_and_the_work_zero() {
        let stock = Some((Vec2::new(-12.5, -3.0), Vec2::new(40.0, 60.0)));
        let g = write_gcode_on(&square(), &job(), stock).unwrap();
        assert!(
            g.contains("(stock: X-12.5..40 Y-3..60, top 0, safe z 5 mm)"),
            "{g}"
        );
        assert!(
            g.contains("(work zero: X0 12.5 mm from its left, Y0 3 from its front)"),
            "{g}"
        );
        assert!(g.contains("(work zero: Z0 on the stock top)"), "{g}");
        // A profile's sheet: the cut bounds grown by the tool radius.
        let g = write_gcode(&square(), &job()).unwrap();
        let e = stock_extent(&square(), job().tool.diameter / 2.0, None).unwrap();
        let (lo, hi) = cut_bounds(&square()).unwrap();
        let r = job().tool.diameter / 2.0;
        assert!(!e.known);
        assert!((e.lo.x - (lo.x - r)).abs() < 1e-12 && (e.hi.y - (hi.y + r)).abs() < 1e-12);
        assert!(g.contains("(sheet at least: X"), "{g}");
        for line in g.lines() {
            assert!(line.len() <= MAX_LINE_LEN, "{line}");
        }
    }

    use super::*;
    use crate::job::parse_job;
    use crate::toolpath::Section;
    use std::path::Path;

    fn job() -> Job {
        let text = "[job]\nname = \"t\"\n[shape]\ntext = \"I\"\n[tool]\ndiameter = 3.175\nfeed = 800\nplunge_feed = 200\nspindle = 18000\n[operation]\ndepth = 2\n";
        match parse_job(text, "t", Path::new(".")) {
            Ok(j) => j,
            Err(e) => panic!("{e}"),
        }
    }

    /// A square pass with a quarter-circle arc, a plunge and a retract.
    fn square() -> Toolpath {
        let p = Vec3::new;
        Toolpath {
            start: p(0.0, 0.0, 5.0),
            sections: vec![
                Section {
                    label: "link (1)".into(),
                    z: 5.0,
                    moves: vec![Move::Rapid {
                        to: p(10.0, 0.0, 5.0),
                    }],
                },
                Section {
                    label: "outside I (1), z -1.000".into(),
                    z: -1.0,
                    moves: vec![
                        Move::Linear {
                            to: p(10.0, 0.0, -1.0),
                            feed: 200.0,
                        },
                        Move::Linear {
                            to: p(20.0, 0.0, -1.0),
                            feed: 800.0,
                        },
                        Move::Arc {
                            to: p(25.0, 5.0, -1.0),
                            cx: 20.0,
                            cy: 5.0,
                            ccw: true,
                            feed: 800.0,
                        },
                        Move::Linear {
                            to: p(25.0, 20.0000001, -1.0),
                            feed: 800.0,
                        },
                        Move::Linear {
                            to: p(-0.0000001, 20.0, -1.0),
                            feed: 800.0,
                        },
                        Move::Linear {
                            to: p(0.0, 20.0, -1.0),
                            feed: 800.0,
                        },
                        Move::Linear {
                            to: p(10.0, 0.0, -1.0),
                            feed: 800.0,
                        },
                        Move::Rapid {
                            to: p(10.0, 0.0, 5.0),
                        },
                    ],
                },
            ],
        }
    }

    fn gcode() -> String {
        match write_gcode(&square(), &job()) {
            Ok(g) => g,
            Err(e) => panic!("{e}"),
        }
    }

    #[test]
    fn numbers() {
        assert_eq!(fmt_num(1.0), "1");
        assert_eq!(fmt_num(1.5), "1.5");
        assert_eq!(fmt_num(-0.0), "0");
        assert_eq!(fmt_num(-0.0001), "0");
        assert_eq!(fmt_num(-0.0006), "-0.001");
        assert_eq!(fmt_num(12.3456), "12.346");
        assert_eq!(fmt_num(100.0), "100");
        assert_eq!(fmt_num(0.1 + 0.2), "0.3");
    }

    #[test]
    fn durations() {
        assert_eq!(format_duration(45.4), "45 s");
        assert_eq!(format_duration(754.2), "12 min 34 s");
        assert_eq!(format_duration(3725.0), "1 h 2 min 5 s");
        assert_eq!(format_duration(f64::NAN), "0 s");
    }

    #[test]
    fn comments_cannot_break_out() {
        assert_eq!(comment_text("A (1); é"), "A [1], ?");
        let long = comment(&"x".repeat(200));
        assert_eq!(long.len(), MAX_LINE_LEN);
    }

    #[test]
    fn program_shape() {
        let g = gcode();
        let lines: Vec<&str> = g.lines().collect();
        assert!(lines[0].starts_with("(pfcam ") && lines[0].ends_with(" job t)"));
        let code: Vec<&str> = lines
            .iter()
            .copied()
            .filter(|l| !l.starts_with('('))
            .collect();
        assert_eq!(
            code,
            [
                "G21 G90 G17 G94",
                "G0 Z5",
                "G0 X0 Y0",
                "M3 S18000",
                "G4 P2",
                "G0 X10",
                "G1 Z-1 F200",
                "G1 X20 F800",
                "G3 X25 Y5 I0 J5",
                "G1 Y20",
                "G1 X0",
                "G1 X10 Y0",
                "G0 Z5",
                "M5",
                "M2",
            ]
        );
        assert!(g.contains("(outside I [1], z -1.000)\n"), "{g}");
        assert!(g.contains("(cut min: X0 Y0 Z-1)\n"), "{g}");
        assert!(g.contains("(cut max: X25 Y20 Z5)\n"), "{g}");
        assert!(g.contains("(estimated time: "), "{g}");
        assert!(g.ends_with("M5\nM2\n"));
    }

    #[test]
    fn only_grbl_words_and_short_lines() {
        let g = gcode();
        for line in g.lines() {
            assert!(line.len() <= MAX_LINE_LEN, "{line}");
            if line.starts_with('(') {
                assert!(line.ends_with(')') && line[1..line.len() - 1].find(['(', ')']).is_none());
                continue;
            }
            for word in line.split(' ') {
                let (letter, num) = word.split_at(1);
                assert!("GMXYZIJFSP".contains(letter), "{word}");
                assert!(num.parse::<f64>().is_ok(), "{word}");
                assert!(!num.starts_with("-0") || num.starts_with("-0."), "{word}");
                assert!(!(num.contains('.') && num.ends_with('0')), "{word}");
                if letter == "G" {
                    assert!(
                        ["0", "1", "2", "3", "4", "17", "21", "90", "94"].contains(&num),
                        "{word}"
                    );
                }
                if letter == "M" {
                    assert!(["2", "3", "5", "8", "9"].contains(&num), "{word}");
                }
            }
        }
    }

    #[test]
    fn header_has_levels_and_moves() {
        let g = gcode();
        assert!(g.contains("\n(levels: 1, z -1)\n"), "{g}");
        assert!(
            g.contains("\n(moves: 6 lines, 1 arcs of radius <= 1000 mm)\n"),
            "{g}"
        );
        assert!(g.contains("acceleration ignored)\n"), "{g}");
        assert!(!g.contains("M8") && !g.contains("M9"), "{g}");
    }

    /// A finishing program's header counts its passes along the surface (two
    /// loops of pass 2 are one pass), not the z-levels its sloped moves would
    /// make.
    #[test]
    fn a_finishing_header_counts_passes() {
        let p = Vec3::new;
        let pass = |k: usize, z0: f64, z1: f64| Section {
            label: format!("{} {k} s 0.9{k}000", crate::toolpath::FINISH_PASS),
            z: z1,
            moves: vec![
                Move::Linear {
                    to: p(k as f64, 0.0, z0),
                    feed: 500.0,
                },
                Move::Linear {
                    to: p(k as f64, 5.0, z1),
                    feed: 500.0,
                },
            ],
        };
        let tp = Toolpath {
            start: p(0.0, 0.0, 5.0),
            sections: vec![
                pass(1, -3.0, -2.5),
                pass(2, -2.5, -2.0),
                pass(2, -2.4, -1.5),
            ],
        };
        let g = write_gcode(&tp, &job()).unwrap();
        assert!(
            g.contains(
                "\n(passes: 2 along the surface from the floor up, lowest z -2.5 to -1.5)\n"
            ),
            "{g}"
        );
        assert!(!g.contains("(levels:"), "{g}");
        // Any other section among them: z-levels as before.
        let mut mixed = tp.clone();
        mixed.sections.push(Section {
            label: "level z -1".into(),
            ..pass(3, -1.0, -1.0)
        });
        assert!(write_gcode(&mixed, &job()).unwrap().contains("\n(levels: "));
    }

    #[test]
    fn coolant_on_and_off() {
        let mut j = job();
        j.machine.coolant = true;
        let g = write_gcode(&square(), &j).unwrap();
        assert!(g.contains("\nM3 S18000\nM8\nG4 P2\n"), "{g}");
        assert!(g.ends_with("\nM9\nM5\nM2\n"), "{g}");
    }

    #[test]
    fn arcs_off_and_radius_bound_write_lines() {
        let mut j = job();
        j.output.arcs = false;
        let g = write_gcode(&square(), &j).unwrap();
        assert!(!g.contains("\nG2 ") && !g.contains("\nG3 "), "{g}");
        assert!(g.contains(" lines, arcs off)"), "{g}");
        // The quarter circle of radius 5 within 0.005 mm: 2·acos(0.999) ≈ 0.0894
        // rad per chord, 18 chords.
        assert_eq!(g.lines().filter(|l| l.starts_with("G1")).count(), 6 + 17);
        let mut j = job();
        j.output.max_arc_radius = 4.0;
        let g = write_gcode(&square(), &j).unwrap();
        assert!(!g.contains("\nG3 "), "{g}");
    }

    #[test]
    fn deterministic() {
        assert_eq!(gcode(), gcode());
    }

    #[test]
    fn no_dwell_when_disabled_and_retract_added() {
        let mut j = job();
        j.machine.spindle_dwell = 0.0;
        let mut tp = square();
        tp.sections[1].moves.pop(); // no final retract
        let g = write_gcode(&tp, &j).unwrap();
        assert!(!g.contains("G4"));
        assert!(g.ends_with("G1 X10 Y0\nG0 Z5\nM5\nM2\n"), "{g}");
    }

    #[test]
    fn full_circle_and_degenerate_arc() {
        let p = Vec3::new;
        let tp = Toolpath {
            start: p(0.0, 0.0, 5.0),
            sections: vec![Section {
                label: "circle".into(),
                z: 0.0,
                moves: vec![
                    Move::Linear {
                        to: p(10.0, 0.0, 0.0),
                        feed: 100.0,
                    },
                    Move::Arc {
                        to: p(10.0, 0.0, 0.0),
                        cx: 5.0,
                        cy: 0.0,
                        ccw: false,
                        feed: 100.0,
                    },
                    Move::Arc {
                        to: p(10.0, 0.0001, 0.0),
                        cx: 10.0,
                        cy: 0.0,
                        ccw: false,
                        feed: 100.0,
                    },
                ],
            }],
        };
        let g = write_gcode(&tp, &job()).unwrap();
        // The full circle is two half circles.
        assert!(g.contains("\nG2 X0 Y0 I-5 J0\nG2 X10 Y0 I5 J0\n"), "{g}");
        // The full circle reaches X0 and Y±5.
        assert!(g.contains("(cut min: X0 Y-5 Z0)"), "{g}");
        assert!(g.contains("(cut max: X10 Y5 Z5)"), "{g}");
        assert_eq!(g.lines().filter(|l| l.starts_with("G2 ")).count(), 2, "{g}");
    }

    #[test]
    fn bad_paths_are_errors() {
        let mut tp = square();
        tp.sections[1].moves[1] = Move::Linear {
            to: Vec3::new(f64::NAN, 0.0, 0.0),
            feed: 800.0,
        };
        assert!(matches!(
            write_gcode(&tp, &job()),
            Err(GcodeError::NonFinite { .. })
        ));
        let mut tp = square();
        tp.sections[1].moves[1] = Move::Linear {
            to: Vec3::new(1.0, 0.0, 0.0),
            feed: 0.0,
        };
        assert!(matches!(
            write_gcode(&tp, &job()),
            Err(GcodeError::BadFeed { .. })
        ));
        let mut tp = square();
        tp.sections[1].moves[1] = Move::Linear {
            to: Vec3::new(1e40, 1e40, 0.0),
            feed: 1e15,
        };
        assert!(matches!(
            write_gcode(&tp, &job()),
            Err(GcodeError::LineTooLong { .. })
        ));
    }

    /// Arcs at awkward angles and coordinates still pass GRBL 1.1's check that
    /// the start and the end are at the same distance from the centre (error 33
    /// when they differ by more than 0.005 mm and 0.1 % of the radius).
    #[test]
    fn arcs_pass_grbls_radius_check() {
        let mut moves = Vec::new();
        let (cx, cy) = (12.345_678, -7.654_321);
        for k in 0..40 {
            let r = 0.3 + 0.731 * k as f64;
            let a0 = 0.1 + 0.37 * k as f64;
            let a1 = a0 + 0.05 + 0.29 * k as f64;
            let at = |a: f64| Vec3::new(cx + r * a.cos(), cy + r * a.sin(), -1.0);
            moves.push(Move::Linear {
                to: at(a0),
                feed: 500.0,
            });
            moves.push(Move::Arc {
                to: at(a1),
                cx,
                cy,
                ccw: k % 2 == 0,
                feed: 500.0,
            });
        }
        let tp = Toolpath {
            start: Vec3::new(0.0, 0.0, 5.0),
            sections: vec![Section {
                label: "arcs".into(),
                z: -1.0,
                moves,
            }],
        };
        let g = write_gcode(&tp, &job()).unwrap();
        let (mut x, mut y) = (0.0, 0.0);
        let mut arcs = 0;
        for line in g.lines().filter(|l| !l.starts_with('(')) {
            let word = |c: char| {
                line.split(' ')
                    .find_map(|w| w.strip_prefix(c).and_then(|n| n.parse::<f64>().ok()))
            };
            let (nx, ny) = (word('X').unwrap_or(x), word('Y').unwrap_or(y));
            if line.starts_with("G2 ") || line.starts_with("G3 ") {
                let (i, j) = (word('I').unwrap(), word('J').unwrap());
                let (ccx, ccy) = (x + i, y + j);
                let r0 = i.hypot(j);
                let r1 = (nx - ccx).hypot(ny - ccy);
                let dr = (r0 - r1).abs();
                assert!(dr <= 0.005 || dr <= 0.001 * r1, "{line}: radii {r0} {r1}");
                arcs += 1;
            }
            (x, y) = (nx, ny);
        }
        // Sweeps over half a turn are split.
        assert!(arcs > 40, "{arcs}");
    }
}
