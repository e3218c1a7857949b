//! The `pfcam` binary, run as a user would: exit codes, messages that name the
//! key or place, and no output file left behind after an error.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::{pfcam, root, scratch, shipped, test_data, text, PFCAM};

/// Every file under `dir` (recursively), or nothing if it does not exist.
fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    if let Ok(rd) = fs::read_dir(dir) {
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                out.extend(files_in(&p));
            } else {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

const GOOD: &str =
    "[shape]\ntext = \"I\"\nheight = 50.0\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n";

/// Write `job` as `dir/job.toml`, run `validate` and `run --out out` on it, and
/// check both fail, say every one of `needles`, and leave no file in `out`.
fn assert_rejected(case: &str, job: &str, needles: &[&str]) {
    assert_rejected_in(case, job, needles, false);
}

/// As `assert_rejected`; with `in_last_line`, the error may follow the progress
/// of a stage that had begun (modelling a composition), so the checks apply to
/// stderr's last line.
fn assert_rejected_in(case: &str, job: &str, needles: &[&str], in_last_line: bool) {
    let dir = scratch("cli", case);
    fs::write(dir.join("job.toml"), job).expect("write job");
    for args in [
        &["validate", "job.toml"][..],
        &["run", "job.toml", "--out", "out"][..],
    ] {
        let o = pfcam(args, &dir);
        let all = text(&o.stderr);
        let err = if in_last_line {
            all.lines().last().unwrap_or("").to_string()
        } else {
            all.clone()
        };
        assert!(!o.status.success(), "{case}: {args:?} succeeded");
        assert_eq!(o.status.code(), Some(1), "{case}: {args:?}: {err}");
        assert!(err.starts_with("error: "), "{case}: {err}");
        for n in needles {
            assert!(
                err.contains(n),
                "{case}: {args:?}: stderr lacks {n:?}: {err}"
            );
        }
        let left = files_in(&dir.join("out"));
        assert!(left.is_empty(), "{case}: files left behind: {left:?}");
    }
}

#[test]
fn malformed_toml_gives_line_and_column() {
    let job = GOOD.replace("height = 50.0", "height = = 50.0");
    assert_rejected("malformed", &job, &["job.toml:3:"]);
}

#[test]
fn unknown_key_is_named() {
    let job = GOOD.replace("diameter = 3.175", "diameter = 3.175\ndiamter = 3.0");
    assert_rejected(
        "unknown-key",
        &job,
        &["job.toml:6:1", "tool.diamter", "unknown field"],
    );
    let job = format!("{GOOD}[spindle]\nrpm = 1\n");
    assert_rejected("unknown-table", &job, &["spindle"]);
}

#[test]
fn negative_diameter_is_named() {
    let job = GOOD.replace("diameter = 3.175", "diameter = -3");
    assert_rejected(
        "negative-diameter",
        &job,
        &["job.toml: tool.diameter must be a positive number of mm, got -3"],
    );
}

#[test]
fn missing_font_file_is_named() {
    let job = GOOD.replace("text = \"I\"", "text = \"I\"\nfont = \"fonts/missing.ttf\"");
    assert_rejected(
        "missing-font",
        &job,
        &["shape.font: no such file", "fonts/missing.ttf"],
    );
}

#[test]
fn a_font_family_not_installed_is_named() {
    // With the system's fonts (none on a bare CI machine, whose message
    // differs) the key is named either way.
    let job = GOOD.replace(
        "text = \"I\"",
        "text = \"I\"\nfont = \"No Such Family Xyzzy Bold\"",
    );
    assert_rejected(
        "missing-family",
        &job,
        &["shape.font", "\"No Such Family Xyzzy Bold\""],
    );
}

#[test]
fn a_glyph_missing_from_a_font_file_is_named() {
    let font = test_data("DejaVuSans.ttf");
    let job = GOOD.replace(
        "text = \"I\"",
        &format!(
            "text = \"I\\U0001D11E\"\nfont = {:?}",
            font.display().to_string()
        ),
    );
    assert_rejected(
        "missing-glyph-file",
        &job,
        &["no glyph for '\u{1d11e}'", "DejaVuSans.ttf"],
    );
}

#[test]
fn glyph_missing_from_the_font() {
    let job = GOOD.replace("text = \"I\"", "text = \"Z\"");
    assert_rejected("missing-glyph", &job, &["shape.text", "no glyph", "'Z'"]);
}

#[test]
fn zero_and_negative_depth() {
    assert_rejected(
        "zero-depth",
        &GOOD.replace("depth = 3.0", "depth = 0.0"),
        &["operation.depth must be > 0"],
    );
    assert_rejected(
        "negative-depth",
        &GOOD.replace("depth = 3.0", "depth = -2"),
        &["operation.depth must be > 0", "-2"],
    );
}

#[test]
fn unsupported_operation_lists_accepted_values() {
    let job = GOOD.replace("depth = 3.0", "depth = 3.0\nkind = \"pocket\"");
    assert_rejected("kind", &job, &["operation.kind", "`pocket`", "`profile`"]);
    let job = GOOD.replace("depth = 3.0", "depth = 3.0\nside = \"inside\"");
    assert_rejected("side", &job, &["operation.side", "`outside`"]);
}

#[test]
fn both_or_neither_shape_source() {
    let job = GOOD.replace(
        "text = \"I\"",
        "text = \"I\"\nsvg_path = \"M0 0 L1 0 L1 1 Z\"",
    );
    assert_rejected("both-sources", &job, &["shape.text", "shape.svg_path"]);
    let job = GOOD.replace("text = \"I\"", "");
    assert_rejected("no-source", &job, &["shape.text", "shape.svg_path"]);
}

const OPEN_SVG: &str = "[shape]\nsvg_path = \"M0 0 L10 0 L10 10\"\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n";

#[test]
fn open_svg_path_is_rejected() {
    // The job itself is well formed; the shape is not. Until geometry reads SVG
    // path data, the message may only say the source is unsupported, so this
    // checks the failure and the absence of output; the test below checks words.
    assert_rejected("open-svg", OPEN_SVG, &[]);
}

#[test]
fn open_svg_path_is_named_open() {
    assert_rejected("open-svg-named", OPEN_SVG, &["shape", "open"]);
}

/// A composition that parses but cannot be built (the intersection of two parts
/// that do not meet) fails while modelling, naming the part as the file numbers
/// it, and writes nothing.
#[test]
fn a_composition_that_cannot_be_built_names_its_part() {
    let job = "[shape]\nheight = 30.0\n\
        [[shape.part]]\nname = \"a\"\npolygon = [[0, 0], [40, 0], [40, 30], [0, 30]]\n\
        [[shape.part]]\nname = \"b\"\npolygon = [[80, 0], [120, 0], [120, 30], [80, 30]]\n\
        [[shape.part]]\nname = \"r\"\nop = \"intersect\"\nof = [\"a\", \"b\"]\n\
        [tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n";
    assert_rejected_in(
        "disjoint-intersection",
        job,
        &["shape.part[3] \"r\"", "do not overlap"],
        true,
    );
    // The cause once: the error held it both in its message and as its
    // source, and the CLI appended the source's own wording after it.
    let dir = scratch("cli", "disjoint-intersection-once");
    fs::write(dir.join("job.toml"), job).expect("write job");
    for args in [
        &["validate", "job.toml"][..],
        &["run", "job.toml", "--out", "out"][..],
    ] {
        let o = pfcam(args, &dir);
        let err = text(&o.stderr);
        let last = err.lines().last().unwrap_or("");
        assert_eq!(last.matches("do not overlap").count(), 1, "{args:?}: {err}");
        assert_eq!(
            err.matches("the result has no boundary").count(),
            1,
            "{args:?}: {err}"
        );
    }
}

#[test]
fn foreign_output_file_is_not_overwritten() {
    let dir = scratch("cli", "foreign");
    fs::write(dir.join("job.toml"), GOOD).expect("write job");
    fs::create_dir_all(dir.join("out")).expect("mkdir");
    let foreign = dir.join("out/job.nc");
    fs::write(&foreign, "G0 X0 (my own program)\n").expect("write");
    let o = pfcam(&["run", "job.toml", "--out", "out"], &dir);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(
        err.contains("out/job.nc") && err.contains("--force"),
        "{err}"
    );
    assert_eq!(
        fs::read_to_string(&foreign).expect("read"),
        "G0 X0 (my own program)\n"
    );
    assert_eq!(files_in(&dir.join("out")), [foreign]);
}

#[test]
fn own_output_file_is_not_refused() {
    let dir = scratch("cli", "own");
    fs::write(dir.join("job.toml"), GOOD).expect("write job");
    fs::create_dir_all(dir.join("out")).expect("mkdir");
    let own = dir.join("out/job.nc");
    fs::write(&own, "(pfcam 0.0.1 job job)\nM2\n").expect("write");
    let o = pfcam(&["run", "job.toml", "--out", "out"], &dir);
    let err = text(&o.stderr);
    assert!(!err.contains("refusing"), "{err}");
    assert_ne!(o.status.code(), Some(3), "{err}");
    // Replaced by a new pfcam file if the run succeeded (with its preview and
    // report beside it), untouched otherwise.
    let now = fs::read_to_string(&own).expect("read");
    assert!(now.starts_with("(pfcam "), "{now}");
    let files = files_in(&dir.join("out"));
    if o.status.success() {
        assert_eq!(
            files,
            [
                own.with_extension("json"),
                own.clone(),
                own.with_extension("svg")
            ]
        );
    } else {
        assert_eq!(files, [own]);
    }
}

#[test]
fn validate_accepts_every_shipped_job() {
    let jobs = root().join("jobs");
    let mut n = 0;
    for p in files_in(&jobs) {
        if p.extension().is_some_and(|e| e == "toml") {
            let o = pfcam(&["validate", &p.to_string_lossy()], &jobs);
            let stem = p.file_stem().map(|s| s.to_string_lossy().into_owned());
            assert!(o.status.success(), "{}: {}", p.display(), text(&o.stderr));
            assert_eq!(
                text(&o.stdout),
                format!("ok: {}\n", stem.unwrap_or_default())
            );
            n += 1;
        }
    }
    assert!(n >= 4, "only {n} job files in jobs/");
}

#[test]
fn glyphs_lists_the_paper_letters() {
    let o = pfcam(&["glyphs"], Path::new("."));
    assert!(o.status.success());
    let out = text(&o.stdout);
    let letters: Vec<&str> = out.lines().skip(1).collect();
    assert_eq!(letters, ["I", "H", "A", "M", "F", "S"]);
}

#[test]
fn convergence_rejects_unknown_glyph() {
    let o = pfcam(
        &["convergence", "--glyph", "Z", "--n", "78"],
        Path::new("."),
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("--glyph"), "{}", text(&o.stderr));
}

#[test]
fn usage_errors_exit_2() {
    let o = pfcam(&["run"], Path::new("."));
    assert_eq!(o.status.code(), Some(2));
    let o = pfcam(&["frobnicate"], Path::new("."));
    assert_eq!(o.status.code(), Some(2));
    let o = pfcam(&["--version"], Path::new("."));
    assert_eq!(o.status.code(), Some(0));
    assert!(text(&o.stdout).starts_with("pfcam "));
}

#[test]
fn missing_job_file_is_named() {
    let dir = scratch("cli", "no-job");
    let o = pfcam(&["run", "nope.toml", "--out", "out"], &dir);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("nope.toml"), "{}", text(&o.stderr));
    assert!(files_in(&dir.join("out")).is_empty());
}

// ---- These need the real pipeline (pfcam::pipeline::run) or MFS solver. ----

fn shipped_job(name: &str) -> String {
    shipped(name).to_string_lossy().into_owned()
}

#[test]
fn run_writes_gcode_and_a_rerun_replaces_it_identically() {
    let dir = scratch("cli", "run");
    let job = shipped_job("letter-i.toml");
    let o = pfcam(&["run", &job, "--out", "out"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    for n in [
        "wrote out/letter-i.nc",
        "glyphs: ",
        "solve ",
        "min clearance",
        "estimated time",
    ] {
        assert!(out.contains(n), "summary lacks {n:?}: {out}");
    }
    let nc = dir.join("out/letter-i.nc");
    let first = fs::read_to_string(&nc).expect("read");
    assert!(first.starts_with("(pfcam ") && first.ends_with("M5\nM2\n"));
    let o = pfcam(&["run", &job, "--out", "out", "--quiet"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(o.stdout.is_empty(), "--quiet printed {}", text(&o.stdout));
    assert_eq!(fs::read_to_string(&nc).expect("read"), first);
    // The preview and the report are written beside the G-code.
    assert_eq!(
        files_in(&dir.join("out")),
        [
            nc.with_extension("json"),
            nc.clone(),
            nc.with_extension("svg")
        ]
    );
}

#[test]
fn the_summary_names_the_font_file() {
    let dir = scratch("cli", "font-summary");
    let font = test_data("DejaVuSans.ttf");
    let job = GOOD.replace(
        "text = \"I\"",
        &format!("text = \"I\"\nfont = {:?}", font.display().to_string()),
    );
    fs::write(dir.join("job.toml"), job).expect("write job");
    let o = pfcam(&["run", "job.toml", "--out", "out"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    let want = format!("font: {}\n", font.display());
    assert!(out.contains(&want), "summary lacks {want:?}: {out}");
    assert!(out.contains("glyphs: I (1)\n"), "{out}");
}

#[test]
fn force_replaces_a_foreign_file() {
    let dir = scratch("cli", "force");
    fs::create_dir_all(dir.join("out")).expect("mkdir");
    let nc = dir.join("out/letter-i.nc");
    fs::write(&nc, "G0 X0\n").expect("write");
    let job = shipped_job("letter-i.toml");
    let o = pfcam(&["run", &job, "--out", "out", "--force", "--quiet"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(fs::read_to_string(&nc)
        .expect("read")
        .starts_with("(pfcam "));
}

#[test]
fn convergence_json_has_the_documented_keys() {
    let o = pfcam(
        &["convergence", "--glyph", "I", "--n", "78,148", "--json"],
        Path::new("."),
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let rows = v.as_array().expect("array");
    assert_eq!(rows.len(), 2);
    for (r, n) in rows.iter().zip([78, 148]) {
        assert_eq!(r["n"], n);
        assert_eq!(r["m"], 2 * n);
        assert!(r["distance"].as_f64().is_some_and(|d| d > 0.0));
        assert!(r["max_error"].as_f64().is_some_and(|e| e >= 0.0));
    }
}

/// Runs pfcam with a time bound: a case that would hang or run for minutes fails
/// the test instead of stalling it (a guard, not a speed target).
fn pfcam_bounded(args: &[&str], dir: &Path, secs: u64) -> Output {
    use std::io::Read;
    let mut child = Command::new(PFCAM)
        .args(args)
        .current_dir(dir)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run pfcam");
    let start = std::time::Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("wait") {
            let mut stdout = Vec::new();
            let mut stderr = Vec::new();
            if let Some(mut o) = child.stdout.take() {
                o.read_to_end(&mut stdout).expect("stdout");
            }
            if let Some(mut e) = child.stderr.take() {
                e.read_to_end(&mut stderr).expect("stderr");
            }
            return Output {
                status,
                stdout,
                stderr,
            };
        }
        if start.elapsed().as_secs() >= secs {
            let _ = child.kill();
            panic!("pfcam {args:?} still running after {secs} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// A job whose one part is a circle of `n` polygon points.
fn circle_job(n: usize) -> String {
    let pts: Vec<String> = (0..n)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / n as f64;
            format!("[{:.4},{:.4}]", 50.0 * a.cos(), 50.0 * a.sin())
        })
        .collect();
    format!(
        "[shape]\nheight = 50.0\n[[shape.part]]\nname = \"p\"\npolygon = [{}]\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n",
        pts.join(",")
    )
}

/// The inputs that once crashed, aborted or ran without bound (issue 15's
/// table), one case per row: each now fails at load time with exit 1, a single
/// message naming the key, and no file written.
#[test]
fn values_no_machine_could_use_are_refused_by_key() {
    let boss = "[shape]\ntext = \"I\"\nheight = 50.0\n[tool]\ndiameter = 3.175\n[operation]\nkind = \"boss\"\ndepth = 3.0\n";
    let cases: &[(&str, String, &str)] = &[
        (
            "depth-1e300",
            GOOD.replace("depth = 3.0", "depth = 1e300"),
            "operation.depth",
        ),
        (
            "depth-1e6",
            GOOD.replace("depth = 3.0", "depth = 1e6"),
            "operation.depth",
        ),
        (
            "margin-1e300",
            format!("{boss}[stock]\nmargin = 1e300\n"),
            "stock.margin",
        ),
        (
            "margin-1e6",
            format!("{boss}[stock]\nmargin = 1e6\n"),
            "stock.margin",
        ),
        (
            "singularities-1e5",
            format!("{GOOD}[field]\nsingularities = 100000\n"),
            "field.singularities",
        ),
        (
            "height-1e6",
            GOOD.replace("height = 50.0", "height = 1e6"),
            "shape.height",
        ),
        (
            "height-1e300",
            GOOD.replace("height = 50.0", "height = 1e300"),
            "shape.height",
        ),
        (
            "diameter-1e300",
            GOOD.replace("diameter = 3.175", "diameter = 1e300"),
            "tool.diameter",
        ),
        (
            "feed-1e300",
            GOOD.replace("diameter = 3.175", "diameter = 3.175\nfeed = 1e300"),
            "tool.feed",
        ),
        (
            "plunge-1e300",
            GOOD.replace("diameter = 3.175", "diameter = 3.175\nplunge_feed = 1e300"),
            "tool.plunge_feed",
        ),
        (
            "spindle-1e300",
            GOOD.replace("diameter = 3.175", "diameter = 3.175\nspindle = 1e300"),
            "tool.spindle",
        ),
        (
            "safe-z-1e300",
            format!("{GOOD}[stock]\nsafe_z = 1e300\n"),
            "stock.safe_z",
        ),
        (
            "dwell-1e300",
            format!("{GOOD}[machine]\nspindle_dwell = 1e300\n"),
            "machine.spindle_dwell",
        ),
        ("polygon-500k", circle_job(500_000), "not a job file"),
        ("polygon-20k", circle_job(20_000), "shape.part[1].polygon"),
        (
            "parts-20k",
            {
                let mut s = String::from("[shape]\nheight = 50.0\n");
                for i in 0..20_000 {
                    s += &format!(
                        "[[shape.part]]\nname = \"p{i}\"\npolygon = [[0,0],[1,0],[0,1]]\n"
                    );
                }
                s + "[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n"
            },
            "not a job file",
        ),
        (
            "parts-200",
            {
                let mut s = String::from("[shape]\nheight = 50.0\n");
                for i in 0..200 {
                    s += &format!(
                        "[[shape.part]]\nname = \"p{i}\"\npolygon = [[0,0],[1,0],[0,1]]\n"
                    );
                }
                s + "[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n"
            },
            "shape.part",
        ),
        (
            "tolerance-1e-4",
            GOOD.replace("depth = 3.0", "depth = 3.0\ntolerance = 0.0001"),
            "operation.tolerance must be in [0.001, 1] mm, got 0.0001",
        ),
        (
            "stepover-0.001",
            GOOD.replace("diameter = 3.175", "diameter = 3.175\nstepover = 0.001"),
            "tool.stepover must be at least 0.05 of tool.diameter (0.15875 mm)",
        ),
        (
            "margin-rings",
            boss.replace("diameter = 3.175", "diameter = 3.175\nstepover = 0.16")
                + "[stock]\nmargin = 200\n",
            "stock.margin = 200 mm is 1250 clearing rings of tool.stepover = 0.16 mm",
        ),
        (
            "boss-levels-500",
            boss.replace("diameter = 3.175", "diameter = 3.175\nstepdown = 0.2").replace("depth = 3.0", "depth = 100"),
            "operation.depth needs 500 levels of tool.stepdown = 0.2 mm",
        ),
        (
            "diameter-1e-300",
            GOOD.replace("diameter = 3.175", "diameter = 1e-300"),
            "tool.diameter must be in [0.01, 100] mm, got 1e-300",
        ),
        (
            "height-1e-300",
            GOOD.replace("height = 50.0", "height = 1e-300"),
            "shape.height must be in [0.1, 2000] mm, got 1e-300",
        ),
        (
            "polygon-1km",
            "[shape]\n[[shape.part]]\nname = \"p\"\npolygon = [[0,0],[1e6,0],[1e6,1e6],[0,1e6]]\n[tool]\ndiameter = 3.175\n[operation]\nkind = \"boss\"\ndepth = 3.0\n".to_string(),
            "shape.result makes a shape 1000000.0 × 1000000.0 mm; at most 2000 mm",
        ),
        (
            "svg-1km",
            "[shape]\nsvg_path = \"M0 0 H1e6 V1e6 Z\"\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n".to_string(),
            "shape.svg_path makes a shape",
        ),
        (
            "text-53m",
            GOOD.replace(
                "text = \"I\"",
                &format!("text = \"{}\"\nletter_spacing = 1000", "I".repeat(53)),
            ),
            "shape.text makes a shape",
        ),
        (
            "level-1e-300",
            "[shape]\n[[shape.part]]\nname = \"p\"\npolygon = [[0,0],[1,0],[1,1],[0,1]]\nlevel = 1e-300\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n".to_string(),
            "shape.part[1] \"p\": Γ(1e-300) of its field does not close",
        ),
        (
            "text-10k",
            GOOD.replace(
                "text = \"I\"",
                &format!("text = \"{}\"", "I".repeat(10_000)),
            ),
            "shape.text",
        ),
    ];
    for (case, job, key) in cases {
        let dir = scratch("cli", case);
        fs::write(dir.join("job.toml"), job).expect("write job");
        for args in [
            &["validate", "job.toml"][..],
            &["run", "job.toml", "--out", "out"][..],
        ] {
            let o = pfcam_bounded(args, &dir, 60);
            let all = text(&o.stderr);
            assert_eq!(o.status.code(), Some(1), "{case}: {args:?}: {all}");
            // A run may say which stage it is in (a composition is built
            // before its size is known); then comes one message.
            let err = all.lines().last().unwrap_or_default();
            assert!(err.starts_with("error: "), "{case}: {all}");
            assert!(err.contains(key), "{case}: {args:?}: no {key:?} in {all}");
            assert_eq!(
                all.matches("error").count(),
                1,
                "{case}: one message: {all}"
            );
            assert!(all.len() < 400, "{case}: message not clipped: {all}");
            let left = files_in(&dir.join("out"));
            assert!(left.is_empty(), "{case}: files left behind: {left:?}");
        }
    }
}

#[test]
fn a_job_file_that_is_no_job_file_is_refused_unread() {
    let dir = scratch("cli", "not-a-job");
    let big = dir.join("big.toml");
    fs::write(&big, "# ".repeat(5 << 20)).expect("write");
    for (file, needle) in [
        (
            "/dev/zero",
            "/dev/zero is not a job file: it is larger than",
        ),
        (
            big.to_str().unwrap(),
            "is not a job file: it is larger than",
        ),
        (
            dir.to_str().unwrap(),
            "is not a job file: it is a directory",
        ),
        (
            "missing.toml",
            "cannot read job file missing.toml: no such file",
        ),
    ] {
        let o = pfcam_bounded(&["validate", file], &dir, 60);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{file}: {err}");
        assert!(err.contains(needle), "{file}: {err}");
        assert_eq!(err.lines().count(), 1, "{file}: {err}");
    }
    let o = pfcam_bounded(&["convergence", "--glyph", "I", "--n", "100000"], &dir, 60);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("--n") && err.contains("8000"), "{err}");
    let many = vec!["10"; 51].join(",");
    let o = pfcam_bounded(&["convergence", "--glyph", "I", "--n", &many], &dir, 60);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("--n: give at most 50 counts, got 51"), "{err}");
    fs::write(dir.join("job.toml"), GOOD).expect("write job");
    let many = vec!["0.5"; 1001].join(",");
    let o = pfcam_bounded(&["preview", "job.toml", "--levels", &many], &dir, 60);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--levels: give at most 1000 values, got 1001"),
        "{err}"
    );
}

/// Wrong shapes of values are named by their key, once: extra numbers, an
/// array of tables for a table, a float for a count, a directory for a font.
#[test]
fn wrongly_shaped_values_name_their_key() {
    for (case, job, needles) in [
        (
            "profile-point-3",
            "[shape]\ntext = \"I\"\n[tool]\ndiameter = 3.175\n[operation]\nkind = \"boss\"\ndepth = 3.0\n[profile]\nkind = \"table\"\npoints = [[0.8, -3.0], [0.9, -1.0, 7.0], [1.0, 0.0]]\n".to_string(),
            &["profile.points", "invalid length 3, expected 2 numbers [x, y]"][..],
        ),
        (
            "polygon-point-3",
            "[shape]\n[[shape.part]]\nname = \"p\"\npolygon = [[0, 0], [10, 0, 1], [0, 10]]\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n".to_string(),
            &["shape.part[1].polygon", "invalid length 3, expected 2 numbers [x, y]"][..],
        ),
        (
            "origin-3",
            GOOD.replace("height = 50.0", "height = 50.0\norigin = [1.0, 2.0, 3.0]"),
            &["shape.origin", "invalid length 3, expected 2 numbers [x, y]"][..],
        ),
        (
            "tool-array",
            GOOD.replace("[tool]", "[[tool]]"),
            &["tool must be a table, written [tool], not an array of tables [[tool]]"][..],
        ),
        (
            "finish-integer",
            format!("finish = 3\n{GOOD}"),
            &["finish must be a table, written [finish], not an integer"][..],
        ),
        (
            "profile-string",
            format!("profile = \"linear\"\n{GOOD}"),
            &["profile must be a table, written [profile], not a string"][..],
        ),
        (
            "singularities-float",
            format!("{GOOD}[field]\nsingularities = 100.0\n"),
            &["field.singularities", "got 100.0"][..],
        ),
        (
            "steepness-0",
            "[shape]\ntext = \"I\"\n[tool]\ndiameter = 3.175\n[operation]\nkind = \"boss\"\ndepth = 3.0\n[profile]\nkind = \"sigmoid\"\nsteepness = 0\n".to_string(),
            &["profile.steepness must be a positive number, got 0"][..],
        ),
        (
            "font-device",
            GOOD.replace("height = 50.0", "height = 50.0\nfont = \"/dev/zero\""),
            &["shape.font is not a regular file: /dev/zero"][..],
        ),
        (
            "font-dir",
            GOOD.replace("height = 50.0", "height = 50.0\nfont = \".\""),
            &["shape.font is a directory, not a font file"][..],
        ),
    ] {
        assert_rejected(case, &job, needles);
    }
}

/// A value pasted by mistake (600 000 characters, the job file's limit allows
/// it) is echoed once, clipped to its start and its length: an unknown key, a
/// word, a name, a path, a string where a number belongs.
#[test]
fn long_values_are_echoed_clipped() {
    let long = "x".repeat(600_000);
    let clipped = format!("{}… (600000 characters)", "x".repeat(60));
    for (case, job, key) in [
        (
            "key",
            format!("{GOOD}{long} = 1\n"),
            "operation.xxxxxxxxxx",
        ),
        (
            "kind",
            GOOD.replace("depth = 3.0", &format!("depth = 3.0\nkind = \"{long}\"")),
            "operation.kind has no value",
        ),
        (
            "font",
            GOOD.replace("height = 50.0", &format!("height = 50.0\nfont = \"{long}\"")),
            "shape.font xxxxxxxxxx",
        ),
        (
            "font-path",
            GOOD.replace("height = 50.0", &format!("height = 50.0\nfont = \"fonts/{long}\"")),
            "shape.font: no such file",
        ),
        (
            "name",
            format!("[job]\nname = \"{long}\"\n{GOOD}"),
            "job.name must be",
        ),
        (
            "result",
            format!("[shape]\nresult = \"{long}\"\n[[shape.part]]\nname = \"p\"\npolygon = [[0,0],[1,0],[1,1]]\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n"),
            "shape.result names an unknown part",
        ),
        (
            "string-for-number",
            GOOD.replace("depth = 3.0", &format!("depth = \"{long}\"")),
            "operation.depth: invalid type: string",
        ),
    ] {
        let dir = scratch("cli", &format!("clip-{case}"));
        fs::write(dir.join("job.toml"), job).expect("write job");
        let o = pfcam_bounded(&["validate", "job.toml"], &dir, 60);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{case}");
        assert!(err.contains(key), "{case}: no {key:?} in {}", &err[..err.len().min(400)]);
        assert!(err.len() < 400, "{case}: {} bytes: {}", err.len(), &err[..400]);
        assert!(err.contains("… (6000"), "{case}: not clipped: {err}");
        assert_eq!(err.lines().count(), 1, "{case}: {err}");
        // The path is clipped with its directory: `fonts/xxx… (600006 characters)`.
        if !["key", "string-for-number", "font-path"].contains(&case) {
            assert!(err.contains(&clipped), "{case}: {err}");
        }
    }
}

/// A closed standard error (`pfcam run job.toml 2>&1 | head -1`) is no crash:
/// the progress lines nobody reads are dropped and the run finishes (it
/// panicked with exit 101 at the first line), as does an error message.
#[test]
fn a_closed_stderr_is_no_crash() {
    let dir = scratch("cli", "closed-stderr");
    fs::write(dir.join("job.toml"), GOOD).expect("write job");
    fs::write(dir.join("bad.toml"), GOOD.replace("3.175", "-3")).expect("write job");
    for (job, code) in [("job.toml", 0), ("bad.toml", 1)] {
        let mut child = Command::new(PFCAM)
            .args(["run", job, "-o", "out"])
            .current_dir(&dir)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("run pfcam");
        drop(child.stderr.take());
        let status = child.wait().expect("wait");
        assert_eq!(status.code(), Some(code), "{job}");
    }
    assert!(dir.join("out/job.nc").is_file());
}

/// The command line reads the same way in every command: `-o`, `-q`, comma
/// separated defaults, an output name that fits its format, an empty G-code
/// file named as such, an unwritable directory found before the work.
#[test]
fn command_line_consistency() {
    let dir = scratch("cli", "consistency");
    fs::write(dir.join("job.toml"), GOOD).expect("write job");
    // `run -o DIR` as the other commands' -o.
    let o = pfcam(&["run", "job.toml", "-o", "o1", "-q"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(dir.join("o1/job.nc").is_file());
    // validate -q prints nothing when the job is good.
    let o = pfcam(&["validate", "-q", "job.toml"], &dir);
    assert!(
        o.status.success() && o.stdout.is_empty(),
        "{}",
        text(&o.stdout)
    );
    // check -q prints no totals for a clean file.
    let o = pfcam(&["check", "-q", "o1/job.nc"], &dir);
    assert!(
        o.status.success() && o.stdout.is_empty(),
        "{}",
        text(&o.stdout)
    );
    // The help shows defaults as they must be typed.
    let o = pfcam(&["convergence", "--help"], &dir);
    assert!(
        text(&o.stdout).contains("78,148,272,396,516"),
        "{}",
        text(&o.stdout)
    );
    let o = pfcam(&["preview", "--help"], &dir);
    assert!(
        text(&o.stdout).contains("0.9,0.95,0.98,0.99"),
        "{}",
        text(&o.stdout)
    );
    // A preview into a .png name, a field into .svg: refused before the run.
    for (cmd, name) in [
        ("preview", "p.png"),
        ("field", "f.svg"),
        ("surface", "s.nc"),
    ] {
        let o = pfcam(&[cmd, "job.toml", "-o", name], &dir);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{cmd}: {err}");
        assert!(err.contains("--output") && err.contains(name), "{err}");
        assert!(!dir.join(name).exists());
    }
    // An empty G-code file is an error that says so.
    fs::write(dir.join("empty.nc"), "").expect("write");
    let o = pfcam(&["check", "empty.nc"], &dir);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("empty.nc is empty"),
        "{}",
        text(&o.stderr)
    );
    // An output directory that cannot take files fails before the run.
    let o = pfcam(&["run", "job.toml", "--out", "/proc/pfcam-out"], &dir);
    assert_eq!(o.status.code(), Some(3), "{}", text(&o.stderr));
    assert!(!text(&o.stderr).contains("solving"), "{}", text(&o.stderr));
    assert_eq!(text(&o.stderr).lines().count(), 1, "{}", text(&o.stderr));
    // So do the other commands that write a file (a boss, which has a surface).
    let boss = GOOD.replace("depth = 3.0", "depth = 3.0\nkind = \"boss\"");
    fs::write(dir.join("boss.toml"), boss).expect("write job");
    for (cmd, name) in [
        ("surface", "/proc/pfcam-out/s.stl"),
        ("preview", "/proc/pfcam-out/p.svg"),
        ("field", "/proc/pfcam-out/f.png"),
    ] {
        let o = pfcam(&[cmd, "boss.toml", "-o", name], &dir);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(3), "{cmd}: {err}");
        assert!(
            err.starts_with("error: cannot ") && err.contains("/proc"),
            "{cmd}: {err}"
        );
        assert_eq!(err.lines().count(), 1, "{cmd}: before the work: {err}");
    }
}

/// A batch: the good jobs are written, the bad one is named in the table, and
/// the exit status says a job failed; two jobs with one name are refused.
#[test]
fn a_batch_runs_every_job_and_reports_each() {
    let dir = scratch("cli", "batch");
    fs::write(dir.join("a.toml"), GOOD).expect("write");
    fs::write(dir.join("b.toml"), GOOD.replace("\"I\"", "\"H\"")).expect("write");
    fs::write(dir.join("bad.toml"), GOOD.replace("3.175", "-3")).expect("write");
    let o = pfcam(&["run", "a.toml", "bad.toml", "b.toml", "-o", "out"], &dir);
    let table = text(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{table}{}", text(&o.stderr));
    let rows: Vec<&str> = table.lines().collect();
    assert_eq!(rows.len(), 4, "{table}");
    assert!(
        rows[1].starts_with("a ") && rows[1].contains("ok: a.nc"),
        "{table}"
    );
    assert!(
        rows[2].starts_with("bad.toml") && rows[2].contains("tool.diameter"),
        "{table}"
    );
    assert!(
        rows[3].starts_with("b ") && rows[3].contains("ok: b.nc"),
        "{table}"
    );
    assert!(text(&o.stderr).contains("1 of 3 jobs failed"));
    // The levels column counts what the G-code header counts (a profile's
    // passes: 3 for depth 3 at the default 1 mm stepdown).
    let header = fs::read_to_string(dir.join("out/a.nc")).expect("a.nc");
    let in_header: usize = header
        .lines()
        .find_map(|l| l.strip_prefix("(levels: "))
        .and_then(|l| l.split(',').next())
        .and_then(|n| n.parse().ok())
        .expect("levels in the header");
    let in_table: usize = rows[1].split_whitespace().nth(1).unwrap().parse().unwrap();
    assert_eq!((in_table, in_header), (3, 3), "{table}");
    let written: Vec<String> = files_in(&dir.join("out"))
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        written,
        ["a.json", "a.nc", "a.svg", "b.json", "b.nc", "b.svg"]
    );
    // The same G-code as a run of its own.
    let alone = pfcam(&["run", "b.toml", "-o", "alone", "-q"], &dir);
    assert!(alone.status.success());
    assert_eq!(
        fs::read(dir.join("out/b.nc")).unwrap(),
        fs::read(dir.join("alone/b.nc")).unwrap()
    );
    fs::write(dir.join("a2.toml"), format!("[job]\nname = \"a\"\n{GOOD}")).expect("write");
    let o = pfcam(&["run", "a.toml", "a2.toml", "-o", "dup"], &dir);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("would write the same files"),
        "{}",
        text(&o.stderr)
    );
    assert!(files_in(&dir.join("dup")).is_empty());
}

/// Progress: every stage reports exactly as many steps as it announced (no
/// "2/1"), the levels of a boss are counted one by one, and without a terminal
/// the lines say how far the levels are and how long is left.
#[test]
fn progress_counts_each_level_and_never_overruns() {
    use pfcam::pipeline::Progress;
    let boss = "[shape]\ntext = \"I\"\nheight = 30.0\n[tool]\ndiameter = 3.175\n[operation]\nkind = \"boss\"\ndepth = 2.0\n";
    let job = pfcam::job::parse_job(boss, "boss", Path::new(".")).expect("job");
    let mut stages: Vec<(String, u64, u64)> = Vec::new();
    pfcam::pipeline::run(&job, &mut |p| match p {
        Progress::Stage { name, total } => stages.push((name, total, 0)),
        Progress::Step => stages.last_mut().expect("a stage first").2 += 1,
    })
    .expect("run");
    for (name, total, steps) in &stages {
        assert_eq!(steps, total, "{name}: {steps} steps of {total}");
    }
    let levels = stages
        .iter()
        .find(|s| s.0 == "solving and tracing the levels")
        .expect("a level stage");
    assert!(levels.1 > 1, "levels counted one by one: {levels:?}");

    let dir = scratch("cli", "progress");
    fs::write(dir.join("boss.toml"), boss).expect("write");
    let o = pfcam(&["run", "boss.toml"], &dir);
    let err = text(&o.stderr);
    assert!(o.status.success(), "{err}");
    let n = levels.1;
    assert!(
        err.contains(&format!("solving and tracing the levels ({n} steps)")),
        "{err}"
    );
    assert!(
        err.contains(&format!("solving and tracing the levels: {n}/{n} after")),
        "{err}"
    );
    assert!(err.contains("s left"), "{err}");
}

/// The G-code does not depend on the number of threads (issue 13): levels,
/// arcs and gouge checks run in parallel and the fields' expansions are built
/// lazily by whichever thread first needs a box, so a boss with a cavity of
/// its own (the letter A, whose counter is a hole) is run on 1, 2 and 3
/// threads and must come out byte for byte the same; so must a composition,
/// whose independent parts are built in parallel (a rectangle less an
/// equipotential of a triangle: the triangle and the rectangle in one wave).
#[test]
fn the_program_is_the_same_on_any_number_of_threads() {
    let dir = scratch("cli", "threads");
    let jobs = [
        (
            "a",
            "[shape]\ntext = \"A\"\nheight = 30.0\n[tool]\ndiameter = 3.175\nstepdown = 1.0\n\
             [operation]\nkind = \"boss\"\ndepth = 2.0\n[profile]\nkind = \"sigmoid\"\ns1 = 0.98\ns2 = 0.9\n",
        ),
        (
            "c",
            "[shape]\nheight = 30.0\n\
             [[shape.part]]\nname = \"a\"\npolygon = [[0, 0], [60, 0], [60, 40], [0, 40]]\n\
             [[shape.part]]\nname = \"b\"\npolygon = [[20, 10], [45, 12], [30, 32]]\n\
             [[shape.part]]\nname = \"c\"\nof = \"b\"\nlevel = 0.9\n\
             [[shape.part]]\nname = \"r\"\nop = \"subtract\"\nof = [\"a\", \"c\"]\n\
             [tool]\ndiameter = 3.175\n[operation]\ndepth = 2.0\n",
        ),
        // With a finishing program, whose passes, tips and sections are
        // computed in parallel.
        (
            "f",
            "[shape]\ntext = \"I\"\nheight = 20.0\n[tool]\ndiameter = 3.175\nstepdown = 1.5\n\
             [stock]\nmargin = 4.0\n[operation]\nkind = \"boss\"\ndepth = 2.0\nmax_scallop = 1.0\n\
             [profile]\nkind = \"sigmoid\"\ns1 = 0.97\ns2 = 0.85\nsteepness = 6.0\n\
             [finish]\ndiameter = 3.175\nfeed = 1200.0\n",
        ),
    ];
    for (name, job) in jobs {
        fs::write(dir.join(format!("{name}.toml")), job).expect("write job");
        let mut programs = Vec::new();
        for threads in ["1", "2", "3"] {
            let out = format!("out{threads}");
            let o = Command::new(PFCAM)
                .args(["run", &format!("{name}.toml"), "-o", &out, "-q"])
                .env("RAYON_NUM_THREADS", threads)
                .current_dir(&dir)
                .output()
                .expect("run pfcam");
            assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
            let files: &[String] = if name == "f" {
                &[format!("{name}.rough.nc"), format!("{name}.finish.nc")]
            } else {
                &[format!("{name}.nc")]
            };
            let mut program = Vec::new();
            for f in files {
                let bytes = fs::read(dir.join(&out).join(f)).expect("program");
                assert!(bytes.len() > 1000, "{name}: {f}");
                program.extend(bytes);
            }
            programs.push(program);
        }
        assert!(
            programs[0] == programs[1] && programs[1] == programs[2],
            "{name}: the program differs with the thread count"
        );
    }
}

/// Issue 14's guard before the work: a large cavity cut with a 0.5 mm tool
/// has a lower bound past the default `machine.max_hours` (8 h), so the run
/// stops once the levels' contours are known, before any level is traced
/// (with `max_hours = 1000` the same job had not finished one of its levels
/// after 40 s): exit 1, a message naming the key, the bound and its cause,
/// no file. A stepover finer than the default is named as the cause instead.
#[test]
fn a_job_whose_lower_bound_passes_max_hours_stops_before_the_work() {
    let dir = scratch("cli", "max-hours-bound");
    let job = "[shape]\ntext = \"H\"\nheight = 60.0\n[tool]\ndiameter = 0.5\nstepdown = 0.25\n[operation]\nkind = \"cavity\"\ndepth = 10.0\n[profile]\nkind = \"sigmoid\"\ns1 = 0.97\ns2 = 0.9\n";
    let fine = job.replace("diameter = 0.5", "diameter = 1.0\nstepover = 0.1");
    for (name, text_of_job, cause) in [
        (
            "small-tool",
            job.to_string(),
            "cause: tool too small for the area: use a larger tool.diameter",
        ),
        (
            "fine-stepover",
            fine,
            "cause: stepover too small: raise tool.stepover",
        ),
    ] {
        fs::write(dir.join(format!("{name}.toml")), text_of_job).expect("write job");
        let o = pfcam_bounded(&["run", &format!("{name}.toml"), "-o", "out"], &dir, 30);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        let last = err.lines().last().unwrap_or("");
        for n in [
            &format!("error: {name}.toml: machine.max_hours = 8 h: this job needs at least "),
            "before any level was traced",
            cause,
        ] {
            assert!(last.contains(n), "{name}: lacks {n:?}: {err}");
        }
        assert!(!err.contains("tracing the levels"), "{name}: {err}");
        assert!(files_in(&dir.join("out")).is_empty(), "{name}");
    }
}

/// The header's `length:` and `estimated time:` of a G-code file: (cut mm,
/// rapid mm, time as written).
fn header_figures(gcode: &str) -> (f64, f64, String) {
    let find = |prefix: &str| {
        gcode
            .lines()
            .find_map(|l| l.strip_prefix(prefix))
            .unwrap_or_else(|| panic!("no {prefix:?} in the header"))
            .to_string()
    };
    let length = find("(length: cut ");
    let (cut, rapid) = length.split_once(" mm, rapid ").expect("length line");
    let rapid = rapid.strip_suffix(" mm)").expect("length line");
    let time = find("(estimated time: ");
    let time = time.split(',').next().expect("time").to_string();
    (
        cut.parse().expect("cut"),
        rapid.parse().expect("rapid"),
        time,
    )
}

/// The JSON report and the summary give each program's cut and rapid length
/// and time, equal to its G-code header's, with the lower bound below them
/// (a profile and a boss of the shipped jobs).
#[test]
fn the_report_gives_each_program_its_header_figures_and_bound() {
    let dir = scratch("cli", "programs-json");
    // A profile (one program) and a boss with a finishing ball (two).
    for (name, files) in [
        ("letter-i", vec!["letter-i.nc"]),
        ("q-sign", vec!["q-sign.rough.nc", "q-sign.finish.nc"]),
    ] {
        let o = pfcam(
            &["run", &shipped_job(&format!("{name}.toml")), "-o", "out"],
            &dir,
        );
        assert!(o.status.success(), "{}", text(&o.stderr));
        let json: serde_json::Value = serde_json::from_str(
            &fs::read_to_string(dir.join(format!("out/{name}.json"))).expect("json"),
        )
        .expect("parse json");
        let programs = json["programs"].as_array().expect("programs");
        assert_eq!(programs.len(), files.len(), "{name}");
        let summary = text(&o.stdout);
        for (p, file) in programs.iter().zip(&files) {
            let nc = fs::read_to_string(dir.join("out").join(file)).expect("nc");
            let (cut, rapid, time) = header_figures(&nc);
            let num = |k: &str| {
                p[k].as_f64()
                    .unwrap_or_else(|| panic!("{file}: {k} in {p}"))
            };
            assert_eq!(p["file"], *file);
            assert!(
                (num("cut_length_mm") - cut).abs() <= 0.05,
                "{file}: {p} against {cut}"
            );
            assert!(
                (num("rapid_length_mm") - rapid).abs() <= 0.05,
                "{file}: {p} against {rapid}"
            );
            assert_eq!(pfcam::gcode::format_duration(num("time_s")), time, "{file}");
            let bound = num("lower_bound_s");
            assert!(bound > 0.0 && bound <= num("time_s"), "{file}: {p}");
            let parts = num("lower_bound_clearing_s") + num("lower_bound_outline_s");
            assert!((parts - bound).abs() <= 1e-9 * bound, "{file}: {p}");
            assert!(
                (num("time_over_bound") - num("time_s") / bound).abs() < 1e-9,
                "{file}: {p}"
            );
            let line = format!(
                "program {file}: {cut:.1} mm cutting, {rapid:.1} mm rapid, estimated time {time} "
            );
            assert!(summary.contains(&line), "{file}: lacks {line:?}: {summary}");
        }
        // The old totals stay.
        assert!(json["totals"]["time_s"].as_f64().is_some(), "{name}");
        assert!(summary.contains("; lower bound "), "{summary}");
    }
}

/// Issue 14's guards after the work, on a shipped job: a `machine.max_file_mb`
/// one byte under its program's size, or a `machine.max_hours` between its
/// lower bound and its estimate, stops the run with exit 1 and a message
/// naming the key and the figure, and writes nothing (an earlier run's files
/// are left as they were); a limit equal to the size passes.
#[test]
fn a_program_past_max_file_mb_or_max_hours_is_not_written() {
    let dir = scratch("cli", "max-file-mb");
    let job = fs::read_to_string(shipped_job("letter-i.toml")).expect("job");
    assert!(!job.contains("[machine]"), "the test appends the table");
    fs::write(dir.join("letter-i.toml"), &job).expect("write");
    let o = pfcam(&["run", "letter-i.toml", "-o", "before", "-q"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let nc = fs::read(dir.join("before/letter-i.nc")).expect("nc");
    let json: serde_json::Value =
        serde_json::from_slice(&fs::read(dir.join("before/letter-i.json")).expect("json"))
            .expect("json");
    let p = &json["programs"][0];
    let (time_s, bound_s) = (
        p["time_s"].as_f64().unwrap(),
        p["lower_bound_s"].as_f64().unwrap(),
    );
    assert!(bound_s < time_s, "{p}");
    let size = nc.len() as f64;
    let limited = |table: &str| {
        fs::write(
            dir.join("letter-i.toml"),
            format!("{job}\n[machine]\n{table}\n"),
        )
        .expect("write");
    };
    let hours = (bound_s + time_s) / 2.0 / 3600.0;
    for (table, needles) in [
        (
            format!("max_file_mb = {}", (size - 1.0) / 1e6),
            vec![
                "letter-i.toml: nothing written: machine.max_file_mb = ".to_string(),
                format!("the G-code would be {:.6} MB", size / 1e6),
            ],
        ),
        (
            format!("max_hours = {hours}"),
            vec![
                format!("letter-i.toml: nothing written: machine.max_hours = {hours} h"),
                format!(
                    "the program's estimated time is {}",
                    pfcam::gcode::format_duration(time_s)
                ),
            ],
        ),
    ] {
        limited(&table);
        for out in ["new", "before"] {
            let o = pfcam(&["run", "letter-i.toml", "-o", out], &dir);
            let err = text(&o.stderr);
            assert_eq!(o.status.code(), Some(1), "{table}: {err}");
            for n in &needles {
                assert!(err.contains(n.as_str()), "{table}: lacks {n:?}: {err}");
            }
        }
        assert!(files_in(&dir.join("new")).is_empty(), "{table}");
        assert_eq!(files_in(&dir.join("before")).len(), 3, "{table}");
        assert_eq!(fs::read(dir.join("before/letter-i.nc")).expect("nc"), nc);
    }
    limited(&format!("max_file_mb = {}", size / 1e6));
    let o = pfcam(&["run", "letter-i.toml", "-o", "new", "-q"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(fs::read(dir.join("new/letter-i.nc")).expect("nc"), nc);
}
