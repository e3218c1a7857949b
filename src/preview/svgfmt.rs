//! How the preview writes numbers, polylines and text into SVG: part
//! coordinates in mm, y flipped (SVG's y runs down).

use crate::geometry::Vec2;
use svg::node::element::Text;

/// Font families for every text.
pub(super) const FONT: &str = "DejaVu Sans, Arial, Helvetica, sans-serif";

/// A number for SVG: three decimals, trailing zeros dropped, no `-0`.
pub(super) fn num(x: f64) -> String {
    let s = format!("{x:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" || s.is_empty() {
        "0".into()
    } else {
        s.into()
    }
}

/// An equipotential value as written in a job (`0.9995`, not `num`'s `1`):
/// the shortest decimal that reads back as the same number.
pub(super) fn level_label(s: f64) -> String {
    format!("{s}")
}

/// SVG path data for polylines in part coordinates (y flipped).
pub(super) fn path_data(lines: &[Vec<Vec2>], close: bool) -> String {
    let mut d = String::new();
    for pl in lines.iter().filter(|pl| pl.len() >= 2) {
        for (k, p) in pl.iter().enumerate() {
            d += if k == 0 { "M" } else { "L" };
            d += &num(p.x);
            d.push(' ');
            d += &num(-p.y);
        }
        if close {
            d.push('Z');
        }
    }
    d
}

/// A text at SVG position (`x`, `y`) (already flipped), `size` mm.
pub(super) fn text(x: f64, y: f64, size: f64, content: &str) -> Text {
    Text::new(content)
        .set("x", num(x))
        .set("y", num(y))
        .set("font-size", num(size))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_never_minus_zero() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(-0.0001), "0");
        assert_eq!(num(2.5), "2.5");
        assert_eq!(num(-1.23456), "-1.235");
    }
}
