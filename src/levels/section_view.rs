//! A part's section at one height as `pfcam sections` shows it: text, JSON
//! and an SVG drawing (mm, y up). The library formats; the CLI prints and
//! writes.

use super::sections::{net_area, Ring, Sections};
use crate::geometry::Vec2;

/// One section of a job's part, described.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SectionView {
    /// `pfcam <version>`.
    pub generator: String,
    /// The job's name.
    pub job: String,
    /// The height asked for, machine z (mm).
    pub z: f64,
    /// The part's heights (bottom, top), machine z (mm).
    pub z_range: [f64; 2],
    /// The source's parameter of the level (the MFS: s(z)).
    pub level_value: f64,
    /// Net area, mm²: outlines minus holes.
    pub area: f64,
    /// The rings, material on the left (holes clockwise).
    pub rings: Vec<Ring>,
}

impl SectionView {
    /// The section of `source` at machine height `z`, the part's top at
    /// `top` (the stock top).
    pub fn new(job: &str, source: &dyn Sections, z: f64, top: f64) -> SectionView {
        let (lo, hi) = source.z_range();
        let polys = source.section(z - top);
        SectionView {
            generator: format!("pfcam {}", env!("CARGO_PKG_VERSION")),
            job: job.into(),
            z,
            z_range: [top + lo, top + hi],
            level_value: source.level_value(z - top),
            area: net_area(&polys),
            rings: polys.iter().map(|p| Ring::of(p)).collect(),
        }
    }

    /// "1 ring", "3 rings".
    pub fn ring_count(&self) -> String {
        counted(self.rings.len(), "ring")
    }

    /// Lines for a person: the height, the ring counts, one line per ring.
    pub fn text(&self) -> String {
        let holes = self.rings.iter().filter(|r| r.hole).count();
        let mut s = format!(
            "section of {} at z {:.3} mm (the part spans z {:.3} to {:.3}; level value {:.6})\n{}: {}, {}; net area {:.3} mm²\n",
            self.job,
            self.z,
            self.z_range[0],
            self.z_range[1],
            self.level_value,
            self.ring_count(),
            counted(self.rings.len() - holes, "outline"),
            counted(holes, "hole"),
            self.area
        );
        for (i, r) in self.rings.iter().enumerate() {
            s += &format!(
                "ring {}: {}, {} points, area {:.3} mm², {}\n",
                i + 1,
                if r.hole { "hole" } else { "outline" },
                r.points.len(),
                r.area.abs(),
                if r.hole {
                    "clockwise"
                } else {
                    "counter-clockwise"
                }
            );
        }
        s
    }

    /// Pretty JSON of the whole view (`rings[i].points` as [x, y] in mm).
    pub fn json(&self) -> String {
        // Plain numbers, strings and bools: serialising cannot fail.
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }

    /// An SVG drawing at 1:1 (viewBox in mm, y up): the material grey under
    /// the non-zero rule (holes clockwise), every ring outlined; a section
    /// whose outermost ring is a hole (a mould: net area negative) has its
    /// material drawn out to its bounding box plus 5 mm.
    pub fn svg(&self) -> String {
        let pts: Vec<Vec2> = self
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
        if self.area < 0.0 {
            d += &format!("M{x0:.4},{y0:.4} H{:.4} V{:.4} H{x0:.4} Z ", x0 + w, y0 + h);
        }
        for r in &self.rings {
            d += &ring_path(&r.points);
        }
        format!(
            "{}\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.3}mm\" height=\"{h:.3}mm\" viewBox=\"{x0:.4} {:.4} {w:.4} {h:.4}\">\n<title>{} at z {:.3} mm: {}, net area {:.3} mm²</title>\n<g transform=\"scale(1,-1)\">\n<path d=\"{}\" fill=\"#c8c8c8\" fill-rule=\"nonzero\" stroke=\"#202020\" stroke-width=\"0.1\"/>\n</g>\n</svg>\n",
            crate::preview::svg_marker(&self.job),
            -(y0 + h),
            xml_escape(&self.job),
            self.z,
            self.ring_count(),
            self.area,
            d.trim_end()
        )
    }
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

/// `n` and `word`, plural unless n = 1 ("1 hole", "0 holes").
fn counted(n: usize, word: &str) -> String {
    if n == 1 {
        format!("1 {word}")
    } else {
        format!("{n} {word}s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::levels::sections::LevelField;

    /// Fixed rings at every height over z ∈ [−2, 0].
    struct Fixed(Vec<Vec<Vec2>>);

    impl Sections for Fixed {
        fn z_range(&self) -> (f64, f64) {
            (-2.0, 0.0)
        }
        fn section(&self, _z: f64) -> Vec<Vec<Vec2>> {
            self.0.clone()
        }
        fn level_value(&self, z: f64) -> f64 {
            z
        }
        fn level_field(&self, _z: f64) -> Option<LevelField> {
            None
        }
    }

    /// The square [a, b]², counter-clockwise.
    fn square(a: f64, b: f64) -> Vec<Vec2> {
        [(a, a), (b, a), (b, b), (a, b)]
            .iter()
            .map(|&(x, y)| Vec2::new(x, y))
            .collect()
    }

    fn rev(p: Vec<Vec2>) -> Vec<Vec2> {
        p.into_iter().rev().collect()
    }

    #[test]
    fn a_frame_is_an_outline_round_a_hole_and_drawn_without_a_border() {
        let src = Fixed(vec![square(0.0, 30.0), rev(square(10.0, 20.0))]);
        let v = SectionView::new("frame", &src, 9.0, 10.0);
        assert_eq!(v.z_range, [8.0, 10.0]);
        assert_eq!(v.level_value, -1.0);
        assert!((v.area - 800.0).abs() < 1e-12);
        assert!(v
            .text()
            .contains("2 rings: 1 outline, 1 hole; net area 800.000"));
        let one = SectionView::new("square", &Fixed(vec![square(0.0, 30.0)]), 9.0, 10.0);
        assert!(
            one.text().contains("1 ring: 1 outline, 0 holes;"),
            "{}",
            one.text()
        );
        let svg = v.svg();
        assert!(
            svg.starts_with("<!-- pfcam ")
                && svg.contains("viewBox=\"-5.0000 -35.0000 40.0000 40.0000\"")
        );
        assert_eq!(svg.matches('M').count(), 2, "{svg}");
    }

    #[test]
    fn a_mould_with_an_island_is_drawn_out_to_a_border() {
        // The pocket (a hole) round an island (an outline): net area negative.
        let src = Fixed(vec![rev(square(0.0, 30.0)), square(10.0, 20.0)]);
        let v = SectionView::new("mould", &src, -1.0, 0.0);
        assert!((v.area + 800.0).abs() < 1e-12);
        assert_eq!(v.rings.iter().filter(|r| r.hole).count(), 1);
        let svg = v.svg();
        // The border, counter-clockwise (y up), then the two rings.
        assert!(
            svg.contains("M-5.0000,-5.0000 H35.0000 V35.0000 H-5.0000 Z M"),
            "{svg}"
        );
        assert_eq!(svg.matches('M').count(), 3, "{svg}");
    }
}
