//! A small closed loop round an uncut spot of stock.

use super::zlevel::CutPath;
use crate::geometry::Vec2;

/// The sides of a spot loop.
const SIDES: usize = 24;

/// A closed tool path round the spot `centre`: the regular 24-gon inscribed in
/// the circle of `radius` ρ about it,
///
/// pₖ = centre + ρ (cos 2πk/24, sin 2πk/24), k = 0, …, 23, then p₀ again,
///
/// its sides ρ · 2 sin(π/24) ≈ 0.261 ρ long, every point of it within ρ of
/// the centre (a chord's midpoint ρ cos(π/24) ≈ 0.991 ρ from it). The callers
/// choose ρ so that the tool's disk on the loop keeps clear of the part; the
/// disk sweeps the spot when ρ is at most the tool radius. Labelled `label`,
/// not a boss's clearing ring.
pub(crate) fn spot_loop(centre: Vec2, radius: f64, label: String) -> CutPath {
    let mut points: Vec<Vec2> = (0..SIDES)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / SIDES as f64;
            centre + Vec2::new(a.cos(), a.sin()) * radius
        })
        .collect();
    points.push(points[0]);
    CutPath {
        label,
        points,
        closed: true,
        ring: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closed_24_gon_on_the_circle() {
        let c = Vec2::new(3.0, -2.0);
        let path = spot_loop(c, 1.5, "spot".into());
        assert_eq!(path.label, "spot");
        assert!(path.closed && path.ring.is_none());
        assert_eq!(path.points.len(), SIDES + 1);
        assert_eq!(path.points[0], path.points[SIDES]);
        assert_eq!(path.points[0], c + Vec2::new(1.5, 0.0));
        for w in path.points.windows(2) {
            assert!((w[0].dist(c) - 1.5).abs() < 1e-12);
            let side = 2.0 * 1.5 * (std::f64::consts::PI / SIDES as f64).sin();
            assert!((w[0].dist(w[1]) - side).abs() < 1e-12);
        }
    }
}
