//! Helpers the test modules share. Each was copied into every file that needed
//! it while each file was a test binary of its own; a new module takes them
//! from here.
//!
//! - [`files`]: the crate's own files, found from the crate root whatever the
//!   working directory: `root`, `files` (a directory's files with one
//!   extension), `shipped` and `shipped_jobs` (`jobs/`), `test_data`
//!   (`tests/data/`).
//! - [`bin`]: the `pfcam` binary run as a user runs it (`pfcam`, `text`) and
//!   `scratch` directories to run it in; `simulate_report` and `run_and_simulate`
//!   (a clean `pfcam simulate --json` of programs, its `part`).
//! - [`oracle`]: geometry measured independently of pfcam, to hold pfcam's to:
//!   `seg_dist`, `sample_pline` (cavalier_contours' polylines), and a shape's
//!   `area`, `holes` and `perimeter`.
//! - [`rng`]: `Rng`, a fixed-seed xorshift (`next`, `range`, `below`, `pick`).

pub mod bin;
pub mod files;
pub mod oracle;
pub mod rng;

pub use bin::{assert_within_part, pfcam, run_and_simulate, scratch, simulate_report, text, PFCAM};
pub use files::{files, root, shipped, shipped_jobs, test_data};
pub use oracle::{area, holes, perimeter, sample_pline, seg_dist};
pub use rng::Rng;
