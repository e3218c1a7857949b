//! Arc fitting: runs of the traced polyline become circular arcs (G2/G3) wherever
//! one arc stays within a tolerance of the polyline; lines elsewhere.
//!
//! # Method
//!
//! Greedy, left to right over each run of straight feed moves at constant Z: from
//! vertex `i`, the longest run `i..=j` (found by doubling `j`, then bisecting) that
//! one arc through `P[i]` and `P[j]` fits becomes an arc; where a straight line
//! fits a longer run (collinear segments, within the same tolerance), that line;
//! otherwise `P[i]→P[i+1]` stays as it is. The arc through the two end points is the one-parameter family of
//! circles with signed curvature κ ∈ [−2/c, 2/c] (c the chord, |κ| = 2/c a
//! half circle); κ is chosen by golden-section search to minimise the largest
//! radial deviation of the run (a minimax circle with pinned ends).
//!
//! # What "fits" means (checked exactly, not sampled)
//!
//! With centre C, radius R and the run's vertices `P[i..=j]`:
//! 1. every vertex and the point of every segment closest to C are within `tol`
//!    of the circle: | |q − C| − R | ≤ tol, with the numerically stable form
//!    (|q−M|² − 2s⟨q−M, n⟩ − c²/4) / (|q−C| + R) (M the chord's midpoint, n its
//!    left normal, s the signed distance of C from M along n), so that large radii
//!    lose no digits;
//! 2. the vertices' angles about C increase strictly along the arc's direction,
//!    from the start (0) to the end (the sweep), and the sweep is at most π.
//!
//! Then the Hausdorff distance between the arc and the polyline is at most `tol`
//! both ways: every ray from C at an angle of the sweep crosses exactly one
//! segment (the angle is monotone along a segment whose points all lie within
//! tol < R of the circle), at a point whose radial distance to the arc is
//! ≤ tol; every point of the polyline lies on such a ray. `tests/all/arcs.rs` measures
//! it independently by sampling both curves.
//!
//! # Limits (why the values)
//!
//! - [`MAX_SWEEP`] = π: a full circle is always at least two arcs (no
//!   start = end ambiguity), and the minor-arc geometry above holds.
//! - `max_radius` (job key `output.max_arc_radius`, default 1000 mm): flatter arcs
//!   are lines. A nearly straight run fitted by a huge arc is where controllers
//!   fail (FreeCAD users have crashed GRBL with kilometre radii).
//! - [`MIN_ARC_CHORD`] = 0.05 mm: shorter arcs are lines. That is 25 times
//!   GRBL's default arc tolerance `$12` = 0.002 mm and 50 times the 0.001 mm the
//!   G-code is written to, so the rounded end points and centre still describe the
//!   same arc (GRBL's end-radius check, error 33, allows 0.005 mm).
//! - [`MIN_ARC_SEGMENTS`] = 3: an arc replaces at least three polyline segments,
//!   so it is a fit of a curve, not the circle any three points lie on.

use super::{arc_points, Move, Section, Toolpath, Vec3};
use crate::geometry::{arc, Vec2};
use std::f64::consts::{PI, TAU};

/// Largest sweep of one fitted arc, radians (see the module docs).
pub(crate) const MAX_SWEEP: f64 = PI;
/// Shortest chord of a fitted arc, mm (see the module docs).
pub const MIN_ARC_CHORD: f64 = 0.05;
/// Fewest polyline segments one arc replaces.
pub(crate) const MIN_ARC_SEGMENTS: usize = 3;
/// Default of `output.max_arc_radius`, mm (the job's default, where the
/// reason for it is written).
#[cfg(test)]
pub(crate) const DEFAULT_MAX_RADIUS: f64 = crate::job::defaults::MAX_ARC_RADIUS;
/// Golden-section iterations for κ: the bracket [−2/c, 2/c] shrinks by
/// 0.618^60 ≈ 3e-13, far below any tolerance in mm.
const GOLDEN_ITERATIONS: usize = 60;
/// Slack for comparing angles, radians (float rounding of atan2).
const ANGLE_EPS: f64 = 1e-12;

/// Settings of the fit, mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcFitParams {
    /// Largest distance between an arc and the polyline it replaces, both ways.
    /// The pipeline gives half the job tolerance (the traced polyline already
    /// spends the other half).
    pub(crate) tol: f64,
    /// Arcs of larger radius are left as lines.
    pub(crate) max_radius: f64,
    /// Arcs with a shorter chord are left as lines.
    pub(crate) min_chord: f64,
    /// Fit arcs; `false` only merges collinear segments into lines.
    pub(crate) arcs: bool,
}

impl ArcFitParams {
    /// Arcs within half the job tolerance, the given radius bound,
    /// [`MIN_ARC_CHORD`].
    pub fn new(job_tolerance: f64, max_radius: f64) -> Self {
        ArcFitParams {
            tol: job_tolerance / 2.0,
            max_radius,
            min_chord: MIN_ARC_CHORD,
            arcs: true,
        }
    }

    /// The fit for `job`: arcs as `output.arcs` and `output.max_arc_radius` say.
    pub fn for_job(job: &crate::job::Job) -> Self {
        ArcFitParams {
            arcs: job.output.arcs,
            ..Self::new(job.operation.tolerance, job.output.max_arc_radius)
        }
    }
}

/// A fitted circular arc in the XY plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Arc2 {
    /// Centre.
    pub(crate) centre: Vec2,
    /// Radius.
    pub(crate) radius: f64,
    /// Counter-clockwise (G3) or clockwise (G2).
    pub(crate) ccw: bool,
    /// Angle swept, radians, in (0, π].
    pub(crate) sweep: f64,
    /// Largest deviation from the polyline it replaces (both ways), mm.
    pub(crate) deviation: f64,
}

/// One piece of a fitted polyline: a line or an arc to the vertex `end`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Piece {
    /// Straight to `end`.
    Line {
        /// end point (a vertex of the polyline)
        end: Vec2,
    },
    /// Arc to `end`.
    Arc {
        /// end point (a vertex of the polyline)
        end: Vec2,
        /// the arc
        arc: Arc2,
    },
}

/// Stably computed signed radial deviation |q − C| − R of `q` from the circle
/// through the chord's ends with centre `m + n·s` and radius `r`.
#[inline]
fn radial(q: Vec2, m: Vec2, n: Vec2, s: f64, half_c2: f64, centre: Vec2, r: f64) -> f64 {
    let d = q - m;
    (d.norm2() - 2.0 * s * d.dot(n) - half_c2) / ((q - centre).norm() + r)
}

/// The circle of signed curvature `k` through `a` and `b`: (centre, radius, s).
/// Positive `k` puts the centre on the left of a→b (a counter-clockwise arc).
fn circle(a: Vec2, b: Vec2, k: f64) -> (Vec2, f64, f64) {
    let c = a.dist(b);
    let n = ((b - a) / c).perp();
    let r = 1.0 / k.abs();
    let s = k.signum() * (r * r - c * c / 4.0).max(0.0).sqrt();
    ((a + b) / 2.0 + n * s, r, s)
}

/// Largest |radial deviation| of the run's vertices and of each segment's point
/// closest to the centre, for the circle of curvature `k` through its ends.
fn max_radial(pts: &[Vec2], k: f64) -> f64 {
    let (a, b) = (pts[0], pts[pts.len() - 1]);
    let c = a.dist(b);
    let n = ((b - a) / c).perp();
    let m = (a + b) / 2.0;
    let (centre, r, s) = circle(a, b, k);
    let h = c * c / 4.0;
    let mut worst: f64 = 0.0;
    for w in pts.windows(2) {
        let (p, q) = (w[0], w[1]);
        worst = worst.max(radial(q, m, n, s, h, centre, r).abs());
        let d = q - p;
        let l2 = d.norm2();
        if l2 > 0.0 {
            let t = (centre - p).dot(d) / l2;
            if t > 0.0 && t < 1.0 {
                let foot = p + d * t;
                worst = worst.max(radial(foot, m, n, s, h, centre, r).abs());
            }
        }
    }
    worst
}

/// The arc through the ends of `pts` that stays within `p.tol` of the polyline
/// `pts` (both ways, see the module docs), or `None`.
pub(crate) fn fit_arc(pts: &[Vec2], p: &ArcFitParams) -> Option<Arc2> {
    if pts.len() < 3 {
        return None;
    }
    let (a, b) = (pts[0], pts[pts.len() - 1]);
    let c = a.dist(b);
    if c.is_nan() || c < p.min_chord {
        return None;
    }
    // Golden-section search of the minimax curvature.
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut lo, mut hi) = (-2.0 / c, 2.0 / c);
    let mut x1 = hi - g * (hi - lo);
    let mut x2 = lo + g * (hi - lo);
    let mut f1 = max_radial(pts, x1);
    let mut f2 = max_radial(pts, x2);
    for _ in 0..GOLDEN_ITERATIONS {
        if f1 <= f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = max_radial(pts, x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = max_radial(pts, x2);
        }
    }
    let k = if f1 <= f2 { x1 } else { x2 };
    if k == 0.0 || 1.0 / k.abs() > p.max_radius {
        return None;
    }
    arc_through(pts, k, p.tol)
}

/// Check the circle of curvature `k` through the ends of `pts` against the two
/// conditions of the module docs; the arc when both hold within `tol`.
fn arc_through(pts: &[Vec2], k: f64, tol: f64) -> Option<Arc2> {
    let (a, b) = (pts[0], pts[pts.len() - 1]);
    let (centre, radius, _) = circle(a, b, k);
    let deviation = max_radial(pts, k);
    if deviation.is_nan() || deviation > tol {
        return None;
    }
    let ccw = k > 0.0;
    let sign = if ccw { 1.0 } else { -1.0 };
    let ra = a - centre;
    // Angle of q from a about the centre, along the arc's direction, in [0, 2π).
    let angle = |q: Vec2| {
        let v = q - centre;
        (sign * ra.cross(v)).atan2(ra.dot(v)).rem_euclid(TAU)
    };
    let sweep = angle(b);
    if !(sweep > 0.0 && sweep <= MAX_SWEEP + ANGLE_EPS) {
        return None;
    }
    let mut prev = 0.0;
    for &q in &pts[1..pts.len() - 1] {
        let t = angle(q);
        if !(t > prev + ANGLE_EPS && t < sweep - ANGLE_EPS) {
            return None;
        }
        prev = t;
    }
    Some(Arc2 {
        centre,
        radius,
        ccw,
        sweep,
        deviation,
    })
}

/// Whether the straight line from the first to the last of `pts` stays within
/// `tol` of the polyline `pts`, both ways: every vertex is within `tol` of the
/// line, and the vertices' projections on it increase strictly from the start to
/// the end (then every point of either lies within `tol` of the other, as for
/// arcs in the module docs).
pub(crate) fn fits_line(pts: &[Vec2], tol: f64) -> bool {
    let (a, b) = (pts[0], pts[pts.len() - 1]);
    let c = a.dist(b);
    if c.is_nan() || c <= 0.0 {
        return false;
    }
    let u = (b - a) / c;
    let mut prev = 0.0;
    for &q in &pts[1..pts.len() - 1] {
        let d = q - a;
        let t = d.dot(u);
        if t.is_nan() || t <= prev || t >= c || u.cross(d).abs() > tol {
            return false;
        }
        prev = t;
    }
    true
}

/// The largest `j` in `first..=n` for which `fit(j)` holds, with its value,
/// assuming runs that fit have shorter runs that fit (found by doubling the run
/// while it fits, then bisecting the last step); `None` when `first` does not fit.
fn gallop<T>(first: usize, n: usize, fit: impl Fn(usize) -> Option<T>) -> Option<(usize, T)> {
    if first > n {
        return None;
    }
    let mut good = (first, fit(first)?);
    let mut bad = n + 1;
    let mut step = 1;
    while good.0 < n {
        let j = (good.0 + step).min(n);
        match fit(j) {
            Some(a) => {
                good = (j, a);
                step *= 2;
            }
            None => {
                bad = j;
                break;
            }
        }
    }
    while bad <= n && bad - good.0 > 1 {
        let mid = (good.0 + bad) / 2;
        match fit(mid) {
            Some(a) => good = (mid, a),
            None => bad = mid,
        }
    }
    Some(good)
}

/// Fit a polyline: lines and arcs (lines only when `!p.arcs`), in order, each
/// ending at a vertex of `pts`;
/// the last piece ends at the last point. From each vertex, the longer of the
/// longest arc ([`fit_arc`], at least [`MIN_ARC_SEGMENTS`] segments) and the
/// longest straight line ([`fits_line`], merging collinear segments) wins, a line
/// on a tie; with neither, the polyline's own segment.
pub(crate) fn fit_polyline(pts: &[Vec2], p: &ArcFitParams) -> Vec<Piece> {
    let n = pts.len().saturating_sub(1);
    let mut out = Vec::new();
    let mut i = 0;
    while i < n {
        let arc = if p.arcs {
            gallop(i + MIN_ARC_SEGMENTS, n, |j| fit_arc(&pts[i..=j], p))
        } else {
            None
        };
        let line = gallop(i + 2, n, |j| fits_line(&pts[i..=j], p.tol).then_some(()))
            .map_or(i + 1, |l| l.0);
        match arc {
            Some((j, arc)) if j > line => {
                out.push(Piece::Arc { end: pts[j], arc });
                i = j;
            }
            _ => {
                out.push(Piece::Line { end: pts[line] });
                i = line;
            }
        }
    }
    out
}

/// The tool path with every run of straight feed moves at constant Z (same feed)
/// fitted with arcs. Rapids, plunges and other moves are kept as they are.
/// Runs with the same points (the passes of one loop) are fitted once, so every
/// pass gets the same arcs. Sections are fitted in parallel (each starts where
/// the one before it ends, known before any fitting: fitting keeps every
/// run's ends); the result depends on nothing but the input.
pub fn fit_toolpath(tp: &Toolpath, p: &ArcFitParams) -> Toolpath {
    use rayon::prelude::*;
    let mut starts = Vec::with_capacity(tp.sections.len());
    let mut at = tp.start;
    for s in &tp.sections {
        starts.push(at);
        if let Some(m) = s.moves.last() {
            at = m.to();
        }
    }
    let sections = tp
        .sections
        .par_iter()
        .zip(starts)
        .map(|(s, at)| fit_section(s, at, p))
        .collect();
    Toolpath {
        start: tp.start,
        sections,
    }
}

/// One section of [`fit_toolpath`], entered at `at`.
fn fit_section(s: &Section, mut at: Vec3, p: &ArcFitParams) -> Section {
    let mut cache: Option<(Vec<Vec2>, Vec<Piece>)> = None;
    let mut moves = Vec::with_capacity(s.moves.len());
    let mut k = 0;
    while k < s.moves.len() {
        // The longest run of level linear moves from `at` with one feed.
        let feed = match s.moves[k] {
            Move::Linear { to, feed } if to.z == at.z => feed,
            m => {
                moves.push(m);
                at = m.to();
                k += 1;
                continue;
            }
        };
        let z = at.z;
        let mut pts = vec![Vec2::new(at.x, at.y)];
        while let Some(Move::Linear { to, feed: f }) = s.moves.get(k) {
            if to.z != z || *f != feed {
                break;
            }
            pts.push(Vec2::new(to.x, to.y));
            k += 1;
        }
        let pieces = match &cache {
            Some((q, pieces)) if *q == pts => pieces.clone(),
            _ => {
                let pieces = fit_polyline(&pts, p);
                cache = Some((pts.clone(), pieces.clone()));
                pieces
            }
        };
        for pc in pieces {
            moves.push(match pc {
                Piece::Line { end } => Move::Linear {
                    to: Vec3::new(end.x, end.y, z),
                    feed,
                },
                Piece::Arc { end, arc } => Move::Arc {
                    to: Vec3::new(end.x, end.y, z),
                    cx: arc.centre.x,
                    cy: arc.centre.y,
                    ccw: arc.ccw,
                    feed,
                },
            });
        }
        let last = pts[pts.len() - 1];
        at = Vec3::new(last.x, last.y, z);
    }
    Section {
        label: s.label.clone(),
        z: s.z,
        moves,
    }
}

/// What the G-code writer may emit for an arc (see [`legalize`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcLimits {
    /// Write arcs at all (`output.arcs`).
    pub(crate) arcs: bool,
    /// Largest radius written as an arc, mm (`output.max_arc_radius`).
    pub(crate) max_radius: f64,
    /// Arcs shorter than this (length along the arc) become lines, mm.
    pub(crate) min_length: f64,
    /// Chord tolerance of arcs replaced by lines, mm.
    pub(crate) tol: f64,
}

/// The tool path as the writer may emit it: with `!limits.arcs`, or for an arc
/// flatter than `max_radius` or shorter than `min_length`, the arc is replaced by
/// chords within `tol` of it (a line when one chord is close enough); an arc
/// sweeping more than π (a full circle included) is split into equal arcs of at
/// most π. Paths from [`fit_toolpath`] with the same limits pass unchanged.
pub fn legalize(tp: &Toolpath, limits: &ArcLimits) -> Toolpath {
    let mut at = tp.start;
    let mut sections = Vec::with_capacity(tp.sections.len());
    for s in &tp.sections {
        let mut moves = Vec::with_capacity(s.moves.len());
        for m in &s.moves {
            if let Move::Arc {
                to,
                cx,
                cy,
                ccw,
                feed,
            } = *m
            {
                let c = Vec2::new(cx, cy);
                let r = arc::radius(at.xy(), c);
                let sw = arc::sweep(at.xy(), to.xy(), c, ccw);
                let len = arc::helix_length(r, sw, to.z - at.z);
                let line = !limits.arcs || r > limits.max_radius || len < limits.min_length;
                let n = if line {
                    arc::chords(r, sw, limits.tol)
                } else {
                    (sw / (MAX_SWEEP + ANGLE_EPS)).ceil().max(1.0) as usize
                };
                for p in arc_points(at, to, cx, cy, ccw, n) {
                    moves.push(if line {
                        Move::Linear { to: p, feed }
                    } else {
                        Move::Arc {
                            to: p,
                            cx,
                            cy,
                            ccw,
                            feed,
                        }
                    });
                }
            } else {
                moves.push(*m);
            }
            at = m.to();
        }
        sections.push(Section {
            label: s.label.clone(),
            z: s.z,
            moves,
        });
    }
    Toolpath {
        start: tp.start,
        sections,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> ArcFitParams {
        ArcFitParams::new(0.01, DEFAULT_MAX_RADIUS)
    }

    fn arc_pts(c: Vec2, r: f64, a0: f64, a1: f64, n: usize) -> Vec<Vec2> {
        (0..=n)
            .map(|k| {
                let t = a0 + (a1 - a0) * k as f64 / n as f64;
                c + Vec2::new(t.cos(), t.sin()) * r
            })
            .collect()
    }

    #[test]
    fn points_on_a_circle_become_one_arc() {
        // 90° of radius 5 in 30 chords: sagitta 5·(1 − cos(1.5°)) ≈ 0.0017 < 0.005.
        let c = Vec2::new(3.0, -2.0);
        let pts = arc_pts(c, 5.0, 0.2, 0.2 + PI / 2.0, 30);
        let pieces = fit_polyline(&pts, &params());
        assert_eq!(pieces.len(), 1, "{pieces:?}");
        let Piece::Arc { end, arc } = pieces[0] else {
            panic!("{pieces:?}")
        };
        assert_eq!(end, pts[30]);
        assert!(arc.ccw);
        // The minimax circle with pinned ends bulges a little past the vertices
        // to meet the chords halfway.
        assert!(arc.centre.dist(c) < 1e-2, "{arc:?}");
        assert!((arc.radius - 5.0).abs() < 1e-2, "{arc:?}");
        assert!(arc.deviation <= 0.005);
        // Reversed: clockwise, same circle.
        let rev: Vec<Vec2> = pts.iter().rev().copied().collect();
        let pieces = fit_polyline(&rev, &params());
        assert!(matches!(pieces[..], [Piece::Arc { arc, .. }] if !arc.ccw));
    }

    #[test]
    fn straight_runs_stay_lines() {
        let pts: Vec<Vec2> = (0..20).map(|k| Vec2::new(k as f64, 0.0)).collect();
        let pieces = fit_polyline(&pts, &params());
        assert_eq!(pieces, [Piece::Line { end: pts[19] }]);
        // Slightly bent, radius ~ 5000 mm: within tolerance, but too flat.
        let pts: Vec<Vec2> = arc_pts(Vec2::new(0.0, 5000.0), 5000.0, -1.6, -1.54, 40);
        let pieces = fit_polyline(&pts, &params());
        assert!(pieces.iter().all(|p| matches!(p, Piece::Line { .. })));
    }

    #[test]
    fn arcs_off_merges_lines_only() {
        let mut p = params();
        p.arcs = false;
        let c = Vec2::new(3.0, -2.0);
        let pts = arc_pts(c, 5.0, 0.2, 0.2 + PI / 2.0, 30);
        let pieces = fit_polyline(&pts, &p);
        assert!(pieces.iter().all(|p| matches!(p, Piece::Line { .. })));
        let pts: Vec<Vec2> = (0..20).map(|k| Vec2::new(k as f64, 0.0)).collect();
        assert_eq!(fit_polyline(&pts, &p), [Piece::Line { end: pts[19] }]);
    }

    #[test]
    fn a_corner_is_not_an_arc() {
        // Two legs of a square, fine steps: no arc can stay within 0.005 mm.
        let mut pts: Vec<Vec2> = (0..=10).map(|k| Vec2::new(k as f64, 0.0)).collect();
        pts.extend((1..=10).map(|k| Vec2::new(10.0, k as f64)));
        assert_eq!(
            fit_polyline(&pts, &params()),
            [Piece::Line { end: pts[10] }, Piece::Line { end: pts[20] }]
        );
        assert!(fit_arc(&pts, &params()).is_none());
        assert!(!fits_line(&pts, 0.005) && fits_line(&pts[..=10], 0.0));
    }

    #[test]
    fn full_circle_is_at_least_two_arcs() {
        let pts = arc_pts(Vec2::new(0.0, 0.0), 10.0, 0.0, TAU, 200);
        let pieces = fit_polyline(&pts, &params());
        assert!((2..=3).contains(&pieces.len()), "{pieces:?}");
        for pc in &pieces {
            let Piece::Arc { arc, .. } = pc else {
                panic!("{pieces:?}")
            };
            assert!(arc.sweep <= PI + 1e-9);
        }
    }

    #[test]
    fn short_chords_stay_lines() {
        let pts = arc_pts(Vec2::new(0.0, 0.0), 0.02, 0.0, PI / 2.0, 6);
        assert!(fit_polyline(&pts, &params())
            .iter()
            .all(|p| matches!(p, Piece::Line { .. })));
    }

    #[test]
    fn legalize_flattens_and_splits() {
        let tp = Toolpath {
            start: Vec3::new(10.0, 0.0, -1.0),
            sections: vec![Section {
                label: "c".into(),
                z: -1.0,
                moves: vec![Move::Arc {
                    to: Vec3::new(10.0, 0.0, -1.0),
                    cx: 0.0,
                    cy: 0.0,
                    ccw: true,
                    feed: 100.0,
                }],
            }],
        };
        let mut lim = ArcLimits {
            arcs: true,
            max_radius: 1000.0,
            min_length: MIN_ARC_CHORD,
            tol: 0.005,
        };
        let split = legalize(&tp, &lim);
        assert_eq!(split.sections[0].moves.len(), 2);
        assert!(split.moves().all(|m| matches!(m, Move::Arc { .. })));
        assert_eq!(split.moves().last().map(|m| m.to()), Some(tp.start));
        lim.arcs = false;
        let lines = legalize(&tp, &lim);
        assert!(lines.moves().all(|m| matches!(m, Move::Linear { .. })));
        // Chords within 0.005 of r = 10: 2·acos(0.9995) ≈ 0.0632 rad → 100 chords.
        assert_eq!(lines.sections[0].moves.len(), 100);
        for m in lines.moves() {
            let p = m.to();
            assert!((p.x.hypot(p.y) - 10.0).abs() < 1e-9);
        }
        lim.arcs = true;
        lim.max_radius = 5.0;
        assert!(legalize(&tp, &lim)
            .moves()
            .all(|m| matches!(m, Move::Linear { .. })));
    }
}
