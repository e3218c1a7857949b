//! pfcam: potential-field CNC tool paths for GRBL milling machines.
//!
//! The pipeline (see `docs/architecture.md`): job → shape → field → tool path →
//! G-code / preview. Each stage is a module; the library never prints, never exits
//! and never panics on user input.
//!
//! # Public API
//!
//! What the `pfcam` binary calls, and what a program using the library calls:
//!
//! - **Load a job**: [`job::load_job`] (a TOML file) or [`job::parse_job`]
//!   (TOML text) give a checked [`job::Job`] or a [`job::JobError`] naming the
//!   key; [`job::load_machine`] reads `[machine]` alone (`--machine`);
//!   [`job::parse_job_with`] looks files and font names up through its own
//!   [`job::Sources`] (a given font database, [`job::Fonts`]).
//! - **Run it**: [`pipeline::run`] takes the job and a progress callback
//!   ([`pipeline::Progress`] events) and returns a [`pipeline::RunOutput`]:
//!   the [`toolpath::Toolpath`], the MFS solves, the gouge check's least
//!   clearance, the warnings and, with `[finish]`, the finishing program
//!   ([`finish::Finished`], its tool's job from [`job::Job::finishing`]); or a
//!   [`pipeline::PipelineError`].
//! - **Write the program**: [`gcode::write_gcode_on`] (on the run's stock) or
//!   [`gcode::write_gcode`] turn a tool path into GRBL G-code;
//!   [`estimate::check_program`] holds it to `machine.max_hours` and
//!   `machine.max_file_mb`; [`output::write_atomic`] writes a file without
//!   replacing one pfcam did not write.
//! - **Check it**: [`simulate::verify_program`] and [`simulate::verify_finish`]
//!   simulate the written programs against the stock;
//!   [`simulate::simulate`] and [`simulate::simulate_programs`] give the
//!   whole simulation; [`gcode::check::check_gcode`] checks any G-code file
//!   against a machine's limits.
//! - **Show it**: [`report::RunReport`] (the JSON report and the summary
//!   table), [`preview::preview_svg`] (the SVG preview), [`preview::field_png`]
//!   (the field's colour map), [`surface::job_part_surface`] and
//!   [`surface::stl_bytes`] (the modelled part as STL).
//! - **Send it**: [`grbl::run_stream`] streams a program to a GRBL machine,
//!   reporting to an [`grbl::Observer`].
//!
//! Everything else is crate-private (`pub(crate)`) by default: an item is
//! `pub` beyond the list above only because the binary, the integration tests,
//! the examples or the benches use it, or a public item's signature names it.
//!
//! A profile of the paper's letter I (`jobs/letter-i.toml`), from TOML text
//! to a checked program:
//!
//! ```
//! use pfcam::{gcode, job, pipeline, simulate};
//!
//! let toml = r#"
//! [shape]
//! text = "I"
//! height = 50.0
//!
//! [tool]
//! diameter = 3.175
//! feed = 800.0
//! plunge_feed = 200.0
//! spindle = 18000
//! stepdown = 1.0
//!
//! [operation]
//! depth = 3.0
//! tolerance = 0.01
//! "#;
//! let job = job::parse_job(toml, "letter-i", std::path::Path::new("."))?;
//! let out = pipeline::run(&job, &mut |_progress| {})?;
//! // The run's own gouge check passed: no tool position is closer to the
//! // part than the tool radius, beyond the tolerance.
//! assert!(out.min_clearance >= -job.operation.tolerance);
//! let program = gcode::write_gcode_on(&out.toolpath, &job, out.stock)?;
//! assert!(program.contains("Z-3"), "the last pass reaches the depth");
//! // Simulated against the stock, the program cuts nothing it should not.
//! let verdict = simulate::verify_program(&program, job.tool.diameter, job.tool.stepdown)?;
//! assert!(verdict.is_ok());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

// The modules' docs are written for whoever works on pfcam and link to
// crate-private items (constants, helpers) by name; `cargo doc
// --document-private-items` resolves every such link. Broken links still warn.
#![allow(rustdoc::private_intra_doc_links)]

pub mod compose;
pub mod count;
pub mod estimate;
pub mod field;
pub mod finish;
pub mod gcode;
pub mod geometry;
pub mod grbl;
pub mod job;
pub mod levels;
pub(crate) mod num;
pub mod output;
pub(crate) mod patch;
pub mod pipeline;
pub mod preview;
pub(crate) mod profile;
pub mod report;
pub mod simulate;
pub mod sources;
pub mod surface;
pub mod toolpath;
pub(crate) mod tube;
