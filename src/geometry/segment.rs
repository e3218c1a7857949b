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
    (0.408_282_678_752_175, 0.181_341_891_689_181),
    (0.591_717_321_247_825, 0.181_341_891_689_181),
    (0.762_766_204_958_164_5, 0.156_853_322_938_943_64),
    (0.898_333_238_706_813_4, 0.111_190_517_226_687_24),
    (0.980_144_928_248_768_2, 0.050_614_268_145_188_13),
];

impl Segment {
    /// A quadratic Bézier raised exactly to a cubic.
    pub(crate) fn quad(p0: Vec2, q: Vec2, p2: Vec2) -> Segment {
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
    pub(crate) fn end(&self) -> Vec2 {
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
    pub(crate) fn tangent(&self, t: f64) -> Vec2 {
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

    /// Arc length from t = 0 to t = `t`: adaptive 8-point Gauss–Legendre on [0, t],
    /// halving an interval until its estimate agrees with the sum of its halves
    /// within 1e-13 of the control polygon's length (exact for lines). Measured in
    /// the tests against a 2·10⁵-chord flattening: relative error ≤ 1e-10 on glyph
    /// serifs and on an S-bend with a near-cusp (a fixed 4×8-point rule gave 7e-8).
    pub fn length_to(&self, t: f64) -> f64 {
        match *self {
            Segment::Line { a, b } => a.dist(b) * t,
            Segment::Cubic { p0, p1, p2, p3 } => {
                let poly = p0.dist(p1) + p1.dist(p2) + p2.dist(p3);
                if poly == 0.0 || t <= 0.0 {
                    return 0.0;
                }
                let tol = 1e-13 * poly;
                let whole = self.gl8(0.0, t);
                self.length_adaptive(0.0, t, whole, tol, 0)
            }
        }
    }

    /// 8-point Gauss–Legendre estimate of the arc length over [t0, t1].
    fn gl8(&self, t0: f64, t1: f64) -> f64 {
        let h = t1 - t0;
        GL8.iter()
            .map(|&(x, w)| w * h * self.deriv(t0 + h * x).norm())
            .sum()
    }

    /// Recursive halving for `length_to`; depth ≤ 24 bounds the work on a true cusp.
    fn length_adaptive(&self, t0: f64, t1: f64, whole: f64, tol: f64, depth: u32) -> f64 {
        let tm = 0.5 * (t0 + t1);
        let left = self.gl8(t0, tm);
        let right = self.gl8(tm, t1);
        if depth >= 24 || (left + right - whole).abs() <= tol {
            return left + right;
        }
        self.length_adaptive(t0, tm, left, 0.5 * tol, depth + 1)
            + self.length_adaptive(tm, t1, right, 0.5 * tol, depth + 1)
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
    pub(crate) fn reversed(&self) -> Segment {
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
    pub(crate) fn map(&self, f: impl Fn(Vec2) -> Vec2) -> Segment {
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

    /// Tight bounding box of the curve itself (not of its control points): the end
    /// points and the interior extrema, where a coordinate of the derivative vanishes.
    pub(crate) fn tight_bbox(&self) -> (Vec2, Vec2) {
        let (a, b) = (self.start(), self.end());
        let mut lo = Vec2::new(a.x.min(b.x), a.y.min(b.y));
        let mut hi = Vec2::new(a.x.max(b.x), a.y.max(b.y));
        if let Segment::Cubic { p0, p1, p2, p3 } = *self {
            // B'(t)/3 = d0 (1−t)² + 2 d1 (1−t) t + d2 t² = A t² + B t + C per coordinate.
            let (d0, d1, d2) = (p1 - p0, p2 - p1, p3 - p2);
            let qa = d0 - d1 * 2.0 + d2;
            let qb = (d1 - d0) * 2.0;
            for (qa, qb, qc) in [(qa.x, qb.x, d0.x), (qa.y, qb.y, d0.y)] {
                for t in quadratic_roots(qa, qb, qc) {
                    if t > 0.0 && t < 1.0 {
                        let p = self.eval(t);
                        lo = Vec2::new(lo.x.min(p.x), lo.y.min(p.y));
                        hi = Vec2::new(hi.x.max(p.x), hi.y.max(p.y));
                    }
                }
            }
        }
        (lo, hi)
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

/// Real roots of a t² + b t + c = 0 (a linear or constant equation when a is
/// negligible), in no particular order.
fn quadratic_roots(a: f64, b: f64, c: f64) -> Vec<f64> {
    let scale = a.abs().max(b.abs()).max(c.abs());
    if scale == 0.0 {
        return Vec::new();
    }
    if a.abs() <= 1e-12 * scale {
        return if b != 0.0 { vec![-c / b] } else { Vec::new() };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return Vec::new();
    }
    // The numerically stable pair of formulas.
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    if q == 0.0 {
        return vec![0.0];
    }
    vec![q / a, c / q]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    /// Cubics of various kinds: a glyph serif (paper letter I), an S-bend, a tight
    /// loop-like curve, a cusp-free arch and one with a control point on its start.
    pub(crate) fn test_cubics() -> Vec<Segment> {
        vec![
            Segment::Cubic {
                p0: v(18.0, 19.0),
                p1: v(103.0, 21.0),
                p2: v(115.0, 38.0),
                p3: v(115.0, 109.0),
            },
            Segment::Cubic {
                p0: v(0.0, 0.0),
                p1: v(100.0, 200.0),
                p2: v(-50.0, 300.0),
                p3: v(200.0, 100.0),
            },
            Segment::Cubic {
                p0: v(0.0, 0.0),
                p1: v(300.0, 100.0),
                p2: v(-200.0, 100.0),
                p3: v(100.0, 0.0),
            },
            Segment::Cubic {
                p0: v(-1.0, 0.0),
                p1: v(-1.0, 0.55),
                p2: v(1.0, 0.55),
                p3: v(1.0, 0.0),
            },
            Segment::Cubic {
                p0: v(5.0, 5.0),
                p1: v(5.0, 5.0),
                p2: v(40.0, -7.0),
                p3: v(60.0, 30.0),
            },
            // A true cusp at t = 1/2: B'(t) = 3((1−2t)², 1−2t).
            Segment::Cubic {
                p0: v(0.0, 0.0),
                p1: v(10.0, 10.0),
                p2: v(0.0, 10.0),
                p3: v(10.0, 0.0),
            },
        ]
    }

    /// Fine polyline of the segment: `n` equal parameter steps.
    fn fine(seg: &Segment, n: usize) -> Vec<Vec2> {
        (0..=n).map(|k| seg.eval(k as f64 / n as f64)).collect()
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-5;
        let mut worst1: f64 = 0.0;
        let mut worst2: f64 = 0.0;
        for seg in test_cubics().iter().chain(&[Segment::Line {
            a: v(1.0, 2.0),
            b: v(-3.0, 7.0),
        }]) {
            let scale = seg.deriv(0.5).norm().max(1.0);
            for k in 1..20 {
                let t = k as f64 / 20.0;
                let fd1 = (seg.eval(t + h) - seg.eval(t - h)) / (2.0 * h);
                let fd2 = (seg.deriv(t + h) - seg.deriv(t - h)) / (2.0 * h);
                worst1 = worst1.max((fd1 - seg.deriv(t)).norm() / scale);
                worst2 = worst2.max((fd2 - seg.deriv2(t)).norm() / scale);
            }
        }
        // Central differences with h = 1e-5 are accurate to about h² ≈ 1e-10 relative.
        assert!(worst1 < 1e-7, "deriv vs finite difference: {worst1:e}");
        assert!(worst2 < 1e-7, "deriv2 vs finite difference: {worst2:e}");
    }

    #[test]
    fn eval_hits_end_points() {
        for seg in test_cubics() {
            assert_eq!(seg.eval(0.0), seg.start());
            assert_eq!(seg.eval(1.0), seg.end());
        }
    }

    #[test]
    fn length_matches_fine_flattening() {
        for seg in test_cubics() {
            let pts = fine(&seg, 200_000);
            let poly: f64 = pts.windows(2).map(|w| w[0].dist(w[1])).sum();
            let rel = (seg.length() - poly).abs() / poly;
            // A chord polyline with 2e5 pieces underestimates by ~1e-10 relative.
            assert!(
                rel < 1e-10,
                "{seg:?}: length {} vs {poly}: rel {rel:e}",
                seg.length()
            );
        }
        let line = Segment::Line {
            a: v(0.0, 0.0),
            b: v(3.0, 4.0),
        };
        assert_eq!(line.length(), 5.0);
    }

    #[test]
    fn t_at_length_round_trip() {
        let mut worst: f64 = 0.0;
        for seg in test_cubics() {
            let total = seg.length();
            for k in 0..=50 {
                let s = total * k as f64 / 50.0;
                let t = seg.t_at_length(s);
                worst = worst.max((seg.length_to(t) - s).abs() / total);
            }
            assert_eq!(seg.t_at_length(-1.0), 0.0);
            assert!((seg.t_at_length(total * 2.0) - 1.0).abs() < 1e-12);
        }
        assert!(worst < 1e-11, "round trip relative error {worst:e}");
    }

    #[test]
    fn cubic_area_term_matches_fine_flattening() {
        for seg in test_cubics() {
            let pts = fine(&seg, 100_000);
            let poly: f64 = pts.windows(2).map(|w| 0.5 * w[0].cross(w[1])).sum();
            let scale = seg.length().powi(2);
            let err = (seg.area_term() - poly).abs() / scale;
            assert!(
                err < 1e-9,
                "{seg:?}: area {} vs {poly}: rel {err:e}",
                seg.area_term()
            );
            // Reversal negates the term exactly (up to rounding).
            assert!((seg.area_term() + seg.reversed().area_term()).abs() < 1e-9 * scale);
        }
    }

    #[test]
    fn flatten_stays_within_tolerance() {
        for tol in [1.0, 0.1, 0.01, 0.001] {
            for seg in test_cubics() {
                let mut pts = vec![seg.start()];
                seg.flatten_into(tol, &mut pts);
                assert_eq!(*pts.last().unwrap(), seg.end());
                // Each chord covers an equal parameter step; measure the curve's
                // distance to its chord at many parameters inside the step.
                let n = pts.len() - 1;
                let mut worst: f64 = 0.0;
                for k in 0..n {
                    let (a, b) = (pts[k], pts[k + 1]);
                    for j in 1..64 {
                        let t = (k as f64 + j as f64 / 64.0) / n as f64;
                        let p = seg.eval(t);
                        let ab = b - a;
                        let u = ((p - a).dot(ab) / ab.norm2().max(1e-300)).clamp(0.0, 1.0);
                        worst = worst.max(p.dist(a + ab * u));
                    }
                }
                assert!(worst <= tol, "tol {tol}: deviation {worst} for {seg:?}");
                // And the bound is not wildly pessimistic: within 20× of tol on the
                // curvy test cubics (measured ratio is reported on failure).
                if seg.length() > 50.0 && tol <= 0.1 {
                    assert!(worst > tol / 20.0, "tol {tol}: deviation only {worst}");
                }
            }
        }
    }

    #[test]
    fn tight_bbox_matches_dense_sampling() {
        for seg in test_cubics() {
            let (lo, hi) = seg.tight_bbox();
            let pts = fine(&seg, 100_000);
            let mut slo = pts[0];
            let mut shi = pts[0];
            for p in &pts {
                slo = Vec2::new(slo.x.min(p.x), slo.y.min(p.y));
                shi = Vec2::new(shi.x.max(p.x), shi.y.max(p.y));
            }
            let scale = seg.length();
            // Dense sampling misses an extremum by at most O(h²) ≈ 1e-10 × size.
            assert!(lo.dist(slo) < 1e-8 * scale, "{lo:?} vs {slo:?}");
            assert!(hi.dist(shi) < 1e-8 * scale, "{hi:?} vs {shi:?}");
        }
    }

    #[test]
    fn quad_is_exactly_the_quadratic() {
        let (p0, q, p2) = (v(0.0, 0.0), v(50.0, 120.0), v(100.0, -20.0));
        let c = Segment::quad(p0, q, p2);
        let mut worst: f64 = 0.0;
        for k in 0..=100 {
            let t = k as f64 / 100.0;
            let mt = 1.0 - t;
            let exact = p0 * (mt * mt) + q * (2.0 * mt * t) + p2 * (t * t);
            worst = worst.max(c.eval(t).dist(exact));
        }
        assert!(worst < 1e-12, "quad deviation {worst:e}");
    }

    #[test]
    fn reversed_and_mapped() {
        for seg in test_cubics() {
            let r = seg.reversed();
            for k in 0..=10 {
                let t = k as f64 / 10.0;
                assert!(seg.eval(t).dist(r.eval(1.0 - t)) < 1e-12);
            }
            assert!((seg.length() - r.length()).abs() < 1e-9 * seg.length());
            let m = seg.map(|p| p * 2.0 + v(1.0, 1.0));
            assert!((m.length() - 2.0 * seg.length()).abs() < 1e-9 * seg.length());
        }
    }

    #[test]
    fn tangent_of_degenerate_control_point() {
        // p1 == p0: the derivative vanishes at t = 0, the tangent points to p2.
        let seg = test_cubics()[4];
        let t = seg.tangent(0.0);
        let want = (v(40.0, -7.0) - v(5.0, 5.0)).normalized();
        assert!(t.dist(want) < 1e-5, "{t:?} vs {want:?}");
        assert!((t.norm() - 1.0).abs() < 1e-12);
    }
}
