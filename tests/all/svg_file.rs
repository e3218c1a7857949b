//! `shape.svg_file`: whole SVG documents read through usvg, on drawings made
//! for the purpose (tests/data/svg-*.svg). Outlines are compared with the
//! analytic shapes they draw: areas, hole counts under each fill rule,
//! positions through nested transforms, units; then the errors, each naming
//! its key.

use std::f64::consts::PI;
use std::path::PathBuf;

use pfcam::geometry::svgfile::{svg_file_shape, SvgFileSource, SvgSize};
use pfcam::geometry::{build_shape, Shape, ShapeSource, Vec2};
use pfcam::job::parse_job;

use crate::common::{area, holes, perimeter, root, test_data};

/// The job's default tolerance, mm.
const TOL: f64 = 0.01;

fn source(file: &str, id: Option<&str>, size: SvgSize) -> SvgFileSource {
    SvgFileSource {
        path: test_data(file),
        id: id.map(str::to_string),
        size,
        origin: Vec2::ZERO,
        tolerance: TOL,
        max_size: 2000.0,
    }
}

fn shape(file: &str, id: Option<&str>) -> Shape {
    svg_file_shape(&source(file, id, SvgSize::Natural))
        .unwrap_or_else(|e| panic!("{file} {id:?}: {e}"))
}

fn bbox(s: &Shape) -> (Vec2, Vec2) {
    s.tight_bbox().expect("a shape has a box")
}

/// Flattening within `TOL` cuts at most `TOL` off along the perimeter; usvg's
/// cubics for an arc lie within 2.7e-4 of the radius outside it.
fn assert_area(s: &Shape, want: f64, what: &str) {
    let got = area(s);
    let bound = perimeter(s) * TOL;
    assert!(
        (got - want).abs() <= bound,
        "{what}: area {got:.5}, want {want:.5} within {bound:.5}"
    );
}

#[test]
fn a_circle_has_area_pi_r_squared_and_its_radius() {
    let s = shape("svg-shapes.svg", Some("circle"));
    assert_eq!(s.regions.len(), 1);
    assert_eq!(holes(&s), 0);
    assert_area(&s, PI * 100.0, "circle");
    // Every vertex lies on the circle of radius 10 about the box's centre:
    // flattening puts them on the curve, usvg's cubics are within 2.7e-4 r.
    let (lo, hi) = bbox(&s);
    let c = (lo + hi) * 0.5;
    assert!((hi.x - lo.x - 20.0).abs() < 0.01 && (hi.y - lo.y - 20.0).abs() < 0.01);
    let worst = s.regions[0]
        .outline
        .segments
        .iter()
        .map(|seg| (seg.start().dist(c) - 10.0).abs())
        .fold(0.0, f64::max);
    assert!(worst < 10.0 * 3e-4, "radial error {worst}");
}

#[test]
fn a_rounded_rect_an_arc_an_ellipse_a_polygon_and_a_use() {
    let cases = [
        ("rounded", 600.0 - (4.0 - PI) * 16.0),
        ("arc", PI * 50.0),
        ("ellipse", PI * 12.0 * 6.0),
        ("polygon", 17.0 * 8.0 / 2.0),
        ("used", 64.0),
        ("nested", 200.0),
    ];
    for (id, want) in cases {
        let s = shape("svg-shapes.svg", Some(id));
        assert_eq!(s.regions.len(), 1, "{id}");
        assert_eq!(holes(&s), 0, "{id}");
        assert_area(&s, want, id);
        assert_eq!(
            bbox(&s).0,
            Vec2::ZERO,
            "{id}: the box's corner is at the origin"
        );
    }
}

#[test]
fn fill_rules_decide_the_holes() {
    // evenodd: the inner square, drawn the same way, is a hole.
    let s = shape("svg-shapes.svg", Some("evenodd"));
    assert_eq!((s.regions.len(), holes(&s)), (1, 1));
    assert_area(&s, 900.0 - 256.0, "evenodd");
    // usvg computes in f32: coordinates are exact to about 1e-7 of their size.
    assert!((s.regions[0].counters[0].signed_area() + 256.0).abs() < 1e-4);
    // nonzero: the same two squares fill the whole square.
    let s = shape("svg-shapes.svg", Some("nonzero-filled"));
    assert_eq!((s.regions.len(), holes(&s)), (1, 0));
    assert_area(&s, 900.0, "nonzero-filled");
    // nonzero with the inner rectangle drawn the other way: a hole.
    let s = shape("svg-shapes.svg", Some("nonzero-hole"));
    assert_eq!((s.regions.len(), holes(&s)), (1, 1));
    assert_area(&s, 600.0 - 160.0, "nonzero-hole");
}

#[test]
fn the_whole_document_keeps_its_layout_through_nested_transforms() {
    let s = shape("svg-shapes.svg", None);
    // Ten filled elements, two holes; the stroked page frame is not material.
    assert_eq!(s.regions.len(), 10);
    assert_eq!(holes(&s), 2);
    let want = PI * 100.0 + 600.0 - (4.0 - PI) * 16.0
        + 200.0
        + 68.0
        + 644.0
        + 900.0
        + 440.0
        + PI * 50.0
        + PI * 72.0
        + 64.0;
    assert_area(&s, want, "document");
    // The drawing spans page x 5..95, y 5..76; y is flipped and the box's
    // corner moved to the origin: page (x, y) is at (x − 5, 76 − y).
    let (lo, hi) = bbox(&s);
    assert!(lo.norm() < 1e-9, "{lo:?}");
    assert!((hi - Vec2::new(90.0, 71.0)).norm() < 1e-3, "{hi:?}");
    let at = |x: f64, y: f64| Vec2::new(x - 5.0, 76.0 - y);
    // The nested rectangle: page corners (75, 5) and (95, 15).
    let nested = s
        .regions
        .iter()
        .find(|r| {
            let (a, b) = r.outline.tight_bbox().expect("box");
            (a - at(75.0, 15.0)).norm() < 1e-4 && (b - at(95.0, 5.0)).norm() < 1e-4
        })
        .unwrap_or_else(|| panic!("no region at the nested rectangle's place"));
    assert!((nested.outline.signed_area() - 200.0).abs() < 1e-4);
    // The circle's centre, page (15, 15).
    let circle = s
        .regions
        .iter()
        .map(|r| r.outline.tight_bbox().expect("box"))
        .find(|(a, b)| ((*a + *b) * 0.5 - at(15.0, 15.0)).norm() < 1e-3)
        .map(|(a, b)| b - a);
    let size = circle.expect("a region centred on the circle's centre");
    assert!((size.x - 20.0).abs() < 1e-2 && (size.y - 20.0).abs() < 1e-2);
    // The tile, used at page (80, 66): its corner at page (80, 74).
    assert!(s
        .regions
        .iter()
        .any(|r| (r.outline.tight_bbox().expect("box").0 - at(80.0, 74.0)).norm() < 1e-4));
}

#[test]
fn scale_width_height_and_origin() {
    let natural = shape("svg-shapes.svg", None);
    let a0 = area(&natural);
    for (size, k) in [
        (SvgSize::Scale(0.5), 0.5),
        (SvgSize::Width(180.0), 2.0),
        (SvgSize::Height(35.5), 0.5),
    ] {
        let mut src = source("svg-shapes.svg", None, size);
        src.origin = Vec2::new(10.0, -20.0);
        let s = svg_file_shape(&src).expect("scaled");
        let (lo, hi) = bbox(&s);
        assert!((lo - src.origin).norm() < 1e-9, "{size:?}: {lo:?}");
        assert!(
            ((hi - lo) - Vec2::new(90.0 * k, 71.0 * k)).norm() < 1e-6 * k.max(1.0) + 2e-3,
            "{size:?}: {:?}",
            hi - lo
        );
        // Each is flattened within TOL at its own size.
        let off = area(&s) - a0 * k * k;
        let bound = perimeter(&s) * TOL + perimeter(&natural) * TOL * k * k;
        assert!(
            off.abs() < bound,
            "{size:?}: area off by {off:e}, bound {bound:e}"
        );
    }
}

#[test]
fn units_px_at_96_dpi_and_inches() {
    for file in ["svg-px.svg", "svg-inches.svg"] {
        let s = shape(file, None);
        let (lo, hi) = bbox(&s);
        let size = hi - lo;
        assert!(
            (size - Vec2::new(25.4, 12.7)).norm() < 1e-4,
            "{file}: {size:?}"
        );
        assert!((area(&s) - 25.4 * 12.7).abs() < 1e-3, "{file}");
    }
}

/// The key and message of a failed SVG file.
fn failure(src: &SvgFileSource) -> (String, String) {
    match svg_file_shape(src) {
        // The file's errors name their key: `key: message`.
        Err(e) if e.file_key().is_some() => {
            let key = e.file_key().unwrap_or_default().to_string();
            let text = e.to_string();
            let message = text.strip_prefix(&format!("{key}: ")).unwrap_or(&text);
            (key, message.to_string())
        }
        other => panic!("{:?}: expected an SVG file error, got {other:?}", src.path),
    }
}

#[test]
fn errors_name_the_key() {
    let scratch = std::env::temp_dir().join(format!("pfcam-svg-file-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).expect("scratch dir");
    let html = scratch.join("page.svg");
    std::fs::write(&html, "<html><body>no</body></html>").expect("write");
    let broken = scratch.join("broken.svg");
    std::fs::write(&broken, "<svg xmlns=\"http://www.w3.org/2000/svg\"><rect").expect("write");
    let huge = scratch.join("huge.svg");
    std::fs::write(
        &huge,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"5000mm\" height=\"10mm\" viewBox=\"0 0 5000 10\"><rect width=\"5000\" height=\"10\"/></svg>",
    )
    .expect("write");
    let with = |path: PathBuf, id: Option<&str>, size: SvgSize| SvgFileSource {
        path,
        ..source("svg-shapes.svg", id, size)
    };
    let cases: Vec<(SvgFileSource, &str, &str)> = vec![
        (
            with(test_data("absent.svg"), None, SvgSize::Natural),
            "shape.svg_file",
            "no such file",
        ),
        (
            with(test_data("DejaVu-LICENSE.txt"), None, SvgSize::Natural),
            "shape.svg_file",
            "is not an SVG document",
        ),
        (
            with(test_data("DejaVuSerif.ttf"), None, SvgSize::Natural),
            "shape.svg_file",
            "not UTF-8",
        ),
        (
            with(html, None, SvgSize::Natural),
            "shape.svg_file",
            "root element is <html>",
        ),
        (
            with(broken, None, SvgSize::Natural),
            "shape.svg_file",
            "is not an SVG document",
        ),
        (
            with(test_data("svg-strokes.svg"), None, SvgSize::Natural),
            "shape.svg_file",
            "fills nothing",
        ),
        (
            with(test_data("svg-text.svg"), None, SvgSize::Natural),
            "shape.svg_file",
            "has text (<text> at line 3",
        ),
        (
            with(test_data("svg-shapes.svg"), Some("nope"), SvgSize::Natural),
            "shape.id",
            "ids there: tile, circle",
        ),
        (
            with(test_data("svg-shapes.svg"), Some("tile"), SvgSize::Natural),
            "shape.id",
            "draws nothing",
        ),
        (
            with(huge.clone(), None, SvgSize::Natural),
            "shape.svg_file",
            "5000.0 × 10.0 mm, larger than the 2000 mm",
        ),
        (
            with(test_data("svg-shapes.svg"), None, SvgSize::Scale(30.0)),
            "shape.scale",
            "larger than the 2000 mm",
        ),
        (
            with(test_data("svg-shapes.svg"), None, SvgSize::Width(5000.0)),
            "shape.width",
            "larger than",
        ),
        (
            with(huge, None, SvgSize::Height(20.0)),
            "shape.height",
            "10000.0 × 20.0 mm",
        ),
    ];
    for (src, key, words) in cases {
        let (k, m) = failure(&src);
        assert_eq!(k, key, "{:?}: {m}", src.path);
        assert!(m.contains(words), "{:?}: {m}", src.path);
    }
    std::fs::remove_dir_all(&scratch).ok();
}

#[test]
fn a_job_names_the_file_key_and_resolves_it_beside_the_job() {
    let job = |shape: &str| {
        format!("[shape]\n{shape}\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\n")
    };
    let base = root().join("tests");
    let j = parse_job(
        &job("svg_file = \"data/svg-shapes.svg\"\nid = \"circle\"\nwidth = 30.0"),
        "x",
        &base,
    )
    .expect("job");
    let ShapeSource::SvgFile(f) = &j.shape else {
        panic!("{:?}", j.shape)
    };
    assert_eq!(f.path, base.join("data/svg-shapes.svg"));
    assert_eq!(f.size, SvgSize::Width(30.0));
    assert_eq!(f.tolerance, j.operation.tolerance);
    let s = build_shape(&j.shape).expect("shape");
    let (lo, hi) = bbox(&s);
    assert!((hi.x - lo.x - 30.0).abs() < 1e-9);
    let err = |shape: &str| parse_job(&job(shape), "x", &base).unwrap_err().to_string();
    assert!(err("svg_file = \"data/absent.svg\"").starts_with("shape.svg_file: no such file"));
    assert!(err("svg_file = \"data\"").starts_with("shape.svg_file is a directory"));
    assert!(
        err("svg_file = \"data/svg-px.svg\"\nscale = 2.0\nwidth = 3.0")
            .starts_with("shape.scale and shape.width")
    );
    assert!(err("svg_file = \"data/svg-px.svg\"\nscale = 0").starts_with("shape.scale must be"));
    assert!(err("svg_file = \"data/svg-px.svg\"\nwidth = 3000").starts_with("shape.width must be"));
    assert!(
        err("svg_file = \"data/svg-px.svg\"\nid = \"\"").starts_with("shape.id must not be empty")
    );
    assert!(err("svg_file = \"data/svg-px.svg\"\nfont = \"paper\"")
        .starts_with("shape.font only applies"));
    assert!(err("svg_path = \"M0 0 H1 V1 Z\"\nid = \"a\"")
        .starts_with("shape.id only applies to shape.svg_file"));
    assert!(err("text = \"A\"\nsvg_file = \"data/svg-px.svg\"")
        .starts_with("shape.text and shape.svg_file"));
}
