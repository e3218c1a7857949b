//! The built-in font `paper`: the Times letters I, H, A, M, F, S of the paper's
//! Tables 3.1 and 3.3–3.7, in PostScript font units (cap height 662, y up).

use super::{Contour, GeometryError, Segment, Vec2};
use serde::Deserialize;
use std::sync::OnceLock;

/// The transcription of the paper's tables, kept verbatim in the crate.
pub(crate) const PAPER_GLYPHS_TOML: &str = include_str!("data/paper-glyphs.toml");

/// Cap height of the paper's letters, in font units.
pub(crate) const PAPER_CAP_HEIGHT: f64 = 662.0;

/// Gaps up to this size (font units) between consecutive printed segments are
/// misprints and are closed by moving the next segment's start onto the previous
/// end (letter M, two gaps of about 2.8 units at the top right).
pub(crate) const PAPER_GAP_SNAP: f64 = 5.0;

/// A glyph in font units: outlines counter-clockwise, counters clockwise.
#[derive(Clone, Debug, PartialEq)]
pub struct Glyph {
    /// The character.
    pub(crate) ch: char,
    /// Outer contours, counter-clockwise.
    pub outlines: Vec<Contour>,
    /// Holes, clockwise.
    pub counters: Vec<Contour>,
    /// Horizontal advance to the next glyph, font units.
    pub(crate) advance: f64,
}

#[derive(Deserialize)]
struct RawFile {
    glyph: Vec<RawGlyph>,
    q_construction: RawQ,
}
#[derive(Deserialize)]
struct RawGlyph {
    name: String,
    contour: Vec<RawContour>,
}
#[derive(Deserialize)]
struct RawContour {
    role: String,
    segments: Vec<RawSegment>,
}
#[derive(Deserialize)]
struct RawSegment {
    kind: String,
    points: Vec<[f64; 2]>,
}
/// The primitives of the paper's letter Q construction (Section 5).
#[derive(Deserialize, Clone, Debug)]
pub struct RawQ {
    /// rectangle m1
    pub m1_rectangle: Vec<[f64; 2]>,
    /// polygon m4
    pub m4_polygon: Vec<[f64; 2]>,
    /// level of the outer oval m2
    pub m2_level: f64,
    /// level of the inner oval m3
    pub m3_level: f64,
    /// level of the tail m5
    pub m5_level: f64,
}

struct PaperFont {
    glyphs: Vec<Glyph>,
    q: RawQ,
}

fn v(p: [f64; 2]) -> Vec2 {
    Vec2::new(p[0], p[1])
}

fn build_contour(name: &str, raw: &RawContour) -> Result<Contour, GeometryError> {
    let mut segs: Vec<Segment> = Vec::new();
    for s in &raw.segments {
        let seg = match (s.kind.as_str(), s.points.len()) {
            ("line", 2) => Segment::Line {
                a: v(s.points[0]),
                b: v(s.points[1]),
            },
            ("cubic", 4) => Segment::Cubic {
                p0: v(s.points[0]),
                p1: v(s.points[1]),
                p2: v(s.points[2]),
                p3: v(s.points[3]),
            },
            (k, n) => {
                return Err(GeometryError::BadGlyphSegment {
                    glyph: name.to_string(),
                    kind: k.to_string(),
                    points: n,
                })
            }
        };
        segs.push(seg);
    }
    // Close the printed misprint gaps explicitly (see PAPER_GAP_SNAP).
    let n = segs.len();
    for i in 0..n {
        let end = segs[i].end();
        let j = (i + 1) % n;
        let start = segs[j].start();
        let gap = end.dist(start);
        if gap > 0.0 && gap <= PAPER_GAP_SNAP {
            let d = end - start;
            segs[j] = match segs[j] {
                Segment::Line { b, .. } => Segment::Line { a: end, b },
                Segment::Cubic { p1, p2, p3, .. } => Segment::Cubic {
                    p0: end,
                    p1: p1 + d,
                    p2,
                    p3,
                },
            };
        }
    }
    Contour::new(segs)
}

fn load() -> Result<PaperFont, GeometryError> {
    let raw: RawFile = toml::from_str(PAPER_GLYPHS_TOML)
        .map_err(|source| GeometryError::BuiltInGlyphs { source })?;
    let mut glyphs = Vec::new();
    for g in &raw.glyph {
        let ch = g.name.chars().next().unwrap_or('?');
        let mut outlines = Vec::new();
        let mut counters = Vec::new();
        for c in &g.contour {
            let contour = build_contour(&g.name, c)?;
            if c.role == "counter" {
                counters.push(if contour.is_ccw() {
                    contour.reversed()
                } else {
                    contour
                });
            } else {
                outlines.push(if contour.is_ccw() {
                    contour
                } else {
                    contour.reversed()
                });
            }
        }
        let xmax = outlines
            .iter()
            .filter_map(Contour::bbox)
            .map(|b| b.1.x)
            .fold(0.0, f64::max);
        // The paper gives no advance widths: the right side bearing is taken equal to
        // a typical Times value of 20 units past the rightmost point.
        glyphs.push(Glyph {
            ch,
            outlines,
            counters,
            advance: xmax + 20.0,
        });
    }
    Ok(PaperFont {
        glyphs,
        q: raw.q_construction,
    })
}

fn font() -> &'static Result<PaperFont, GeometryError> {
    static FONT: OnceLock<Result<PaperFont, GeometryError>> = OnceLock::new();
    FONT.get_or_init(load)
}

/// The characters the built-in `paper` font has, in the paper's order.
pub fn paper_chars() -> Vec<char> {
    match font() {
        Ok(f) => f.glyphs.iter().map(|g| g.ch).collect(),
        Err(_) => Vec::new(),
    }
}

/// The built-in glyph for `ch`, in font units.
pub fn paper_glyph(ch: char) -> Result<Glyph, GeometryError> {
    let f = font().as_ref().map_err(Clone::clone)?;
    f.glyphs
        .iter()
        .find(|g| g.ch == ch)
        .cloned()
        .ok_or(GeometryError::MissingGlyph {
            font: "paper".into(),
            ch,
        })
}

/// The paper's letter-Q primitives (Section 5), in font units.
pub fn paper_q() -> Result<RawQ, GeometryError> {
    Ok(font().as_ref().map_err(Clone::clone)?.q.clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_paper_glyph_loads_closed_and_oriented() {
        let chars = paper_chars();
        assert_eq!(chars, vec!['I', 'H', 'A', 'M', 'F', 'S']);
        for ch in chars {
            let g = paper_glyph(ch).expect("paper glyph");
            assert_eq!(g.ch, ch);
            assert_eq!(g.outlines.len(), 1, "{ch}");
            for c in &g.outlines {
                assert!(c.is_ccw(), "{ch} outline is not CCW");
                // Still closed after loading (the constructor checks the joins).
                assert!(Contour::new(c.segments.clone()).is_ok());
                let (lo, hi) = c.bbox().expect("bbox");
                assert!(lo.y >= -20.0 && hi.y <= PAPER_CAP_HEIGHT + 20.0, "{ch}");
                assert!(g.advance > hi.x);
            }
            for c in &g.counters {
                assert!(!c.is_ccw(), "{ch} counter is not CW");
            }
            assert_eq!(g.counters.len(), usize::from(ch == 'A'), "{ch}");
        }
    }

    #[test]
    fn m_gaps_closed_and_cap_at_662() {
        let m = paper_glyph('M').expect("M");
        let c = &m.outlines[0];
        let (_, hi) = c.bbox().expect("bbox");
        assert_eq!(hi.y, 662.0);
        // Exactly joined, not merely within tolerance.
        let n = c.segments.len();
        for i in 0..n {
            assert_eq!(c.segments[i].end(), c.segments[(i + 1) % n].start());
        }
        // The top-right cap after the snap: (664, 662) → (863, 662).
        assert!(c.segments.iter().any(|s| *s
            == Segment::Line {
                a: Vec2::new(863.0, 662.0),
                b: Vec2::new(664.0, 662.0)
            }));
        for ch in ['I', 'H', 'F'] {
            let g = paper_glyph(ch).expect("glyph");
            assert_eq!(g.outlines[0].bbox().expect("bbox").1.y, 662.0, "{ch}");
        }
    }

    #[test]
    fn missing_glyph_and_q() {
        assert_eq!(
            paper_glyph('Z'),
            Err(GeometryError::MissingGlyph {
                font: "paper".into(),
                ch: 'Z'
            })
        );
        let q = paper_q().expect("q");
        assert!(q.m1_rectangle.len() >= 4);
    }
}
