//! The walk: every move, in program order, lowers the cells under the tool
//! ([`Segment::surface_over`]) and is measured as it goes: how much material
//! it removed (axial engagement), across how much of the tool's width
//! (radial engagement), whether a rapid touched material, whether a feed move
//! went straight down into it, and how much feed length cut only air.
//!
//! The full-width rule looks at the tool's flat part: all of a flat end
//! mill, the cells within r − rc of the axis for a bull nose (a corner
//! lowers cells beside the flat part by less, and a cut half as wide as the
//! tool would otherwise span the flat part's width with them); a ball has
//! no flat part and is not judged by it.

use super::moves::Move;
use super::report::{Finding, Kind, Worst};
use super::stock::{Grid, HeightMap};
use super::tool::{Segment, Tool, ToolShape};
use super::{
    AIR_DEPTH, PLUNGE_ANGLE_DEG, PLUNGE_DEPTH, RAPID_DEPTH, SLOT_MIDDLE, SLOT_SHARE, SLOT_SLACK,
};
use rayon::prelude::*;

/// What one move did to the stock (within one band of rows, or merged).
#[derive(Clone, Copy, Debug)]
struct MoveCut {
    /// Deepest removal, mm, and where: (piece number, row, column), the first
    /// in program and scan order among equal depths.
    depth: f64,
    key: (u32, usize, usize),
    /// Smallest and largest signed offset (mm, from each piece's axis) of a
    /// cell where more than [`AIR_DEPTH`] was removed.
    off_lo: f64,
    off_hi: f64,
    /// The same, over cells where more than the slot depth (the stepdown
    /// plus [`SLOT_SLACK`]) was removed: how wide the cut is at depth.
    deep_lo: f64,
    deep_hi: f64,
    /// Smallest |offset| of such a cell: a slot is deep under the tool's
    /// middle, while slivers left at the rim by rounding (on one side here,
    /// on the other a little further, as a straight move crosses the arcs an
    /// earlier pass cut) span the width without ever reaching the middle.
    deep_mid: f64,
}

impl Default for MoveCut {
    fn default() -> Self {
        MoveCut {
            depth: 0.0,
            key: (0, 0, 0),
            off_lo: f64::INFINITY,
            off_hi: f64::NEG_INFINITY,
            deep_lo: f64::INFINITY,
            deep_hi: f64::NEG_INFINITY,
            deep_mid: f64::INFINITY,
        }
    }
}

impl MoveCut {
    /// Whether (depth, key) beats the deepest so far.
    fn deeper(&self, depth: f64, key: (u32, usize, usize)) -> bool {
        depth > self.depth || (depth == self.depth && depth > 0.0 && key < self.key)
    }

    /// Both bands' figures in one.
    fn merge(&mut self, o: &MoveCut) {
        if self.deeper(o.depth, o.key) {
            self.depth = o.depth;
            self.key = o.key;
        }
        self.off_lo = self.off_lo.min(o.off_lo);
        self.off_hi = self.off_hi.max(o.off_hi);
        self.deep_lo = self.deep_lo.min(o.deep_lo);
        self.deep_hi = self.deep_hi.max(o.deep_hi);
        self.deep_mid = self.deep_mid.min(o.deep_mid);
    }

    /// Share of the tool's width `2r` between `lo` and `hi` (0 when empty).
    fn share(lo: f64, hi: f64, r: f64) -> f64 {
        if hi >= lo {
            ((hi - lo) / (2.0 * r)).min(1.0)
        } else {
            0.0
        }
    }
}

/// The walk's running figures.
#[derive(Clone, Debug, Default)]
pub(crate) struct Walk {
    /// Collisions and errors.
    pub(crate) findings: Vec<Finding>,
    /// Rapids that removed more than [`RAPID_DEPTH`].
    pub(crate) rapids_into_material: usize,
    /// Deepest rapid removal.
    pub(crate) worst_rapid: Worst,
    /// Straight plunges.
    pub(crate) straight_plunges: usize,
    /// Steepest entry, degrees.
    pub(crate) steepest_entry: Worst,
    /// Largest axial engagement, mm.
    pub(crate) max_axial: Worst,
    /// Largest radial share.
    pub(crate) max_radial: Worst,
    /// Full-width cuts deeper than the stepdown.
    pub(crate) deep_slots: usize,
    /// Feed length, mm.
    pub(crate) feed_length: f64,
    /// Feed length in air, mm.
    pub(crate) air_length: f64,
}

/// At most this many bands of rows are cut at once (rayon, one per thread),
/// each band running every move over its own rows: cells are independent and
/// ties are broken by program and scan order, so the result is the same as
/// one pass in program order, on any number of threads.
pub(crate) const MAX_BANDS: usize = 8;

/// Runs `moves` over `map` with `tool`; arcs are cut into chords within
/// `chord_tol` mm; `stepdown` (mm) enables the slot check (not for a ball);
/// a cell lowered by line L records `line_base + L` as its last cut (the
/// lines of the programs simulated before on the same stock come first).
pub(crate) fn walk(
    map: &mut HeightMap,
    moves: &[Move],
    tool: &Tool,
    chord_tol: f64,
    stepdown: Option<f64>,
    line_base: u32,
) -> Walk {
    let g = map.grid;
    let top = map.top;
    let r = tool.radius();
    // The slot rule's half width: the flat part's (none for a ball).
    let slot_r = (tool.shape() != ToolShape::Ball).then(|| tool.flat_radius());
    let stepdown = stepdown.filter(|_| slot_r.is_some());
    let slot_depth = stepdown.map_or(f64::INFINITY, |sd| sd + SLOT_SLACK);
    // Deep cells of a bull nose count only under its flat part.
    let deep_within = (tool.shape() == ToolShape::Bull).then(|| tool.flat_radius());
    let bands = rayon::current_num_threads().clamp(1, MAX_BANDS);
    let rows_per = g.ny.div_ceil(bands).max(1);
    let chunk = rows_per * g.nx;
    let bands: Vec<BandResult> = map
        .h
        .par_chunks_mut(chunk)
        .zip(map.last_cut.par_chunks_mut(chunk))
        .enumerate()
        .map(|(b, (h, last_cut))| {
            let j0 = b * rows_per;
            let mut band = Band {
                grid: g,
                j0,
                j1: (j0 + rows_per).min(g.ny) - 1,
                top,
                slot_depth,
                deep_within,
                tool: *tool,
                line_base,
                h,
                last_cut,
            };
            band.walk(moves, chord_tol)
        })
        .collect();
    let mut cuts = vec![MoveCut::default(); moves.len()];
    let mut pieces_cutting = Vec::new();
    for band in &bands {
        for (m, c) in &band.cuts {
            cuts[*m].merge(c);
        }
        if pieces_cutting.len() < band.cutting.len() {
            pieces_cutting.resize(band.cutting.len(), false);
        }
        for (k, &c) in band.cutting.iter().enumerate() {
            pieces_cutting[k] |= c;
        }
    }
    let mut w = Walk::default();
    let mut piece = 0;
    for (mv, cut) in moves.iter().zip(&cuts) {
        let mut air = 0.0;
        for s in mv.pieces(chord_tol) {
            if !pieces_cutting.get(piece).copied().unwrap_or(false) {
                air += s.len();
            }
            piece += 1;
        }
        let (_, j, i) = cut.key;
        let at = [g.cx(i), g.cy(j)];
        w.record(mv, cut, at, air, r, slot_r.zip(stepdown));
    }
    w
}

/// What one band found: the moves that removed material in it, and for every
/// piece whether it removed more than [`AIR_DEPTH`] there.
struct BandResult {
    cuts: Vec<(usize, MoveCut)>,
    cutting: Vec<bool>,
}

/// Rows `j0..=j1` of the stock.
struct Band<'a> {
    grid: Grid,
    j0: usize,
    j1: usize,
    top: f64,
    /// Removal deeper than this (mm) counts toward a slot's width.
    slot_depth: f64,
    /// If set, only cells within this distance (mm) of the piece's XY
    /// segment count toward it (a bull nose's flat part).
    deep_within: Option<f64>,
    /// The tool.
    tool: Tool,
    /// Added to the line numbers recorded in `last_cut`.
    line_base: u32,
    /// Heights of rows j0..=j1.
    h: &'a mut [f64],
    /// Lines that last cut them.
    last_cut: &'a mut [u32],
}

impl Band<'_> {
    fn walk(&mut self, moves: &[Move], chord_tol: f64) -> BandResult {
        let r = self.tool.radius();
        let flat = self.tool.shape() == ToolShape::Flat;
        let mut out = BandResult {
            cuts: Vec::new(),
            cutting: Vec::new(),
        };
        // Where the last piece ended: every cell within r of it is at or below
        // its z.
        let mut last_end: Option<[f64; 3]> = None;
        for (m, mv) in moves.iter().enumerate() {
            let mut cut = MoveCut::default();
            for s in mv.pieces(chord_tol) {
                // A piece that starts where the last one ended and does not
                // descend cannot lower the cells within r of its start that
                // it moves away from: the last piece left each at or below
                // z(0) + p(ρ(0)), and z(t) is not lower, nor ρ(t) smaller
                // behind the start. For a flat end mill (p = 0) that is the
                // whole start disk, left out of the rows' ranges; a curved
                // end moving on brings its lower middle over the cells ahead
                // of its start, so only the half behind is skipped, cell by
                // cell.
                let from_last = last_end == Some(s.a) && s.b[2] >= s.a[2];
                let skip = match (from_last, flat) {
                    (false, _) => Skip::None,
                    (true, true) => Skip::Disk,
                    (true, false) => Skip::HalfDisk,
                };
                let piece = out.cutting.len() as u32;
                let removed = self.cut_segment(&s, r, mv.line, skip, piece, &mut cut);
                out.cutting.push(removed > AIR_DEPTH);
                last_end = Some(s.b);
            }
            if cut.depth > 0.0 {
                out.cuts.push((m, cut));
            }
        }
        out
    }

    /// Lowers every cell of the band under the tool along `s`, adds to `cut`
    /// and returns the most it removed from one cell.
    fn cut_segment(
        &mut self,
        s: &Segment,
        r: f64,
        line: usize,
        skip: Skip,
        piece: u32,
        cut: &mut MoveCut,
    ) -> f64 {
        let zmin = s.z_min();
        // Heights never rise above the top: a piece entirely above it cuts nothing.
        if zmin >= self.top {
            return 0.0;
        }
        let g = self.grid;
        let (ylo, yhi) = (s.a[1].min(s.b[1]) - r, s.a[1].max(s.b[1]) + r);
        let Some((j0, j1)) = g.rows(ylo, yhi) else {
            return 0.0;
        };
        let (j0, j1) = (j0.max(self.j0), j1.min(self.j1));
        if j0 > j1 {
            return 0.0;
        }
        let axis = Axis::new(s);
        let mut removed = 0.0f64;
        let (dx, dy) = (s.b[0] - s.a[0], s.b[1] - s.a[1]);
        let rr2 = (r - RIM) * (r - RIM);
        for j in j0..=j1 {
            let cy = g.cy(j);
            let row = (j - self.j0) * g.nx;
            for (i0, i1) in row_ranges(&g, s, cy, r, skip == Skip::Disk)
                .into_iter()
                .flatten()
            {
                for i in i0..=i1 {
                    let k = row + i;
                    // No point of the piece is lower than the cell: nothing to
                    // cut (the common case where pieces overlap).
                    if self.h[k] <= zmin {
                        continue;
                    }
                    let cx = g.cx(i);
                    if skip == Skip::HalfDisk {
                        let (ux, uy) = (cx - s.a[0], cy - s.a[1]);
                        if ux * dx + uy * dy <= 0.0 && ux * ux + uy * uy <= rr2 {
                            continue;
                        }
                    }
                    let Some(zb) = s.surface_over(cx, cy, &self.tool) else {
                        continue;
                    };
                    let d = self.h[k] - zb;
                    if d <= 0.0 {
                        continue;
                    }
                    self.h[k] = zb;
                    self.last_cut[k] = self.line_base + line as u32;
                    removed = removed.max(d);
                    if cut.deeper(d, (piece, j, i)) {
                        cut.depth = d;
                        cut.key = (piece, j, i);
                    }
                    if d > AIR_DEPTH {
                        let o = axis.offset(cx, cy);
                        cut.off_lo = cut.off_lo.min(o);
                        cut.off_hi = cut.off_hi.max(o);
                        if d > self.slot_depth
                            && self.deep_within.is_none_or(|w| s.xy_dist(cx, cy) <= w)
                        {
                            cut.deep_lo = cut.deep_lo.min(o);
                            cut.deep_hi = cut.deep_hi.max(o);
                            cut.deep_mid = cut.deep_mid.min(o.abs());
                        }
                    }
                }
            }
        }
        removed
    }
}

/// Which cells of a piece's start disk the walk may leave out (see
/// `Band::walk`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Skip {
    /// None.
    None,
    /// All (a flat end mill).
    Disk,
    /// Those behind the piece's direction (a curved end).
    HalfDisk,
}

/// Slack (mm) by which the skipped start disk is shrunk, so that a cell centre
/// on its rim, which rounding may have kept out of the last piece, is visited.
const RIM: f64 = 1e-9;

/// The columns of row `cy` under the piece, as up to two ranges: the piece's
/// span, less the start disk's interval when `skip_start`.
fn row_ranges(
    g: &Grid,
    s: &Segment,
    cy: f64,
    r: f64,
    skip_start: bool,
) -> [Option<(usize, usize)>; 2] {
    let Some((xa, xb)) = s.span_at(cy, r) else {
        return [None, None];
    };
    let dy = cy - s.a[1];
    let rr = r - RIM;
    if !skip_start || dy.abs() >= rr {
        return [g.cols(xa, xb), None];
    }
    let w = (rr * rr - dy * dy).sqrt();
    let (da, db) = (s.a[0] - w, s.a[0] + w);
    // Columns strictly outside [da, db]: centres below da or above db.
    let left = g.cols(xa, da).and_then(|(i0, i1)| {
        if g.cx(i1) >= da {
            i1.checked_sub(1).map(|e| (i0, e))
        } else {
            Some((i0, i1))
        }
    });
    let right = g.cols(db, xb).map(|(i0, i1)| {
        if g.cx(i0) <= db {
            (i0 + 1, i1)
        } else {
            (i0, i1)
        }
    });
    let valid = |x: Option<(usize, usize)>| x.filter(|&(a, b)| a <= b);
    [valid(left), valid(right)]
}

impl Walk {
    fn push(&mut self, mv: &Move, kind: Kind, depth: f64, at: [f64; 2], message: String) {
        self.findings.push(Finding {
            line: mv.line,
            kind,
            depth,
            x: at[0],
            y: at[1],
            message,
        });
    }

    /// The findings and figures of one move; `slot` is the slot rule's half
    /// width and stepdown, when it applies.
    fn record(
        &mut self,
        mv: &Move,
        cut: &MoveCut,
        at: [f64; 2],
        air: f64,
        r: f64,
        slot: Option<(f64, f64)>,
    ) {
        if mv.rapid {
            if cut.depth > RAPID_DEPTH {
                self.rapids_into_material += 1;
                self.worst_rapid.take(cut.depth, mv.line);
                let msg = format!(
                    "rapid (G0) into material: removes {:.3} mm at X{:.3} Y{:.3}",
                    cut.depth, at[0], at[1]
                );
                self.push(mv, Kind::RapidIntoMaterial, cut.depth, at, msg);
            }
            return;
        }
        let len = mv_length(mv);
        self.feed_length += len;
        self.air_length += air.min(len);
        self.max_axial.take(cut.depth, mv.line);
        let radial = MoveCut::share(cut.off_lo, cut.off_hi, r);
        self.max_radial.take(radial, mv.line);
        let angle = entry_angle_deg(mv);
        if cut.depth > PLUNGE_DEPTH {
            self.steepest_entry.take(angle, mv.line);
            if angle > PLUNGE_ANGLE_DEG {
                self.straight_plunges += 1;
                let msg = format!(
                    "straight plunge: enters {:.3} mm of material at {:.0} deg from horizontal (more than {PLUNGE_ANGLE_DEG} deg) at X{:.3} Y{:.3}",
                    cut.depth, angle, at[0], at[1]
                );
                self.push(mv, Kind::StraightPlunge, cut.depth, at, msg);
            }
        }
        if let Some((w, sd)) = slot {
            // Full width at depth: more than the stepdown removed across
            // SLOT_SHARE of the tool's flat part (a sliver at the rim deeper
            // than the stepdown, left by rounding, is not a slot).
            let deep = MoveCut::share(cut.deep_lo, cut.deep_hi, w);
            if deep >= SLOT_SHARE && cut.deep_mid <= SLOT_MIDDLE * w && cut.depth > sd + SLOT_SLACK
            {
                self.deep_slots += 1;
                let of = if w < r {
                    "the tool's flat part"
                } else {
                    "the tool"
                };
                let msg = format!(
                    "full-width cut ({:.0} % of {of} deeper than the stepdown {sd} mm), {:.3} mm deep",
                    100.0 * deep,
                    cut.depth
                );
                self.push(mv, Kind::SlotDeeperThanStepdown, cut.depth, at, msg);
            }
        }
    }
}

/// The move's true length, mm (an arc by its helix length).
fn mv_length(mv: &Move) -> f64 {
    match mv.arc {
        Some((arc, [a0, a1])) => {
            let lin = 3 - a0 - a1;
            arc.length(mv.to[lin] - mv.from[lin])
        }
        None => Segment {
            a: mv.from,
            b: mv.to,
        }
        .len(),
    }
}

/// The coordinates' rounding in the programs pfcam writes, mm: a move's
/// descent is known to this much.
pub const Z_ROUNDING: f64 = 0.001;

/// How steeply a move descends, degrees from horizontal: atan(−Δz / XY length)
/// (an arc's XY length is r·sweep); 0 for a move that does not descend, 90 for
/// a vertical one. A sloped move's descent is taken less [`Z_ROUNDING`]: a
/// ramp's 9 µm step, rounded to 1 µm in Z, would otherwise read as 6°
/// (mfs-mould.rough.nc) whatever the ramp's angle; a real plunge, vertical
/// or steep over more than a few µm, reads as before.
pub(crate) fn entry_angle_deg(mv: &Move) -> f64 {
    let dz = mv.from[2] - mv.to[2];
    if dz <= 0.0 {
        return 0.0;
    }
    let xy = match mv.arc {
        Some((arc, [a0, a1])) if 3 - a0 - a1 == 2 => arc.length(0.0),
        _ => (mv.to[0] - mv.from[0]).hypot(mv.to[1] - mv.from[1]),
    };
    if xy <= 0.0 {
        return 90.0;
    }
    (dz - Z_ROUNDING).max(0.0).atan2(xy).to_degrees()
}

/// A piece's XY direction, for the signed offset of a cell from its axis.
struct Axis {
    a: [f64; 2],
    /// Unit direction (0 for a move without XY length).
    u: [f64; 2],
}

impl Axis {
    fn new(s: &Segment) -> Axis {
        let (dx, dy) = (s.b[0] - s.a[0], s.b[1] - s.a[1]);
        let l = (dx * dx + dy * dy).sqrt();
        let u = if l < 1e-9 {
            [0.0, 0.0]
        } else {
            [dx / l, dy / l]
        };
        Axis {
            a: [s.a[0], s.a[1]],
            u,
        }
    }

    /// Signed distance of (x, y) from the axis line, left positive.
    fn offset(&self, x: f64, y: f64) -> f64 {
        self.u[0] * (y - self.a[1]) - self.u[1] * (x - self.a[0])
    }
}
