//! What the level planner asks of a part's shape: its z range and its
//! horizontal sections, as closed polygons, through the [`Sections`] trait.
//!
//! Units: millimetres. Heights are relative to the part's top, which the
//! job places at the stock top: z = 0 at the top, negative downward, so a
//! part of depth d spans z ∈ [−d, 0] (the convention of [`super::DepthProfile`]
//! and of the planner; the machine z is `stock.top + z`).
//!
//! The MFS field of a shape ([`super::mfs_sections::MfsSections`]: the
//! paper's S2 = {(x, y) ∈ Γ(s), z = φ(s)}) and a profile job's prism
//! ([`super::prism::PrismSections`]) implement it.

use crate::field::Field;
use crate::geometry::polygon_area;
use crate::geometry::Vec2;

/// A part described by its horizontal sections.
///
/// A section is a list of closed polygons (first point not repeated) with the
/// material on the left: outlines counter-clockwise (positive area), holes
/// clockwise. A mould's sections (a cavity job) are its pockets as holes,
/// with any islands in them as outlines: its material reaches out to the
/// stock's edge, which is the planner's, not the part's.
pub trait Sections: Sync {
    /// The part's heights (bottom, top), mm, relative to its top: (−depth, 0).
    fn z_range(&self) -> (f64, f64);

    /// The section at height `z` (mm, within [`Self::z_range`]; outside it a
    /// source may clamp), material on the left.
    fn section(&self, z: f64) -> Vec<Vec<Vec2>>;

    /// The source's own parameter of the level at `z`, reported with the level
    /// and written in the G-code's comments (the MFS: the equipotential value
    /// s(z) ∈ (0, 1]).
    fn level_value(&self, z: f64) -> f64;

    /// A field to trace the level at `z` in, when the source knows one exactly
    /// (the MFS boss: u/s, the level's own problem solved by the shape's field);
    /// `None` when the planner must solve the level's MFS problem on the
    /// section itself (the MFS cavity, or a source without a field).
    fn level_field(&self, z: f64) -> Option<LevelField>;
}

/// A level's field, its figures, and a remark on its accuracy when it errs
/// more than the level may (the planner adds the level's name in front).
pub struct LevelField {
    /// The field: 1 on the level's section, decreasing away from the material.
    pub(crate) field: Field,
    /// Its solve's figures.
    pub(crate) figures: crate::field::FieldFigures,
    /// Why its accuracy is a concern, if it is.
    pub(crate) warning: Option<String>,
}

/// One ring of a section, described.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SectionRing {
    /// Its vertices, mm.
    pub points: Vec<[f64; 2]>,
    /// Signed area (shoelace), mm²: positive counter-clockwise.
    pub area: f64,
    /// True for a hole (clockwise: the material outside it).
    pub hole: bool,
}

impl SectionRing {
    /// The ring of polygon `p` (material on its left).
    pub(crate) fn of(p: &[Vec2]) -> SectionRing {
        let area = polygon_area(p);
        SectionRing {
            points: p.iter().map(|q| [q.x, q.y]).collect(),
            area,
            hole: area < 0.0,
        }
    }
}

/// A section's net area, mm²: outlines minus holes (the signed areas'
/// sum). A mould's section, its pockets as holes round any islands, has a
/// negative net area.
pub fn net_area(section: &[Vec<Vec2>]) -> f64 {
    section.iter().map(|p| polygon_area(p)).sum()
}

/// Why a height is not in the part.
pub(crate) fn check_z(z: f64, range: (f64, f64), top: f64) -> Result<(), OutsidePart> {
    let (lo, hi) = (top + range.0, top + range.1);
    if z.is_finite() && z >= lo - 1e-9 && z <= hi + 1e-9 {
        return Ok(());
    }
    Err(OutsidePart { z, lo, hi, top })
}

/// A height (`--z`) outside the part's machine z range [lo, hi], mm.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("--z {z}: the part spans z {lo:.3} to {hi:.3} mm (machine z, stock.top = {top})")]
pub struct OutsidePart {
    /// The height asked for.
    pub(crate) z: f64,
    /// The part's lowest machine z.
    pub(crate) lo: f64,
    /// Its highest.
    pub(crate) hi: f64,
    /// `stock.top`.
    pub(crate) top: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rings_know_their_orientation() {
        let sq = [
            Vec2::new(0.0, 0.0),
            Vec2::new(2.0, 0.0),
            Vec2::new(2.0, 3.0),
            Vec2::new(0.0, 3.0),
        ];
        let r = SectionRing::of(&sq);
        assert!((r.area - 6.0).abs() < 1e-12 && !r.hole);
        let rev: Vec<Vec2> = sq.iter().rev().copied().collect();
        let h = SectionRing::of(&rev);
        assert!((h.area + 6.0).abs() < 1e-12 && h.hole);
        assert!((net_area(&[sq.to_vec(), rev]) - 0.0).abs() < 1e-12);
    }

    #[test]
    fn a_z_outside_the_part_names_the_flag_and_the_range() {
        assert!(check_z(-1.0, (-3.0, 0.0), 0.0).is_ok());
        assert!(check_z(-3.0, (-3.0, 0.0), 0.0).is_ok());
        let e = check_z(0.5, (-3.0, 0.0), 0.0).unwrap_err().to_string();
        assert!(
            e.contains("--z 0.5") && e.contains("-3.000 to 0.000"),
            "{e}"
        );
        assert!(check_z(f64::NAN, (-3.0, 0.0), 0.0).is_err());
        assert!(check_z(9.0, (-3.0, 0.0), 10.0).is_ok());
    }
}
