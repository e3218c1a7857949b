//! `pfcam stream`: the front end of the streamer.
//!
//! This is the one part of the `grbl` module that talks to the user: it draws the
//! progress bar, prints GRBL's messages, asks resume-or-abort after Ctrl-C, and maps
//! the outcome to an exit code ([`ExitStatus`]). [`run_stream`] is the same flow
//! without the terminal, for tests and other front ends.

use std::io::{BufRead, IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::Arc;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

use super::link::Link;
use super::protocol::{Override, Position, StatusReport, WorkOffset};
use super::streamer::{
    check_blocks, resume_blocks, Block, Event, Observer, OperatorCommand, Resume, Settings,
    StreamReport, Streamer,
};
use super::GrblError;
use crate::gcode::parse::Program;

/// `pfcam stream FILE --port PORT [...]`.
#[derive(clap::Args, Debug, Clone)]
pub struct StreamArgs {
    /// G-code file to send.
    pub file: PathBuf,
    /// Serial port of the GRBL controller (e.g. /dev/ttyUSB0).
    #[arg(long)]
    pub port: String,
    /// Baud rate (8N1, no flow control).
    #[arg(long, default_value_t = 115200)]
    pub baud: u32,
    /// GRBL's serial receive buffer, bytes (character counting never exceeds it).
    #[arg(long, default_value_t = 128, value_name = "BYTES")]
    pub rx_buffer: usize,
    /// Status report (`?`) polling rate, Hz.
    #[arg(long, default_value_t = 5.0, value_name = "HZ")]
    pub status_hz: f64,
    /// Do not stop at `error:N`: keep streaming and list the rejected lines at the end.
    #[arg(long)]
    pub continue_on_error: bool,
    /// Run the file in GRBL's check mode ($C) only: report every error, move nothing.
    #[arg(long, conflicts_with = "check_first")]
    pub check: bool,
    /// Run the check mode pass first; stream only if GRBL accepts every line.
    #[arg(long)]
    pub check_first: bool,
    /// Resume at this file line (1-based): restore the modal state in force there,
    /// go to the resume point through safe Z, then continue.
    #[arg(long, value_name = "N")]
    pub from_line: Option<usize>,
    /// Safe Z for --from-line, mm in work coordinates [default: highest Z before N].
    #[arg(long, value_name = "MM", allow_hyphen_values = true)]
    pub safe_z: Option<f64>,
    /// Spindle spin-up dwell for --from-line, seconds.
    #[arg(long, default_value_t = 3.0, value_name = "S")]
    pub spindle_delay: f64,
    /// Send `$X` if GRBL is in alarm at connect (only if you know the position is good).
    #[arg(long)]
    pub unlock: bool,
    /// Record every line sent and every response, with timestamps, to FILE.
    #[arg(long, value_name = "FILE")]
    pub log: Option<PathBuf>,
    /// Seconds to wait for GRBL's banner (before and after a soft reset).
    #[arg(long, default_value_t = 2.0, value_name = "S")]
    pub connect_timeout: f64,
    /// Seconds of silence (not even a status report) after which GRBL counts as gone.
    #[arg(long, default_value_t = 10.0, value_name = "S")]
    pub response_timeout: f64,
}

impl StreamArgs {
    /// Minimal arguments: `FILE --port PORT`, everything else default.
    pub fn new(file: impl Into<PathBuf>, port: impl Into<String>) -> StreamArgs {
        StreamArgs {
            file: file.into(),
            port: port.into(),
            baud: 115200,
            rx_buffer: 128,
            status_hz: 5.0,
            continue_on_error: false,
            check: false,
            check_first: false,
            from_line: None,
            safe_z: None,
            spindle_delay: 3.0,
            unlock: false,
            log: None,
            connect_timeout: 2.0,
            response_timeout: 10.0,
        }
    }

    /// The protocol settings these arguments ask for.
    pub fn settings(&self) -> Settings {
        let secs = |s: f64, min: f64| {
            Duration::from_secs_f64(if s.is_finite() { s.max(min) } else { min })
        };
        Settings {
            rx_buffer: self.rx_buffer.max(2),
            status_interval: secs(1.0 / self.status_hz.max(0.1), 0.01),
            stop_on_error: !self.continue_on_error,
            banner_timeout: secs(self.connect_timeout, 0.05),
            response_timeout: secs(self.response_timeout, 0.5),
            unlock: self.unlock,
            ..Settings::default()
        }
    }
}

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

/// Reads the file and builds the blocks to send (with the resume preamble if
/// `--from-line`).
pub fn job_blocks(args: &StreamArgs) -> Result<(Program, Vec<Block>), GrblError> {
    let text = std::fs::read_to_string(&args.file)
        .map_err(|e| GrblError::Input(format!("cannot read {}: {e}", args.file.display())))?;
    let program = Program::parse(&text);
    let blocks = match args.from_line {
        Some(line) => resume_blocks(
            &program,
            &Resume {
                line,
                safe_z: args.safe_z,
                spindle_delay: args.spindle_delay,
            },
        )?,
        None => Block::from_program(&program),
    };
    Ok((program, blocks))
}

/// The whole `pfcam stream` flow without a terminal: read the file, open the port,
/// connect, optionally check, stream. `operator` carries hold/resume/abort requests.
pub fn run_stream(
    args: &StreamArgs,
    operator: &Receiver<OperatorCommand>,
    obs: &mut dyn Observer,
) -> Result<StreamReport, GrblError> {
    let (_program, blocks) = job_blocks(args)?;
    check_blocks(&blocks, &args.settings())?;
    let mut link = Link::open(&args.port, args.baud)?;
    if let Some(path) = &args.log {
        let file = std::fs::File::create(path)
            .map_err(|e| GrblError::Input(format!("cannot create log {}: {e}", path.display())))?;
        link.set_log(Box::new(std::io::LineWriter::new(file)));
    }
    let mut streamer = Streamer::connect(link, args.settings(), obs)?;
    if args.check || args.check_first {
        let report = streamer.check(&blocks, operator, obs)?;
        if !report.faults.is_empty() {
            return Err(GrblError::CheckFailed {
                faults: report.faults,
            });
        }
        if args.check {
            return Ok(report);
        }
    }
    streamer.stream(&blocks, operator, obs)
}

/// `pfcam stream`: streams, shows progress, handles Ctrl-C, returns the exit code.
pub fn stream_command(args: &StreamArgs) -> ExitCode {
    let (tx, rx) = mpsc::channel();
    let held = Arc::new(AtomicBool::new(false));
    // The prompt (resume or abort after a hold) needs someone at a terminal.
    let interactive = std::io::stdin().is_terminal();
    let signals = match catch_signals(tx.clone(), held.clone(), interactive) {
        Ok(handle) => Some(handle),
        Err(e) => {
            eprintln!(
                "warning: cannot catch signals ({e}); Ctrl-C, SIGTERM or SIGHUP will kill \
                 pfcam without stopping the machine"
            );
            None
        }
    };
    if interactive {
        spawn_prompt_reader(tx);
    }
    let mut ui = Terminal::new(held, interactive);
    let outcome = run_stream(args, &rx, &mut ui);
    ui.finish();
    if let Some(handle) = signals {
        handle.close();
    }
    let status = ExitStatus::of(&outcome);
    let program = job_blocks(args).ok().map(|(p, _)| p);
    match &outcome {
        Ok(report) => {
            if !report.faults.is_empty() {
                note("lines GRBL rejected (not executed):");
                for f in &report.faults {
                    note(&format!("  {f}"));
                }
            }
            let what = if args.check { "checked" } else { "sent" };
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
            for line in stop_advice(e, args, program.as_ref()) {
                note(&line);
            }
        }
    }
    status.into()
}

/// One line to stderr; a failed write is ignored (the terminal may be gone
/// after SIGHUP), where `eprintln!` would panic.
fn note(text: &str) {
    let _ = writeln!(std::io::stderr(), "{text}");
}

/// What `pfcam stream` prints after a failed stream, line by line: the error, what
/// state the machine was left in, and how to resume. For a rejected line it names
/// that line (number and text as in the file) and the line to resume at once it is
/// fixed, not the last acknowledged line (which follows the rejected one).
pub fn stop_advice(e: &GrblError, args: &StreamArgs, program: Option<&Program>) -> Vec<String> {
    let line_text = |n: usize| {
        program
            .and_then(|p| p.lines.get(n.wrapping_sub(1)))
            .map(|l| l.raw.trim().to_string())
            .unwrap_or_default()
    };
    let resume_cmd = |n: usize| {
        format!(
            "pfcam stream {} --port {} --from-line {n}",
            args.file.display(),
            args.port
        )
    };
    let mut out = vec![format!("error: {e}")];
    if let GrblError::CheckFailed { faults } = e {
        out.extend(faults.iter().map(|f| format!("  {f}")));
        if args.check_first {
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

/// Turns SIGINT, SIGTERM and SIGHUP into operator commands ([`signal_command`])
/// on a thread of their own, until the returned handle is closed.
fn catch_signals(
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

/// What a line typed during a stream asks for (case and spaces ignored):
/// `r`/`resume`, `a`/`abort` at the hold prompt; overrides at any time:
/// `f+`/`f-` feed ±10 %, `f+1`/`f-1` ±1 %, `f=` (or `f100`) back to 100 %;
/// `s+`, `s-`, `s+1`, `s-1`, `s=` (`s100`) the same for the spindle;
/// `r100`, `r50`, `r25` rapids. Anything else: `None`.
pub fn typed_command(line: &str) -> Option<OperatorCommand> {
    let key: String = line
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect::<String>()
        .to_ascii_lowercase();
    let o = match key.as_str() {
        "r" | "resume" => return Some(OperatorCommand::Resume),
        "a" | "abort" => return Some(OperatorCommand::Abort),
        "f=" | "f100" => Override::FeedReset,
        "f+" => Override::FeedUp10,
        "f-" => Override::FeedDown10,
        "f+1" => Override::FeedUp1,
        "f-1" => Override::FeedDown1,
        "r100" => Override::Rapid100,
        "r50" => Override::Rapid50,
        "r25" => Override::Rapid25,
        "s=" | "s100" => Override::SpindleReset,
        "s+" => Override::SpindleUp10,
        "s-" => Override::SpindleDown10,
        "s+1" => Override::SpindleUp1,
        "s-1" => Override::SpindleDown1,
        _ => return None,
    };
    Some(OperatorCommand::Override(o))
}

/// Reads typed commands ([`typed_command`]) from stdin.
fn spawn_prompt_reader(tx: Sender<OperatorCommand>) {
    if !std::io::stdin().is_terminal() {
        return;
    }
    let _ = std::thread::Builder::new()
        .name("hold-prompt".into())
        .spawn(move || {
            for line in std::io::stdin().lock().lines() {
                let Ok(line) = line else { return };
                let Some(cmd) = typed_command(&line) else {
                    continue;
                };
                if tx.send(cmd).is_err() {
                    return;
                }
            }
        });
}

/// Progress bar on a terminal, plain periodic lines otherwise.
struct Terminal {
    bar: Option<ProgressBar>,
    held: Arc<AtomicBool>,
    /// Someone can type commands (stdin is a terminal).
    interactive: bool,
    status: Option<StatusReport>,
    offset: WorkOffset,
    position: Option<Position>,
    acked: usize,
    total: usize,
    line: usize,
    start: Instant,
    last_plain: Instant,
}

impl Terminal {
    fn new(held: Arc<AtomicBool>, interactive: bool) -> Terminal {
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = ProgressBar::new(0);
            if let Ok(style) = ProgressStyle::with_template(
                "{bar:30.cyan/blue} {percent:>3}% {pos}/{len} lines  {elapsed_precise} ETA {eta_precise}  {msg}",
            ) {
                bar.set_style(style);
            }
            bar
        });
        Terminal {
            bar,
            held,
            interactive,
            status: None,
            offset: WorkOffset::default(),
            position: None,
            acked: 0,
            total: 0,
            line: 0,
            start: Instant::now(),
            last_plain: Instant::now(),
        }
    }

    /// Prints a line. Never panics (unlike `eprintln!`): after SIGHUP the terminal
    /// may be gone, and the machine still has to be stopped.
    fn say(&self, text: &str) {
        match &self.bar {
            Some(bar) => bar.println(text),
            None => note(text),
        }
    }

    fn machine(&self) -> String {
        match (&self.status, &self.position) {
            (Some(s), Some(p)) => format!("line {}  {}  {p}", self.line, s.state),
            (Some(s), None) => format!("line {}  {}", self.line, s.state),
            _ => format!("line {}", self.line),
        }
    }

    fn update(&mut self) {
        if let Some(bar) = &self.bar {
            bar.set_length(self.total as u64);
            bar.set_position(self.acked as u64);
            bar.set_message(self.machine());
        } else if self.last_plain.elapsed() >= Duration::from_secs(5) {
            self.last_plain = Instant::now();
            let pct = (self.acked * 100).checked_div(self.total).unwrap_or(0);
            self.say(&format!(
                "stream: {}/{} lines ({pct}%), {:.0} s, {}",
                self.acked,
                self.total,
                self.start.elapsed().as_secs_f64(),
                self.machine()
            ));
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish();
        }
        let _ = std::io::stderr().flush();
    }
}

impl Observer for Terminal {
    fn event(&mut self, event: Event<'_>) {
        match event {
            Event::Connected { version } => {
                self.say(&format!("connected to GRBL {version}"));
                if self.interactive {
                    self.say(
                        "overrides (type, then Enter): f+ f- f+1 f-1 f= feed, s+ s- s+1 s-1 s= \
                         spindle, r100 r50 r25 rapids; Ctrl-C holds",
                    );
                }
            }
            Event::Message(m) => self.say(&format!("GRBL: {m}")),
            Event::Status(s) => {
                self.position = self.offset.update(s);
                self.status = Some(s.clone());
                self.update();
            }
            Event::Progress { acked, total, line } => {
                self.acked = acked;
                self.total = total;
                self.line = line;
                self.update();
            }
            Event::Rejected(f) => self.say(&format!("GRBL rejected {f}; continuing")),
            Event::HoldRequested => self.say("feed hold sent; waiting for the machine to stop..."),
            Event::HoldComplete => {
                self.held.store(true, Ordering::SeqCst);
                self.say(
                    "machine stopped (feed hold). Type `r` + Enter to resume, `a` + Enter to \
                     abort; Ctrl-C again aborts.",
                );
            }
            Event::Resumed => {
                self.held.store(false, Ordering::SeqCst);
                self.say("resumed");
            }
            Event::Stopping(why) => self.say(&format!("stopping the machine: {why}")),
        }
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

    #[test]
    fn typed_commands_map_to_grbl_override_bytes() {
        let byte = |t: &str| match typed_command(t) {
            Some(OperatorCommand::Override(o)) => Some(o.byte()),
            _ => None,
        };
        let keys = [
            "f=", "f+", "f-", "f+1", "f-1", "r100", "r50", "r25", "s=", "s+", "s-", "s+1", "s-1",
        ];
        let bytes: Vec<Option<u8>> = keys.iter().map(|k| byte(k)).collect();
        let want: Vec<Option<u8>> = (0x90..=0x97).chain(0x99..=0x9D).map(Some).collect();
        assert_eq!(bytes, want);
        assert_eq!(byte("f100"), Some(0x90));
        assert_eq!(byte("S100"), Some(0x99));
        assert_eq!(typed_command(" R "), Some(OperatorCommand::Resume));
        assert_eq!(typed_command("abort"), Some(OperatorCommand::Abort));
        assert_eq!(typed_command("f+2"), None);
        assert_eq!(typed_command(""), None);
    }

    #[test]
    fn every_outcome_has_a_distinct_exit_code() {
        let outcomes = [
            Ok(StreamReport::default()),
            Err(GrblError::Input("x".into())),
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
