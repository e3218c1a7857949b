//! Boss and cavity jobs: every level gouge-free against its own Γ(s_k), every
//! entry into uncut material ramped, the cavity's coverage within bound, the
//! same G-code on any thread count, and bad profiles named.

use pfcam::geometry::Vec2;
use pfcam::job::{load_job, parse_job, Job};
use pfcam::pipeline::{self, RunOutput};
use pfcam::toolpath::Move;
use std::path::Path;

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

/// No vertical move goes below the floor of the level above except outside the
/// stock (in air); everything else enters by a ramp.
fn assert_no_plunge_into_material(out: &RunOutput, top: f64) {
    let (lo, hi) = out.stock.expect("a boss or cavity has a stock rectangle");
    let r = 3.175 / 2.0;
    let mut at = out.toolpath.start;
    let mut z_prev = top;
    let mut plunges = 0;
    let mut ramps = 0;
    for (sec, lv) in out.toolpath.sections.iter().zip(&out.levels) {
        for m in &sec.moves {
            if let Move::Linear { to, .. } = *m {
                let vertical = (to.x - at.x).abs() < 1e-9 && (to.y - at.y).abs() < 1e-9;
                if vertical && to.z < z_prev - 1e-9 {
                    let p = Vec2::new(to.x, to.y);
                    let outside = p.x < lo.x - r + 1e-6
                        || p.x > hi.x + r - 1e-6
                        || p.y < lo.y - r + 1e-6
                        || p.y > hi.y + r - 1e-6;
                    assert!(outside, "straight plunge into material at ({:.3}, {:.3}) to z {:.3} (level z {:.3})", p.x, p.y, to.z, lv.z);
                    plunges += 1;
                }
                if !vertical && to.z < at.z - 1e-9 {
                    ramps += 1;
                }
            }
            at = m.to();
        }
        z_prev = lv.z;
    }
    assert!(ramps > 0, "no ramped entries at all");
    let _ = plunges;
}

#[test]
fn mfs_sign_boss_levels_are_gouge_free_ramped_and_reported() {
    let job = load_job(Path::new("jobs/mfs-sign.toml")).unwrap();
    let out = run(&job);
    assert_eq!(out.levels.len(), 40, "the shipped sign has 40 levels");
    assert_eq!(out.toolpath.sections.len(), 40);
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
    assert!((bottom.z + 3.0).abs() < 1e-9 && (bottom.s - 0.90).abs() < 1e-9);
    for l in &out.levels {
        assert!(
            l.min_clearance >= -0.01,
            "level z {}: clearance {}",
            l.z,
            l.min_clearance
        );
        assert!(
            l.max_error.is_finite() && l.max_error < 5e-3,
            "level z {}: max boundary error {}",
            l.z,
            l.max_error
        );
        assert!(l.n > 0 && l.m == 2 * l.n);
    }
    assert_no_plunge_into_material(&out, 0.0);
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
    assert_no_plunge_into_material(&out, 0.0);
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
}
