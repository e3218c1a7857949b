//! The stock's edge and the work zero: what the machinist sets the job up by.

use super::frame::Frame;
use super::svgfmt::{num, path_data, text};
use crate::geometry::Vec2;
use crate::job::Job;
use crate::pipeline::RunOutput;
use svg::node::element::{Group, Path};

/// The stock rectangle (a boss's or cavity's; for a profile the least sheet
/// the tool sweeps, dotted) and the work zero X0 Y0 as a cross with its label:
/// where the machinist sets the job up.
pub(super) fn stock_and_zero(job: &Job, out: &RunOutput, frame: &Frame) -> Group {
    let (lw, fs) = (frame.lw, frame.fs);
    let mut g = Group::new().set("class", "stock");
    if let Some(e) = crate::gcode::stock_extent(&out.toolpath, job.tool.diameter / 2.0, out.stock) {
        let rect = vec![
            e.lo,
            Vec2::new(e.hi.x, e.lo.y),
            e.hi,
            Vec2::new(e.lo.x, e.hi.y),
        ];
        let dash = if e.known {
            "none".to_string()
        } else {
            format!("{} {}", num(0.3 * fs), num(0.3 * fs))
        };
        g = g.add(
            Path::new()
                .set("d", path_data(&[rect], true))
                .set("fill", "none")
                .set("stroke", "#8b5a2b")
                .set("stroke-width", num(lw))
                .set("stroke-dasharray", dash),
        );
    }
    let arm = 0.8 * fs;
    let cross = vec![
        vec![Vec2::new(-arm, 0.0), Vec2::new(arm, 0.0)],
        vec![Vec2::new(0.0, -arm), Vec2::new(0.0, arm)],
    ];
    g.add(
        Path::new()
            .set("d", path_data(&cross, false))
            .set("stroke", "#0050b4")
            .set("stroke-width", num(1.5 * lw))
            .set("class", "work-zero"),
    )
    .add(text(0.4 * fs, 0.4 * fs - arm, 0.7 * fs, "X0 Y0").set("fill", "#0050b4"))
}
