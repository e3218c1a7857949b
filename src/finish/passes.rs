//! The finishing passes: the curves the finisher's contact points follow,
//! spaced so that the cutter's scallop stays under the bound.
//!
//! The wall's own passes are the levels σ = k·w of the distance on S2 from
//! the top edge ([`super::geodesic`]), w the cutter's pass width for the
//! scallop bound ([`pass_width`]): w apart on the surface everywhere, closed
//! where the wall is taller than k·w all round, open arcs ending on the foot
//! where it is not. The foot Γ(s_foot) and the top edge Γ(s_top) are
//! equipotentials, cut whole. Past the foot of the wall (where the roughing
//! left `stock_to_leave` on the floor) the foot's loops are offset over the
//! flat floor, w apart, until the last one lies `leave` out.

use super::geodesic::{self, Curve, Distance};
use super::FinishError;
use crate::field::isolines::Grid;
use crate::field::level::curves;
use crate::field::Field;
use crate::geometry::{DistanceIndex, Ring, Vec2};
use crate::levels::DepthProfile;
use rayon::prelude::*;

/// Most passes of one program (a bound on work and file size; the job's
/// `machine.max_hours` and `machine.max_file_mb` usually stop it first).
pub(crate) const MAX_PASSES: usize = 2000;

/// Distance between neighbouring contact points for a scallop of height `h`
/// under a cutter corner of radius `rc`, mm: a circle of radius rc stepped w
/// along a flat leaves h = rc − √(rc² − w²/4), so w = 2√(2·rc·h − h²). A flat
/// end mill (rc = 0) leaves a stair whose corner stands w·sinθ·cosθ ≤ w/2 off
/// the surface: w = 2h.
pub(crate) fn pass_width(rc: f64, h: f64) -> f64 {
    if rc <= 0.0 {
        2.0 * h
    } else {
        2.0 * (2.0 * rc * h - h * h).max(0.0).sqrt()
    }
}

/// dφ/ds by central differences (one-sided at the ends of φ's range, 0
/// outside it, where φ is flat).
pub(crate) fn dphi_ds(profile: &DepthProfile, s: f64) -> f64 {
    let (lo, hi) = profile.s_range();
    if s < lo || s > hi {
        return 0.0;
    }
    let e = 1e-7 * (hi - lo);
    let (a, b) = ((s - e).max(lo), (s + e).min(hi));
    (profile.z(b) - profile.z(a)) / (b - a)
}

/// The curves Γ(s) of a field, from one grid (`field::level::curves`, as the
/// level planner extracts them).
pub(crate) struct Curves<'a> {
    /// The field.
    pub(crate) field: &'a Field,
    /// u sampled over the part.
    pub(crate) grid: Grid,
    /// The glyphs (the material where u is pinned to 1).
    pub(crate) glyphs: &'a [Vec<Vec2>],
    /// Grid spacing, mm.
    pub(crate) h: f64,
    /// Chord tolerance, mm.
    pub(crate) tol: f64,
}

impl Curves<'_> {
    /// Γ(s) as rings.
    pub(crate) fn at(&self, s: f64) -> Vec<Ring> {
        curves(&self.grid, self.field, self.glyphs, s, self.h, self.tol)
    }

    /// The smallest |∇u| over the vertices of `ring` (where the passes are
    /// farthest apart), or `None` if ∇u vanishes.
    fn min_grad(&self, ring: &Ring) -> Option<f64> {
        let mut m = f64::INFINITY;
        for &p in ring.points() {
            let g = self.field.grad(p).norm();
            if !(g > 0.0 && g.is_finite()) {
                return None;
            }
            m = m.min(g);
        }
        m.is_finite().then_some(m)
    }

    /// σ, the distance on S2 from the top edge ([`geodesic::Distance`]), on
    /// a grid of [`geodesic::SPACING`] over this grid's box; `z_of(s)` is
    /// S2's height where u = s, `corner` the cutter's corner radius.
    pub(crate) fn distance(
        &self,
        profile: &DepthProfile,
        (cavity, corner): (bool, f64),
        z_of: &dyn Fn(f64) -> f64,
    ) -> Distance {
        let g = &self.grid;
        let hi = g.origin + Vec2::new(g.h * (g.nx - 1) as f64, g.h * (g.ny - 1) as f64);
        let fine = Grid::sample(self.field, g.origin, hi, geodesic::SPACING, self.glyphs);
        Distance::from_top_edge(&fine, profile, (cavity, corner), z_of)
    }
}

/// Where a pass lies: on an equipotential Γ(s) (the floor's, the foot's and
/// the top edge's), or at distance σ = d (mm) on S2 from the top edge
/// ([`super::geodesic`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum At {
    /// On Γ(s).
    S(f64),
    /// σ = d, mm.
    D(f64),
}

/// One pass: where it lies and its curves.
pub(crate) type Pass = (At, Vec<Curve>);

/// The passes from the floor up, the floor's first.
pub(crate) struct Planned {
    /// The passes in the order the finisher cuts them (ascending z).
    pub(crate) passes: Vec<Pass>,
    /// How many of `passes` lie over the floor; the next is the foot's.
    pub(crate) floor: usize,
}

/// The passes from the floor up (see [`Planned`]): the floor's, then the
/// wall's. With `geodesic` (σ of [`geodesic::Distance`]) the wall's are the
/// foot Γ(s_foot), the levels of σ from the deepest ([`geodesic::passes`])
/// and the top edge Γ(s_top); without, the wall's candidate levels
/// (`candidate_levels`) with each loop kept only where its wall's spacing
/// needs it (`thin`). `cavity` mirrors the profile (its floor is at the
/// high end of s). Errors name what failed.
pub(crate) fn pass_levels(
    curves: &Curves,
    geodesic: Option<&Distance>,
    profile: &DepthProfile,
    cavity: bool,
    w: f64,
    leave: f64,
) -> Result<Planned, FinishError> {
    let (lo, hi) = profile.s_range();
    let (foot, top) = if cavity { (hi, lo) } else { (lo, hi) };
    let foot_loops = curves.at(foot);
    if foot_loops.is_empty() {
        return Err(FinishError::FootWithoutCurve { foot });
    }
    let mut passes = floor_passes(curves.field, (foot, &foot_loops), cavity, w, leave);
    let floor = passes.len();
    let wall = match geodesic {
        Some(dist) => geodesic_wall(curves, dist, (foot, top), foot_loops, w)?,
        None => equipotential_wall(curves, profile, (foot, top), foot_loops, (w, floor))?,
    };
    passes.extend(wall);
    Ok(Planned { passes, floor })
}

/// The wall's passes along equipotentials: the candidate levels, each loop
/// kept where [`thin`] says; `w` the pass width, `before` the passes already
/// planned.
fn equipotential_wall(
    curves: &Curves,
    profile: &DepthProfile,
    ends: (f64, f64),
    foot_loops: Vec<Ring>,
    (w, before): (f64, usize),
) -> Result<Vec<Pass>, FinishError> {
    let levels = candidate_levels(curves, profile, ends, foot_loops, w, before)?;
    let cut = thin(&levels, profile, w);
    Ok(levels
        .into_iter()
        .zip(cut)
        .filter_map(|(l, keep)| {
            let loops: Vec<Curve> = l
                .loops
                .into_iter()
                .zip(keep)
                .filter_map(|(lp, k)| k.then(|| Curve::closed(lp.into_points())))
                .collect();
            (!loops.is_empty()).then_some((At::S(l.s), loops))
        })
        .collect())
}

/// The wall's passes along the levels of σ: the foot, the levels from the
/// deepest, the top edge.
fn geodesic_wall(
    curves: &Curves,
    dist: &Distance,
    (foot, top): (f64, f64),
    foot_loops: Vec<Ring>,
    w: f64,
) -> Result<Vec<Pass>, FinishError> {
    let closed = |loops: Vec<Ring>| -> Vec<Curve> {
        loops
            .into_iter()
            .map(|l| Curve::closed(l.into_points()))
            .collect()
    };
    let foot_curves = closed(foot_loops);
    let wall = geodesic::passes(dist, &foot_curves, w, MIN_CURVE, MAX_PASSES)
        .map_err(|n| FinishError::TooManyPasses { n, max: MAX_PASSES })?;
    let mut passes = vec![(At::S(foot), foot_curves)];
    passes.extend(wall.into_iter().map(|(d, c)| (At::D(d), c)));
    let top_loops = curves.at(top);
    if !top_loops.is_empty() {
        passes.push((At::S(top), closed(top_loops)));
    }
    Ok(passes)
}

/// Shortest curve of σ a pass keeps, mm: shorter ones are the grid's
/// crumbs round a maximum of σ within a cell or two, which the passes on
/// either side cover.
pub(crate) const MIN_CURVE: f64 = 1.0;

/// Over the floor, outwards from the foot Γ(`foot`): the foot's loops
/// offset along the field's downhill direction by k·w (k = 1, 2, ...) until
/// the last pass's band, w/2 either side of it, reaches `leave` + w/2 (k·w ≥
/// `leave`; the foot's own pass covers the first w/2), the farthest first. Equipotentials would be as
/// far apart there as |∇u| varies along the foot; the floor is flat, so plain
/// offsets are the even spacing (a loop of the foot is smooth, far rounder
/// than these few tenths of a millimetre). Their s lies just past φ's range:
/// flat.
fn floor_passes(
    field: &Field,
    foot: (f64, &[Ring]),
    cavity: bool,
    w: f64,
    leave: f64,
) -> Vec<Pass> {
    let (away, up) = if cavity { (1.0, -1.0) } else { (-1.0, 1.0) };
    let k_max = ((leave / w).ceil() as usize).max(1);
    let s_floor = foot.0 - up * 1e-9;
    (1..=k_max)
        .rev()
        .map(|k| {
            let d = k as f64 * w;
            let loops = foot
                .1
                .iter()
                .map(|l| {
                    Curve::closed(
                        l.points()
                            .iter()
                            .map(|&p| p + field.grad(p).normalized() * (away * d))
                            .collect(),
                    )
                })
                .collect();
            (At::S(s_floor), loops)
        })
        .collect()
}

/// Distance on S2 per unit of s where |∇u| = g and φ' = dphi, mm.
fn spread(g: f64, dphi: f64) -> f64 {
    (1.0 / (g * g) + dphi * dphi).sqrt()
}

/// Candidate levels per pass width: the wall's candidate levels Γ(s) lie
/// w/REFINE apart where Γ(s) is most spread, and each wall (each loop of
/// Γ(s) and its continuation up the wall) is cut only at the candidates it
/// needs (`thin`).
pub(crate) const REFINE: usize = 2;

/// A candidate level of the wall: s, the loops of Γ(s) and the least |∇u|
/// over each loop.
struct Level {
    s: f64,
    loops: Vec<Ring>,
    grad: Vec<f64>,
}

/// The candidate levels up the wall, from the foot to the top edge
/// (`ends`): Δs = (w/[`REFINE`]) / max over Γ(s) of the spread apart (the
/// slope may steepen over the step: the larger spread of its ends).
/// `before` passes are already planned (they count towards
/// [`MAX_PASSES`]).
fn candidate_levels(
    curves: &Curves,
    profile: &DepthProfile,
    (foot, top): (f64, f64),
    foot_loops: Vec<Ring>,
    w: f64,
    before: usize,
) -> Result<Vec<Level>, FinishError> {
    let up = if top > foot { 1.0 } else { -1.0 };
    let step = w / REFINE as f64;
    let level = |s: f64, loops: Vec<Ring>| -> Result<Level, FinishError> {
        let grad = loops
            .par_iter()
            .map(|l| curves.min_grad(l))
            .collect::<Option<Vec<f64>>>()
            .ok_or(FinishError::GradientVanishes { s })?;
        Ok(Level { s, loops, grad })
    };
    let mut out = vec![level(foot, foot_loops)?];
    let mut s = foot;
    while (top - s) * up > 1e-12 {
        if before + out.len() >= MAX_PASSES * REFINE {
            return Err(FinishError::TooManyLevels { max: MAX_PASSES });
        }
        let last = &out[out.len() - 1];
        let g = last.grad.iter().copied().fold(f64::INFINITY, f64::min);
        let mut next = next_level(profile, s, up, g, step);
        if (next - top) * up > -1e-9 {
            next = top;
        }
        let next_loops = curves.at(next);
        if next_loops.is_empty() {
            break;
        }
        out.push(level(next, next_loops)?);
        s = next;
    }
    Ok(out)
}

/// The next candidate level above `s` (`up` = ±1 towards the top) for a
/// least |∇u| of `g`: Δs with Δs·spread(g, max(|φ′(s)|, |φ′(s + Δs)|)) =
/// `step`, found by fixed-point
/// iteration on the slope at the far end and, should it not have settled,
/// shrunk until the bound holds.
fn next_level(profile: &DepthProfile, s: f64, up: f64, g: f64, step: f64) -> f64 {
    let d0 = dphi_ds(profile, s).abs();
    let bound = |next: f64| (next - s).abs() * spread(g, d0.max(dphi_ds(profile, next).abs()));
    let mut next = s + up * step / spread(g, d0);
    for _ in 0..8 {
        let d = d0.max(dphi_ds(profile, next).abs());
        next = s + up * step / spread(g, d);
    }
    let mut k = 0;
    while bound(next) > step && k < 60 {
        next = s + 0.99 * (next - s);
        k += 1;
    }
    next
}

/// Which loops of each candidate level the contact points' spacing needs.
/// Each loop carries `acc`, a bound on the distance on S2 from the last pass
/// cut below it on its wall: a step from a loop of level k to a loop of
/// level k + 1 near it (within 2w: its predecessor; several where loops
/// merge, or split) adds Δs × the spread of the lower loop's least |∇u|
/// and the steeper of the two levels' slopes φ′, the bound
/// [`next_level`] spaces the levels by. A loop is cut when a
/// step to one of its successors would take that bound past w (or when it
/// has none), else skipped. The foot, the top edge and loops with no
/// predecessor are always cut.
fn thin(levels: &[Level], profile: &DepthProfile, w: f64) -> Vec<Vec<bool>> {
    let n = levels.len();
    let mut cut: Vec<Vec<bool>> = levels
        .iter()
        .enumerate()
        .map(|(k, l)| vec![k == 0 || k + 1 == n; l.loops.len()])
        .collect();
    let mut acc = vec![0.0; levels.first().map_or(0, |l| l.loops.len())];
    for k in 0..n.saturating_sub(1) {
        let (a, b) = (&levels[k], &levels[k + 1]);
        let dphi = dphi_ds(profile, a.s).abs().max(dphi_ds(profile, b.s).abs());
        let ds = (b.s - a.s).abs();
        let preds = predecessors(&a.loops, &b.loops, 2.0 * w);
        let step = |i: usize| ds * spread(a.grad[i], dphi);
        for i in 0..a.loops.len() {
            let succ: Vec<usize> = (0..b.loops.len())
                .filter(|&j| preds[j].contains(&i))
                .collect();
            let worst = succ.iter().map(|_| acc[i] + step(i)).fold(0.0, f64::max);
            if succ.is_empty() || worst > w * (1.0 + 1e-9) {
                cut[k][i] = true;
            }
            if cut[k][i] {
                acc[i] = 0.0;
            }
        }
        acc = (0..b.loops.len())
            .map(|j| {
                preds[j]
                    .iter()
                    .map(|&i| acc[i] + step(i))
                    .fold(0.0, f64::max)
            })
            .collect();
        for (j, p) in preds.iter().enumerate() {
            if p.is_empty() {
                cut[k + 1][j] = true;
            }
        }
    }
    cut
}

/// For each curve of `next`, the curves of `below` that come within `reach`
/// of it.
fn predecessors(below: &[Ring], next: &[Ring], reach: f64) -> Vec<Vec<usize>> {
    let index: Vec<DistanceIndex> = below
        .iter()
        .map(|l| DistanceIndex::new(std::slice::from_ref(l)))
        .collect();
    next.iter()
        .map(|m| {
            (0..below.len())
                .filter(|&i| {
                    let hint = std::cell::Cell::new(0);
                    (m.points().iter()).any(|&p| index[i].closer_than(p, reach, &hint))
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pass_width_gives_the_scallop_back() {
        for (rc, h) in [(1.5875, 0.01), (3.0, 0.002), (0.5, 0.05)] {
            let w = pass_width(rc, h);
            // Two circles of radius rc, w apart: the cusp between them.
            let cusp = rc - (rc * rc - 0.25 * w * w).sqrt();
            assert!((cusp - h).abs() < 1e-12, "{rc} {h}: {cusp}");
        }
        assert_eq!(pass_width(0.0, 0.01), 0.02);
    }

    #[test]
    fn the_profile_slope_matches_its_finite_difference_and_is_zero_outside() {
        let p = DepthProfile::Sigmoid {
            s1: 0.97,
            s2: 0.9,
            steepness: 6.0,
            depth: 3.0,
        };
        for s in [0.91, 0.93, 0.95, 0.965] {
            let e = 1e-5;
            let fd = (p.z(s + e) - p.z(s - e)) / (2.0 * e);
            assert!((dphi_ds(&p, s) - fd).abs() < 1e-4 * fd.abs(), "{s}");
        }
        assert_eq!(dphi_ds(&p, 0.85), 0.0);
        assert_eq!(dphi_ds(&p, 0.99), 0.0);
    }

    /// Two walls round one centre, the inner one's |∇u| five times the
    /// outer's: each wall's cut passes lie at most w apart by the bound
    /// `thin` sums (checked here from the levels), the ends are cut, and the
    /// steeper-gradient wall needs fewer passes.
    #[test]
    fn each_wall_takes_its_own_spacing_within_the_pass_width() {
        let p = DepthProfile::Linear {
            s_bottom: 0.9,
            depth: 3.0,
        };
        let circle = |r: f64| -> Ring {
            let pts = (0..200).map(|k| {
                let t = k as f64 / 200.0 * std::f64::consts::TAU;
                Vec2::new(r * t.cos(), r * t.sin())
            });
            Ring::new(pts.collect()).expect("a circle")
        };
        let (w, g) = (pass_width(1.5875, 0.01), [0.01, 0.05]);
        let levels: Vec<Level> = (0..=40)
            .map(|k| Level {
                s: 0.9 + k as f64 * 0.0005,
                loops: vec![
                    circle(20.0 - 0.02 * k as f64),
                    circle(5.0 + 0.02 * k as f64),
                ],
                grad: g.to_vec(),
            })
            .collect();
        let cut = thin(&levels, &p, w);
        let mut count = [0; 2];
        for wall in 0..2 {
            let mut acc = 0.0;
            for k in 0..levels.len() {
                if cut[k][wall] {
                    count[wall] += 1;
                    acc = 0.0;
                }
                if k + 1 < levels.len() {
                    let d = dphi_ds(&p, levels[k].s)
                        .abs()
                        .max(dphi_ds(&p, levels[k + 1].s).abs());
                    acc += (levels[k + 1].s - levels[k].s) * spread(g[wall], d);
                    assert!(acc <= w * (1.0 + 1e-9), "wall {wall} level {k}: {acc}");
                }
            }
            assert!(cut[0][wall] && cut[levels.len() - 1][wall]);
        }
        assert!(count[1] < count[0], "{count:?}");
    }
}
