//! TrueType/OpenType fonts from a file, through `ttf-parser`: glyph outlines in
//! font units (y up), cap height and line height. Positioning (advances,
//! kerning, ligatures, marks) is the shaper's: `geometry::shaping`.
//!
//! Quadratic (TrueType) curves are raised to cubics exactly with
//! [`Segment::quad`]; CFF cubics are kept as they are.

use super::{Cause, Contour, GeometryError, Segment, Vec2};
use std::path::Path;

/// A font file read into memory and checked to parse.
pub struct FontFile {
    /// The path as given, for messages.
    pub(crate) name: String,
    data: Vec<u8>,
    /// The face's index in a collection (`.ttc`); 0 for a single font.
    index: u32,
}

/// Why a font file cannot be used ([`GeometryError::Font`]).
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum FontFault {
    /// The file cannot be opened.
    #[error("{0}")]
    Open(#[source] Cause<std::io::Error>),
    /// The file cannot be read.
    #[error("{0}")]
    Read(#[source] Cause<std::io::Error>),
    /// The file is larger than [`MAX_FONT_BYTES`].
    #[error("larger than {cap} bytes; not a font file")]
    TooLarge {
        /// The cap, bytes.
        cap: u64,
    },
    /// `ttf-parser` refuses the face.
    #[error("not a TrueType/OpenType font ({0})")]
    NotAFont(#[source] ttf_parser::FaceParsingError),
    /// No cap height to size the text by.
    #[error("the font gives no cap height (OS/2) and has no glyph `H` to measure it")]
    NoCapHeight,
    /// A glyph's outline is not a closed contour.
    #[error("glyph for {what:?}: {source}")]
    Glyph {
        /// The characters the glyph stands for.
        what: String,
        /// What is wrong with its outline.
        source: Box<GeometryError>,
    },
}

fn font_err(name: &str, reason: FontFault) -> GeometryError {
    GeometryError::Font {
        path: name.to_string(),
        reason,
    }
}

/// Largest font file read, bytes: the largest CJK fonts are about 20 MB; a
/// larger file is refused before it is read into memory.
pub(crate) const MAX_FONT_BYTES: u64 = 64 << 20;

impl FontFile {
    /// Reads and checks face `index` of the font at `path` (0 for a single font;
    /// a face of a `.ttc` collection otherwise). Errors name the path: missing,
    /// unreadable, larger than [`MAX_FONT_BYTES`], or not a TrueType/OpenType font.
    pub fn open(path: &Path, index: u32) -> Result<FontFile, GeometryError> {
        let name = path.display().to_string();
        let data = read_capped(path, MAX_FONT_BYTES)?;
        let file = FontFile { name, data, index };
        file.face()?;
        Ok(file)
    }

    /// The parsed face, ready for the shaper (it dereferences to a
    /// `ttf_parser::Face` for outlines and metrics).
    pub fn face(&self) -> Result<rustybuzz::Face<'_>, GeometryError> {
        ttf_parser::Face::parse(&self.data, self.index)
            .map(rustybuzz::Face::from_face)
            .map_err(|e| font_err(&self.name, FontFault::NotAFont(e)))
    }
}

/// The bytes of the file at `path`, refused past `cap` bytes without reading
/// further.
fn read_capped(path: &Path, cap: u64) -> Result<Vec<u8>, GeometryError> {
    use std::io::Read;
    let name = path.display().to_string();
    let file =
        std::fs::File::open(path).map_err(|e| font_err(&name, FontFault::Open(Cause::new(e))))?;
    let mut data = Vec::new();
    file.take(cap + 1)
        .read_to_end(&mut data)
        .map_err(|e| font_err(&name, FontFault::Read(Cause::new(e))))?;
    if data.len() as u64 > cap {
        return Err(font_err(&name, FontFault::TooLarge { cap }));
    }
    Ok(data)
}

/// The cap height in font units: the OS/2 `sCapHeight` when present and positive,
/// else the top of the glyph `H`.
pub fn cap_height(face: &ttf_parser::Face<'_>, name: &str) -> Result<f64, GeometryError> {
    if let Some(h) = face.capital_height().filter(|&h| h > 0) {
        return Ok(f64::from(h));
    }
    face.glyph_index('H')
        .and_then(|id| face.glyph_bounding_box(id))
        .map(|r| f64::from(r.y_max))
        .filter(|&h| h > 0.0)
        .ok_or_else(|| font_err(name, FontFault::NoCapHeight))
}

/// Baseline-to-baseline distance the font asks for, font units: ascender −
/// descender + line gap, as `ttf-parser` reads them (the `hhea` values, or
/// the OS/2 typographic ones when the font sets USE_TYPO_METRICS or `hhea`
/// gives none). `None` when that sum is not positive.
pub fn line_height(face: &ttf_parser::Face<'_>) -> Option<f64> {
    let h = f64::from(face.ascender()) - f64::from(face.descender()) + f64::from(face.line_gap());
    (h > 0.0).then_some(h)
}

/// The outline of glyph `id` as closed contours in font units, as the font
/// orders and orients them; none for an empty glyph (a space). `what` names
/// the glyph in errors (the characters it stands for).
pub(crate) fn outline(
    face: &ttf_parser::Face<'_>,
    name: &str,
    id: u16,
    what: &str,
) -> Result<Vec<Contour>, GeometryError> {
    let mut b = Builder::default();
    // `None` means an empty outline (a space): no contours.
    let _ = face.outline_glyph(ttf_parser::GlyphId(id), &mut b);
    b.finish();
    b.contours
        .into_iter()
        .filter(|segs| !segs.is_empty())
        .map(Contour::new)
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| {
            let what = what.to_string();
            font_err(
                name,
                FontFault::Glyph {
                    what,
                    source: Box::new(e),
                },
            )
        })
}

/// Collects `ttf-parser` outline callbacks into closed segment lists.
#[derive(Default)]
struct Builder {
    contours: Vec<Vec<Segment>>,
    current: Vec<Segment>,
    start: Vec2,
    pen: Vec2,
}

impl Builder {
    /// Closes the open contour, if any, with a line back to its start.
    fn finish(&mut self) {
        if self.current.is_empty() {
            return;
        }
        if self.pen != self.start {
            self.current.push(Segment::Line {
                a: self.pen,
                b: self.start,
            });
        }
        self.contours.push(std::mem::take(&mut self.current));
        self.pen = self.start;
    }
}

fn p(x: f32, y: f32) -> Vec2 {
    Vec2::new(f64::from(x), f64::from(y))
}

impl ttf_parser::OutlineBuilder for Builder {
    fn move_to(&mut self, x: f32, y: f32) {
        self.finish();
        self.start = p(x, y);
        self.pen = self.start;
    }
    fn line_to(&mut self, x: f32, y: f32) {
        let b = p(x, y);
        if b != self.pen {
            self.current.push(Segment::Line { a: self.pen, b });
        }
        self.pen = b;
    }
    fn quad_to(&mut self, x1: f32, y1: f32, x: f32, y: f32) {
        let (q, b) = (p(x1, y1), p(x, y));
        // A curve collapsed onto one point has no tangent: leave it out.
        if !(q == self.pen && b == self.pen) {
            self.current.push(Segment::quad(self.pen, q, b));
        }
        self.pen = b;
    }
    fn curve_to(&mut self, x1: f32, y1: f32, x2: f32, y2: f32, x: f32, y: f32) {
        let (c1, c2, b) = (p(x1, y1), p(x2, y2), p(x, y));
        if !(c1 == self.pen && c2 == self.pen && b == self.pen) {
            self.current.push(Segment::Cubic {
                p0: self.pen,
                p1: c1,
                p2: c2,
                p3: b,
            });
        }
        self.pen = b;
    }
    fn close(&mut self) {
        self.finish();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The texts are the ones the causes had as strings (issue 16), and the
    /// I/O error stays in the chain.
    #[test]
    fn faults_say_the_strings_they_replace() {
        let io = || std::io::Error::new(std::io::ErrorKind::NotFound, "No such file");
        let (cap, parse) = (1u64 << 26, ttf_parser::FaceParsingError::UnknownMagic);
        let glyph = GeometryError::Empty;
        let cases = [
            (FontFault::Open(Cause::new(io())), io().to_string()),
            (FontFault::Read(Cause::new(io())), io().to_string()),
            (
                FontFault::TooLarge { cap },
                format!("larger than {cap} bytes; not a font file"),
            ),
            (
                FontFault::NotAFont(parse),
                format!("not a TrueType/OpenType font ({parse})"),
            ),
            (
                FontFault::NoCapHeight,
                "the font gives no cap height (OS/2) and has no glyph `H` to measure it".into(),
            ),
            (
                FontFault::Glyph {
                    what: "fi".into(),
                    source: Box::new(glyph.clone()),
                },
                format!("glyph for {:?}: {glyph}", "fi"),
            ),
        ];
        for (fault, text) in cases {
            let e = font_err("a.ttf", fault);
            assert_eq!(e.to_string(), format!("font file `a.ttf`: {text}"));
        }
        let missing = FontFile::open(Path::new("/no/such/dir/font.ttf"), 0)
            .err()
            .expect("missing");
        let mut chain =
            std::iter::successors(Some(&missing as &dyn std::error::Error), |e| e.source());
        assert!(chain.any(|c| c.is::<std::io::Error>()), "{missing}");
    }

    #[test]
    fn a_file_past_the_cap_is_refused_and_one_at_it_is_read() {
        let dir = std::env::temp_dir().join(format!("pfcam-font-cap-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("f.ttf");
        std::fs::write(&path, [7u8; 20]).expect("write");
        assert_eq!(read_capped(&path, 20).expect("at the cap").len(), 20);
        let e = read_capped(&path, 19).unwrap_err().to_string();
        assert!(e.contains("larger than 19 bytes; not a font file"), "{e}");
        let e = FontFile::open(&path, 0)
            .err()
            .expect("not a font")
            .to_string();
        assert!(e.contains("not a TrueType/OpenType font"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
