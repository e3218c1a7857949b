//! Bloor–Wilson PDE surfaces with a spine (Ugail 2004, seed 004; remainder form
//! from Ugail's trimming paper, seed 002, eq. (12)).
//!
//! The surface X(u, v), u ∈ [0, 1], v ∈ [0, 2π) periodic, solves (004 eq. (1))
//!
//! ```text
//! (∂²/∂u² + a² ∂²/∂v²)² X = 0
//! ```
//!
//! with X(0, v), X(1, v), Xᵤ(0, v), Xᵤ(1, v) given as closed curves sampled at K
//! equally spaced vₖ = 2πk/K. The solution as implemented (004 eqs. (2)–(8)):
//!
//! ```text
//! X(u, v) = A₀(u) + Σ_{n=1..N} [Aₙ(u) cos nv + Bₙ(u) sin nv] + R(u, v)
//! A₀(u)   = Hermite cubic of the four conditions' means           (3), (10)
//! Aₙ, Bₙ  = c₁ e^{λ(u−1)} + c₂ u e^{λ(u−1)} + c₃ e^{−λu} + c₄ u e^{−λu},  λ = a n
//! R(u, v) = r₁ e^{w(u−1)} + r₂ u e^{w(u−1)} + r₃ e^{−wu} + r₄ u e^{−wu},  w = a (N + 1)
//! ```
//!
//! The basis is the paper's (4)–(5) with e^{λu} rescaled by e^{−λ}: the same span,
//! but every function stays in [−1, 1]·max(1, u) on u ∈ [0, 1] (the paper's form
//! overflows f64 once a·N passes about 30 and loses the conditions well before).
//! 004's (7) drops the factor u from the second and fourth remainder terms; 002's
//! (12) has them, and so does this code. Neither paper gives w; w = a (N + 1) is the
//! first frequency not carried by F (attributed to Bloor and Wilson's spectral
//! method, whose paper is not among the seeds: unchecked).
//!
//! The remainder rᵢ(v) is solved pointwise in v from the conditions' residual
//! (given minus what the truncated series F meets). The residual is known at the
//! samples only; between them it is taken as its trigonometric interpolant, i.e.
//! the DFT modes N < n ≤ K/2 of the samples. The 4 × 4 remainder system does not
//! depend on v, so rᵢ(v) is that interpolant pushed through the same solve: the
//! conditions hold exactly (to rounding) at every sample vₖ, and at any other v
//! they equal the trigonometric interpolant of the samples (exact when the given
//! curves are trigonometric polynomials of degree < K/2).

use nalgebra::{Matrix4, Matrix4x3, RowVector3, Vector4};

/// Largest number of samples per curve: the Fourier analysis is a direct
/// O(K · K/2) sum, and K = 4096 already resolves any curve a job can mill.
pub(crate) const MAX_SAMPLES: usize = 4096;

/// Bad input to [`PdeSurface::solve`]; `key` names the field at fault.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PdeError {
    /// A parameter or curve is out of range; `reason` says how.
    #[error("{key}: {reason}")]
    Invalid {
        /// The field: `a`, `modes`, `x0`, `x1`, `xu0` or `xu1`.
        key: &'static str,
        /// What is wrong with it.
        #[source]
        reason: PdeFault,
    },
    /// A mode system of the four-curve conditions (002) amplifies its data
    /// beyond `four_curves::GAIN_LIMIT`: the surface between the curves would
    /// be dominated by rounding.
    #[error("{key}: the mode-{mode} system (λ = {lambda}) amplifies its data {gain:.1e}-fold between the curves (limit {limit:.0e}); lower a or modes, or space the curves more evenly")]
    IllConditioned {
        /// The parameter to change (`modes` when the remainder's w = a(N + 1) fails, else `a`).
        key: &'static str,
        /// The Fourier mode n (N + 1 for the remainder).
        mode: usize,
        /// Its exponent λ.
        lambda: f64,
        /// max over u ∈ [0, 1] of |φ(λ, u)ᵀ M⁻¹ eᵢ| over the unit data eᵢ.
        gain: f64,
        /// `four_curves::GAIN_LIMIT`.
        limit: f64,
    },
    /// A 4 × 4 mode system could not be solved to finite coefficients.
    #[error("a: the mode-{mode} system (λ = {lambda}) is singular; use a larger a")]
    Singular {
        /// The Fourier mode n (for the remainder: the mode whose residual failed).
        mode: usize,
        /// Its exponent λ.
        lambda: f64,
    },
}

/// The boundary conditions of 004 §2.1: X(0, v) = `x0`, X(1, v) = `x1`,
/// Xᵤ(0, v) = `xu0`, Xᵤ(1, v) = `xu1`, each sampled at vₖ = 2πk/K, k = 0..K.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryCurves {
    /// X(0, vₖ) (mm).
    pub x0: Vec<[f64; 3]>,
    /// X(1, vₖ) (mm).
    pub x1: Vec<[f64; 3]>,
    /// Xᵤ(0, vₖ) (mm per unit u).
    pub xu0: Vec<[f64; 3]>,
    /// Xᵤ(1, vₖ) (mm per unit u).
    pub xu1: Vec<[f64; 3]>,
}

/// The spine (004 §2.2–3, eq. (10)): the mean part A₀(u) of the surface, a Hermite
/// cubic H(u) = B₁p₁ + B₂p₂ + B₃v₁ + B₄v₂ with H(0) = p₁, H(1) = p₂, H′(0) = v₁,
/// H′(1) = v₂.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spine {
    /// Position at u = 0 (mm).
    pub(crate) p1: [f64; 3],
    /// Position at u = 1 (mm).
    pub(crate) p2: [f64; 3],
    /// Derivative at u = 0 (mm per unit u).
    pub(crate) v1: [f64; 3],
    /// Derivative at u = 1 (mm per unit u).
    pub(crate) v2: [f64; 3],
}

impl Spine {
    /// Hermite weights (B₁, B₂, B₃, B₄)(u) and their u-derivatives.
    fn weights(u: f64) -> ([f64; 4], [f64; 4]) {
        let (u2, u3) = (u * u, u * u * u);
        (
            [
                2.0 * u3 - 3.0 * u2 + 1.0,
                -2.0 * u3 + 3.0 * u2,
                u3 - 2.0 * u2 + u,
                u3 - u2,
            ],
            [
                6.0 * u2 - 6.0 * u,
                -6.0 * u2 + 6.0 * u,
                3.0 * u2 - 4.0 * u + 1.0,
                3.0 * u2 - 2.0 * u,
            ],
        )
    }

    fn combine(&self, w: [f64; 4]) -> [f64; 3] {
        std::array::from_fn(|i| {
            w[0] * self.p1[i] + w[1] * self.p2[i] + w[2] * self.v1[i] + w[3] * self.v2[i]
        })
    }

    /// H(u).
    pub fn point(&self, u: f64) -> [f64; 3] {
        self.combine(Self::weights(u).0)
    }

    /// H′(u).
    pub(crate) fn derivative(&self, u: f64) -> [f64; 3] {
        self.combine(Self::weights(u).1)
    }
}

/// One Fourier mode n of the solution: X gains
/// Σᵢ φᵢ(λ, u) (cosᵢ cos nv + sinᵢ sin nv), φ the scaled basis of the module doc.
#[derive(Debug, Clone, PartialEq)]
struct Term {
    n: usize,
    lambda: f64,
    cos: Matrix4x3<f64>,
    sin: Matrix4x3<f64>,
}

/// A solved fourth-order PDE surface (see the module doc for the maths).
#[derive(Debug, Clone, PartialEq)]
pub struct PdeSurface {
    spine: Spine,
    /// The modes 1..=N of F, then the remainder's modes N < n ≤ K/2 (all λ = w).
    terms: Vec<Term>,
    /// How many of `terms` belong to F (= N).
    modes: usize,
}

/// The scaled basis φ(λ, u) = (e^{λ(u−1)}, u e^{λ(u−1)}, e^{−λu}, u e^{−λu}) and
/// its u-derivative; λ > 0.
fn basis(lambda: f64, u: f64) -> (Vector4<f64>, Vector4<f64>) {
    let p = (lambda * (u - 1.0)).exp();
    let m = (-lambda * u).exp();
    (
        Vector4::new(p, u * p, m, u * m),
        Vector4::new(
            lambda * p,
            (1.0 + lambda * u) * p,
            -lambda * m,
            (1.0 - lambda * u) * m,
        ),
    )
}

/// The 4 × 4 system: rows X(0), X(1), Xᵤ(0), Xᵤ(1) of the scaled basis.
fn mode_matrix(lambda: f64) -> Matrix4<f64> {
    let (f0, d0) = basis(lambda, 0.0);
    let (f1, d1) = basis(lambda, 1.0);
    Matrix4::from_rows(&[
        f0.transpose(),
        f1.transpose(),
        d0.transpose(),
        d1.transpose(),
    ])
}

/// Fourier coefficients of one sampled curve at mode n, (cos part, sin part):
/// c = (2/K) Σ fₖ cos nvₖ (1/K at n = 0 and at the Nyquist mode n = K/2), likewise
/// for sin.
pub(super) fn fourier_curve(curve: &[[f64; 3]], n: usize) -> (RowVector3<f64>, RowVector3<f64>) {
    let k = curve.len();
    let scale = if n == 0 || 2 * n == k { 1.0 } else { 2.0 } / k as f64;
    let (mut c, mut s) = (RowVector3::zeros(), RowVector3::zeros());
    for (j, p) in curve.iter().enumerate() {
        // n·j mod K keeps the angle in [0, 2π): exact samples for large n·j.
        let t = std::f64::consts::TAU * ((n * j) % k) as f64 / k as f64;
        let (st, ct) = t.sin_cos();
        c += RowVector3::from(*p) * (scale * ct);
        s += RowVector3::from(*p) * (scale * st);
    }
    (c, s)
}

/// The four conditions' coefficients at mode n: rows X(0), X(1), Xᵤ(0), Xᵤ(1),
/// columns x, y, z, for the cos and the sin part.
fn fourier(curves: &[&[[f64; 3]]; 4], n: usize) -> (Matrix4x3<f64>, Matrix4x3<f64>) {
    let (mut c, mut s) = (Matrix4x3::zeros(), Matrix4x3::zeros());
    for (row, curve) in curves.iter().enumerate() {
        let (cr, sr) = fourier_curve(curve, n);
        c.set_row(row, &cr);
        s.set_row(row, &sr);
    }
    (c, s)
}

/// Checks the curves: equal lengths, at least 2N + 1 samples (else mode N aliases),
/// at most [`MAX_SAMPLES`], finite coordinates.
fn check(curves: &BoundaryCurves, a: f64, modes: usize) -> Result<(), PdeError> {
    check_a(a)?;
    let named = [
        ("x0", curves.x0.as_slice()),
        ("x1", &curves.x1),
        ("xu0", &curves.xu0),
        ("xu1", &curves.xu1),
    ];
    check_curves(&named, modes, |_, _| Ok(()))
}

/// The PDE's a (key `a`): finite and > 0.
pub(crate) fn check_a(a: f64) -> Result<(), PdeError> {
    if a.is_finite() && a > 0.0 {
        return Ok(());
    }
    Err(PdeError::Invalid {
        key: "a",
        reason: PdeFault::NotPositive { value: a },
    })
}

/// Curves sampled at the same K parameters, each named by its key: the
/// first's K within 2N + 1 ≤ K ≤ [`MAX_SAMPLES`] (fewer samples alias mode
/// N), then curve by curve K samples, each finite, and what `more` checks
/// of it.
pub(crate) fn check_curves<const D: usize>(
    curves: &[(&'static str, &[[f64; D]])],
    modes: usize,
    more: impl Fn(&'static str, &[[f64; D]]) -> Result<(), PdeError>,
) -> Result<(), PdeError> {
    let bad = |key, reason| Err(PdeError::Invalid { key, reason });
    let Some(&(first, c0)) = curves.first() else {
        return Ok(());
    };
    let k = c0.len();
    if k < 2 * modes + 1 || k > MAX_SAMPLES {
        let need = 2 * modes + 1;
        return bad(first, PdeFault::SampleCount { samples: k, need });
    }
    for &(key, curve) in curves {
        if curve.len() != k {
            let samples = curve.len();
            return bad(
                key,
                PdeFault::SampleMismatch {
                    samples,
                    first,
                    first_samples: k,
                },
            );
        }
        if let Some(index) = first_not_finite(curve) {
            return bad(key, PdeFault::SampleNotFinite { index });
        }
        more(key, curve)?;
    }
    Ok(())
}

/// The index of the curve's first sample with a coordinate that is not finite.
pub(crate) fn first_not_finite<const D: usize>(curve: &[[f64; D]]) -> Option<usize> {
    curve.iter().position(|p| p.iter().any(|x| !x.is_finite()))
}

/// Coefficients of the scaled basis for λ meeting the conditions `rhs` (rows X(0),
/// X(1), Xᵤ(0), Xᵤ(1)); an error when the system is singular or the result not finite.
fn solve_mode(
    lu: &nalgebra::LU<f64, nalgebra::U4, nalgebra::U4>,
    rhs: &Matrix4x3<f64>,
    n: usize,
    lambda: f64,
) -> Result<Matrix4x3<f64>, PdeError> {
    match lu.solve(rhs) {
        Some(c) if c.iter().all(|x| x.is_finite()) => Ok(c),
        _ => Err(PdeError::Singular { mode: n, lambda }),
    }
}

impl PdeSurface {
    /// Solves the surface for the `curves`, the smoothing parameter `a` (> 0) and
    /// N = `modes` Fourier modes in F; the remainder carries the modes N < n ≤ K/2.
    pub fn solve(curves: &BoundaryCurves, a: f64, modes: usize) -> Result<Self, PdeError> {
        check(curves, a, modes)?;
        let cs: [&[[f64; 3]]; 4] = [&curves.x0, &curves.x1, &curves.xu0, &curves.xu1];
        let (mean, _) = fourier(&cs, 0);
        let row = |r: usize| -> [f64; 3] { std::array::from_fn(|i| mean[(r, i)]) };
        let spine = Spine {
            p1: row(0),
            p2: row(1),
            v1: row(2),
            v2: row(3),
        };
        let k = curves.x0.len();
        let mut terms = Vec::with_capacity(k / 2);
        for n in 1..=modes {
            let lambda = a * n as f64;
            let lu = mode_matrix(lambda).lu();
            let (c, s) = fourier(&cs, n);
            let cos = solve_mode(&lu, &c, n, lambda)?;
            let sin = solve_mode(&lu, &s, n, lambda)?;
            terms.push(Term {
                n,
                lambda,
                cos,
                sin,
            });
        }
        let w = a * (modes + 1) as f64;
        let lu = mode_matrix(w).lu();
        for n in modes + 1..=k / 2 {
            // The residual's mode n: F carries nothing above N, so it is the data's.
            let (c, s) = fourier(&cs, n);
            let cos = solve_mode(&lu, &c, n, w)?;
            let sin = solve_mode(&lu, &s, n, w)?;
            terms.push(Term {
                n,
                lambda: w,
                cos,
                sin,
            });
        }
        Ok(Self {
            spine,
            terms,
            modes,
        })
    }

    /// The same surface without its remainder: F of 004 eq. (8) alone.
    pub fn without_remainder(&self) -> Self {
        let mut f = self.clone();
        f.terms.truncate(self.modes);
        f
    }

    /// The spine A₀ (004 §2.2).
    pub fn spine(&self) -> Spine {
        self.spine
    }

    /// The surface with its spine replaced (004 §3): every point moves by
    /// H_new(u) − A₀(u); the periodic part is unchanged.
    #[cfg(test)]
    pub(crate) fn with_spine(&self, spine: Spine) -> Self {
        Self {
            spine,
            ..self.clone()
        }
    }

    /// Sums the periodic terms Σ φ(λ, u) · (cosₙ cos nv + sinₙ sin nv), with φ
    /// replaced by φ′ when `deriv_u` and (cos nv, sin nv) by their v-derivatives
    /// when `deriv_v`.
    fn periodic(&self, u: f64, v: f64, deriv_u: bool, deriv_v: bool) -> [f64; 3] {
        let mut x = RowVector3::zeros();
        for t in &self.terms {
            let (f, d) = basis(t.lambda, u);
            let phi = if deriv_u { d } else { f };
            let (s, c) = (t.n as f64 * v).sin_cos();
            let (wc, ws) = if deriv_v {
                (-(t.n as f64) * s, t.n as f64 * c)
            } else {
                (c, s)
            };
            x += phi.transpose() * (t.cos * wc + t.sin * ws);
        }
        [x[0], x[1], x[2]]
    }

    /// X(u, vⱼ) at the `p` equally spaced vⱼ = 2πj/p, j = 0..p (mm): the same
    /// sums as [`Self::point`], with φ(λ, u) computed once per term and cos nvⱼ,
    /// sin nvⱼ read from one table of 2πi/p (nj mod p, so exact angles). A
    /// section of a tube is one such ring; this is ~30 times faster than p
    /// calls of `point` at K = 128.
    pub(crate) fn ring(&self, u: f64, p: usize) -> Vec<[f64; 3]> {
        let table: Vec<(f64, f64)> = (0..p)
            .map(|i| (std::f64::consts::TAU * i as f64 / p as f64).sin_cos())
            .collect();
        let weighted: Vec<(usize, RowVector3<f64>, RowVector3<f64>)> = self
            .terms
            .iter()
            .map(|t| {
                let phi = basis(t.lambda, u).0.transpose();
                (t.n, phi * t.cos, phi * t.sin)
            })
            .collect();
        let spine = self.spine.point(u);
        (0..p)
            .map(|j| {
                let mut x = RowVector3::from(spine);
                for (n, c, s) in &weighted {
                    let (sn, cn) = table[(n * j) % p];
                    x += c * cn + s * sn;
                }
                [x[0], x[1], x[2]]
            })
            .collect()
    }

    /// X(u, v) (mm). Meant for u ∈ [0, 1]; v in radians, any value (periodic).
    pub fn point(&self, u: f64, v: f64) -> [f64; 3] {
        add(self.spine.point(u), self.periodic(u, v, false, false))
    }

    /// ∂X/∂u (mm per unit u).
    pub fn du(&self, u: f64, v: f64) -> [f64; 3] {
        add(self.spine.derivative(u), self.periodic(u, v, true, false))
    }

    /// ∂X/∂v (mm per radian).
    pub(crate) fn dv(&self, u: f64, v: f64) -> [f64; 3] {
        self.periodic(u, v, false, true)
    }
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i] + b[i])
}

mod fault;
mod four_curves;
pub(crate) use fault::PdeFault;
pub use four_curves::conditioning as four_curve_conditioning;

#[cfg(test)]
mod tests;
