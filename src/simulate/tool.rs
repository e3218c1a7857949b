//! The flat end mill's sweep along a straight segment: for every cell centre
//! the tool's axis passes within radius r of, the lowest z of the tool's flat
//! bottom over it.
//!
//! The segment runs from a = (ax, ay, az) to b; its XY part is
//! p(t) = a + t·d, d = b − a, t ∈ [0, 1], and z(t) = az + t·(bz − az). A cell
//! centre c is under the tool while |p(t) − c|² ≤ r², i.e. while
//! A t² + B t + C ≤ 0 with A = d·d, B = 2 (a − c)·d, C = |a − c|² − r²: an
//! interval [t₁, t₂] ∩ [0, 1] (exact, from the quadratic). z is linear in t, so
//! the lowest bottom over the cell is min(z(t₁), z(t₂)).

/// A straight move of the tool's tip (the centre of its flat bottom), mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Start (x, y, z).
    pub a: [f64; 3],
    /// End (x, y, z).
    pub b: [f64; 3],
}

impl Segment {
    /// The XY length, mm.
    pub fn xy_len(&self) -> f64 {
        let (dx, dy) = (self.b[0] - self.a[0], self.b[1] - self.a[1]);
        (dx * dx + dy * dy).sqrt()
    }

    /// The 3-D length, mm.
    pub fn len(&self) -> f64 {
        let d = [0, 1, 2].map(|k| self.b[k] - self.a[k]);
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
    }

    /// The lower of the two end heights, mm.
    pub fn z_min(&self) -> f64 {
        self.a[2].min(self.b[2])
    }

    /// The x-interval of the points at height `y` that lie within `r` of the XY
    /// segment (the capsule: the segment's disk sweep), or `None`. The capsule
    /// is convex, so its cut by a line is an interval, bounded by the end disks'
    /// circles or the two sides offset by ±r along the normal.
    pub fn span_at(&self, y: f64, r: f64) -> Option<(f64, f64)> {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for p in [self.a, self.b] {
            let dy = y - p[1];
            if dy.abs() <= r {
                let w = (r * r - dy * dy).sqrt();
                lo = lo.min(p[0] - w);
                hi = hi.max(p[0] + w);
            }
        }
        let (dx, dy) = (self.b[0] - self.a[0], self.b[1] - self.a[1]);
        let l = (dx * dx + dy * dy).sqrt();
        if l > 0.0 {
            let (nx, ny) = (-dy / l * r, dx / l * r);
            for s in [1.0, -1.0] {
                let (px, py) = (self.a[0] + s * nx, self.a[1] + s * ny);
                let (qx, qy) = (self.b[0] + s * nx, self.b[1] + s * ny);
                if (py - y) * (qy - y) <= 0.0 && py != qy {
                    let x = px + (y - py) / (qy - py) * (qx - px);
                    lo = lo.min(x);
                    hi = hi.max(x);
                }
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// The lowest tool-bottom z over the point (cx, cy) for a tool of radius
    /// `r` (see the module docs), or `None` if the point is never within `r`
    /// of the axis.
    pub fn bottom_over(&self, cx: f64, cy: f64, r: f64) -> Option<f64> {
        let (dx, dy) = (self.b[0] - self.a[0], self.b[1] - self.a[1]);
        let (ex, ey) = (self.a[0] - cx, self.a[1] - cy);
        let aa = dx * dx + dy * dy;
        let c = ex * ex + ey * ey - r * r;
        let z = |t: f64| self.a[2] + t * (self.b[2] - self.a[2]);
        // A move shorter than a nanometre in XY: the tool stands still.
        if aa < 1e-18 {
            return (c <= 0.0).then(|| self.z_min());
        }
        let b = 2.0 * (ex * dx + ey * dy);
        let disc = b * b - 4.0 * aa * c;
        if disc < 0.0 {
            return None;
        }
        let q = disc.sqrt();
        let t1 = ((-b - q) / (2.0 * aa)).max(0.0);
        let t2 = ((-b + q) / (2.0 * aa)).min(1.0);
        (t1 <= t2).then(|| z(t1).min(z(t2)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance from (x, y) to the XY segment, the textbook way (projection
    /// clamped to the segment): an oracle independent of the quadratic.
    fn dist(s: &Segment, x: f64, y: f64) -> f64 {
        let (dx, dy) = (s.b[0] - s.a[0], s.b[1] - s.a[1]);
        let l2 = dx * dx + dy * dy;
        let t = if l2 > 0.0 {
            (((x - s.a[0]) * dx + (y - s.a[1]) * dy) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (s.a[0] + t * dx - x).hypot(s.a[1] + t * dy - y)
    }

    #[test]
    fn bottom_and_span_agree_with_the_distance_oracle() {
        let s = Segment {
            a: [1.0, 2.0, 0.0],
            b: [7.0, 4.5, -3.0],
        };
        let r = 1.5;
        for k in 0..4000 {
            let (x, y) = (-1.0 + (k % 80) as f64 * 0.13, 0.0 + (k / 80) as f64 * 0.15);
            let d = dist(&s, x, y);
            let got = s.bottom_over(x, y, r);
            if d < r - 1e-9 {
                let z = got.expect("inside");
                // Brute force over t: the lowest z(t) with the point under the disk.
                let zb = (0..=20000)
                    .map(|i| i as f64 / 20000.0)
                    .filter(|&t| {
                        let (px, py) = (s.a[0] + t * 6.0, s.a[1] + t * 2.5);
                        (px - x).hypot(py - y) <= r
                    })
                    .map(|t| -3.0 * t)
                    .fold(f64::INFINITY, f64::min);
                assert!((z - zb).abs() < 1e-3, "{x} {y}: {z} vs {zb}");
                let (lo, hi) = s.span_at(y, r).expect("span");
                assert!(lo <= x && x <= hi);
            } else if d > r + 1e-9 {
                assert!(got.is_none(), "{x} {y}");
                if let Some((lo, hi)) = s.span_at(y, r) {
                    // Outside the capsule, yet maybe in its span's hull only
                    // if the span's ends are capsule points.
                    for e in [lo, hi] {
                        assert!(dist(&s, e, y) <= r + 1e-9);
                    }
                }
            }
        }
    }

    #[test]
    fn a_vertical_move_cuts_its_disk_to_the_lower_end() {
        let s = Segment {
            a: [0.0, 0.0, 1.0],
            b: [0.0, 0.0, -2.0],
        };
        assert_eq!(s.bottom_over(0.5, 0.5, 1.0), Some(-2.0));
        assert_eq!(s.bottom_over(0.8, 0.8, 1.0), None);
        assert_eq!(s.span_at(0.6, 1.0), Some((-0.8, 0.8)));
    }
}
