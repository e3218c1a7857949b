//! The crate's own files (jobs, samples, docs, test inputs), found from the
//! crate root whatever the working directory.

use pfcam::job::{load_job, Job};
use std::fs;
use std::path::{Path, PathBuf};

/// The crate root (`CARGO_MANIFEST_DIR`).
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Every file with extension `ext` in the crate's directory `dir` (`"jobs"`,
/// `"gcode-samples"`), sorted by name. Panics if `dir` cannot be read.
pub fn files(dir: &str, ext: &str) -> Vec<PathBuf> {
    let dir = root().join(dir);
    let mut v: Vec<PathBuf> = fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    v.sort();
    v
}

/// The shipped job `jobs/<name>` (`name` with its `.toml`).
pub fn shipped(name: &str) -> PathBuf {
    root().join("jobs").join(name)
}

/// Every shipped job (`jobs/*.toml`; the directory is read, not listed here),
/// loaded, in file name order. Panics naming a job that does not load, or if
/// there is none.
pub fn shipped_jobs() -> Vec<Job> {
    let paths = files("jobs", "toml");
    assert!(!paths.is_empty(), "no jobs in jobs/");
    paths
        .iter()
        .map(|p| load_job(p).unwrap_or_else(|e| panic!("{}: {e}", p.display())))
        .collect()
}

/// A test input in `tests/data/` (`name` may start with a subdirectory).
pub fn test_data(name: &str) -> PathBuf {
    root().join("tests/data").join(name)
}
