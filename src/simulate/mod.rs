//! `pfcam simulate`: a machinist's dry run of a G-code file on a height-map
//! stock, written independently of the path generator (it reads G-code text,
//! never a `Toolpath`).
//!
//! Every move removes material ([`run`]): `G0`, `G1`, `G2`/`G3` (I/J/K or R,
//! helical), each arc cut into chords within [`CHORD_FRACTION`] of the
//! resolution. The tool is a flat end mill of radius r; along a straight piece
//! each cell centre within r of the tool's axis is lowered to the lowest z the
//! tool bottom has over it ([`tool`], exact: the quadratic for the parameter
//! interval). The rules of the findings:
//! - a rapid that removes more than [`RAPID_DEPTH`] touches material;
//! - a feed move that removes more than [`PLUNGE_DEPTH`] of material while
//!   descending steeper than [`PLUNGE_ANGLE_DEG`] from horizontal (Δz over its
//!   XY length) is a straight plunge;
//! - axial engagement of a move: the deepest material it removes under the
//!   tool; radial engagement: the spread, across the move's direction, of the
//!   cells where it removes more than [`AIR_DEPTH`], over the tool diameter;
//!   a move whose cells cut deeper than stepdown + [`SLOT_SLACK`] span at
//!   least [`SLOT_SHARE`] of the tool width, and reach within [`SLOT_MIDDLE`]
//!   of the radius from its axis, is a full-width cut deeper than the
//!   stepdown;
//! - feed length in air: pieces that remove at most [`AIR_DEPTH`];
//! - with a job: cells cut below the part's own model by more than the
//!   tolerance are gouges ([`part`]).
//!
//! The library never prints; [`simulate`] returns a [`Simulation`] (the
//! [`Report`] and the final [`HeightMap`]), and [`png::stock_png`] draws it.

pub mod header;
pub mod moves;
pub mod part;
pub mod png;
pub mod report;
pub mod run;
pub mod stock;
pub mod tool;
mod verify;

pub use part::{job_facts, JobFacts, PartModel};
pub use report::{Finding, Kind, PartComparison, Report, StockInfo, Worst};
pub use stock::{Grid, HeightMap};
pub use verify::{verify_program, UnsafeProgram};

/// A rapid removing more than this (mm) touches material: far below a chip,
/// above the rounding of 3-decimal coordinates' binary values.
pub const RAPID_DEPTH: f64 = 0.001;
/// A feed move entering more material than this (mm) steeper than
/// [`PLUNGE_ANGLE_DEG`] is a straight plunge (issue 11's 0.05 mm).
pub const PLUNGE_DEPTH: f64 = 0.05;
/// Entry angles steeper than this (degrees from horizontal) are plunges: a
/// ramp is a few degrees (pfcam's `tool.ramp_angle`), a straight plunge 90.
pub const PLUNGE_ANGLE_DEG: f64 = 45.0;
/// A piece removing at most this (mm) cuts air, and such cells do not count
/// for radial engagement.
pub const AIR_DEPTH: f64 = 0.001;
/// A cut whose removed cells span at least this share of the tool diameter is
/// full width. Cell centres can lie at most r − res/2 off the axis, so a slot
/// spans 1 − res/(2r) of it; 0.9 keeps slots at resolutions up to 0.1·d.
pub const SLOT_SHARE: f64 = 0.9;
/// Slack over the stepdown (mm) before a full-width cut is too deep (the
/// stepdown is reached exactly by design).
pub const SLOT_SLACK: f64 = 0.01;

/// A full-width cut must also be deeper than the slot depth within this share
/// of the radius from the tool's axis (a slot is deep under the middle of the
/// tool; rim slivers are not).
pub const SLOT_MIDDLE: f64 = 0.5;
/// Chords of arcs stay within this fraction of the resolution of the arc.
pub const CHORD_FRACTION: f64 = 0.05;
/// Default cell side, mm.
pub const DEFAULT_RESOLUTION: f64 = 0.1;
/// The most cells a stock gets (8 bytes of height and 4 of line each); a
/// larger stock is simulated on coarser cells, with a note.
pub const MAX_CELLS: usize = 16_000_000;

/// What can stop a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// No tool diameter from the flags, the job or the file's header.
    #[error("no tool diameter: give --tool-diameter MM or --job JOB.toml (the file's header does not name a tool)")]
    NoTool,
    /// Nothing tells where the stock is.
    #[error("no feed move from a known position and no stock given: nothing to simulate (give --stock X0,Y0,X1,Y1,TOP)")]
    NoStock,
    /// An option out of range.
    #[error("{0}")]
    Invalid(String),
    /// The part could not be modelled from the job.
    #[error("the part of the job: {0}")]
    Part(String),
    /// The PNG could not be encoded.
    #[error("drawing the stock: {0}")]
    Png(String),
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
            stepdown: None,
            job: None,
            max_cells: MAX_CELLS,
        }
    }
}

/// A finished simulation: the report and the final stock.
#[derive(Clone, Debug)]
pub struct Simulation {
    /// The figures and findings.
    pub report: Report,
    /// The stock after the program.
    pub map: HeightMap,
}

fn positive(name: &str, v: f64) -> Result<f64, SimError> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(SimError::Invalid(format!(
            "{name} must be a positive number of mm, got {v}"
        )))
    }
}

/// Simulates the program `text` (see the module docs).
pub fn simulate(text: &str, opts: &SimOptions) -> Result<Simulation, SimError> {
    let res = positive("--resolution", opts.resolution)?;
    let head = header::read_header(text);
    let job = opts.job.as_ref();
    let (diameter, tool_source) = match (opts.tool_diameter, job, head.tool_diameter) {
        (Some(d), _, _) => (positive("--tool-diameter", d)?, "--tool-diameter"),
        (None, Some(j), _) => (j.tool_diameter, "job"),
        (None, None, Some(d)) => (d, "header"),
        (None, None, None) => return Err(SimError::NoTool),
    };
    let r = diameter / 2.0;
    let stepdown = match opts.stepdown {
        Some(s) => Some(positive("--stepdown", s)?),
        None => job.map(|j| j.stepdown).or(head.stepdown),
    };
    let read = moves::read_moves(text);
    let (stock, source) = choose_stock(opts, &head, &read.moves, r)?;
    let grid = Grid::covering(stock.lo, stock.hi, res, opts.max_cells.max(1));
    let mut notes = Vec::new();
    if grid.res > res {
        notes.push(format!(
            "the stock needs more than {} cells at {res} mm: simulated at {} mm",
            opts.max_cells, grid.res
        ));
    }
    for (line, e) in read.rejected.iter().take(10) {
        notes.push(format!(
            "line {line}: GRBL would reject it ({e}); not simulated"
        ));
    }
    if read.rejected.len() > 10 {
        notes.push(format!("{} more rejected lines", read.rejected.len() - 10));
    }
    let mut map = HeightMap::new(grid, stock.top);
    let w = run::walk(
        &mut map,
        &read.moves,
        r,
        grid.res * CHORD_FRACTION,
        stepdown,
    );
    let mut findings = w.findings;
    let part = job
        .and_then(|j| j.part.as_ref().map(|p| (j, p)))
        .map(|(j, p)| part::compare(&map, p, j, &mut findings));
    findings.sort_by_key(|f| f.line);
    let report = Report {
        tool_diameter: diameter,
        tool_source: tool_source.into(),
        stepdown,
        stock: StockInfo {
            lo: stock.lo,
            hi: grid.hi(),
            top: stock.top,
            resolution: grid.res,
            cells: [grid.nx, grid.ny],
            source: source.into(),
            lowest: map.min(),
        },
        moves: read.moves.len(),
        unknown_start: read.unknown_start,
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
        part,
        findings,
        notes,
    };
    Ok(Simulation { report, map })
}

/// The stock: `--stock`, else the job's, else the header's rectangle, else the
/// XY extent of the feed moves grown by the tool radius; the top from the
/// same place, else the header's `top`, else 0.
fn choose_stock(
    opts: &SimOptions,
    head: &header::Header,
    moves: &[moves::Move],
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
            return Err(SimError::Invalid(format!(
                "--stock: X0 < X1 and Y0 < Y1 must be finite numbers, got {},{},{},{},{}",
                s.lo[0], s.lo[1], s.hi[0], s.hi[1], s.top
            )));
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
        let mut seed: u64 = 0x51u64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as usize
        };
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
