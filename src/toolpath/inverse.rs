//! Clearing a cavity level by the inverse problem's equipotentials, where
//! offset rings could not be built (`toolpath::band`): the fallback of
//! [`super::zlevel::cavity_paths`].
//!
//! 1. A second loop one stepover in from each wall, by the rolling disk: it
//!    keeps the wall's sharp corners, which the equipotential rings would cut
//!    by more than the tool can bridge (the measured uncut area sat in those
//!    corners). The inverse problem is solved inside these loops.
//! 2. The inverse problem (`field::inverse`): u = 1 on those loops, 0 on sinks
//!    deep inside.
//! 3. Clearing rings: equipotentials of that field, each value chosen by
//!    bisection so that neighbouring rings are at most `stepover` apart
//!    (symmetric Hausdorff distance, measured), until every ring is small
//!    enough for the tool to cover its inside (`rings`).

use super::profile::ProfileError;
use super::trace::{trace, Navigator, TraceParams};
use super::zlevel::{
    lowest, orient_v, region_mask, ring_gap, ring_gap_from, ring_index, wall_paths, CutPath,
    LevelParams, Pockets,
};
use crate::count::{set_stage, Stage};
use crate::field::isolines::{isolines, isolines_linear, Grid};
use crate::field::{Field, Sink};
use crate::geometry::{polygons_bbox, DistanceIndex, Ring, Vec2};

/// The clearing paths of a level and the region V their coverage is
/// measured in (`None`: the wall loops are the whole cut).
pub(super) type Cleared = (Vec<CutPath>, Option<Vec<Vec<Vec2>>>);

/// Most clearing rings of one level.
const MAX_RINGS: usize = 400;

/// The clearing paths of a cavity level by the inverse problem, with the
/// region V their coverage is measured in (its boundary loops, oriented), or
/// `None` for V when the wall loops `finish` are the whole cut (V is too
/// small for a ring or a sink).
pub(super) fn inverse_paths<N: Navigator + Sync>(
    nav: &N,
    pk: &Pockets,
    p: &LevelParams,
    label: &str,
    band: Option<f64>,
    finish: Vec<Vec<Vec2>>,
) -> Result<Cleared, ProfileError> {
    let r = p.radius;
    let (second, n_pockets2) = second_loops(nav, pk, p);
    let inner_paths = second.clone();
    let finish_all = finish.clone();
    // V's boundary, oriented for the inverse problem: pocket loops clockwise
    // (outside V on their left), island loops counter-clockwise.
    let oriented = if n_pockets2 > 0 {
        orient_v(&second, n_pockets2)
    } else {
        orient_v(&finish, pk.pockets.len())
    };
    let Some((lo, hi)) = polygons_bbox(&oriented) else {
        return Ok((wall_paths(finish_all, label), None));
    };
    let vindex = DistanceIndex::new(&oriented);
    let mask = region_mask(&oriented, lo, hi, 4.0 * r);
    let h = (p.stepover / 4.0).max(0.05);
    set_stage(Stage::LevelSolve);
    let sinks = crate::field::inverse::sinks(&vindex, lo, hi, h, &mask);
    // No grid point of V lies deeper than h/2 ≤ r from its boundary: the
    // finishing loops' tool covers all of V, so the walls are the whole cut
    // (nothing for the user to act on, so no warning).
    if sinks.is_empty() {
        return Ok((wall_paths(finish_all, label), None));
    }
    let field = crate::field::inverse::solve(&oriented, &sinks, lo, hi, p.stepover, p.tol)?;
    // Local expansions over the grid's box (docs/method.md §12).
    let inv = field.accelerated_around(lo, hi);
    set_stage(Stage::InverseGrid);
    let grid = inverse_grid(&inv, &sinks, lo, hi, h, &mask);
    let v = Region {
        oriented: &oriented,
        vindex: &vindex,
        mask: &mask,
    };
    let rings = rings(&grid, &inv, &v, pk.index, p, band, label)?;
    // Cutting order: innermost rings first, then outward, then the walls.
    let mut paths = Vec::new();
    for (k, set) in rings.iter().enumerate().rev() {
        for l in set {
            let mut pts = l.clone();
            pts.push(pts[0]);
            paths.push(CutPath {
                label: format!("{label}: ring {}", k + 1),
                points: pts,
                closed: true,
                ring: None,
            });
        }
    }
    if n_pockets2 > 0 {
        for pts in inner_paths {
            paths.push(CutPath {
                label: format!("{label}: one stepover from the wall"),
                points: pts,
                closed: true,
                ring: None,
            });
        }
    }
    paths.extend(wall_paths(finish_all, label));
    Ok((paths, Some(oriented)))
}

/// The loops 0.9 stepover in from each wall (pockets with room for them,
/// then islands) by the rolling disk, and how many of them are pockets'.
fn second_loops<N: Navigator + Sync>(
    nav: &N,
    pk: &Pockets,
    p: &LevelParams,
) -> (Vec<Vec<Vec2>>, usize) {
    let r2 = p.wall() + 0.9 * p.stepover;
    let tp2 = TraceParams {
        radius: r2,
        tol: p.tol,
        part_on_left: !p.climb,
    };
    let mut second: Vec<Vec<Vec2>> = Vec::new();
    let mut n_pockets2 = 0;
    for (k, &(_, room)) in pk.deepest.iter().enumerate() {
        if room > r2 + p.stepover {
            if let Ok(t) = trace(nav, pk.index, pk.start(k, r2, p.tol), tp2) {
                second.push(t.points);
                n_pockets2 += 1;
            }
        }
    }
    for is in pk.islands {
        let start = lowest(is) - Vec2::new(0.0, r2 + p.tol);
        if let Ok(t) = trace(nav, pk.index, start, tp2) {
            second.push(t.points);
        }
    }
    (second, n_pockets2)
}

/// u of the inverse problem on a grid over V, pinned to 0 inside the sinks
/// (where the sum is singular at the charges).
fn inverse_grid(
    inv: &Field,
    sinks: &[Sink],
    lo: Vec2,
    hi: Vec2,
    h: f64,
    mask: &[Vec<Vec2>],
) -> Grid {
    let mut grid = Grid::sample(inv, lo, hi, h, mask);
    for j in 0..grid.ny {
        for i in 0..grid.nx {
            let q = Vec2::new(grid.origin.x + h * i as f64, grid.origin.y + h * j as f64);
            if sinks.iter().any(|s| s.centre.dist(q) < 0.75 * s.radius) {
                grid.values[j * grid.nx + i] = 0.0;
            }
        }
    }
    grid
}

/// The region V of the inverse problem: its boundary loops (oriented), their
/// distance index, and the mask of what lies outside V on the grid.
struct Region<'a> {
    oriented: &'a [Vec<Vec2>],
    vindex: &'a DistanceIndex,
    mask: &'a [Vec<Vec2>],
}

/// The clearing rings, outermost first, each set the level curve of one
/// value (see the module docs); they stop when the last is small enough for
/// the tool to cover its inside, deeper than `band` from the wall, or when no
/// value gives a safe ring within 1.25 stepovers of the last.
fn rings(
    grid: &Grid,
    inv: &Field,
    v: &Region,
    index: &DistanceIndex,
    p: &LevelParams,
    band: Option<f64>,
    label: &str,
) -> Result<Vec<Vec<Vec<Vec2>>>, ProfileError> {
    let r = p.radius;
    let h = grid.h;
    let mut rings: Vec<Vec<Vec<Vec2>>> = Vec::new();
    let mut prev: Vec<Vec<Vec2>> = v.oriented.to_vec();
    let mut c_prev = 1.0;
    for _ in 0..MAX_RINGS {
        let small = prev.iter().all(|l| {
            let n = l.len() as f64;
            let cx = l.iter().fold(Vec2::ZERO, |a, &b| a + b) / n;
            l.iter().all(|&q| q.dist(cx) <= 0.7 * r)
        });
        if small && !rings.is_empty() {
            break;
        }
        let Some(c) = next_value(grid, &prev, c_prev, rings.is_empty(), index, p, label)? else {
            break;
        };
        // The exact ring (vertices on the level by regula falsi) must be safe too;
        // if not, step the value down until it is.
        let (mut c, mut exact) = (c, Vec::new());
        for _ in 0..20 {
            exact = isolines(grid, c, inv, &v.mask[1..])
                .into_iter()
                .filter(|l| l.signed_area().abs() > h * h)
                .map(Ring::into_points)
                .collect();
            if safe(&exact, index, p) {
                break;
            }
            exact.clear();
            c *= 0.98;
        }
        if exact.is_empty() {
            break;
        }
        let depth_in = exact
            .iter()
            .flatten()
            .map(|&q| v.vindex.distance(q))
            .fold(f64::INFINITY, f64::min);
        prev = exact.clone();
        c_prev = c;
        rings.push(exact);
        if band.is_some_and(|d| depth_in > d) || c < 1e-4 {
            break;
        }
    }
    Ok(rings)
}

/// A ring is usable when it keeps the wall radius − tol/4 from the part
/// everywhere (the field's error could carry a ring with c near 1 across ∂V).
fn safe(set: &[Vec<Vec2>], index: &DistanceIndex, p: &LevelParams) -> bool {
    set.iter().all(|l| {
        let n = l.len();
        (0..n).all(|i| {
            index.segment_distance(l[i], l[(i + 1) % n], 2.0 * p.radius) >= p.wall() - 0.25 * p.tol
        })
    })
}

/// The value of the next ring inside `prev` (value `c_prev`): by eight
/// halvings, the safe ring at most 0.9 stepover from `prev` (1/256 of the
/// remaining range: it lands between 0.9 and about 1 stepover from the
/// last), else the safe ring nearest to it if that is within 1.25 stepovers
/// (a wider cut than asked, never a slot: nothing the user must act on);
/// `None` when there is none, and the rings stop (what they leave is cleared
/// by `cover_left` and measured by the coverage check).
fn next_value(
    grid: &Grid,
    prev: &[Vec<Vec2>],
    c_prev: f64,
    first: bool,
    index: &DistanceIndex,
    p: &LevelParams,
    label: &str,
) -> Result<Option<f64>, ProfileError> {
    let target = 0.9 * p.stepover;
    let (mut a, mut bnd) = (0.0_f64, c_prev);
    let prev_index = ring_index(prev);
    let mut best: Option<f64> = None;
    // The safe ring with the smallest gap, for when none meets the target.
    let mut fallback: Option<(f64, f64)> = None;
    for _ in 0..8 {
        let c = 0.5 * (a + bnd);
        let set = isolines_linear(grid, c);
        if !safe(&set, index, p) {
            bnd = c;
            continue;
        }
        // The first ring is bounded one way (see `ring_gap`); between two inner
        // rings both ways, so that no lobe of an outer ring is left behind.
        let g = if first {
            ring_gap_from(prev_index.as_ref(), &set)
        } else {
            crate::num::max_or_nan(
                ring_gap_from(prev_index.as_ref(), &set),
                ring_gap(&set, prev),
            )
        };
        if g.is_nan() {
            return Err(ProfileError::RingGapNotANumber {
                level: label.to_string(),
            });
        }
        if fallback.is_none_or(|f| g < f.1) {
            fallback = Some((c, g));
        }
        if g <= target {
            best = Some(c);
            bnd = c;
        } else {
            a = c;
        }
        if bnd - a < 1e-6 {
            break;
        }
    }
    Ok(match (best, fallback) {
        (Some(c), _) => Some(c),
        (None, Some((c, g))) if g <= 1.25 * p.stepover => Some(c),
        (None, _) => None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::trace::NearestWall;
    use crate::toolpath::zlevel::{cover_left, deepest_in_pocket};

    /// Distance from `q` to the closed polygon `poly`, by brute force.
    fn dist_to(poly: &[Vec2], q: Vec2) -> f64 {
        let n = poly.len();
        (0..n)
            .map(|i| {
                let (a, b) = (poly[i], poly[(i + 1) % n]);
                let t = ((q - a).dot(b - a) / (b - a).norm2()).clamp(0.0, 1.0);
                q.dist(a.lerp(b, t))
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// A 20 mm square pocket cleared by the inverse problem: the rings keep
    /// the tool out of the wall, and the cut (rings, the loop a stepover in,
    /// the wall loop, and `cover_left`'s loops at what they leave) covers
    /// every point the tool can reach, both checked by brute-force distances
    /// that do not use the field.
    #[test]
    fn a_square_pocket_is_cleared_by_the_inverse_problems_rings() {
        let p = crate::toolpath::zlevel::test_params();
        let half = 10.0;
        // Clockwise: a pocket.
        let pocket = vec![
            Vec2::new(-half, -half),
            Vec2::new(-half, half),
            Vec2::new(half, half),
            Vec2::new(half, -half),
        ];
        let part = vec![pocket.clone()];
        let index = DistanceIndex::new(&part);
        let pockets: Vec<&Vec<Vec2>> = part.iter().collect();
        let deepest = vec![deepest_in_pocket(&pocket, &[], &index)];
        let pk = Pockets {
            pockets: &pockets,
            islands: &[],
            deepest: &deepest,
            index: &index,
        };
        let nav = NearestWall(&index);
        let tp = TraceParams {
            radius: p.wall(),
            tol: p.tol,
            part_on_left: !p.climb,
        };
        let wall = trace(&nav, &index, pk.start(0, p.wall(), p.tol), tp).expect("wall loop");
        let (paths, v) =
            inverse_paths(&nav, &pk, &p, "t", None, vec![wall.points]).expect("solves");
        let v = v.expect("a region V to measure");
        let rings = paths.iter().filter(|c| c.label.contains(": ring ")).count();
        assert!(rings >= 3, "{rings} rings");
        // As `cavity_paths` does: loops at the spots the rings leave.
        let (paths, uncut) = cover_left(&part, &index, &v, paths, &p, None, "t").expect("covers");
        assert!(uncut < 1e-3, "uncut share {uncut}");
        let pts: Vec<Vec2> = paths.iter().flat_map(|c| c.points.clone()).collect();
        for q in &pts {
            assert!(
                dist_to(&pocket, *q) >= p.radius - 0.25 * p.tol,
                "{q:?} is {} from the wall",
                dist_to(&pocket, *q)
            );
        }
        // Every point at least r from the wall lies under the tool somewhere
        // along a path (densified to 0.05 mm).
        let dense: Vec<Vec2> = paths
            .iter()
            .flat_map(|c| crate::geometry::densify(&c.points, 0.05, false))
            .collect();
        let mut worst: f64 = 0.0;
        for j in 0..=80 {
            for i in 0..=80 {
                let q = Vec2::new(-half + 0.25 * i as f64, -half + 0.25 * j as f64);
                if dist_to(&pocket, q) >= p.radius {
                    let d = dense
                        .iter()
                        .map(|c| c.dist(q))
                        .fold(f64::INFINITY, f64::min);
                    worst = worst.max(d);
                }
            }
        }
        assert!(worst <= p.radius, "a point {worst} mm from every path");
    }
}
