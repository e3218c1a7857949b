//! The four-curve conditions of Ugail's trimming paper (seed 002, eqs. (2)–(12)):
//! the fourth-order surface of 002 eq. (1) through four position curves,
//!
//! ```text
//! X(0, v) = P₀(v),  X(s, v) = P₁(v),  X(t, v) = P₂(v),  X(1, v) = P₃(v),   0 < s < t < 1
//! ```
//!
//! (002 (2)–(5); the paper writes "0 < s, t < 1", and its next sentence names the
//! end curves P₀, P₁ where it means P₀, P₃). The solution has the form of
//! [`super`] (002 (6)–(12), the same modes and remainder); only the conditions
//! change: every mode's 4 × 4 system has the rows φ(λ, 0), φ(λ, s), φ(λ, t),
//! φ(λ, 1) of the scaled basis, and A₀ is the cubic through the four curves'
//! means at u = 0, s, t, 1 (Lagrange form, stored as its Hermite spine).
//!
//! Each row is divided by its largest entry before the LU (the rows at s and t
//! are of size e^{−λ min(s, 1−s)}), and its right-hand side with it.
//!
//! Conditioning: interior position conditions make each mode an interpolation
//! problem whose solution between the nodes grows exponentially with λ: a unit
//! wiggle of mode n on one curve moves the surface between the curves by up to
//! [`ModeConditioning::gain`] (measured for s, t = 0.3, 0.7: 25 at λ = 20,
//! 5.0e3 at 40, 1.3e6 at 60; `cargo run --release --example pde_figures`).
//! The row-equilibrated matrix itself stays well conditioned (cond ≈ 12 there),
//! so the conditions are met to rounding whatever the gain; the gain is what a
//! user's wiggle (or rounding in the data) becomes inside. Above
//! `GAIN_LIMIT` (1e6) the solve is refused.

use super::basis;
#[cfg(test)]
use super::{
    check_a, check_curves, fourier_curve, solve_mode, PdeError, PdeFault, PdeSurface, Spine, Term,
};
#[cfg(test)]
use nalgebra::Matrix4x3;
use nalgebra::{Matrix4, Vector4};

/// Largest amplification of a unit datum by a mode system that
/// [`PdeSurface::through_four_curves`] accepts. A gain g turns a data rounding
/// of 1e-16 (relative) into g·1e-16 in the surface, and a 1 µm wiggle of a
/// curve into g µm; 1e6 keeps both below what a mill can see on a part of
/// 100 mm (1e-8 mm rounding), while the four curves are met to 1e-12 mm.
#[cfg(test)]
pub(crate) const GAIN_LIMIT: f64 = 1e6;

/// Points per unit u at which [`ModeConditioning::gain`] samples |φ(λ, u)ᵀc|.
const GAIN_SAMPLES: usize = 400;

/// The four position curves of 002 (2)–(5), each sampled at vₖ = 2πk/K, and the
/// interior parameters s, t.
#[cfg(test)]
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FourCurves {
    /// X(0, vₖ) (mm).
    pub(crate) p0: Vec<[f64; 3]>,
    /// X(s, vₖ) (mm).
    pub(crate) p1: Vec<[f64; 3]>,
    /// X(t, vₖ) (mm).
    pub(crate) p2: Vec<[f64; 3]>,
    /// X(1, vₖ) (mm).
    pub(crate) p3: Vec<[f64; 3]>,
    /// u of `p1`, 0 < s < t.
    pub(crate) s: f64,
    /// u of `p2`, s < t < 1.
    pub(crate) t: f64,
}

/// How well one mode's 4 × 4 system is posed (n = 0: the cubic A₀; n = N + 1: the
/// remainder, λ = w).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeConditioning {
    /// The Fourier mode.
    pub(crate) n: usize,
    /// Its exponent λ (0 for A₀).
    pub(crate) lambda: f64,
    /// 2-norm condition number σ_max/σ_min of the row-equilibrated matrix.
    pub cond: f64,
    /// max over the four unit data eᵢ and u ∈ [0, 1] (sampled at
    /// 1/`GAIN_SAMPLES`) of |φ(λ, u)ᵀ M⁻¹ eᵢ|: how far a unit change of one curve
    /// moves the surface.
    pub gain: f64,
}

/// The four conditions' nodes.
fn nodes(s: f64, t: f64) -> [f64; 4] {
    [0.0, s, t, 1.0]
}

/// Basis row at u: the scaled exponentials for λ > 0, the monomials 1, u, u², u³
/// for λ = 0 (A₀).
fn row(lambda: f64, u: f64) -> Vector4<f64> {
    if lambda == 0.0 {
        Vector4::new(1.0, u, u * u, u * u * u)
    } else {
        basis(lambda, u).0
    }
}

/// Rows at 0, s, t, 1, each divided by its largest entry; the factors.
fn system(lambda: f64, s: f64, t: f64) -> (Matrix4<f64>, [f64; 4]) {
    let xs = nodes(s, t);
    let mut scale = [1.0; 4];
    let mut m = Matrix4::zeros();
    for (i, &x) in xs.iter().enumerate() {
        let r = row(lambda, x);
        scale[i] = 1.0 / r.amax();
        m.set_row(i, &(r.transpose() * scale[i]));
    }
    (m, scale)
}

/// The conditioning of mode `n`'s system at λ (λ = 0: the cubic A₀) for
/// conditions at u = 0, s, t, 1 (see [`ModeConditioning`]).
pub fn conditioning(n: usize, lambda: f64, s: f64, t: f64) -> ModeConditioning {
    let (m, scale) = system(lambda, s, t);
    let sv = m.singular_values();
    let cond = sv.max() / sv.min();
    let lu = m.lu();
    let mut gain: f64 = 0.0;
    for (i, &d) in scale.iter().enumerate() {
        let mut e = Vector4::zeros();
        e[i] = d;
        let c = lu.solve(&e).unwrap_or(Vector4::repeat(f64::NAN));
        for j in 0..=GAIN_SAMPLES {
            let v = row(lambda, j as f64 / GAIN_SAMPLES as f64).dot(&c).abs();
            gain = crate::num::max_or_nan(gain, v);
        }
    }
    ModeConditioning {
        n,
        lambda,
        cond,
        gain,
    }
}

/// The cubic through (xᵢ, yᵢ), i = 0..4, as its Hermite spine (values and
/// derivatives at u = 0 and 1), from the Lagrange basis Lᵢ and Lᵢ′.
#[cfg(test)]
fn cubic_spine(y: [[f64; 3]; 4], s: f64, t: f64) -> Spine {
    let x = nodes(s, t);
    let deriv = |u: f64| -> [f64; 3] {
        let mut d = [0.0; 3];
        for i in 0..4 {
            let denom: f64 = (0..4).filter(|&m| m != i).map(|m| x[i] - x[m]).product();
            let mut li = 0.0;
            for j in (0..4).filter(|&j| j != i) {
                li += (0..4)
                    .filter(|&m| m != i && m != j)
                    .map(|m| u - x[m])
                    .product::<f64>();
            }
            (0..3).for_each(|k| d[k] += y[i][k] * li / denom);
        }
        d
    };
    Spine {
        p1: y[0],
        p2: y[3],
        v1: deriv(0.0),
        v2: deriv(1.0),
    }
}

/// Checks a, s, t and the curves (equal lengths, 2N + 1 ≤ K ≤ [`MAX_SAMPLES`](super::MAX_SAMPLES),
/// finite).
#[cfg(test)]
fn check(c: &FourCurves, a: f64, modes: usize) -> Result<(), PdeError> {
    let bad = |key, reason| Err(PdeError::Invalid { key, reason });
    check_a(a)?;
    if !(c.s > 0.0 && c.s < 1.0) {
        return bad("s", PdeFault::SOutside { s: c.s });
    }
    if !(c.t > c.s && c.t < 1.0) {
        return bad("t", PdeFault::TOutside { s: c.s, t: c.t });
    }
    let named = [
        ("p0", c.p0.as_slice()),
        ("p1", &c.p1),
        ("p2", &c.p2),
        ("p3", &c.p3),
    ];
    check_curves(&named, modes, |_, _| Ok(()))
}

/// The mode-n coefficients of the four curves (rows P₀…P₃, columns x, y, z), each
/// row times `scale`: (cos part, sin part).
#[cfg(test)]
fn data(c: &FourCurves, n: usize, scale: [f64; 4]) -> (Matrix4x3<f64>, Matrix4x3<f64>) {
    let (mut cm, mut sm) = (Matrix4x3::zeros(), Matrix4x3::zeros());
    for (i, curve) in [&c.p0, &c.p1, &c.p2, &c.p3].into_iter().enumerate() {
        let (cr, sr) = fourier_curve(curve, n);
        cm.set_row(i, &(cr * scale[i]));
        sm.set_row(i, &(sr * scale[i]));
    }
    (cm, sm)
}

/// One mode's term at λ, after its conditioning passes [`GAIN_LIMIT`].
#[cfg(test)]
fn term(c: &FourCurves, n: usize, lambda: f64, key: &'static str) -> Result<Term, PdeError> {
    let (m, scale) = system(lambda, c.s, c.t);
    let lu = m.lu();
    let (cd, sd) = data(c, n, scale);
    Ok(Term {
        n,
        lambda,
        cos: solve_mode(&lu, &cd, n, lambda).map_err(|_| singular(key, n, lambda))?,
        sin: solve_mode(&lu, &sd, n, lambda).map_err(|_| singular(key, n, lambda))?,
    })
}

#[cfg(test)]
fn singular(key: &'static str, mode: usize, lambda: f64) -> PdeError {
    PdeError::IllConditioned {
        key,
        mode,
        lambda,
        gain: f64::INFINITY,
        limit: GAIN_LIMIT,
    }
}

/// The report's entry for λ, or the error when its gain is above the limit.
#[cfg(test)]
fn conditioned(
    n: usize,
    lambda: f64,
    c: &FourCurves,
    key: &'static str,
) -> Result<ModeConditioning, PdeError> {
    let r = conditioning(n, lambda, c.s, c.t);
    if r.gain <= GAIN_LIMIT {
        return Ok(r);
    }
    Err(PdeError::IllConditioned {
        key,
        mode: n,
        lambda,
        gain: r.gain,
        limit: GAIN_LIMIT,
    })
}

#[cfg(test)]
impl PdeSurface {
    /// Solves 002's four-curve problem with a > 0 and N = `modes` modes in F; the
    /// remainder (λ = w = a(N + 1)) carries the samples' modes N < n ≤ K/2, so the
    /// four curves are met exactly (to rounding) at every sample vₖ. Returns the
    /// surface and the conditioning of A₀, of each mode and of the remainder.
    /// Evaluation, spine edits and [`PdeSurface::without_remainder`] are those of
    /// the two-end surface.
    pub(crate) fn through_four_curves(
        c: &FourCurves,
        a: f64,
        modes: usize,
    ) -> Result<(Self, Vec<ModeConditioning>), PdeError> {
        check(c, a, modes)?;
        let mean = |p: &[[f64; 3]]| -> [f64; 3] {
            let (m, _) = fourier_curve(p, 0);
            [m[0], m[1], m[2]]
        };
        let spine = cubic_spine(
            [mean(&c.p0), mean(&c.p1), mean(&c.p2), mean(&c.p3)],
            c.s,
            c.t,
        );
        let mut report = vec![conditioned(0, 0.0, c, "t")?];
        let mut terms = Vec::with_capacity(c.p0.len() / 2);
        for n in 1..=modes {
            let lambda = a * n as f64;
            report.push(conditioned(n, lambda, c, "a")?);
            terms.push(term(c, n, lambda, "a")?);
        }
        let w = a * (modes + 1) as f64;
        let k = c.p0.len();
        if k / 2 > modes {
            report.push(conditioned(modes + 1, w, c, "modes")?);
        }
        for n in modes + 1..=k / 2 {
            terms.push(term(c, n, w, "modes")?);
        }
        let surface = PdeSurface {
            spine,
            terms,
            modes,
        };
        Ok((surface, report))
    }
}

#[cfg(test)]
mod tests;
