//! What one accepted block moves: its motion mode and, for `G2`/`G3`, the arc as
//! GRBL constructs it. Shared by `pfcam check` (lengths and bounds) and
//! `pfcam simulate` (the swept material), so both read arcs the same way.

use super::parse::{ModalState, Motion, Units, Word};
use std::f64::consts::{FRAC_PI_2, TAU};

const MM_PER_INCH: f64 = 25.4;

/// The G codes of a block, ×10 (`G38.2` → 382).
pub fn gcodes(words: &[Word]) -> Vec<u32> {
    words
        .iter()
        .filter(|w| w.letter == 'G')
        .map(|w| (w.value * 10.0).round() as u32)
        .collect()
}

/// Whether the block uses its axis words for something other than a programmed
/// move (G10, G28, G30, G53, G92 and their .1 forms, G43.1, G49): no move to
/// measure or simulate.
pub fn is_axis_command(gcodes: &[u32]) -> bool {
    gcodes
        .iter()
        .any(|g| matches!(g, 100 | 280 | 281 | 300 | 301 | 431 | 490 | 530 | 920 | 921))
}

/// The motion-group G code the block names (`G0`, `G1`, `G2`, `G3`, `G38.x`,
/// `G80`), ×10, if any.
pub fn explicit_motion(gcodes: &[u32]) -> Option<u32> {
    gcodes
        .iter()
        .copied()
        .find(|g| matches!(g, 0 | 10 | 20 | 30 | 382..=385 | 800))
}

/// The motion a block GRBL accepted performs with its axis words: the one it
/// names, else the modal one in force `before` it; `None` when the block has
/// no axis words or uses them for an axis command ([`is_axis_command`]).
pub fn block_motion(words: &[Word], before: &ModalState) -> Option<Motion> {
    let codes = gcodes(words);
    let has_axes = words.iter().any(|w| matches!(w.letter, 'X' | 'Y' | 'Z'));
    if !has_axes || is_axis_command(&codes) {
        return None;
    }
    Some(match explicit_motion(&codes) {
        Some(0) => Motion::Rapid,
        Some(10) => Motion::Linear,
        Some(20) => Motion::ArcCw,
        Some(30) => Motion::ArcCcw,
        Some(800) => Motion::None,
        Some(p) => Motion::Probe(p as u16),
        None => before.motion,
    })
}

/// The arc of a `G2`/`G3` block from `from` to `to` (mm, both fully known in the
/// arc's plane), in the plane of `after` (the state after the block), with the
/// block's R or offset words in its program units. Returns the arc and the
/// indices of its plane's two axes ([`super::parse::Plane::axes`]).
pub fn block_arc(
    words: &[Word],
    after: &ModalState,
    from: [f64; 2],
    to: [f64; 2],
    ccw: bool,
) -> (Arc, [usize; 2]) {
    let value = |c: char| words.iter().find(|w| w.letter == c).map(|w| w.value);
    let scale = if after.units == Units::Inch {
        MM_PER_INCH
    } else {
        1.0
    };
    let axes = after.plane.axes();
    let offsets = match axes[0] {
        0 => ['I', 'J'],
        2 => ['K', 'I'],
        _ => ['J', 'K'],
    };
    let arc = Arc::new(
        from,
        to,
        value('R').map(|r| r * scale),
        [
            value(offsets[0]).unwrap_or(0.0) * scale,
            value(offsets[1]).unwrap_or(0.0) * scale,
        ],
        ccw,
    );
    (arc, axes)
}

/// A circular arc in its plane's (first axis, second axis) coordinates, mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    /// Centre.
    pub centre: [f64; 2],
    /// Radius (the distance from the centre to the start).
    pub r: f64,
    /// Start angle, rad.
    pub a0: f64,
    /// Angle travelled, rad, in (0, 2π]; a start equal to the end is a full circle.
    pub sweep: f64,
    /// Counter-clockwise (G3) in the plane's axes.
    pub ccw: bool,
}

impl Arc {
    /// From start `s`, end `t`, and either a radius `r` (negative: the long way
    /// round, as in GRBL) or the centre's `offset` from the start.
    pub fn new(s: [f64; 2], t: [f64; 2], r: Option<f64>, offset: [f64; 2], ccw: bool) -> Arc {
        let centre = match r {
            Some(r) => {
                // GRBL's construction: the centre is on the perpendicular
                // bisector of start-end, on the side that makes the arc short for
                // R > 0 and long for R < 0.
                let (x, y) = (t[0] - s[0], t[1] - s[1]);
                let d = x.hypot(y);
                let mut h = -(4.0 * r * r - x * x - y * y).max(0.0).sqrt() / d;
                if ccw {
                    h = -h;
                }
                if r < 0.0 {
                    h = -h;
                }
                [s[0] + 0.5 * (x - y * h), s[1] + 0.5 * (y + x * h)]
            }
            None => [s[0] + offset[0], s[1] + offset[1]],
        };
        let r = (s[0] - centre[0]).hypot(s[1] - centre[1]);
        let a0 = (s[1] - centre[1]).atan2(s[0] - centre[0]);
        let a1 = (t[1] - centre[1]).atan2(t[0] - centre[0]);
        let mut sweep = if ccw { a1 - a0 } else { a0 - a1 }.rem_euclid(TAU);
        // GRBL's own rule for a full circle: end and start the same (to its float
        // precision), so a sweep of almost nothing is a whole turn.
        if sweep <= 1e-9 {
            sweep += TAU;
        }
        Arc {
            centre,
            r,
            a0,
            sweep,
            ccw,
        }
    }

    /// The point at fraction `f` ∈ [0, 1] of the sweep: angle a0 ± f·sweep.
    pub fn point(&self, f: f64) -> [f64; 2] {
        let a = if self.ccw {
            self.a0 + f * self.sweep
        } else {
            self.a0 - f * self.sweep
        };
        let (s, c) = a.sin_cos();
        [self.centre[0] + self.r * c, self.centre[1] + self.r * s]
    }

    /// How many equal chords keep every chord within `tol` mm of the arc: a chord
    /// spanning angle φ deviates by the sagitta r(1 − cos(φ/2)), so
    /// φ ≤ 2·acos(1 − tol/r). At least 1, at most `max`.
    pub fn chords(&self, tol: f64, max: usize) -> usize {
        if !(self.r > tol && tol > 0.0) {
            return 1;
        }
        let phi = 2.0 * (1.0 - tol / self.r).acos();
        let n = (self.sweep / phi).ceil();
        if n.is_finite() {
            (n as usize).clamp(1, max.max(1))
        } else {
            1
        }
    }

    /// The points where the arc crosses the quadrant angles (0, 90°, 180°, 270°),
    /// which with its ends bound it.
    pub fn extremes(&self) -> Vec<[f64; 2]> {
        (0..4)
            .filter_map(|k| {
                let a = k as f64 * FRAC_PI_2;
                let d = if self.ccw { a - self.a0 } else { self.a0 - a }.rem_euclid(TAU);
                (d <= self.sweep).then(|| {
                    let (s, c) = a.sin_cos();
                    [self.centre[0] + self.r * c, self.centre[1] + self.r * s]
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chords_stay_within_the_tolerance() {
        let a = Arc::new([0.0, 0.0], [10.0, 0.0], None, [5.0, 0.0], false);
        let n = a.chords(0.001, 100_000);
        let phi = a.sweep / n as f64;
        assert!(a.r * (1.0 - (phi / 2.0).cos()) <= 0.001 + 1e-12);
        // One chord fewer would not do.
        let phi = a.sweep / (n - 1) as f64;
        assert!(a.r * (1.0 - (phi / 2.0).cos()) > 0.001);
        assert_eq!(a.chords(0.001, 7), 7);
        let end = a.point(1.0);
        assert!((end[0] - 10.0).abs() < 1e-12 && end[1].abs() < 1e-12);
        // G2 (clockwise) from the left of the centre goes over the top.
        assert!(a.point(0.5)[1] > 4.999);
    }
}
