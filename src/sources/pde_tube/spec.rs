//! A PDE tube as a job describes it (`[shape] kind = "pde-tube"`): two end
//! curves, each a superellipse centred on the tube's axis, their derivative
//! conditions, the PDE's parameter a and the mode count N.
//!
//! The end curve of half-sizes A, B and exponent p is, in polar form about
//! the axis,
//!
//! ```text
//! c(v) = r(v) (cos v, sin v),   r(v) = (|cos v / A|^p + |sin v / B|^p)^(−1/p)
//! ```
//!
//! (|x/A|^p + |y/B|^p = 1: p = 2 an ellipse, a circle when A = B; p = 4 the
//! squircle). Its polar angle is v itself, so every curve X(0, ·), X(1, ·)
//! is star-shaped about the axis with v its angle. The boundary conditions
//! (004 §2.1) sampled at K equally spaced vₖ are
//!
//! ```text
//! X(0, v) = (c₀(v), 0),   X(1, v) = (c₁(v), H),
//! Xᵤ(0, v) = (f₀ cos v, f₀ sin v, ρ₀),   Xᵤ(1, v) = (f₁ cos v, f₁ sin v, ρ₁)
//! ```
//!
//! with H the height (mm), f the flare (mm per unit u, outward along the ray
//! from the axis) and ρ the rise (mm per unit u, Xᵤ's z). For a mould the
//! same tube is turned upside down (z → H − z, so Xᵤ's z is −ρ): the bottom
//! curve is the rim at the stock top and the top curve the pocket's floor,
//! the mould of the boss the same keys give (as mfs-mould is mfs-sign's).

use super::{PdeTube, TubeError, TubeKind, MAX_POINTS};
use crate::geometry::Vec2;
use crate::levels::plan::CHORD_FRACTION;
use crate::sources::pde::{BoundaryCurves, PdeError, PdeSurface};
use std::f64::consts::TAU;

/// One end curve of a tube and its derivative condition.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TubeEnd {
    /// [2A, 2B]: the curve's extents in x and y, mm.
    pub size: [f64; 2],
    /// p ≥ 1: 2 an ellipse, 4 a squircle.
    pub exponent: f64,
    /// Xᵤ's outward part along the ray from the axis, mm per unit u.
    pub flare: f64,
    /// Xᵤ's z, mm per unit u (for the boss; negated for the mould).
    pub rise: f64,
}

impl TubeEnd {
    /// r(v), mm (module doc).
    pub fn radius(&self, v: f64) -> f64 {
        let (s, c) = v.sin_cos();
        let (a, b) = (0.5 * self.size[0], 0.5 * self.size[1]);
        let p = self.exponent;
        ((c / a).abs().powf(p) + (s / b).abs().powf(p)).powf(-1.0 / p)
    }

    /// c(v) relative to the axis, mm.
    pub fn point(&self, v: f64) -> Vec2 {
        let r = self.radius(v);
        Vec2::new(r * v.cos(), r * v.sin())
    }
}

/// A trim as a job gives it: the angles and heights between which the
/// tube's skin is cut away (down to the spine, `sources::pde_tube`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrimRect {
    /// [from, to], radians, from < to: the parameter v, the polar angle
    /// about the axis on the end curves (module doc).
    pub angles: [f64; 2],
    /// [bottom, top], mm relative to the part's top (z ≤ 0).
    pub z: [f64; 2],
}

impl TrimRect {
    /// The rectangle in the (u, v) plane, counter-clockwise (u along the
    /// first axis): u = u(z) at the two heights (`u_of`, the tube's inverse
    /// of A₀z), v the two angles. A top at the part's top (z = 0) is u = 1
    /// for a rising tube.
    pub fn polygon(&self, u_of: impl Fn(f64) -> f64) -> Vec<[f64; 2]> {
        let (mut u0, mut u1) = (u_of(self.z[0]), u_of(self.z[1]));
        if u0 > u1 {
            std::mem::swap(&mut u0, &mut u1);
        }
        let [a, b] = self.angles;
        vec![[u0, a], [u1, a], [u1, b], [u0, b]]
    }
}

/// The job's description of a PDE tube (validated when the job is resolved:
/// [`TubeSpec::tube`] succeeds on every resolved spec).
#[derive(Clone, Debug, PartialEq)]
pub struct TubeSpec {
    /// The curve at u = 0 (the part's bottom for a boss, the rim for a mould).
    pub bottom: TubeEnd,
    /// The curve at u = 1.
    pub top: TubeEnd,
    /// H, mm: the part's depth.
    pub height: f64,
    /// The PDE's parameter a (004 eq. (1)), > 0.
    pub a: f64,
    /// N, the Fourier modes solved exactly (the rest is the remainder's).
    pub modes: usize,
    /// K, samples of each condition in v.
    pub samples: usize,
    /// Where the axis goes, mm.
    pub origin: Vec2,
    /// Boss, or its mould (`operation.kind`).
    pub kind: TubeKind,
    /// Chords of a section stay within [`CHORD_FRACTION`] of this (mm); the
    /// nesting check allows a vertex this far out (`operation.tolerance`).
    pub tolerance: f64,
    /// Trims given by heights and angles (`[[shape.trim]]`), cut out as
    /// `sources::pde_tube`'s (u, v) trims ([`TrimRect::polygon`]).
    pub trims: Vec<TrimRect>,
}

impl TubeSpec {
    /// The boundary conditions sampled at K points (module doc), in job
    /// coordinates (the axis at `origin`).
    pub fn curves(&self) -> BoundaryCurves {
        let k = self.samples;
        let mould = self.kind == TubeKind::Mould;
        let z = |z: f64| if mould { self.height - z } else { z };
        let sign = if mould { -1.0 } else { 1.0 };
        let ring = |f: &dyn Fn(f64) -> [f64; 3]| -> Vec<[f64; 3]> {
            (0..k).map(|j| f(TAU * j as f64 / k as f64)).collect()
        };
        let end = |e: &TubeEnd, h: f64| {
            ring(&|v| {
                let p = self.origin + e.point(v);
                [p.x, p.y, z(h)]
            })
        };
        let deriv = |e: &TubeEnd| ring(&|v| [e.flare * v.cos(), e.flare * v.sin(), sign * e.rise]);
        BoundaryCurves {
            x0: end(&self.bottom, 0.0),
            x1: end(&self.top, self.height),
            xu0: deriv(&self.bottom),
            xu1: deriv(&self.top),
        }
    }

    /// The solved surface (cheap: no nesting check).
    pub fn surface(&self) -> Result<PdeSurface, PdeError> {
        PdeSurface::solve(&self.curves(), self.a, self.modes)
    }

    /// Points per section: the least P = 64·2ᵐ (up to [`MAX_POINTS`]) whose
    /// chords, on the rings u = 0, ¼, ½, ¾, 1, stay within
    /// [`CHORD_FRACTION`] × tolerance of the surface's point half way in v.
    pub fn points(&self, surface: &PdeSurface) -> usize {
        let limit = CHORD_FRACTION * self.tolerance;
        let mut p = 64;
        while p < MAX_POINTS && max_sagitta(surface, p) > limit {
            p *= 2;
        }
        p
    }

    /// The tube as a part: the surface, its checks and its nesting.
    pub fn tube(&self) -> Result<PdeTube, TubeError> {
        let surface = self.surface()?;
        let p = self.points(&surface);
        PdeTube::new_with(
            &self.curves(),
            self.a,
            self.modes,
            self.kind,
            (p, self.tolerance),
            |t| {
                self.trims
                    .iter()
                    .map(|r| r.polygon(|z| t.u_of(z)))
                    .collect()
            },
        )
    }

    /// The part seen from above: its widest curve (the boss's bottom, the
    /// mould's rim; both the bottom curve) at `p` points, counter-clockwise,
    /// job coordinates.
    pub fn outline(&self, p: usize) -> Vec<Vec2> {
        (0..p)
            .map(|j| self.origin + self.bottom.point(TAU * j as f64 / p as f64))
            .collect()
    }
}

/// The largest distance, over the rings u = 0, ¼, ½, ¾, 1 sampled at `p`
/// points, from a chord to the surface's point half way between its ends in
/// v (mm).
pub fn max_sagitta(surface: &PdeSurface, p: usize) -> f64 {
    let mut worst: f64 = 0.0;
    for u in [0.0, 0.25, 0.5, 0.75, 1.0] {
        let fine = surface.ring(u, 2 * p);
        let at = |i: usize| {
            let q = fine[i % (2 * p)];
            Vec2::new(q[0], q[1])
        };
        for j in 0..p {
            let (a, m, b) = (at(2 * j), at(2 * j + 1), at(2 * j + 2));
            worst = crate::num::max_or_nan(worst, segment_distance(a, b, m));
        }
    }
    worst
}

/// Distance from q to the segment ab, mm.
fn segment_distance(a: Vec2, b: Vec2, q: Vec2) -> f64 {
    let ab = b - a;
    let l2 = ab.dot(ab);
    let t = if l2 > 0.0 {
        ((q - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - q).norm()
}

/// The unit tests' vase: a 20 mm squircle (superellipse exponent 4) foot
/// rising to a 12 mm circle 15 mm up, both ends leaving vertically
/// (rise 15, no flare), a = 1, 8 modes on 128 samples, to 0.01 mm.
#[cfg(test)]
pub(crate) fn test_vase(kind: TubeKind, origin: Vec2) -> TubeSpec {
    let end = |d: f64, p: f64| TubeEnd {
        size: [d, d],
        exponent: p,
        flare: 0.0,
        rise: 15.0,
    };
    TubeSpec {
        bottom: end(20.0, 4.0),
        top: end(12.0, 2.0),
        height: 15.0,
        a: 1.0,
        modes: 8,
        samples: 128,
        origin,
        kind,
        tolerance: 0.01,
        trims: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vase(kind: TubeKind) -> TubeSpec {
        test_vase(kind, Vec2::new(3.0, -2.0))
    }

    #[test]
    fn the_end_curves_are_the_superellipses() {
        let s = vase(TubeKind::Boss);
        for j in 0..50 {
            let v = 0.37 + j as f64 * 0.123;
            let p = s.bottom.point(v);
            let e = (p.x / 10.0).powi(4) + (p.y / 10.0).powi(4);
            assert!((e - 1.0).abs() < 1e-13, "{e}");
            assert!((s.top.point(v).norm() - 6.0).abs() < 1e-13);
        }
        let c = s.curves();
        assert_eq!(c.x0.len(), 128);
        assert!((c.x0[0][0] - 13.0).abs() < 1e-12 && c.x0[0][1] == -2.0);
        assert_eq!(c.x1[5][2], 15.0);
        assert_eq!(c.xu1[7], [0.0, 0.0, 15.0]);
    }

    #[test]
    fn the_mould_is_the_boss_upside_down() {
        let (b, m) = (vase(TubeKind::Boss), vase(TubeKind::Mould));
        let (sb, sm) = (b.surface().unwrap(), m.surface().unwrap());
        for u in [0.0, 0.3, 0.8] {
            for v in [0.1, 2.0, 4.5] {
                let (p, q) = (sb.point(u, v), sm.point(u, v));
                assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
                assert!((p[2] + q[2] - 15.0).abs() < 1e-12, "{p:?} {q:?}");
            }
        }
    }

    #[test]
    fn points_are_doubled_until_the_chords_fit() {
        let mut s = vase(TubeKind::Boss);
        let surface = s.surface().unwrap();
        let p = s.points(&surface);
        assert!(max_sagitta(&surface, p) <= 0.001, "{p}");
        assert!(max_sagitta(&surface, p / 2) > 0.001, "{p}");
        s.tolerance = 1e-6;
        assert_eq!(s.points(&surface), MAX_POINTS);
    }
}
