//! Straight lines and cubic Béziers: the pieces of every contour.

use super::Vec2;

/// One piece of a closed contour. A quadratic (TrueType) curve is raised to the
/// cubic with control points `p0 + 2/3 (q - p0)` and `p2 + 2/3 (q - p2)`, which is
/// the same curve exactly, so only these two kinds exist.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    /// The straight line from `a` to `b`.
    Line {
        /// start
        a: Vec2,
        /// end
        b: Vec2,
    },
    /// The cubic Bézier with control points `p0..p3`.
    Cubic {
        /// start
        p0: Vec2,
        /// first control point
        p1: Vec2,
        /// second control point
        p2: Vec2,
        /// end
        p3: Vec2,
    },
}

/// Gauss–Legendre nodes and weights on [0, 1] (8 points), for arc length.
const GL8: [(f64, f64); 8] = [
    (0.019_855_071_751_231_856, 0.050_614_268_145_188_13),
    (0.101_666_761_293_186_63, 0.111_190_517_226_687_24),
    (0.237_233_795_041_835_5, 0.156_853_322_938_943_64),
    (0.408_282_678_752_175_1, 0.181_341_891_689_180_99),
    (0.591_717_321_247_824_9, 0.181_341_891_689_180_99),
    (0.762_766_204_958_164_5, 0.156_853_322_938_943_64),
    (0.898_333_238_706_813_4, 0.111_190_517_226_687_24),
    (0.980_144_928_248_768_2, 0.050_614_268_145_188_13),
];

impl Segment {
    /// A quadratic Bézier raised exactly to a cubic.
    pub fn quad(p0: Vec2, q: Vec2, p2: Vec2) -> Segment {
        Segment::Cubic {
            p0,
            p1: p0 + (q - p0) * (2.0 / 3.0),
            p2: p2 + (q - p2) * (2.0 / 3.0),
            p3: p2,
        }
    }

    /// Start point.
    pub fn start(&self) -> Vec2 {
        match *self {
            Segment::Line { a, .. } => a,
            Segment::Cubic { p0, .. } => p0,
        }
    }

    /// End point.
    pub fn end(&self) -> Vec2 {
        match *self {
            Segment::Line { b, .. } => b,
            Segment::Cubic { p3, .. } => p3,
        }
    }

    /// Point at parameter `t` in [0, 1].
    pub fn eval(&self, t: f64) -> Vec2 {
        match *self {
            Segment::Line { a, b } => a.lerp(b, t),
            Segment::Cubic { p0, p1, p2, p3 } => {
                let mt = 1.0 - t;
                p0 * (mt * mt * mt)
                    + p1 * (3.0 * mt * mt * t)
                    + p2 * (3.0 * mt * t * t)
                    + p3 * (t * t * t)
            }
        }
    }

    /// First derivative d/dt at `t`.
    pub fn deriv(&self, t: f64) -> Vec2 {
        match *self {
            Segment::Line { a, b } => b - a,
            Segment::Cubic { p0, p1, p2, p3 } => {
                let mt = 1.0 - t;
                (p1 - p0) * (3.0 * mt * mt) + (p2 - p1) * (6.0 * mt * t) + (p3 - p2) * (3.0 * t * t)
            }
        }
    }

    /// Second derivative d²/dt² at `t`.
    pub fn deriv2(&self, t: f64) -> Vec2 {
        match *self {
            Segment::Line { .. } => Vec2::ZERO,
            Segment::Cubic { p0, p1, p2, p3 } => {
                (p2 - p1 * 2.0 + p0) * (6.0 * (1.0 - t)) + (p3 - p2 * 2.0 + p1) * (6.0 * t)
            }
        }
    }

    /// Unit tangent at `t`. Where the derivative vanishes (a control point on an end
    /// point) the direction of the nearest non-degenerate difference is used.
    pub fn tangent(&self, t: f64) -> Vec2 {
        let d = self.deriv(t);
        if d.norm2() > 1e-24 {
            return d.normalized();
        }
        match *self {
            Segment::Line { a, b } => (b - a).normalized(),
            Segment::Cubic { p0, p1, p2, p3 } => {
                let d = if t < 0.5 {
                    if p1.dist(p0) > 1e-12 {
                        p2 - p0
                    } else {
                        p2 - p0 + (p3 - p0) * 1e-6
                    }
                } else if p3.dist(p2) > 1e-12 {
                    p3 - p1
                } else {
                    p3 - p1 + (p3 - p0) * 1e-6
                };
                d.normalized()
            }
        }
    }

    /// Arc length from t = 0 to t = `t`, by 8-point Gauss–Legendre on [0, t]
    /// (exact for lines; for the glyph cubics the relative error is below 1e-9,
    /// checked in the tests against fine flattening).
    pub fn length_to(&self, t: f64) -> f64 {
        match *self {
            Segment::Line { a, b } => a.dist(b) * t,
            Segment::Cubic { .. } => {
                // Split in 4 pieces for accuracy on tight cubics.
                let pieces = 4;
                let mut s = 0.0;
                for k in 0..pieces {
                    let t0 = t * k as f64 / pieces as f64;
                    let t1 = t * (k + 1) as f64 / pieces as f64;
                    let h = t1 - t0;
                    for (x, w) in GL8 {
                        s += w * h * self.deriv(t0 + h * x).norm();
                    }
                }
                s
            }
        }
    }

    /// Total arc length.
    pub fn length(&self) -> f64 {
        self.length_to(1.0)
    }

    /// Parameter `t` at which the arc length from the start is `s` (Newton on the
    /// length function, safeguarded by bisection; `s` clamped to [0, length]).
    pub fn t_at_length(&self, s: f64) -> f64 {
        let total = self.length();
        if total <= 0.0 {
            return 0.0;
        }
        let s = s.clamp(0.0, total);
        match *self {
            Segment::Line { .. } => s / total,
            Segment::Cubic { .. } => {
                let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
                let mut t = s / total;
                for _ in 0..60 {
                    let f = self.length_to(t) - s;
                    if f.abs() < 1e-12 * total.max(1.0) {
                        break;
                    }
                    if f > 0.0 {
                        hi = t;
                    } else {
                        lo = t;
                    }
                    let d = self.deriv(t).norm();
                    let mut tn = if d > 0.0 { t - f / d } else { 0.5 * (lo + hi) };
                    if !(tn > lo && tn < hi) {
                        tn = 0.5 * (lo + hi);
                    }
                    t = tn;
                }
                t
            }
        }
    }

    /// This segment traversed backwards.
    pub fn reversed(&self) -> Segment {
        match *self {
            Segment::Line { a, b } => Segment::Line { a: b, b: a },
            Segment::Cubic { p0, p1, p2, p3 } => Segment::Cubic {
                p0: p3,
                p1: p2,
                p2: p1,
                p3: p0,
            },
        }
    }

    /// The segment with every point mapped through `f` (an affine map keeps it exact).
    pub fn map(&self, f: impl Fn(Vec2) -> Vec2) -> Segment {
        match *self {
            Segment::Line { a, b } => Segment::Line { a: f(a), b: f(b) },
            Segment::Cubic { p0, p1, p2, p3 } => Segment::Cubic {
                p0: f(p0),
                p1: f(p1),
                p2: f(p2),
                p3: f(p3),
            },
        }
    }

    /// Appends points approximating the segment within `tol` (chord deviation),
    /// excluding the start point and including the end point.
    ///
    /// For a cubic the number of pieces comes from the bound on the second
    /// derivative: a chord over a parameter step h deviates from the curve by at most
    /// h²·max|B''|/8, and max|B''| ≤ 6·max(|p0−2p1+p2|, |p1−2p2+p3|).
    pub fn flatten_into(&self, tol: f64, out: &mut Vec<Vec2>) {
        match *self {
            Segment::Line { b, .. } => out.push(b),
            Segment::Cubic { p0, p1, p2, p3 } => {
                let dd = (p0 - p1 * 2.0 + p2).norm().max((p1 - p2 * 2.0 + p3).norm()) * 6.0;
                let n = ((dd / (8.0 * tol.max(1e-12))).sqrt().ceil() as usize).clamp(1, 100_000);
                for k in 1..=n {
                    out.push(self.eval(k as f64 / n as f64));
                }
            }
        }
    }

    /// Signed area contribution ∮ x dy − y dx / 2 over this segment (exact).
    pub fn area_term(&self) -> f64 {
        match *self {
            Segment::Line { a, b } => 0.5 * a.cross(b),
            Segment::Cubic { p0, p1, p2, p3 } => {
                // Exact integral of (x y' − y x')/2 for a cubic Bézier.
                (p0.cross(p1) * 6.0
                    + p0.cross(p2) * 3.0
                    + p0.cross(p3)
                    + p1.cross(p2) * 3.0
                    + p1.cross(p3) * 3.0
                    + p2.cross(p3) * 6.0)
                    / 20.0
            }
        }
    }
}
