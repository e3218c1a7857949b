//! A closed polyharmonic solid's own surface as `pfcam surface` writes it
//! (`shape.solid = "closed"`): T₁ = 0 meshed by marching tetrahedra
//! (`sources::polyharmonic::closed`), placed as the milled part is: x, y as
//! given, z shifted so that max h (the top envelope's highest point) is at
//! `stock.top`. The milled part is still the block under the envelope
//! (`simulate` and the finisher read that one, `super::patch_part_triangles`).

use super::{patch_stock, placement, HeightSource};
use crate::job::Job;
use crate::sources::polyharmonic::PolySpec;
use crate::surface::{Mesh, Surface, SurfaceError};

/// The closed solid's mesh at `resolution` mm (a grid of that spacing over
/// the region round the points), or None for a relief.
pub(crate) fn closed_surface(
    job: &Job,
    spec: &PolySpec,
    resolution: f64,
) -> Option<Result<Surface, SurfaceError>> {
    let built = spec.closed_mesh(resolution)?;
    Some(built.map_err(SurfaceError::from).map(|iso| {
        let mut mesh = Mesh {
            vertices: iso.vertices,
            triangles: iso.triangles,
        };
        let dz = placement(job).top - spec.range().max;
        for v in &mut mesh.vertices {
            v[2] += dz;
        }
        let (stock_lo, stock_hi) = patch_stock(job, HeightSource::Poly(spec));
        let z_bottom = mesh.bbox().map_or(dz, |b| b.0[2]);
        let cells = |k: usize| ((spec.size[k] / resolution).ceil() as usize).max(1) + 1;
        Surface {
            mesh,
            stock_lo,
            stock_hi,
            z_bottom,
            levels: Vec::new(),
            crossings: Vec::new(),
            grid: (cells(0), cells(1)),
        }
    }))
}
