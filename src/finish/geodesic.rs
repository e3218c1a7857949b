//! Constant-scallop passes: the level sets of the distance on S2 from the
//! wall's top edge.
//!
//! Passes along equipotentials Γ(s) lie Δs/|∇u| apart across the wall, and
//! |∇u| varies along one Γ(s) by a factor of 3 to 13 on a lettered sign (its
//! bays and the saddles of u between letters, where |∇u| → 0): spaced for
//! the widest place, whole equipotentials cut most of the wall several times
//! over. The distance σ(p) on S2 from the top edge (the shortest path on the
//! surface) has |∇_S σ| = 1, so its level sets σ = k·w lie exactly w apart on
//! the surface everywhere: every point of the wall between levels k and k + 1
//! is at most w/2 from one of them, and the scallop between them is the
//! bound's. Where the wall is shorter than k·w a level ends on the wall's
//! foot: such a pass is an open arc.
//!
//! σ is computed by Dijkstra's algorithm on a grid of S2's heights z =
//! φ(u(x, y)) with 16 neighbours (steps (1, 0), (1, 1) and (2, 1) and their
//! turns), each edge the straight chord between two nodes in 3-D. A path
//! along grid edges is never shorter than the geodesic it stands for, so σ is
//! over-estimated (by at most 2.7 % on a plane, the 16-neighbour stencil's
//! worst direction) and the levels lie at most w apart: the scallop errs on
//! the side of the bound.

use crate::field::isolines::Grid;
use crate::geometry::Vec2;
use crate::levels::DepthProfile;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

/// Grid spacing of σ, mm (the finishing mesh's, so the level sets place the
/// passes to a few micrometres).
pub(crate) const SPACING: f64 = 0.1;

/// The 16 neighbours of a node: (1, 0), (1, 1), (2, 1) and their turns and
/// reflections.
const STEPS: [(i64, i64); 16] = [
    (1, 0),
    (-1, 0),
    (0, 1),
    (0, -1),
    (1, 1),
    (1, -1),
    (-1, 1),
    (-1, -1),
    (2, 1),
    (2, -1),
    (-2, 1),
    (-2, -1),
    (1, 2),
    (1, -2),
    (-1, 2),
    (-1, -2),
];

/// Where a node of the grid lies on S2.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Part {
    /// The flat top (a boss's letters, a mould's rim and beyond): σ = 0.
    Top,
    /// The wall between the top edge and the foot.
    Wall,
    /// The floor past the foot: no σ.
    Floor,
}

/// σ on a grid: the distance on S2 from the top edge, +∞ on the floor.
#[derive(Clone, Debug)]
pub(crate) struct Distance {
    origin: Vec2,
    h: f64,
    nx: usize,
    ny: usize,
    d: Vec<f64>,
    /// u at the nodes as sampled (not held to φ's range: a level's crossing
    /// of an edge from a top node reads where u passes the top edge's s).
    u: Vec<f64>,
    /// S2's height at [`Z_TABLE`] + 1 values of u evenly over φ's range.
    z_table: Vec<f64>,
    /// φ's range of s.
    range: (f64, f64),
    /// The top edge's s (the end of φ's range at the top).
    s_top: f64,
    /// The least and greatest σ over the corners of the cells of each run
    /// of [`CHUNK`] cells along a row that have a σ at all four corners
    /// (row-major, `chunks_per_row` a row; (+∞, −∞) if none has): a level
    /// crosses none of a run's cells unless it lies in that range.
    chunks: Vec<(f64, f64)>,
    chunks_per_row: usize,
}

/// Cells along a row that [`Distance::segments`] skips together when a level
/// misses their σ range (a level crosses a band a few cells wide, and a
/// scan of every cell for each of a hundred levels was a third of
/// mfs-mould's compute time).
const CHUNK: usize = 32;

/// Intervals of the table of S2's height over φ's range that a level's
/// crossing of a grid edge reads.
const Z_TABLE: usize = 4096;
/// Pieces an edge is cut into to measure its length on S2.
const EDGE_PIECES: usize = 16;

/// One pass curve: closed (the first point not repeated) or an open arc.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Curve {
    /// The points in order.
    pub(crate) pts: Vec<Vec2>,
    /// Whether the last point joins the first.
    pub(crate) closed: bool,
    /// The s each point stands for (a level of σ: u where its crossing of a
    /// grid edge lies, u linear along the edge), one per point; empty on an
    /// equipotential. On a near-vertical wall a point's height is far
    /// better known than its place in plan (0.01 mm across is 0.2 mm up on
    /// an 87° wall), so the finisher moves each point onto Γ(s) for its s.
    pub(crate) s: Vec<f64>,
}

impl Curve {
    /// A closed curve.
    pub(crate) fn closed(pts: Vec<Vec2>) -> Curve {
        Curve {
            pts,
            closed: true,
            s: Vec::new(),
        }
    }

    /// Its length in XY, mm.
    pub(crate) fn length(&self) -> f64 {
        let n = self.pts.len();
        let chords = if self.closed { n } else { n.saturating_sub(1) };
        (0..chords)
            .map(|i| self.pts[i].dist(self.pts[(i + 1) % n]))
            .sum()
    }
}

impl Distance {
    /// σ over `grid` (u at its nodes, 1 inside the material), for the wall
    /// of φ = `profile` from its top edge: z at a node is `z_of(u)` with u
    /// held to φ's range; `cavity` mirrors which end of the range is the top;
    /// `corner` is the cutter's corner radius (see `dijkstra`).
    pub(crate) fn from_top_edge(
        grid: &Grid,
        profile: &DepthProfile,
        (cavity, corner): (bool, f64),
        z_of: &dyn Fn(f64) -> f64,
    ) -> Distance {
        let (lo, hi) = profile.s_range();
        let part = |u: f64| {
            let (top, floor) = if cavity {
                (u <= lo, u >= hi)
            } else {
                (u >= hi, u <= lo)
            };
            if top {
                Part::Top
            } else if floor {
                Part::Floor
            } else {
                Part::Wall
            }
        };
        let parts: Vec<Part> = grid.values.iter().map(|&u| part(u)).collect();
        // z of the top and the floor once: there u is held to the range's end.
        let (z_lo, z_hi) = (z_of(lo), z_of(hi));
        let z: Vec<f64> = grid
            .values
            .iter()
            .map(|&u| {
                let u = u.clamp(lo, hi);
                if u == lo {
                    z_lo
                } else if u == hi {
                    z_hi
                } else {
                    z_of(u)
                }
            })
            .collect();
        let s_top = if cavity { lo } else { hi };
        let d = dijkstra(
            (grid.nx, grid.ny, grid.h),
            &parts,
            (&z, &grid.values, s_top),
            corner,
        );
        let z_table = (0..=Z_TABLE)
            .map(|k| z_of(lo + (hi - lo) * k as f64 / Z_TABLE as f64))
            .collect();
        let (chunks, chunks_per_row) = chunk_ranges(&d, grid.nx, grid.ny);
        Distance {
            origin: grid.origin,
            h: grid.h,
            nx: grid.nx,
            ny: grid.ny,
            d,
            chunks,
            chunks_per_row,
            u: grid.values.clone(),
            z_table,
            range: (lo, hi),
            s_top,
        }
    }

    /// The largest σ on the wall, mm (0 if it has none).
    pub(crate) fn max(&self) -> f64 {
        self.d
            .iter()
            .copied()
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max)
    }

    fn point(&self, i: usize, j: usize) -> Vec2 {
        Vec2::new(
            self.origin.x + self.h * i as f64,
            self.origin.y + self.h * j as f64,
        )
    }

    /// The level set σ = `c` in the cells whose four corners have a σ (top or
    /// wall), by marching squares with linear interpolation along the cell
    /// edges: closed curves, and open arcs that end where the level meets a
    /// cell with a corner on the floor.
    pub(crate) fn level(&self, c: f64) -> Vec<Curve> {
        let segs = self.segments(c);
        chain(&segs)
            .into_iter()
            .map(|(edges, closed)| {
                let (pts, s) = edges.iter().map(|&e| self.crossing(e, c)).unzip();
                Curve { pts, closed, s }
            })
            .collect()
    }

    /// S2's height where u = `u` (the table, linearly between entries).
    fn z_at(&self, u: f64) -> f64 {
        let (lo, hi) = self.range;
        let x = if hi > lo {
            ((u - lo) / (hi - lo)).clamp(0.0, 1.0) * Z_TABLE as f64
        } else {
            0.0
        };
        let k = (x.floor() as usize).min(Z_TABLE - 1);
        let f = x - k as f64;
        self.z_table[k] * (1.0 - f) + self.z_table[k + 1] * f
    }

    /// Where the level crosses grid edge `e` (see [`Distance::edge`]): the
    /// share (c − σa)/(σb − σa) of the edge's length on S2 from its end a,
    /// that length measured over [`EDGE_PIECES`] pieces with u linear along
    /// the edge (smooth on a grid step) and z = φ(u) (not: a near-vertical
    /// wall crosses one 0.1 mm edge in millimetres of height, and a share of
    /// the edge in plan put the levels up to 0.5 mm apart in z where σ said
    /// 0.356).
    ///
    /// A top node (σ = 0) stands for σ = −(the edge's flat part, from it to
    /// where u passes the top edge's s), as [`dijkstra`] measures σ from
    /// that point: so the level lies c along S2 from the top edge.
    fn crossing(&self, e: usize, c: f64) -> (Vec2, f64) {
        let (a, b) = self.edge(e);
        let (ka, kb) = (a.1 * self.nx + a.0, b.1 * self.nx + b.0);
        let (ua, ub) = (self.u[ka], self.u[kb]);
        let flat = |d: f64, u: f64, other: f64| {
            if d == 0.0 {
                -self.h * top_share(u, other, self.s_top)
            } else {
                d
            }
        };
        let (da, db) = (flat(self.d[ka], ua, ub), flat(self.d[kb], ub, ua));
        let f = if db != da { (c - da) / (db - da) } else { 0.5 };
        let f = f.clamp(0.0, 1.0);
        let step = self.h / EDGE_PIECES as f64;
        let mut len = [0.0; EDGE_PIECES + 1];
        let mut z0 = self.z_at(ua);
        for k in 1..=EDGE_PIECES {
            let z1 = self.z_at(ua + (ub - ua) * k as f64 / EDGE_PIECES as f64);
            len[k] = len[k - 1] + step.hypot(z1 - z0);
            z0 = z1;
        }
        let target = f * len[EDGE_PIECES];
        let k = len.partition_point(|&l| l < target).clamp(1, EDGE_PIECES);
        let piece = len[k] - len[k - 1];
        let within = if piece > 0.0 {
            (target - len[k - 1]) / piece
        } else {
            0.0
        };
        let t = ((k - 1) as f64 + within.clamp(0.0, 1.0)) / EDGE_PIECES as f64;
        let (lo, hi) = self.range;
        (
            self.point(a.0, a.1).lerp(self.point(b.0, b.1), t),
            (ua + (ub - ua) * t).clamp(lo, hi),
        )
    }

    /// The nodes at the ends of edge `e`: 2k is the horizontal edge from node
    /// k, 2k + 1 the vertical one.
    fn edge(&self, e: usize) -> ((usize, usize), (usize, usize)) {
        let k = e / 2;
        let (i, j) = (k % self.nx, k / self.nx);
        if e % 2 == 0 {
            ((i, j), (i + 1, j))
        } else {
            ((i, j), (i, j + 1))
        }
    }

    /// The level's segments, each a pair of the edges it joins, cell by cell
    /// in row order (a saddle cell split as its centre's average says); the
    /// runs of cells whose σ range misses `c` are skipped whole.
    fn segments(&self, c: f64) -> Vec<[usize; 2]> {
        let nx = self.nx;
        let mut out = Vec::new();
        for j in 0..self.ny.saturating_sub(1) {
            for (q, &(lo, hi)) in self.chunks[j * self.chunks_per_row..][..self.chunks_per_row]
                .iter()
                .enumerate()
            {
                if !(lo < c && c <= hi) {
                    continue;
                }
                for i in q * CHUNK..((q + 1) * CHUNK).min(nx - 1) {
                    let (pair, n) = self.cell(j * nx + i, c);
                    out.extend_from_slice(&pair[..n]);
                }
            }
        }
        out
    }

    /// The level's segments in the cell whose lower-left node is `k` (the
    /// first `n` of the pair): none unless σ is finite at its four corners.
    fn cell(&self, k: usize, c: f64) -> ([[usize; 2]; 2], usize) {
        let nx = self.nx;
        let v = [self.d[k], self.d[k + 1], self.d[k + nx + 1], self.d[k + nx]];
        if v.iter().any(|x| !x.is_finite()) {
            return ([[0, 0]; 2], 0);
        }
        // Edges a-b, b-c, c-d, d-a of the cell's corners a, b, c, d
        // (counter-clockwise from node k).
        let e = [2 * k, 2 * (k + 1) + 1, 2 * (k + nx), 2 * k + 1];
        cell_segments(v, c, e)
    }
}

/// The σ range of each run of [`CHUNK`] cells along each row of an `nx` ×
/// `ny` grid of σ (`d`, row-major), over the cells with a finite σ at all
/// four corners, and the runs a row has.
fn chunk_ranges(d: &[f64], nx: usize, ny: usize) -> (Vec<(f64, f64)>, usize) {
    let cells = nx.saturating_sub(1);
    let per_row = cells.div_ceil(CHUNK);
    let mut out = vec![(f64::INFINITY, f64::NEG_INFINITY); per_row * ny.saturating_sub(1)];
    for j in 0..ny.saturating_sub(1) {
        for i in 0..cells {
            let k = j * nx + i;
            let v = [d[k], d[k + 1], d[k + nx + 1], d[k + nx]];
            if v.iter().any(|x| !x.is_finite()) {
                continue;
            }
            let r = &mut out[j * per_row + i / CHUNK];
            for x in v {
                r.0 = r.0.min(x);
                r.1 = r.1.max(x);
            }
        }
    }
    (out, per_row)
}

/// The segments of level `c` in one cell with corner values `v` (counter-
/// clockwise) and edges `e` (`e[m]` joins corners m and m + 1): the first `n`
/// of the pair returned.
fn cell_segments(v: [f64; 4], c: f64, e: [usize; 4]) -> ([[usize; 2]; 2], usize) {
    let above = v.map(|x| x >= c);
    let mut crossed = [0; 4];
    let mut n = 0;
    for m in 0..4 {
        if above[m] != above[(m + 1) % 4] {
            crossed[n] = m;
            n += 1;
        }
    }
    match n {
        2 => ([[e[crossed[0]], e[crossed[1]]], [0, 0]], 1),
        4 => {
            // Corners a and c on one side, b and d on the other: the centre
            // joins the pair on its own side, and the other two are cut off.
            let centre = 0.25 * v.iter().sum::<f64>() >= c;
            if centre == above[0] {
                ([[e[0], e[1]], [e[2], e[3]]], 2)
            } else {
                ([[e[3], e[0]], [e[1], e[2]]], 2)
            }
        }
        _ => ([[0, 0]; 2], 0),
    }
}

/// Segments joined at their shared edges into chains of edges: open chains
/// (from an edge only one segment touches) first, then closed ones, each
/// with whether it is closed. Deterministic: in the order of the segments.
fn chain(segs: &[[usize; 2]]) -> Vec<(Vec<usize>, bool)> {
    let mut at: HashMap<usize, Vec<usize>> = HashMap::new();
    for (s, pair) in segs.iter().enumerate() {
        for &e in pair {
            at.entry(e).or_default().push(s);
        }
    }
    let mut used = vec![false; segs.len()];
    let mut out = Vec::new();
    let walk = |start: usize, first: usize, used: &mut Vec<bool>| -> (Vec<usize>, bool) {
        let mut edges = vec![start];
        let (mut e, mut s) = (start, first);
        loop {
            used[s] = true;
            let next = if segs[s][0] == e {
                segs[s][1]
            } else {
                segs[s][0]
            };
            if next == start {
                return (edges, true);
            }
            edges.push(next);
            match at[&next].iter().find(|&&t| !used[t]) {
                Some(&t) => (e, s) = (next, t),
                None => return (edges, false),
            }
        }
    };
    // Open chains from their ends, in segment order.
    for s in 0..segs.len() {
        for &e in &segs[s] {
            if !used[s] && at[&e].len() == 1 {
                out.push(walk(e, s, &mut used));
            }
        }
    }
    for s in 0..segs.len() {
        if !used[s] {
            out.push(walk(segs[s][0], s, &mut used));
        }
    }
    out
}

/// Dijkstra's algorithm from every top node (σ = 0) over the wall nodes; a
/// floor node keeps +∞. An edge's length is its chord on S2 (from a top
/// node, the chord from where u, linear along the edge, passes `s_top`: the
/// top edge lies up to a grid step from its nearest node, and counting that
/// flat step put σ up to 0.2 mm over at mfs-sign's corners) times
/// √(1 + rc·κ) where S2 bends convexly along it with curvature κ (from the
/// second difference of z along the edge, the node behind it included) and
/// rc = `corner`: a corner of radius rc touching a convex bend of radius R
/// = 1/κ at contact points w apart leaves a cusp of about w²/8·(1/rc + κ),
/// so the levels close in by that factor to keep the flat's cusp. Ties are
/// settled by node index, so the result does not depend on anything but the
/// grid.
fn dijkstra(
    (nx, ny, h): (usize, usize, f64),
    parts: &[Part],
    (z, u, s_top): (&[f64], &[f64], f64),
    corner: f64,
) -> Vec<f64> {
    let mut d: Vec<f64> = parts
        .iter()
        .map(|&p| if p == Part::Top { 0.0 } else { f64::INFINITY })
        .collect();
    // σ ≥ 0, so its bits order as its values.
    let mut heap: BinaryHeap<Reverse<(u64, usize)>> = (0..nx * ny)
        .filter(|&k| parts[k] == Part::Top)
        .map(|k| Reverse((0u64, k)))
        .collect();
    let steps: Vec<(i64, i64, f64)> = STEPS
        .iter()
        .map(|&(a, b)| (a, b, h * ((a * a + b * b) as f64).sqrt()))
        .collect();
    while let Some(Reverse((bits, k))) = heap.pop() {
        let dk = f64::from_bits(bits);
        if dk > d[k] {
            continue;
        }
        let (i, j) = ((k % nx) as i64, (k / nx) as i64);
        for &(a, b, run) in &steps {
            let (x, y) = (i + a, j + b);
            if x < 0 || y < 0 || x >= nx as i64 || y >= ny as i64 {
                continue;
            }
            let m = y as usize * nx + x as usize;
            if parts[m] != Part::Wall {
                continue;
            }
            let rise = z[m] - z[k];
            // From a top node, σ starts where u passes the top edge's s.
            let from = if parts[k] == Part::Top {
                run * (1.0 - top_share(u[k], u[m], s_top))
            } else {
                run
            };
            let (bx, by) = (i - a, j - b);
            let zee = if bx >= 0 && by >= 0 && bx < nx as i64 && by < ny as i64 {
                let back = z[by as usize * nx + bx as usize];
                (z[m] - 2.0 * z[k] + back) / (run * run)
            } else {
                0.0
            };
            // Only a convex bend (z″ < 0) lengthens the edge: elsewhere the
            // factor is exactly 1, and its power and root are skipped.
            let nd = if zee < 0.0 {
                let slope = rise / run;
                let bend = -zee / (1.0 + slope * slope).powf(1.5);
                dk + from.hypot(rise) * (1.0 + corner * bend).sqrt()
            } else {
                dk + from.hypot(rise)
            };
            if nd < d[m] {
                d[m] = nd;
                heap.push(Reverse((nd.to_bits(), m)));
            }
        }
    }
    d
}

/// The share of an edge from a top node (u = `top`) to a neighbour (u =
/// `other`) before u, linear along it, passes the top edge's `s_top`.
fn top_share(top: f64, other: f64, s_top: f64) -> f64 {
    let share = (top - s_top) / (top - other);
    if share.is_finite() {
        share.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The passes of the wall between its top edge and its foot: the levels σ =
/// k·`w` for k = 1, 2, ... below the largest σ, the deepest first (the
/// finisher cuts from the floor up), each with its curves (`kept` says
/// which: none shorter than `min_len`, mm, unless it reaches past the foot's
/// band), and between levels k + 1 and k the pieces of σ = (k + ½)·w that
/// neither level k + 1 nor the wall's foot `foot` comes near
/// ([`ridge_pieces`]). `max_passes` bounds the work: `Err` names the count.
pub(crate) fn passes(
    dist: &Distance,
    foot: &[Curve],
    w: f64,
    min_len: f64,
    max_passes: usize,
) -> Result<Vec<(f64, Vec<Curve>)>, usize> {
    use rayon::prelude::*;
    let k_max = (dist.max() / w).floor() as usize;
    if k_max > max_passes {
        return Err(k_max);
    }
    let foot_index = segment_index(foot);
    let long = |c: &Curve| kept(c, min_len, foot_index.as_ref(), w);
    let levels: Vec<Vec<Curve>> = (0..=k_max + 1)
        .into_par_iter()
        .map(|k| {
            if k == 0 || k > k_max {
                return Vec::new();
            }
            dist.level(k as f64 * w).into_iter().filter(long).collect()
        })
        .collect();
    let halves: Vec<Vec<Curve>> = (0..=k_max)
        .into_par_iter()
        .map(|k| {
            if k == 0 {
                return Vec::new();
            }
            let half = dist.level((k as f64 + 0.5) * w);
            let near: Vec<Curve> = levels[k + 1].iter().chain(foot).cloned().collect();
            ridge_pieces(&half, &near, w)
                .into_iter()
                .filter(|c| c.length() >= w)
                .collect()
        })
        .collect();
    let mut out = Vec::new();
    for k in (1..=k_max).rev() {
        out.push(((k as f64 + 0.5) * w, halves[k].clone()));
        out.push((k as f64 * w, levels[k].clone()));
    }
    // Half a width under the top edge as well: where the wall meets the top
    // in a crease the cutter on the edge touches it at the crease, tilted
    // less than the wall, and does not reach the wall under it.
    let first: Vec<Curve> = dist.level(0.5 * w).into_iter().filter(long).collect();
    out.push((0.5 * w, first));
    Ok(out.into_iter().filter(|(_, c)| !c.is_empty()).collect())
}

/// How near (XY, in pass widths) level k + 1 must come to a point of σ =
/// (k + ½)·w for the point to count as covered: on a gentle wall the level
/// lies w/2 off along the surface; a wall up to 40° steep brings that to
/// 0.38·w in XY, and a point whose neighbour level lies farther is a ridge's.
pub(crate) const COVERED: f64 = 0.75;

/// The pieces of the half level `half` (σ = (k + ½)·w) farther than
/// [`COVERED`]·w from every curve of `next` (level k + 1 and the foot,
/// which the half level nears where the wall ends), each grown by
/// a few points at either end. Where fronts from two parts of the top edge
/// meet (a ridge of σ: the col between two letters, the bottom of a pit)
/// level k + 1 lies only beyond the ridge, and a ridge point up to w from
/// level k would be left with a scallop up to four times the bound; the
/// half level runs w/2 from level k there.
pub(crate) fn ridge_pieces(half: &[Curve], next: &[Curve], w: f64) -> Vec<Curve> {
    let index = segment_index(next);
    let far = |q: Vec2| index.as_ref().is_none_or(|ix| ix.distance(q) > COVERED * w);
    half.iter()
        .flat_map(|c| uncovered_runs(c, &c.pts.iter().map(|&q| far(q)).collect::<Vec<_>>()))
        .collect()
}

/// Whether a level's curve `c` is cut: if it is at least `min_len` long, or
/// if it is open (it ends where the wall meets the floor, see
/// [`Distance::level`]) and reaches farther than w/2 from the foot (`foot`,
/// indexed by [`segment_index`]), past the band the foot's own pass covers.
/// A short closed curve is the grid's crumb round a maximum of σ, which the
/// half level under it covers ([`ridge_pieces`]); a short open one within
/// w/2 of the foot is a level grazing the foot. But where a ridge of σ runs
/// down into the foot, the level's last V there is short and open, and
/// without it the ball left 0.021 mm between the V under it and the foot
/// (mfs-sign's M, a 1° slope).
fn kept(c: &Curve, min_len: f64, foot: Option<&crate::geometry::DistanceIndex>, w: f64) -> bool {
    if c.length() >= min_len {
        return true;
    }
    !c.closed && foot.is_none_or(|ix| c.pts.iter().any(|&q| ix.distance(q) > 0.5 * w))
}

/// A distance index over the segments of `curves` (an open curve's last
/// point is not joined to its first), or `None` when there are none.
fn segment_index(curves: &[Curve]) -> Option<crate::geometry::DistanceIndex> {
    let segs: Vec<Vec<Vec2>> = curves
        .iter()
        .flat_map(|c| {
            let n = c.pts.len();
            let m = if c.closed { n } else { n.saturating_sub(1) };
            (0..m).map(move |i| vec![c.pts[i], c.pts[(i + 1) % n]])
        })
        .collect();
    (!segs.is_empty()).then(|| crate::geometry::DistanceIndex::new(&segs))
}

/// Points either side of an uncovered run that are kept with it.
const GROW: usize = 3;

/// The runs of `c` whose points are marked in `open` (each grown by [`GROW`]
/// points), as curves: the whole curve if every point is marked.
fn uncovered_runs(c: &Curve, open: &[bool]) -> Vec<Curve> {
    let n = c.pts.len();
    if n == 0 || !open.iter().any(|&o| o) {
        return Vec::new();
    }
    if open.iter().all(|&o| o) {
        return vec![c.clone()];
    }
    let at = |i: isize| -> usize {
        if c.closed {
            i.rem_euclid(n as isize) as usize
        } else {
            i.clamp(0, n as isize - 1) as usize
        }
    };
    let mut keep = vec![false; n];
    for i in (0..n).filter(|&i| open[i]) {
        for d in -(GROW as isize)..=GROW as isize {
            keep[at(i as isize + d)] = true;
        }
    }
    if keep.iter().all(|&k| k) {
        return vec![c.clone()];
    }
    // Start the walk at a dropped point so no run of a closed curve wraps.
    let start = if c.closed {
        keep.iter().position(|&k| !k).unwrap_or(0)
    } else {
        0
    };
    let mut out = Vec::new();
    let mut run: Vec<usize> = Vec::new();
    let piece = |run: &[usize]| Curve {
        pts: run.iter().map(|&i| c.pts[i]).collect(),
        closed: false,
        s: run.iter().filter_map(|&i| c.s.get(i).copied()).collect(),
    };
    for m in 0..n {
        let i = (start + m) % n;
        if keep[i] {
            run.push(i);
        } else if !run.is_empty() {
            out.push(piece(&run));
            run.clear();
        }
    }
    if !run.is_empty() {
        out.push(piece(&run));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid of u over [0, 10]² from a function.
    fn grid_of(h: f64, u: impl Fn(Vec2) -> f64) -> Grid {
        let n = (10.0 / h) as usize + 1;
        let values = (0..n * n)
            .map(|k| u(Vec2::new((k % n) as f64 * h, (k / n) as f64 * h)))
            .collect();
        Grid {
            origin: Vec2::ZERO,
            h,
            nx: n,
            ny: n,
            values,
            inside: vec![false; n * n],
        }
    }

    /// The runs of cells skipped by their σ range hide no segment: on a
    /// bumpy field with floor and top regions (σ +∞ and 0), a wall wider
    /// than several runs and rows whose width is not a multiple of a run,
    /// the level's segments are those of a scan of every cell, in the same
    /// order, for levels across the whole range.
    #[test]
    fn skipping_runs_of_cells_loses_no_segment() {
        let p = DepthProfile::Linear {
            s_bottom: 0.2,
            depth: 5.0,
        };
        let g = grid_of(0.1, |q| {
            0.5 + 0.45 * (q.x * 0.7).sin() * (q.y * 0.45).cos() + 0.01 * q.y
        });
        let z_of = |u: f64| p.z(u);
        let d = Distance::from_top_edge(&g, &p, (false, 0.0), &z_of);
        assert!(d.nx - 1 > 3 * CHUNK && (d.nx - 1) % CHUNK != 0);
        let every_cell = |c: f64| {
            let nx = d.nx;
            let mut out = Vec::new();
            for j in 0..d.ny - 1 {
                for i in 0..nx - 1 {
                    let (pair, n) = d.cell(j * nx + i, c);
                    out.extend_from_slice(&pair[..n]);
                }
            }
            out
        };
        let top = d.max();
        assert!(top > 1.0, "σ reaches {top}");
        let mut found = 0;
        for k in 1..40 {
            let c = top * k as f64 / 40.0;
            let segs = d.segments(c);
            assert_eq!(segs, every_cell(c), "level {c}");
            found += segs.len();
        }
        assert!(found > 1000, "{found} segments");
    }

    /// A plane wall rising along x at slope 1 (u = x/9, z = x − 9 up to the
    /// top edge at x = 9): σ is (9 − x)·√2 within the stencil's 2.7 % and
    /// never under it; a level is a straight line across the grid (an open
    /// arc from border to border).
    #[test]
    fn on_a_plane_sigma_is_the_slanted_distance_within_the_stencil() {
        let p = DepthProfile::Linear {
            s_bottom: 0.0,
            depth: 9.0,
        };
        let g = grid_of(0.1, |q| q.x / 9.0);
        let z_of = |u: f64| p.z(u);
        let d = Distance::from_top_edge(&g, &p, (false, 0.0), &z_of);
        for (i, j) in [(5, 0), (30, 70), (85, 3), (50, 50)] {
            let x = i as f64 * 0.1;
            let exact = (9.0 - x) * 2f64.sqrt();
            let got = d.d[j * d.nx + i];
            assert!(
                got >= exact - 1e-9 && got <= exact * 1.03 + 0.2,
                "{x}: {got} vs {exact}"
            );
        }
        let lv = d.level(5.0);
        assert_eq!(lv.len(), 1);
        assert!(!lv[0].closed);
        let x = 9.0 - 5.0 / 2f64.sqrt();
        for q in &lv[0].pts {
            assert!((q.x - x).abs() < 0.15, "{q:?} vs x {x}");
        }
    }

    /// A near-vertical plane wall (z falls 20 mm per mm, 87°) whose top edge
    /// u = 1 lies halfway between two grid columns: a level σ = c lies where
    /// the surface is c from that edge, z = −c·20/√401, to a few hundredths
    /// of a millimetre in z (0.001 mm in plan), and σ at a node is its
    /// distance from the edge. With u held to φ's range at
    /// the top node, the wall was spread over the whole edge from it and the
    /// levels stood up to 0.5 mm too high.
    #[test]
    fn on_a_near_vertical_wall_a_level_lies_at_its_distance_from_the_edge() {
        let p = DepthProfile::Linear {
            s_bottom: 0.5,
            depth: 100.0,
        };
        let u = |x: f64| 1.0 + (x - 5.05) * 0.1;
        let g = grid_of(0.1, |q| u(q.x));
        let z_of = |u: f64| p.z(u);
        let d = Distance::from_top_edge(&g, &p, (false, 0.0), &z_of);
        // σ at the nodes is measured from the edge, not from the top node
        // 0.05 mm beyond it (that added 0.0037 mm here, 0.2 mm at corners).
        for i in 10..50 {
            let exact = (5.05 - i as f64 * 0.1) * 401f64.sqrt();
            let got = d.d[20 * d.nx + i];
            assert!(
                (got - exact).abs() < 1e-9 * exact.max(1.0),
                "{i}: {got} vs {exact}"
            );
        }
        for c in [0.2, 0.5, 0.8, 1.5, 2.5] {
            let want = -c * 20.0 / 401f64.sqrt();
            let lv = d.level(c);
            assert!(!lv.is_empty(), "σ {c}");
            for q in lv.iter().flat_map(|l| &l.pts) {
                let z = p.z(u(q.x).min(1.0));
                assert!((z - want).abs() < 0.06, "σ {c} at {q:?}: z {z} vs {want}");
            }
        }
    }

    /// A cone: u = 1 − (r − 2)/10, z = −(r − 2) (1 mm per mm of radius
    /// from the top edge at r = 2 to the foot at r = 8): its levels inside
    /// the grid are closed circles of radius 2 + σ/√2, neighbours at most w
    /// and at least 0.9·w apart on the surface.
    #[test]
    fn on_a_cone_the_levels_are_circles_w_apart_on_the_surface() {
        let p = DepthProfile::Linear {
            s_bottom: 0.4,
            depth: 6.0,
        };
        let c = Vec2::new(5.0, 5.0);
        let g = grid_of(0.05, |q| 1.0 - (q.dist(c) - 2.0) / 10.0);
        let z_of = |u: f64| p.z(u);
        let d = Distance::from_top_edge(&g, &p, (false, 0.0), &z_of);
        let w = 0.5;
        let passes = passes(&d, &[], w, 0.1, 100).unwrap();
        // r from 2 to 5 (the grid's edge) at slope 1: σ up to 3√2.
        assert!(passes.len() >= 7, "{}", passes.len());
        let mut radii = Vec::new();
        for (sig, cv) in passes.iter().rev() {
            let k = sig / w;
            // Circles that lie inside the grid (radius under 4.9), and the
            // half levels between them, which the next circle covers.
            if 2.0 + (k.floor() + 1.0) * w / 2f64.sqrt() > 4.9 {
                continue;
            }
            if k < 1.0 {
                // Half a width under the top edge: always cut.
                assert!((k - 0.5).abs() < 1e-9 && cv.len() == 1 && cv[0].closed);
                continue;
            }
            assert!(
                (k - k.round()).abs() < 1e-9,
                "a half level at σ {sig}: {cv:?}"
            );
            assert_eq!(cv.len(), 1, "σ {sig}");
            assert!(cv[0].closed, "σ {sig}");
            let r: f64 = cv[0].pts.iter().map(|q| q.dist(c)).sum::<f64>() / cv[0].pts.len() as f64;
            radii.push(r);
        }
        assert!(radii.len() >= 5);
        for r in radii.windows(2) {
            let on_surface = (r[1] - r[0]) * 2f64.sqrt();
            assert!(
                on_surface <= w * 1.0 + 1e-3 && on_surface > 0.9 * w,
                "{r:?}"
            );
        }
    }

    /// A V-shaped valley between two top edges at x = 2 and x = 8 (z =
    /// −min(x − 2, 8 − x)): the fronts meet head-on on the ridge of σ at x =
    /// 5, σ = 3√2 there. With w = 0.55 the last level, 7·w = 3.85, lies
    /// 0.39 mm (more than w/2) from the ridge on either side and level 8
    /// does not exist: the half level 7.5·w is kept, along the ridge.
    #[test]
    fn a_ridge_that_the_next_level_misses_gets_the_half_level() {
        let p = DepthProfile::Linear {
            s_bottom: 0.0,
            depth: 4.0,
        };
        let g = grid_of(0.05, |q| 1.0 - (q.x - 2.0).min(8.0 - q.x) / 4.0);
        let z_of = |u: f64| p.z(u);
        let d = Distance::from_top_edge(&g, &p, (false, 0.0), &z_of);
        let w = 0.55;
        let passes = passes(&d, &[], w, 0.1, 100).unwrap();
        let sigmas: Vec<f64> = passes.iter().map(|(s, _)| *s).collect();
        let half = passes
            .iter()
            .find(|(s, _)| (s - 7.5 * w).abs() < 1e-9)
            .unwrap_or_else(|| panic!("no half level: {sigmas:?}"));
        for c in &half.1 {
            for q in &c.pts {
                assert!((q.x - 5.0).abs() < 0.3, "{q:?} far from the ridge");
            }
        }
        // No half level where the next level comes near (the rest of the
        // valley's walls), but for the one half a width under the top edge.
        assert_eq!(
            sigmas
                .iter()
                .filter(|s| ((*s / w).fract() - 0.5).abs() < 1e-9)
                .count(),
            2,
            "{sigmas:?}"
        );
        assert!((sigmas[sigmas.len() - 1] - 0.5 * w).abs() < 1e-12);
    }

    /// Which short curves a level keeps, against a foot along y = 0 and w =
    /// 0.36: a V 0.9 mm long whose tip lies 0.3 mm (over w/2) from the foot
    /// is kept; a piece grazing the foot 0.1 mm off it and a closed crumb
    /// round a maximum are not; anything at least `min_len` long is.
    #[test]
    fn a_short_level_is_kept_only_where_it_reaches_past_the_foot_band() {
        let v = |x: f64, y: f64| Vec2::new(x, y);
        let foot = [Curve {
            pts: vec![v(-5.0, 0.0), v(5.0, 0.0)],
            closed: false,
            s: Vec::new(),
        }];
        let ix = segment_index(&foot);
        let open = |pts: Vec<Vec2>| Curve {
            pts,
            closed: false,
            s: Vec::new(),
        };
        let w = 0.36;
        let vee = open(vec![v(-0.3, 0.05), v(0.0, 0.3), v(0.3, 0.05)]);
        assert!(vee.length() < 1.0);
        assert!(kept(&vee, 1.0, ix.as_ref(), w));
        let grazing = open(vec![v(1.0, 0.1), v(1.5, 0.1)]);
        assert!(!kept(&grazing, 1.0, ix.as_ref(), w));
        let crumb = Curve::closed(vec![v(0.0, 2.0), v(0.1, 2.0), v(0.1, 2.1)]);
        assert!(!kept(&crumb, 1.0, ix.as_ref(), w));
        let long = open(vec![v(1.0, 0.1), v(2.5, 0.1)]);
        assert!(kept(&long, 1.0, ix.as_ref(), w));
    }

    /// A convex wall z = −(x − 1)²/4 (radius of curvature 2 at its top
    /// edge x = 1): with a corner of radius 1, σ grows by √(1 + rc·κ) per
    /// unit of surface, κ = (1/2)/(1 + z′²)^{3/2}: within 3 % of that
    /// integral, and over the plain surface length.
    #[test]
    fn on_a_convex_bend_the_levels_close_in_by_the_cusp_factor() {
        let p = DepthProfile::Linear {
            s_bottom: 0.0,
            depth: 10.0,
        };
        let g = grid_of(0.05, |q| {
            let x = (q.x - 1.0).max(0.0);
            1.0 - x * x / 40.0
        });
        let z_of = |u: f64| p.z(u);
        let d = Distance::from_top_edge(&g, &p, (false, 1.0), &z_of);
        let (mut plain, mut bent) = (0.0, 0.0);
        let n = 20_000;
        for k in 0..n {
            let x = 1.0 + 3.0 * (k as f64 + 0.5) / n as f64;
            let slope = (x - 1.0) / 2.0;
            let ds = (1.0 + slope * slope).sqrt() * 3.0 / n as f64;
            let kappa = 0.5 / (1.0 + slope * slope).powf(1.5);
            plain += ds;
            bent += ds * (1.0 + kappa).sqrt();
        }
        let i = (4.0 / 0.05f64).round() as usize;
        let got = d.d[100 * d.nx + i];
        assert!(got > plain * 1.05, "{got} vs the plain {plain}");
        assert!((got - bent).abs() < 0.03 * bent, "{got} vs {bent}");
    }
}
