//! `pfcam run A.toml B.toml ...`: a shop's batch. The jobs run in parallel on
//! the machine's cores (each job's own parallel stages share the same pool), a
//! failing job does not stop the others, and one table ends the run. Jobs are
//! independent files, so a larger batch is spread over several machines with
//! the scheduler a shop already has (docs/architecture.md).

use super::{cmd_run, exit_code, load, message, stdout_line, Done, EXIT_FAILED};
use anyhow::{bail, Result};
use pfcam::gcode::format_duration;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One job's outcome: what it made, or its error (message and exit status).
struct Outcome {
    path: PathBuf,
    seconds: f64,
    result: std::result::Result<Done, (String, u8)>,
}

/// Run every job; the error, if any, says how many failed and carries the
/// worst exit status of the failures.
pub fn run_all(
    jobs: &[PathBuf],
    out_dir: &Path,
    force: bool,
    quiet: bool,
    field_image: bool,
) -> Result<()> {
    refuse_shared_outputs(jobs)?;
    let outcomes: Vec<Outcome> = jobs
        .par_iter()
        .map(|path| {
            let t0 = Instant::now();
            let result = cmd_run(path, out_dir, force, true, field_image)
                .map_err(|e| (message(&e), exit_code(&e)));
            Outcome {
                path: path.clone(),
                seconds: t0.elapsed().as_secs_f64(),
                result,
            }
        })
        .collect();
    if !quiet {
        stdout_line(&table(&outcomes))?;
    }
    let failed: Vec<&Outcome> = outcomes.iter().filter(|o| o.result.is_err()).collect();
    if failed.is_empty() {
        return Ok(());
    }
    let worst = failed
        .iter()
        .filter_map(|o| o.result.as_ref().err().map(|e| e.1))
        .max()
        .unwrap_or(EXIT_FAILED);
    Err(BatchFailed {
        failed: failed.len(),
        total: outcomes.len(),
        code: worst,
    }
    .into())
}

/// Some jobs of a batch failed; `code` is the worst of their exit statuses.
#[derive(Debug, thiserror::Error)]
#[error("{failed} of {total} jobs failed (see the table)")]
pub struct BatchFailed {
    failed: usize,
    total: usize,
    /// The exit status to end with.
    pub code: u8,
}

/// Two jobs of one batch with the same name would write the same files.
fn refuse_shared_outputs(jobs: &[PathBuf]) -> Result<()> {
    let mut names: Vec<(String, &PathBuf)> = Vec::new();
    for path in jobs {
        // A job that does not load fails in the run, with its own message.
        let Ok(job) = load(path) else { continue };
        if let Some((_, other)) = names.iter().find(|(n, _)| *n == job.name) {
            bail!(
                "{} and {} are both job {:?}: they would write the same files (give one a [job] name)",
                other.display(),
                path.display(),
                job.name
            );
        }
        names.push((job.name, path));
    }
    Ok(())
}

/// The table that ends a batch: job, levels, machining time, warnings, compute
/// time and status, one row a job in the order given.
fn table(outcomes: &[Outcome]) -> String {
    let mut s = format!(
        "{:<28} {:>6} {:>10} {:>8} {:>9}  status",
        "job", "levels", "machining", "warnings", "compute"
    );
    for o in outcomes {
        let file = o.path.display().to_string();
        let row = match &o.result {
            Ok(d) => format!(
                "{:<28} {:>6} {:>10} {:>8} {:>8.1}s  ok: {}.nc",
                d.name,
                d.levels,
                format_duration(d.machining_s),
                d.warnings,
                o.seconds,
                d.name
            ),
            Err((m, code)) => format!(
                "{:<28} {:>6} {:>10} {:>8} {:>8.1}s  failed (exit {code}): {m}",
                file, "-", "-", "-", o.seconds
            ),
        };
        s += "\n";
        s += &row;
    }
    s
}
