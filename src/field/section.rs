//! A level's own MFS problem on its section (the paper's Section 7: "The
//! corresponding MFS problem is solved at each level to find the offset
//! lines"): u = 1 on the section's closed polygons, 0 on the outer circle and
//! on the sinks `setup` places in the counters, [`N_PER_LOOP`] charges per
//! outer loop, corner clusters with a fifth of the free charges, one quick
//! solve ([`super::solve_quick`]), and local expansions over the section's box.
//! The level planner solves a cavity level's field with it; the inverse
//! problem of a cavity level's clearing is [`super::inverse`].

use super::{setup, solve_quick, Boundary, Field, FieldError, FieldFigures, Layout};
use super::{Prepared, Solved};
use crate::geometry::{polygon_area, polygons_bbox, Contour, Vec2};

/// Singularities per outer loop of a level's Γ(s) (smooth curves need fewer than
/// the glyphs with their corners).
pub const N_PER_LOOP: usize = 90;

/// The field of the section `oriented` (closed polygons, material on their
/// left: outlines counter-clockwise, counters clockwise) with the outer
/// circle of radius `outer_radius`, flattened within `tol`, and its solve's
/// figures. A NaN max error is returned as it is (the caller names the
/// level); the field is then left without local expansions.
pub fn solve_section(
    oriented: &[Vec<Vec2>],
    tol: f64,
    outer_radius: f64,
) -> Result<(Field, FieldFigures), FieldError> {
    let prep = Prepared::new(section_boundary(oriented, tol, outer_radius))?;
    let solved = solve_quick(&prep, section_layout(&prep, outer_loops(oriented)))?;
    let figures = solved.figures();
    if figures.max_error.is_nan() {
        return Ok((solved.solution.field, figures));
    }
    Ok((accelerated(solved, oriented), figures))
}

/// The section's boundary: its polygons as contours, each a counter when
/// clockwise, the outer circle about the material's centroid.
fn section_boundary(oriented: &[Vec<Vec2>], tol: f64, outer_radius: f64) -> Boundary {
    let contours: Vec<Contour> = oriented
        .iter()
        .filter_map(|p| Contour::polygon(p).ok())
        .collect();
    let is_counter: Vec<bool> = oriented.iter().map(|p| polygon_area(p) < 0.0).collect();
    Boundary::about_centroid(contours, is_counter, outer_radius, tol)
}

/// The number of outer loops (counter-clockwise polygons), at least one.
fn outer_loops(oriented: &[Vec<Vec2>]) -> usize {
    oriented
        .iter()
        .filter(|p| polygon_area(p) > 0.0)
        .count()
        .max(1)
}

/// The layout of a section's solve: [`N_PER_LOOP`] per outer loop, the outer
/// ring's charges, and each sink's own plus [`N_PER_LOOP`]; the distance is
/// chosen by [`solve_quick`].
fn section_layout(prep: &Prepared, loops: usize) -> Layout {
    let n_total = N_PER_LOOP * loops
        + setup::OUTER_CHARGES
        + prep.sinks.len() * (setup::SINK_CHARGES + N_PER_LOOP);
    Layout {
        n_total,
        distance: 1.0,
        corner_clusters: true,
        corner_fraction: 0.2,
        pairs: false,
    }
}

/// The solved field with local expansions over the section's box: the rings
/// and the coverage grid evaluate it millions of times (docs/method.md §12).
fn accelerated(solved: Solved, oriented: &[Vec<Vec2>]) -> Field {
    match polygons_bbox(oriented) {
        Some((lo, hi)) => solved.solution.field.accelerated_around(lo, hi),
        None => solved.solution.field,
    }
}
