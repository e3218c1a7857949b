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

/// `pfcam simulate PROGRAMS... --job JOB --json` in `dir`, asserted to
/// succeed and report `clean: true`; the whole report (its `part`: the
/// gouge and the material left, for the caller to hold to its bounds).
pub fn simulate_report(programs: &[&str], job: &str, dir: &Path) -> serde_json::Value {
    let mut args = vec!["simulate"];
    args.extend_from_slice(programs);
    args.extend_from_slice(&["--job", job, "--json"]);
    let out = pfcam(&args, dir);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["clean"], true, "{v}");
    v
}

/// The shipped job `name` (jobs/`name`.toml) run into a scratch directory
/// of `module`, then its rough and finish programs simulated
/// ([`simulate_report`]).
pub fn run_and_simulate(module: &str, name: &str) -> serde_json::Value {
    let dir = scratch(module, "shipped");
    let job = super::shipped(&format!("{name}.toml"));
    let job = job.to_str().unwrap();
    let out = pfcam(&["run", job, "-o", ".", "-q"], &dir);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (rough, finish) = (format!("{name}.rough.nc"), format!("{name}.finish.nc"));
    simulate_report(&[&rough, &finish], job, &dir)
}

/// A simulation report's `part` held to its bounds: max gouge at most
/// `gouge`, material left over the last tool's reach at most `left` (and on
/// the walls along the normal, with a ball finisher), and no cell gouged
/// past the tolerance.
pub fn assert_within_part(part: &serde_json::Value, gouge: f64, left: f64) {
    let g = part["max_gouge"]["value"].as_f64().unwrap();
    let l = part["max_left_reachable"]["value"].as_f64().unwrap();
    assert!(g <= gouge, "max gouge {g}");
    assert!(l <= left, "material left {l}");
    assert_eq!(part["gouged_cells"], 0);
    // With a ball finisher, the same bound along the walls' normal.
    if let Some(w) = part["walls"]["left"]["value"].as_f64() {
        assert!(w <= left, "material left on the walls {w}");
    }
}
