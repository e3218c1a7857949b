//! Offset rings inside a cavity: the band a level added for the scallop
//! bound cuts, and (with the band as deep as the pocket) a whole level.
//!
//! A band level is cut after the level below it
//! ([`crate::levels::cutting_order`]), which cleared everything inside its
//! own contour, so only a band next to the wall is left, `band` wide.
//! Rolling-disk rings at r + j·stepover from the wall, j from
//! ⌈band/stepover⌉ − 1 down to 1, then the wall loops at r, cover it: ring
//! j's disk reaches j·stepover + 2r from the wall, and each engages at most a
//! stepover of new material. The inverse problem's rings, which clear a whole
//! pocket, stop only once they are deeper than the band and then leave spots
//! in its lobes (q-mould's band levels cut 7.5 m and 4.3 m where their bands
//! needed well under one). A whole level is the band as deep as the pocket's
//! deepest point; what its rings leave about the medial axis is measured and
//! cleared by the caller (`zlevel::cover_left`).

use super::trace::{trace, NearestWall, TraceParams};
use super::zlevel::{CutPath, LevelParams};
use crate::geometry::{polygons_bbox, DistanceIndex, Vec2};

/// Widest band (in stepovers) cut by offset rings; a wider one is cleared by
/// the inverse problem's rings, as a stepdown level is.
pub(crate) const MAX_BAND_STEPOVERS: f64 = 4.0;

/// At most this many loops per ring radius (every loop of the offset curve is
/// traced; with more the band is left to the inverse problem's rings).
const MAX_LOOPS: usize = 400;

/// Grid points of the cavity (inside `part`'s pockets, outside its islands)
/// with their distance to the wall, on a grid of spacing `h` over the part's
/// box.
fn cavity_points(part: &[Vec<Vec2>], index: &DistanceIndex, h: f64) -> Vec<(f64, Vec2)> {
    let Some((lo, hi)) = polygons_bbox(part) else {
        return Vec::new();
    };
    let size = hi - lo;
    let (nx, ny) = (
        (size.x / h).floor() as usize + 1,
        (size.y / h).floor() as usize + 1,
    );
    // Material on the left of `part`: reversed, the cavity is inside.
    let reversed: Vec<Vec<Vec2>> = part
        .iter()
        .map(|l| l.iter().rev().copied().collect())
        .collect();
    let inside = crate::field::isolines::fill_rows(lo, h, nx, ny, &reversed);
    let mut out = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            if inside[j * nx + i] {
                let q = lo + Vec2::new(i as f64 * h, j as f64 * h);
                out.push((index.distance(q), q));
            }
        }
    }
    out
}

/// Every loop of the rolling disk's path at radius `rj` inside the cavity: a
/// trace from each grid point just clear of that radius that no loop traced so
/// far passes near.
fn loops_at(
    points: &[(f64, Vec2)],
    index: &DistanceIndex,
    p: &LevelParams,
    rj: f64,
    h: f64,
) -> Option<Vec<Vec<Vec2>>> {
    let mut seeds: Vec<Vec2> = points
        .iter()
        .filter(|&&(d, _)| d >= rj + p.tol && d <= rj + p.tol + 2.0 * h)
        .map(|&(_, q)| q)
        .collect();
    let tp = TraceParams {
        radius: rj,
        tol: p.tol,
        part_on_left: !p.climb,
    };
    let mut loops = Vec::new();
    // The kept loops' indices, for telling a loop traced again.
    let mut kept: Vec<DistanceIndex> = Vec::new();
    while let Some(&q) = seeds.first() {
        if loops.len() == MAX_LOOPS {
            return None;
        }
        // A trace that does not close (the distance's gradient turns
        // abruptly on the medial axis) hands the level to the caller's
        // fallback, as too many loops do.
        let t = trace(&NearestWall(index), index, q, tp).ok()?;
        let ring = DistanceIndex::new(&[t.points[..t.points.len() - 1].to_vec()]);
        let hint = std::cell::Cell::new(0);
        let before = seeds.len();
        seeds.retain(|&s| !ring.closer_than(s, 3.0 * h + p.tol, &hint));
        if seeds.len() == before {
            // The trace did not pass its own seed: drop the seed, and the loop
            // too if it is one already kept.
            seeds.remove(0);
            let start = t.points[0];
            if kept.iter().any(|k| k.distance(start) <= 2.0 * p.tol) {
                continue;
            }
        }
        kept.push(ring);
        loops.push(without_crumbs(t.points, 0.5 * p.tol));
    }
    Some(loops)
}

/// A closed path without points nearer than `eps` to the last one kept (the
/// trace's compass can land a few µm from its last point at a sharp turn;
/// such a crumb, rounded to the G-code's 1 µm, reads as a steep step of a
/// ramp). The chord over a dropped point strays from it by less than `eps`.
fn without_crumbs(points: Vec<Vec2>, eps: f64) -> Vec<Vec2> {
    let n = points.len();
    if n < 4 {
        return points;
    }
    let mut out: Vec<Vec2> = Vec::with_capacity(n);
    for &q in &points[..n - 1] {
        if out.last().is_none_or(|l| l.dist(q) >= eps) {
            out.push(q);
        }
    }
    // The last kept point must not sit on top of the first either.
    while out.len() > 3 && out[out.len() - 1].dist(out[0]) < eps {
        out.pop();
    }
    out.push(out[0]);
    out
}

/// The rings that cut a cavity level's band `band` wide next to the wall,
/// innermost first, without the wall loops themselves (at r, traced by the
/// caller). `None` when a radius has more than `MAX_LOOPS` loops.
pub(crate) fn band_rings(
    part: &[Vec<Vec2>],
    index: &DistanceIndex,
    p: &LevelParams,
    label: &str,
    band: f64,
) -> Option<Vec<CutPath>> {
    let n = ((band / p.stepover).ceil() as usize).saturating_sub(1);
    if n == 0 {
        return Some(Vec::new());
    }
    let h = 0.25 * p.stepover.min(p.radius);
    let points = cavity_points(part, index, h);
    let mut paths = Vec::new();
    for j in (1..=n).rev() {
        let rj = p.wall() + j as f64 * p.stepover;
        let loops = loops_at(&points, index, p, rj, h)?;
        for pts in loops {
            paths.push(CutPath {
                label: format!("{label}: ring {j} of the band"),
                points: pts,
                closed: true,
                ring: None,
            });
        }
    }
    Some(paths)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(c: Vec2, half: f64, ccw: bool) -> Vec<Vec2> {
        let mut s = vec![
            c + Vec2::new(-half, -half),
            c + Vec2::new(half, -half),
            c + Vec2::new(half, half),
            c + Vec2::new(-half, half),
        ];
        if !ccw {
            s.reverse();
        }
        s
    }

    fn params() -> LevelParams {
        crate::toolpath::zlevel::test_params()
    }

    /// A 40 mm square pocket (clockwise: the mould's material on the left)
    /// around a 10 mm square island: every ring radius has two loops, one in
    /// the pocket and one around the island, each at its distance from the
    /// wall; with the wall loops at r, the disks cover every point of the
    /// band that the tool can reach, on a grid the rings were not traced on.
    #[test]
    fn a_band_is_covered_by_every_loop_of_its_offsets() {
        let part = vec![
            square(Vec2::ZERO, 20.0, false),
            square(Vec2::new(3.0, -2.0), 5.0, true),
        ];
        let index = DistanceIndex::new(&part);
        let p = params();
        let band = 5.0;
        let rings = band_rings(&part, &index, &p, "test", band).expect("traced, few loops");
        // ⌈5 / 1.27⌉ − 1 = 3 radii, two loops each.
        assert_eq!(
            rings.len(),
            6,
            "{:?}",
            rings.iter().map(|c| &c.label).collect::<Vec<_>>()
        );
        for (k, c) in rings.iter().enumerate() {
            let rj = p.radius + (3 - k / 2) as f64 * p.stepover;
            for &q in &c.points {
                let d = index.distance(q);
                assert!(
                    (d - rj).abs() <= p.tol,
                    "ring {k}: {d} from the wall, not {rj}"
                );
            }
        }
        let h = 0.25 * p.stepover.min(p.radius);
        let pts = cavity_points(&part, &index, h);
        let walls = loops_at(&pts, &index, &p, p.radius, h).expect("traced, few loops");
        assert_eq!(walls.len(), 2);
        let mut all: Vec<Vec<Vec2>> = walls.clone();
        all.extend(rings.iter().map(|c| c.points.clone()));
        let cut = DistanceIndex::new(&all);
        let wall = DistanceIndex::new(&walls);
        let (mut checked, mut left) = (0, 0);
        let mut y = -19.95;
        while y < 20.0 {
            let mut x = -19.95;
            while x < 20.0 {
                let q = Vec2::new(x, y);
                let d = index.distance(q);
                let in_cavity = !(x - 3.0).abs().max((y + 2.0).abs()).lt(&5.0);
                let reachable = d >= p.radius || wall.distance(q) <= p.radius;
                if in_cavity && d <= band && reachable {
                    checked += 1;
                    if cut.distance(q) > p.radius + p.tol {
                        left += 1;
                    }
                }
                x += 0.1;
            }
            y += 0.1;
        }
        assert!(checked > 40_000, "{checked}");
        assert_eq!(left, 0, "{left} of {checked} band points left");
    }
}
