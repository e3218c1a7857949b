//! What one `pfcam stream` is asked to do: the file, the port, the protocol's
//! tunables and the mode (check, resume). Plain data: the command line that fills
//! it in lives in the binary (`src/cli/stream_args.rs`).

use std::path::PathBuf;
use std::time::Duration;

use super::streamer::Settings;

/// The options of one stream (the flags of `pfcam stream`, docs/grbl.md).
#[derive(Debug, Clone)]
pub struct StreamOptions {
    /// G-code file to send.
    pub file: PathBuf,
    /// Serial port of the GRBL controller (e.g. /dev/ttyUSB0).
    pub port: String,
    /// Baud rate (8N1, no flow control).
    pub baud: u32,
    /// GRBL's serial receive buffer, bytes (character counting never exceeds it).
    pub rx_buffer: usize,
    /// Status report (`?`) polling rate, Hz.
    pub status_hz: f64,
    /// Do not stop at `error:N`: keep streaming and list the rejected lines at the end.
    pub continue_on_error: bool,
    /// Run the file in GRBL's check mode ($C) only: report every error, move nothing.
    pub check: bool,
    /// Run the check mode pass first; stream only if GRBL accepts every line.
    pub check_first: bool,
    /// Resume at this file line (1-based): restore the modal state in force there,
    /// go to the resume point through safe Z, then continue.
    pub from_line: Option<usize>,
    /// Safe Z for `from_line`, mm in work coordinates (`None`: highest Z before it).
    pub safe_z: Option<f64>,
    /// Spindle spin-up dwell for `from_line`, seconds.
    pub spindle_delay: f64,
    /// Send `$X` if GRBL is in alarm at connect (only if you know the position is good).
    pub unlock: bool,
    /// Record every line sent and every response, with timestamps, to this file.
    pub log: Option<PathBuf>,
    /// Seconds to wait for GRBL's banner (before and after a soft reset).
    pub connect_timeout: f64,
    /// Seconds of silence (not even a status report) after which GRBL counts as gone.
    pub response_timeout: f64,
}

impl StreamOptions {
    /// `FILE` to `PORT`, everything else at its default (the defaults of
    /// `pfcam stream`'s flags).
    pub fn new(file: impl Into<PathBuf>, port: impl Into<String>) -> StreamOptions {
        StreamOptions {
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

    /// The protocol settings these options ask for (out-of-range values clamped).
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
