//! The height range of a harmonic patch, for sizing stock: a harmonic patch
//! overshoots its rows (its inner control points leave the rows' range), so
//! the range is computed from the surface, not read off the rows.
//!
//! By the maximum principle a function harmonic in the parameter square
//! (h_uu + h_vv = 0 there) takes its max and min on the square's boundary, so
//! the search runs over the four edges, each a univariate Bézier (the rows at
//! u = 0 and u = 1, the end columns at v = 0 and v = 1): a fine sampling
//! (`SAMPLES_PER_DEGREE` per degree), then every sign change of the
//! derivative between samples refined by bisection to where the derivative
//! vanishes (a local extremum). `tests` checks the result against a grid over
//! the whole square.

use super::bernstein::{de_casteljau, derivative};
use super::patch::HarmonicPatch;

/// Samples per unit of degree along an edge. A polynomial of degree ≤ 12 has
/// at most 11 turning points; 64 samples a degree put several samples between
/// any two of them unless they are so close that the extreme value between
/// them differs from the sampled neighbours by far less than a micron.
const SAMPLES_PER_DEGREE: usize = 64;

/// Bisection steps: 2⁻⁶⁰ of a sample interval is below f64's resolution on [0, 1].
const BISECTIONS: usize = 60;

/// The lowest and highest heights of a patch and where they are (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightRange {
    /// min h, mm.
    pub min: f64,
    /// max h, mm.
    pub max: f64,
    /// (x, y) of the minimum, mm.
    pub argmin: [f64; 2],
    /// (x, y) of the maximum, mm.
    pub argmax: [f64; 2],
}

impl HarmonicPatch {
    /// The true min and max of h over the rectangle (module doc).
    pub fn height_range(&self) -> HeightRange {
        let net = self.net();
        let [sx, sy] = self.size;
        let (m, n) = (net.rows - 1, net.cols - 1);
        // Each edge: its control points, and (x, y) at t = 0 and the step to t = 1.
        let edges = [
            (net.row(0).to_vec(), [0.0, 0.0], [sx, 0.0]),
            (net.row(m).to_vec(), [0.0, sy], [sx, 0.0]),
            (net.column(0), [0.0, 0.0], [0.0, sy]),
            (net.column(n), [sx, 0.0], [0.0, sy]),
        ];
        let place = |o: [f64; 2], d: [f64; 2], t: f64| [o[0] + t * d[0], o[1] + t * d[1]];
        let mut range = HeightRange {
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            argmin: [0.0; 2],
            argmax: [0.0; 2],
        };
        for (curve, o, d) in edges {
            let ((tmin, hmin), (tmax, hmax)) = curve_extremes(&curve);
            if hmin < range.min {
                (range.min, range.argmin) = (hmin, place(o, d, tmin));
            }
            if hmax > range.max {
                (range.max, range.argmax) = (hmax, place(o, d, tmax));
            }
        }
        range
    }
}

/// ((t, value) of the min, (t, value) of the max) of Σ c_i B_i(t) on [0, 1].
pub(crate) fn curve_extremes(c: &[f64]) -> ((f64, f64), (f64, f64)) {
    let d = derivative(c);
    let k = SAMPLES_PER_DEGREE * c.len().max(2);
    let ts: Vec<f64> = (0..=k).map(|s| s as f64 / k as f64).collect();
    let mut candidates: Vec<f64> = ts.clone();
    for w in ts.windows(2) {
        let (da, db) = (de_casteljau(&d, w[0]), de_casteljau(&d, w[1]));
        if da * db < 0.0 {
            candidates.push(derivative_root(&d, w[0], w[1], da));
        }
    }
    let mut lo = (0.0, f64::INFINITY);
    let mut hi = (0.0, f64::NEG_INFINITY);
    for t in candidates {
        let h = de_casteljau(c, t);
        if h < lo.1 {
            lo = (t, h);
        }
        if h > hi.1 {
            hi = (t, h);
        }
    }
    (lo, hi)
}

/// The zero of the derivative d in [a, b], where it changes sign (d(a) = da).
fn derivative_root(d: &[f64], mut a: f64, mut b: f64, da: f64) -> f64 {
    for _ in 0..BISECTIONS {
        let mid = 0.5 * (a + b);
        if de_casteljau(d, mid) * da > 0.0 {
            a = mid;
        } else {
            b = mid;
        }
    }
    0.5 * (a + b)
}
