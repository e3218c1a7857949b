//! Roughing with stock to leave, then finishing with a ball (issue 14): both
//! programs run through `pfcam simulate` (an independent height-map model of
//! the cutters) against the part's own surface S2.

use pfcam::gcode::write_gcode_on;
use pfcam::job::{parse_job, Job};
use pfcam::simulate::{job_facts, simulate_programs, SimOptions};
use std::path::Path;

/// A 20 mm letter I as a boss (or its mould) with a sigmoid wall and a
/// 3.175 mm ball finisher.
fn job(kind: &str, extra: &str) -> Job {
    let text = format!(
        "[job]\nname = \"t\"\n[shape]\ntext = \"I\"\nheight = 20.0\n[tool]\ndiameter = 3.175\nstepdown = 1.5\n[stock]\nmargin = 4.0\n[operation]\nkind = \"{kind}\"\ndepth = 2.0\nmax_scallop = 1.0\n[profile]\nkind = \"sigmoid\"\ns1 = 0.97\ns2 = 0.85\nsteepness = 6.0\n[finish]\ndiameter = 3.175\nfeed = 1200.0\n{extra}"
    );
    parse_job(&text, "t", Path::new(".")).expect("job")
}

/// The two programs of `job` simulated in order: (sequence, rough G-code, finish G-code).
fn rough_then_finish(job: &Job) -> (pfcam::simulate::Sequence, String, String) {
    let out = pfcam::pipeline::run(job, &mut |_| {}).expect("runs");
    let rough = write_gcode_on(&out.toolpath, job, out.stock).expect("rough");
    let f = out.finish.as_ref().expect("a finishing program");
    let fjob = job.finishing().expect("finishing job");
    let finish = write_gcode_on(&f.toolpath, &fjob, out.stock).expect("finish");
    let facts = job_facts(job, 0.1).expect("facts");
    let opts = SimOptions {
        job: Some(facts),
        ..SimOptions::default()
    };
    let seq =
        simulate_programs(&[("rough", &rough), ("finish", &finish)], &opts).expect("simulates");
    (seq, rough, finish)
}

#[test]
fn a_boss_finished_with_a_ball_is_within_the_scallop_and_never_gouged() {
    let j = job("boss", "");
    let (seq, _, finish) = rough_then_finish(&j);
    assert!(
        finish
            .lines()
            .nth(1)
            .unwrap()
            .starts_with("(tool: 3.175 mm ball end mill, feed 1200"),
        "{}",
        finish.lines().nth(1).unwrap()
    );
    for p in &seq.programs {
        let r = &p.report;
        assert_eq!(r.rapids_into_material, 0, "{}", p.name);
        assert_eq!(r.straight_plunges, 0, "{}", p.name);
        assert_eq!(r.deep_slots, 0, "{}", p.name);
    }
    assert_eq!(
        seq.programs[1].report.tool_shape,
        pfcam::simulate::ToolShape::Ball
    );
    let part = seq.part.as_ref().expect("compared with the part");
    let tol = j.operation.tolerance;
    let scallop = j.finish.as_ref().unwrap().scallop;
    assert!(
        part.max_gouge.value <= tol,
        "gouge {}",
        part.max_gouge.value
    );
    assert!(
        part.max_left.value <= scallop + 0.01,
        "material left {} mm",
        part.max_left.value
    );
}

/// A near-vertical wall (the README sign's power profile, n = 500) round the
/// letter I's square serif corners: the finisher's tips spread round each
/// corner and its drops change fast along a pass. Neither may gouge the part
/// or dive into the wall the roughing left.
#[test]
fn a_near_vertical_wall_is_finished_without_plunges() {
    let text = "[job]\nname = \"t\"\n[shape]\ntext = \"I\"\nheight = 20.0\n[tool]\ndiameter = 3.175\nstepdown = 1.0\n[stock]\nmargin = 4.0\n[operation]\nkind = \"boss\"\ndepth = 2.0\nmax_scallop = 1.0\n[profile]\nkind = \"power\"\ns1 = 0.999\ns2 = 0.99\nexponent = 500.0\n[field]\nsingularities = \"auto\"\npseudo_boundary = \"auto\"\n[finish]\ndiameter = 3.175\nfeed = 1200.0\n";
    let j = parse_job(text, "t", Path::new(".")).expect("job");
    let (seq, _, _) = rough_then_finish(&j);
    for p in &seq.programs {
        assert_eq!(p.report.rapids_into_material, 0, "{}", p.name);
        assert_eq!(p.report.straight_plunges, 0, "{}", p.name);
    }
    // Within the tolerance since the finisher drops on a mesh as fine as
    // the one `pfcam simulate` measures against (0.1 mm; with 0.2 mm
    // isobands the serif corners' near-vertical walls were cut short and
    // the ball lowered into what they left out: 0.022 mm). docs/method.md §13.
    let part = seq.part.as_ref().expect("compared with the part");
    assert!(
        part.max_gouge.value <= j.operation.tolerance,
        "gouge {} at line {}",
        part.max_gouge.value,
        part.max_gouge.line
    );
}

#[test]
fn the_rough_alone_leaves_the_stock_the_finisher_removes() {
    let j = job("boss", "");
    let (seq, rough, _) = rough_then_finish(&j);
    let facts = job_facts(&j, 0.1).expect("facts");
    let alone = pfcam::simulate::simulate(
        &rough,
        &SimOptions {
            job: Some(facts),
            ..SimOptions::default()
        },
    )
    .expect("simulates");
    let left_rough = alone.report.part.as_ref().unwrap().max_left.value;
    let left_both = seq.part.as_ref().unwrap().max_left.value;
    // The rough keeps stock_to_leave (0.2 mm in plan) on the walls: on a
    // sloped wall that stands at least that much over S2 somewhere.
    assert!(left_rough >= j.operation.stock_to_leave, "{left_rough}");
    assert!(left_both < 0.1 * left_rough, "{left_both} vs {left_rough}");
    // And it never cuts into the part.
    assert!(alone.report.part.as_ref().unwrap().max_gouge.value <= j.operation.tolerance);
}

#[test]
fn a_mould_finished_with_a_ball_is_within_the_scallop_wherever_the_ball_reaches() {
    let j = job("cavity", "");
    let (seq, _, _) = rough_then_finish(&j);
    for p in &seq.programs {
        assert_eq!(p.report.rapids_into_material, 0, "{}", p.name);
        assert_eq!(p.report.straight_plunges, 0, "{}", p.name);
    }
    let part = seq.part.as_ref().unwrap();
    assert!(
        part.max_gouge.value <= j.operation.tolerance,
        "{}",
        part.max_gouge.value
    );
    // The floor's corners are the glyph's, rounded by Γ(0.97) to less than
    // the ball's radius: the ball cannot reach into them. Over what it can
    // reach (simulate's envelope of the part for the last tool) the scallop
    // bound holds.
    let scallop = j.finish.as_ref().unwrap().scallop;
    assert!(
        part.max_left_reachable.value <= scallop + 0.01,
        "{} mm over the ball's reach",
        part.max_left_reachable.value
    );
    assert!(part.max_left.value > part.max_left_reachable.value);
}

/// `finish.pattern = "geodesic"` (docs/method.md §13, *Geodesic passes*) on
/// the letter I, boss and mould, and on the near-vertical power wall: no
/// rapid into material, no plunge, no gouge past the tolerance; every wall
/// within the scallop bound along its normal where the ball reaches
/// (`simulate::walls`: 0.0112, 0.0114 and 0.0168 mm at 286e50d; the power
/// wall's was 0.023 mm before 823dc07, 24a2735 and 286e50d), and the
/// sigmoid walls on the height map too (on the power wall the map's reach
/// envelope sinks under the foot, docs/simulate.md).
#[test]
fn geodesic_passes_finish_the_letter_within_the_bound() {
    let power = "[job]\nname = \"t\"\n[shape]\ntext = \"I\"\nheight = 20.0\n[tool]\ndiameter = 3.175\nstepdown = 1.0\n[stock]\nmargin = 4.0\n[operation]\nkind = \"boss\"\ndepth = 2.0\nmax_scallop = 1.0\n[profile]\nkind = \"power\"\ns1 = 0.999\ns2 = 0.99\nexponent = 500.0\n[field]\nsingularities = \"auto\"\npseudo_boundary = \"auto\"\n[finish]\ndiameter = 3.175\nfeed = 1200.0\npattern = \"geodesic\"\n";
    let jobs = [
        ("boss", job("boss", "pattern = \"geodesic\"\n")),
        ("mould", job("cavity", "pattern = \"geodesic\"\n")),
        (
            "power wall",
            parse_job(power, "t", Path::new(".")).expect("job"),
        ),
    ];
    for (what, j) in jobs {
        let (seq, _, finish) = rough_then_finish(&j);
        assert!(finish.contains(" d "), "{what}: no pass of σ");
        for p in &seq.programs {
            assert_eq!(p.report.rapids_into_material, 0, "{what}: {}", p.name);
            assert_eq!(p.report.straight_plunges, 0, "{what}: {}", p.name);
        }
        let part = seq.part.as_ref().expect("compared with the part");
        let scallop = j.finish.as_ref().unwrap().scallop;
        assert!(
            part.max_gouge.value <= j.operation.tolerance,
            "{what}: gouge {} at line {}",
            part.max_gouge.value,
            part.max_gouge.line
        );
        let walls = part.walls.as_ref().expect("a ball finished the walls");
        assert!(walls.left.value <= scallop + 0.01, "{what}: {:?}", walls);
        if what != "power wall" {
            assert!(
                part.max_left_reachable.value <= scallop + 0.01,
                "{what}: {} mm left over the ball's reach",
                part.max_left_reachable.value
            );
        }
    }
}
