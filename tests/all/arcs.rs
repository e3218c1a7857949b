//! Arc fitting against the traced path, on every job in `jobs/`: the deviation
//! measured by sampling both ways, the radius bound, lines only when asked, the
//! arcs GRBL reads back from the written G-code, and byte-identical output.

use cavalier_contours::polyline::{PlineSource, PlineSourceMut, Polyline};
use pfcam::gcode::write_gcode;
use pfcam::geometry::{build_shape, DistanceIndex, Vec2};
use pfcam::job::Job;
use pfcam::pipeline;
use pfcam::toolpath::arcfit::{fit_toolpath, legalize, ArcFitParams, MIN_ARC_CHORD};
use pfcam::toolpath::{gouge, profile};
use pfcam::toolpath::{Move, Section, Toolpath, Vec3};
use std::f64::consts::TAU;

use crate::common::{sample_pline, seg_dist, shipped_jobs};
use crate::doc_figures;

/// The profile jobs in `jobs/`. (Boss and cavity jobs are fitted too, but the
/// traced path these tests compare with is the profile planner's; their arcs are
/// checked by the gouge check of every level in tests/all/levels.rs and by
/// `pfcam check` in tests/all/check.rs.)
fn jobs() -> Vec<Job> {
    let jobs: Vec<Job> = shipped_jobs()
        .into_iter()
        .filter(|j| j.operation.kind == pfcam::job::OperationKind::Profile)
        .collect();
    assert!(jobs.len() >= 4, "the profile jobs");
    jobs
}

/// The linked (traced, lines only) tool path of a job, and the same fitted.
fn traced_and_fitted(job: &Job) -> (Toolpath, Toolpath) {
    let plan = pipeline::plan(job, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    let traced = profile::link(&plan.loops, &plan.params);
    let fitted = fit_toolpath(&traced, &ArcFitParams::for_job(job));
    (traced, fitted)
}

/// An arc from `a` to `b` about `c`: its sweep (radians) and radius.
fn sweep_radius(a: Vec2, b: Vec2, c: Vec2, ccw: bool) -> (f64, f64) {
    let s = if ccw { 1.0 } else { -1.0 };
    let (u, v) = (a - c, b - c);
    let mut sw = (s * u.cross(v)).atan2(u.dot(v)).rem_euclid(TAU);
    if sw == 0.0 {
        sw = TAU;
    }
    (sw, u.norm())
}

fn arc_point(a: Vec2, c: Vec2, ccw: bool, angle: f64) -> Vec2 {
    let s = if ccw { 1.0 } else { -1.0 };
    let (sn, cs) = (s * angle).sin_cos();
    let u = a - c;
    c + Vec2::new(u.x * cs - u.y * sn, u.x * sn + u.y * cs)
}

/// Distance from `p` to the arc (not the whole circle).
fn arc_dist(p: Vec2, a: Vec2, b: Vec2, c: Vec2, ccw: bool) -> f64 {
    let (sw, r) = sweep_radius(a, b, c, ccw);
    let (t, _) = sweep_radius(a, p, c, ccw);
    if t <= sw || t == TAU {
        ((p - c).norm() - r).abs()
    } else {
        p.dist(a).min(p.dist(b))
    }
}

/// Largest distance between every fitted move (arc, or line merging several
/// traced segments) and the stretch of the traced polyline it replaces, sampled
/// both ways: points every 0.002 mm along the move to the polyline, and points
/// along the polyline (vertices and 16 per segment) to the move. Also returns
/// the number of arcs and the largest radius.
fn deviation(traced: &Toolpath, fitted: &Toolpath) -> (f64, usize, f64) {
    let tr: Vec<&Move> = traced.moves().collect();
    let mut worst: f64 = 0.0;
    let mut arcs = 0;
    let mut max_r: f64 = 0.0;
    let mut k = 0; // index in `tr` of the move ending where the fitted path is
    let mut at = fitted.start;
    for m in fitted.moves() {
        let to = m.to();
        // The traced move that ends at this move's end.
        let mut end = k;
        while tr[end].to() != to {
            end += 1;
            assert!(end < tr.len(), "fitted path left the traced one at {to:?}");
        }
        let (a, b) = (Vec2::new(at.x, at.y), Vec2::new(to.x, to.y));
        let mut poly = vec![a];
        for t in &tr[k..=end] {
            poly.push(Vec2::new(t.to().x, t.to().y));
        }
        // Samples along the fitted move, and its distance function.
        let (samples, dist): (Vec<Vec2>, Box<dyn Fn(Vec2) -> f64>) = match *m {
            Move::Arc { cx, cy, ccw, .. } => {
                arcs += 1;
                assert_eq!(at.z, to.z, "arcs stay level");
                assert!(tr[k..=end].iter().all(|t| t.to().z == at.z));
                let c = Vec2::new(cx, cy);
                let (sw, r) = sweep_radius(a, b, c, ccw);
                max_r = max_r.max(r);
                assert!((b.dist(c) - r).abs() < 1e-9, "end off the circle");
                let n = ((sw * r / 0.002).ceil() as usize).max(64);
                let s = (0..=n)
                    .map(|i| arc_point(a, c, ccw, sw * i as f64 / n as f64))
                    .collect();
                (s, Box::new(move |q| arc_dist(q, a, b, c, ccw)))
            }
            _ if end > k => {
                assert!(tr[k..=end].iter().all(|t| t.to().z == at.z));
                let n = ((a.dist(b) / 0.002).ceil() as usize).max(64);
                let s = (0..=n).map(|i| a.lerp(b, i as f64 / n as f64)).collect();
                (s, Box::new(move |q| seg_dist(q, a, b)))
            }
            _ => (Vec::new(), Box::new(|_| 0.0)),
        };
        for q in samples {
            let d = poly
                .windows(2)
                .map(|w| seg_dist(q, w[0], w[1]))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
        for w in poly.windows(2) {
            for i in 0..=16 {
                worst = worst.max(dist(w[0].lerp(w[1], i as f64 / 16.0)));
            }
        }
        k = end + 1;
        at = to;
    }
    assert_eq!(
        k,
        tr.len(),
        "the fitted path ends where the traced one does"
    );
    (worst, arcs, max_r)
}

#[test]
fn arcs_stay_within_half_the_tolerance_of_the_traced_path() {
    for job in jobs() {
        let (traced, fitted) = traced_and_fitted(&job);
        let (dev, arcs, max_r) = deviation(&traced, &fitted);
        let tol = job.operation.tolerance;
        assert!(dev <= tol / 2.0 + 1e-9, "{}: deviation {dev}", job.name);
        assert!(arcs > 0, "{}: no arcs", job.name);
        assert!(max_r <= job.output.max_arc_radius, "{}", job.name);
        // Fewer moves than the polyline.
        assert!(fitted.moves().count() < traced.moves().count() / 2);
    }
}

#[test]
fn merged_lines_stay_within_half_the_tolerance_with_arcs_off() {
    for mut job in jobs() {
        job.output.arcs = false;
        let (traced, fitted) = traced_and_fitted(&job);
        let (dev, arcs, _) = deviation(&traced, &fitted);
        assert_eq!(arcs, 0);
        assert!(
            dev <= job.operation.tolerance / 2.0 + 1e-9,
            "{}: {dev}",
            job.name
        );
        assert!(fitted.moves().count() < traced.moves().count());
    }
}

#[test]
fn radius_bound_is_respected() {
    for mut job in jobs().into_iter().take(2) {
        job.output.max_arc_radius = 5.0;
        let (traced, fitted) = traced_and_fitted(&job);
        let (dev, _, max_r) = deviation(&traced, &fitted);
        assert!(max_r <= 5.0, "{}: radius {max_r}", job.name);
        assert!(dev <= job.operation.tolerance / 2.0 + 1e-9);
    }
}

/// The `X`/`Y`/`I`/`J` words of every arc line, with the written start.
fn written_arcs(g: &str) -> Vec<(String, Vec2, Vec2, Vec2)> {
    let (mut x, mut y) = (0.0, 0.0);
    let mut out = Vec::new();
    for line in g.lines().filter(|l| !l.starts_with('(')) {
        let word = |c: char| {
            line.split(' ')
                .find_map(|w| w.strip_prefix(c).and_then(|n| n.parse::<f64>().ok()))
        };
        let (nx, ny) = (word('X').unwrap_or(x), word('Y').unwrap_or(y));
        if line.starts_with("G2 ") || line.starts_with("G3 ") {
            let (i, j) = (word('I').expect("I"), word('J').expect("J"));
            out.push((
                line.to_string(),
                Vec2::new(x, y),
                Vec2::new(nx, ny),
                Vec2::new(x + i, y + j),
            ));
        }
        (x, y) = (nx, ny);
    }
    out
}

#[test]
fn grbl_reads_back_every_arc_on_its_circle() {
    let mut radii_differ = 0.0f64;
    for job in jobs() {
        let out = pipeline::run(&job, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
        let g = write_gcode(&out.toolpath, &job).unwrap_or_else(|e| panic!("{e}"));
        let arcs = written_arcs(&g);
        assert!(!arcs.is_empty(), "{}", job.name);
        // The fitted arcs reach the writer unchanged, one line each.
        let limits = pfcam::gcode::writer::arc_limits(&job);
        assert_eq!(legalize(&out.toolpath, &limits), out.toolpath);
        let fitted: Vec<(Vec3, Vec2)> = out
            .toolpath
            .moves()
            .filter_map(|m| match *m {
                Move::Arc { to, cx, cy, .. } => Some((to, Vec2::new(cx, cy))),
                _ => None,
            })
            .collect();
        assert_eq!(fitted.len(), arcs.len(), "{}", job.name);
        for ((to, centre), (line, _, e, c)) in fitted.iter().zip(&arcs) {
            assert!(c.dist(*centre) <= 0.0036, "{line}: centre {centre:?}");
            assert!(e.dist(Vec2::new(to.x, to.y)) <= 0.00071, "{line}");
        }
        for (line, s, e, c) in &arcs {
            let (r1, r2) = (s.dist(*c), e.dist(*c));
            radii_differ = radii_differ.max((r1 - r2).abs());
            assert!(
                (r1 - r2).abs() < 0.002,
                "{}: {line}: radii {r1} {r2}",
                job.name
            );
            assert!(r1 <= job.output.max_arc_radius + 0.01, "{line}");
            assert!(s.dist(*e) >= MIN_ARC_CHORD - 0.002, "{line}");
        }
    }
    // docs/gcode.md quotes the largest difference of the written radii.
    let doc = doc_figures::read("docs/gcode.md");
    let stated =
        doc_figures::number_after(&doc, "docs/gcode.md", "the written radii differ by at most");
    doc_figures::assert_figure("docs/gcode.md, written radii", &stated, radii_differ);
}
#[test]
fn arcs_off_gives_lines_only() {
    let mut job = jobs().remove(0);
    job.output.arcs = false;
    let out = pipeline::run(&job, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    assert!(out.toolpath.moves().all(|m| !matches!(m, Move::Arc { .. })));
    let g = write_gcode(&out.toolpath, &job).unwrap_or_else(|e| panic!("{e}"));
    assert!(g
        .lines()
        .all(|l| !l.starts_with("G2") || l.starts_with("G21")));
    assert!(g.lines().all(|l| !l.starts_with("G3")));
    // An arc-bearing path handed to the writer with arcs off is written as lines.
    job.output.arcs = true;
    let with_arcs = pipeline::run(&job, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    job.output.arcs = false;
    let g = write_gcode(&with_arcs.toolpath, &job).unwrap_or_else(|e| panic!("{e}"));
    assert!(g
        .lines()
        .all(|l| !l.starts_with("G3") && !l.starts_with("G2 ")));
}

#[test]
fn a_circle_ish_traced_path_becomes_few_arcs() {
    // A 12 mm circle traced as 400 chords with noise of ±0.001 mm, two passes.
    let mut moves = Vec::new();
    let pt = |k: usize| {
        let t = TAU * k as f64 / 400.0;
        let noise = 0.001 * ((k * 7919) % 13) as f64 / 6.0 - 0.001;
        Vec2::new(
            20.0 + (6.0 + noise) * t.cos(),
            10.0 + (6.0 + noise) * t.sin(),
        )
    };
    let p0 = pt(0);
    moves.push(Move::Rapid {
        to: Vec3::new(p0.x, p0.y, 1.0),
    });
    for z in [-1.0, -2.0] {
        moves.push(Move::Linear {
            to: Vec3::new(p0.x, p0.y, z),
            feed: 100.0,
        });
        for k in 1..=400 {
            let p = pt(k % 400);
            moves.push(Move::Linear {
                to: Vec3::new(p.x, p.y, z),
                feed: 500.0,
            });
        }
    }
    let traced = Toolpath {
        start: Vec3::new(0.0, 0.0, 5.0),
        sections: vec![Section {
            label: "circle".into(),
            z: -2.0,
            moves,
        }],
    };
    let fitted = fit_toolpath(&traced, &ArcFitParams::new(0.01, 1000.0));
    let arcs = fitted
        .moves()
        .filter(|m| matches!(m, Move::Arc { .. }))
        .count();
    let lines = fitted
        .moves()
        .filter(|m| matches!(m, Move::Linear { .. }))
        .count();
    assert!((4..=8).contains(&arcs), "{arcs} arcs");
    assert_eq!(lines, 2, "only the plunges stay lines");
    let (dev, _, _) = deviation(&traced, &fitted);
    assert!(dev <= 0.005 + 1e-9, "{dev}");
}

#[test]
fn same_gcode_on_every_run_and_thread_count() {
    let job = jobs().pop().expect("a job");
    let gcode = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| {
            let out = pipeline::run(&job, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
            write_gcode(&out.toolpath, &job).unwrap_or_else(|e| panic!("{e}"))
        })
    };
    let one = gcode(1);
    assert_eq!(one, gcode(1));
    assert_eq!(one, gcode(2));
    assert_eq!(one, gcode(4));
}

/// Points every 0.002 mm along the first level pass of every section.
fn sample_passes(tp: &Toolpath) -> Vec<Vec<Vec2>> {
    let mut out = Vec::new();
    let mut at = tp.start;
    for s in &tp.sections {
        let mut pts: Vec<Vec2> = Vec::new();
        let mut z = None;
        for m in &s.moves {
            let to = m.to();
            let level = at.z == to.z && !matches!(m, Move::Rapid { .. });
            if level && z.is_none_or(|z| z == to.z) {
                z = Some(to.z);
                let (a, b) = (Vec2::new(at.x, at.y), Vec2::new(to.x, to.y));
                match *m {
                    Move::Arc { cx, cy, ccw, .. } => {
                        let c = Vec2::new(cx, cy);
                        let (sw, r) = sweep_radius(a, b, c, ccw);
                        let n = ((sw * r / 0.002).ceil() as usize).max(1);
                        pts.extend((0..n).map(|i| arc_point(a, c, ccw, sw * i as f64 / n as f64)));
                    }
                    _ => {
                        let n = ((a.dist(b) / 0.002).ceil() as usize).max(1);
                        pts.extend((0..n).map(|i| a.lerp(b, i as f64 / n as f64)));
                    }
                }
            }
            at = to;
        }
        out.push(pts);
    }
    out
}

/// Symmetric Hausdorff distance between every sampled pass and the nearest exact
/// (cavalier) offset of the part's contours by the tool radius.
fn hausdorff_to_exact(job: &Job, tp: &Toolpath) -> f64 {
    let shape = build_shape(&job.shape).unwrap_or_else(|e| panic!("{e}"));
    let r = job.tool.diameter / 2.0;
    let mut oracles = Vec::new();
    for c in shape.contours() {
        let mut pl: Polyline = Polyline::new_closed();
        for p in c.flatten(3e-4) {
            pl.add(p.x, p.y, 0.0);
        }
        for o in pl.parallel_offset(-r) {
            oracles.push(sample_pline(&o, 0.002));
        }
    }
    let mut worst: f64 = 0.0;
    for pass in sample_passes(tp) {
        let oracle = oracles
            .iter()
            .min_by(|a, b| {
                let d = |o: &Vec<Vec2>| {
                    o.iter()
                        .map(|q| q.dist(pass[0]))
                        .fold(f64::INFINITY, f64::min)
                };
                d(a).total_cmp(&d(b))
            })
            .expect("an oracle");
        let oi = DistanceIndex::new(std::slice::from_ref(oracle));
        let pi = DistanceIndex::new(std::slice::from_ref(&pass));
        for q in &pass {
            worst = worst.max(oi.distance(*q));
        }
        for q in oracle {
            worst = worst.max(pi.distance(*q));
        }
    }
    worst
}

/// The whole budget: traced (tol/2) plus fitted (tol/2) stays within the job
/// tolerance of the exact offset, arcs on and off. Prints the table of
/// `docs/gcode.md` with
/// `cargo test --release --test all -- --nocapture arcs::fitted_path_is_within_tolerance_of_the_exact_offset`.
#[test]
fn fitted_path_is_within_tolerance_of_the_exact_offset() {
    let doc = doc_figures::read("docs/gcode.md");
    let table = doc_figures::after(
        &doc,
        "docs/gcode.md",
        "The whole budget, measured against the exact offset",
    );
    println!("| job | traced | `arcs = false` | `arcs = true` |");
    println!("|---|---|---|---|");
    for mut job in jobs() {
        let cells = doc_figures::table_row(table, "docs/gcode.md", &job.name);
        let what = format!("docs/gcode.md's exact-offset row of {}", job.name);
        let plan = pipeline::plan(&job, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
        let traced = profile::link(&plan.loops, &plan.params);
        let h = hausdorff_to_exact(&job, &traced);
        doc_figures::assert_figure(&what, cells[1], h);
        let mut row = vec![job.name.clone(), format!("{h:.4}")];
        for (arcs, cell) in [(false, cells[2]), (true, cells[3])] {
            job.output.arcs = arcs;
            let fitted = fit_toolpath(&traced, &ArcFitParams::for_job(&job));
            let h = hausdorff_to_exact(&job, &fitted);
            assert!(h <= job.operation.tolerance, "{}: {h}", job.name);
            doc_figures::assert_figure(&what, cell, h);
            row.push(format!("{h:.4}"));
        }
        println!("| {} |", row.join(" | "));
    }
}

/// docs/gcode.md's table of the profile jobs (lines and bytes traced, with
/// `arcs = false` and with `arcs = true`, arcs, deviation, clearance) and the
/// ratios and clearance loss it draws from it are what the jobs give now:
/// `cargo test --release --test all -- --nocapture arcs::measure_every_job` prints
/// the table.
#[test]
fn measure_every_job() {
    let doc = doc_figures::read("docs/gcode.md");
    println!("| job | traced: lines | bytes | `arcs = false`: lines | bytes | `arcs = true`: lines | bytes | arcs | max deviation, off / on (mm) | min clearance, traced / off / on (mm) |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let (mut line_ratios, mut byte_ratios, mut clearance_loss) = (Vec::new(), Vec::new(), 0.0f64);
    for mut job in jobs() {
        let plan = pipeline::plan(&job, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
        let part = DistanceIndex::new(&plan.polys);
        let traced = profile::link(&plan.loops, &plan.params);
        let clearance = |tp: &Toolpath| {
            gouge::check(tp, &part, plan.params.radius, plan.params.top).min_clearance
        };
        job.output.arcs = false;
        let g = write_gcode(&traced, &job).unwrap_or_else(|e| panic!("{e}"));
        let mut counts = vec![g.lines().count(), g.len()];
        let (mut devs, mut clear) = (Vec::new(), vec![clearance(&traced)]);
        let mut n_arcs = 0;
        for arcs in [false, true] {
            job.output.arcs = arcs;
            let fitted = fit_toolpath(&traced, &ArcFitParams::for_job(&job));
            let g = write_gcode(&fitted, &job).unwrap_or_else(|e| panic!("{e}"));
            counts.extend([g.lines().count(), g.len()]);
            let (dev, a, _) = deviation(&traced, &fitted);
            devs.push(dev);
            clear.push(clearance(&fitted));
            n_arcs = a;
        }
        counts.push(n_arcs);
        line_ratios.push(counts[0] as f64 / counts[4] as f64);
        byte_ratios.push(counts[1] as f64 / counts[5] as f64);
        clearance_loss = clearance_loss.max(clear[0] - clear[2]);
        let f4 = |v: &[f64]| {
            v.iter()
                .map(|x| format!("{x:.4}"))
                .collect::<Vec<_>>()
                .join(" / ")
        };
        let row: Vec<String> = std::iter::once(job.name.clone())
            .chain(counts.iter().map(usize::to_string))
            .chain([f4(&devs), f4(&clear)])
            .collect();
        println!("| {} |", row.join(" | "));

        let cells = doc_figures::table_row(&doc, "docs/gcode.md", &job.name);
        assert_eq!(cells.len(), 10, "docs/gcode.md's {} row", job.name);
        let stated: Vec<usize> = cells[1..8].iter().map(|c| c.parse().expect(c)).collect();
        assert_eq!(
            stated, counts,
            "docs/gcode.md's {} row (lines, bytes, arcs) against the job",
            job.name
        );
        for (cell, values) in [(cells[8], &devs), (cells[9], &clear)] {
            let figures: Vec<&str> = cell.split(" / ").collect();
            assert_eq!(figures.len(), values.len(), "{cell}");
            for (f, v) in figures.iter().zip(values.iter()) {
                doc_figures::assert_figure(&format!("docs/gcode.md, {}", job.name), f, *v);
            }
        }
    }
    let range = |v: &[f64]| {
        (
            v.iter().copied().fold(f64::INFINITY, f64::min),
            v.iter().copied().fold(0.0, f64::max),
        )
    };
    let stated =
        doc_figures::numbers_after(&doc, "docs/gcode.md", "With arcs the profile files have", 4);
    let ((l0, l1), (b0, b1)) = (range(&line_ratios), range(&byte_ratios));
    for (figure, value) in stated.iter().zip([l0, l1, b0, b1]) {
        doc_figures::assert_figure(
            "docs/gcode.md, fewer lines and bytes with arcs",
            figure,
            value,
        );
    }
    let stated = doc_figures::number_after(&doc, "docs/gcode.md", "clearance loses up to");
    doc_figures::assert_figure(
        "docs/gcode.md, clearance lost to arcs",
        &stated,
        clearance_loss,
    );
}
