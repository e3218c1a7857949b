//! The whole run: job → shape → field → tool path, with the gouge check.

use crate::job::Job;
use crate::toolpath::Toolpath;

/// One MFS solve, as reported to the user.
#[derive(Clone, Debug, PartialEq)]
pub struct SolveReport {
    /// What was solved (e.g. `MFS`, or a level).
    pub label: String,
    /// Singularities N (all of them).
    pub n: usize,
    /// Collocation points M.
    pub m: usize,
    /// Pseudo-boundary distance chosen, mm.
    pub distance: f64,
    /// Max boundary error |u − g| over the check points.
    pub max_error: f64,
}

/// What a run produces.
#[derive(Clone, Debug, PartialEq)]
pub struct RunOutput {
    /// The tool path.
    pub toolpath: Toolpath,
    /// One report per MFS solve.
    pub solves: Vec<SolveReport>,
    /// Smallest distance from any tool-centre position to the part, minus the tool
    /// radius, mm (≥ −tolerance, or the run fails).
    pub min_clearance: f64,
    /// Warnings for the user (e.g. a counter too small for the tool).
    pub warnings: Vec<String>,
    /// Region names in the shape.
    pub glyphs: Vec<String>,
}

/// Progress events for a front end's progress bar.
#[derive(Clone, Debug, PartialEq)]
pub enum Progress {
    /// A stage started; `total` steps follow.
    Stage {
        /// name
        name: String,
        /// steps
        total: u64,
    },
    /// One step of the current stage done.
    Step,
}

/// What can go wrong in a run.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The shape source is bad.
    #[error("shape: {0}")]
    Geometry(#[from] crate::geometry::GeometryError),
    /// Anything else (filled in as the stages land).
    #[error("{0}")]
    Other(String),
}

/// Run a job to a tool path.
pub fn run(job: &Job, progress: &mut dyn FnMut(Progress)) -> Result<RunOutput, PipelineError> {
    let _ = (job, progress);
    Err(PipelineError::Other("the pipeline is being built".into()))
}
