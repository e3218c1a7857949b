//! Why a job cannot be sent as it is ([`GrblError::Input`](super::GrblError::Input)):
//! one variant per cause, holding what its message quotes. The OS's words
//! (a file that cannot be read) stay text: they are data, not a cause of
//! pfcam's.

use crate::gcode::parse::LineError;
use std::path::PathBuf;

/// What is wrong with the job or the options before anything is sent.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InputFault {
    /// The G-code file could not be read.
    #[error("cannot read {}: {reason}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// What the OS said.
        reason: String,
    },
    /// The traffic log could not be created.
    #[error("cannot create log {}: {reason}", path.display())]
    Log {
        /// The log file.
        path: PathBuf,
        /// What the OS said.
        reason: String,
    },
    /// A block longer than GRBL's line (or receive) buffer.
    #[error("line {line}: {chars} characters after stripping comments and spaces; GRBL takes at most {most} per line")]
    LineTooLong {
        /// The file line, from 1.
        line: usize,
        /// The block's characters.
        chars: usize,
        /// The most GRBL takes (its buffer less the newline).
        most: usize,
    },
    /// A block with non-ASCII or control characters.
    #[error("line {line}: contains non-ASCII or control characters")]
    NotAscii {
        /// The file line, from 1.
        line: usize,
    },
    /// `--from-line` past the file's lines (or 0).
    #[error("--from-line {line}: the file has lines 1 to {last}")]
    ResumeOutside {
        /// The line asked for.
        line: usize,
        /// The file's last line.
        last: usize,
    },
    /// The modal state before `--from-line` cannot be computed.
    #[error("--from-line {line}: cannot compute the state: {error}")]
    ResumeState {
        /// The line asked for.
        line: usize,
        /// The program's error before it.
        #[source]
        error: LineError,
    },
    /// No Z move before `--from-line` and no `--safe-z`.
    #[error("--from-line {line}: no Z move before this line; give --safe-z")]
    ResumeNoSafeZ {
        /// The line asked for.
        line: usize,
    },
    /// An axis position not known before `--from-line`.
    #[error("--from-line {line}: the {axis} position before this line is not known (set by G28/G30/G53/G10 or never set)")]
    ResumePosition {
        /// The line asked for.
        line: usize,
        /// The axis: `X`, `Y` or `Z`.
        axis: char,
    },
    /// No feed rate before `--from-line`.
    #[error("--from-line {line}: no feed rate (F) is set before this line")]
    ResumeNoFeed {
        /// The line asked for.
        line: usize,
    },
    /// The program ends before `--from-line`.
    #[error("--from-line {line}: the program has already ended (M2/M30) before this line")]
    ResumeEnded {
        /// The line asked for.
        line: usize,
    },
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gcode::parse::BlockError;

    /// The texts are the ones the causes had as strings (the `format!`s
    /// below are the old call sites'), and a state the program cannot
    /// compute keeps the program's error as its source (issue 16).
    #[test]
    fn messages_are_the_strings_they_replace() {
        let (n, last, line, chars, max) = (120, 80, 7, 300, 128);
        let path = PathBuf::from("dir/part.nc");
        let os = "No such file or directory (os error 2)".to_string();
        let e = LineError {
            line: 3,
            text: "G1X".into(),
            error: BlockError {
                code: 2,
                detail: "bad number".into(),
            },
        };
        let cases = [
            (
                InputFault::Read {
                    path: path.clone(),
                    reason: os.clone(),
                },
                format!("cannot read {}: {os}", path.display()),
            ),
            (
                InputFault::Log {
                    path: path.clone(),
                    reason: os.clone(),
                },
                format!("cannot create log {}: {os}", path.display()),
            ),
            (
                InputFault::LineTooLong {
                    line,
                    chars,
                    most: max - 1,
                },
                format!(
                    "line {}: {} characters after stripping comments and spaces; GRBL takes \
                     at most {} per line",
                    line,
                    chars,
                    max - 1
                ),
            ),
            (
                InputFault::NotAscii { line },
                format!("line {}: contains non-ASCII or control characters", line),
            ),
            (
                InputFault::ResumeOutside { line: n, last },
                format!("--from-line {n}: the file has lines 1 to {last}"),
            ),
            (
                InputFault::ResumeState {
                    line: n,
                    error: e.clone(),
                },
                format!("--from-line {n}: cannot compute the state: {e}"),
            ),
            (
                InputFault::ResumeNoSafeZ { line: n },
                format!("--from-line {n}: no Z move before this line; give --safe-z"),
            ),
            (
                InputFault::ResumePosition { line: n, axis: 'Y' },
                format!(
                    "--from-line {n}: the {} position before this line is not known \
                     (set by G28/G30/G53/G10 or never set)",
                    'Y'
                ),
            ),
            (
                InputFault::ResumeNoFeed { line: n },
                format!("--from-line {n}: no feed rate (F) is set before this line"),
            ),
            (
                InputFault::ResumeEnded { line: n },
                format!("--from-line {n}: the program has already ended (M2/M30) before this line"),
            ),
        ];
        for (fault, text) in cases {
            assert_eq!(fault.to_string(), text);
            assert_eq!(super::super::GrblError::Input(fault).to_string(), text);
        }
        let state = InputFault::ResumeState {
            line: n,
            error: e.clone(),
        };
        let source = std::error::Error::source(&state).expect("a source");
        assert_eq!(source.downcast_ref::<LineError>(), Some(&e));
    }
}
