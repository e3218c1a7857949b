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
//!
//! One file a part of the drawing: `frame` (the page and its sizes),
//! `equipotentials`, `cut` (the levels' bands), `finish` (the finishing
//! program's passes), `arrows`, `travel` (rapids and
//! the start), `stock`, `header`, `legend`; `polyline` turns the tool path into
//! XY tracks, `colours` and `svgfmt` are the shared styles and formatting.

mod arrows;
pub mod colormap;
mod colours;
mod cut;
mod equipotentials;
mod finish;
mod frame;
mod header;
mod legend;
mod marker;
mod polyline;
mod section;
mod stock;
mod svgfmt;
mod travel;

pub use colours::depth_colour;
pub(crate) use finish::FINISH_COLOUR;
pub(crate) use frame::drawing_area;
pub(crate) use marker::is_pfcam_svg;
pub(crate) use marker::svg_marker;
pub use section::section_svg;

use crate::field::isolines::ContourError;
use crate::geometry::Vec2;
use crate::job::Job;
use crate::pipeline::RunOutput;
use crate::report::{run_levels, RunReport};
use colormap::{auto_exponent, base64, encode_png, field_image, ColourMap, FieldImageSpec};
use frame::Frame;
use svg::node::element::{Group, Image, Path, Rectangle, Title};
use svg::Document;
use svgfmt::{num, path_data};

/// Equipotential values drawn by default: far (0.9) to close (0.99) to the part.
pub(crate) const DEFAULT_LEVELS: [f64; 4] = [0.9, 0.95, 0.98, 0.99];

/// The equipotentials a job's preview draws by default: for a boss or cavity
/// the part's own outlines, its top edge Γ(s_top) and its foot Γ(s_bottom)
/// (for a mould, its floor and its rim); for a profile `DEFAULT_LEVELS`; for
/// a harmonic patch or a PDE tube none (their levels are heights, not
/// equipotentials).
pub fn levels_for(job: &crate::job::Job) -> Vec<f64> {
    use crate::job::OperationKind;
    if job.shape.height_source().is_some()
        || matches!(job.shape, crate::geometry::ShapeSource::PdeTube(_))
    {
        return Vec::new();
    }
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

impl PreviewOptions {
    /// Every level strictly between 0 and 1, and at least 10 grid cells.
    fn check(&self) -> Result<(), PreviewError> {
        if let Some(s) = self.levels.iter().find(|s| !(**s > 0.0 && **s < 1.0)) {
            return Err(PreviewError::Level(*s));
        }
        if self.contour_cells < 10 {
            return Err(PreviewError::TooFewCells);
        }
        Ok(())
    }

    /// The levels to draw, sorted farthest first, each once.
    fn sorted_levels(&self) -> Vec<f64> {
        let mut levels = self.levels.clone();
        levels.sort_by(f64::total_cmp);
        levels.dedup();
        levels
    }
}

/// What can go wrong making a preview or a field image.
#[derive(Debug, thiserror::Error)]
pub enum PreviewError {
    /// The equipotential grid.
    #[error(transparent)]
    Contour(#[from] ContourError),
    /// The colour map refused the picture.
    #[error("field image: {0}")]
    Image(#[from] colormap::ImageError),
    /// The colour map's PNG encoding failed.
    #[error("field image: {0}")]
    Png(#[from] colormap::PngError),
    /// An equipotential value not strictly between 0 and 1.
    #[error("equipotential values must lie strictly between 0 and 1, got {0}")]
    Level(f64),
    /// An equipotential grid of fewer than 10 cells.
    #[error("the equipotential grid needs at least 10 cells")]
    TooFewCells,
}

/// The preview of a finished run as an SVG document (first line: [`svg_marker`]).
///
/// Drawn bottom to top: the field image (optional), the equipotentials, the
/// part, rapids, the cut, the finishing program's passes (a job with
/// `[finish]`), direction arrows, the start, the stock and work zero; then
/// the header above and the legend below.
pub fn preview_svg(
    job: &Job,
    out: &RunOutput,
    report: &RunReport,
    opts: &PreviewOptions,
) -> Result<String, PreviewError> {
    opts.check()?;
    let depths = cut::Depths::new(run_levels(out));
    let frame = Frame::new(job, out, header::text_size(job, report, &depths));
    let d = job.tool.diameter;
    let polys: Vec<Vec<Vec2>> = out
        .shape
        .contours()
        .map(|c| c.flatten(frame.tol_draw))
        .collect();
    let mut body = Group::new();
    if opts.field_image {
        body = body.add(field_underlay(
            job,
            out,
            &frame,
            &polys,
            opts.image_px_per_mm,
        )?);
    }
    let levels = opts.sorted_levels();
    let mut shown: Vec<f64> = Vec::new();
    if !levels.is_empty() {
        let e = equipotentials::equipotentials(
            job,
            out,
            &frame,
            &polys,
            &levels,
            opts.contour_cells,
            opts.field_image,
        )?;
        body = body.add(e.curves).add(e.labels);
        shown = e.shown;
    }
    body = body
        .add(part_path(&polys, frame.lw))
        .add(travel::rapids(out, &frame));
    let (cut, deepest) = cut::cut_group(&depths, frame.lw, d, frame.tol_draw);
    body = body.add(cut);
    let finish = out.finish.as_ref();
    if let Some(passes) = finish.and_then(|f| finish::finish_passes(&f.toolpath, &frame)) {
        body = body.add(passes);
    }
    if let Some(arrows) = arrows::direction_arrows(deepest, &frame) {
        body = body.add(arrows);
    }
    if let Some((tool, start)) = travel::start_marker(out, d / 2.0, &frame) {
        body = body.add(tool).add(start);
    }
    // On top: the stock's edge and the work zero, what the machine is set up by.
    body = body.add(stock::stock_and_zero(job, out, &frame));
    let head = header::header(job, report, &depths, &frame);
    let (foot, bottom) = legend::footer(&frame, &depths, d, &levels, &shown, finish.is_some());
    Ok(document(job, &frame, bottom, [body, head, foot]))
}

/// The SVG document: the marker line, then a white page from the frame's
/// top to `bottom` (SVG y) holding `groups`.
fn document(job: &Job, frame: &Frame, bottom: f64, groups: [Group; 3]) -> String {
    let (x0, top_y, doc_w) = (frame.x0, frame.top_y, frame.doc_w);
    let doc_h = bottom - top_y;
    let mut doc = Document::new()
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
        );
    for g in groups {
        doc = doc.add(g);
    }
    format!("{}\n{}\n", svg_marker(&job.name), doc)
}

/// The part: outlines and counters, even-odd so counters are holes.
fn part_path(polys: &[Vec<Vec2>], lw: f64) -> Path {
    Path::new()
        .set("d", path_data(polys, true))
        .set("fill", "#d4d4d4")
        .set("fill-rule", "evenodd")
        .set("stroke", "#1a1a1a")
        .set("stroke-width", num(lw))
        .set("class", "part")
}

/// The field's colour map over the drawing area as an embedded PNG, to lie
/// under the drawing.
fn field_underlay(
    job: &Job,
    out: &RunOutput,
    frame: &Frame,
    polys: &[Vec<Vec2>],
    px_per_mm: f64,
) -> Result<Image, PreviewError> {
    let (lo, hi) = (frame.lo, frame.hi);
    let map = ColourMap::RedCyan(auto_exponent(&out.field, lo, hi));
    let png = area_png(job, out, (lo, hi), polys, px_per_mm, map)?;
    Ok(Image::new()
        .set("x", num(lo.x))
        .set("y", num(-hi.y))
        .set("width", num(frame.w))
        .set("height", num(frame.h))
        .set("preserveAspectRatio", "none")
        .set("href", format!("data:image/png;base64,{}", base64(&png))))
}

/// The field's colour map `map` over the rectangle `(lo, hi)`, the part
/// `polys` in the material colour, as PNG bytes (`Software` chunk
/// `pfcam <version>`).
fn area_png(
    job: &Job,
    out: &RunOutput,
    (lo, hi): (Vec2, Vec2),
    polys: &[Vec<Vec2>],
    px_per_mm: f64,
    map: ColourMap,
) -> Result<Vec<u8>, PreviewError> {
    let img = field_image(
        &out.field,
        polys,
        &FieldImageSpec {
            lo,
            hi,
            px_per_mm,
            step_px: 2,
            map,
        },
    )?;
    Ok(encode_png(&img, &job.name)?)
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
    area_png(job, out, (lo, hi), &polys, px_per_mm, map)
}
