//! What the simulation found: findings with line numbers, the figures of the
//! whole program, and the comparison with the part. Serialised as JSON by the
//! CLI's `--json`.

use super::tool::{Tool, ToolShape};
use serde::Serialize;

/// What kind of thing a finding is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A `G0` that removes material (a collision at rapid speed).
    RapidIntoMaterial,
    /// A feed move entering material steeper than [`super::PLUNGE_ANGLE_DEG`]
    /// and deeper than [`super::PLUNGE_DEPTH`].
    StraightPlunge,
    /// A full-width cut (radial share ≥ [`super::SLOT_SHARE`]) deeper than the
    /// stepdown.
    SlotDeeperThanStepdown,
    /// The stock cut below the part by more than the job's tolerance.
    Gouge,
}

/// One collision or error, at one line.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Finding {
    /// 1-based line number of the move.
    pub line: usize,
    /// What it is.
    pub kind: Kind,
    /// How deep, mm: material removed by the rapid, plunge depth, slot depth,
    /// or depth below the part.
    pub depth: f64,
    /// Where (the cell centre of the deepest point), mm.
    pub x: f64,
    /// Where, mm.
    pub y: f64,
    /// In words.
    pub message: String,
}

/// The largest value of something and the line where it occurs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Worst {
    /// The value (mm, degrees or a share, as named).
    pub value: f64,
    /// 1-based line number (0: nowhere).
    pub line: usize,
}

impl Worst {
    /// Keeps the larger of itself and (`value`, `line`); the first line wins a tie.
    pub(crate) fn take(&mut self, value: f64, line: usize) {
        if value > self.value {
            *self = Worst { value, line };
        }
    }
}

/// The stock that was simulated.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StockInfo {
    /// Lower-left corner (x, y), mm.
    pub(crate) lo: [f64; 2],
    /// Upper-right corner (x, y), mm (the grid's, whole cells).
    pub(crate) hi: [f64; 2],
    /// The uncut top, mm.
    pub(crate) top: f64,
    /// Cell side, mm.
    pub(crate) resolution: f64,
    /// Cells (columns, rows).
    pub cells: [usize; 2],
    /// Where the stock came from: `--stock`, `job`, `header` or `feed moves`.
    pub source: String,
    /// Lowest height after the program, mm.
    pub(crate) lowest: f64,
}

/// The final stock against the part (with `--job`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PartComparison {
    /// What the part is measured from (e.g. `surface S2`).
    pub(crate) model: String,
    /// Cells compared (those over the part's model).
    pub cells: usize,
    /// Deepest cut below the part, mm, and the line that made it.
    pub max_gouge: Worst,
    /// When several programs were simulated: the one `max_gouge.line` is in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) max_gouge_program: Option<String>,
    /// Cells cut below the part by more than the tolerance.
    pub gouged_cells: usize,
    /// Most material left above the part, mm, and the line that last cut
    /// there (0: never cut).
    pub max_left: Worst,
    /// When several programs were simulated: the one `max_left.line` is in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_left_program: Option<String>,
    /// Most material left above what the last program's tool can reach of
    /// the part (`simulate::reach`), measured along the part's normal (the
    /// vertical height times the cosine of the slope, as a scallop is), mm,
    /// and the line that last cut there:
    /// the programs' own shortfall, without the valleys and corners the tool
    /// is too large for.
    pub max_left_reachable: Worst,
    /// When several programs were simulated: the one `max_left_reachable.line` is in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) max_left_reachable_program: Option<String>,
    /// With a ball as the last tool: the most material left along the
    /// normal on the part's walls where the ball reaches, measured in 3-D
    /// (`simulate::walls`; the height map cannot on near-vertical walls).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub walls: Option<super::walls::WallLeft>,
    /// Share of the compared cells with more than `scallop + tolerance` left.
    pub left_share_over_scallop: f64,
    /// The job's tolerance, mm.
    pub(crate) tolerance: f64,
    /// The job's scallop bound (`operation.max_scallop`), mm.
    pub(crate) scallop: f64,
    /// The job's stepover, mm.
    pub(crate) stepover: f64,
}

/// Everything `pfcam simulate` reports.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    /// Tool diameter used, mm, and where it came from.
    pub tool_diameter: f64,
    /// The tool's shape.
    pub tool_shape: ToolShape,
    /// Its corner radius, mm (0 flat, the radius for a ball).
    pub corner_radius: f64,
    /// Where the tool came from: `job`, `header`, or the flags used
    /// (`--tool-diameter`, `--tool-shape`, `--corner-radius`), followed by
    /// `job` or `header` when that gave the rest.
    pub tool_source: String,
    /// Stepdown used for the slot check, mm (`None`: not checked; always
    /// `None` for a ball end mill, which the full-width rule does not judge).
    pub stepdown: Option<f64>,
    /// The stock.
    pub stock: StockInfo,
    /// Moves simulated.
    pub moves: usize,
    /// Moves from an unknown position, not simulated.
    pub(crate) unknown_start: usize,
    /// Rapids that removed material.
    pub rapids_into_material: usize,
    /// Deepest material removal by a rapid, mm.
    pub worst_rapid: Worst,
    /// Feed moves that are straight plunges.
    pub straight_plunges: usize,
    /// Steepest entry into material (degrees from horizontal) of a
    /// descending feed move removing more than [`super::PLUNGE_DEPTH`].
    pub steepest_entry_deg: Worst,
    /// Largest axial engagement: depth of material removed under the tool by
    /// one move, mm.
    pub max_axial: Worst,
    /// Largest radial engagement: share of the tool's width in material.
    pub max_radial: Worst,
    /// Full-width cuts deeper than the stepdown.
    pub deep_slots: usize,
    /// Feed length, mm.
    pub feed_length: f64,
    /// Feed length that removed nothing, mm.
    pub air_length: f64,
    /// `air_length / feed_length` (0 without feed moves).
    pub air_share: f64,
    /// With a job: the final stock against the part.
    pub part: Option<PartComparison>,
    /// The collisions and errors, by line.
    pub findings: Vec<Finding>,
    /// Things to know (coarsened grid, lines GRBL would reject, ...).
    pub notes: Vec<String>,
}

impl Report {
    /// Whether anything makes the program unsafe or wrong: a rapid into
    /// material, a straight plunge, a slot deeper than the stepdown, a gouge.
    pub fn is_clean(&self) -> bool {
        self.findings.is_empty()
    }

    /// The figures as text, one per line (the CLI prints findings before it).
    pub fn summary(&self) -> String {
        let s = &self.stock;
        let mut t = format!(
            "stock: X{:.3}..{:.3} Y{:.3}..{:.3}, top {} mm ({}), {} x {} cells of {} mm; lowest z {:.3}\n",
            s.lo[0], s.hi[0], s.lo[1], s.hi[1], s.top, s.source, s.cells[0], s.cells[1], s.resolution, s.lowest
        );
        t += &format!(
            "tool: {} ({})\nmoves: {} simulated, {} from an unknown position\n",
            self.tool().describe(),
            self.tool_source,
            self.moves,
            self.unknown_start
        );
        t += &format!(
            "rapids into material: {} (worst {:.3} mm, line {})\n",
            self.rapids_into_material, self.worst_rapid.value, self.worst_rapid.line
        );
        t += &format!(
            "straight plunges: {}; steepest entry {:.1} deg (line {})\n",
            self.straight_plunges, self.steepest_entry_deg.value, self.steepest_entry_deg.line
        );
        t += &format!(
            "largest engagement: axial {:.3} mm (line {}), radial {:.0} % (line {})\n",
            self.max_axial.value,
            self.max_axial.line,
            100.0 * self.max_radial.value,
            self.max_radial.line
        );
        t += &match (self.stepdown, self.tool_shape) {
            (_, ToolShape::Ball) => {
                "full-width cuts: not checked (a ball end mill has no flat part)\n".into()
            }
            (Some(sd), ToolShape::Flat) => format!(
                "full-width cuts deeper than the stepdown {sd} mm: {}\n",
                self.deep_slots
            ),
            (Some(sd), ToolShape::Bull) => format!(
                "full-width cuts of the flat part deeper than the stepdown {sd} mm: {}\n",
                self.deep_slots
            ),
            (None, _) => {
                "full-width cuts: not checked (no stepdown: give --stepdown or --job)\n".into()
            }
        };
        t += &format!(
            "feed: {:.1} mm, {:.1} % in air",
            self.feed_length,
            100.0 * self.air_share
        );
        if let Some(p) = &self.part {
            t += "\n";
            t += &p.summary();
        }
        t
    }

    /// The tool simulated.
    pub(crate) fn tool(&self) -> Tool {
        let corner = (self.tool_shape == ToolShape::Bull).then_some(self.corner_radius);
        Tool::new(self.tool_shape, self.tool_diameter, corner)
            .unwrap_or_else(|_| Tool::flat_unchecked(self.tool_diameter))
    }
}

impl PartComparison {
    /// The comparison in one line (the last of [`Report::summary`]).
    pub fn summary(&self) -> String {
        let at = |program: &Option<String>, line: usize| match program {
            Some(name) => format!("{name} line {line}"),
            None => format!("line {line}"),
        };
        format!(
            "part ({}): max gouge {:.4} mm ({}), {} cell(s) below the part by more than the tolerance {} mm; max material left {:.3} mm ({}), {:.3} mm over what the last tool can reach ({}), {:.2} % of {} cells above scallop + tolerance ({} mm)",
            self.model,
            self.max_gouge.value,
            at(&self.max_gouge_program, self.max_gouge.line),
            self.gouged_cells,
            self.tolerance,
            self.max_left.value,
            at(&self.max_left_program, self.max_left.line),
            self.max_left_reachable.value,
            at(&self.max_left_reachable_program, self.max_left_reachable.line),
            100.0 * self.left_share_over_scallop,
            self.cells,
            self.scallop + self.tolerance
        ) + &self.walls.as_ref().map_or(String::new(), |w| {
            format!(
                "; on the walls, along the normal where the ball reaches: {:.3} mm left ({}, at X{:.2} Y{:.2} Z{:.3}) of {} points",
                w.left.value,
                at(&w.program, w.left.line),
                w.at[0],
                w.at[1],
                w.at[2],
                w.points
            )
        })
    }
}
