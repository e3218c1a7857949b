//! The program as moves: every line GRBL would run goes through the same
//! modal-state tracker as `pfcam check` and the streamer
//! ([`crate::gcode::parse::ModalState`]); each block that moves from a known
//! position becomes a [`Move`], its arc built by
//! [`crate::gcode::motion::block_arc`] as GRBL constructs it.

use super::tool::Segment;
use crate::gcode::motion::{block_arc, block_motion, Arc};
use crate::gcode::parse::{tokenize, ModalState, Motion, Program};
use crate::geometry::{arc, Vec2};

/// One move of the tool tip, mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Move {
    /// 1-based line number in the file.
    pub(crate) line: usize,
    /// `G0`.
    pub(crate) rapid: bool,
    /// Start.
    pub(crate) from: [f64; 3],
    /// End.
    pub(crate) to: [f64; 3],
    /// For `G2`/`G3`: the arc in its plane and the plane's axes.
    pub(crate) arc: Option<(Arc, [usize; 2])>,
}

impl Move {
    /// The move as straight pieces: itself for a line; for an arc, equal chords
    /// within `tol` mm of it ([`crate::geometry::arc::chords`]) with the third axis linear in the
    /// angle (a helix), the last point exactly the programmed end.
    pub(crate) fn pieces(&self, tol: f64) -> Vec<Segment> {
        let Some((arc, [a0, a1])) = self.arc else {
            return vec![Segment {
                a: self.from,
                b: self.to,
            }];
        };
        let lin = 3 - a0 - a1;
        // At most arc::MAX_CHORDS: a bound on the work of one line (a 1 m radius
        // full circle at 1 µm tolerance needs about 2200).
        let n = arc.chords(tol);
        let plane = |p: [f64; 3]| Vec2::new(p[a0], p[a1]);
        let c = Vec2::new(arc.centre[0], arc.centre[1]);
        let ends = arc::divide(plane(self.from), plane(self.to), c, arc.ccw, n);
        let mut pts = Vec::with_capacity(n + 1);
        pts.push(self.from);
        for (k, q) in ends.into_iter().enumerate() {
            let p = if k + 1 == n {
                self.to
            } else {
                let f = (k + 1) as f64 / n as f64;
                let mut p = [0.0; 3];
                p[a0] = q.x;
                p[a1] = q.y;
                p[lin] = self.from[lin] + f * (self.to[lin] - self.from[lin]);
                p
            };
            pts.push(p);
        }
        pts.windows(2)
            .map(|w| Segment { a: w[0], b: w[1] })
            .collect()
    }
}

/// The moves of a program, and what could not be simulated.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Moves {
    /// Moves from a known position, in program order.
    pub(crate) moves: Vec<Move>,
    /// Moves that start where the position is not known (the first `G0 Z`, or
    /// after `G28`/`G30`/`G53`): not simulated.
    pub(crate) unknown_start: usize,
    /// Lines GRBL would reject (they do not run): (line, GRBL's message).
    pub(crate) rejected: Vec<(usize, String)>,
}

/// Reads a program's moves (see the module docs).
pub(crate) fn read_moves(text: &str) -> Moves {
    let mut out = Moves::default();
    let mut state = ModalState::default();
    for line in Program::parse(text).blocks() {
        if line.block.starts_with('$') {
            continue;
        }
        let before = state.clone();
        if let Err(e) = state.execute(&line.block) {
            out.rejected.push((line.number, e.to_string()));
            continue;
        }
        let Ok(words) = tokenize(&line.block) else {
            continue;
        };
        let Some(motion) = block_motion(&words, &before) else {
            continue;
        };
        let known = |p: [Option<f64>; 3]| -> Option<[f64; 3]> { Some([p[0]?, p[1]?, p[2]?]) };
        let (Some(from), Some(to)) = (known(before.position), known(state.position)) else {
            if motion != Motion::None {
                out.unknown_start += 1;
            }
            continue;
        };
        let arc = match motion {
            Motion::None => continue,
            Motion::Rapid | Motion::Linear | Motion::Probe(_) => None,
            Motion::ArcCw | Motion::ArcCcw => {
                let [a0, a1] = state.plane.axes();
                let ccw = motion == Motion::ArcCcw;
                Some(block_arc(
                    &words,
                    &state,
                    [from[a0], from[a1]],
                    [to[a0], to[a1]],
                    ccw,
                ))
            }
        };
        out.moves.push(Move {
            line: line.number,
            rapid: motion == Motion::Rapid,
            from,
            to,
            arc,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_lines_arcs_and_unknown_starts() {
        let m = read_moves("G21 G90\nG0 Z5\nG0 X0 Y0\nG1 Z-1 F100\nG2 X10 Y0 I5 J0\nG41\nM2\n");
        assert_eq!(m.unknown_start, 2, "G0 Z5 and G0 X0 Y0 start unknown");
        assert_eq!(m.moves.len(), 2);
        assert_eq!(m.moves[0].line, 4);
        assert!(!m.moves[0].rapid);
        assert_eq!(m.rejected.len(), 1);
        assert_eq!(m.rejected[0].0, 6);
        let arc = m.moves[1];
        let pieces = arc.pieces(0.001);
        assert!(pieces.len() > 10);
        assert_eq!(pieces.last().map(|s| s.b), Some([10.0, 0.0, -1.0]));
        // Every chord point is on the circle of radius 5 about (5, 0).
        for s in &pieces {
            assert!(((s.a[0] - 5.0).hypot(s.a[1]) - 5.0).abs() < 1e-9);
            assert!(s.a[1] >= -1e-9, "G2 from the left goes over the top");
        }
    }

    #[test]
    fn helical_arcs_descend_linearly() {
        let m = read_moves("G0 X0 Y0 Z0\nG3 X0 Y0 Z-2 I5 J0 F100\n");
        let p = m.moves[0].pieces(0.01);
        let n = p.len() as f64;
        for (k, s) in p.iter().enumerate() {
            assert!((s.b[2] + 2.0 * (k + 1) as f64 / n).abs() < 1e-9);
        }
    }
}
