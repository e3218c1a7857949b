//! The page: the rectangle of the part the preview pictures, and the sizes
//! (type, lines, header, document width) that scale with it. All in mm.

use crate::geometry::Vec2;
use crate::job::Job;
use crate::pipeline::RunOutput;

/// The rectangle the preview (and `pfcam field`) pictures: the part, the tool
/// path (rapids included) and the program's start point, with a margin of
/// 5 % of the diagonal but at least two tool diameters and 3 mm.
pub(crate) fn drawing_area(job: &Job, out: &RunOutput) -> (Vec2, Vec2) {
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
    add(out.toolpath.start.xy());
    for m in out.toolpath.moves() {
        add(m.to().xy());
    }
    let margin = (0.05 * (hi - lo).norm())
        .max(2.0 * job.tool.diameter)
        .max(3.0);
    let d = Vec2::new(margin, margin);
    (lo - d, hi + d)
}

/// The preview's page: the drawing area in part coordinates and the sizes
/// derived from it.
pub(super) struct Frame {
    /// Lower-left corner of the drawing area (part coordinates, y up).
    pub(crate) lo: Vec2,
    /// Upper-right corner of the drawing area.
    pub(crate) hi: Vec2,
    /// Width of the drawing area.
    pub(crate) w: f64,
    /// Height of the drawing area.
    pub(crate) h: f64,
    /// The longer of `w` and `h`.
    pub(crate) size: f64,
    /// Type size: size / 60, within 1.5 to 6.
    pub(crate) fs: f64,
    /// Base line width: size / 900, within 0.06 to 0.3.
    pub(crate) lw: f64,
    /// Document width: the drawing's, but at least 36 type sizes for the text.
    pub(crate) doc_w: f64,
    /// SVG x of the document's left edge (the drawing centred in it).
    pub(crate) x0: f64,
    /// SVG y of the document's top edge, above the header.
    pub(crate) top_y: f64,
    /// Chord tolerance for drawing curves: size / 4000, at least 0.005.
    pub(crate) tol_draw: f64,
}

impl Frame {
    /// The page of a run's preview under a header of `lines` lines of text
    /// below the job's name, the longest `widest` characters: the header is
    /// 1.2 type sizes taller for each line past three, and the page wide
    /// enough for the longest line at type size 0.9 (DejaVu Sans averages
    /// about 0.55 em a character; a finishing program's line ran off a
    /// narrow part's page).
    pub(crate) fn new(job: &Job, out: &RunOutput, (lines, widest): (usize, usize)) -> Frame {
        let (lo, hi) = drawing_area(job, out);
        let (w, h) = (hi.x - lo.x, hi.y - lo.y);
        let size = w.max(h);
        let fs = (size / 60.0).clamp(1.5, 6.0);
        let lw = (size / 900.0).clamp(0.06, 0.3);
        let header = (5.6 + 1.2 * lines.saturating_sub(3) as f64) * fs;
        let text_w = (widest as f64 * 0.55 * 0.9 + 2.0) * fs;
        let doc_w = w.max(36.0 * fs).max(text_w);
        Frame {
            lo,
            hi,
            w,
            h,
            size,
            fs,
            lw,
            doc_w,
            x0: lo.x - 0.5 * (doc_w - w),
            top_y: -hi.y - header,
            tol_draw: (size / 4000.0).max(0.005),
        }
    }
}
