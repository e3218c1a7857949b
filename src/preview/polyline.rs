//! The tool path as XY polylines for drawing: feed moves joined into tracks,
//! arcs flattened into chords, and points spaced evenly along a track.

use crate::geometry::{arc, Vec2};
use crate::toolpath::{Move, Vec3};

/// XY polylines of a level's feed moves (arcs flattened within `tol`); plunges
/// add no length and so no vertex.
pub(super) fn level_polylines(moves: &[(Vec3, Move)], tol: f64) -> Vec<Vec<Vec2>> {
    let mut out: Vec<Vec<Vec2>> = Vec::new();
    for (from, m) in moves {
        let a = from.xy();
        let continues = out
            .last()
            .and_then(|pl| pl.last())
            .is_some_and(|&last| last.dist(a) < 1e-9);
        if !continues {
            out.push(vec![a]);
        }
        let pts = match *m {
            Move::Arc {
                to, cx, cy, ccw, ..
            } => arc::flatten(a, to.xy(), Vec2::new(cx, cy), ccw, tol),
            _ => vec![m.to().xy()],
        };
        if let Some(pl) = out.last_mut() {
            for p in pts {
                if pl.last().is_none_or(|&q| q.dist(p) >= 1e-9) {
                    pl.push(p);
                }
            }
        }
    }
    out.retain(|pl| pl.len() >= 2);
    out
}

/// Length of a polyline, mm.
pub(super) fn polyline_length(pl: &[Vec2]) -> f64 {
    pl.windows(2).map(|w| w[0].dist(w[1])).sum()
}

/// Points and unit tangents at `count` evenly spaced arc lengths along `pl`.
pub(super) fn along(pl: &[Vec2], count: usize) -> Vec<(Vec2, Vec2)> {
    let len = polyline_length(pl);
    let mut out = Vec::new();
    if len <= 0.0 || count == 0 {
        return out;
    }
    let mut targets = (0..count)
        .map(|k| (k as f64 + 0.5) * len / count as f64)
        .peekable();
    let mut acc = 0.0;
    for w in pl.windows(2) {
        let l = w[0].dist(w[1]);
        while let Some(&t) = targets.peek() {
            if t > acc + l || l <= 0.0 {
                break;
            }
            let f = (t - acc) / l;
            out.push((w[0].lerp(w[1], f), (w[1] - w[0]) / l));
            targets.next();
        }
        acc += l;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arcs_in_a_level_are_drawn_at_their_length() {
        use crate::report::feed_length_time;
        use crate::toolpath::{Section, Toolpath};
        // Plunge at (5, 0), a full circle about the origin, then a half circle back.
        let from = Vec3::new(5.0, 0.0, 1.0);
        let moves = vec![
            Move::Linear {
                to: Vec3::new(5.0, 0.0, -1.0),
                feed: 100.0,
            },
            Move::Arc {
                to: Vec3::new(5.0, 0.0, -1.0),
                cx: 0.0,
                cy: 0.0,
                ccw: true,
                feed: 600.0,
            },
            Move::Arc {
                to: Vec3::new(-5.0, 0.0, -1.0),
                cx: 0.0,
                cy: 0.0,
                ccw: false,
                feed: 600.0,
            },
        ];
        let tp = Toolpath {
            start: from,
            sections: vec![Section {
                label: "circle".into(),
                z: -1.0,
                moves,
            }],
        };
        let lv = crate::report::split_levels(&tp);
        assert_eq!(lv.len(), 1);
        let pls = level_polylines(&lv[0].moves, 0.001);
        assert_eq!(pls.len(), 1, "one continuous track");
        let drawn: f64 = pls[0].windows(2).map(|w| w[0].dist(w[1])).sum();
        let fed: f64 = lv[0]
            .moves
            .iter()
            .map(|(f, m)| feed_length_time(*f, m).0)
            .sum();
        let exact = 1.5 * std::f64::consts::TAU * 5.0;
        assert!((fed - 2.0 - exact).abs() < 1e-9, "{fed}");
        assert!((drawn - exact).abs() < 1e-3 * exact, "{drawn}");
        // Clockwise half circle from (5, 0) passes below the centre.
        assert!(pls[0].iter().any(|p| p.y < -4.9));
    }
}
