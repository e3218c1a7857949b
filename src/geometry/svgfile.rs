//! A whole SVG document (`shape.svg_file`), read by usvg, the parser behind
//! resvg: it resolves units, the viewBox, transforms, `<use>`, CSS and the
//! basic shapes (rect with rounded corners, circle, ellipse, line, polyline,
//! polygon) into paths of lines and Béziers, its arcs as cubics. Every visible
//! element with a fill is material: its outline is what it fills under its own
//! `fill-rule` (`fill.rs`), and the elements are united as paint covers paint.
//! Strokes, images, clip paths and masks are not read.
//!
//! Units: usvg's user space is CSS px at 96 per inch, so 1 px = 25.4/96 mm;
//! `mm`, `cm`, `in`, `pt` in width/height keep their length. The result is
//! flipped (y up), flattened within the job's tolerance, scaled (`scale`, or
//! so the outline's box is `width` or `height` mm), and moved so the box's
//! bottom-left corner is at `origin`.

use std::path::{Path, PathBuf};

use usvg::roxmltree;

use super::fill::{fill_outlines, FillRule};
use super::{
    polygons_bbox, regions_from_contours, Cause, Contour, GeometryError, Segment, Shape, Vec2,
};

/// Millimetres per CSS px (96 px to the inch).
pub(crate) const MM_PER_PX: f64 = 25.4 / 96.0;

/// Largest SVG file read, bytes.
pub(crate) const MAX_SVG_BYTES: u64 = 32 << 20;

/// Most XML nodes parsed (elements, text, attributes' nodes).
pub(crate) const MAX_XML_NODES: u32 = 1_000_000;

/// Most vertices of the flattened outlines.
pub(crate) const MAX_VERTICES: usize = 500_000;

/// How big the document's drawing becomes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SvgSize {
    /// As the document says (its units, px at 96 dpi).
    Natural,
    /// The document's size times this.
    Scale(f64),
    /// The outline's box this many mm wide.
    Width(f64),
    /// The outline's box this many mm high.
    Height(f64),
}

/// A whole SVG document as a shape source (`shape.svg_file`).
#[derive(Clone, Debug, PartialEq)]
pub struct SvgFileSource {
    /// The file, resolved against the job's directory.
    pub path: PathBuf,
    /// `shape.id`: only this element (and what it contains).
    pub id: Option<String>,
    /// The size.
    pub size: SvgSize,
    /// Where the bottom-left corner of the outline's box goes, mm.
    pub origin: Vec2,
    /// Curves are flattened within this, mm (`operation.tolerance`).
    pub tolerance: f64,
    /// The largest width or height accepted, mm (the job's bound for its tool).
    pub max_size: f64,
}

fn fail(key: &str, message: impl Into<String>) -> GeometryError {
    GeometryError::SvgFile {
        key: key.to_string(),
        message: message.into(),
    }
}

const FILE: &str = "shape.svg_file";

/// The shape a document draws (see the module documentation).
pub fn svg_file_shape(src: &SvgFileSource) -> Result<Shape, GeometryError> {
    let text = read_document(&src.path)?;
    let opts = roxmltree::ParsingOptions {
        allow_dtd: true,
        nodes_limit: MAX_XML_NODES,
        ..roxmltree::ParsingOptions::default()
    };
    let doc = roxmltree::Document::parse_with_options(&text, opts)
        .map_err(|source| GeometryError::SvgXml { source })?;
    check_document(&doc)?;
    let tree = usvg::Tree::from_xmltree(&doc, &usvg::Options::default()).map_err(|e| {
        GeometryError::SvgTree {
            source: Cause::new(e),
        }
    })?;
    let mut paths = Vec::new();
    let key = match &src.id {
        Some(id) => {
            collect_node(pick(&tree, &doc, id)?, &mut paths);
            "shape.id"
        }
        None => {
            collect_group(tree.root(), &mut paths);
            FILE
        }
    };
    if paths.is_empty() {
        return Err(fail(key, nothing_filled(src.id.as_deref())));
    }
    place(&paths, src, key)
}

/// The bytes of the file as UTF-8 text, refused past [`MAX_SVG_BYTES`].
fn read_document(path: &Path) -> Result<String, GeometryError> {
    let shown = path.display();
    let bytes = super::capped::read_capped(path, "an SVG", MAX_SVG_BYTES)
        .map_err(|reason| GeometryError::FileRead { key: FILE, reason })?;
    if bytes.starts_with(&[0x1f, 0x8b]) {
        return Err(fail(
            FILE,
            format!("is compressed (.svgz); unpack it with gunzip first: {shown}"),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        fail(
            FILE,
            format!(
                "is not an SVG document: it is not UTF-8 text (byte {} is not valid): {shown}",
                e.utf8_error().valid_up_to() + 1
            ),
        )
    })
}

/// An `<svg>` root, and no text (which pfcam does not turn into outlines).
fn check_document(doc: &roxmltree::Document) -> Result<(), GeometryError> {
    let root = doc.root_element();
    if root.tag_name().name() != "svg" {
        return Err(fail(
            FILE,
            format!(
                "is not an SVG document: its root element is <{}>, not <svg>",
                root.tag_name().name()
            ),
        ));
    }
    let text = doc.descendants().find(|n| {
        n.is_element()
            && n.tag_name().name() == "text"
            && n.descendants()
                .any(|t| t.is_text() && !t.text().unwrap_or("").trim().is_empty())
    });
    if let Some(t) = text {
        let pos = doc.text_pos_at(t.range().start);
        return Err(fail(
            FILE,
            format!(
                "has text (<text> at line {}, column {}), which pfcam does not turn into outlines: convert it to paths in the drawing program (Inkscape: Path > Object to Path)",
                pos.row, pos.col
            ),
        ));
    }
    Ok(())
}

/// The node `id` names.
fn pick<'a>(
    tree: &'a usvg::Tree,
    doc: &roxmltree::Document,
    id: &str,
) -> Result<&'a usvg::Node, GeometryError> {
    match tree.node_by_id(id) {
        Some(node) => Ok(node),
        None => {
            let in_doc = doc.descendants().any(|n| n.attribute("id") == Some(id));
            if in_doc {
                return Err(fail(
                    "shape.id",
                    format!("names \"{id}\", which draws nothing (it is hidden, empty or only a definition in <defs>)"),
                ));
            }
            let ids: Vec<&str> = doc
                .descendants()
                .filter_map(|n| n.attribute("id"))
                .take(12)
                .collect();
            let list = if ids.is_empty() {
                "the document has no ids".to_string()
            } else {
                format!("ids there: {}", ids.join(", "))
            };
            Err(fail(
                "shape.id",
                format!("\"{id}\" is not the id of any element of the document ({list})"),
            ))
        }
    }
}

/// A filled path: its subpaths in mm (y up, not yet scaled) and its rule.
struct Filled {
    subpaths: Vec<Vec<Segment>>,
    rule: FillRule,
}

fn collect_group(g: &usvg::Group, out: &mut Vec<Filled>) {
    for child in g.children() {
        collect_node(child, out);
    }
}

/// Every visible path with a fill under `node`, in page millimetres.
fn collect_node(node: &usvg::Node, out: &mut Vec<Filled>) {
    match node {
        usvg::Node::Group(g) => collect_group(g, out),
        usvg::Node::Path(p) => {
            let Some(fill) = p.fill().filter(|_| p.is_visible()) else {
                return;
            };
            let rule = match fill.rule() {
                usvg::FillRule::NonZero => FillRule::NonZero,
                usvg::FillRule::EvenOdd => FillRule::EvenOdd,
            };
            let subpaths = subpaths_mm(p.data(), p.abs_transform());
            if !subpaths.is_empty() {
                out.push(Filled { subpaths, rule });
            }
        }
        usvg::Node::Image(_) | usvg::Node::Text(_) => {}
    }
}

/// The path's subpaths through `ts`, in mm with y up. Every subpath is closed
/// (a fill closes an open one with a straight line).
fn subpaths_mm(data: &usvg::tiny_skia_path::Path, ts: usvg::Transform) -> Vec<Vec<Segment>> {
    use usvg::tiny_skia_path::PathSegment as S;
    let map = |p: usvg::tiny_skia_path::Point| {
        let (x, y) = (f64::from(p.x), f64::from(p.y));
        let px = f64::from(ts.sx) * x + f64::from(ts.kx) * y + f64::from(ts.tx);
        let py = f64::from(ts.ky) * x + f64::from(ts.sy) * y + f64::from(ts.ty);
        Vec2::new(px * MM_PER_PX, -py * MM_PER_PX)
    };
    let mut out: Vec<Vec<Segment>> = Vec::new();
    let mut cur: Vec<Segment> = Vec::new();
    let (mut start, mut at) = (Vec2::ZERO, Vec2::ZERO);
    let mut finish = |cur: &mut Vec<Segment>, at: Vec2, start: Vec2| {
        if cur.is_empty() {
            return;
        }
        if at != start {
            cur.push(Segment::Line { a: at, b: start });
        }
        out.push(std::mem::take(cur));
    };
    for seg in data.segments() {
        match seg {
            S::MoveTo(p) => {
                finish(&mut cur, at, start);
                start = map(p);
                at = start;
            }
            S::LineTo(p) => {
                let b = map(p);
                cur.push(Segment::Line { a: at, b });
                at = b;
            }
            S::QuadTo(q, p) => {
                let b = map(p);
                cur.push(Segment::quad(at, map(q), b));
                at = b;
            }
            S::CubicTo(p1, p2, p) => {
                let b = map(p);
                cur.push(Segment::Cubic {
                    p0: at,
                    p1: map(p1),
                    p2: map(p2),
                    p3: b,
                });
                at = b;
            }
            S::Close => {
                finish(&mut cur, at, start);
                at = start;
            }
        }
    }
    finish(&mut cur, at, start);
    out
}

/// What the paths fill, flattened within the tolerance at the final scale,
/// scaled and placed.
fn place(paths: &[Filled], src: &SvgFileSource, key: &str) -> Result<Shape, GeometryError> {
    let boxes = paths
        .iter()
        .flat_map(|f| f.subpaths.iter().flatten())
        .map(Segment::tight_bbox);
    let (lo0, hi0) = boxes
        .reduce(|(a, b), (c, d)| {
            (
                Vec2::new(a.x.min(c.x), a.y.min(c.y)),
                Vec2::new(b.x.max(d.x), b.y.max(d.y)),
            )
        })
        .ok_or_else(|| fail(key, nothing_filled(src.id.as_deref())))?;
    let mut scale = scale_for(src.size, hi0 - lo0, key)?;
    check_size((hi0 - lo0) * scale, src, key)?;
    // Flatten at the scale the curves' box gives; the outline's box can only be
    // smaller, its scale larger: then flatten once more at that scale.
    for pass in 0..2 {
        let loops = outlines(paths, src.tolerance / scale)?;
        let (lo, hi) =
            polygons_bbox(&loops).ok_or_else(|| fail(key, nothing_filled(src.id.as_deref())))?;
        let exact = scale_for(src.size, hi - lo, key)?;
        if pass == 1 || exact <= scale * (1.0 + 1e-9) {
            return Ok(Shape {
                regions: regions(&loops, lo, exact, src, key)?,
            });
        }
        scale = exact;
    }
    Err(fail(key, nothing_filled(src.id.as_deref())))
}

/// An error when the drawing, `size` mm, is larger than the job allows.
fn check_size(size: Vec2, src: &SvgFileSource, key: &str) -> Result<(), GeometryError> {
    if size.x <= src.max_size && size.y <= src.max_size {
        return Ok(());
    }
    let advice = match src.size {
        SvgSize::Natural => "set shape.width, shape.height or shape.scale to scale it",
        _ => "make it smaller",
    };
    let key = match src.size {
        SvgSize::Natural => key,
        SvgSize::Scale(_) => "shape.scale",
        SvgSize::Width(_) => "shape.width",
        SvgSize::Height(_) => "shape.height",
    };
    Err(fail(
        key,
        format!(
            "makes the drawing {:.1} × {:.1} mm, larger than the {} mm this job allows for its tool: {advice}",
            size.x, size.y, src.max_size
        ),
    ))
}

/// The regions of `loops` scaled by `scale` about `lo`, placed at the origin.
fn regions(
    loops: &[Vec<Vec2>],
    lo: Vec2,
    scale: f64,
    src: &SvgFileSource,
    key: &str,
) -> Result<Vec<super::Region>, GeometryError> {
    let contours: Vec<Contour> = loops
        .iter()
        .filter_map(|l| {
            let pts: Vec<Vec2> = l.iter().map(|&p| src.origin + (p - lo) * scale).collect();
            Contour::polygon(&pts).ok()
        })
        .collect();
    let name = src.id.clone().unwrap_or_else(|| "svg".into());
    let regions = regions_from_contours(&name, contours);
    if regions.is_empty() {
        return Err(fail(key, nothing_filled(src.id.as_deref())));
    }
    Ok(regions)
}

/// The loops each path fills under its rule, united over the paths.
fn outlines(paths: &[Filled], tol: f64) -> Result<Vec<Vec<Vec2>>, GeometryError> {
    let too_many = || {
        fail(
            FILE,
            format!("is too detailed: flattened within operation.tolerance its outlines have more than {MAX_VERTICES} vertices (or cross each other too often); simplify it or raise operation.tolerance"),
        )
    };
    let mut vertices = 0;
    let mut all = Vec::new();
    for f in paths {
        let mut polys = Vec::with_capacity(f.subpaths.len());
        for sub in &f.subpaths {
            let mut pts = vec![sub[0].start()];
            for s in sub {
                s.flatten_into(tol, &mut pts);
            }
            pts.pop();
            vertices += pts.len();
            if vertices > MAX_VERTICES {
                return Err(too_many());
            }
            polys.push(pts);
        }
        all.extend(fill_outlines(&polys, f.rule).map_err(|_| too_many())?);
    }
    if paths.len() > 1 {
        all = fill_outlines(&all, FillRule::NonZero).map_err(|_| too_many())?;
    }
    Ok(all)
}

/// mm per document mm for a drawing whose box is `size` mm.
fn scale_for(spec: SvgSize, size: Vec2, key: &str) -> Result<f64, GeometryError> {
    let by = |want: f64, have: f64, what: &str| {
        if have > 0.0 && have.is_finite() {
            Ok(want / have)
        } else {
            Err(fail(
                key,
                format!("fills nothing with a {what}, so it cannot be scaled to a {what}"),
            ))
        }
    };
    match spec {
        SvgSize::Natural => Ok(1.0),
        SvgSize::Scale(s) => Ok(s),
        SvgSize::Width(w) => by(w, size.x, "width"),
        SvgSize::Height(h) => by(h, size.y, "height"),
    }
}

fn nothing_filled(id: Option<&str>) -> String {
    let what = match id {
        Some(id) => format!("the element \"{id}\""),
        None => "the document".into(),
    };
    format!("{what} fills nothing: no visible element has a fill (strokes, text and images are not read)")
}
