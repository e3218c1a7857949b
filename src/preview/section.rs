//! `pfcam sections -o FILE.svg`: a part's section ([`SectionView`]) drawn at
//! 1:1.

use crate::geometry::Vec2;
use crate::levels::section_view::SectionView;

/// An SVG drawing at 1:1 (viewBox in mm, y up): the material grey under
/// the non-zero rule (holes clockwise), every ring outlined; a section
/// whose outermost ring is a hole (a mould: net area negative) has its
/// material drawn out to its bounding box plus 5 mm.
pub fn section_svg(view: &SectionView) -> String {
    let pts: Vec<Vec2> = view
        .rings
        .iter()
        .flat_map(|r| r.points.iter().map(|p| Vec2::new(p[0], p[1])))
        .collect();
    // The unit square at the origin when there is nothing to draw.
    let (lo, hi) = crate::geometry::polygons_bbox(std::slice::from_ref(&pts))
        .unwrap_or((Vec2::ZERO, Vec2::new(1.0, 1.0)));
    let pad = 5.0;
    let (x0, y0, w, h) = (
        lo.x - pad,
        lo.y - pad,
        hi.x - lo.x + 2.0 * pad,
        hi.y - lo.y + 2.0 * pad,
    );
    let mut d = String::new();
    if view.area < 0.0 {
        d += &format!("M{x0:.4},{y0:.4} H{:.4} V{:.4} H{x0:.4} Z ", x0 + w, y0 + h);
    }
    for r in &view.rings {
        d += &ring_path(&r.points);
    }
    format!(
        "{}\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.3}mm\" height=\"{h:.3}mm\" viewBox=\"{x0:.4} {:.4} {w:.4} {h:.4}\">\n<title>{} at z {:.3} mm: {}, net area {:.3} mm²</title>\n<g transform=\"scale(1,-1)\">\n<path d=\"{}\" fill=\"#c8c8c8\" fill-rule=\"nonzero\" stroke=\"#202020\" stroke-width=\"0.1\"/>\n</g>\n</svg>\n",
        crate::preview::svg_marker(&view.job),
        -(y0 + h),
        xml_escape(&view.job),
        view.z,
        view.ring_count(),
        view.area,
        d.trim_end()
    )
}

/// `M x,y L ... Z` for one ring.
fn ring_path(points: &[[f64; 2]]) -> String {
    let mut d = String::new();
    for (i, p) in points.iter().enumerate() {
        d += &format!("{}{:.4},{:.4} ", if i == 0 { "M" } else { "L" }, p[0], p[1]);
    }
    if !points.is_empty() {
        d += "Z ";
    }
    d
}

/// Text safe inside an XML element.
fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::levels::sections::SectionRing;

    /// The square [a, b]², counter-clockwise, or clockwise when `hole`.
    fn square(a: f64, b: f64, hole: bool) -> SectionRing {
        let mut p: Vec<Vec2> = [(a, a), (b, a), (b, b), (a, b)]
            .iter()
            .map(|&(x, y)| Vec2::new(x, y))
            .collect();
        if hole {
            p.reverse();
        }
        SectionRing::of(&p)
    }

    fn view(rings: Vec<SectionRing>) -> SectionView {
        let area = rings.iter().map(|r| r.area).sum();
        SectionView {
            generator: "pfcam test".into(),
            job: "frame".into(),
            z: 9.0,
            z_range: [8.0, 10.0],
            level_value: -1.0,
            area,
            rings,
        }
    }

    #[test]
    fn a_frame_is_drawn_without_a_border() {
        let svg = section_svg(&view(vec![
            square(0.0, 30.0, false),
            square(10.0, 20.0, true),
        ]));
        assert!(
            svg.starts_with("<!-- pfcam ")
                && svg.contains("viewBox=\"-5.0000 -35.0000 40.0000 40.0000\""),
            "{svg}"
        );
        assert_eq!(svg.matches('M').count(), 2, "{svg}");
    }

    #[test]
    fn a_mould_with_an_island_is_drawn_out_to_a_border() {
        // The pocket (a hole) round an island (an outline): net area negative.
        let svg = section_svg(&view(vec![
            square(0.0, 30.0, true),
            square(10.0, 20.0, false),
        ]));
        // The border, counter-clockwise (y up), then the two rings.
        assert!(
            svg.contains("M-5.0000,-5.0000 H35.0000 V35.0000 H-5.0000 Z M"),
            "{svg}"
        );
        assert_eq!(svg.matches('M').count(), 3, "{svg}");
    }
}
