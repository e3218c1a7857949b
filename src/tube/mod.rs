//! A PDE tube job (`shape.kind = "pde-tube"`) through the pipeline: the
//! tube's horizontal sections ([`PdeTube`], docs/method.md §16.3) go
//! through the level planner unchanged (the schedule, each level's MFS solve
//! on its section and its rings, linking, arcs and the gouge check of every
//! level against its section), as a boss's, or as a cavity's for the mould.
//! The stock top is the tube's top; its depth is `shape.height`. With
//! `[finish]` a ring of the finishing tool follows each section ([`rings`]).

pub(crate) mod mesh;
mod mesh_slot;
pub(crate) mod ring_contacts;
pub(crate) mod rings;

use crate::count::{set_stage, Stage};
use crate::geometry::{polygons_bbox, Vec2};
use crate::job::Job;
use crate::levels::sections::Sections;
use crate::pipeline::{
    job_shape, run_sections, Internal, PipelineError, Progress, RunOutput, SectionsPart,
    OUTER_RADIUS_FACTOR,
};
use crate::sources::pde_tube::spec::TubeSpec;
use crate::sources::pde_tube::{PdeTube, TubeKind};

/// The tube's sections for a job (its spec's kind and tolerance are the
/// job's; the job's resolve has built it once, so an error here is a bug).
pub(crate) fn tube_sections(spec: &TubeSpec) -> Result<PdeTube, PipelineError> {
    Ok(spec.tube().map_err(Internal::Tube)?)
}

/// The height of the widest section, relative to the top: a boss's foot,
/// a mould's rim.
fn widest_z(tube: &PdeTube) -> f64 {
    match tube.kind() {
        TubeKind::Boss => tube.z_range().0,
        TubeKind::Mould => tube.z_range().1,
    }
}

/// The stock rectangle of a tube job: the widest section's bounding box
/// grown by `stock.margin` (what the level planner computes, from the same
/// section).
pub(crate) fn tube_stock(job: &Job, tube: &PdeTube) -> (Vec2, Vec2) {
    let m = Vec2::new(job.stock.margin, job.stock.margin);
    let (lo, hi) = polygons_bbox(&tube.section(widest_z(tube))).unwrap_or((Vec2::ZERO, Vec2::ZERO));
    (lo - m, hi + m)
}

/// Rough a tube by levels.
pub(crate) fn run_tube(
    job: &Job,
    spec: &TubeSpec,
    progress: &mut dyn FnMut(Progress),
) -> Result<RunOutput, PipelineError> {
    set_stage(Stage::ShapeSolve);
    // The widest end curve: the part seen from above, for the preview and report.
    let shape = job_shape(job, progress)?;
    let tube = tube_sections(spec)?;
    let (lo, hi) = tube_stock(job, &tube);
    let part = SectionsPart {
        source: &tube,
        cavity: tube.kind() == TubeKind::Mould,
        outer_radius: OUTER_RADIUS_FACTOR * (hi - lo).norm(),
        name: "tube",
        finish_stage: "finishing rings",
    };
    let mut finish = |f: &crate::job::Finish| finish_tube(job, f, &tube);
    run_sections(job, shape, part, &mut finish, progress)
}

/// The finishing program: a ring along each section ([`rings`]) against
/// the part's mesh at `pipeline::FINISH_MESH`.
fn finish_tube(
    job: &Job,
    f: &crate::job::Finish,
    tube: &PdeTube,
) -> Result<crate::finish::Finished, PipelineError> {
    let fine = crate::pipeline::FINISH_MESH;
    let stock = tube_stock(job, tube);
    let s = mesh::tube_mesh(tube, job.stock.top, fine, stock).map_err(Internal::from)?;
    let tris = s.mesh.up_triangles();
    let area = crate::finish::wall_area(&tris);
    let index = crate::pipeline::finish_index(tris)?;
    let contacts = ring_contacts::Rings::new(tube, tube.points(), f.radius())?;
    let part = rings::RingPart {
        tube,
        mesh: &index,
        area,
        top: job.stock.top,
        rings: &contacts,
    };
    Ok(rings::ring_finish(job, f, &part)?)
}

/// The tube's part as a closed mesh at `resolution` mm (`pfcam surface`).
pub(crate) fn tube_surface(
    job: &Job,
    spec: &TubeSpec,
    resolution: f64,
) -> Result<crate::surface::Surface, PipelineError> {
    let tube = tube_sections(spec)?;
    let stock = tube_stock(job, &tube);
    Ok(mesh::tube_mesh(&tube, job.stock.top, resolution, stock).map_err(Internal::from)?)
}

/// The part for `simulate`: the mesh's up-facing triangles (the tube's
/// wall and caps, and the floor or slab top round it).
pub(crate) fn tube_part_triangles(
    job: &Job,
    spec: &TubeSpec,
    resolution: f64,
) -> Result<Vec<[[f64; 3]; 3]>, PipelineError> {
    let s = tube_surface(job, spec, resolution)?;
    let m = &s.mesh;
    Ok(m.up_triangles())
}
