//! Trimming a PDE surface (Ugail, seed 002, §3.1, eqs. (13)–(20)).
//!
//! A trim curve C₁ and the border C₂ are closed curves in the surface's (u, v)
//! parameter plane. The trimmed surface is the PDE surface composed with a
//! parameter map M from the annulus (ξ, η) ∈ [0, 1] × [0, 2π) (η periodic) onto
//! the region between them:
//!
//! ```text
//! Y(ξ, η) = X(M(ξ, η)),   M(0, η) = C₁(η),   M(1, η) = C₂(η),   (∂²/∂ξ² + ∂²/∂η²) M = 0   (13)
//! ```
//!
//! M's two components (u and v) are harmonic in (ξ, η): 002's (13), the Laplace
//! equation, solved by the spectral code of the fourth-order surface at order 2
//! (002 (14)–(20)), as implemented:
//!
//! ```text
//! M(ξ, η) = A₀(ξ) + Σ_{n=1..N} [Aₙ(ξ) cos nη + Bₙ(ξ) sin nη] + R(ξ, η)      (14), (18), (19)
//! A₀(ξ)   = a₀₀ + a₀₁ ξ                                                      (15)
//! Aₙ, Bₙ  = c₁ e^{n(ξ−1)} + c₂ e^{−nξ}                                       (16), (17)
//! R(ξ, η) = r₁(η) e^{w(ξ−1)} + r₂(η) e^{−wξ},   w = N + 1                    (20)
//! ```
//!
//! Corrections to 002: its (16)–(17) print a_{n1}e^{anu} + a_{n2}ue^{−anu}; the
//! Laplace modes are e^{nξ} and e^{−nξ} (no factor u, and no a: (13) has none).
//! Its (18) writes M ≈ A₀ + F + R with F already containing A₀ (19); it is
//! M ≈ F + R. The growing function is scaled by e^{−n} (as in [`super::pde`]),
//! so each mode's 2 × 2 system [[e^{−n}, 1], [1, e^{−n}]] is bounded and regular.
//! The remainder carries the samples' DFT modes N < n ≤ K/2 exactly as in
//! [`super::pde`]: M meets C₁ and C₂ at every sample ηₖ = 2πk/K to rounding, and
//! between samples their trigonometric interpolants. R is not harmonic for
//! n ≠ w (002's approximation).
//!
//! M is one-to-one when its Jacobian det[∂M/∂ξ, ∂M/∂η] keeps one sign; with
//! both curves counter-clockwise that sign is positive. A Laplace map of an
//! annulus is not univalent for every pair of curves, so [`TrimMap::solve`]
//! samples the Jacobian and refuses a fold.

#[cfg(test)]
use super::pde::PdeSurface;
use super::pde::{check_curves, fourier_curve, PdeError, PdeFault};
use nalgebra::{Matrix2, Vector2};
use std::f64::consts::TAU;

/// Jacobian samples per unit ξ in [`TrimMap::solve`]'s fold check (the η
/// direction: 4 per curve sample).
const FOLD_SAMPLES_XI: usize = 64;

/// The two boundary curves of 002 (13), each sampled at ηₖ = 2πk/K, points
/// (u, v) of the surface's parameter plane (u dimensionless, v in radians).
#[derive(Debug, Clone, PartialEq)]
pub struct TrimCurves {
    /// C₁, the trim curve: M(0, ηₖ).
    pub trim: Vec<[f64; 2]>,
    /// C₂, the border: M(1, ηₖ).
    pub border: Vec<[f64; 2]>,
}

/// One mode of M: (n, λ, cos coefficients, sin coefficients); rows the two basis
/// functions, columns u, v.
type Mode = (usize, f64, Matrix2<f64>, Matrix2<f64>);

/// The solved map M of 002 (13)–(20).
#[derive(Debug, Clone, PartialEq)]
pub struct TrimMap {
    /// A₀(0) and A₀(1) (the curves' means).
    mean: [Vector2<f64>; 2],
    modes: Vec<Mode>,
}

/// (e^{λ(ξ−1)}, e^{−λξ}) and its ξ-derivative.
fn basis(lambda: f64, xi: f64) -> (Vector2<f64>, Vector2<f64>) {
    let (p, m) = ((lambda * (xi - 1.0)).exp(), (-lambda * xi).exp());
    (Vector2::new(p, m), Vector2::new(lambda * p, -lambda * m))
}

/// Mode n's coefficients of both curves, (cos, sin), rows C₁, C₂.
fn data(c: &TrimCurves, n: usize) -> (Matrix2<f64>, Matrix2<f64>) {
    let (mut cm, mut sm) = (Matrix2::zeros(), Matrix2::zeros());
    for (row, curve) in [&c.trim, &c.border].into_iter().enumerate() {
        let flat: Vec<[f64; 3]> = curve.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let (cr, sr) = fourier_curve(&flat, n);
        cm.set_row(row, &nalgebra::RowVector2::new(cr[0], cr[1]));
        sm.set_row(row, &nalgebra::RowVector2::new(sr[0], sr[1]));
    }
    (cm, sm)
}

/// Twice the signed area of a closed polygon (shoelace), positive
/// counter-clockwise in the (u, v) plane.
fn twice_area(p: &[[f64; 2]]) -> f64 {
    (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum()
}

/// Equal lengths, 2N + 1 ≤ K ≤ [`MAX_SAMPLES`](crate::sources::pde::MAX_SAMPLES), finite, both counter-clockwise.
fn check(c: &TrimCurves, modes: usize) -> Result<(), PdeError> {
    let named = [("trim", c.trim.as_slice()), ("border", &c.border)];
    check_curves(&named, modes, |key, curve| {
        if twice_area(curve) <= 0.0 {
            return Err(PdeError::Invalid {
                key,
                reason: PdeFault::Clockwise,
            });
        }
        Ok(())
    })
}

impl TrimMap {
    /// Solves M for the curves with N = `modes` harmonic modes; the remainder
    /// (w = N + 1) carries the modes N < n ≤ K/2. Errors: bad curves (key `trim`
    /// or `border`), or a fold: a sampled Jacobian ≤ 0 (key `trim`, at the ξ, η
    /// named).
    pub fn solve(c: &TrimCurves, modes: usize) -> Result<TrimMap, PdeError> {
        check(c, modes)?;
        let (m0, _) = data(c, 0);
        let mean = [m0.row(0).transpose(), m0.row(1).transpose()];
        let k = c.trim.len();
        let mut out = Vec::with_capacity(k / 2);
        for n in 1..=k / 2 {
            let lambda = n.min(modes + 1) as f64;
            let (f0, _) = basis(lambda, 0.0);
            let (f1, _) = basis(lambda, 1.0);
            let lu = Matrix2::from_rows(&[f0.transpose(), f1.transpose()]).lu();
            let (cd, sd) = data(c, n);
            let solve = |rhs: &Matrix2<f64>| match lu.solve(rhs) {
                Some(x) if x.iter().all(|v| v.is_finite()) => Ok(x),
                _ => Err(PdeError::Singular { mode: n, lambda }),
            };
            out.push((n, lambda, solve(&cd)?, solve(&sd)?));
        }
        let map = TrimMap { mean, modes: out };
        let (det, xi, eta) = map.min_jacobian(FOLD_SAMPLES_XI, 4 * k);
        if det.is_nan() || det <= 0.0 {
            return Err(PdeError::Invalid {
                key: "trim",
                reason: PdeFault::Folds { det, xi, eta },
            });
        }
        Ok(map)
    }

    /// Sums the modes: M (or ∂M/∂ξ when `d_xi`, ∂M/∂η when `d_eta`).
    fn sum(&self, xi: f64, eta: f64, d_xi: bool, d_eta: bool) -> Vector2<f64> {
        let mut m = if d_eta {
            Vector2::zeros()
        } else if d_xi {
            self.mean[1] - self.mean[0]
        } else {
            self.mean[0] * (1.0 - xi) + self.mean[1] * xi
        };
        for (n, lambda, c, s) in &self.modes {
            let (f, df) = basis(*lambda, xi);
            let phi = if d_xi { df } else { f };
            let nf = *n as f64;
            let (sn, cs) = (nf * eta).sin_cos();
            let (wc, ws) = if d_eta { (-nf * sn, nf * cs) } else { (cs, sn) };
            m += (c * wc + s * ws).transpose() * phi;
        }
        m
    }

    /// M(ξ, η) = (u, v).
    pub fn map(&self, xi: f64, eta: f64) -> [f64; 2] {
        let m = self.sum(xi, eta, false, false);
        [m[0], m[1]]
    }

    /// (∂M/∂ξ, ∂M/∂η), each (∂u, ∂v).
    pub(crate) fn derivatives(&self, xi: f64, eta: f64) -> ([f64; 2], [f64; 2]) {
        let (a, b) = (
            self.sum(xi, eta, true, false),
            self.sum(xi, eta, false, true),
        );
        ([a[0], a[1]], [b[0], b[1]])
    }

    /// det[∂M/∂ξ, ∂M/∂η] = u_ξ v_η − v_ξ u_η.
    pub(crate) fn jacobian(&self, xi: f64, eta: f64) -> f64 {
        let (a, b) = self.derivatives(xi, eta);
        a[0] * b[1] - a[1] * b[0]
    }

    /// The smallest Jacobian over ξ = i/`nxi` (i = 0..=nxi) and η = 2πj/`neta`
    /// (j < neta), with where it is: (det, ξ, η). NaN if any sample is NaN.
    pub fn min_jacobian(&self, nxi: usize, neta: usize) -> (f64, f64, f64) {
        let mut best = (f64::INFINITY, 0.0, 0.0);
        for i in 0..=nxi {
            let xi = i as f64 / nxi.max(1) as f64;
            for j in 0..neta {
                let eta = TAU * j as f64 / neta as f64;
                let d = self.jacobian(xi, eta);
                if d.is_nan() {
                    return (f64::NAN, xi, eta);
                }
                if d < best.0 {
                    best = (d, xi, eta);
                }
            }
        }
        best
    }
}

/// A PDE surface trimmed by a [`TrimMap`]: Y(ξ, η) = X(M(ξ, η)).
#[cfg(test)]
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TrimmedSurface {
    /// The untrimmed surface X(u, v).
    pub(crate) surface: PdeSurface,
    /// The map from the annulus onto the kept region of the (u, v) plane.
    pub(crate) map: TrimMap,
}

#[cfg(test)]
impl TrimmedSurface {
    /// Y(ξ, η) (mm): ξ = 0 on the trim curve, ξ = 1 on the border.
    pub(crate) fn point(&self, xi: f64, eta: f64) -> [f64; 3] {
        let [u, v] = self.map.map(xi, eta);
        self.surface.point(u, v)
    }
}

/// `k` points of the closed polygon `p` (first point not repeated), equally
/// spaced in arc length from `p[0]`: the samples ηₖ of a [`TrimCurves`] curve.
/// Empty for fewer than two distinct points.
pub fn resample_closed(p: &[[f64; 2]], k: usize) -> Vec<[f64; 2]> {
    let n = p.len();
    let seg = |i: usize| {
        let (a, b) = (p[i], p[(i + 1) % n]);
        (b[0] - a[0]).hypot(b[1] - a[1])
    };
    let total: f64 = (0..n).map(seg).sum();
    if n < 2 || !(total > 0.0 && total.is_finite()) {
        return Vec::new();
    }
    let mut out = Vec::with_capacity(k);
    let (mut i, mut start) = (0, 0.0);
    for j in 0..k {
        let target = total * j as f64 / k as f64;
        while i + 1 < n && start + seg(i) < target {
            start += seg(i);
            i += 1;
        }
        let t = if seg(i) > 0.0 {
            (target - start) / seg(i)
        } else {
            0.0
        };
        let (a, b) = (p[i], p[(i + 1) % n]);
        out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
    }
    out
}

#[cfg(test)]
mod tests;
