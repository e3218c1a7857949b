//! The curves of a DXF drawing once placed in the plane: lines, elliptical
//! arcs (circles, arcs, bulges and ellipses are all the affine image of the
//! unit circle) and NURBS, each flattened into chords within a tolerance.
//!
//! Everything here is in drawing units; [`Budget`] bounds the vertices made.

use super::super::Vec2;

/// A 3-D point or direction, as DXF gives them.
pub(crate) type P3 = [f64; 3];

/// An affine map of space, x ↦ M x + t, stored as the rows of [M | t].
/// Block inserts and object coordinate systems compose as these; a curve is
/// placed in the plane by mapping its defining points and dropping z (the
/// drawing seen from above).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Affine3(pub [[f64; 4]; 3]);

impl Affine3 {
    /// x ↦ x.
    pub(crate) const IDENTITY: Affine3 = Affine3([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ]);

    /// x ↦ x + t.
    pub(crate) fn translate(t: P3) -> Affine3 {
        let mut m = Self::IDENTITY;
        for (row, ti) in m.0.iter_mut().zip(t) {
            row[3] = ti;
        }
        m
    }

    /// Scale by s along the axes.
    pub(crate) fn scale(s: P3) -> Affine3 {
        let mut m = Self::IDENTITY;
        for (i, si) in s.into_iter().enumerate() {
            m.0[i][i] = si;
        }
        m
    }

    /// Turn by `angle` radians about z (counter-clockwise seen from +z).
    pub(crate) fn rotate_z(angle: f64) -> Affine3 {
        let (s, c) = angle.sin_cos();
        Affine3([[c, -s, 0.0, 0.0], [s, c, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
    }

    /// The map whose columns are the axes `x`, `y`, `z` (a change of frame).
    pub(crate) fn axes(x: P3, y: P3, z: P3) -> Affine3 {
        Affine3([
            [x[0], y[0], z[0], 0.0],
            [x[1], y[1], z[1], 0.0],
            [x[2], y[2], z[2], 0.0],
        ])
    }

    /// `self` after `o`: x ↦ self(o(x)).
    pub(crate) fn after(&self, o: &Affine3) -> Affine3 {
        let (a, b) = (&self.0, &o.0);
        let mut m = [[0.0; 4]; 3];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = (0..3).map(|k| a[i][k] * b[k][j]).sum::<f64>()
                    + if j == 3 { a[i][3] } else { 0.0 };
            }
        }
        Affine3(m)
    }

    /// The point `p` mapped and seen from above.
    pub(crate) fn point(&self, p: P3) -> Vec2 {
        let r = |i: usize| {
            let m = &self.0[i];
            m[0] * p[0] + m[1] * p[1] + m[2] * p[2] + m[3]
        };
        Vec2::new(r(0), r(1))
    }

    /// The direction `v` mapped (no translation) and seen from above.
    pub(crate) fn vector(&self, v: P3) -> Vec2 {
        let r = |i: usize| {
            let m = &self.0[i];
            m[0] * v[0] + m[1] * v[1] + m[2] * v[2]
        };
        Vec2::new(r(0), r(1))
    }

    /// Whether every entry is finite.
    pub(crate) fn is_finite(&self) -> bool {
        self.0.iter().flatten().all(|v| v.is_finite())
    }
}

/// A non-uniform rational B-spline in the plane.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Nurbs {
    /// Degree p ≥ 1.
    pub(crate) degree: usize,
    /// Knots U, nondecreasing, n + p + 1 of them.
    pub(crate) knots: Vec<f64>,
    /// Control points, n of them (n > p).
    pub(crate) points: Vec<Vec2>,
    /// Weights, n of them, all > 0 (1 for a non-rational spline).
    pub(crate) weights: Vec<f64>,
}

/// One piece of a path.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Piece {
    /// A straight line from a to b.
    Line(Vec2, Vec2),
    /// c + u cos t + v sin t for t from `t0` to `t1` (either way): a circle
    /// when u ⟂ v with |u| = |v|, else an ellipse, as any affine map leaves it.
    Conic {
        /// centre
        c: Vec2,
        /// the point at t = 0, from the centre
        u: Vec2,
        /// the point at t = π/2, from the centre
        v: Vec2,
        /// start parameter, radians
        t0: f64,
        /// end parameter, radians
        t1: f64,
    },
    /// A NURBS over its whole domain [U_p, U_n].
    Spline(Nurbs),
}

/// A chain of pieces, each starting where the one before ends; `closed` when
/// the last one ends where the first starts.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Path {
    /// The pieces, in order.
    pub(crate) pieces: Vec<Piece>,
    /// Whether the path is a closed contour.
    pub(crate) closed: bool,
}

/// How many more vertices may be made; `Err(())` once it runs out.
pub(crate) struct Budget(pub usize);

impl Budget {
    fn take(&mut self, n: usize) -> Result<(), ()> {
        self.0 = self.0.checked_sub(n).ok_or(())?;
        Ok(())
    }
}

/// Deepest bisection of one knot span of a spline: 2²⁰ chords, far past any
/// budget, so only a curve that never meets the test (a NaN) reaches it.
const MAX_DEPTH: u32 = 20;

impl Piece {
    /// Where the piece starts.
    pub(crate) fn start(&self) -> Vec2 {
        match self {
            Piece::Line(a, _) => *a,
            Piece::Conic { c, u, v, t0, .. } => conic_at(*c, *u, *v, *t0),
            Piece::Spline(s) => s.at(s.knots[s.degree]),
        }
    }

    /// The chord vertices after the start, the end included, appended to
    /// `out`: every point of the curve lies within `tol` of its chord (for a
    /// spline: checked at three points inside each chord).
    pub(crate) fn flatten_into(
        &self,
        tol: f64,
        out: &mut Vec<Vec2>,
        budget: &mut Budget,
    ) -> Result<(), ()> {
        match self {
            Piece::Line(_, b) => {
                budget.take(1)?;
                out.push(*b);
            }
            Piece::Conic { c, u, v, t0, t1 } => {
                let n = conic_chords(*u, *v, t1 - t0, tol);
                if n == 0 {
                    return Err(());
                }
                budget.take(n)?;
                out.extend(
                    (1..=n).map(|k| conic_at(*c, *u, *v, t0 + (t1 - t0) * k as f64 / n as f64)),
                );
            }
            Piece::Spline(s) => s.flatten_into(tol, out, budget)?,
        }
        Ok(())
    }
}

/// c + u cos t + v sin t.
pub(crate) fn conic_at(c: Vec2, u: Vec2, v: Vec2, t: f64) -> Vec2 {
    let (s, co) = t.sin_cos();
    c + u * co + v * s
}

/// Chords for a sweep of `sweep` radians of c + u cos t + v sin t within
/// `tol`. The curve is the unit circle under the linear map [u v], whose
/// largest stretch is σ, the larger singular value; a chord over Δt of the
/// circle is within 1 − cos(Δt/2) of it, so of the image within
/// σ (1 − cos(Δt/2)) ≤ tol: Δt = 2 acos(1 − tol/σ), at most a quarter turn.
fn conic_chords(u: Vec2, v: Vec2, sweep: f64, tol: f64) -> usize {
    // σ² is the larger eigenvalue of [u v]ᵀ[u v].
    let (a, b, d) = (u.norm2(), u.dot(v), v.norm2());
    let half = (a + d) / 2.0;
    let sigma = (half + (((a - d) / 2.0).powi(2) + b * b).sqrt()).sqrt();
    let step = if tol >= sigma {
        std::f64::consts::FRAC_PI_2
    } else {
        (2.0 * (1.0 - tol / sigma).acos()).min(std::f64::consts::FRAC_PI_2)
    };
    let n = (sweep.abs() / step).ceil();
    if n.is_finite() && n < usize::MAX as f64 {
        (n as usize).max(1)
    } else {
        0
    }
}

impl Nurbs {
    /// The point at parameter t in [U_p, U_n], by de Boor's algorithm on the
    /// homogeneous points (w x, w y, w) (Piegl & Tiller, The NURBS Book,
    /// A2.1 and A4.1).
    pub(crate) fn at(&self, t: f64) -> Vec2 {
        let p = self.degree;
        let n = self.points.len();
        // The span k with U_k ≤ t < U_{k+1}, p ≤ k < n (the last non-empty one at t = U_n).
        let mut k = p;
        while k + 1 < n && self.knots[k + 1] <= t {
            k += 1;
        }
        let u = &self.knots;
        let mut d: Vec<[f64; 3]> = (0..=p)
            .map(|j| {
                let (q, w) = (self.points[j + k - p], self.weights[j + k - p]);
                [q.x * w, q.y * w, w]
            })
            .collect();
        for r in 1..=p {
            for j in (r..=p).rev() {
                let i = j + k - p;
                let den = u[i + p + 1 - r] - u[i];
                let a = if den > 0.0 { (t - u[i]) / den } else { 0.0 };
                let prev = d[j - 1];
                for (v, q) in d[j].iter_mut().zip(prev) {
                    *v = (1.0 - a) * q + a * *v;
                }
            }
        }
        let [x, y, w] = d[p];
        Vec2::new(x / w, y / w)
    }

    /// Chords within `tol`: each non-empty knot span is cut into 2p pieces
    /// and each piece halved until the curve at its quarter points lies within
    /// `tol` of its chord.
    fn flatten_into(&self, tol: f64, out: &mut Vec<Vec2>, budget: &mut Budget) -> Result<(), ()> {
        let p = self.degree;
        for k in p..self.points.len() {
            let (a, b) = (self.knots[k], self.knots[k + 1]);
            if b <= a {
                continue;
            }
            let m = 2 * p;
            let mut prev = self.at(a);
            for i in 1..=m {
                let t1 = a + (b - a) * i as f64 / m as f64;
                let t0 = a + (b - a) * (i - 1) as f64 / m as f64;
                let end = self.at(t1);
                self.bisect(t0, t1, prev, end, tol, 0, out, budget)?;
                prev = end;
            }
        }
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    fn bisect(
        &self,
        t0: f64,
        t1: f64,
        p0: Vec2,
        p1: Vec2,
        tol: f64,
        depth: u32,
        out: &mut Vec<Vec2>,
        budget: &mut Budget,
    ) -> Result<(), ()> {
        let flat = (1..4).all(|q| {
            let x = self.at(t0 + (t1 - t0) * q as f64 / 4.0);
            seg_dist(x, p0, p1) <= tol
        });
        if flat || depth >= MAX_DEPTH {
            budget.take(1)?;
            out.push(p1);
            return Ok(());
        }
        let tm = (t0 + t1) / 2.0;
        let pm = self.at(tm);
        self.bisect(t0, tm, p0, pm, tol, depth + 1, out, budget)?;
        self.bisect(tm, t1, pm, p1, tol, depth + 1, out, budget)
    }
}

/// Distance from x to the segment a–b.
fn seg_dist(x: Vec2, a: Vec2, b: Vec2) -> f64 {
    let d = b - a;
    let l2 = d.norm2();
    let t = if l2 > 0.0 {
        ((x - a).dot(d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    x.dist(a + d * t)
}

impl Path {
    /// The path as a polyline within `tol`: its start, then every chord's end.
    pub(crate) fn flatten(&self, tol: f64, budget: &mut Budget) -> Result<Vec<Vec2>, ()> {
        let Some(first) = self.pieces.first() else {
            return Ok(Vec::new());
        };
        budget.take(1)?;
        let mut pts = vec![first.start()];
        for piece in &self.pieces {
            piece.flatten_into(tol, &mut pts, budget)?;
        }
        Ok(pts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::polygon_area;
    use std::f64::consts::PI;

    #[test]
    fn an_ellipse_flattens_within_the_tolerance() {
        // a = 20, b = 5 turned: u, v conjugate but not the axes (a shear).
        let (u, v) = (Vec2::new(20.0, 0.0), Vec2::new(3.0, 5.0));
        let piece = Piece::Conic {
            c: Vec2::ZERO,
            u,
            v,
            t0: 0.0,
            t1: 2.0 * PI,
        };
        for tol in [0.1, 0.01, 0.001] {
            let mut pts = vec![piece.start()];
            piece
                .flatten_into(tol, &mut pts, &mut Budget(1_000_000))
                .unwrap();
            // The largest distance of the curve to its chord, sampled finely
            // (the chords are uniform in t).
            let mut worst: f64 = 0.0;
            let dense = 200_000;
            let mut j = 0;
            for i in 0..dense {
                let t = 2.0 * PI * i as f64 / dense as f64;
                let x = conic_at(Vec2::ZERO, u, v, t);
                // chord index by parameter: chords are uniform in t.
                let n = pts.len() - 1;
                while j + 1 < n && (j + 1) as f64 * 2.0 * PI / n as f64 <= t {
                    j += 1;
                }
                worst = worst.max(seg_dist(x, pts[j], pts[j + 1]));
            }
            assert!(worst <= tol * (1.0 + 1e-9), "tol {tol}: {worst}");
            assert!(worst >= tol * 0.3, "tol {tol}: too fine, {worst}");
            let exact = PI * u.cross(v).abs();
            assert!((polygon_area(&pts[..pts.len() - 1]) - exact).abs() < 2.0 * PI * 20.0 * tol);
        }
    }

    #[test]
    fn a_clamped_spline_matches_bernstein_and_a_rational_one_a_circle_arc() {
        // Degree 3, one span: a cubic Bézier.
        let pts = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 3.0),
            Vec2::new(4.0, 3.0),
            Vec2::new(5.0, 0.0),
        ];
        let s = Nurbs {
            degree: 3,
            knots: vec![0.0, 0.0, 0.0, 0.0, 2.0, 2.0, 2.0, 2.0],
            points: pts.to_vec(),
            weights: vec![1.0; 4],
        };
        for i in 0..=10 {
            let t = i as f64 / 10.0;
            let b = pts[0] * (1.0 - t).powi(3)
                + pts[1] * (3.0 * t * (1.0 - t).powi(2))
                + pts[2] * (3.0 * t * t * (1.0 - t))
                + pts[3] * t.powi(3);
            assert!(s.at(2.0 * t).dist(b) < 1e-12);
        }
        // A quarter circle as a rational quadratic: weights 1, √2/2, 1.
        let q = Nurbs {
            degree: 2,
            knots: vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            points: vec![
                Vec2::new(1.0, 0.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(0.0, 1.0),
            ],
            weights: vec![1.0, 0.5f64.sqrt(), 1.0],
        };
        for i in 0..=20 {
            assert!((q.at(i as f64 / 20.0).norm() - 1.0).abs() < 1e-14);
        }
        let mut out = vec![q.at(0.0)];
        q.flatten_into(1e-4, &mut out, &mut Budget(100_000))
            .unwrap();
        for w in out.windows(2) {
            let mid = w[0].lerp(w[1], 0.5);
            assert!(1.0 - mid.norm() <= 1e-4 * (1.0 + 1e-9));
        }
    }

    #[test]
    fn affine_maps_compose_in_order() {
        let m = Affine3::translate([10.0, 0.0, 0.0]).after(&Affine3::rotate_z(PI / 2.0));
        let p = m.point([1.0, 0.0, 0.0]);
        assert!(p.dist(Vec2::new(10.0, 1.0)) < 1e-15);
        let s = Affine3::scale([2.0, 3.0, 1.0]).after(&m);
        assert!(s.point([1.0, 0.0, 0.0]).dist(Vec2::new(20.0, 3.0)) < 1e-14);
        assert!(s.vector([1.0, 0.0, 0.0]).dist(Vec2::new(0.0, 3.0)) < 1e-15);
    }

    #[test]
    fn the_budget_stops_a_fine_flattening() {
        let piece = Piece::Conic {
            c: Vec2::ZERO,
            u: Vec2::new(1e6, 0.0),
            v: Vec2::new(0.0, 1e6),
            t0: 0.0,
            t1: 2.0 * PI,
        };
        let mut pts = Vec::new();
        assert!(piece
            .flatten_into(1e-3, &mut pts, &mut Budget(1000))
            .is_err());
        assert!(pts.is_empty());
    }
}
