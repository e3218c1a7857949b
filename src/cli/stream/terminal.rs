//! The stream's display: a progress bar when standard error is a terminal, a
//! plain line every 5 s otherwise, and GRBL's messages and the hold prompt.

use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use pfcam::grbl::protocol::{Position, StatusReport, WorkOffset};
use pfcam::grbl::{Event, Observer};

use super::note;

/// Progress bar on a terminal, plain periodic lines otherwise.
pub struct Terminal {
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
    pub fn new(held: Arc<AtomicBool>, interactive: bool) -> Terminal {
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

    pub fn finish(&self) {
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
