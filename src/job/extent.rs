//! The size of the built shape, bounded once it is built. `shape.height` bounds
//! a text's cap height, but the width of a long text, an SVG path or a
//! composition without `shape.height` (1 unit = 1 mm), or a wide path scaled to
//! a given height are only known from the geometry: a 1 km polygon would
//! otherwise be traced, cleared and written as G-code for hours.

use super::resolve::show;
use super::{limits, JobError};
use crate::geometry::svgfile::SvgSize;
use crate::geometry::{Shape, ShapeSource};

/// The largest side accepted for a shape cut with a tool of `diameter` mm:
/// [`limits::MAX_EXTENT`], and at most [`limits::MAX_HEIGHT_PER_DIAMETER`]
/// tool diameters (the rule `shape.height` follows).
pub fn max_side(diameter: f64) -> f64 {
    limits::MAX_EXTENT.min(limits::MAX_HEIGHT_PER_DIAMETER * diameter)
}

/// `Ok` when the shape's bounding box (width w, height h, mm) has
/// max(w, h) ≤ [`max_side`]; else an error naming the key that made it so large
/// and what to change. A shape with no contour passes (other checks refuse it);
/// a non-finite box never does.
pub fn check_extent(source: &ShapeSource, shape: &Shape, diameter: f64) -> Result<(), JobError> {
    let Some((lo, hi)) = shape.bbox() else {
        return Ok(());
    };
    let (w, h) = (hi.x - lo.x, hi.y - lo.y);
    let limit = max_side(diameter);
    if w <= limit && h <= limit {
        return Ok(());
    }
    let (key, advice) = match source {
        ShapeSource::Text { as_lines, .. } => (
            if *as_lines { "shape.lines" } else { "shape.text" },
            "use fewer letters or lines, a smaller shape.height, shape.letter_spacing or shape.line_spacing",
        ),
        ShapeSource::SvgPath { height: None, .. } => (
            "shape.svg_path",
            "1 path unit is 1 mm without shape.height: set shape.height to scale it",
        ),
        ShapeSource::SvgPath { .. } => (
            "shape.svg_path",
            "the path is wide for its height: lower shape.height",
        ),
        ShapeSource::SvgFile(f) => match f.size {
            SvgSize::Natural => (
                "shape.svg_file",
                "the document's own size is used without shape.width, shape.height or shape.scale: set one to scale it",
            ),
            SvgSize::Scale(_) => ("shape.scale", "lower shape.scale"),
            SvgSize::Width(_) => ("shape.width", "the drawing is tall for its width: lower shape.width"),
            SvgSize::Height(_) => ("shape.height", "the drawing is wide for its height: lower shape.height"),
        },
        ShapeSource::DxfFile(_) => (
            "shape.dxf_file",
            "the drawing keeps the size its $INSUNITS gives: check its units, or scale it in the CAD program",
        ),
        ShapeSource::Composite(c) if c.height.is_none() => (
            "shape.result",
            "1 design unit is 1 mm without shape.height: set shape.height to scale it",
        ),
        ShapeSource::Composite(_) => (
            "shape.result",
            "the result is wide for its height: lower shape.height",
        ),
        ShapeSource::HarmonicBezier(_) => (
            "shape.size",
            "make the patch smaller, or use a larger tool",
        ),
        ShapeSource::Polyharmonic(_) => (
            "shape.size",
            "make the rectangle smaller, or use a larger tool",
        ),
        ShapeSource::PdeTube(_) => (
            "shape.bottom_size",
            "make the tube smaller, or use a larger tool",
        ),
    };
    let why = if limit < limits::MAX_EXTENT {
        format!(
            " ({} × tool.diameter)",
            show(limits::MAX_HEIGHT_PER_DIAMETER)
        )
    } else {
        String::new()
    };
    Err(super::invalid(
        key,
        format!(
            "makes a shape {} × {} mm; at most {} mm on a side are allowed{why}: {advice}",
            show_mm(w),
            show_mm(h),
            show(limit),
        ),
    ))
}

/// A length in mm to 0.1 mm, or as written when huge or not finite.
fn show_mm(x: f64) -> String {
    if x.is_finite() && x.abs() < 1e9 {
        format!("{x:.1}")
    } else {
        show(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{build_shape, FontSource, Vec2};

    fn svg(d: &str, height: Option<f64>) -> ShapeSource {
        ShapeSource::SvgPath {
            d: d.into(),
            height,
            origin: Vec2::ZERO,
        }
    }

    #[test]
    fn a_shape_at_the_limit_passes_and_one_past_it_is_named() {
        let at = svg("M0 0 H2000 V10 H0 Z", None);
        let shape = build_shape(&at).expect("shape");
        assert!(check_extent(&at, &shape, 3.0).is_ok());
        let past = svg("M0 0 H2000.5 V10 H0 Z", None);
        let shape = build_shape(&past).expect("shape");
        let e = check_extent(&past, &shape, 3.0).unwrap_err().to_string();
        assert!(
            e.starts_with("shape.svg_path makes a shape 2000.5 × 10.0 mm; at most 2000 mm"),
            "{e}"
        );
        assert!(e.contains("set shape.height"), "{e}");
    }

    #[test]
    fn the_limit_follows_the_tool() {
        // 2000 diameters of a 0.5 mm tool: 1000 mm.
        assert_eq!(max_side(0.5), 1000.0);
        assert_eq!(max_side(3.175), 2000.0);
        let src = svg("M0 0 H1001 V10 H0 Z", None);
        let shape = build_shape(&src).expect("shape");
        let e = check_extent(&src, &shape, 0.5).unwrap_err().to_string();
        assert!(
            e.contains("at most 1000 mm on a side are allowed (2000 × tool.diameter)"),
            "{e}"
        );
        assert!(check_extent(&src, &shape, 0.6).is_ok());
    }

    #[test]
    fn a_long_text_is_named_by_its_text() {
        let src = ShapeSource::Text {
            text: "I".repeat(60),
            font: FontSource::Paper,
            height: 50.0,
            letter_spacing: 40.0,
            line_spacing: None,
            align: crate::geometry::Align::Left,
            origin: Vec2::ZERO,
            as_lines: false,
        };
        let shape = build_shape(&src).expect("shape");
        let e = check_extent(&src, &shape, 3.0).unwrap_err().to_string();
        assert!(e.starts_with("shape.text makes a shape "), "{e}");
        assert!(e.contains("fewer letters"), "{e}");
        // Lines far apart make a tall shape, named by `shape.lines`.
        let tall = ShapeSource::Text {
            text: "I\n\n\nI".into(),
            font: FontSource::Paper,
            height: 50.0,
            letter_spacing: 0.0,
            line_spacing: Some(9.0),
            align: crate::geometry::Align::Left,
            origin: Vec2::ZERO,
            as_lines: true,
        };
        let shape = build_shape(&tall).expect("shape");
        let e = check_extent(&tall, &shape, 0.5).unwrap_err().to_string();
        assert!(e.starts_with("shape.lines makes a shape "), "{e}");
    }
}
