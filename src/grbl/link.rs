//! The link to GRBL: any byte stream (a serial port, or an in-memory fake in the
//! tests), a reader thread that splits GRBL's output into lines, and an optional
//! traffic log.
//!
//! Reads never block the streamer: the reader thread polls its handle with a short
//! timeout and hands whole lines over a channel, so every wait in the streamer is a
//! bounded `recv_timeout`. A port that fails or hangs up (USB unplugged, pty master
//! closed) ends the reader with `Incoming::Closed`.

use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use serialport::SerialPort;

use super::GrblError;

/// How long one port read waits before the reader checks whether to stop.
const READ_POLL: Duration = Duration::from_millis(20);
/// How long one write may wait for the port (a stuck port is an error, not a hang).
const WRITE_TIMEOUT: Duration = Duration::from_secs(2);
/// Bytes without a newline after which the reader hands them over anyway, so noise
/// from a device that is not GRBL is seen (and reported) instead of piling up.
const MAX_LINE: usize = 256;

/// What the reader thread hands over.
#[derive(Debug)]
pub(crate) enum Incoming {
    /// One line, without `\r\n`.
    Line(String),
    /// The port failed; the reader stopped.
    Closed(String),
}

/// A traffic log: every line sent and received, with seconds since the link opened.
pub type LogSink = Box<dyn Write + Send>;

/// An open link to a (possible) GRBL controller.
///
/// It writes through one handle of the byte stream and reads through another on
/// its own thread: [`Link::open`] / [`Link::from_port`] for a serial port (two
/// handles of one port), [`Link::from_io`] for anything that is `Read` + `Write`.
pub struct Link {
    name: String,
    port: Box<dyn Write + Send>,
    rx: Receiver<Incoming>,
    stop: Arc<AtomicBool>,
    reader: Option<JoinHandle<()>>,
    log: Option<LogSink>,
    start: Instant,
    closed: Option<String>,
}

impl Link {
    /// Opens `path` at `baud` 8N1, no flow control, and starts fresh: DTR is
    /// toggled where the port allows it (an Arduino-style board resets and prints a
    /// new banner), then whatever arrived before now is thrown away, so a banner or
    /// an `ok` printed before pfcam connected is never taken as fresh.
    pub fn open(path: &str, baud: u32) -> Result<Link, GrblError> {
        let mut port = serialport::new(path, baud)
            .data_bits(serialport::DataBits::Eight)
            .parity(serialport::Parity::None)
            .stop_bits(serialport::StopBits::One)
            .flow_control(serialport::FlowControl::None)
            .timeout(WRITE_TIMEOUT)
            .open()
            .map_err(|e| GrblError::Open {
                port: path.to_string(),
                reason: e.to_string(),
            })?;
        fresh_start(port.as_mut());
        Link::from_port(path, port)
    }

    /// Wraps an already open serial port: writes wait at most 2 s, and a clone of
    /// the port read with a short timeout feeds the reader thread.
    pub fn from_port(name: &str, mut port: Box<dyn SerialPort>) -> Result<Link, GrblError> {
        let open_err = |e: serialport::Error| GrblError::Open {
            port: name.to_string(),
            reason: e.to_string(),
        };
        port.set_timeout(WRITE_TIMEOUT).map_err(open_err)?;
        let mut reader_port = port.try_clone().map_err(open_err)?;
        reader_port.set_timeout(READ_POLL).map_err(open_err)?;
        Link::from_io(name, reader_port, port)
    }

    /// A link over any byte stream: `writer` takes what pfcam sends, `reader`
    /// (moved to the reader thread) yields what GRBL answers.
    ///
    /// `reader` must not block for long: a read returns data, or an
    /// `ErrorKind::TimedOut` / `WouldBlock` error within a few tens of
    /// milliseconds (a serial port with a read timeout does), so the thread can
    /// notice when the link is dropped. `Ok(0)` or any other error means the
    /// link is gone.
    pub fn from_io(
        name: &str,
        reader: impl Read + Send + 'static,
        writer: impl Write + Send + 'static,
    ) -> Result<Link, GrblError> {
        let (tx, rx) = mpsc::channel();
        let stop = Arc::new(AtomicBool::new(false));
        let stop_reader = stop.clone();
        let reader = std::thread::Builder::new()
            .name("grbl-reader".into())
            .spawn(move || read_lines(reader, tx, stop_reader))
            .map_err(|e| GrblError::Open {
                port: name.to_string(),
                reason: format!("cannot start the reader thread: {e}"),
            })?;
        Ok(Link {
            name: name.to_string(),
            port: Box::new(writer),
            rx,
            stop,
            reader: Some(reader),
            log: None,
            start: Instant::now(),
            closed: None,
        })
    }

    /// Records all traffic to `sink` from now on.
    pub fn set_log(&mut self, sink: LogSink) {
        self.log = Some(sink);
    }

    /// The port's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    fn log(&mut self, dir: &str, text: &str) {
        let t = self.start.elapsed().as_secs_f64();
        if let Some(log) = self.log.as_mut() {
            // A failing log must not stop a running machine: ignore write errors.
            let _ = writeln!(log, "{t:10.3} {dir} {text}");
        }
    }

    fn lost(&mut self, reason: String) -> GrblError {
        self.closed = Some(reason.clone());
        GrblError::LinkLost {
            reason,
            last_acked: None,
            resume_from: None,
        }
    }

    /// Sends one line; appends `\n`.
    pub fn send_line(&mut self, line: &str) -> Result<(), GrblError> {
        self.log(">", line);
        let mut bytes = Vec::with_capacity(line.len() + 1);
        bytes.extend_from_slice(line.as_bytes());
        bytes.push(b'\n');
        if let Err(e) = self.port.write_all(&bytes).and_then(|_| self.port.flush()) {
            return Err(self.lost(format!("write failed: {e}")));
        }
        Ok(())
    }

    /// Sends one real-time byte, as a byte (0x85+ must not become UTF-8).
    /// Logged as `[0xNN]`, except `?` queries: their answers are logged.
    pub fn send_realtime(&mut self, byte: u8) -> Result<(), GrblError> {
        if byte != super::protocol::STATUS_QUERY {
            self.log(">", &format!("[0x{byte:02X}]"));
        }
        if let Err(e) = self.port.write_all(&[byte]).and_then(|_| self.port.flush()) {
            return Err(self.lost(format!("write failed: {e}")));
        }
        Ok(())
    }

    /// Next line from GRBL, waiting at most `timeout`; `Ok(None)` on timeout.
    pub fn recv(&mut self, timeout: Duration) -> Result<Option<String>, GrblError> {
        if let Some(reason) = self.closed.clone() {
            return Err(self.lost(reason));
        }
        match self.rx.recv_timeout(timeout) {
            Ok(Incoming::Line(line)) => {
                self.log("<", &line);
                Ok(Some(line))
            }
            Ok(Incoming::Closed(reason)) => Err(self.lost(reason)),
            Err(RecvTimeoutError::Timeout) => Ok(None),
            Err(RecvTimeoutError::Disconnected) => Err(self.lost("reader stopped".into())),
        }
    }
}

impl Drop for Link {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(reader) = self.reader.take() {
            // The reader wakes up every READ_POLL, so this join is bounded.
            let _ = reader.join();
        }
    }
}

/// How long DTR is held low: long enough for a board's auto-reset circuit.
const DTR_PULSE: Duration = Duration::from_millis(100);

/// Toggles DTR (bCNC does the same; a pty or a port without modem lines refuses,
/// which is fine) and flushes the input queue. Errors are ignored: a port that
/// cannot do either still works, and the banner wait deals with what comes.
fn fresh_start(port: &mut dyn SerialPort) {
    if port.write_data_terminal_ready(false).is_ok() {
        std::thread::sleep(DTR_PULSE);
        let _ = port.write_data_terminal_ready(true);
    }
    let _ = port.clear(serialport::ClearBuffer::Input);
}

fn read_lines(mut port: impl Read, tx: mpsc::Sender<Incoming>, stop: Arc<AtomicBool>) {
    let mut buf = [0u8; 512];
    let mut line: Vec<u8> = Vec::new();
    while !stop.load(Ordering::Relaxed) {
        match port.read(&mut buf) {
            Ok(0) => {
                let _ = tx.send(Incoming::Closed("the port was closed (end of file)".into()));
                return;
            }
            Ok(n) => {
                for &b in &buf[..n] {
                    match b {
                        b'\n' => {
                            let text = String::from_utf8_lossy(&line).trim().to_string();
                            line.clear();
                            if !text.is_empty() && tx.send(Incoming::Line(text)).is_err() {
                                return;
                            }
                        }
                        b'\r' => {}
                        b => {
                            line.push(b);
                            if line.len() >= MAX_LINE {
                                let text = String::from_utf8_lossy(&line).to_string();
                                line.clear();
                                if tx.send(Incoming::Line(text)).is_err() {
                                    return;
                                }
                            }
                        }
                    }
                }
            }
            Err(e)
                if e.kind() == std::io::ErrorKind::TimedOut
                    || e.kind() == std::io::ErrorKind::Interrupted
                    || e.kind() == std::io::ErrorKind::WouldBlock => {}
            Err(e) => {
                let _ = tx.send(Incoming::Closed(format!("read failed: {e}")));
                return;
            }
        }
    }
}
