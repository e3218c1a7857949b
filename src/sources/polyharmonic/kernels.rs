//! The polyharmonic kernels T*ᵢ (Ochiai eq. (9)) and their ball-spread forms
//! T*ᵢA (eqs. (11)–(15)), with gradients (eqs. (24)–(27)).
//!
//! With r = |P − Q| (any length unit; the kernels scale as r^{2i−3}):
//!
//! ```text
//! T*ᵢ(r) = r^{2i−3} / (4π (2i − 2)!)      T*₁ = 1/(4πr), T*₂ = r/(8π), T*₃ = r³/(96π)
//! ΔT*₁ = −δ,  ΔT*ᵢ₊₁ = T*ᵢ                 (Δf = f'' + 2f'/r: Δr = 2/r, Δr³ = 12r)
//! ```
//!
//! T*ᵢA(r) = ∫_{|y| ≤ A} T*ᵢ(|x − y|) dy with |x| = r: the kernel spread over a
//! ball of radius A with unit density (not normalised, so T*ᵢA → (4πA³/3)·T*ᵢ as
//! A → 0). From the shell means of 1/|x − y| (1/max(r, a)) and of |x − y|
//! (r + a²/(3r) for a < r, a + r²/(3a) for a > r) over a sphere of radius a:
//!
//! ```text
//! T*₁A = A³/(3r)                        r > A      (12)
//!      = (3A² − r²)/6                   r ≤ A      (13)
//! T*₂A = (A³/30)(5r + A²/r)             r > A      (14)
//!      = (15A⁴ + 10A²r² − r⁴)/120       r ≤ A      (15)
//! dT*₁A/dr = −A³/(3r²) | −r/3                      (24), (25)
//! dT*₂A/dr = A³(5r² − A²)/(30r²) | (5A²r − r³)/30  (26), (27)
//! ```
//!
//! Both are continuous with their first derivative at r = A (A²/3, −A/3 and
//! A⁴/5, 4A³/30). The printed (26) reads A³(r² − 5A²)/(30r²), which is not the
//! derivative of (14) and does not meet (27) at r = A; the form above is.
//! ΔT*₁A = −1 inside the ball and 0 outside; ΔT*₂A = T*₁A.

use super::error::{invalid, PolyError};
use super::fault::PolyFault;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// A polyharmonic kernel; `a` is the ball radius A of the spread forms, in the
/// points' length unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kernel {
    /// T*₁ = 1/(4πr).
    T1,
    /// T*₂ = r/(8π).
    T2,
    /// T*₃ = r³/(96π).
    T3,
    /// T*₁ spread over a ball of radius `a`.
    T1A {
        /// Ball radius A > 0.
        a: f64,
    },
    /// T*₂ spread over a ball of radius `a`.
    T2A {
        /// Ball radius A > 0.
        a: f64,
    },
}

/// A radial kernel's profile at r: f(r), g = f'(r)/r and h = g'(r)/r. With
/// d = P − Q: the value is f, ∇_P = g·d, ∂/∂n_Q = −g (d·n) and
/// ∇_P ∂/∂n_Q = −(h (d·n) d + g n); Δf = h r² + 3g.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Radial {
    /// f(r).
    pub(crate) f: f64,
    /// f'(r)/r.
    pub(crate) g: f64,
    /// g'(r)/r.
    pub(crate) h: f64,
}

impl Kernel {
    /// The kernel after checking its radius: `kernel.a` must be finite and > 0.
    pub(crate) fn validated(self) -> Result<Self, PolyError> {
        match self {
            Kernel::T1A { a } | Kernel::T2A { a } if !(a.is_finite() && a > 0.0) => {
                Err(invalid("kernel.a", PolyFault::Radius { a }))
            }
            k => Ok(k),
        }
    }

    /// The radial profile at distance `r` ≥ 0 (infinite for T*₁ and T*₁'s
    /// derivatives at r = 0).
    pub(crate) fn radial(self, r: f64) -> Radial {
        let pi4 = 4.0 * PI;
        match self {
            Kernel::T1 => Radial {
                f: 1.0 / (pi4 * r),
                g: -1.0 / (pi4 * r * r * r),
                h: 3.0 / (pi4 * r.powi(5)),
            },
            Kernel::T2 => Radial {
                f: r / (8.0 * PI),
                g: 1.0 / (8.0 * PI * r),
                h: -1.0 / (8.0 * PI * r * r * r),
            },
            Kernel::T3 => Radial {
                f: r * r * r / (96.0 * PI),
                g: r / (32.0 * PI),
                h: 1.0 / (32.0 * PI * r),
            },
            Kernel::T1A { a } => t1a(a, r),
            Kernel::T2A { a } => t2a(a, r),
        }
    }

    /// T*(P, Q) for d = P − Q.
    pub(crate) fn value(self, d: Vector3<f64>) -> f64 {
        self.radial(d.norm()).f
    }

    /// ∇_P T*(P, Q) for d = P − Q.
    pub(crate) fn gradient(self, d: Vector3<f64>) -> Vector3<f64> {
        d * self.radial(d.norm()).g
    }
}

/// T*₁A's profile, eqs. (12), (13), (24), (25).
fn t1a(a: f64, r: f64) -> Radial {
    let a3 = a * a * a;
    if r > a {
        Radial {
            f: a3 / (3.0 * r),
            g: -a3 / (3.0 * r * r * r),
            h: a3 / r.powi(5),
        }
    } else {
        Radial {
            f: (3.0 * a * a - r * r) / 6.0,
            g: -1.0 / 3.0,
            h: 0.0,
        }
    }
}

/// T*₂A's profile, eqs. (14), (15), (26) corrected, (27).
fn t2a(a: f64, r: f64) -> Radial {
    let (a2, a3) = (a * a, a * a * a);
    if r > a {
        let r2 = r * r;
        Radial {
            f: a3 / 30.0 * (5.0 * r + a2 / r),
            g: a3 / 30.0 * (5.0 / r - a2 / (r2 * r)),
            h: a3 / 30.0 * (-5.0 / (r2 * r) + 3.0 * a2 / (r2 * r2 * r)),
        }
    } else {
        Radial {
            f: (15.0 * a2 * a2 + 10.0 * a2 * r * r - r.powi(4)) / 120.0,
            g: (5.0 * a2 - r * r) / 30.0,
            h: -1.0 / 15.0,
        }
    }
}

#[cfg(test)]
mod tests;
