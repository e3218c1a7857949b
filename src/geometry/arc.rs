//! Circular arcs in a plane as G-code gives them: a start, an end, a centre and a
//! direction. The one definition of the sweep, the length (of a helix too), the
//! bounding points and the flattening into chords, for the writer, the arc
//! fitter, the statistics, the gouge check, the stock model, the preview, and
//! `check` and `simulate` (which read arcs as GRBL builds them, then measure
//! and flatten them here).
//!
//! Conventions: angles are `atan2` angles about the centre; the sweep is the
//! angle travelled, in (0, 2π]; ends at the same angle (to [`FULL_TURN_EPS`])
//! make a whole turn, as G-code reads equal ends.

use super::Vec2;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Ends whose angles about the centre differ by at most this (radians, in the
/// arc's direction) make a full circle rather than an arc of almost no sweep.
/// One value for every reader of arcs, so that what pfcam writes and what
/// `check` and `simulate` read back agree on which arcs are whole turns.
pub(crate) const FULL_TURN_EPS: f64 = 1e-9;

/// Most chords [`chords`] asks for, however fine the tolerance.
pub(crate) const MAX_CHORDS: usize = 100_000;

/// Sweep (radians) from angle `a0` to angle `a1` turning counter-clockwise when
/// `ccw`: in (0, 2π], a whole turn when they agree to [`FULL_TURN_EPS`].
pub(crate) fn sweep_between(a0: f64, a1: f64, ccw: bool) -> f64 {
    let s = if ccw { a1 - a0 } else { a0 - a1 }.rem_euclid(TAU);
    if s <= FULL_TURN_EPS {
        s + TAU
    } else {
        s
    }
}

/// Angle of `p` about `c` (`atan2`).
pub(crate) fn angle(p: Vec2, c: Vec2) -> f64 {
    (p.y - c.y).atan2(p.x - c.x)
}

/// Radius of the arc starting at `a` about `c`.
pub(crate) fn radius(a: Vec2, c: Vec2) -> f64 {
    (a.x - c.x).hypot(a.y - c.y)
}

/// Sweep (radians) of the arc from `a` to `b` about `c`, turning
/// counter-clockwise when `ccw`: [`sweep_between`] of their angles.
pub(crate) fn sweep(a: Vec2, b: Vec2, c: Vec2, ccw: bool) -> f64 {
    sweep_between(angle(a, c), angle(b, c), ccw)
}

/// Length of a helix of radius `r` turning through `sweep` while rising `rise`
/// along the third axis: the hypotenuse of the planar length r·sweep and the rise.
pub(crate) fn helix_length(r: f64, sweep: f64, rise: f64) -> f64 {
    (r * sweep).hypot(rise)
}

/// Length of the (helical, when `rise` ≠ 0) arc from `a` to `b` about `c`.
pub(crate) fn length(a: Vec2, b: Vec2, c: Vec2, ccw: bool, rise: f64) -> f64 {
    helix_length(radius(a, c), sweep(a, b, c, ccw), rise)
}

/// How many equal chords keep an arc of radius `r` and `sweep` within `tol` of
/// them. The rule: a chord spanning angle φ ≤ π lies at most its sagitta
/// r(1 − cos(φ/2)) from its arc, so φ = 2·acos(1 − tol/r) will do; when r ≤ tol
/// any chord of at most π does (it stays within r of the arc). At least 1, at
/// most [`MAX_CHORDS`] (and that many for a tolerance of zero).
pub(crate) fn chords(r: f64, sweep: f64, tol: f64) -> usize {
    let phi = if r <= tol {
        PI
    } else {
        2.0 * (1.0 - tol / r).clamp(-1.0, 1.0).acos()
    };
    ((sweep / phi.max(1e-9)).ceil() as usize).clamp(1, MAX_CHORDS)
}

/// The ends of `n` equal pieces of the arc from `a` to `b` about `c`: the point
/// at angle a0 ± sweep·k/n for k = 1..n, the last exactly `b`. (A helix's third
/// axis goes linearly with k/n.)
pub(crate) fn divide(a: Vec2, b: Vec2, c: Vec2, ccw: bool, n: usize) -> Vec<Vec2> {
    let r = radius(a, c);
    let a0 = angle(a, c);
    let sw = sweep(a, b, c, ccw);
    let dir = if ccw { 1.0 } else { -1.0 };
    (1..=n)
        .map(|k| {
            if k == n {
                b
            } else {
                let t = a0 + dir * sw * k as f64 / n as f64;
                Vec2::new(c.x + r * t.cos(), c.y + r * t.sin())
            }
        })
        .collect()
}

/// Points along the arc from `a` (excluded) to `b` (included, exactly) about
/// `c`: equal chords within `tol` of the arc ([`chords`]).
pub(crate) fn flatten(a: Vec2, b: Vec2, c: Vec2, ccw: bool, tol: f64) -> Vec<Vec2> {
    let n = chords(radius(a, c), sweep(a, b, c, ccw), tol);
    divide(a, b, c, ccw, n)
}

/// The points where the arc of radius `r` about `c`, starting at angle `a0` and
/// turning through `sweep`, crosses the quadrant angles (0, 90°, 180°, 270°):
/// with its ends they bound it.
pub(crate) fn extremes(c: Vec2, r: f64, a0: f64, sweep: f64, ccw: bool) -> Vec<Vec2> {
    (0..4)
        .filter_map(|k| {
            let a = k as f64 * FRAC_PI_2;
            // Angle travelled from the start to reach `a`, in [0, 2π).
            let d = if ccw { a - a0 } else { a0 - a }.rem_euclid(TAU);
            (d <= sweep).then(|| {
                let (s, co) = a.sin_cos();
                Vec2::new(c.x + r * co, c.y + r * s)
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_turns_both_ways_and_a_whole_turn_for_equal_ends() {
        let c = Vec2::new(1.0, 2.0);
        let (a, b) = (Vec2::new(2.0, 2.0), Vec2::new(1.0, 3.0));
        assert!((sweep(a, b, c, true) - FRAC_PI_2).abs() < 1e-15);
        assert!((sweep(a, b, c, false) - 3.0 * FRAC_PI_2).abs() < 1e-15);
        assert_eq!(sweep(a, a, c, true), TAU);
        assert_eq!(sweep(a, a, c, false), TAU);
        // Across the ±π cut of atan2.
        let (p, q) = (Vec2::new(0.0, 2.0 + 1e-8), Vec2::new(0.0, 2.0 - 1e-8));
        assert!((sweep(p, q, c, true) - 2e-8).abs() < 1e-12);
        assert!((sweep(q, p, c, true) - (TAU - 2e-8)).abs() < 1e-9);
        assert!((sweep(p, q, c, false) - (TAU - 2e-8)).abs() < 1e-9);
        assert!(sweep(p, q, c, false) > PI);
        // Within the full-turn epsilon: a whole turn, either way round.
        let (p, q) = (Vec2::new(0.0, 2.0 + 1e-10), Vec2::new(0.0, 2.0 - 1e-10));
        assert!((sweep(p, q, c, true) - TAU).abs() < 1e-9);
        assert!((sweep(p, q, c, false) - TAU).abs() < 1e-9);
        // The same point on either side of the cut (−0 against +0).
        let (p, q) = (Vec2::new(0.0, 0.0), Vec2::new(0.0, -0.0));
        let o = Vec2::new(1.0, 0.0);
        assert_eq!(sweep(p, q, o, true), TAU);
        assert_eq!(sweep(q, p, o, false), TAU);
    }

    /// Sum of the chords of a fine flattening, with the rise spread evenly.
    fn fine_length(a: Vec2, b: Vec2, c: Vec2, ccw: bool, rise: f64) -> f64 {
        let n = 200_000;
        let mut at = (a, 0.0);
        let mut sum = 0.0;
        for (k, p) in divide(a, b, c, ccw, n).into_iter().enumerate() {
            let z = rise * (k + 1) as f64 / n as f64;
            sum += (p.dist(at.0)).hypot(z - at.1);
            at = (p, z);
        }
        sum
    }

    #[test]
    fn length_is_the_sum_of_a_fine_flattening() {
        let c = Vec2::new(-3.0, 4.0);
        let a = c + Vec2::new(5.0, 0.0);
        for (b, ccw, rise) in [
            (c + Vec2::new(0.0, 5.0), true, 0.0),
            (c + Vec2::new(0.0, 5.0), false, -2.0),
            (c + Vec2::new(-3.0, -4.0), true, 7.5),
            (a, false, 3.0),
        ] {
            let want = fine_length(a, b, c, ccw, rise);
            let got = length(a, b, c, ccw, rise);
            assert!((got - want).abs() < 1e-6 * want, "{got} {want}");
        }
        // A whole turn: 2πr.
        assert!((length(a, a, c, true, 0.0) - TAU * 5.0).abs() < 1e-12);
    }

    /// Largest distance from the arc to the polyline a, pts…, measured at many
    /// points of the arc.
    fn max_gap(a: Vec2, pts: &[Vec2], c: Vec2, r: f64) -> f64 {
        let mut worst: f64 = 0.0;
        let mut prev = a;
        for &p in pts {
            // The arc between two consecutive points lies over their chord.
            let (t0, t1) = (angle(prev, c), angle(p, c));
            let mut d = t1 - t0;
            if d > PI {
                d -= TAU;
            } else if d < -PI {
                d += TAU;
            }
            for j in 0..=64 {
                let t = t0 + d * j as f64 / 64.0;
                let q = Vec2::new(c.x + r * t.cos(), c.y + r * t.sin());
                let (u, v) = (p - prev, q - prev);
                let f = (u.dot(v) / u.norm2()).clamp(0.0, 1.0);
                worst = worst.max(q.dist(prev + u * f));
            }
            prev = p;
        }
        worst
    }

    #[test]
    fn flattening_stays_within_the_tolerance_and_ends_on_the_end() {
        let c = Vec2::new(10.0, -7.0);
        for (r, tol) in [(5.0, 0.01), (0.3, 0.001), (50.0, 1e-4), (0.01, 0.05)] {
            let a = c + Vec2::new(r * 0.6, r * 0.8);
            for (b, ccw) in [
                (c + Vec2::new(-r, 0.0), true),
                (c + Vec2::new(-r, 0.0), false),
                (a, true),
            ] {
                let pts = flatten(a, b, c, ccw, tol);
                assert_eq!(*pts.last().unwrap(), b);
                let gap = max_gap(a, &pts, c, r);
                assert!(gap <= tol * (1.0 + 1e-9), "r {r} tol {tol}: {gap}");
                // Every point on the circle, equally spaced in angle.
                for p in &pts {
                    assert!((p.dist(c) - r).abs() < 1e-9 * r.max(1.0));
                }
                // Not needlessly fine: one chord fewer would not do.
                let n = pts.len();
                if n > 1 && r > tol {
                    let phi = sweep(a, b, c, ccw) / (n - 1) as f64;
                    assert!(r * (1.0 - (phi / 2.0).cos()) > tol);
                }
            }
        }
        assert_eq!(chords(5.0, PI, 0.0), MAX_CHORDS);
        assert_eq!(chords(0.01, TAU, 0.05), 2);
    }

    #[test]
    fn moving_or_reversing_the_arc_changes_nothing_but_the_order() {
        let c = Vec2::new(2.0, 1.0);
        let a = c + Vec2::new(3.0, -1.0);
        let b = c + Vec2::new(-1.0, 3.0);
        let shift = Vec2::new(-123.25, 77.5);
        for ccw in [true, false] {
            let s = sweep(a, b, c, ccw);
            let moved = sweep(a + shift, b + shift, c + shift, ccw);
            assert!((s - moved).abs() < 1e-12);
            // Back the other way round: the same arc.
            assert!((sweep(b, a, c, !ccw) - s).abs() < 1e-12);
            // The other way round between the same ends: the rest of the circle.
            assert!((sweep(a, b, c, !ccw) + s - TAU).abs() < 1e-12);
            let l = length(a, b, c, ccw, 1.5);
            assert!((length(a + shift, b + shift, c + shift, ccw, 1.5) - l).abs() < 1e-9);
            assert!((length(b, a, c, !ccw, -1.5) - l).abs() < 1e-12);
            let fwd = flatten(a, b, c, ccw, 0.001);
            let mut back = flatten(b, a, c, !ccw, 0.001);
            assert_eq!(fwd.len(), back.len());
            back.pop();
            back.reverse();
            back.push(b);
            for (p, q) in fwd.iter().zip(&back) {
                assert!(p.dist(*q) < 1e-9);
            }
            let moved = flatten(a + shift, b + shift, c + shift, ccw, 0.001);
            for (p, q) in fwd.iter().zip(&moved) {
                assert!((*p + shift).dist(*q) < 1e-9);
            }
        }
    }

    #[test]
    fn extremes_are_the_quadrant_points_the_arc_passes() {
        let c = Vec2::new(1.0, 1.0);
        // From angle 0 counter-clockwise a quarter turn: 0° and 90°.
        let e = extremes(c, 2.0, 0.0, FRAC_PI_2, true);
        assert_eq!(e.len(), 2);
        // Clockwise from 0 a quarter turn: 0° and 270°.
        let e = extremes(c, 2.0, 0.0, FRAC_PI_2, false);
        assert!(e.iter().any(|p| (p.y - -1.0).abs() < 1e-12));
        assert_eq!(extremes(c, 2.0, 0.3, TAU, true).len(), 4);
    }
}
