//! Turning a `ShapeSource` into a `Shape` in millimetres.

use super::font::{self, FontFile};
use super::shaping::{self, ShapedGlyph};
use super::{
    glyphs, regions_from_contours, svgpath, Align, Contour, FontSource, GeometryError, Shape,
    ShapeSource, Vec2,
};
use std::path::Path;

/// Advance of a space in the paper font, font units (the paper gives none; 250 is
/// the Times value).
pub(crate) const PAPER_SPACE_ADVANCE: f64 = 250.0;

/// The paper font's em, font units: its letters are PostScript Times (1000
/// units per em, cap height 662).
pub(crate) const PAPER_EM: f64 = 1000.0;

/// The paper font's default line spacing, em. The paper gives no line metrics;
/// 1.2 em is the customary 120 % leading (10 pt type on 12 pt lines).
pub(crate) const PAPER_LINE_SPACING: f64 = 1.2;

/// Line spacing, em, of a font file whose ascender − descender + line gap is
/// not positive (a broken `hhea`): the customary 120 %.
pub(crate) const FALLBACK_LINE_SPACING: f64 = 1.2;

/// Build the shape a job describes, in millimetres, outlines counter-clockwise and
/// counters clockwise.
pub fn build_shape(src: &ShapeSource) -> Result<Shape, GeometryError> {
    match src {
        ShapeSource::Text {
            text,
            font,
            height,
            letter_spacing,
            line_spacing,
            align,
            origin,
            ..
        } => {
            check_finite("height", *height, true)?;
            check_finite("letter_spacing", *letter_spacing, false)?;
            if let Some(s) = line_spacing {
                check_finite("line_spacing", *s, true)?;
            }
            check_point("origin", *origin)?;
            let layout = Layout {
                height: *height,
                letter_spacing: *letter_spacing,
                line_spacing: *line_spacing,
                align: *align,
                origin: *origin,
            };
            match font {
                FontSource::Paper => layout.run(text, &PAPER_METRICS, paper_line),
                FontSource::File(path) => text_in_file(&layout, text, path, 0),
                FontSource::Found { path, index, .. } => text_in_file(&layout, text, path, *index),
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
        ShapeSource::HarmonicBezier(p) => {
            check_point("origin", p.origin)?;
            let outline = super::Contour::polygon(&p.rectangle())?;
            Ok(super::Shape {
                regions: vec![super::Region {
                    name: "patch".into(),
                    outline,
                    counters: Vec::new(),
                }],
            })
        }
        ShapeSource::Polyharmonic(p) => {
            let o = Vec2::new(p.origin[0], p.origin[1]);
            check_point("origin", o)?;
            let rect = super::rectangle(o, p.size);
            Ok(super::Shape {
                regions: vec![super::Region {
                    name: "relief".into(),
                    outline: super::Contour::polygon(&rect)?,
                    counters: Vec::new(),
                }],
            })
        }
        ShapeSource::PdeTube(t) => {
            check_point("origin", t.origin)?;
            let outline = super::Contour::polygon(&t.outline(TUBE_OUTLINE_POINTS))?;
            Ok(super::Shape {
                regions: vec![super::Region {
                    name: "tube".into(),
                    outline,
                    counters: Vec::new(),
                }],
            })
        }
        ShapeSource::Composite(_) => Err(GeometryError::CompositeNotHere),
    }
}

/// Points of a PDE tube's outline seen from above (its widest end curve):
/// for the preview and the report, not the tool path.
const TUBE_OUTLINE_POINTS: usize = 512;

fn check_finite(what: &'static str, x: f64, positive: bool) -> Result<(), GeometryError> {
    if !x.is_finite() || (positive && x <= 0.0) {
        return Err(GeometryError::BadNumber {
            key: what,
            value: x,
            positive,
            unit: if what == "line_spacing" { "em" } else { "mm" },
        });
    }
    Ok(())
}

fn check_point(what: &'static str, p: Vec2) -> Result<(), GeometryError> {
    if !p.is_finite() {
        return Err(GeometryError::NotFinitePoint { key: what, at: p });
    }
    Ok(())
}

/// The paper font's metrics (font units).
const PAPER_METRICS: Metrics = Metrics {
    cap_height: glyphs::PAPER_CAP_HEIGHT,
    em: PAPER_EM,
    line: PAPER_LINE_SPACING * PAPER_EM,
};

/// One line in the paper font: one glyph per character, no kerning.
fn paper_line(line: &str) -> Result<Vec<LaidGlyph>, GeometryError> {
    line.chars()
        .enumerate()
        .map(|(cluster, ch)| {
            if ch == ' ' {
                return Ok(LaidGlyph::plain(Vec::new(), PAPER_SPACE_ADVANCE, cluster));
            }
            let g = glyphs::paper_glyph(ch)?;
            let mut contours = g.outlines;
            contours.extend(g.counters);
            Ok(LaidGlyph::plain(contours, g.advance, cluster))
        })
        .collect()
}

/// Lines of `text` in face `index` of the font file at `path`, shaped.
fn text_in_file(
    layout: &Layout,
    text: &str,
    path: &Path,
    index: u32,
) -> Result<Shape, GeometryError> {
    let file = FontFile::open(path, index)?;
    let face = file.face()?;
    let em = f64::from(face.units_per_em());
    let metrics = Metrics {
        cap_height: font::cap_height(&face, &file.name)?,
        em,
        line: font::line_height(&face).unwrap_or(FALLBACK_LINE_SPACING * em),
    };
    layout.run(text, &metrics, |line| {
        let chars: Vec<char> = line.chars().collect();
        shaping::shape_line(&face, &file.name, line)?
            .into_iter()
            .map(|g: ShapedGlyph| {
                let what = chars.get(g.cluster).map_or(String::new(), char::to_string);
                Ok(LaidGlyph {
                    contours: font::outline(&face, &file.name, g.id, &what)?,
                    advance: g.advance,
                    offset: g.offset,
                    cluster: g.cluster,
                })
            })
            .collect()
    })
}

/// A font's metrics for layout, font units.
struct Metrics {
    /// Scaled to the text's `height`.
    cap_height: f64,
    /// Units per em (`line_spacing` is in em).
    em: f64,
    /// Default baseline-to-baseline distance.
    line: f64,
}

/// A glyph ready for layout, in font units.
struct LaidGlyph {
    contours: Vec<Contour>,
    /// Pen advance after the glyph.
    advance: f64,
    /// Where the glyph is drawn relative to the pen.
    offset: Vec2,
    /// Character index (from 0, in its line) of its cluster's first character.
    cluster: usize,
}

impl LaidGlyph {
    /// A glyph drawn at the pen, its own cluster.
    fn plain(contours: Vec<Contour>, advance: f64, cluster: usize) -> LaidGlyph {
        LaidGlyph {
            contours,
            advance,
            offset: Vec2::ZERO,
            cluster,
        }
    }
}

/// Layout of lines of text, shared by the paper font and font files.
struct Layout {
    height: f64,
    letter_spacing: f64,
    line_spacing: Option<f64>,
    align: Align,
    origin: Vec2,
}

impl Layout {
    /// Sets the lines of `text` (split at `\n`) with the glyphs `line_glyphs`
    /// gives for each. Scale s = height / cap height (mm per font unit). Line k
    /// (from 0) has its baseline at origin.y − k × line spacing × em × s. Along
    /// a line the pen moves by advance × s after each glyph, plus
    /// `letter_spacing` mm where the next glyph starts another cluster (so a
    /// mark stays on its base and a ligature is one letter); a glyph is drawn
    /// at the pen plus its offset × s. `align` shifts the line by 0, −w/2 or −w,
    /// w being its advance box (the pen's travel without the spacing after
    /// the last cluster).
    fn run(
        &self,
        text: &str,
        metrics: &Metrics,
        mut line_glyphs: impl FnMut(&str) -> Result<Vec<LaidGlyph>, GeometryError>,
    ) -> Result<Shape, GeometryError> {
        let scale = self.height / metrics.cap_height;
        let em_mm = metrics.em * scale;
        let step = self.line_spacing.unwrap_or(metrics.line / metrics.em) * em_mm;
        let lines: Vec<&str> = text.split('\n').collect();
        let mut regions = Vec::new();
        for (k, line) in lines.iter().enumerate() {
            let glyphs = line_glyphs(line)?;
            let base_y = 0.0 - k as f64 * step;
            let placed = self.place_line(&glyphs, scale, base_y);
            let chars: Vec<char> = line.chars().collect();
            for (cluster, contours) in placed {
                let place = if lines.len() > 1 {
                    format!("{}:{}", k + 1, cluster + 1)
                } else {
                    format!("{}", cluster + 1)
                };
                let name = format!("{} ({place})", cluster_text(&chars, &glyphs, cluster));
                regions.extend(regions_from_contours(&name, contours));
            }
        }
        if regions.is_empty() {
            return Err(GeometryError::NoVisibleGlyph {
                text: text.to_string(),
            });
        }
        Ok(Shape { regions })
    }

    /// The glyphs of one line placed in mm (baseline at origin.y + `base_y`),
    /// their contours gathered by cluster in the order clusters first appear.
    fn place_line(
        &self,
        glyphs: &[LaidGlyph],
        scale: f64,
        base_y: f64,
    ) -> Vec<(usize, Vec<Contour>)> {
        let n = glyphs.len();
        // Letter spacing after glyph i: where glyph i + 1 is another cluster.
        let after: Vec<f64> = (0..n)
            .map(|i| match glyphs.get(i + 1) {
                Some(next) if next.cluster == glyphs[i].cluster => 0.0,
                _ => self.letter_spacing,
            })
            .collect();
        let travel: f64 = glyphs
            .iter()
            .zip(&after)
            .map(|(g, a)| g.advance * scale + a)
            .sum();
        let width = if n > 0 {
            travel - self.letter_spacing
        } else {
            0.0
        };
        let shift = match self.align {
            Align::Left => 0.0,
            Align::Centre => -width / 2.0,
            Align::Right => -width,
        };
        let o = self.origin;
        let mut pen = 0.0;
        let mut out: Vec<(usize, Vec<Contour>)> = Vec::new();
        for (g, a) in glyphs.iter().zip(&after) {
            let (px, py) = (
                pen + shift + g.offset.x * scale,
                base_y + g.offset.y * scale,
            );
            let f = move |p: Vec2| Vec2::new(o.x + px + p.x * scale, o.y + py + p.y * scale);
            let placed = g.contours.iter().map(|c| c.map(f));
            match out.iter_mut().find(|(c, _)| *c == g.cluster) {
                Some((_, cs)) => cs.extend(placed),
                None => out.push((g.cluster, placed.collect())),
            }
            pen += g.advance * scale + a;
        }
        out
    }
}

/// The characters of the cluster starting at `cluster`: up to the next
/// cluster start of the line's glyphs, or the line's end.
fn cluster_text(chars: &[char], glyphs: &[LaidGlyph], cluster: usize) -> String {
    let end = glyphs
        .iter()
        .map(|g| g.cluster)
        .filter(|&c| c > cluster)
        .min()
        .unwrap_or(chars.len());
    chars.get(cluster..end).unwrap_or(&[]).iter().collect()
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

    fn sans() -> PathBuf {
        PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/data/DejaVuSans.ttf"
        ))
    }

    fn text(s: &str, font: FontSource, height: f64, spacing: f64) -> Result<Shape, GeometryError> {
        set(s, font, height, spacing, Align::Left, None)
    }

    fn set(
        s: &str,
        font: FontSource,
        height: f64,
        spacing: f64,
        align: Align,
        line_spacing: Option<f64>,
    ) -> Result<Shape, GeometryError> {
        build_shape(&ShapeSource::Text {
            text: s.into(),
            font,
            height,
            letter_spacing: spacing,
            line_spacing,
            align,
            origin: Vec2::new(10.0, 20.0),
            as_lines: s.contains('\n'),
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
    fn kerned_advance_letter_spacing_and_space() {
        let f = || FontSource::File(sans());
        let file = FontFile::open(&sans(), 0).expect("font");
        let face = file.face().expect("face");
        let scale = 50.0 / font::cap_height(&face, &file.name).expect("cap");
        let a = face.glyph_index('A').expect("A");
        let a_adv = f64::from(face.glyph_hor_advance(a).expect("advance"));
        let av = text("AV", f(), 50.0, 0.0).expect("AV");
        let v_alone = text("V", f(), 50.0, 0.0).expect("V");
        let shift = left(&av, "V (2)") - left(&v_alone, "V (1)");
        // −131 units: DejaVu Sans's GPOS pair A–V (read from the table in
        // `shaping::tests`); its legacy `kern` table is not what sets it.
        assert!(
            ((shift - (a_adv - 131.0) * scale).abs()) < 1e-9,
            "shift {shift}"
        );
        // Letter spacing adds exactly, and a space advances by its glyph's
        // shaped width.
        let spaced = text("AV", f(), 50.0, 3.0).expect("AV");
        assert!((left(&spaced, "V (2)") - left(&av, "V (2)") - 3.0).abs() < 1e-9);
        let g = shaping::shape_line(&face, "t", "A V").expect("shaped");
        let with_space = text("A V", f(), 50.0, 0.0).expect("A V");
        let want = (g[0].advance + g[1].advance) * scale;
        assert!((left(&with_space, "V (3)") - left(&v_alone, "V (1)") - want).abs() < 1e-9);
    }

    #[test]
    fn a_ligature_is_one_region_and_one_letter_for_spacing() {
        let f = || FontSource::File(sans());
        let fit = text("fit", f(), 20.0, 2.0).expect("fit");
        let names: Vec<&str> = fit.regions.iter().map(|r| r.name.as_str()).collect();
        // The fi ligature of DejaVu Sans (glyph 5042): its stem and its dot.
        assert_eq!(names, ["fi (1.1)", "fi (1.2)", "t (3)"]);
        let file = FontFile::open(&sans(), 0).expect("font");
        let face = file.face().expect("face");
        let scale = 20.0 / font::cap_height(&face, &file.name).expect("cap");
        let lig = f64::from(
            face.glyph_hor_advance(ttf_parser::GlyphId(5042))
                .expect("adv"),
        );
        let t_alone = text("t", f(), 20.0, 2.0).expect("t");
        // t starts one ligature advance and one letter spacing after the origin.
        let shift = left(&fit, "t (3)") - left(&t_alone, "t (1)");
        assert!((shift - (lig * scale + 2.0)).abs() < 1e-9, "{shift}");
    }

    #[test]
    fn a_combining_mark_is_drawn_over_its_base() {
        let f = || FontSource::File(sans());
        // One cluster: x and its acute, one name; the acute lies above the x
        // and within its width (GPOS anchors, `shaping::tests`), whatever the
        // letter spacing (no spacing inside a cluster).
        for spacing in [0.0, 5.0] {
            let x = text("x\u{301}", f(), 20.0, spacing).expect("x acute");
            let names: Vec<&str> = x.regions.iter().map(|r| r.name.as_str()).collect();
            assert_eq!(names, ["x\u{301} (1.1)", "x\u{301} (1.2)"]);
            let (base_lo, base_hi) = region_bbox(&x.regions[0]);
            let (acc_lo, acc_hi) = region_bbox(&x.regions[1]);
            assert!(acc_lo.y > base_hi.y, "accent above: {acc_lo:?} {base_hi:?}");
            let mid = 0.5 * (acc_lo.x + acc_hi.x);
            assert!(
                mid > base_lo.x && mid < base_hi.x,
                "{mid} in {base_lo:?}..{base_hi:?}"
            );
        }
        // e + U+0301 is the font's é.
        let composed = text("e\u{301}", f(), 20.0, 0.0).expect("e acute");
        let precomposed = text("é", f(), 20.0, 0.0).expect("é");
        assert_eq!(composed.bbox(), precomposed.bbox());
        assert_eq!(composed.regions.len(), 2);
        assert_eq!(composed.regions[0].name, "e\u{301} (1.1)");
    }

    #[test]
    fn lines_step_down_by_the_fonts_line_height() {
        // DejaVu Sans: ascender 1901, descender −483, line gap 0 (hhea), 2048
        // units per em, cap height 1493 (top of H): lines 2384 units apart.
        let file = FontFile::open(&sans(), 0).expect("font");
        let face = file.face().expect("face");
        assert_eq!(font::line_height(&face), Some(2384.0));
        let scale = 50.0 / 1493.0;
        let two = set(
            "H\nH",
            FontSource::File(sans()),
            50.0,
            0.0,
            Align::Left,
            None,
        )
        .expect("two lines");
        let names: Vec<&str> = two.regions.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(names, ["H (1:1)", "H (2:1)"]);
        let (lo1, _) = region_bbox(&two.regions[0]);
        let (lo2, _) = region_bbox(&two.regions[1]);
        assert!((lo1.y - lo2.y - 2384.0 * scale).abs() < 1e-9);
        assert_eq!(lo1.x, lo2.x);
        // Given in em: 1.5 em = 1.5 × 2048 units.
        let spaced = set(
            "H\n\nH",
            FontSource::File(sans()),
            50.0,
            0.0,
            Align::Left,
            Some(1.5),
        )
        .expect("three lines");
        let (lo3, _) = region_bbox(&spaced.regions[1]);
        assert_eq!(spaced.regions[1].name, "H (3:1)");
        assert!((20.0 - lo3.y - 2.0 * 1.5 * 2048.0 * scale).abs() < 1e-9);
        // The paper font: em 1000 units, 1.2 em by default.
        let paper = set("I\nI", FontSource::Paper, 66.2, 0.0, Align::Left, None).expect("I I");
        let (p1, _) = region_bbox(&paper.regions[0]);
        let (p2, _) = region_bbox(&paper.regions[1]);
        assert!((p1.y - p2.y - 120.0).abs() < 1e-9, "{}", p1.y - p2.y);
    }

    #[test]
    fn align_left_centre_right_on_the_advance_box() {
        // Paper font at 66.2 mm: 0.1 mm per unit; letter spacing 2 mm.
        let m = glyphs::paper_glyph('M').expect("M").advance * 0.1;
        let f = glyphs::paper_glyph('F').expect("F").advance * 0.1;
        let i = glyphs::paper_glyph('I').expect("I").advance * 0.1;
        let i_min = glyphs::paper_glyph('I').expect("I").outlines[0]
            .bbox()
            .expect("bbox")
            .0
            .x
            * 0.1;
        let m_min = glyphs::paper_glyph('M').expect("M").outlines[0]
            .bbox()
            .expect("bbox")
            .0
            .x
            * 0.1;
        let widths = [m + 2.0 + f, i];
        for (align, k) in [
            (Align::Left, 0.0),
            (Align::Centre, 0.5),
            (Align::Right, 1.0),
        ] {
            let s = set("MF\nI", FontSource::Paper, 66.2, 2.0, align, None).expect("MF I");
            let names: Vec<&str> = s.regions.iter().map(|r| r.name.as_str()).collect();
            assert_eq!(names, ["M (1:1)", "F (1:2)", "I (2:1)"]);
            let m_left = region_bbox(&s.regions[0]).0.x;
            let i_left = region_bbox(&s.regions[2]).0.x;
            assert!(
                (m_left - (10.0 - k * widths[0] + m_min)).abs() < 1e-9,
                "{align:?}"
            );
            assert!(
                (i_left - (10.0 - k * widths[1] + i_min)).abs() < 1e-9,
                "{align:?}"
            );
        }
        // A blank line takes its place and gives no region.
        let s = set("I\n \nI", FontSource::Paper, 66.2, 0.0, Align::Right, None).expect("I I");
        let names: Vec<&str> = s.regions.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(names, ["I (1:1)", "I (3:1)"]);
        assert!(matches!(
            set("I", FontSource::Paper, 66.2, 0.0, Align::Left, Some(0.0)),
            Err(e @ GeometryError::BadNumber { key: "line_spacing", .. })
                if e.to_string().contains("line_spacing must be a positive number of em")
        ));
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
            Err(GeometryError::BadNumber { key: "height", .. })
        ));
        assert!(matches!(
            text("A", FontSource::Paper, f64::NAN, 0.0),
            Err(GeometryError::BadNumber { key: "height", .. })
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
