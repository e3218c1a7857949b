//! pfcam's integration tests: one test binary (`all`), one module per area.
//!
//! Cargo builds each `tests/*.rs` as a binary of its own, each linked against
//! pfcam and its dependencies; one binary is linked once (ripgrep's
//! `tests/tests.rs`). docs/architecture.md ("Tests") gives the build times.
//!
//! Run one module with a name filter: `cargo test --release --test all golden::`
//! (a filter matches any part of a test's path `module::test_name`).
//!
//! **Adding a module** (e.g. `tests/sections.rs` from another branch):
//! 1. put the file here, as `tests/all/sections.rs` (not in `tests/`, where
//!    Cargo would build it as a binary of its own);
//! 2. add `mod sections;` below, in alphabetical order;
//! 3. in it, replace `mod doc_figures;` with `use crate::doc_figures;` and
//!    take helpers from `crate::common` instead of copying them (see its
//!    list: `pfcam`, `scratch`, `shipped_jobs`, `sample_pline`, ...). All
//!    modules run in one process, in parallel: a scratch directory is
//!    `common::scratch("sections", name)`, and a file of its own in
//!    `std::env::temp_dir()` needs the module's name in it (the process id
//!    no longer tells two modules apart). No test may call
//!    `std::env::set_var` or `set_current_dir`: they would change every
//!    module's process (give the `pfcam` child its own with `Command`);
//! 4. a `#[path = ...]` in it is relative to `tests/all/` (one more `../`), and
//!    its submodules go in `tests/all/sections/`;
//! 5. `cargo test --release --test all sections::` runs it; commands in docs
//!    and comments name it that way (not `--test sections`).

mod common;
mod doc_figures;

mod arcs;
mod boolean;
mod check;
mod cli;
mod dxf_file;
mod field;
mod field_robust;
mod finish;
mod golden;
mod harmonic_bezier;
mod harmonic_patch;
mod imports;
mod inputs;
mod levels;
mod pde;
mod pde_job;
mod pde_trim_job;
mod polyharmonic;
mod polyharmonic_closed;
mod preview;
mod sections;
mod simulate;
mod surface;
mod svg_file;
mod toolpath;
