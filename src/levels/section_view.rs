//! A part's section at one height as `pfcam sections` shows it: text and
//! JSON (its SVG drawing is `preview::section_svg`). The library formats;
//! the CLI prints and writes.

use super::sections::{net_area, SectionRing, Sections};

/// One section of a job's part, described.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SectionView {
    /// `pfcam <version>`.
    pub(crate) generator: String,
    /// The job's name.
    pub(crate) job: String,
    /// The height asked for, machine z (mm).
    pub(crate) z: f64,
    /// The part's heights (bottom, top), machine z (mm).
    pub z_range: [f64; 2],
    /// The source's parameter of the level (the MFS: s(z)).
    pub(crate) level_value: f64,
    /// Net area, mm²: outlines minus holes.
    pub area: f64,
    /// The rings, material on the left (holes clockwise).
    pub rings: Vec<SectionRing>,
}

impl SectionView {
    /// The section of `source` at machine height `z`, the part's top at
    /// `top` (the stock top).
    pub(crate) fn new(job: &str, source: &dyn Sections, z: f64, top: f64) -> SectionView {
        let (lo, hi) = source.z_range();
        let polys = source.section(z - top);
        SectionView {
            generator: format!("pfcam {}", env!("CARGO_PKG_VERSION")),
            job: job.into(),
            z,
            z_range: [top + lo, top + hi],
            level_value: source.level_value(z - top),
            area: net_area(&polys),
            rings: polys.iter().map(|p| SectionRing::of(p)).collect(),
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
    use crate::geometry::Vec2;
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
    fn a_frame_is_an_outline_round_a_hole() {
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
    }

    #[test]
    fn a_mould_with_an_island_has_a_negative_net_area() {
        // The pocket (a hole) round an island (an outline): net area negative.
        let src = Fixed(vec![rev(square(0.0, 30.0)), square(10.0, 20.0)]);
        let v = SectionView::new("mould", &src, -1.0, 0.0);
        assert!((v.area + 800.0).abs() < 1e-12);
        assert_eq!(v.rings.iter().filter(|r| r.hole).count(), 1);
    }
}
