//! The header above the drawing: the job's name and its key figures.

use super::cut::Depths;
use super::frame::Frame;
use super::svgfmt::{num, text, FONT};
use crate::gcode::format_duration;
use crate::job::Job;
use crate::report::RunReport;
use svg::node::element::Group;

/// The header: the job's name in bold, then the operation, tool and depths;
/// the path's lengths and time; the field's error and the clearance; a line
/// for a finishing program; and the first warning, if any, in orange.
pub(super) fn header(job: &Job, report: &RunReport, depths: &Depths, frame: &Frame) -> Group {
    let (fs, x0, top_y) = (frame.fs, frame.x0, frame.top_y);
    let mut lines = lines(job, report, depths);
    if let Some(w) = warning_line(report, frame.doc_w - 2.0 * fs, fs) {
        lines.push((w, Some("#b34700")));
    }
    let mut head = Group::new()
        .set("font-family", FONT)
        .set("fill", "#000000")
        .set("class", "header");
    head = head
        .add(text(x0 + fs, top_y + 1.5 * fs, 1.25 * fs, &report.job).set("font-weight", "bold"));
    for (k, (l, colour)) in lines.iter().enumerate() {
        let t = text(x0 + fs, top_y + (2.9 + 1.2 * k as f64) * fs, 0.9 * fs, l);
        head = head.add(match colour {
            Some(c) => t.set("fill", *c),
            None => t,
        });
    }
    head
}

/// The header's lines under the job's name, but for the warning (which is
/// cut to the page's width), each with its colour where it is not the
/// header's black: the finishing program's in the colour its passes are
/// drawn in.
fn lines(job: &Job, report: &RunReport, depths: &Depths) -> Vec<(String, Option<&'static str>)> {
    let mut lines: Vec<(String, Option<&str>)> = figure_lines(job, report, depths)
        .into_iter()
        .map(|l| (l, None))
        .collect();
    if let Some(f) = finish_line(job, report) {
        lines.push((f, Some(super::FINISH_COLOUR)));
    }
    lines
}

/// What the page must leave room for above the drawing: the header's lines
/// (a warning adds one) and the longest one's characters, which the page is
/// at least as wide as ([`Frame::new`]).
pub(super) fn text_size(job: &Job, report: &RunReport, depths: &Depths) -> (usize, usize) {
    let lines = lines(job, report, depths);
    let widest = lines
        .iter()
        .map(|(l, _)| l.chars().count())
        .max()
        .unwrap_or(0);
    (
        lines.len() + usize::from(!report.warnings.is_empty()),
        widest,
    )
}

/// The header's lines of figures (the roughing program's, or the only one).
fn figure_lines(job: &Job, report: &RunReport, depths: &Depths) -> Vec<String> {
    let t = &report.totals;
    let n_lv = depths.count();
    let z_range = if n_lv == 0 {
        "no cut".to_string()
    } else if n_lv == 1 {
        format!("1 level, z {} mm", num(depths.zmin))
    } else {
        format!(
            "{n_lv} levels, z {} to {} mm",
            num(depths.zmax),
            num(depths.zmin)
        )
    };
    vec![
        format!(
            "{} · tool ⌀{} mm · {}",
            report.operation,
            num(job.tool.diameter),
            z_range
        ),
        format!(
            "path {:.1} mm cutting + {:.1} mm rapid · est. time {}",
            t.cut_length_mm,
            t.rapid_length_mm,
            format_duration(t.time_s)
        ),
        format!(
            "max boundary error {:.2e} · min clearance {}",
            t.max_boundary_error,
            t.min_clearance_mm
                .map_or("-".into(), |c| format!("{c:.4} mm"))
        ),
    ]
}

/// The line for the finishing program (its own file, its passes drawn over
/// the cut) with its figures as the report gives them.
fn finish_line(job: &Job, report: &RunReport) -> Option<String> {
    let (f, p) = (job.finish.as_ref()?, report.programs.get(1)?);
    Some(format!(
        "then {}: {} ⌀{} mm · {:.1} mm cutting · est. time {}",
        p.file,
        f.shape.header_words(),
        num(f.diameter),
        p.cut_length_mm,
        format_duration(p.time_s)
    ))
}

/// The first warning, with how many there are, cut with `…` to fit `width`
/// mm at type size 0.9 `fs` (DejaVu Sans averages about 0.55 em a character).
fn warning_line(report: &RunReport, width: f64, fs: f64) -> Option<String> {
    let w = report.warnings.first()?;
    let mut w = format!(
        "{} warning{}: {w}",
        report.warnings.len(),
        if report.warnings.len() == 1 { "" } else { "s" }
    );
    let fit = (width / (0.55 * 0.9 * fs)).floor().max(10.0) as usize;
    if w.chars().count() > fit {
        w = w.chars().take(fit - 1).collect::<String>() + "…";
    }
    Some(w)
}
