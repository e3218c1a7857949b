//! `pfcam stream`'s terminal side: the progress display, the Ctrl-C prompt and
//! typed overrides, signals, what is printed at the end and the exit status.
//! The streaming itself is the library's (`pfcam::grbl::run_stream`), which
//! prints nothing and reports through [`pfcam::grbl::Event`]s and its result.
//!
//! This module uses only `pfcam::` and outside crates (no `crate::`), so that
//! `tests/grbl/main.rs` can include it and check the exit codes and messages.

mod advice;
mod exit;
pub mod keys;
mod signals;
mod terminal;

pub use advice::stop_advice;
pub use exit::ExitStatus;

use std::io::{IsTerminal, Write};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::mpsc;
use std::sync::Arc;

use pfcam::grbl::{job_blocks, run_stream, GrblError, StreamOptions, StreamReport};

use keys::spawn_prompt_reader;
use signals::catch_signals;
use terminal::Terminal;

/// `pfcam stream`: streams, shows progress, handles Ctrl-C, returns the exit code.
pub fn stream_command(opts: &StreamOptions) -> ExitCode {
    let (tx, rx) = mpsc::channel();
    let held = Arc::new(AtomicBool::new(false));
    // The prompt (resume or abort after a hold) needs someone at a terminal.
    let interactive = std::io::stdin().is_terminal();
    let signals = match catch_signals(tx.clone(), held.clone(), interactive) {
        Ok(handle) => Some(handle),
        Err(e) => {
            note(&format!(
                "warning: cannot catch signals ({e}); Ctrl-C, SIGTERM or SIGHUP will kill \
                 pfcam without stopping the machine"
            ));
            None
        }
    };
    if interactive {
        spawn_prompt_reader(tx);
    }
    let mut ui = Terminal::new(held, interactive);
    let outcome = run_stream(opts, &rx, &mut ui);
    ui.finish();
    if let Some(handle) = signals {
        handle.close();
    }
    print_outcome(&outcome, opts);
    ExitStatus::of(&outcome).into()
}

/// What is printed once the stream has ended: the summary, or why it stopped
/// and how to resume.
fn print_outcome(outcome: &Result<StreamReport, GrblError>, opts: &StreamOptions) {
    match outcome {
        Ok(report) => {
            if !report.faults.is_empty() {
                note("lines GRBL rejected (not executed):");
                for f in &report.faults {
                    note(&format!("  {f}"));
                }
            }
            let what = if opts.check { "checked" } else { "sent" };
            note(&format!(
                "{what} {} lines in {:.1} s (mean receive-buffer fill {:.0}%){}",
                report.acked,
                report.elapsed.as_secs_f64(),
                report.mean_fill * 100.0,
                if report.faults.is_empty() {
                    String::new()
                } else {
                    format!(", {} rejected by GRBL", report.faults.len())
                }
            ));
        }
        Err(e) => {
            let program = job_blocks(opts).ok().map(|(p, _)| p);
            for line in stop_advice(e, opts, program.as_ref()) {
                note(&line);
            }
        }
    }
}

/// One line to stderr; a failed write is ignored (the terminal may be gone
/// after SIGHUP), where `eprintln!` would panic.
fn note(text: &str) {
    let _ = writeln!(std::io::stderr(), "{text}");
}
