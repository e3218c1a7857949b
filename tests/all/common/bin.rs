//! The `pfcam` binary, run as a user runs it, in a directory of its own.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The `pfcam` binary Cargo built for these tests.
pub const PFCAM: &str = env!("CARGO_BIN_EXE_pfcam");

/// Runs `pfcam args` with `dir` as its working directory; its exit status,
/// stdout and stderr.
pub fn pfcam(args: &[&str], dir: &Path) -> Output {
    Command::new(PFCAM)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run pfcam")
}

/// Bytes a command printed, as text (invalid UTF-8 replaced).
pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A fresh, empty directory `<module>-<name>` for one test, under Cargo's
/// scratch directory for integration tests (`CARGO_TARGET_TMPDIR`). Every
/// module of the one test binary shares that directory, and tests run in
/// parallel: `module` (the calling module's name) keeps two modules' tests of
/// the same name apart.
pub fn scratch(module: &str, name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{module}-{name}"));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).expect("create scratch dir");
    d
}
