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
//! 3. in it, replace `mod doc_figures;` with `use crate::doc_figures;`, take
//!    helpers from `crate::common` instead of copying them (see its list), and
//!    give scratch directories a name starting with the module's;
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
mod grbl;
mod inputs;
mod levels;
mod preview;
mod simulate;
mod surface;
mod svg_file;
mod toolpath;
