//! `pfcam simulate`: hand-made programs caught at the right line, the height
//! map checked against an independent distance oracle, I/J against R arcs,
//! invariance under translation, ball and bull nose tools, several programs
//! on one stock, and every shipped sample run through it.

use pfcam::gcode::check::{check_gcode, CheckOptions};
use pfcam::simulate::{
    simulate, simulate_programs, JobFacts, Kind, PartModel, SimError, SimOptions, Simulation,
    StockBox, ToolShape,
};
use std::path::Path;

use crate::common::{self, files, root, scratch, seg_dist, test_data, text};
use crate::doc_figures;
use pfcam::geometry::Vec2;

fn data(name: &str) -> String {
    let p = test_data("simulate").join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn stock30() -> Option<StockBox> {
    Some(StockBox {
        lo: [0.0, 0.0],
        hi: [30.0, 30.0],
        top: 0.0,
    })
}

fn opts(d: f64) -> SimOptions {
    SimOptions {
        tool_diameter: Some(d),
        stock: stock30(),
        ..SimOptions::default()
    }
}

fn run(text: &str, o: &SimOptions) -> Simulation {
    simulate(text, o).expect("simulates")
}

/// Both stocks have the same cells at the same heights (to 1e-9 mm).
fn assert_same_stock(a: &Simulation, b: &Simulation) {
    assert_eq!(a.map.h.len(), b.map.h.len());
    let differ = a
        .map
        .h
        .iter()
        .zip(&b.map.h)
        .filter(|(x, y)| (*x - *y).abs() > 1e-9)
        .count();
    assert_eq!(differ, 0, "cells at different heights");
}

/// (line, kind) of every finding.
fn found(s: &Simulation) -> Vec<(usize, Kind)> {
    s.report.findings.iter().map(|f| (f.line, f.kind)).collect()
}

#[test]
fn a_rapid_into_stock_is_caught_at_its_line() {
    let s = run(&data("rapid-into-stock.nc"), &opts(3.0));
    assert_eq!(found(&s), vec![(5, Kind::RapidIntoMaterial)]);
    let f = &s.report.findings[0];
    assert!((f.depth - 1.0).abs() < 1e-9, "{f:?}");
    assert!((f.x - 10.0).hypot(f.y - 10.0) <= 1.5, "{f:?}");
    assert_eq!(s.report.rapids_into_material, 1);
    assert_eq!(s.report.worst_rapid.line, 5);
}

#[test]
fn a_straight_plunge_is_caught_and_a_ramp_is_not() {
    let s = run(&data("straight-plunge.nc"), &opts(3.0));
    assert_eq!(found(&s), vec![(6, Kind::StraightPlunge)]);
    assert!((s.report.findings[0].depth - 1.0).abs() < 1e-9);
    assert_eq!(s.report.steepest_entry_deg.value, 90.0);
    // The same depth entered along a 10 mm ramp (8.5 degrees) is clean.
    let ramp = "G21 G90\nG0 Z5\nG0 X10 Y10\nG0 Z0.5\nG1 X20 Z-1 F100\nG1 X10\nM2\n";
    let s = run(ramp, &opts(3.0));
    assert!(s.report.is_clean(), "{:?}", s.report.findings);
    // The descent is known to the program's rounding, 1 µm.
    let want = ((1.5 - pfcam::simulate::run::Z_ROUNDING) / 10.0)
        .atan()
        .to_degrees();
    assert!((s.report.steepest_entry_deg.value - want).abs() < 1e-9);
    assert_eq!(s.report.steepest_entry_deg.line, 5);
    // A 3-degree ramp with a 9 µm step that rounding made 1 µm deep reads as
    // the ramp, not as 6 degrees.
    let crumb = "G21 G90\nG0 Z5\nG0 X10 Y10\nG0 Z0.5\nG1 X20 Z-0.024 F100\nG1 X20.009 Z-0.025\nG1 X30 Z-0.549\nG1 X10\nM2\n";
    let s = run(crumb, &opts(3.0));
    assert!(s.report.is_clean(), "{:?}", s.report.findings);
    assert!(
        s.report.steepest_entry_deg.value < 3.01,
        "{}",
        s.report.steepest_entry_deg.value
    );
}

#[test]
fn a_slot_deeper_than_the_stepdown_is_caught() {
    let o = SimOptions {
        stepdown: Some(1.0),
        ..opts(3.0)
    };
    let s = run(&data("deep-slot.nc"), &o);
    assert_eq!(found(&s), vec![(8, Kind::SlotDeeperThanStepdown)]);
    assert!((s.report.findings[0].depth - 1.5).abs() < 1e-9);
    assert!(s.report.max_radial.value > 0.95);
    assert!((s.report.max_axial.value - 1.5).abs() < 1e-9);
    assert_eq!(s.report.max_axial.line, 8);
    // Without a stepdown the slot is not judged.
    assert!(run(&data("deep-slot.nc"), &opts(3.0)).report.is_clean());
}

/// The square 10..20 × 10..20 standing 1 mm above a floor at z = −1.
fn square_part() -> PartModel {
    let quad = |x0: f64, y0: f64, x1: f64, y1: f64, z: f64| {
        [
            [[x0, y0, z], [x1, y0, z], [x1, y1, z]],
            [[x0, y0, z], [x1, y1, z], [x0, y1, z]],
        ]
    };
    let mut triangles = quad(0.0, 0.0, 30.0, 30.0, -1.0).to_vec();
    triangles.extend(quad(10.0, 10.0, 20.0, 20.0, 0.0));
    PartModel {
        name: "square".into(),
        triangles,
        outlines: Vec::new(),
        outline_z: 0.0,
        wall_points: Vec::new(),
    }
}

fn square_job() -> JobFacts {
    JobFacts {
        tool_diameter: 3.0,
        stepdown: 1.0,
        stock: stock30(),
        part: Some(square_part()),
        tolerance: 0.01,
        scallop: 0.1,
        stepover: 1.0,
    }
}

#[test]
fn an_arc_that_gouges_is_caught_at_its_line() {
    let o = SimOptions {
        job: Some(square_job()),
        ..SimOptions::default()
    };
    let s = run(&data("arc-gouge.nc"), &o);
    assert_eq!(found(&s), vec![(10, Kind::Gouge)]);
    let p = s.report.part.as_ref().expect("compared");
    // The tool's edge passes 6.5 mm from the centre, inside the corners
    // (7.07 mm): it cuts the corners down to the floor, 1 mm below the part.
    assert!((p.max_gouge.value - 1.0).abs() < 1e-9, "{p:?}");
    assert_eq!(p.max_gouge.line, 10);
    // The first circle alone leaves the square whole: a corner cell nearest
    // the circle is 7.5 − 7.07 mm away from the tool.
    let first: String = data("arc-gouge.nc")
        .lines()
        .filter(|l| !l.starts_with("G1 X23") && !l.starts_with("G2 X23"))
        .map(|l| format!("{l}\n"))
        .collect();
    let s = run(&first, &o);
    assert!(s.report.is_clean(), "{:?}", s.report.findings);
    let p = s.report.part.as_ref().expect("compared");
    assert!(p.max_gouge.value < 1e-9, "{p:?}");
    assert!(
        p.max_left.value > 0.9,
        "the floor between circle and square is left"
    );
}

/// The same square as a profile's part: an outline (with a counter, the
/// 14..16 square hole, which the cut never reaches) standing at z 0.
#[test]
fn an_outline_part_catches_the_same_gouge() {
    let square = |a: f64, b: f64| vec![[a, a], [b, a], [b, b], [a, b]];
    let mut job = square_job();
    job.part = Some(PartModel {
        name: "outline".into(),
        triangles: Vec::new(),
        outlines: vec![square(10.0, 20.0), square(14.0, 16.0)],
        outline_z: 0.0,
        wall_points: Vec::new(),
    });
    let o = SimOptions {
        job: Some(job),
        ..SimOptions::default()
    };
    let s = run(&data("arc-gouge.nc"), &o);
    assert_eq!(found(&s), vec![(10, Kind::Gouge)]);
    let p = s.report.part.as_ref().expect("compared");
    assert!((p.max_gouge.value - 1.0).abs() < 1e-9, "{p:?}");
    // Cells inside the outline less the hole: 100 − 4 mm² at 0.01 mm² each.
    assert_eq!(p.cells, 9600);
}

/// A wall at 60°: the plane z = −√3·(x − 10) over 10..30 × 0..30. A flat end
/// mill of 3 mm at X15 cuts the cells out to x = 13.55 (the leftmost centre
/// within 1.5 mm); `below` mm under the part there is `below`·cos 60° along
/// the wall's normal, which is what a gouge is measured by.
fn wall_gouge(below: f64) -> (f64, Vec<(usize, Kind)>) {
    let k = 3f64.sqrt();
    let z = |x: f64| -k * (x - 10.0);
    let (a, b) = ([10.0, 0.0, z(10.0)], [30.0, 0.0, z(30.0)]);
    let (c, d) = ([30.0, 30.0, z(30.0)], [10.0, 30.0, z(10.0)]);
    let mut job = square_job();
    job.part = Some(PartModel {
        name: "wall".into(),
        triangles: vec![[a, b, c], [a, c, d]],
        outlines: Vec::new(),
        outline_z: 0.0,
        wall_points: Vec::new(),
    });
    let o = SimOptions {
        job: Some(job),
        ..SimOptions::default()
    };
    let zt = z(13.55) - below;
    let prog = format!("G21 G90\nG0 Z5\nG0 X15 Y5\nG1 Z{zt:.6} F100\nG1 Y25\nM2\n");
    let s = run(&prog, &o);
    let gouges = found(&s)
        .into_iter()
        .filter(|f| f.1 == Kind::Gouge)
        .collect();
    (s.report.part.expect("compared").max_gouge.value, gouges)
}

#[test]
fn a_gouge_into_a_wall_is_measured_along_its_normal() {
    // 0.016 mm below vertically is 0.008 mm into the wall: within 0.01.
    let (g, found) = wall_gouge(0.016);
    assert!((g - 0.008).abs() < 1e-5, "{g}");
    assert!(found.is_empty(), "{found:?}");
    // 0.03 mm below vertically is 0.015 mm into it: a gouge, at the lines
    // that cut there (the plunge and the pass).
    let (g, found) = wall_gouge(0.03);
    assert!((g - 0.015).abs() < 1e-5, "{g}");
    assert_eq!(found, vec![(4, Kind::Gouge), (5, Kind::Gouge)]);
}

/// A square loop of tool centres 5..15 at z −1, entered by a plunge at (5, 5),
/// shifted by (ox, oy).
fn square_loop(ox: f64, oy: f64) -> String {
    let p = |x: f64, y: f64| format!("X{} Y{}", x + ox, y + oy);
    format!(
        "G21 G90\nG0 Z5\nG0 {}\nG1 Z-1 F100\nG1 {}\nG1 {}\nG1 {}\nG1 {}\nM2\n",
        p(5.0, 5.0),
        p(15.0, 5.0),
        p(15.0, 15.0),
        p(5.0, 15.0),
        p(5.0, 5.0)
    )
}

#[test]
fn a_square_loop_gives_exactly_the_expected_heights() {
    let s = run(
        &square_loop(0.0, 0.0),
        &SimOptions {
            stock: Some(StockBox {
                lo: [0.0, 0.0],
                hi: [20.0, 20.0],
                top: 0.0,
            }),
            ..opts(2.0)
        },
    );
    let g = s.map.grid;
    assert_eq!((g.nx, g.ny), (200, 200));
    let corners = [
        Vec2::new(5.0, 5.0),
        Vec2::new(15.0, 5.0),
        Vec2::new(15.0, 15.0),
        Vec2::new(5.0, 15.0),
        Vec2::new(5.0, 5.0),
    ];
    let (mut cut, mut uncut) = (0, 0);
    for j in 0..g.ny {
        for i in 0..g.nx {
            let c = Vec2::new(g.cx(i), g.cy(j));
            let d = corners
                .windows(2)
                .map(|w| seg_dist(c, w[0], w[1]))
                .fold(f64::INFINITY, f64::min);
            let want = if d <= 1.0 { -1.0 } else { 0.0 };
            assert_eq!(
                s.map.at(i, j),
                want,
                "cell ({i}, {j}) at {c:?}, {d} from the path"
            );
            if want < 0.0 {
                cut += 1;
            } else {
                uncut += 1;
            }
        }
    }
    // The 12 mm square with corners rounded to r = 1, less the 8 mm hole.
    let area = cut as f64 * 0.01;
    let exact = 144.0 - (4.0 - std::f64::consts::PI) - 64.0;
    assert!((area - exact).abs() < 0.3, "{area} vs {exact}");
    assert!(uncut > 0);
    // The plunge at the start is the only finding.
    assert_eq!(found(&s), vec![(4, Kind::StraightPlunge)]);
}

/// The same circle cut as two G2 halves with I/J and with R, and the same
/// ramps: identical stock.
#[test]
fn ij_and_r_arcs_give_the_same_stock() {
    let head = "G21 G90\nG0 Z5\nG0 X24 Y15\nG0 Z0\n";
    let ij =
        format!("{head}G2 X6 Y15 Z-0.5 I-9 J0 F300\nG2 X24 Y15 Z-1 I9 J0\nG3 X15 Y6 I-9 J0\nM2\n");
    let r = format!("{head}G2 X6 Y15 Z-0.5 R9 F300\nG2 X24 Y15 Z-1 R9\nG3 X15 Y6 R-9\nM2\n");
    let a = run(&ij, &opts(3.0));
    let b = run(&r, &opts(3.0));
    assert_same_stock(&a, &b);
    assert!(a.map.min() < -0.99, "the helix reaches z -1");
    assert_eq!(found(&a), found(&b));
    assert_eq!(a.report.max_axial.line, b.report.max_axial.line);
}

/// Shifting the program and the stock by whole cells shifts the stock: the
/// same heights and the same figures.
#[test]
fn translating_the_program_translates_the_stock() {
    let arcs = "G2 X12 Y10 I-3 J0\nG3 X18 Y10 R3\nG1 X10 Y10 Z-1.5\n";
    let base = |ox: f64, oy: f64| {
        let mut t = square_loop(ox, oy).replace("M2\n", "");
        for l in arcs.lines() {
            let mut l = l.to_string();
            for (axis, o) in [('X', ox), ('Y', oy)] {
                if let Some(p) = l.find(axis) {
                    let end = l[p + 1..].find(' ').map_or(l.len(), |e| p + 1 + e);
                    let v: f64 = l[p + 1..end].parse().unwrap();
                    l.replace_range(p + 1..end, &format!("{}", v + o));
                }
            }
            t += &l;
            t.push('\n');
        }
        t
    };
    let (ox, oy) = (37.0, -12.5);
    let at = |ox: f64, oy: f64| SimOptions {
        stock: Some(StockBox {
            lo: [ox, oy],
            hi: [20.0 + ox, 20.0 + oy],
            top: 0.0,
        }),
        ..opts(2.0)
    };
    let a = run(&base(0.0, 0.0), &at(0.0, 0.0));
    let b = run(&base(ox, oy), &at(ox, oy));
    assert_same_stock(&a, &b);
    assert_eq!(found(&a), found(&b));
    let (ra, rb) = (&a.report, &b.report);
    assert!((ra.feed_length - rb.feed_length).abs() < 1e-9);
    assert!((ra.air_length - rb.air_length).abs() < 1e-9);
    assert!((ra.max_radial.value - rb.max_radial.value).abs() < 1e-9);
    assert_eq!(ra.max_axial.line, rb.max_axial.line);
}

/// A sample's report; a finishing program (`X.finish.nc`) runs on what its
/// roughing program (`X.rough.nc`) left, as on the machine.
fn sample_report(p: &Path, opts: &SimOptions) -> pfcam::simulate::Report {
    let text = std::fs::read_to_string(p).unwrap();
    let name = p.file_name().unwrap().to_string_lossy().into_owned();
    match name.strip_suffix(".finish.nc") {
        Some(stem) => {
            let rough = std::fs::read_to_string(p.with_file_name(format!("{stem}.rough.nc")))
                .expect("the roughing program of a finishing sample");
            let seq = simulate_programs(&[("rough", &rough), ("finish", &text)], opts)
                .expect("simulates");
            seq.programs[1].report.clone()
        }
        None => run(&text, opts).report,
    }
}

/// Every sample simulates, its feed length agrees with `pfcam check`'s own
/// measure of the file, and its figures are printed (`--nocapture`).
#[test]
fn every_sample_simulates() {
    let doc = doc_figures::read("docs/simulate.md");
    let mut bench_sample = false;
    for p in files("gcode-samples", "nc") {
        let text = std::fs::read_to_string(&p).unwrap();
        let report = sample_report(&p, &SimOptions::default());
        let r = &report;
        let want = check_gcode(&text, &CheckOptions::default())
            .totals
            .cut_length;
        assert!(
            (r.feed_length - want).abs() <= 1e-6 * want.max(1.0),
            "{}: {} vs {want}",
            p.display(),
            r.feed_length
        );
        assert!(r.moves > 0 && r.stock.cells[0] > 0);
        eprintln!(
            "{}: rapids into material {} (worst {:.3} mm, line {}), straight plunges {}, steepest entry {:.1} deg, axial {:.3} mm, radial {:.0} %, deep slots {}, air {:.1} %",
            p.file_name().unwrap().to_string_lossy(),
            r.rapids_into_material,
            r.worst_rapid.value,
            r.worst_rapid.line,
            r.straight_plunges,
            r.steepest_entry_deg.value,
            r.max_axial.value,
            100.0 * r.max_radial.value,
            r.deep_slots,
            100.0 * r.air_share
        );
        // docs/simulate.md's table of the shipped samples: this sample's row.
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        let cells = doc_figures::table_row(&doc, "docs/simulate.md", &name);
        let what = format!("docs/simulate.md's row of {name}");
        let rapids = doc_figures::numbers_after(cells[1], "docs/simulate.md", "", 3);
        assert_eq!(
            rapids[0].parse().ok(),
            Some(r.rapids_into_material),
            "{what}"
        );
        doc_figures::assert_figure(&what, &rapids[1], r.worst_rapid.value);
        assert_eq!(rapids[2].parse().ok(), Some(r.worst_rapid.line), "{what}");
        assert_eq!(cells[2].parse().ok(), Some(r.straight_plunges), "{what}");
        assert_eq!(cells[6].parse().ok(), Some(r.deep_slots), "{what}");
        for (cell, value) in [
            (cells[3], r.steepest_entry_deg.value),
            (cells[4], r.max_axial.value),
            (cells[5], 100.0 * r.max_radial.value),
            (cells[7], 100.0 * r.air_share),
        ] {
            let figure = doc_figures::first_number(cell).expect(cell);
            doc_figures::assert_figure(&what, &figure, value);
        }
        // The notes under the table name the lines of some of these figures.
        let line_after = |marker: &str| -> usize {
            let n = doc_figures::number_after(&doc, "docs/simulate.md", marker);
            n.parse().expect(marker)
        };
        let notes: &[(&str, usize)] = match name.as_str() {
            "letter-a.nc" => &[("(`letter-a.nc` line", r.max_axial.line)],
            _ => &[],
        };
        for &(marker, line) in notes {
            assert_eq!(line_after(marker), line, "docs/simulate.md: `{marker}`");
        }
        if name == "mfs-mould.rough.nc" {
            // The simulation bench's sample: its lines, feed and cells.
            let stated = doc_figures::numbers_after(
                &doc,
                "docs/simulate.md",
                "`cargo bench --bench pfcam -- \"simulate mfs-mould\"` (",
                5,
            );
            let what = "docs/simulate.md, the simulation bench's sample";
            assert_eq!(
                stated[0].parse().ok(),
                Some(text.lines().count()),
                "{what}: lines"
            );
            doc_figures::assert_figure(what, &stated[1], r.feed_length / 1000.0);
            let [nx, ny] = r.stock.cells;
            assert_eq!(stated[2].parse().ok(), Some(nx), "{what}: cells across");
            assert_eq!(stated[3].parse().ok(), Some(ny), "{what}: cells up");
            doc_figures::assert_figure(what, &stated[4], (nx * ny) as f64 / 1e6);
            bench_sample = true;
        }
    }
    assert!(
        bench_sample,
        "gcode-samples/mfs-mould.rough.nc was simulated"
    );
}

/// Issue 11's "done when": no golden sample rapids into material or plunges
/// straight into it (the crash `G0 Z-0.625` at X1.78 Y26.4 of the old
/// q-mould sample is the kind of finding this catches; its pattern is kept in
/// `tests/data/simulate/rapid-into-stock.nc`).
#[test]
fn every_sample_is_clean() {
    for p in files("gcode-samples", "nc") {
        let r = sample_report(&p, &SimOptions::default());
        assert!(r.is_clean(), "{}: {:?}", p.display(), r.findings.first());
    }
}

#[test]
fn the_cli_exits_1_on_a_collision_and_writes_the_png() {
    let dir = scratch("simulate", "collision");
    let file = test_data("simulate/rapid-into-stock.nc");
    let png = dir.join("stock.png");
    let (file, png_arg) = (file.to_str().unwrap(), png.to_str().unwrap());
    let out = common::pfcam(
        &[
            "simulate",
            file,
            "--tool-diameter",
            "3",
            "--stock",
            "0,0,30,30,0",
            "--png",
            png_arg,
        ],
        root(),
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(
        stdout.contains("rapid-into-stock.nc:5: error: rapid (G0) into material"),
        "{stdout}"
    );
    let bytes = std::fs::read(&png).unwrap();
    assert!(pfcam::output::is_pfcam_file(
        &bytes[..bytes.len().min(4096)]
    ));
    // A file pfcam did not write is not replaced without --force (exit 3).
    std::fs::write(&png, b"mine").unwrap();
    let out = common::pfcam(
        &["simulate", file, "--tool-diameter", "3", "--png", png_arg],
        root(),
    );
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(std::fs::read(&png).unwrap(), b"mine");
    // A clean program: exit 0, and --json parses.
    let clean = dir.join("clean.nc");
    std::fs::write(
        &clean,
        "G21 G90\nG0 Z5\nG0 X10 Y10\nG0 Z0.5\nG1 X20 Z-1 F100\nM2\n",
    )
    .unwrap();
    let clean = clean.to_str().unwrap();
    let out = common::pfcam(
        &["simulate", clean, "--tool-diameter", "3", "--json"],
        root(),
    );
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["clean"], true);
    assert_eq!(v["report"]["straight_plunges"], 0);
    // No tool anywhere: an error naming the flag.
    let out = common::pfcam(&["simulate", clean], root());
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--tool-diameter"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// With its job, a sample is simulated on the job's stock and measured
/// against the job's own part (S2): the model covers the stock, and the cut
/// lies on it to within a few hundredths (a part placed or scaled wrongly would
/// be millimetres off).
#[test]
fn a_job_measures_the_stock_against_its_part() {
    let root = root();
    let job = pfcam::job::load_job(&root.join("jobs/q-sign.toml")).unwrap();
    let facts = pfcam::simulate::job_facts(&job, 0.2).unwrap();
    // The job's two programs, rough then finish, as on the machine.
    let rough = std::fs::read_to_string(root.join("gcode-samples/q-sign.rough.nc")).unwrap();
    let finish = std::fs::read_to_string(root.join("gcode-samples/q-sign.finish.nc")).unwrap();
    let seq = simulate_programs(
        &[("rough", &rough), ("finish", &finish)],
        &SimOptions {
            job: Some(facts),
            ..SimOptions::default()
        },
    )
    .unwrap();
    let r = &seq.programs[0].report;
    assert_eq!(r.stock.source, "job");
    assert_eq!(r.tool_source, "job");
    assert_eq!(seq.programs[1].report.tool_source, "header");
    let p = seq.part.as_ref().expect("compared with S2");
    let total = r.stock.cells[0] * r.stock.cells[1];
    assert!(
        p.cells as f64 >= 0.99 * total as f64,
        "{} of {total}",
        p.cells
    );
    assert!(p.max_gouge.value < 0.05, "{p:?}");
    assert!(p.max_left.value > 0.0 && p.max_left.value < 1.0, "{p:?}");
}

/// Issue 11's "done when" with the jobs: every shipped job's sample, simulated
/// on the job's stock at 0.1 mm and measured against the job's own part (S2 for
/// a boss or cavity, the glyph outlines for a profile), cuts no cell into the
/// part by more than the job's tolerance and leaves no cell more than the
/// stated scallop (plus the tolerance) above it.
#[test]
fn every_job_sample_is_within_its_part() {
    let root = root();
    let jobs = files("jobs", "toml");
    assert!(jobs.len() >= 7, "{jobs:?}");
    let doc = doc_figures::read("docs/simulate.md");
    let mut quoted_runs = 0;
    for path in jobs {
        let job = pfcam::job::load_job(&path).unwrap();
        // Every program of the job, in order, on one stock.
        let files = pfcam::report::program_files(&job);
        let texts: Vec<String> = files
            .iter()
            .map(|f| std::fs::read_to_string(root.join("gcode-samples").join(f)).unwrap())
            .collect();
        // Named as the command line names them.
        let paths: Vec<String> = files.iter().map(|f| format!("gcode-samples/{f}")).collect();
        let progs: Vec<(&str, &str)> = paths
            .iter()
            .zip(&texts)
            .map(|(f, t)| (f.as_str(), t.as_str()))
            .collect();
        let facts = pfcam::simulate::job_facts(&job, 0.1).unwrap();
        let seq = simulate_programs(
            &progs,
            &SimOptions {
                job: Some(facts),
                ..SimOptions::default()
            },
        )
        .unwrap();
        let p = seq.part.as_ref().expect("compared with the part");
        let summary = p.summary();
        eprintln!("{}: {summary}", job.name);
        // docs/simulate.md quotes what `pfcam simulate SAMPLE... --job JOB`
        // prints for the bosses and cavities, and the profiles' max gouge.
        let command = format!(
            "$ pfcam simulate {} --job jobs/{}.toml",
            files
                .iter()
                .map(|f| format!("gcode-samples/{f}"))
                .collect::<Vec<_>>()
                .join(" "),
            job.name
        );
        if let Some(at) = doc.find(&command) {
            let quoted = doc[at..].lines().nth(1).expect("the command's output");
            assert_eq!(quoted, summary, "docs/simulate.md, `{command}`");
            quoted_runs += 1;
        } else if job.operation.kind == pfcam::job::OperationKind::Profile {
            let stated = doc_figures::number_after(
                &doc,
                "docs/simulate.md",
                "`mfs-profile`, `svg-logo`, `dxf-plate`): max gouge",
            );
            let what = format!("docs/simulate.md, the profiles' max gouge ({})", job.name);
            doc_figures::assert_figure(&what, &stated, p.max_gouge.value);
        }
        assert!(seq.is_clean(), "{}: {:?}", job.name, seq.findings().next());
        assert_eq!(p.gouged_cells, 0, "{}: {p:?}", job.name);
        assert!(
            p.max_gouge.value <= job.operation.tolerance,
            "{}: {p:?}",
            job.name
        );
        match &job.finish {
            // Finished: within the scallop (and the tolerance) wherever the
            // ball reaches (issue 14's "done when").
            Some(f) => assert!(
                p.max_left_reachable.value <= f.scallop + 0.01,
                "{}: {p:?}",
                job.name
            ),
            None => assert_eq!(p.left_share_over_scallop, 0.0, "{}: {p:?}", job.name),
        }
    }
    assert_eq!(
        quoted_runs, 5,
        "docs/simulate.md quotes the four bosses and cavities and the PDE vase"
    );
}

/// Runs the pfcam binary in the crate root; (exit code, stdout, stderr).
fn pfcam(args: &[&str]) -> (Option<i32>, String, String) {
    let out = common::pfcam(args, root());
    (out.status.code(), text(&out.stdout), text(&out.stderr))
}

/// One straight G1 at depth 1 along y = 10 across the 20 mm stock, the tool
/// entering and leaving outside it, under the header's `tool` line.
fn groove(tool: &str) -> String {
    format!(
        "(pfcam 0.1.0 job groove)\n({tool})\n(stock: X0..20 Y0..20, top 0, safe z 5 mm)\nG21 G90\nG0 Z5\nG0 X-5 Y10\nG0 Z-1\nG1 X25 F300\nG0 Z5\nM2\n"
    )
}

/// A 4 mm ball along a straight line at depth 1 cuts the round groove
/// computed by hand: the cell at ρ from the line is lowered to
/// −1 + 2 − √(4 − ρ²) where that is below the top, and is untouched beyond.
#[test]
fn a_ball_cuts_the_round_groove_computed_by_hand() {
    let s = run(
        &groove("tool: 4 mm ball end mill, feed 800, plunge 200 mm/min, spindle 18000 rpm"),
        &SimOptions::default(),
    );
    let r = &s.report;
    assert_eq!(
        (r.tool_shape, r.tool_diameter, r.corner_radius),
        (ToolShape::Ball, 4.0, 2.0)
    );
    assert_eq!(r.tool_source, "header");
    let g = s.map.grid;
    assert_eq!((g.nx, g.ny), (200, 200));
    let mut checked = 0;
    for j in 0..g.ny {
        let rho = (g.cy(j) - 10.0).abs();
        let want = if rho <= 2.0 {
            (-1.0 + 2.0 - (4.0 - rho * rho).sqrt()).min(0.0)
        } else {
            0.0
        };
        for i in 0..g.nx {
            let got = s.map.at(i, j);
            assert!(
                (got - want).abs() < 1e-12,
                "cell ({i}, {j}), {rho} mm off: {got} vs {want}"
            );
            checked += usize::from(want < 0.0);
        }
    }
    // Cut where √(4 − ρ²) > 1, i.e. ρ < √3: 2·√3 / 0.1 ≈ 34 rows of 200.
    assert_eq!(checked, 34 * 200);
    // The deepest cell is the row nearest the line, 0.05 mm off.
    let deepest = 1.0 - (2.0 - (4.0f64 - 0.05 * 0.05).sqrt());
    assert!(
        (r.max_axial.value - deepest).abs() < 1e-12,
        "{:?}",
        r.max_axial
    );
    assert_eq!(r.max_axial.line, 8);
    // Removing more than 0.001 mm: the rows within 1.73 mm of the line, 0.05..1.65 off.
    assert!(
        (r.max_radial.value - 3.3 / 4.0).abs() < 1e-9,
        "{:?}",
        r.max_radial
    );
    assert!(r.is_clean(), "{:?}", r.findings);
    let doc = doc_figures::read("docs/simulate.md");
    let stated = doc_figures::number_after(&doc, "docs/simulate.md", "a 4 mm ball 1 mm deep reads");
    doc_figures::assert_figure(
        "docs/simulate.md, the ball's radial engagement",
        &stated,
        100.0 * r.max_radial.value,
    );
    // The flat end mill of the same diameter cuts the full 4 mm wide slot,
    // and nowhere less deep than the ball.
    let flat = run(
        &groove("tool: 4 mm end mill, feed 800, plunge 200 mm/min, spindle 18000 rpm"),
        &SimOptions::default(),
    );
    assert_eq!(flat.report.tool_shape, ToolShape::Flat);
    assert!(flat.map.h.iter().zip(&s.map.h).all(|(f, b)| f <= b));
    assert_eq!(flat.map.h.iter().filter(|h| **h == -1.0).count(), 40 * 200);
}

/// The three tool lines a pfcam header may carry, read by the CLI: flat
/// stays `end mill`, and `--json` says the shape and corner.
#[test]
fn the_cli_reads_the_three_tool_lines_of_a_header() {
    let dir = scratch("simulate", "headers");
    let tail = "feed 800, plunge 200 mm/min, spindle 18000 rpm";
    for (line, shape, d, corner, summary) in [
        (
            format!("tool: 3.175 mm end mill, {tail}"),
            "flat",
            3.175,
            0.0,
            "tool: 3.175 mm flat end mill (header)",
        ),
        (
            format!("tool: 3.175 mm ball end mill, {tail}"),
            "ball",
            3.175,
            1.5875,
            "tool: 3.175 mm ball end mill (header)",
        ),
        (
            format!("tool: 6 mm bull nose end mill, corner 1.5 mm, {tail}"),
            "bull",
            6.0,
            1.5,
            "tool: 6 mm bull nose end mill, corner 1.5 mm (header)",
        ),
    ] {
        let file = dir.join(format!("{shape}.nc"));
        std::fs::write(&file, groove(&line)).unwrap();
        let f = file.to_str().unwrap();
        let (code, out, err) = pfcam(&["simulate", f, "--json"]);
        assert_eq!(code, Some(0), "{line}: {err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let r = &v["report"];
        assert_eq!(r["tool_shape"], shape, "{line}");
        assert_eq!(r["tool_diameter"], d, "{line}");
        assert_eq!(r["corner_radius"], corner, "{line}");
        assert_eq!(r["tool_source"], "header", "{line}");
        assert_eq!(v["programs"][0]["report"]["tool_shape"], shape, "{line}");
        let (_, text, _) = pfcam(&["simulate", f]);
        assert!(text.contains(summary), "{line}: {text}");
    }
    // A tool line naming no tool the simulator models: noted, and the tool
    // must come from the flags.
    let file = dir.join("vbit.nc");
    std::fs::write(&file, groove("tool: 6 mm v-bit, feed 800")).unwrap();
    let f = file.to_str().unwrap();
    let (code, _, err) = pfcam(&["simulate", f]);
    assert_eq!(code, Some(1));
    assert!(err.contains("--tool-diameter"), "{err}");
    let (code, out, _) = pfcam(&["simulate", f, "--tool-diameter", "6"]);
    assert_eq!(code, Some(0));
    assert!(
        out.contains("note: the header's `tool: 6 mm v-bit, feed 800` names no tool"),
        "{out}"
    );
    // The flags override the header's parts: the shape, and a bull's corner.
    let file = dir.join("bull.nc");
    let f = file.to_str().unwrap();
    let (_, out, _) = pfcam(&["simulate", f, "--corner-radius", "1", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["report"]["corner_radius"], 1.0);
    assert_eq!(v["report"]["tool_source"], "--corner-radius, header");
    let (_, out, _) = pfcam(&["simulate", f, "--tool-shape", "ball", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["report"]["tool_shape"], "ball");
    assert_eq!(v["report"]["corner_radius"], 3.0);
    // A bull nose needs its corner; a ball takes none.
    let (code, _, err) = pfcam(&[
        "simulate",
        dir.join("flat.nc").to_str().unwrap(),
        "--tool-shape",
        "bull",
    ]);
    assert_eq!(code, Some(1));
    assert!(err.contains("--corner-radius"), "{err}");
    let (code, _, err) = pfcam(&[
        "simulate",
        dir.join("ball.nc").to_str().unwrap(),
        "--corner-radius",
        "0.5",
    ]);
    assert_eq!(code, Some(1));
    assert!(err.contains("is for --tool-shape bull"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The job's tool is the first program's, unless that program's header names
/// another (the job's finish tool); the stepdown goes with the tool; a later
/// program's tool is its header's.
#[test]
fn the_jobs_tool_yields_to_a_header_naming_another() {
    let o = SimOptions {
        job: Some(square_job()), // a 3 mm flat end mill, stepdown 1
        ..SimOptions::default()
    };
    let same = groove("tool: 3 mm end mill, feed 800");
    let r = run(&same, &o).report;
    assert_eq!(
        (r.tool_source.as_str(), r.tool_shape, r.stepdown),
        ("job", ToolShape::Flat, Some(1.0))
    );
    let other = groove("tool: 4 mm ball end mill, feed 800");
    let r = run(&other, &o).report;
    assert_eq!(
        (r.tool_source.as_str(), r.tool_shape, r.tool_diameter),
        ("header", ToolShape::Ball, 4.0)
    );
    assert_eq!(r.stepdown, None, "the job's stepdown is its own tool's");
    // Flags override the job's tool too.
    let r = run(
        &same,
        &SimOptions {
            tool_shape: Some(ToolShape::Ball),
            ..o.clone()
        },
    )
    .report;
    assert_eq!(
        (r.tool_source.as_str(), r.tool_shape, r.tool_diameter),
        ("--tool-shape, job", ToolShape::Ball, 3.0)
    );
    // A later program without a tool line gets no tool from the job.
    let bare = "G21 G90\nG0 Z5\nG0 X-5 Y10\nG0 Z-1\nG1 X25 F300\nM2\n";
    match simulate_programs(&[("rough.nc", &same), ("finish.nc", bare)], &o) {
        Err(SimError::Program { name, error }) => {
            assert_eq!(name, "finish.nc");
            assert!(matches!(*error, SimError::NoToolAfterFirst), "{error}");
        }
        other => panic!("{:?}", other.map(|s| s.programs.len())),
    }
    let seq = simulate_programs(&[("rough.nc", &same), ("finish.nc", &other)], &o).unwrap();
    let tools: Vec<_> = seq
        .programs
        .iter()
        .map(|p| (p.report.tool_shape, p.report.tool_source.as_str()))
        .collect();
    assert_eq!(
        tools,
        [(ToolShape::Flat, "job"), (ToolShape::Ball, "header")]
    );
}

/// The floor of `pocket.*.nc`: the plane z = −2 over their 20 mm stock.
fn pocket_job() -> JobFacts {
    let (a, b, c, d) = (
        [0.0, 0.0, -2.0],
        [20.0, 0.0, -2.0],
        [20.0, 20.0, -2.0],
        [0.0, 20.0, -2.0],
    );
    JobFacts {
        tool_diameter: 6.0,
        stepdown: 1.5,
        stock: Some(StockBox {
            lo: [0.0, 0.0],
            hi: [20.0, 20.0],
            top: 0.0,
        }),
        part: Some(PartModel {
            name: "floor".into(),
            triangles: vec![[a, b, c], [a, c, d]],
            outlines: Vec::new(),
            outline_z: 0.0,
            wall_points: Vec::new(),
        }),
        tolerance: 0.01,
        scallop: 0.1,
        stepover: 4.0,
    }
}

/// A rough program (6 mm flat end mill, leaving 0.5 mm on the floor) then a
/// finish program (4 mm ball on the floor): the finish starts on the rough's
/// stock, removes only what is left, and leaves less than the rough alone;
/// the stock at the end is the lower of the two programs' cuts, cell by cell.
#[test]
fn a_finish_program_after_the_rough_leaves_less_than_the_rough_alone() {
    let (rough, finish) = (data("pocket.rough.nc"), data("pocket.finish.nc"));
    let o = SimOptions {
        job: Some(pocket_job()),
        ..SimOptions::default()
    };
    let alone = run(&rough, &o);
    let left = alone.report.part.as_ref().unwrap();
    assert!((left.max_left.value - 0.5).abs() < 1e-12, "{left:?}");
    assert_eq!(left.left_share_over_scallop, 1.0);
    let seq = simulate_programs(
        &[("pocket.rough.nc", &rough), ("pocket.finish.nc", &finish)],
        &o,
    )
    .unwrap();
    assert!(seq.is_clean());
    let [a, b] = &seq.programs[..] else { panic!() };
    assert_eq!(
        (a.report.tool_shape, b.report.tool_shape),
        (ToolShape::Flat, ToolShape::Ball)
    );
    // The first program's report is the one it has alone (the part aside).
    let mut first = alone.report.clone();
    first.part = None;
    assert_eq!(a.report, first);
    // The finish meets 0.5 mm of material: alone on fresh stock each of its
    // rows would cut a crescent 1.26 mm deep.
    let fresh = run(
        &finish,
        &SimOptions {
            job: Some(pocket_job()),
            ..SimOptions::default()
        },
    );
    assert!(
        fresh.report.max_axial.value > 1.0,
        "{:?}",
        fresh.report.max_axial
    );
    let doc = doc_figures::read("docs/simulate.md");
    let stated = doc_figures::number_after(
        &doc,
        "docs/simulate.md",
        "alone on fresh stock its rows would cut",
    );
    doc_figures::assert_figure(
        "docs/simulate.md, the finish alone",
        &stated,
        fresh.report.max_axial.value,
    );
    assert!(
        b.report.max_axial.value <= 0.5 + 1e-12,
        "{:?}",
        b.report.max_axial
    );
    // What is left is the ball's scallop, 2 − √(4 − 0.25²) = 0.016 mm, by the
    // finish's lines; nothing below the floor.
    let p = seq.part.as_ref().unwrap();
    let scallop = 2.0 - (4.0f64 - 0.0625).sqrt();
    assert!(
        p.max_left.value < scallop + 1e-9 && p.max_left.value > 0.5 * scallop,
        "{p:?}"
    );
    assert!(p.max_left.value < left.max_left.value);
    assert_eq!(p.max_left_program.as_deref(), Some("pocket.finish.nc"));
    assert!(
        p.max_left.line > 8 && p.max_left.line < finish.lines().count(),
        "{p:?}"
    );
    assert_eq!(p.left_share_over_scallop, 0.0);
    assert!(p.max_gouge.value <= 1e-12, "{p:?}");
    // Order aside, the final stock is each cell's lowest cut.
    assert!(seq
        .map
        .h
        .iter()
        .zip(alone.map.h.iter().zip(&fresh.map.h))
        .all(|(s, (a, b))| *s == a.min(*b)));
}

/// On the command line: the same two files, in order, with a `programs`
/// list in `--json`; a finding names its own file and line, and depends on
/// what ran before (a rapid down into the rough's pocket is harmless after
/// the rough, a collision before it).
#[test]
fn the_cli_runs_several_files_in_order() {
    let dir = scratch("simulate", "several");
    let root = test_data("simulate");
    let rough = root.join("pocket.rough.nc");
    let finish = root.join("pocket.finish.nc");
    let (rough, finish) = (rough.to_str().unwrap(), finish.to_str().unwrap());
    let (code, out, err) = pfcam(&["simulate", rough, finish, "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["clean"], true);
    assert_eq!(v["files"][1], finish);
    let programs = v["programs"].as_array().unwrap();
    assert_eq!(programs.len(), 2);
    assert_eq!(programs[0]["file"], rough);
    assert_eq!(programs[0]["report"]["tool_shape"], "flat");
    assert_eq!(programs[1]["report"]["tool_shape"], "ball");
    assert_eq!(programs[1]["report"]["tool_diameter"], 4.0);
    assert!(
        programs[1]["report"]["max_axial"]["value"]
            .as_f64()
            .unwrap()
            <= 0.5
    );
    assert!(v.get("report").is_none(), "one report per program");
    // A 3 mm flat end mill dropping by G0 to z −1 in the middle of the pocket.
    let drop = dir.join("drop.nc");
    std::fs::write(
        &drop,
        "(tool: 3 mm end mill, feed 300)\nG21 G90\nG0 Z5\nG0 X10 Y10\nG0 Z-1\nG1 X12 F300\nG0 Z5\nM2\n",
    )
    .unwrap();
    let drop = drop.to_str().unwrap();
    let (code, out, _) = pfcam(&["simulate", rough, drop]);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains(&format!("program 2 of 2: {drop}")), "{out}");
    assert!(out.contains("tool: 3 mm flat end mill (header)"), "{out}");
    let png = dir.join("final.png");
    // The first file's header names no stock: the pocket's is given.
    let (code, out, err) = pfcam(&[
        "simulate",
        drop,
        rough,
        "--stock",
        "0,0,20,20,0",
        "--png",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.contains(&format!("{drop}:5: error: rapid (G0) into material")),
        "{out}"
    );
    assert!(
        err.contains(&format!("{drop}, {rough}: 1 finding(s)")),
        "{err}"
    );
    assert!(std::fs::metadata(&png).is_ok());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The full-width rule: a ball is not judged by it; a bull nose is judged by
/// the cells under its flat part, so a cut whose corner reaches deep beside
/// a flat part half in material is not a slot, and the same cut in fresh
/// stock is.
#[test]
fn the_slot_rule_looks_at_the_flat_part() {
    let slot = data("deep-slot.nc");
    let tool = |shape, corner| SimOptions {
        tool_shape: Some(shape),
        corner_radius: corner,
        stepdown: Some(1.0),
        ..opts(3.0)
    };
    let ball = run(&slot, &tool(ToolShape::Ball, None));
    assert!(ball.report.is_clean(), "{:?}", ball.report.findings);
    assert_eq!(ball.report.stepdown, None);
    assert!(ball
        .report
        .summary()
        .contains("full-width cuts: not checked (a ball end mill has no flat part)"));
    let bull = run(&slot, &tool(ToolShape::Bull, Some(0.5)));
    assert_eq!(found(&bull), vec![(8, Kind::SlotDeeperThanStepdown)]);
    assert!(bull.report.findings[0]
        .message
        .contains("of the tool's flat part"));
    // y < 10 cleared to −2 by a 10 mm flat end mill (stepdown 5: no slot),
    // then a 6 mm bull nose with 2 mm corners (flat part 2 mm wide) along
    // y = 10 at −2: its flat part is half in material, its corner cuts more
    // than the stepdown 1 out to y = 12.7.
    let clear = "(tool: 10 mm end mill, feed 800)\n(stock: X0..30 Y0..20, top 0, safe z 5 mm)\n(operation: pocket, stepdown 5, tol 0.01 mm)\nG21 G90\nG0 Z5\nG0 X-6 Y5\nG1 Z-2 F200\nG1 X36 F800\nG0 Z5\nM2\n";
    let side = "(tool: 6 mm bull nose end mill, corner 2 mm, feed 800)\n(operation: finish, stepdown 1, tol 0.01 mm)\nG21 G90\nG0 Z5\nG0 X-4 Y10\nG1 Z-2 F200\nG1 X34 F800\nG0 Z5\nM2\n";
    let seq = simulate_programs(
        &[("clear.nc", clear), ("side.nc", side)],
        &SimOptions::default(),
    )
    .unwrap();
    let [a, b] = &seq.programs[..] else { panic!() };
    assert!(a.report.is_clean(), "{:?}", a.report.findings);
    assert_eq!(b.report.stepdown, Some(1.0));
    assert!(b.report.max_axial.value > 1.9);
    assert!(b.report.is_clean(), "{:?}", b.report.findings);
    let alone = simulate_programs(
        &[("side.nc", side)],
        &SimOptions {
            stock: Some(StockBox {
                lo: [0.0, 0.0],
                hi: [30.0, 20.0],
                top: 0.0,
            }),
            ..SimOptions::default()
        },
    )
    .unwrap();
    let found: Vec<_> = alone.programs[0]
        .report
        .findings
        .iter()
        .map(|f| (f.line, f.kind))
        .collect();
    assert_eq!(found, vec![(7, Kind::SlotDeeperThanStepdown)]);
}

/// Helical arcs reach the tool as chords within 1/20 of a cell of the arc;
/// the swept ball along the chords is then within that distance of the
/// swept ball along the helix (both are the path ⊕ the ball). So every cell
/// lies between the helix's sweep by a ball larger by the chord tolerance
/// (and the oracle's sample spacing) and by one smaller by it, and never
/// below a flat end mill's cut.
#[test]
fn a_ball_along_a_helix_stays_within_the_chord_tolerance() {
    let prog = "G21 G90\nG0 Z5\nG0 X21 Y15\nG0 Z0\nG2 X21 Y15 Z-1.5 I-6 J0 F300\nM2\n";
    let (r, res) = (1.5, 0.1);
    let o = |shape| SimOptions {
        tool_shape: Some(shape),
        ..opts(2.0 * r)
    };
    let ball = run(prog, &o(ToolShape::Ball));
    let flat = run(prog, &o(ToolShape::Flat));
    assert!(flat.map.h.iter().zip(&ball.map.h).all(|(f, b)| f <= b));
    let delta = res * pfcam::simulate::CHORD_FRACTION;
    // The helix's centre path, densely: 60 000 points 0.0006 mm apart.
    let n = 60_000;
    let g = ball.map.grid;
    let mut lo = vec![0.0f64; g.nx * g.ny]; // ball of r + δ + spacing
    let mut hi = vec![0.0f64; g.nx * g.ny]; // ball of r − δ
    let spacing = 2.0 * std::f64::consts::PI * 6.0 / n as f64;
    let (r_lo, r_hi) = (r + delta + spacing, r - delta);
    for k in 0..=n {
        let f = k as f64 / n as f64;
        let a = -2.0 * std::f64::consts::PI * f; // clockwise from angle 0
        let (x, y, zc) = (15.0 + 6.0 * a.cos(), 15.0 + 6.0 * a.sin(), -1.5 * f + r);
        let (Some((i0, i1)), Some((j0, j1))) =
            (g.cols(x - r_lo, x + r_lo), g.rows(y - r_lo, y + r_lo))
        else {
            continue;
        };
        for j in j0..=j1 {
            for i in i0..=i1 {
                let rho2 = (g.cx(i) - x).powi(2) + (g.cy(j) - y).powi(2);
                let c = j * g.nx + i;
                if rho2 <= r_lo * r_lo {
                    lo[c] = lo[c].min(zc - (r_lo * r_lo - rho2).sqrt());
                }
                if rho2 <= r_hi * r_hi {
                    hi[c] = hi[c].min(zc - (r_hi * r_hi - rho2).sqrt());
                }
            }
        }
    }
    let mut worst = 0.0f64;
    for c in 0..lo.len() {
        let h = ball.map.h[c];
        assert!(
            h >= lo[c] - 1e-9 && h <= hi[c] + 1e-9,
            "cell {c}: {} not in [{}, {}]",
            h,
            lo[c],
            hi[c]
        );
        worst = worst.max(hi[c] - lo[c]);
    }
    assert!(ball.map.min() < -1.49);
    eprintln!("helix: the ball's cells lie within bounds at most {worst:.4} mm apart");
}

/// docs/simulate.md's example of two programs is what the command prints.
#[test]
fn the_docs_example_of_two_programs_is_what_the_cli_prints() {
    let doc = doc_figures::read("docs/simulate.md");
    let command =
        "pfcam simulate tests/data/simulate/pocket.rough.nc tests/data/simulate/pocket.finish.nc";
    let quoted = doc_figures::after(&doc, "docs/simulate.md", &format!("$ {command}\n"));
    let quoted = &quoted[quoted.find('\n').unwrap() + 1..];
    let quoted = &quoted[..quoted.find("```").expect("the block's end")];
    let args: Vec<&str> = command.split(' ').skip(1).collect();
    let out = common::pfcam(&args, root());
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        quoted,
        "docs/simulate.md, `{command}`"
    );
}

/// The walk leaves out cells of a piece's start disk that the piece cannot
/// lower (all of it for a flat end mill, the half behind it for a curved
/// end) when the piece goes on from where the last ended without
/// descending. Cut as separate programs the moves skip nothing: the stock
/// is the same, for every shape.
#[test]
fn skipping_the_start_disk_changes_no_cell() {
    let pts = [
        [5.0, 5.0, -1.0],
        [15.0, 5.0, -1.0],
        [15.0, 8.0, -1.0],
        [5.0, 12.0, -0.5],
        [8.0, 12.0, -0.5],
        [8.05, 12.02, -0.5],
        [8.1, 12.0, -0.45],
        [12.0, 15.0, -1.2],
        [18.0, 10.0, -0.3],
        [18.0, 10.0, 0.2],
        [18.0, 10.0, -0.8],
        [18.03, 10.0, -0.8],
        [11.0, 21.0, -0.2],
    ];
    let p = |q: [f64; 3]| format!("X{} Y{} Z{}", q[0], q[1], q[2]);
    let mut whole = format!("G21 G90\nG0 {}\n", p(pts[0]));
    let mut parts = Vec::new();
    for w in pts.windows(2) {
        whole += &format!("G1 {} F300\n", p(w[1]));
        parts.push(format!("G21 G90\nG0 {}\nG1 {} F300\n", p(w[0]), p(w[1])));
    }
    let named: Vec<(&str, &str)> = parts.iter().map(|t| ("part", t.as_str())).collect();
    for (shape, corner) in [
        (ToolShape::Flat, None),
        (ToolShape::Ball, None),
        (ToolShape::Bull, Some(0.8)),
    ] {
        let o = SimOptions {
            tool_shape: Some(shape),
            corner_radius: corner,
            ..opts(3.0)
        };
        let a = run(&whole, &o);
        let b = simulate_programs(&named, &o).unwrap();
        let differ = a
            .map
            .h
            .iter()
            .zip(&b.map.h)
            .filter(|(x, y)| (*x - *y).abs() > 1e-12)
            .count();
        assert_eq!(differ, 0, "{shape:?}: cells at different heights");
        assert!(a.map.min() < -1.19);
    }
}

/// docs/simulate.md: mfs-mould.rough.nc, planned for its flat end mill, run with a
/// ball and a bull nose, reads the straight plunges the doc states (the
/// linker's `G1 Z` descents into what only a flat end mill cleared).
#[test]
fn the_flat_mould_with_curved_ends_reads_the_plunges_the_doc_states() {
    let root = root();
    let text = std::fs::read_to_string(root.join("gcode-samples/mfs-mould.rough.nc")).unwrap();
    let doc = doc_figures::read("docs/simulate.md");
    let stated =
        doc_figures::numbers_after(&doc, "docs/simulate.md", "--corner-radius 0.5`) reads", 2);
    for (figure, shape, corner) in [
        (&stated[0], ToolShape::Ball, None),
        (&stated[1], ToolShape::Bull, Some(0.5)),
    ] {
        let s = run(
            &text,
            &SimOptions {
                tool_shape: Some(shape),
                corner_radius: corner,
                ..SimOptions::default()
            },
        );
        let r = &s.report;
        let source = match corner {
            Some(_) => "--tool-shape, --corner-radius, header",
            None => "--tool-shape, header",
        };
        assert_eq!(r.tool_source, source);
        assert_eq!(
            figure.parse().ok(),
            Some(r.straight_plunges),
            "docs/simulate.md, {shape:?}"
        );
        assert!(r.findings.iter().all(|f| f.kind == Kind::StraightPlunge));
    }
}
