//! Boss and cavity jobs: every level gouge-free against its own Γ(s_k), every
//! program clean under its own simulation, the cavity's coverage within bound, the
//! same G-code on any thread count, and bad profiles named.

use pfcam::job::{load_job, parse_job, Job};
use pfcam::pipeline::{self, RunOutput};
use pfcam::simulate::verify_program;
use std::path::Path;

use crate::common::shipped;

fn run(job: &Job) -> RunOutput {
    pipeline::run(job, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

fn small_mould() -> Job {
    parse_job(
        r#"
[job]
name = "i-mould"
[shape]
text = "I"
height = 50.0
[tool]
diameter = 3.175
stepdown = 1.0
[operation]
kind = "cavity"
depth = 2.0
tolerance = 0.01
max_scallop = 2.0
[profile]
kind = "linear"
s_bottom = 0.97
"#,
        "i-mould",
        Path::new("."),
    )
    .unwrap()
}

/// The written program, simulated on its stock (`pfcam simulate`'s rules):
/// no rapid into material, no straight plunge, no full-width cut deeper than
/// the stepdown.
fn assert_simulation_clean(job: &Job, out: &RunOutput) {
    let g = pfcam::gcode::write_gcode_on(&out.toolpath, job, out.stock).unwrap();
    let v = verify_program(&g, job.tool.diameter, job.tool.stepdown).unwrap();
    assert!(v.is_ok(), "{v:?}");
}

/// jobs/mfs-sign.toml as one program for one tool, as it shipped before it
/// had a finishing ball: no `[finish]` table, no `stock_to_leave`, and the
/// end mill's terraces at most `max_scallop = 1.0` mm wide (55 levels).
fn one_tool_sign() -> Job {
    let path = shipped("mfs-sign.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let (head, finish) = text.split_once("[finish]").expect("a [finish] table");
    let rest = &finish[finish.find("\n[").expect("a table after [finish]")..];
    let lines: Vec<String> = head
        .lines()
        .filter(|l| !l.starts_with("stock_to_leave"))
        .map(|l| match l.starts_with("max_scallop") {
            true => "max_scallop = 1.0".to_string(),
            false => l.to_string(),
        })
        .collect();
    let text = format!("{}\n{rest}", lines.join("\n"));
    let job = parse_job(&text, "mfs-sign", path.parent().unwrap()).unwrap();
    assert!(job.finishing().is_none());
    job
}

#[test]
fn mfs_sign_boss_levels_are_gouge_free_ramped_and_reported() {
    let shipped_job = load_job(&shipped("mfs-sign.toml")).unwrap();
    assert!(
        shipped_job.finishing().is_some(),
        "the shipped sign is roughed, then finished"
    );
    let job = one_tool_sign();
    let out = run(&job);
    assert_eq!(out.levels.len(), 55, "the one-tool sign has 55 levels");
    assert_eq!(out.toolpath.sections.len(), 55);
    // z strictly decreasing, s increasing toward the foot... decreasing: a boss's
    // contours widen as it goes down.
    for w in out.levels.windows(2) {
        assert!(
            w[1].z < w[0].z && w[1].s < w[0].s,
            "{:?} then {:?}",
            w[0],
            w[1]
        );
    }
    let bottom = out.levels.last().unwrap();
    assert!((bottom.z + 3.0).abs() < 1e-9 && (bottom.s - 0.99).abs() < 1e-9);
    for l in &out.levels {
        assert!(
            l.min_clearance >= -0.01,
            "level z {}: clearance {}",
            l.z,
            l.min_clearance
        );
        assert!(
            // The job's field target: s2 (1 - s1) / 100 = 9.9e-6.
            l.max_error.is_finite() && l.max_error <= 9.9e-6,
            "level z {}: max boundary error {}",
            l.z,
            l.max_error
        );
        assert!(l.n > 0 && l.m == 2 * l.n);
    }
    assert_simulation_clean(&job, &out);
    assert_top_shows_the_letters(&out, 0.999);
}

/// A sign shows its letters: its top edge Γ(s1), contoured on a 0.25 mm grid
/// of the solved field, is one outline per letter, each around exactly one of
/// the glyphs (not a plateau over all three). A glyph is found by its deepest
/// point (Γ(s) for s < 1 encloses its glyph, but near s = 1 the contoured
/// polygon may cut a hair inside a vertex).
fn assert_top_shows_the_letters(out: &RunOutput, s1: f64) {
    use pfcam::field::isolines::{isolines, Grid};
    use pfcam::geometry::{deepest_point, DistanceIndex, Ring, Vec2};
    let polys: Vec<Vec<Vec2>> = out.shape.contours().map(|c| c.flatten(0.01)).collect();
    let (lo, hi) = out.shape.bbox().unwrap();
    let pad = Vec2::new(3.0, 3.0);
    let grid = Grid::sample(&out.field, lo - pad, hi + pad, 0.25, &polys);
    let outlines: Vec<Ring> = isolines(&grid, s1, &out.field, &polys)
        .into_iter()
        .filter(Ring::is_ccw)
        .collect();
    // M, F and S have no counters: one contour each.
    assert_eq!(polys.len(), 3);
    assert_eq!(outlines.len(), 3, "Γ({s1}) should be M, F and S apart");
    for o in &outlines {
        let held = polys
            .iter()
            .filter(|g| o.contains(deepest_point(g, &DistanceIndex::new(&[g.to_vec()])).0))
            .count();
        assert_eq!(held, 1, "an outline of Γ({s1}) holds {held} letters");
    }
}

#[test]
fn mould_covers_every_level_within_a_thousandth() {
    let job = small_mould();
    let out = run(&job);
    assert!(out.levels.len() >= 3);
    for l in &out.levels {
        let u = l.uncut.expect("a cavity level reports its coverage");
        assert!(u <= 1e-3, "level z {}: {:.4} % uncut", l.z, 100.0 * u);
        assert!(l.min_clearance >= -0.01);
    }
    // The floor of the mould is the glyph itself (s = 1).
    assert!((out.levels.last().unwrap().s - 1.0).abs() < 1e-12);
    assert_simulation_clean(&job, &out);
}

#[test]
fn levels_give_the_same_gcode_on_any_thread_count() {
    let job = small_mould();
    let on = |n: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap();
        pool.install(|| pfcam::gcode::write_gcode(&run(&job).toolpath, &job).unwrap())
    };
    let one = on(1);
    assert_eq!(one, on(2));
    assert_eq!(one, on(3));
}

#[test]
fn bad_profiles_are_named() {
    let base = |profile: &str| {
        format!(
            "[shape]\ntext = \"I\"\n[tool]\ndiameter = 3.175\n[operation]\nkind = \"boss\"\ndepth = 3.0\n[profile]\n{profile}\n"
        )
    };
    let e = parse_job(
        &base("kind = \"spline\"\npoints = [[0.8, -3.0], [0.9, -1.0], [0.95, -1.5], [1.0, 0.0]]"),
        "j",
        Path::new("."),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("profile.points") && e.contains("(0.9, -1)") && e.contains("(0.95, -1.5)"),
        "{e}"
    );
    let e = parse_job(
        &base("kind = \"table\"\npoints = [[0.8, -2.0], [1.0, 0.0]]"),
        "j",
        Path::new("."),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("operation.depth"), "{e}");
    let e = parse_job(
        &base("kind = \"sigmoid\"\ns1 = 0.8\ns2 = 0.9"),
        "j",
        Path::new("."),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("profile.s2"), "{e}");
    let e = parse_job(&base("kind = \"linear\"\ns1 = 0.9"), "j", Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("profile.s1") && e.contains("does not apply"),
        "{e}"
    );
    let e = parse_job(
        "[shape]\ntext = \"I\"\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n[profile]\nkind = \"linear\"\n",
        "j",
        Path::new("."),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("profile") && e.contains("boss"), "{e}");
    // The power wall: its exponent is named when it is wrong or misplaced.
    for (profile, key) in [
        ("kind = \"power\"\nexponent = 0.0", "profile.exponent"),
        ("kind = \"power\"\nsteepness = 6.0", "profile.steepness"),
        ("kind = \"sigmoid\"\nexponent = 500.0", "profile.exponent"),
        ("kind = \"power\"\ns1 = 0.99\ns2 = 0.999", "profile.s2"),
    ] {
        let e = parse_job(&base(profile), "j", Path::new("."))
            .unwrap_err()
            .to_string();
        assert!(e.contains(key), "{profile}: {e}");
    }
    let ok = parse_job(&base("kind = \"power\""), "j", Path::new(".")).unwrap();
    assert_eq!(ok.profile.unwrap().s_range(), (0.99, 0.999), "the defaults");
}
