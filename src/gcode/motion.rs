//! What one accepted block moves: its motion mode and, for `G2`/`G3`, the arc as
//! GRBL constructs it. Shared by `pfcam check` (lengths and bounds) and
//! `pfcam simulate` (the swept material), so both read arcs the same way.

use super::parse::{ModalState, Motion, Units, Word};
use crate::geometry::{arc, Vec2};

const MM_PER_INCH: f64 = 25.4;

/// The G codes of a block, ×10 (`G38.2` → 382).
pub(crate) fn gcodes(words: &[Word]) -> Vec<u32> {
    words
        .iter()
        .filter(|w| w.letter == 'G')
        .map(|w| (w.value * 10.0).round() as u32)
        .collect()
}

/// Whether the block uses its axis words for something other than a programmed
/// move (G10, G28, G30, G53, G92 and their .1 forms, G43.1, G49): no move to
/// measure or simulate.
pub(crate) fn is_axis_command(gcodes: &[u32]) -> bool {
    gcodes
        .iter()
        .any(|g| matches!(g, 100 | 280 | 281 | 300 | 301 | 431 | 490 | 530 | 920 | 921))
}

/// The motion-group G code the block names (`G0`, `G1`, `G2`, `G3`, `G38.x`,
/// `G80`), ×10, if any.
pub(crate) fn explicit_motion(gcodes: &[u32]) -> Option<u32> {
    gcodes
        .iter()
        .copied()
        .find(|g| matches!(g, 0 | 10 | 20 | 30 | 382..=385 | 800))
}

/// The motion a block GRBL accepted performs with its axis words: the one it
/// names, else the modal one in force `before` it; `None` when the block has
/// no axis words or uses them for an axis command ([`is_axis_command`]).
pub(crate) fn block_motion(words: &[Word], before: &ModalState) -> Option<Motion> {
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
pub(crate) fn block_arc(
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
pub(crate) struct Arc {
    /// Centre.
    pub(crate) centre: [f64; 2],
    /// Radius (the distance from the centre to the start).
    pub(crate) r: f64,
    /// Start angle, rad.
    pub(crate) a0: f64,
    /// Angle travelled, rad, in (0, 2π]; a start equal to the end is a full circle
    /// ([`arc::sweep_between`]).
    pub(crate) sweep: f64,
    /// Counter-clockwise (G3) in the plane's axes.
    pub(crate) ccw: bool,
}

impl Arc {
    /// From start `s`, end `t`, and either a radius `r` (negative: the long way
    /// round, as in GRBL) or the centre's `offset` from the start.
    pub(crate) fn new(
        s: [f64; 2],
        t: [f64; 2],
        r: Option<f64>,
        offset: [f64; 2],
        ccw: bool,
    ) -> Arc {
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
        let (s, t, c) = (
            Vec2::new(s[0], s[1]),
            Vec2::new(t[0], t[1]),
            Vec2::new(centre[0], centre[1]),
        );
        let (r, a0) = (arc::radius(s, c), arc::angle(s, c));
        let sweep = arc::sweep(s, t, c, ccw);
        Arc {
            centre,
            r,
            a0,
            sweep,
            ccw,
        }
    }

    /// Length of the arc while the third axis moves `rise`: the helix's
    /// ([`arc::helix_length`]).
    pub(crate) fn length(&self, rise: f64) -> f64 {
        arc::helix_length(self.r, self.sweep, rise)
    }

    /// How many equal chords keep every chord within `tol` mm of the arc
    /// ([`arc::chords`]).
    pub(crate) fn chords(&self, tol: f64) -> usize {
        arc::chords(self.r, self.sweep, tol)
    }

    /// The points where the arc crosses the quadrant angles (0, 90°, 180°, 270°),
    /// which with its ends bound it ([`arc::extremes`]).
    pub(crate) fn extremes(&self) -> Vec<[f64; 2]> {
        let c = Vec2::new(self.centre[0], self.centre[1]);
        arc::extremes(c, self.r, self.a0, self.sweep, self.ccw)
            .into_iter()
            .map(|p| [p.x, p.y])
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chords_stay_within_the_tolerance() {
        let a = Arc::new([0.0, 0.0], [10.0, 0.0], None, [5.0, 0.0], false);
        let n = a.chords(0.001);
        let phi = a.sweep / n as f64;
        assert!(a.r * (1.0 - (phi / 2.0).cos()) <= 0.001 + 1e-12);
        // One chord fewer would not do.
        let phi = a.sweep / (n - 1) as f64;
        assert!(a.r * (1.0 - (phi / 2.0).cos()) > 0.001);
        // G2 (clockwise) from the left of the centre goes over the top.
        assert!((a.sweep - std::f64::consts::PI).abs() < 1e-12);
        let top = a.extremes();
        assert_eq!(top.len(), 3);
        assert!(top.iter().any(|p| (p[1] - 5.0).abs() < 1e-12));
        assert!(top.iter().all(|p| p[1] >= -1e-12));
    }
}
