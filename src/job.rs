//! Jobs: the TOML schema (raw), and the resolved, validated job the pipeline reads.
//!
//! Two steps, as in ripgrep's `lowargs`/`hiargs`: [`RawJob`] mirrors the TOML file
//! exactly (every table and key optional, unknown keys rejected), and
//! [`resolve`](RawJob::resolve) turns it into a [`Job`] with defaults applied and
//! every value checked. Every error names the key (`tool.diameter`, ...), and a
//! syntax error names the line and column. The keys, units and defaults are
//! documented in `docs/job-format.md`.

use crate::geometry::svgfile::SvgSize;
use crate::geometry::ShapeSource;
use serde::Deserialize;
use std::path::{Path, PathBuf};

mod composition;
mod dxffile;
pub mod echo;
mod exact;
pub mod extent;
mod field;
pub mod finish;
mod font;
mod harmonic;
pub mod limits;
mod operation;
mod polyharmonic;
mod polyharmonic_file;
mod profile;
mod shape;
mod stock;
mod svgfile;
mod text;
mod tool;
mod tube;
mod tube_trim;

pub use composition::PART_OPS;
pub use finish::{CutterShape, Finish, Pattern};
pub use font::{Fonts, Sources};

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
    pub field: FieldSpec,
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
    pub shape: CutterShape,
    /// Corner radius, mm (0 for a flat end mill).
    pub corner: f64,
    /// Diameter, mm (> 0).
    pub diameter: f64,
    /// Cutting feed, mm/min.
    pub feed: f64,
    /// Plunge feed, mm/min.
    pub plunge_feed: f64,
    /// Spindle speed, rev/min.
    pub spindle: f64,
    /// Largest depth of one pass, mm.
    pub stepdown: f64,
    /// Largest sideways step between clearing rings, mm.
    pub stepover: f64,
    /// Angle of ramped entries into uncut material, degrees.
    pub ramp_angle: f64,
}

/// The stock.
#[derive(Clone, Debug, PartialEq)]
pub struct Stock {
    /// Z of the stock's top surface, mm.
    pub top: f64,
    /// Z for rapid moves, mm (above `top`).
    pub safe_z: f64,
    /// Z for the rapids between the cuts of one program, mm: above `top`, at
    /// most `safe_z` (which the program starts and ends at).
    pub retract_z: f64,
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
pub enum Side {
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
    pub side: Side,
    /// Depth of cut below `stock.top`, mm (> 0).
    pub depth: f64,
    /// Chord and fitting tolerance, mm (> 0).
    pub tolerance: f64,
    /// Climb or conventional.
    pub direction: Direction,
    /// Largest horizontal step between the contours of neighbouring levels, mm.
    pub max_scallop: f64,
    /// Material the roughing leaves on the walls, mm (in plan, beyond the tool
    /// radius); floors are cut to size.
    pub stock_to_leave: f64,
}

/// How the MFS field is set up.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct FieldSpec {
    /// Total number of singularities N; `None` chooses from the shape.
    pub singularities: Option<usize>,
    /// Pseudo-boundary distance in mm; `None` chooses it to minimise the max boundary error.
    pub pseudo_boundary: Option<f64>,
}

/// Machine settings used by the G-code writer and the time estimate.
#[derive(Clone, Debug, PartialEq)]
pub struct Machine {
    /// Rate assumed for rapid (G0) moves in time estimates, mm/min. GRBL's real
    /// rapid rate is its `$110`/`$111`/`$112` setting; pfcam cannot read it.
    pub rapid_rate: f64,
    /// Dwell after `M3` so the spindle reaches speed before the first cut, seconds
    /// (0 writes no `G4`).
    pub spindle_dwell: f64,
    /// Flood coolant: `M8` after the spindle starts, `M9` before it stops.
    pub coolant: bool,
    /// Travel of X, Y, Z in mm (GRBL's `$130`–`$132`): after homing, machine
    /// coordinates run from 0 down to −travel. Read only by `pfcam check`.
    pub travel: Option<[f64; 3]>,
    /// Machine position of the work origin (G54's offset as `$#` shows it,
    /// MPos − WPos), mm. With `travel`, `pfcam check` tests every move against the
    /// machine's limits; without it, only the program's size against the travel.
    pub work_offset: Option<[f64; 3]>,
    /// Longest estimated machining time of a program, hours: a job whose lower
    /// bound or whose program's estimate passes it stops with an error.
    pub max_hours: f64,
    /// Largest G-code file, MB (10⁶ bytes): a program that would be larger is
    /// not written.
    pub max_file_mb: f64,
}

impl Default for Machine {
    fn default() -> Self {
        Machine {
            rapid_rate: defaults::RAPID_RATE,
            spindle_dwell: defaults::SPINDLE_DWELL,
            travel: None,
            work_offset: None,
            coolant: defaults::COOLANT,
            max_hours: defaults::MAX_HOURS,
            max_file_mb: defaults::MAX_FILE_MB,
        }
    }
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
pub mod defaults {
    /// `shape.font`: the built-in letters of the paper.
    pub const FONT: &str = "paper";
    /// `shape.height` for text, mm of cap height.
    pub const TEXT_HEIGHT: f64 = 50.0;
    /// `shape.part.size`: cap height of a text part, design units.
    pub const PART_TEXT_SIZE: f64 = 100.0;
    /// `tool.feed`, mm/min: a moderate feed for a 3 mm cutter in wood or plastic.
    pub const FEED: f64 = 800.0;
    /// `tool.plunge_feed`, mm/min: a quarter of the feed.
    pub const PLUNGE_FEED: f64 = 200.0;
    /// `tool.spindle`, rev/min.
    pub const SPINDLE: f64 = 10000.0;
    /// `tool.stepdown`, mm per pass.
    pub const STEPDOWN: f64 = 1.0;
    /// `stock.top`, mm.
    pub const STOCK_TOP: f64 = 0.0;
    /// `stock.safe_z` is this far above `stock.top`, mm.
    pub const SAFE_CLEARANCE: f64 = 5.0;
    /// `operation.tolerance`, mm.
    pub const TOLERANCE: f64 = 0.01;
    /// `shape.join_tolerance`, mm: DXF pieces whose ends are closer join.
    pub const JOIN_TOLERANCE: f64 = 0.01;
    /// `machine.rapid_rate`, mm/min (GRBL's own default `$110` is 500; most
    /// hobby machines are set faster).
    pub const RAPID_RATE: f64 = 1000.0;
    /// `machine.spindle_dwell`, seconds.
    pub const SPINDLE_DWELL: f64 = 2.0;
    /// `tool.stepover` as a fraction of the diameter.
    pub const STEPOVER_FRACTION: f64 = 0.4;
    /// `tool.ramp_angle`, degrees: gentle enough for a flat end mill in wood, plastic or aluminium.
    pub const RAMP_ANGLE: f64 = 3.0;
    /// `stock.margin`, mm.
    pub const MARGIN: f64 = 5.0;
    /// `operation.max_scallop`, mm.
    pub const MAX_SCALLOP: f64 = 0.5;
    /// `profile.kind`.
    pub const PROFILE_KIND: &str = "linear";
    /// `profile.s_bottom` for a linear profile.
    pub const S_BOTTOM: f64 = 0.8;
    /// `profile.s1`, `profile.s2`, `profile.steepness` for a sigmoid (the paper's Section 7 values).
    pub const SIGMOID: (f64, f64, f64) = (0.99, 0.75, 8.0);
    /// `profile.s1`, `s2`, `exponent` for a power wall: the paper's n = 500
    /// (Section 3.2), from Γ(0.999) down to Γ(0.99).
    pub const POWER: (f64, f64, f64) = (0.999, 0.99, 500.0);
    /// `machine.coolant`: off (most hobby routers have none).
    pub const COOLANT: bool = false;
    /// `machine.max_hours`: a working day; the longest shipped program
    /// (mfs-sign) is estimated at under 6 h.
    pub const MAX_HOURS: f64 = 8.0;
    /// `machine.max_file_mb`: the largest shipped program (mfs-mould.rough.nc)
    /// is 1.9 MB.
    pub const MAX_FILE_MB: f64 = 100.0;
    /// `output.arcs`: on (GRBL 1.1 cuts arcs well and the file is smaller).
    pub const ARCS: bool = true;
    /// `output.max_arc_radius`, mm: a 1000 mm arc over a 100 mm chord bulges
    /// 1.25 mm, so anything flatter is a line to the eye and to the machine.
    pub const MAX_ARC_RADIUS: f64 = 1000.0;
}

/// The accepted values of `operation.kind`.
pub const OPERATION_KINDS: &[&str] = &["profile", "boss", "cavity"];
/// The accepted values of `profile.kind`.
pub const PROFILE_KINDS: &[&str] = &["linear", "sigmoid", "power", "spline", "table"];
/// The accepted values of `operation.side`.
pub const SIDES: &[&str] = &["outside"];
/// The accepted values of `operation.direction`.
pub const DIRECTIONS: &[&str] = &["climb", "conventional"];

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
    #[error("{origin}:{line}:{column}: {}{message}", key.as_ref().map(|k| format!("{k}: ")).unwrap_or_default())]
    Parse {
        /// the file, or `job` for text not read from a file
        origin: String,
        /// 1-based line
        line: usize,
        /// 1-based column (characters)
        column: usize,
        /// the key at that place, when one can be named (`tool.diamter`)
        key: Option<String>,
        /// what the TOML reader says
        message: String,
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

/// The job file as written: every key optional, unknown keys rejected.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawJob {
    /// `[job]`
    pub job: Option<RawJobTable>,
    /// `[shape]`
    pub shape: Option<RawShape>,
    /// `[tool]`
    pub tool: Option<RawTool>,
    /// `[stock]`
    pub stock: Option<RawStock>,
    /// `[operation]`
    pub operation: Option<RawOperation>,
    /// `[field]`
    pub field: Option<RawField>,
    /// `[machine]`
    pub machine: Option<RawMachine>,
    /// `[output]`
    pub output: Option<RawOutput>,
    /// `[profile]`
    pub profile: Option<RawProfile>,
    /// `[finish]`
    pub finish: Option<finish::RawFinish>,
}

/// `[profile]`: the depth profile φ(s) of a boss or cavity.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawProfile {
    /// `kind`: linear, sigmoid, power, spline or table
    pub kind: Option<String>,
    /// `s_bottom` (linear)
    pub s_bottom: Option<f64>,
    /// `s1` (sigmoid: top edge)
    pub s1: Option<f64>,
    /// `s2` (sigmoid: foot of the wall)
    pub s2: Option<f64>,
    /// `steepness` (sigmoid)
    pub steepness: Option<f64>,
    /// `exponent` (power)
    pub exponent: Option<f64>,
    /// `points`: [[s, z], ...] (spline, table), z in mm relative to stock.top
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub points: Option<Vec<[f64; 2]>>,
}

/// `[job]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawJobTable {
    /// `name`
    pub name: Option<String>,
}

/// `[shape]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawShape {
    /// `text`
    pub text: Option<String>,
    /// `lines`: several lines of text, top to bottom
    pub lines: Option<Vec<String>>,
    /// `align`: left, centre (center) or right
    pub align: Option<String>,
    /// `line_spacing`, em
    pub line_spacing: Option<f64>,
    /// `svg_path`
    pub svg_path: Option<String>,
    /// `svg_file`: an SVG document, relative to the job file's directory
    pub svg_file: Option<String>,
    /// `id`: the one element of `svg_file` to use
    pub id: Option<String>,
    /// `scale`: the `svg_file` drawing's size times this
    pub scale: Option<f64>,
    /// `width`, mm: the `svg_file` drawing's width
    pub width: Option<f64>,
    /// `dxf_file`: a DXF drawing, relative to the job file's directory
    pub dxf_file: Option<String>,
    /// `layer`: only this layer of `dxf_file`
    pub layer: Option<String>,
    /// `join_tolerance`, mm: `dxf_file` pieces whose ends are closer join
    pub join_tolerance: Option<f64>,
    /// `font`
    pub font: Option<String>,
    /// `height`, mm
    pub height: Option<f64>,
    /// `letter_spacing`, mm
    pub letter_spacing: Option<f64>,
    /// `origin`, mm
    #[serde(default, deserialize_with = "exact::opt")]
    pub origin: Option<[f64; 2]>,
    /// `result`: the name of the part that is the shape (with `[[shape.part]]`)
    pub result: Option<String>,
    /// `[[shape.part]]`: the parts of a composition
    pub part: Option<Vec<RawPart>>,
    /// `kind`: a surface source, `"harmonic-bezier"`
    pub kind: Option<String>,
    /// `degree` (harmonic patch): n, the degree along the rows
    pub degree: Option<i64>,
    /// `form` (harmonic patch): `"square"` or `"raised"`
    pub form: Option<String>,
    /// `size` (harmonic patch), mm: [X, Y]
    #[serde(default, deserialize_with = "exact::opt")]
    pub size: Option<[f64; 2]>,
    /// `row0` (harmonic patch), mm: heights of the edge y = 0
    pub row0: Option<Vec<f64>>,
    /// `row1` (harmonic patch), mm: heights of the edge y = Y
    pub row1: Option<Vec<f64>>,
    /// `points` (polyharmonic), mm: [[x, y, z], ...] on the surface
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub points: Option<Vec<[f64; 3]>>,
    /// `inside` (polyharmonic), mm: points inside the solid
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub inside: Option<Vec<[f64; 3]>>,
    /// `outside` (polyharmonic), mm: points outside the solid (separators)
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub outside: Option<Vec<[f64; 3]>>,
    /// `points_file` (polyharmonic): a CSV or XYZ file of the points
    pub points_file: Option<String>,
    /// `kernel` (polyharmonic): `"T2A"` or `"T2"`
    pub kernel: Option<String>,
    /// `a`: the T2A kernel's ball radius A, mm (polyharmonic), or the PDE's
    /// parameter (PDE tube)
    pub a: Option<f64>,
    /// `box` (polyharmonic), mm: [[x0, y0, z0], [x1, y1, z1]]
    #[serde(rename = "box", default, deserialize_with = "exact::opt_vec")]
    pub box_: Option<Vec<[f64; 3]>>,
    /// `elements` (polyharmonic): elements per box edge
    pub elements: Option<i64>,
    /// `base` (polyharmonic), mm: the height of the block's foot
    pub base: Option<f64>,
    /// `solid` (polyharmonic): `"relief"` or `"closed"`
    pub solid: Option<String>,
    /// `bottom_size` (PDE tube), mm: [X, Y] of the curve at u = 0
    #[serde(default, deserialize_with = "exact::opt")]
    pub bottom_size: Option<[f64; 2]>,
    /// `bottom_exponent` (PDE tube): the superellipse's p at u = 0
    pub bottom_exponent: Option<f64>,
    /// `top_size` (PDE tube), mm: [X, Y] of the curve at u = 1
    #[serde(default, deserialize_with = "exact::opt")]
    pub top_size: Option<[f64; 2]>,
    /// `top_exponent` (PDE tube): the superellipse's p at u = 1
    pub top_exponent: Option<f64>,
    /// `flare` (PDE tube), mm per unit u: [bottom, top]
    #[serde(default, deserialize_with = "exact::opt")]
    pub flare: Option<[f64; 2]>,
    /// `rise` (PDE tube), mm per unit u: [bottom, top]
    #[serde(default, deserialize_with = "exact::opt")]
    pub rise: Option<[f64; 2]>,
    /// `modes` (PDE tube): N
    pub modes: Option<i64>,
    /// `samples` (PDE tube): K
    pub samples: Option<i64>,
    /// `[[shape.trim]]` (PDE tube): the trims cut out of the tube
    pub trim: Option<Vec<RawTrim>>,
}

/// `[[shape.trim]]`: one trim of a PDE tube, a rectangle in (angle, z).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawTrim {
    /// `angles`, degrees: [from, to] counter-clockwise from +x
    #[serde(default, deserialize_with = "exact::opt")]
    pub angles: Option<[f64; 2]>,
    /// `z`, mm (machine z): [bottom, top]
    #[serde(default, deserialize_with = "exact::opt")]
    pub z: Option<[f64; 2]>,
}

/// `[[shape.part]]`: one part of a composition, in design units.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawPart {
    /// `name`
    pub name: Option<String>,
    /// `polygon`: [[x, y], ...]
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub polygon: Option<Vec<[f64; 2]>>,
    /// `svg`: path data
    pub svg: Option<String>,
    /// `text`
    pub text: Option<String>,
    /// `font` (with `text`)
    pub font: Option<String>,
    /// `size`: cap height, design units (with `text`)
    pub size: Option<f64>,
    /// `of`: names of earlier parts
    pub of: Option<Names>,
    /// `op`: union, intersect, subtract or invert
    pub op: Option<String>,
    /// `level`: the part is Γ(level) of its source's field
    pub level: Option<f64>,
    /// `singularities`: `"auto"` or a count
    pub singularities: Option<AutoOr>,
}

/// One name or a list of names (`of = "m1"` is `of = ["m1"]`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Names(pub Vec<String>);

impl<'de> Deserialize<'de> for Names {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Names;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a part name or a list of part names")
            }
            fn visit_str<E>(self, v: &str) -> Result<Names, E> {
                Ok(Names(vec![v.to_string()]))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut a: A) -> Result<Names, A::Error> {
                let mut v = Vec::new();
                while let Some(n) = a.next_element::<String>()? {
                    v.push(n);
                }
                Ok(Names(v))
            }
        }
        d.deserialize_any(V)
    }
}

/// `[tool]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawTool {
    /// `diameter`, mm
    pub diameter: Option<f64>,
    /// `feed`, mm/min
    pub feed: Option<f64>,
    /// `plunge_feed`, mm/min
    pub plunge_feed: Option<f64>,
    /// `spindle`, rev/min
    pub spindle: Option<f64>,
    /// `stepdown`, mm
    pub stepdown: Option<f64>,
    /// `stepover`, mm
    pub stepover: Option<f64>,
    /// `ramp_angle`, degrees
    pub ramp_angle: Option<f64>,
}

/// `[stock]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawStock {
    /// `top`, mm
    pub top: Option<f64>,
    /// `safe_z`, mm
    pub safe_z: Option<f64>,
    /// `retract_z`, mm
    pub retract_z: Option<f64>,
    /// `margin`, mm
    pub margin: Option<f64>,
}

/// `[operation]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawOperation {
    /// `kind`
    pub kind: Option<String>,
    /// `side`
    pub side: Option<String>,
    /// `depth`, mm
    pub depth: Option<f64>,
    /// `tolerance`, mm
    pub tolerance: Option<f64>,
    /// `direction`
    pub direction: Option<String>,
    /// `max_scallop`, mm
    pub max_scallop: Option<f64>,
    /// `stock_to_leave`, mm
    pub stock_to_leave: Option<f64>,
}

/// `[field]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawField {
    /// `singularities`: `"auto"` or a count
    pub singularities: Option<AutoOr>,
    /// `pseudo_boundary`: `"auto"` or a distance in mm
    pub pseudo_boundary: Option<AutoOr>,
}

/// `[machine]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawMachine {
    /// `rapid_rate`, mm/min
    pub rapid_rate: Option<f64>,
    /// `spindle_dwell`, s
    pub spindle_dwell: Option<f64>,
    /// `coolant`
    pub coolant: Option<bool>,
    /// `travel`, mm: [x, y, z]
    #[serde(default, deserialize_with = "exact::opt")]
    pub travel: Option<[f64; 3]>,
    /// `work_offset`, mm: [x, y, z]
    #[serde(default, deserialize_with = "exact::opt")]
    pub work_offset: Option<[f64; 3]>,
    /// `max_hours`, h
    pub max_hours: Option<f64>,
    /// `max_file_mb`, MB
    pub max_file_mb: Option<f64>,
}

/// `[output]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawOutput {
    /// `arcs`
    pub arcs: Option<bool>,
    /// `max_arc_radius`, mm
    pub max_arc_radius: Option<f64>,
}

impl RawMachine {
    /// Checks `[machine]` and applies its defaults.
    pub fn resolve(self) -> Result<Machine, JobError> {
        let m = self;
        let travel = match m.travel {
            None => None,
            Some(t) => {
                for (k, axis) in t.iter().zip(["x", "y", "z"]) {
                    limits::TRAVEL.check(&format!("machine.travel ({axis})"), *k)?;
                }
                Some(t)
            }
        };
        let work_offset = match m.work_offset {
            None => None,
            Some(o) => {
                if travel.is_none() {
                    return Err(invalid(
                        "machine.work_offset",
                        "needs machine.travel (the offset places the work origin inside it)",
                    ));
                }
                for v in o {
                    limits::WORK_OFFSET.check("machine.work_offset", v)?;
                }
                Some(o)
            }
        };
        Ok(Machine {
            rapid_rate: limits::RAPID_RATE.check(
                "machine.rapid_rate",
                m.rapid_rate.unwrap_or(defaults::RAPID_RATE),
            )?,
            spindle_dwell: limits::SPINDLE_DWELL.check(
                "machine.spindle_dwell",
                m.spindle_dwell.unwrap_or(defaults::SPINDLE_DWELL),
            )?,
            coolant: m.coolant.unwrap_or(defaults::COOLANT),
            travel,
            work_offset,
            max_hours: limits::MAX_HOURS.check(
                "machine.max_hours",
                m.max_hours.unwrap_or(defaults::MAX_HOURS),
            )?,
            max_file_mb: limits::MAX_FILE_MB.check(
                "machine.max_file_mb",
                m.max_file_mb.unwrap_or(defaults::MAX_FILE_MB),
            )?,
        })
    }
}

/// A file with only a `[machine]` table (see [`load_machine`]).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMachineFile {
    machine: Option<RawMachine>,
}

/// Where [`load_machine`] found the machine settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MachineSource {
    /// A whole job file: its `[machine]` table.
    Job,
    /// A machine file: a TOML file with only a `[machine]` table.
    MachineFile,
}

/// Reads `[machine]` from either a job file or a machine file (a TOML file whose
/// only table is `[machine]`), with the same keys and checks as in a job.
pub fn load_machine(path: &Path) -> Result<(Machine, MachineSource), JobError> {
    let text = read_bounded(path)?;
    let is_machine_file = match text.parse::<toml::Table>() {
        Ok(t) => t.keys().all(|k| k == "machine"),
        // Let the job reader report where the TOML is wrong.
        Err(_) => false,
    };
    if !is_machine_file {
        return Ok((load_job(path)?.machine, MachineSource::Job));
    }
    let raw: RawMachineFile =
        toml::from_str(&text).map_err(|e| parse_error(&text, &e).in_file(path))?;
    Ok((
        raw.machine.unwrap_or_default().resolve()?,
        MachineSource::MachineFile,
    ))
}

/// A number, or a word (only `"auto"` is accepted; any other word is reported
/// with its key by [`RawJob::resolve`]).
#[derive(Debug, Clone, PartialEq)]
pub enum AutoOr {
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
    /// A word.
    Word(String),
}

impl<'de> Deserialize<'de> for AutoOr {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = AutoOr;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"auto\" or a number")
            }
            fn visit_i64<E>(self, v: i64) -> Result<AutoOr, E> {
                Ok(AutoOr::Int(v))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<AutoOr, E> {
                i64::try_from(v)
                    .map(AutoOr::Int)
                    .map_err(|_| E::custom(format!("{v} is too large")))
            }
            fn visit_f64<E>(self, v: f64) -> Result<AutoOr, E> {
                Ok(AutoOr::Float(v))
            }
            fn visit_str<E>(self, v: &str) -> Result<AutoOr, E> {
                Ok(AutoOr::Word(v.to_string()))
            }
        }
        d.deserialize_any(V)
    }
}

/// Read and resolve a job file. The job name defaults to the file stem, and a font
/// path is resolved relative to the file's directory.
pub fn load_job(path: &Path) -> Result<Job, JobError> {
    let text = read_bounded(path)?;
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "job".into());
    let base = path.parent().unwrap_or_else(|| Path::new(""));
    parse_job(&text, &stem, base).map_err(|e| e.in_file(path))
}

/// The tables of a job file.
const SECTIONS: &[&str] = &[
    "job",
    "shape",
    "tool",
    "stock",
    "operation",
    "field",
    "machine",
    "output",
    "profile",
];

/// Every section is a table: `[[tool]]` (an array of tables) or `tool = 3`
/// would otherwise reach serde, which reads a struct from an array and says
/// `tool[1]: invalid type: map, expected f64`.
fn check_sections(table: &toml::Table) -> Result<(), JobError> {
    for (key, value) in table.iter().filter(|(k, _)| SECTIONS.contains(&k.as_str())) {
        let what = match value {
            toml::Value::Table(_) => continue,
            toml::Value::Array(a) if a.iter().all(|v| v.is_table()) => {
                format!("an array of tables [[{key}]]")
            }
            v => format!("a {}", v.type_str()),
        };
        return Err(invalid(
            key,
            format!("must be a table, written [{key}], not {what}"),
        ));
    }
    Ok(())
}

/// The text of a job file, refused past `limits::MAX_JOB_BYTES` without reading
/// further (a device such as `/dev/zero`, a log given by mistake) and when it is
/// not a regular file or not UTF-8.
fn read_bounded(path: &Path) -> Result<String, JobError> {
    use std::io::Read;
    let read_error = |error| JobError::Read {
        path: path.to_path_buf(),
        error,
    };
    if path.is_dir() {
        return Err(JobError::NotAJob {
            path: path.to_path_buf(),
            why: "it is a directory".into(),
        });
    }
    let file = std::fs::File::open(path).map_err(read_error)?;
    let mut bytes = Vec::new();
    file.take(limits::MAX_JOB_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(read_error)?;
    if bytes.len() as u64 > limits::MAX_JOB_BYTES {
        return Err(JobError::NotAJob {
            path: path.to_path_buf(),
            why: format!(
                "it is larger than {} KiB; a job file is a few kilobytes of TOML",
                limits::MAX_JOB_BYTES / 1024
            ),
        });
    }
    String::from_utf8(bytes).map_err(|e| JobError::NotAJob {
        path: path.to_path_buf(),
        why: format!(
            "it is not UTF-8 text (byte {} is not valid)",
            e.utf8_error().valid_up_to() + 1
        ),
    })
}

/// Parse and resolve job text. `name_hint` is the name used when `[job] name` is
/// absent; `base_dir` is where relative font paths are looked up; font names
/// are looked up among the system's fonts.
pub fn parse_job(text: &str, name_hint: &str, base_dir: &Path) -> Result<Job, JobError> {
    let src = Sources {
        base_dir,
        fonts: Fonts::System,
    };
    parse_job_with(text, name_hint, &src)
}

/// As [`parse_job`], with font names looked up in `src.fonts`.
pub fn parse_job_with(text: &str, name_hint: &str, src: &Sources<'_>) -> Result<Job, JobError> {
    let table: toml::Table = text.parse().map_err(|e| parse_error(text, &e))?;
    check_sections(&table)?;
    let raw: RawJob = toml::from_str(text).map_err(|e| parse_error(text, &e))?;
    raw.resolve_with(name_hint, src)
}

fn parse_error(text: &str, e: &toml::de::Error) -> JobError {
    let pos = e.span().map_or(0, |s| s.start).min(text.len());
    let (line, column) = line_col(text, pos);
    let key = e.span().and_then(|_| key_at(text, pos));
    let mut message = e.message().trim().to_string();
    // TOML puts every key after `[[shape.part]]` into that part.
    let misplaced = key.as_deref().is_some_and(|k| {
        k.starts_with("shape.part[")
            && ["result", "height", "origin"]
                .iter()
                .any(|f| k.ends_with(&format!("].{f}")))
    });
    if misplaced && message.starts_with("unknown field") {
        message.push_str(
            " (shape.result, shape.height and shape.origin belong in [shape], above the first [[shape.part]])",
        );
    }
    JobError::Parse {
        origin: "job".into(),
        line,
        column,
        key: key.map(|k| echo::clip(&k).into_owned()),
        message: echo::clip_message(&message),
    }
}

/// 1-based line and column (in characters) of byte offset `pos`.
fn line_col(text: &str, pos: usize) -> (usize, usize) {
    let before = text.get(..pos).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}

/// The dotted key at byte offset `pos`: the table header when `pos` is in one,
/// otherwise `<last table>.<key before '='>` on that line. A table of an array
/// of tables gets its number, counted from 1: `shape.part[2].polygon`.
fn key_at(text: &str, pos: usize) -> Option<String> {
    let before = text.get(..pos)?;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[pos..].find('\n').map_or(text.len(), |i| pos + i);
    let line = &text[line_start..line_end];
    // `[name]` or `[[name]]`, nothing after it but a comment; not `[0, 1],` in a
    // multi-line array.
    let header = |l: &str| -> Option<(String, bool)> {
        let t = l.trim();
        let array = t.starts_with("[[");
        let open = if array { 2 } else { 1 };
        let t = t.strip_prefix(&"[["[..open])?;
        let end = t.find(']')?;
        let rest = t[end..].strip_prefix(&"]]"[..open])?.trim_start();
        let name = t[..end].trim();
        let ok = !name.is_empty()
            && (rest.is_empty() || rest.starts_with('#'))
            && name
                .chars()
                .all(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | '.' | '"' | '\'' | ' '));
        ok.then(|| (name.to_string(), array))
    };
    // The header's name, numbered if it is an array's: `lines` end with it.
    let named = |lines: &[&str], h: (String, bool)| -> String {
        if h.1 {
            let n = lines
                .iter()
                .filter(|l| header(l).as_ref() == Some(&h))
                .count();
            format!("{}[{n}]", h.0)
        } else {
            h.0
        }
    };
    let lines: Vec<&str> = text[..line_start].lines().collect();
    if let Some(h) = header(line) {
        let mut upto = lines.clone();
        upto.push(line);
        return Some(named(&upto, h));
    }
    // The line with the key: this one, or, inside a multi-line array, the one
    // that opened it (its `[`s not yet closed at `pos`).
    let mut key_line = lines.len();
    let key_text = if line.contains('=') {
        line
    } else {
        let i = lines
            .iter()
            .rposition(|l| l.contains('=') || header(l).is_some())?;
        let open = |s: &str| s.matches('[').count() as i64 - s.matches(']').count() as i64;
        let from = &lines[i][lines[i].find('=')? + 1..];
        let depth = open(from)
            + lines[i + 1..].iter().map(|l| open(l)).sum::<i64>()
            + open(&text[line_start..pos]);
        if depth <= 0 {
            return None;
        }
        key_line = i;
        lines[i]
    };
    let eq = key_text.find('=')?;
    let key = key_text[..eq].trim().trim_matches('"');
    if key.is_empty() {
        return None;
    }
    let table = lines[..key_line]
        .iter()
        .rposition(|l| header(l).is_some())
        .and_then(|i| header(lines[i]).map(|h| named(&lines[..=i], h)));
    Some(match table {
        Some(t) => format!("{t}.{key}"),
        None => key.to_string(),
    })
}

/// Of `keys`, each with whether the job gives it, at most one: the error
/// names the first two given (keyed on the first) and says `rule`; else the
/// one given, if any.
fn at_most_one<'a>(keys: &[(&'a str, bool)], rule: &str) -> Result<Option<&'a str>, JobError> {
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
fn show(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{x}")
    } else {
        format!("{x:?}")
    }
}

fn finite(key: &str, x: f64) -> Result<f64, JobError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(invalid(
            key,
            format!("must be a finite number, got {}", show(x)),
        ))
    }
}

fn one_of(key: &str, value: &str, accepted: &[&str]) -> Result<(), JobError> {
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
    /// Apply defaults and check every value; see `docs/job-format.md`. Font
    /// names are looked up among the system's fonts.
    pub fn resolve(self, name_hint: &str, base_dir: &Path) -> Result<Job, JobError> {
        let src = Sources {
            base_dir,
            fonts: Fonts::System,
        };
        self.resolve_with(name_hint, &src)
    }

    /// As [`resolve`](RawJob::resolve), with files and font names found
    /// through `src`. The tables in the order their checks run: the tool
    /// first (the letter spacing defaults to its diameter), then the shape,
    /// the stock, the operation with `[profile]` and `[finish]`, the field,
    /// the machine and the output.
    pub fn resolve_with(self, name_hint: &str, src: &Sources<'_>) -> Result<Job, JobError> {
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

fn auto_word(key: &str, word: &str, what: &str) -> Result<(), JobError> {
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
    use super::*;
    use crate::geometry::{BoolOp, Composition, FontSource, Part, PartSource, Vec2};

    const GOOD: &str = r#"
[job]
name = "letter-a"
[shape]
text = "A"
height = 50.0
[tool]
diameter = 3.175
[operation]
depth = 3.0
"#;

    fn parse(text: &str) -> Result<Job, JobError> {
        parse_job(text, "hint", Path::new("."))
    }

    /// `GOOD` with `line` added under `[table]` (the table is created if absent).
    fn with(table: &str, line: &str) -> String {
        let header = format!("[{table}]\n");
        if GOOD.contains(&header) {
            GOOD.replace(&header, &format!("{header}{line}\n"))
        } else {
            format!("{GOOD}{header}{line}\n")
        }
    }

    fn err_key(text: &str) -> (String, String) {
        match parse(text) {
            Ok(j) => panic!("expected an error, got {j:?}"),
            Err(e) => (e.key().unwrap_or("").to_string(), e.to_string()),
        }
    }

    /// A parse error in a file read from disk names the file, whether the
    /// file is a job or a machine file ([`JobError::in_file`]).
    #[test]
    fn a_parse_error_in_a_file_names_the_file() {
        let dir = std::env::temp_dir().join(format!("pfcam-job-origin-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let machine = dir.join("machine.toml");
        std::fs::write(
            &machine,
            "[machine]
rapid_rat = 3000
",
        )
        .unwrap();
        let job = dir.join("job.toml");
        std::fs::write(&job, with("tool", "diamter = 3")).unwrap();
        let m = load_machine(&machine).unwrap_err();
        let j = load_job(&job).unwrap_err();
        std::fs::remove_dir_all(&dir).unwrap();
        for (e, path, key) in [(m, machine, "machine.rapid_rat"), (j, job, "tool.diamter")] {
            let JobError::Parse { origin, .. } = &e else {
                panic!("{e:?}")
            };
            assert_eq!(origin, &path.display().to_string());
            assert_eq!(e.key(), Some(key), "{e}");
        }
        // Text not read from a file keeps `job` as its origin.
        let text = parse(&with("tool", "diamter = 3")).unwrap_err();
        assert!(text.to_string().starts_with("job:"), "{text}");
    }

    #[test]
    fn good_job_gets_defaults() {
        let j = parse(GOOD).unwrap();
        assert_eq!(j.name, "letter-a");
        assert_eq!(j.tool.feed, defaults::FEED);
        assert_eq!(j.tool.plunge_feed, defaults::PLUNGE_FEED);
        assert_eq!(j.stock.safe_z, 5.0);
        assert_eq!(j.operation.tolerance, 0.01);
        assert_eq!(j.operation.direction, Direction::Climb);
        assert_eq!(j.field, FieldSpec::default());
        assert_eq!(j.machine, Machine::default());
        assert_eq!(j.output, Output::default());
        assert!(j.output.arcs && !j.machine.coolant);
        assert_eq!(j.output.max_arc_radius, 1000.0);
        match j.shape {
            ShapeSource::Text {
                font,
                letter_spacing,
                height,
                ..
            } => {
                assert_eq!(font, FontSource::Paper);
                assert_eq!(letter_spacing, 3.175);
                assert_eq!(height, 50.0);
            }
            other => panic!("{other:?}"),
        }
    }

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
    fn syntax_error_has_line_and_column() {
        let e = parse("[shape]\ntext = \"A\"\nheight = = 5\n").unwrap_err();
        match &e {
            JobError::Parse { line, column, .. } => {
                assert_eq!(*line, 3);
                assert!(*column >= 8, "column {column}");
            }
            other => panic!("{other:?}"),
        }
        assert!(e.to_string().starts_with("job:3:"), "{e}");
    }

    #[test]
    fn unknown_key_is_named() {
        let (k, msg) = err_key(&with("tool", "diamter = 3.0"));
        assert_eq!(k, "tool.diamter");
        assert!(
            msg.contains("job:8:1: tool.diamter: unknown field"),
            "{msg}"
        );
        let (k, _) = err_key(&with("spindle", "rpm = 3"));
        assert_eq!(k, "spindle");
    }

    #[test]
    fn wrong_type_is_named() {
        let (k, msg) = err_key(&GOOD.replace("height = 50.0", "height = \"tall\""));
        assert_eq!(k, "shape.height");
        assert!(msg.contains("job:6:"), "{msg}");
    }

    #[test]
    fn negative_diameter() {
        let (k, msg) = err_key(&GOOD.replace("diameter = 3.175", "diameter = -3"));
        assert_eq!(k, "tool.diameter");
        assert_eq!(msg, "tool.diameter must be a positive number of mm, got -3");
    }

    #[test]
    fn missing_required_keys() {
        assert_eq!(
            err_key(&GOOD.replace("diameter = 3.175", "")).0,
            "tool.diameter"
        );
        assert_eq!(
            err_key(&GOOD.replace("depth = 3.0", "")).0,
            "operation.depth"
        );
        assert_eq!(err_key(&GOOD.replace("text = \"A\"", "")).0, "shape.text");
    }

    #[test]
    fn depth_must_be_positive() {
        for d in ["0.0", "-1", "nan", "inf"] {
            let (k, msg) = err_key(&GOOD.replace("depth = 3.0", &format!("depth = {d}")));
            assert_eq!(k, "operation.depth");
            assert!(msg.contains("must be > 0"), "{msg}");
        }
    }

    #[test]
    fn feeds_stepdown_spindle() {
        assert_eq!(err_key(&with("tool", "feed = 0")).0, "tool.feed");
        assert_eq!(
            err_key(&with("tool", "plunge_feed = -5")).0,
            "tool.plunge_feed"
        );
        assert_eq!(err_key(&with("tool", "stepdown = 0")).0, "tool.stepdown");
        assert_eq!(err_key(&with("tool", "spindle = -1")).0, "tool.spindle");
        assert_eq!(
            parse(&with("tool", "spindle = 0")).unwrap().tool.spindle,
            0.0
        );
    }

    #[test]
    fn tolerance_positive_and_below_radius() {
        assert_eq!(
            err_key(&with("operation", "tolerance = 0")).0,
            "operation.tolerance"
        );
        let (k, msg) = err_key(&with("operation", "tolerance = 2"));
        assert_eq!(k, "operation.tolerance");
        assert!(msg.contains("tool radius"), "{msg}");
    }

    #[test]
    fn safe_z_above_top() {
        let (k, msg) = err_key(&with("stock", "top = 2.0\nsafe_z = 1.0"));
        assert_eq!(k, "stock.safe_z");
        assert!(msg.contains("above stock.top (2)"), "{msg}");
        let j = parse(&with("stock", "top = 2.0")).unwrap();
        assert_eq!(j.stock.safe_z, 7.0);
    }

    #[test]
    fn retract_z_between_top_and_safe_z() {
        for bad in ["retract_z = 6.0", "retract_z = 0.0", "retract_z = -1.0"] {
            let (k, msg) = err_key(&with("stock", &format!("safe_z = 5.0\n{bad}")));
            assert_eq!(k, "stock.retract_z", "{bad}");
            assert!(msg.contains("at most stock.safe_z (5)"), "{msg}");
        }
        let j = parse(&with("stock", "safe_z = 5.0\nretract_z = 1.0")).unwrap();
        assert_eq!((j.stock.safe_z, j.stock.retract_z), (5.0, 1.0));
        let j = parse(&with("stock", "safe_z = 4.0")).unwrap();
        assert_eq!(j.stock.retract_z, 4.0);
    }

    #[test]
    fn exactly_one_shape_source() {
        let (k, msg) = err_key(&with("shape", "svg_path = \"M0 0 L1 0 L1 1 Z\""));
        assert_eq!(k, "shape.text");
        assert!(msg.contains("exactly one"), "{msg}");
        let svg = GOOD.replace("text = \"A\"", "svg_path = \"M0 0 L10 0 L10 10 Z\"");
        assert_eq!(
            err_key(&svg.replace("height = 50.0", "font = \"paper\"")).0,
            "shape.font"
        );
        let j = parse(&svg.replace("height = 50.0", "")).unwrap();
        assert!(matches!(j.shape, ShapeSource::SvgPath { height: None, .. }));
    }

    #[test]
    fn glyph_missing_from_paper_font() {
        let (k, msg) = err_key(&GOOD.replace("text = \"A\"", "text = \"AZ\""));
        assert_eq!(k, "shape.text");
        assert!(msg.contains("no glyph") && msg.contains("'Z'"), "{msg}");
    }

    #[test]
    fn missing_font_file_is_resolved_against_the_job_dir() {
        let text = with("shape", "font = \"fonts/nope.ttf\"");
        let e = parse_job(&text, "x", Path::new("/some/dir")).unwrap_err();
        assert_eq!(e.key(), Some("shape.font"));
        assert_eq!(
            e.to_string(),
            "shape.font: no such file: /some/dir/fonts/nope.ttf"
        );
    }

    #[test]
    fn enums_list_accepted_values() {
        let (k, msg) = err_key(&with("operation", "kind = \"pocket\""));
        assert_eq!(k, "operation.kind");
        assert!(
            msg.contains("`pocket`") && msg.contains("`profile`"),
            "{msg}"
        );
        assert_eq!(
            err_key(&with("operation", "side = \"inside\"")).0,
            "operation.side"
        );
        assert_eq!(
            err_key(&with("operation", "direction = \"up\"")).0,
            "operation.direction"
        );
        let j = parse(&with("operation", "direction = \"conventional\"")).unwrap();
        assert_eq!(j.operation.direction, Direction::Conventional);
    }

    #[test]
    fn field_auto_or_number() {
        let j = parse(&with("field", "singularities = 400\npseudo_boundary = 5")).unwrap();
        assert_eq!(j.field.singularities, Some(400));
        assert_eq!(j.field.pseudo_boundary, Some(5.0));
        let j = parse(&with(
            "field",
            "singularities = \"auto\"\npseudo_boundary = \"auto\"",
        ))
        .unwrap();
        assert_eq!(j.field, FieldSpec::default());
        assert_eq!(
            err_key(&with("field", "singularities = 0")).0,
            "field.singularities"
        );
        assert_eq!(
            err_key(&with("field", "singularities = \"many\"")).0,
            "field.singularities"
        );
        assert_eq!(
            err_key(&with("field", "pseudo_boundary = -2.0")).0,
            "field.pseudo_boundary"
        );
        let (k, msg) = err_key(&with("field", "singularities = 12.5"));
        assert_eq!(k, "field.singularities");
        assert!(msg.contains("whole number"), "{msg}");
        let (k, msg) = err_key(&with("field", "pseudo_boundary = true"));
        assert_eq!(k, "field.pseudo_boundary");
        assert!(msg.contains("\"auto\" or a number"), "{msg}");
    }

    #[test]
    fn machine_settings() {
        let j = parse(&with("machine", "rapid_rate = 3000\nspindle_dwell = 0")).unwrap();
        assert_eq!(j.machine.rapid_rate, 3000.0);
        assert_eq!(j.machine.spindle_dwell, 0.0);
        assert_eq!(
            err_key(&with("machine", "rapid_rate = 0")).0,
            "machine.rapid_rate"
        );
        assert_eq!(
            err_key(&with("machine", "spindle_dwell = -1")).0,
            "machine.spindle_dwell"
        );
        let j = parse(&with(
            "machine",
            "travel = [300, 200, 60]\nwork_offset = [-250.0, -150, -40]",
        ))
        .unwrap();
        assert_eq!(j.machine.travel, Some([300.0, 200.0, 60.0]));
        assert_eq!(j.machine.work_offset, Some([-250.0, -150.0, -40.0]));
        assert_eq!(
            err_key(&with("machine", "travel = [300, 0, 60]")).0,
            "machine.travel (y)"
        );
        assert_eq!(
            err_key(&with("machine", "work_offset = [0, 0, 0]")).0,
            "machine.work_offset"
        );
        let j = parse(&with("machine", "max_hours = 0.5\nmax_file_mb = 2")).unwrap();
        assert_eq!((j.machine.max_hours, j.machine.max_file_mb), (0.5, 2.0));
        for (bad, key) in [
            ("max_hours = 0", "machine.max_hours"),
            ("max_hours = 1001", "machine.max_hours"),
            ("max_file_mb = -1", "machine.max_file_mb"),
            ("max_file_mb = 10001", "machine.max_file_mb"),
        ] {
            assert_eq!(err_key(&with("machine", bad)).0, key, "{bad}");
        }
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

    /// The paper's letter Q (Section 5): (m2 ∪ m5) − m3.
    pub(super) const Q: &str = r#"
[job]
name = "letter-q"
[tool]
diameter = 3.175
[operation]
depth = 3.0
[shape]
height = 60.0
origin = [10.0, 10.0]
result = "Q"

[[shape.part]]
name = "m1"
polygon = [[0, 0], [100, 0], [100, 300], [0, 300]]

[[shape.part]]
name = "m2"
of = "m1"
level = 0.85

[[shape.part]]
name = "m3"
of = ["m1"]
level = 0.95

[[shape.part]]
name = "m4"
polygon = [
    [20, 70], [50, 120], [100, 120], [280, 20],
    [300, 50], [270, 20], [100, 90], [50, 90],
]

[[shape.part]]
name = "m5"
of = "m4"
level = 0.97
singularities = 300

[[shape.part]]
name = "m6"
op = "union"
of = ["m2", "m5"]

[[shape.part]]
name = "Q"
op = "subtract"
of = ["m6", "m3"]
"#;

    fn pts(p: &[[f64; 2]]) -> PartSource {
        PartSource::Polygon(p.iter().map(|&[x, y]| Vec2::new(x, y)).collect())
    }

    fn part(name: &str, source: PartSource, level: Option<f64>) -> Part {
        Part {
            name: name.into(),
            source,
            level,
            singularities: None,
        }
    }

    fn names(n: &[&str]) -> Vec<String> {
        n.iter().map(|s| s.to_string()).collect()
    }

    /// `Q` with `from` replaced by `to` (which must occur).
    fn q_with(from: &str, to: &str) -> String {
        assert!(Q.contains(from), "{from}");
        Q.replacen(from, to, 1)
    }

    /// The error of `text`: its key and message; the message must contain every
    /// one of `needles`.
    fn q_err(text: &str, key: &str, needles: &[&str]) {
        let (k, msg) = err_key(text);
        assert_eq!(k, key, "{msg}");
        assert!(msg.starts_with(key), "{msg}");
        for n in needles {
            assert!(msg.contains(n), "{n:?} not in: {msg}");
        }
    }

    #[test]
    fn letter_q_parses_to_its_composition() {
        let j = parse(Q).unwrap();
        let mut m5 = part("m5", PartSource::Ref("m4".into()), Some(0.97));
        m5.singularities = Some(300);
        let expected = Composition {
            parts: vec![
                part(
                    "m1",
                    pts(&[[0.0, 0.0], [100.0, 0.0], [100.0, 300.0], [0.0, 300.0]]),
                    None,
                ),
                part("m2", PartSource::Ref("m1".into()), Some(0.85)),
                part("m3", PartSource::Ref("m1".into()), Some(0.95)),
                part(
                    "m4",
                    pts(&[
                        [20.0, 70.0],
                        [50.0, 120.0],
                        [100.0, 120.0],
                        [280.0, 20.0],
                        [300.0, 50.0],
                        [270.0, 20.0],
                        [100.0, 90.0],
                        [50.0, 90.0],
                    ]),
                    None,
                ),
                m5,
                part(
                    "m6",
                    PartSource::Op {
                        op: BoolOp::Union,
                        of: names(&["m2", "m5"]),
                    },
                    None,
                ),
                part(
                    "Q",
                    PartSource::Op {
                        op: BoolOp::Subtract,
                        of: names(&["m6", "m3"]),
                    },
                    None,
                ),
            ],
            result: "Q".into(),
            height: Some(60.0),
            origin: Vec2::new(10.0, 10.0),
        };
        assert_eq!(j.shape, ShapeSource::Composite(expected));
    }

    #[test]
    fn composition_defaults() {
        // No result: the last part. No height: 1 design unit = 1 mm. Text parts.
        let text = GOOD.replace(
            "text = \"A\"\nheight = 50.0",
            "[[shape.part]]\nname = \"t\"\ntext = \"AH\"\n\n[[shape.part]]\nname = \"big\"\ntext = \"I\"\nsize = 30\nfont = \"paper\"\n\n[[shape.part]]\nname = \"out\"\nop = \"invert\"\nof = \"t\"\n\n[[shape.part]]\nname = \"cut\"\nop = \"intersect\"\nof = [\"big\", \"out\"]\nlevel = 0.5",
        );
        let j = parse(&text).unwrap();
        let ShapeSource::Composite(c) = j.shape else {
            panic!("{:?}", j.shape)
        };
        assert_eq!(c.result, "cut");
        assert_eq!(c.height, None);
        assert_eq!(c.origin, Vec2::ZERO);
        assert_eq!(
            c.parts[0].source,
            PartSource::Text {
                text: "AH".into(),
                font: FontSource::Paper,
                size: defaults::PART_TEXT_SIZE,
            }
        );
        assert!(matches!(c.parts[1].source, PartSource::Text { size, .. } if size == 30.0));
        assert_eq!(
            c.parts[2].source,
            PartSource::Op {
                op: BoolOp::Invert,
                of: names(&["t"]),
            }
        );
        assert_eq!(c.parts[3].level, Some(0.5));
        // svg parts, and singularities = "auto".
        let j = parse(&q_with(
            "polygon = [[0, 0], [100, 0], [100, 300], [0, 300]]",
            "svg = \"M0 0 H100 V300 H0 Z\"\nsingularities = \"auto\"",
        ))
        .unwrap();
        let ShapeSource::Composite(c) = j.shape else {
            panic!()
        };
        assert_eq!(
            c.parts[0].source,
            PartSource::Svg("M0 0 H100 V300 H0 Z".into())
        );
        assert_eq!(c.parts[0].singularities, None);
    }

    #[test]
    fn part_names_and_references() {
        q_err(
            &q_with("of = [\"m6\", \"m3\"]", "of = [\"m6\", \"m7\"]"),
            "shape.part[7].of",
            &[
                "unknown part \"m7\"",
                "defined before it: m1, m2, m3, m4, m5, m6",
            ],
        );
        q_err(
            &q_with("of = \"m1\"\nlevel = 0.85", "of = \"m3\"\nlevel = 0.85"),
            "shape.part[2].of",
            &["\"m3\", which is defined after it", "defined before it: m1"],
        );
        q_err(
            &q_with("of = \"m1\"\nlevel = 0.85", "of = \"m2\"\nlevel = 0.85"),
            "shape.part[2].of",
            &["the part itself, \"m2\""],
        );
        q_err(
            &q_with("name = \"m3\"", "name = \"m2\""),
            "shape.part[3].name",
            &["\"m2\" is already the name of shape.part[2]"],
        );
        q_err(
            &q_with("name = \"m4\"", "name = \" \""),
            "shape.part[4].name",
            &["must not be empty"],
        );
        q_err(
            &q_with("name = \"m4\"\n", ""),
            "shape.part[4].name",
            &["is required"],
        );
        q_err(
            &q_with("of = [\"m2\", \"m5\"]", "of = [\"m2\", \"m2\"]"),
            "shape.part[6].of",
            &["\"m2\" twice"],
        );
        q_err(
            &q_with("of = [\"m2\", \"m5\"]", "of = []"),
            "shape.part[6].of",
            &["at least one", "[]"],
        );
        q_err(
            &q_with("result = \"Q\"", "result = \"q\""),
            "shape.result",
            &["unknown part \"q\"", "m1, m2, m3, m4, m5, m6, Q"],
        );
    }

    #[test]
    fn part_ops_and_operand_counts() {
        q_err(
            &q_with("op = \"union\"", "op = \"merge\""),
            "shape.part[6].op",
            &[
                "`merge`",
                "`union`",
                "`intersect`",
                "`subtract`",
                "`invert`",
            ],
        );
        q_err(
            &q_with(
                "op = \"union\"\nof = [\"m2\", \"m5\"]",
                "op = \"union\"\nof = \"m2\"",
            ),
            "shape.part[6].of",
            &["at least 2 parts", "op = \"union\"", "got 1 (\"m2\")"],
        );
        q_err(
            &q_with(
                "op = \"subtract\"\nof = [\"m6\", \"m3\"]",
                "op = \"subtract\"\nof = [\"m6\"]",
            ),
            "shape.part[7].of",
            &[
                "at least 2 parts (the first minus the others)",
                "\"subtract\"",
            ],
        );
        q_err(
            &q_with("op = \"union\"", "op = \"intersect\"\nof = \"m2\"")
                .replace("of = \"m2\"\nof = [\"m2\", \"m5\"]", "of = \"m2\""),
            "shape.part[6].of",
            &["at least 2 parts", "\"intersect\""],
        );
        q_err(
            &q_with("op = \"union\"", "op = \"invert\""),
            "shape.part[6].of",
            &["exactly 1 part", "got 2 (\"m2\", \"m5\")"],
        );
        q_err(
            &q_with("op = \"union\"\n", ""),
            "shape.part[6].op",
            &["is required when shape.part[6].of names several parts"],
        );
        q_err(
            &q_with("of = \"m1\"\nlevel = 0.85", "of = \"m1\""),
            "shape.part[2].level",
            &["is required", "plain copy of \"m1\""],
        );
        q_err(
            &q_with("op = \"union\"\nof = [\"m2\", \"m5\"]", "op = \"union\""),
            "shape.part[6].op",
            &["needs shape.part[6].of"],
        );
    }

    #[test]
    fn part_sources_exclude_each_other() {
        q_err(
            &q_with(
                "name = \"m5\"\nof = \"m4\"",
                "name = \"m5\"\nof = \"m4\"\npolygon = [[0, 0], [1, 0], [0, 1]]",
            ),
            "shape.part[5].of",
            &["cannot be combined with shape.part[5].polygon"],
        );
        q_err(
            &q_with(
                "op = \"union\"\n",
                "op = \"union\"\nsvg = \"M0 0 L1 0 L0 1 Z\"\n",
            ),
            "shape.part[6].of",
            &["cannot be combined with shape.part[6].svg"],
        );
        q_err(
            &q_with("name = \"m1\"\n", "name = \"m1\"\ntext = \"I\"\n"),
            "shape.part[1].polygon",
            &["and shape.part[1].text are both given"],
        );
        q_err(
            &q_with(
                "name = \"m6\"\nop = \"union\"\nof = [\"m2\", \"m5\"]\n",
                "name = \"m6\"\n",
            ),
            "shape.part[6]",
            &["has no source", "polygon, svg or text", "of"],
        );
        q_err(
            &q_with("name = \"m1\"\n", "name = \"m1\"\nsize = 20\n"),
            "shape.part[1].size",
            &["only applies to a text part"],
        );
        q_err(
            &q_with("name = \"m1\"\n", "name = \"m1\"\nfont = \"paper\"\n"),
            "shape.part[1].font",
            &["only applies to a text part"],
        );
    }

    #[test]
    fn part_values_are_checked() {
        for (l, shown) in [
            ("1.2", "1.2"),
            ("0", "0"),
            ("1", "1"),
            ("-0.5", "-0.5"),
            ("nan", "NaN"),
            ("inf", "inf"),
        ] {
            q_err(
                &q_with("level = 0.85", &format!("level = {l}")),
                "shape.part[2].level",
                &["must be strictly between 0 and 1", &format!("got {shown}")],
            );
        }
        q_err(
            &q_with(
                "polygon = [[0, 0], [100, 0], [100, 300], [0, 300]]",
                "polygon = []",
            ),
            "shape.part[1].polygon",
            &["3 to 10000 points", "got 0"],
        );
        q_err(
            &q_with("[0, 300]]", "[nan, 300]]"),
            "shape.part[1].polygon",
            &["point 4 must be finite", "[NaN, 300]"],
        );
        q_err(
            &q_with(
                "polygon = [[0, 0], [100, 0], [100, 300], [0, 300]]",
                "polygon = [[0, 0], [100, 100], [50, 50], [200, 200]]",
            ),
            "shape.part[1].polygon",
            &["on one line"],
        );
        q_err(
            &q_with(
                "polygon = [[0, 0], [100, 0], [100, 300], [0, 300]]",
                "svg = \"  \"",
            ),
            "shape.part[1].svg",
            &["must not be empty"],
        );
        q_err(
            &q_with("singularities = 300", "singularities = 0"),
            "shape.part[5].singularities",
            &["in [1, 8000], got 0"],
        );
        q_err(
            &q_with("singularities = 300", "singularities = 2.5"),
            "shape.part[5].singularities",
            &["whole number, got 2.5"],
        );
        q_err(
            &q_with("singularities = 300", "singularities = \"many\""),
            "shape.part[5].singularities",
            &["\"many\""],
        );
        q_err(
            &q_with("height = 60.0", "height = -60.0"),
            "shape.height",
            &["got -60"],
        );
        q_err(
            &q_with("origin = [10.0, 10.0]", "origin = [10.0, inf]"),
            "shape.origin",
            &["got inf"],
        );
        let t = q_with(
            "name = \"m1\"\npolygon = [[0, 0], [100, 0], [100, 300], [0, 300]]",
            "name = \"m1\"\ntext = \"IZ\"",
        );
        q_err(&t, "shape.part[1].text", &["'Z'", "no glyph"]);
        q_err(
            &t.replace("text = \"IZ\"", "text = \"I\"\nsize = 0"),
            "shape.part[1].size",
            &["positive", "got 0"],
        );
        let e = parse_job(
            &t.replace("text = \"IZ\"", "text = \"I\"\nfont = \"fonts/none.ttf\""),
            "x",
            Path::new("/some/dir"),
        )
        .unwrap_err();
        assert_eq!(e.key(), Some("shape.part[1].font"));
        assert_eq!(
            e.to_string(),
            "shape.part[1].font: no such file: /some/dir/fonts/none.ttf"
        );
    }

    #[test]
    fn result_must_be_bounded() {
        let inverted = q_with(
            "op = \"subtract\"\nof = [\"m6\", \"m3\"]",
            "op = \"invert\"\nof = \"m6\"",
        );
        q_err(
            &inverted,
            "shape.result",
            &["\"Q\", which is an invert", "unbounded"],
        );
        q_err(
            &inverted.replace("result = \"Q\"\n", ""),
            "shape.result",
            &["an invert", "the last part is the result"],
        );
        // Built from an invert: a union with the void is unbounded, an
        // intersection with it is not.
        let more = format!(
            "{inverted}\n[[shape.part]]\nname = \"R\"\nop = \"union\"\nof = [\"m4\", \"Q\"]\n"
        );
        q_err(
            &more.replace("result = \"Q\"", "result = \"R\""),
            "shape.result",
            &["\"R\"", "built from an invert"],
        );
        q_err(
            &more
                .replace("result = \"Q\"", "result = \"R\"")
                .replace("of = [\"m4\", \"Q\"]", "of = [\"Q\", \"m4\"]")
                .replace("\"union\"\nof = [\"Q\"", "\"subtract\"\nof = [\"Q\""),
            "shape.result",
            &["built from an invert"],
        );
        let ok = more.replace("result = \"Q\"", "result = \"R\"").replace(
            "op = \"union\"\nof = [\"m4\", \"Q\"]",
            "op = \"intersect\"\nof = [\"m4\", \"Q\"]",
        );
        assert!(parse(&ok).is_ok());
        let ok = more.replace("result = \"Q\"", "result = \"R\"").replace(
            "op = \"union\"\nof = [\"m4\", \"Q\"]",
            "op = \"subtract\"\nof = [\"m4\", \"Q\"]",
        );
        assert!(parse(&ok).is_ok());
    }

    #[test]
    fn one_shape_source_per_job() {
        q_err(
            &q_with("result = \"Q\"", "result = \"Q\"\ntext = \"A\""),
            "shape.part",
            &["cannot be combined with shape.text", "one shape source"],
        );
        q_err(
            &q_with(
                "result = \"Q\"",
                "result = \"Q\"\nsvg_path = \"M0 0 L1 0 L0 1 Z\"",
            ),
            "shape.part",
            &["cannot be combined with shape.svg_path"],
        );
        q_err(
            &q_with("result = \"Q\"", "result = \"Q\"\nfont = \"paper\""),
            "shape.font",
            &["[[shape.part]]"],
        );
        q_err(
            &q_with("result = \"Q\"", "result = \"Q\"\nletter_spacing = 2"),
            "shape.letter_spacing",
            &["[[shape.part]]"],
        );
        q_err(
            &with("shape", "result = \"A\""),
            "shape.result",
            &["[[shape.part]]"],
        );
        q_err(
            &with("shape", "part = []").replace("text = \"A\"\n", ""),
            "shape.part",
            &["at least one part"],
        );
    }

    #[test]
    fn part_keys_are_named_in_toml_errors() {
        // A misspelt key, a wrong type, and a [shape] key written after the parts.
        let (k, msg) = err_key(&q_with("level = 0.95", "levle = 0.95"));
        assert_eq!(k, "shape.part[3].levle");
        assert!(msg.contains("unknown field `levle`"), "{msg}");
        let (k, msg) = err_key(&q_with("of = \"m4\"", "of = 4"));
        assert_eq!(k, "shape.part[5].of");
        assert!(msg.contains("a part name or a list of part names"), "{msg}");
        // In a multi-line array, the key that opened it.
        let (k, msg) = err_key(&q_with("[50, 120], [100, 120]", "[50, 120], [100]"));
        assert_eq!(k, "shape.part[4].polygon", "{msg}");
        let (k, msg) = err_key(&format!("{Q}result = \"m6\"\n"));
        assert_eq!(k, "shape.part[7].result");
        assert!(
            msg.contains("belong in [shape], above the first [[shape.part]]"),
            "{msg}"
        );
        let (k, _) = err_key(&q_with(
            "polygon = [[0, 0], [100, 0], [100, 300], [0, 300]]",
            "polygon = [[0, 0], [100, 0], \"x\"]",
        ));
        assert_eq!(k, "shape.part[1].polygon");
    }

    #[test]
    fn load_job_names_the_file() {
        let e = load_job(Path::new("/no/such/job.toml")).unwrap_err();
        assert!(matches!(e, JobError::Read { .. }));
        assert!(e.to_string().contains("/no/such/job.toml"), "{e}");
    }
}

#[cfg(test)]
mod doc_tests {
    use super::*;

    const DOC: &str = include_str!("../docs/job-format.md");

    #[test]
    fn the_example_is_the_shipped_job() {
        let job = include_str!("../jobs/mfs-sign.toml");
        let example = DOC
            .split("`jobs/mfs-sign.toml` as shipped")
            .nth(1)
            .and_then(|rest| rest.split("```toml\n").nth(1))
            .and_then(|block| block.split("```").next())
            .expect("docs/job-format.md has the mfs-sign example");
        assert_eq!(example, job, "docs/job-format.md's example is stale");
    }

    /// (Over 120 lines because it is a list: one line per key of the job
    /// format, which is what it checks.)
    #[test]
    fn every_key_is_documented() {
        let keys = [
            "name",
            "text",
            "shape.lines",
            "shape.line_spacing",
            "shape.align",
            "font",
            "height",
            "letter_spacing",
            "origin",
            "svg_path",
            "svg_file",
            "id",
            "scale",
            "width",
            "dxf_file",
            "layer",
            "join_tolerance",
            "diameter",
            "feed",
            "plunge_feed",
            "spindle",
            "stepdown",
            "top",
            "safe_z",
            "retract_z",
            "kind",
            "side",
            "depth",
            "tolerance",
            "direction",
            "singularities",
            "pseudo_boundary",
            "rapid_rate",
            "spindle_dwell",
            "coolant",
            "arcs",
            "max_arc_radius",
            "travel",
            "work_offset",
            "max_hours",
            "max_file_mb",
            "stepover",
            "ramp_angle",
            "margin",
            "max_scallop",
            "scallop",
            "pattern",
            "corner_radius",
            "s_bottom",
            "s1",
            "s2",
            "steepness",
            "exponent",
            "points",
            "shape.result",
            "shape.kind",
            "shape.degree",
            "shape.form",
            "shape.size",
            "shape.row0",
            "shape.row1",
            "shape.points",
            "shape.inside",
            "shape.outside",
            "shape.points_file",
            "shape.kernel",
            "shape.a",
            "shape.box",
            "shape.elements",
            "shape.base",
            "shape.solid",
            "shape.bottom_size",
            "shape.bottom_exponent",
            "shape.top_size",
            "shape.top_exponent",
            "shape.flare",
            "shape.rise",
            "shape.modes",
            "shape.samples",
            "shape.part.name",
            "shape.part.polygon",
            "shape.part.svg",
            "shape.part.text",
            "shape.part.font",
            "shape.part.size",
            "shape.part.of",
            "shape.part.op",
            "shape.part.level",
            "shape.part.singularities",
            "shape.trim.angles",
            "shape.trim.z",
        ];
        // The text of the section `## `heading``, up to the next `## `.
        let section = |heading: &str| -> &str {
            let h = format!("## `{heading}`");
            let from = DOC
                .find(&h)
                .unwrap_or_else(|| panic!("{heading} is not documented"));
            let rest = &DOC[from + h.len()..];
            &rest[..rest.find("\n## ").unwrap_or(rest.len())]
        };
        for k in keys {
            // `shape.part.level` in `[[shape.part]]`, `shape.result` in `[shape]`.
            let (text, key) = match k.rsplit_once('.') {
                Some(("shape.part", key)) => (section("[[shape.part]]"), key),
                Some(("shape.trim", key)) => (section("[[shape.trim]]"), key),
                Some((table, key)) => (section(&format!("[{table}]")), key),
                None => (DOC, k),
            };
            assert!(
                text.contains(&format!("| `{key}` |")),
                "{k} is not in docs/job-format.md"
            );
        }
        for t in SECTIONS
            .iter()
            .copied()
            .chain(["[shape.part]", "[shape.trim]"])
        {
            assert!(
                DOC.contains(&format!("## `[{t}]`")),
                "[{t}] is not documented"
            );
        }
    }

    /// Mangled job files (the shipped jobs with bytes dropped, repeated or
    /// swapped, numbers replaced by extremes, lines shuffled) always give a job
    /// or an error, never a panic; every job that resolves has every numeric
    /// key within its documented range. A fixed seed, so a failure repeats.
    #[test]
    fn mangled_jobs_never_panic() {
        let jobs: Vec<String> = std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/jobs"))
            .expect("jobs/")
            .filter_map(|e| std::fs::read_to_string(e.ok()?.path()).ok())
            .collect();
        assert!(jobs.len() >= 5);
        let mut g = crate::num::testing::Lcg(0x6a6f62);
        let mut next = |n: usize| g.below(n);
        let extremes = [
            "1e300",
            "-1e300",
            "nan",
            "inf",
            "-inf",
            "0",
            "-0.0",
            "1e-320",
            "99999999999999999999",
            "-9223372036854775808",
            "\"\"",
            "[]",
            "[[]]",
            "{}",
            "true",
            "\"auto\"",
            "1.5",
            "-3",
        ];
        let (mut ok, mut refused) = (0, 0);
        for round in 0..3000 {
            let mut text = jobs[round % jobs.len()].clone().into_bytes();
            for _ in 0..1 + next(4) {
                let at = next(text.len());
                match next(5) {
                    0 => {
                        let len = next(8).min(text.len() - at);
                        text.drain(at..at + len);
                    }
                    1 => {
                        let piece: Vec<u8> = text[at..(at + next(40)).min(text.len())].to_vec();
                        let to = next(text.len());
                        text.splice(to..to, piece);
                    }
                    2 => {
                        let junk = b"=[]{}\"#.,-\n\x00\xff";
                        text.insert(at, junk[next(junk.len())]);
                    }
                    _ => {
                        // Replace the number after the next `=` by an extreme.
                        let s = String::from_utf8_lossy(&text).into_owned();
                        let from = (at.min(s.len())..=s.len())
                            .find(|&i| s.is_char_boundary(i))
                            .unwrap_or(s.len());
                        if let Some(eq) = s[from..].find('=').map(|i| i + from) {
                            let end = s[eq..].find('\n').map_or(s.len(), |i| eq + i);
                            let new = format!(
                                "{}= {}{}",
                                &s[..eq],
                                extremes[next(extremes.len())],
                                &s[end..]
                            );
                            text = new.into_bytes();
                        }
                    }
                }
            }
            let text = String::from_utf8_lossy(&text);
            match parse_job(&text, "fuzz", Path::new(".")) {
                Ok(job) => {
                    ok += 1;
                    let t = &job.tool;
                    for (key, x) in [
                        ("tool.diameter", t.diameter),
                        ("tool.feed", t.feed),
                        ("tool.plunge_feed", t.plunge_feed),
                        ("tool.spindle", t.spindle),
                        ("operation.depth", job.operation.depth),
                        ("stock.margin", job.stock.margin),
                    ] {
                        let r = limits::KEYS.iter().find(|(k, _)| *k == key).unwrap().1;
                        assert!(
                            r.contains(x),
                            "round {round}: {key} = {x} resolved from\n{text}"
                        );
                    }
                }
                Err(e) => {
                    refused += 1;
                    assert!(!e.to_string().is_empty());
                }
            }
        }
        // The mutations are neither all harmless nor all fatal.
        assert!(ok > 100 && refused > 100, "ok {ok}, refused {refused}");
    }

    /// Every range in `limits::KEYS` is the one docs/job-format.md gives on
    /// that key's row.
    #[test]
    fn every_range_is_documented() {
        for (k, range) in limits::KEYS {
            let (table, key) = k.rsplit_once('.').unwrap_or(("", k));
            let heading = if table == "shape.part" {
                "## `[[shape.part]]`".to_string()
            } else {
                format!("## `[{table}]`")
            };
            let from = DOC.find(&heading).unwrap_or_else(|| panic!("{heading}"));
            let rest = &DOC[from + heading.len()..];
            let text = &rest[..rest.find("\n## ").unwrap_or(rest.len())];
            let row = text
                .lines()
                .find(|l| l.starts_with(&format!("| `{key}` |")))
                .unwrap_or_else(|| panic!("{k} has no row"));
            assert!(
                row.contains(&range.interval()),
                "{k}: the row does not say {}: {row}",
                range.interval()
            );
        }
    }

    /// The first TOML block after `after` in the doc.
    fn toml_block(after: &str) -> &'static str {
        let from = DOC
            .find(after)
            .unwrap_or_else(|| panic!("no {after:?} in docs/job-format.md"));
        let start = DOC[from..].find("```toml\n").map(|i| from + i + 8);
        let block = start.and_then(|s| DOC[s..].find("```").map(|e| &DOC[s..s + e]));
        block.unwrap_or_else(|| panic!("no toml example after {after:?} in docs/job-format.md"))
    }

    #[test]
    fn the_documented_example_is_valid() {
        match parse_job(toml_block("\n## Example\n"), "x", Path::new(".")) {
            Ok(j) => assert_eq!(j.name, "mfs-sign"),
            Err(e) => panic!("docs example: {e}"),
        }
    }

    #[test]
    fn the_documented_letter_q_is_the_papers() {
        let doc = parse_job(
            toml_block("### Example: the paper's letter Q"),
            "x",
            Path::new("."),
        )
        .unwrap_or_else(|e| panic!("docs example: {e}"));
        assert_eq!(doc.name, "letter-q");
        let ShapeSource::Composite(mut doc) = doc.shape else {
            panic!("{:?}", doc.shape)
        };
        let ShapeSource::Composite(test) = parse_job(super::tests::Q, "x", Path::new("."))
            .unwrap()
            .shape
        else {
            panic!()
        };
        // The test's m5 sets its singularities; the doc's leaves them to pfcam.
        assert_eq!(doc.parts[4].singularities, None);
        doc.parts[4].singularities = test.parts[4].singularities;
        assert_eq!(doc, test);
    }
}
