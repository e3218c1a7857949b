//! One stream from start to end: read the file, build the blocks (with the
//! resume preamble for `from_line`), open the port, connect, check, stream.

use std::sync::mpsc::Receiver;

use super::link::Link;
use super::options::StreamOptions;
use super::streamer::{
    check_blocks, resume_blocks, Block, Observer, OperatorCommand, Resume, StreamReport, Streamer,
};
use super::{GrblError, InputFault};
use crate::gcode::parse::Program;

/// Reads the file and builds the blocks to send (with the resume preamble if
/// `--from-line`).
pub fn job_blocks(opts: &StreamOptions) -> Result<(Program, Vec<Block>), GrblError> {
    let text = std::fs::read_to_string(&opts.file).map_err(|e| {
        GrblError::Input(InputFault::Read {
            path: opts.file.clone(),
            reason: e.to_string(),
        })
    })?;
    let program = Program::parse(&text);
    let blocks = match opts.from_line {
        Some(line) => resume_blocks(
            &program,
            &Resume {
                line,
                safe_z: opts.safe_z,
                spindle_delay: opts.spindle_delay,
            },
        )?,
        None => Block::from_program(&program),
    };
    Ok((program, blocks))
}

/// The whole `pfcam stream` flow: read the file, open the port, connect,
/// optionally check, stream. `operator` carries hold/resume/abort requests, `obs`
/// hears what happens; nothing is printed. The outcome is the report or the
/// reason the stream stopped (the binary turns either into messages and an exit
/// status).
pub fn run_stream(
    opts: &StreamOptions,
    operator: &Receiver<OperatorCommand>,
    obs: &mut dyn Observer,
) -> Result<StreamReport, GrblError> {
    let (_program, blocks) = job_blocks(opts)?;
    check_blocks(&blocks, &opts.settings())?;
    let mut link = Link::open(&opts.port, opts.baud)?;
    if let Some(path) = &opts.log {
        let file = std::fs::File::create(path).map_err(|e| {
            GrblError::Input(InputFault::Log {
                path: path.clone(),
                reason: e.to_string(),
            })
        })?;
        link.set_log(Box::new(std::io::LineWriter::new(file)));
    }
    let mut streamer = Streamer::connect(link, opts.settings(), obs)?;
    if opts.check || opts.check_first {
        let report = streamer.check(&blocks, operator, obs)?;
        if !report.faults.is_empty() {
            return Err(GrblError::CheckFailed {
                faults: report.faults,
            });
        }
        if opts.check {
            return Ok(report);
        }
    }
    streamer.stream(&blocks, operator, obs)
}
