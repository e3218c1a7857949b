//! What `pfcam stream` says after a failed stream: the error, the state the
//! machine was left in, and how to resume.

use pfcam::gcode::parse::Program;
use pfcam::grbl::{GrblError, StreamOptions};

/// What `pfcam stream` prints after a failed stream, line by line: the error, what
/// state the machine was left in, and how to resume. For a rejected line it names
/// that line (number and text as in the file) and the line to resume at once it is
/// fixed, not the last acknowledged line (which follows the rejected one).
pub fn stop_advice(e: &GrblError, opts: &StreamOptions, program: Option<&Program>) -> Vec<String> {
    let line_text = |n: usize| {
        program
            .and_then(|p| p.lines.get(n.wrapping_sub(1)))
            .map(|l| l.raw.trim().to_string())
            .unwrap_or_default()
    };
    let resume_cmd = |n: usize| {
        format!(
            "pfcam stream {} --port {} --from-line {n}",
            opts.file.display(),
            opts.port
        )
    };
    let mut out = vec![format!("error: {e}")];
    if let GrblError::CheckFailed { faults } = e {
        out.extend(faults.iter().map(|f| format!("  {f}")));
        if opts.check_first {
            out.push("nothing was streamed: fix these lines first".into());
        }
    }
    if matches!(e, GrblError::Rejected { .. } | GrblError::Aborted { .. }) {
        out.push(
            "the machine was stopped with a feed hold and, once the hold was complete \
             (Hold:0), a soft reset: spindle and coolant are off, GRBL is idle and keeps \
             its position (GRBL 1.1 raises ALARM:3 only when reset while still moving, \
             i.e. if the hold did not complete within 10 s: then home with `$H`)"
                .into(),
        );
    }
    if let GrblError::Alarm { .. } = e {
        out.push(
            "GRBL has stopped and locks out G-code until it is unlocked (`$X`) or homed (`$H`)"
                .into(),
        );
    }
    if let GrblError::Rejected {
        fault, resume_from, ..
    } = e
    {
        if fault.line == 0 {
            out.push(format!(
                "the rejected line is pfcam's resume preamble `{}`, not a file line",
                fault.text
            ));
        } else {
            out.push(format!(
                "rejected: line {}: `{}`",
                fault.line,
                line_text(fault.line)
            ));
        }
        match resume_from {
            Some(n) if *n == fault.line => out.push(format!(
                "every move before it had run; after fixing line {}, resume there: {}",
                fault.line,
                resume_cmd(*n)
            )),
            Some(n) => out.push(format!(
                "lines {n} to {} were still in GRBL's planner and did not run; after fixing \
                 line {}, resume at line {n} (`{}`): {}",
                fault.line.saturating_sub(1).max(*n),
                fault.line,
                line_text(*n),
                resume_cmd(*n)
            )),
            None => out.push(format!(
                "moves from the start of the job may not have run; after fixing line {}, \
                 restart the job from the beginning",
                fault.line
            )),
        }
        return out;
    }
    if let Some(resume) = e.resume_from() {
        match e.last_acked() {
            Some(n) => out.push(format!(
                "last line acknowledged by GRBL: {n}: `{}`",
                line_text(n)
            )),
            None => out.push("no line of the file was acknowledged by GRBL".into()),
        }
        match resume {
            Some(n) => out.push(format!(
                "lines from {n} on may not have been (fully) executed; to resume after \
                 fixing the cause: {}",
                resume_cmd(n)
            )),
            None => out.push("to resume, restart the job from the beginning".into()),
        }
    }
    out
}
