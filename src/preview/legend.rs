//! The footer under the drawing: a scale bar, then the legend, flowing into
//! rows.

use super::colours::{curve_colour, depth_colour};
use super::cut::{Depths, BAND_LEVELS};
use super::frame::Frame;
use super::svgfmt::{level_label, num, text, FONT};
use svg::node::element::{Circle, Definitions, Group, Line, LinearGradient, Rectangle, Stop};

/// What a legend entry shows before its label.
enum Swatch {
    /// A line: colour, width (mm), dashed.
    Line(String, f64, bool),
    /// A dot of this colour.
    Dot(String),
    /// The depth colour bar, from the shallowest to the deepest level.
    Bar,
}

/// A rectangle with its top-left corner at SVG `(x, y)`, `(width, height)`
/// mm, filled with `fill`, of class `class`.
fn filled_rect((x, y): (f64, f64), (w, h): (f64, f64), fill: &str, class: &str) -> Rectangle {
    Rectangle::new()
        .set("x", num(x))
        .set("y", num(y))
        .set("width", num(w))
        .set("height", num(h))
        .set("fill", fill)
        .set("class", class)
}

/// A "nice" scale-bar length (1, 2 or 5 × 10ᵏ mm) of at most `max` mm.
fn nice_length(max: f64) -> f64 {
    let p = 10f64.powf(max.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&l| l <= max)
        .unwrap_or(p)
}

/// The footer and the SVG y of its bottom edge. `levels` are the
/// equipotentials asked for (sorted), `shown` those with a curve in the
/// drawing; `d` is the tool diameter.
pub(super) fn footer(
    frame: &Frame,
    depths: &Depths,
    d: f64,
    levels: &[f64],
    shown: &[f64],
    finish: bool,
) -> (Group, f64) {
    let (fs, x0) = (frame.fs, frame.x0);
    let foot_y = -frame.lo.y + 0.8 * fs; // top of the footer
    let mut foot = Group::new()
        .set("font-family", FONT)
        .set("font-size", num(0.8 * fs))
        .set("class", "legend");
    let bar = nice_length(0.3 * frame.w);
    let (bx, by) = (x0 + fs, foot_y + 0.6 * fs);
    foot = foot
        .add(filled_rect(
            (bx, by - 0.15 * fs),
            (bar, 0.3 * fs),
            "#000000",
            "scale-bar",
        ))
        .add(text(
            bx + bar + 0.5 * fs,
            by + 0.3 * fs,
            0.8 * fs,
            &format!("{} mm", num(bar)),
        ));
    // Each entry is about 2 fs + 0.5 fs per character wide.
    let mut x = bx + bar + 5.0 * fs;
    let mut row_y = by;
    let right = x0 + frame.doc_w - fs;
    for (sw, label) in entries(frame, depths, d, levels, shown, finish) {
        // The swatch is 1.6 fs long (the colour bar 6 fs), its label follows.
        let sw_w = if matches!(sw, Swatch::Bar) { 6.0 } else { 1.6 } * fs;
        let ew = sw_w + 0.9 * fs + 0.5 * fs * label.chars().count() as f64;
        if x + ew > right && x > x0 + 2.0 * fs {
            x = x0 + fs;
            row_y += 1.4 * fs;
        }
        foot = draw_swatch(foot, sw, x, row_y, sw_w, fs);
        foot = foot.add(text(
            x + sw_w + 0.4 * fs,
            row_y + 0.3 * fs,
            0.8 * fs,
            &label,
        ));
        x += ew;
    }
    (foot, row_y + 1.2 * fs)
}

/// The legend's entries: the levels (each, or the colour bar when there are
/// more than [`BAND_LEVELS`]), the finishing passes (when `finish`), rapids,
/// the start, and the equipotentials.
fn entries(
    frame: &Frame,
    depths: &Depths,
    d: f64,
    levels: &[f64],
    shown: &[f64],
    finish: bool,
) -> Vec<(Swatch, String)> {
    let (fs, lw) = (frame.fs, frame.lw);
    let n_lv = depths.count();
    let mut entries: Vec<(Swatch, String)> = Vec::new();
    if n_lv > BAND_LEVELS {
        entries.push((
            Swatch::Bar,
            format!(
                "z {} … {} mm, {n_lv} levels",
                num(depths.zmax),
                num(depths.zmin)
            ),
        ));
    } else {
        for (k, l) in depths.levels.iter().enumerate() {
            let (colour, width) = depths.style(k, lw, d);
            entries.push((
                Swatch::Line(colour, width.max(0.3 * fs), false),
                format!("z {}", num(l.z)),
            ));
        }
    }
    if finish {
        entries.push((
            Swatch::Line(super::FINISH_COLOUR.into(), 0.5 * lw, false),
            "finish".into(),
        ));
    }
    entries.push((Swatch::Line("#6b6b6b".into(), lw, true), "rapid".into()));
    entries.push((Swatch::Dot("#00a650".into()), "start, tool ⌀".into()));
    if !shown.is_empty() {
        let vals: Vec<String> = shown.iter().map(|s| level_label(*s)).collect();
        entries.push((
            Swatch::Line(curve_colour(levels.len() - 1, levels.len()), lw, false),
            format!("Γ(s), s = {}", vals.join(", ")),
        ));
    }
    entries
}

/// Adds swatch `sw`, `sw_w` mm wide, at (`x`, `row_y`) to `foot`.
fn draw_swatch(foot: Group, sw: Swatch, x: f64, row_y: f64, sw_w: f64, fs: f64) -> Group {
    match sw {
        Swatch::Line(c, width, dashed) => {
            let mut line = Line::new()
                .set("x1", num(x))
                .set("y1", num(row_y))
                .set("x2", num(x + 1.6 * fs))
                .set("y2", num(row_y))
                .set("stroke", c)
                .set("stroke-width", num(width));
            if dashed {
                line = line.set(
                    "stroke-dasharray",
                    format!("{} {}", num(0.4 * fs), num(0.25 * fs)),
                );
            }
            foot.add(line)
        }
        Swatch::Dot(c) => foot.add(
            Circle::new()
                .set("cx", num(x + 0.8 * fs))
                .set("cy", num(row_y))
                .set("r", num(0.3 * fs))
                .set("fill", c),
        ),
        Swatch::Bar => {
            let mut grad = LinearGradient::new()
                .set("id", "pfcam-depth")
                .set("x1", "0")
                .set("x2", "1")
                .set("y1", "0")
                .set("y2", "0");
            for t in [0.0, 0.35, 0.7, 1.0] {
                grad = grad.add(
                    Stop::new()
                        .set("offset", num(t))
                        .set("stop-color", depth_colour(t)),
                );
            }
            foot.add(Definitions::new().add(grad)).add(filled_rect(
                (x, row_y - 0.3 * fs),
                (sw_w, 0.6 * fs),
                "url(#pfcam-depth)",
                "depth-bar",
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_scale_lengths() {
        assert_eq!(nice_length(57.0), 50.0);
        assert_eq!(nice_length(19.0), 10.0);
        assert_eq!(nice_length(2.2), 2.0);
    }
}
