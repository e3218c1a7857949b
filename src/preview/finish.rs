//! The finishing program's passes, drawn over the roughing's cut as thin
//! lines in one colour, so that the preview shows where the second tool goes
//! (its own file, `<name>.finish.nc`; the header names it in that colour).

use super::frame::Frame;
use super::polyline::level_polylines;
use super::svgfmt::{num, path_data};
use crate::geometry::thin::keep_mask;
use crate::geometry::{seg_seg_dist, Vec2};
use crate::toolpath::Toolpath;
use svg::node::element::Path;

/// The colour of the finishing passes and of the header's line about them.
pub(crate) const FINISH_COLOUR: &str = "#e66a00";

/// The finishing program's feed moves as one thin path (arcs flattened and
/// the tracks thinned within the drawing's tolerance `frame.tol_draw`), or
/// `None` when it has none.
pub(super) fn finish_passes(tp: &Toolpath, frame: &Frame) -> Option<Path> {
    let moves: Vec<_> = tp.feed_moves().collect();
    let tracks: Vec<Vec<Vec2>> = level_polylines(&moves, frame.tol_draw)
        .iter()
        .map(|pl| thin(pl, frame.tol_draw))
        .collect();
    if tracks.is_empty() {
        return None;
    }
    Some(
        Path::new()
            .set("d", path_data(&tracks, false))
            .set("fill", "none")
            .set("stroke", FINISH_COLOUR)
            .set("stroke-width", num(0.5 * frame.lw))
            .set("stroke-linejoin", "round")
            .set("class", "finish"),
    )
}

/// The points of `pl` that Douglas–Peucker keeps in the plane at `tol`:
/// every dropped point lies within `tol` of the chord that replaces it. The
/// finishing passes climb and fall along the walls, so seen from above they
/// are dense where the drawing needs few points.
fn thin(pl: &[Vec2], tol: f64) -> Vec<Vec2> {
    let keep = keep_mask(
        pl.len(),
        tol,
        |k, a, b| seg_seg_dist(pl[k], pl[k], pl[a], pl[b]),
        |_, _| None,
    );
    pl.iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(p, _)| *p)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A zigzag within the tolerance of its chord thins to its ends; a
    /// corner past it is kept; every dropped point lies within the
    /// tolerance of the thinned line.
    #[test]
    fn thinning_keeps_corners_and_drops_what_lies_on_the_chord() {
        let tol = 0.01;
        let flat: Vec<Vec2> = (0..=10)
            .map(|i| Vec2::new(i as f64, if i % 2 == 0 { 0.0 } else { 0.004 }))
            .collect();
        assert_eq!(thin(&flat, tol), vec![flat[0], flat[10]]);
        let mut bent = flat.clone();
        bent.extend((1..=10).map(|i| Vec2::new(10.0, i as f64)));
        let t = thin(&bent, tol);
        assert_eq!(t, vec![bent[0], Vec2::new(10.0, 0.0), bent[20]]);
        for p in &bent {
            let d = t
                .windows(2)
                .map(|w| seg_seg_dist(*p, *p, w[0], w[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= tol, "{p:?} {d}");
        }
    }
}
