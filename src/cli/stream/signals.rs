//! Signals during a stream: SIGINT (Ctrl-C), SIGTERM and SIGHUP become operator
//! commands (hold, or abort: feed hold then soft reset), never a kill with the
//! machine still running.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Sender;
use std::sync::Arc;

use pfcam::grbl::OperatorCommand;

/// Turns SIGINT, SIGTERM and SIGHUP into operator commands ([`signal_command`])
/// on a thread of their own, until the returned handle is closed.
pub fn catch_signals(
    tx: Sender<OperatorCommand>,
    held: Arc<AtomicBool>,
    interactive: bool,
) -> std::io::Result<signal_hook::iterator::Handle> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    let handle = signals.handle();
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            for signal in signals.forever() {
                if tx.send(signal_command(signal, &held, interactive)).is_err() {
                    return;
                }
            }
        })?;
    Ok(handle)
}

/// What a signal means during a stream. SIGTERM and SIGHUP (a service stopping
/// pfcam, the terminal gone) abort: feed hold, soft reset, exit 6. So does SIGINT
/// when nobody is at a terminal to answer the resume-or-abort prompt: a hold
/// without it would leave the machine held with the spindle running. At a
/// terminal, SIGINT (Ctrl-C) holds and asks; see [`ctrl_c`].
pub fn signal_command(signal: i32, held: &AtomicBool, interactive: bool) -> OperatorCommand {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    match signal {
        SIGINT if interactive => ctrl_c(held),
        SIGINT => OperatorCommand::Stop(
            "aborted: pfcam received SIGINT with no terminal to ask whether to resume",
        ),
        SIGTERM => OperatorCommand::Stop(
            "aborted: pfcam received SIGTERM (the system or a service asked it to stop)",
        ),
        SIGHUP => OperatorCommand::Stop("aborted: pfcam received SIGHUP (its terminal closed)"),
        _ => OperatorCommand::Stop("aborted: pfcam received a signal"),
    }
}

/// What a Ctrl-C means: a feed hold, or an abort when already held (second
/// Ctrl-C, or Ctrl-C at the resume-or-abort prompt).
pub fn ctrl_c(held: &AtomicBool) -> OperatorCommand {
    if held.swap(true, Ordering::SeqCst) {
        OperatorCommand::Abort
    } else {
        OperatorCommand::Hold
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_ctrl_c_holds_second_aborts() {
        let held = AtomicBool::new(false);
        assert_eq!(ctrl_c(&held), OperatorCommand::Hold);
        assert_eq!(ctrl_c(&held), OperatorCommand::Abort);
        // After a resume the front end clears the flag: Ctrl-C holds again.
        held.store(false, Ordering::SeqCst);
        assert_eq!(ctrl_c(&held), OperatorCommand::Hold);
    }

    #[test]
    fn signals_abort_unless_someone_can_answer_the_prompt() {
        use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
        let held = AtomicBool::new(false);
        for (sig, name) in [(SIGTERM, "SIGTERM"), (SIGHUP, "SIGHUP")] {
            for interactive in [false, true] {
                assert!(
                    matches!(signal_command(sig, &held, interactive), OperatorCommand::Stop(why) if why.contains(name))
                );
            }
        }
        assert!(matches!(
            signal_command(SIGINT, &held, false),
            OperatorCommand::Stop(why) if why.contains("SIGINT")
        ));
        assert_eq!(signal_command(SIGINT, &held, true), OperatorCommand::Hold);
        assert_eq!(signal_command(SIGINT, &held, true), OperatorCommand::Abort);
    }
}
