//! A height-field job (`shape.kind = "harmonic-bezier"`, a harmonic patch,
//! or `"polyharmonic"`, a solid's top envelope: [`HeightSource`]) through the
//! pipeline: the patch's sections ([`HeightFieldSections`]) go through the
//! level planner unchanged (the schedule, each level's MFS solve on its
//! section and rolling-disk rings, linking, arcs and the gouge check of every
//! level against its section), as a boss's. The stock top is max h; the
//! part's foot, min h, is `operation.depth` below it.

pub(crate) mod closed;
pub(crate) mod mesh;
pub(crate) mod raster;

use crate::count::{set_stage, Stage};
use crate::geometry::ShapeSource;
use crate::geometry::Vec2;
use crate::job::Job;
use crate::levels::height_field::HeightFieldSections;
use crate::pipeline::{
    job_shape, run_sections, PipelineError, Progress, RunOutput, SectionsPart, OUTER_RADIUS_FACTOR,
};
use crate::sources::harmonic_bezier::{HarmonicError, PatchSpec};
use crate::sources::polyharmonic::{PolySpec, Solid};

/// A shape source that is a height field over a rectangle.
#[derive(Clone, Copy, Debug)]
pub(crate) enum HeightSource<'a> {
    /// A harmonic Bézier patch.
    Bezier(&'a PatchSpec),
    /// A polyharmonic solid's top envelope.
    Poly(&'a PolySpec),
}

impl ShapeSource {
    /// The height field this source is, if it is one.
    pub(crate) fn height_source(&self) -> Option<HeightSource<'_>> {
        match self {
            ShapeSource::HarmonicBezier(s) => Some(HeightSource::Bezier(s)),
            ShapeSource::Polyharmonic(s) => Some(HeightSource::Poly(s)),
            _ => None,
        }
    }
}

impl HeightSource<'_> {
    /// The rectangle's lower-left corner, mm.
    pub(crate) fn origin(&self) -> Vec2 {
        match self {
            HeightSource::Bezier(s) => s.origin,
            HeightSource::Poly(s) => Vec2::new(s.origin[0], s.origin[1]),
        }
    }

    /// What the run summary calls the part (`glyphs: ...`, the preview's
    /// solve): `patch`, `polyharmonic relief` or `polyharmonic solid`
    /// (`shape.solid = "closed"`).
    pub(crate) fn label(&self) -> &'static str {
        match self {
            HeightSource::Bezier(_) => "patch",
            HeightSource::Poly(s) if s.solid == Solid::Closed => "polyharmonic solid",
            HeightSource::Poly(_) => "polyharmonic relief",
        }
    }

    /// The rectangle's size [X, Y], mm.
    pub(crate) fn size(&self) -> [f64; 2] {
        match self {
            HeightSource::Bezier(s) => s.size,
            HeightSource::Poly(s) => s.size,
        }
    }

    /// Its sections, chords within `CHORD_FRACTION` × `tol` (mm).
    pub(crate) fn sections(&self, tol: f64) -> Result<HeightFieldSections, HarmonicError> {
        match self {
            HeightSource::Bezier(s) => HeightFieldSections::new(s, tol),
            HeightSource::Poly(s) => Ok(HeightFieldSections::of_height(
                Box::new(s.relief().clone()),
                self.origin(),
                s.size,
                s.range(),
                tol,
            )),
        }
    }
}

/// The height field's sections for a job (chords within the job's tolerance).
pub(crate) fn patch_sections(
    job: &Job,
    spec: HeightSource<'_>,
) -> Result<HeightFieldSections, PipelineError> {
    // The job's resolve has built the patch once: an error here is a bug.
    let sections = spec.sections(job.operation.tolerance);
    Ok(sections.map_err(crate::pipeline::Internal::HeightField)?)
}

/// Rough a patch by levels (and finish it, with `[finish]`).
pub(crate) fn run_patch(
    job: &Job,
    spec: HeightSource<'_>,
    progress: &mut dyn FnMut(Progress),
) -> Result<RunOutput, PipelineError> {
    set_stage(Stage::ShapeSolve);
    // The rectangle: the part seen from above, for the preview and report.
    let shape = job_shape(job, progress)?;
    let source = patch_sections(job, spec)?;
    let [sx, sy] = spec.size();
    let part = SectionsPart {
        source: &source,
        cavity: false,
        outer_radius: OUTER_RADIUS_FACTOR * sx.hypot(sy),
        name: spec.label(),
        finish_stage: "finishing passes",
    };
    let mut finish = |f: &crate::job::Finish| finish_patch(job, spec, f, &source);
    run_sections(job, shape, part, &mut finish, progress)
}

/// The finishing program: the raster of [`raster`] against the part's
/// mesh at `pipeline::FINISH_MESH` (its top surface and the floor round it).
fn finish_patch(
    job: &Job,
    spec: HeightSource<'_>,
    f: &crate::job::Finish,
    source: &HeightFieldSections,
) -> Result<crate::finish::Finished, PipelineError> {
    let fine = crate::pipeline::FINISH_MESH;
    let tris = patch_part_triangles(job, spec, fine)?;
    let z_floor = placement(job).z_floor();
    // The top surface's area (the floor is flat and finished by the roughing).
    let area = tris
        .iter()
        .filter(|c| c.iter().any(|v| v[2] > z_floor + 1e-9))
        .map(crate::surface::triangle_area)
        .sum();
    let index = crate::pipeline::finish_index(tris)?;
    // A patch's floor is only round it; a relief's base is also its own flat
    // top between the rectangle's edges and the solid's rim, which the
    // levels leave stepped: the ball finishes it too, so only below the base
    // (the block's bottom, never under the cutter) is off the part.
    let off_part = match spec {
        HeightSource::Bezier(_) => z_floor,
        HeightSource::Poly(_) => placement(job).z_bottom(),
    };
    let part = raster::RasterPart {
        rect: source.rectangle_box(),
        max_slope_y: source.max_slope_y(),
        mesh: &index,
        z_floor: off_part,
        area,
        valleys: matches!(spec, HeightSource::Poly(_)),
    };
    Ok(raster::raster_finish(job, f, &part)?)
}

/// The stock rectangle of a patch job: the rectangle grown by `stock.margin`
/// (what the level planner computes from the bottom section, which is the
/// rectangle).
pub(crate) fn patch_stock(job: &Job, spec: HeightSource<'_>) -> (Vec2, Vec2) {
    let m = Vec2::new(job.stock.margin, job.stock.margin);
    let size = Vec2::new(spec.size()[0], spec.size()[1]);
    (spec.origin() - m, spec.origin() + size + m)
}

/// Where the part's heights go: max h at `stock.top`, `operation.depth`
/// (max h − min h) deep.
pub(crate) fn placement(job: &Job) -> mesh::Placement {
    mesh::Placement {
        top: job.stock.top,
        depth: job.operation.depth,
    }
}

/// The patch block as a closed mesh at `resolution` mm (`pfcam surface`).
pub(crate) fn patch_surface(
    job: &Job,
    spec: HeightSource<'_>,
    resolution: f64,
) -> Result<crate::surface::Surface, PipelineError> {
    let sections = patch_sections(job, spec)?;
    let stock = patch_stock(job, spec);
    Ok(mesh::patch_mesh(
        &sections,
        placement(job),
        resolution,
        stock,
    ))
}

/// The part for `simulate` and the finisher: the block's up-facing
/// triangles (its top surface) and the floor around it at min h, over the
/// stock rectangle.
pub(crate) fn patch_part_triangles(
    job: &Job,
    spec: HeightSource<'_>,
    resolution: f64,
) -> Result<Vec<[[f64; 3]; 3]>, PipelineError> {
    let s = patch_surface(job, spec, resolution)?;
    let m = &s.mesh;
    let mut tris = m.up_triangles();
    let size = Vec2::new(spec.size()[0], spec.size()[1]);
    tris.extend(mesh::floor_triangles(
        (spec.origin(), spec.origin() + size),
        (s.stock_lo, s.stock_hi),
        placement(job).z_floor(),
    ));
    Ok(tris)
}
