//! Links through the air beside the stock.
//!
//! A tool whose axis is outside the stock rectangle grown by its radius
//! touches nothing, whatever its depth. A boss level's clearing rings leave
//! the stock and come back (their runs start and end out there), so the tool
//! can go from the end of one run to the start of the next at depth, around
//! the stock, instead of retracting, rapiding over and coming down again.
//! The route runs along the rectangle grown by a further [`AIR_MARGIN`].

use crate::geometry::Vec2;

/// How far outside the grown rectangle a route around it keeps, mm.
pub(crate) const AIR_MARGIN: f64 = 0.5;

/// An axis-aligned rectangle the tool's axis must stay out of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Keepout {
    /// Lower-left corner.
    pub(crate) lo: Vec2,
    /// Upper-right corner.
    pub(crate) hi: Vec2,
}

impl Keepout {
    /// The stock `[lo, hi]` grown by the tool radius `r`.
    pub(crate) fn around_stock(lo: Vec2, hi: Vec2, r: f64) -> Keepout {
        let g = Vec2::new(r, r);
        Keepout {
            lo: lo - g,
            hi: hi + g,
        }
    }

    /// Whether `p` is strictly outside.
    pub(crate) fn clear(&self, p: Vec2) -> bool {
        p.x < self.lo.x || p.x > self.hi.x || p.y < self.lo.y || p.y > self.hi.y
    }

    fn grown(&self, m: f64) -> Keepout {
        let g = Vec2::new(m, m);
        Keepout {
            lo: self.lo - g,
            hi: self.hi + g,
        }
    }

    fn perimeter(&self) -> f64 {
        2.0 * ((self.hi.x - self.lo.x) + (self.hi.y - self.lo.y))
    }

    /// The corners counter-clockwise from `lo`, with their perimeter
    /// coordinates.
    fn corners(&self) -> [(f64, Vec2); 4] {
        let (w, h) = (self.hi.x - self.lo.x, self.hi.y - self.lo.y);
        [
            (0.0, self.lo),
            (w, Vec2::new(self.hi.x, self.lo.y)),
            (w + h, self.hi),
            (2.0 * w + h, Vec2::new(self.lo.x, self.hi.y)),
        ]
    }

    /// The point of the boundary nearest `p`, and its perimeter coordinate
    /// (counter-clockwise from `lo`).
    fn boundary_point(&self, p: Vec2) -> (Vec2, f64) {
        let (lo, hi) = (self.lo, self.hi);
        let (w, h) = (hi.x - lo.x, hi.y - lo.y);
        let q = if self.clear(p) {
            Vec2::new(p.x.clamp(lo.x, hi.x), p.y.clamp(lo.y, hi.y))
        } else {
            // Inside: the nearest edge.
            let d = [p.y - lo.y, hi.x - p.x, hi.y - p.y, p.x - lo.x];
            let k = (0..4).min_by(|&a, &b| d[a].total_cmp(&d[b])).unwrap_or(0);
            match k {
                0 => Vec2::new(p.x, lo.y),
                1 => Vec2::new(hi.x, p.y),
                2 => Vec2::new(p.x, hi.y),
                _ => Vec2::new(lo.x, p.y),
            }
        };
        let t = if q.y <= lo.y {
            q.x - lo.x
        } else if q.x >= hi.x {
            w + (q.y - lo.y)
        } else if q.y >= hi.y {
            w + h + (hi.x - q.x)
        } else {
            2.0 * w + h + (hi.y - q.y)
        };
        (q, t)
    }

    /// The route from `a` to `b`, both clear, around the rectangle grown by
    /// [`AIR_MARGIN`], the shorter way: the points after `a`, ending at `b`.
    /// Every segment stays clear: from a point outside a convex set to its
    /// nearest boundary point of a larger one, then along that boundary.
    pub(crate) fn route(&self, a: Vec2, b: Vec2) -> Vec<Vec2> {
        let ring = self.grown(AIR_MARGIN);
        let (qa, ta) = ring.boundary_point(a);
        let (qb, tb) = ring.boundary_point(b);
        let per = ring.perimeter();
        let ccw = (tb - ta).rem_euclid(per);
        // The walk's distance to a perimeter coordinate, the shorter way.
        let forward = ccw <= per - ccw;
        let along = |t: f64| {
            if forward {
                (t - ta).rem_euclid(per)
            } else {
                (ta - t).rem_euclid(per)
            }
        };
        let walk = if forward { ccw } else { per - ccw };
        let mut turns: Vec<(f64, Vec2)> = ring
            .corners()
            .into_iter()
            .map(|(tc, c)| (along(tc), c))
            .filter(|&(d, _)| d > 0.0 && d < walk)
            .collect();
        turns.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut out = vec![qa];
        out.extend(turns.into_iter().map(|(_, c)| c));
        out.push(qb);
        out.push(b);
        out.dedup_by(|p, q| p.dist(*q) < 1e-12);
        out
    }

    /// Length of [`route`](Self::route) from `a`.
    pub(crate) fn route_length(&self, a: Vec2, b: Vec2) -> f64 {
        let mut at = a;
        let mut len = 0.0;
        for q in self.route(a, b) {
            len += at.dist(q);
            at = q;
        }
        len
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stock() -> Keepout {
        Keepout::around_stock(Vec2::new(0.0, 0.0), Vec2::new(100.0, 50.0), 2.0)
    }

    fn stays_clear(k: &Keepout, a: Vec2, route: &[Vec2]) {
        let mut at = a;
        for &q in route {
            for i in 0..=100 {
                let p = at + (q - at) * (i as f64 / 100.0);
                assert!(
                    k.clear(p),
                    "{p:?} on the way {at:?} -> {q:?} is over the stock"
                );
            }
            at = q;
        }
    }

    #[test]
    fn a_route_round_a_corner_turns_it_and_stays_clear() {
        let k = stock();
        let (a, b) = (Vec2::new(103.0, 10.0), Vec2::new(90.0, 53.0));
        let r = k.route(a, b);
        stays_clear(&k, a, &r);
        assert_eq!(*r.last().unwrap(), b);
        // Up the right side to the corner (102.5, 52.5), then left: 43.5 + 13.
        let len = k.route_length(a, b);
        assert!((len - (0.5 + 42.5 + 12.5 + 0.5)).abs() < 1e-9, "{len}");
    }

    #[test]
    fn a_route_takes_the_shorter_way_in_either_direction() {
        let k = stock();
        let (a, b) = (Vec2::new(103.0, 25.0), Vec2::new(-3.0, 25.0));
        let ab = k.route_length(a, b);
        let ba = k.route_length(b, a);
        assert!((ab - ba).abs() < 1e-9);
        // Round either end: 0.5 + 27.5 + 105 + 27.5 + 0.5.
        assert!((ab - 161.0).abs() < 1e-9, "{ab}");
        stays_clear(&k, a, &k.route(a, b));
        stays_clear(&k, b, &k.route(b, a));
    }

    #[test]
    fn neighbours_on_one_side_go_straight_along_it() {
        let k = stock();
        let (a, b) = (Vec2::new(20.0, -2.5), Vec2::new(30.0, -2.2));
        let r = k.route(a, b);
        stays_clear(&k, a, &r);
        assert_eq!(r.len(), 3, "{r:?}");
        assert!((k.route_length(a, b) - (0.0 + 10.0 + 0.3)).abs() < 1e-9);
    }
}
