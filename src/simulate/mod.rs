//! `pfcam simulate`: a machinist's dry run of a G-code file on a height-map
//! stock, written independently of the path generator (it reads G-code text,
//! never a `Toolpath`).
//!
//! Every move removes material ([`run`]): `G0`, `G1`, `G2`/`G3` (I/J/K or R,
//! helical), each arc cut into chords within [`CHORD_FRACTION`] of the
//! resolution. The tool ([`Tool`]) is a flat, ball or bull nose end mill of
//! radius r; along a straight piece each cell centre within r of the tool's
//! axis is lowered to the lowest z the tool's lower surface has over it
//! ([`tool`]: exact for the flat end and the ball, within 1e-7 mm for the
//! bull nose). Several programs ([`simulate_programs`]) run one after the
//! other on one stock, each with its own tool. The rules of the findings:
//! - a rapid that removes more than [`RAPID_DEPTH`] touches material;
//! - a feed move that removes more than [`PLUNGE_DEPTH`] of material while
//!   descending steeper than [`PLUNGE_ANGLE_DEG`] from horizontal (Δz over its
//!   XY length) is a straight plunge;
//! - axial engagement of a move: the deepest material it removes under the
//!   tool; radial engagement: the spread, across the move's direction, of the
//!   cells where it removes more than [`AIR_DEPTH`], over the tool diameter;
//!   a move whose cells cut deeper than stepdown + [`SLOT_SLACK`] span at
//!   least [`SLOT_SHARE`] of the width of the tool's flat part, and reach
//!   within [`SLOT_MIDDLE`] of its radius from the axis, is a full-width cut
//!   deeper than the stepdown (for a bull nose only cells under its flat part
//!   count; a ball has none and is not judged by this rule);
//! - feed length in air: pieces that remove at most [`AIR_DEPTH`];
//! - with a job: cells cut below the part's own model by more than the
//!   tolerance are gouges ([`part`]).
//!
//! The library never prints; [`simulate`] returns a [`Simulation`] (the
//! [`Report`] and the final [`HeightMap`]), and the tests draw it (`png::stock_png`);
//! [`simulate_programs`] returns a [`Sequence`] (a report per program, the
//! part compared once, the final stock), and [`png::sequence_png`] draws it.

pub(crate) mod balldrop;
pub mod header;
pub(crate) mod moves;
pub mod part;
pub mod png;
pub mod reach;
pub(crate) mod report;
pub mod run;
pub(crate) mod stock;
pub(crate) mod tool;
mod verify;
pub(crate) mod walls;

use serde::Serialize;

pub use part::job_facts;
pub use part::JobFacts;
pub use part::PartModel;
pub(crate) use report::Finding;
pub use report::Kind;
pub(crate) use report::PartComparison;
pub use report::Report;
pub(crate) use report::StockInfo;
pub(crate) use stock::Grid;
pub(crate) use stock::HeightMap;
pub(crate) use tool::Tool;
pub use tool::ToolShape;
pub use verify::verify_finish;
pub use verify::verify_program;
pub use verify::UnsafeProgram;

/// A rapid removing more than this (mm) touches material: far below a chip,
/// above the rounding of 3-decimal coordinates' binary values.
pub(crate) const RAPID_DEPTH: f64 = 0.001;
/// A feed move entering more material than this (mm) steeper than
/// [`PLUNGE_ANGLE_DEG`] is a straight plunge (issue 11's 0.05 mm).
pub(crate) const PLUNGE_DEPTH: f64 = 0.05;
/// Entry angles steeper than this (degrees from horizontal) are plunges: a
/// ramp is a few degrees (pfcam's `tool.ramp_angle`), a straight plunge 90.
pub(crate) const PLUNGE_ANGLE_DEG: f64 = 45.0;
/// A piece removing at most this (mm) cuts air, and such cells do not count
/// for radial engagement.
pub(crate) const AIR_DEPTH: f64 = 0.001;
/// A cut whose removed cells span at least this share of the tool diameter is
/// full width. Cell centres can lie at most r − res/2 off the axis, so a slot
/// spans 1 − res/(2r) of it; 0.9 keeps slots at resolutions up to 0.1·d.
pub(crate) const SLOT_SHARE: f64 = 0.9;
/// Slack over the stepdown (mm) before a full-width cut is too deep (the
/// stepdown is reached exactly by design).
pub(crate) const SLOT_SLACK: f64 = 0.01;

/// A full-width cut must also be deeper than the slot depth within this share
/// of the radius from the tool's axis (a slot is deep under the middle of the
/// tool; rim slivers are not).
pub(crate) const SLOT_MIDDLE: f64 = 0.5;
/// Chords of arcs stay within this fraction of the resolution of the arc.
pub const CHORD_FRACTION: f64 = 0.05;
/// Default cell side, mm.
pub const DEFAULT_RESOLUTION: f64 = 0.1;
/// The most cells a stock gets (8 bytes of height and 4 of line each); a
/// larger stock is simulated on coarser cells, with a note.
pub(crate) const MAX_CELLS: usize = 16_000_000;

/// What can stop a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// No tool diameter from the flags, the job or the file's header.
    #[error("no tool diameter: give --tool-diameter MM or --job JOB.toml (the file's header does not name a tool)")]
    NoTool,
    /// A program after the first whose header names no tool, without flags.
    #[error("no tool: the file's header does not name one, and a job's tool is the first program's only: give --tool-diameter MM (and --tool-shape; the flags apply to every program)")]
    NoToolAfterFirst,
    /// Nothing tells where the stock is.
    #[error("no feed move from a known position and no stock given: nothing to simulate (give --stock X0,Y0,X1,Y1,TOP)")]
    NoStock,
    /// A length that must be a positive number of mm (a flag's value).
    #[error("{name} must be a positive number of mm, got {value}")]
    NotPositive {
        /// The flag, e.g. `--resolution`.
        name: &'static str,
        /// What it was given.
        value: f64,
    },
    /// The tool's diameter is not a positive number of mm.
    #[error("the tool diameter must be a positive number of mm, got {0}")]
    ToolDiameter(f64),
    /// A bull nose's corner radius outside (0, r).
    #[error("a bull nose's corner radius must lie between 0 and the tool radius {radius} mm (exclusive), got {corner} (a corner of the full radius is --tool-shape ball)")]
    BullCorner {
        /// The corner radius given, mm.
        corner: f64,
        /// The tool's radius, mm.
        radius: f64,
    },
    /// A bull nose without its corner radius.
    #[error("a bull nose end mill needs its corner radius: give --corner-radius MM")]
    BullWithoutCorner,
    /// A corner radius given for a flat or ball end mill that is not its own.
    #[error("--corner-radius {corner} is for --tool-shape bull, not a {} end mill", shape.name())]
    CornerNotBull {
        /// The corner radius given, mm.
        corner: f64,
        /// The tool's shape.
        shape: ToolShape,
    },
    /// `--stock` not a finite rectangle with X0 < X1 and Y0 < Y1.
    #[error("--stock: X0 < X1 and Y0 < Y1 must be finite numbers, got {},{},{},{},{}", stock.lo[0], stock.lo[1], stock.hi[0], stock.hi[1], stock.top)]
    BadStock {
        /// The stock as given.
        stock: StockBox,
    },
    /// No program was given.
    #[error("no program to simulate")]
    NoProgram,
    /// The programs have more lines together than a line number can hold.
    #[error("more than {} lines in all: too many to simulate together", u32::MAX)]
    TooManyLines,
    /// The part could not be modelled from the job. Held, not a source:
    /// a composition's error has its own source, which names the part
    /// otherwise than this message, and a front end that adds the chain's
    /// causes would add it too.
    #[error("the part of the job: {0}")]
    Part(Box<crate::pipeline::PipelineError>),
    /// The PNG could not be encoded.
    #[error("drawing the stock: {0}")]
    Png(#[from] crate::preview::colormap::PngError),
    /// What stopped one program of several, and its name.
    #[error("{name}: {error}")]
    Program {
        /// The program's name (its file).
        name: String,
        /// What stopped it.
        error: Box<SimError>,
    },
}

/// A stock block: the rectangle `lo`..`hi` (mm) and its top z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StockBox {
    /// Lower-left corner (x, y).
    pub lo: [f64; 2],
    /// Upper-right corner (x, y).
    pub hi: [f64; 2],
    /// Top, mm.
    pub top: f64,
}

/// How to simulate.
#[derive(Clone, Debug)]
pub struct SimOptions {
    /// Cell side, mm.
    pub resolution: f64,
    /// `--stock`.
    pub stock: Option<StockBox>,
    /// `--tool-diameter`, mm.
    pub tool_diameter: Option<f64>,
    /// `--tool-shape`.
    pub tool_shape: Option<ToolShape>,
    /// `--corner-radius`, mm (a bull nose's).
    pub corner_radius: Option<f64>,
    /// `--stepdown`, mm.
    pub stepdown: Option<f64>,
    /// What `--job` says (tool, stepdown, stock, part).
    pub job: Option<JobFacts>,
    /// Cap on the cells ([`MAX_CELLS`]).
    pub max_cells: usize,
}

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            resolution: DEFAULT_RESOLUTION,
            stock: None,
            tool_diameter: None,
            tool_shape: None,
            corner_radius: None,
            stepdown: None,
            job: None,
            max_cells: MAX_CELLS,
        }
    }
}

/// A finished simulation of one program: the report and the final stock.
#[derive(Clone, Debug)]
pub struct Simulation {
    /// The figures and findings.
    pub report: Report,
    /// The stock after the program.
    pub map: HeightMap,
}

/// One program of a [`Sequence`]: its name and what it did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ProgramReport {
    /// The name it was given (its file).
    pub name: String,
    /// Its figures and findings (line numbers its own); `part` is `None`: the
    /// part is compared once, on the final stock ([`Sequence::part`]).
    pub report: Report,
}

/// Several programs run one after the other on one stock (a rough and a
/// finish program: GRBL has no tool changer, the machinist runs one, changes
/// the tool, runs the next).
#[derive(Clone, Debug)]
pub struct Sequence {
    /// Each program, in order.
    pub programs: Vec<ProgramReport>,
    /// With a job: the final stock against the part. Its lines name the
    /// program in `max_gouge_program` / `max_left_program`.
    pub part: Option<PartComparison>,
    /// The stock after the last program.
    pub map: HeightMap,
}

impl Sequence {
    /// No finding in any program (gouges included).
    pub fn is_clean(&self) -> bool {
        self.programs.iter().all(|p| p.report.is_clean())
    }

    /// Every finding, with the name of its program.
    pub fn findings(&self) -> impl Iterator<Item = (&str, &Finding)> {
        self.programs
            .iter()
            .flat_map(|p| p.report.findings.iter().map(|f| (p.name.as_str(), f)))
    }
}

fn positive(name: &'static str, v: f64) -> Result<f64, SimError> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(SimError::NotPositive { name, value: v })
    }
}

/// Simulates the program `text` (see the module docs).
pub fn simulate(text: &str, opts: &SimOptions) -> Result<Simulation, SimError> {
    let seq = simulate_programs(&[("", text)], opts).map_err(|e| match e {
        SimError::Program { error, .. } => *error,
        e => e,
    })?;
    let Sequence {
        programs,
        part,
        map,
    } = seq;
    let mut report = programs
        .into_iter()
        .next()
        .map(|p| p.report)
        .ok_or(SimError::NoProgram)?;
    report.part = part;
    Ok(Simulation { report, map })
}

/// Where a program's tool comes from before the flags: the job's or the
/// header's, and which.
fn base_tool(
    job: Option<&JobFacts>,
    head: &header::Header,
    first: bool,
) -> Option<(Tool, &'static str)> {
    let header = head.tool.map(|t| (t, "header"));
    match job {
        // The job's tool is the first program's, unless its header names
        // another (the job's finish tool).
        Some(j) if first => {
            let jt = Tool::flat_unchecked(j.tool_diameter);
            match header {
                Some((t, _)) if t != jt => header,
                _ => Some((jt, "job")),
            }
        }
        _ => header,
    }
}

/// The program's tool: each of `--tool-diameter`, `--tool-shape` and
/// `--corner-radius` given overrides that part of the header's or job's
/// tool; the source names the flags used and the base when it gave a part.
fn choose_tool(
    opts: &SimOptions,
    base: Option<(Tool, &'static str)>,
    first: bool,
) -> Result<(Tool, String), SimError> {
    let no_tool = if first {
        SimError::NoTool
    } else {
        SimError::NoToolAfterFirst
    };
    let diameter = match opts.tool_diameter {
        Some(d) => positive("--tool-diameter", d)?,
        None => base.map(|(t, _)| t.diameter()).ok_or(no_tool)?,
    };
    let base_shape = base.map(|(t, _)| t.shape());
    let shape = opts.tool_shape.or(base_shape).unwrap_or(ToolShape::Flat);
    let base_corner = base
        .filter(|(t, _)| t.shape() == ToolShape::Bull && shape == ToolShape::Bull)
        .map(|(t, _)| t.corner_radius());
    let corner = match (opts.corner_radius, shape) {
        (Some(c), _) => Some(c),
        (None, ToolShape::Bull) => base_corner,
        (None, _) => None,
    };
    let tool = Tool::new(shape, diameter, corner)?;
    let mut flags: Vec<&str> = Vec::new();
    if opts.tool_diameter.is_some() {
        flags.push("--tool-diameter");
    }
    if opts.tool_shape.is_some() {
        flags.push("--tool-shape");
    }
    if opts.corner_radius.is_some() {
        flags.push("--corner-radius");
    }
    // The base gave a part: the diameter, a shape other than the flat one
    // every tool defaults to, or the corner.
    let from_base = opts.tool_diameter.is_none()
        || (opts.tool_shape.is_none() && base_shape.is_some_and(|s| s != ToolShape::Flat))
        || (opts.corner_radius.is_none() && base_corner.is_some());
    if let (true, Some((_, name))) = (from_base, base) {
        flags.push(name);
    }
    Ok((tool, flags.join(", ")))
}

/// One program read and its tool chosen, before the walk.
struct Prepared<'a> {
    name: &'a str,
    head: header::Header,
    read: moves::Moves,
    tool: Tool,
    tool_source: String,
    stepdown: Option<f64>,
}

/// Simulates `programs` (name, G-code text) one after the other on one stock
/// (see the module docs): the stock the first leaves is where the second
/// starts. The stock box is `--stock`, the job's, the first program's
/// header's, else the feed moves of all of them grown by the largest tool
/// radius. Each program has its own tool: the flags, else its header's, else
/// (the first program only) the job's; and its own stepdown: `--stepdown`,
/// else the job's when its tool is the job's, else its header's.
pub fn simulate_programs(
    programs: &[(&str, &str)],
    opts: &SimOptions,
) -> Result<Sequence, SimError> {
    let res = positive("--resolution", opts.resolution)?;
    let job = opts.job.as_ref();
    let prepared = programs
        .iter()
        .enumerate()
        .map(|(k, &(name, text))| prepare(name, text, opts, k == 0))
        .collect::<Result<Vec<_>, _>>()?;
    let Some(first) = prepared.first() else {
        return Err(SimError::NoProgram);
    };
    let r = prepared.iter().map(|p| p.tool.radius()).fold(0.0, f64::max);
    let all_moves: Vec<&moves::Move> = prepared.iter().flat_map(|p| &p.read.moves).collect();
    let (stock, source) = choose_stock(opts, &first.head, &all_moves, r)?;
    let grid = Grid::covering(stock.lo, stock.hi, res, opts.max_cells.max(1));
    let mut map = HeightMap::new(grid, stock.top);
    let bases = line_bases(&prepared, programs)?;
    let mut reports = Vec::with_capacity(prepared.len());
    for (p, &line_base) in prepared.iter().zip(&bases) {
        let notes = program_notes(p, &grid, res, opts.max_cells);
        let w = run::walk(
            &mut map,
            &p.read.moves,
            &p.tool,
            grid.res * CHORD_FRACTION,
            p.stepdown,
            line_base,
        );
        let stock_info = StockInfo {
            lo: stock.lo,
            hi: grid.hi(),
            top: stock.top,
            resolution: grid.res,
            cells: [grid.nx, grid.ny],
            source: source.into(),
            lowest: map.min(),
        };
        reports.push(program_report(p, w, stock_info, notes));
    }
    let part = job
        .and_then(|j| j.part.as_ref().map(|p| (j, p)))
        .map(|(j, p)| compare_part(&map, p, j, &prepared, &bases, &mut reports));
    for p in &mut reports {
        p.report.findings.sort_by_key(|f| f.line);
    }
    Ok(Sequence {
        programs: reports,
        part,
        map,
    })
}

/// Reads program `name` and chooses its tool and stepdown (`first`: the
/// first program, which may take the job's tool); errors name the program.
fn prepare<'a>(
    name: &'a str,
    text: &str,
    opts: &SimOptions,
    first: bool,
) -> Result<Prepared<'a>, SimError> {
    let job = opts.job.as_ref();
    let in_program = |error: SimError| SimError::Program {
        name: name.to_string(),
        error: Box::new(error),
    };
    let head = header::read_header(text);
    let base = base_tool(job, &head, first);
    let (tool, tool_source) = choose_tool(opts, base, first).map_err(in_program)?;
    let stepdown = match opts.stepdown {
        Some(s) => Some(positive("--stepdown", s).map_err(in_program)?),
        None => match (job, base) {
            (Some(j), Some((_, "job"))) => Some(j.stepdown),
            _ => head.stepdown,
        },
    };
    Ok(Prepared {
        name,
        read: moves::read_moves(text),
        head,
        tool,
        tool_source,
        stepdown,
    })
}

/// The lines of all programs as one count (`HeightMap::last_cut`): program
/// k's line L is `bases[k]` + L. An error past `u32::MAX` lines in all.
fn line_bases(prepared: &[Prepared], programs: &[(&str, &str)]) -> Result<Vec<u32>, SimError> {
    let mut bases = Vec::with_capacity(prepared.len());
    let mut base: u64 = 0;
    for (p, &(_, text)) in prepared.iter().zip(programs) {
        bases.push(base as u32);
        let last = p.read.moves.iter().map(|m| m.line).max().unwrap_or(0);
        base += text.lines().count().max(last) as u64;
        if base > u64::from(u32::MAX) {
            return Err(SimError::TooManyLines);
        }
    }
    Ok(bases)
}

/// A program's notes: a coarser grid than asked (`res` mm, at most
/// `max_cells`), a header tool pfcam cannot model, and the first ten lines
/// GRBL would reject.
fn program_notes(p: &Prepared, grid: &Grid, res: f64, max_cells: usize) -> Vec<String> {
    let mut notes = Vec::new();
    if grid.res > res {
        notes.push(format!(
            "the stock needs more than {max_cells} cells at {res} mm: simulated at {} mm",
            grid.res
        ));
    }
    if let Some(line) = &p.head.tool_unread {
        notes.push(format!(
            "the header's `{line}` names no tool pfcam simulate models (flat, ball or bull nose end mill): not used"
        ));
    }
    for (line, e) in p.read.rejected.iter().take(10) {
        notes.push(format!(
            "line {line}: GRBL would reject it ({e}); not simulated"
        ));
    }
    if p.read.rejected.len() > 10 {
        notes.push(format!(
            "{} more rejected lines",
            p.read.rejected.len() - 10
        ));
    }
    notes
}

/// A program's report from its walk `w` over the stock `stock`.
fn program_report(
    p: &Prepared,
    w: run::Walk,
    stock: StockInfo,
    notes: Vec<String>,
) -> ProgramReport {
    ProgramReport {
        name: p.name.to_string(),
        report: Report {
            tool_diameter: p.tool.diameter(),
            tool_shape: p.tool.shape(),
            corner_radius: p.tool.corner_radius(),
            tool_source: p.tool_source.clone(),
            stepdown: p.stepdown.filter(|_| p.tool.shape() != ToolShape::Ball),
            stock,
            moves: p.read.moves.len(),
            unknown_start: p.read.unknown_start,
            rapids_into_material: w.rapids_into_material,
            worst_rapid: w.worst_rapid,
            straight_plunges: w.straight_plunges,
            steepest_entry_deg: w.steepest_entry,
            max_axial: w.max_axial,
            max_radial: w.max_radial,
            deep_slots: w.deep_slots,
            feed_length: w.feed_length,
            air_length: w.air_length,
            air_share: if w.feed_length > 0.0 {
                w.air_length / w.feed_length
            } else {
                0.0
            },
            part: None,
            findings: w.findings,
            notes,
        },
    }
}

/// The final stock against the job's part: gouges go to the findings of the
/// program whose line made them, and the worst gouge and material left name
/// their program's line (and, with several programs, the program). `bases`
/// are the programs' line bases ([`line_bases`]).
fn compare_part(
    map: &HeightMap,
    part: &PartModel,
    job: &JobFacts,
    prepared: &[Prepared],
    bases: &[u32],
    reports: &mut [ProgramReport],
) -> PartComparison {
    // Program k holds the counted lines bases[k] + 1 ..= bases[k + 1].
    let locate = |id: usize| -> (usize, usize) {
        let k = bases.partition_point(|&b| (b as usize) < id).max(1) - 1;
        (k, id - bases[k] as usize)
    };
    let several = reports.len() > 1;
    let mut gouges = Vec::new();
    let last_tool = prepared.last().map(|p| &p.tool);
    let mut cmp = part::compare(map, part, job, last_tool, &mut gouges);
    if let Some(p) = prepared
        .last()
        .filter(|p| p.tool.shape() == ToolShape::Ball)
    {
        cmp.walls = walls::ball_left_on_walls(
            part,
            &p.read.moves,
            p.tool.radius(),
            map.grid.res * CHORD_FRACTION,
        );
        if let Some(w) = cmp.walls.as_mut() {
            if several {
                w.program = Some(p.name.to_string());
            }
        }
    }
    for mut f in gouges {
        let (k, line) = locate(f.line);
        f.line = line;
        reports[k].report.findings.push(f);
    }
    for (worst, program) in [
        (&mut cmp.max_gouge, &mut cmp.max_gouge_program),
        (&mut cmp.max_left, &mut cmp.max_left_program),
        (
            &mut cmp.max_left_reachable,
            &mut cmp.max_left_reachable_program,
        ),
    ] {
        if worst.line > 0 {
            let (k, line) = locate(worst.line);
            worst.line = line;
            if several {
                *program = Some(reports[k].name.clone());
            }
        }
    }
    cmp
}

/// The stock: `--stock`, else the job's, else the header's rectangle, else the
/// XY extent of the feed moves grown by the tool radius; the top from the
/// same place, else the header's `top`, else 0.
fn choose_stock(
    opts: &SimOptions,
    head: &header::Header,
    moves: &[&moves::Move],
    r: f64,
) -> Result<(StockBox, &'static str), SimError> {
    if let Some(s) = opts.stock {
        let ok =
            s.lo.iter()
                .chain(&s.hi)
                .chain([&s.top])
                .all(|v| v.is_finite())
                && s.lo[0] < s.hi[0]
                && s.lo[1] < s.hi[1];
        if !ok {
            return Err(SimError::BadStock { stock: s });
        }
        return Ok((s, "--stock"));
    }
    if let Some(s) = opts.job.as_ref().and_then(|j| j.stock) {
        return Ok((s, "job"));
    }
    let top = head.stock_top.unwrap_or(0.0);
    if let Some([x0, y0, x1, y1]) = head.stock_rect {
        return Ok((
            StockBox {
                lo: [x0, y0],
                hi: [x1, y1],
                top,
            },
            "header",
        ));
    }
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for mv in moves.iter().filter(|m| !m.rapid) {
        let mut add = |p: [f64; 3]| {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        };
        add(mv.from);
        add(mv.to);
        if let Some((arc, [0, 1])) = mv.arc {
            for [x, y] in arc.extremes() {
                add([x, y, 0.0]);
            }
        }
    }
    if !(lo[0] <= hi[0] && lo[1] <= hi[1]) {
        return Err(SimError::NoStock);
    }
    Ok((
        StockBox {
            lo: [lo[0] - r, lo[1] - r],
            hi: [hi[0] + r, hi[1] + r],
            top,
        },
        "feed moves",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Garbage and mangled G-code simulate or fail with an error, never panic
    /// (a fixed-seed generator, so a failure is reproducible).
    #[test]
    fn never_panics_on_garbage() {
        let mut g = crate::num::testing::Lcg(0x51u64);
        let mut next = move || g.word();
        let alphabet: Vec<char> = "GXYZIJKRF0123456789.- ".chars().collect();
        let mut lines: Vec<String> = [
            "G0 X0 Y0 Z0",
            "G20",
            "G91",
            "G90",
            "G18",
            "G17",
            "G2 X1 Y0 I0 J0 F1",
            "G3 X0 Y0 I0 J0 F1",
            "G2 X5 Y5 R-3 F10",
            "G28",
            "G1 Z-3 F100",
            "G0 Z-1",
            "G3 X0 Y0 Z-50 I0.001 J0 F10",
            "G1 X99999999999 F1",
            "G2 X0 Y0 I999999999 J0 F1",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        for _ in 0..300 {
            let len = next() % 20;
            lines.push(
                (0..len)
                    .map(|_| alphabet[next() % alphabet.len()])
                    .collect(),
            );
        }
        let mut simulated = 0;
        for case in 0..40 {
            let mut text = String::new();
            for _ in 0..60 {
                text += &lines[next() % lines.len()];
                text.push('\n');
            }
            let opts = SimOptions {
                tool_diameter: Some(0.5 + (case % 4) as f64),
                resolution: [0.1, 0.5, 1e-6, 50.0][case % 4],
                max_cells: 200_000,
                stock: (case % 2 == 0).then_some(StockBox {
                    lo: [-10.0, -10.0],
                    hi: [10.0, 10.0],
                    top: 0.0,
                }),
                ..SimOptions::default()
            };
            if let Ok(sim) = simulate(&text, &opts) {
                let g = sim.map.grid;
                assert!(g.nx * g.ny <= 200_000);
                assert!(png::stock_png(&sim, "t").is_ok());
                simulated += 1;
            }
        }
        assert!(simulated >= 20, "only {simulated} of 40 programs simulated");
    }
}
