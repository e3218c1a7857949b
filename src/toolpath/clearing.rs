//! A boss level's clearing loops, cut from the inside out.
//!
//! With r the tool radius, s the stepover, r_w the wall radius (r plus the
//! stock to leave) and δ(x) the signed distance of x inside the stock
//! rectangle (its nearest side's, negative outside), let
//!
//!   f(x) = min(d_part(x) − r_w, δ(x) + r − s).
//!
//! Loop j is the boundary of A_j = {f ≥ j·s} = R_j ∖ P_j: R_j the stock
//! rectangle grown by r − s − j·s (shrunk once j·s passes r − s), P_j the
//! inside of ring j, the rolling-disk offset of the part at r_w + j·s. The
//! loops are nested a stepover apart. Cut from the largest j down, each takes
//! a band at most a stepover wide on both of its sides, the part's and the
//! stock edge's, and the next begins a stepover from where it ends. Where the
//! part stands near the stock's edge a loop runs along ring j on one side and
//! along the rectangle on the other, closed, so there are no runs that start
//! and end beside the stock, each needing a way back through the air.
//!
//! Loop 0 holds the wall ring. Its side along R_0 (r − s outside the stock)
//! is air wherever loop 1 runs a stepover inside it, since loop 1's disk
//! already reaches 2(r − s) past the stock's edge; it is kept only where the
//! stock's margin is too thin for loop 1 ([`first_loop_pieces`]).
//!
//! Every point x of the stock outside P_0 lies within a stepover of ∂A_J,
//! J = ⌊f(x)/s⌋ (f falls at unit rate towards the nearest part or side), so
//! the loops' disks cover the stock; the tests measure that on a grid, with
//! R_0's side dropped where loop 1 runs.

use super::air::Keepout;
use super::zlevel::clip_ring;
use crate::geometry::fill::{fill_outlines, FillRule};
use crate::geometry::{densify, polygon_area, polygon_winding_number, DistanceIndex, Vec2};

/// Too many ring points for the exact difference (`geometry::fill`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("too many points for the exact difference of the stock and the part's ring")]
pub struct TooComplex;

/// What loop j is cut around.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frame {
    /// Lower-left corner of the stock rectangle.
    pub(crate) stock_lo: Vec2,
    /// Upper-right corner of the stock rectangle.
    pub(crate) stock_hi: Vec2,
    /// Tool radius, mm.
    pub(crate) radius: f64,
    /// Stepover, mm.
    pub(crate) stepover: f64,
    /// Climb milling: the loops run with what they have cleared on their left
    /// (the material on the right, as the rings around the part run).
    pub(crate) climb: bool,
}

impl Frame {
    /// Points of the stock that the tool's disk at `y` (outside the stock)
    /// reaches: the nearest, the deepest, and the ends of the chord the disk
    /// cuts on the stock's edge there (each held to the stock). When the
    /// disks of a loop's tool reach all of them, the disk at `y` cuts nothing.
    fn stock_under(&self, y: Vec2) -> [Vec2; 4] {
        let (lo, hi) = (self.stock_lo, self.stock_hi);
        let hold = |p: Vec2| Vec2::new(p.x.clamp(lo.x, hi.x), p.y.clamp(lo.y, hi.y));
        let c = hold(y);
        let d = c.dist(y);
        if d <= 0.0 || d >= self.radius {
            return [c; 4];
        }
        let n = (c - y) * (1.0 / d);
        let t = Vec2::new(-n.y, n.x);
        let h = (self.radius * self.radius - d * d).sqrt();
        [
            c,
            hold(y + n * self.radius),
            hold(c + t * h),
            hold(c - t * h),
        ]
    }

    /// The corners of R_j, or None when it is empty.
    fn rect(&self, j: usize) -> Option<(Vec2, Vec2)> {
        let grow = self.radius - self.stepover - j as f64 * self.stepover;
        let g = Vec2::new(grow, grow);
        let (lo, hi) = (self.stock_lo - g, self.stock_hi + g);
        (lo.x < hi.x && lo.y < hi.y).then_some((lo, hi))
    }
}

/// Loop j's paths in cutting direction, as (points, closed), from `rings`,
/// ring j around each outer loop of the part as traced (closed, last point =
/// first, the part on the right for climb, on the left otherwise). For j > 0
/// a piece less than a stepover across is dropped ([`too_small`]). A ring
/// found twice (a merged ring traced again from another loop's start) counts
/// once; a ring inside another (around an island in a counter) is cut as it
/// runs, clipped to R_j (runs that cross it are open).
pub(crate) fn clearing_loops(
    frame: &Frame,
    j: usize,
    rings: &[Vec<Vec2>],
) -> Result<Vec<(Vec<Vec2>, bool)>, TooComplex> {
    let Some((lo, hi)) = frame.rect(j) else {
        return Ok(Vec::new());
    };
    let open = |r: &Vec<Vec2>| r[..r.len() - 1].to_vec();
    let mut kept: Vec<usize> = Vec::new();
    for k in (0..rings.len()).filter(|&k| rings[k].len() > 3) {
        if !kept
            .iter()
            .any(|&i| same_ring(&rings[i], &rings[k], 0.25 * frame.stepover))
        {
            kept.push(k);
        }
    }
    // A ring's repeated last point is an edge of no length: it adds nothing
    // to a winding number.
    let inside_another = |k: usize| {
        let p = rings[k][0];
        kept.iter()
            .any(|&i| i != k && polygon_winding_number(&rings[i], p) != 0)
    };
    let (islands, outer): (Vec<usize>, Vec<usize>) = kept.iter().partition(|&&k| inside_another(k));
    let rect = vec![lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)];
    let mut polys = vec![rect];
    for &k in &outer {
        let mut r = open(&rings[k]);
        if polygon_area(&r) > 0.0 {
            r.reverse(); // clockwise: the part is taken off
        }
        polys.push(r);
    }
    let mut out = Vec::new();
    for mut l in fill_outlines(&polys, FillRule::Positive).map_err(|_| TooComplex)? {
        if j > 0 && too_small(&l, frame.stepover) {
            continue;
        }
        if !frame.climb {
            l.reverse();
        }
        l.push(l[0]);
        out.push((l, true));
    }
    let inside_rect = Keepout { lo, hi };
    for k in islands {
        out.extend(clip_ring(&rings[k], &inside_rect));
    }
    Ok(out)
}

/// Whether loop `l` spans less than a stepover `s` (the diagonal of its
/// box): a sliver where ring j grazes a corner of R_j. Loop j − 1 runs within
/// a stepover of every point of it, and a ramp around it would be a plunge.
fn too_small(l: &[Vec2], s: f64) -> bool {
    crate::geometry::polygons_bbox(std::slice::from_ref(&l.to_vec()))
        .is_none_or(|(a, b)| a.dist(b) < s)
}

/// Whether more than half the points of ring `b` lie within `d` of ring `a`.
fn same_ring(a: &[Vec2], b: &[Vec2], d: f64) -> bool {
    let index = DistanceIndex::new(&[a.to_vec()]);
    let near = b.iter().filter(|&&p| index.distance(p) <= d).count();
    2 * near > b.len()
}

/// Loop 0's pieces, as (points, closed): the loops of [`clearing_loops`] at
/// j = 0 less the stretches along the rectangle R_0 that loop 1 (`next`, its
/// loops) already cut. A point of R_0's side is dropped when loop 1 passes
/// within a stepover of it: there loop 1's rectangle side runs a stepover
/// inside and its disk reaches 2(r − s) past the stock's edge. Where the
/// stock's margin is too thin for loop 1 (no loop there), R_0's side stays,
/// its disk taking the last stepover of the edge. A loop with stretches
/// dropped falls into open runs, each extended by one point at both ends.
pub(crate) fn first_loop_pieces(
    frame: &Frame,
    rings: &[Vec<Vec2>],
    next: &[Vec<Vec2>],
) -> Result<Vec<(Vec<Vec2>, bool)>, TooComplex> {
    let loops = clearing_loops(frame, 0, rings)?;
    let Some((lo, hi)) = frame.rect(0) else {
        return Ok(loops);
    };
    let index = (!next.is_empty()).then(|| DistanceIndex::new(next));
    let mut out = Vec::new();
    for (l, closed) in loops {
        if !closed {
            out.push((l, false));
            continue;
        }
        // Points a quarter stepover apart along the rectangle's sides, which
        // come with their corners only.
        let l = densify(&l, 0.25 * frame.stepover, false);
        let n = l.len() - 1; // last = first
        let air: Vec<bool> = l[..n]
            .iter()
            .map(|&p| {
                on_rect(p, lo, hi)
                    && index.as_ref().is_some_and(|i| {
                        frame
                            .stock_under(p)
                            .iter()
                            .all(|&z| i.distance(z) < frame.radius)
                    })
            })
            .collect();
        out.extend(runs_between(&l, &air));
    }
    Ok(out)
}

/// The closed loop `l` (last = first) less its points marked in `air`: the
/// whole loop when none is, nothing when all are, else the runs of the others
/// (cyclically), each extended by one point at both ends (so that a ring
/// clipped to the stock starts and ends where the tool is clear of it,
/// [`super::zlevel::clip_ring`]).
pub(super) fn runs_between(l: &[Vec2], air: &[bool]) -> Vec<(Vec<Vec2>, bool)> {
    let n = air.len();
    if !air.iter().any(|&a| a) {
        return vec![(l.to_vec(), true)];
    }
    let Some(k0) = (0..n).find(|&k| air[k]) else {
        return Vec::new();
    };
    let mut runs = Vec::new();
    let mut cur: Vec<Vec2> = Vec::new();
    for step in 1..=n {
        let k = (k0 + step) % n;
        if !air[k] {
            if cur.is_empty() {
                cur.push(l[(k + n - 1) % n]);
            }
            cur.push(l[k]);
        } else if !cur.is_empty() {
            cur.push(l[k]);
            runs.push((std::mem::take(&mut cur), false));
        }
    }
    runs
}

/// Whether `p` lies on the sides of the rectangle `[lo, hi]` (to within the
/// exact difference's rounding).
fn on_rect(p: Vec2, lo: Vec2, hi: Vec2) -> bool {
    let eps = 1e-6 * (1.0 + (hi.x - lo.x).abs().max((hi.y - lo.y).abs()));
    let near = |a: f64, b: f64| (a - b).abs() <= eps;
    (near(p.x, lo.x) || near(p.x, hi.x) || near(p.y, lo.y) || near(p.y, hi.y))
        && p.x >= lo.x - eps
        && p.x <= hi.x + eps
        && p.y >= lo.y - eps
        && p.y <= hi.y + eps
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::DistanceIndex;

    const R: f64 = 1.5875;
    const S: f64 = 1.27;

    /// A circle of `radius` about `c`, clockwise (the part on the right of
    /// a climb ring), closed.
    fn circle(c: Vec2, radius: f64) -> Vec<Vec2> {
        let n = 720;
        (0..=n)
            .map(|k| {
                let a = -std::f64::consts::TAU * k as f64 / n as f64;
                c + Vec2::new(radius * a.cos(), radius * a.sin())
            })
            .collect()
    }

    /// A 60 × 40 stock with a disk part of radius 12 at (25, 20): its rings
    /// cross the stock's near sides, not the far ones.
    fn frame(climb: bool) -> Frame {
        Frame {
            stock_lo: Vec2::new(0.0, 0.0),
            stock_hi: Vec2::new(60.0, 40.0),
            radius: R,
            stepover: S,
            climb,
        }
    }

    /// The same part in a stock 3 mm larger all round: loop 1 has room only
    /// in the corners.
    fn thin_frame() -> Frame {
        Frame {
            stock_lo: C - Vec2::new(PART + 3.0, PART + 3.0),
            stock_hi: C + Vec2::new(PART + 3.0, PART + 3.0),
            ..frame(true)
        }
    }

    const C: Vec2 = Vec2 { x: 25.0, y: 20.0 };
    const PART: f64 = 12.0;
    const WALL: f64 = R + 0.2;

    fn ring(j: usize) -> Vec<Vec2> {
        circle(C, PART + WALL + j as f64 * S)
    }

    /// f of the module's comment, computed directly.
    fn f(fr: &Frame, x: Vec2) -> f64 {
        let d_part = x.dist(C) - PART;
        let inside = (x.x - fr.stock_lo.x)
            .min(fr.stock_hi.x - x.x)
            .min(x.y - fr.stock_lo.y)
            .min(fr.stock_hi.y - x.y);
        (d_part - WALL).min(inside + R - S)
    }

    /// Loop j's paths, all closed.
    fn closed(fr: &Frame, j: usize) -> Vec<Vec<Vec2>> {
        let loops = clearing_loops(fr, j, &[ring(j)]).unwrap();
        assert!(loops.iter().all(|l| l.1), "j {j}: an open path");
        loops.into_iter().map(|l| l.0).collect()
    }

    /// Every piece the level cuts, loop 0's from `first_loop_pieces`, by j.
    fn pieces(fr: &Frame, jmax: usize) -> Vec<Vec<(Vec<Vec2>, bool)>> {
        let mut by_j = vec![first_loop_pieces(fr, &[ring(0)], &closed(fr, 1)).unwrap()];
        by_j.extend((1..=jmax).map(|j| clearing_loops(fr, j, &[ring(j)]).unwrap()));
        by_j
    }

    /// Every grid point of the stock outside the wall ring lies within the
    /// tool's radius of a piece (an open run measured without a closing
    /// chord: walked there and back).
    fn assert_covers(fr: &Frame, by_j: &[Vec<(Vec<Vec2>, bool)>]) {
        let polys: Vec<Vec<Vec2>> = by_j
            .iter()
            .flatten()
            .map(|(p, closed)| {
                if *closed {
                    p[..p.len() - 1].to_vec()
                } else {
                    p.iter()
                        .chain(p[1..p.len() - 1].iter().rev())
                        .copied()
                        .collect()
                }
            })
            .collect();
        let idx = DistanceIndex::new(&polys);
        let h = 0.2;
        let size = fr.stock_hi - fr.stock_lo;
        for a in 0..=(size.x / h) as usize {
            for b in 0..=(size.y / h) as usize {
                let x = fr.stock_lo + Vec2::new(a as f64 * h, b as f64 * h);
                if x.dist(C) < PART + WALL {
                    continue;
                }
                let d = idx.distance(x);
                assert!(
                    d <= R,
                    "({:.1}, {:.1}) is {d:.3} from every piece",
                    x.x,
                    x.y
                );
            }
        }
    }

    /// Every point of loop j lies where f = j·s (to the rings' chords), and
    /// the loops run with what they enclose on their left (counter-clockwise
    /// outlines) when climbing, on their right otherwise.
    #[test]
    fn loop_j_is_the_level_j_s_of_f() {
        for climb in [true, false] {
            let fr = frame(climb);
            let mut seen_mixed = false;
            for j in 0..20 {
                let loops = closed(&fr, j);
                for l in &loops {
                    assert_eq!(l.first(), l.last());
                    for &x in l {
                        let e = f(&fr, x) - j as f64 * S;
                        assert!(e.abs() < 2e-3, "j {j}: f - js = {e} at {x:?}");
                    }
                    let on_ring = l
                        .iter()
                        .any(|x| (x.dist(C) - PART - WALL - j as f64 * S).abs() < 1e-3);
                    let on_side = l.iter().any(|&x| {
                        let (lo, hi) = fr.rect(j).unwrap();
                        on_rect(x, lo, hi)
                    });
                    seen_mixed |= on_ring && on_side;
                }
                let area: f64 = loops.iter().map(|l| polygon_area(l)).sum();
                if !loops.is_empty() {
                    assert_eq!(area > 0.0, climb, "j {j}: net area {area}");
                }
            }
            assert!(seen_mixed, "no loop ran along both the ring and the stock");
        }
    }

    /// The tool on all the pieces covers every point of the stock outside
    /// the wall ring, and every point of loop j + 1 lies within a stepover of
    /// loop j (what loop j cuts after it is a band no wider). Measured with
    /// distance indexes of the loops, independent of how they were made.
    #[test]
    fn the_loops_clear_the_stock_a_stepover_at_a_time() {
        let fr = frame(true);
        let by_j = pieces(&fr, 39);
        assert!(by_j[39].is_empty(), "the loops must run out before j = 39");
        assert_covers(&fr, &by_j);
        // From loop 1 on (loop 0's side along the stock's edge is dropped).
        for j in 1..38 {
            let inner: Vec<&Vec<Vec2>> = by_j[j + 1].iter().map(|l| &l.0).collect();
            if inner.is_empty() {
                continue;
            }
            let outer = DistanceIndex::new(&closed(&fr, j));
            for &x in inner.into_iter().flatten() {
                let d = outer.distance(x);
                assert!(d <= S + 2e-3, "j {}: {x:?} is {d:.4} from loop {j}", j + 1);
            }
        }
    }

    /// Loop 0 is the wall ring alone where loop 1 runs along the stock's
    /// edge: its rectangle would cut air.
    #[test]
    fn loop_0_is_the_wall_ring_where_loop_1_runs() {
        let fr = frame(true);
        let pieces = first_loop_pieces(&fr, &[ring(0)], &closed(&fr, 1)).unwrap();
        assert!(!pieces.is_empty());
        for (p, _) in &pieces {
            assert!(p.iter().all(|x| (x.dist(C) - PART - WALL).abs() < 1e-6));
        }
    }

    /// Where the margin is too thin for loop 1 (the middles of the sides),
    /// loop 0 keeps its side along the rectangle, and the stock is still all
    /// cut.
    #[test]
    fn a_thin_margin_keeps_the_rectangle() {
        let fr = thin_frame();
        let by_j = pieces(&fr, 10);
        assert!(!by_j[1].is_empty(), "loop 1 in the corners");
        let (lo, hi) = fr.rect(0).unwrap();
        assert!(by_j[0]
            .iter()
            .any(|(p, _)| p.iter().any(|&x| on_rect(x, lo, hi))));
        assert_covers(&fr, &by_j);
    }

    /// Where ring j passes a hair's breadth inside R_j's corner, the
    /// difference leaves a sliver there a few µm across: no loop is cut
    /// around it (its ramp would be a plunge), and the stock is still all
    /// cut, by loop j − 1 a stepover out.
    #[test]
    fn a_sliver_at_a_corner_is_not_a_loop() {
        let j = 3;
        let rho = PART + WALL + j as f64 * S;
        let inset = j as f64 * S - (R - S);
        let d = (rho + 0.005) / std::f64::consts::SQRT_2;
        let fr = Frame {
            stock_lo: C - Vec2::new(d + inset, d + inset),
            stock_hi: C + Vec2::new(30.0, 25.0),
            ..frame(true)
        };
        for (l, _) in clearing_loops(&fr, j, &[ring(j)]).unwrap() {
            let (a, b) = crate::geometry::polygons_bbox(&[l]).unwrap();
            assert!(a.dist(b) >= S, "a loop {:.4} mm across", a.dist(b));
        }
        assert_covers(&fr, &pieces(&fr, 30));
    }

    /// A ring inside another (an island in a counter) is cut as it runs, not
    /// taken off twice; a ring traced twice counts once.
    #[test]
    fn an_island_is_cut_and_a_ring_traced_twice_counts_once() {
        let fr = frame(true);
        let outer = circle(C, 10.0);
        let island = circle(C, 3.0);
        let loops = clearing_loops(&fr, 2, &[outer.clone(), island.clone()]).unwrap();
        assert!(loops.contains(&(island, true)));
        assert_eq!(
            loops.len(),
            3,
            "the rectangle's loop, the hole and the island"
        );
        let twice = clearing_loops(&fr, 2, &[outer.clone(), outer.clone()]).unwrap();
        assert_eq!(twice, clearing_loops(&fr, 2, &[outer]).unwrap());
    }
}
