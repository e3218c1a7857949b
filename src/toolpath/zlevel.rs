//! Z-level operations (boss and cavity): the paths of one level and the linking of
//! all levels into a tool path with ramped entries.

use super::air::Keepout;
use super::entry::{enter, ramp_start, start_near, Entry, CLEARANCE};
use super::profile::{deepest_point, ProfileError};
use super::runs;
use super::spot::spot_loop;
use super::stock::{model_radius, StockMap};
use super::trace::{trace, Navigator, TraceParams};
use super::{Move, Section, Toolpath, Vec3};
use crate::geometry::{polygon_area, polygon_winding_number, polygons_bbox, DistanceIndex, Vec2};

/// Settings shared by every level, mm, mm/min and degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LevelParams {
    /// Tool radius.
    pub(crate) radius: f64,
    /// Chord tolerance.
    pub(crate) tol: f64,
    /// Largest distance between neighbouring clearing rings.
    pub(crate) stepover: f64,
    /// Ramp angle for entries into uncut material, degrees.
    pub(crate) ramp_angle: f64,
    /// Climb milling.
    pub(crate) climb: bool,
    /// Cutting feed.
    pub(crate) feed: f64,
    /// Plunge and ramp feed.
    pub(crate) plunge_feed: f64,
    /// Rate of rapids, mm/min (for choosing between a link at depth and a
    /// retract).
    pub(crate) rapid_rate: f64,
    /// Safe Z: where the tool path starts and ends.
    pub(crate) safe_z: f64,
    /// Z of the rapids between paths (`stock.retract_z`), at most `safe_z`.
    pub(crate) retract_z: f64,
    /// Stock top Z.
    pub(crate) top: f64,
    /// Deepest cut allowed in one move (the tool's stepdown): a sideways link
    /// at depth may cross material no deeper than this.
    pub(crate) stepdown: f64,
    /// Material left on the walls for a finishing tool, mm
    /// (`operation.stock_to_leave`): the paths keep the wall radius
    /// [`wall`](Self::wall) from the part, and cover with the true radius.
    pub(crate) leave: f64,
    /// Lower-left corner of the stock rectangle.
    pub(crate) stock_lo: Vec2,
    /// Upper-right corner of the stock rectangle.
    pub(crate) stock_hi: Vec2,
}

impl LevelParams {
    /// How far the tool's axis stays from the part: its radius plus the
    /// stock to leave, mm.
    pub(crate) fn wall(&self) -> f64 {
        self.radius + self.leave
    }

    /// The entry settings of these parameters.
    pub(crate) fn entry(&self) -> Entry {
        Entry {
            radius: self.radius,
            ramp_angle: self.ramp_angle,
            plunge_feed: self.plunge_feed,
            feed: self.feed,
            safe_z: self.retract_z,
            top: self.top,
        }
    }
}

/// One path at a level.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CutPath {
    /// What it is, e.g. `ring 3 around the part`.
    pub(crate) label: String,
    /// The tool centre positions (for a closed path the last equals the first).
    pub(crate) points: Vec<Vec2>,
    /// Closed loop (entered by a ramp) or open run (starts and ends outside the
    /// stock, entered by a plunge in air).
    pub(crate) closed: bool,
    /// A boss's clearing ring around the part: its index j (radius r +
    /// j·stepover). The linker orders these ([`runs::order`]); every other
    /// path keeps its place after them.
    pub(crate) ring: Option<usize>,
}

/// All the paths of one level.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LevelCut {
    /// Z of the level (absolute).
    pub(crate) z: f64,
    /// The equipotential value s of the level.
    pub(crate) s: f64,
    /// The part at this level, Γ(s), as closed polygons.
    pub(crate) part: Vec<Vec<Vec2>>,
    /// The paths in cutting order.
    pub(crate) paths: Vec<CutPath>,
}

/// Split a closed ring into the runs over the stock (the points `keep` does
/// not clear), each run extended by one point at both ends so that it starts
/// and ends where the tool is clear of the stock. A ring wholly over it stays
/// closed.
pub(super) fn clip_ring(ring: &[Vec2], keep: &Keepout) -> Vec<(Vec<Vec2>, bool)> {
    let n = ring.len() - 1; // last = first
    let clear: Vec<bool> = ring[..n].iter().map(|&p| keep.clear(p)).collect();
    super::clearing::runs_between(ring, &clear)
}

pub(super) fn lowest(poly: &[Vec2]) -> Vec2 {
    poly.iter().copied().fold(poly[0], |a, b| {
        if b.y < a.y || (b.y == a.y && b.x < a.x) {
            b
        } else {
            a
        }
    })
}

/// The paths of one boss level. A level that clears its whole area: the
/// clearing loops ([`clearing`](super::clearing)), each the boundary of the
/// stock rectangle, inset a stepover further for each, less the inside of
/// ring j (the rolling-disk offset of radius r + j·stepover), cut from the
/// inside out, down to the finishing ring at r. A level added for the scallop
/// bound (`reach`, the band of that width): the rings around every outer loop
/// of the part out to the band's width, clipped to the stock grown by r.
/// Inside every hole of the part, rings from the innermost out.
pub(crate) fn boss_paths<N: Navigator + Sync>(
    part: &[Vec<Vec2>],
    nav: &N,
    p: &LevelParams,
    label: &str,
    warnings: &mut Vec<String>,
    reach: Option<f64>,
) -> Result<Vec<CutPath>, ProfileError> {
    let index = DistanceIndex::new(part);
    // Rings are offsets of the wall radius; the tool covers its true radius.
    let r = p.wall();
    let dmax =
        super::farthest::farthest_stock_point(part, &index, p.stock_lo, p.stock_hi, p.stepover);
    let full = ((dmax - r - p.radius) / p.stepover).ceil().max(0.0) as usize;
    // A level added for the scallop bound only clears the band, `reach` wide, out
    // to the contour of the level below, which was cut first: ring j's disk
    // reaches j·stepover + 2r out, and the outermost engages at most a stepover
    // of the band.
    let rings = match reach {
        Some(d) => ((d / p.stepover).ceil() as usize)
            .saturating_sub(1)
            .min(full),
        None => full,
    };
    let w = Walls {
        part,
        index: &index,
        nav,
        p,
        label,
    };
    // A level that clears its whole area does so by the clearing loops, up to
    // the last whose ring still lies in the stock (beyond it A_j is empty).
    let mut paths = if reach.is_some() {
        w.outer_rings(rings)?
    } else {
        w.clearing_loops(((dmax - r) / p.stepover).ceil().max(0.0) as usize)?
    };
    // On a level added for the scallop bound, only the band next to a hole's
    // wall (the level below cleared the counter inside its own contour).
    let most = if reach.is_some() { rings } else { usize::MAX };
    let holes: Vec<&Vec<Vec2>> = part.iter().filter(|q| polygon_area(q) < 0.0).collect();
    for (h, hole) in holes.iter().enumerate() {
        paths.extend(w.hole_rings(h, hole, most, warnings)?);
    }
    if reach.is_none() {
        super::bays::clear_bays(part, &index, nav, p, label, &mut paths, warnings)?;
    }
    Ok(paths)
}

/// What a boss level's rings are traced against: the part (Γ(s), material on
/// the left), its distance index, the level's field, the settings and the
/// level's label.
struct Walls<'a, N> {
    part: &'a [Vec<Vec2>],
    index: &'a DistanceIndex,
    nav: &'a N,
    p: &'a LevelParams,
    label: &'a str,
}

impl<N: Navigator + Sync> Walls<'_, N> {
    /// Tracing settings for a disk of `radius`.
    fn tp(&self, radius: f64) -> TraceParams {
        TraceParams {
            radius,
            tol: self.p.tol,
            part_on_left: !self.p.climb,
        }
    }

    /// Rings 0..=`rings` around the part, at the wall radius + j·stepover, in
    /// parallel over j; for each j the outer loops in turn, skipping a loop
    /// whose ring was already traced from another (the rings of neighbouring
    /// letters merge as they grow). Each ring is clipped to the stock: the
    /// runs that cross it, then the closed rings, outermost first (the linker
    /// orders them, `runs::order`).
    fn outer_rings(&self, rings: usize) -> Result<Vec<CutPath>, ProfileError> {
        use rayon::prelude::*;
        let (p, label) = (self.p, self.label);
        let keep = Keepout::around_stock(p.stock_lo, p.stock_hi, p.radius);
        type Rings = Result<Vec<(usize, Vec<Vec2>)>, ProfileError>;
        let traced: Vec<Rings> = (0..=rings)
            .rev()
            .collect::<Vec<_>>()
            .par_iter()
            .map(|&j| self.rings_at(j))
            .collect();
        let (mut open, mut closed) = (Vec::new(), Vec::new());
        for res in traced {
            for (j, ring) in res? {
                for (run, whole) in clip_ring(&ring, &keep) {
                    if whole {
                        closed.push((j, run));
                    } else {
                        open.push((j, run));
                    }
                }
            }
        }
        let ring_path = |(j, run): (usize, Vec<Vec2>), closed: bool| CutPath {
            label: format!("{label}: ring {j} around the part"),
            points: run,
            closed,
            ring: Some(j),
        };
        let mut paths: Vec<CutPath> = open.into_iter().map(|r| ring_path(r, false)).collect();
        paths.extend(closed.into_iter().map(|r| ring_path(r, true)));
        Ok(paths)
    }

    /// The clearing loops 0..=`rings` of a level that clears its whole
    /// area ([`clearing`](super::clearing)): loop j from ring j and the stock
    /// rectangle, closed, the largest first (the linker orders them,
    /// `runs::order`).
    fn clearing_loops(&self, rings: usize) -> Result<Vec<CutPath>, ProfileError> {
        use rayon::prelude::*;
        let p = self.p;
        let frame = super::clearing::Frame {
            stock_lo: p.stock_lo,
            stock_hi: p.stock_hi,
            radius: p.radius,
            stepover: p.stepover,
            climb: p.climb,
        };
        let label = |j: usize| format!("{}: loop {j} of the clearing", self.label);
        let too_complex = |j: usize| {
            move |source| ProfileError::TooComplex {
                path: label(j),
                source,
            }
        };
        let path = |j: usize, points: Vec<Vec2>, closed: bool| CutPath {
            label: label(j),
            points,
            closed,
            ring: Some(j),
        };
        type Loops = Result<(usize, Vec<(Vec<Vec2>, bool)>), ProfileError>;
        let traced = |j: usize| -> Result<Vec<Vec<Vec2>>, ProfileError> {
            Ok(self.rings_at(j)?.into_iter().map(|(_, r)| r).collect())
        };
        let keep = Keepout::around_stock(p.stock_lo, p.stock_hi, p.radius);
        let loops: Vec<Loops> = (1..=rings)
            .rev()
            .collect::<Vec<_>>()
            .par_iter()
            .map(|&j| {
                let rings = traced(j)?;
                let l =
                    super::clearing::clearing_loops(&frame, j, &rings).map_err(too_complex(j))?;
                if self.keeps_clear(&l, j) {
                    return Ok((j, l));
                }
                // A side of R_j crosses a loop of the part that no ring
                // went round: the rings clipped to the stock instead.
                Ok((j, rings.iter().flat_map(|r| clip_ring(r, &keep)).collect()))
            })
            .collect();
        let mut paths = Vec::new();
        let mut next: Vec<Vec<Vec2>> = Vec::new();
        for l in loops {
            let (j, l) = l?;
            if j == 1 {
                // Closed loops only: a distance index closes every polygon.
                next = l.iter().filter(|c| c.1).map(|c| c.0.clone()).collect();
            }
            paths.extend(l.into_iter().map(|(pts, closed)| path(j, pts, closed)));
        }
        let rings0 = traced(0)?;
        let mut first =
            super::clearing::first_loop_pieces(&frame, &rings0, &next).map_err(too_complex(0))?;
        if !self.keeps_clear(&first, 0) {
            first = rings0.iter().flat_map(|r| clip_ring(r, &keep)).collect();
        }
        paths.extend(first.into_iter().map(|(pts, closed)| path(0, pts, closed)));
        Ok(paths)
    }

    /// Whether every segment of loop j's `pieces` keeps its distance from the
    /// part: the wall radius (less two tolerances) on loop 0, half a stepover
    /// less than ring j's radius beyond. R_j's sides are not traced against
    /// the part; they keep clear of it only where the rings go round every
    /// loop of it.
    fn keeps_clear(&self, pieces: &[(Vec<Vec2>, bool)], j: usize) -> bool {
        let p = self.p;
        let least = if j == 0 {
            p.wall() - 2.0 * p.tol
        } else {
            p.wall() + (j as f64 - 0.5) * p.stepover
        };
        pieces.iter().all(|(pts, _)| {
            pts.windows(2)
                .all(|w| self.index.segment_distance(w[0], w[1], least + 1.0) >= least)
        })
    }

    /// The rings of index `j` around the part's outer loops (see
    /// [`Self::outer_rings`]).
    fn rings_at(&self, j: usize) -> Result<Vec<(usize, Vec<Vec2>)>, ProfileError> {
        let p = self.p;
        let rj = p.wall() + j as f64 * p.stepover;
        let mut done: Vec<Vec<Vec2>> = Vec::new();
        let mut out = Vec::new();
        for lp in self.part.iter().filter(|q| polygon_area(q) > 0.0) {
            let low = lowest(lp);
            let probe = low - Vec2::new(0.0, rj);
            if !done.is_empty() {
                let idx = DistanceIndex::new(&done);
                if idx.distance(probe) < 0.5 * rj.min(p.stepover) + 10.0 * p.tol {
                    continue;
                }
            }
            let start = low - Vec2::new(0.0, rj + 1.0);
            let t = trace(self.nav, self.index, start, self.tp(rj)).map_err(|source| {
                ProfileError::Trace {
                    label: format!("{}: ring {j} around the part", self.label),
                    source,
                }
            })?;
            done.push(t.points[..t.points.len() - 1].to_vec());
            out.push((j, t.points));
        }
        Ok(out)
    }

    /// Rings in hole `h` (a counter of the sign) from the innermost out to the
    /// wall ring, at most `most` + 1 of them; a hole too small for the tool
    /// gets a warning and no ring.
    fn hole_rings(
        &self,
        h: usize,
        hole: &[Vec2],
        most: usize,
        warnings: &mut Vec<String>,
    ) -> Result<Vec<CutPath>, ProfileError> {
        let (p, label) = (self.p, self.label);
        let r = p.wall();
        let (deep, room) = deepest_point(hole, self.index);
        if room < r + p.tol {
            warnings.push(format!(
                "{label}: hole {} is too small for the tool (largest inscribed radius {room:.3} mm, tool radius {r:.3} mm): not cut",
                h + 1
            ));
            return Ok(Vec::new());
        }
        let n_in = (((room - r - p.tol) / p.stepover).floor() as usize).min(most);
        let mut paths = Vec::new();
        for j in (0..=n_in).rev() {
            let rj = r + j as f64 * p.stepover;
            if rj > room - p.tol {
                continue;
            }
            // The innermost rings of a long hole are thin slivers about its
            // medial axis, which the rolling disk may fail to close (the Q's
            // counter): such a ring is retried up to three times, each a fifth
            // of a stepover closer to the wall, which keeps the rings within a
            // stepover of each other. Nearer the wall than planned only
            // overlaps the ring outside it more: no warning, nothing for the
            // user to do.
            let mut traced = trace(self.nav, self.index, deep, self.tp(rj));
            for k in 1..=3 {
                if traced.is_ok() || j == 0 {
                    break;
                }
                let rk = rj - 0.2 * k as f64 * p.stepover;
                traced = trace(self.nav, self.index, deep, self.tp(rk));
            }
            let t = traced.map_err(|source| ProfileError::Trace {
                label: format!("{label}: ring {j} in hole {}", h + 1),
                source,
            })?;
            paths.push(CutPath {
                label: format!("{label}: ring {j} in hole {}", h + 1),
                points: t.points,
                closed: true,
                ring: None,
            });
        }
        Ok(paths)
    }
}

/// Link the levels, in the order given, into a tool path, keeping a model of the stock
/// ([`StockMap`]) as the moves cut it. Between paths of a level the tool moves
/// sideways at depth when the next path starts within two stepovers, the straight
/// move keeps clear of the part and the material it crosses is no deeper than a
/// stepdown; otherwise it retracts to safe Z, rapids over and enters the path
/// ([`enter`]): a rapid down to a clearance above the material actually left
/// under the tool, then a ramp from that material's top.
pub(crate) fn link_levels(levels: &[&LevelCut], p: &LevelParams) -> Toolpath {
    let start = Vec3::new(0.0, 0.0, p.safe_z);
    let mut stock = StockMap::new(p.stock_lo, p.stock_hi, p.top, p.radius);
    let e = p.entry();
    let mut pos = start;
    let mut sections = Vec::new();
    let keep = Keepout::around_stock(p.stock_lo, p.stock_hi, p.radius);
    for lv in levels {
        let index = DistanceIndex::new(&lv.part);
        let mut moves = Vec::new();
        let mut at: Option<Vec2> = None; // XY when the tool is down at this level
        for path in cutting_order(&lv.paths, p, &keep, Vec2::new(pos.x, pos.y)) {
            let pts = if path.closed {
                start_near(&path.points, at.unwrap_or(Vec2::new(pos.x, pos.y)))
            } else {
                path.points.clone()
            };
            let first = pts[0];
            let mark = moves.len();
            let sideways = at.filter(|&a| {
                let clear_of_part =
                    index.segment_distance(a, first, 2.0 * p.radius) >= p.radius - 0.5 * p.tol;
                let over = stock.top_near_segment(a, first, p.radius) - lv.z;
                let near = a.dist(first) <= 2.0 * p.stepover + p.tol && over <= p.stepdown + 1e-9;
                let cleared = over <= 1e-6
                    && a.dist(first) / p.feed
                        <= reentry_time(&stock, &pts, path.closed, a, lv.z, p);
                clear_of_part && (near || cleared)
            });
            // Both ends beside the stock: round it at depth, through air,
            // when that beats leaving and coming back.
            let around = at.filter(|&a| {
                sideways.is_none()
                    && keep.clear(a)
                    && keep.clear(first)
                    && keep.route_length(a, first) / p.feed
                        <= reentry_time(&stock, &pts, path.closed, a, lv.z, p)
            });
            if let Some(a) = around {
                for q in keep
                    .route(a, first)
                    .into_iter()
                    .chain(pts[1..].iter().copied())
                {
                    moves.push(Move::Linear {
                        to: Vec3::new(q.x, q.y, lv.z),
                        feed: p.feed,
                    });
                }
            } else if sideways.is_some() {
                for q in &pts {
                    moves.push(Move::Linear {
                        to: Vec3::new(q.x, q.y, lv.z),
                        feed: p.feed,
                    });
                }
            } else {
                if let Some(a) = at {
                    moves.push(Move::Rapid {
                        to: Vec3::new(a.x, a.y, p.retract_z),
                    });
                }
                moves.push(Move::Rapid {
                    to: Vec3::new(first.x, first.y, pos.z.max(p.retract_z)),
                });
                enter(&stock, &pts, path.closed, lv.z, &e, &mut moves);
                if !path.closed {
                    for q in &pts[1..] {
                        moves.push(Move::Linear {
                            to: Vec3::new(q.x, q.y, lv.z),
                            feed: p.feed,
                        });
                    }
                }
            }
            pos = stock.cut_moves(pos, &moves[mark..], model_radius(p.radius, p.tol));
            at = Some(Vec2::new(pos.x, pos.y));
        }
        if let Some(a) = at {
            moves.push(Move::Rapid {
                to: Vec3::new(a.x, a.y, p.retract_z),
            });
            pos.z = p.retract_z;
        }
        let from = sections
            .last()
            .and_then(|s: &Section| s.moves.last().map(|m| m.to()))
            .unwrap_or(start);
        drop_zero_length(from, &mut moves);
        sections.push(Section {
            label: format!("level z {:.3} (s = {:.4})", lv.z, lv.s),
            z: lv.z,
            moves,
        });
    }
    // The program ends at safe Z (the rapids between cuts were at retract Z).
    if let Some(last) = sections.last_mut() {
        if pos.z < p.safe_z {
            last.moves.push(Move::Rapid {
                to: Vec3::new(pos.x, pos.y, p.safe_z),
            });
        }
    }
    Toolpath { start, sections }
}

/// A level's paths in the order to cut them: its boss rings as
/// [`runs::order`] puts them from `from`, where the tool is, then the rest
/// in their own order.
fn cutting_order<'a>(
    paths: &'a [CutPath],
    p: &LevelParams,
    keep: &Keepout,
    from: Vec2,
) -> Vec<&'a CutPath> {
    let (rings, rest): (Vec<&CutPath>, Vec<&CutPath>) =
        paths.iter().partition(|c| c.ring.is_some());
    let pieces: Vec<runs::Piece> = rings
        .iter()
        .map(|c| runs::Piece {
            ring: c.ring.unwrap_or(0),
            points: &c.points,
            closed: c.closed,
        })
        .collect();
    let order = runs::order(&pieces, 1.5 * p.stepover + p.tol, keep, from);
    order.into_iter().map(|i| rings[i]).chain(rest).collect()
}

/// Minutes the tool takes to leave the level at `a`, rapid over and enter
/// `pts` at `z` ([`enter`]): what a sideways move at depth through cleared space
/// must beat.
fn reentry_time(
    stock: &StockMap,
    pts: &[Vec2],
    closed: bool,
    a: Vec2,
    z: f64,
    p: &LevelParams,
) -> f64 {
    let e = p.entry();
    let z_from = ramp_start(stock, pts, closed, z, &e).max(z);
    let down_to = (z_from + CLEARANCE).min(p.retract_z);
    let rapid = (p.retract_z - z) + a.dist(pts[0]) + (p.retract_z - down_to);
    let ramp = (z_from - z) / p.ramp_angle.to_radians().sin();
    rapid / p.rapid_rate + (down_to - z_from) / p.plunge_feed + ramp / e.ramp_feed()
}

/// Remove moves of no length (a path's repeated point, a link onto the spot
/// where the tool already is), the tool being at `from` before `moves`.
fn drop_zero_length(from: Vec3, moves: &mut Vec<Move>) {
    let mut pos = from;
    moves.retain(|m| {
        let to = m.to();
        let keep = !matches!(m, Move::Linear { .. } | Move::Rapid { .. })
            || (to.x - pos.x).abs() > 1e-9
            || (to.y - pos.y).abs() > 1e-9
            || (to.z - pos.z).abs() > 1e-9;
        if keep {
            pos = to;
        }
        keep
    });
}

/// The paths reordered so that each starts as near as possible to where the one
/// before it starts (greedy, from the first): O(n²), for the few thousand loops
/// at uncut spots a level may need.
fn nearest_neighbour_order(mut paths: Vec<CutPath>) -> Vec<CutPath> {
    let mut out = Vec::with_capacity(paths.len());
    while !paths.is_empty() {
        let k = match out.last() {
            None => 0,
            Some(last) => {
                let at: Vec2 = last_point(last);
                (0..paths.len())
                    .min_by(|&a, &b| {
                        at.dist(paths[a].points[0])
                            .total_cmp(&at.dist(paths[b].points[0]))
                    })
                    .unwrap_or(0)
            }
        };
        out.push(paths.swap_remove(k));
    }
    out
}

fn last_point(c: &CutPath) -> Vec2 {
    c.points[c.points.len() - 1]
}

/// Gap from a new (inner) set of rings `b` to the set outside it `a`: the largest
/// distance from a point of `b` to `a`. (The other direction cannot be bounded by
/// equipotentials: near a convex corner of V, 1 − u ~ r², so every ring cuts the
/// corner by about √(1 − c) while it follows straight walls at a distance ∝ 1 − c;
/// what that leaves uncut is measured by the coverage check instead.)
pub(super) fn ring_gap(a: &[Vec<Vec2>], b: &[Vec<Vec2>]) -> f64 {
    ring_gap_from(ring_index(a).as_ref(), b)
}

/// The index `ring_gap` measures to, None for no rings (built once per ring
/// for the bisection's eight tries, issue 13).
pub(super) fn ring_index(a: &[Vec<Vec2>]) -> Option<DistanceIndex> {
    (!a.is_empty()).then(|| DistanceIndex::new(a))
}

/// [`ring_gap`] with the index of `a` already built (`ring_index`).
pub(super) fn ring_gap_from(ia: Option<&DistanceIndex>, b: &[Vec<Vec2>]) -> f64 {
    let Some(ia) = ia else {
        return f64::INFINITY;
    };
    if b.is_empty() {
        return f64::INFINITY;
    }
    b.iter()
        .flatten()
        .map(|&p| ia.distance(p))
        .fold(0.0, crate::num::max_or_nan)
}

/// The least f64 above a positive finite `x` (f64::next_up, stable only
/// after the crate's MSRV): `closer_than(p, next_up(x))`, "nearer than the
/// next number up", is exactly `distance(p) <= x`.
fn next_up(x: f64) -> f64 {
    debug_assert!(x > 0.0 && x.is_finite());
    f64::from_bits(x.to_bits() + 1)
}

/// A cavity level's wall loops as its paths.
pub(super) fn wall_paths(loops: Vec<Vec<Vec2>>, label: &str) -> Vec<CutPath> {
    loops
        .into_iter()
        .map(|pts| CutPath {
            label: format!("{label}: wall"),
            points: pts,
            closed: true,
            ring: None,
        })
        .collect()
}

/// Level settings for unit tests: a 3.175 mm tool, 1.27 mm stepover, climb,
/// over a 60 mm square stock.
#[cfg(test)]
pub(crate) fn test_params() -> LevelParams {
    LevelParams {
        radius: 1.5875,
        tol: 0.01,
        stepover: 1.27,
        ramp_angle: 3.0,
        climb: true,
        feed: 800.0,
        plunge_feed: 200.0,
        rapid_rate: 1000.0,
        safe_z: 5.0,
        retract_z: 5.0,
        top: 0.0,
        stepdown: 1.0,
        leave: 0.0,
        stock_lo: Vec2::new(-30.0, -30.0),
        stock_hi: Vec2::new(30.0, 30.0),
    }
}

/// A cavity level's pockets (the part's clockwise loops) and islands, each
/// pocket's deepest point and room (its distance from every wall), and the
/// part's distance index.
pub(super) struct Pockets<'a> {
    pub(crate) pockets: &'a [&'a Vec<Vec2>],
    pub(crate) islands: &'a [&'a Vec<Vec2>],
    pub(crate) deepest: &'a [(Vec2, f64)],
    pub(crate) index: &'a DistanceIndex,
}

impl Pockets<'_> {
    /// Whether `q` lies in pocket `k` and in none of the islands.
    fn inside(&self, k: usize, q: Vec2) -> bool {
        inside_pocket(self.pockets[k], self.islands, q)
    }

    /// Where the wall of pocket `k` is traced from by a disk of `radius`:
    /// just below its highest point, so the disk meets that wall and not an
    /// island's, which may be nearer to the deepest point (the Q's counter).
    /// Without islands, or where that point has no room, the deepest point.
    pub(crate) fn start(&self, k: usize, radius: f64, tol: f64) -> Vec2 {
        let (pk, deep) = (self.pockets[k], self.deepest[k].0);
        if self.islands.is_empty() {
            return deep;
        }
        let top = pk.iter().copied().fold(pk[0], |a, b| {
            if b.y > a.y || (b.y == a.y && b.x < a.x) {
                b
            } else {
                a
            }
        });
        let q = top - Vec2::new(0.0, radius + tol);
        if self.inside(k, q) && self.index.distance(q) >= radius {
            q
        } else {
            deep
        }
    }
}

/// Whether `q` lies in `pocket` and in none of `islands`.
fn inside_pocket(pocket: &[Vec2], islands: &[&Vec<Vec2>], q: Vec2) -> bool {
    polygon_winding_number(pocket, q) != 0
        && islands.iter().all(|is| polygon_winding_number(is, q) == 0)
}

/// The point of a pocket farthest from every wall, islands excluded (a
/// pocket's own polygon contains its islands: the counter of a Q's mould is
/// wider than the ring around it, and the tool started inside it), and that
/// distance.
pub(super) fn deepest_in_pocket(
    pk: &[Vec2],
    islands: &[&Vec<Vec2>],
    index: &DistanceIndex,
) -> (Vec2, f64) {
    let (lo, hi) = polygons_bbox(&[pk.to_vec()]).unwrap_or((pk[0], pk[0]));
    let inside = |q: Vec2| inside_pocket(pk, islands, q);
    crate::geometry::deepest_point_in(lo, hi, &inside, index)
}

/// The paths of one level traced in its field `nav`: a cavity's
/// ([`cavity_paths`], with the uncut share of its reachable area) when
/// `cavity`, else a boss's ([`boss_paths`]). `section` is the level's Γ(s)
/// with the part's material on its left (a cavity's: the mould's), `label`
/// names the level in paths and warnings, `band` is the width of the band a
/// level added for the scallop bound clears.
pub(crate) fn level_paths<N: Navigator + Sync>(
    cavity: bool,
    section: &[Vec<Vec2>],
    nav: &N,
    p: &LevelParams,
    label: &str,
    warnings: &mut Vec<String>,
    band: Option<f64>,
) -> Result<(Vec<CutPath>, Option<f64>), ProfileError> {
    if cavity {
        let (paths, uncut) = cavity_paths(section, nav, p, label, warnings, band)?;
        Ok((paths, Some(uncut)))
    } else {
        Ok((boss_paths(section, nav, p, label, warnings, band)?, None))
    }
}

/// The paths of one cavity level. `part` holds the level's Γ(s) loops with the
/// mould's material on their left: pockets clockwise, islands counter-clockwise.
///
/// 1. The finishing loops: the rolling disk inside every pocket and around every
///    island, in the level's field. They bound V, the region the tool centre may
///    reach.
/// 2. The inverse problem of the paper's Section 4 on ∂V: u = 1 on the finishing
///    loops, u = 0 on sinks spread along each pocket (farthest-point selection on
///    the distance to ∂V, so that u does not underflow toward 1 in long strokes),
///    singularities outside V and inside the sinks.
/// 3. Clearing rings: equipotentials of that field, each value chosen by bisection
///    so that neighbouring rings are at most `stepover` apart (symmetric Hausdorff
///    distance, measured), until every ring is small enough for the tool to cover
///    its inside.
/// 4. Coverage: the uncut share of the reachable area, on a grid.
///
/// With `band` (a level added for the scallop bound) the rings stop once they
/// are deeper than that from the wall and coverage is measured within it: the
/// next stepdown level below clears the rest.
pub(crate) fn cavity_paths<N: Navigator + Sync>(
    part: &[Vec<Vec2>],
    nav: &N,
    p: &LevelParams,
    label: &str,
    warnings: &mut Vec<String>,
    band: Option<f64>,
) -> Result<(Vec<CutPath>, f64), ProfileError> {
    use crate::count::{set_stage, Stage};
    let index = DistanceIndex::new(part);
    // The wall loops keep `rw` (radius + stock to leave) from the part; the
    // coverage below is measured with the tool's true radius `r`.
    let r = p.radius;
    let rw = p.wall();
    let tp = TraceParams {
        radius: rw,
        tol: p.tol,
        part_on_left: !p.climb,
    };
    let pockets: Vec<&Vec<Vec2>> = part.iter().filter(|q| polygon_area(q) < 0.0).collect();
    let islands: Vec<&Vec<Vec2>> = part.iter().filter(|q| polygon_area(q) > 0.0).collect();
    // Each pocket's deepest point and its room (a grid search), once.
    let deepest: Vec<(Vec2, f64)> = pockets
        .iter()
        .map(|pk| deepest_in_pocket(pk, &islands, &index))
        .collect();
    let pk = Pockets {
        pockets: &pockets,
        islands: &islands,
        deepest: &deepest,
        index: &index,
    };
    // 1. Finishing loops.
    let mut finish: Vec<Vec<Vec2>> = Vec::new();
    for (i, &(_, room)) in deepest.iter().enumerate() {
        if room < rw + p.tol {
            warnings.push(format!(
                "{label}: pocket {} is too narrow for the tool (room {room:.3} mm): not cut",
                i + 1
            ));
            continue;
        }
        let t = trace(nav, &index, pk.start(i, rw, p.tol), tp).map_err(|source| {
            ProfileError::Trace {
                label: format!("{label}: wall of pocket {}", i + 1),
                source,
            }
        })?;
        finish.push(t.points);
    }
    let n_pocket_walls = finish.len();
    for (i, is) in islands.iter().enumerate() {
        let start = lowest(is) - Vec2::new(0.0, rw + p.tol);
        match trace(nav, &index, start, tp) {
            Ok(t) => finish.push(t.points),
            Err(source) => {
                return Err(ProfileError::Trace {
                    label: format!("{label}: around island {}", i + 1),
                    source,
                })
            }
        }
    }
    if finish.is_empty() {
        return Ok((Vec::new(), 0.0));
    }
    // A band no wider than the tool's radius or the stepover (a level added for
    // the scallop bound; the level below, cut first, cleared inside its own
    // contour): the wall loops alone clear it, engaging at most the band's width.
    // A reachable point of the band lies within r of the wall loops (the
    // boundary of where the centre may go), so the coverage measure below would
    // find nothing; `pfcam simulate` checks the part on the stock model instead.
    if band.is_some_and(|d| d <= r.min(p.stepover)) {
        return Ok((wall_paths(finish, label), 0.0));
    }
    // A wider band, up to a few stepovers: offset rings, then the walls; the
    // offsets cover the band by construction, and `pfcam simulate` measures it.
    if let Some(d) = band.filter(|&d| d <= super::band::MAX_BAND_STEPOVERS * p.stepover) {
        if let Some(mut paths) = super::band::band_rings(part, &index, p, label, d) {
            paths.extend(wall_paths(finish, label));
            return Ok((paths, 0.0));
        }
    }
    // A whole level, or a wider band: offset rings too, from the deepest in
    // out to the wall, then loops at what they leave (`cover_left`). They are
    // a stepover apart everywhere, so they cut about area ÷ stepover; the
    // inverse problem's equipotentials, a stepover apart only where they are
    // farthest apart, cut 24.9 m on mfs-mould's first level where these cut
    // 11.9 m (docs/method.md §9, *Cavity*).
    let room = deepest.iter().map(|d| d.1).fold(0.0, f64::max);
    let reach = band.map_or(room, |b| b.min(room));
    set_stage(Stage::Rings);
    if let Some(mut paths) = super::band::band_rings(part, &index, p, label, reach) {
        let v = orient_v(&finish, n_pocket_walls);
        paths.extend(wall_paths(finish, label));
        return cover_left(part, &index, &v, paths, p, band, label);
    }
    // Offset rings could not be built: the inverse problem's equipotentials
    // (`super::inverse`).
    match super::inverse::inverse_paths(nav, &pk, p, label, band, finish)? {
        (paths, Some(oriented)) => cover_left(part, &index, &oriented, paths, p, band, label),
        (paths, None) => Ok((paths, 0.0)),
    }
}

/// The region a cavity level's tool centre may go, from its closed wall
/// loops (the first `n_pockets` around pockets, the rest around islands),
/// oriented for the inverse problem and the coverage masks: pocket loops
/// clockwise (outside the region on their left), island loops
/// counter-clockwise; the closing point dropped.
pub(super) fn orient_v(loops: &[Vec<Vec2>], n_pockets: usize) -> Vec<Vec<Vec2>> {
    loops
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let l = &l[..l.len() - 1];
            if (polygon_area(l) < 0.0) == (i < n_pockets) {
                l.to_vec()
            } else {
                l.iter().rev().copied().collect()
            }
        })
        .collect()
}

/// A mask for `Grid::sample` that marks everything but the region V as
/// material: a rectangle `pad` beyond V's box `lo`..`hi`, and V's loops
/// (pocket loops clockwise, island loops counter-clockwise) cut from it.
pub(super) fn region_mask(v: &[Vec<Vec2>], lo: Vec2, hi: Vec2, pad: f64) -> Vec<Vec<Vec2>> {
    let (a, b) = (lo - Vec2::new(pad, pad), hi + Vec2::new(pad, pad));
    let mut mask = vec![vec![a, Vec2::new(b.x, a.y), b, Vec2::new(a.x, b.y)]];
    mask.extend(v.iter().cloned());
    mask
}

/// Coverage of a cavity level by its paths, and loops at the spots they
/// leave. `v` is the region the tool centre may go (pocket loops clockwise,
/// island loops counter-clockwise). Returns the paths, the spots' loops first,
/// and the share of the reachable area still uncut.
pub(super) fn cover_left(
    part: &[Vec<Vec2>],
    index: &DistanceIndex,
    v: &[Vec<Vec2>],
    mut paths: Vec<CutPath>,
    p: &LevelParams,
    band: Option<f64>,
    label: &str,
) -> Result<(Vec<CutPath>, f64), ProfileError> {
    use crate::count::{set_stage, Stage};
    let vindex = DistanceIndex::new(v);
    let Some((lo, hi)) = polygons_bbox(v) else {
        return Ok((paths, 0.0));
    };
    // 4. Coverage: reachable points (in V, or within r of V) not within r of a path,
    // on a grid of r/10. Where points are left (between rings that part around a
    // lobe), small loops of radius r/2 are added at them, centred where the tool
    // centre may go, and coverage is measured again.
    set_stage(Stage::Coverage);
    let cov = Coverage::new(part, index, v, &vindex, (lo, hi), p.radius, band);
    let (reach, mut left) = cov.measure(&paths);
    if !left.is_empty() {
        let spots = cov.spot_loops(&left, p, label);
        // Cut first, each next to the last, so the linker can step from one to
        // the next at depth instead of retracting and ramping in again.
        paths.splice(0..0, nearest_neighbour_order(spots));
        left = cov.measure(&paths).1;
    }
    let frac = if reach > 0 {
        left.len() as f64 / reach as f64
    } else {
        0.0
    };
    Ok((paths, frac))
}

/// The coverage grid of a cavity level: points inside the cavity (spacing
/// r/10, at least 0.05 mm) over V's box grown by 2r, and which of them lie
/// outside V (where the tool centre may not go).
struct Coverage<'a> {
    index: &'a DistanceIndex,
    vindex: &'a DistanceIndex,
    in_cavity: crate::field::isolines::Grid,
    out_v: crate::field::isolines::Grid,
    r: f64,
    hc: f64,
    band: Option<f64>,
}

impl<'a> Coverage<'a> {
    fn new(
        part: &[Vec<Vec2>],
        index: &'a DistanceIndex,
        v: &[Vec<Vec2>],
        vindex: &'a DistanceIndex,
        (lo, hi): (Vec2, Vec2),
        r: f64,
        band: Option<f64>,
    ) -> Coverage<'a> {
        use crate::field::isolines::Grid;
        let pad = Vec2::new(2.0 * r, 2.0 * r);
        // The mask's rectangle reaches past the grid below (whose last row and
        // column may overshoot `hi + pad` by a spacing): outside it the mask
        // reads "not material", which would put a sliver of the part's thin
        // serifs beyond V's box into V.
        let mask = region_mask(v, lo, hi, 4.0 * r);
        let hc = (r / 10.0).max(0.05);
        let empty = crate::field::Field::new(vec![], vec![]);
        let pocket_mask: Vec<Vec<Vec2>> = part
            .iter()
            .map(|q| q.iter().rev().copied().collect())
            .collect();
        Coverage {
            index,
            vindex,
            in_cavity: Grid::sample(&empty, lo - pad, hi + pad, hc, &pocket_mask),
            out_v: Grid::sample(&empty, lo - pad, hi + pad, hc, &mask),
            r,
            hc,
            band,
        }
    }

    /// The grid point at `(i, j)`.
    fn point(&self, i: usize, j: usize) -> Vec2 {
        let g = &self.in_cavity;
        Vec2::new(
            g.origin.x + self.hc * i as f64,
            g.origin.y + self.hc * j as f64,
        )
    }

    /// How many grid points the tool can reach (in V or within r of it, and
    /// within the band's reach of the wall), and those of them farther than
    /// r from every path.
    fn measure(&self, paths: &[CutPath]) -> (usize, Vec<Vec2>) {
        let r = self.r;
        let all: Vec<Vec<Vec2>> = paths
            .iter()
            .map(|c| c.points[..c.points.len() - 1].to_vec())
            .collect();
        let pindex = DistanceIndex::new(&all);
        let hints: [std::cell::Cell<u32>; 3] = Default::default();
        let (mut reach, mut left) = (0usize, Vec::new());
        let g = &self.in_cavity;
        for j in 0..g.ny {
            for i in 0..g.nx {
                let k = j * g.nx + i;
                if !g.inside[k] {
                    continue;
                }
                let q = self.point(i, j);
                // `closer_than(q, next_up(x))` is exactly `distance(q) <= x`
                // (the same minimum over the edges), but stops at the first
                // edge that decides it and needs no nearest point: the
                // coverage grid asks millions of these (issue 13).
                if self
                    .band
                    .is_some_and(|d| !self.index.closer_than(q, next_up(d + r), &hints[0]))
                {
                    continue;
                }
                let in_v = !self.out_v.inside[k];
                if in_v || self.vindex.closer_than(q, next_up(r), &hints[1]) {
                    reach += 1;
                    if !pindex.closer_than(q, next_up(r + 1e-9), &hints[2]) {
                        left.push(q);
                    }
                }
            }
        }
        (reach, left)
    }

    /// Whether the grid point nearest `q` lies in V.
    fn in_v(&self, q: Vec2) -> bool {
        let g = &self.in_cavity;
        let i = ((q.x - g.origin.x) / self.hc).round() as usize;
        let j = ((q.y - g.origin.y) / self.hc).round() as usize;
        !self.out_v.inside[(j.min(g.ny - 1)) * g.nx + i.min(g.nx - 1)]
    }

    /// Loops of radius r/2 at the uncut points `left` (one per cluster),
    /// centred at the point or pulled into V when it lies near ∂V, skipped
    /// where such a loop would not keep clear of ∂V and of the part.
    fn spot_loops(&self, left: &[Vec2], p: &LevelParams, label: &str) -> Vec<CutPath> {
        let (r, hc) = (self.r, self.hc);
        let dab_r = 0.5 * r;
        let mut dabs: Vec<Vec2> = Vec::new();
        let mut spots: Vec<CutPath> = Vec::new();
        for &q in left {
            if dabs.iter().any(|d| d.dist(q) <= r + dab_r - 2.0 * hc) {
                continue;
            }
            let (dv, near) = self.vindex.nearest(q);
            let c = if !self.in_v(q) {
                continue;
            } else if dv >= dab_r + p.tol {
                q
            } else {
                q + (q - near).normalized() * (dab_r + p.tol - dv)
            };
            if self.vindex.distance(c) < dab_r + 0.5 * p.tol || self.index.distance(c) < r + dab_r {
                continue;
            }
            dabs.push(c);
            spots.push(spot_loop(
                c,
                dab_r,
                format!("{label}: loop at an uncut spot"),
            ));
        }
        spots
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The coverage measure's shortcut: `closer_than(q, next_up(x))` answers
    /// `distance(q) <= x` exactly, including points at exactly x from an edge
    /// (integer coordinates: the distances below are exact).
    #[test]
    fn closer_than_next_up_is_distance_at_most() {
        let square = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(4.0, 0.0),
            Vec2::new(4.0, 4.0),
            Vec2::new(0.0, 4.0),
        ];
        let index = DistanceIndex::new(&[square]);
        let hint = std::cell::Cell::new(0);
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut rnd = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut ties, mut both) = (0, [0, 0]);
        for k in 0..20_000 {
            // Half on the integer lattice (exact ties), half anywhere.
            let q = if k % 2 == 0 {
                Vec2::new((rnd() * 10.0).floor() - 3.0, (rnd() * 10.0).floor() - 3.0)
            } else {
                Vec2::new(rnd() * 10.0 - 3.0, rnd() * 10.0 - 3.0)
            };
            for x in [1.0, 2.0, 0.5 + rnd()] {
                let d = index.distance(q);
                let exact = d <= x;
                ties += usize::from(d == x);
                both[usize::from(exact)] += 1;
                assert_eq!(index.closer_than(q, next_up(x), &hint), exact, "{q:?} {x}");
            }
        }
        assert!(
            ties > 100 && both[0] > 100 && both[1] > 100,
            "{ties} {both:?}"
        );
    }

    /// A NaN point makes the gap between rings NaN (f64::max would have
    /// dropped it and read the gap as the others' largest), which
    /// cavity_paths refuses as a bug instead of placing a ring by it.
    #[test]
    fn a_nan_point_makes_the_ring_gap_nan() {
        let square = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(10.0, 0.0),
            Vec2::new(10.0, 10.0),
            Vec2::new(0.0, 10.0),
        ];
        let mut inner: Vec<Vec2> = square
            .iter()
            .map(|&p| p * 0.5 + Vec2::new(2.5, 2.5))
            .collect();
        let gap = ring_gap(std::slice::from_ref(&inner), std::slice::from_ref(&square));
        assert!((gap - 2.5 * 2f64.sqrt()).abs() < 1e-12, "{gap}");
        inner[1] = Vec2::new(f64::NAN, 3.0);
        assert!(ring_gap(&[square], &[inner]).is_nan());
    }
}
