//! Turning a `ShapeSource` into a `Shape` in millimetres.

use super::font::{self, FontFile};
use super::{
    glyphs, regions_from_contours, svgpath, Contour, FontSource, GeometryError, Shape, ShapeSource,
    Vec2,
};

/// Advance of a space in the paper font, font units (the paper gives none; 250 is
/// the Times value).
pub const PAPER_SPACE_ADVANCE: f64 = 250.0;

/// Build the shape a job describes, in millimetres, outlines counter-clockwise and
/// counters clockwise.
pub fn build_shape(src: &ShapeSource) -> Result<Shape, GeometryError> {
    match src {
        ShapeSource::Text {
            text,
            font,
            height,
            letter_spacing,
            origin,
        } => {
            check_finite("height", *height, true)?;
            check_finite("letter_spacing", *letter_spacing, false)?;
            check_point("origin", *origin)?;
            let layout = Layout {
                height: *height,
                letter_spacing: *letter_spacing,
                origin: *origin,
            };
            match font {
                FontSource::Paper => layout.run(
                    text,
                    glyphs::PAPER_CAP_HEIGHT,
                    |ch| {
                        if ch == ' ' {
                            return Ok(LaidGlyph {
                                contours: Vec::new(),
                                advance: PAPER_SPACE_ADVANCE,
                                id: 0,
                            });
                        }
                        let g = glyphs::paper_glyph(ch)?;
                        let mut contours = g.outlines;
                        contours.extend(g.counters);
                        Ok(LaidGlyph {
                            contours,
                            advance: g.advance,
                            id: 0,
                        })
                    },
                    |_, _| 0.0,
                ),
                FontSource::File(path) => {
                    let file = FontFile::open(path)?;
                    let face = file.face()?;
                    let cap = font::cap_height(&face, &file.name)?;
                    layout.run(
                        text,
                        cap,
                        |ch| {
                            let g = font::glyph(&face, &file.name, ch)?;
                            Ok(LaidGlyph {
                                contours: g.contours,
                                advance: g.advance,
                                id: g.id,
                            })
                        },
                        |a, b| font::kerning(&face, a, b),
                    )
                }
            }
        }
        ShapeSource::SvgPath { d, height, origin } => {
            if let Some(h) = height {
                check_finite("height", *h, true)?;
            }
            check_point("origin", *origin)?;
            svgpath::svg_shape(d, *height, *origin)
        }
        ShapeSource::SvgFile(src) => super::svgfile::svg_file_shape(src),
        ShapeSource::DxfFile(src) => super::dxffile::dxf_file_shape(src),
        ShapeSource::Composite(_) => Err(GeometryError::Invalid(
            "a composition of parts is built with its fields (pipeline::job_shape)".into(),
        )),
    }
}

fn check_finite(what: &str, x: f64, positive: bool) -> Result<(), GeometryError> {
    if !x.is_finite() || (positive && x <= 0.0) {
        let want = if positive {
            "a positive number"
        } else {
            "a finite number"
        };
        return Err(GeometryError::Invalid(format!(
            "{what} must be {want} of mm, got {x}"
        )));
    }
    Ok(())
}

fn check_point(what: &str, p: Vec2) -> Result<(), GeometryError> {
    if !p.is_finite() {
        return Err(GeometryError::Invalid(format!(
            "{what} must be finite, got ({}, {})",
            p.x, p.y
        )));
    }
    Ok(())
}

/// A glyph ready for layout, in font units.
struct LaidGlyph {
    contours: Vec<Contour>,
    advance: f64,
    /// Glyph id for kerning (0 where the font has no kerning).
    id: u16,
}

/// Horizontal layout of a line of text, shared by the paper font and font files.
struct Layout {
    height: f64,
    letter_spacing: f64,
    origin: Vec2,
}

impl Layout {
    /// Places the glyphs of `text` left to right: scale = height / cap height; the
    /// pen moves by advance × scale + kerning × scale + letter spacing. A glyph's
    /// contours become regions named `{char} ({position})`, position counted
    /// from 1 over all characters, spaces included.
    fn run(
        &self,
        text: &str,
        cap_height: f64,
        mut glyph: impl FnMut(char) -> Result<LaidGlyph, GeometryError>,
        kern: impl Fn(u16, u16) -> f64,
    ) -> Result<Shape, GeometryError> {
        let scale = self.height / cap_height;
        let mut pen = 0.0;
        let mut prev: Option<u16> = None;
        let mut regions = Vec::new();
        for (i, ch) in text.chars().enumerate() {
            let g = glyph(ch)?;
            if let Some(left) = prev {
                pen += kern(left, g.id) * scale;
            }
            let (px, o) = (pen, self.origin);
            let f = move |p: Vec2| Vec2::new(o.x + px + p.x * scale, o.y + p.y * scale);
            let contours = g.contours.iter().map(|c| c.map(f)).collect();
            regions.extend(regions_from_contours(
                &format!("{ch} ({})", i + 1),
                contours,
            ));
            pen += g.advance * scale + self.letter_spacing;
            prev = Some(g.id);
        }
        if regions.is_empty() {
            return Err(GeometryError::Invalid(format!(
                "the text {text:?} has no visible glyph to cut"
            )));
        }
        Ok(Shape { regions })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Region;
    use std::path::PathBuf;

    fn dejavu() -> PathBuf {
        PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/data/DejaVuSerif.ttf"
        ))
    }

    fn text(s: &str, font: FontSource, height: f64, spacing: f64) -> Result<Shape, GeometryError> {
        build_shape(&ShapeSource::Text {
            text: s.into(),
            font,
            height,
            letter_spacing: spacing,
            origin: Vec2::new(10.0, 20.0),
        })
    }

    fn region_bbox(r: &Region) -> (Vec2, Vec2) {
        Shape {
            regions: vec![r.clone()],
        }
        .bbox()
        .expect("bbox")
    }

    #[test]
    fn font_h_has_cap_height() {
        let shape = text("H", FontSource::File(dejavu()), 50.0, 0.0).expect("H");
        assert_eq!(shape.regions.len(), 1);
        assert_eq!(shape.regions[0].name, "H (1)");
        let (lo, hi) = shape.bbox().expect("bbox");
        // The baseline is at origin.y = 20; H is flat on top, so its control-point
        // box is its true box.
        assert!((lo.y - 20.0).abs() < 1e-9, "{lo:?}");
        assert!((hi.y - lo.y - 50.0).abs() < 1e-9, "height {}", hi.y - lo.y);
        assert!(lo.x >= 10.0);
    }

    #[test]
    fn font_o_and_a_have_one_cw_counter() {
        for ch in ["O", "A", "o", "e"] {
            let shape = text(ch, FontSource::File(dejavu()), 50.0, 0.0).expect("glyph");
            assert_eq!(shape.regions.len(), 1, "{ch}");
            let r = &shape.regions[0];
            assert!(r.outline.is_ccw(), "{ch}");
            assert_eq!(r.counters.len(), 1, "{ch}");
            assert!(!r.counters[0].is_ccw(), "{ch}");
            // The counter is inside the outline (Appendix I winding number).
            let p = r.counters[0].segments[0].start();
            assert_eq!(r.outline.winding_number(p, 1e-3), 1, "{ch}");
        }
        // O is made of quadratics raised to cubics.
        let o = text("O", FontSource::File(dejavu()), 50.0, 0.0).expect("O");
        assert!(o.regions[0]
            .outline
            .segments
            .iter()
            .any(|s| matches!(s, crate::geometry::Segment::Cubic { .. })));
    }

    #[test]
    fn several_outlines_give_several_regions() {
        let shape = text("i%", FontSource::File(dejavu()), 20.0, 0.0).expect("i%");
        let names: Vec<&str> = shape.regions.iter().map(|r| r.name.as_str()).collect();
        // i: stem and dot; %: two rings (each with a counter) and the bar.
        assert_eq!(&names[..2], &["i (1.1)", "i (1.2)"]);
        assert_eq!(names.len(), 5, "{names:?}");
        let ring_counters: usize = shape.regions[2..].iter().map(|r| r.counters.len()).sum();
        assert_eq!(ring_counters, 2);
        assert!(names[2..].iter().all(|n| n.starts_with("% (2.")));
        // A composite glyph (e + acute accent, assembled by ttf-parser).
        let e = text("é", FontSource::File(dejavu()), 20.0, 0.0).expect("é");
        assert_eq!(e.regions.len(), 2);
        let counters: Vec<usize> = e.regions.iter().map(|r| r.counters.len()).collect();
        assert_eq!(counters.iter().sum::<usize>(), 1, "{counters:?}");
    }

    /// Left edge of the region whose name starts with `prefix`.
    fn left(shape: &Shape, prefix: &str) -> f64 {
        let r = shape
            .regions
            .iter()
            .find(|r| r.name.starts_with(prefix))
            .expect("region");
        region_bbox(r).0.x
    }

    #[test]
    fn font_kerning_advance_and_spacing() {
        let f = || FontSource::File(dejavu());
        let file = FontFile::open(&dejavu()).expect("font");
        let face = file.face().expect("face");
        let cap = font::cap_height(&face, &file.name).expect("cap");
        let scale = 50.0 / cap;
        let a = font::glyph(&face, &file.name, 'A').expect("A");
        let v = font::glyph(&face, &file.name, 'V').expect("V");
        let k = font::kerning(&face, a.id, v.id);
        // DejaVu Serif kerns A–V in its `kern` table.
        assert!(k < 0.0, "A-V kerning {k}");
        let av = text("AV", f(), 50.0, 0.0).expect("AV");
        let v_alone = text("V", f(), 50.0, 0.0).expect("V");
        let shift = left(&av, "V (2)") - left(&v_alone, "V (1)");
        assert!(
            ((shift - (a.advance + k) * scale).abs()) < 1e-9,
            "shift {shift}"
        );
        // Letter spacing adds exactly, and a space advances by its glyph's width.
        let spaced = text("AV", f(), 50.0, 3.0).expect("AV");
        assert!((left(&spaced, "V (2)") - left(&av, "V (2)") - 3.0).abs() < 1e-9);
        let sp = font::glyph(&face, &file.name, ' ').expect("space");
        assert!(sp.contours.is_empty() && sp.advance > 0.0);
        let with_space = text("A V", f(), 50.0, 0.0).expect("A V");
        let want = (a.advance
            + font::kerning(&face, a.id, sp.id)
            + sp.advance
            + font::kerning(&face, sp.id, v.id))
            * scale;
        assert!((left(&with_space, "V (3)") - left(&v_alone, "V (1)") - want).abs() < 1e-9);
    }

    #[test]
    fn font_errors_name_the_path_and_glyph() {
        let missing = PathBuf::from("/no/such/dir/font.ttf");
        match text("A", FontSource::File(missing), 10.0, 0.0) {
            Err(e @ GeometryError::Font { .. }) => {
                let msg = e.to_string();
                assert!(msg.contains("/no/such/dir/font.ttf"), "{msg}");
            }
            other => panic!("{other:?}"),
        }
        let not_font = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml"));
        match text("A", FontSource::File(not_font), 10.0, 0.0) {
            Err(e @ GeometryError::Font { .. }) => {
                let msg = e.to_string();
                assert!(
                    msg.contains("Cargo.toml") && msg.contains("not a TrueType"),
                    "{msg}"
                );
            }
            other => panic!("{other:?}"),
        }
        match text("A\u{1D11E}", FontSource::File(dejavu()), 10.0, 0.0) {
            Err(GeometryError::MissingGlyph { font, ch }) => {
                assert_eq!(ch, '\u{1D11E}');
                assert!(font.ends_with("DejaVuSerif.ttf"));
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            text("A", FontSource::File(dejavu()), 0.0, 0.0),
            Err(GeometryError::Invalid(_))
        ));
        assert!(matches!(
            text("A", FontSource::Paper, f64::NAN, 0.0),
            Err(GeometryError::Invalid(_))
        ));
        for (s, font) in [("", FontSource::Paper), ("  ", FontSource::File(dejavu()))] {
            let e = text(s, font, 10.0, 0.0).expect_err("nothing to cut");
            assert!(e.to_string().contains("no visible glyph"), "{e}");
        }
    }

    #[test]
    fn paper_layout() {
        let shape = text("MF S", FontSource::Paper, 66.2, 1.0).expect("MF S");
        let names: Vec<&str> = shape.regions.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(names, ["M (1)", "F (2)", "S (4)"]);
        let scale = 0.1; // 66.2 mm / 662 units
        let m = glyphs::paper_glyph('M').expect("M");
        let f = glyphs::paper_glyph('F').expect("F");
        let f_min = f.outlines[0].bbox().expect("bbox").0.x;
        // F starts one advance (xmax + 20 units) plus the spacing after the origin.
        let want = 10.0 + m.advance * scale + 1.0 + f_min * scale;
        assert!((region_bbox(&shape.regions[1]).0.x - want).abs() < 1e-9);
        let (lo, hi) = region_bbox(&shape.regions[0]);
        assert!((hi.y - 20.0 - 66.2).abs() < 1e-9 && (lo.y - 20.0).abs() < 1e-9);
        let s = glyphs::paper_glyph('S').expect("S");
        let s_min = s.outlines[0].bbox().expect("bbox").0.x;
        let want_s =
            10.0 + (m.advance + f.advance + PAPER_SPACE_ADVANCE) * scale + 3.0 + s_min * scale;
        assert!((region_bbox(&shape.regions[2]).0.x - want_s).abs() < 1e-9);
        let a = text("A", FontSource::Paper, 50.0, 0.0).expect("A");
        assert_eq!(a.regions[0].counters.len(), 1);
        assert!(matches!(
            text("AZ", FontSource::Paper, 50.0, 0.0),
            Err(GeometryError::MissingGlyph { ch: 'Z', .. })
        ));
    }

    #[test]
    fn every_ascii_glyph_of_the_test_font() {
        let ascii: String = (33u8..127).map(char::from).collect();
        let shape = text(&ascii, FontSource::File(dejavu()), 10.0, 0.0).expect("ascii");
        let mut counters = 0;
        for r in &shape.regions {
            assert!(r.outline.is_ccw(), "{}", r.name);
            assert!(r.counters.iter().all(|c| !c.is_ccw()), "{}", r.name);
            counters += r.counters.len();
            for c in std::iter::once(&r.outline).chain(&r.counters) {
                assert!(Contour::new(c.segments.clone()).is_ok(), "{}", r.name);
                for seg in &c.segments {
                    assert!(seg.length() > 0.0, "{}: zero-length {seg:?}", r.name);
                }
                for smp in c.sample_uniform(50, 0.0) {
                    assert!((smp.t.norm() - 1.0).abs() < 1e-9, "{}", r.name);
                }
            }
        }
        // Measured for DejaVu Serif (a regression value): the 94 glyphs give 104
        // regions (i j ! ? : ; = % " and others have several outlines) and 29 counters.
        assert_eq!(shape.regions.len(), 104);
        assert_eq!(counters, 29);
    }

    #[test]
    fn cap_height_from_os2_or_the_top_of_h() {
        let data = std::fs::read(dejavu()).expect("test font");
        let face = ttf_parser::Face::parse(&data, 0).expect("face");
        // DejaVu Serif's OS/2 table is version 1, without sCapHeight: the cap height
        // is the top of its H.
        assert_eq!(face.capital_height(), None);
        let h = face.glyph_index('H').expect("H");
        let top = f64::from(face.glyph_bounding_box(h).expect("bbox").y_max);
        assert_eq!(font::cap_height(&face, "x").expect("cap"), top);
        assert_eq!(top, 1493.0);
        // A copy whose OS/2 table is rewritten as version 2 with sCapHeight = 1400
        // (appended at the end of the file, the table directory pointed at it).
        let tables = usize::from(u16::from_be_bytes([data[4], data[5]]));
        let rec = (0..tables)
            .map(|k| 12 + 16 * k)
            .find(|&r| &data[r..r + 4] == b"OS/2")
            .expect("OS/2 table");
        let word = |r: usize| u32::from_be_bytes([data[r], data[r + 1], data[r + 2], data[r + 3]]);
        let (off, len) = (word(rec + 8) as usize, word(rec + 12) as usize);
        let mut os2 = data[off..off + len].to_vec();
        os2[0..2].copy_from_slice(&2u16.to_be_bytes());
        os2.resize(86, 0);
        os2.extend_from_slice(&[0, 0]); // sxHeight
        os2.extend_from_slice(&1400i16.to_be_bytes()); // sCapHeight
        os2.extend_from_slice(&[0; 6]); // usDefaultChar, usBreakChar, usMaxContext
        let mut patched = data.clone();
        while patched.len() % 4 != 0 {
            patched.push(0);
        }
        let new_off = patched.len() as u32;
        patched.extend_from_slice(&os2);
        patched[rec + 8..rec + 12].copy_from_slice(&new_off.to_be_bytes());
        patched[rec + 12..rec + 16].copy_from_slice(&(os2.len() as u32).to_be_bytes());
        let face2 = ttf_parser::Face::parse(&patched, 0).expect("patched face");
        assert_eq!(face2.capital_height(), Some(1400));
        assert_eq!(font::cap_height(&face2, "x").expect("cap"), 1400.0);
    }
}
