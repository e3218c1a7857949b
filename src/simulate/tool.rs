//! The tool and its sweep along a straight segment: for every cell centre the
//! tool's axis passes within radius r of, the lowest z of the tool's lower
//! surface over it.
//!
//! A tool ([`Tool`]) is an end mill of radius r and corner radius rc: flat
//! (rc = 0), ball (rc = r) or bull nose (0 < rc < r). The G-code coordinates
//! are its tip, the lowest point on its axis, whatever the shape. Its lower
//! surface stands p(ρ) above the tip at horizontal distance ρ from the axis:
//! p(ρ) = 0 for ρ ≤ r − rc, and rc − √(rc² − (ρ − (r − rc))²) for
//! r − rc < ρ ≤ r ([`Tool::lift`]).
//!
//! The segment runs from a = (ax, ay, az) to b; its XY part is
//! p(t) = a + t·d, d = b − a, t ∈ [0, 1], and z(t) = az + t·(bz − az). A cell
//! centre c is under the tool while |p(t) − c|² ≤ r², i.e. while
//! A t² + B t + C ≤ 0 with A = d·d, B = 2 (a − c)·d, C = |a − c|² − r²: an
//! interval [t₁, t₂] ∩ [0, 1] (exact, from the quadratic). The lowest tool
//! surface over c is the minimum over that interval of
//! f(t) = z(t) + p(ρ(t)), ρ(t) = |p(t) − c|:
//! - flat ([`Segment::bottom_over`]): p = 0 and z is linear in t, so the
//!   minimum is min(z(t₁), z(t₂)), exact;
//! - ball ([`Segment::ball_over`]): the swept ball is a capsule (the balls of
//!   radius r about the centre segment a + (0, 0, r) .. b + (0, 0, r)), and
//!   f's minimum is the lowest point of the vertical line through c inside
//!   it: on the capsule's cylinder where f'(t) = 0, at
//!   t* = t₀ − Δz·√((r² − ρ₀²) / (A (A + Δz²))) (t₀ the XY closest approach,
//!   ρ₀ its distance, Δz = bz − az; the cylinder root in t), clamped to the
//!   interval, which gives the end spheres when t* falls outside it (f is
//!   convex, so the clamped stationary point is the minimum); exact up to
//!   rounding;
//! - bull nose ([`Segment::bull_over`]): f is convex (the tool is a convex
//!   body and the offset p(t) is affine in t), so its minimum is found by
//!   bisection on the sign of f' in the interval, stopped when the tangents
//!   at the bracket's ends prove the best end within [`BULL_TOL`] of the
//!   minimum, or after [`MAX_BISECTIONS`] halvings.
//!
//! A move that does not move in XY (a plunge, or no move at all) keeps ρ
//! fixed: the surface over c is the lower end's z plus p(ρ).
//!
//! Arcs reach this module as chords within a tolerance δ of the arc
//! ([`super::CHORD_FRACTION`] of the cell). The swept tool along a path is
//! the path ⊕ the tool's body (a Minkowski sum), and the Hausdorff distance
//! of two such sums is at most the paths' (δ), whatever the convex shape: the
//! chord tolerance bounds the error of a ball's or a bull nose's sweep as it
//! bounds a flat's, measured across the swept surface (vertically it grows
//! with the surface's slope, as at a flat's vertical rim).

use super::SimError;
use serde::Serialize;

/// A bull nose's lowest surface is within this (mm) of the exact minimum:
/// far below a cell's height figures (3 decimals) and the brief's 1e-6 mm.
pub(crate) const BULL_TOL: f64 = 1e-7;
/// The most halvings of the bull nose's bracket: 2⁻⁶⁴ of [0, 1] is below the
/// spacing of doubles near 1, so more cannot narrow it.
pub(crate) const MAX_BISECTIONS: usize = 64;

/// The shape of an end mill's end.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ToolShape {
    /// Flat end mill: corner radius 0.
    Flat,
    /// Ball end mill: corner radius = radius.
    Ball,
    /// Bull nose end mill: 0 < corner radius < radius.
    Bull,
}

impl ToolShape {
    /// `flat`, `ball` or `bull` (the CLI's `--tool-shape` values).
    pub(crate) fn name(self) -> &'static str {
        match self {
            ToolShape::Flat => "flat",
            ToolShape::Ball => "ball",
            ToolShape::Bull => "bull",
        }
    }
}

/// An end mill: diameter and shape, the corner radius checked against the
/// radius (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tool {
    diameter: f64,
    shape: ToolShape,
    corner: f64,
}

impl Tool {
    /// A tool of `diameter` mm (positive, finite) and `shape`; `corner_radius`
    /// (mm) is needed for a bull nose (0 < rc < r) and may be given for the
    /// others only as their own (0 for flat, r for ball).
    pub(crate) fn new(
        shape: ToolShape,
        diameter: f64,
        corner_radius: Option<f64>,
    ) -> Result<Tool, SimError> {
        if !(diameter > 0.0 && diameter.is_finite()) {
            return Err(SimError::ToolDiameter(diameter));
        }
        let r = diameter / 2.0;
        let corner = match (shape, corner_radius) {
            (ToolShape::Flat, None | Some(0.0)) => 0.0,
            (ToolShape::Ball, None) => r,
            (ToolShape::Ball, Some(c)) if c == r => r,
            (ToolShape::Bull, Some(c)) if c > 0.0 && c < r => c,
            (ToolShape::Bull, Some(c)) => {
                return Err(SimError::BullCorner {
                    corner: c,
                    radius: r,
                })
            }
            (ToolShape::Bull, None) => return Err(SimError::BullWithoutCorner),
            (s, Some(c)) => {
                return Err(SimError::CornerNotBull {
                    corner: c,
                    shape: s,
                })
            }
        };
        Ok(Tool {
            diameter,
            shape,
            corner,
        })
    }

    /// A flat end mill of `diameter` mm (not checked: for callers that have).
    pub(crate) fn flat_unchecked(diameter: f64) -> Tool {
        Tool {
            diameter,
            shape: ToolShape::Flat,
            corner: 0.0,
        }
    }

    /// Diameter, mm.
    pub(crate) fn diameter(&self) -> f64 {
        self.diameter
    }

    /// Radius r, mm.
    pub(crate) fn radius(&self) -> f64 {
        self.diameter / 2.0
    }

    /// The shape.
    pub(crate) fn shape(&self) -> ToolShape {
        self.shape
    }

    /// Corner radius rc, mm (0 flat, r ball).
    pub(crate) fn corner_radius(&self) -> f64 {
        self.corner
    }

    /// Radius of the flat part of the end, r − rc, mm (r flat, 0 ball).
    pub(crate) fn flat_radius(&self) -> f64 {
        match self.shape {
            ToolShape::Flat => self.radius(),
            ToolShape::Ball => 0.0,
            ToolShape::Bull => self.radius() - self.corner,
        }
    }

    /// p(ρ): how far above the tip the lower surface stands at `rho` mm from
    /// the axis; `None` beyond the radius.
    pub(crate) fn lift(&self, rho: f64) -> Option<f64> {
        let r = self.radius();
        (rho <= r).then(|| match self.shape {
            ToolShape::Flat => 0.0,
            ToolShape::Ball => r - (r * r - rho * rho).max(0.0).sqrt(),
            ToolShape::Bull => corner_lift(rho, r - self.corner, self.corner),
        })
    }

    /// The report's words for it: `3.175 mm flat end mill`,
    /// `3.175 mm ball end mill`, `6 mm bull nose end mill, corner 1.5 mm`.
    pub(crate) fn describe(&self) -> String {
        match self.shape {
            ToolShape::Flat => format!("{} mm flat end mill", self.diameter),
            ToolShape::Ball => format!("{} mm ball end mill", self.diameter),
            ToolShape::Bull => format!(
                "{} mm bull nose end mill, corner {} mm",
                self.diameter, self.corner
            ),
        }
    }
}

/// The bull nose's p(ρ) (flat part of radius `r0`, corner `rc`).
fn corner_lift(rho: f64, r0: f64, rc: f64) -> f64 {
    if rho <= r0 {
        0.0
    } else {
        let e = rho - r0;
        rc - (rc * rc - e * e).max(0.0).sqrt()
    }
}

/// A straight move of the tool's tip (the lowest point of its axis), mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Segment {
    /// Start (x, y, z).
    pub(crate) a: [f64; 3],
    /// End (x, y, z).
    pub(crate) b: [f64; 3],
}

/// Where a cell centre is under the tool along a segment.
enum Under {
    /// Never within r of the axis.
    Never,
    /// The segment has no XY length (under 1 nm): the tool stands still over
    /// the centre, at squared distance `rho2`.
    Still { rho2: f64 },
    /// Within r along a part of the segment.
    Along(Span),
}

/// Where a cell centre is under the tool: for t in [t1, t2] ⊂ [0, 1]; `ex`,
/// `ey`: a − c, `dx`, `dy`: b − a in XY, `aa` = dx² + dy².
#[derive(Clone, Copy)]
struct Span {
    t1: f64,
    t2: f64,
    ex: f64,
    ey: f64,
    dx: f64,
    dy: f64,
    aa: f64,
}

impl Span {
    /// p(t) − c in XY, mm.
    fn offset(&self, t: f64) -> (f64, f64) {
        (self.ex + t * self.dx, self.ey + t * self.dy)
    }

    /// t₀, the XY closest approach of the axis to c (unclamped).
    fn closest(&self) -> f64 {
        -(self.ex * self.dx + self.ey * self.dy) / self.aa
    }

    /// ρ₀², the squared XY distance at t₀, from the cross product: free of
    /// the cancellation in C − B²/4A.
    fn rho0_squared(&self) -> f64 {
        let cross = self.dx * self.ey - self.dy * self.ex;
        cross * cross / self.aa
    }

    /// `t` clamped to [t1, t2].
    fn clamp(&self, t: f64) -> f64 {
        t.clamp(self.t1, self.t2)
    }
}

impl Segment {
    /// Distance (mm) from (x, y) to the segment's XY projection, the textbook
    /// way (the projection clamped to the segment); the tests hold the
    /// quadratic of [`Segment::ball_over`] and its kin to it.
    pub(crate) fn xy_dist(&self, x: f64, y: f64) -> f64 {
        let (dx, dy) = (self.b[0] - self.a[0], self.b[1] - self.a[1]);
        let l2 = dx * dx + dy * dy;
        let t = if l2 > 0.0 {
            (((x - self.a[0]) * dx + (y - self.a[1]) * dy) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (self.a[0] + t * dx - x).hypot(self.a[1] + t * dy - y)
    }

    /// The 3-D length, mm.
    pub(crate) fn len(&self) -> f64 {
        let d = [0, 1, 2].map(|k| self.b[k] - self.a[k]);
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
    }

    /// The lower of the two end heights, mm.
    pub(crate) fn z_min(&self) -> f64 {
        self.a[2].min(self.b[2])
    }

    /// z at parameter `t`, mm.
    fn z(&self, t: f64) -> f64 {
        self.a[2] + t * (self.b[2] - self.a[2])
    }

    /// The x-interval of the points at height `y` that lie within `r` of the XY
    /// segment (the capsule: the segment's disk sweep), or `None`. The capsule
    /// is convex, so its cut by a line is an interval, bounded by the end disks'
    /// circles or the two sides offset by ±r along the normal.
    pub(crate) fn span_at(&self, y: f64, r: f64) -> Option<(f64, f64)> {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for p in [self.a, self.b] {
            let dy = y - p[1];
            if dy.abs() <= r {
                let w = (r * r - dy * dy).sqrt();
                lo = lo.min(p[0] - w);
                hi = hi.max(p[0] + w);
            }
        }
        let (dx, dy) = (self.b[0] - self.a[0], self.b[1] - self.a[1]);
        let l = (dx * dx + dy * dy).sqrt();
        if l > 0.0 {
            let (nx, ny) = (-dy / l * r, dx / l * r);
            for s in [1.0, -1.0] {
                let (px, py) = (self.a[0] + s * nx, self.a[1] + s * ny);
                let (qx, qy) = (self.b[0] + s * nx, self.b[1] + s * ny);
                if (py - y) * (qy - y) <= 0.0 && py != qy {
                    let x = px + (y - py) / (qy - py) * (qx - px);
                    lo = lo.min(x);
                    hi = hi.max(x);
                }
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// The parameters for which (cx, cy) lies within `r` of the axis (the
    /// quadratic of the module docs).
    fn under(&self, cx: f64, cy: f64, r: f64) -> Under {
        let (dx, dy) = (self.b[0] - self.a[0], self.b[1] - self.a[1]);
        let (ex, ey) = (self.a[0] - cx, self.a[1] - cy);
        let aa = dx * dx + dy * dy;
        let rho2 = ex * ex + ey * ey;
        let c = rho2 - r * r;
        // A move shorter than a nanometre in XY: the tool stands still.
        if aa < 1e-18 {
            return if c <= 0.0 {
                Under::Still { rho2 }
            } else {
                Under::Never
            };
        }
        let b = 2.0 * (ex * dx + ey * dy);
        let disc = b * b - 4.0 * aa * c;
        if disc < 0.0 {
            return Under::Never;
        }
        let q = disc.sqrt();
        let t1 = ((-b - q) / (2.0 * aa)).max(0.0);
        let t2 = ((-b + q) / (2.0 * aa)).min(1.0);
        if t1 <= t2 {
            Under::Along(Span {
                t1,
                t2,
                ex,
                ey,
                dx,
                dy,
                aa,
            })
        } else {
            Under::Never
        }
    }

    /// The lowest surface of `tool` over the point (cx, cy) along the segment
    /// (see the module docs), or `None` if the point is never within the
    /// tool's radius of its axis.
    pub(crate) fn surface_over(&self, cx: f64, cy: f64, tool: &Tool) -> Option<f64> {
        match tool.shape {
            ToolShape::Flat => self.bottom_over(cx, cy, tool.radius()),
            ToolShape::Ball => self.ball_over(cx, cy, tool.radius()),
            ToolShape::Bull => self.bull_over(cx, cy, tool.radius(), tool.corner),
        }
    }

    /// The lowest tool-bottom z over the point (cx, cy) for a flat end mill
    /// of radius `r` (see the module docs), or `None` if the point is never
    /// within `r` of the axis.
    pub(crate) fn bottom_over(&self, cx: f64, cy: f64, r: f64) -> Option<f64> {
        match self.under(cx, cy, r) {
            Under::Never => None,
            Under::Still { .. } => Some(self.z_min()),
            Under::Along(s) => Some(self.z(s.t1).min(self.z(s.t2))),
        }
    }

    /// The lowest surface over (cx, cy) of a ball end mill of radius `r`
    /// whose tip follows the segment: the capsule's lowest point over it
    /// (see the module docs), or `None` if the point is never within `r` of
    /// the axis.
    pub(crate) fn ball_over(&self, cx: f64, cy: f64, r: f64) -> Option<f64> {
        let span = match self.under(cx, cy, r) {
            Under::Never => return None,
            Under::Still { rho2 } => {
                return Some(self.z_min() + r - (r * r - rho2).max(0.0).sqrt())
            }
            Under::Along(s) => s,
        };
        let f = |t: f64| {
            let (px, py) = span.offset(t);
            self.z(t) + r - (r * r - (px * px + py * py)).max(0.0).sqrt()
        };
        let dz = self.b[2] - self.a[2];
        // XY closest approach t₀; a level move is lowest there.
        let t0 = span.closest();
        let t = if dz == 0.0 {
            t0
        } else {
            let aa = span.aa;
            t0 - dz * ((r * r - span.rho0_squared()).max(0.0) / (aa * (aa + dz * dz))).sqrt()
        };
        Some(f(span.clamp(t)))
    }

    /// The lowest surface over (cx, cy) of a bull nose end mill of radius `r`
    /// and corner radius `rc` whose tip follows the segment, within
    /// [`BULL_TOL`] (see the module docs), or `None` if the point is never
    /// within `r` of the axis.
    pub(crate) fn bull_over(&self, cx: f64, cy: f64, r: f64, rc: f64) -> Option<f64> {
        let r0 = r - rc;
        let span = match self.under(cx, cy, r) {
            Under::Never => return None,
            Under::Still { rho2 } => return Some(self.z_min() + corner_lift(rho2.sqrt(), r0, rc)),
            Under::Along(s) => s,
        };
        let (dx, dy) = (span.dx, span.dy);
        let dz = self.b[2] - self.a[2];
        // f(t) and f'(t) = Δz + p'(ρ) ρ'(t), ρ' = (p(t) − c)·d / ρ,
        // p'(ρ) = (ρ − r0) / √(rc² − (ρ − r0)²) on the corner (infinite at
        // the rim, where the corner's wall is vertical).
        let f = |t: f64| -> (f64, f64) {
            let (px, py) = span.offset(t);
            let rho = (px * px + py * py).sqrt();
            let z = self.z(t);
            if rho <= r0 {
                return (z, dz);
            }
            let e = rho - r0;
            let w = (rc * rc - e * e).max(0.0).sqrt();
            let drho = (px * dx + py * dy) / rho;
            let slope = if drho == 0.0 {
                0.0
            } else if w > 0.0 {
                e / w * drho
            } else {
                f64::INFINITY.copysign(drho)
            };
            (z + rc - w, dz + slope)
        };
        if dz == 0.0 {
            // Level: the lowest surface is where ρ is least (p grows with ρ),
            // the XY closest approach clamped to the interval.
            return Some(f(span.clamp(span.closest())).0);
        }
        let (mut lo, mut hi) = (span.t1, span.t2);
        let (mut flo, mut glo) = f(lo);
        let (mut fhi, mut ghi) = f(hi);
        if glo >= 0.0 || lo == hi {
            return Some(flo.min(fhi));
        }
        if ghi <= 0.0 {
            return Some(fhi.min(flo));
        }
        for _ in 0..MAX_BISECTIONS {
            // f is convex: each end's tangent lies below it, so over the
            // bracket f ≥ max(f(lo) + f'(lo)·w, f(hi) − f'(hi)·w).
            let w = hi - lo;
            let bound = (flo + glo * w).max(fhi - ghi * w);
            if flo.min(fhi) - bound <= BULL_TOL {
                break;
            }
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            let (fm, gm) = f(mid);
            if gm > 0.0 {
                (hi, fhi, ghi) = (mid, fm, gm);
            } else if gm < 0.0 {
                (lo, flo, glo) = (mid, fm, gm);
            } else {
                return Some(fm.min(flo).min(fhi));
            }
        }
        Some(flo.min(fhi))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bottom_and_span_agree_with_the_distance_oracle() {
        let s = Segment {
            a: [1.0, 2.0, 0.0],
            b: [7.0, 4.5, -3.0],
        };
        let r = 1.5;
        for k in 0..4000 {
            let (x, y) = (-1.0 + (k % 80) as f64 * 0.13, 0.0 + (k / 80) as f64 * 0.15);
            let d = s.xy_dist(x, y);
            let got = s.bottom_over(x, y, r);
            if d < r - 1e-9 {
                let z = got.expect("inside");
                // Brute force over t: the lowest z(t) with the point under the disk.
                let zb = (0..=20000)
                    .map(|i| i as f64 / 20000.0)
                    .filter(|&t| {
                        let (px, py) = (s.a[0] + t * 6.0, s.a[1] + t * 2.5);
                        (px - x).hypot(py - y) <= r
                    })
                    .map(|t| -3.0 * t)
                    .fold(f64::INFINITY, f64::min);
                assert!((z - zb).abs() < 1e-3, "{x} {y}: {z} vs {zb}");
                let (lo, hi) = s.span_at(y, r).expect("span");
                assert!(lo <= x && x <= hi);
            } else if d > r + 1e-9 {
                assert!(got.is_none(), "{x} {y}");
                if let Some((lo, hi)) = s.span_at(y, r) {
                    // Outside the capsule, yet maybe in its span's hull only
                    // if the span's ends are capsule points.
                    for e in [lo, hi] {
                        assert!(s.xy_dist(e, y) <= r + 1e-9);
                    }
                }
            }
        }
    }

    #[test]
    fn a_vertical_move_cuts_its_disk_to_the_lower_end() {
        let s = Segment {
            a: [0.0, 0.0, 1.0],
            b: [0.0, 0.0, -2.0],
        };
        assert_eq!(s.bottom_over(0.5, 0.5, 1.0), Some(-2.0));
        assert_eq!(s.bottom_over(0.8, 0.8, 1.0), None);
        assert_eq!(s.span_at(0.6, 1.0), Some((-0.8, 0.8)));
    }

    /// A fixed-seed generator (the simulator's tests use no crate for it).
    use crate::num::testing::Lcg;

    /// The flat rule as it was before the tool learned other shapes, kept
    /// verbatim: `bottom_over` must give the same bits.
    fn bottom_over_before(s: &Segment, cx: f64, cy: f64, r: f64) -> Option<f64> {
        let (dx, dy) = (s.b[0] - s.a[0], s.b[1] - s.a[1]);
        let (ex, ey) = (s.a[0] - cx, s.a[1] - cy);
        let aa = dx * dx + dy * dy;
        let c = ex * ex + ey * ey - r * r;
        let z = |t: f64| s.a[2] + t * (s.b[2] - s.a[2]);
        if aa < 1e-18 {
            return (c <= 0.0).then(|| s.z_min());
        }
        let b = 2.0 * (ex * dx + ey * dy);
        let disc = b * b - 4.0 * aa * c;
        if disc < 0.0 {
            return None;
        }
        let q = disc.sqrt();
        let t1 = ((-b - q) / (2.0 * aa)).max(0.0);
        let t2 = ((-b + q) / (2.0 * aa)).min(1.0);
        (t1 <= t2).then(|| z(t1).min(z(t2)))
    }

    /// Random segments of every kind: slanted, level, vertical (a plunge),
    /// nearly vertical, and standing still.
    fn random_segment(g: &mut Lcg, k: usize) -> Segment {
        let a = [g.range(-5.0, 5.0), g.range(-5.0, 5.0), g.range(-3.0, 1.0)];
        let mut b = [g.range(-5.0, 5.0), g.range(-5.0, 5.0), g.range(-3.0, 1.0)];
        match k % 6 {
            0 => b[2] = a[2],                                        // level
            1 => (b[0], b[1]) = (a[0], a[1]),                        // plunge or lift
            2 => b = a,                                              // no move
            3 => (b[0], b[1]) = (a[0] + 1e-6, a[1] - 3e-7),          // nearly vertical
            4 => (b[0], b[1]) = (a[0] + g.range(-0.05, 0.05), a[1]), // short
            _ => {}
        }
        Segment { a, b }
    }

    /// The lowest of z(t) + p(ρ(t)) over t by dense sampling: 4001 samples
    /// over [0, 1], then 4001 between the best sample's neighbours (f is
    /// convex, so its minimum lies there). `None` when no sample has the
    /// point under the tool. `p` is the tool's profile written from the
    /// definition, apart from [`Tool::lift`].
    fn oracle(s: &Segment, c: [f64; 2], r: f64, p: &dyn Fn(f64) -> f64) -> Option<f64> {
        let f = |t: f64| {
            let (x, y) = (
                s.a[0] + t * (s.b[0] - s.a[0]),
                s.a[1] + t * (s.b[1] - s.a[1]),
            );
            let rho = (x - c[0]).hypot(y - c[1]);
            (rho <= r).then(|| s.a[2] + t * (s.b[2] - s.a[2]) + p(rho))
        };
        let n = 4000;
        let (mut best, mut at) = (f64::INFINITY, None);
        for i in 0..=n {
            if let Some(v) = f(i as f64 / n as f64) {
                if v < best {
                    (best, at) = (v, Some(i));
                }
            }
        }
        let i = at?;
        let (lo, hi) = (
            (i.max(1) - 1) as f64 / n as f64,
            ((i + 1).min(n)) as f64 / n as f64,
        );
        for k in 0..=n {
            if let Some(v) = f(lo + (hi - lo) * k as f64 / n as f64) {
                best = best.min(v);
            }
        }
        Some(best)
    }

    #[test]
    fn every_shape_agrees_with_a_dense_oracle_on_random_segments() {
        let mut g = Lcg(0);
        let (mut worst_ball, mut worst_bull, mut compared) = (0.0f64, 0.0f64, 0);
        for k in 0..600 {
            let s = random_segment(&mut g, k);
            let r = g.range(0.3, 4.0);
            let rc = r * g.range(0.05, 0.95);
            let ball = Tool::new(ToolShape::Ball, 2.0 * r, None).unwrap();
            let bull = Tool::new(ToolShape::Bull, 2.0 * r, Some(rc)).unwrap();
            let flat = Tool::new(ToolShape::Flat, 2.0 * r, None).unwrap();
            let p_ball = |rho: f64| r - (r * r - rho * rho).max(0.0).sqrt();
            let p_bull = |rho: f64| {
                let e = (rho - (r - rc)).max(0.0);
                rc - (rc * rc - e * e).max(0.0).sqrt()
            };
            for _ in 0..20 {
                // Cell centres near the swept disk (some outside it).
                let t = g.range(-0.2, 1.2);
                let c = [
                    s.a[0] + t * (s.b[0] - s.a[0]) + g.range(-1.1, 1.1) * r,
                    s.a[1] + t * (s.b[1] - s.a[1]) + g.range(-1.1, 1.1) * r,
                ];
                let zf = s.surface_over(c[0], c[1], &flat);
                let zb = s.surface_over(c[0], c[1], &ball);
                let zn = s.surface_over(c[0], c[1], &bull);
                // The flat is bit for bit the rule it always was.
                assert_eq!(zf, bottom_over_before(&s, c[0], c[1], r));
                // The same footprint for every shape.
                assert_eq!(zf.is_some(), zb.is_some(), "{s:?} {c:?}");
                assert_eq!(zf.is_some(), zn.is_some(), "{s:?} {c:?}");
                let (Some(zf), Some(zb), Some(zn)) = (zf, zb, zn) else {
                    continue;
                };
                // A ball removes a subset of what a flat removes, and a bull
                // nose lies between them.
                assert!(zb >= zf - 1e-12, "ball below flat: {s:?} {c:?}");
                assert!(zn >= zf - 1e-12, "bull below flat: {s:?} {c:?}");
                assert!(zn <= zb + 1e-9, "bull above ball: {s:?} {c:?}");
                let d = s.xy_dist(c[0], c[1]);
                if d > r * (1.0 - 1e-6) {
                    continue; // the oracle's samples may all miss a rim cell
                }
                let (Some(ob), Some(on)) = (oracle(&s, c, r, &p_ball), oracle(&s, c, r, &p_bull))
                else {
                    continue;
                };
                // The oracle is a minimum over samples: never below the exact one.
                assert!(
                    zb <= ob + 1e-9,
                    "ball: {zb} above the oracle {ob}: {s:?} {c:?}"
                );
                // The bull nose's minimum is bracketed to BULL_TOL, from above.
                assert!(
                    zn <= on + BULL_TOL + 1e-9,
                    "bull: {zn} above the oracle {on}: {s:?} {c:?}"
                );
                worst_ball = worst_ball.max(ob - zb);
                worst_bull = worst_bull.max((on - zn).abs());
                compared += 1;
            }
        }
        eprintln!(
            "{compared} cells: ball {worst_ball:e}, bull nose {worst_bull:e} from the oracle"
        );
        assert!(compared > 5000, "{compared} cells compared");
        assert!(worst_ball < 1e-9, "ball: {worst_ball:e} from the oracle");
        assert!(
            worst_bull < 1e-6,
            "bull nose: {worst_bull:e} from the oracle"
        );
    }

    #[test]
    fn a_level_ball_cuts_a_round_groove_and_a_plunge_a_spherical_dimple() {
        // A 4 mm ball along y = 0 at depth 1: −1 + 2 − √(4 − ρ²) at ρ off the line.
        let s = Segment {
            a: [0.0, 0.0, -1.0],
            b: [10.0, 0.0, -1.0],
        };
        for rho in [0.0, 0.5, 1.0, 1.5, 1.9, 2.0] {
            let want = -1.0 + 2.0 - (4.0f64 - rho * rho).sqrt();
            assert_eq!(s.ball_over(5.0, rho, 2.0), Some(want));
        }
        assert_eq!(s.ball_over(5.0, 2.01, 2.0), None);
        // Beyond the end: the end sphere.
        let want = -1.0 + 2.0 - (4.0f64 - 1.0).sqrt();
        assert!((s.ball_over(11.0, 0.0, 2.0).unwrap() - want).abs() < 1e-12);
        // A plunge to −2: the dimple of the ball at its lowest.
        let p = Segment {
            a: [0.0, 0.0, 1.0],
            b: [0.0, 0.0, -2.0],
        };
        assert_eq!(p.ball_over(0.0, 1.2, 2.0), Some(-1.6));
        assert_eq!(p.bull_over(0.5, 0.0, 2.0, 1.0), Some(-2.0));
        let e = 1.6 - 1.0;
        assert_eq!(
            p.bull_over(1.6, 0.0, 2.0, 1.0),
            Some(-2.0 + 1.0 - (1.0f64 - e * e).sqrt())
        );
    }

    #[test]
    fn a_descending_ball_is_lowest_on_the_cylinder_between_its_ends() {
        // A 45° descent seen from a point beside the path: the lowest point is
        // inside the segment, not at an end sphere, and matches the capsule's
        // cylinder: distance r from the centre line.
        let s = Segment {
            a: [0.0, 0.0, 0.0],
            b: [10.0, 0.0, -10.0],
        };
        let (r, c) = (2.0, [4.0, 1.0]);
        let z = s.ball_over(c[0], c[1], r).unwrap();
        let centre = |t: f64| [10.0 * t, 0.0, -10.0 * t + r];
        // The point (c, z) is at distance r from the centre line.
        let (ax, az) = (centre(0.0), centre(1.0));
        let u = [
            (az[0] - ax[0]) / 200f64.sqrt(),
            0.0,
            (az[2] - ax[2]) / 200f64.sqrt(),
        ];
        let w = [c[0] - ax[0], c[1] - ax[1], z - ax[2]];
        let along = w[0] * u[0] + w[2] * u[2];
        let perp2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2] - along * along;
        assert!((perp2.sqrt() - r).abs() < 1e-12, "{}", perp2.sqrt());
        assert!(along > 0.0 && along < 200f64.sqrt());
        // Lower than the ball standing over the point's foot (t = 0.4).
        assert!(z < -4.0 + r - (r * r - 1.0f64).sqrt());
    }

    #[test]
    fn tools_are_checked() {
        let bull = Tool::new(ToolShape::Bull, 6.0, Some(1.5)).unwrap();
        assert_eq!((bull.radius(), bull.flat_radius()), (3.0, 1.5));
        assert_eq!(bull.lift(1.5), Some(0.0));
        assert_eq!(bull.lift(3.0), Some(1.5));
        assert_eq!(bull.lift(3.01), None);
        let ball = Tool::new(ToolShape::Ball, 4.0, None).unwrap();
        assert_eq!((ball.corner_radius(), ball.flat_radius()), (2.0, 0.0));
        assert_eq!(ball.lift(2.0), Some(2.0));
        assert_eq!(Tool::new(ToolShape::Ball, 4.0, Some(2.0)).ok(), Some(ball));
        for (shape, d, c) in [
            (ToolShape::Bull, 6.0, None),
            (ToolShape::Bull, 6.0, Some(3.0)),
            (ToolShape::Bull, 6.0, Some(0.0)),
            (ToolShape::Bull, 6.0, Some(f64::NAN)),
            (ToolShape::Flat, 6.0, Some(1.0)),
            (ToolShape::Ball, 6.0, Some(1.0)),
            (ToolShape::Flat, 0.0, None),
            (ToolShape::Ball, f64::INFINITY, None),
        ] {
            assert!(Tool::new(shape, d, c).is_err(), "{shape:?} {d} {c:?}");
        }
        assert_eq!(bull.describe(), "6 mm bull nose end mill, corner 1.5 mm");
    }
}
