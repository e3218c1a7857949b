//! The equipotential curves Γ(s) drawn over the part, each labelled with its
//! value where the label is readable.

use super::colours::curve_colour;
use super::frame::Frame;
use super::svgfmt::{level_label, num, path_data, text, FONT};
use super::PreviewError;
use crate::field::isolines::{material_mask, pieces, Equipotential, Grid};
use crate::geometry::{DistanceIndex, Vec2};
use crate::job::Job;
use crate::pipeline::RunOutput;
use svg::node::element::{Group, Path};

/// The curves of the drawn levels, their labels, and the values that have a
/// curve inside the drawing (for the legend).
pub(super) struct Equipotentials {
    /// One path per level, farthest first.
    pub(crate) curves: Group,
    /// The value labels, haloed in white.
    pub(crate) labels: Group,
    /// The levels with at least one curve piece.
    pub(crate) shown: Vec<f64>,
}

/// The curves Γ(s) for each of `levels` (sorted, farthest first), traced on a
/// grid of `cells` cells along the drawing's longer side over the part
/// `polys` (`field::isolines`, the planner's sampling and extractor, with the
/// pieces that leave the drawing). Drawn black over the field image (`on_image`), else in
/// [`curve_colour`].
pub(super) fn equipotentials(
    job: &Job,
    out: &RunOutput,
    frame: &Frame,
    polys: &[Vec<Vec2>],
    levels: &[f64],
    cells: usize,
    on_image: bool,
) -> Result<Equipotentials, PreviewError> {
    let fs = frame.fs;
    let mask = material_mask(polys);
    let part = DistanceIndex::new(polys);
    let h = frame.size / cells as f64;
    let grid = Grid::try_sample(&out.field, frame.lo, frame.hi, h, polys)?;
    let mut curves_group = Group::new()
        .set("fill", "none")
        .set("stroke-width", num(0.8 * frame.lw))
        .set("class", "equipotentials");
    let mut labels = Group::new()
        .set("font-family", FONT)
        .set("font-size", num(0.6 * fs))
        .set("text-anchor", "middle")
        .set("stroke", "#ffffff")
        .set("stroke-width", num(0.25 * fs))
        .set("paint-order", "stroke")
        .set("class", "equipotential-labels");
    let mut placed: Vec<Vec2> = Vec::new();
    let mut shown: Vec<f64> = Vec::new();
    for (k, &s) in levels.iter().enumerate() {
        let curves = pieces(&grid, s, &out.field, &mask);
        let colour = if on_image {
            "#000000".to_string()
        } else {
            curve_colour(k, levels.len())
        };
        if !curves.is_empty() {
            shown.push(s);
        }
        let clear = |p: &Vec2| part.distance(*p) > job.tool.diameter + 0.5 * fs;
        if let Some(at) = label_spot(&curves, frame, clear, &placed) {
            placed.push(at);
            labels = labels.add(
                text(at.x, -at.y + 0.2 * fs, 0.6 * fs, &level_label(s)).set("fill", colour.clone()),
            );
        }
        if let Some(path) = level_path(&curves, s, colour) {
            curves_group = curves_group.add(path);
        }
    }
    Ok(Equipotentials {
        curves: curves_group,
        labels,
        shown,
    })
}

/// Where to label a level: on its longest piece, at a vertex (every third)
/// inside the frame and `clear` of the cut, as far as possible from the labels
/// `placed` so far (then as high as possible), so that labels of close curves
/// do not pile up.
fn label_spot(
    curves: &[Equipotential],
    frame: &Frame,
    clear: impl Fn(&Vec2) -> bool,
    placed: &[Vec2],
) -> Option<Vec2> {
    let (lo, hi, fs) = (frame.lo, frame.hi, frame.fs);
    let inside = |p: &Vec2| {
        p.x > lo.x + 2.0 * fs
            && p.x < hi.x - 2.0 * fs
            && p.y < hi.y - fs
            && p.y > lo.y + fs
            && clear(p)
    };
    let score = |p: &Vec2| {
        let free = placed
            .iter()
            .map(|q: &Vec2| q.dist(*p))
            .fold(8.0 * fs, f64::min);
        (free, p.y)
    };
    curves
        .iter()
        .max_by(|a, b| a.length().total_cmp(&b.length()))
        .and_then(|c| {
            c.points
                .iter()
                .step_by(3)
                .filter(|p| inside(p))
                .max_by(|a, b| {
                    score(a)
                        .partial_cmp(&score(b))
                        .unwrap_or(std::cmp::Ordering::Equal)
                })
        })
        .copied()
}

/// One level's curve pieces as a path (closed ones closed), or `None` when
/// nothing is drawn.
fn level_path(curves: &[Equipotential], s: f64, colour: String) -> Option<Path> {
    let pieces = |closed: bool| -> Vec<Vec<Vec2>> {
        curves
            .iter()
            .filter(|c| c.closed == closed)
            .map(|c| c.points.clone())
            .collect()
    };
    let d = path_data(&pieces(true), true) + &path_data(&pieces(false), false);
    (!d.is_empty()).then(|| {
        Path::new()
            .set("d", d)
            .set("stroke", colour)
            .set("data-s", num(s))
    })
}
