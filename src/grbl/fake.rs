//! An in-memory GRBL for the streamer's unit tests: a `Read + Write` byte stream
//! that answers as GRBL 1.1 does (banner, `ok` / `error:N` in order, status
//! reports, feed hold, soft reset) and records what pfcam sent. No pty, no thread.
//!
//! It answers one line per millisecond at most, so the streamer keeps its receive
//! buffer full and the character counting is really exercised. `tests/grbl/main.rs`
//! has the full emulator (planner, alarms, overrides) on a pseudo-terminal.

use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use super::protocol::{CYCLE_START, FEED_HOLD, SOFT_RESET, STATUS_QUERY};

/// GRBL 1.1's receive buffer.
const RX_BUFFER: usize = 128;
/// Time GRBL takes to parse one line here.
const LINE_TIME: Duration = Duration::from_millis(1);
/// How long a read waits for something to say.
const READ_WAIT: Duration = Duration::from_millis(5);
const BANNER: &str = "\r\nGrbl 1.1h ['$' for help]\r\n";

/// What the fake GRBL has seen and holds.
#[derive(Debug)]
pub(crate) struct State {
    /// Bytes waiting for pfcam to read.
    out: VecDeque<u8>,
    /// The line being received.
    partial: Vec<u8>,
    /// Whole lines received and not answered yet.
    queued: VecDeque<String>,
    /// Bytes in the receive buffer (queued lines and the partial one, newlines
    /// included), now and at most.
    pub in_rx: usize,
    pub max_rx: usize,
    /// Every line received, in order.
    pub lines: Vec<String>,
    /// Every real-time byte received other than `?`.
    pub realtime: Vec<u8>,
    /// Lines containing this text are answered `error:N`.
    pub reject: Option<(&'static str, u8)>,
    /// In a feed hold (`!` received, no `~` since): no line is answered.
    held: bool,
    last_answer: Instant,
}

/// The fake port; clones share one GRBL (one for the reader, one for the writer).
#[derive(Clone)]
pub(crate) struct FakeGrbl {
    shared: Arc<(Mutex<State>, Condvar)>,
}

impl FakeGrbl {
    /// A GRBL that has just printed its banner.
    pub fn new() -> FakeGrbl {
        let state = State {
            out: BANNER.bytes().collect(),
            partial: Vec::new(),
            queued: VecDeque::new(),
            in_rx: 0,
            max_rx: 0,
            lines: Vec::new(),
            realtime: Vec::new(),
            reject: None,
            held: false,
            last_answer: Instant::now(),
        };
        FakeGrbl {
            shared: Arc::new((Mutex::new(state), Condvar::new())),
        }
    }

    /// Its state, to inspect or configure.
    pub fn state(&self) -> MutexGuard<'_, State> {
        self.shared.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl State {
    fn say(&mut self, text: &str) {
        self.out.extend(text.bytes());
    }

    fn status(&self) -> String {
        let state = if self.held {
            "Hold:0"
        } else if self.queued.is_empty() {
            "Idle"
        } else {
            "Run"
        };
        let free = RX_BUFFER.saturating_sub(self.in_rx);
        format!("<{state}|MPos:0.000,0.000,0.000|Bf:15,{free}|FS:0,0>\r\n")
    }

    fn receive(&mut self, byte: u8) {
        match byte {
            STATUS_QUERY => {
                let s = self.status();
                self.say(&s);
            }
            SOFT_RESET => {
                self.realtime.push(byte);
                self.queued.clear();
                self.partial.clear();
                self.in_rx = 0;
                self.held = false;
                self.say(BANNER);
            }
            FEED_HOLD | CYCLE_START => {
                self.realtime.push(byte);
                self.held = byte == FEED_HOLD;
            }
            0x80.. => self.realtime.push(byte),
            b'\n' => {
                self.in_rx += 1;
                let line = String::from_utf8_lossy(&self.partial).into_owned();
                self.partial.clear();
                self.lines.push(line.clone());
                self.queued.push_back(line);
            }
            b => {
                self.in_rx += 1;
                self.partial.push(b);
            }
        }
        self.max_rx = self.max_rx.max(self.in_rx);
    }

    /// Answers the oldest line if GRBL has had time to parse it.
    fn answer(&mut self) {
        if self.held || self.last_answer.elapsed() < LINE_TIME {
            return;
        }
        let Some(line) = self.queued.pop_front() else {
            return;
        };
        self.last_answer = Instant::now();
        self.in_rx -= line.len() + 1;
        match self.reject {
            Some((text, code)) if line.contains(text) => self.say(&format!("error:{code}\r\n")),
            _ => self.say("ok\r\n"),
        }
    }
}

impl Write for FakeGrbl {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let mut s = self.state();
        for &b in buf {
            s.receive(b);
        }
        drop(s);
        self.shared.1.notify_all();
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

impl Read for FakeGrbl {
    /// What GRBL has to say, or `TimedOut` after a short wait (as a serial port
    /// with a read timeout).
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let (lock, cvar) = &*self.shared;
        let mut s = lock.lock().unwrap_or_else(|e| e.into_inner());
        s.answer();
        if s.out.is_empty() {
            // Until the next line is parsed, or something is sent.
            let wait = if s.held || s.queued.is_empty() {
                READ_WAIT
            } else {
                LINE_TIME.saturating_sub(s.last_answer.elapsed())
            };
            s = cvar
                .wait_timeout(s, wait)
                .unwrap_or_else(|e| e.into_inner())
                .0;
            s.answer();
        }
        if s.out.is_empty() {
            return Err(io::ErrorKind::TimedOut.into());
        }
        let n = buf.len().min(s.out.len());
        for (slot, byte) in buf.iter_mut().zip(s.out.drain(..n)) {
            *slot = byte;
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gcode::parse::Program;
    use crate::grbl::{Block, Event, GrblError, Link, Observer, OperatorCommand, Settings};
    use crate::grbl::{StreamReport, Streamer};
    use std::sync::mpsc::{self, Sender};

    fn settings() -> Settings {
        Settings {
            status_interval: Duration::from_millis(10),
            banner_timeout: Duration::from_millis(500),
            response_timeout: Duration::from_secs(3),
            hold_timeout: Duration::from_secs(3),
            ..Settings::default()
        }
    }

    /// `n` moves of about 25 bytes after a short header.
    fn job(n: usize) -> Vec<Block> {
        let mut text = String::from("G21 G90\nG0 Z5\nM3 S10000\nG1 Z-1 F300\n");
        for i in 0..n {
            text.push_str(&format!("G1 X{:.3} Y{:.3} F800\n", i as f64 * 0.5, i % 7));
        }
        text.push_str("M5\nM30\n");
        Block::from_program(&Program::parse(&text))
    }

    /// Sends `command` to the streamer once `at` lines are acknowledged.
    struct At {
        at: usize,
        command: OperatorCommand,
        tx: Sender<OperatorCommand>,
    }

    impl Observer for At {
        fn event(&mut self, event: Event<'_>) {
            if let Event::Progress { acked, .. } = event {
                if acked == self.at {
                    let _ = self.tx.send(self.command);
                }
            }
        }
    }

    /// Streams `blocks` to `grbl`; `command` goes to the streamer after `at` acks.
    fn stream(
        grbl: &FakeGrbl,
        blocks: &[Block],
        at: usize,
        command: OperatorCommand,
    ) -> Result<StreamReport, GrblError> {
        let link = Link::from_io("fake", grbl.clone(), grbl.clone()).expect("link");
        let (tx, rx) = mpsc::channel();
        let mut obs = At { at, command, tx };
        let mut streamer = Streamer::connect(link, settings(), &mut obs)?;
        streamer.stream(blocks, &rx, &mut obs)
    }

    #[test]
    fn character_counting_keeps_at_most_128_bytes_in_flight() {
        let grbl = FakeGrbl::new();
        let blocks = job(300);
        let report = stream(&grbl, &blocks, 0, OperatorCommand::Resume).expect("completes");
        assert_eq!(report.acked, blocks.len());
        assert!(
            report.max_in_flight <= RX_BUFFER,
            "{}",
            report.max_in_flight
        );
        let s = grbl.state();
        assert!(s.max_rx <= RX_BUFFER, "GRBL held {} bytes", s.max_rx);
        // Slower than pfcam: the buffer really filled.
        assert!(s.max_rx > RX_BUFFER - 30, "at most {} bytes", s.max_rx);
        let sent: Vec<&str> = blocks.iter().map(|b| b.text.as_str()).collect();
        assert_eq!(s.lines, sent, "every line once, in order");
        assert!(s.realtime.is_empty(), "{:?}", s.realtime);
    }

    #[test]
    fn error_stops_the_stream_with_its_line() {
        let grbl = FakeGrbl::new();
        let mut blocks = job(200);
        blocks[60].text = "G41X10".into();
        let line = blocks[60].line;
        grbl.state().reject = Some(("G41", 20));
        let err = stream(&grbl, &blocks, 0, OperatorCommand::Resume).expect_err("stops");
        let GrblError::Rejected { fault, .. } = &err else {
            panic!("{err:?}");
        };
        assert_eq!((fault.line, fault.code), (line, 20));
        assert!(err.to_string().contains(&format!("line {line}")), "{err}");
        let s = grbl.state();
        assert_eq!(s.realtime, [FEED_HOLD, SOFT_RESET], "hold, then reset");
        assert!(s.lines.len() < blocks.len(), "stopped early");
        assert!(s.max_rx <= RX_BUFFER);
    }

    #[test]
    fn abort_holds_then_resets() {
        let grbl = FakeGrbl::new();
        let blocks = job(300);
        let err = stream(&grbl, &blocks, 40, OperatorCommand::Abort).expect_err("aborted");
        let GrblError::Aborted { by, last_acked, .. } = &err else {
            panic!("{err:?}");
        };
        assert_eq!(*by, "aborted by the operator");
        assert!(last_acked.is_some_and(|l| l >= blocks[39].line), "{err:?}");
        let s = grbl.state();
        assert_eq!(s.realtime, [FEED_HOLD, SOFT_RESET], "hold, then reset");
        assert!(s.lines.len() < blocks.len(), "stopped early");
    }

    #[test]
    fn hold_then_resume_completes_the_job() {
        let grbl = FakeGrbl::new();
        let blocks = job(150);
        let link = Link::from_io("fake", grbl.clone(), grbl.clone()).expect("link");
        let (tx, rx) = mpsc::channel();
        // Hold after 30 lines; resume once the hold is complete.
        struct HoldResume(Sender<OperatorCommand>);
        impl Observer for HoldResume {
            fn event(&mut self, event: Event<'_>) {
                let command = match event {
                    Event::Progress { acked: 30, .. } => OperatorCommand::Hold,
                    Event::HoldComplete => OperatorCommand::Resume,
                    _ => return,
                };
                let _ = self.0.send(command);
            }
        }
        let mut obs = HoldResume(tx);
        let mut streamer = Streamer::connect(link, settings(), &mut obs).expect("connects");
        let report = streamer.stream(&blocks, &rx, &mut obs).expect("completes");
        assert_eq!(report.acked, blocks.len());
        let s = grbl.state();
        assert_eq!(s.realtime, [FEED_HOLD, CYCLE_START]);
        assert_eq!(s.lines.len(), blocks.len());
    }
}
