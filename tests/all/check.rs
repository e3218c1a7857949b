//! `pfcam check` run as a user would: each error class on its own hand-made bad
//! file (exact line and GRBL error number), the totals of a small file worked out
//! by hand, and every G-code file pfcam writes passing.

use serde_json::Value;
use std::fs;
use std::path::Path;

use crate::common::{files, pfcam, root, text};

fn check_json(file: &str, extra: &[&str]) -> (i32, Value) {
    let mut args = vec!["check", file, "--json"];
    args.extend_from_slice(extra);
    let o = pfcam(&args, root());
    let v: Value = serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|e| panic!("{file}: not JSON ({e}): {}", text(&o.stdout)));
    (o.status.code().unwrap_or(-1), v)
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// The one error of `bad-gcode/<name>.nc`: its line and code, in the JSON and in
/// the text report (`FILE:LINE: error NN: ...`), with exit status 1.
fn assert_error(name: &str, line: u64, code: Option<u64>) {
    let file = format!("tests/data/bad-gcode/{name}.nc");
    let machine = "tests/data/bad-gcode/machine.toml";
    let (status, v) = check_json(&file, &["--machine", machine]);
    assert_eq!(status, 1, "{name}: {v}");
    assert_eq!(v["errors"], 1, "{name}: {v}");
    let errors: Vec<&Value> = v["findings"]
        .as_array()
        .expect("findings")
        .iter()
        .filter(|f| f["severity"] == "error")
        .collect();
    assert_eq!(errors[0]["line"], line, "{name}: {v}");
    assert_eq!(errors[0]["code"].as_u64(), code, "{name}: {v}");

    let o = pfcam(&["check", &file, "--machine", machine], root());
    assert_eq!(o.status.code(), Some(1));
    let want = match code {
        Some(c) => format!("{file}:{line}: error {c}: "),
        None => format!("{file}:{line}: error: "),
    };
    let out = text(&o.stdout);
    assert!(out.contains(&want), "{name}: want {want:?} in\n{out}");
    assert!(text(&o.stderr).contains("1 error(s)"), "{name}");
}

#[test]
fn unsupported_words_are_error_20() {
    assert_error("cutter-comp", 6, Some(20));
    assert_error("canned-cycle", 5, Some(20));
    assert_error("tool-length", 4, Some(20));
    assert_error("unknown-m", 4, Some(20));
}

#[test]
fn modal_group_conflict_is_error_21() {
    assert_error("modal-conflict", 5, Some(21));
    // Two motion commands: GRBL reports the axis-word clash (24) first.
    assert_error("axis-conflict", 5, Some(24));
}

#[test]
fn missing_or_zero_feed_is_error_22() {
    assert_error("no-feed", 5, Some(22));
    assert_error("feed-zero", 6, Some(22));
}

#[test]
fn arcs_grbl_rejects() {
    assert_error("arc-off-circle", 7, Some(33));
    assert_error("arc-radius", 7, Some(34));
    assert_error("arc-no-offset", 6, Some(35));
}

#[test]
fn malformed_blocks() {
    assert_error("long-line", 5, Some(11));
    assert_error("bad-number", 5, Some(2));
    assert_error("repeated-word", 5, Some(25));
    assert_error("negative-spindle", 4, Some(4));
}

#[test]
fn moves_past_the_travel() {
    assert_error("travel", 7, None);
    // Without the machine file nothing is known about the travel.
    let (status, v) = check_json("tests/data/bad-gcode/travel.nc", &[]);
    assert_eq!(status, 0, "{v}");
}

#[test]
fn g0_g1_without_axis_words_are_warnings() {
    let (status, v) = check_json("tests/data/bad-gcode/no-axis-words.nc", &[]);
    assert_eq!(status, 0, "{v}");
    assert_eq!(v["errors"], 0);
    let lines: Vec<u64> = v["findings"]
        .as_array()
        .expect("findings")
        .iter()
        .map(|f| f["line"].as_u64().unwrap_or(0))
        .collect();
    assert_eq!(lines, [5, 6], "{v}");
}

#[test]
fn usage_errors_exit_2() {
    let o = pfcam(&["check", "tests/data/no-such-file.nc"], root());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    let o = pfcam(
        &[
            "check",
            "tests/data/check-totals.nc",
            "--machine",
            "tests/data/no-such.toml",
        ],
        root(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    let o = pfcam(&["check"], root());
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn a_job_file_without_travel_says_so() {
    let o = pfcam(
        &[
            "check",
            "gcode-samples/hand-rounded-rect.nc",
            "--machine",
            "jobs/letter-i.toml",
        ],
        root(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("has no machine.travel"),
        "{}",
        text(&o.stderr)
    );
}

/// `tests/data/check-totals.nc`, by hand (1 in = 25.4 mm, F10 in/min = 254 mm/min):
/// - `G0 X0 Y0 Z0.2`: from an unknown position, not measured;
/// - `G1 Z-0.1`: 0.3 in;  `G91 G1 X2`: 2 in, to (2, 0);
/// - `G3 X1 Y1 R1`: quarter circle of radius 1 in about (2, 1), to (3, 1): π/2 in;
/// - `G90 G2 X2 Y2 I-1 J0`: clockwise about (2, 1) from (3, 1) to (2, 2), the long
///   way through (2, 0) and (1, 1): 3π/2 in;
/// - `G0 Z0.2`: rapid 0.3 in; `G4 P1.5`: 1.5 s.
///
/// Cut 2.3 + 2π in, rapid 0.3 in; time = cut / 254 mm/min + rapid / rapid rate +
/// 1.5 s. Bounds X 0 .. 3, Y 0 .. 2, Z −0.1 .. 0.2 in.
#[test]
fn totals_of_a_small_file_by_hand() {
    let inch = 25.4;
    let cut = (2.3 + std::f64::consts::TAU) * inch;
    let rapid = 0.3 * inch;
    for (extra, rate) in [
        (&[][..], 1000.0),
        (
            &["--machine", "tests/data/bad-gcode/machine.toml"][..],
            2000.0,
        ),
    ] {
        let (status, v) = check_json("tests/data/check-totals.nc", extra);
        assert_eq!(status, 0, "{v}");
        assert_eq!(v["findings"].as_array().map(Vec::len), Some(0), "{v}");
        let t = &v["totals"];
        assert!((num(&t["cut_length"]) - cut).abs() < 1e-9, "{t}");
        assert!((num(&t["rapid_length"]) - rapid).abs() < 1e-9, "{t}");
        assert_eq!(t["unmeasured_moves"], 1);
        assert!((num(&t["dwell_s"]) - 1.5).abs() < 1e-12);
        let time = cut / 254.0 * 60.0 + rapid / rate * 60.0 + 1.5;
        assert!((num(&t["time_s"]) - time).abs() < 1e-9, "{t} vs {time}");
        let (lo, hi) = ([0.0, 0.0, -0.1], [3.0, 2.0, 0.2]);
        for k in 0..3 {
            assert!(
                (num(&t["bounds"]["min"][k]) - lo[k] * inch).abs() < 1e-9,
                "{t}"
            );
            assert!(
                (num(&t["bounds"]["max"][k]) - hi[k] * inch).abs() < 1e-9,
                "{t}"
            );
        }
        assert_eq!(t["lines"], 12);
        assert_eq!(t["blocks"], 11);
    }
    let o = pfcam(&["check", "tests/data/check-totals.nc"], root());
    let out = text(&o.stdout);
    assert!(
        out.contains("bounds: X 0 .. 76.2, Y 0 .. 50.8, Z -2.54 .. 5.08 mm"),
        "{out}"
    );
    assert!(out.contains("length: cut 218.0 mm, rapid 7.6 mm"), "{out}");
}

/// The numbers of a header comment such as `(length: cut 199.3 mm, rapid 17 mm)`,
/// if the file has that comment.
fn header_numbers(gcode: &str, prefix: &str) -> Option<Vec<f64>> {
    let line = gcode.lines().find(|l| l.starts_with(prefix))?;
    Some(
        line.split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
            .filter_map(|w| w.parse().ok())
            .collect(),
    )
}

/// `pfcam check` passes `file`, and its totals agree with the header pfcam wrote
/// (lengths to the 0.1 mm written, cut bounds to the 0.001 mm written).
fn assert_passes(file: &Path) {
    let shown = file.display().to_string();
    let (status, v) = check_json(&shown, &[]);
    assert_eq!(status, 0, "{shown}: {v}");
    assert_eq!(v["errors"], 0, "{shown}: {v}");
    assert_eq!(v["warnings"], 0, "{shown}: {v}");
    let gcode = fs::read_to_string(file).expect("read G-code");
    let t = &v["totals"];
    // The writer's header is the writer's business; compare with it where it
    // still says these things.
    if let Some(len) = header_numbers(&gcode, "(length:") {
        // The header rounds to 0.1 mm; the checker measures arcs about the
        // printed centres, which differ from the exact ones by up to 0.0036 mm,
        // a relative error that adds up over a long file; and every move's
        // ends are rounded to 1 µm, which lengthens a polyline of tiny moves
        // (ramps, micro-links) on average: mfs-mould.rough.nc's 62 396 blocks
        // measure 1.16 mm more than its header, its lines-only version
        // (`arcs = false`) 0.99 mm more, so it is not the arcs.
        let blocks = num(&t["blocks"]);
        let tol = |x: f64| 0.051 + 1e-5 * x + 2e-5 * blocks;
        assert!(
            (num(&t["cut_length"]) - len[0]).abs() <= tol(len[0]),
            "{shown}: {t}"
        );
        assert!(
            (num(&t["rapid_length"]) - len[1]).abs() <= tol(len[1]),
            "{shown}: {t}"
        );
    }
    if let (Some(lo), Some(hi)) = (
        header_numbers(&gcode, "(cut min:"),
        header_numbers(&gcode, "(cut max:"),
    ) {
        for k in 0..3 {
            // The header's bounds use the arcs' exact centres; the checker's the
            // centres as printed, which the writer moves onto the 0.001 mm grid
            // by at most 0.0036 mm (docs/gcode.md): an arc's extreme moves as much.
            assert!(
                (num(&t["cut_bounds"]["min"][k]) - lo[k]).abs() <= 0.0036 + 0.0005,
                "{shown}: {t}"
            );
            assert!(
                (num(&t["cut_bounds"]["max"][k]) - hi[k]).abs() <= 0.0036 + 0.0005,
                "{shown}: {t}"
            );
        }
    }
}

#[test]
fn every_gcode_sample_passes() {
    let samples = files("gcode-samples", "nc");
    assert!(!samples.is_empty());
    for f in samples {
        assert_passes(&f);
    }
}

#[test]
fn every_job_runs_to_gcode_that_passes() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("check-jobs");
    let _ = fs::remove_dir_all(&out);
    let jobs = files("jobs", "toml");
    assert!(!jobs.is_empty());
    for job in &jobs {
        let o = pfcam(
            &[
                "run",
                &job.display().to_string(),
                "--out",
                &out.display().to_string(),
                "--quiet",
            ],
            root(),
        );
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}: {}",
            job.display(),
            text(&o.stderr)
        );
    }
    let written = files(&out.display().to_string(), "nc");
    // One program per job, two for a job with a finishing tool.
    let programs: usize = jobs
        .iter()
        .map(|j| pfcam::report::program_files(&pfcam::job::load_job(j).expect("job")).len())
        .sum();
    assert_eq!(written.len(), programs);
    for f in written {
        assert_passes(&f);
    }
    // Warnings are for what the user must know or act on, once: no shipped
    // job has more than one, and the only one left is q-mould's summary of
    // its levels' field errors (it had ten lines saying the same, plus a
    // "no room inside the finishing loops" where the walls cut everything).
    for report in files(&out.display().to_string(), "json") {
        let v: Value = serde_json::from_str(&fs::read_to_string(&report).unwrap()).unwrap();
        let warnings = v["warnings"].as_array().expect("warnings array");
        assert!(
            warnings.len() <= 1
                && warnings.iter().all(|w| w
                    .as_str()
                    .is_some_and(|w| w.contains("levels have fields that err above"))),
            "{}: {warnings:?}",
            report.display()
        );
    }
}

/// docs/grbl.md shows what `pfcam check` prints for the travel example (its
/// lines, bounds, lengths and time): the same command prints it now, report
/// on standard output, then the closing error on standard error.
#[test]
fn grbl_doc_check_example_is_what_the_command_prints() {
    let doc = fs::read_to_string(root().join("docs/grbl.md")).expect("docs/grbl.md");
    let prompt = "$ pfcam check ";
    let at = doc
        .find(prompt)
        .expect("docs/grbl.md shows a `$ pfcam check` run");
    let mut block = doc[at..].lines();
    let command = block.next().expect("the command line");
    let shown: Vec<&str> = block.take_while(|l| !l.starts_with("```")).collect();
    let args: Vec<&str> = command[prompt.len()..].split_whitespace().collect();
    let o = pfcam(
        &["check"].into_iter().chain(args).collect::<Vec<_>>(),
        root(),
    );
    let printed = text(&o.stdout) + &text(&o.stderr);
    assert_eq!(
        shown,
        printed.lines().collect::<Vec<_>>(),
        "docs/grbl.md's `{command}` against what it prints"
    );
}
