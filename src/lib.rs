//! pfcam: potential-field CNC tool paths for GRBL milling machines.
//!
//! The pipeline (see `docs/architecture.md`): job → shape → field → tool path →
//! G-code / preview. Each stage is a module; the library never prints, never exits
//! and never panics on user input.

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
pub mod num;
pub mod output;
pub mod patch;
pub mod pipeline;
pub mod preview;
pub mod profile;
pub mod report;
pub mod simulate;
pub mod sources;
pub mod surface;
pub mod toolpath;
pub mod tube;
