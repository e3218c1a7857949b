//! Arrows along the deepest pass that show the cutting direction.

use super::frame::Frame;
use super::polyline::{along, polyline_length};
use super::svgfmt::num;
use crate::geometry::Vec2;
use svg::node::element::Path;

/// At most this many tracks of the deepest level get direction arrows (the
/// longest ones): a clearing level has many.
pub(crate) const ARROW_TRACKS: usize = 8;

/// Direction arrows along the longest [`ARROW_TRACKS`] of the deepest level's
/// tracks: arrows of size a = min(size / 35, 0.7 fs), one per fifth of the
/// drawing's diagonal (2 to 12 a track), none on a track shorter than 3a.
/// `None` when no track gets one.
pub(super) fn direction_arrows(mut deepest: Vec<Vec<Vec2>>, frame: &Frame) -> Option<Path> {
    let diag = Vec2::new(frame.w, frame.h).norm();
    let a = (frame.size / 35.0).min(0.7 * frame.fs);
    let mut arrows = String::new();
    deepest.sort_by(|p, q| polyline_length(q).total_cmp(&polyline_length(p)));
    deepest.truncate(ARROW_TRACKS);
    for pl in &deepest {
        let len = polyline_length(pl);
        if len < 3.0 * a {
            continue;
        }
        let count = ((len / (diag / 5.0)).round() as usize).clamp(2, 12);
        for (p, t) in along(pl, count) {
            arrows += &arrow_head(p, t, a);
        }
    }
    (!arrows.is_empty()).then(|| {
        Path::new()
            .set("d", arrows)
            .set("fill", "#ffffff")
            .set("stroke", "#000000")
            .set("stroke-width", num(0.5 * frame.lw))
            .set("class", "direction")
    })
}

/// Path data of a triangle of size `a` at `p` pointing along the unit tangent
/// `t`: the tip 0.6a ahead, the base 0.4a behind and 0.7a wide.
fn arrow_head(p: Vec2, t: Vec2, a: f64) -> String {
    let n = t.perp();
    let tip = p + t * (0.6 * a);
    let l = p - t * (0.4 * a) + n * (0.35 * a);
    let r = p - t * (0.4 * a) - n * (0.35 * a);
    format!(
        "M{} {}L{} {}L{} {}Z",
        num(tip.x),
        num(-tip.y),
        num(l.x),
        num(-l.y),
        num(r.x),
        num(-r.y)
    )
}
