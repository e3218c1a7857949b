//! [`super::PipelineError::Internal`]'s causes: broken invariants of pfcam
//! itself, never the input's fault, each with what it holds.

use crate::sources::harmonic_bezier::HarmonicError;
use crate::sources::pde_tube::TubeError;
use crate::tube::mesh::TubeMeshError;

/// A broken invariant of pfcam (the message goes on with "this is a pfcam
/// bug, please report it").
#[derive(Debug, thiserror::Error)]
pub enum Internal {
    /// A boss or cavity job reached the planner without its `[profile]`
    /// (the job's checks require one).
    #[error("a boss or cavity job has no depth profile [profile]")]
    NoProfile,
    /// A thread of the level planner panicked.
    #[error("the level planner panicked")]
    PlannerPanicked,
    /// The level planner stopped without a result.
    #[error("the level planner did not finish")]
    PlannerUnfinished,
    /// A PDE tube that the job's resolve built once fails to build again.
    #[error("the PDE tube of a resolved job: {0}")]
    Tube(#[source] TubeError),
    /// A height field that the job's resolve built once fails to build again.
    #[error("the height field of a resolved job: {0}")]
    HeightField(#[source] HarmonicError),
    /// The finisher's mesh of the part had triangles the drop-cutter's index
    /// leaves out (a coordinate not finite): finishing without them could cut
    /// into the part there.
    #[error("{left_out} of the {total} triangles of the part's finishing mesh have a coordinate that is not finite")]
    FinishMeshLeftOut {
        /// Triangles left out.
        left_out: usize,
        /// Triangles in the mesh.
        total: usize,
    },
    /// The tube's part could not be meshed.
    #[error(transparent)]
    TubeMesh(#[from] TubeMeshError),
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::PipelineError;

    /// What the strings said: the cause's text inside the bug report's words.
    #[test]
    fn internal_errors_say_what_the_strings_said() {
        let said = |e: Internal| PipelineError::from(e).to_string();
        let bug =
            |what: &str| format!("internal error: {what} (this is a pfcam bug, please report it)");
        let tube = TubeError::NotMonotone { z: -1.5, u: 0.25 };
        let text = format!("the PDE tube of a resolved job: {tube}");
        assert_eq!(said(Internal::Tube(tube)), bug(&text));
        let patch = HarmonicError::DegreeTooLow { degree: 0 };
        let text = format!("the height field of a resolved job: {patch}");
        assert_eq!(said(Internal::HeightField(patch)), bug(&text));
        let mesh = TubeMeshError::WindsTwice;
        let text = mesh.to_string();
        assert_eq!(said(mesh.into()), bug(&text));
        assert_eq!(
            said(Internal::PlannerUnfinished),
            bug("the level planner did not finish")
        );
    }
}
