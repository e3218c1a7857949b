//! Geometry measured independently of pfcam's own, to hold pfcam's results to:
//! distances by clamped projection, points along cavalier_contours' exact
//! polylines, and a shape's area, holes and perimeter summed over its
//! contours. Lengths in mm, areas in mm².

use cavalier_contours::polyline::{PlineSource, Polyline};
use pfcam::geometry::{Shape, Vec2};

/// Distance from `p` to the segment a–b: the projection parameter
/// t = (p − a)·(b − a) / |b − a|² clamped to [0, 1] (0 for a point segment),
/// then |p − (a + t (b − a))|.
pub fn seg_dist(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let d = b - a;
    let l2 = d.norm2();
    let t = if l2 > 0.0 {
        ((p - a).dot(d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.dist(a + d * t)
}

/// Points at most `step` mm apart along a closed cavalier polyline (lines and
/// arcs), each piece from its start vertex, the end left to the next piece.
pub fn sample_pline(pl: &Polyline, step: f64) -> Vec<Vec2> {
    let n = pl.vertex_count();
    let mut out = Vec::new();
    for i in 0..n {
        let v1 = pl.at(i);
        let v2 = pl.at((i + 1) % n);
        let (a, b) = (Vec2::new(v1.x, v1.y), Vec2::new(v2.x, v2.y));
        if v1.bulge.abs() < 1e-12 {
            let k = ((a.dist(b) / step).ceil() as usize).max(1);
            out.extend((0..k).map(|j| a.lerp(b, j as f64 / k as f64)));
        } else {
            // Arc: sweep θ = 4·atan(bulge), centre from the chord.
            let theta = 4.0 * v1.bulge.atan();
            let chord = b - a;
            let r = chord.norm() / (2.0 * (theta / 2.0).sin()).abs();
            let mid = a.lerp(b, 0.5);
            let h = (r * r - chord.norm2() / 4.0).max(0.0).sqrt();
            let side = if (theta > 0.0) == (theta.abs() < std::f64::consts::PI) {
                1.0
            } else {
                -1.0
            };
            let c = mid + chord.perp().normalized() * (h * side);
            let a0 = (a.y - c.y).atan2(a.x - c.x);
            let k = (((r * theta.abs()) / step).ceil() as usize).max(1);
            out.extend((0..k).map(|j| {
                let t = a0 + theta * j as f64 / k as f64;
                Vec2::new(c.x + r * t.cos(), c.y + r * t.sin())
            }));
        }
    }
    out
}

/// The area a shape encloses: the signed areas of its regions' outlines
/// (counter-clockwise, positive) and counters (clockwise, negative) summed.
pub fn area(s: &Shape) -> f64 {
    s.regions
        .iter()
        .map(|r| r.outline.signed_area() + r.counters.iter().map(|c| c.signed_area()).sum::<f64>())
        .sum()
}

/// How many holes (counters) a shape has, over all its regions.
pub fn holes(s: &Shape) -> usize {
    s.regions.iter().map(|r| r.counters.len()).sum()
}

/// The total length of a shape's contours, outlines and counters.
pub fn perimeter(s: &Shape) -> f64 {
    s.contours().map(|c| c.length()).sum()
}
