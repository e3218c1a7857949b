//! The sane range of every numeric job key, and the sizes that drive memory and
//! time (points, parts, text, singularities), checked when a job is loaded so
//! that a value no machine could use fails at once, naming its key, instead of
//! exhausting memory or running for hours. `docs/job-format.md` lists the same
//! ranges; `every_range_is_documented` (in `job/doc_tests.rs`) keeps the two in step.

use super::resolve::show;
use super::{invalid, JobError};

/// A closed or half-open interval of accepted values, with its unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Range {
    /// Smallest accepted value (excluded when `lo_open`).
    pub(crate) lo: f64,
    /// Whether `lo` itself is refused (`> lo` rather than `>= lo`).
    pub(crate) lo_open: bool,
    /// Largest accepted value (included).
    pub(crate) hi: f64,
    /// The unit, as written in messages (`mm`, `mm/min`), or empty.
    pub(crate) unit: &'static str,
}

impl Range {
    const fn open(lo: f64, hi: f64, unit: &'static str) -> Range {
        Range {
            lo,
            lo_open: true,
            hi,
            unit,
        }
    }

    const fn closed(lo: f64, hi: f64, unit: &'static str) -> Range {
        Range {
            lo,
            lo_open: false,
            hi,
            unit,
        }
    }

    /// Whether `x` is in the range (NaN never is).
    pub(crate) fn contains(&self, x: f64) -> bool {
        let above = if self.lo_open {
            x > self.lo
        } else {
            x >= self.lo
        };
        above && x <= self.hi
    }

    /// The interval as docs/job-format.md writes it: `(0, 50]`.
    pub(crate) fn interval(&self) -> String {
        let open = if self.lo_open { '(' } else { '[' };
        format!("{open}{}, {}]", show(self.lo), show(self.hi))
    }

    /// The range as messages write it: `(0, 50] mm`.
    pub(crate) fn describe(&self) -> String {
        if self.unit.is_empty() {
            self.interval()
        } else {
            format!("{} {}", self.interval(), self.unit)
        }
    }

    /// `x` if it is in the range, else an error naming `key`. A range of
    /// positive numbers says so for a value ≤ 0: `must be a positive number of
    /// mm, got -3`.
    pub(crate) fn check(&self, key: &str, x: f64) -> Result<f64, JobError> {
        if self.contains(x) {
            return Ok(x);
        }
        let positive = self.lo > 0.0 || (self.lo == 0.0 && self.lo_open);
        let message = if positive && (x.is_nan() || x <= 0.0) {
            let of = if self.unit.is_empty() {
                String::new()
            } else {
                format!(" of {}", self.unit)
            };
            format!("must be a positive number{of}, got {}", show(x))
        } else {
            format!("must be in {}, got {}", self.describe(), show(x))
        };
        Err(invalid(key, message))
    }
}

/// `tool.diameter`: from a 10 µm micro-engraving bit to a 100 mm surfacing cutter.
pub(crate) const TOOL_DIAMETER: Range = Range::closed(0.01, 100.0, "mm");
/// `tool.feed` and `tool.plunge_feed`: no GRBL machine moves faster than 100 m/min.
pub(crate) const FEED: Range = Range::open(0.0, 100_000.0, "mm/min");
/// `tool.spindle`.
pub(crate) const SPINDLE: Range = Range::closed(0.0, 100_000.0, "rev/min");
/// `tool.stepdown`.
pub(crate) const STEPDOWN: Range = Range::open(0.0, 50.0, "mm");
/// `tool.stepover` (also at most the tool radius, checked on its own): the
/// default, 0.4 × the smallest diameter, is inside it.
pub(crate) const STEPOVER: Range = Range::closed(0.001, 50.0, "mm");
/// `tool.ramp_angle`: below half a degree a ramp is longer than any part.
pub(crate) const RAMP_ANGLE: Range = Range::closed(0.5, 45.0, "degrees");
/// Smallest `tool.stepover` as a fraction of `tool.diameter`: the time of a
/// boss or cavity grows as 1/stepover (the letter I boss, 3.175 mm tool: 16 s at
/// the default 0.4 D, 125 s at 0.05 D, `time pfcam run`); 0.05 D is finer than
/// any finishing pass of a flat end mill.
pub(crate) const MIN_STEPOVER_FRACTION: f64 = 0.05;
/// `stock.top`.
pub(crate) const STOCK_TOP: Range = Range::closed(-1000.0, 1000.0, "mm");
/// `stock.safe_z`, as a height above `stock.top` (also above it, checked on its own).
pub(crate) const SAFE_CLEARANCE: Range = Range::open(0.0, 200.0, "mm above stock.top");
/// `stock.margin`: a boss clears the whole margin at every level, and its
/// time grows faster than the margin: the letter I boss took 16 s at 5 mm and
/// 160 s at 200 mm, and at 1000 mm had not finished its first level of 96 after
/// 8.9 min (`time pfcam run`, load 3 to 6). So 200 mm, not more.
pub(crate) const MARGIN: Range = Range::closed(0.0, 200.0, "mm");
/// `operation.depth`.
pub(crate) const DEPTH: Range = Range::open(0.0, 200.0, "mm");
/// `operation.tolerance` (also below the tool radius, checked on its own): no
/// finer than the G-code's 3 decimals, which round every coordinate by up to
/// 0.5 µm (0.0001 failed the gouge check of the letter I by its own size).
pub(crate) const TOLERANCE: Range = Range::closed(0.001, 1.0, "mm");
/// `operation.max_scallop`.
pub(crate) const MAX_SCALLOP: Range = Range::closed(0.01, 50.0, "mm");
/// `shape.height`: from a 0.1 mm engraving to a sign as large as a large
/// router's bed. The width and height of the built shape are bounded by the
/// same 2000 mm ([`MAX_EXTENT`]).
pub(crate) const SHAPE_HEIGHT: Range = Range::closed(0.1, 2000.0, "mm");
/// `shape.width` (with `shape.svg_file`): as `shape.height`.
pub(crate) const SHAPE_WIDTH: Range = Range::closed(0.1, 2000.0, "mm");
/// `shape.scale` (with `shape.svg_file`): the document's size times this.
pub(crate) const SVG_SCALE: Range = Range::open(0.0, 1000.0, "");
/// `shape.join_tolerance` (with `shape.dxf_file`): from a micrometre (below
/// any drawing's rounding of interest) to 10 mm (past that, pieces that are
/// meant apart would join).
pub(crate) const JOIN_TOLERANCE: Range = Range::closed(0.000001, 10.0, "mm");
/// `shape.origin`, each coordinate.
pub(crate) const ORIGIN: Range = Range::closed(-10_000.0, 10_000.0, "mm");
/// `shape.size` (harmonic patch), each side: as `shape.height`, from 1 mm.
pub(crate) const PATCH_SIZE: Range = Range::closed(1.0, 2000.0, "mm");
/// `shape.row0`, `shape.row1` (harmonic patch), each height: the part is at
/// most `operation.depth`'s 200 mm deep.
pub(crate) const PATCH_HEIGHT: Range = Range::closed(-200.0, 200.0, "mm");
/// `shape.bottom_size`, `shape.top_size` (PDE tube), each side.
pub(crate) const TUBE_SIZE: Range = Range::closed(1.0, 2000.0, "mm");
/// `shape.bottom_exponent`, `shape.top_exponent` (PDE tube): 1 a diamond,
/// 2 an ellipse, 4 a squircle; past 16 the curve is a rectangle whose
/// corners K samples cannot follow.
pub(crate) const TUBE_EXPONENT: Range = Range::closed(1.0, 16.0, "");
/// `shape.flare`, `shape.rise` (PDE tube), each end: Xᵤ's parts, mm per unit u.
pub(crate) const TUBE_SLOPE: Range = Range::closed(-1000.0, 1000.0, "mm");
/// `shape.a` (PDE tube): the PDE's parameter; e^{−a} below rounding past 50.
pub(crate) const TUBE_A: Range = Range::closed(0.01, 50.0, "");
/// `shape.modes` (PDE tube): N.
pub(crate) const TUBE_MODES: Range = Range::closed(0.0, 64.0, "");
/// `shape.samples` (PDE tube): K, also at least 2·modes + 1.
pub(crate) const TUBE_SAMPLES: Range = Range::closed(16.0, 1024.0, "");
/// `shape.letter_spacing`.
pub(crate) const LETTER_SPACING: Range = Range::closed(-1000.0, 1000.0, "mm");
/// `shape.line_spacing`, baseline to baseline in em: lines may overlap (below
/// about 1) but not coincide; 10 em is already far apart.
pub(crate) const LINE_SPACING: Range = Range::open(0.0, 10.0, "em");
/// Every polygon coordinate of a part, design units.
pub(crate) const DESIGN: Range = Range::closed(-1e6, 1e6, "design units");
/// `shape.part[i].size`, the cap height of a text part, design units.
pub(crate) const PART_SIZE: Range = Range::open(0.0, 1e6, "design units");
/// `profile.steepness`.
pub(crate) const STEEPNESS: Range = Range::open(0.0, 10_000.0, "");
/// `profile.exponent`: n in (s/s1)ⁿ; past 1e6 the whole wall sits within
/// rounding of s1.
pub(crate) const EXPONENT: Range = Range::open(0.0, 1e6, "");
/// `field.pseudo_boundary`.
pub(crate) const PSEUDO_BOUNDARY: Range = Range::open(0.0, 10_000.0, "mm");
/// `machine.rapid_rate`.
pub(crate) const RAPID_RATE: Range = Range::open(0.0, 100_000.0, "mm/min");
/// `machine.spindle_dwell`.
pub(crate) const SPINDLE_DWELL: Range = Range::closed(0.0, 600.0, "s");
/// `machine.travel`, each axis.
pub(crate) const TRAVEL: Range = Range::open(0.0, 10_000.0, "mm");
/// `machine.work_offset`, each axis.
pub(crate) const WORK_OFFSET: Range = Range::closed(-10_000.0, 10_000.0, "mm");
/// `machine.max_hours`: six weeks of machining at most.
pub(crate) const MAX_HOURS: Range = Range::open(0.0, 1000.0, "h");
/// `machine.max_file_mb`: 10 GB, far beyond what GRBL streams in a day.
pub(crate) const MAX_FILE_MB: Range = Range::open(0.0, 10_000.0, "MB");
/// `output.max_arc_radius`.
pub(crate) const MAX_ARC_RADIUS: Range = Range::open(0.0, 100_000.0, "mm");
/// `operation.stock_to_leave`, mm: a roughing allowance, never a part's size.
pub(crate) const STOCK_TO_LEAVE: Range = Range::closed(0.0, 5.0, "mm");
/// `finish.scallop`, mm: a thousandth of a millimetre is below any machine's
/// repeatability; a millimetre is no finish.
pub(crate) const SCALLOP: Range = Range::closed(0.001, 1.0, "mm");

/// Every numeric key with its range, for the docs test and for `pfcam validate`.
#[cfg(test)]
pub(crate) const KEYS: &[(&str, Range)] = &[
    ("tool.diameter", TOOL_DIAMETER),
    ("tool.feed", FEED),
    ("tool.plunge_feed", FEED),
    ("tool.spindle", SPINDLE),
    ("tool.stepdown", STEPDOWN),
    ("tool.stepover", STEPOVER),
    ("tool.ramp_angle", RAMP_ANGLE),
    ("stock.top", STOCK_TOP),
    ("stock.safe_z", SAFE_CLEARANCE),
    ("stock.margin", MARGIN),
    ("operation.depth", DEPTH),
    ("operation.tolerance", TOLERANCE),
    ("operation.max_scallop", MAX_SCALLOP),
    ("operation.stock_to_leave", STOCK_TO_LEAVE),
    ("finish.diameter", TOOL_DIAMETER),
    ("finish.feed", FEED),
    ("finish.plunge_feed", FEED),
    ("finish.spindle", SPINDLE),
    ("finish.scallop", SCALLOP),
    ("shape.height", SHAPE_HEIGHT),
    ("shape.width", SHAPE_WIDTH),
    ("shape.scale", SVG_SCALE),
    ("shape.origin", ORIGIN),
    ("shape.size", PATCH_SIZE),
    ("shape.row0", PATCH_HEIGHT),
    ("shape.row1", PATCH_HEIGHT),
    ("shape.bottom_size", TUBE_SIZE),
    ("shape.top_size", TUBE_SIZE),
    ("shape.bottom_exponent", TUBE_EXPONENT),
    ("shape.top_exponent", TUBE_EXPONENT),
    ("shape.flare", TUBE_SLOPE),
    ("shape.rise", TUBE_SLOPE),
    ("shape.a", TUBE_A),
    ("shape.modes", TUBE_MODES),
    ("shape.samples", TUBE_SAMPLES),
    ("shape.join_tolerance", JOIN_TOLERANCE),
    ("shape.letter_spacing", LETTER_SPACING),
    ("shape.line_spacing", LINE_SPACING),
    ("shape.part.size", PART_SIZE),
    ("shape.part.polygon", DESIGN),
    ("profile.steepness", STEEPNESS),
    ("profile.exponent", EXPONENT),
    ("field.pseudo_boundary", PSEUDO_BOUNDARY),
    ("machine.rapid_rate", RAPID_RATE),
    ("machine.spindle_dwell", SPINDLE_DWELL),
    ("machine.travel", TRAVEL),
    ("machine.work_offset", WORK_OFFSET),
    ("machine.max_hours", MAX_HOURS),
    ("machine.max_file_mb", MAX_FILE_MB),
    ("output.max_arc_radius", MAX_ARC_RADIUS),
];

/// Largest job file read, bytes: a job is a few kilobytes; this leaves room for
/// long SVG path data and polygons while refusing `/dev/zero` or a stray log.
pub(crate) const MAX_JOB_BYTES: u64 = 1 << 20;
/// Largest number of singularities of one MFS solve (`field.singularities`,
/// `shape.part[i].singularities`, `pfcam convergence --n`): the dense system is
/// about 3N × N numbers, 1.5 GB at this N.
pub const MAX_SINGULARITIES: usize = 8000;
/// Largest number of counts in one `pfcam convergence --n` study.
pub const MAX_STUDY_COUNTS: usize = 50;
/// Largest number of curves `pfcam preview --levels` draws.
pub const MAX_PREVIEW_LEVELS: usize = 1000;
/// Largest number of characters of `shape.text`, of all of `shape.lines`
/// together (line breaks not counted), or of a text part.
pub(crate) const MAX_TEXT_CHARS: usize = 200;
/// Largest number of `shape.lines`.
pub(crate) const MAX_TEXT_LINES: usize = 50;
/// Largest number of `[[shape.part]]` tables: each may need a field solve.
pub(crate) const MAX_PARTS: usize = 100;
/// Largest number of points of one polygon part.
pub(crate) const MAX_POLYGON_POINTS: usize = 10_000;
/// Largest number of `profile.points`.
pub(crate) const MAX_PROFILE_POINTS: usize = 1000;
/// Largest number of passes or stepdown levels, `operation.depth / tool.stepdown`.
pub(crate) const MAX_PASSES: f64 = 1000.0;
/// Most clearing rings across a boss's `stock.margin` (margin / stepover): the
/// 160 s measured for the largest margin (200 mm at the 3.175 mm tool's 1.27 mm
/// stepover, see [`MARGIN`]); a fine stepover or a small tool lowers the margin.
pub(crate) const MAX_MARGIN_RINGS: f64 = 160.0;
/// Most z-levels of a boss or cavity, the stepdown's and those added for
/// `operation.max_scallop` together: each is a field solve and a trace (the
/// mfs-sign job has 31), and each added one a contour comparison first.
pub(crate) const MAX_LEVELS: usize = 400;
/// Largest ratio of the shape's height to the tool diameter: beyond it the tool
/// path runs to kilometres (issue-sized letters with an engraving bit).
pub(crate) const MAX_HEIGHT_PER_DIAMETER: f64 = 2000.0;
/// Largest width or height of the built shape, mm (`shape.height`'s upper end),
/// checked once the shape is built: a composition, an SVG path without
/// `shape.height`, or a long text can be larger than its height says.
pub(crate) const MAX_EXTENT: f64 = 2000.0;

/// `n` if it is a count in [1, limit], else an error naming `key`.
pub(crate) fn count(key: &str, n: i64, limit: usize, what: &str) -> Result<usize, JobError> {
    match usize::try_from(n) {
        Ok(u) if (1..=limit).contains(&u) => Ok(u),
        _ => Err(invalid(
            key,
            format!("must be \"auto\" or a whole number of {what} in [1, {limit}], got {n}"),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_refuse_nan_infinity_and_their_ends_as_stated() {
        for (key, r) in KEYS {
            assert!(!r.contains(f64::NAN), "{key}");
            assert!(!r.contains(f64::INFINITY), "{key}");
            assert!(!r.contains(f64::NEG_INFINITY), "{key}");
            assert!(r.contains(r.hi), "{key}");
            assert!(!r.contains(r.hi * 1.000_001 + 1e-9), "{key}");
            assert_eq!(r.contains(r.lo), !r.lo_open, "{key}");
            assert!(r
                .check(key, 1e300)
                .unwrap_err()
                .to_string()
                .starts_with(key));
        }
    }

    #[test]
    fn describe_and_message() {
        assert_eq!(TOOL_DIAMETER.describe(), "[0.01, 100] mm");
        assert_eq!(SPINDLE.describe(), "[0, 100000] rev/min");
        assert_eq!(STEEPNESS.describe(), "(0, 10000]");
        let e = TOOL_DIAMETER.check("tool.diameter", 1e300).unwrap_err();
        assert_eq!(
            e.to_string(),
            "tool.diameter must be in [0.01, 100] mm, got 1e300"
        );
        let e = DEPTH.check("operation.depth", -3.0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "operation.depth must be a positive number of mm, got -3"
        );
        let e = STEEPNESS.check("profile.steepness", 0.0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "profile.steepness must be a positive number, got 0"
        );
        assert_eq!(count("field.singularities", 100_000, MAX_SINGULARITIES, "singularities").unwrap_err().to_string(),
            "field.singularities must be \"auto\" or a whole number of singularities in [1, 8000], got 100000");
        assert_eq!(count("k", 7, 10, "x").unwrap(), 7);
        assert!(count("k", 0, 10, "x").is_err());
        assert!(count("k", -3, 10, "x").is_err());
    }
}
