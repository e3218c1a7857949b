//! Streaming G-code to a GRBL 1.1 controller over a serial link (`pfcam stream`).
//!
//! - [`protocol`]: GRBL's lines and real-time bytes.
//! - [`link`]: any byte stream (a serial port, an in-memory fake), a reader
//!   thread, the traffic log.
//! - [`streamer`]: connect (banner, soft reset, alarm check), character-counting
//!   streaming, status polling, feed hold / resume / abort, check mode, resume from a
//!   line.
//! - [`options`] and [`session`]: what one `pfcam stream` asks for
//!   ([`StreamOptions`]) and the whole flow ([`run_stream`]).
//!
//! Nothing here prints or exits: progress and GRBL's messages go to an
//! [`Observer`] as [`Event`]s, the outcome is a [`StreamReport`] or a
//! [`GrblError`]. The terminal side of `pfcam stream` (flags, progress bar,
//! Ctrl-C prompt, signals, exit codes) is the binary's, in `src/cli/stream/`.
//!
//! The protocol as implemented and the safety behaviour are described in
//! `docs/grbl.md`.

pub mod codes;
#[cfg(test)]
mod fake;
mod fault;
pub mod link;
pub mod options;
pub mod protocol;
pub mod session;
pub mod streamer;

pub use fault::InputFault;
pub use link::Link;
pub use options::StreamOptions;
pub use session::{job_blocks, run_stream};
pub use streamer::{
    Block, Event, Fault, Observer, OperatorCommand, Settings, StreamReport, Streamer,
};

/// Why a stream did not complete. Every variant that can happen mid-job says which
/// file line GRBL acknowledged last (`None`: none yet, or only pfcam's own lines).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GrblError {
    /// The port could not be opened.
    #[error("cannot open {port}: {reason}")]
    Open {
        /// Port path.
        port: String,
        /// What the OS said.
        reason: String,
    },
    /// Nothing GRBL-like answered, even after a soft reset.
    #[error("no GRBL answered on {port} (no banner, even after a soft reset); {heard}")]
    NoGrbl {
        /// Port path.
        port: String,
        /// What was received instead.
        heard: String,
    },
    /// GRBL is in alarm state at connect; pfcam does not unlock or home on its own.
    #[error("GRBL is in ALARM state{}: {advice}", code.map(|c| format!(" (ALARM:{c})")).unwrap_or_default())]
    AlarmAtConnect {
        /// The alarm number, if GRBL said it.
        code: Option<u8>,
        /// What to do.
        advice: String,
    },
    /// GRBL rejected a line and the stream was stopped (feed hold, soft reset).
    #[error("stopped: GRBL rejected {fault}")]
    Rejected {
        /// The rejected line.
        fault: Fault,
        /// Last line acknowledged with `ok`.
        last_acked: Option<usize>,
        /// First file line that may not have been fully executed: where
        /// `--from-line` should resume (conservative; `None`: from the start).
        resume_from: Option<usize>,
    },
    /// Check mode found errors (`--check`/`--check-first`).
    #[error("check mode: GRBL rejected {} line(s)", faults.len())]
    CheckFailed {
        /// Every rejected line.
        faults: Vec<Fault>,
    },
    /// GRBL raised an alarm: it has stopped and locks out G-code until `$X`/`$H`.
    #[error("ALARM:{code}: {}", codes::alarm_meaning(*code))]
    Alarm {
        /// The alarm number.
        code: u8,
        /// Last line acknowledged with `ok`.
        last_acked: Option<usize>,
        /// First file line that may not have been fully executed: where
        /// `--from-line` should resume (conservative; `None`: from the start).
        resume_from: Option<usize>,
    },
    /// The operator aborted (Ctrl-C → abort), or a signal stopped pfcam:
    /// feed hold, then soft reset. `by` says which, e.g. "aborted by the
    /// operator" or "aborted: pfcam received SIGTERM (...)".
    #[error("{by}")]
    Aborted {
        /// Who or what stopped the stream, as the message says it.
        by: &'static str,
        /// Last line acknowledged with `ok`.
        last_acked: Option<usize>,
        /// First file line that may not have been fully executed: where
        /// `--from-line` should resume (conservative; `None`: from the start).
        resume_from: Option<usize>,
    },
    /// The port failed or disappeared.
    #[error("serial link lost: {reason}")]
    LinkLost {
        /// What failed.
        reason: String,
        /// Last line acknowledged with `ok`.
        last_acked: Option<usize>,
        /// First file line that may not have been fully executed: where
        /// `--from-line` should resume (conservative; `None`: from the start).
        resume_from: Option<usize>,
    },
    /// GRBL stopped answering (not even status reports).
    #[error("GRBL stopped answering for {seconds:.1} s (not even status reports); feed hold and soft reset sent")]
    Unresponsive {
        /// How long it was silent.
        seconds: f64,
        /// Last line acknowledged with `ok`.
        last_acked: Option<usize>,
        /// First file line that may not have been fully executed: where
        /// `--from-line` should resume (conservative; `None`: from the start).
        resume_from: Option<usize>,
    },
    /// GRBL sat idle with empty buffers while lines were still unacknowledged:
    /// their `ok`s were lost on the way (noise on the cable), so character counting
    /// can never finish. Status reports still come, so this is not silence.
    #[error(
        "GRBL is idle with empty buffers but {unacked} line(s) were never acknowledged \
         (for {seconds:.1} s): acknowledgements were lost on the link; feed hold and soft \
         reset sent"
    )]
    Stalled {
        /// How long GRBL was idle with the lines outstanding.
        seconds: f64,
        /// Lines sent and never acknowledged.
        unacked: usize,
        /// Last line acknowledged with `ok`.
        last_acked: Option<usize>,
        /// First file line that may not have been fully executed: where
        /// `--from-line` should resume (conservative; `None`: from the start).
        resume_from: Option<usize>,
    },
    /// GRBL printed its banner mid-job: it was reset (reset button, power, brown-out).
    #[error("GRBL reset itself in the middle of the job (banner received)")]
    UnexpectedReset {
        /// Last line acknowledged with `ok`.
        last_acked: Option<usize>,
        /// First file line that may not have been fully executed: where
        /// `--from-line` should resume (conservative; `None`: from the start).
        resume_from: Option<usize>,
    },
    /// A system command (`$C`, `$X`) did not get the expected answer.
    #[error("`{command}` failed: {reason}")]
    Command {
        /// The command.
        command: String,
        /// What happened.
        reason: String,
    },
    /// The job cannot be sent as it is (line too long, `--from-line` impossible).
    #[error("{0}")]
    Input(#[source] InputFault),
}

impl GrblError {
    /// The last file line GRBL acknowledged, if the error carries one.
    pub fn last_acked(&self) -> Option<usize> {
        self.stop_point().map(|(l, _)| l).unwrap_or(None)
    }

    /// Where to resume with `--from-line`, if the error happened mid-job
    /// (`Some(None)`: from the start).
    pub fn resume_from(&self) -> Option<Option<usize>> {
        self.stop_point().map(|(_, r)| r)
    }

    fn stop_point(&self) -> Option<(Option<usize>, Option<usize>)> {
        match self {
            GrblError::Rejected {
                last_acked,
                resume_from,
                ..
            }
            | GrblError::Alarm {
                last_acked,
                resume_from,
                ..
            }
            | GrblError::Aborted {
                last_acked,
                resume_from,
                ..
            }
            | GrblError::LinkLost {
                last_acked,
                resume_from,
                ..
            }
            | GrblError::Unresponsive {
                last_acked,
                resume_from,
                ..
            }
            | GrblError::Stalled {
                last_acked,
                resume_from,
                ..
            }
            | GrblError::UnexpectedReset {
                last_acked,
                resume_from,
            } => Some((*last_acked, *resume_from)),
            _ => None,
        }
    }

    pub(crate) fn with_stop(self, last: Option<usize>, resume: Option<usize>) -> GrblError {
        match self {
            GrblError::LinkLost { reason, .. } => GrblError::LinkLost {
                reason,
                last_acked: last,
                resume_from: resume,
            },
            other => other,
        }
    }
}
