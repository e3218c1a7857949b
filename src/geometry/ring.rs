//! A closed polygon ("ring") and the maths of closed polygons: signed area,
//! perimeter, winding number.
//!
//! A [`Ring`] holds n ≥ 3 vertices p₀, …, pₙ₋₁, pairwise distinct as
//! neighbours (pᵢ ≠ pᵢ₊₁, with pₙ = p₀), at least three of them distinct, all
//! finite. The closing edge pₙ₋₁ → p₀ is implied: the first point is never
//! repeated at the end, so "is the first point repeated?" is answered once,
//! by [`Ring::new`], and every edge loop is [`Ring::edges`].
//!
//! - Signed area (shoelace): A = ½ Σᵢ pᵢ × pᵢ₊₁, positive counter-clockwise.
//!   It is unchanged when the start vertex is cycled and changes sign when the
//!   order is reversed.
//! - Perimeter: L = Σᵢ |pᵢ₊₁ − pᵢ|, unchanged by cycling and by reversal.
//! - Winding number of a point q: the signed count of edges crossing the ray
//!   from q to +x (upward crossings with q on the left count +1, downward ones
//!   with q on the right −1): the index (8.2) of the paper's Appendix I,
//!   exact for straight edges. q is inside where it is non-zero.
//!
//! The free functions take a slice under the same convention (first point not
//! repeated) for the polygons not yet held as rings; a `Ring` calls them.

use super::Vec2;

/// A closed polygon: at least three distinct finite vertices, neighbours
/// distinct, the first not repeated at the end (see the module's doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Ring {
    pts: Vec<Vec2>,
}

impl Ring {
    /// The ring through `pts` in order, with consecutive duplicates and a
    /// repeated closing point dropped; `None` when a coordinate is not finite
    /// or fewer than three distinct points remain.
    pub(crate) fn new(mut pts: Vec<Vec2>) -> Option<Ring> {
        if !pts.iter().all(|p| p.is_finite()) {
            return None;
        }
        pts.dedup();
        while pts.len() > 1 && pts.first() == pts.last() {
            pts.pop();
        }
        three_distinct(&pts).then_some(Ring { pts })
    }

    /// The vertices in order (the first not repeated).
    pub fn points(&self) -> &[Vec2] {
        &self.pts
    }

    /// The vertices, owned.
    pub fn into_points(self) -> Vec<Vec2> {
        self.pts
    }

    /// The number of vertices (and of edges).
    pub fn len(&self) -> usize {
        self.pts.len()
    }

    /// Never: a ring has at least three vertices (for clippy's `len` rule).
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Signed area, mm²: positive counter-clockwise.
    pub(crate) fn signed_area(&self) -> f64 {
        polygon_area(&self.pts)
    }

    /// Counter-clockwise (positive signed area).
    pub fn is_ccw(&self) -> bool {
        self.signed_area() > 0.0
    }

    /// The same ring traversed the other way: the vertices in reverse order,
    /// the last one first.
    pub(crate) fn reversed(&self) -> Ring {
        Ring {
            pts: self.pts.iter().rev().copied().collect(),
        }
    }

    /// The edges (pᵢ, pᵢ₊₁) in order, the closing edge (pₙ₋₁, p₀) last.
    pub fn edges(&self) -> impl ExactSizeIterator<Item = (Vec2, Vec2)> + '_ {
        edges(&self.pts)
    }

    /// The length of the closed boundary, mm.
    #[cfg(test)]
    pub(crate) fn perimeter(&self) -> f64 {
        closed_length(&self.pts)
    }

    /// The winding number of the ring about `p`.
    pub(crate) fn winding_number(&self, p: Vec2) -> i32 {
        polygon_winding_number(&self.pts, p)
    }

    /// Is `p` inside (winding number ≠ 0)?
    pub fn contains(&self, p: Vec2) -> bool {
        self.winding_number(p) != 0
    }
}

impl AsRef<[Vec2]> for Ring {
    fn as_ref(&self) -> &[Vec2] {
        &self.pts
    }
}

/// Does `pts` hold three pairwise distinct points?
fn three_distinct(pts: &[Vec2]) -> bool {
    let Some(&a) = pts.first() else {
        return false;
    };
    let Some(&b) = pts.iter().find(|&&p| p != a) else {
        return false;
    };
    pts.iter().any(|&p| p != a && p != b)
}

/// The edges of the closed polygon `p` (first point not repeated), the
/// closing edge last.
pub(crate) fn edges(p: &[Vec2]) -> impl ExactSizeIterator<Item = (Vec2, Vec2)> + '_ {
    let n = p.len();
    (0..n).map(move |i| (p[i], p[(i + 1) % n]))
}

/// Signed area of a closed polygon, first point not repeated (positive
/// counter-clockwise): the shoelace sum. The one definition; the z-levels, the
/// planner, compose and the sections all orient and drop loops by it.
pub fn polygon_area(p: &[Vec2]) -> f64 {
    edges(p).map(|(a, b)| a.cross(b)).sum::<f64>() / 2.0
}

/// Length of a closed polygon (first point not repeated), mm.
pub(crate) fn closed_length(p: &[Vec2]) -> f64 {
    edges(p).map(|(a, b)| a.dist(b)).sum()
}

/// Winding number of a closed polygon about `p` (the polygon's last vertex joins
/// its first). This is the index (8.2) of the paper's Appendix I, evaluated exactly
/// for straight edges by counting signed crossings of the ray to +x.
pub fn polygon_winding_number(poly: &[Vec2], p: Vec2) -> i32 {
    let mut w = 0;
    for (a, b) in edges(poly) {
        if a.y <= p.y {
            if b.y > p.y && (b - a).cross(p - a) > 0.0 {
                w += 1;
            }
        } else if b.y <= p.y && (b - a).cross(p - a) < 0.0 {
            w -= 1;
        }
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    /// An L of area 3 (a 2×2 square less a unit square), counter-clockwise.
    fn ell() -> Vec<Vec2> {
        vec![
            v(0.0, 0.0),
            v(2.0, 0.0),
            v(2.0, 1.0),
            v(1.0, 1.0),
            v(1.0, 2.0),
            v(0.0, 2.0),
        ]
    }

    fn cycled(pts: &[Vec2], k: usize) -> Ring {
        let mut p = pts.to_vec();
        p.rotate_left(k);
        Ring::new(p).unwrap()
    }

    #[test]
    fn new_drops_the_repeated_closing_point_and_consecutive_duplicates() {
        let mut pts = ell();
        pts.insert(3, pts[2]);
        pts.push(pts[0]);
        pts.push(pts[0]);
        let r = Ring::new(pts).unwrap();
        assert_eq!(r.points(), &ell()[..]);
        assert_eq!(r.len(), 6);
        assert_eq!(r.into_points(), ell());
    }

    #[test]
    fn new_refuses_fewer_than_three_distinct_points_and_non_finite_ones() {
        let (a, b) = (v(0.0, 0.0), v(1.0, 0.0));
        assert_eq!(Ring::new(vec![]), None);
        assert_eq!(Ring::new(vec![a, b, a]), None);
        assert_eq!(Ring::new(vec![a, b, a, b]), None);
        assert_eq!(Ring::new(vec![a, a, a, a]), None);
        assert!(Ring::new(vec![a, b, v(0.0, 1.0)]).is_some());
        let mut bad = ell();
        bad[4].x = f64::NAN;
        assert_eq!(Ring::new(bad), None);
        let mut far = ell();
        far[1].y = f64::INFINITY;
        assert_eq!(Ring::new(far), None);
    }

    #[test]
    fn area_is_invariant_under_cycling_and_changes_sign_under_reversal() {
        for k in 0..6 {
            let r = cycled(&ell(), k);
            assert_eq!(r.signed_area(), 3.0, "start {k}");
            assert!(r.is_ccw());
            let back = r.reversed();
            assert_eq!(back.signed_area(), -3.0);
            assert!(!back.is_ccw());
            assert_eq!(back.points()[0], r.points()[5]);
            assert_eq!(back.reversed(), r);
        }
    }

    #[test]
    fn edges_close_the_ring_and_chain_end_to_start() {
        let r = Ring::new(ell()).unwrap();
        let e: Vec<_> = r.edges().collect();
        assert_eq!(e.len(), 6);
        assert_eq!(e[5], (v(0.0, 2.0), v(0.0, 0.0)));
        for i in 0..6 {
            assert_eq!(e[i].1, e[(i + 1) % 6].0);
        }
    }

    #[test]
    fn perimeter_is_invariant_under_cycling_and_reversal() {
        for k in 0..6 {
            let r = cycled(&ell(), k);
            assert!((r.perimeter() - 8.0).abs() < 1e-12);
            assert!((r.reversed().perimeter() - 8.0).abs() < 1e-12);
        }
        let d = Ring::new(vec![v(0.0, 0.0), v(3.0, 0.0), v(0.0, 4.0)]).unwrap();
        assert!((d.perimeter() - 12.0).abs() < 1e-12);
    }

    #[test]
    fn contains_the_inside_of_the_ell_and_not_its_notch() {
        for k in 0..6 {
            let r = cycled(&ell(), k);
            for back in [false, true] {
                let r = if back { r.reversed() } else { r.clone() };
                let w = if back { -1 } else { 1 };
                assert_eq!(r.winding_number(v(0.5, 0.5)), w);
                assert_eq!(r.winding_number(v(1.5, 0.5)), w);
                assert_eq!(r.winding_number(v(0.5, 1.5)), w);
                assert!(r.contains(v(0.5, 1.5)));
                assert!(!r.contains(v(1.5, 1.5)), "the notch");
                assert!(!r.contains(v(3.0, 0.5)));
                assert!(!r.contains(v(-1.0, 1.0)));
            }
        }
    }

    #[test]
    fn slices_and_rings_agree() {
        let r = Ring::new(ell()).unwrap();
        assert_eq!(polygon_area(&ell()), r.signed_area());
        assert_eq!(closed_length(&ell()), r.perimeter());
        assert_eq!(polygon_winding_number(&ell(), v(0.5, 0.5)), 1);
        assert_eq!(polygon_area(&[]), 0.0);
    }
}
