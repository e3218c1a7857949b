//! Jobs: the TOML schema (raw), and the resolved, validated job the pipeline reads.
//!
//! Two steps, as in ripgrep's `lowargs`/`hiargs`: [`RawJob`] mirrors the TOML file
//! exactly (every table and key optional, unknown keys rejected), and
//! [`resolve`](RawJob::resolve) turns it into a [`Job`] with defaults applied and
//! every value checked. Every error names the key (`tool.diameter`, ...), and a
//! syntax error names the line and column. The keys, units and defaults are
//! documented in `docs/job-format.md`.

use crate::geometry::{glyphs, FontSource, ShapeSource, Vec2};
use serde::Deserialize;
use std::path::{Path, PathBuf};

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
    pub profile: Option<crate::levels::DepthProfile>,
    /// What the G-code may contain (arcs).
    pub output: Output,
}

/// A flat end mill.
#[derive(Clone, Debug, PartialEq)]
pub struct Tool {
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
}

impl Default for Machine {
    fn default() -> Self {
        Machine {
            rapid_rate: defaults::RAPID_RATE,
            spindle_dwell: defaults::SPINDLE_DWELL,
            travel: None,
            work_offset: None,
            coolant: defaults::COOLANT,
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
    /// `machine.coolant`: off (most hobby routers have none).
    pub const COOLANT: bool = false;
    /// `output.arcs`: on (GRBL 1.1 cuts arcs well and the file is smaller).
    pub const ARCS: bool = true;
    /// `output.max_arc_radius`, mm: a 1000 mm arc over a 100 mm chord bulges
    /// 1.25 mm, so anything flatter is a line to the eye and to the machine.
    pub const MAX_ARC_RADIUS: f64 = crate::toolpath::arcfit::DEFAULT_MAX_RADIUS;
}

/// The accepted values of `operation.kind`.
pub const OPERATION_KINDS: &[&str] = &["profile", "boss", "cavity"];
/// The accepted values of `profile.kind`.
pub const PROFILE_KINDS: &[&str] = &["linear", "sigmoid", "spline", "table"];
/// The accepted values of `operation.side`.
pub const SIDES: &[&str] = &["outside"];
/// The accepted values of `operation.direction`.
pub const DIRECTIONS: &[&str] = &["climb", "conventional"];

/// What can be wrong with a job.
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    /// The job file cannot be read.
    #[error("cannot read job file {}: {source}", path.display())]
    Read {
        /// the file
        path: PathBuf,
        /// why
        source: std::io::Error,
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
    /// A font file that does not exist.
    #[error("shape.font: no such file: {}", path.display())]
    FontNotFound {
        /// the resolved path
        path: PathBuf,
    },
}

impl JobError {
    /// The key the error is about, when there is one.
    pub fn key(&self) -> Option<&str> {
        match self {
            JobError::Read { .. } => None,
            JobError::Parse { key, .. } => key.as_deref(),
            JobError::Invalid { key, .. } => Some(key),
            JobError::FontNotFound { .. } => Some("shape.font"),
        }
    }
}

fn invalid(key: &str, message: impl Into<String>) -> JobError {
    JobError::Invalid {
        key: key.into(),
        message: message.into(),
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
}

/// `[profile]`: the depth profile φ(s) of a boss or cavity.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawProfile {
    /// `kind`: linear, sigmoid, spline or table
    pub kind: Option<String>,
    /// `s_bottom` (linear)
    pub s_bottom: Option<f64>,
    /// `s1` (sigmoid: top edge)
    pub s1: Option<f64>,
    /// `s2` (sigmoid: foot of the wall)
    pub s2: Option<f64>,
    /// `steepness` (sigmoid)
    pub steepness: Option<f64>,
    /// `points`: [[s, z], ...] (spline, table), z in mm relative to stock.top
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
    /// `svg_path`
    pub svg_path: Option<String>,
    /// `font`
    pub font: Option<String>,
    /// `height`, mm
    pub height: Option<f64>,
    /// `letter_spacing`, mm
    pub letter_spacing: Option<f64>,
    /// `origin`, mm
    pub origin: Option<[f64; 2]>,
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
    pub travel: Option<[f64; 3]>,
    /// `work_offset`, mm: [x, y, z]
    pub work_offset: Option<[f64; 3]>,
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
                    positive(&format!("machine.travel ({axis})"), *k, "mm")?;
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
                    finite("machine.work_offset", v)?;
                }
                Some(o)
            }
        };
        Ok(Machine {
            rapid_rate: positive(
                "machine.rapid_rate",
                m.rapid_rate.unwrap_or(defaults::RAPID_RATE),
                "mm/min",
            )?,
            spindle_dwell: {
                let d = finite(
                    "machine.spindle_dwell",
                    m.spindle_dwell.unwrap_or(defaults::SPINDLE_DWELL),
                )?;
                if d < 0.0 {
                    return Err(invalid(
                        "machine.spindle_dwell",
                        format!("must be >= 0 s, got {}", show(d)),
                    ));
                }
                d
            },
            coolant: m.coolant.unwrap_or(defaults::COOLANT),
            travel,
            work_offset,
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
    let text = std::fs::read_to_string(path).map_err(|source| JobError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let is_machine_file = match text.parse::<toml::Table>() {
        Ok(t) => t.keys().all(|k| k == "machine"),
        // Let the job reader report where the TOML is wrong.
        Err(_) => false,
    };
    if !is_machine_file {
        return Ok((load_job(path)?.machine, MachineSource::Job));
    }
    let raw: RawMachineFile = toml::from_str(&text).map_err(|e| match parse_error(&text, &e) {
        JobError::Parse {
            line,
            column,
            key,
            message,
            ..
        } => JobError::Parse {
            origin: path.display().to_string(),
            line,
            column,
            key,
            message,
        },
        e => e,
    })?;
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
    let text = std::fs::read_to_string(path).map_err(|source| JobError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "job".into());
    let base = path.parent().unwrap_or_else(|| Path::new(""));
    parse_job(&text, &stem, base).map_err(|e| match e {
        JobError::Parse {
            line,
            column,
            key,
            message,
            ..
        } => JobError::Parse {
            origin: path.display().to_string(),
            line,
            column,
            key,
            message,
        },
        e => e,
    })
}

/// Parse and resolve job text. `name_hint` is the name used when `[job] name` is
/// absent; `base_dir` is where relative font paths are looked up.
pub fn parse_job(text: &str, name_hint: &str, base_dir: &Path) -> Result<Job, JobError> {
    let raw: RawJob = toml::from_str(text).map_err(|e| parse_error(text, &e))?;
    raw.resolve(name_hint, base_dir)
}

fn parse_error(text: &str, e: &toml::de::Error) -> JobError {
    let pos = e.span().map_or(0, |s| s.start).min(text.len());
    let (line, column) = line_col(text, pos);
    JobError::Parse {
        origin: "job".into(),
        line,
        column,
        key: e.span().and_then(|_| key_at(text, pos)),
        message: e.message().trim().to_string(),
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
/// otherwise `<last table>.<key before '='>` on that line.
fn key_at(text: &str, pos: usize) -> Option<String> {
    let before = text.get(..pos)?;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[pos..].find('\n').map_or(text.len(), |i| pos + i);
    let line = &text[line_start..line_end];
    let header = |l: &str| -> Option<String> {
        let t = l.trim();
        let t = t.strip_prefix('[')?;
        let end = t.find(']')?;
        Some(t[..end].trim_matches(|c| c == '[' || c == ' ').to_string())
    };
    if let Some(h) = header(line) {
        return Some(h);
    }
    let eq = line.find('=')?;
    let key = line[..eq].trim().trim_matches('"');
    if key.is_empty() {
        return None;
    }
    let table = text[..line_start].lines().rev().find_map(header);
    Some(match table {
        Some(t) => format!("{t}.{key}"),
        None => key.to_string(),
    })
}

/// `x` as the user wrote it: `-3`, `0.5`.
fn show(x: f64) -> String {
    format!("{x}")
}

fn positive(key: &str, x: f64, unit: &str) -> Result<f64, JobError> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(invalid(
            key,
            format!("must be a positive number of {unit}, got {}", show(x)),
        ))
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
                "has no value `{value}`; accepted: {}",
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
                "must be 1 to 64 of the characters A-Z a-z 0-9 - _ . (not starting with .), got {name:?}"
            ),
        ))
    }
}

impl RawJob {
    /// Apply defaults and check every value; see `docs/job-format.md`.
    pub fn resolve(self, name_hint: &str, base_dir: &Path) -> Result<Job, JobError> {
        let name = match self.job.and_then(|j| j.name) {
            Some(n) => {
                check_name("job.name", &n)?;
                n
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
                name_hint.to_string()
            }
        };

        // The tool first: the letter spacing defaults to its diameter.
        let t = self.tool.unwrap_or_default();
        let diameter = positive(
            "tool.diameter",
            t.diameter
                .ok_or_else(|| invalid("tool.diameter", "is required (mm)"))?,
            "mm",
        )?;
        let tool = Tool {
            diameter,
            feed: positive("tool.feed", t.feed.unwrap_or(defaults::FEED), "mm/min")?,
            plunge_feed: positive(
                "tool.plunge_feed",
                t.plunge_feed.unwrap_or(defaults::PLUNGE_FEED),
                "mm/min",
            )?,
            spindle: {
                let s = finite("tool.spindle", t.spindle.unwrap_or(defaults::SPINDLE))?;
                if s < 0.0 {
                    return Err(invalid(
                        "tool.spindle",
                        format!("must be >= 0 rev/min, got {}", show(s)),
                    ));
                }
                s
            },
            stepdown: positive(
                "tool.stepdown",
                t.stepdown.unwrap_or(defaults::STEPDOWN),
                "mm",
            )?,
            stepover: {
                let so = positive(
                    "tool.stepover",
                    t.stepover.unwrap_or(defaults::STEPOVER_FRACTION * diameter),
                    "mm",
                )?;
                if so > diameter / 2.0 {
                    return Err(invalid(
                        "tool.stepover",
                        format!(
                            "must be at most the tool radius ({} mm) so neighbouring rings overlap, got {}",
                            show(diameter / 2.0),
                            show(so)
                        ),
                    ));
                }
                so
            },
            ramp_angle: {
                let a = positive(
                    "tool.ramp_angle",
                    t.ramp_angle.unwrap_or(defaults::RAMP_ANGLE),
                    "degrees",
                )?;
                if a > 45.0 {
                    return Err(invalid(
                        "tool.ramp_angle",
                        format!("must be at most 45 degrees, got {}", show(a)),
                    ));
                }
                a
            },
        };

        let shape = resolve_shape(self.shape.unwrap_or_default(), diameter, base_dir)?;

        let s = self.stock.unwrap_or_default();
        let top = finite("stock.top", s.top.unwrap_or(defaults::STOCK_TOP))?;
        let safe_z = finite(
            "stock.safe_z",
            s.safe_z.unwrap_or(top + defaults::SAFE_CLEARANCE),
        )?;
        if safe_z <= top {
            return Err(invalid(
                "stock.safe_z",
                format!(
                    "must be above stock.top ({}), got {}",
                    show(top),
                    show(safe_z)
                ),
            ));
        }
        let margin = finite("stock.margin", s.margin.unwrap_or(defaults::MARGIN))?;
        if margin < 0.0 {
            return Err(invalid(
                "stock.margin",
                format!("must be >= 0 mm, got {}", show(margin)),
            ));
        }
        let stock = Stock {
            top,
            safe_z,
            margin,
        };

        let o = self.operation.unwrap_or_default();
        let kind = o.kind.unwrap_or_else(|| "profile".into());
        one_of("operation.kind", &kind, OPERATION_KINDS)?;
        let side = o.side.unwrap_or_else(|| "outside".into());
        one_of("operation.side", &side, SIDES)?;
        let direction = o.direction.unwrap_or_else(|| "climb".into());
        one_of("operation.direction", &direction, DIRECTIONS)?;
        let depth = o
            .depth
            .ok_or_else(|| invalid("operation.depth", "is required (mm below stock.top)"))?;
        if !(depth.is_finite() && depth > 0.0) {
            return Err(invalid(
                "operation.depth",
                format!("must be > 0 (mm below stock.top), got {}", show(depth)),
            ));
        }
        let tolerance = o.tolerance.unwrap_or(defaults::TOLERANCE);
        if !(tolerance.is_finite() && tolerance > 0.0) {
            return Err(invalid(
                "operation.tolerance",
                format!("must be > 0 mm, got {}", show(tolerance)),
            ));
        }
        if tolerance >= diameter / 2.0 {
            return Err(invalid(
                "operation.tolerance",
                format!(
                    "must be smaller than the tool radius ({} mm), got {}",
                    show(diameter / 2.0),
                    show(tolerance)
                ),
            ));
        }
        let max_scallop = positive(
            "operation.max_scallop",
            o.max_scallop.unwrap_or(defaults::MAX_SCALLOP),
            "mm",
        )?;
        let op_kind = match kind.as_str() {
            "boss" => OperationKind::Boss,
            "cavity" => OperationKind::Cavity,
            _ => OperationKind::Profile,
        };
        let profile = if op_kind == OperationKind::Profile {
            if self.profile.is_some() {
                return Err(invalid(
                    "profile",
                    "only applies to operation.kind = \"boss\" or \"cavity\"",
                ));
            }
            None
        } else {
            Some(resolve_profile(self.profile.unwrap_or_default(), depth)?)
        };
        let operation = Operation {
            max_scallop,
            kind: op_kind,
            side: Side::Outside,
            depth,
            tolerance,
            direction: if direction == "climb" {
                Direction::Climb
            } else {
                Direction::Conventional
            },
        };

        let f = self.field.unwrap_or_default();
        let singularities =
            match f.singularities {
                None => None,
                Some(AutoOr::Word(w)) => {
                    auto_word("field.singularities", &w, "a whole number of singularities")?;
                    None
                }
                Some(AutoOr::Float(x)) => {
                    return Err(invalid(
                        "field.singularities",
                        format!("must be \"auto\" or a whole number, got {}", show(x)),
                    ))
                }
                Some(AutoOr::Int(n)) => {
                    if n < 1 {
                        return Err(invalid(
                            "field.singularities",
                            format!("must be \"auto\" or a count >= 1, got {n}"),
                        ));
                    }
                    Some(usize::try_from(n).map_err(|_| {
                        invalid("field.singularities", format!("is too large: {n}"))
                    })?)
                }
            };
        let pseudo_boundary = match f.pseudo_boundary {
            None => None,
            Some(AutoOr::Word(w)) => {
                auto_word("field.pseudo_boundary", &w, "a distance in mm")?;
                None
            }
            Some(AutoOr::Int(d)) => Some(positive("field.pseudo_boundary", d as f64, "mm")?),
            Some(AutoOr::Float(d)) => Some(positive("field.pseudo_boundary", d, "mm")?),
        };
        let field = FieldSpec {
            singularities,
            pseudo_boundary,
        };

        let machine = self.machine.unwrap_or_default().resolve()?;

        let o = self.output.unwrap_or_default();
        let output = Output {
            arcs: o.arcs.unwrap_or(defaults::ARCS),
            max_arc_radius: positive(
                "output.max_arc_radius",
                o.max_arc_radius.unwrap_or(defaults::MAX_ARC_RADIUS),
                "mm",
            )?,
        };

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
        })
    }
}

/// `[profile]` into a depth profile; `depth` is `operation.depth`, which spline
/// and table points must agree with (their lowest z is −depth).
fn resolve_profile(p: RawProfile, depth: f64) -> Result<crate::levels::DepthProfile, JobError> {
    use crate::levels::DepthProfile;
    let kind = p.kind.unwrap_or_else(|| defaults::PROFILE_KIND.into());
    one_of("profile.kind", &kind, PROFILE_KINDS)?;
    let unit = |key: &str, v: f64| -> Result<f64, JobError> {
        if v.is_finite() && v > 0.0 && v < 1.0 {
            Ok(v)
        } else {
            Err(invalid(
                key,
                format!("must be an equipotential value in (0, 1), got {}", show(v)),
            ))
        }
    };
    let unused = |key: &str, present: bool| -> Result<(), JobError> {
        if present {
            Err(invalid(
                key,
                format!("does not apply to profile.kind = {kind:?}"),
            ))
        } else {
            Ok(())
        }
    };
    match kind.as_str() {
        "linear" => {
            unused("profile.s1", p.s1.is_some())?;
            unused("profile.s2", p.s2.is_some())?;
            unused("profile.steepness", p.steepness.is_some())?;
            unused("profile.points", p.points.is_some())?;
            let s_bottom = unit("profile.s_bottom", p.s_bottom.unwrap_or(defaults::S_BOTTOM))?;
            Ok(DepthProfile::Linear { s_bottom, depth })
        }
        "sigmoid" => {
            unused("profile.s_bottom", p.s_bottom.is_some())?;
            unused("profile.points", p.points.is_some())?;
            let (d1, d2, dk) = defaults::SIGMOID;
            let s1 = unit("profile.s1", p.s1.unwrap_or(d1))?;
            let s2 = unit("profile.s2", p.s2.unwrap_or(d2))?;
            if s2 >= s1 {
                return Err(invalid(
                    "profile.s2",
                    format!("must be below profile.s1 ({}), got {}", show(s1), show(s2)),
                ));
            }
            let steepness = positive("profile.steepness", p.steepness.unwrap_or(dk), "")?;
            Ok(DepthProfile::Sigmoid {
                s1,
                s2,
                steepness,
                depth,
            })
        }
        _ => {
            unused("profile.s_bottom", p.s_bottom.is_some())?;
            unused("profile.s1", p.s1.is_some())?;
            unused("profile.s2", p.s2.is_some())?;
            unused("profile.steepness", p.steepness.is_some())?;
            let points = p
                .points
                .ok_or_else(|| invalid("profile.points", "is required for a spline or table: [[s, z], ...] with z in mm relative to stock.top"))?;
            let prof = DepthProfile::from_points(&points, kind == "spline")
                .map_err(|e| invalid("profile.points", e.to_string()))?;
            if (prof.depth() - depth).abs() > 1e-9 {
                return Err(invalid(
                    "profile.points",
                    format!(
                        "the lowest point is at z = {} but operation.depth is {}: they must agree",
                        show(-prof.depth()),
                        show(depth)
                    ),
                ));
            }
            Ok(prof)
        }
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

fn resolve_shape(
    s: RawShape,
    tool_diameter: f64,
    base_dir: &Path,
) -> Result<ShapeSource, JobError> {
    let origin = match s.origin {
        Some([x, y]) => Vec2::new(finite("shape.origin", x)?, finite("shape.origin", y)?),
        None => Vec2::ZERO,
    };
    let height = s
        .height
        .map(|h| positive("shape.height", h, "mm"))
        .transpose()?;
    match (s.text, s.svg_path) {
        (Some(_), Some(_)) => Err(invalid(
            "shape.text",
            "and shape.svg_path are both given; give exactly one",
        )),
        (None, None) => Err(invalid(
            "shape.text",
            "or shape.svg_path is required (exactly one of them)",
        )),
        (Some(text), None) => {
            if text.trim().is_empty() {
                return Err(invalid("shape.text", "must not be empty"));
            }
            let font = match s.font.as_deref().unwrap_or(defaults::FONT) {
                "paper" => {
                    let have = glyphs::paper_chars();
                    if let Some(ch) = text.chars().find(|c| *c != ' ' && !have.contains(c)) {
                        let list: String = have.iter().collect();
                        return Err(invalid(
                            "shape.text",
                            format!(
                                "has {ch:?}, but the font `paper` has no glyph for it (it has {list})"
                            ),
                        ));
                    }
                    FontSource::Paper
                }
                path => {
                    let p = base_dir.join(path);
                    if !p.is_file() {
                        return Err(JobError::FontNotFound { path: p });
                    }
                    FontSource::File(p)
                }
            };
            let letter_spacing = finite(
                "shape.letter_spacing",
                s.letter_spacing.unwrap_or(tool_diameter),
            )?;
            Ok(ShapeSource::Text {
                text,
                font,
                height: height.unwrap_or(defaults::TEXT_HEIGHT),
                letter_spacing,
                origin,
            })
        }
        (None, Some(d)) => {
            if s.font.is_some() {
                return Err(invalid(
                    "shape.font",
                    "only applies to shape.text, not shape.svg_path",
                ));
            }
            if s.letter_spacing.is_some() {
                return Err(invalid(
                    "shape.letter_spacing",
                    "only applies to shape.text, not shape.svg_path",
                ));
            }
            if d.trim().is_empty() {
                return Err(invalid("shape.svg_path", "must not be empty"));
            }
            Ok(ShapeSource::SvgPath { d, height, origin })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn every_key_is_documented() {
        let keys = [
            "name",
            "text",
            "font",
            "height",
            "letter_spacing",
            "origin",
            "svg_path",
            "diameter",
            "feed",
            "plunge_feed",
            "spindle",
            "stepdown",
            "top",
            "safe_z",
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
            "stepover",
            "ramp_angle",
            "margin",
            "max_scallop",
            "s_bottom",
            "s1",
            "s2",
            "steepness",
            "points",
        ];
        for k in keys {
            assert!(
                DOC.contains(&format!("| `{k}` |")),
                "{k} is not in docs/job-format.md"
            );
        }
        for t in [
            "job",
            "shape",
            "tool",
            "stock",
            "operation",
            "field",
            "machine",
            "output",
            "profile",
        ] {
            assert!(
                DOC.contains(&format!("## `[{t}]`")),
                "[{t}] is not documented"
            );
        }
    }

    #[test]
    fn the_documented_example_is_valid() {
        let start = DOC.find("```toml\n").map(|i| i + 8);
        let block = start.and_then(|s| DOC[s..].find("```").map(|e| &DOC[s..s + e]));
        let Some(block) = block else {
            panic!("no toml example in docs/job-format.md")
        };
        match parse_job(block, "x", Path::new(".")) {
            Ok(j) => assert_eq!(j.name, "mfs-sign"),
            Err(e) => panic!("docs example: {e}"),
        }
    }
}
