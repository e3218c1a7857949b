//! A fourth-order PDE surface as a part: a tube with horizontal sections
//! (issue 18, seeds 004 and 002), a [`Sections`] source.
//!
//! When both end curves are horizontal (X_z(0, v), X_z(1, v) constant) and the z
//! components of Xᵤ(0, v), Xᵤ(1, v) are constant, the z component's data have
//! no mode n ≥ 1, so X_z(u, v) = A₀z(u), the spine's z (004 eq. (10)): every
//! curve u = const is horizontal. With A₀z strictly monotone on [0, 1] the
//! section at height z is the closed curve
//!
//! ```text
//! S(z) = { X(u(z), v) : v ∈ [0, 2π) },   u(z) = A₀z⁻¹(z)
//! ```
//!
//! the paper's S2 = {Γ(s), z = φ(s)} with u in place of s. A boss is the region
//! inside S(z) (material on the left: outlines counter-clockwise); its mould is
//! the same curves as holes (clockwise), at the same heights. Heights are
//! relative to the part's top: z ∈ [−depth, 0], depth = |A₀z(1) − A₀z(0)|.
//!
//! Trims: closed polygons in the (u, v) parameter plane (002 §3). A trimmed
//! window of the skin removes the material between it and the spine, 004's
//! picture of X as the spine plus a radius vector (004 §2.2): at height z the
//! trim region's v-intervals at u(z) are cut out of the section as sectors
//! with their apex at the spine point A₀(u(z)). A section with trimmed
//! intervals is the kept pie pieces [apex, X(u, b), …, X(u, a)], one per kept
//! arc; the apex lies inside the section when the curve is star-shaped about
//! the spine (not checked). A section trimmed all round is empty.
//!
//! Nesting (3-axis milling from above): a boss's section at a higher z must lie
//! inside the one below; a mould's pocket must contain the pocket below.
//! [`PdeTube::new`] checks it between [`NEST_LEVELS`] + 1 evenly spaced heights
//! (vertices of one against the region of the other, allowed out by the
//! caller's tolerance, the job's `tol` in mm) and refuses an overhang with the
//! heights named. A trimmed window's sides are the rays from the spine to
//! X(u, v) at the trim's v; they twist a little as u changes (the polar angle
//! of X(u, v) is not v), so a window can overhang by a few µm: the tolerance
//! decides.

use super::pde::{BoundaryCurves, PdeError, PdeSurface};
use crate::geometry::polygon_area;
use crate::geometry::Vec2;
use crate::levels::sections::{LevelField, Sections};
use std::f64::consts::TAU;

mod fault;
pub mod spec;
mod trim;

pub use fault::TubeFault;

/// Heights between which [`PdeTube::new`] checks that sections nest.
pub const NEST_LEVELS: usize = 200;

/// Most points per section (each point is one evaluation of X).
pub const MAX_POINTS: usize = 8192;

/// Vertices of each section the nesting check tests (every ⌈P/512⌉-th).
const NEST_VERTICES: usize = 512;

/// Relative tolerance of "constant" in the horizontality checks.
const FLAT: f64 = 1e-9;

/// Boss (the tube's inside is the material) or mould (the inside is a pocket).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TubeKind {
    /// Outlines counter-clockwise.
    Boss,
    /// The same curves as holes.
    Mould,
}

/// Why a tube cannot be a part.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TubeError {
    /// The surface's own input is bad (see [`PdeError`]).
    #[error(transparent)]
    Pde(#[from] PdeError),
    /// A curve or parameter does not fit a tube; `reason` says how.
    #[error("{key}: {reason}")]
    Invalid {
        /// The field: `x0`, `x1`, `xu0`, `xu1`, `points`, `tol` or `trims`.
        key: &'static str,
        /// What is wrong with it.
        #[source]
        reason: TubeFault,
    },
    /// A₀z(u) is not monotone: the surface turns back in z.
    #[error("xu0, xu1: the tube's spine turns back in z at z = {z:.4} mm (u = {u:.4}); A₀z(u) must be monotone for horizontal sections to be one curve each: make the z parts of xu0 and xu1 agree in sign with x1 − x0")]
    NotMonotone {
        /// Height of the turning point, relative to the part's top (mm).
        z: f64,
        /// Its parameter u.
        u: f64,
    },
    /// Sections do not nest: the part overhangs.
    #[error("the part overhangs between z = {lower:.4} and {upper:.4} mm (about z = {z:.4}): {what} by {by:.2e} mm (tol {tol} mm); a 3-axis mill cannot reach under it")]
    Overhang {
        /// The middle of the two heights (mm, relative to the part's top).
        z: f64,
        /// The lower height.
        lower: f64,
        /// The upper height.
        upper: f64,
        /// Which way it fails.
        what: &'static str,
        /// How far (mm) the farthest tested vertex is out.
        by: f64,
        /// The tolerance it exceeds (mm).
        tol: f64,
    },
}

/// A PDE tube as a part; see the module doc.
#[derive(Debug, Clone, PartialEq)]
pub struct PdeTube {
    surface: PdeSurface,
    kind: TubeKind,
    trims: Vec<Vec<[f64; 2]>>,
    points: usize,
    /// A₀z at u = 0 and u = 1 (mm, the curves' own z).
    z_ends: (f64, f64),
}

/// The first sample whose z differs from sample 0's by more than [`FLAT`]
/// relative, with its z.
fn not_flat(c: &[[f64; 3]]) -> Option<(usize, f64)> {
    let z0 = c.first()?[2];
    let scale = c.iter().map(|p| p[2].abs()).fold(1.0, f64::max);
    c.iter()
        .position(|p| (p[2] - z0).abs() > FLAT * scale)
        .map(|j| (j, c[j][2]))
}

fn check_flat(curves: &BoundaryCurves) -> Result<(), TubeError> {
    for (key, c, what) in [
        ("x0", &curves.x0, "horizontal (one z)"),
        ("x1", &curves.x1, "horizontal (one z)"),
        ("xu0", &curves.xu0, "of constant z component"),
        ("xu1", &curves.xu1, "of constant z component"),
    ] {
        if let Some((j, z)) = not_flat(c) {
            let z0 = c[0][2];
            return Err(TubeError::Invalid {
                key,
                reason: TubeFault::NotFlat {
                    what,
                    sample: j,
                    z,
                    z0,
                },
            });
        }
    }
    Ok(())
}

/// The checks before the solve: flat z data, `points` in 16 to
/// [`MAX_POINTS`], `tol` finite and > 0.
fn check_inputs(curves: &BoundaryCurves, points: usize, tol: f64) -> Result<(), TubeError> {
    check_flat(curves)?;
    if !(tol.is_finite() && tol > 0.0) {
        return Err(TubeError::Invalid {
            key: "tol",
            reason: TubeFault::Tolerance { tol },
        });
    }
    if !(16..=MAX_POINTS).contains(&points) {
        return Err(TubeError::Invalid {
            key: "points",
            reason: TubeFault::Points { points },
        });
    }
    Ok(())
}

impl PdeTube {
    /// Solves the surface (a > 0, N = `modes`), checks that it is a tube (flat
    /// z data, monotone A₀z), and that its sections, with `points` samples each
    /// (16 to [`MAX_POINTS`]) and the `trims` cut out, nest for `kind` to `tol`
    /// (mm, > 0).
    pub fn new(
        curves: &BoundaryCurves,
        a: f64,
        modes: usize,
        kind: TubeKind,
        trims: Vec<Vec<[f64; 2]>>,
        (points, tol): (usize, f64),
    ) -> Result<PdeTube, TubeError> {
        check_inputs(curves, points, tol)?;
        trim::check(&trims)?;
        Self::new_with(curves, a, modes, kind, (points, tol), |_| trims)
    }

    /// As [`PdeTube::new`], the trims given by `trims` from the untrimmed
    /// tube (e.g. trims given by heights, through its [`PdeTube::u_of`]);
    /// they are checked as `new`'s are.
    pub fn new_with(
        curves: &BoundaryCurves,
        a: f64,
        modes: usize,
        kind: TubeKind,
        (points, tol): (usize, f64),
        trims: impl FnOnce(&PdeTube) -> Vec<Vec<[f64; 2]>>,
    ) -> Result<PdeTube, TubeError> {
        check_inputs(curves, points, tol)?;
        let surface = PdeSurface::solve(curves, a, modes)?;
        let sp = surface.spine();
        let mut tube = PdeTube {
            z_ends: (sp.p1[2], sp.p2[2]),
            surface,
            kind,
            trims: Vec::new(),
            points,
        };
        tube.check_monotone()?;
        tube.trims = trims(&tube);
        trim::check(&tube.trims)?;
        tube.check_nesting(tol)?;
        Ok(tube)
    }

    /// The trim polygons in the (u, v) plane.
    pub fn trims(&self) -> &[Vec<[f64; 2]>] {
        &self.trims
    }

    /// The kept arcs (a, b) of v at u, a < b (b possibly past 2π): `None`
    /// where no trim applies, empty where the whole curve is trimmed.
    pub fn kept_arcs(&self, u: f64) -> Option<Vec<(f64, f64)>> {
        trim::kept_arcs(&self.trims, u)
    }

    /// The solved surface.
    pub fn surface(&self) -> &PdeSurface {
        &self.surface
    }

    /// Boss or mould.
    pub fn kind(&self) -> TubeKind {
        self.kind
    }

    /// Points per section.
    pub fn points(&self) -> usize {
        self.points
    }

    /// Whether the tube rises with u (A₀z(1) > A₀z(0)).
    pub fn rising(&self) -> bool {
        self.z_ends.1 > self.z_ends.0
    }

    /// The part's top: the larger end z (mm, the curves' frame).
    fn top(&self) -> f64 {
        self.z_ends.0.max(self.z_ends.1)
    }

    /// The part's top in the curves' frame (mm): the z that heights
    /// relative to the top are measured from.
    pub fn top_z(&self) -> f64 {
        self.top()
    }

    /// A₀z(u) − top (mm).
    fn z_of(&self, u: f64) -> f64 {
        self.surface.spine().point(u)[2] - self.top()
    }

    /// A₀z monotone: sign · A₀z′ ≥ 0 at 1001 samples of u (sign that of
    /// A₀z(1) − A₀z(0)), else the turning point: the first sign change of A₀z′,
    /// bracketed by two samples and bisected.
    fn check_monotone(&self) -> Result<(), TubeError> {
        let (z0, z1) = self.z_ends;
        if z1 == z0 || !(z1 - z0).is_finite() {
            return Err(TubeError::Invalid {
                key: "x1",
                reason: TubeFault::NoDepth { z0 },
            });
        }
        let sign = (z1 - z0).signum();
        let bad = |u: f64| sign * self.surface.spine().derivative(u)[2] < 0.0;
        let n = 1000;
        let at = |i: usize| i as f64 / n as f64;
        let Some(first) = (0..=n).find(|&i| bad(at(i))) else {
            return Ok(());
        };
        // Good → bad at `first`, or (first = 0) bad → good further on.
        let hi = if first > 0 {
            first
        } else {
            (1..=n).find(|&i| !bad(at(i))).unwrap_or(n)
        };
        let (mut lo, mut hi) = (at(hi - 1), at(hi));
        let left = bad(lo);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if bad(mid) == left {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let u = 0.5 * (lo + hi);
        Err(TubeError::NotMonotone { z: self.z_of(u), u })
    }

    /// u(z): A₀z(u) − top = z by bisection on [0, 1] (A₀z monotone), z clamped
    /// to the part.
    pub fn u_of(&self, z: f64) -> f64 {
        let (lo_z, hi_z) = self.z_range();
        let z = z.clamp(lo_z, hi_z);
        let rising = self.z_ends.1 > self.z_ends.0;
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            if (self.z_of(mid) < z) == rising {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    /// X(u, v) projected on the plane, v = v₀ + i (v₁ − v₀)/m, i = 0..m.
    fn arc(&self, u: f64, v0: f64, v1: f64, m: usize) -> Vec<Vec2> {
        (0..=m)
            .map(|i| {
                let p = self.surface.point(u, v0 + (v1 - v0) * i as f64 / m as f64);
                Vec2::new(p[0], p[1])
            })
            .collect()
    }

    /// The boss's section at parameter u: the closed curve, or the kept pie
    /// pieces where trims apply; counter-clockwise.
    fn boss_section(&self, u: f64) -> Vec<Vec<Vec2>> {
        let p = self.points;
        let mut full: Vec<Vec2> = self
            .surface
            .ring(u, p)
            .iter()
            .map(|q| Vec2::new(q[0], q[1]))
            .collect();
        let ccw = polygon_area(&full) >= 0.0;
        let Some(kept) = trim::kept_arcs(&self.trims, u) else {
            if !ccw {
                full.reverse();
            }
            return vec![full];
        };
        let c = self.surface.spine().point(u);
        let apex = Vec2::new(c[0], c[1]);
        kept.iter()
            .map(|&(a, b)| {
                let m = (((b - a) / TAU * p as f64).ceil() as usize).max(1);
                let mut piece = vec![apex];
                piece.extend(self.arc(u, a, b, m));
                if !ccw {
                    piece.reverse();
                }
                piece
            })
            .collect()
    }

    /// Sections at [`NEST_LEVELS`] + 1 heights, lowest first, each pair nested
    /// to `tol` (mm).
    fn check_nesting(&self, tol: f64) -> Result<(), TubeError> {
        let (lo, hi) = self.z_range();
        let z_at = |i: usize| lo + (hi - lo) * i as f64 / NEST_LEVELS as f64;
        let mut below = self.boss_section(self.u_of(lo));
        for i in 1..=NEST_LEVELS {
            let above = self.boss_section(self.u_of(z_at(i)));
            let (inner, outer, what) = match self.kind {
                TubeKind::Boss => (&above, &below, "its section reaches outside the one below"),
                TubeKind::Mould => (&below, &above, "its pocket reaches outside the one above"),
            };
            let by = trim::outside_by(inner, outer, NEST_VERTICES);
            if by.is_nan() || by > tol {
                let (l, u) = (z_at(i - 1), z_at(i));
                return Err(TubeError::Overhang {
                    z: 0.5 * (l + u),
                    lower: l,
                    upper: u,
                    what,
                    by,
                    tol,
                });
            }
            below = above;
        }
        Ok(())
    }
}

impl Sections for PdeTube {
    fn z_range(&self) -> (f64, f64) {
        (-(self.z_ends.1 - self.z_ends.0).abs(), 0.0)
    }

    /// S(z) with the trims cut out: outlines for a boss, holes for a mould.
    fn section(&self, z: f64) -> Vec<Vec<Vec2>> {
        let mut s = self.boss_section(self.u_of(z));
        if self.kind == TubeKind::Mould {
            s.iter_mut().for_each(|p| p.reverse());
        }
        s
    }

    /// u(z), the surface parameter of the level.
    fn level_value(&self, z: f64) -> f64 {
        self.u_of(z)
    }

    fn level_field(&self, _z: f64) -> Option<LevelField> {
        None
    }
}

#[cfg(test)]
mod tests;
