//! The SVG preview of a run and the field's colour map (PNG).
//!
//! The preview shows, seen from above (y up, millimetres in the `viewBox`, width
//! and height in mm so it prints at 1:1): the part, equipotential curves Γ(s) of
//! the field at a few values, the tool path of every depth level in its own
//! colour (deeper is darker and drawn narrower on top, so passes over the same
//! XY stay visible as bands), rapids dashed, the start point with the tool disk
//! and arrows for the cutting direction, a scale bar, a legend and the job's key
//! figures. The field's colour map can be laid underneath as an embedded PNG
//! (off by default: it makes the file large).
//!
//! Every SVG pfcam writes starts with the line `<!-- pfcam <version> job <name> -->`
//! ([`svg_marker`]), which is how pfcam recognises its own files.

pub mod colormap;

use crate::field::contour::{material_mask, ContourError, FieldGrid, GridSpec};
use crate::geometry::{DistanceIndex, Vec2};
use crate::job::Job;
use crate::pipeline::RunOutput;
use crate::report::{run_levels, RunReport};
use crate::toolpath::{Move, Vec3};
use colormap::{auto_exponent, base64, encode_png, field_image, ColourMap, FieldImageSpec};
use svg::node::element::{
    Circle, Definitions, Group, Image, Line, LinearGradient, Path, Rectangle, Stop, Text, Title,
};
use svg::Document;

/// Equipotential values drawn by default: far (0.9) to close (0.99) to the part.
pub const DEFAULT_LEVELS: [f64; 4] = [0.9, 0.95, 0.98, 0.99];

/// What the first line of every pfcam SVG starts with.
pub const SVG_MARKER_PREFIX: &str = "<!-- pfcam ";

/// The first line of a pfcam SVG for job `name` (an XML comment before the root
/// element; `--` cannot occur inside a comment, so it is broken up).
pub fn svg_marker(name: &str) -> String {
    format!(
        "{SVG_MARKER_PREFIX}{} job {} -->",
        env!("CARGO_PKG_VERSION"),
        name.replace("--", "- -").replace('\n', " ")
    )
}

/// Whether `first_line` is the first line of an SVG pfcam wrote.
pub fn is_pfcam_svg(first_line: &str) -> bool {
    first_line.starts_with(SVG_MARKER_PREFIX) && first_line.trim_end().ends_with("-->")
}

/// The equipotentials a job's preview draws by default: for a boss or cavity
/// the part's own outlines, its top edge Γ(s_top) and its foot Γ(s_bottom)
/// (for a mould, its floor and its rim); for a profile `DEFAULT_LEVELS`.
pub fn levels_for(job: &crate::job::Job) -> Vec<f64> {
    use crate::job::OperationKind;
    match (job.operation.kind, &job.profile) {
        (OperationKind::Boss | OperationKind::Cavity, Some(p)) => {
            let (lo, hi) = p.s_range();
            // s = 1 is the glyph itself, drawn anyway.
            [lo, hi].into_iter().filter(|s| *s < 1.0).collect()
        }
        _ => DEFAULT_LEVELS.to_vec(),
    }
}

/// Settings of the preview.
#[derive(Clone, Debug, PartialEq)]
pub struct PreviewOptions {
    /// Equipotential values s to draw (each in (0, 1)).
    pub levels: Vec<f64>,
    /// Cells of the equipotential grid along the longer side of the drawing.
    /// 500 puts vertices about 0.4 mm apart on a 200 mm part.
    pub contour_cells: usize,
    /// Lay the field's colour map (Appendix II) under the drawing as an embedded PNG.
    pub field_image: bool,
    /// Resolution of that image, pixels per mm.
    pub image_px_per_mm: f64,
}

impl Default for PreviewOptions {
    fn default() -> Self {
        PreviewOptions {
            levels: DEFAULT_LEVELS.to_vec(),
            contour_cells: 500,
            field_image: false,
            image_px_per_mm: 4.0,
        }
    }
}

/// What can go wrong making a preview or a field image.
#[derive(Debug, thiserror::Error)]
pub enum PreviewError {
    /// The equipotential grid.
    #[error(transparent)]
    Contour(#[from] ContourError),
    /// The colour map or its PNG encoding.
    #[error("field image: {0}")]
    Image(String),
    /// A bad option.
    #[error("{0}")]
    Invalid(String),
}

/// The rectangle the preview (and `pfcam field`) pictures: the part, the tool
/// path (rapids included) and the program's start point, with a margin of
/// 5 % of the diagonal but at least two tool diameters and 3 mm.
pub fn drawing_area(job: &Job, out: &RunOutput) -> (Vec2, Vec2) {
    let mut lo = Vec2::new(f64::MAX, f64::MAX);
    let mut hi = Vec2::new(f64::MIN, f64::MIN);
    let mut add = |p: Vec2| {
        lo = Vec2::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Vec2::new(hi.x.max(p.x), hi.y.max(p.y));
    };
    if let Some((a, b)) = out.shape.tight_bbox() {
        add(a);
        add(b);
    }
    if let Some((a, b)) = out.stock {
        add(a);
        add(b);
    }
    add(Vec2::ZERO);
    add(xy(out.toolpath.start));
    for m in out.toolpath.moves() {
        add(xy(m.to()));
    }
    let margin = (0.05 * (hi - lo).norm())
        .max(2.0 * job.tool.diameter)
        .max(3.0);
    let d = Vec2::new(margin, margin);
    (lo - d, hi + d)
}

fn xy(p: Vec3) -> Vec2 {
    Vec2::new(p.x, p.y)
}

/// An equipotential value as written in a job (`0.9995`, not `num`'s `1`):
/// the shortest decimal that reads back as the same number.
fn level_label(s: f64) -> String {
    format!("{s}")
}

/// A number for SVG: three decimals, trailing zeros dropped, no `-0`.
fn num(x: f64) -> String {
    let s = format!("{x:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" || s.is_empty() {
        "0".into()
    } else {
        s.into()
    }
}

/// SVG path data for polylines in part coordinates (y flipped).
fn path_data(lines: &[Vec<Vec2>], close: bool) -> String {
    let mut d = String::new();
    for pl in lines.iter().filter(|pl| pl.len() >= 2) {
        for (k, p) in pl.iter().enumerate() {
            d += if k == 0 { "M" } else { "L" };
            d += &num(p.x);
            d.push(' ');
            d += &num(-p.y);
        }
        if close {
            d.push('Z');
        }
    }
    d
}

/// Colour of depth fraction t (0 shallowest, 1 deepest): a stretch of viridis,
/// green to dark violet, darker deeper.
pub fn depth_colour(t: f64) -> String {
    const STOPS: [(f64, [f64; 3]); 4] = [
        (0.0, [122.0, 209.0, 81.0]),
        (0.35, [33.0, 145.0, 140.0]),
        (0.7, [59.0, 82.0, 139.0]),
        (1.0, [68.0, 1.0, 84.0]),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        1.0
    };
    let k = STOPS.iter().rposition(|s| s.0 <= t).unwrap_or(0).min(2);
    let (t0, c0) = STOPS[k];
    let (t1, c1) = STOPS[k + 1];
    let f = (t - t0) / (t1 - t0);
    let c: Vec<u8> = (0..3)
        .map(|i| (c0[i] + f * (c1[i] - c0[i])).round() as u8)
        .collect();
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// Colour of the equipotential with index `k` of `n` (0 the farthest from the
/// part): light to dark red, as the paper's colour figures go red near the part.
fn curve_colour(k: usize, n: usize) -> String {
    let t = if n <= 1 {
        1.0
    } else {
        k as f64 / (n - 1) as f64
    };
    let c0 = [244.0, 165.0, 130.0];
    let c1 = [178.0, 24.0, 43.0];
    let c: Vec<u8> = (0..3)
        .map(|i| (c0[i] + t * (c1[i] - c0[i])).round() as u8)
        .collect();
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// XY polylines of a level's feed moves (arcs flattened within `tol`); plunges
/// add no length and so no vertex.
fn level_polylines(moves: &[(Vec3, Move)], tol: f64) -> Vec<Vec<Vec2>> {
    let mut out: Vec<Vec<Vec2>> = Vec::new();
    for (from, m) in moves {
        let a = xy(*from);
        let continues = out
            .last()
            .and_then(|pl| pl.last())
            .is_some_and(|&last| last.dist(a) < 1e-9);
        if !continues {
            out.push(vec![a]);
        }
        let pts = match *m {
            Move::Arc {
                to, cx, cy, ccw, ..
            } => flatten_arc(a, xy(to), Vec2::new(cx, cy), ccw, tol),
            _ => vec![xy(m.to())],
        };
        if let Some(pl) = out.last_mut() {
            for p in pts {
                if pl.last().is_none_or(|&q| q.dist(p) >= 1e-9) {
                    pl.push(p);
                }
            }
        }
    }
    out.retain(|pl| pl.len() >= 2);
    out
}

/// Points along an XY arc from `a` (excluded) to `b` (included) about `c`, chords
/// within `tol`; a zero sweep is a full circle, as in G-code.
fn flatten_arc(a: Vec2, b: Vec2, c: Vec2, ccw: bool, tol: f64) -> Vec<Vec2> {
    let r = a.dist(c);
    let a0 = (a.y - c.y).atan2(a.x - c.x);
    let a1 = (b.y - c.y).atan2(b.x - c.x);
    let mut sweep = if ccw { a1 - a0 } else { a0 - a1 };
    if sweep <= 1e-12 {
        sweep += std::f64::consts::TAU;
    }
    let max_step = if r > tol {
        2.0 * (1.0 - tol / r).acos()
    } else {
        sweep
    };
    let n = (sweep / max_step.max(1e-3)).ceil().clamp(1.0, 10_000.0) as usize;
    let dir = if ccw { 1.0 } else { -1.0 };
    (1..=n)
        .map(|k| {
            if k == n {
                b
            } else {
                let t = a0 + dir * sweep * k as f64 / n as f64;
                c + Vec2::new(t.cos(), t.sin()) * r
            }
        })
        .collect()
}

fn polyline_length(pl: &[Vec2]) -> f64 {
    pl.windows(2).map(|w| w[0].dist(w[1])).sum()
}

/// Points and unit tangents at `count` evenly spaced arc lengths along `pl`.
fn along(pl: &[Vec2], count: usize) -> Vec<(Vec2, Vec2)> {
    let len: f64 = pl.windows(2).map(|w| w[0].dist(w[1])).sum();
    let mut out = Vec::new();
    if len <= 0.0 || count == 0 {
        return out;
    }
    let mut targets = (0..count)
        .map(|k| (k as f64 + 0.5) * len / count as f64)
        .peekable();
    let mut acc = 0.0;
    for w in pl.windows(2) {
        let l = w[0].dist(w[1]);
        while let Some(&t) = targets.peek() {
            if t > acc + l || l <= 0.0 {
                break;
            }
            let f = (t - acc) / l;
            out.push((w[0].lerp(w[1], f), (w[1] - w[0]) / l));
            targets.next();
        }
        acc += l;
    }
    out
}

/// A "nice" scale-bar length (1, 2 or 5 × 10ᵏ mm) of at most `max` mm.
fn nice_length(max: f64) -> f64 {
    let p = 10f64.powf(max.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&l| l <= max)
        .unwrap_or(p)
}

/// Font families for every text.
const FONT: &str = "DejaVu Sans, Arial, Helvetica, sans-serif";

/// Up to this many levels each get a band width and a legend entry of their own;
/// more (a boss or cavity has dozens) are drawn in one width with a colour bar.
pub const BAND_LEVELS: usize = 6;

/// At most this many tracks of the deepest level get direction arrows (the
/// longest ones): a clearing level has many.
pub const ARROW_TRACKS: usize = 8;

/// Stroke width of the level `above` levels above the deepest of `n` levels:
/// with few levels each shallower one is wider by three base widths, so passes
/// over the same track show as bands; with many, all are 1.5 base widths. The
/// widest band is never wider than the cut itself, the tool diameter `d`
/// (with a 0.5 mm tool the bands would otherwise cover the neighbouring
/// tracks), so all are scaled down together when it would be.
fn band_width(lw: f64, above: usize, n: usize, d: f64) -> f64 {
    let width = |above: usize| {
        if n > BAND_LEVELS {
            1.5 * lw
        } else {
            lw * (2.0 + 3.0 * above.min(BAND_LEVELS) as f64)
        }
    };
    let widest = width(n.saturating_sub(1));
    width(above) * (d / widest).min(1.0)
}

fn text(x: f64, y: f64, size: f64, content: &str) -> Text {
    Text::new(content)
        .set("x", num(x))
        .set("y", num(y))
        .set("font-size", num(size))
}

/// The stock rectangle (a boss's or cavity's; for a profile the least sheet
/// the tool sweeps, dotted) and the work zero X0 Y0 as a cross with its label:
/// where the machinist sets the job up.
fn stock_and_zero(job: &Job, out: &RunOutput, lw: f64, fs: f64) -> Group {
    let mut g = Group::new().set("class", "stock");
    if let Some(e) = crate::gcode::stock_extent(&out.toolpath, job.tool.diameter / 2.0, out.stock) {
        let rect = vec![
            e.lo,
            Vec2::new(e.hi.x, e.lo.y),
            e.hi,
            Vec2::new(e.lo.x, e.hi.y),
        ];
        let dash = if e.known {
            "none".to_string()
        } else {
            format!("{} {}", num(0.3 * fs), num(0.3 * fs))
        };
        g = g.add(
            Path::new()
                .set("d", path_data(&[rect], true))
                .set("fill", "none")
                .set("stroke", "#8b5a2b")
                .set("stroke-width", num(lw))
                .set("stroke-dasharray", dash),
        );
    }
    let arm = 0.8 * fs;
    let cross = vec![
        vec![Vec2::new(-arm, 0.0), Vec2::new(arm, 0.0)],
        vec![Vec2::new(0.0, -arm), Vec2::new(0.0, arm)],
    ];
    g.add(
        Path::new()
            .set("d", path_data(&cross, false))
            .set("stroke", "#0050b4")
            .set("stroke-width", num(1.5 * lw))
            .set("class", "work-zero"),
    )
    .add(text(0.4 * fs, 0.4 * fs - arm, 0.7 * fs, "X0 Y0").set("fill", "#0050b4"))
}

/// The preview of a finished run as an SVG document (first line: [`svg_marker`]).
pub fn preview_svg(
    job: &Job,
    out: &RunOutput,
    report: &RunReport,
    opts: &PreviewOptions,
) -> Result<String, PreviewError> {
    if let Some(s) = opts.levels.iter().find(|s| !(**s > 0.0 && **s < 1.0)) {
        return Err(PreviewError::Invalid(format!(
            "equipotential values must lie strictly between 0 and 1, got {s}"
        )));
    }
    if opts.contour_cells < 10 {
        return Err(PreviewError::Invalid(
            "the equipotential grid needs at least 10 cells".into(),
        ));
    }
    let (lo, hi) = drawing_area(job, out);
    let (w, h) = (hi.x - lo.x, hi.y - lo.y);
    let size = w.max(h);
    // Type size and line width scale with the drawing (mm).
    let fs = (size / 60.0).clamp(1.5, 6.0);
    let lw = (size / 900.0).clamp(0.06, 0.3);
    let header = if report.warnings.is_empty() { 5.6 } else { 6.8 } * fs;
    let doc_w = w.max(36.0 * fs);
    let x0 = lo.x - 0.5 * (doc_w - w);
    let top_y = -hi.y - header; // SVG y of the document's top edge
    let tol_draw = (size / 4000.0).max(0.005);

    let mut body = Group::new();
    // Field colour map underneath (optional).
    let polys_draw: Vec<Vec<Vec2>> = out.shape.contours().map(|c| c.flatten(tol_draw)).collect();
    if opts.field_image {
        let img = field_image(
            &out.field,
            &polys_draw,
            &FieldImageSpec {
                lo,
                hi,
                px_per_mm: opts.image_px_per_mm,
                step_px: 2,
                map: ColourMap::RedCyan(auto_exponent(&out.field, lo, hi)),
            },
        )
        .map_err(PreviewError::Image)?;
        let png = encode_png(&img, &job.name).map_err(PreviewError::Image)?;
        body = body.add(
            Image::new()
                .set("x", num(lo.x))
                .set("y", num(-hi.y))
                .set("width", num(w))
                .set("height", num(h))
                .set("preserveAspectRatio", "none")
                .set("href", format!("data:image/png;base64,{}", base64(&png))),
        );
    }

    // Equipotential curves, farthest first.
    let mut levels = opts.levels.clone();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    // The values that have a curve inside the drawing (for the legend).
    let mut shown: Vec<f64> = Vec::new();
    if !levels.is_empty() {
        let mask = material_mask(&polys_draw);
        let part = DistanceIndex::new(&polys_draw);
        let mut placed: Vec<Vec2> = Vec::new();
        let spec = GridSpec {
            lo,
            hi,
            cell: size / opts.contour_cells as f64,
        };
        let grid = FieldGrid::sample(&out.field, &spec, &mask, 1.0)?;
        let mut g = Group::new()
            .set("fill", "none")
            .set("stroke-width", num(0.8 * lw))
            .set("class", "equipotentials");
        let mut labels = Group::new()
            .set("font-family", FONT)
            .set("font-size", num(0.6 * fs))
            .set("text-anchor", "middle")
            .set("stroke", "#ffffff")
            .set("stroke-width", num(0.25 * fs))
            .set("paint-order", "stroke")
            .set("class", "equipotential-labels");
        for (k, &s) in levels.iter().enumerate() {
            let curves = grid.level(&out.field, s, &mask);
            let colour = if opts.field_image {
                "#000000".to_string()
            } else {
                curve_colour(k, levels.len())
            };
            if !curves.is_empty() {
                shown.push(s);
            }
            // Label the longest piece at a vertex inside the frame, clear of the
            // cut, as far as possible from the labels placed so far (then as high
            // as possible): labels of close curves do not pile up.
            let inside = |p: &Vec2| {
                p.x > lo.x + 2.0 * fs
                    && p.x < hi.x - 2.0 * fs
                    && p.y < hi.y - fs
                    && p.y > lo.y + fs
                    && part.distance(*p) > job.tool.diameter + 0.5 * fs
            };
            let score = |p: &Vec2| {
                let free = placed
                    .iter()
                    .map(|q: &Vec2| q.dist(*p))
                    .fold(8.0 * fs, f64::min);
                (free, p.y)
            };
            if let Some(at) = curves
                .iter()
                .max_by(|a, b| a.length().total_cmp(&b.length()))
                .and_then(|c| {
                    c.points
                        .iter()
                        .step_by(3)
                        .filter(|p| inside(p))
                        .max_by(|a, b| {
                            score(a)
                                .partial_cmp(&score(b))
                                .unwrap_or(std::cmp::Ordering::Equal)
                        })
                })
            {
                placed.push(*at);
                labels = labels.add(
                    text(at.x, -at.y + 0.2 * fs, 0.6 * fs, &level_label(s))
                        .set("fill", colour.clone()),
                );
            }
            let closed: Vec<Vec<Vec2>> = curves
                .iter()
                .filter(|c| c.closed)
                .map(|c| c.points.clone())
                .collect();
            let open: Vec<Vec<Vec2>> = curves
                .iter()
                .filter(|c| !c.closed)
                .map(|c| c.points.clone())
                .collect();
            let d = path_data(&closed, true) + &path_data(&open, false);
            if !d.is_empty() {
                g = g.add(
                    Path::new()
                        .set("d", d)
                        .set("stroke", colour)
                        .set("data-s", num(s)),
                );
            }
        }
        body = body.add(g).add(labels);
    }

    // The part: outlines and counters, even-odd so counters are holes.
    body = body.add(
        Path::new()
            .set("d", path_data(&polys_draw, true))
            .set("fill", "#d4d4d4")
            .set("fill-rule", "evenodd")
            .set("stroke", "#1a1a1a")
            .set("stroke-width", num(lw))
            .set("class", "part"),
    );

    // Rapids, dashed.
    let mut rapids = Vec::new();
    let mut at = out.toolpath.start;
    for m in out.toolpath.moves() {
        if let Move::Rapid { to } = m {
            if xy(at).dist(xy(*to)) > 1e-9 {
                rapids.push(vec![xy(at), xy(*to)]);
            }
        }
        at = m.to();
    }
    body = body.add(
        Path::new()
            .set("d", path_data(&rapids, false))
            .set("fill", "none")
            .set("stroke", "#6b6b6b")
            .set("stroke-width", num(lw))
            .set(
                "stroke-dasharray",
                format!("{} {}", num(0.8 * fs), num(0.5 * fs)),
            )
            .set("class", "rapids"),
    );

    // The cut, one colour per level; deeper levels narrower and on top.
    let lv = run_levels(out);
    let (zmax, zmin) = (
        lv.first().map_or(0.0, |l| l.z),
        lv.last().map_or(0.0, |l| l.z),
    );
    let depth_t = |z: f64| {
        if zmax - zmin > 1e-9 {
            (zmax - z) / (zmax - zmin)
        } else {
            1.0
        }
    };
    let n_lv = lv.len();
    let mut deepest: Vec<Vec<Vec2>> = Vec::new();
    let mut cut = Group::new()
        .set("fill", "none")
        .set("stroke-linejoin", "round")
        .set("stroke-linecap", "round")
        .set("class", "toolpath");
    for (k, l) in lv.iter().enumerate() {
        let pls = level_polylines(&l.moves, tol_draw);
        let width = band_width(lw, n_lv - 1 - k, n_lv, job.tool.diameter);
        cut = cut.add(
            Path::new()
                .set("d", path_data(&pls, false))
                .set("stroke", depth_colour(depth_t(l.z)))
                .set("stroke-width", num(width))
                .set("data-z", num(l.z)),
        );
        if k + 1 == n_lv {
            deepest = pls;
        }
    }
    body = body.add(cut);

    // Direction arrows along the deepest pass.
    let diag = Vec2::new(w, h).norm();
    let a = (size / 35.0).min(0.7 * fs);
    let mut arrows = String::new();
    deepest.sort_by(|p, q| polyline_length(q).total_cmp(&polyline_length(p)));
    deepest.truncate(ARROW_TRACKS);
    for pl in &deepest {
        let len: f64 = pl.windows(2).map(|w| w[0].dist(w[1])).sum();
        if len < 3.0 * a {
            continue;
        }
        let count = ((len / (diag / 5.0)).round() as usize).clamp(2, 12);
        for (p, t) in along(pl, count) {
            let n = t.perp();
            let tip = p + t * (0.6 * a);
            let l = p - t * (0.4 * a) + n * (0.35 * a);
            let r = p - t * (0.4 * a) - n * (0.35 * a);
            arrows += &format!(
                "M{} {}L{} {}L{} {}Z",
                num(tip.x),
                num(-tip.y),
                num(l.x),
                num(-l.y),
                num(r.x),
                num(-r.y)
            );
        }
    }
    if !arrows.is_empty() {
        body = body.add(
            Path::new()
                .set("d", arrows)
                .set("fill", "#ffffff")
                .set("stroke", "#000000")
                .set("stroke-width", num(0.5 * lw))
                .set("class", "direction"),
        );
    }

    // The start: where the first feed move begins, with the tool disk.
    let mut at = out.toolpath.start;
    let mut start = None;
    for m in out.toolpath.moves() {
        if !matches!(m, Move::Rapid { .. }) {
            start = Some(xy(at));
            break;
        }
        at = m.to();
    }
    if let Some(s) = start {
        body = body
            .add(
                Circle::new()
                    .set("cx", num(s.x))
                    .set("cy", num(-s.y))
                    .set("r", num(job.tool.diameter / 2.0))
                    .set("fill", "#ff9900")
                    .set("fill-opacity", "0.45")
                    .set("stroke", "#cc6600")
                    .set("stroke-width", num(lw))
                    .set("class", "tool"),
            )
            .add(
                Circle::new()
                    .set("cx", num(s.x))
                    .set("cy", num(-s.y))
                    .set("r", num(0.3 * fs))
                    .set("fill", "#00a650")
                    .set("stroke", "#ffffff")
                    .set("stroke-width", num(0.5 * lw))
                    .set("class", "start"),
            );
    }

    // On top: the stock's edge and the work zero, what the machine is set up by.
    body = body.add(stock_and_zero(job, out, lw, fs));

    // Header: the job and its key figures.
    let t = &report.totals;
    let z_range = if n_lv == 0 {
        "no cut".to_string()
    } else if n_lv == 1 {
        format!("1 level, z {} mm", num(zmin))
    } else {
        format!("{n_lv} levels, z {} to {} mm", num(zmax), num(zmin))
    };
    let lines = [
        format!(
            "{} · tool ⌀{} mm · {}",
            report.operation,
            num(job.tool.diameter),
            z_range
        ),
        format!(
            "path {:.1} mm cutting + {:.1} mm rapid · est. time {}",
            t.cut_length_mm,
            t.rapid_length_mm,
            crate::gcode::format_duration(t.time_s)
        ),
        format!(
            "max boundary error {:.2e} · min clearance {}",
            t.max_boundary_error,
            t.min_clearance_mm
                .map_or("-".into(), |c| format!("{c:.4} mm"))
        ),
    ];
    let mut lines = lines.to_vec();
    // A finishing program is its own file, not drawn here: say so, with its
    // figures (the report's, as its header gives them).
    if let (Some(f), Some(p)) = (&job.finish, report.programs.get(1)) {
        lines.push(format!(
            "then {}: {} ⌀{} mm · {:.1} mm cutting · est. time {} (not drawn)",
            p.file,
            f.shape.header_words(),
            num(f.diameter),
            p.cut_length_mm,
            crate::gcode::format_duration(p.time_s)
        ));
    }
    if let Some(w) = report.warnings.first() {
        let mut w = format!(
            "{} warning{}: {w}",
            report.warnings.len(),
            if report.warnings.len() == 1 { "" } else { "s" }
        );
        // Keep it on the page: DejaVu Sans averages about 0.55 em a character.
        let fit = ((doc_w - 2.0 * fs) / (0.55 * 0.9 * fs)).floor().max(10.0) as usize;
        if w.chars().count() > fit {
            w = w.chars().take(fit - 1).collect::<String>() + "…";
        }
        lines.push(w);
    }
    let mut head = Group::new()
        .set("font-family", FONT)
        .set("fill", "#000000")
        .set("class", "header");
    head = head
        .add(text(x0 + fs, top_y + 1.5 * fs, 1.25 * fs, &report.job).set("font-weight", "bold"));
    for (k, l) in lines.iter().enumerate() {
        let t = text(x0 + fs, top_y + (2.9 + 1.2 * k as f64) * fs, 0.9 * fs, l);
        // The fourth line, if any, is a warning.
        head = head.add(if k == 3 { t.set("fill", "#b34700") } else { t });
    }

    // Footer: scale bar, then the legend, flowing into rows.
    let foot_y = -lo.y + 0.8 * fs; // top of the footer
    let mut foot = Group::new()
        .set("font-family", FONT)
        .set("font-size", num(0.8 * fs))
        .set("class", "legend");
    let bar = nice_length(0.3 * w);
    let (bx, by) = (x0 + fs, foot_y + 0.6 * fs);
    foot = foot
        .add(
            Rectangle::new()
                .set("x", num(bx))
                .set("y", num(by - 0.15 * fs))
                .set("width", num(bar))
                .set("height", num(0.3 * fs))
                .set("fill", "#000000")
                .set("class", "scale-bar"),
        )
        .add(text(
            bx + bar + 0.5 * fs,
            by + 0.3 * fs,
            0.8 * fs,
            &format!("{} mm", num(bar)),
        ));
    // Legend entries: (swatch, label); each is about 2 fs + 0.5 fs per character wide.
    enum Swatch {
        Line(String, f64, bool),
        Dot(String),
        /// The depth colour bar, from the shallowest to the deepest level.
        Bar,
    }
    let mut entries: Vec<(Swatch, String)> = Vec::new();
    if n_lv > BAND_LEVELS {
        entries.push((
            Swatch::Bar,
            format!("z {} … {} mm, {n_lv} levels", num(zmax), num(zmin)),
        ));
    } else {
        for (k, l) in lv.iter().enumerate() {
            let width = band_width(lw, n_lv - 1 - k, n_lv, job.tool.diameter);
            entries.push((
                Swatch::Line(depth_colour(depth_t(l.z)), width.max(0.3 * fs), false),
                format!("z {}", num(l.z)),
            ));
        }
    }
    entries.push((Swatch::Line("#6b6b6b".into(), lw, true), "rapid".into()));
    entries.push((Swatch::Dot("#00a650".into()), "start, tool ⌀".into()));
    if !shown.is_empty() {
        let vals: Vec<String> = shown.iter().map(|s| level_label(*s)).collect();
        entries.push((
            Swatch::Line(curve_colour(levels.len() - 1, levels.len()), lw, false),
            format!("Γ(s), s = {}", vals.join(", ")),
        ));
    }
    let mut x = bx + bar + 5.0 * fs;
    let mut row_y = by;
    let right = x0 + doc_w - fs;
    for (sw, label) in entries {
        // The swatch is 1.6 fs long (the colour bar 6 fs), its label follows.
        let sw_w = if matches!(sw, Swatch::Bar) { 6.0 } else { 1.6 } * fs;
        let ew = sw_w + 0.9 * fs + 0.5 * fs * label.chars().count() as f64;
        if x + ew > right && x > x0 + 2.0 * fs {
            x = x0 + fs;
            row_y += 1.4 * fs;
        }
        foot = match sw {
            Swatch::Line(c, width, dashed) => {
                let mut line = Line::new()
                    .set("x1", num(x))
                    .set("y1", num(row_y))
                    .set("x2", num(x + 1.6 * fs))
                    .set("y2", num(row_y))
                    .set("stroke", c)
                    .set("stroke-width", num(width));
                if dashed {
                    line = line.set(
                        "stroke-dasharray",
                        format!("{} {}", num(0.4 * fs), num(0.25 * fs)),
                    );
                }
                foot.add(line)
            }
            Swatch::Dot(c) => foot.add(
                Circle::new()
                    .set("cx", num(x + 0.8 * fs))
                    .set("cy", num(row_y))
                    .set("r", num(0.3 * fs))
                    .set("fill", c),
            ),
            Swatch::Bar => {
                let mut grad = LinearGradient::new()
                    .set("id", "pfcam-depth")
                    .set("x1", "0")
                    .set("x2", "1")
                    .set("y1", "0")
                    .set("y2", "0");
                for t in [0.0, 0.35, 0.7, 1.0] {
                    grad = grad.add(
                        Stop::new()
                            .set("offset", num(t))
                            .set("stop-color", depth_colour(t)),
                    );
                }
                foot.add(Definitions::new().add(grad)).add(
                    Rectangle::new()
                        .set("x", num(x))
                        .set("y", num(row_y - 0.3 * fs))
                        .set("width", num(sw_w))
                        .set("height", num(0.6 * fs))
                        .set("fill", "url(#pfcam-depth)")
                        .set("class", "depth-bar"),
                )
            }
        };
        foot = foot.add(text(
            x + sw_w + 0.4 * fs,
            row_y + 0.3 * fs,
            0.8 * fs,
            &label,
        ));
        x += ew;
    }
    let bottom = row_y + 1.2 * fs;
    let doc_h = bottom - top_y;

    let doc = Document::new()
        .set(
            "viewBox",
            format!("{} {} {} {}", num(x0), num(top_y), num(doc_w), num(doc_h)),
        )
        .set("width", format!("{}mm", num(doc_w)))
        .set("height", format!("{}mm", num(doc_h)))
        .add(Title::new(format!("pfcam preview of job {}", job.name)))
        .add(
            Rectangle::new()
                .set("x", num(x0))
                .set("y", num(top_y))
                .set("width", num(doc_w))
                .set("height", num(doc_h))
                .set("fill", "#ffffff"),
        )
        .add(body)
        .add(head)
        .add(foot);
    Ok(format!("{}\n{}\n", svg_marker(&job.name), doc))
}

/// The field's colour map over the preview's drawing area as PNG bytes
/// (`Software` chunk `pfcam <version>`). `map` gets the [`auto_exponent`] of
/// that area and returns the colour map to use.
pub fn field_png(
    job: &Job,
    out: &RunOutput,
    px_per_mm: f64,
    map: impl FnOnce(f64) -> ColourMap,
) -> Result<Vec<u8>, PreviewError> {
    let (lo, hi) = drawing_area(job, out);
    let map = map(auto_exponent(&out.field, lo, hi));
    let tol = ((hi - lo).norm() / 4000.0).max(0.005);
    let polys: Vec<Vec<Vec2>> = out.shape.contours().map(|c| c.flatten(tol)).collect();
    let img = field_image(
        &out.field,
        &polys,
        &FieldImageSpec {
            lo,
            hi,
            px_per_mm,
            step_px: 2,
            map,
        },
    )
    .map_err(PreviewError::Image)?;
    encode_png(&img, &job.name).map_err(PreviewError::Image)
}

#[cfg(test)]
mod tests {

    #[test]
    fn bands_are_never_wider_than_the_cut() {
        for d in [0.5, 3.175, 12.0] {
            for n in 1..10 {
                let widths: Vec<f64> = (0..n).map(|a| band_width(0.3, a, n, d)).collect();
                assert!(
                    widths.iter().all(|&w| w > 0.0 && w <= d + 1e-12),
                    "{d} {n}: {widths:?}"
                );
                // Shallower levels stay wider (or, with many levels, equal).
                assert!(widths.windows(2).all(|w| w[1] >= w[0]), "{widths:?}");
            }
        }
        // Unscaled when the tool is wide enough.
        assert_eq!(band_width(0.1, 2, 3, 3.175), 0.1 * 8.0);
    }

    use super::*;

    #[test]
    fn numbers_are_short_and_never_minus_zero() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(-0.0001), "0");
        assert_eq!(num(2.5), "2.5");
        assert_eq!(num(-1.23456), "-1.235");
    }

    #[test]
    fn marker_is_recognised_and_survives_odd_names() {
        let m = svg_marker("a--b");
        assert!(is_pfcam_svg(&m), "{m}");
        assert!(!m[4..m.len() - 3].contains("--"), "{m}");
        assert!(!is_pfcam_svg("<svg xmlns=\"http://www.w3.org/2000/svg\">"));
    }

    #[test]
    fn arcs_in_a_level_are_drawn_at_their_length() {
        use crate::report::feed_length_time;
        use crate::toolpath::{Section, Toolpath};
        // Plunge at (5, 0), a full circle about the origin, then a half circle back.
        let from = Vec3::new(5.0, 0.0, 1.0);
        let moves = vec![
            Move::Linear {
                to: Vec3::new(5.0, 0.0, -1.0),
                feed: 100.0,
            },
            Move::Arc {
                to: Vec3::new(5.0, 0.0, -1.0),
                cx: 0.0,
                cy: 0.0,
                ccw: true,
                feed: 600.0,
            },
            Move::Arc {
                to: Vec3::new(-5.0, 0.0, -1.0),
                cx: 0.0,
                cy: 0.0,
                ccw: false,
                feed: 600.0,
            },
        ];
        let tp = Toolpath {
            start: from,
            sections: vec![Section {
                label: "circle".into(),
                z: -1.0,
                moves,
            }],
        };
        let lv = crate::report::split_levels(&tp);
        assert_eq!(lv.len(), 1);
        let pls = level_polylines(&lv[0].moves, 0.001);
        assert_eq!(pls.len(), 1, "one continuous track");
        let drawn: f64 = pls[0].windows(2).map(|w| w[0].dist(w[1])).sum();
        let fed: f64 = lv[0]
            .moves
            .iter()
            .map(|(f, m)| feed_length_time(*f, m).0)
            .sum();
        let exact = 1.5 * std::f64::consts::TAU * 5.0;
        assert!((fed - 2.0 - exact).abs() < 1e-9, "{fed}");
        assert!((drawn - exact).abs() < 1e-3 * exact, "{drawn}");
        // Clockwise half circle from (5, 0) passes below the centre.
        assert!(pls[0].iter().any(|p| p.y < -4.9));
    }

    #[test]
    fn nice_scale_lengths() {
        assert_eq!(nice_length(57.0), 50.0);
        assert_eq!(nice_length(19.0), 10.0);
        assert_eq!(nice_length(2.2), 2.0);
    }

    #[test]
    fn arc_flattening_ends_on_the_end_point_and_stays_on_the_circle() {
        let c = Vec2::new(1.0, 2.0);
        let a = Vec2::new(6.0, 2.0);
        let b = Vec2::new(1.0, 7.0);
        let pts = flatten_arc(a, b, c, true, 0.01);
        assert_eq!(*pts.last().unwrap(), b);
        assert!(pts.iter().all(|p| (p.dist(c) - 5.0).abs() < 1e-9));
        // A quarter turn counter-clockwise passes through 45°.
        assert!(pts
            .iter()
            .any(|p| p.x > 1.0 && p.y > 2.0 && (p.x - p.y + 1.0).abs() < 0.5));
        // Same end point: a full circle.
        let full = flatten_arc(a, a, c, false, 0.01);
        let len: f64 = std::iter::once(a)
            .chain(full.iter().copied())
            .collect::<Vec<_>>()
            .windows(2)
            .map(|w| w[0].dist(w[1]))
            .sum();
        assert!((len - std::f64::consts::TAU * 5.0).abs() < 0.05, "{len}");
    }
}
