//! Closed contours of lines and cubic Béziers.

use super::{GeometryError, Segment, Vec2};

/// Gap (in the contour's units) below which consecutive segments count as joined.
pub(crate) const JOIN_EPS: f64 = 1e-9;

/// A closed curve: the end of each segment is the start of the next, and the end
/// of the last is the start of the first.
#[derive(Clone, Debug, PartialEq)]
pub struct Contour {
    /// The pieces, in order.
    pub segments: Vec<Segment>,
}

/// A point where the tangent turns abruptly (a corner of the outline).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Corner {
    /// Index of the segment that starts at the corner.
    pub(crate) segment: usize,
    /// The corner point.
    pub(crate) p: Vec2,
    /// Arc length from the contour's start to the corner.
    pub(crate) s: f64,
    /// Unit tangent arriving at the corner.
    pub(crate) t_in: Vec2,
    /// Unit tangent leaving the corner.
    pub(crate) t_out: Vec2,
    /// Signed turning angle in radians, in (−π, π]: positive turns left.
    pub(crate) turn: f64,
}

/// A point on the contour with its unit tangent and arc-length position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Sample {
    /// The point.
    pub(crate) p: Vec2,
    /// Unit tangent in the contour's direction.
    pub(crate) t: Vec2,
    /// Arc length from the contour's start.
    pub(crate) s: f64,
}

impl Contour {
    /// A contour from segments that must join end to start, the last to the first
    /// (within `JOIN_EPS` relative to the contour's size).
    pub fn new(segments: Vec<Segment>) -> Result<Contour, GeometryError> {
        if segments.is_empty() {
            return Err(GeometryError::Empty);
        }
        let c = Contour { segments };
        let scale = c
            .bbox()
            .map(|(lo, hi)| (hi - lo).norm())
            .unwrap_or(1.0)
            .max(1.0);
        let n = c.segments.len();
        for i in 0..n {
            let e = c.segments[i].end();
            let s = c.segments[(i + 1) % n].start();
            if e.dist(s) > JOIN_EPS * scale {
                return Err(GeometryError::Open { at: e, next: s });
            }
        }
        Ok(c)
    }

    /// The closed polygon through `points` (the last joins the first), as line
    /// segments.
    pub fn polygon(points: &[Vec2]) -> Result<Contour, GeometryError> {
        let n = points.len();
        Contour::new(
            (0..n)
                .map(|i| Segment::Line {
                    a: points[i],
                    b: points[(i + 1) % n],
                })
                .collect(),
        )
    }

    /// Bounding box of the control points (contains the curve).
    pub fn bbox(&self) -> Option<(Vec2, Vec2)> {
        let mut it = self.segments.iter().flat_map(|s| match *s {
            Segment::Line { a, b } => vec![a, b],
            Segment::Cubic { p0, p1, p2, p3 } => vec![p0, p1, p2, p3],
        });
        let first = it.next()?;
        let (mut lo, mut hi) = (first, first);
        for p in it {
            lo = Vec2::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Vec2::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        Some((lo, hi))
    }

    /// Tight bounding box of the curve (see [`Segment::tight_bbox`]).
    pub fn tight_bbox(&self) -> Option<(Vec2, Vec2)> {
        self.segments
            .iter()
            .map(Segment::tight_bbox)
            .reduce(|(a, b), (c, d)| {
                (
                    Vec2::new(a.x.min(c.x), a.y.min(c.y)),
                    Vec2::new(b.x.max(d.x), b.y.max(d.y)),
                )
            })
    }

    /// Signed area (exact for lines and cubics): positive when counter-clockwise.
    pub fn signed_area(&self) -> f64 {
        self.segments.iter().map(Segment::area_term).sum()
    }

    /// True when the contour runs counter-clockwise.
    pub(crate) fn is_ccw(&self) -> bool {
        self.signed_area() > 0.0
    }

    /// The same curve traversed the other way.
    pub fn reversed(&self) -> Contour {
        Contour {
            segments: self.segments.iter().rev().map(Segment::reversed).collect(),
        }
    }

    /// The same curve starting at segment `k`.
    pub fn cycled(&self, k: usize) -> Contour {
        let n = self.segments.len();
        Contour {
            segments: (0..n).map(|i| self.segments[(i + k) % n]).collect(),
        }
    }

    /// Every point mapped through `f` (affine maps keep the curve exact).
    pub fn map(&self, f: impl Fn(Vec2) -> Vec2 + Copy) -> Contour {
        Contour {
            segments: self.segments.iter().map(|s| s.map(f)).collect(),
        }
    }

    /// Total arc length.
    pub fn length(&self) -> f64 {
        self.segments.iter().map(Segment::length).sum()
    }

    /// The closed polygon (first point not repeated at the end) within `tol` of the curve.
    pub fn flatten(&self, tol: f64) -> Vec<Vec2> {
        let Some(first) = self.segments.first() else {
            return Vec::new();
        };
        let mut pts = vec![first.start()];
        for s in &self.segments {
            s.flatten_into(tol, &mut pts);
        }
        // The last point is the first point again.
        pts.pop();
        pts
    }

    /// Cumulative arc length at the start of every segment, plus the total at the end.
    pub(crate) fn cumulative_lengths(&self) -> Vec<f64> {
        let mut acc = Vec::with_capacity(self.segments.len() + 1);
        let mut s = 0.0;
        acc.push(0.0);
        for seg in &self.segments {
            s += seg.length();
            acc.push(s);
        }
        acc
    }

    /// The point at arc length `s` (taken modulo the length); `cum` is
    /// [`Contour::cumulative_lengths`] of this contour.
    pub(crate) fn sample_at(&self, cum: &[f64], s: f64) -> Sample {
        let total = *cum.last().unwrap_or(&0.0);
        if self.segments.is_empty() || cum.len() != self.segments.len() + 1 {
            // No curve (only reachable by building a Contour without `new`).
            return Sample {
                p: Vec2::ZERO,
                t: Vec2::new(1.0, 0.0),
                s: 0.0,
            };
        }
        let s = if total > 0.0 {
            s.rem_euclid(total)
        } else {
            0.0
        };
        // Find the segment holding s.
        let i =
            match cum.binary_search_by(|v| v.partial_cmp(&s).unwrap_or(std::cmp::Ordering::Less)) {
                Ok(i) => i.min(self.segments.len() - 1),
                Err(i) => i.saturating_sub(1).min(self.segments.len() - 1),
            };
        let seg = &self.segments[i];
        let t = seg.t_at_length(s - cum[i]);
        Sample {
            p: seg.eval(t),
            t: seg.tangent(t),
            s,
        }
    }

    /// `n` points equally spaced in arc length, the first at arc length `offset`.
    pub(crate) fn sample_uniform(&self, n: usize, offset: f64) -> Vec<Sample> {
        let cum = self.cumulative_lengths();
        let total = *cum.last().unwrap_or(&0.0);
        (0..n)
            .map(|k| self.sample_at(&cum, offset + total * k as f64 / n as f64))
            .collect()
    }

    /// The corners: joins between segments where the tangent turns by more than
    /// `min_turn` radians.
    pub(crate) fn corners(&self, min_turn: f64) -> Vec<Corner> {
        let n = self.segments.len();
        let cum = self.cumulative_lengths();
        let degenerate = |s: &Segment| match *s {
            Segment::Line { a, b } => a == b,
            Segment::Cubic { p0, p1, p2, p3 } => p0 == p1 && p1 == p2 && p2 == p3,
        };
        let mut out = Vec::new();
        for (i, (cur, &s)) in self.segments.iter().zip(&cum).enumerate() {
            if degenerate(cur) {
                continue;
            }
            // The nearest segment before this one that has a direction: a zero-length
            // piece between two segments must not hide the corner they make.
            let Some(prev) = (1..=n)
                .map(|k| &self.segments[(i + n - k) % n])
                .find(|p| !degenerate(p))
            else {
                continue;
            };
            let t_in = prev.tangent(1.0);
            let t_out = cur.tangent(0.0);
            let turn = t_in.cross(t_out).atan2(t_in.dot(t_out));
            if turn.abs() > min_turn {
                out.push(Corner {
                    segment: i,
                    p: cur.start(),
                    s,
                    t_in,
                    t_out,
                    turn,
                });
            }
        }
        out
    }

    /// Winding number of the contour about `p` (the index of the paper's Appendix I,
    /// eq. (8.2)), computed on the flattening within `tol`: +1 inside a
    /// counter-clockwise contour, −1 inside a clockwise one, 0 outside.
    /// This flattens the contour on every call: to test many points, flatten once
    /// and call [`polygon_winding_number`](super::polygon_winding_number).
    #[cfg(test)]
    pub(crate) fn winding_number(&self, p: Vec2, tol: f64) -> i32 {
        super::polygon_winding_number(&self.flatten(tol), p)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geometry::glyphs;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    fn line(a: Vec2, b: Vec2) -> Segment {
        Segment::Line { a, b }
    }

    /// A closed polygon of lines through `pts`.
    pub(crate) fn polygon(pts: &[Vec2]) -> Contour {
        let n = pts.len();
        Contour::new((0..n).map(|i| line(pts[i], pts[(i + 1) % n])).collect())
            .expect("test polygon is closed")
    }

    /// Axis-aligned square, counter-clockwise.
    pub(crate) fn square(x0: f64, y0: f64, side: f64) -> Contour {
        polygon(&[
            v(x0, y0),
            v(x0 + side, y0),
            v(x0 + side, y0 + side),
            v(x0, y0 + side),
        ])
    }

    /// Circle of radius `r` about `c` from four cubic quarter arcs (k = 0.5519…),
    /// counter-clockwise.
    pub(crate) fn circle(c: Vec2, r: f64) -> Contour {
        let k = 0.551_915_024_494 * r;
        let pts = [v(r, 0.0), v(0.0, r), v(-r, 0.0), v(0.0, -r)];
        let segs = (0..4)
            .map(|i| {
                let a = pts[i];
                let b = pts[(i + 1) % 4];
                Segment::Cubic {
                    p0: c + a,
                    p1: c + a + a.perp().normalized() * k,
                    p2: c + b - b.perp().normalized() * k,
                    p3: c + b,
                }
            })
            .collect();
        Contour::new(segs).expect("circle is closed")
    }

    /// A rounded rectangle: lines and tangent-continuous cubic corners, CCW.
    fn rounded_rect() -> Contour {
        let (w, h, r) = (40.0, 20.0, 5.0);
        let k = 0.551_915_024_494 * r;
        let segs = vec![
            line(v(r, 0.0), v(w - r, 0.0)),
            Segment::Cubic {
                p0: v(w - r, 0.0),
                p1: v(w - r + k, 0.0),
                p2: v(w, r - k),
                p3: v(w, r),
            },
            line(v(w, r), v(w, h - r)),
            Segment::Cubic {
                p0: v(w, h - r),
                p1: v(w, h - r + k),
                p2: v(w - r + k, h),
                p3: v(w - r, h),
            },
            line(v(w - r, h), v(r, h)),
            Segment::Cubic {
                p0: v(r, h),
                p1: v(r - k, h),
                p2: v(0.0, h - r + k),
                p3: v(0.0, h - r),
            },
            line(v(0.0, h - r), v(0.0, r)),
            Segment::Cubic {
                p0: v(0.0, r),
                p1: v(0.0, r - k),
                p2: v(r - k, 0.0),
                p3: v(r, 0.0),
            },
        ];
        Contour::new(segs).expect("rounded rectangle is closed")
    }

    fn test_contours() -> Vec<Contour> {
        let mut cs = vec![
            square(1.0, 2.0, 3.0),
            circle(v(5.0, -3.0), 7.0),
            rounded_rect(),
        ];
        for ch in glyphs::paper_chars() {
            let g = glyphs::paper_glyph(ch).expect("paper glyph");
            cs.extend(g.outlines);
            cs.extend(g.counters);
        }
        cs
    }

    #[test]
    fn new_rejects_open_and_empty() {
        assert_eq!(Contour::new(vec![]), Err(GeometryError::Empty));
        let open = vec![
            line(v(0.0, 0.0), v(1.0, 0.0)),
            line(v(1.0, 0.0), v(1.0, 1.0)),
        ];
        match Contour::new(open) {
            Err(GeometryError::Open { at, next }) => {
                assert_eq!(at, v(1.0, 1.0));
                assert_eq!(next, v(0.0, 0.0));
            }
            other => panic!("expected Open, got {other:?}"),
        }
        // A gap in the middle is found too.
        let gap = vec![
            line(v(0.0, 0.0), v(1.0, 0.0)),
            line(v(1.0, 0.001), v(0.0, 0.0)),
        ];
        assert!(matches!(Contour::new(gap), Err(GeometryError::Open { .. })));
    }

    #[test]
    fn area_matches_flattening_and_is_invariant() {
        for c in test_contours() {
            let area = c.signed_area();
            let poly = crate::geometry::polygon_area(&c.flatten(1e-4));
            let len = c.length();
            // The flattening is within 1e-4 of the curve, so the areas differ by at
            // most about length × 1e-4.
            assert!(
                (area - poly).abs() <= len * 1e-4,
                "area {area} vs flattened {poly}"
            );
            let r = c.reversed();
            assert!((r.signed_area() + area).abs() < 1e-9 * area.abs());
            assert!((r.length() - len).abs() < 1e-9 * len);
            for k in 0..c.segments.len() {
                let cy = c.cycled(k);
                assert!((cy.signed_area() - area).abs() < 1e-9 * area.abs());
                assert!((cy.length() - len).abs() < 1e-9 * len);
                assert!(Contour::new(cy.segments.clone()).is_ok());
            }
            assert!(Contour::new(r.segments.clone()).is_ok());
        }
    }

    #[test]
    fn known_areas_and_lengths() {
        let sq = square(0.0, 0.0, 3.0);
        assert_eq!(sq.signed_area(), 9.0);
        assert_eq!(sq.length(), 12.0);
        let c = circle(Vec2::ZERO, 10.0);
        // The 4-cubic circle deviates from the true one by at most 2.7e-4 relative.
        let pi_area = c.signed_area() / 100.0;
        let pi_len = c.length() / 20.0;
        assert!((pi_area - std::f64::consts::PI).abs() < 1e-3, "{pi_area}");
        assert!((pi_len - std::f64::consts::PI).abs() < 1e-3, "{pi_len}");
        assert!(c.is_ccw() && !c.reversed().is_ccw());
    }

    #[test]
    fn corners_of_square_and_smooth_contours() {
        let sq = square(0.0, 0.0, 2.0);
        let cs = sq.corners(0.1);
        assert_eq!(cs.len(), 4);
        for (i, c) in cs.iter().enumerate() {
            assert_eq!(c.segment, i);
            assert_eq!(c.s, 2.0 * i as f64);
            assert!((c.turn - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        }
        assert_eq!(cs[1].p, v(2.0, 0.0));
        // Reversed: the turns are to the right.
        for c in sq.reversed().corners(0.1) {
            assert!((c.turn + std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        }
        // A zero-length piece at a corner does not hide it.
        let with_dot = Contour::new(vec![
            line(v(0.0, 0.0), v(2.0, 0.0)),
            line(v(2.0, 0.0), v(2.0, 0.0)),
            line(v(2.0, 0.0), v(2.0, 2.0)),
            line(v(2.0, 2.0), v(0.0, 0.0)),
        ])
        .expect("closed");
        let cs2 = with_dot.corners(0.1);
        assert_eq!(cs2.len(), 3);
        assert_eq!(cs2[1].segment, 2);
        assert!((cs2[1].turn - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        // Tangent-continuous joins are not corners.
        assert!(rounded_rect().corners(1e-6).is_empty());
        assert!(circle(Vec2::ZERO, 1.0).corners(1e-6).is_empty());
        // The paper's H: the total turning of a simple CCW contour is 2π, and the
        // corners with smooth joins excluded account for the rest.
        let h = &glyphs::paper_glyph('H').expect("H").outlines[0];
        let corners = h.corners(0.01);
        assert!(corners.len() >= 8, "H has {} corners", corners.len());
        for c in &corners {
            assert!(c.turn.abs() <= std::f64::consts::PI);
            assert!((c.t_in.norm() - 1.0).abs() < 1e-12);
            assert!((c.t_out.norm() - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn sample_uniform_is_equally_spaced() {
        for c in [rounded_rect(), circle(v(1.0, 1.0), 3.0)] {
            let n = 400;
            let total = c.length();
            let samples = c.sample_uniform(n, 0.25);
            assert_eq!(samples.len(), n);
            let cum = c.cumulative_lengths();
            let mut worst_s: f64 = 0.0;
            let mut worst_chord: f64 = 0.0;
            for (k, smp) in samples.iter().enumerate() {
                let want = (0.25 + total * k as f64 / n as f64).rem_euclid(total);
                worst_s = worst_s.max((smp.s - want).abs());
                assert!((smp.t.norm() - 1.0).abs() < 1e-12);
                // The point is on the contour: arc length from the segment start matches.
                let i = cum
                    .iter()
                    .rposition(|&x| x <= smp.s)
                    .unwrap_or(0)
                    .min(c.segments.len() - 1);
                let seg = c.segments[i];
                let t = seg.t_at_length(smp.s - cum[i]);
                assert!(seg.eval(t).dist(smp.p) < 1e-9);
                let next = &samples[(k + 1) % n];
                worst_chord = worst_chord.max((smp.p.dist(next.p) - total / n as f64).abs());
            }
            assert!(worst_s < 1e-9, "{worst_s:e}");
            // Chords of equal arcs are shorter by at most h³κ²/24 (h = step).
            assert!(worst_chord < 1e-3 * total / n as f64, "{worst_chord:e}");
        }
    }

    #[test]
    fn empty_contour_does_not_panic() {
        // Only constructible through the public field, never through `new`.
        let c = Contour { segments: vec![] };
        assert!(c.flatten(0.1).is_empty());
        assert_eq!(c.sample_uniform(3, 0.0).len(), 3);
        assert_eq!(c.winding_number(Vec2::ZERO, 0.1), 0);
        assert!(c.corners(0.1).is_empty());
        assert_eq!(c.bbox(), None);
    }

    #[test]
    fn winding_number_inside_outside() {
        let c = circle(Vec2::ZERO, 10.0);
        assert_eq!(c.winding_number(v(0.0, 0.0), 0.01), 1);
        assert_eq!(c.winding_number(v(9.9, 0.0), 0.01), 1);
        assert_eq!(c.winding_number(v(10.1, 0.0), 0.01), 0);
        assert_eq!(c.reversed().winding_number(v(3.0, 3.0), 0.01), -1);
        let a = glyphs::paper_glyph('A').expect("A");
        let counter = &a.counters[0];
        let (lo, hi) = counter.bbox().expect("bbox");
        let mid = (lo + hi) * 0.5;
        assert_eq!(counter.winding_number(mid, 0.1), -1);
        // The counter's middle is not material: outline +1, counter −1.
        assert_eq!(a.outlines[0].winding_number(mid, 0.1), 1);
    }
}
