//! Shapes: lines and cubic Béziers, closed contours, regions (an outline and its
//! counters), built-in glyphs, fonts and SVG path data. Knows nothing of fields.

mod contour;
mod distance;
pub mod glyphs;
mod segment;
pub mod text;
mod vec2;

pub use contour::{Contour, Corner, Sample, JOIN_EPS};
pub use distance::{seg_seg_dist, DistanceIndex};
pub use segment::Segment;
pub use text::build_shape;
pub use vec2::Vec2;

/// What can be wrong with a shape.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum GeometryError {
    /// A contour with no segments.
    #[error("a contour has no segments")]
    Empty,
    /// A contour whose pieces do not join up.
    #[error("the contour is open: a segment ends at ({:.4}, {:.4}) but the next starts at ({:.4}, {:.4})", at.x, at.y, next.x, next.y)]
    Open {
        /// where a segment ends
        at: Vec2,
        /// where the next one starts
        next: Vec2,
    },
    /// A glyph that the font does not have.
    #[error("the font `{font}` has no glyph for {ch:?}")]
    MissingGlyph {
        /// font name or path
        font: String,
        /// the character
        ch: char,
    },
    /// Anything else wrong with the shape source, said in words.
    #[error("{0}")]
    Invalid(String),
}

/// One connected piece of material: an outline (counter-clockwise) and the
/// counters (holes, clockwise) nested directly inside it.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// A human name for messages: the character and its position, e.g. `A (2)`.
    pub name: String,
    /// The outer boundary, counter-clockwise.
    pub outline: Contour,
    /// The holes, each clockwise.
    pub counters: Vec<Contour>,
}

/// A whole shape in millimetres: every region of every glyph.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Shape {
    /// The regions, in reading order.
    pub regions: Vec<Region>,
}

impl Shape {
    /// Every contour (outlines and counters), in order.
    pub fn contours(&self) -> impl Iterator<Item = &Contour> {
        self.regions
            .iter()
            .flat_map(|r| std::iter::once(&r.outline).chain(r.counters.iter()))
    }

    /// Bounding box of the control points of every contour.
    pub fn bbox(&self) -> Option<(Vec2, Vec2)> {
        self.contours()
            .filter_map(Contour::bbox)
            .reduce(|(a, b), (c, d)| {
                (
                    Vec2::new(a.x.min(c.x), a.y.min(c.y)),
                    Vec2::new(b.x.max(d.x), b.y.max(d.y)),
                )
            })
    }

    /// Every point mapped through `f`.
    pub fn map(&self, f: impl Fn(Vec2) -> Vec2 + Copy) -> Shape {
        Shape {
            regions: self
                .regions
                .iter()
                .map(|r| Region {
                    name: r.name.clone(),
                    outline: r.outline.map(f),
                    counters: r.counters.iter().map(|c| c.map(f)).collect(),
                })
                .collect(),
        }
    }
}

/// Winding number of a closed polygon about `p` (the polygon's last vertex joins
/// its first). This is the index (8.2) of the paper's Appendix I, evaluated exactly
/// for straight edges by counting signed crossings of the ray to +x.
pub fn polygon_winding_number(poly: &[Vec2], p: Vec2) -> i32 {
    let n = poly.len();
    let mut w = 0;
    for i in 0..n {
        let a = poly[i];
        let b = poly[(i + 1) % n];
        if a.y <= p.y {
            if b.y > p.y && (b - a).cross(p - a) > 0.0 {
                w += 1;
            }
        } else if b.y <= p.y && (b - a).cross(p - a) < 0.0 {
            w -= 1;
        }
    }
    w
}

/// Where a shape comes from, as the job describes it (mm).
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeSource {
    /// A string of glyphs.
    Text {
        /// The characters.
        text: String,
        /// `paper` (built in) or a TrueType/OpenType file.
        font: FontSource,
        /// Cap height in mm: the font's cap height is scaled to this.
        height: f64,
        /// Extra space between letters, mm.
        letter_spacing: f64,
        /// Where the baseline-left of the first glyph goes, mm.
        origin: Vec2,
    },
    /// SVG path data (`d` attribute syntax).
    SvgPath {
        /// The path data.
        d: String,
        /// Height of the result in mm; `None` keeps 1 unit = 1 mm.
        height: Option<f64>,
        /// Where the bottom-left of the bounding box goes, mm.
        origin: Vec2,
    },
}

/// A font.
#[derive(Clone, Debug, PartialEq)]
pub enum FontSource {
    /// The built-in letters of the paper.
    Paper,
    /// A TrueType/OpenType file.
    File(std::path::PathBuf),
}
