//! SVG path data (the `d` attribute).

use super::{GeometryError, Shape, Vec2};

/// Placeholder until the parser lands.
pub fn svg_shape(_d: &str, _height: Option<f64>, _origin: Vec2) -> Result<Shape, GeometryError> {
    Err(GeometryError::Invalid(
        "SVG path data is not supported yet".into(),
    ))
}
