//! The streamer: connect to GRBL, then send a job with character counting.
//!
//! # Character counting
//! GRBL has a 128-byte serial receive buffer and answers each line with `ok` or
//! `error:N`, in order, once the line is parsed. The streamer keeps the lengths of
//! sent-but-unacknowledged lines (newline included) in a FIFO and sends the next
//! line only if the sum stays within [`Settings::rx_buffer`]; each `ok`/`error:N`
//! pops the oldest. So GRBL's buffer never overflows and stays as full as possible.
//!
//! # Waiting
//! Every wait is bounded. A `?` status query goes out every
//! [`Settings::status_interval`] and GRBL answers it even in a feed hold, so silence
//! longer than [`Settings::response_timeout`] means the controller or the link is
//! dead, not that a long move is running.
//!
//! # Stopping
//! A rejected line (by default) and an operator abort stop the machine the same way:
//! feed hold `!`, wait until the hold is complete (`Hold:0`, bounded), soft reset
//! (spindle and coolant off, buffers flushed), wait for the banner. GRBL 1.1h
//! resets from `Hold:0` to `Idle` with no alarm and keeps its position; only a
//! reset while still moving (the hold not complete in time) raises `ALARM:3`. An `ALARM:N`
//! needs no stop (GRBL has already stopped); pfcam sends nothing more.

use std::collections::VecDeque;
use std::fmt;
use std::sync::mpsc::{Receiver, TryRecvError};
use std::time::{Duration, Instant};

use super::codes;
use super::link::Link;
use super::protocol::{
    parse_response, MachineState, Override, Response, StatusReport, CYCLE_START, FEED_HOLD,
    SOFT_RESET, STATUS_QUERY,
};
use super::{GrblError, InputFault};
use crate::gcode::parse::{Distance, FeedMode, ModalState, Motion, Plane, Program, Spindle, Units};

/// Tunables of the protocol. [`Settings::default`] fits a stock GRBL 1.1.
#[derive(Clone, Debug)]
pub struct Settings {
    /// GRBL's serial receive buffer, bytes (GRBL 1.1 on an ATmega328: 128).
    pub rx_buffer: usize,
    /// GRBL's line buffer, bytes: a line plus its newline must fit (GRBL: 80).
    pub line_buffer: usize,
    /// Time between `?` status queries (GRBL advises at most 5 Hz: 200 ms).
    pub status_interval: Duration,
    /// Stop at the first `error:N` (default) or list them at the end.
    pub stop_on_error: bool,
    /// How long to wait for the banner, before and after the soft reset.
    pub banner_timeout: Duration,
    /// Silence (no line at all, status reports included) that means GRBL is gone;
    /// also how long GRBL may sit idle with empty buffers while lines are still
    /// unacknowledged (lost `ok`s) before the stream stops (plus any `G4` dwell
    /// among those lines).
    pub response_timeout: Duration,
    /// How long a feed hold may take to come to a stop before pfcam resets anyway.
    pub hold_timeout: Duration,
    /// Send `$X` when GRBL is in alarm at connect, instead of refusing.
    pub unlock: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            rx_buffer: 128,
            line_buffer: 80,
            status_interval: Duration::from_millis(200),
            stop_on_error: true,
            banner_timeout: Duration::from_millis(2000),
            response_timeout: Duration::from_secs(10),
            hold_timeout: Duration::from_secs(10),
            unlock: false,
        }
    }
}

/// One line to send: the file line it came from (0 = written by pfcam, e.g. the
/// resume preamble) and the cleaned block.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// 1-based file line, 0 for lines pfcam adds.
    pub line: usize,
    /// What goes on the wire (without the newline).
    pub text: String,
}

impl Block {
    /// Every non-empty line of a program.
    pub fn from_program(program: &Program) -> Vec<Block> {
        program
            .blocks()
            .map(|l| Block {
                line: l.number,
                text: l.block.clone(),
            })
            .collect()
    }
}

/// A line GRBL rejected.
#[derive(Clone, Debug, PartialEq)]
pub struct Fault {
    /// File line (0: a line pfcam added).
    pub line: usize,
    /// The text sent.
    pub text: String,
    /// `error:N`.
    pub code: u8,
}

impl fmt::Display for Fault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "pfcam's resume line")?;
        } else {
            write!(f, "line {}", self.line)?;
        }
        write!(
            f,
            " `{}`: error:{} ({})",
            self.text,
            self.code,
            codes::error_meaning(self.code)
        )
    }
}

/// What the operator (Ctrl-C handler, prompt, a test) asks for during a stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OperatorCommand {
    /// Feed hold now.
    Hold,
    /// Resume from the hold.
    Resume,
    /// Stop: feed hold, then soft reset.
    Abort,
    /// Stop as `Abort` does, for the reason given (a signal: SIGTERM, SIGHUP,
    /// SIGINT with nobody at a terminal), which the messages name.
    Stop(&'static str),
    /// A feed, rapid or spindle override: its real-time byte goes out at once
    /// (GRBL applies it while running or held).
    Override(Override),
}

/// What happens during a stream, for a front end (progress bar, log, prompt).
#[derive(Clone, Debug, PartialEq)]
pub enum Event<'a> {
    /// Connected to GRBL `version`.
    Connected {
        /// e.g. `1.1h`.
        version: &'a str,
    },
    /// A push message or other text from GRBL (`[MSG:...]`, `[GC:...]`, ...).
    Message(&'a str),
    /// A status report.
    Status(&'a StatusReport),
    /// A line was acknowledged.
    Progress {
        /// Lines acknowledged so far.
        acked: usize,
        /// Lines in the job.
        total: usize,
        /// File line of the last acknowledged line.
        line: usize,
    },
    /// A rejected line that does not stop the stream (check mode,
    /// `--continue-on-error`).
    Rejected(&'a Fault),
    /// Feed hold sent at the operator's request.
    HoldRequested,
    /// The machine is stopped in a hold (operator's or the program's M0): ask the
    /// operator to resume or abort.
    HoldComplete,
    /// Resumed from a hold.
    Resumed,
    /// Stopping the machine: feed hold then soft reset, for this reason.
    Stopping(&'a str),
}

/// Receives [`Event`]s. `()` ignores them.
pub trait Observer {
    /// One event.
    fn event(&mut self, event: Event<'_>);
}

impl Observer for () {
    fn event(&mut self, _: Event<'_>) {}
}

/// How a completed stream went.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StreamReport {
    /// Lines acknowledged (`ok` or `error:N`).
    pub acked: usize,
    /// Rejected lines (check mode, `--continue-on-error`).
    pub faults: Vec<Fault>,
    /// Wall time of the stream.
    pub elapsed: Duration,
    /// Mean of the unacknowledged bytes over the time lines were still left to send,
    /// as a fraction of the receive buffer.
    pub mean_fill: f64,
    /// Most unacknowledged bytes at any time.
    pub max_in_flight: usize,
}

/// A connected GRBL.
pub struct Streamer {
    link: Link,
    settings: Settings,
    version: String,
    status: Option<StatusReport>,
    wco: Option<[f64; 3]>,
    /// Most free planner blocks and receive-buffer bytes GRBL has reported (`Bf:`):
    /// what it says when both are empty.
    empty_buffers: Option<(u32, u32)>,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Mode {
    Run,
    Check,
}

/// State of one stream.
struct Run<'a> {
    blocks: &'a [Block],
    next: usize,
    pending: VecDeque<(usize, usize)>,
    in_flight: usize,
    acked: usize,
    last_acked: Option<usize>,
    /// File lines of the last acknowledged lines with axis words.
    acked_motion: VecDeque<usize>,
    faults: Vec<Fault>,
    held: bool,
    hold_announced: bool,
    resume_pending: bool,
    /// `~` sent; status reports still saying Hold were asked before it.
    awaiting_run: bool,
    /// Since when GRBL has been idle with empty buffers while lines are
    /// outstanding (see [`Streamer::looks_stalled`]).
    stall_since: Option<Instant>,
    fill_integral: f64,
    fill_time: f64,
    last_change: Instant,
    max_in_flight: usize,
}

impl Streamer {
    /// Waits for GRBL's banner (soft reset if none comes), then checks the state.
    ///
    /// GRBL in alarm is an error ([`GrblError::AlarmAtConnect`]) unless
    /// [`Settings::unlock`] is set, then `$X` is sent.
    pub fn connect(
        link: Link,
        settings: Settings,
        obs: &mut dyn Observer,
    ) -> Result<Streamer, GrblError> {
        let mut s = Streamer {
            link,
            settings,
            version: String::new(),
            status: None,
            wco: None,
            empty_buffers: None,
        };
        let mut heard = String::new();
        let mut alarm_hint = false;
        let version = match s.wait_banner(&mut heard, &mut alarm_hint, obs)? {
            Some(v) => v,
            None => {
                s.link.send_realtime(SOFT_RESET)?;
                match s.wait_banner(&mut heard, &mut alarm_hint, obs)? {
                    Some(v) => v,
                    None => {
                        return Err(GrblError::NoGrbl {
                            port: s.link.name().to_string(),
                            heard: if heard.is_empty() {
                                "nothing was received".to_string()
                            } else {
                                format!("received instead: {:?}", truncate(&heard, 80))
                            },
                        })
                    }
                }
            }
        };
        s.version = version;
        obs.event(Event::Connected {
            version: &s.version,
        });
        let status = s.query_status(obs)?;
        if status.state == MachineState::Alarm || alarm_hint {
            if s.settings.unlock {
                s.command("$X", obs)?;
            } else {
                return Err(GrblError::AlarmAtConnect {
                    code: None,
                    advice: "machine position may be unknown; home with `$H` (or unlock with \
                             `$X` if you are sure of the position, e.g. `pfcam stream --unlock`) \
                             before streaming"
                        .to_string(),
                });
            }
        }
        Ok(s)
    }

    /// GRBL's version word (`1.1h`).
    pub fn version(&self) -> &str {
        &self.version
    }

    /// The last status report.
    pub fn last_status(&self) -> Option<&StatusReport> {
        self.status.as_ref()
    }

    /// Waits up to `banner_timeout` for the banner; pushes other text to `heard`.
    fn wait_banner(
        &mut self,
        heard: &mut String,
        alarm_hint: &mut bool,
        obs: &mut dyn Observer,
    ) -> Result<Option<String>, GrblError> {
        let deadline = Instant::now() + self.settings.banner_timeout;
        let mut version = None;
        loop {
            let now = Instant::now();
            // After the banner, give GRBL a moment for its follow-up messages
            // (`[MSG:'$H'|'$X' to unlock]`, startup-line echoes).
            let wait = match version {
                Some(_) => Duration::from_millis(50),
                None if now >= deadline => return Ok(None),
                None => deadline - now,
            };
            let Some(line) = self.link.recv(wait)? else {
                return Ok(version);
            };
            match parse_response(&line) {
                Response::Banner { version: v } => version = Some(v),
                Response::Alarm(_) => *alarm_hint = true,
                Response::Feedback(m) if version.is_some() => {
                    if m.contains("unlock") {
                        *alarm_hint = true;
                    }
                    obs.event(Event::Message(&m));
                }
                Response::StartupEcho(_) | Response::Feedback(_) if version.is_some() => {
                    obs.event(Event::Message(&line))
                }
                _ => {
                    if heard.len() < 200 {
                        heard.push_str(&line);
                        heard.push('\n');
                    }
                }
            }
        }
    }

    /// Sends `?` and waits (bounded) for the report.
    fn query_status(&mut self, obs: &mut dyn Observer) -> Result<StatusReport, GrblError> {
        let deadline = Instant::now() + self.settings.banner_timeout.max(Duration::from_secs(1));
        self.link.send_realtime(STATUS_QUERY)?;
        let mut next_poll = Instant::now() + Duration::from_millis(250);
        loop {
            let now = Instant::now();
            if now >= deadline {
                return Err(GrblError::Command {
                    command: "?".into(),
                    reason: "no status report".into(),
                });
            }
            if now >= next_poll {
                self.link.send_realtime(STATUS_QUERY)?;
                next_poll = now + Duration::from_millis(250);
            }
            if let Some(line) = self.link.recv(Duration::from_millis(20))? {
                match parse_response(&line) {
                    Response::Status(r) => {
                        self.note_status(&r);
                        // Observers see it too: it may be the one with the WCO.
                        obs.event(Event::Status(&r));
                        return Ok(r);
                    }
                    _ => obs.event(Event::Message(&line)),
                }
            }
        }
    }

    fn note_status(&mut self, r: &StatusReport) {
        if r.wco.is_some() {
            self.wco = r.wco;
        }
        if let Some((planner, rx)) = r.buffer {
            let (p, x) = self.empty_buffers.unwrap_or((0, 0));
            self.empty_buffers = Some((p.max(planner), x.max(rx)));
        }
        self.status = Some(r.clone());
    }

    /// Sends a system command with nothing else in flight and waits for its `ok`.
    fn command(&mut self, command: &str, obs: &mut dyn Observer) -> Result<(), GrblError> {
        self.link.send_line(command)?;
        let deadline = Instant::now() + self.settings.response_timeout;
        loop {
            let now = Instant::now();
            if now >= deadline {
                return Err(GrblError::Command {
                    command: command.into(),
                    reason: "no answer".into(),
                });
            }
            let Some(line) = self.link.recv(deadline - now)? else {
                continue;
            };
            match parse_response(&line) {
                Response::Ok => return Ok(()),
                Response::Error(n) => {
                    return Err(GrblError::Command {
                        command: command.into(),
                        reason: format!("error:{n} ({})", codes::error_meaning(n)),
                    })
                }
                Response::Alarm(n) => {
                    return Err(GrblError::Alarm {
                        code: n,
                        last_acked: None,
                        resume_from: None,
                    })
                }
                Response::Status(r) => self.note_status(&r),
                _ => obs.event(Event::Message(&line)),
            }
        }
    }

    /// Streams `blocks`, obeying `operator`, reporting to `obs`.
    ///
    /// Completes when every line is acknowledged and GRBL reports `Idle`. Rejected
    /// lines stop the stream unless [`Settings::stop_on_error`] is off; then they
    /// are in [`StreamReport::faults`].
    pub fn stream(
        &mut self,
        blocks: &[Block],
        operator: &Receiver<OperatorCommand>,
        obs: &mut dyn Observer,
    ) -> Result<StreamReport, GrblError> {
        self.run(blocks, Mode::Run, operator, obs)
    }

    /// Runs `blocks` in GRBL's check mode (`$C`): parsed, not moved. Every rejected
    /// line is in [`StreamReport::faults`]. Leaving check mode soft-resets GRBL;
    /// this waits for the banner, so the streamer is ready for a real run after.
    pub fn check(
        &mut self,
        blocks: &[Block],
        operator: &Receiver<OperatorCommand>,
        obs: &mut dyn Observer,
    ) -> Result<StreamReport, GrblError> {
        self.command("$C", obs)?;
        let report = self.run(blocks, Mode::Check, operator, obs)?;
        self.command("$C", obs)?;
        let mut heard = String::new();
        let mut alarm = false;
        if self.wait_banner(&mut heard, &mut alarm, obs)?.is_none() {
            return Err(GrblError::Command {
                command: "$C".into(),
                reason: "no banner after leaving check mode".into(),
            });
        }
        Ok(report)
    }

    fn check_lengths(&self, blocks: &[Block]) -> Result<(), GrblError> {
        check_blocks(blocks, &self.settings)
    }

    fn run(
        &mut self,
        blocks: &[Block],
        mode: Mode,
        operator: &Receiver<OperatorCommand>,
        obs: &mut dyn Observer,
    ) -> Result<StreamReport, GrblError> {
        self.check_lengths(blocks)?;
        let start = Instant::now();
        let mut r = Run {
            blocks,
            next: 0,
            pending: VecDeque::new(),
            in_flight: 0,
            acked: 0,
            last_acked: None,
            acked_motion: VecDeque::new(),
            faults: Vec::new(),
            held: false,
            hold_announced: false,
            resume_pending: false,
            awaiting_run: false,
            stall_since: None,
            fill_integral: 0.0,
            fill_time: 0.0,
            last_change: Instant::now(),
            max_in_flight: 0,
        };
        let interval = self.settings.status_interval;
        let mut next_poll = Instant::now();
        let mut last_rx = Instant::now();
        // Completion needs a status report answering a query sent after the last
        // acknowledgement (GRBL answers `?` in order), so a stale `Idle` from
        // before the last moves were planned does not count.
        let mut polls_sent: u64 = 0;
        let mut reports: u64 = 0;
        let mut final_poll: Option<u64> = None;
        loop {
            // Operator requests.
            self.obey(&mut r, mode, operator, obs)?;
            // Resume once the hold is complete (GRBL ignores `~` before `Hold:0`).
            if r.resume_pending && self.hold_complete() {
                self.resume(&mut r, obs)?;
            }
            if !r.held {
                self.fill_rx_buffer(&mut r)?;
            }
            let now = Instant::now();
            // Done?
            if r.next == blocks.len() && r.pending.is_empty() {
                if mode == Mode::Check {
                    break;
                }
                if final_poll.is_none() {
                    final_poll = Some(polls_sent + 1);
                    next_poll = now;
                }
                if final_poll.is_some_and(|seq| reports >= seq)
                    && matches!(
                        self.status.as_ref().map(|s| &s.state),
                        Some(MachineState::Idle)
                    )
                {
                    break;
                }
            }
            if now >= next_poll {
                self.link
                    .send_realtime(STATUS_QUERY)
                    .map_err(|e| lost(e, &r))?;
                polls_sent += 1;
                next_poll = now + interval;
            }
            let wait = next_poll
                .saturating_duration_since(Instant::now())
                .min(Duration::from_millis(50));
            let line = match self.link.recv(wait) {
                Ok(Some(line)) => line,
                Ok(None) => {
                    let silent = last_rx.elapsed();
                    if silent > self.settings.response_timeout {
                        // Best effort: stop whatever may still be moving.
                        let _ = self.link.send_realtime(FEED_HOLD);
                        let _ = self.link.send_realtime(SOFT_RESET);
                        return Err(GrblError::Unresponsive {
                            seconds: silent.as_secs_f64(),
                            last_acked: r.last_acked,
                            resume_from: self.resume_point(&r, true),
                        });
                    }
                    continue;
                }
                Err(e) => return Err(e.with_stop(r.last_acked, self.resume_point(&r, true))),
            };
            last_rx = Instant::now();
            self.on_line(&mut r, mode, &line, &mut reports, obs)?;
        }
        Ok(StreamReport {
            acked: r.acked,
            faults: r.faults,
            elapsed: start.elapsed(),
            mean_fill: if r.fill_time > 0.0 {
                r.fill_integral / r.fill_time / self.settings.rx_buffer as f64
            } else {
                0.0
            },
            max_in_flight: r.max_in_flight,
        })
    }

    /// Cycle start `~` after a completed hold.
    fn resume(&mut self, r: &mut Run<'_>, obs: &mut dyn Observer) -> Result<(), GrblError> {
        self.link
            .send_realtime(CYCLE_START)
            .map_err(|e| lost(e, r))?;
        r.resume_pending = false;
        r.held = false;
        r.hold_announced = false;
        r.awaiting_run = true;
        // Until a fresh report says otherwise, the machine is running again.
        if let Some(s) = self.status.as_mut() {
            s.state = MachineState::Run;
        }
        obs.event(Event::Resumed);
        Ok(())
    }

    /// Character counting: sends the next lines while their bytes (newlines
    /// included) and those still unacknowledged fit GRBL's receive buffer.
    fn fill_rx_buffer(&mut self, r: &mut Run<'_>) -> Result<(), GrblError> {
        let blocks = r.blocks;
        while r.next < blocks.len() {
            let len = blocks[r.next].text.len() + 1;
            if r.in_flight + len > self.settings.rx_buffer {
                break;
            }
            self.link
                .send_line(&blocks[r.next].text)
                .map_err(|e| lost(e, r))?;
            r.account();
            r.pending.push_back((r.next, len));
            r.in_flight += len;
            r.max_in_flight = r.max_in_flight.max(r.in_flight);
            r.next += 1;
        }
        Ok(())
    }

    /// Applies what the operator asked for since the last look: a feed hold, a
    /// resume (noted; `run` sends `~` once the hold is complete), an override
    /// byte, or a stop (hold, reset, and the error that ends the stream).
    fn obey(
        &mut self,
        r: &mut Run<'_>,
        mode: Mode,
        operator: &Receiver<OperatorCommand>,
        obs: &mut dyn Observer,
    ) -> Result<(), GrblError> {
        loop {
            match operator.try_recv() {
                Ok(OperatorCommand::Hold) if mode == Mode::Check => {
                    // Check mode moves nothing: a hold there means "stop checking".
                    obs.event(Event::Stopping("check aborted by the operator"));
                    self.stop_machine(r, obs)?;
                    return Err(GrblError::Aborted {
                        by: "check aborted by the operator",
                        last_acked: r.last_acked,
                        resume_from: None,
                    });
                }
                Ok(OperatorCommand::Hold) => {
                    if !r.held {
                        self.link.send_realtime(FEED_HOLD).map_err(|e| lost(e, r))?;
                        r.held = true;
                        r.hold_announced = false;
                        r.awaiting_run = false;
                        obs.event(Event::HoldRequested);
                    }
                }
                Ok(OperatorCommand::Resume) => {
                    if r.held || self.in_hold() {
                        r.resume_pending = true;
                    }
                }
                Ok(OperatorCommand::Override(o)) => {
                    self.link.send_realtime(o.byte()).map_err(|e| lost(e, r))?;
                }
                Ok(cmd @ (OperatorCommand::Abort | OperatorCommand::Stop(_))) => {
                    let by = match cmd {
                        OperatorCommand::Stop(why) => why,
                        _ => "aborted by the operator",
                    };
                    obs.event(Event::Stopping(by));
                    self.stop_machine(r, obs)?;
                    return Err(GrblError::Aborted {
                        by,
                        last_acked: r.last_acked,
                        resume_from: self.resume_point(r, false),
                    });
                }
                Err(TryRecvError::Empty) | Err(TryRecvError::Disconnected) => return Ok(()),
            }
        }
    }

    /// Handles one line from GRBL during a stream: `ok` / `error:N` (which may
    /// stop the stream), an alarm, a status report (hold, stall), a banner (GRBL
    /// reset itself), anything else for the observer. `Err` ends the stream.
    fn on_line(
        &mut self,
        r: &mut Run<'_>,
        mode: Mode,
        line: &str,
        reports: &mut u64,
        obs: &mut dyn Observer,
    ) -> Result<(), GrblError> {
        match parse_response(line) {
            Response::Ok => {
                self.ack(r, None, obs);
            }
            Response::Error(code) => {
                if let Some(fault) = self.ack(r, Some(code), obs) {
                    if mode == Mode::Run && self.settings.stop_on_error {
                        obs.event(Event::Stopping("GRBL rejected a line"));
                        self.stop_machine(r, obs)?;
                        let resume_from = self.rejected_resume(r, fault.line);
                        return Err(GrblError::Rejected {
                            fault,
                            last_acked: r.last_acked,
                            resume_from,
                        });
                    }
                    obs.event(Event::Rejected(&fault));
                    r.faults.push(fault);
                }
            }
            Response::Alarm(code) => {
                return Err(GrblError::Alarm {
                    code,
                    last_acked: r.last_acked,
                    resume_from: self.resume_point(r, true),
                })
            }
            Response::Status(report) => {
                self.note_status(&report);
                *reports += 1;
                if self.looks_stalled(r, &report) {
                    let since = *r.stall_since.get_or_insert_with(Instant::now);
                    if since.elapsed() > self.settings.response_timeout + pending_dwell(r) {
                        return Err(self.stalled(r, since, obs));
                    }
                } else {
                    r.stall_since = None;
                }
                if !matches!(report.state, MachineState::Hold(_)) {
                    r.awaiting_run = false;
                }
                if self.hold_complete() && !r.hold_announced && !r.awaiting_run {
                    r.hold_announced = true;
                    r.held = true;
                    obs.event(Event::HoldComplete);
                }
                obs.event(Event::Status(&report));
            }
            Response::Banner { .. } => {
                return Err(GrblError::UnexpectedReset {
                    last_acked: r.last_acked,
                    resume_from: self.resume_point(r, true),
                })
            }
            _ => obs.event(Event::Message(line)),
        }
        Ok(())
    }

    /// Resume point from the planner fill in the last status report (`Bf:`), or
    /// assuming a full planner when `worst_case` or when GRBL did not report it.
    fn resume_point(&self, r: &Run<'_>, worst_case: bool) -> Option<usize> {
        resume_point(r, self.planner_used(worst_case))
    }

    /// Planner blocks in use at the last status report: its capacity (the most free
    /// blocks GRBL ever reported, else GRBL 1.1's 15) less the free ones, or the
    /// whole capacity when `worst_case` or without `Bf:`.
    fn planner_used(&self, worst_case: bool) -> usize {
        let capacity = self
            .empty_buffers
            .map_or(PLANNER_BLOCKS, |(p, _)| p as usize);
        match self.status.as_ref().and_then(|s| s.buffer) {
            Some((free, _)) if !worst_case => capacity.saturating_sub(free as usize),
            _ => capacity,
        }
    }

    /// Where to resume after GRBL rejected file line `fault` and the machine was
    /// stopped (hold, reset: the planner is discarded). The planner held the newest
    /// acknowledged moves; those after the rejected line take their share, the rest
    /// are moves before it that never ran. Resume at the oldest of those, or at the
    /// rejected line itself when none was left. `None`: from the start.
    fn rejected_resume(&self, r: &Run<'_>, fault: usize) -> Option<usize> {
        if fault == 0 {
            // pfcam's own resume preamble was rejected: resume where it was for.
            return r.blocks.iter().find(|b| b.line != 0).map(|b| b.line);
        }
        let after = r.acked_motion.iter().filter(|&&l| l > fault).count();
        let before: Vec<usize> = r
            .acked_motion
            .iter()
            .copied()
            .filter(|&l| l < fault)
            .collect();
        match self.planner_used(false).saturating_sub(after) {
            0 => Some(fault),
            k if k <= before.len() => Some(before[before.len() - k]),
            _ => None,
        }
    }

    /// GRBL idle (or in check mode, where nothing is planned), its planner and
    /// receive buffer empty (as empty as it has ever reported them; without `Bf:`
    /// the state alone), yet lines are unacknowledged: their `ok`s can only have
    /// been lost. Status reports keep coming in this state, so only this check
    /// ends it.
    fn looks_stalled(&self, r: &Run<'_>, report: &StatusReport) -> bool {
        !r.pending.is_empty()
            && matches!(report.state, MachineState::Idle | MachineState::Check)
            && match (report.buffer, self.empty_buffers) {
                (Some(now), Some(empty)) => now == empty,
                _ => true,
            }
    }

    /// Ends a stall: hold and reset (the spindle may be running), then the error.
    fn stalled(&mut self, r: &mut Run<'_>, since: Instant, obs: &mut dyn Observer) -> GrblError {
        let seconds = since.elapsed().as_secs_f64();
        let unacked = r.pending.len();
        obs.event(Event::Stopping(
            "GRBL is idle with empty buffers but lines are unacknowledged",
        ));
        if let Err(e) = self.stop_machine(r, obs) {
            return e;
        }
        GrblError::Stalled {
            seconds,
            unacked,
            last_acked: r.last_acked,
            // Idle with an empty planner: every acknowledged line has run.
            resume_from: resume_point(r, 0),
        }
    }

    fn in_hold(&self) -> bool {
        matches!(
            self.status.as_ref().map(|s| &s.state),
            Some(MachineState::Hold(_))
        )
    }

    /// Stopped and resumable: `Hold:0`, or `Door:0` (door closed again).
    fn hold_complete(&self) -> bool {
        matches!(
            self.status.as_ref().map(|s| &s.state),
            Some(MachineState::Hold(0)) | Some(MachineState::Door(0))
        )
    }

    /// Matches an `ok`/`error:N` to the oldest unacknowledged line.
    fn ack(&mut self, r: &mut Run<'_>, error: Option<u8>, obs: &mut dyn Observer) -> Option<Fault> {
        let Some((index, len)) = r.pending.pop_front() else {
            obs.event(Event::Message(
                "unexpected acknowledgement (no line in flight)",
            ));
            return None;
        };
        r.account();
        r.in_flight -= len;
        r.acked += 1;
        r.stall_since = None;
        let block = &r.blocks[index];
        let fault = error.map(|code| Fault {
            line: block.line,
            text: block.text.clone(),
            code,
        });
        if error.is_none() && block.line != 0 {
            r.last_acked = Some(block.line);
            if block.text.contains(['X', 'Y', 'Z']) {
                r.acked_motion.push_back(block.line);
                if r.acked_motion.len() > 4 * PLANNER_BLOCKS {
                    r.acked_motion.pop_front();
                }
            }
        }
        obs.event(Event::Progress {
            acked: r.acked,
            total: r.blocks.len(),
            line: block.line,
        });
        fault
    }

    /// Feed hold, wait (bounded) for the stop, soft reset, wait for the banner.
    fn stop_machine(&mut self, r: &mut Run<'_>, obs: &mut dyn Observer) -> Result<(), GrblError> {
        self.link.send_realtime(FEED_HOLD).map_err(|e| lost(e, r))?;
        let deadline = Instant::now() + self.settings.hold_timeout;
        let mut next_poll = Instant::now();
        loop {
            let now = Instant::now();
            if now >= deadline {
                break;
            }
            if now >= next_poll {
                self.link
                    .send_realtime(STATUS_QUERY)
                    .map_err(|e| lost(e, r))?;
                next_poll = now
                    + self
                        .settings
                        .status_interval
                        .min(Duration::from_millis(100));
            }
            let Some(line) = self
                .link
                .recv(Duration::from_millis(20))
                .map_err(|e| e.with_stop(r.last_acked, self.resume_point(r, true)))?
            else {
                continue;
            };
            match parse_response(&line) {
                Response::Ok => {
                    self.ack(r, None, obs);
                }
                Response::Error(code) => {
                    if let Some(f) = self.ack(r, Some(code), obs) {
                        obs.event(Event::Rejected(&f));
                        r.faults.push(f);
                    }
                }
                Response::Status(report) => {
                    self.note_status(&report);
                    obs.event(Event::Status(&report));
                    if matches!(
                        report.state,
                        MachineState::Hold(0)
                            | MachineState::Idle
                            | MachineState::Alarm
                            | MachineState::Check
                    ) {
                        break;
                    }
                }
                Response::Alarm(code) => {
                    return Err(GrblError::Alarm {
                        code,
                        last_acked: r.last_acked,
                        resume_from: self.resume_point(r, true),
                    })
                }
                _ => obs.event(Event::Message(&line)),
            }
        }
        self.link
            .send_realtime(SOFT_RESET)
            .map_err(|e| lost(e, r))?;
        let mut heard = String::new();
        let mut alarm = false;
        let banner = self
            .wait_banner(&mut heard, &mut alarm, obs)
            .map_err(|e| e.with_stop(r.last_acked, self.resume_point(r, true)))?;
        if banner.is_none() {
            return Err(GrblError::Unresponsive {
                seconds: self.settings.banner_timeout.as_secs_f64(),
                last_acked: r.last_acked,
                resume_from: self.resume_point(r, true),
            });
        }
        if alarm {
            // GRBL 1.1 resets from a completed hold (Hold:0) without an alarm; an
            // alarm here means the hold had not completed within `hold_timeout`.
            obs.event(Event::Message(
                "GRBL is in alarm after the reset (ALARM:3: the reset came before the \
                 hold had stopped the machine); position may be lost: home ($H) before \
                 continuing",
            ));
        }
        Ok(())
    }
}

/// Refuses blocks GRBL cannot take whole: longer than its line buffer (or the
/// receive buffer), or with non-ASCII / control characters.
pub fn check_blocks(blocks: &[Block], settings: &Settings) -> Result<(), GrblError> {
    let max = settings.line_buffer.min(settings.rx_buffer);
    for b in blocks {
        if b.text.len() + 1 > max {
            return Err(GrblError::Input(InputFault::LineTooLong {
                line: b.line,
                chars: b.text.len(),
                most: max - 1,
            }));
        }
        if !b.text.is_ascii() || b.text.bytes().any(|c| c.is_ascii_control()) {
            return Err(GrblError::Input(InputFault::NotAscii { line: b.line }));
        }
    }
    Ok(())
}

impl Run<'_> {
    /// Adds the time since the last change of `in_flight` to the fill average,
    /// while lines remain to be sent (the drain at the end is not streaming).
    fn account(&mut self) {
        let now = Instant::now();
        if self.next < self.blocks.len() {
            let dt = (now - self.last_change).as_secs_f64();
            self.fill_integral += dt * self.in_flight as f64;
            self.fill_time += dt;
        }
        self.last_change = now;
    }
}

fn lost(e: GrblError, r: &Run<'_>) -> GrblError {
    let resume = resume_point(r, PLANNER_BLOCKS);
    e.with_stop(r.last_acked, resume)
}

/// GRBL 1.1's usable planner blocks (BLOCK_BUFFER_SIZE 16, one kept free).
const PLANNER_BLOCKS: usize = 15;

/// The acknowledged lines that may still sit unexecuted in GRBL's planner are the
/// last `planner_used` lines with axis words (one block each; an arc takes several
/// blocks, which only moves the point earlier). Resume at the oldest of them, or
/// after the last acknowledged line when the planner is empty.
fn resume_point(r: &Run<'_>, planner_used: usize) -> Option<usize> {
    if planner_used == 0 {
        return r.last_acked.map(|l| l + 1);
    }
    if r.acked_motion.len() < planner_used {
        return None;
    }
    r.acked_motion
        .get(r.acked_motion.len() - planner_used)
        .copied()
}

/// Seconds of `G4 P` dwell in the unacknowledged lines: GRBL is idle while it
/// dwells, so a stall is declared only after them (each capped at an hour).
fn pending_dwell(r: &Run<'_>) -> Duration {
    let secs: f64 = r
        .pending
        .iter()
        .map(|&(i, _)| dwell_seconds(&r.blocks[i].text))
        .sum();
    Duration::from_secs_f64(secs)
}

/// The `P` of a block with a `G4` word (cleaned, upper-case text), else 0.
fn dwell_seconds(block: &str) -> f64 {
    let mut words = Vec::new();
    let mut rest = block;
    while let Some(c) = rest.chars().next() {
        let tail = &rest[c.len_utf8()..];
        let end = tail
            .find(|ch: char| ch.is_ascii_alphabetic())
            .unwrap_or(tail.len());
        words.push((c, tail[..end].parse::<f64>().ok()));
        rest = &tail[end..];
    }
    let dwell = words.iter().any(|&(c, v)| c == 'G' && v == Some(4.0));
    let p = words
        .iter()
        .find_map(|&(c, v)| (c == 'P').then_some(v).flatten());
    match p {
        Some(p) if dwell && p.is_finite() && p > 0.0 => p.min(3600.0),
        _ => 0.0,
    }
}

fn truncate(s: &str, n: usize) -> String {
    s.chars().take(n).collect()
}

/// What the program did before line `n`: the highest Z it reached and the feed
/// (mm/min) of its last plunge, a `G1` in units per minute that moves Z down and
/// neither X nor Y.
fn history_before(program: &Program, n: usize) -> (Option<f64>, Option<f64>) {
    let mut highest_z: Option<f64> = None;
    let mut plunge_feed = None;
    let mut s = ModalState::default();
    for l in program.blocks().take_while(|l| l.number < n) {
        let before = s.position;
        if s.execute(&l.block).is_err() {
            continue;
        }
        let after = s.position;
        if let Some(z) = after[2] {
            highest_z = Some(highest_z.map_or(z, |h: f64| h.max(z)));
        }
        let down = matches!((before[2], after[2]), (Some(a), Some(b)) if b < a);
        if down
            && s.motion == Motion::Linear
            && s.feed_mode == FeedMode::UnitsPerMinute
            && before[..2] == after[..2]
        {
            plunge_feed = s.feed.or(plunge_feed);
        }
    }
    (highest_z, plunge_feed)
}

/// Options for resuming a job from a line.
#[derive(Clone, Debug)]
pub struct Resume {
    /// 1-based file line to resume at (this line is sent, earlier ones are not).
    pub line: usize,
    /// Safe Z in work coordinates, mm; `None`: the highest Z the program reached
    /// before `line`.
    pub safe_z: Option<f64>,
    /// Dwell after starting the spindle, seconds.
    pub spindle_delay: f64,
}

/// The blocks that bring a machine from anywhere to the state in force at
/// `resume.line`, followed by the program from that line on.
///
/// Preamble: units, plane, work coordinate system, absolute mode; rapid up to safe
/// Z; spindle (speed and direction) and coolant restored, with a dwell for spin-up;
/// rapid to X/Y of the resume point; feed down to its Z; then distance mode, feed
/// mode, motion mode and feed rate as they were. Fails when the position at that
/// line is not known (G28/G30/G53/G10 before it, or an axis never set), when no
/// feed rate is set, or when the program has an error before the line.
pub fn resume_blocks(program: &Program, resume: &Resume) -> Result<Vec<Block>, GrblError> {
    let n = resume.line;
    let point = ResumePoint::find(program, resume)?;
    let mut blocks: Vec<Block> = point
        .preamble(resume.spindle_delay)
        .into_iter()
        .map(|text| Block { line: 0, text })
        .collect();
    blocks.extend(program.blocks().filter(|l| l.number >= n).map(|l| Block {
        line: l.number,
        text: l.block.clone(),
    }));
    Ok(blocks)
}

/// Where a resumed program picks up and the state in force there.
struct ResumePoint {
    /// The modal state before the line.
    state: ModalState,
    /// The work position before the line, mm.
    pos: [f64; 3],
    /// The height to travel at, mm: `--safe-z`, else the highest Z before.
    safe_z: f64,
    /// The feed rate in force, mm/min.
    feed: f64,
    /// The program's plunge feed before the line, mm/min, if it has one.
    plunge_feed: Option<f64>,
}

impl ResumePoint {
    /// The state before `resume.line`: an error when the line is not in the
    /// file, the program has an error or has ended before it, or the position,
    /// a safe Z or the feed rate is not known there.
    fn find(program: &Program, resume: &Resume) -> Result<ResumePoint, GrblError> {
        let n = resume.line;
        let last = program.lines.len();
        if n == 0 || n > last {
            return Err(GrblError::Input(InputFault::ResumeOutside {
                line: n,
                last,
            }));
        }
        let state = program
            .state_before(n)
            .map_err(|e| GrblError::Input(InputFault::ResumeState { line: n, error: e }))?;
        let (highest_z, plunge_feed) = history_before(program, n);
        let safe_z = resume
            .safe_z
            .or(highest_z)
            .ok_or(GrblError::Input(InputFault::ResumeNoSafeZ { line: n }))?;
        let axis = ['X', 'Y', 'Z'];
        let mut pos = [0.0; 3];
        for i in 0..3 {
            pos[i] = state.position[i].ok_or_else(|| {
                GrblError::Input(InputFault::ResumePosition {
                    line: n,
                    axis: axis[i],
                })
            })?;
        }
        let feed = state
            .feed
            .ok_or(GrblError::Input(InputFault::ResumeNoFeed { line: n }))?;
        if state.ended {
            return Err(GrblError::Input(InputFault::ResumeEnded { line: n }));
        }
        Ok(ResumePoint {
            state,
            pos,
            safe_z,
            feed,
            plunge_feed,
        })
    }

    /// The preamble (see [`resume_blocks`]), in the program's units, with a
    /// dwell of `spindle_delay` s after a running spindle is started.
    fn preamble(&self, spindle_delay: f64) -> Vec<String> {
        let state = &self.state;
        let u = ProgramUnits::of(state.units);
        let mut out: Vec<String> = Vec::new();
        out.push(format!(
            "{}{}G{}G90G94",
            if state.units == Units::Inch {
                "G20"
            } else {
                "G21"
            },
            match state.plane {
                Plane::XY => "G17",
                Plane::ZX => "G18",
                Plane::YZ => "G19",
            },
            state.wcs
        ));
        // Rounded up, so the printed safe Z is never below the asked one.
        let scale = 10f64.powi(u.decimals as i32);
        let safe = (u.of_mm(self.safe_z.max(self.pos[2])) * scale).ceil() / scale;
        out.push(format!("G0Z{}", u.num(safe)));
        let spindle = match state.spindle {
            Spindle::Off => "M5",
            Spindle::Cw => "M3",
            Spindle::Ccw => "M4",
        };
        out.push(format!("{spindle}S{}", u.num(state.spindle_speed)));
        out.extend(coolant_blocks(state.mist, state.flood));
        if state.spindle != Spindle::Off && spindle_delay > 0.0 {
            out.push(format!("G4P{}", u.num(spindle_delay)));
        }
        out.push(format!(
            "G0X{}Y{}",
            u.num(u.of_mm(self.pos[0])),
            u.num(u.of_mm(self.pos[1]))
        ));
        // Down at the program's own plunge feed, then its cutting feed is restored.
        let plunge = self.plunge_feed.unwrap_or(self.feed);
        out.push(format!(
            "G1Z{}F{}",
            u.num(u.of_mm(self.pos[2])),
            u.num(u.of_mm(plunge))
        ));
        out.extend(self.restored_modes(plunge, &u));
        out
    }

    /// The block that restores, after the plunge at `plunge` mm/min, the
    /// cutting feed, distance mode, feed mode and motion mode; `None` when
    /// nothing differs from what the preamble leaves.
    fn restored_modes(&self, plunge: f64, u: &ProgramUnits) -> Option<String> {
        let state = &self.state;
        let mut modes = String::new();
        if plunge != self.feed {
            modes.push_str(&format!("F{}", u.num(u.of_mm(self.feed))));
        }
        if state.distance == Distance::Incremental {
            modes.push_str("G91");
        }
        if state.feed_mode == FeedMode::InverseTime {
            modes.push_str("G93");
        }
        match state.motion {
            Motion::Rapid => modes.push_str("G0"),
            Motion::None => modes.push_str("G80"),
            // G1 is in force after the plunge; G2/G3/G38.x need axis words, so the
            // program's own line has to name them (CAM output does).
            _ => {}
        }
        (!modes.is_empty()).then_some(modes)
    }
}

/// The blocks that restore coolant: M9, M7, M8, or M7 and M8 on two lines
/// (they share GRBL's coolant modal group: two words in one block are error
/// 21).
fn coolant_blocks(mist: bool, flood: bool) -> Vec<String> {
    match (mist, flood) {
        (false, false) => vec!["M9".into()],
        (true, false) => vec!["M7".into()],
        (false, true) => vec!["M8".into()],
        (true, true) => vec!["M7".into(), "M8".into()],
    }
}

/// Numbers written in a program's units: 4 decimals in mm, 5 in inches.
struct ProgramUnits {
    /// The program is in inches (G20).
    inch: bool,
    /// Decimals written.
    decimals: usize,
}

impl ProgramUnits {
    /// The units of a program in `units`.
    fn of(units: Units) -> ProgramUnits {
        let inch = units == Units::Inch;
        ProgramUnits {
            inch,
            decimals: if inch { 5 } else { 4 },
        }
    }

    /// A length (or feed) in mm in the program's units.
    fn of_mm(&self, mm: f64) -> f64 {
        if self.inch {
            mm / 25.4
        } else {
            mm
        }
    }

    /// A number with the units' decimals, trailing zeros dropped, no `-0`.
    fn num(&self, v: f64) -> String {
        let decimals = self.decimals;
        let s = format!("{v:.decimals$}");
        let s = s.trim_end_matches('0').trim_end_matches('.').to_string();
        if s == "-0" {
            "0".to_string()
        } else {
            s
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resume_preamble_restores_state() {
        let p = Program::parse(
            "G21 G90 G17\nG0 Z5\nM3 S12000\nM8\nG0 X10 Y10\nG1 Z-1 F300\nG1 X20\nG1 Y20\nM5\n",
        );
        let b = resume_blocks(
            &p,
            &Resume {
                line: 8,
                safe_z: None,
                spindle_delay: 1.0,
            },
        )
        .unwrap();
        let texts: Vec<&str> = b.iter().map(|b| b.text.as_str()).collect();
        assert_eq!(
            texts,
            [
                "G21G17G54G90G94",
                "G0Z5",
                "M3S12000",
                "M8",
                "G4P1",
                "G0X20Y10",
                "G1Z-1F300",
                "G1Y20",
                "M5"
            ]
        );
        let mut s = ModalState::default();
        for t in &texts[..7] {
            s.execute(t).unwrap();
        }
        let expected = p.state_before(8).unwrap();
        assert_eq!(s.position, expected.position);
        assert_eq!(s.spindle, expected.spindle);
        assert_eq!(s.feed, expected.feed);
        assert_eq!(s.flood, expected.flood);
    }

    #[test]
    fn dwell_is_read_from_g4_only() {
        assert_eq!(dwell_seconds("G4P2.5"), 2.5);
        assert_eq!(dwell_seconds("P3G4"), 3.0);
        assert_eq!(dwell_seconds("G40P2"), 0.0);
        assert_eq!(dwell_seconds("G1X1F100"), 0.0);
        assert_eq!(dwell_seconds("G4P99999"), 3600.0);
    }

    #[test]
    fn resume_refuses_unknown_position() {
        let p = Program::parse("G0 Z5\nG28\nG1 X1 F100\n");
        assert!(resume_blocks(
            &p,
            &Resume {
                line: 3,
                safe_z: Some(5.0),
                spindle_delay: 0.0
            }
        )
        .is_err());
    }
}
