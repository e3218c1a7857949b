//! Jobs: the TOML schema (raw), and the resolved, validated job the pipeline reads.
//!
//! Two steps, as in ripgrep's `lowargs`/`hiargs`: [`RawJob`] mirrors the TOML file
//! exactly (every table and key optional, unknown keys rejected), and
//! [`resolve_with`](RawJob::resolve_with) turns it into a [`Job`] with defaults applied and
//! every value checked. Every error names the key (`tool.diameter`, ...), and a
//! syntax error names the line and column. The keys, units and defaults are
//! documented in `docs/job-format.md`.
//!
//! This file holds the resolved types and [`JobError`]; the steps are in
//! `job/`: `raw.rs` (the schema), `load.rs` (reading the file, parsing the
//! TOML, placing its errors by line, column and key), `resolve.rs`
//! ([`RawJob::resolve_with`] and the checkers the tables' resolvers share),
//! `machine.rs` (`[machine]`, and machine files), and one resolver per table
//! (`tool.rs`, `shape.rs`, `stock.rs`, `operation.rs`, `field.rs`, ...).

use crate::geometry::ShapeSource;
use std::path::{Path, PathBuf};

mod composition;
#[cfg(test)]
mod doc_tests;
mod dxffile;
pub mod echo;
mod exact;
pub mod extent;
mod field;
pub(crate) mod finish;
mod font;
mod harmonic;
pub mod limits;
mod load;
mod machine;
mod operation;
mod polyharmonic;
mod polyharmonic_file;
mod profile;
mod raw;
mod resolve;
mod shape;
mod stock;
mod svgfile;
#[cfg(test)]
mod tests;
mod text;
mod tool;
mod tube;
mod tube_trim;

pub(crate) use finish::CutterShape;
pub(crate) use finish::Finish;
pub(crate) use finish::Pattern;
pub use font::Fonts;
pub use font::Sources;
pub use load::load_job;
pub use load::parse_job;
pub use load::parse_job_with;
pub use machine::load_machine;
pub(crate) use machine::Machine;
pub use machine::MachineSource;
pub(crate) use raw::AutoOr;
pub(crate) use raw::RawField;
pub(crate) use raw::RawJob;
pub(crate) use raw::RawOperation;
pub(crate) use raw::RawOutput;
pub(crate) use raw::RawPart;
pub(crate) use raw::RawProfile;
pub(crate) use raw::RawShape;
pub(crate) use raw::RawStock;
pub(crate) use raw::RawTool;
pub(crate) use raw::RawTrim;

/// A resolved job: units in mm, mm/min and rev/min, defaults applied, validated.
#[derive(Clone, Debug, PartialEq)]
pub struct Job {
    /// Job name: output files are `<name>.nc` etc.
    pub name: String,
    /// What to cut.
    pub shape: ShapeSource,
    /// The cutter.
    pub tool: Tool,
    /// The stock.
    pub stock: Stock,
    /// What to do.
    pub operation: Operation,
    /// How to build the potential field.
    pub(crate) field: FieldSpec,
    /// Machine settings that only the G-code writer and time estimates read.
    pub machine: Machine,
    /// The depth profile φ(s) of a boss or cavity (`None` for a profile).
    pub profile: Option<crate::profile::DepthProfile>,
    /// What the G-code may contain (arcs).
    pub output: Output,
    /// The finishing tool of a boss or cavity (`[finish]`): with it the job
    /// writes a roughing and a finishing program.
    pub finish: Option<Finish>,
}

impl Job {
    /// The job as its finishing program sees it: `[finish]`'s cutter, feeds
    /// and spindle as the tool (`None` without a `[finish]` table).
    pub fn finishing(&self) -> Option<Job> {
        let f = self.finish.as_ref()?;
        let mut j = self.clone();
        j.tool.shape = f.shape;
        j.tool.corner = f.corner;
        j.tool.diameter = f.diameter;
        j.tool.feed = f.feed;
        j.tool.plunge_feed = f.plunge_feed;
        j.tool.spindle = f.spindle;
        Some(j)
    }
}

/// The cutter of a program: `[tool]` (a flat end mill, the roughing) or, for
/// the finishing program, the `[finish]` tool ([`Job::finishing`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Tool {
    /// Flat for `[tool]`; `[finish]` may be ball or bull nose.
    pub(crate) shape: CutterShape,
    /// Corner radius, mm (0 for a flat end mill).
    pub(crate) corner: f64,
    /// Diameter, mm (> 0).
    pub diameter: f64,
    /// Cutting feed, mm/min.
    pub(crate) feed: f64,
    /// Plunge feed, mm/min.
    pub(crate) plunge_feed: f64,
    /// Spindle speed, rev/min.
    pub(crate) spindle: f64,
    /// Largest depth of one pass, mm.
    pub stepdown: f64,
    /// Largest sideways step between clearing rings, mm.
    pub(crate) stepover: f64,
    /// Angle of ramped entries into uncut material, degrees.
    pub(crate) ramp_angle: f64,
}

/// The stock.
#[derive(Clone, Debug, PartialEq)]
pub struct Stock {
    /// Z of the stock's top surface, mm.
    pub top: f64,
    /// Z for rapid moves, mm (above `top`).
    pub(crate) safe_z: f64,
    /// Z for the rapids between the cuts of one program, mm: above `top`, at
    /// most `safe_z` (which the program starts and ends at).
    pub(crate) retract_z: f64,
    /// Stock around the part's largest level (a boss's base), mm on every side.
    pub margin: f64,
}

/// Operation kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OperationKind {
    /// Cut along the shape's boundary with vertical walls.
    Profile,
    /// A raised sign whose walls follow φ(s): material outside Γ(s(z)) is removed at every level.
    Boss,
    /// The sign's mould: the inverse model milled into a slab, level by level.
    Cavity,
}

/// Which side of the material the tool runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    /// Outside the material: outside every outline, inside every counter.
    Outside,
}

/// Milling direction (with a clockwise spindle, M3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Climb: the material on the tool's right (outlines clockwise, counters counter-clockwise).
    Climb,
    /// Conventional: the material on the tool's left.
    Conventional,
}

/// The operation.
#[derive(Clone, Debug, PartialEq)]
pub struct Operation {
    /// Kind.
    pub kind: OperationKind,
    /// Side.
    pub(crate) side: Side,
    /// Depth of cut below `stock.top`, mm (> 0).
    pub depth: f64,
    /// Chord and fitting tolerance, mm (> 0).
    pub tolerance: f64,
    /// Climb or conventional.
    pub direction: Direction,
    /// Largest horizontal step between the contours of neighbouring levels, mm.
    pub(crate) max_scallop: f64,
    /// Material the roughing leaves on the walls, mm (in plan, beyond the tool
    /// radius); floors are cut to size.
    pub stock_to_leave: f64,
}

/// How the MFS field is set up.
#[derive(Clone, Debug, PartialEq, Default)]
pub(crate) struct FieldSpec {
    /// Total number of singularities N; `None` chooses from the shape.
    pub(crate) singularities: Option<usize>,
    /// Pseudo-boundary distance in mm; `None` chooses it to minimise the max boundary error.
    pub(crate) pseudo_boundary: Option<f64>,
}

/// What the G-code may contain.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    /// Fit arcs (`G2`/`G3`) to the traced path; `false` writes lines only, for
    /// controllers that handle arcs badly.
    pub arcs: bool,
    /// Arcs flatter than this radius are written as lines, mm (> 0).
    pub max_arc_radius: f64,
}

impl Default for Output {
    fn default() -> Self {
        Output {
            arcs: defaults::ARCS,
            max_arc_radius: defaults::MAX_ARC_RADIUS,
        }
    }
}

/// The defaults of optional keys (documented in `docs/job-format.md`).
pub(crate) mod defaults {
    /// `shape.font`: the built-in letters of the paper.
    pub(crate) const FONT: &str = "paper";
    /// `shape.height` for text, mm of cap height.
    pub(crate) const TEXT_HEIGHT: f64 = 50.0;
    /// `shape.part.size`: cap height of a text part, design units.
    pub(crate) const PART_TEXT_SIZE: f64 = 100.0;
    /// `tool.feed`, mm/min: a moderate feed for a 3 mm cutter in wood or plastic.
    pub(crate) const FEED: f64 = 800.0;
    /// `tool.plunge_feed`, mm/min: a quarter of the feed.
    pub(crate) const PLUNGE_FEED: f64 = 200.0;
    /// `tool.spindle`, rev/min.
    pub(crate) const SPINDLE: f64 = 10000.0;
    /// `tool.stepdown`, mm per pass.
    pub(crate) const STEPDOWN: f64 = 1.0;
    /// `stock.top`, mm.
    pub(crate) const STOCK_TOP: f64 = 0.0;
    /// `stock.safe_z` is this far above `stock.top`, mm.
    pub(crate) const SAFE_CLEARANCE: f64 = 5.0;
    /// `operation.tolerance`, mm.
    pub(crate) const TOLERANCE: f64 = 0.01;
    /// `shape.join_tolerance`, mm: DXF pieces whose ends are closer join.
    pub(crate) const JOIN_TOLERANCE: f64 = 0.01;
    /// `machine.rapid_rate`, mm/min (GRBL's own default `$110` is 500; most
    /// hobby machines are set faster).
    pub(crate) const RAPID_RATE: f64 = 1000.0;
    /// `machine.spindle_dwell`, seconds.
    pub(crate) const SPINDLE_DWELL: f64 = 2.0;
    /// `tool.stepover` as a fraction of the diameter.
    pub(crate) const STEPOVER_FRACTION: f64 = 0.4;
    /// `tool.ramp_angle`, degrees: gentle enough for a flat end mill in wood, plastic or aluminium.
    pub(crate) const RAMP_ANGLE: f64 = 3.0;
    /// `stock.margin`, mm.
    pub(crate) const MARGIN: f64 = 5.0;
    /// `operation.max_scallop`, mm.
    pub(crate) const MAX_SCALLOP: f64 = 0.5;
    /// `profile.kind`.
    pub(crate) const PROFILE_KIND: &str = "linear";
    /// `profile.s_bottom` for a linear profile.
    pub(crate) const S_BOTTOM: f64 = 0.8;
    /// `profile.s1`, `profile.s2`, `profile.steepness` for a sigmoid (the paper's Section 7 values).
    pub(crate) const SIGMOID: (f64, f64, f64) = (0.99, 0.75, 8.0);
    /// `profile.s1`, `s2`, `exponent` for a power wall: the paper's n = 500
    /// (Section 3.2), from Γ(0.999) down to Γ(0.99).
    pub(crate) const POWER: (f64, f64, f64) = (0.999, 0.99, 500.0);
    /// `machine.coolant`: off (most hobby routers have none).
    pub(crate) const COOLANT: bool = false;
    /// `machine.max_hours`: a working day; the longest shipped program
    /// (mfs-sign) is estimated at under 6 h.
    pub(crate) const MAX_HOURS: f64 = 8.0;
    /// `machine.max_file_mb`: the largest shipped program (mfs-mould.rough.nc)
    /// is 1.9 MB.
    pub(crate) const MAX_FILE_MB: f64 = 100.0;
    /// `output.arcs`: on (GRBL 1.1 cuts arcs well and the file is smaller).
    pub(crate) const ARCS: bool = true;
    /// `output.max_arc_radius`, mm: a 1000 mm arc over a 100 mm chord bulges
    /// 1.25 mm, so anything flatter is a line to the eye and to the machine.
    pub(crate) const MAX_ARC_RADIUS: f64 = 1000.0;
}

/// The accepted values of `operation.kind`.
pub(crate) const OPERATION_KINDS: &[&str] = &["profile", "boss", "cavity"];
/// The accepted values of `profile.kind`.
pub(crate) const PROFILE_KINDS: &[&str] = &["linear", "sigmoid", "power", "spline", "table"];
/// The accepted values of `operation.side`.
pub(crate) const SIDES: &[&str] = &["outside"];
/// The accepted values of `operation.direction`.
pub(crate) const DIRECTIONS: &[&str] = &["climb", "conventional"];

/// What can be wrong with a job.
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    /// The job file cannot be read.
    #[error("cannot read job file {}: {reason}", path.display(), reason = io_reason(error))]
    Read {
        /// the file
        path: PathBuf,
        /// why (not a `source`: the message already says it, once)
        error: std::io::Error,
    },
    /// The file is not a job file at all (too large, not text, a directory).
    #[error("{} is not a job file: {why}", path.display())]
    NotAJob {
        /// the file
        path: PathBuf,
        /// why not
        why: String,
    },
    /// The TOML does not parse, or does not fit the schema (unknown key, wrong type).
    #[error("{origin}:{line}:{column}: {}{}", key.as_ref().map(|k| format!("{k}: ")).unwrap_or_default(), toml_message(error, *misplaced))]
    Parse {
        /// the file, or `job` for text not read from a file
        origin: String,
        /// 1-based line
        line: usize,
        /// 1-based column (characters)
        column: usize,
        /// the key at that place, when one can be named (`tool.diamter`)
        key: Option<String>,
        /// what the TOML reader says (not a `source`: the message already
        /// says it, once)
        error: Box<toml::de::Error>,
        /// the key is one of `[shape]`'s written after the first
        /// `[[shape.part]]`, which TOML reads as the part's: the message says
        /// where it belongs
        misplaced: bool,
    },
    /// A value is out of range or inconsistent: `tool.diameter must be ...`.
    #[error("{key} {message}")]
    Invalid {
        /// the key, e.g. `tool.diameter`
        key: String,
        /// what is wrong, starting with a verb (`must be > 0, got -3`)
        message: String,
    },
    /// A file named by a key (`shape.svg_file`) that does not exist.
    #[error("{key}: no such file: {}", echo::clip(&path.display().to_string()))]
    FileNotFound {
        /// the key
        key: String,
        /// the resolved path
        path: PathBuf,
    },
    /// A font file that does not exist.
    #[error("{key}: no such file: {}", echo::clip(&path.display().to_string()))]
    FontNotFound {
        /// the key: `shape.font`, or a part's `shape.part[2].font`
        key: String,
        /// the resolved path
        path: PathBuf,
    },
}

/// An I/O error as a reader wants it: `no such file` rather than
/// `No such file or directory (os error 2)`.
fn io_reason(e: &std::io::Error) -> String {
    use std::io::ErrorKind;
    match e.kind() {
        ErrorKind::NotFound => "no such file".into(),
        ErrorKind::PermissionDenied => "permission denied".into(),
        _ => e.to_string(),
    }
}

/// What the TOML reader says, trimmed, with where a misplaced `[shape]`
/// key belongs, and clipped ([`echo::clip_message`]).
fn toml_message(e: &toml::de::Error, misplaced: bool) -> String {
    let mut message = e.message().trim().to_string();
    if misplaced {
        message.push_str(
            " (shape.result, shape.height and shape.origin belong in [shape], above the first [[shape.part]])",
        );
    }
    echo::clip_message(&message)
}

impl JobError {
    /// The key the error is about, when there is one.
    pub fn key(&self) -> Option<&str> {
        match self {
            JobError::Read { .. } | JobError::NotAJob { .. } => None,
            JobError::Parse { key, .. } => key.as_deref(),
            JobError::Invalid { key, .. } => Some(key),
            JobError::FontNotFound { key, .. } | JobError::FileNotFound { key, .. } => Some(key),
        }
    }

    /// A parse error placed in the file at `path` (its origin the path
    /// rather than `job`, which text not read from a file has); any other
    /// error as it is. The job and machine readers both parse text they
    /// read from a file.
    fn in_file(mut self, path: &Path) -> JobError {
        if let JobError::Parse { origin, .. } = &mut self {
            *origin = path.display().to_string();
        }
        self
    }
}

/// An invalid value's error; echoed values in `message` are clipped
/// ([`echo::clip_message`]).
fn invalid(key: &str, message: impl Into<String>) -> JobError {
    JobError::Invalid {
        key: key.into(),
        message: echo::clip_message(&message.into()),
    }
}
