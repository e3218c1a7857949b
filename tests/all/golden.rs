//! Golden files: `gcode-samples/<name>.nc` against freshly generated G-code.
//!
//! The comparison (`pfcam::gcode::compare_gcode`) ignores comments, so the
//! version in the first line, labels and estimates may change; code words are
//! compared token by token, numbers within `GOLDEN_TOLERANCE` (0.001 mm), and X,
//! Y, Z, F as modal state. Samples are rewritten only on purpose, with
//! `PFCAM_BLESS=1 cargo test --release --test all golden:: -- --include-ignored`; a
//! missing sample is a failure, never created silently.

use pfcam::gcode::{compare_gcode, write_gcode, GOLDEN_TOLERANCE};
use pfcam::job::{load_job, parse_job, Job};
use pfcam::toolpath::{Move, Section, Toolpath, Vec3};
use std::fs;
use std::path::{Path, PathBuf};

use crate::common::{files, root, shipped};
use crate::doc_figures;

fn sample_path(name: &str) -> PathBuf {
    root().join("gcode-samples").join(format!("{name}.nc"))
}

/// The samples of a job's programs, without `.nc`.
fn programs(job: &Job) -> Vec<String> {
    pfcam::report::program_files(job)
        .iter()
        .map(|f| f.trim_end_matches(".nc").to_string())
        .collect()
}

/// The sample of a shipped job's first (roughing) program, without `.nc`.
fn first_program(name: &str) -> String {
    let job = load_job(&shipped(&format!("{name}.toml"))).expect("job");
    programs(&job)[0].clone()
}

fn blessing() -> bool {
    std::env::var("PFCAM_BLESS").is_ok_and(|v| v == "1")
}

/// Compare `actual` with the sample `name`, or rewrite the sample when blessing.
fn check_golden(name: &str, actual: &str) {
    let path = sample_path(name);
    if blessing() {
        fs::create_dir_all(path.parent().expect("samples dir")).expect("mkdir gcode-samples");
        fs::write(&path, actual).expect("write sample");
        return;
    }
    let expected = match fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) => panic!(
            "{}: {e}; generate it with PFCAM_BLESS=1 cargo test --release --test all golden:: -- --include-ignored, and review it",
            path.display()
        ),
    };
    if let Err(d) = compare_gcode(&expected, actual, GOLDEN_TOLERANCE) {
        panic!(
            "{} differs from the generated G-code: {d}\n(if the change is intended, re-bless with PFCAM_BLESS=1)",
            path.display()
        );
    }
}

fn hand_job() -> Job {
    let text = "[shape]\ntext = \"I\"\n[tool]\ndiameter = 3.175\nfeed = 800\nplunge_feed = 200\nspindle = 18000\nstepdown = 1\n[operation]\ndepth = 2\n";
    match parse_job(text, "hand-rounded-rect", Path::new(".")) {
        Ok(j) => j,
        Err(e) => panic!("{e}"),
    }
}

/// A 30 × 20 mm rectangle with 4 mm corner arcs, cut in two passes: the
/// writer's golden case, independent of the pipeline. Each pass comes down by
/// rapid to 0.5 mm above the floor of the pass before, ramps in along the
/// front edge (1.5 mm over 22 mm, 3.9°), goes round, and runs the front edge
/// once more at depth to clear the ramp.
fn hand_toolpath() -> Toolpath {
    let p = Vec3::new;
    let r = 4.0;
    let (w, h) = (30.0, 20.0);
    let mut sections = Vec::new();
    let mut floor = 0.0;
    for (k, z) in [-1.0, -2.0].into_iter().enumerate() {
        let mut moves = vec![
            Move::Rapid { to: p(r, 0.0, 5.0) },
            Move::Rapid {
                to: p(r, 0.0, floor + 0.5),
            },
            Move::Linear {
                to: p(w - r, 0.0, z),
                feed: 200.0,
            },
        ];
        let corners = [
            ((w - r, r), p(w, r, z), p(w, h - r, z)),
            ((w - r, h - r), p(w - r, h, z), p(r, h, z)),
            ((r, h - r), p(0.0, h - r, z), p(0.0, r, z)),
            ((r, r), p(r, 0.0, z), p(w - r, 0.0, z)),
        ];
        for ((cx, cy), arc_to, line_to) in corners {
            moves.push(Move::Arc {
                to: arc_to,
                cx,
                cy,
                ccw: true,
                feed: 800.0,
            });
            moves.push(Move::Linear {
                to: line_to,
                feed: 800.0,
            });
        }
        moves.push(Move::Rapid {
            to: p(w - r, 0.0, 5.0),
        });
        sections.push(Section {
            label: format!("rounded rectangle ({}), z {z:.3}", k + 1),
            z,
            moves,
        });
        floor = z;
    }
    Toolpath {
        start: p(0.0, 0.0, 5.0),
        sections,
    }
}

#[test]
fn writer_matches_its_sample() {
    let g = write_gcode(&hand_toolpath(), &hand_job()).expect("write");
    check_golden("hand-rounded-rect", &g);
}

#[test]
fn comparator_catches_a_change_of_the_real_sample() {
    let Ok(sample) = fs::read_to_string(sample_path("hand-rounded-rect")) else {
        panic!("gcode-samples/hand-rounded-rect.nc is missing");
    };
    // Every "X30" (the far side) moved by 0.01 mm: beyond the tolerance.
    let moved = sample.replace("X30 ", "X30.01 ");
    assert_ne!(moved, sample, "the sample has no X30 word");
    assert!(compare_gcode(&sample, &moved, GOLDEN_TOLERANCE).is_err());
    // Moved by 0.0005 mm (written as an extra digit): within it.
    let nudged = sample.replace("X30 ", "X30.0005 ");
    assert_eq!(compare_gcode(&sample, &nudged, GOLDEN_TOLERANCE), Ok(()));
}

#[test]
fn every_job_matches_its_sample() {
    let jobs = files("jobs", "toml");
    assert!(!jobs.is_empty());
    let mut quoting = 0;
    for path in jobs {
        let job = load_job(&path).unwrap_or_else(|e| panic!("{e}"));
        let out = pfcam::pipeline::run(&job, &mut |_| {})
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let g = pfcam::gcode::write_gcode_on(&out.toolpath, &job, out.stock)
            .unwrap_or_else(|e| panic!("{e}"));
        // One sample per program: `<name>`, or `<name>.rough` and
        // `<name>.finish` for a job with a finishing tool.
        let names = programs(&job);
        check_golden(&names[0], &g);
        if let (Some(f), Some(fj)) = (&out.finish, job.finishing()) {
            let gf = pfcam::gcode::write_gcode_on(&f.toolpath, &fj, out.stock)
                .unwrap_or_else(|e| panic!("{e}"));
            check_golden(&names[1], &gf);
        }
        quoting += usize::from(check_run_figures(&job.name, &out));
    }
    assert_eq!(
        quoting, 4,
        "mfs-profile, mfs-sign, q-mould and mfs-mould are quoted"
    );
}

/// The figures of a run that README.md and docs/method.md quote, against
/// this run (`pfcam run JOB` prints them): mfs-profile's tracer fallbacks,
/// mfs-sign's field (max boundary
/// error, N) and min clearance, the cavity levels whose field errs above
/// (1 − s)/100 on q-mould and mfs-mould, and mfs-mould's uncut share.
/// Returns whether the docs quote this job.
fn check_run_figures(name: &str, out: &pfcam::pipeline::RunOutput) -> bool {
    let method = doc_figures::read("docs/method.md");
    // A cavity level warns when its field errs above (1 − s)/100 (§9).
    let warned: Vec<(f64, f64, f64)> = out
        .levels
        .iter()
        .map(|l| (l.max_error, (1.0 - l.s) / 100.0, l.s))
        .filter(|(e, bound, _)| e > bound)
        .collect();
    let range = |f: fn(&(f64, f64, f64)) -> f64| {
        let v = warned.iter().map(f);
        (
            v.clone().fold(f64::INFINITY, f64::min),
            v.fold(0.0, f64::max),
        )
    };
    match name {
        "mfs-profile" => {
            // §7: the tracer's fallbacks, and the N of the shape's field.
            let stated =
                doc_figures::numbers_after(&method, "docs/method.md", "On mfs-profile it is", 2);
            let what = "docs/method.md §7, mfs-profile's fallbacks at N";
            assert_eq!(stated[0].parse().ok(), Some(out.fallbacks), "{what}");
            assert_eq!(
                stated[1].parse().ok(),
                out.solves.first().map(|s| s.n),
                "{what}"
            );
        }
        "mfs-sign" => {
            let readme = doc_figures::read("README.md");
            let shape = out
                .solves
                .iter()
                .find(|s| !s.label.starts_with("level"))
                .expect("the shape's solve");
            let what = "README.md, mfs-sign's field";
            let stated = doc_figures::number_after(&readme, "README.md", "max boundary error of");
            doc_figures::assert_figure(what, &stated, shape.max_error);
            let n = doc_figures::number_after(&readme, "README.md", "with N =");
            assert_eq!(n.parse().ok(), Some(shape.n), "{what}: N");
            // §3c: the largest move of the surface, as the solve's label says.
            let marker = "move the surface by up to";
            let moved = doc_figures::number_after(&shape.label, "the solve's label", marker);
            let stated = doc_figures::number_after(&method, "docs/method.md", marker);
            assert_eq!(stated, moved, "docs/method.md §3c, mfs-sign's move");
            let stated = doc_figures::number_after(
                &method,
                "docs/method.md",
                "Measured on mfs-sign: min clearance",
            );
            doc_figures::assert_figure("docs/method.md §8", &stated, out.min_clearance);
        }
        "q-mould" | "mfs-mould" => {
            // "On q-mould 10 of the 12 ...", "on mfs-mould 1 of the 26 ..."
            let rule = doc_figures::after(&method, "docs/method.md", "**The level rule.**");
            let marker = format!("n {name} ");
            let stated = doc_figures::numbers_after(rule, "docs/method.md", &marker, 2);
            let at = rule.find(&marker).expect("found just above");
            let what = format!("docs/method.md §9, {name}'s warning levels");
            assert_eq!(stated[0].parse().ok(), Some(warned.len()), "{what}");
            assert_eq!(stated[1].parse().ok(), Some(out.levels.len()), "{what}");
            let (errors, bounds) = (range(|w| w.0), range(|w| w.1));
            if name == "q-mould" {
                // "(errors A to B against bounds C to D"
                let figures =
                    doc_figures::numbers_after(&rule[at..], "docs/method.md", "(errors", 4);
                for (f, v) in figures.iter().zip([errors.0, errors.1, bounds.0, bounds.1]) {
                    doc_figures::assert_figure(&what, f, v);
                }
            } else {
                // "(E against B at s = S"
                let figures = doc_figures::numbers_after(&rule[at..], "docs/method.md", " (", 3);
                for (f, v) in figures.iter().zip([errors.1, bounds.1, range(|w| w.2).1]) {
                    doc_figures::assert_figure(&what, f, v);
                }
                // §9's coverage: the worst uncut share over all levels, in %.
                let stated =
                    doc_figures::number_after(&method, "docs/method.md", "On mfs-mould it is");
                let worst = out
                    .levels
                    .iter()
                    .filter_map(|l| l.uncut)
                    .fold(0.0, f64::max);
                doc_figures::assert_figure(
                    "docs/method.md §9, uncut share",
                    &stated,
                    100.0 * worst,
                );
                let levels = doc_figures::number_after(&method, "docs/method.md", "% on all");
                assert_eq!(
                    levels.parse().ok(),
                    Some(out.levels.len()),
                    "docs/method.md §9"
                );
            }
        }
        _ => return false,
    }
    true
}

/// docs/gcode.md's table of the boss and the mould gives, for `arcs = true`,
/// the lines, bytes and arcs of exactly the programs in gcode-samples (the
/// shipped jobs write arcs): re-blessing a sample without re-measuring the
/// table fails here. (The `arcs = false` columns need a run of each job.)
#[test]
fn gcode_doc_table_matches_the_samples() {
    let doc = fs::read_to_string(root().join("docs/gcode.md")).expect("docs/gcode.md");
    let mut seen = 0;
    for (name, row_start) in [
        ("mfs-sign.rough", "| mfs-sign.rough (boss"),
        ("mfs-mould.rough", "| mfs-mould.rough (cavity"),
    ] {
        let row = doc
            .lines()
            .find(|l| l.starts_with(row_start))
            .unwrap_or_else(|| panic!("docs/gcode.md has no row {row_start}"));
        let cols: Vec<u64> = row
            .split('|')
            .map(str::trim)
            .filter_map(|c| c.parse().ok())
            .collect();
        assert_eq!(cols.len(), 5, "{row}");
        let text = fs::read_to_string(sample_path(name)).expect("sample");
        let lines = text.lines().count() as u64;
        let arcs = text
            .lines()
            .filter(|l| l.starts_with("G2 ") || l.starts_with("G3 "))
            .count() as u64;
        assert_eq!(
            (cols[2], cols[3], cols[4]),
            (lines, text.len() as u64, arcs),
            "docs/gcode.md's {name} row (lines, bytes, arcs) against gcode-samples/{name}.nc"
        );
        seen += 1;
    }
    assert_eq!(seen, 2);
}

/// The level count in the header of the sample `name` (`(levels: 55, ...)`).
fn header_levels(name: &str) -> usize {
    let sample = fs::read_to_string(sample_path(name)).expect("sample");
    sample
        .lines()
        .find_map(|l| l.strip_prefix("(levels: "))
        .and_then(|l| l.split(',').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("levels in the header of {name}.nc"))
}

/// The README's first paragraph counts mfs-sign's z-levels: the count in
/// the shipped roughing program's header (`(levels: 3, ...)`) is the one it
/// states.
#[test]
fn readme_level_count_matches_the_sample() {
    let readme = fs::read_to_string(root().join("README.md")).expect("README.md");
    let stated: usize = readme
        .split(" z-levels")
        .next()
        .and_then(|before| before.split_whitespace().last())
        .and_then(|n| n.parse().ok())
        .expect("README.md states mfs-sign's z-levels as 'N z-levels'");
    assert_eq!(
        stated,
        header_levels("mfs-sign.rough"),
        "README.md against gcode-samples/mfs-sign.rough.nc"
    );
}

/// docs/gcode.md shows the first and last lines of the mfs-profile program:
/// they are the sample's, so the header's counts, lengths and time it quotes
/// are the ones `pfcam run jobs/mfs-profile.toml` writes.
#[test]
fn gcode_doc_program_is_the_sample() {
    let doc = doc_figures::read("docs/gcode.md");
    let block = doc_figures::after(&doc, "docs/gcode.md", "## The program")
        .split("```\n")
        .nth(1)
        .expect("docs/gcode.md: the program block under ## The program");
    let (head, tail) = block
        .split_once("...\n")
        .expect("the block elides the middle with ...");
    let sample = fs::read_to_string(sample_path("mfs-profile")).expect("sample");
    let head: Vec<&str> = head.lines().collect();
    let tail: Vec<&str> = tail.lines().collect();
    assert!(head.len() >= 12, "the header is shown: {head:?}");
    let lines: Vec<&str> = sample.lines().collect();
    assert_eq!(
        head,
        lines[..head.len()],
        "docs/gcode.md's program against the start of gcode-samples/mfs-profile.nc"
    );
    assert_eq!(
        tail,
        lines[lines.len() - tail.len()..],
        "docs/gcode.md's program against the end of gcode-samples/mfs-profile.nc"
    );
}

/// The README's table of shipped jobs gives each boss's and cavity's z-levels:
/// the count in its sample's header. (A profile's row counts its one outline
/// level, whose passes the header lists as levels; it is not checked here.)
#[test]
fn readme_jobs_table_levels_match_the_samples() {
    let readme = doc_figures::read("README.md");
    let mut checked = 0;
    for name in [
        "mfs-sign",
        "mfs-mould",
        "q-sign",
        "q-mould",
        "polyharmonic-face",
        "polyharmonic-pebble",
    ] {
        let cells = doc_figures::table_row(&readme, "README.md", &format!("`jobs/{name}.toml`"));
        let stated: usize = cells[2].parse().expect("a level count");
        assert_eq!(
            stated,
            header_levels(&first_program(name)),
            "README.md's {name} row against its roughing sample"
        );
        checked += 1;
    }
    assert_eq!(checked, 6);
}

/// The README's jobs table gives each shipped job's machining time: the
/// estimate in its sample's header, word for word (the letters share a row,
/// in the order i, a, s).
#[test]
fn readme_jobs_table_times_are_the_headers() {
    let readme = doc_figures::read("README.md");
    let rows: [(&str, &[&str]); 11] = [
        (
            "`jobs/mfs-sign.toml`",
            &["mfs-sign.rough", "mfs-sign.finish"],
        ),
        (
            "`jobs/mfs-mould.toml`",
            &["mfs-mould.rough", "mfs-mould.finish"],
        ),
        ("`jobs/mfs-profile.toml`", &["mfs-profile"]),
        (
            "`jobs/letter-i.toml`, `letter-a.toml`, `letter-s.toml`",
            &["letter-i", "letter-a", "letter-s"],
        ),
        ("`jobs/q-sign.toml`", &["q-sign.rough", "q-sign.finish"]),
        ("`jobs/q-mould.toml`", &["q-mould.rough", "q-mould.finish"]),
        ("`jobs/svg-logo.toml`", &["svg-logo"]),
        ("`jobs/dxf-plate.toml`", &["dxf-plate"]),
        (
            "`jobs/pde-trimmed.toml`",
            &["pde-trimmed.rough", "pde-trimmed.finish"],
        ),
        (
            "`jobs/polyharmonic-face.toml`",
            &["polyharmonic-face.rough", "polyharmonic-face.finish"],
        ),
        (
            "`jobs/polyharmonic-pebble.toml`",
            &["polyharmonic-pebble.rough", "polyharmonic-pebble.finish"],
        ),
    ];
    for (key, names) in rows {
        let cells = doc_figures::table_row(&readme, "README.md", key);
        let want: Vec<String> = names
            .iter()
            .map(|name| {
                let sample = fs::read_to_string(sample_path(name)).expect("sample");
                sample
                    .lines()
                    .find_map(|l| l.strip_prefix("(estimated time: "))
                    .and_then(|l| l.split(',').next())
                    .unwrap_or_else(|| panic!("an estimated time in {name}.nc"))
                    .to_string()
            })
            .collect();
        assert_eq!(cells[3], want.join(", "), "README.md's {key} row");
    }
}
