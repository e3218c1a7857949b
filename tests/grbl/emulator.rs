//! TEST SUPPORT ONLY: a GRBL 1.1 emulator on a real pseudo-terminal.
//!
//! Not part of pfcam. It runs in a thread on the master side of a pty
//! (`TTYPort::pair()`); the code under test opens the slave by its path, exactly
//! like `/dev/ttyUSB0`. What it models of GRBL 1.1:
//! - banner `Grbl 1.1h ['$' for help]` on boot and after a soft reset;
//! - a receive buffer of `rx_buffer` bytes: real-time bytes are picked off on
//!   arrival, everything else queues; **exceeding the buffer is recorded as an
//!   overflow** (the tests fail on it);
//! - lines pulled from the buffer only while the planner has a free block (15) and
//!   no feed hold is active; `ok` once parsed and planned, `error:N` (from
//!   pfcam's parser, which mirrors GRBL's codes) otherwise, `error:11` for a line
//!   over 79 characters;
//! - a planner that executes motion at `speedup` × the programmed feed (rapids at
//!   3000 mm/min), so positions in status reports advance;
//! - `?` status reports (state, MPos = work position + `wco` or WPos, Bf, FS,
//!   WCO only every `wco_every`-th report as GRBL does), `!` feed hold
//!   (Hold:1 while decelerating, then Hold:0), `~` resume (ignored before Hold:0,
//!   as GRBL does), 0x18 soft reset (ALARM:3 if in motion or still decelerating
//!   in Hold:1; from Hold:0 straight to Idle, as GRBL 1.1h does);
//! - override bytes 0x90-0x9D (recorded, applied, reported in `Ov:`);
//! - alarm state (G-code gets `error:9`; `$X` / `$H` unlock), `$C` check mode
//!   (leaving it resets), an injectable `ALARM:N` after the k-th line, a link that
//!   dies after the k-th line, an `ok` lost on the way (`drop_ok`), and
//!   personalities that are not GRBL (silent, noise).

use std::collections::VecDeque;
use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use pfcam::gcode::parse::{ModalState, Motion, Spindle};
use serialport::{SerialPort, TTYPort};

/// What is on the other end of the cable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Personality {
    /// GRBL 1.1.
    Grbl,
    /// Reads everything, never says anything.
    Silent,
    /// Says things that are not GRBL.
    Noise,
}

/// Emulator knobs.
#[derive(Clone, Debug)]
pub struct Config {
    pub personality: Personality,
    pub rx_buffer: usize,
    pub planner_blocks: usize,
    /// Simulated seconds per real second.
    pub speedup: f64,
    /// Real time a feed hold takes to decelerate (state Hold:1).
    pub decel: Duration,
    pub start_in_alarm: bool,
    /// After this many G-code lines are received, raise `ALARM:code`.
    pub alarm_after: Option<(usize, u8)>,
    /// After this many G-code lines are received, close the pty master.
    pub die_after: Option<usize>,
    /// After this many G-code lines, stop reading and answering (port stays open).
    pub freeze_after: Option<usize>,
    /// After this many G-code lines, reboot (banner) as on a power glitch.
    pub reboot_after: Option<usize>,
    /// A startup line echoed after the banner (`>G54:ok`).
    pub startup_echo: bool,
    /// The `ok` of this G-code line (1-based count) is lost on the way, as on a
    /// noisy cable: the line runs, the sender never hears about it.
    pub drop_ok: Option<usize>,
    /// Work coordinate offset (G54 in machine coordinates): MPos = work + WCO.
    pub wco: [f64; 3],
    /// `WCO:` goes into every n-th status report only, as in GRBL (10 idle, 30 busy).
    pub wco_every: usize,
    /// Report `WPos:` instead of `MPos:` (GRBL's `$10=0`).
    pub report_wpos: bool,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            personality: Personality::Grbl,
            rx_buffer: 128,
            planner_blocks: 15,
            speedup: 200.0,
            decel: Duration::from_millis(30),
            start_in_alarm: false,
            alarm_after: None,
            die_after: None,
            freeze_after: None,
            reboot_after: None,
            startup_echo: false,
            drop_ok: None,
            wco: [0.0; 3],
            wco_every: 10,
            report_wpos: false,
        }
    }
}

/// One line the emulator received, with the parser state just before it.
#[derive(Clone, Debug)]
pub struct Received {
    pub text: String,
    pub state_before: ModalState,
    pub check_mode: bool,
    /// `ok` (None) or `error:N`.
    pub error: Option<u8>,
}

/// What the tests can look at (and poke).
#[derive(Debug, Default)]
pub struct Shared {
    pub received: Vec<Received>,
    /// Real-time bytes other than `?`, in order, with the number of lines received
    /// before each.
    pub realtime: Vec<(u8, usize)>,
    /// Set when the sender overflowed the receive buffer.
    pub overflow: Option<String>,
    pub max_rx: usize,
    pub state: String,
    pub position: [f64; 3],
    pub spindle_on: bool,
    pub resets: usize,
    pub ignored_resumes: usize,
    pub moved: bool,
    pub boot_requested: bool,
    pub dead: bool,
    /// Lines received when the emulator rebooted (`reboot_after`).
    pub rebooted_at: Option<usize>,
    /// Lines whose moves were still in the planner (not or not fully run) when a
    /// soft reset discarded them.
    pub flushed: Vec<String>,
    /// Feed, rapid and spindle overrides in percent (real-time bytes 0x90-0x9D).
    pub overrides: [u32; 3],
    /// Banners printed (at start, on `boot`, after each reset).
    pub banners: usize,
    /// `ok`s swallowed (`drop_ok`).
    pub dropped_oks: usize,
}

pub struct Emulator {
    pub path: String,
    shared: Arc<Mutex<Shared>>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
    _slave: TTYPort,
}

impl Emulator {
    pub fn start(config: Config) -> Emulator {
        let (master, slave) = TTYPort::pair().expect("pty pair");
        let path = slave.name().expect("pty name");
        let shared = Arc::new(Mutex::new(Shared {
            overrides: [100; 3],
            ..Shared::default()
        }));
        let stop = Arc::new(AtomicBool::new(false));
        let thread = {
            let shared = shared.clone();
            let stop = stop.clone();
            std::thread::spawn(move || Machine::new(master, config, shared, stop).run())
        };
        Emulator {
            path,
            shared,
            stop,
            thread: Some(thread),
            _slave: slave,
        }
    }

    pub fn shared(&self) -> MutexGuard<'_, Shared> {
        self.shared.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Prints the banner now (as a board does when the port opening resets it).
    pub fn boot(&self) {
        self.shared().boot_requested = true;
    }

    /// Waits (bounded) until `cond` holds; panics with `what` otherwise.
    pub fn wait_for(&self, what: &str, cond: impl Fn(&Shared) -> bool) {
        let deadline = Instant::now() + Duration::from_secs(20);
        while Instant::now() < deadline {
            if cond(&self.shared()) {
                return;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        panic!("emulator: timed out waiting for {what}");
    }

    /// G-code lines received outside check mode (texts).
    pub fn lines(&self) -> Vec<String> {
        self.shared()
            .received
            .iter()
            .filter(|r| !r.check_mode && !r.text.starts_with('$'))
            .map(|r| r.text.clone())
            .collect()
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum State {
    Idle,
    Run,
    Hold(u8),
    Alarm,
    Check,
}

struct Block {
    /// The line that planned it.
    text: String,
    from: [f64; 3],
    to: [f64; 3],
    /// Simulated seconds.
    duration: f64,
    done: f64,
}

struct Machine {
    port: TTYPort,
    cfg: Config,
    shared: Arc<Mutex<Shared>>,
    stop: Arc<AtomicBool>,
    rx: VecDeque<u8>,
    planner: VecDeque<Block>,
    state: State,
    hold_until: Option<Instant>,
    modal: ModalState,
    position: [f64; 3],
    out: Vec<u8>,
    reports: usize,
    lines: usize,
    /// The line being executed (for the planner blocks it makes).
    current: String,
    last: Instant,
    noise_at: Instant,
}

const RAPID_MM_PER_MIN: f64 = 3000.0;

impl Machine {
    fn new(
        mut port: TTYPort,
        cfg: Config,
        shared: Arc<Mutex<Shared>>,
        stop: Arc<AtomicBool>,
    ) -> Machine {
        let _ = port.set_timeout(Duration::from_millis(1));
        Machine {
            port,
            cfg,
            shared,
            stop,
            rx: VecDeque::new(),
            planner: VecDeque::new(),
            state: State::Idle,
            hold_until: None,
            modal: ModalState::default(),
            position: [0.0; 3],
            out: Vec::new(),
            reports: 0,
            lines: 0,
            current: String::new(),
            last: Instant::now(),
            noise_at: Instant::now(),
        }
    }

    fn shared(&self) -> MutexGuard<'_, Shared> {
        self.shared.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn say(&mut self, line: &str) {
        self.out.extend_from_slice(line.as_bytes());
        self.out.extend_from_slice(b"\r\n");
    }

    fn banner(&mut self) {
        self.shared().banners += 1;
        self.say("Grbl 1.1h ['$' for help]");
        if self.state == State::Alarm {
            self.say("[MSG:'$H'|'$X' to unlock]");
        } else if self.cfg.startup_echo {
            self.say(">G54:ok");
        }
    }

    fn run(mut self) {
        if self.cfg.start_in_alarm {
            self.state = State::Alarm;
        }
        if self.cfg.personality == Personality::Grbl {
            // Like a board that reset when the port was opened; the opener may
            // flush it (then it has to soft-reset).
            self.banner();
        }
        let mut buf = [0u8; 256];
        while !self.stop.load(Ordering::Relaxed) {
            if std::mem::take(&mut self.shared().boot_requested) {
                self.banner();
            }
            match self.port.read(&mut buf) {
                Ok(n) => {
                    for &b in &buf[..n] {
                        self.byte(b);
                    }
                }
                Err(e) if e.kind() == std::io::ErrorKind::TimedOut => {}
                Err(_) => {}
            }
            self.simulate();
            self.protocol();
            if !self.out.is_empty() {
                let out = std::mem::take(&mut self.out);
                let _ = self.port.write_all(&out);
            }
            if let Some(k) = self.cfg.die_after {
                if self.lines >= k {
                    self.shared().dead = true;
                    return; // drops the master: the link disappears
                }
            }
            if self.cfg.freeze_after.is_some_and(|k| self.lines >= k) {
                // Hung firmware: the port stays open, nothing is read or answered.
                while !self.stop.load(Ordering::Relaxed) {
                    std::thread::sleep(Duration::from_millis(5));
                }
                return;
            }
            if self.cfg.reboot_after.is_some_and(|k| self.lines >= k) {
                self.cfg.reboot_after = None;
                let n = self.shared().received.len();
                self.shared().rebooted_at = Some(n);
                self.state = State::Idle;
                self.reset();
                let out = std::mem::take(&mut self.out);
                let _ = self.port.write_all(&out);
            }
            self.publish();
        }
    }

    fn publish(&mut self) {
        let state = self.state_text();
        let position = self.current_position();
        let spindle_on = self.modal.spindle != Spindle::Off;
        let mut s = self.shared();
        s.state = state;
        s.position = position;
        s.spindle_on = spindle_on;
    }

    fn byte(&mut self, b: u8) {
        match self.cfg.personality {
            Personality::Silent => return,
            Personality::Noise => {
                if self.noise_at.elapsed() > Duration::from_millis(20) {
                    self.noise_at = Instant::now();
                    self.out
                        .extend_from_slice(b"\x7fhello?\r\nAT+OK\r\n\xfe\xfe");
                }
                return;
            }
            Personality::Grbl => {}
        }
        let lines = self.lines;
        match b {
            b'?' => self.status_report(),
            b'!' => {
                self.shared().realtime.push((b, lines));
                match self.state {
                    State::Run => {
                        self.state = State::Hold(1);
                        self.hold_until = Some(Instant::now() + self.cfg.decel);
                    }
                    State::Idle => self.state = State::Hold(0),
                    _ => {}
                }
            }
            b'~' => {
                self.shared().realtime.push((b, lines));
                match self.state {
                    State::Hold(0) => {
                        self.state = if self.planner.is_empty() {
                            State::Idle
                        } else {
                            State::Run
                        }
                    }
                    State::Hold(_) => self.shared().ignored_resumes += 1,
                    _ => {}
                }
            }
            0x18 => {
                self.shared().realtime.push((b, lines));
                self.reset();
            }
            0x90..=0x9d => {
                self.shared().realtime.push((b, lines));
                self.override_byte(b);
            }
            0x80..=0xff => self.shared().realtime.push((b, lines)),
            _ => {
                self.rx.push_back(b);
                let len = self.rx.len();
                let mut s = self.shared();
                s.max_rx = s.max_rx.max(len);
                if len > self.cfg.rx_buffer && s.overflow.is_none() {
                    s.overflow = Some(format!(
                        "receive buffer overflow: {len} bytes > {} after {} lines",
                        self.cfg.rx_buffer, lines
                    ));
                }
            }
        }
    }

    /// GRBL 1.1's override commands: feed and spindle in steps, clamped to
    /// 10..=200 %, rapids at 100/50/25 %.
    fn override_byte(&mut self, b: u8) {
        let mut s = self.shared();
        let step = |v: u32, d: i32| (v as i32 + d).clamp(10, 200) as u32;
        let [feed, rapid, spindle] = &mut s.overrides;
        match b {
            0x90 => *feed = 100,
            0x91 => *feed = step(*feed, 10),
            0x92 => *feed = step(*feed, -10),
            0x93 => *feed = step(*feed, 1),
            0x94 => *feed = step(*feed, -1),
            0x95 => *rapid = 100,
            0x96 => *rapid = 50,
            0x97 => *rapid = 25,
            0x99 => *spindle = 100,
            0x9a => *spindle = step(*spindle, 10),
            0x9b => *spindle = step(*spindle, -10),
            0x9c => *spindle = step(*spindle, 1),
            0x9d => *spindle = step(*spindle, -1),
            _ => {}
        }
    }

    fn reset(&mut self) {
        // GRBL 1.1h `mc_reset`: ALARM:3 only when steppers are moving (a cycle, or a
        // hold still decelerating); a completed hold (Hold:0) resets to Idle.
        let moving = matches!(self.state, State::Run | State::Hold(1));
        self.rx.clear();
        if let Some(b) = self.planner.front() {
            self.position = interpolate(b);
        }
        let flushed: Vec<String> = self.planner.drain(..).map(|b| b.text).collect();
        self.shared().flushed.extend(flushed);
        self.modal = ModalState::default();
        self.modal.position = self.position.map(Some);
        self.hold_until = None;
        self.shared().resets += 1;
        if moving {
            // GRBL: a reset while moving flags possible position loss.
            self.say("ALARM:3");
            self.state = State::Alarm;
        } else if self.state != State::Alarm {
            self.state = State::Idle;
        }
        self.banner();
    }

    fn state_text(&self) -> String {
        match self.state {
            State::Idle => "Idle".into(),
            State::Run => "Run".into(),
            State::Hold(n) => format!("Hold:{n}"),
            State::Alarm => "Alarm".into(),
            State::Check => "Check".into(),
        }
    }

    fn current_position(&self) -> [f64; 3] {
        match self.planner.front() {
            Some(b) => interpolate(b),
            None => self.position,
        }
    }

    fn status_report(&mut self) {
        self.reports += 1;
        let w = self.current_position();
        let o = self.cfg.wco;
        let (kind, p) = if self.cfg.report_wpos {
            ("WPos", w)
        } else {
            ("MPos", [w[0] + o[0], w[1] + o[1], w[2] + o[2]])
        };
        let mut r = format!(
            "<{}|{kind}:{:.3},{:.3},{:.3}|Bf:{},{}|FS:{:.0},{:.0}",
            self.state_text(),
            p[0],
            p[1],
            p[2],
            self.cfg.planner_blocks - self.planner.len(),
            self.cfg.rx_buffer.saturating_sub(self.rx.len()),
            if self.state == State::Run {
                self.modal.feed.unwrap_or(0.0)
            } else {
                0.0
            },
            self.modal.spindle_speed
        );
        if (self.reports - 1) % self.cfg.wco_every.max(1) == 0 {
            r.push_str(&format!("|WCO:{:.3},{:.3},{:.3}", o[0], o[1], o[2]));
        }
        if self.reports % 10 == 2 {
            let [f, r0, sp] = self.shared().overrides;
            r.push_str(&format!("|Ov:{f},{r0},{sp}"));
        }
        r.push('>');
        self.say(&r);
    }

    fn simulate(&mut self) {
        let now = Instant::now();
        let dt = (now - self.last).as_secs_f64() * self.cfg.speedup;
        self.last = now;
        if let State::Hold(1) = self.state {
            if self.hold_until.is_some_and(|t| now >= t) {
                self.state = State::Hold(0);
            }
        }
        if self.state != State::Run {
            return;
        }
        let mut dt = dt;
        while let Some(b) = self.planner.front_mut() {
            let left = b.duration - b.done;
            if dt < left {
                b.done += dt;
                break;
            }
            dt -= left;
            self.position = b.to;
            self.planner.pop_front();
        }
        if self.planner.is_empty() {
            self.state = State::Idle;
        }
    }

    fn protocol(&mut self) {
        loop {
            if matches!(self.state, State::Hold(_)) {
                return; // per GRBL's docs for senders: no lines read during a hold
            }
            if self.planner.len() >= self.cfg.planner_blocks {
                return;
            }
            let Some(end) = self.rx.iter().position(|&b| b == b'\n') else {
                return;
            };
            let raw: Vec<u8> = self.rx.drain(..=end).collect();
            let text = String::from_utf8_lossy(&raw).trim().to_string();
            if text.is_empty() {
                continue;
            }
            self.line(text);
            if self.stop.load(Ordering::Relaxed) {
                return;
            }
        }
    }

    fn line(&mut self, text: String) {
        self.current = text.clone();
        let before = self.modal.clone();
        let check = self.state == State::Check;
        let mut error = None;
        let mut extra_ok = true;
        if let Some(cmd) = text.strip_prefix('$') {
            match cmd {
                "X" if self.state == State::Alarm => {
                    self.say("[MSG:Caution: Unlocked]");
                    self.state = State::Idle;
                }
                "H" => {
                    self.position = [0.0; 3];
                    self.modal.position = [Some(0.0); 3];
                    self.state = State::Idle;
                }
                "C" => match self.state {
                    State::Check => {
                        self.say("[MSG:Disabled]");
                        self.say("ok");
                        extra_ok = false;
                        self.state = State::Idle;
                        self.reset();
                    }
                    State::Idle => {
                        self.say("[MSG:Enabled]");
                        self.state = State::Check;
                    }
                    _ => error = Some(8),
                },
                "G" => self.say("[GC:G0 G54 G17 G21 G90 G94 M5 M9 T0 F0 S0]"),
                _ => {}
            }
        } else {
            self.lines += 1;
            if text.len() > 79 {
                error = Some(11);
            } else if self.state == State::Alarm {
                error = Some(9);
            } else {
                match self.modal.execute(&text) {
                    Err(e) => error = Some(e.code),
                    Ok(()) => {
                        if check {
                            // Check mode parses but never moves.
                            self.modal.position = before.position;
                        } else {
                            self.plan(&before);
                        }
                    }
                }
            }
        }
        let pgm_end = error.is_none() && !check && self.modal.ended && !before.ended;
        self.shared().received.push(Received {
            text: text.clone(),
            state_before: before,
            check_mode: check,
            error,
        });
        if error.is_none() && !check && matches!(self.modal.motion, Motion::Probe(_)) {
            let p = self.position_end();
            self.say(&format!("[PRB:{:.3},{:.3},{:.3}:1]", p[0], p[1], p[2]));
        }
        if pgm_end {
            self.say("[MSG:Pgm End]");
            self.modal.ended = false;
        }
        let lost = !text.starts_with('$') && self.cfg.drop_ok == Some(self.lines);
        match error {
            Some(n) => self.say(&format!("error:{n}")),
            None if extra_ok && lost => self.shared().dropped_oks += 1,
            None if extra_ok => self.say("ok"),
            None => {}
        }
        if let Some((k, code)) = self.cfg.alarm_after {
            if self.lines == k && self.state != State::Alarm {
                // A hard limit: GRBL stops dead and flushes everything.
                if let Some(b) = self.planner.front() {
                    self.position = interpolate(b);
                }
                self.planner.clear();
                self.rx.clear();
                self.say(&format!("ALARM:{code}"));
                self.state = State::Alarm;
            }
        }
    }

    fn plan(&mut self, before: &ModalState) {
        let to = [0, 1, 2].map(|i| self.modal.position[i].unwrap_or(self.position_end()[i]));
        let from = self.position_end();
        let dist =
            ((to[0] - from[0]).powi(2) + (to[1] - from[1]).powi(2) + (to[2] - from[2]).powi(2))
                .sqrt();
        if dist == 0.0 && self.modal.position == before.position {
            return;
        }
        let rate = match self.modal.motion {
            Motion::Rapid => RAPID_MM_PER_MIN,
            _ => self.modal.feed_mm_per_min().unwrap_or(RAPID_MM_PER_MIN),
        };
        self.planner.push_back(Block {
            text: self.current.clone(),
            from,
            to,
            duration: dist / (rate / 60.0),
            done: 0.0,
        });
        self.shared().moved = true;
        if self.state == State::Idle {
            self.state = State::Run;
        }
    }

    fn position_end(&self) -> [f64; 3] {
        self.planner.back().map(|b| b.to).unwrap_or(self.position)
    }
}

fn interpolate(b: &Block) -> [f64; 3] {
    let t = if b.duration > 0.0 {
        (b.done / b.duration).clamp(0.0, 1.0)
    } else {
        1.0
    };
    [0, 1, 2].map(|i| b.from[i] + (b.to[i] - b.from[i]) * t)
}
