//! `shape.dxf_file`: DXF drawings read through the `dxf` crate, on drawings
//! written for the purpose by `tests/data/make_dxf.py` (ezdxf), every shape on
//! its own layer. Outlines are compared with the analytic shapes they draw
//! (areas within the flattening's bound, boxes, holes), units from
//! `$INSUNITS`; then the errors, each naming its key.

use std::f64::consts::PI;
use std::path::PathBuf;

use pfcam::geometry::dxffile::{dxf_file_shape, DxfFileSource, FLATTEN_FRACTION};
use pfcam::geometry::{build_shape, Shape, ShapeSource, Vec2};
use pfcam::job::parse_job;

use crate::common::{area, holes, perimeter, root, test_data};

/// The job's default tolerance, mm.
const TOL: f64 = 0.01;

/// What the fill's planar graph moves a vertex by (snapped to a grid of 2³⁰
/// steps across the drawing: 2e-7 mm for the 200 mm test drawing), with room.
const SNAP: f64 = 1e-6;

/// The closed periodic rational cubic on layer SPLINE: its area by ezdxf's own
/// NURBS evaluator, shoelace over 200 000 points (printed by
/// `python3 tests/data/make_dxf.py`: 382.621211193).
const SPLINE_AREA: f64 = 382.621211193;
/// The clamped cubic closed by a LINE on layer SPLINE_OPEN, the same way:
/// 437.624999973.
const SPLINE_OPEN_AREA: f64 = 437.624999973;

fn source(file: &str, layer: Option<&str>) -> DxfFileSource {
    DxfFileSource {
        path: test_data(file),
        layer: layer.map(str::to_string),
        join_tolerance: 0.01,
        origin: Vec2::ZERO,
        tolerance: TOL,
        max_size: 2000.0,
    }
}

fn layer(name: &str) -> Shape {
    dxf_file_shape(&source("dxf-entities.dxf", Some(name)))
        .unwrap_or_else(|e| panic!("layer {name}: {e}"))
}

fn size(s: &Shape) -> Vec2 {
    let (lo, hi) = s.tight_bbox().expect("a shape has a box");
    hi - lo
}

/// Chords within `TOL` × `FLATTEN_FRACTION` of the curve move the boundary by
/// at most that, so the area by at most perimeter times it.
fn assert_area(s: &Shape, want: f64, what: &str) {
    let got = area(s);
    let bound = perimeter(s) * TOL * FLATTEN_FRACTION;
    assert!(
        (got - want).abs() <= bound,
        "{what}: area {got:.6}, want {want:.6} within {bound:.6}"
    );
}

#[test]
fn a_circle_has_area_pi_r_squared_and_its_vertices_on_the_circle() {
    let s = layer("CIRCLE");
    assert_eq!((s.regions.len(), holes(&s)), (1, 0));
    assert_area(&s, PI * 100.0, "circle r 10");
    let d = size(&s);
    assert!(
        (d.x - 20.0).abs() < TOL && (d.y - 20.0).abs() < TOL,
        "{d:?}"
    );
    // Every vertex is on the circle about their mean (the centre of a regular
    // polygon), but for the fill's snapping.
    let segs = &s.regions[0].outline.segments;
    let c = segs.iter().fold(Vec2::ZERO, |a, g| a + g.start()) * (1.0 / segs.len() as f64);
    let mut n = 0;
    for seg in segs {
        assert!((seg.start().dist(c) - 10.0).abs() < SNAP);
        n += 1;
    }
    // Chords of sagitta 0.0025 on r 10: 2 acos(1 - 0.00025) is 0.04472 rad,
    // 141 a turn.
    assert_eq!(n, 141);
}

#[test]
fn lines_out_of_order_with_a_gap_make_a_rectangle() {
    let s = layer("LINES");
    assert_eq!((s.regions.len(), holes(&s)), (1, 0));
    // Straight edges: exact (to the snapping), the 0.004 mm gap along an edge
    // adds no area.
    assert!((area(&s) - 600.0).abs() < SNAP * 100.0, "{}", area(&s));
    let d = size(&s);
    assert!(
        (d.x - 30.0).abs() < 0.005 && (d.y - 20.0).abs() < SNAP,
        "{d:?}"
    );
}

#[test]
fn polylines_with_bulges_make_a_stadium_and_a_rounded_rectangle() {
    let s = layer("LWPOLY");
    assert_eq!(s.regions.len(), 1);
    assert_area(&s, 480.0 + 64.0 * PI, "stadium");
    let d = size(&s);
    assert!(
        (d.x - 46.0).abs() < 2.0 * TOL && (d.y - 16.0).abs() < SNAP,
        "{d:?}"
    );
    let s = layer("POLYLINE");
    assert_eq!(s.regions.len(), 1);
    assert_area(&s, 800.0 - (4.0 - PI) * 25.0, "rounded rectangle");
    let d = size(&s);
    assert!(
        (d.x - 40.0).abs() < SNAP && (d.y - 20.0).abs() < SNAP,
        "{d:?}"
    );
}

#[test]
fn arcs_and_lines_make_a_slot_also_with_a_mirrored_ocs() {
    // The right arc is written with extrusion (0, 0, -1): centre (-25, 40) in
    // its OCS, angles 90 to 270 there, which is (25, 40), -90 to 90 in the world.
    let s = layer("SLOT");
    assert_eq!(s.regions.len(), 1);
    assert_area(&s, 250.0 + 25.0 * PI, "slot");
    // Each end's chords may cut up to TOL off the width.
    let d = size(&s);
    assert!(
        (d.x - 35.0).abs() < 2.0 * TOL && (d.y - 10.0).abs() < SNAP,
        "{d:?}"
    );
}

#[test]
fn ellipses_whole_and_half_have_area_pi_a_b() {
    let s = layer("ELLIPSE");
    assert_area(&s, PI * 15.0 * 7.5, "ellipse a 15 b 7.5");
    // Turned 30°: half widths √(a² cos² + b² sin²), √(a² sin² + b² cos²).
    let (c, sn) = ((PI / 6.0).cos(), (PI / 6.0).sin());
    let w = 2.0 * (225.0 * c * c + 56.25 * sn * sn).sqrt();
    let h = 2.0 * (225.0 * sn * sn + 56.25 * c * c).sqrt();
    let d = size(&s);
    assert!(
        (d.x - w).abs() < TOL && (d.y - h).abs() < TOL,
        "{d:?} vs {w} {h}"
    );
    let s = layer("HALF_ELLIPSE");
    assert_area(&s, PI * 10.0 * 6.0 / 2.0, "half ellipse");
    let d = size(&s);
    assert!(
        (d.x - 20.0).abs() < SNAP && (d.y - 6.0).abs() < TOL,
        "{d:?}"
    );
}

#[test]
fn splines_match_ezdxfs_evaluation() {
    let s = layer("SPLINE");
    assert_eq!((s.regions.len(), holes(&s)), (1, 0));
    assert_area(&s, SPLINE_AREA, "closed rational spline");
    let s = layer("SPLINE_OPEN");
    assert_eq!(s.regions.len(), 1);
    assert_area(&s, SPLINE_OPEN_AREA, "clamped spline and a line");
    // At 1e-4 mm the bound is a hundred times tighter.
    let fine = dxf_file_shape(&DxfFileSource {
        tolerance: 0.0001,
        ..source("dxf-entities.dxf", Some("SPLINE"))
    })
    .expect("fine");
    assert!((area(&fine) - SPLINE_AREA).abs() <= perimeter(&fine) * 0.0001 * FLATTEN_FRACTION);
}

#[test]
fn an_insert_scales_turns_and_makes_its_round_hole_an_ellipse() {
    // TAB (10 × 6 with a hole r 1.5) at scale 2 × 1.5, turned 30°.
    let s = layer("INSERT");
    assert_eq!((s.regions.len(), holes(&s)), (1, 1));
    assert_area(&s, (60.0 - 2.25 * PI) * 3.0, "insert");
    // The 20 × 9 rectangle turned 30°: its box.
    let (c, sn) = ((PI / 6.0).cos(), (PI / 6.0).sin());
    let d = size(&s);
    let (w, h) = (20.0 * c + 9.0 * sn, 20.0 * sn + 9.0 * c);
    assert!(
        (d.x - w).abs() < SNAP && (d.y - h).abs() < SNAP,
        "{d:?} vs {w} {h}"
    );
    // The hole is the ellipse with semi-axes 3 and 2.25.
    let hole = &s.regions[0].counters[0];
    assert!((hole.signed_area().abs() - PI * 3.0 * 2.25).abs() <= hole.length() * TOL);
}

#[test]
fn nested_inserts_with_a_mirror_keep_their_holes() {
    let s = layer("NESTED");
    assert_eq!((s.regions.len(), holes(&s)), (2, 2));
    assert_area(&s, 2.0 * 0.25 * (60.0 - 2.25 * PI), "nested");
    for r in &s.regions {
        assert!(r.outline.signed_area() > 0.0 && r.counters[0].signed_area() < 0.0);
    }
}

#[test]
fn a_hole_and_an_island_alternate_and_a_bow_tie_splits() {
    let s = layer("HOLE");
    assert_eq!((s.regions.len(), holes(&s)), (2, 1));
    assert_area(&s, 400.0 - 25.0 * PI + 4.0 * PI, "square, hole, island");
    let s = layer("BOWTIE");
    assert_eq!((s.regions.len(), holes(&s)), (2, 0));
    for r in &s.regions {
        assert!((r.outline.signed_area() - 100.0).abs() < 1e-9);
    }
}

#[test]
fn the_whole_drawing_is_every_layer_and_text_is_not_read() {
    let s = dxf_file_shape(&source("dxf-entities.dxf", None)).expect("drawing");
    assert_eq!((s.regions.len(), holes(&s)), (16, 4));
    let want = PI * 100.0 + 600.0 + 480.0 + 64.0 * PI + 800.0 - (4.0 - PI) * 25.0
        + 250.0
        + 25.0 * PI
        + PI * 112.5
        + 30.0 * PI
        + SPLINE_AREA
        + SPLINE_OPEN_AREA
        + (60.0 - 2.25 * PI) * 3.0
        + 0.5 * (60.0 - 2.25 * PI)
        + 400.0
        - 21.0 * PI
        + 200.0;
    assert_area(&s, want, "whole drawing");
    // Placed with its box's bottom-left corner at the origin.
    let (lo, _) = s.tight_bbox().expect("box");
    assert!(lo.norm() < SNAP, "{lo:?}");
    let moved = dxf_file_shape(&DxfFileSource {
        origin: Vec2::new(5.0, -7.0),
        ..source("dxf-entities.dxf", Some("circle"))
    })
    .expect("moved");
    let (lo, hi) = moved.tight_bbox().expect("box");
    assert!(lo.dist(Vec2::new(5.0, -7.0)) < SNAP && (hi.x - 25.0).abs() < TOL);
}

#[test]
fn units_come_from_insunits_and_unitless_is_mm() {
    // A 1 × 0.5 rectangle with a hole r 0.125 in both files.
    let inches = dxf_file_shape(&source("dxf-inches.dxf", None)).expect("inches");
    let d = size(&inches);
    assert!(
        (d.x - 25.4).abs() < SNAP && (d.y - 12.7).abs() < SNAP,
        "{d:?}"
    );
    assert_area(&inches, (0.5 - PI / 64.0) * 25.4 * 25.4, "inches");
    let unitless = dxf_file_shape(&source("dxf-unitless.dxf", None)).expect("unitless");
    let d = size(&unitless);
    assert!(
        (d.x - 1.0).abs() < SNAP && (d.y - 0.5).abs() < SNAP,
        "{d:?}"
    );
    assert_area(&unitless, 0.5 - PI / 64.0, "unitless");
}

fn failure(src: &DxfFileSource) -> (String, String) {
    match dxf_file_shape(src) {
        // The file's errors name their key: `key: message`.
        Err(e) if e.file_key().is_some() => {
            let key = e.file_key().unwrap_or_default().to_string();
            let text = e.to_string();
            let message = text.strip_prefix(&format!("{key}: ")).unwrap_or(&text);
            (key, message.to_string())
        }
        other => panic!("{:?}: expected a DXF file error, got {other:?}", src.path),
    }
}

#[test]
fn errors_name_the_key() {
    let scratch = std::env::temp_dir().join(format!("pfcam-dxf-file-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).expect("scratch dir");
    let half = scratch.join("half.dxf");
    let text = std::fs::read_to_string(test_data("dxf-entities.dxf")).expect("read");
    std::fs::write(&half, &text[..text.len() / 2]).expect("write");
    let with = |path: PathBuf, layer: Option<&str>| DxfFileSource {
        path,
        ..source("dxf-entities.dxf", layer)
    };
    let cases: Vec<(DxfFileSource, &str, &str)> = vec![
        (with(test_data("absent.dxf"), None), "shape.dxf_file", "no such file"),
        (with(test_data("."), None), "shape.dxf_file", "is a directory"),
        (with(test_data("DejaVu-LICENSE.txt"), None), "shape.dxf_file", "is not a DXF file"),
        (with(test_data("DejaVuSerif.ttf"), None), "shape.dxf_file", "is not a DXF file"),
        (with(test_data("svg-shapes.svg"), None), "shape.dxf_file", "is not a DXF file"),
        (with(half, None), "shape.dxf_file", "DXF"),
        (
            with(test_data("dxf-entities.dxf"), Some("EMPTY")),
            "shape.layer",
            "\"EMPTY\" has no closed geometry in the drawing (layers with entities pfcam reads: BOWTIE, CIRCLE, ELLIPSE, HALF_ELLIPSE, HOLE, INSERT, LINES, LWPOLY, NESTED, POLYLINE, SLOT, SPLINE and 1 more)",
        ),
        (with(test_data("dxf-entities.dxf"), Some("NOTES")), "shape.layer", "has no closed geometry"),
        (with(test_data("dxf-entities.dxf"), Some("nope")), "shape.layer", "has no closed geometry"),
        (
            with(test_data("dxf-open.dxf"), None),
            "shape.dxf_file",
            "has 1 open contour (in the drawing's coordinates, mm): one with its ends at (5, 15) and (0, 0); every contour must close, its pieces' ends meeting within shape.join_tolerance = 0.01 mm",
        ),
        (
            with(test_data("dxf-huge.dxf"), None),
            "shape.dxf_file",
            "makes the drawing 5000.0 × 5000.0 mm, larger than the 2000 mm",
        ),
        (
            DxfFileSource {
                join_tolerance: 0.001,
                ..source("dxf-entities.dxf", Some("LINES"))
            },
            "shape.dxf_file",
            "with its ends at (50, -10) and (50.004, -10)",
        ),
        (
            DxfFileSource {
                tolerance: 1e-9,
                ..source("dxf-entities.dxf", None)
            },
            "shape.dxf_file",
            "is too detailed",
        ),
    ];
    for (src, key, words) in cases {
        let (k, m) = failure(&src);
        assert_eq!(k, key, "{:?} {:?}: {m}", src.path, src.layer);
        assert!(m.contains(words), "{:?} {:?}: {m}", src.path, src.layer);
    }
    std::fs::remove_dir_all(&scratch).ok();
}

/// Cut, repeated or changed bytes of the test drawing give a shape or an
/// error, never a panic (a fixed seed, so a failure repeats).
#[test]
fn mangled_drawings_never_panic() {
    let bytes = std::fs::read(test_data("dxf-entities.dxf")).expect("read");
    let scratch = std::env::temp_dir().join(format!("pfcam-dxf-mangle-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).expect("scratch dir");
    let mut seed: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    let (mut ok, mut err) = (0, 0);
    for i in 0..1000 {
        let mut b = bytes.clone();
        for _ in 0..1 + next() % 8 {
            if b.is_empty() {
                break;
            }
            let at = (next() as usize) % b.len();
            match next() % 4 {
                0 => b[at] = b"0123456789-.eE \n"[(next() % 16) as usize],
                1 => {
                    b.remove(at);
                }
                2 => b.truncate(at.max(1)),
                _ => {
                    let end = (at + (next() as usize) % 64).min(b.len());
                    let piece = b[at..end].to_vec();
                    b.splice(at..at, piece);
                }
            }
        }
        let path = scratch.join(format!("m{i}.dxf"));
        std::fs::write(&path, &b).expect("write");
        match dxf_file_shape(&DxfFileSource {
            path,
            ..source("dxf-entities.dxf", None)
        }) {
            Ok(_) => ok += 1,
            Err(e) if e.file_key().is_some() => err += 1,
            Err(e) => panic!("{i}: not a DXF file error: {e}"),
        }
    }
    assert!(ok > 0 && err > 0, "{ok} shapes, {err} errors");
    std::fs::remove_dir_all(&scratch).ok();
}

#[test]
fn a_job_names_the_file_key_and_resolves_it_beside_the_job() {
    let job = |shape: &str| {
        format!("[shape]\n{shape}\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 3.0\ntolerance = 0.02\n")
    };
    let base = root().join("tests");
    let j = parse_job(
        &job("dxf_file = \"data/dxf-entities.dxf\"\nlayer = \"CIRCLE\"\njoin_tolerance = 0.05"),
        "x",
        &base,
    )
    .expect("job");
    let ShapeSource::DxfFile(f) = &j.shape else {
        panic!("{:?}", j.shape)
    };
    assert_eq!(f.path, base.join("data/dxf-entities.dxf"));
    assert_eq!(f.layer.as_deref(), Some("CIRCLE"));
    assert_eq!((f.join_tolerance, f.tolerance), (0.05, 0.02));
    let s = build_shape(&j.shape).expect("shape");
    assert!((size(&s).x - 20.0).abs() < 0.02);
    let j = parse_job(&job("dxf_file = \"data/dxf-inches.dxf\""), "x", &base).expect("job");
    let ShapeSource::DxfFile(f) = &j.shape else {
        panic!("{:?}", j.shape)
    };
    assert_eq!((f.layer.as_deref(), f.join_tolerance), (None, 0.01));
    let err = |shape: &str| parse_job(&job(shape), "x", &base).unwrap_err().to_string();
    assert!(err("dxf_file = \"data/absent.dxf\"").starts_with("shape.dxf_file: no such file"));
    assert!(err("dxf_file = \"data\"").starts_with("shape.dxf_file is a directory"));
    assert!(err("dxf_file = \"\"").starts_with("shape.dxf_file must not be empty"));
    assert!(err("dxf_file = \"data/dxf-inches.dxf\"\nlayer = \" \"")
        .starts_with("shape.layer must not be empty"));
    assert!(
        err("dxf_file = \"data/dxf-inches.dxf\"\njoin_tolerance = 0")
            .starts_with("shape.join_tolerance must be")
    );
    assert!(
        err("dxf_file = \"data/dxf-inches.dxf\"\njoin_tolerance = 11")
            .starts_with("shape.join_tolerance must be")
    );
    assert!(err("dxf_file = \"data/dxf-inches.dxf\"\nheight = 20")
        .starts_with("shape.height does not apply to shape.dxf_file"));
    assert!(err("svg_path = \"M0 0 H1 V1 Z\"\nlayer = \"a\"")
        .starts_with("shape.layer only applies to shape.dxf_file"));
    assert!(err("svg_path = \"M0 0 H1 V1 Z\"\njoin_tolerance = 0.1")
        .starts_with("shape.join_tolerance only applies to shape.dxf_file"));
    assert!(
        err("svg_file = \"data/svg-px.svg\"\ndxf_file = \"data/dxf-inches.dxf\"")
            .starts_with("shape.svg_file and shape.dxf_file")
    );
}

/// docs/shapes.md's figures for the test drawing: each layer's area at the
/// default tolerance against the analytic (or ezdxf's) area, within the bound
/// perimeter × tolerance (`cargo test --release --test all --
/// --nocapture dxf_file::layer_figures` prints them).
#[test]
fn layer_figures() {
    let tab = 60.0 - 2.25 * PI;
    let rows: [(&str, f64); 13] = [
        ("CIRCLE", 100.0 * PI),
        ("LINES", 600.0),
        ("LWPOLY", 480.0 + 64.0 * PI),
        ("POLYLINE", 800.0 - (4.0 - PI) * 25.0),
        ("SLOT", 250.0 + 25.0 * PI),
        ("ELLIPSE", 112.5 * PI),
        ("HALF_ELLIPSE", 30.0 * PI),
        ("SPLINE", SPLINE_AREA),
        ("SPLINE_OPEN", SPLINE_OPEN_AREA),
        ("INSERT", 3.0 * tab),
        ("NESTED", 0.5 * tab),
        ("HOLE", 400.0 - 21.0 * PI),
        ("BOWTIE", 200.0),
    ];
    for (name, want) in rows {
        let s = layer(name);
        let vertices: usize = s.contours().map(|c| c.segments.len()).sum();
        eprintln!(
            "| {name} | {want:.4} | {:.4} | {:+.4} | {:.4} | {vertices} |",
            area(&s),
            area(&s) - want,
            perimeter(&s) * TOL * FLATTEN_FRACTION
        );
        assert_area(&s, want, name);
    }
    let t = std::time::Instant::now();
    let s = dxf_file_shape(&source("dxf-entities.dxf", None)).expect("drawing");
    let vertices: usize = s.contours().map(|c| c.segments.len()).sum();
    eprintln!(
        "whole drawing: {} regions, {vertices} vertices, {:?}",
        s.regions.len(),
        t.elapsed()
    );
}

/// Drawings written here with the dxf crate itself: a block that inserts
/// itself, an INSERT of a missing block, a SPLINE with fit points only, a
/// circle with a NaN radius, a MINSERT of a million copies.
#[test]
fn hostile_drawings_give_errors() {
    use dxf::entities::{Circle, Entity, EntityType, Insert, Spline};
    use dxf::{Block, Drawing, Point};
    let scratch = std::env::temp_dir().join(format!("pfcam-dxf-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).expect("scratch dir");
    let insert = |name: &str, rows: i16| {
        Entity::new(EntityType::Insert(Insert {
            name: name.into(),
            row_count: rows,
            column_count: rows,
            ..Default::default()
        }))
    };
    let write = |name: &str, build: &dyn Fn(&mut Drawing)| {
        let mut d = Drawing::new();
        d.header.version = dxf::enums::AcadVersion::R2000;
        build(&mut d);
        let path = scratch.join(name);
        d.save_file(&path).expect("save");
        path
    };
    let self_insert = write("self.dxf", &|d| {
        d.add_block(Block {
            name: "LOOP".into(),
            entities: vec![insert("LOOP", 1)],
            ..Default::default()
        });
        d.add_entity(insert("LOOP", 1));
    });
    let missing = write("missing.dxf", &|d| {
        d.add_entity(insert("NOPE", 1));
    });
    let fit = write("fit.dxf", &|d| {
        d.add_entity(Entity::new(EntityType::Spline(Spline {
            degree_of_curve: 3,
            fit_points: vec![Point::new(0.0, 0.0, 0.0), Point::new(1.0, 1.0, 0.0)],
            ..Default::default()
        })));
    });
    let nan = write("nan.dxf", &|d| {
        d.add_entity(Entity::new(EntityType::Circle(Circle::new(
            Point::new(0.0, 0.0, 0.0),
            f64::NAN,
        ))));
    });
    let many = write("many.dxf", &|d| {
        d.add_block(Block {
            name: "DOT".into(),
            entities: vec![Entity::new(EntityType::Circle(Circle::new(
                Point::new(0.0, 0.0, 0.0),
                0.1,
            )))],
            ..Default::default()
        });
        d.add_entity(insert("DOT", 1000));
    });
    let cases = [
        (self_insert, "nests INSERTs deeper than 16"),
        (missing, "INSERT of block \"NOPE\""),
        (fit, "given by fit points only"),
        (nan, "not a finite number"),
        (many, "has more than 500000 entities"),
    ];
    for (path, words) in cases {
        let (k, m) = failure(&DxfFileSource {
            path: path.clone(),
            ..source("dxf-entities.dxf", None)
        });
        assert_eq!(k, "shape.dxf_file", "{path:?}: {m}");
        assert!(m.contains(words), "{path:?}: {m}");
    }
    std::fs::remove_dir_all(&scratch).ok();
}
