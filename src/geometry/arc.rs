//! Circular arcs in the XY plane as G-code gives them: a start, an end, a
//! centre and a direction. One definition of the sweep for the writer, the
//! statistics, the gouge check, the arc fitter and the preview. (`gcode::motion`
//! keeps its own: it follows GRBL's firmware, whose full-circle test differs.)

use super::Vec2;
use std::f64::consts::TAU;

/// Sweep (radians) of the arc from `a` to `b` about `c`, turning
/// counter-clockwise when `ccw`: in (0, 2π], and a whole turn when the two
/// ends lie at the same angle (to 1e-12 rad), as G-code reads equal ends.
pub fn sweep(a: Vec2, b: Vec2, c: Vec2, ccw: bool) -> f64 {
    let a0 = (a.y - c.y).atan2(a.x - c.x);
    let a1 = (b.y - c.y).atan2(b.x - c.x);
    let mut s = if ccw { a1 - a0 } else { a0 - a1 };
    if s <= 1e-12 {
        s += TAU;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    #[test]
    fn quarter_turns_both_ways_and_a_whole_turn_for_equal_ends() {
        let c = Vec2::new(1.0, 2.0);
        let (a, b) = (Vec2::new(2.0, 2.0), Vec2::new(1.0, 3.0));
        assert!((sweep(a, b, c, true) - FRAC_PI_2).abs() < 1e-15);
        assert!((sweep(a, b, c, false) - 3.0 * FRAC_PI_2).abs() < 1e-15);
        assert_eq!(sweep(a, a, c, true), TAU);
        assert_eq!(sweep(a, a, c, false), TAU);
        // Across the ±π cut of atan2.
        let (p, q) = (Vec2::new(0.0, 2.0 + 1e-9), Vec2::new(0.0, 2.0 - 1e-9));
        assert!((sweep(p, q, c, true) - 2e-9).abs() < 1e-12);
        assert!((sweep(q, p, c, true) - (TAU - 2e-9)).abs() < 1e-9);
        assert!((sweep(p, q, c, false) - (TAU - 2e-9)).abs() < 1e-9);
        assert!(sweep(p, q, c, false) > PI);
    }
}
