//! Turning a `ShapeSource` into a `Shape` in millimetres.

use super::{glyphs, FontSource, GeometryError, Region, Shape, ShapeSource, Vec2};

/// Build the shape a job describes, in millimetres, outlines counter-clockwise and
/// counters clockwise.
pub fn build_shape(src: &ShapeSource) -> Result<Shape, GeometryError> {
    match src {
        ShapeSource::Text {
            text,
            font: FontSource::Paper,
            height,
            letter_spacing,
            origin,
        } => {
            let scale = height / glyphs::PAPER_CAP_HEIGHT;
            let mut pen = 0.0;
            let mut regions = Vec::new();
            for (i, ch) in text.chars().enumerate() {
                if ch == ' ' {
                    pen += 250.0 * scale + letter_spacing;
                    continue;
                }
                let g = glyphs::paper_glyph(ch)?;
                let (px, o) = (pen, *origin);
                let f = move |p: Vec2| Vec2::new(o.x + px + p.x * scale, o.y + p.y * scale);
                for (k, outline) in g.outlines.iter().enumerate() {
                    let name = if g.outlines.len() > 1 {
                        format!("{ch} ({}.{})", i + 1, k + 1)
                    } else {
                        format!("{ch} ({})", i + 1)
                    };
                    regions.push(Region {
                        name,
                        outline: outline.map(f),
                        counters: g.counters.iter().map(|c| c.map(f)).collect(),
                    });
                }
                pen += g.advance * scale + letter_spacing;
            }
            Ok(Shape { regions })
        }
        _ => Err(GeometryError::Invalid(
            "this shape source is not supported yet".into(),
        )),
    }
}
