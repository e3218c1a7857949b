//! The `pfcam` binary: parse the command line, call the library, map errors to
//! exit codes (0 ok, 1 failed, 2 usage, 3 output file; see `cli.rs`; `stream`
//! has its own, `cli/stream/exit.rs`).

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args = match cli::Args::try_parse() {
        Ok(a) => a,
        Err(e) => {
            // --help and --version are "errors" that print to stdout and succeed.
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(cli::EXIT_USAGE)
            } else {
                ExitCode::from(cli::EXIT_OK)
            };
        }
    };
    match cli::run(args) {
        Ok(code) => code,
        Err(e) if cli::is_broken_pipe(&e) => ExitCode::from(cli::EXIT_OK),
        Err(e) => {
            // Not eprintln!, which panics when stderr is closed.
            use std::io::Write as _;
            let _ = writeln!(std::io::stderr(), "error: {}", cli::message(&e));
            ExitCode::from(cli::exit_code(&e))
        }
    }
}
