//! The preview's colour scales: depth (the tool path's levels) and
//! equipotential value (the curves Γ(s)).

/// `#rrggbb` of the colour `t` of the way from `c0` to `c1` (RGB, 0 to 255).
fn mix(c0: [f64; 3], c1: [f64; 3], t: f64) -> String {
    let c: Vec<u8> = (0..3)
        .map(|i| (c0[i] + t * (c1[i] - c0[i])).round() as u8)
        .collect();
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// Colour of depth fraction t (0 shallowest, 1 deepest): a stretch of viridis,
/// green to dark violet, darker deeper.
pub fn depth_colour(t: f64) -> String {
    const STOPS: [(f64, [f64; 3]); 4] = [
        (0.0, [122.0, 209.0, 81.0]),
        (0.35, [33.0, 145.0, 140.0]),
        (0.7, [59.0, 82.0, 139.0]),
        (1.0, [68.0, 1.0, 84.0]),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        1.0
    };
    let k = STOPS.iter().rposition(|s| s.0 <= t).unwrap_or(0).min(2);
    let (t0, c0) = STOPS[k];
    let (t1, c1) = STOPS[k + 1];
    mix(c0, c1, (t - t0) / (t1 - t0))
}

/// Colour of the equipotential with index `k` of `n` (0 the farthest from the
/// part): light to dark red, as the paper's colour figures go red near the part.
pub(super) fn curve_colour(k: usize, n: usize) -> String {
    let t = if n <= 1 {
        1.0
    } else {
        k as f64 / (n - 1) as f64
    };
    mix([244.0, 165.0, 130.0], [178.0, 24.0, 43.0], t)
}
