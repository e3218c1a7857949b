//! Depth profiles φ(s) (the paper's S2 = {(x, y) ∈ Γ(s), z = φ(s)},
//! Section 7): the resolved `[profile]` of a job.
//!
//! Heights are relative to the stock top: φ(s_top) = 0 (the top of the sign) and
//! φ(s_bottom) = −depth. φ increases strictly with s on [s_bottom, s_top], so it
//! can be inverted: at every z-level the generating boundary is Γ(s(z)).
//! Below `job` and `levels`, which both use it.

/// A depth profile.
#[derive(Clone, Debug, PartialEq)]
pub enum DepthProfile {
    /// Straight taper: z goes linearly from −depth at s = `s_bottom` to 0 at s = 1.
    Linear {
        /// s at the bottom.
        s_bottom: f64,
        /// Total height, mm.
        depth: f64,
    },
    /// The paper's outside wall (Section 7): a logistic step between s2 (bottom)
    /// and s1 (top), flat above s1 and below s2.
    Sigmoid {
        /// s at the top edge (the paper: 0.99).
        s1: f64,
        /// s at the foot of the wall (the paper: 0.75).
        s2: f64,
        /// Steepness k of the logistic 1/(1 + e^(−k (t − ½))) in t = (s − s2)/(s1 − s2).
        steepness: f64,
        /// Total height, mm.
        depth: f64,
    },
    /// The paper's wall of Fig. 3.3 (Section 3.2: height sⁿ, n = 500 near
    /// s = 1): w(s) = (s/s1)ⁿ rescaled to run from 0 at the foot s2 to 1 at
    /// the top edge s1, z = −depth·(1 − w). Most of the height falls just below
    /// the top edge, where Γ(s) still follows the letters, and the wall flares
    /// out along the field to the foot; flat above s1 and below s2.
    Power {
        /// s at the top edge.
        s1: f64,
        /// s at the foot of the wall.
        s2: f64,
        /// The exponent n.
        exponent: f64,
        /// Total height, mm.
        depth: f64,
    },
    /// Monotone cubic (Fritsch–Carlson) through (s, z) points.
    Spline {
        /// s values, increasing.
        s: Vec<f64>,
        /// z values (mm, relative to the stock top), increasing.
        z: Vec<f64>,
        /// Tangents dz/ds at the points, limited so the interpolant is monotone.
        m: Vec<f64>,
    },
    /// Piecewise linear through (s, z) points.
    Table {
        /// s values, increasing.
        s: Vec<f64>,
        /// z values (mm, relative to the stock top), increasing.
        z: Vec<f64>,
    },
}

/// Why a profile is not usable.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub(crate) enum ProfileError {
    /// Fewer than two (s, z) points.
    #[error("needs at least two (s, z) points, got {got}")]
    TooFewPoints {
        /// How many there are.
        got: usize,
    },
    /// A point whose s is outside (0, 1] or whose s or z is not finite.
    #[error("every s must be in (0, 1] and every z finite, got ({s}, {z})")]
    PointOutOfRange {
        /// The point's s.
        s: f64,
        /// The point's z, mm.
        z: f64,
    },
    /// Two neighbouring points whose s does not increase.
    #[error("s must increase from point to point, but ({}, {}) is followed by ({}, {})", before[0], before[1], after[0], after[1])]
    SNotIncreasing {
        /// The first point, (s, z).
        before: [f64; 2],
        /// The point after it.
        after: [f64; 2],
    },
    /// Two neighbouring points whose z does not increase (φ not monotone).
    #[error("φ must be strictly monotone: z must increase with s, but ({}, {}) is followed by ({}, {})", before[0], before[1], after[0], after[1])]
    ZNotIncreasing {
        /// The first point, (s, z).
        before: [f64; 2],
        /// The point after it.
        after: [f64; 2],
    },
    /// The last point, the part's top, is not at z = 0.
    #[error("the last point is the top of the part and must have z = 0 (heights are relative to stock.top), got ({s}, {z})")]
    TopNotZero {
        /// The last point's s.
        s: f64,
        /// The last point's z, mm.
        z: f64,
    },
}

fn logistic(x: f64) -> f64 {
    1.0 / (1.0 + (-x).exp())
}

/// Fritsch–Carlson tangents: secant averages, zero at a flat step, then scaled
/// where α² + β² > 9 so each cubic piece stays monotone.
fn fritsch_carlson(s: &[f64], z: &[f64]) -> Vec<f64> {
    let n = s.len();
    let d: Vec<f64> = (0..n - 1)
        .map(|i| (z[i + 1] - z[i]) / (s[i + 1] - s[i]))
        .collect();
    let mut m = vec![0.0; n];
    m[0] = d[0];
    m[n - 1] = d[n - 2];
    for i in 1..n - 1 {
        m[i] = if d[i - 1] * d[i] <= 0.0 {
            0.0
        } else {
            0.5 * (d[i - 1] + d[i])
        };
    }
    for i in 0..n - 1 {
        if d[i] == 0.0 {
            m[i] = 0.0;
            m[i + 1] = 0.0;
            continue;
        }
        let a = m[i] / d[i];
        let b = m[i + 1] / d[i];
        let h = a * a + b * b;
        if h > 9.0 {
            let t = 3.0 / h.sqrt();
            m[i] = t * a * d[i];
            m[i + 1] = t * b * d[i];
        }
    }
    m
}

impl DepthProfile {
    /// A spline or table from (s, z) points, checked: at least two points, s in
    /// (0, 1], s and z both strictly increasing, the last z equal to 0 (the top).
    /// Errors name the offending points.
    pub(crate) fn from_points(
        points: &[[f64; 2]],
        spline: bool,
    ) -> Result<DepthProfile, ProfileError> {
        if points.len() < 2 {
            return Err(ProfileError::TooFewPoints { got: points.len() });
        }
        for p in points {
            if !(p[0].is_finite() && p[1].is_finite()) || p[0] <= 0.0 || p[0] > 1.0 {
                return Err(ProfileError::PointOutOfRange { s: p[0], z: p[1] });
            }
        }
        for w in points.windows(2) {
            let (a, b) = (w[0], w[1]);
            if b[0] <= a[0] {
                return Err(ProfileError::SNotIncreasing {
                    before: a,
                    after: b,
                });
            }
            if b[1] <= a[1] {
                return Err(ProfileError::ZNotIncreasing {
                    before: a,
                    after: b,
                });
            }
        }
        let last = points[points.len() - 1];
        if last[1].abs() > 1e-12 {
            return Err(ProfileError::TopNotZero {
                s: last[0],
                z: last[1],
            });
        }
        let s: Vec<f64> = points.iter().map(|p| p[0]).collect();
        let z: Vec<f64> = points.iter().map(|p| p[1]).collect();
        Ok(if spline {
            let m = fritsch_carlson(&s, &z);
            DepthProfile::Spline { s, z, m }
        } else {
            DepthProfile::Table { s, z }
        })
    }

    /// The range [s_bottom, s_top] on which φ is strictly increasing.
    pub fn s_range(&self) -> (f64, f64) {
        match self {
            DepthProfile::Linear { s_bottom, .. } => (*s_bottom, 1.0),
            DepthProfile::Sigmoid { s1, s2, .. } | DepthProfile::Power { s1, s2, .. } => (*s2, *s1),
            DepthProfile::Spline { s, .. } | DepthProfile::Table { s, .. } => {
                (s[0], s[s.len() - 1])
            }
        }
    }

    /// Total height (φ(s_top) − φ(s_bottom)), mm.
    pub fn depth(&self) -> f64 {
        -self.z(self.s_range().0)
    }

    /// φ(s): z relative to the stock top (0 at s_top, −depth at s_bottom); clamped
    /// outside the range.
    pub fn z(&self, s: f64) -> f64 {
        let (lo, hi) = self.s_range();
        let s = s.clamp(lo, hi);
        match self {
            DepthProfile::Linear { s_bottom, depth } => {
                -depth * (1.0 - (s - s_bottom) / (1.0 - s_bottom))
            }
            DepthProfile::Sigmoid {
                s1,
                s2,
                steepness,
                depth,
            } => {
                let t = (s - s2) / (s1 - s2);
                let k = *steepness;
                let (a, b) = (logistic(-0.5 * k), logistic(0.5 * k));
                let w = (logistic(k * (t - 0.5)) - a) / (b - a);
                -depth * (1.0 - w)
            }
            DepthProfile::Power {
                s1,
                s2,
                exponent,
                depth,
            } => {
                // (s/s1)ⁿ as exp(n ln(s/s1)): no overflow or underflow trouble.
                let pow = |x: f64| (exponent * (x / s1).ln()).exp();
                let a = pow(*s2);
                -depth * (1.0 - (pow(s) - a) / (1.0 - a))
            }
            DepthProfile::Table { s: xs, z } => {
                let i = segment(xs, s);
                let t = (s - xs[i]) / (xs[i + 1] - xs[i]);
                z[i] + t * (z[i + 1] - z[i])
            }
            DepthProfile::Spline { s: xs, z, m } => {
                let i = segment(xs, s);
                let h = xs[i + 1] - xs[i];
                let t = (s - xs[i]) / h;
                let (t2, t3) = (t * t, t * t * t);
                (2.0 * t3 - 3.0 * t2 + 1.0) * z[i]
                    + (t3 - 2.0 * t2 + t) * h * m[i]
                    + (-2.0 * t3 + 3.0 * t2) * z[i + 1]
                    + (t3 - t2) * h * m[i + 1]
            }
        }
    }

    /// φ'(s), mm per unit s: a central difference over a millionth of the
    /// range, one-sided at its ends (so the top and bottom edges take the
    /// wall's slope, not the flat's).
    pub fn slope(&self, s: f64) -> f64 {
        let (lo, hi) = self.s_range();
        let h = 1e-6 * (hi - lo);
        let (a, b) = ((s - h).max(lo), (s + h).min(hi));
        if b <= a {
            return 0.0;
        }
        (self.z(b) - self.z(a)) / (b - a)
    }

    /// s(z), the inverse of φ on [s_bottom, s_top], by bisection to 1e-12 in s
    /// (φ is strictly increasing there, so the bracket always holds).
    pub fn s_at(&self, z: f64) -> f64 {
        let (mut lo, mut hi) = self.s_range();
        if z <= self.z(lo) {
            return lo;
        }
        if z >= self.z(hi) {
            return hi;
        }
        while hi - lo > 1e-13 {
            let mid = 0.5 * (lo + hi);
            if self.z(mid) < z {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }
}

/// Index i of the interval `[xs[i], xs[i+1]]` holding s.
fn segment(xs: &[f64], s: f64) -> usize {
    let n = xs.len();
    match xs.binary_search_by(|v| v.total_cmp(&s)) {
        Ok(i) => i.min(n - 2),
        Err(i) => i.saturating_sub(1).min(n - 2),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all() -> Vec<DepthProfile> {
        vec![
            DepthProfile::Linear {
                s_bottom: 0.8,
                depth: 6.0,
            },
            DepthProfile::Sigmoid {
                s1: 0.99,
                s2: 0.75,
                steepness: 8.0,
                depth: 6.0,
            },
            DepthProfile::Power {
                s1: 0.999,
                s2: 0.99,
                exponent: 500.0,
                depth: 6.0,
            },
            DepthProfile::from_points(
                &[
                    [0.7, -6.0],
                    [0.8, -5.0],
                    [0.9, -1.0],
                    [0.97, -0.2],
                    [1.0, 0.0],
                ],
                true,
            )
            .unwrap(),
            DepthProfile::from_points(&[[0.7, -6.0], [0.8, -5.0], [0.9, -1.0], [1.0, 0.0]], false)
                .unwrap(),
        ]
    }

    #[test]
    fn every_kind_is_strictly_increasing_and_spans_the_depth() {
        for p in all() {
            let (lo, hi) = p.s_range();
            assert!((p.z(hi)).abs() < 1e-12, "{p:?}");
            assert!((p.z(lo) + 6.0).abs() < 1e-12, "{p:?}");
            let mut prev = f64::NEG_INFINITY;
            for k in 0..=10_000 {
                let z = p.z(lo + (hi - lo) * k as f64 / 10_000.0);
                assert!(z > prev, "{p:?} not increasing at step {k}");
                prev = z;
            }
        }
    }

    #[test]
    fn inverse_is_exact_to_1e_12() {
        for p in all() {
            let (lo, hi) = p.s_range();
            for k in 0..=200 {
                let s = lo + (hi - lo) * k as f64 / 200.0;
                let back = p.s_at(p.z(s));
                assert!((back - s).abs() <= 1e-12, "{p:?}: s {s} back {back}");
            }
        }
    }

    #[test]
    fn spline_interpolates_its_points_and_is_c1() {
        let pts = [
            [0.7, -6.0],
            [0.8, -5.0],
            [0.9, -1.0],
            [0.97, -0.2],
            [1.0, 0.0],
        ];
        let p = DepthProfile::from_points(&pts, true).unwrap();
        for q in pts {
            assert!((p.z(q[0]) - q[1]).abs() < 1e-12);
        }
        // Derivative continuous at the inner knots (one-sided finite differences).
        for q in &pts[1..4] {
            let h = 1e-7;
            let left = (p.z(q[0]) - p.z(q[0] - h)) / h;
            let right = (p.z(q[0] + h) - p.z(q[0])) / h;
            assert!(
                (left - right).abs() < 1e-4 * left.abs().max(1.0),
                "at {q:?}: {left} vs {right}"
            );
        }
    }

    #[test]
    fn non_monotone_points_are_named() {
        let e =
            DepthProfile::from_points(&[[0.7, -6.0], [0.8, -3.0], [0.9, -3.5], [1.0, 0.0]], true)
                .unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("(0.8, -3)") && msg.contains("(0.9, -3.5)"),
            "{msg}"
        );
        let e =
            DepthProfile::from_points(&[[0.8, -6.0], [0.8, -3.0], [1.0, 0.0]], false).unwrap_err();
        assert!(e.to_string().contains("s must increase"), "{e}");
        let e = DepthProfile::from_points(&[[0.8, -6.0], [1.0, -1.0]], false).unwrap_err();
        assert!(e.to_string().contains("z = 0"), "{e}");
    }

    /// φ' against the power wall's closed form, n·depth·sⁿ⁻¹/(s1ⁿ(1 − a))
    /// with a = (s2/s1)ⁿ, inside the range and at both ends (one-sided), and
    /// against a coarser difference of φ for every kind.
    #[test]
    fn the_slope_is_the_derivative() {
        let (s1, s2, n, depth) = (0.999_f64, 0.99_f64, 500.0_f64, 6.0);
        let p = DepthProfile::Power {
            s1,
            s2,
            exponent: n,
            depth,
        };
        let a = (s2 / s1).powf(n);
        for s in [s2, 0.993, 0.997, s1] {
            let exact = n * depth * s.powf(n - 1.0) / (s1.powf(n) * (1.0 - a));
            let got = p.slope(s);
            assert!(
                (got - exact).abs() < 1e-4 * exact,
                "s {s}: {got} vs {exact}"
            );
        }
        for p in all() {
            let (lo, hi) = p.s_range();
            for k in 1..10 {
                let s = lo + (hi - lo) * k as f64 / 10.0;
                let h = 1e-4 * (hi - lo);
                let fd = (p.z(s + h) - p.z(s - h)) / (2.0 * h);
                let got = p.slope(s);
                assert!(
                    (got - fd).abs() <= 1e-3 * fd.abs().max(1.0),
                    "{p:?} at {s}: {got} vs {fd}"
                );
            }
        }
    }
}
