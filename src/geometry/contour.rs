//! Closed contours of lines and cubic Béziers.

use super::{GeometryError, Segment, Vec2};

/// Gap (in the contour's units) below which consecutive segments count as joined.
pub const JOIN_EPS: f64 = 1e-9;

/// A closed curve: the end of each segment is the start of the next, and the end
/// of the last is the start of the first.
#[derive(Clone, Debug, PartialEq)]
pub struct Contour {
    /// The pieces, in order.
    pub segments: Vec<Segment>,
}

/// A point where the tangent turns abruptly (a corner of the outline).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// Index of the segment that starts at the corner.
    pub segment: usize,
    /// The corner point.
    pub p: Vec2,
    /// Arc length from the contour's start to the corner.
    pub s: f64,
    /// Unit tangent arriving at the corner.
    pub t_in: Vec2,
    /// Unit tangent leaving the corner.
    pub t_out: Vec2,
    /// Signed turning angle in radians, in (−π, π]: positive turns left.
    pub turn: f64,
}

/// A point on the contour with its unit tangent and arc-length position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// The point.
    pub p: Vec2,
    /// Unit tangent in the contour's direction.
    pub t: Vec2,
    /// Arc length from the contour's start.
    pub s: f64,
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

    /// Signed area (exact for lines and cubics): positive when counter-clockwise.
    pub fn signed_area(&self) -> f64 {
        self.segments.iter().map(Segment::area_term).sum()
    }

    /// True when the contour runs counter-clockwise.
    pub fn is_ccw(&self) -> bool {
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
        let mut pts = vec![self.segments[0].start()];
        for s in &self.segments {
            s.flatten_into(tol, &mut pts);
        }
        // The last point is the first point again.
        pts.pop();
        pts
    }

    /// Cumulative arc length at the start of every segment, plus the total at the end.
    pub fn cumulative_lengths(&self) -> Vec<f64> {
        let mut acc = Vec::with_capacity(self.segments.len() + 1);
        let mut s = 0.0;
        acc.push(0.0);
        for seg in &self.segments {
            s += seg.length();
            acc.push(s);
        }
        acc
    }

    /// The point at arc length `s` (taken modulo the length).
    pub fn sample_at(&self, cum: &[f64], s: f64) -> Sample {
        let total = *cum.last().unwrap_or(&0.0);
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
    pub fn sample_uniform(&self, n: usize, offset: f64) -> Vec<Sample> {
        let cum = self.cumulative_lengths();
        let total = *cum.last().unwrap_or(&0.0);
        (0..n)
            .map(|k| self.sample_at(&cum, offset + total * k as f64 / n as f64))
            .collect()
    }

    /// The corners: joins between segments where the tangent turns by more than
    /// `min_turn` radians.
    pub fn corners(&self, min_turn: f64) -> Vec<Corner> {
        let n = self.segments.len();
        let cum = self.cumulative_lengths();
        let mut out = Vec::new();
        for i in 0..n {
            let prev = &self.segments[(i + n - 1) % n];
            let cur = &self.segments[i];
            if prev.end().dist(prev.start()) == 0.0 && matches!(prev, Segment::Line { .. }) {
                continue;
            }
            let t_in = prev.tangent(1.0);
            let t_out = cur.tangent(0.0);
            let turn = t_in.cross(t_out).atan2(t_in.dot(t_out));
            if turn.abs() > min_turn {
                out.push(Corner {
                    segment: i,
                    p: cur.start(),
                    s: cum[i],
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
    pub fn winding_number(&self, p: Vec2, tol: f64) -> i32 {
        super::polygon_winding_number(&self.flatten(tol), p)
    }
}
