//! The preview, the field image, the run report and the equipotential curves,
//! checked the way a user would see them: the SVG is parsed and rendered by a
//! real renderer (resvg) and the pixels are inspected; the PNG is decoded; the
//! JSON is parsed; the curves are measured against exact ones.

use pfcam::field::isolines::{isolines, material_mask, pieces, Grid};
use pfcam::field::Field;
use pfcam::geometry::{DistanceIndex, Vec2};
use pfcam::job::{load_job, Job};
use pfcam::pipeline::{self, RunOutput};
use pfcam::preview::{depth_colour, preview_svg, PreviewOptions};
use pfcam::report::{split_levels, RunReport};
use pfcam::toolpath::Move;
use resvg::{tiny_skia, usvg};
use std::f64::consts::TAU;
use std::fs;
use std::path::Path;
use std::sync::OnceLock;

use crate::common::{pfcam, scratch, shipped, test_data, text};

/// The letter-A job, run once for every test that needs it (it has a counter).
fn letter_a() -> &'static (Job, RunOutput) {
    static RUN: OnceLock<(Job, RunOutput)> = OnceLock::new();
    RUN.get_or_init(|| {
        let job = load_job(&shipped("letter-a.toml")).expect("job");
        let out = pipeline::run(&job, &mut |_| {}).expect("run");
        (job, out)
    })
}

/// An SVG rendered at `px_per_mm`, with the viewBox origin (x, y) in mm.
struct Rendered {
    pixmap: tiny_skia::Pixmap,
    k: f64,
    x0: f64,
    y0: f64,
}

impl Rendered {
    fn new(svg: &str, px_per_mm: f64) -> Rendered {
        let mut opt = usvg::Options::default();
        let font = fs::read(test_data("DejaVuSerif.ttf")).expect("test font");
        opt.fontdb_mut().load_font_data(font);
        opt.fontdb_mut().set_sans_serif_family("DejaVu Serif");
        let tree = usvg::Tree::from_str(svg, &opt).expect("usvg parses the preview");
        // width/height are in mm; usvg turns them into CSS px at 96 per inch.
        let scale = (px_per_mm / (96.0 / 25.4)) as f32;
        let size = tree.size();
        let mut pixmap = tiny_skia::Pixmap::new(
            (size.width() * scale).ceil() as u32,
            (size.height() * scale).ceil() as u32,
        )
        .expect("pixmap");
        resvg::render(
            &tree,
            tiny_skia::Transform::from_scale(scale, scale),
            &mut pixmap.as_mut(),
        );
        let vb = attr(svg, "viewBox");
        let v: Vec<f64> = vb.split(' ').map(|x| x.parse().expect("number")).collect();
        Rendered {
            pixmap,
            k: px_per_mm,
            x0: v[0],
            y0: v[1],
        }
    }

    /// RGBA at a point of the part's plane (y up), or None outside the image.
    fn at(&self, p: Vec2) -> Option<[u8; 4]> {
        let px = ((p.x - self.x0) * self.k).floor();
        let py = ((-p.y - self.y0) * self.k).floor();
        if px < 0.0 || py < 0.0 {
            return None;
        }
        self.pixmap
            .pixel(px as u32, py as u32)
            .map(|c| [c.red(), c.green(), c.blue(), c.alpha()])
    }
}

/// The value of the first `name="…"` attribute in `svg`.
fn attr<'a>(svg: &'a str, name: &str) -> &'a str {
    let key = format!("{name}=\"");
    let i = svg.find(&key).expect("attribute") + key.len();
    let j = svg[i..].find('"').expect("closing quote") + i;
    &svg[i..j]
}

fn hex(c: &str) -> [u8; 3] {
    let v = |k: usize| u8::from_str_radix(&c[1 + 2 * k..3 + 2 * k], 16).expect("hex");
    [v(0), v(1), v(2)]
}

fn close(a: [u8; 4], b: [u8; 3], tol: i32) -> bool {
    (0..3).all(|k| (i32::from(a[k]) - i32::from(b[k])).abs() <= tol)
}

#[test]
fn rendered_preview_shows_the_part_the_path_and_the_start() {
    let (job, out) = letter_a();
    let report = RunReport::new(job, out);
    let svg = preview_svg(job, out, &report, &PreviewOptions::default()).expect("preview");
    assert!(svg.starts_with("<!-- pfcam "), "marker line");
    assert!(attr(&svg, "width").ends_with("mm") && attr(&svg, "height").ends_with("mm"));
    let img = Rendered::new(&svg, 12.0);

    // Not blank: a white page with a good share of drawn pixels.
    let px = img.pixmap.pixels();
    let white = px
        .iter()
        .filter(|c| c.red() > 250 && c.green() > 250 && c.blue() > 250)
        .count();
    let drawn = px.len() - white;
    assert!(
        white > px.len() / 4,
        "mostly white page: {white} of {}",
        px.len()
    );
    assert!(
        drawn > px.len() / 10,
        "drawn pixels: {drawn} of {}",
        px.len()
    );

    // Path pixels where the path is: every move end of the deepest pass, away
    // from the start marker, shows one of the levels' colours (the passes
    // overlap as bands, the deepest narrowest on top).
    let levels = split_levels(&out.toolpath);
    let deepest = levels.last().expect("a level");
    let colours: Vec<[u8; 3]> = levels
        .iter()
        .map(|l| {
            hex(&depth_colour(
                (levels[0].z - l.z) / (levels[0].z - deepest.z),
            ))
        })
        .collect();
    // Where the first cut begins: the start of the first feed move of the
    // whole program (later passes ramp in from wherever the tool stands).
    let mut from = out.toolpath.start;
    for m in out.toolpath.moves() {
        if !matches!(m, Move::Rapid { .. }) {
            break;
        }
        from = m.to();
    }
    let start = Vec2::new(from.x, from.y);
    let (mut hit, mut tried) = (0, 0);
    for (_, m) in deepest.moves.iter() {
        let to = m.to();
        let p = Vec2::new(to.x, to.y);
        if p.dist(start) < 4.0 || matches!(m, Move::Rapid { .. }) {
            continue;
        }
        tried += 1;
        if img
            .at(p)
            .is_some_and(|c| colours.iter().any(|&w| close(c, w, 40)))
        {
            hit += 1;
        }
    }
    assert!(tried > 30, "{tried}");
    // Arrowheads cover a few vertices; nearly all others show the path.
    assert!(
        hit as f64 >= 0.85 * tried as f64,
        "{hit} of {tried} path points"
    );

    // Pixels off the path, 3 tool radii outside the part and away from the
    // equipotentials' thin lines, are mostly page white; inside the material,
    // part grey.
    let polys: Vec<Vec<Vec2>> = out.shape.contours().map(|c| c.flatten(0.01)).collect();
    let part = DistanceIndex::new(&polys);
    let inside = material_mask(&polys);
    let (lo, hi) = out.shape.tight_bbox().expect("bbox");
    let (mut grey, mut n_in, mut n_out, mut white_out) = (0, 0, 0, 0);
    for i in 0..60 {
        for j in 0..60 {
            let p = Vec2::new(
                lo.x + (hi.x - lo.x) * i as f64 / 59.0,
                lo.y + (hi.y - lo.y) * j as f64 / 59.0,
            );
            let d = part.distance(p);
            let Some(c) = img.at(p) else { continue };
            if inside(p) && d > 1.0 {
                n_in += 1;
                grey += usize::from(close(c, [0xd4, 0xd4, 0xd4], 6));
            } else if !inside(p) && d > 3.0 * job.tool.diameter {
                n_out += 1;
                white_out += usize::from(close(c, [255, 255, 255], 6));
            }
        }
    }
    assert!(
        grey as f64 > 0.97 * n_in as f64,
        "part grey {grey} of {n_in}"
    );
    assert!(
        white_out as f64 > 0.8 * n_out as f64,
        "white {white_out} of {n_out}"
    );

    // The start marker (green) sits where the first cut begins.
    let c = img.at(start).expect("start in the picture");
    assert!(close(c, [0x00, 0xa6, 0x50], 40), "start pixel {c:?}");
}

/// The machinist's set-up: the work zero is drawn where X0 Y0 is, and the
/// report gives the stock rectangle and the zero's distance from its edges as
/// the G-code header does.
#[test]
fn preview_and_report_place_the_stock_and_the_work_zero() {
    let (job, out) = letter_a();
    let report = RunReport::new(job, out);
    let svg = preview_svg(job, out, &report, &PreviewOptions::default()).expect("preview");
    let img = Rendered::new(&svg, 12.0);
    let blue = hex("#0050b4");
    let near_zero = (-2..=2)
        .flat_map(|i| (-2..=2).map(move |j| Vec2::new(0.05 * i as f64, 0.05 * j as f64)))
        .filter_map(|p| img.at(p))
        .filter(|c| close(*c, blue, 40))
        .count();
    assert!(
        near_zero >= 3,
        "the work-zero cross is not at (0, 0): {near_zero} pixels"
    );
    let stock = report.stock.as_ref().expect("a stock");
    assert_eq!(stock.kind, "sheet");
    let radius = job.tool.diameter / 2.0;
    let mut lo = Vec2::new(f64::MAX, f64::MAX);
    for m in out.toolpath.moves() {
        if !matches!(m, Move::Rapid { .. }) {
            lo = Vec2::new(lo.x.min(m.to().x), lo.y.min(m.to().y));
        }
    }
    assert!(
        (stock.x_min - (lo.x - radius)).abs() < 0.01,
        "{stock:?} vs {lo:?}"
    );
    assert_eq!(stock.zero_from_left, -stock.x_min);
    assert_eq!(stock.zero_from_front, -stock.y_min);
    let json: serde_json::Value = serde_json::from_str(&report.to_json()).expect("json");
    assert_eq!(json["stock"]["kind"], "sheet");
    assert!(json["stock"]["zero_from_left"].as_f64().is_some());
}

#[test]
fn preview_with_the_field_image_embeds_a_png_and_renders_it() {
    let (job, out) = letter_a();
    let report = RunReport::new(job, out);
    let opts = PreviewOptions {
        field_image: true,
        ..PreviewOptions::default()
    };
    let svg = preview_svg(job, out, &report, &opts).expect("preview");
    assert!(
        svg.contains("data:image/png;base64,iVBORw0KGgo"),
        "PNG data URI"
    );
    let img = Rendered::new(&svg, 4.0);
    // Just outside the part, beyond the path's bands, the field is red (u near 1).
    let polys: Vec<Vec<Vec2>> = out.shape.contours().map(|c| c.flatten(0.01)).collect();
    let part = DistanceIndex::new(&polys);
    let inside = material_mask(&polys);
    let (lo, hi) = out.shape.tight_bbox().expect("bbox");
    let mut row: Vec<[u8; 4]> = Vec::new();
    for i in 0..50 {
        for j in 0..50 {
            let p = Vec2::new(
                lo.x + (hi.x - lo.x) * i as f64 / 49.0,
                lo.y + (hi.y - lo.y) * j as f64 / 49.0,
            );
            let d = part.distance(p);
            if !inside(p) && (2.5..3.0).contains(&d) {
                row.extend(img.at(p));
            }
        }
    }
    assert!(row.len() > 20, "{}", row.len());
    let red = row
        .iter()
        .filter(|c| c[0] > c[1] + 30 && c[0] > c[2] + 30)
        .count();
    assert!(red * 4 >= row.len() * 3, "{red} of {} reddish", row.len());
}

#[test]
fn equipotentials_of_a_real_field_lie_on_their_level_outside_the_material() {
    let (_, out) = letter_a();
    let polys: Vec<Vec<Vec2>> = out.shape.contours().map(|c| c.flatten(0.01)).collect();
    let part = DistanceIndex::new(&polys);
    let mask = material_mask(&polys);
    let (lo, hi) = out.shape.tight_bbox().expect("bbox");
    let m = Vec2::new(10.0, 10.0);
    let cell = 0.25;
    let grid = Grid::try_sample(&out.field, lo - m, hi + m, cell, &polys).expect("grid");
    let mut mean_dist = Vec::new();
    let err = out.solves[0].max_error;
    for s in [0.98, 0.99, 0.995] {
        let curves = pieces(&grid, s, &out.field, &mask);
        assert!(!curves.is_empty(), "s {s}");
        let outer = curves
            .iter()
            .max_by(|a, b| a.length().total_cmp(&b.length()))
            .expect("a curve");
        assert!(
            outer.closed,
            "the outer curve at s {s} closes around the part"
        );
        // Away from the walls (two cells) every vertex is on its level to
        // rounding. Within them the level may run into the material where the
        // field's own boundary error (u = 1 ± e on the wall) is comparable to
        // 1 − s: there the vertex stops at the wall (u is taken as 1 inside),
        // where |u − s| ≤ (1 − s) + e.
        let (mut worst, mut worst_wall, mut near, mut sum, mut n) = (0.0f64, 0.0f64, 0, 0.0, 0);
        for c in &curves {
            for p in &c.points {
                assert!(
                    !mask(*p) || part.distance(*p) < 1e-9,
                    "vertex in the material at s {s}"
                );
                let e = (out.field.value(*p) - s).abs();
                if part.distance(*p) > 2.0 * cell {
                    worst = worst.max(e);
                } else {
                    worst_wall = worst_wall.max(e);
                    near += 1;
                }
            }
        }
        for p in &outer.points {
            sum += part.distance(*p);
            n += 1;
        }
        let total: usize = curves.iter().map(|c| c.points.len()).sum();
        eprintln!(
            "s {s}: {} curves, {total} vertices; |u - s| <= {worst:.1e}, and <= {worst_wall:.1e} at the {near} within two cells of a wall (field max boundary error {err:.1e})",
            curves.len()
        );
        assert!(worst < 1e-9, "s {s}: |u - s| {worst}");
        assert!(
            worst_wall <= 1.1 * (err + (1.0 - s)),
            "s {s}: near the wall {worst_wall}, field error {err}"
        );
        mean_dist.push(sum / n as f64);
    }
    // Higher s lies closer to the part.
    assert!(
        mean_dist[0] > mean_dist[1] && mean_dist[1] > mean_dist[2],
        "{mean_dist:?}"
    );
}

/// Γ(s) of a unit charge is the circle r = exp(−2πs): vertices exact (regula
/// falsi on the grid edges), chords within h²/(8r), for several cell sizes.
#[test]
fn single_charge_circles_radius_error() {
    let q = Vec2::new(0.37, -0.21);
    let f = Field::new(vec![q], vec![1.0]);
    for (r0, cell) in [(20.0f64, 1.0), (20.0, 0.5), (5.0, 0.25), (2.0, 0.05)] {
        let s = -r0.ln() / TAU;
        let d = Vec2::new(1.5 * r0, 1.5 * r0);
        let grid = Grid::try_sample(&f, q - d, q + d, cell, &[]).expect("grid");
        let curves = isolines(&grid, s, &f, &[]);
        assert_eq!(curves.len(), 1);
        let c = &curves[0];
        let vert = (c.points().iter())
            .map(|p| (p.dist(q) - r0).abs())
            .fold(0.0, f64::max);
        let n = c.len();
        let chord = (c.edges())
            .map(|(a, b)| (a.lerp(b, 0.5).dist(q) - r0).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "r {r0} cell {cell}: {n} vertices, vertex error {vert:.1e}, chord error {chord:.1e} (bound {:.1e})",
            cell * cell / (8.0 * r0) * 2.0
        );
        assert!(vert < 1e-9, "vertex error {vert}");
        // A chord spans at most about √2 cells: sagitta ≤ (√2 h)²/(8r).
        assert!(
            chord <= 2.0 * cell * cell / (8.0 * r0) + 1e-12,
            "chord error {chord}"
        );
    }
}

/// Two equal charges 2a apart: r₁r₂ = b² is two loops for b < a, one for b > a
/// (Cassini ovals), and the vertices satisfy r₁r₂ = b².
#[test]
fn cassini_ovals_change_topology_at_the_lemniscate() {
    let a = 5.0;
    let (q1, q2) = (Vec2::new(-a, 0.0), Vec2::new(a, 0.0));
    let f = Field::new(vec![q1, q2], vec![1.0, 1.0]);
    let (lo, hi) = (Vec2::new(-12.0, -9.0), Vec2::new(12.0, 9.0));
    let grid = Grid::try_sample(&f, lo, hi, 0.2, &[]).expect("grid");
    for (b, loops) in [(4.0f64, 2), (4.8, 2), (5.3, 1), (7.0, 1)] {
        // u = −(1/2π)(ln r₁ + ln r₂) = −(1/π) ln b on the oval.
        let s = -b.ln() / std::f64::consts::PI;
        let curves = isolines(&grid, s, &f, &[]);
        assert_eq!(curves.len(), loops, "b {b}");
        for c in &curves {
            for p in c.points() {
                let e = (p.dist(q1) * p.dist(q2) - b * b).abs() / (b * b);
                assert!(e < 1e-9, "b {b}: relative error {e}");
            }
        }
    }
}

#[test]
fn run_writes_svg_and_json_beside_the_gcode_and_reruns_replace_them() {
    let dir = scratch("preview", "run");
    let job = shipped("letter-i.toml");
    let job = job.to_str().expect("utf-8 path");
    let o = pfcam(&["run", job, "--out", "out"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(stdout.contains("out/letter-i.svg") && stdout.contains("out/letter-i.json"));
    assert!(
        stdout.contains("z (mm)") && stdout.contains("total"),
        "{stdout}"
    );
    let svg = fs::read_to_string(dir.join("out/letter-i.svg")).expect("svg");
    assert!(svg.starts_with("<!-- pfcam ") && svg.contains("<svg"));
    let v: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("out/letter-i.json")).expect("json"))
            .expect("valid JSON");
    assert!(v["generator"]
        .as_str()
        .is_some_and(|g| g.starts_with("pfcam ")));
    assert_eq!(v["job"], "letter-i");
    let levels = v["levels"].as_array().expect("levels");
    assert_eq!(levels.len(), 3, "letter-i cuts 3 mm in 1 mm passes");
    let mut sum = 0.0;
    for (l, z) in levels.iter().zip([-1.0, -2.0, -3.0]) {
        assert_eq!(l["z"].as_f64(), Some(z));
        assert_eq!(l["s"].as_f64(), Some(1.0));
        assert!(l["n"].as_u64().is_some_and(|n| n > 0));
        assert!(l["max_boundary_error"].as_f64().is_some_and(|e| e >= 0.0));
        assert!(l["min_clearance_mm"].as_f64().is_some_and(|c| c >= -0.01));
        assert!(l["time_s"].as_f64().is_some_and(|t| t > 0.0));
        sum += l["path_length_mm"].as_f64().expect("length");
    }
    let t = &v["totals"];
    assert_eq!(t["levels"], 3);
    let cut = t["cut_length_mm"].as_f64().expect("cut length");
    assert!(
        (sum - cut).abs() < 1e-6 * cut,
        "levels {sum} vs total {cut}"
    );
    assert!(
        t["time_s"].as_f64().expect("time")
            > levels
                .iter()
                .map(|l| l["time_s"].as_f64().unwrap_or(0.0))
                .sum::<f64>()
    );

    // A rerun replaces all three (they are pfcam's), quietly.
    let o = pfcam(&["run", job, "--out", "out", "--quiet"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        o.stdout.is_empty() && o.stderr.is_empty(),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(
        fs::read_to_string(dir.join("out/letter-i.svg")).expect("svg"),
        svg
    );
}

#[test]
fn foreign_svg_or_json_blocks_the_run_and_nothing_is_written() {
    for (name, content) in [
        (
            "letter-i.svg",
            "<svg xmlns=\"http://www.w3.org/2000/svg\"/>\n",
        ),
        ("letter-i.json", "{\n  \"mine\": true\n}\n"),
    ] {
        let dir = scratch("preview", &format!("foreign-{name}"));
        fs::create_dir_all(dir.join("out")).expect("mkdir");
        fs::write(dir.join("out").join(name), content).expect("write");
        let job = shipped("letter-i.toml");
        let o = pfcam(&["run", job.to_str().expect("utf-8"), "--out", "out"], &dir);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(3), "{err}");
        assert!(err.contains(name) && err.contains("--force"), "{err}");
        let left: Vec<_> = fs::read_dir(dir.join("out")).expect("dir").collect();
        assert_eq!(left.len(), 1, "only the foreign file remains");
        assert_eq!(
            fs::read_to_string(dir.join("out").join(name)).expect("read"),
            content
        );
        // --force replaces it.
        let o = pfcam(
            &[
                "run",
                job.to_str().expect("utf-8"),
                "--out",
                "out",
                "--force",
                "-q",
            ],
            &dir,
        );
        assert!(o.status.success(), "{}", text(&o.stderr));
        assert_ne!(
            fs::read_to_string(dir.join("out").join(name)).expect("read"),
            content
        );
    }
}

#[test]
fn preview_and_field_commands_write_one_file_each() {
    let dir = scratch("preview", "commands");
    let job = shipped("letter-a.toml");
    let job = job.to_str().expect("utf-8");
    let o = pfcam(
        &["preview", job, "-o", "a.svg", "--levels", "0.97,0.99"],
        &dir,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let svg = fs::read_to_string(dir.join("a.svg")).expect("svg");
    assert!(svg.contains("data-s=\"0.99\"") && svg.contains("data-s=\"0.97\""));
    assert!(!svg.contains("data:image/png"), "no field image by default");

    let o = pfcam(&["field", job, "-o", "a.png", "--px-per-mm", "4"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let bytes = fs::read(dir.join("a.png")).expect("png");
    let mut r = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .expect("PNG");
    let mut buf = vec![0; r.output_buffer_size().expect("size")];
    let info = r.next_frame(&mut buf).expect("frame");
    assert_eq!(info.color_type, png::ColorType::Rgb);
    // The material is yellow: the letter covers a fair share of the picture.
    let yellow = buf[..info.buffer_size()]
        .chunks(3)
        .filter(|p| p[0] > 240 && p[1] > 240 && p[2] < 20)
        .count();
    let total = (info.width * info.height) as usize;
    assert!(
        yellow > total / 20 && yellow < total / 2,
        "{yellow} of {total}"
    );
    assert!(
        fs::read_dir(&dir).expect("dir").count() == 2,
        "nothing else written"
    );

    // Bad options are usage-level errors naming the option, and write nothing.
    let o = pfcam(&["preview", job, "-o", "b.svg", "--levels", "1.5"], &dir);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("--levels"));
    let o = pfcam(
        &[
            "field", job, "-o", "b.png", "--map", "paper", "--power", "3",
        ],
        &dir,
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("--power"));
    assert!(!dir.join("b.svg").exists() && !dir.join("b.png").exists());
}

#[test]
fn quiet_prints_nothing_and_warnings_go_to_the_report_and_the_preview() {
    let dir = scratch("preview", "warn");
    // A 12 mm A: its counter is too small for a 1/8" tool, which is a warning.
    fs::write(
        dir.join("job.toml"),
        "[job]\nname = \"small-a\"\n[shape]\ntext = \"A\"\nheight = 12.0\n[tool]\ndiameter = 3.175\n[operation]\ndepth = 2.0\n",
    )
    .expect("job");
    let o = pfcam(&["run", "job.toml", "--out", "out", "--quiet"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        o.stdout.is_empty() && o.stderr.is_empty(),
        "{}",
        text(&o.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("out/small-a.json")).expect("json"))
            .expect("JSON");
    let w = v["warnings"].as_array().expect("warnings");
    assert_eq!(w.len(), 1);
    assert!(w[0].as_str().is_some_and(|s| s.contains("too small")));
    let svg = fs::read_to_string(dir.join("out/small-a.svg")).expect("svg");
    assert!(
        svg.contains("1 warning: counter"),
        "header shows the warning"
    );
    // Without --quiet the warning is printed.
    let o = pfcam(&["run", "job.toml", "--out", "out"], &dir);
    assert!(text(&o.stderr).contains("warning: counter"));
}

#[test]
fn many_levels_get_one_width_and_a_colour_bar() {
    let mut job = load_job(&shipped("letter-i.toml")).expect("job");
    job.tool.stepdown = 0.25;
    let out = pipeline::run(&job, &mut |_| {}).expect("run");
    let report = RunReport::new(&job, &out);
    assert_eq!(report.levels.len(), 12);
    let svg = preview_svg(&job, &out, &report, &PreviewOptions::default()).expect("preview");
    assert!(svg.contains("12 levels") && svg.contains("class=\"depth-bar\""));
    assert_eq!(svg.matches("data-z=").count(), 12, "one path per level");
    // No per-level legend entries: the bar stands for them.
    assert!(!svg.contains(">z -0.25<"));
    let img = Rendered::new(&svg, 10.0);
    // The bar shows the whole ramp: both ends' colours appear in the picture.
    let px = img.pixmap.pixels();
    for t in [0.0, 1.0] {
        let want = hex(&depth_colour(t));
        assert!(
            px.iter()
                .any(|c| close([c.red(), c.green(), c.blue(), c.alpha()], want, 12)),
            "colour of t = {t}"
        );
    }
}

/// The preview counts a boss's or cavity's levels as the G-code header and the
/// report do: one per planned level, whatever depths its ramps pass through.
#[test]
fn preview_header_and_report_count_the_same_levels() {
    let name = "q-mould.toml";
    let job = load_job(&shipped(name)).expect("job");
    let out = pipeline::run(&job, &mut |_| {}).expect("run");
    let report = RunReport::new(&job, &out);
    let svg = preview_svg(&job, &out, &report, &PreviewOptions::default()).expect("preview");
    let g = pfcam::gcode::write_gcode(&out.toolpath, &job).expect("gcode");
    let header: usize = g
        .lines()
        .find_map(|l| l.strip_prefix("(levels: "))
        .and_then(|l| l.split(',').next())
        .and_then(|n| n.parse().ok())
        .expect("a levels line");
    assert_eq!(report.levels.len(), header, "{name}");
    assert!(
        svg.contains(&format!("{header} levels")),
        "{name}: {header}"
    );
    assert_eq!(svg.matches("data-z=").count(), header, "{name}");
    // And the same depths, shallowest to deepest, though the sections are in
    // cutting order (a slab's stepdown level first).
    let range = g
        .lines()
        .find_map(|l| l.strip_prefix("(levels: "))
        .and_then(|l| l.split_once(", z "))
        .and_then(|(_, r)| r.strip_suffix(')'))
        .expect("a z range");
    assert!(svg.contains(&format!("z {range} mm")), "{name}: z {range}");
}

/// A job with a finishing tool: the preview draws the roughing program,
/// names the finishing one in its header with the report's figures, and
/// draws its passes: every feed move's end of the finishing program lies on
/// the drawn lines (within the drawing's thinning and rounding).
#[test]
fn the_preview_names_and_draws_the_finishing_program() {
    let text = "[job]\nname = \"fi\"\n[shape]\ntext = \"I\"\nheight = 20.0\n[tool]\ndiameter = 3.175\nstepdown = 1.5\n[stock]\nmargin = 4.0\n[operation]\nkind = \"boss\"\ndepth = 2.0\nmax_scallop = 1.0\n[profile]\nkind = \"sigmoid\"\ns1 = 0.97\ns2 = 0.85\n[finish]\ndiameter = 2.0\nfeed = 1200.0\n";
    let job = pfcam::job::parse_job(text, "fi", Path::new(".")).expect("job");
    let out = pipeline::run(&job, &mut |_| {}).expect("runs");
    let report = RunReport::new(&job, &out);
    assert_eq!(report.programs.len(), 2);
    let svg = preview_svg(&job, &out, &report, &PreviewOptions::default()).expect("preview");
    let p = &report.programs[1];
    let want = format!(
        "then fi.finish.nc: ball end mill ⌀2 mm · {:.1} mm cutting · est. time {}",
        p.cut_length_mm,
        pfcam::gcode::format_duration(p.time_s)
    );
    assert!(svg.contains(&want), "no {want:?} in the header");
    // The page is wide enough for it (a narrow part's page cut it off).
    let over = header_overflow(&svg);
    assert!(over <= 0.0, "a header line runs {over} mm off the page");
    let drawn = finish_lines(&svg);
    let finish = &out.finish.as_ref().expect("a finishing program").toolpath;
    let mut ends = 0;
    for m in finish.moves() {
        if matches!(m, Move::Rapid { .. }) {
            continue;
        }
        let p = m.to();
        let d = drawn
            .iter()
            .flat_map(|pl| pl.windows(2))
            .map(|w| {
                pfcam::geometry::seg_seg_dist(Vec2::new(p.x, p.y), Vec2::new(p.x, p.y), w[0], w[1])
            })
            .fold(f64::INFINITY, f64::min);
        assert!(
            d <= 0.02,
            "the finishing move to {p:?} is {d} mm off the drawn passes"
        );
        ends += 1;
    }
    assert!(ends > 100, "{ends} finishing moves");
    // Without [finish], no such line and no passes.
    let plain = pfcam::job::parse_job(
        &text.replace("[finish]\ndiameter = 2.0\nfeed = 1200.0\n", ""),
        "fi",
        Path::new("."),
    )
    .expect("job");
    let out = pipeline::run(&plain, &mut |_| {}).expect("runs");
    let report = RunReport::new(&plain, &out);
    let svg = preview_svg(&plain, &out, &report, &PreviewOptions::default()).expect("preview");
    assert!(!svg.contains("then fi.finish.nc") && finish_lines(&svg).is_empty());
}

/// How far the longest header line runs past the page's right edge, mm
/// (negative: inside), estimating a text's width as 0.55 em a character
/// (DejaVu Sans's average), from each `<text>` of the header group's x and
/// font size and the `viewBox`.
fn header_overflow(svg: &str) -> f64 {
    let view: Vec<f64> = attr(svg, "viewBox")
        .split_whitespace()
        .map(|v| v.parse().expect("a number"))
        .collect();
    let right = view[0] + view[2];
    let head = svg.split("class=\"header\"").nth(1).expect("a header");
    let head = &head[..head.find("</g>").expect("its end")];
    head.split("<text")
        .skip(1)
        .fold(f64::NEG_INFINITY, |worst, t| {
            let x: f64 = attr(t, "x").parse().expect("x");
            let size: f64 = attr(t, "font-size").parse().expect("font-size");
            let content = &t[t.find('>').expect("a tag") + 1..t.find("</text>").expect("an end")];
            worst.max(x + content.chars().count() as f64 * 0.55 * size - right)
        })
}

/// The polylines of the preview's finishing passes (`class="finish"`), in
/// part coordinates.
fn finish_lines(svg: &str) -> Vec<Vec<Vec2>> {
    let Some(tag) = svg.split("<path").find(|t| t.contains("class=\"finish\"")) else {
        return Vec::new();
    };
    let d = tag
        .split(" d=\"")
        .nth(1)
        .and_then(|r| r.split('"').next())
        .expect("d");
    let mut lines: Vec<Vec<Vec2>> = Vec::new();
    for pl in d.split('M').skip(1) {
        let point = |xy: &str| {
            let v: Vec<f64> = xy.split_whitespace().map(|n| n.parse().unwrap()).collect();
            Vec2::new(v[0], -v[1])
        };
        lines.push(pl.split('L').map(point).collect());
    }
    lines
}
