//! The traced tool path against independent geometry: cavalier_contours' exact
//! offset, invariance under the contours' start, direction, the gouge check.

use cavalier_contours::polyline::{PlineSource, PlineSourceMut, Polyline};
use pfcam::geometry::{build_shape, DistanceIndex, Shape, Vec2};
use pfcam::job::{parse_job, Direction, Job};
use pfcam::pipeline::{self, Plan};
use pfcam::toolpath::{gouge, Move, Section, Toolpath, Vec3};

use crate::common::sample_pline;
use crate::doc_figures;

fn job(text: &str, height: f64) -> Job {
    let toml = format!(
        r#"
[shape]
text = "{text}"
height = {height}
letter_spacing = 2.0
[tool]
diameter = 3.175
[operation]
kind = "profile"
depth = 3.0
tolerance = 0.01
direction = "climb"
"#
    );
    parse_job(&toml, "test", std::path::Path::new(".")).unwrap()
}

fn plan(j: &Job) -> Plan {
    pipeline::plan(j, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

/// The exact offsets of every contour by r to the tool side (material on the left,
/// so −r in cavalier's convention), from a flattening within 3e-4 mm. (cavalier
/// 0.9 returns a degenerate loop for the S flattened within 1e-4 mm, 2963 vertices;
/// at 3e-4 and coarser its result is stable, so every oracle loop is also checked
/// for a plausible area.)
fn oracle_offsets(shape: &Shape, r: f64) -> Vec<Polyline> {
    let mut out = Vec::new();
    for c in shape.contours() {
        let mut pl: Polyline = Polyline::new_closed();
        for p in c.flatten(3e-4) {
            pl.add(p.x, p.y, 0.0);
        }
        let offs = pl.parallel_offset(-r);
        assert!(!offs.is_empty());
        for o in &offs {
            assert!(
                o.area().abs() > r * r,
                "degenerate oracle offset (area {})",
                o.area()
            );
        }
        out.extend(offs);
    }
    out
}

/// Symmetric Hausdorff distance between a traced loop and the nearest oracle offset.
fn hausdorff(lp: &[Vec2], oracles: &[Polyline]) -> f64 {
    // The oracle loop that matches: the one nearest to the traced loop's first point.
    let best = oracles
        .iter()
        .min_by(|a, b| {
            let da = sample_pline(a, 0.05)
                .iter()
                .map(|q| q.dist(lp[0]))
                .fold(f64::INFINITY, f64::min);
            let db = sample_pline(b, 0.05)
                .iter()
                .map(|q| q.dist(lp[0]))
                .fold(f64::INFINITY, f64::min);
            da.total_cmp(&db)
        })
        .unwrap();
    let oracle_pts = sample_pline(best, 0.002);
    let oracle_index = DistanceIndex::new(std::slice::from_ref(&oracle_pts));
    let traced_index = DistanceIndex::new(&[lp[..lp.len() - 1].to_vec()]);
    // Traced → oracle: every vertex and chord midpoint.
    let mut d: f64 = 0.0;
    for w in lp.windows(2) {
        for p in [w[0], w[0].lerp(w[1], 0.5)] {
            d = d.max(oracle_index.distance(p));
        }
    }
    // Oracle → traced.
    for q in &oracle_pts {
        d = d.max(traced_index.distance(*q));
    }
    d
}

fn check_hausdorff(text: &str) -> f64 {
    let j = job(text, 50.0);
    let p = plan(&j);
    let oracles = oracle_offsets(&p.shape, j.tool.diameter / 2.0);
    let doc = doc_figures::read("docs/method.md");
    let table = doc_figures::after(&doc, "docs/method.md", "### Accuracy, measured");
    let mut worst: f64 = 0.0;
    for lp in &p.loops {
        let h = hausdorff(&lp.points, &oracles);
        println!(
            "{text}: {} Hausdorff {h:.5} mm ({} points)",
            lp.label,
            lp.points.len()
        );
        worst = worst.max(h);
        // docs/method.md §7 quotes every loop's distance: `I`: outside I, ...
        let label = lp.label.rsplit_once(" (").map_or(&*lp.label, |(l, _)| l);
        let row = format!("`{text}`: {label}");
        let cells = doc_figures::table_row(table, "docs/method.md", &row);
        doc_figures::assert_figure(&format!("docs/method.md, {row}"), cells[1], h);
    }
    assert!(!p.loops.is_empty());
    assert!(worst <= 0.02, "{text}: Hausdorff {worst} mm > 0.02 mm");
    worst
}

#[test]
fn hausdorff_to_exact_offset_i() {
    check_hausdorff("I");
}
#[test]
fn hausdorff_to_exact_offset_a() {
    check_hausdorff("A");
}
#[test]
fn hausdorff_to_exact_offset_s() {
    check_hausdorff("S");
}
#[test]
fn hausdorff_to_exact_offset_mfs() {
    check_hausdorff("MFS");
}

#[test]
fn path_does_not_depend_on_where_contours_start() {
    let j = job("A", 50.0);
    let a = plan(&j);
    // Same shape with every contour starting at another segment.
    let shape: Shape = build_shape(&j.shape).unwrap();
    let mut cycled = shape.clone();
    for r in &mut cycled.regions {
        r.outline = r.outline.cycled(5);
        for c in &mut r.counters {
            *c = c.cycled(1);
        }
    }
    assert_ne!(cycled, shape);
    let b = pipeline::plan_shape(cycled, &j, &mut |_| {}).unwrap();
    assert_eq!(a.loops.len(), b.loops.len());
    for (la, lb) in a.loops.iter().zip(&b.loops) {
        let ia = DistanceIndex::new(&[la.points[..la.points.len() - 1].to_vec()]);
        let ib = DistanceIndex::new(&[lb.points[..lb.points.len() - 1].to_vec()]);
        let d1 = lb
            .points
            .iter()
            .map(|p| ia.distance(*p))
            .fold(0.0, f64::max);
        let d2 = la
            .points
            .iter()
            .map(|p| ib.distance(*p))
            .fold(0.0, f64::max);
        assert!(
            d1.max(d2) <= j.operation.tolerance,
            "{}: paths differ by {}",
            la.label,
            d1.max(d2)
        );
    }
}

fn signed_area(p: &[Vec2]) -> f64 {
    p.windows(2).map(|w| w[0].cross(w[1])).sum::<f64>() / 2.0
}

#[test]
fn climb_runs_outlines_clockwise_and_counters_counter_clockwise() {
    let mut j = job("A", 50.0);
    let climb = plan(&j);
    j.operation.direction = Direction::Conventional;
    let conv = plan(&j);
    for (c, v) in climb.loops.iter().zip(&conv.loops) {
        let (ac, av) = (signed_area(&c.points), signed_area(&v.points));
        if c.label.starts_with("outside") {
            assert!(ac < 0.0 && av > 0.0, "{}: {ac} {av}", c.label);
        } else {
            assert!(ac > 0.0 && av < 0.0, "{}: {ac} {av}", c.label);
        }
        assert!((ac.abs() - av.abs()).abs() < 1e-3 * ac.abs());
    }
    assert_eq!(climb.loops.len(), 2, "outside and the counter of A");
}

#[test]
fn counter_too_small_for_the_tool_is_a_warning_not_a_gouge() {
    // At 10 mm cap height the A's triangle has an inscribed radius under 1.6 mm.
    let out = pipeline::run(&job("A", 10.0), &mut |_| {}).unwrap();
    assert!(
        out.warnings
            .iter()
            .any(|w| w.contains("counter 1 of A (1)") && w.contains("too small")),
        "{:?}",
        out.warnings
    );
    assert_eq!(out.toolpath.sections.len(), 1);
    assert!(out.min_clearance >= -0.01);
}

#[test]
fn gouge_check_finds_a_gouge() {
    let shape = build_shape(&job("I", 50.0).shape).unwrap();
    let polys: Vec<Vec<Vec2>> = shape.contours().map(|c| c.flatten(1e-3)).collect();
    let part = DistanceIndex::new(&polys);
    // A cut straight through the letter's stem at half depth.
    let tp = Toolpath {
        start: Vec3::new(0.0, 0.0, 5.0),
        sections: vec![Section {
            label: "bad".into(),
            z: -1.0,
            moves: vec![
                Move::Rapid {
                    to: Vec3::new(-5.0, 25.0, 5.0),
                },
                Move::Linear {
                    to: Vec3::new(-5.0, 25.0, -1.0),
                    feed: 100.0,
                },
                Move::Linear {
                    to: Vec3::new(30.0, 25.0, -1.0),
                    feed: 100.0,
                },
            ],
        }],
    };
    let rep = gouge::check(&tp, &part, 1.5875, 0.0);
    assert!(!rep.passes(0.01));
    assert!(
        (rep.min_clearance + 1.5875).abs() < 1e-9,
        "crossing the part: clearance −r, got {}",
        rep.min_clearance
    );
    // The same cut above the stock is air and is not checked.
    let mut air = tp.clone();
    for m in &mut air.sections[0].moves {
        if let Move::Linear { to, .. } = m {
            to.z = 1.0;
        }
    }
    assert!(gouge::check(&air, &part, 1.5875, 0.0).passes(0.01));
    // A rapid through the stem below the top is a gouge too.
    let mut rapid = tp.clone();
    rapid.sections[0].moves[2] = Move::Rapid {
        to: Vec3::new(30.0, 25.0, -1.0),
    };
    let rep = gouge::check(&rapid, &part, 1.5875, 0.0);
    assert!(
        (rep.min_clearance + 1.5875).abs() < 1e-9,
        "a rapid crossing the part: clearance −r, got {}",
        rep.min_clearance
    );
}

#[test]
fn same_job_same_path_on_any_thread_count() {
    let j = job("MFS", 50.0);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| pipeline::run(&j, &mut |_| {}).unwrap().toolpath)
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
}
