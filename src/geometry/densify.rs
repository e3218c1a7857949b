//! Points along a polyline no farther apart than a step.

use super::Vec2;

/// The vertices of `pts` and, on every chord longer than `step`, points
/// evenly between them so that none is farther than `step` from the next.
/// `closed`: the chord from the last point back to the first is included and
/// the first is not repeated at the end; open, the last point ends the list.
pub(crate) fn densify(pts: &[Vec2], step: f64, closed: bool) -> Vec<Vec2> {
    spread(pts, pts, step, closed, |a, b, t| a.lerp(b, t))
}

/// Values `vals` given at the points `pts`, spread over [`densify`]'s
/// points (the same steps, linear along each chord).
pub(crate) fn densify_values(pts: &[Vec2], vals: &[f64], step: f64, closed: bool) -> Vec<f64> {
    spread(pts, vals, step, closed, |a, b, t| a + (b - a) * t)
}

/// `vals` (one per point of `pts`) at densify's steps along `pts`'s chords.
fn spread<T: Copy>(
    pts: &[Vec2],
    vals: &[T],
    step: f64,
    closed: bool,
    lerp: impl Fn(T, T, f64) -> T,
) -> Vec<T> {
    let n = pts.len();
    let chords = if closed { n } else { n.saturating_sub(1) };
    let mut out = Vec::with_capacity(n);
    for i in 0..chords {
        let (a, b) = (vals[i], vals[(i + 1) % n]);
        let k = (pts[i].dist(pts[(i + 1) % n]) / step).ceil().max(1.0) as usize;
        out.extend((0..k).map(|j| lerp(a, b, j as f64 / k as f64)));
    }
    if !closed {
        out.extend(vals.last());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Open (the closed case: `finish::path`'s
    /// `resampling_keeps_the_corners_and_bounds_the_spacing`).
    #[test]
    fn an_open_polyline_ends_at_its_last_point() {
        let sq = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ];
        // Three chords of ⌈1/0.3⌉ = 4 points each, and the last point.
        let o = densify(&sq, 0.3, false);
        assert_eq!(o.len(), 13);
        assert_eq!(*o.last().unwrap(), sq[3]);
        assert!(o.windows(2).all(|w| w[0].dist(w[1]) <= 0.3));
        assert!(densify(&[], 0.3, false).is_empty());
        assert_eq!(densify(&sq[..1], 0.3, false), vec![sq[0]]);
    }
}
