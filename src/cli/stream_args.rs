//! `pfcam stream`'s command line (clap): the flags of docs/grbl.md, turned into
//! the library's [`StreamOptions`]. The defaults are the library's.

use std::path::PathBuf;

use pfcam::grbl::StreamOptions;

/// The library's defaults, shown by `--help`.
fn defaults() -> StreamOptions {
    StreamOptions::new("", "")
}

/// `pfcam stream FILE --port PORT [...]`.
#[derive(clap::Args, Debug, Clone)]
pub struct StreamArgs {
    /// G-code file to send.
    pub file: PathBuf,
    /// Serial port of the GRBL controller (e.g. /dev/ttyUSB0).
    #[arg(long)]
    pub port: String,
    /// Baud rate (8N1, no flow control).
    #[arg(long, default_value_t = defaults().baud)]
    pub baud: u32,
    /// GRBL's serial receive buffer, bytes (character counting never exceeds it).
    #[arg(long, default_value_t = defaults().rx_buffer, value_name = "BYTES")]
    pub rx_buffer: usize,
    /// Status report (`?`) polling rate, Hz.
    #[arg(long, default_value_t = defaults().status_hz, value_name = "HZ")]
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
    #[arg(long, default_value_t = defaults().spindle_delay, value_name = "S")]
    pub spindle_delay: f64,
    /// Send `$X` if GRBL is in alarm at connect (only if you know the position is good).
    #[arg(long)]
    pub unlock: bool,
    /// Record every line sent and every response, with timestamps, to FILE.
    #[arg(long, value_name = "FILE")]
    pub log: Option<PathBuf>,
    /// Seconds to wait for GRBL's banner (before and after a soft reset).
    #[arg(long, default_value_t = defaults().connect_timeout, value_name = "S")]
    pub connect_timeout: f64,
    /// Seconds of silence (not even a status report) after which GRBL counts as gone.
    #[arg(long, default_value_t = defaults().response_timeout, value_name = "S")]
    pub response_timeout: f64,
}

impl From<StreamArgs> for StreamOptions {
    /// The library's options for this command line.
    fn from(a: StreamArgs) -> StreamOptions {
        StreamOptions {
            file: a.file,
            port: a.port,
            baud: a.baud,
            rx_buffer: a.rx_buffer,
            status_hz: a.status_hz,
            continue_on_error: a.continue_on_error,
            check: a.check,
            check_first: a.check_first,
            from_line: a.from_line,
            safe_z: a.safe_z,
            spindle_delay: a.spindle_delay,
            unlock: a.unlock,
            log: a.log,
            connect_timeout: a.connect_timeout,
            response_timeout: a.response_timeout,
        }
    }
}
