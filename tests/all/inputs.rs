//! Fixed-seed property tests of the parsers that read what a user or a machine
//! hands pfcam (issue 15): the job TOML as far as the built shape, SVG path
//! data, G-code for `pfcam check`, and GRBL's responses. Each feeds a few
//! thousand random or mutated inputs and checks what the result must satisfy,
//! beyond "no panic": a resolved job's shape is within the size limit, a
//! scaled SVG shape has the height asked for, a check report is ordered and
//! finite, a response parses the same with the blanks GRBL may add. The
//! generator is a xorshift with a fixed seed, so a failure repeats; the case
//! is printed in the assertion.

use pfcam::gcode::check::{check_gcode, CheckOptions};
use pfcam::geometry::svgpath::svg_shape;
use pfcam::geometry::{Contour, GeometryError, ShapeSource, Vec2};
use pfcam::grbl::protocol::{parse_response, Response, StatusReport, WorkOffset};
use pfcam::job::{echo, extent, parse_job};
use std::path::Path;

use crate::common::{files, root, Rng};
use crate::doc_figures;

/// Numbers a careless or hostile input holds.
const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1",
    "-1",
    "0.5",
    "3.175",
    "1e300",
    "-1e300",
    "1e-300",
    "1e308",
    "1e309",
    "nan",
    "inf",
    "-inf",
    "2000",
    "2000.0001",
    "100000",
    "9999999999999999999",
    "1e6",
    "-1e6",
];

/// The texts of the files with extension `ext` in the crate's `dir`.
fn shipped_texts(dir: &str, ext: &str) -> Vec<String> {
    files(dir, ext)
        .iter()
        .map(|p| std::fs::read_to_string(p).expect("read"))
        .collect()
}

/// `text` with one random change: a number replaced by an extreme, a byte
/// range dropped, a line repeated elsewhere, or a junk character inserted.
fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut s = text.to_string();
    let boundary = |s: &str, at: usize| (at..=s.len()).find(|&i| s.is_char_boundary(i));
    let Some(at) = boundary(&s, rng.below(s.len() + 1)) else {
        return s;
    };
    match rng.below(4) {
        0 => {
            // The next number (a run of digits, signs, dots, e) becomes an extreme.
            let is_num = |c: char| c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e');
            if let Some(start) = s[at..].find(|c: char| c.is_ascii_digit()).map(|i| at + i) {
                let end = s[start..]
                    .find(|c: char| !is_num(c))
                    .map_or(s.len(), |i| start + i);
                s.replace_range(start..end, rng.pick(NUMBERS));
            }
        }
        1 => {
            let end = boundary(&s, (at + rng.below(12)).min(s.len())).unwrap_or(s.len());
            s.replace_range(at..end, "");
        }
        2 if !text.trim().is_empty() => {
            let lines: Vec<&str> = text.lines().collect();
            let line = format!("{}\n", rng.pick(&lines));
            s.insert_str(at, &line);
        }
        _ => {
            let junk = [
                "=", "[", "]", "\"", "#", ",", "\n", "é", "\t", "{", "}", "x",
            ];
            s.insert_str(at, rng.pick(&junk));
        }
    }
    s
}

/// Mutated shipped jobs: every one gives a job or an error naming something,
/// clipped; a job with text or an SVG path (built in microseconds, unlike a
/// composition, whose parts need field solves) gives a shape within the size
/// limit or an error, never a panic.
#[test]
fn mutated_jobs_resolve_to_bounded_shapes_or_errors() {
    let jobs = shipped_texts("jobs", "toml");
    assert!(jobs.len() >= 5);
    let mut rng = Rng(0x6a6f_6273);
    let (mut built, mut refused) = (0, 0);
    for case in 0..3000 {
        let mut text = jobs[rng.below(jobs.len())].clone();
        for _ in 0..1 + rng.below(3) {
            text = mutate(&text, &mut rng);
        }
        let job = match parse_job(&text, "fuzz", Path::new(".")) {
            Ok(job) => job,
            Err(e) => {
                refused += 1;
                let m = e.to_string();
                assert!(!m.is_empty(), "case {case}");
                assert!(
                    m.chars().count() <= echo::MAX_MESSAGE + 200,
                    "case {case}: {m}"
                );
                continue;
            }
        };
        if matches!(job.shape, ShapeSource::Composite(_)) {
            continue;
        }
        let Ok(shape) = pfcam::geometry::build_shape(&job.shape) else {
            refused += 1;
            continue;
        };
        match extent::check_extent(&job.shape, &shape, job.tool.diameter) {
            Ok(()) => {
                built += 1;
                let (lo, hi) = shape.bbox().expect("a built shape has contours");
                let side = extent::max_side(job.tool.diameter);
                assert!(
                    hi.x - lo.x <= side && hi.y - lo.y <= side,
                    "case {case}: {lo:?}..{hi:?} passed\n{text}"
                );
            }
            Err(e) => {
                refused += 1;
                assert!(e.key().is_some(), "case {case}: {e}");
            }
        }
    }
    // Neither all harmless nor all fatal: the mutations reach both sides.
    assert!(
        built > 100 && refused > 100,
        "built {built}, refused {refused}"
    );
}

/// Random SVG path data: commands, numbers (extremes among them) and junk in
/// any order. A shape scaled to a height has that height (its curves' tight
/// box, as `svg_shape` scales it), with the box's corner at the origin; an
/// error is an SVG error at a place inside the data, or a contour error.
#[test]
fn random_svg_paths_scale_exactly_or_fail_with_a_place() {
    let mut rng = Rng(0x7376_6770);
    let tokens = [
        "M", "m", "L", "l", "H", "h", "V", "v", "C", "c", "S", "s", "Q", "q", "T", "t", "A", "a",
        "Z", "z", " ", ",", "-", ".", "e", "+", "é", "\n",
    ];
    // Valid paths to mutate: lines, both Béziers, their smooth forms, arcs,
    // relative commands, two subpaths.
    let valid = [
        "M0 0 L10 0 L10 10 Z",
        "M0 0 C5 -5 10 5 10 10 S0 15 0 0 Z",
        "m1 1 q5 -5 10 0 t-10 10 z",
        "M0 0 H20 V5 A5 5 0 0 1 10 5 Z M2 1 h3 v2 h-3 z",
        "M 0,0 L 3,0 2,2 Z",
    ];
    let (mut ok, mut bad) = (0, 0);
    for case in 0..5000 {
        let mut d = String::from(rng.pick(&["M0 0", "M 1,1", "m-3-4", ""]));
        if case % 2 == 0 {
            d = rng.pick(&valid).to_string();
            for _ in 0..rng.below(3) {
                d = mutate(&d, &mut rng);
            }
        }
        for _ in 0..(case % 2) * rng.below(16) {
            match rng.below(3) {
                0 => d.push_str(rng.pick(&tokens)),
                1 => d.push_str(rng.pick(NUMBERS)),
                _ => d.push_str(&format!(" {}", rng.below(200) as f64 / 10.0 - 10.0)),
            }
            if rng.below(2) == 0 {
                d.push(' ');
            }
        }
        if rng.below(2) == 0 {
            d.push('Z');
        }
        let height = [None, Some(10.0), Some(0.1), Some(2000.0)][rng.below(4)];
        match svg_shape(&d, height, Vec2::new(5.0, -5.0)) {
            Ok(shape) => {
                ok += 1;
                let (lo, hi) = tight_box(&shape).expect("a shape has contours");
                assert!(lo.x.is_finite() && hi.y.is_finite(), "case {case}: {d:?}");
                let near = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0);
                assert!(
                    near(lo.x, 5.0) && near(lo.y, -5.0),
                    "case {case}: {d:?} at {lo:?}"
                );
                if let Some(h) = height {
                    assert!(
                        near(hi.y - lo.y, h),
                        "case {case}: {d:?} is {} high, not {h}",
                        hi.y - lo.y
                    );
                }
            }
            Err(GeometryError::Svg { offset, .. }) => {
                bad += 1;
                assert!(
                    offset <= d.chars().count(),
                    "case {case}: {d:?} at {offset}"
                );
            }
            Err(e) => {
                bad += 1;
                assert!(!e.to_string().is_empty(), "case {case}: {d:?}");
            }
        }
    }
    assert!(ok > 50 && bad > 50, "ok {ok}, errors {bad}");
}

/// The tight bounding box of a shape's curves.
fn tight_box(shape: &pfcam::geometry::Shape) -> Option<(Vec2, Vec2)> {
    shape
        .contours()
        .filter_map(Contour::tight_bbox)
        .reduce(|(a, b), (c, d)| {
            (
                Vec2::new(a.x.min(c.x), a.y.min(c.y)),
                Vec2::new(b.x.max(d.x), b.y.max(d.y)),
            )
        })
}

/// Mutated shipped G-code for `pfcam check`: the report's findings are in line
/// order and on lines of the file, and its totals are never NaN.
#[test]
fn mutated_gcode_checks_to_ordered_finite_reports() {
    let samples: Vec<String> = shipped_texts("gcode-samples", "nc")
        .into_iter()
        .map(|s| s.lines().take(400).collect::<Vec<_>>().join("\n"))
        .collect();
    let mut rng = Rng(0x6763_6f64);
    let mut with_errors = 0;
    for case in 0..2000 {
        let mut text = samples[rng.below(samples.len())].clone();
        for _ in 0..1 + rng.below(6) {
            text = mutate(&text, &mut rng);
        }
        let r = check_gcode(&text, &CheckOptions::default());
        let lines = text.lines().count().max(1);
        assert!(
            r.findings.windows(2).all(|w| w[0].line <= w[1].line),
            "case {case}"
        );
        assert!(
            r.findings
                .iter()
                .all(|f| f.line >= 1 && f.line <= lines + 1),
            "case {case}: a finding past line {lines}"
        );
        let t = &r.totals;
        for (what, x) in [
            ("cut_length", t.cut_length),
            ("rapid_length", t.rapid_length),
            ("time_s", t.time_s),
            ("dwell_s", t.dwell_s),
        ] {
            assert!(!x.is_nan() && x >= 0.0, "case {case}: {what} = {x}");
        }
        with_errors += usize::from(r.errors() > 0);
    }
    assert!(
        with_errors > 100,
        "only {with_errors} mutated files had errors"
    );
}

/// GRBL 1.1 lines, real and mangled: classification never panics, ignores the
/// blanks and carriage return a serial line may carry, and a status report
/// gives a position exactly when it has `MPos` or `WPos`.
#[test]
fn grbl_responses_parse_the_same_with_blanks() {
    let real = [
        "ok",
        "error:20",
        "ALARM:3",
        "Grbl 1.1h ['$' for help]",
        "[MSG:Reset to continue]",
        "[GC:G0 G54 G17 G21 G90 G94 M5 M9 T0 F0 S0]",
        ">G54:ok",
        "<Idle|MPos:0.000,0.000,0.000|FS:0,0|WCO:-50.000,-50.000,-10.000>",
        "<Run|MPos:-10.000,-12.500,-1.000|Bf:15,128|FS:800,10000|Ov:100,100,100>",
        "<Hold:0|WPos:1.000,2.000,3.000|Bf:14,100|FS:0,0|Pn:XZ>",
        "$110=1000.000",
    ];
    let mut rng = Rng(0x6772_626c);
    let alphabet: Vec<char> = "<>|:,.-0123456789okerrorALARMIdleRunMPosWPosWCOBfFSOvPn[]$=\r é"
        .chars()
        .collect();
    let mut statuses = 0;
    let mut offset = WorkOffset::default();
    for case in 0..5000 {
        let line = match rng.below(3) {
            0 => mutate(rng.pick(&real), &mut rng),
            1 => (0..rng.below(40)).map(|_| rng.pick(&alphabet)).collect(),
            _ => {
                let mut l = rng.pick(&real).to_string();
                for _ in 0..3 {
                    l = mutate(&l, &mut rng);
                }
                l
            }
        };
        let r = parse_response(&line);
        // Compared as text: a NaN coordinate is not equal to itself.
        assert_eq!(
            format!("{:?}", parse_response(&format!("  {line}\r"))),
            format!("{r:?}"),
            "case {case}: {line:?}"
        );
        if line.trim() == "ok" {
            assert_eq!(r, Response::Ok);
        }
        if let Some(report) = StatusReport::parse(&line) {
            statuses += 1;
            let has_position = report.mpos.is_some() || report.wpos.is_some();
            assert_eq!(
                offset.update(&report).is_some(),
                has_position,
                "case {case}: {line:?}"
            );
        }
    }
    assert!(statuses > 100, "only {statuses} status reports survived");
}

/// docs/shapes.md's figures of the test fonts: DejaVu Serif's cap height (the
/// top of its H) of so many units per em; DejaVu Sans's A–V and T–o kerning as
/// the shaper sets it (its GPOS pairs: `geometry::shaping`'s tests read them
/// from the table), in units and in mm at a 50 mm cap height, and its line
/// height.
#[test]
fn shapes_doc_font_figures_are_the_test_fonts() {
    use pfcam::geometry::font::{self, FontFile};
    use pfcam::geometry::shaping::shape_line;
    let data = root().join("tests/data");
    let file = FontFile::open(&data.join("DejaVuSerif.ttf"), 0).expect("DejaVu Serif");
    let face = file.face().expect("face");
    let cap = font::cap_height(&face, "DejaVu Serif").expect("cap height");
    let doc = doc_figures::read("docs/shapes.md");
    let what = "docs/shapes.md, DejaVu Serif";
    let stated = doc_figures::numbers_after(&doc, "docs/shapes.md", "the top of its H,", 2);
    doc_figures::assert_figure(what, &stated[0], cap);
    doc_figures::assert_figure(what, &stated[1], f64::from(face.units_per_em()));

    let file = FontFile::open(&data.join("DejaVuSans.ttf"), 0).expect("DejaVu Sans");
    let face = file.face().expect("face");
    let cap = font::cap_height(&face, "DejaVu Sans").expect("cap height");
    let kern = |pair: &str| {
        let g = shape_line(&face, "DejaVu Sans", pair).expect("shaped");
        let first = face
            .glyph_index(pair.chars().next().expect("char"))
            .expect("glyph");
        g[0].advance - f64::from(face.glyph_hor_advance(first).expect("advance"))
    };
    let (av, to) = (kern("AV"), kern("To"));
    let shift = -av * 50.0 / cap;
    let line = font::line_height(&face).expect("line height");
    eprintln!(
        "DejaVu Sans: cap height {cap}, A–V {av} units ({shift:.3} mm at 50 mm), T–o {to} units, line height {line} of {} units per em",
        face.units_per_em()
    );
    let what = "docs/shapes.md, DejaVu Sans";
    let stated = doc_figures::numbers_after(&doc, "docs/shapes.md", "DejaVu Sans kerns A–V by", 2);
    doc_figures::assert_figure(what, &stated[0], av);
    doc_figures::assert_figure(what, &stated[1], to);
    let stated = doc_figures::number_after(&doc, "docs/shapes.md", "which moves the V");
    doc_figures::assert_figure(what, &stated, shift);
    let stated =
        doc_figures::numbers_after(&doc, "docs/shapes.md", "DejaVu Sans's line height is", 2);
    doc_figures::assert_figure(what, &stated[0], line);
    doc_figures::assert_figure(what, &stated[1], f64::from(face.units_per_em()));
}

#[allow(dead_code)] // its `main` is the example's command line
#[path = "../../examples/segment_errors.rs"]
mod segment_errors;

/// docs/shapes.md's table of `Segment`'s measured errors: the first five rows
/// are what `examples/segment_errors.rs` measures now.
#[test]
fn shapes_doc_segment_errors_are_measured() {
    let e = segment_errors::measure();
    let doc = doc_figures::read("docs/shapes.md");
    let row = |first: &str, n: usize| {
        let cells = doc_figures::table_row(&doc, "docs/shapes.md", first);
        doc_figures::numbers_after(cells[2], "docs/shapes.md", "", n)
    };
    let what = "docs/shapes.md, Segment's errors";
    for (rows, values) in [
        (
            row("`Segment::deriv`, `deriv2`", 2),
            vec![e.deriv, e.deriv2],
        ),
        (row("`Segment::length`", 1), vec![e.length]),
        (row("`t_at_length`", 1), vec![e.t_at_length]),
        (row("`Segment::area_term` (cubic)", 1), vec![e.area_term]),
        (
            row("`flatten_into(tol)`", 2),
            vec![e.flatten.0, e.flatten.1],
        ),
    ] {
        for (figure, value) in rows.iter().zip(values) {
            doc_figures::assert_figure(what, figure, value);
        }
    }
}
