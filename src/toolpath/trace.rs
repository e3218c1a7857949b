//! The rolling disk of the paper's Section 6: the tool centre is carried by the
//! potential field around the part.
//!
//! - Phase (a): from a start point in the void, gradient ascent of u (6.1) toward
//!   the part, each step as long as the disk can move without touching (the
//!   current clearance), then a dichotomy along ∇u to the first contact.
//! - Phase (b): from a contact point, a step of length h in the direction of
//!   travel and a dichotomy back to contact, repeated until the loop closes. The
//!   dichotomy runs on the circle of radius h about the current point (a
//!   "compass" step): from the field's normal ∇u (toward the part, where the disk
//!   is blocked) it turns toward the tangent of the equipotential until the disk
//!   is free, then bisects the angle. On straight and convex stretches this is the
//!   paper's tangent step plus dichotomy along the normal; at a concave corner,
//!   where the disk touches two walls and the offset turns back sharply, the
//!   straight dichotomy along the normal finds no contact ahead and the compass
//!   still does.
//! - The step h adapts so that every chord stays within half the tolerance of the
//!   exact offset (checked at ¼, ½ and ¾ of the chord).
//!
//! Navigation (the directions) comes from the field; contact, "the disk touches the
//! part", is judged with plain geometry: the distance from the centre to the
//! flattened part equals the tool radius. The issue allows either; the geometric
//! test makes every traced point exact to the bisection tolerance whatever the
//! field's boundary error. Where ∇u does not point into the blocked directions of
//! the wall being touched (near saddles of u, or where a coarse field is wrong
//! near thin strokes) the geometric normal seeds the compass instead; the count is
//! reported as `fallbacks`.

use crate::field::Field;
use crate::geometry::{DistanceIndex, Vec2};

/// The directions the tracer takes from a field.
pub(crate) trait Navigator {
    /// ∇u at `p`: points toward the part (u grows toward the generating boundary).
    fn grad(&self, p: Vec2) -> Vec2;
}

impl Navigator for Field {
    fn grad(&self, p: Vec2) -> Vec2 {
        Field::grad(self, p)
    }
}

/// Directions from plain geometry: toward the nearest point of the part, the
/// gradient of the distance to it. For offset rings inside a cavity, where a
/// level's field (solved outside Γ(s), its charges inside) points anywhere.
pub(crate) struct NearestWall<'a>(pub &'a DistanceIndex);

impl Navigator for NearestWall<'_> {
    fn grad(&self, p: Vec2) -> Vec2 {
        (self.0.nearest(p).1 - p).normalized()
    }
}

/// Tracing parameters, all in mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TraceParams {
    /// Tool radius r: the centre is kept at distance r from the part.
    pub(crate) radius: f64,
    /// Chord tolerance: every chord between two traced points stays within this
    /// distance of the exact offset (checked at ¼, ½, ¾ of the chord).
    pub(crate) tol: f64,
    /// Travel with the part on the tool's left (`true`) or right (`false`).
    /// With the part's contours oriented material-on-the-left, `true` follows
    /// the contour's own direction (conventional milling with M3), `false` runs
    /// against it (climb).
    pub(crate) part_on_left: bool,
}

/// A traced closed path of the tool centre.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Traced {
    /// The centre positions; the last equals the first.
    pub(crate) points: Vec<Vec2>,
    /// Steps where ∇u did not point into the blocked directions (a saddle of u, or
    /// the field's error near a thin stroke) and the geometric normal started the
    /// compass instead.
    pub(crate) fallbacks: usize,
    /// Field gradient evaluations.
    pub(crate) grad_evals: usize,
}

/// Why a trace failed.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum TraceError {
    /// Phase (a) never reached the part.
    #[error("the tool never reached the part from ({:.3}, {:.3}) (phase a)", from.x, from.y)]
    NoContact {
        /// start point
        from: Vec2,
    },
    /// Phase (b) could not bracket the contact.
    #[error("lost contact with the part near ({:.3}, {:.3})", at.x, at.y)]
    LostContact {
        /// where
        at: Vec2,
    },
    /// The loop did not close within the step budget.
    #[error("the path around the part did not close after {steps} steps")]
    NotClosed {
        /// steps taken
        steps: usize,
    },
}

/// Relative bisection tolerance: contact is found to within `tol * BISECT_FRACTION`.
const BISECT_FRACTION: f64 = 1e-3;

struct Tracer<'a, N: Navigator> {
    nav: &'a N,
    part: &'a DistanceIndex,
    /// The edge nearest to the last point asked about (see
    /// [`DistanceIndex::nearest_hinted`]): the tracer's queries walk along the part.
    hint: std::cell::Cell<u32>,
    p: TraceParams,
    grad_evals: usize,
    fallbacks: usize,
}

impl<'a, N: Navigator> Tracer<'a, N> {
    /// Signed contact function: clearance of the disk, distance − r.
    fn g(&self, x: Vec2) -> f64 {
        self.part.nearest_hinted(x, &self.hint).0 - self.p.radius
    }

    /// Whether the disk at `x` overlaps the part (`g(x) < 0`, decided the
    /// same way but without finding the nearest edge).
    fn blocked(&self, x: Vec2) -> bool {
        self.part.closer_than(x, self.p.radius, &self.hint)
    }

    fn grad_dir(&mut self, x: Vec2) -> Vec2 {
        self.grad_evals += 1;
        self.nav.grad(x).normalized()
    }

    /// Bisect g on the line x + λ·dir between λ = `a` (g ≥ 0) and λ = `b` (g < 0).
    fn bisect(&self, x: Vec2, dir: Vec2, mut a: f64, mut b: f64) -> Vec2 {
        let eps = self.p.tol * BISECT_FRACTION;
        for _ in 0..200 {
            if (b - a).abs() <= eps {
                break;
            }
            let m = 0.5 * (a + b);
            if !self.blocked(x + dir * m) {
                a = m;
            } else {
                b = m;
            }
        }
        x + dir * a
    }

    /// Move from `x` along ±`n` to contact. Toward the part each step is the
    /// current clearance (the disk cannot touch within it) but at least r/20, so
    /// the step lands inside the band of width 2r around the part rather than
    /// jumping it; away from the part, steps of r/2.
    fn to_contact(&self, x: Vec2, n: Vec2) -> Option<Vec2> {
        let r = self.p.radius;
        let g0 = self.g(x);
        if g0 >= 0.0 {
            let (mut a, mut ga) = (0.0, g0);
            for _ in 0..256 {
                let lam = a + ga.max(0.05 * r);
                let gl = self.g(x + n * lam);
                if gl < 0.0 {
                    return Some(self.bisect(x, n, a, lam));
                }
                a = lam;
                ga = gl;
            }
            None
        } else {
            let mut b = 0.0;
            for k in 1..=64 {
                let lam = (-g0).max(1e-9) + 0.5 * r * (k - 1) as f64;
                if !self.blocked(x - n * lam) {
                    return Some(self.bisect(x, -n, lam, b));
                }
                b = lam;
            }
            None
        }
    }

    /// The next contact at distance `h` from `cur` (the "compass" step): on the
    /// circle of radius h about `cur`, start at the field's normal `n0` (toward
    /// the part, where the disk is blocked) and turn in the travel sense (`sign`,
    /// +1 counter-clockwise) until the first free direction, then bisect the angle
    /// between the last blocked and the first free direction. Where the offset
    /// turns sharply back (a concave corner, the disk touching two walls) the free
    /// direction lies beyond the tangent and is still found.
    fn compass(&self, cur: Vec2, n0: Vec2, h: f64, sign: f64) -> Option<Vec2> {
        // Coarse directions 10° apart: a free gap narrower than that at radius h
        // (under 0.17 h) is a passage the disk's centre does not need.
        const STEPS: usize = 36;
        let a0 = n0.y.atan2(n0.x);
        let dir = |k: f64| {
            let a = a0 + sign * k * std::f64::consts::TAU / STEPS as f64;
            Vec2::new(a.cos(), a.sin())
        };
        let mut prev_blocked = self.blocked(cur + dir(0.0) * h);
        for k in 1..=STEPS {
            let blocked = self.blocked(cur + dir(k as f64) * h);
            if prev_blocked && !blocked {
                let (mut lo, mut hi) = ((k - 1) as f64, k as f64);
                // The contact is found to 1e-2 of the tolerance along the circle.
                let eps = (self.p.tol * 1e-2 / h).min(1e-3) * STEPS as f64 / std::f64::consts::TAU;
                while hi - lo > eps {
                    let mid = 0.5 * (lo + hi);
                    if self.blocked(cur + dir(mid) * h) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                return Some(cur + dir(hi) * h);
            }
            prev_blocked = blocked;
        }
        None
    }

    /// At a concave corner of the offset (the disk touching two walls) a chord
    /// from `a` to `b` cuts off the corner, and the sharper the corner the further
    /// the corner lies from the chord for the same chord error. The corner is where
    /// the offset lines of the two walls meet: the line through `a` square to its
    /// nearest wall point, and the one through `b`. Returns that intersection when
    /// it is in contact (|clearance| within a tenth of the tolerance) and keeps both
    /// new chords within half the tolerance.
    fn concave_corner(&self, a: Vec2, b: Vec2, h: f64) -> Option<Vec2> {
        let (_, wa) = self.part.nearest_hinted(a, &self.hint);
        let (_, wb) = self.part.nearest_hinted(b, &self.hint);
        let da = (wa - a).perp();
        let db = (wb - b).perp();
        let den = da.cross(db);
        if den.abs() < 1e-12 * da.norm() * db.norm() {
            return None;
        }
        let t = (b - a).cross(db) / den;
        let x = a + da * t;
        let tol = self.p.tol;
        if x.dist(a) > 2.0 * h || x.dist(b) > 2.0 * h || self.g(x).abs() > 0.1 * tol {
            return None;
        }
        if self.chord_error(a, x) <= 0.5 * tol && self.chord_error(x, b) <= 0.5 * tol {
            Some(x)
        } else {
            None
        }
    }

    /// Largest deviation |distance − r| at ¼, ½, ¾ of the chord a–b.
    fn chord_error(&self, a: Vec2, b: Vec2) -> f64 {
        [0.25, 0.5, 0.75]
            .iter()
            .map(|&t| self.g(a.lerp(b, t)).abs())
            .fold(0.0, crate::num::max_or_nan)
    }
}

/// Trace the closed path of the tool centre around the part, starting from `start`
/// in the void.
pub(crate) fn trace<N: Navigator>(
    nav: &N,
    part: &DistanceIndex,
    start: Vec2,
    p: TraceParams,
) -> Result<Traced, TraceError> {
    let mut t = Tracer {
        nav,
        part,
        hint: std::cell::Cell::new(0),
        p,
        grad_evals: 0,
        fallbacks: 0,
    };
    let r = p.radius;
    // Phase (a): gradient ascent with steps equal to the clearance (the disk cannot
    // touch the part within that distance), then dichotomy.
    let mut x = start;
    let mut reached = None;
    for _ in 0..10_000 {
        let g = t.g(x);
        let n = t.grad_dir(x);
        if n.norm2() < 0.5 {
            break;
        }
        if g <= 0.05 * r {
            reached = t.to_contact(x, n);
            break;
        }
        x += n * (0.9 * g);
    }
    let first = reached.ok_or(TraceError::NoContact { from: start })?;

    // Phase (b).
    let h_max = r.max(4.0 * p.tol);
    let h_min = (p.tol * 1e-2).max(1e-6);
    let mut h = (8.0 * r * p.tol).sqrt().min(h_max);
    let mut pts = vec![first];
    let mut cur = first;
    let mut travelled = 0.0;
    let sign = if p.part_on_left { -1.0 } else { 1.0 };
    // A loop of the paper's letters takes a few hundred steps; this bound only
    // turns a bug into an error instead of a hang.
    let max_steps = 200_000;
    // A disk rolling once around walls of total length P travels at most
    // P + 2πr; one that has gone twice that (plus slack) without closing is
    // circling in a sliver it cannot get out of (the innermost ring of a long
    // hole), and stops here instead of after 200 000 steps.
    let max_travel = 2.0 * (t.part.perimeter() + std::f64::consts::TAU * r) + 10.0 * h_max;
    for _ in 0..max_steps {
        if travelled > max_travel {
            return Err(TraceError::NotClosed { steps: pts.len() });
        }
        // The field's direction toward the part; it only has to point into the
        // arc of blocked directions (the compass finds the exit from there).
        // It must also lean toward the wall the disk touches (within 90° of the
        // direction to the nearest point), or near a concave corner it could seed
        // the compass in the other wall's blocked arc and send the tool back.
        let mut n0 = t.grad_dir(cur);
        let (d, near) = t.part.nearest_hinted(cur, &t.hint);
        let geo = if d > 0.0 { (near - cur) / d } else { n0 };
        if n0.norm2() < 0.5 || n0.dot(geo) <= 0.0 || !t.blocked(cur + n0 * h.min(0.5 * r)) {
            n0 = geo;
            t.fallbacks += 1;
        }
        let next = loop {
            match t.compass(cur, n0, h, sign) {
                Some(q) if t.chord_error(cur, q) <= p.tol * 0.5 => break q,
                _ if h > h_min => h *= 0.5,
                Some(q) => break q,
                None => return Err(TraceError::LostContact { at: cur }),
            }
        };
        let chord = next.dist(cur);
        // Closing: once well under way, when the first point is within this step,
        // join it if the chord to it is within tolerance, else shorten the step.
        if travelled > 4.0 * h_max && first.dist(cur) <= h.max(chord) {
            if t.chord_error(cur, first) <= p.tol * 0.5 {
                pts.push(first);
                return Ok(Traced {
                    points: pts,
                    fallbacks: t.fallbacks,
                    grad_evals: t.grad_evals,
                });
            }
            if h > h_min {
                h = (0.5 * first.dist(cur)).max(h_min);
                continue;
            }
        }
        travelled += chord;
        if t.g(cur.lerp(next, 0.5)) > 0.05 * p.tol {
            if let Some(x) = t.concave_corner(cur, next, h) {
                pts.push(x);
            }
        }
        pts.push(next);
        cur = next;
        if t.chord_error(pts[pts.len() - 2], cur) < p.tol * 0.1 {
            h = (h * 1.5).min(h_max);
        }
    }
    Err(TraceError::NotClosed { steps: max_steps })
}
