//! The cut: every depth level's tracks in its own colour, deeper levels
//! narrower and on top, so that passes over the same XY show as bands.

use super::colours::depth_colour;
use super::polyline::level_polylines;
use super::svgfmt::{num, path_data};
use crate::geometry::Vec2;
use crate::report::LevelMoves;
use svg::node::element::{Group, Path};

/// Up to this many levels each get a band width and a legend entry of their own;
/// more (a boss or cavity has dozens) are drawn in one width with a colour bar.
pub(crate) const BAND_LEVELS: usize = 6;

/// Stroke width of the level `above` levels above the deepest of `n` levels:
/// with few levels each shallower one is wider by three base widths, so passes
/// over the same track show as bands; with many, all are 1.5 base widths. The
/// widest band is never wider than the cut itself, the tool diameter `d`
/// (with a 0.5 mm tool the bands would otherwise cover the neighbouring
/// tracks), so all are scaled down together when it would be.
pub(super) fn band_width(lw: f64, above: usize, n: usize, d: f64) -> f64 {
    let width = |above: usize| {
        if n > BAND_LEVELS {
            1.5 * lw
        } else {
            lw * (2.0 + 3.0 * above.min(BAND_LEVELS) as f64)
        }
    };
    let widest = width(n.saturating_sub(1));
    width(above) * (d / widest).min(1.0)
}

/// The run's levels, shallowest first, and their depth range.
pub(super) struct Depths {
    /// The levels' feed moves.
    pub(crate) levels: Vec<LevelMoves>,
    /// The shallowest level's z, mm (0 without levels).
    pub(crate) zmax: f64,
    /// The deepest level's z, mm (0 without levels).
    pub(crate) zmin: f64,
}

impl Depths {
    /// The depth range of `levels` (shallowest first).
    pub(crate) fn new(levels: Vec<LevelMoves>) -> Depths {
        let (zmax, zmin) = (
            levels.first().map_or(0.0, |l| l.z),
            levels.last().map_or(0.0, |l| l.z),
        );
        Depths { levels, zmax, zmin }
    }

    /// How many levels.
    pub(crate) fn count(&self) -> usize {
        self.levels.len()
    }

    /// Where `z` lies in the range: 0 the shallowest, 1 the deepest (1 when
    /// all levels share one z).
    pub(crate) fn fraction(&self, z: f64) -> f64 {
        if self.zmax - self.zmin > 1e-9 {
            (self.zmax - z) / (self.zmax - self.zmin)
        } else {
            1.0
        }
    }

    /// The stroke colour and width of level `k` with base width `lw` and tool
    /// diameter `d`.
    pub(crate) fn style(&self, k: usize, lw: f64, d: f64) -> (String, f64) {
        let n = self.count();
        (
            depth_colour(self.fraction(self.levels[k].z)),
            band_width(lw, n - 1 - k, n, d),
        )
    }
}

/// The levels' tracks as paths (arcs flattened within `tol`), and the deepest
/// level's tracks for the direction arrows.
pub(super) fn cut_group(depths: &Depths, lw: f64, d: f64, tol: f64) -> (Group, Vec<Vec<Vec2>>) {
    let mut deepest: Vec<Vec<Vec2>> = Vec::new();
    let mut cut = Group::new()
        .set("fill", "none")
        .set("stroke-linejoin", "round")
        .set("stroke-linecap", "round")
        .set("class", "toolpath");
    for (k, l) in depths.levels.iter().enumerate() {
        let pls = level_polylines(&l.moves, tol);
        let (colour, width) = depths.style(k, lw, d);
        cut = cut.add(
            Path::new()
                .set("d", path_data(&pls, false))
                .set("stroke", colour)
                .set("stroke-width", num(width))
                .set("data-z", num(l.z)),
        );
        if k + 1 == depths.count() {
            deepest = pls;
        }
    }
    (cut, deepest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_are_never_wider_than_the_cut() {
        for d in [0.5, 3.175, 12.0] {
            for n in 1..10 {
                let widths: Vec<f64> = (0..n).map(|a| band_width(0.3, a, n, d)).collect();
                assert!(
                    widths.iter().all(|&w| w > 0.0 && w <= d + 1e-12),
                    "{d} {n}: {widths:?}"
                );
                // Shallower levels stay wider (or, with many levels, equal).
                assert!(widths.windows(2).all(|w| w[1] >= w[0]), "{widths:?}");
            }
        }
        // Unscaled when the tool is wide enough.
        assert_eq!(band_width(0.1, 2, 3, 3.175), 0.1 * 8.0);
    }
}
