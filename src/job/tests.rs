//! Tests of the whole parse: job text in, a resolved [`Job`] or the error
//! naming its key out, for every table; and the fixtures the modules' own
//! tests share (`GOOD`, `with`, `err_key`, the paper's letter `Q`).

use super::*;
use crate::geometry::{BoolOp, Composition, FontSource, Part, PartSource, Vec2};

pub(super) const GOOD: &str = r#"
[job]
name = "letter-a"
[shape]
text = "A"
height = 50.0
[tool]
diameter = 3.175
[operation]
depth = 3.0
"#;

pub(super) fn parse(text: &str) -> Result<Job, JobError> {
    parse_job(text, "hint", Path::new("."))
}

/// `GOOD` with `line` added under `[table]` (the table is created if absent).
pub(super) fn with(table: &str, line: &str) -> String {
    let header = format!("[{table}]\n");
    if GOOD.contains(&header) {
        GOOD.replace(&header, &format!("{header}{line}\n"))
    } else {
        format!("{GOOD}{header}{line}\n")
    }
}

pub(super) fn err_key(text: &str) -> (String, String) {
    match parse(text) {
        Ok(j) => panic!("expected an error, got {j:?}"),
        Err(e) => (e.key().unwrap_or("").to_string(), e.to_string()),
    }
}

#[test]
fn good_job_gets_defaults() {
    let j = parse(GOOD).unwrap();
    assert_eq!(j.name, "letter-a");
    assert_eq!(j.tool.feed, defaults::FEED);
    assert_eq!(j.tool.plunge_feed, defaults::PLUNGE_FEED);
    assert_eq!(j.stock.safe_z, 5.0);
    assert_eq!(j.operation.tolerance, 0.01);
    assert_eq!(j.operation.direction, Direction::Climb);
    assert_eq!(j.field, FieldSpec::default());
    assert_eq!(j.machine, Machine::default());
    assert_eq!(j.output, Output::default());
    assert!(j.output.arcs && !j.machine.coolant);
    assert_eq!(j.output.max_arc_radius, 1000.0);
    match j.shape {
        ShapeSource::Text {
            font,
            letter_spacing,
            height,
            ..
        } => {
            assert_eq!(font, FontSource::Paper);
            assert_eq!(letter_spacing, 3.175);
            assert_eq!(height, 50.0);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn negative_diameter() {
    let (k, msg) = err_key(&GOOD.replace("diameter = 3.175", "diameter = -3"));
    assert_eq!(k, "tool.diameter");
    assert_eq!(msg, "tool.diameter must be a positive number of mm, got -3");
}

#[test]
fn missing_required_keys() {
    assert_eq!(
        err_key(&GOOD.replace("diameter = 3.175", "")).0,
        "tool.diameter"
    );
    assert_eq!(
        err_key(&GOOD.replace("depth = 3.0", "")).0,
        "operation.depth"
    );
    assert_eq!(err_key(&GOOD.replace("text = \"A\"", "")).0, "shape.text");
}

#[test]
fn depth_must_be_positive() {
    for d in ["0.0", "-1", "nan", "inf"] {
        let (k, msg) = err_key(&GOOD.replace("depth = 3.0", &format!("depth = {d}")));
        assert_eq!(k, "operation.depth");
        assert!(msg.contains("must be > 0"), "{msg}");
    }
}

#[test]
fn feeds_stepdown_spindle() {
    assert_eq!(err_key(&with("tool", "feed = 0")).0, "tool.feed");
    assert_eq!(
        err_key(&with("tool", "plunge_feed = -5")).0,
        "tool.plunge_feed"
    );
    assert_eq!(err_key(&with("tool", "stepdown = 0")).0, "tool.stepdown");
    assert_eq!(err_key(&with("tool", "spindle = -1")).0, "tool.spindle");
    assert_eq!(
        parse(&with("tool", "spindle = 0")).unwrap().tool.spindle,
        0.0
    );
}

#[test]
fn tolerance_positive_and_below_radius() {
    assert_eq!(
        err_key(&with("operation", "tolerance = 0")).0,
        "operation.tolerance"
    );
    let (k, msg) = err_key(&with("operation", "tolerance = 2"));
    assert_eq!(k, "operation.tolerance");
    assert!(msg.contains("tool radius"), "{msg}");
}

#[test]
fn safe_z_above_top() {
    let (k, msg) = err_key(&with("stock", "top = 2.0\nsafe_z = 1.0"));
    assert_eq!(k, "stock.safe_z");
    assert!(msg.contains("above stock.top (2)"), "{msg}");
    let j = parse(&with("stock", "top = 2.0")).unwrap();
    assert_eq!(j.stock.safe_z, 7.0);
}

#[test]
fn retract_z_between_top_and_safe_z() {
    for bad in ["retract_z = 6.0", "retract_z = 0.0", "retract_z = -1.0"] {
        let (k, msg) = err_key(&with("stock", &format!("safe_z = 5.0\n{bad}")));
        assert_eq!(k, "stock.retract_z", "{bad}");
        assert!(msg.contains("at most stock.safe_z (5)"), "{msg}");
    }
    let j = parse(&with("stock", "safe_z = 5.0\nretract_z = 1.0")).unwrap();
    assert_eq!((j.stock.safe_z, j.stock.retract_z), (5.0, 1.0));
    let j = parse(&with("stock", "safe_z = 4.0")).unwrap();
    assert_eq!(j.stock.retract_z, 4.0);
}

#[test]
fn exactly_one_shape_source() {
    let (k, msg) = err_key(&with("shape", "svg_path = \"M0 0 L1 0 L1 1 Z\""));
    assert_eq!(k, "shape.text");
    assert!(msg.contains("exactly one"), "{msg}");
    let svg = GOOD.replace("text = \"A\"", "svg_path = \"M0 0 L10 0 L10 10 Z\"");
    assert_eq!(
        err_key(&svg.replace("height = 50.0", "font = \"paper\"")).0,
        "shape.font"
    );
    let j = parse(&svg.replace("height = 50.0", "")).unwrap();
    assert!(matches!(j.shape, ShapeSource::SvgPath { height: None, .. }));
}

#[test]
fn glyph_missing_from_paper_font() {
    let (k, msg) = err_key(&GOOD.replace("text = \"A\"", "text = \"AZ\""));
    assert_eq!(k, "shape.text");
    assert!(msg.contains("no glyph") && msg.contains("'Z'"), "{msg}");
}

#[test]
fn missing_font_file_is_resolved_against_the_job_dir() {
    let text = with("shape", "font = \"fonts/nope.ttf\"");
    let e = parse_job(&text, "x", Path::new("/some/dir")).unwrap_err();
    assert_eq!(e.key(), Some("shape.font"));
    assert_eq!(
        e.to_string(),
        "shape.font: no such file: /some/dir/fonts/nope.ttf"
    );
}

#[test]
fn enums_list_accepted_values() {
    let (k, msg) = err_key(&with("operation", "kind = \"pocket\""));
    assert_eq!(k, "operation.kind");
    assert!(
        msg.contains("`pocket`") && msg.contains("`profile`"),
        "{msg}"
    );
    assert_eq!(
        err_key(&with("operation", "side = \"inside\"")).0,
        "operation.side"
    );
    assert_eq!(
        err_key(&with("operation", "direction = \"up\"")).0,
        "operation.direction"
    );
    let j = parse(&with("operation", "direction = \"conventional\"")).unwrap();
    assert_eq!(j.operation.direction, Direction::Conventional);
}

#[test]
fn field_auto_or_number() {
    let j = parse(&with("field", "singularities = 400\npseudo_boundary = 5")).unwrap();
    assert_eq!(j.field.singularities, Some(400));
    assert_eq!(j.field.pseudo_boundary, Some(5.0));
    let j = parse(&with(
        "field",
        "singularities = \"auto\"\npseudo_boundary = \"auto\"",
    ))
    .unwrap();
    assert_eq!(j.field, FieldSpec::default());
    assert_eq!(
        err_key(&with("field", "singularities = 0")).0,
        "field.singularities"
    );
    assert_eq!(
        err_key(&with("field", "singularities = \"many\"")).0,
        "field.singularities"
    );
    assert_eq!(
        err_key(&with("field", "pseudo_boundary = -2.0")).0,
        "field.pseudo_boundary"
    );
    let (k, msg) = err_key(&with("field", "singularities = 12.5"));
    assert_eq!(k, "field.singularities");
    assert!(msg.contains("whole number"), "{msg}");
    let (k, msg) = err_key(&with("field", "pseudo_boundary = true"));
    assert_eq!(k, "field.pseudo_boundary");
    assert!(msg.contains("\"auto\" or a number"), "{msg}");
}

/// The paper's letter Q (Section 5): (m2 ∪ m5) − m3.
pub(super) const Q: &str = r#"
[job]
name = "letter-q"
[tool]
diameter = 3.175
[operation]
depth = 3.0
[shape]
height = 60.0
origin = [10.0, 10.0]
result = "Q"

[[shape.part]]
name = "m1"
polygon = [[0, 0], [100, 0], [100, 300], [0, 300]]

[[shape.part]]
name = "m2"
of = "m1"
level = 0.85

[[shape.part]]
name = "m3"
of = ["m1"]
level = 0.95

[[shape.part]]
name = "m4"
polygon = [
[20, 70], [50, 120], [100, 120], [280, 20],
[300, 50], [270, 20], [100, 90], [50, 90],
]

[[shape.part]]
name = "m5"
of = "m4"
level = 0.97
singularities = 300

[[shape.part]]
name = "m6"
op = "union"
of = ["m2", "m5"]

[[shape.part]]
name = "Q"
op = "subtract"
of = ["m6", "m3"]
"#;

fn pts(p: &[[f64; 2]]) -> PartSource {
    PartSource::Polygon(p.iter().map(|&[x, y]| Vec2::new(x, y)).collect())
}

fn part(name: &str, source: PartSource, level: Option<f64>) -> Part {
    Part {
        name: name.into(),
        source,
        level,
        singularities: None,
    }
}

fn names(n: &[&str]) -> Vec<String> {
    n.iter().map(|s| s.to_string()).collect()
}

/// `Q` with `from` replaced by `to` (which must occur).
pub(super) fn q_with(from: &str, to: &str) -> String {
    assert!(Q.contains(from), "{from}");
    Q.replacen(from, to, 1)
}

/// The error of `text`: its key and message; the message must contain every
/// one of `needles`.
fn q_err(text: &str, key: &str, needles: &[&str]) {
    let (k, msg) = err_key(text);
    assert_eq!(k, key, "{msg}");
    assert!(msg.starts_with(key), "{msg}");
    for n in needles {
        assert!(msg.contains(n), "{n:?} not in: {msg}");
    }
}

#[test]
fn letter_q_parses_to_its_composition() {
    let j = parse(Q).unwrap();
    let mut m5 = part("m5", PartSource::Ref("m4".into()), Some(0.97));
    m5.singularities = Some(300);
    let expected = Composition {
        parts: vec![
            part(
                "m1",
                pts(&[[0.0, 0.0], [100.0, 0.0], [100.0, 300.0], [0.0, 300.0]]),
                None,
            ),
            part("m2", PartSource::Ref("m1".into()), Some(0.85)),
            part("m3", PartSource::Ref("m1".into()), Some(0.95)),
            part(
                "m4",
                pts(&[
                    [20.0, 70.0],
                    [50.0, 120.0],
                    [100.0, 120.0],
                    [280.0, 20.0],
                    [300.0, 50.0],
                    [270.0, 20.0],
                    [100.0, 90.0],
                    [50.0, 90.0],
                ]),
                None,
            ),
            m5,
            part(
                "m6",
                PartSource::Op {
                    op: BoolOp::Union,
                    of: names(&["m2", "m5"]),
                },
                None,
            ),
            part(
                "Q",
                PartSource::Op {
                    op: BoolOp::Subtract,
                    of: names(&["m6", "m3"]),
                },
                None,
            ),
        ],
        result: "Q".into(),
        height: Some(60.0),
        origin: Vec2::new(10.0, 10.0),
    };
    assert_eq!(j.shape, ShapeSource::Composite(expected));
}

#[test]
fn composition_defaults() {
    // No result: the last part. No height: 1 design unit = 1 mm. Text parts.
    let text = GOOD.replace(
        "text = \"A\"\nheight = 50.0",
        "[[shape.part]]\nname = \"t\"\ntext = \"AH\"\n\n[[shape.part]]\nname = \"big\"\ntext = \"I\"\nsize = 30\nfont = \"paper\"\n\n[[shape.part]]\nname = \"out\"\nop = \"invert\"\nof = \"t\"\n\n[[shape.part]]\nname = \"cut\"\nop = \"intersect\"\nof = [\"big\", \"out\"]\nlevel = 0.5",
    );
    let j = parse(&text).unwrap();
    let ShapeSource::Composite(c) = j.shape else {
        panic!("{:?}", j.shape)
    };
    assert_eq!(c.result, "cut");
    assert_eq!(c.height, None);
    assert_eq!(c.origin, Vec2::ZERO);
    assert_eq!(
        c.parts[0].source,
        PartSource::Text {
            text: "AH".into(),
            font: FontSource::Paper,
            size: defaults::PART_TEXT_SIZE,
        }
    );
    assert!(matches!(c.parts[1].source, PartSource::Text { size, .. } if size == 30.0));
    assert_eq!(
        c.parts[2].source,
        PartSource::Op {
            op: BoolOp::Invert,
            of: names(&["t"]),
        }
    );
    assert_eq!(c.parts[3].level, Some(0.5));
    // svg parts, and singularities = "auto".
    let j = parse(&q_with(
        "polygon = [[0, 0], [100, 0], [100, 300], [0, 300]]",
        "svg = \"M0 0 H100 V300 H0 Z\"\nsingularities = \"auto\"",
    ))
    .unwrap();
    let ShapeSource::Composite(c) = j.shape else {
        panic!()
    };
    assert_eq!(
        c.parts[0].source,
        PartSource::Svg("M0 0 H100 V300 H0 Z".into())
    );
    assert_eq!(c.parts[0].singularities, None);
}

#[test]
fn part_names_and_references() {
    q_err(
        &q_with("of = [\"m6\", \"m3\"]", "of = [\"m6\", \"m7\"]"),
        "shape.part[7].of",
        &[
            "unknown part \"m7\"",
            "defined before it: m1, m2, m3, m4, m5, m6",
        ],
    );
    q_err(
        &q_with("of = \"m1\"\nlevel = 0.85", "of = \"m3\"\nlevel = 0.85"),
        "shape.part[2].of",
        &["\"m3\", which is defined after it", "defined before it: m1"],
    );
    q_err(
        &q_with("of = \"m1\"\nlevel = 0.85", "of = \"m2\"\nlevel = 0.85"),
        "shape.part[2].of",
        &["the part itself, \"m2\""],
    );
    q_err(
        &q_with("name = \"m3\"", "name = \"m2\""),
        "shape.part[3].name",
        &["\"m2\" is already the name of shape.part[2]"],
    );
    q_err(
        &q_with("name = \"m4\"", "name = \" \""),
        "shape.part[4].name",
        &["must not be empty"],
    );
    q_err(
        &q_with("name = \"m4\"\n", ""),
        "shape.part[4].name",
        &["is required"],
    );
    q_err(
        &q_with("of = [\"m2\", \"m5\"]", "of = [\"m2\", \"m2\"]"),
        "shape.part[6].of",
        &["\"m2\" twice"],
    );
    q_err(
        &q_with("of = [\"m2\", \"m5\"]", "of = []"),
        "shape.part[6].of",
        &["at least one", "[]"],
    );
    q_err(
        &q_with("result = \"Q\"", "result = \"q\""),
        "shape.result",
        &["unknown part \"q\"", "m1, m2, m3, m4, m5, m6, Q"],
    );
}

#[test]
fn part_ops_and_operand_counts() {
    q_err(
        &q_with("op = \"union\"", "op = \"merge\""),
        "shape.part[6].op",
        &[
            "`merge`",
            "`union`",
            "`intersect`",
            "`subtract`",
            "`invert`",
        ],
    );
    q_err(
        &q_with(
            "op = \"union\"\nof = [\"m2\", \"m5\"]",
            "op = \"union\"\nof = \"m2\"",
        ),
        "shape.part[6].of",
        &["at least 2 parts", "op = \"union\"", "got 1 (\"m2\")"],
    );
    q_err(
        &q_with(
            "op = \"subtract\"\nof = [\"m6\", \"m3\"]",
            "op = \"subtract\"\nof = [\"m6\"]",
        ),
        "shape.part[7].of",
        &[
            "at least 2 parts (the first minus the others)",
            "\"subtract\"",
        ],
    );
    q_err(
        &q_with("op = \"union\"", "op = \"intersect\"\nof = \"m2\"")
            .replace("of = \"m2\"\nof = [\"m2\", \"m5\"]", "of = \"m2\""),
        "shape.part[6].of",
        &["at least 2 parts", "\"intersect\""],
    );
    q_err(
        &q_with("op = \"union\"", "op = \"invert\""),
        "shape.part[6].of",
        &["exactly 1 part", "got 2 (\"m2\", \"m5\")"],
    );
    q_err(
        &q_with("op = \"union\"\n", ""),
        "shape.part[6].op",
        &["is required when shape.part[6].of names several parts"],
    );
    q_err(
        &q_with("of = \"m1\"\nlevel = 0.85", "of = \"m1\""),
        "shape.part[2].level",
        &["is required", "plain copy of \"m1\""],
    );
    q_err(
        &q_with("op = \"union\"\nof = [\"m2\", \"m5\"]", "op = \"union\""),
        "shape.part[6].op",
        &["needs shape.part[6].of"],
    );
}

#[test]
fn part_sources_exclude_each_other() {
    q_err(
        &q_with(
            "name = \"m5\"\nof = \"m4\"",
            "name = \"m5\"\nof = \"m4\"\npolygon = [[0, 0], [1, 0], [0, 1]]",
        ),
        "shape.part[5].of",
        &["cannot be combined with shape.part[5].polygon"],
    );
    q_err(
        &q_with(
            "op = \"union\"\n",
            "op = \"union\"\nsvg = \"M0 0 L1 0 L0 1 Z\"\n",
        ),
        "shape.part[6].of",
        &["cannot be combined with shape.part[6].svg"],
    );
    q_err(
        &q_with("name = \"m1\"\n", "name = \"m1\"\ntext = \"I\"\n"),
        "shape.part[1].polygon",
        &["and shape.part[1].text are both given"],
    );
    q_err(
        &q_with(
            "name = \"m6\"\nop = \"union\"\nof = [\"m2\", \"m5\"]\n",
            "name = \"m6\"\n",
        ),
        "shape.part[6]",
        &["has no source", "polygon, svg or text", "of"],
    );
    q_err(
        &q_with("name = \"m1\"\n", "name = \"m1\"\nsize = 20\n"),
        "shape.part[1].size",
        &["only applies to a text part"],
    );
    q_err(
        &q_with("name = \"m1\"\n", "name = \"m1\"\nfont = \"paper\"\n"),
        "shape.part[1].font",
        &["only applies to a text part"],
    );
}

#[test]
fn part_values_are_checked() {
    for (l, shown) in [
        ("1.2", "1.2"),
        ("0", "0"),
        ("1", "1"),
        ("-0.5", "-0.5"),
        ("nan", "NaN"),
        ("inf", "inf"),
    ] {
        q_err(
            &q_with("level = 0.85", &format!("level = {l}")),
            "shape.part[2].level",
            &["must be strictly between 0 and 1", &format!("got {shown}")],
        );
    }
    q_err(
        &q_with(
            "polygon = [[0, 0], [100, 0], [100, 300], [0, 300]]",
            "polygon = []",
        ),
        "shape.part[1].polygon",
        &["3 to 10000 points", "got 0"],
    );
    q_err(
        &q_with("[0, 300]]", "[nan, 300]]"),
        "shape.part[1].polygon",
        &["point 4 must be finite", "[NaN, 300]"],
    );
    q_err(
        &q_with(
            "polygon = [[0, 0], [100, 0], [100, 300], [0, 300]]",
            "polygon = [[0, 0], [100, 100], [50, 50], [200, 200]]",
        ),
        "shape.part[1].polygon",
        &["on one line"],
    );
    q_err(
        &q_with(
            "polygon = [[0, 0], [100, 0], [100, 300], [0, 300]]",
            "svg = \"  \"",
        ),
        "shape.part[1].svg",
        &["must not be empty"],
    );
    q_err(
        &q_with("singularities = 300", "singularities = 0"),
        "shape.part[5].singularities",
        &["in [1, 8000], got 0"],
    );
    q_err(
        &q_with("singularities = 300", "singularities = 2.5"),
        "shape.part[5].singularities",
        &["whole number, got 2.5"],
    );
    q_err(
        &q_with("singularities = 300", "singularities = \"many\""),
        "shape.part[5].singularities",
        &["\"many\""],
    );
    q_err(
        &q_with("height = 60.0", "height = -60.0"),
        "shape.height",
        &["got -60"],
    );
    q_err(
        &q_with("origin = [10.0, 10.0]", "origin = [10.0, inf]"),
        "shape.origin",
        &["got inf"],
    );
    let t = q_with(
        "name = \"m1\"\npolygon = [[0, 0], [100, 0], [100, 300], [0, 300]]",
        "name = \"m1\"\ntext = \"IZ\"",
    );
    q_err(&t, "shape.part[1].text", &["'Z'", "no glyph"]);
    q_err(
        &t.replace("text = \"IZ\"", "text = \"I\"\nsize = 0"),
        "shape.part[1].size",
        &["positive", "got 0"],
    );
    let e = parse_job(
        &t.replace("text = \"IZ\"", "text = \"I\"\nfont = \"fonts/none.ttf\""),
        "x",
        Path::new("/some/dir"),
    )
    .unwrap_err();
    assert_eq!(e.key(), Some("shape.part[1].font"));
    assert_eq!(
        e.to_string(),
        "shape.part[1].font: no such file: /some/dir/fonts/none.ttf"
    );
}

#[test]
fn result_must_be_bounded() {
    let inverted = q_with(
        "op = \"subtract\"\nof = [\"m6\", \"m3\"]",
        "op = \"invert\"\nof = \"m6\"",
    );
    q_err(
        &inverted,
        "shape.result",
        &["\"Q\", which is an invert", "unbounded"],
    );
    q_err(
        &inverted.replace("result = \"Q\"\n", ""),
        "shape.result",
        &["an invert", "the last part is the result"],
    );
    // Built from an invert: a union with the void is unbounded, an
    // intersection with it is not.
    let more =
        format!("{inverted}\n[[shape.part]]\nname = \"R\"\nop = \"union\"\nof = [\"m4\", \"Q\"]\n");
    q_err(
        &more.replace("result = \"Q\"", "result = \"R\""),
        "shape.result",
        &["\"R\"", "built from an invert"],
    );
    q_err(
        &more
            .replace("result = \"Q\"", "result = \"R\"")
            .replace("of = [\"m4\", \"Q\"]", "of = [\"Q\", \"m4\"]")
            .replace("\"union\"\nof = [\"Q\"", "\"subtract\"\nof = [\"Q\""),
        "shape.result",
        &["built from an invert"],
    );
    let ok = more.replace("result = \"Q\"", "result = \"R\"").replace(
        "op = \"union\"\nof = [\"m4\", \"Q\"]",
        "op = \"intersect\"\nof = [\"m4\", \"Q\"]",
    );
    assert!(parse(&ok).is_ok());
    let ok = more.replace("result = \"Q\"", "result = \"R\"").replace(
        "op = \"union\"\nof = [\"m4\", \"Q\"]",
        "op = \"subtract\"\nof = [\"m4\", \"Q\"]",
    );
    assert!(parse(&ok).is_ok());
}

#[test]
fn one_shape_source_per_job() {
    q_err(
        &q_with("result = \"Q\"", "result = \"Q\"\ntext = \"A\""),
        "shape.part",
        &["cannot be combined with shape.text", "one shape source"],
    );
    q_err(
        &q_with(
            "result = \"Q\"",
            "result = \"Q\"\nsvg_path = \"M0 0 L1 0 L0 1 Z\"",
        ),
        "shape.part",
        &["cannot be combined with shape.svg_path"],
    );
    q_err(
        &q_with("result = \"Q\"", "result = \"Q\"\nfont = \"paper\""),
        "shape.font",
        &["[[shape.part]]"],
    );
    q_err(
        &q_with("result = \"Q\"", "result = \"Q\"\nletter_spacing = 2"),
        "shape.letter_spacing",
        &["[[shape.part]]"],
    );
    q_err(
        &with("shape", "result = \"A\""),
        "shape.result",
        &["[[shape.part]]"],
    );
    q_err(
        &with("shape", "part = []").replace("text = \"A\"\n", ""),
        "shape.part",
        &["at least one part"],
    );
}
