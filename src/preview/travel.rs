//! The moves outside the cut: rapids (dashed) and the start of the first
//! feed move, with the tool's disk.

use super::frame::Frame;
use super::svgfmt::{num, path_data};
use crate::geometry::Vec2;
use crate::pipeline::RunOutput;
use svg::node::element::{Circle, Path};

/// The rapids with XY length, dashed grey.
pub(super) fn rapids(out: &RunOutput, frame: &Frame) -> Path {
    let mut rapids = Vec::new();
    let mut at = out.toolpath.start;
    for m in out.toolpath.moves() {
        if let crate::toolpath::Move::Rapid { to } = m {
            if at.xy().dist(to.xy()) > 1e-9 {
                rapids.push(vec![at.xy(), to.xy()]);
            }
        }
        at = m.to();
    }
    Path::new()
        .set("d", path_data(&rapids, false))
        .set("fill", "none")
        .set("stroke", "#6b6b6b")
        .set("stroke-width", num(frame.lw))
        .set(
            "stroke-dasharray",
            format!("{} {}", num(0.8 * frame.fs), num(0.5 * frame.fs)),
        )
        .set("class", "rapids")
}

/// Where the first feed move begins, if there is one.
fn start_point(out: &RunOutput) -> Option<Vec2> {
    out.toolpath.feed_moves().next().map(|(at, _)| at.xy())
}

/// The start: the tool's disk (radius `tool_radius`) at the first feed
/// move's beginning and a dot on it; nothing for a path without feed.
pub(super) fn start_marker(
    out: &RunOutput,
    tool_radius: f64,
    frame: &Frame,
) -> Option<(Circle, Circle)> {
    let s = start_point(out)?;
    let (lw, fs) = (frame.lw, frame.fs);
    Some((
        Circle::new()
            .set("cx", num(s.x))
            .set("cy", num(-s.y))
            .set("r", num(tool_radius))
            .set("fill", "#ff9900")
            .set("fill-opacity", "0.45")
            .set("stroke", "#cc6600")
            .set("stroke-width", num(lw))
            .set("class", "tool"),
        Circle::new()
            .set("cx", num(s.x))
            .set("cy", num(-s.y))
            .set("r", num(0.3 * fs))
            .set("fill", "#00a650")
            .set("stroke", "#ffffff")
            .set("stroke-width", num(0.5 * lw))
            .set("class", "start"),
    ))
}
