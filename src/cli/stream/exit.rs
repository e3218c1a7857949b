//! The exit status of `pfcam stream`: one code per kind of outcome
//! (docs/grbl.md, "Exit codes").

use std::process::ExitCode;

use pfcam::grbl::{GrblError, StreamReport};

/// Exit codes of `pfcam stream` (documented in `docs/grbl.md`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum ExitStatus {
    /// 0: every line sent and acknowledged, machine idle (or check mode clean).
    Completed = 0,
    /// 2: the file or the arguments are unusable (unreadable, line too long,
    /// `--from-line` impossible).
    BadInput = 2,
    /// 3: no GRBL: port cannot be opened, no banner, no answer to a command.
    Connection = 3,
    /// 4: GRBL rejected lines (`error:N`: stopped, or listed with
    /// `--continue-on-error`, or found by `--check`/`--check-first`).
    GrblError = 4,
    /// 5: GRBL is in alarm (at connect or mid-job).
    Alarm = 5,
    /// 6: the operator aborted.
    Aborted = 6,
    /// 7: the link died mid-job (port gone, GRBL silent, GRBL reset itself,
    /// acknowledgements lost).
    LinkLost = 7,
}

impl ExitStatus {
    /// The exit status for an outcome.
    pub fn of(outcome: &Result<StreamReport, GrblError>) -> ExitStatus {
        match outcome {
            Ok(r) if r.faults.is_empty() => ExitStatus::Completed,
            Ok(_) => ExitStatus::GrblError,
            Err(e) => match e {
                GrblError::Input(_) => ExitStatus::BadInput,
                GrblError::Open { .. } | GrblError::NoGrbl { .. } | GrblError::Command { .. } => {
                    ExitStatus::Connection
                }
                GrblError::Rejected { .. } | GrblError::CheckFailed { .. } => ExitStatus::GrblError,
                GrblError::Alarm { .. } | GrblError::AlarmAtConnect { .. } => ExitStatus::Alarm,
                GrblError::Aborted { .. } => ExitStatus::Aborted,
                GrblError::LinkLost { .. }
                | GrblError::Unresponsive { .. }
                | GrblError::Stalled { .. }
                | GrblError::UnexpectedReset { .. } => ExitStatus::LinkLost,
            },
        }
    }
}

impl From<ExitStatus> for ExitCode {
    fn from(s: ExitStatus) -> ExitCode {
        ExitCode::from(s as u8)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pfcam::grbl::InputFault;

    #[test]
    fn every_outcome_has_a_distinct_exit_code() {
        let outcomes = [
            Ok(StreamReport::default()),
            Err(GrblError::Input(InputFault::ResumeNoFeed { line: 1 })),
            Err(GrblError::NoGrbl {
                port: "p".into(),
                heard: String::new(),
            }),
            Err(GrblError::CheckFailed { faults: Vec::new() }),
            Err(GrblError::Alarm {
                code: 1,
                last_acked: None,
                resume_from: None,
            }),
            Err(GrblError::Aborted {
                by: "aborted by the operator",
                last_acked: None,
                resume_from: None,
            }),
            Err(GrblError::LinkLost {
                reason: String::new(),
                last_acked: None,
                resume_from: None,
            }),
        ];
        let codes: Vec<u8> = outcomes.iter().map(|o| ExitStatus::of(o) as u8).collect();
        assert_eq!(codes, [0, 2, 3, 4, 5, 6, 7]);
    }
}
