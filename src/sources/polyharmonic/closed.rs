//! The closed solid {T₁ < 0} as a mesh: its surface T₁ = 0 by marching
//! tetrahedra ([`super::iso`]) over a region round the given points.
//!
//! The region is the bounding box of the surface and inside points grown on
//! every side by a quarter of its largest extent plus the ball radius A,
//! then cut to the box shrunk by one element side (the field's interpolant
//! needs a margin from the box faces, and near them the constant elements'
//! field is rough). On it T₁ is the [`FastField`] (the box's part
//! interpolated on nodes a fifth of an element side apart, the loads' part
//! exact: within about 1e-5 of the full sum, docs/method.md §17). A solid is
//! *closed* when T₁ > 0 on the region's boundary: [`Region::check_closed`]
//! samples it coarsely when the job is resolved, and the mesher checks every
//! boundary node of its grid.

use super::error::{invalid, PolyError};
use super::fast::FastField;
use super::fault::PolyFault;
use super::iso::{zero_set, Grid3, IsoError, IsoMesh};
use super::system::{GivenPoint, PointKind, Solution};
use super::Kernel;
use nalgebra::Vector3;
use rayon::prelude::*;

/// Samples per region edge of the boundary check at resolve time.
pub(crate) const CHECK_SAMPLES: usize = 24;

/// Interpolation nodes per smallest element side (as the relief's).
const NODES_PER_ELEMENT: f64 = 5.0;

/// The region searched for the closed solid, mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    /// Lower corner.
    pub lo: Vector3<f64>,
    /// Upper corner.
    pub hi: Vector3<f64>,
}

/// The smallest element side of the box, mm.
fn element_side(sol: &Solution, per_edge: usize) -> f64 {
    (sol.mesh().hi - sol.mesh().lo).min() / per_edge as f64
}

impl Region {
    /// The region of the module doc; an error (`shape.box`) when it is
    /// empty after the cut.
    pub fn of(
        points: &[GivenPoint],
        kernel: Kernel,
        sol: &Solution,
        per_edge: usize,
    ) -> Result<Region, PolyError> {
        let mut lo = Vector3::repeat(f64::INFINITY);
        let mut hi = Vector3::repeat(f64::NEG_INFINITY);
        for g in points.iter().filter(|g| g.kind != PointKind::Outside) {
            lo = lo.inf(&g.p);
            hi = hi.sup(&g.p);
        }
        let a = match kernel {
            Kernel::T2A { a } | Kernel::T1A { a } => a,
            _ => 0.0,
        };
        let pad = 0.25 * (hi - lo).max() + a;
        let side = element_side(sol, per_edge);
        let lo = (lo - Vector3::repeat(pad)).sup(&(sol.mesh().lo + Vector3::repeat(side)));
        let hi = (hi + Vector3::repeat(pad)).inf(&(sol.mesh().hi - Vector3::repeat(side)));
        if (0..3).any(|k| hi[k] <= lo[k]) {
            return Err(invalid("box", PolyFault::NoRoom));
        }
        Ok(Region { lo, hi })
    }

    /// T₁ (exact) > 0 at [`CHECK_SAMPLES`]² points on each face of the
    /// region, else an error naming `shape.solid`.
    pub fn check_closed(&self, sol: &Solution) -> Result<(), PolyError> {
        let n = CHECK_SAMPLES;
        let at = |face: usize, i: usize, j: usize| {
            let (axis, end) = (face / 2, face % 2);
            let (u, v) = (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64);
            let mut t = Vector3::zeros();
            t[axis] = end as f64;
            t[(axis + 1) % 3] = u;
            t[(axis + 2) % 3] = v;
            self.lo + (self.hi - self.lo).component_mul(&t)
        };
        let worst = (0..6 * n * n)
            .into_par_iter()
            .map(|k| {
                let p = at(k / (n * n), k % n, k / n % n);
                (sol.value(p).unwrap_or(f64::NAN), p)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match worst {
            Some((v, p)) if v.is_nan() || v <= 0.0 => Err(not_closed(self, p, v)),
            _ => Ok(()),
        }
    }
}

/// The error for a solid that reaches the region's boundary.
fn not_closed(r: &Region, p: Vector3<f64>, v: f64) -> PolyError {
    invalid(
        "shape.solid",
        PolyFault::NotClosed {
            region: *r,
            at: p,
            t1: v,
        },
    )
}

/// Coarse cells per largest region edge of the first pass of
/// [`closed_mesh`].
pub(crate) const COARSE_CELLS: f64 = 40.0;

/// The surface T₁ = 0 over `region` on a grid at most `spacing` apart:
/// closed, facing out, in the points' coordinates. Two passes: T₁ on a
/// coarse grid over the region (at most [`COARSE_CELLS`] cells an edge, and
/// no finer than `spacing`) finds the box of its inside nodes; the fine grid
/// covers that box grown by two coarse cells (within the region), so a
/// piece of the solid that falls between the coarse nodes and lies more
/// than two cells from the rest is not meshed. Errors: `shape.solid` (not
/// closed, or no coarse node inside), `resolution` (more than
/// `iso::MAX_NODES` fine nodes), `box` (the fast field).
pub fn closed_mesh(
    sol: &Solution,
    per_edge: usize,
    region: Region,
    spacing: f64,
) -> Result<IsoMesh, PolyError> {
    let side = element_side(sol, per_edge);
    let fast = FastField::new(
        sol.clone(),
        region.lo,
        region.hi,
        side / NODES_PER_ELEMENT,
        4,
    )?;
    let f = |x: Vector3<f64>| fast.value(x);
    let coarse_step = ((region.hi - region.lo).max() / COARSE_CELLS).max(spacing);
    let coarse = Grid3::covering(region.lo, region.hi, coarse_step)
        .ok_or_else(|| too_fine(&region, coarse_step))?;
    let (lo, hi) = (0..coarse.len())
        .into_par_iter()
        .map(|id| (id, f(coarse.node(id))))
        .filter(|(_, v)| *v < 0.0)
        .map(|(id, _)| (coarse.node(id), coarse.node(id)))
        .reduce_with(|a, b| (a.0.inf(&b.0), a.1.sup(&b.1)))
        .ok_or_else(|| invalid("shape.solid", PolyFault::EmptySolid { step: coarse_step }))?;
    let grow = Vector3::repeat(2.0 * coarse_step);
    let fine = Region {
        lo: (lo - grow).sup(&region.lo),
        hi: (hi + grow).inf(&region.hi),
    };
    let grid =
        Grid3::covering(fine.lo, fine.hi, spacing).ok_or_else(|| too_fine(&fine, spacing))?;
    zero_set(&grid, &f).map_err(|e| match e {
        IsoError::Open { at, value } => not_closed(&region, at.into(), value),
        source @ IsoError::NotFinite { .. } => PolyError::ZeroSet { source },
    })
}

/// The error for a grid of too many nodes.
fn too_fine(r: &Region, spacing: f64) -> PolyError {
    invalid(
        "resolution",
        PolyFault::TooFine {
            spacing,
            region: *r,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sources::polyharmonic::system::{solve, tests::sphere_model};

    /// A region that cuts the solid: the coarse check and the mesher both
    /// refuse it, naming `shape.solid`.
    #[test]
    fn a_solid_cut_by_the_region_is_not_closed() {
        let model = sphere_model(4);
        let sol = solve(&model).unwrap();
        let cut = Region {
            lo: Vector3::repeat(-0.6),
            hi: Vector3::repeat(0.6),
        };
        let e = cut.check_closed(&sol).unwrap_err().to_string();
        assert!(e.starts_with("shape.solid: "), "{e}");
        let e = closed_mesh(&sol, 4, cut, 0.1).unwrap_err().to_string();
        assert!(e.starts_with("shape.solid: "), "{e}");
    }
}
