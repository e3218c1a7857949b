//! Douglas–Peucker thinning of a polyline, whatever its points are: the
//! caller gives the distance of a point from a chord and, optionally, its
//! own reason to keep a point the distance would drop.

/// Which of `n` points Douglas–Peucker keeps at `eps`: the ends always; on
/// each chord a–b the point k farthest from it (`dist(k, a, b)`, the first
/// of equals) when farther than `eps`, else the first point `split(a, b)`
/// names; each kept point splits its chord in two. Every dropped point then
/// lies within `eps` of the chord that replaces it.
pub(crate) fn keep_mask(
    n: usize,
    eps: f64,
    dist: impl Fn(usize, usize, usize) -> f64,
    split: impl Fn(usize, usize) -> Option<usize>,
) -> Vec<bool> {
    let mut keep = vec![false; n];
    if n == 0 {
        return keep;
    }
    keep[0] = true;
    keep[n - 1] = true;
    let mut stack = vec![(0, n - 1)];
    while let Some((a, b)) = stack.pop() {
        let mut worst = (0.0, 0);
        for k in a + 1..b {
            let d = dist(k, a, b);
            if d > worst.0 {
                worst = (d, k);
            }
        }
        let at = if worst.0 > eps {
            Some(worst.1)
        } else {
            split(a, b)
        };
        if let Some(k) = at {
            keep[k] = true;
            stack.push((a, k));
            stack.push((k, b));
        }
    }
    keep
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On the line y = 0 with one bump: the bump over `eps` is kept, the
    /// ones under it dropped unless `split` names them.
    #[test]
    fn keeps_what_stands_off_the_chord_or_what_split_names() {
        let ys = [0.0, 0.004, 0.0, 1.0, 0.0, 0.004, 0.0];
        let dist = |k: usize, _: usize, _: usize| ys[k];
        let kept = keep_mask(ys.len(), 0.01, dist, |_, _| None);
        assert_eq!(kept, [true, false, false, true, false, false, true]);
        let named = keep_mask(ys.len(), 0.01, dist, |a, b| (a < 5 && 5 < b).then_some(5));
        assert_eq!(named, [true, false, false, true, false, true, true]);
        assert!(keep_mask(0, 0.01, dist, |_, _| None).is_empty());
    }
}
