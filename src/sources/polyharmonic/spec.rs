//! A polyharmonic relief as a job describes it (`shape.kind =
//! "polyharmonic"`), built once when the job is resolved: the solve, the
//! fast field over the work region, the coarse rays and the height range.
//!
//! The work region is the job's rectangle × [base − step, start], start =
//! z_max + ¼(box top − z_max) with z_max the highest given point: the rays
//! begin there, so the solid must not reach it (checked on the coarse rays).
//! The box part of T₁ is interpolated on nodes a fifth of the smallest
//! element side apart (4-point stencils). max h is the best coarse ray
//! refined by a pattern search (steps from the coarse spacing halved to
//! 1e-7 mm); min h is the base (the block's foot). A closed solid
//! (`Solid::Closed`) also gets its region (`closed::Region`), checked
//! closed here; its surface is meshed on demand ([`PolySpec::closed_mesh`]).

use super::closed::{closed_mesh, Region};
use super::error::{invalid, PolyError};
use super::fast::FastField;
use super::fault::PolyFault;
use super::iso::IsoMesh;
use super::relief::{Relief, ReliefSpec};
use super::system::{solve, GivenPoint, Model};
use super::{Kernel, Quadrature};
use crate::sources::harmonic_bezier::HeightRange;
use nalgebra::Vector3;
use std::sync::Arc;

/// The march step along a ray, mm: the thinnest piece (in z) seen.
pub(crate) const RAY_STEP: f64 = 0.5;

/// The coarse rays' spacing, mm: the narrowest piece (in x, y) seen away
/// from others.
pub(crate) const COARSE: f64 = 1.0;

/// Built specs kept for reuse by [`PolySpec::build_cached`].
pub(crate) const CACHE: usize = 4;

/// Interpolation nodes per smallest element side.
const NODES_PER_ELEMENT: f64 = 5.0;

/// The inputs of a relief and what was built from them; it reads as its
/// inputs ([`PolyInputs`], through `Deref`).
#[derive(Clone)]
pub struct PolySpec {
    inputs: PolyInputs,
    built: Arc<(Relief, HeightRange, Option<Region>)>,
}

impl std::ops::Deref for PolySpec {
    type Target = PolyInputs;
    fn deref(&self) -> &PolyInputs {
        &self.inputs
    }
}

/// What the points describe (`shape.solid`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Solid {
    /// A relief: only its top envelope is meant (the face).
    Relief,
    /// A closed solid: T₁ > 0 all round it within the box (checked).
    Closed,
}

impl std::fmt::Debug for PolySpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PolySpec")
            .field("points", &self.points.len())
            .field("kernel", &self.kernel)
            .field("box", &(self.lo, self.hi))
            .field("per_edge", &self.per_edge)
            .field("origin", &self.origin)
            .field("size", &self.size)
            .field("base", &self.base)
            .field("solid", &self.solid)
            .finish()
    }
}

/// Specs are equal when their inputs are (the built parts follow from them).
impl PartialEq for PolySpec {
    fn eq(&self, o: &Self) -> bool {
        self.inputs == o.inputs
    }
}

/// The inputs of [`PolySpec::build`].
#[derive(Debug, Clone, PartialEq)]
pub struct PolyInputs {
    /// The given points.
    pub(crate) points: Vec<GivenPoint>,
    /// The load kernel.
    pub(crate) kernel: Kernel,
    /// The box.
    pub(crate) lo: Vector3<f64>,
    /// Upper corner.
    pub(crate) hi: Vector3<f64>,
    /// Elements per face edge.
    pub(crate) per_edge: usize,
    /// The rectangle.
    pub(crate) origin: [f64; 2],
    /// Its size.
    pub(crate) size: [f64; 2],
    /// The base height.
    pub(crate) base: f64,
    /// Relief or closed solid.
    pub(crate) solid: Solid,
}

impl PolySpec {
    /// Solves and builds the relief (module doc). Errors name the job key.
    pub(crate) fn build(i: PolyInputs) -> Result<PolySpec, PolyError> {
        let model = Model {
            lo: i.lo,
            hi: i.hi,
            per_edge: i.per_edge,
            kernel: i.kernel,
            points: i.points.clone(),
            quadrature: Quadrature::default(),
        };
        let sol = solve(&model)?;
        let region = match i.solid {
            Solid::Relief => None,
            Solid::Closed => {
                let r = Region::of(&i.points, i.kernel, &sol, i.per_edge)?;
                r.check_closed(&sol)?;
                Some(r)
            }
        };
        let zmax = i.points.iter().map(|p| p.p.z).fold(f64::MIN, f64::max);
        let start = zmax + 0.25 * (i.hi.z - zmax);
        if start <= i.base + RAY_STEP {
            return Err(invalid("shape.base", PolyFault::BaseTooHigh { zmax }));
        }
        let [ox, oy] = i.origin;
        let lo = Vector3::new(ox, oy, i.base - RAY_STEP);
        let hi = Vector3::new(ox + i.size[0], oy + i.size[1], start);
        let side = (i.hi - i.lo).min() / i.per_edge as f64;
        let fast = FastField::new(sol, lo, hi, side / NODES_PER_ELEMENT, 4)?;
        let spec = ReliefSpec {
            origin: i.origin,
            size: i.size,
            base: i.base,
            start,
            step: RAY_STEP,
            coarse: COARSE,
        };
        let relief = Relief::new(fast, spec)?;
        let range = height_range(&relief);
        Ok(PolySpec {
            inputs: i,
            built: Arc::new((relief, range, region)),
        })
    }

    /// As [`PolySpec::build`], reusing the result for inputs equal to one
    /// of the last [`CACHE`] built (a job is resolved, then run, simulated
    /// and meshed from the same inputs; the build is deterministic, so a
    /// cached spec is the one a new build would make).
    pub(crate) fn build_cached(i: PolyInputs) -> Result<PolySpec, PolyError> {
        use std::sync::Mutex;
        static BUILT: Mutex<Vec<PolySpec>> = Mutex::new(Vec::new());
        if let Ok(cache) = BUILT.lock() {
            if let Some(s) = cache.iter().find(|s| s.inputs == i) {
                return Ok(s.clone());
            }
        }
        let spec = Self::build(i)?;
        if let Ok(mut cache) = BUILT.lock() {
            if cache.len() >= CACHE {
                cache.remove(0);
            }
            cache.push(spec.clone());
        }
        Ok(spec)
    }

    /// The relief.
    pub fn relief(&self) -> &Relief {
        &self.built.0
    }

    /// The closed solid's surface T₁ = 0 on a grid at most `spacing` mm
    /// apart, in the points' coordinates (`closed::closed_mesh`); None for
    /// a relief.
    pub(crate) fn closed_mesh(&self, spacing: f64) -> Option<Result<IsoMesh, PolyError>> {
        let region = self.built.2?;
        let sol = self.relief().field().solution();
        Some(closed_mesh(sol, self.per_edge, region, spacing))
    }

    /// max h (and where, relative to the origin) and min h = base.
    pub fn range(&self) -> HeightRange {
        self.built.1
    }
}

/// max h by the best coarse ray and a pattern search (module doc).
fn height_range(r: &Relief) -> HeightRange {
    let s = *r.spec();
    let inside = |p: [f64; 2]| p[0] >= 0.0 && p[1] >= 0.0 && p[0] <= s.size[0] && p[1] <= s.size[1];
    let (mut best, mut hbest) = ([0.0, 0.0], f64::MIN);
    for (p, h) in r.coarse_rays() {
        if h > hbest {
            (best, hbest) = (p, h);
        }
    }
    let mut step = s.coarse;
    for _ in 0..10_000 {
        if step <= 1e-7 {
            break;
        }
        let mut moved = false;
        for d in [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]] {
            let q = [best[0] + step * d[0], best[1] + step * d[1]];
            if inside(q) {
                let h = r.height(q[0], q[1]);
                if h > hbest {
                    (best, hbest, moved) = (q, h, true);
                }
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    HeightRange {
        min: s.base,
        max: hbest.max(s.base),
        argmin: [0.0, 0.0],
        argmax: best,
    }
}
