//! Shapes: lines and cubic Béziers, closed contours, regions (an outline and its
//! counters), built-in glyphs, fonts and SVG path data. Knows nothing of fields.

pub(crate) mod arc;
mod arrangement;
mod bvh;
pub(crate) mod capped;
mod cause;
mod contour;
mod densify;
mod distance;
pub mod dxffile;
pub(crate) mod fill;
pub mod font;
pub(crate) mod font_lookup;
pub mod glyphs;
mod nesting;
pub(crate) mod ring;
mod segment;
pub mod shaping;
pub mod svgfile;
pub mod svgpath;
pub(crate) mod text;
pub(crate) mod thin;
mod vec2;

pub(crate) use cause::Cause;
pub use contour::Contour;
pub(crate) use contour::Sample;
pub(crate) use densify::densify;
pub(crate) use densify::densify_values;
pub use distance::deepest_point;
pub(crate) use distance::deepest_point_in;
pub use distance::seg_seg_dist;
pub use distance::DistanceIndex;
pub use nesting::regions_from_contours;
pub(crate) use ring::closed_length;
pub use ring::polygon_area;
pub use ring::polygon_winding_number;
pub use ring::Ring;
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
    /// A font file that cannot be used.
    #[error("font file `{path}`: {reason}")]
    Font {
        /// the path as given
        path: String,
        /// what is wrong
        #[source]
        reason: font::FontFault,
    },
    /// Malformed or unsupported SVG path data.
    #[error("SVG path data: {message}, at character {offset}")]
    Svg {
        /// character offset into the `d` string, counted from 0
        offset: usize,
        /// what was found and what was expected
        message: String,
    },
    /// An SVG document that cannot be used, with the job key to look at
    /// (`shape.svg_file`, `shape.id`, `shape.width`, ...).
    #[error("{key}: {message}")]
    SvgFile {
        /// the key
        key: String,
        /// what is wrong
        message: String,
    },
    /// A user's drawing whose file cannot be read, with the job key to look
    /// at (`shape.svg_file`, `shape.dxf_file`).
    #[error("{key}: {reason}")]
    FileRead {
        /// the key
        key: &'static str,
        /// why
        #[source]
        reason: capped::ReadFault,
    },
    /// An SVG document that is not well-formed XML.
    #[error("shape.svg_file: is not an SVG document: {source}")]
    SvgXml {
        /// the XML parser's error
        source: usvg::roxmltree::Error,
    },
    /// An SVG document usvg cannot turn into a tree.
    #[error("shape.svg_file: is not a usable SVG document: {source}")]
    SvgTree {
        /// usvg's error
        source: Cause<usvg::Error>,
    },
    /// A DXF file dxf-rs cannot load.
    #[error("shape.dxf_file: is not a readable DXF file: {source}: {}", .path.display())]
    DxfLoad {
        /// the file
        path: std::path::PathBuf,
        /// dxf-rs's error
        source: Cause<dxf::DxfError>,
    },
    /// A DXF drawing that cannot be used, with the job key to look at
    /// (`shape.dxf_file`, `shape.layer`).
    #[error("{key}: {message}")]
    DxfFile {
        /// the key
        key: String,
        /// what is wrong
        message: String,
    },
    /// A number of the shape source (`height`, `letter_spacing`,
    /// `line_spacing`) that is not finite, or not positive where it must be.
    #[error("{key} must be {} of {unit}, got {value}", if *positive { "a positive number" } else { "a finite number" })]
    BadNumber {
        /// The key, e.g. `height`.
        key: &'static str,
        /// What it was given.
        value: f64,
        /// Whether it must be positive (else only finite).
        positive: bool,
        /// Its unit: `mm`, or `em` for `line_spacing`.
        unit: &'static str,
    },
    /// A point of the shape source (`origin`) that is not finite.
    #[error("{key} must be finite, got ({}, {})", at.x, at.y)]
    NotFinitePoint {
        /// The key, e.g. `origin`.
        key: &'static str,
        /// What it was given.
        at: Vec2,
    },
    /// A text whose glyphs draw nothing.
    #[error("the text {text:?} has no visible glyph to cut")]
    NoVisibleGlyph {
        /// The text.
        text: String,
    },
    /// A composed shape asked of the plain shape builder: a broken invariant
    /// (compositions are built with their fields, by `pipeline::job_shape`).
    #[error("a composition of parts is built with its fields (pipeline::job_shape)")]
    CompositeNotHere,
    /// The built-in paper glyphs could not be read (a broken build).
    #[error("built-in paper glyphs: {source}")]
    BuiltInGlyphs {
        /// The TOML parser's error.
        source: toml::de::Error,
    },
    /// A built-in glyph's segment of an unknown kind or point count.
    #[error("glyph {glyph}: bad segment kind {kind} with {points} points")]
    BadGlyphSegment {
        /// The glyph's name.
        glyph: String,
        /// The segment's kind as written.
        kind: String,
        /// Its number of points.
        points: usize,
    },
}

impl GeometryError {
    /// The job key an error of a drawing's file names (`shape.svg_file`,
    /// `shape.id`, `shape.dxf_file`, `shape.layer`, ...), its text being
    /// `key: ...`; `None` for the other errors.
    pub fn file_key(&self) -> Option<&str> {
        match self {
            GeometryError::SvgFile { key, .. } | GeometryError::DxfFile { key, .. } => Some(key),
            GeometryError::FileRead { key, .. } => Some(key),
            GeometryError::SvgXml { .. } | GeometryError::SvgTree { .. } => Some("shape.svg_file"),
            GeometryError::DxfLoad { .. } => Some("shape.dxf_file"),
            _ => None,
        }
    }
}

/// One connected piece of material: an outline (counter-clockwise) and the
/// counters (holes, clockwise) nested directly inside it.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// A human name for messages: the character and its position, e.g. `A (2)`.
    pub(crate) name: String,
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

    /// Tight bounding box of the curves themselves (see [`Segment::tight_bbox`]).
    pub fn tight_bbox(&self) -> Option<(Vec2, Vec2)> {
        self.contours()
            .filter_map(Contour::tight_bbox)
            .reduce(|(a, b), (c, d)| {
                (
                    Vec2::new(a.x.min(c.x), a.y.min(c.y)),
                    Vec2::new(b.x.max(d.x), b.y.max(d.y)),
                )
            })
    }

    /// Every point mapped through `f`.
    pub(crate) fn map(&self, f: impl Fn(Vec2) -> Vec2 + Copy) -> Shape {
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

/// Marks the points (`xs[i]`, `ys[j]`) inside the closed polygons (non-zero
/// winding), row-major (index j·xs.len() + i), `xs` ascending: each row from
/// its crossings with the polygons' edges (an edge counts where one end lies
/// at or below the row and the other above it), rows in parallel.
pub(crate) fn winding_rows(xs: &[f64], ys: &[f64], polys: &[Vec<Vec2>]) -> Vec<bool> {
    use rayon::prelude::*;
    let nx = xs.len();
    let mut inside = vec![false; nx * ys.len()];
    if nx == 0 {
        return inside;
    }
    inside.par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
        let y = ys[j];
        let mut cuts: Vec<(f64, i32)> = Vec::new();
        for poly in polys {
            for (a, b) in ring::edges(poly) {
                if (a.y <= y) != (b.y <= y) {
                    let t = (y - a.y) / (b.y - a.y);
                    cuts.push((a.x + t * (b.x - a.x), if b.y > a.y { 1 } else { -1 }));
                }
            }
        }
        cuts.sort_by(|p, q| p.0.total_cmp(&q.0));
        let (mut w, mut k) = (0, 0);
        for (i, cell) in row.iter_mut().enumerate() {
            while k < cuts.len() && cuts[k].0 <= xs[i] {
                w += cuts[k].1;
                k += 1;
            }
            *cell = w != 0;
        }
    });
    inside
}

/// Bounding box of the vertices of polygons; `None` when there are none.
pub fn polygons_bbox<P: AsRef<[Vec2]>>(polys: &[P]) -> Option<(Vec2, Vec2)> {
    let mut it = polys.iter().flat_map(|p| p.as_ref());
    let first = *it.next()?;
    Some(it.fold((first, first), |(lo, hi), p| {
        (
            Vec2::new(lo.x.min(p.x), lo.y.min(p.y)),
            Vec2::new(hi.x.max(p.x), hi.y.max(p.y)),
        )
    }))
}

/// The rectangle [ox, ox + X] × [oy, oy + Y] as a polygon, counter-clockwise
/// from its corner `origin`, `size` = [X, Y] (mm); the first point is not
/// repeated.
pub(crate) fn rectangle(origin: Vec2, size: [f64; 2]) -> Vec<Vec2> {
    let [x, y] = size;
    vec![
        origin,
        origin + Vec2::new(x, 0.0),
        origin + Vec2::new(x, y),
        origin + Vec2::new(0.0, y),
    ]
}

/// Where the lines p + u·d1 and r + v·d2 meet, as (u, v); `None` when they are
/// parallel.
pub(crate) fn line_crossing(p: Vec2, d1: Vec2, r: Vec2, d2: Vec2) -> Option<(f64, f64)> {
    let den = d1.cross(d2);
    if den.abs() < 1e-300 {
        return None;
    }
    Some(((r - p).cross(d2) / den, (r - p).cross(d1) / den))
}

/// Where a shape comes from, as the job describes it (mm).
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeSource {
    /// Lines of glyphs.
    Text {
        /// The characters, lines separated by `\n`.
        text: String,
        /// `paper` (built in) or a TrueType/OpenType file.
        font: FontSource,
        /// Cap height in mm: the font's cap height is scaled to this.
        height: f64,
        /// Extra space between letters (between clusters), mm.
        letter_spacing: f64,
        /// Baseline-to-baseline distance in em; `None` takes the font's own.
        line_spacing: Option<f64>,
        /// How each line sits on `origin.x`.
        align: Align,
        /// The first line's baseline point that `align` refers to, mm.
        origin: Vec2,
        /// The job gave `shape.lines` rather than `shape.text` (for messages).
        as_lines: bool,
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
    /// A whole SVG document (`shape.svg_file`).
    SvgFile(svgfile::SvgFileSource),
    /// A DXF drawing (`shape.dxf_file`).
    DxfFile(dxffile::DxfFileSource),
    /// Parts combined by the paper's Boolean operations on fields (Section 4);
    /// built by `field::boolean`, since every step needs a potential field.
    Composite(Composition),
    /// A harmonic tensor-product Bézier patch (`kind = "harmonic-bezier"`):
    /// a height field over a rectangle, which is its shape seen from above.
    HarmonicBezier(crate::sources::harmonic_bezier::PatchSpec),
    /// A polyharmonic solid's top envelope over a rectangle (`kind =
    /// "polyharmonic"`): a height field, its shape seen from above the
    /// rectangle.
    Polyharmonic(crate::sources::polyharmonic::PolySpec),
    /// A Bloor–Wilson PDE tube (`kind = "pde-tube"`): a boss or its mould
    /// with horizontal sections; seen from above, its widest end curve.
    PdeTube(crate::sources::pde_tube::spec::TubeSpec),
}

/// A shape built from named parts in design units (the paper's Section 5): each
/// part is a primitive, an equipotential of an earlier part, or a Boolean
/// operation on earlier parts.
#[derive(Clone, Debug, PartialEq)]
pub struct Composition {
    /// The parts, in order: a part refers only to parts before it.
    pub parts: Vec<Part>,
    /// Name of the part that is the shape.
    pub result: String,
    /// Height of the result in mm; `None` keeps 1 design unit = 1 mm.
    pub height: Option<f64>,
    /// Where the bottom-left of the result's bounding box goes, mm.
    pub origin: Vec2,
}

/// One part of a composition.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// Its name (unique), for references and messages.
    pub name: String,
    /// What it is made of.
    pub source: PartSource,
    /// When set, the part is the equipotential Γ(level) of that source's field
    /// (0 < level < 1), a new generating boundary (the paper's model set 1).
    pub level: Option<f64>,
    /// Singularities N for this part's own field; `None` chooses.
    pub singularities: Option<usize>,
}

/// What a part is made of.
#[derive(Clone, Debug, PartialEq)]
pub enum PartSource {
    /// A closed polygon, design units (either orientation).
    Polygon(Vec<Vec2>),
    /// SVG path data, design units, y up as written (no flip, no move).
    Svg(String),
    /// Glyphs, cap height `size` design units, baseline-left at the origin.
    Text {
        /// The characters.
        text: String,
        /// The font.
        font: FontSource,
        /// Cap height, design units.
        size: f64,
    },
    /// An earlier part as it is (with `level`, its equipotential).
    Ref(String),
    /// A Boolean operation on earlier parts.
    Op {
        /// Which.
        op: BoolOp,
        /// Operands, in order (`subtract`: the first minus all the others).
        of: Vec<String>,
    },
}

/// The paper's Boolean operations on MFS problems (Section 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoolOp {
    /// Ω₁ ∪ Ω₂ ∪ …
    Union,
    /// Ω₁ ∩ Ω₂ ∩ …
    Intersect,
    /// Ω₁ − Ω₂ − …
    Subtract,
    /// R² − Ω (one operand); unbounded, so only useful inside other operations.
    Invert,
}

/// A font.
#[derive(Clone, Debug, PartialEq)]
pub enum FontSource {
    /// The built-in letters of the paper.
    Paper,
    /// A TrueType/OpenType file given by its path (its first face).
    File(std::path::PathBuf),
    /// A face found by family and style name among installed fonts
    /// (`font_lookup`).
    Found {
        /// The name as the job wrote it (`DejaVu Sans Bold`).
        name: String,
        /// The font file.
        path: std::path::PathBuf,
        /// The face's index in the file (non-zero in a `.ttc` collection).
        index: u32,
    },
}

impl ShapeSource {
    /// The font files the shape's text is set in (`paper` is not a file), each
    /// once, in the order of the job.
    pub fn font_files(&self) -> Vec<&FontSource> {
        let mut out: Vec<&FontSource> = Vec::new();
        let fonts: Vec<&FontSource> = match self {
            ShapeSource::Text { font, .. } => vec![font],
            ShapeSource::Composite(c) => c
                .parts
                .iter()
                .filter_map(|p| match &p.source {
                    PartSource::Text { font, .. } => Some(font),
                    _ => None,
                })
                .collect(),
            _ => Vec::new(),
        };
        for f in fonts {
            if *f != FontSource::Paper && !out.contains(&f) {
                out.push(f);
            }
        }
        out
    }
}

impl FontSource {
    /// The font in words for a run's summary: `paper`, the file, or the name
    /// and the file it was found in.
    pub fn describe(&self) -> String {
        match self {
            FontSource::Paper => "paper (built in)".into(),
            FontSource::File(p) => p.display().to_string(),
            FontSource::Found { name, path, index } => {
                let face = if *index > 0 {
                    format!(" (face {index})")
                } else {
                    String::new()
                };
                format!("{name:?} found in {}{face}", path.display())
            }
        }
    }
}

/// Where each line of a text sits horizontally against `origin.x`: its
/// advance box (from the pen's start to its end, letter spacing between
/// clusters included) starts there, is centred on it, or ends there.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Align {
    /// The line starts at `origin.x`.
    #[default]
    Left,
    /// The line is centred on `origin.x`.
    Centre,
    /// The line ends at `origin.x`.
    Right,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The file sources' library errors say what their strings said
    /// (`{key}: {message}` with the message formatted from the error), and
    /// stay in the chain (issue 16).
    #[test]
    fn file_errors_say_the_strings_they_replace() {
        let xml = usvg::roxmltree::Document::parse("<svg")
            .map(|_| ())
            .unwrap_err();
        let path = std::path::PathBuf::from("/d/a.dxf");
        let dxf = || dxf::DxfError::UnexpectedEndOfInput;
        let missing = capped::ReadFault::NotFound { path: path.clone() };
        let cases = [
            (
                GeometryError::SvgXml {
                    source: xml.clone(),
                },
                format!("shape.svg_file: is not an SVG document: {xml}"),
            ),
            (
                GeometryError::SvgTree {
                    source: Cause::new(usvg::Error::InvalidSize),
                },
                format!(
                    "shape.svg_file: is not a usable SVG document: {}",
                    usvg::Error::InvalidSize
                ),
            ),
            (
                GeometryError::DxfLoad {
                    path: path.clone(),
                    source: Cause::new(dxf()),
                },
                format!(
                    "shape.dxf_file: is not a readable DXF file: {}: {}",
                    dxf(),
                    path.display()
                ),
            ),
            (
                GeometryError::FileRead {
                    key: "shape.dxf_file",
                    reason: missing.clone(),
                },
                format!("shape.dxf_file: {missing}"),
            ),
        ];
        for (e, text) in cases {
            assert_eq!(e.to_string(), text);
            assert!(text.starts_with(&format!("{}: ", e.file_key().expect("a key"))));
            let source = std::error::Error::source(&e).expect("a source");
            assert!(text.contains(&source.to_string()), "{text}");
        }
    }

    /// The paper's Appendix I literally: the index as the sum of the angles
    /// B_k P B_{k+1} in (−π, π), divided by 2π.
    fn index_by_angles(poly: &[Vec2], p: Vec2) -> i32 {
        let n = poly.len();
        let sum: f64 = (0..n)
            .map(|k| {
                let a = poly[k] - p;
                let b = poly[(k + 1) % n] - p;
                a.cross(b).atan2(a.dot(b))
            })
            .sum();
        (sum / std::f64::consts::TAU).round() as i32
    }

    #[test]
    fn winding_number_equals_appendix_i_angle_sum() {
        // A pentagram (winding 2 in the middle), a square and a clockwise triangle.
        let star: Vec<Vec2> = (0..5)
            .map(|k| {
                let a = std::f64::consts::FRAC_PI_2 + 4.0 * std::f64::consts::PI * k as f64 / 5.0;
                Vec2::new(10.0 * a.cos(), 10.0 * a.sin())
            })
            .collect();
        let square = vec![
            Vec2::new(-3.0, -3.0),
            Vec2::new(3.0, -3.0),
            Vec2::new(3.0, 3.0),
            Vec2::new(-3.0, 3.0),
        ];
        let tri = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(0.0, 8.0),
            Vec2::new(8.0, 0.0),
        ];
        assert_eq!(polygon_winding_number(&star, Vec2::ZERO), 2);
        assert_eq!(polygon_winding_number(&tri, Vec2::new(1.0, 1.0)), -1);
        let mut g = crate::num::testing::Lcg(7);
        let mut rnd = || (g.next() - 0.5) * 24.0;
        let mut counts = [0usize; 4];
        for _ in 0..5000 {
            let p = Vec2::new(rnd(), rnd());
            for poly in [&star, &square, &tri] {
                let w = polygon_winding_number(poly, p);
                assert_eq!(w, index_by_angles(poly, p), "at {p:?}");
                counts[(w + 1) as usize] += 1;
            }
        }
        // Every value −1, 0, 1, 2 occurred.
        assert!(counts.iter().all(|&c| c > 0), "{counts:?}");
        // Points on a vertex's horizontal line count once, not twice.
        assert_eq!(
            polygon_winding_number(&square, Vec2::new(0.0, 3.0 - 1e-12)),
            1
        );
        assert_eq!(polygon_winding_number(&square, Vec2::new(-5.0, 3.0)), 0);
    }

    /// `winding_rows` marks a point inside exactly when the union's winding
    /// number there (summed over the polygons, [`polygon_winding_number`])
    /// is not zero, on a grid that passes through vertices' rows and
    /// columns and at random points.
    #[test]
    fn winding_rows_agree_with_the_winding_number() {
        let star: Vec<Vec2> = (0..5)
            .map(|k| {
                let a = k as f64 * 4.0 * std::f64::consts::PI / 5.0;
                Vec2::new(7.0 * a.cos(), 7.0 * a.sin())
            })
            .collect();
        let hole: Vec<Vec2> = [(-2.0, -2.0), (-2.0, 2.0), (2.0, 2.0), (2.0, -2.0)]
            .iter()
            .map(|&(x, y)| Vec2::new(x + 5.0, y))
            .collect();
        let polys = vec![star, hole];
        let mut g = crate::num::testing::Lcg(11);
        let mut xs: Vec<f64> = (0..60).map(|_| g.range(-9.0, 9.0)).collect();
        xs.extend((-9..=9).map(f64::from));
        xs.sort_by(f64::total_cmp);
        let mut ys: Vec<f64> = (0..40).map(|_| g.range(-9.0, 9.0)).collect();
        ys.extend((-9..=9).map(f64::from));
        let inside = winding_rows(&xs, &ys, &polys);
        let mut both = [0usize; 2];
        for (j, &y) in ys.iter().enumerate() {
            for (i, &x) in xs.iter().enumerate() {
                let p = Vec2::new(x, y);
                let w: i32 = polys.iter().map(|q| polygon_winding_number(q, p)).sum();
                assert_eq!(inside[j * xs.len() + i], w != 0, "at {p:?}, winding {w}");
                both[usize::from(w != 0)] += 1;
            }
        }
        assert!(both[0] > 100 && both[1] > 100, "{both:?}");
        assert!(winding_rows(&[], &ys, &polys).is_empty());
    }

    #[test]
    fn shape_bbox_and_map() {
        let sq = contour::tests::square(1.0, 2.0, 3.0);
        let shape = Shape {
            regions: vec![Region {
                name: "sq".into(),
                outline: sq,
                counters: vec![],
            }],
        };
        assert_eq!(
            shape.bbox(),
            Some((Vec2::new(1.0, 2.0), Vec2::new(4.0, 5.0)))
        );
        let moved = shape.map(|p| p * 2.0);
        assert_eq!(
            moved.bbox(),
            Some((Vec2::new(2.0, 4.0), Vec2::new(8.0, 10.0)))
        );
        assert_eq!(Shape::default().bbox(), None);
    }
}
