//! The tube's trims in the (u, v) plane (002 §3), cut out of its sections, and
//! the containment test of the nesting check.

use super::{TubeError, TubeFault};
use crate::geometry::Vec2;
use std::f64::consts::TAU;

/// Most vertices of one trim polygon.
pub const MAX_TRIM_VERTICES: usize = 100_000;

/// Each trim: 3 to [`MAX_TRIM_VERTICES`] finite (u, v) points.
pub(super) fn check(trims: &[Vec<[f64; 2]>]) -> Result<(), TubeError> {
    for (i, t) in trims.iter().enumerate() {
        let bad = |reason| TubeError::Invalid {
            key: "trims",
            reason,
        };
        if t.len() < 3 || t.len() > MAX_TRIM_VERTICES {
            let points = t.len();
            return Err(bad(TubeFault::TrimPoints { trim: i, points }));
        }
        if let Some(j) = t
            .iter()
            .position(|p| !(p[0].is_finite() && p[1].is_finite()))
        {
            return Err(bad(TubeFault::TrimNotFinite { trim: i, point: j }));
        }
    }
    Ok(())
}

/// The v-intervals [a, b] (b ≥ a) where the line u = const is inside `poly`
/// (even-odd: the sorted crossings, paired).
fn crossings(poly: &[[f64; 2]], u: f64) -> Vec<(f64, f64)> {
    let mut vs: Vec<f64> = (0..poly.len())
        .filter_map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            ((a[0] > u) != (b[0] > u)).then(|| a[1] + (u - a[0]) / (b[0] - a[0]) * (b[1] - a[1]))
        })
        .collect();
    vs.sort_by(f64::total_cmp);
    vs.chunks_exact(2).map(|p| (p[0], p[1])).collect()
}

/// The trimmed v-intervals at u, merged, as sorted pieces of [0, 2π).
fn trimmed(trims: &[Vec<[f64; 2]>], u: f64) -> Vec<(f64, f64)> {
    let mut pieces = Vec::new();
    for (a, b) in trims.iter().flat_map(|t| crossings(t, u)) {
        if b - a >= TAU {
            return vec![(0.0, TAU)];
        }
        let s = a.rem_euclid(TAU);
        let e = s + (b - a);
        pieces.push((s, e.min(TAU)));
        if e > TAU {
            pieces.push((0.0, e - TAU));
        }
    }
    pieces.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut merged: Vec<(f64, f64)> = Vec::with_capacity(pieces.len());
    for (s, e) in pieces {
        match merged.last_mut() {
            Some(last) if s <= last.1 => last.1 = last.1.max(e),
            _ => merged.push((s, e)),
        }
    }
    merged
}

/// Where the top ring u = 1 takes its trims: a trim is cut out of the section
/// at u where the line just above u crosses it (so a trim's floor u₀ is cut at
/// u₀ itself, as a roughing level there must cut it); above u = 1 there is no
/// line, and the top ring takes the state just below it.
const TOP_U: f64 = 1.0 - 1e-9;

/// The kept arcs (a, b), a < b, b possibly past 2π, at u: `None` when no trim
/// applies there, empty when the whole curve is trimmed.
pub(super) fn kept_arcs(trims: &[Vec<[f64; 2]>], u: f64) -> Option<Vec<(f64, f64)>> {
    let cut = trimmed(trims, u.min(TOP_U));
    let (first, last) = (cut.first()?, cut.last()?);
    let mut kept: Vec<(f64, f64)> = cut.windows(2).map(|w| (w[0].1, w[1].0)).collect();
    kept.push((last.1, first.0 + TAU));
    kept.retain(|(a, b)| b > a);
    Some(kept)
}

/// Whether q lies inside the region of `region`'s polygons (their winding
/// numbers' sum is not 0: outlines count +1, holes −1; the even-odd answer
/// for nested, oriented rings).
fn inside(region: &[Vec<Vec2>], q: Vec2) -> bool {
    region
        .iter()
        .map(|p| crate::geometry::polygon_winding_number(p, q))
        .sum::<i32>()
        != 0
}

/// Distance from q to the region's edges.
fn distance(region: &[Vec<Vec2>], q: Vec2) -> f64 {
    let mut d = f64::INFINITY;
    for p in region {
        for i in 0..p.len() {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            let ab = b - a;
            let t = if ab.dot(ab) > 0.0 {
                ((q - a).dot(ab) / ab.dot(ab)).clamp(0.0, 1.0)
            } else {
                0.0
            };
            d = d.min((a + ab * t - q).norm());
        }
    }
    d
}

/// How far (mm) the farthest of every `⌈n/max⌉`-th vertex of `inner`'s polygons
/// lies outside `outer`'s region (0 when all are inside).
pub(super) fn outside_by(inner: &[Vec<Vec2>], outer: &[Vec<Vec2>], max: usize) -> f64 {
    let mut worst: f64 = 0.0;
    for p in inner {
        let step = p.len().div_ceil(max.max(1)).max(1);
        for &q in p.iter().step_by(step) {
            if !inside(outer, q) {
                worst = crate::num::max_or_nan(worst, distance(outer, q));
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_merge_and_wrap_round_v_zero() {
        let rect =
            |u0: f64, u1: f64, v0: f64, v1: f64| vec![[u0, v0], [u1, v0], [u1, v1], [u0, v1]];
        let trims = vec![
            rect(0.2, 0.8, 1.0, 2.0),
            rect(0.5, 0.9, 1.5, 2.5),
            rect(0.0, 1.0, -0.5, 0.25),
        ];
        assert_eq!(kept_arcs(&trims, 0.1), Some(vec![(0.25, TAU - 0.5)]));
        let k = kept_arcs(&trims, 0.6).unwrap();
        assert_eq!(k, vec![(0.25, 1.0), (2.5, TAU - 0.5)]);
        assert_eq!(kept_arcs(&trims[..2], 0.95), None);
        assert_eq!(kept_arcs(&[rect(0.0, 1.0, 0.0, 7.0)], 0.5), Some(vec![]));
    }

    #[test]
    fn containment_allows_touching_and_finds_a_vertex_outside() {
        let sq = |h: f64| {
            vec![vec![
                Vec2::new(-h, -h),
                Vec2::new(h, -h),
                Vec2::new(h, h),
                Vec2::new(-h, h),
            ]]
        };
        assert_eq!(outside_by(&sq(1.0), &sq(2.0), 512), 0.0);
        assert!(outside_by(&sq(1.0), &sq(1.0), 512) < 1e-15);
        let d = outside_by(&sq(1.0 + 1e-6), &sq(1.0), 512);
        assert!((d - 2f64.sqrt() * 1e-6).abs() < 1e-12, "{d}");
    }
}
