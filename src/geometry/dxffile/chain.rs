//! Open polylines chained into closed contours: a piece whose end lies within
//! the join tolerance of another piece's end continues with that piece
//! (reversed when it is the other's end, not its start), until the chain comes
//! back within the tolerance of where it started.
//!
//! Ends are found through a hash grid of cells the size of the tolerance, so
//! each lookup reads 9 cells: linear in the number of pieces.

use std::collections::HashMap;

use super::super::Vec2;

/// A chain that did not close: where it starts and where it ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct OpenChain {
    /// its first point
    pub(crate) start: Vec2,
    /// its last point
    pub(crate) end: Vec2,
}

/// The closed loops the pieces make (each without its repeated last point),
/// and the chains that stay open, each grown from both its ends. Where several
/// ends lie within `tol` of a chain's end, closing the chain comes first, then
/// the nearest end.
pub(crate) fn chain(pieces: Vec<Vec<Vec2>>, tol: f64) -> (Vec<Vec<Vec2>>, Vec<OpenChain>) {
    let mut grid = Grid::new(tol);
    let mut loops = Vec::new();
    let mut open = Vec::new();
    let mut pieces: Vec<Option<Vec<Vec2>>> = pieces.into_iter().map(Some).collect();
    for (i, p) in pieces.iter().enumerate() {
        if let Some(p) = p.as_ref().filter(|p| p.len() >= 2) {
            grid.insert(p[0], i, false);
            grid.insert(p[p.len() - 1], i, true);
        }
    }
    for i in 0..pieces.len() {
        let Some(mut cur) = pieces[i].take().filter(|p| p.len() >= 2) else {
            continue;
        };
        grid.remove(i, &cur);
        let mut turned = false;
        loop {
            let (start, end) = (cur[0], cur[cur.len() - 1]);
            if cur.len() > 2 && start.dist(end) <= tol {
                if start == end {
                    cur.pop();
                }
                loops.push(cur);
                break;
            }
            let Some((j, at_end)) = grid.nearest(end) else {
                if turned {
                    open.push(OpenChain { start, end });
                    break;
                }
                // Nothing goes on from this end: go on from the other.
                cur.reverse();
                turned = true;
                continue;
            };
            let Some(mut next) = pieces[j].take() else {
                break; // not reached: the grid holds only unused pieces
            };
            grid.remove(j, &next);
            if at_end {
                next.reverse();
            }
            let skip = usize::from(next[0] == end);
            cur.extend_from_slice(&next[skip..]);
        }
    }
    (loops, open)
}

/// An end of a piece: the point, the piece, whether it is the piece's last point.
type End = (Vec2, usize, bool);

/// Ends of unused pieces by cell.
struct Grid {
    tol: f64,
    cells: HashMap<(i64, i64), Vec<End>>,
}

impl Grid {
    fn new(tol: f64) -> Grid {
        Grid {
            tol,
            cells: HashMap::new(),
        }
    }

    /// The cell of p (coordinates past ±2⁶² cells share the border cells).
    fn cell(&self, p: Vec2) -> (i64, i64) {
        let c = |v: f64| (v / self.tol).floor().clamp(-4.6e18, 4.6e18) as i64;
        (c(p.x), c(p.y))
    }

    fn insert(&mut self, p: Vec2, piece: usize, at_end: bool) {
        self.cells
            .entry(self.cell(p))
            .or_default()
            .push((p, piece, at_end));
    }

    /// Forget both ends of `piece`, whose points are `pts`.
    fn remove(&mut self, piece: usize, pts: &[Vec2]) {
        for p in [pts[0], pts[pts.len() - 1]] {
            let key = self.cell(p);
            if let Some(v) = self.cells.get_mut(&key) {
                v.retain(|e| e.1 != piece);
            }
        }
    }

    /// The nearest end within the tolerance of p: (piece, whether its end).
    fn nearest(&self, p: Vec2) -> Option<(usize, bool)> {
        let (cx, cy) = self.cell(p);
        let mut best: Option<(f64, usize, bool)> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                let key = (cx.saturating_add(dx), cy.saturating_add(dy));
                for &(q, i, e) in self.cells.get(&key).into_iter().flatten() {
                    let d = q.dist(p);
                    if d <= self.tol && best.is_none_or(|b| d < b.0) {
                        best = Some((d, i, e));
                    }
                }
            }
        }
        best.map(|(_, i, e)| (i, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    #[test]
    fn scrambled_lines_make_one_square_and_gaps_past_the_tolerance_stay_open() {
        let pieces = vec![
            vec![v(1.0, 0.0), v(1.0, 1.0)],
            vec![v(0.0, 1.0), v(0.0, 0.0)],
            vec![v(1.0, 1.0), v(0.0, 1.0)],
            vec![v(1.004, 0.0), v(0.0, 0.0)], // reversed, 0.004 off
        ];
        let (loops, open) = chain(pieces.clone(), 0.01);
        assert!(open.is_empty());
        assert_eq!(loops.len(), 1);
        let area: f64 = {
            let l = &loops[0];
            (0..l.len())
                .map(|i| l[i].cross(l[(i + 1) % l.len()]))
                .sum::<f64>()
                / 2.0
        };
        assert!((area.abs() - 1.0).abs() < 1e-12, "{area}");
        let (loops, open) = chain(pieces, 0.001);
        assert!(loops.is_empty());
        assert_eq!(open.len(), 1);
        let o = open[0];
        // The one chain runs between the two ends 0.004 apart.
        assert!((o.start.dist(o.end) - 0.004).abs() < 1e-12, "{o:?}");
    }
}
