use super::*;
use crate::num::testing::uniforms;
use crate::sources::pde::BoundaryCurves;
use std::f64::consts::PI;

fn ring(k: usize, f: impl Fn(f64) -> [f64; 2]) -> Vec<[f64; 2]> {
    (0..k).map(|j| f(TAU * j as f64 / k as f64)).collect()
}

fn d2(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// 002's Figure 3: a circle trim in a square border, v = π ± 0.5, u ∈ [0, 1];
/// both start at their right-hand point (002's dotted line).
fn circle_in_square(k: usize) -> TrimCurves {
    let square = [
        [1.0, PI],
        [1.0, PI + 0.5],
        [0.0, PI + 0.5],
        [0.0, PI - 0.5],
        [1.0, PI - 0.5],
    ];
    TrimCurves {
        trim: ring(k, |e| [0.5 + 0.2 * e.cos(), PI + 0.2 * e.sin()]),
        border: resample_closed(&square, k),
    }
}

/// A non-convex (kidney) trim, 002's Figure 6, in the same square.
fn kidney_in_square(k: usize) -> TrimCurves {
    let mut c = circle_in_square(k);
    c.trim = ring(k, |e| {
        let r = 0.2 * (1.0 + 0.35 * (2.0 * e).cos() - 0.1 * (3.0 * e).sin());
        [0.5 + r * e.cos(), PI + r * e.sin()]
    });
    c
}

/// Band-limited curves (degree ≤ 3): an ellipse in a rounded square over the
/// whole periodic domain u ∈ (0, 1), v ∈ (0, 2π).
fn trim_band(e: f64) -> [f64; 2] {
    [0.5 + 0.15 * e.cos(), PI + 1.2 * e.sin()]
}
fn border_band(e: f64) -> [f64; 2] {
    [
        0.5 + 0.46 * e.cos() + 0.03 * (3.0 * e).cos(),
        PI + 3.0 * e.sin() - 0.2 * (3.0 * e).sin(),
    ]
}
fn band(k: usize) -> TrimCurves {
    TrimCurves {
        trim: ring(k, trim_band),
        border: ring(k, border_band),
    }
}

#[test]
fn the_map_meets_trim_curve_and_border_at_the_samples() {
    for (c, n) in [
        (circle_in_square(128), 8),
        (kidney_in_square(128), 4),
        (band(64), 2),
    ] {
        let m = TrimMap::solve(&c, n).unwrap();
        let k = c.trim.len();
        let mut e: f64 = 0.0;
        for j in 0..k {
            let eta = TAU * j as f64 / k as f64;
            e = e.max(d2(m.map(0.0, eta), c.trim[j]));
            e = e.max(d2(m.map(1.0, eta), c.border[j]));
        }
        assert!(e < 1e-12, "N = {n}: {e:e}");
    }
}

#[test]
fn between_samples_it_meets_band_limited_curves_exactly() {
    let m = TrimMap::solve(&band(32), 2).unwrap();
    let e = uniforms(3, 300)
        .iter()
        .map(|r| TAU * r)
        .map(|eta| d2(m.map(0.0, eta), trim_band(eta)).max(d2(m.map(1.0, eta), border_band(eta))))
        .fold(0.0, f64::max);
    assert!(e < 1e-12, "{e:e}");
}

#[test]
fn the_jacobian_is_positive_on_a_dense_sample() {
    // 401 × 4096 points of (ξ, η): ξ every 0.0025, η every 2π/4096.
    for (name, c, n) in [
        ("circle", circle_in_square(128), 8),
        ("kidney", kidney_in_square(128), 8),
        ("band", band(64), 4),
    ] {
        let m = TrimMap::solve(&c, n).unwrap();
        let (det, xi, eta) = m.min_jacobian(400, 4096);
        assert!(det > 0.0, "{name}: {det:e} at ξ = {xi}, η = {eta}");
    }
}

#[test]
fn the_jacobian_integrates_to_the_area_between_the_curves() {
    // ∫∫ det J dξ dη is the area enclosed by M(1, ·) less that of M(0, ·)
    // (Green); here the ellipse's π·0.15·1.2 and the rounded square's, by a
    // 20000-point shoelace of the analytic curve. ξ: Simpson, 200 intervals;
    // η: 512 points (exact for the trigonometric integrand's low modes).
    let m = TrimMap::solve(&band(64), 3).unwrap();
    let (nx, ne) = (200, 512);
    let mut integral = 0.0;
    for i in 0..=nx {
        let xi = i as f64 / nx as f64;
        let w = if i == 0 || i == nx {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let row: f64 = (0..ne)
            .map(|j| m.jacobian(xi, TAU * j as f64 / ne as f64))
            .sum::<f64>()
            * TAU
            / ne as f64;
        integral += w * row / (3.0 * nx as f64);
    }
    let outer = twice_area(&ring(20000, border_band)) / 2.0;
    let want = outer - PI * 0.15 * 1.2;
    assert!(
        (integral - want).abs() < 1e-6 * want,
        "{integral} vs {want}"
    );
}

/// Crossing number of (u, v) against a closed polygon.
fn inside(p: &[[f64; 2]], q: [f64; 2]) -> bool {
    let mut c = false;
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        if (a[1] > q[1]) != (b[1] > q[1]) {
            let x = a[0] + (q[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if q[0] < x {
                c = !c;
            }
        }
    }
    c
}

#[test]
fn the_trimmed_surface_is_the_surface_between_the_curves() {
    let k = 48;
    let curve = |f: fn(f64) -> [f64; 3]| -> Vec<[f64; 3]> {
        (0..k).map(|j| f(TAU * j as f64 / k as f64)).collect()
    };
    let surface = PdeSurface::solve(
        &BoundaryCurves {
            x0: curve(|v| [(10.0 + (5.0 * v).cos()) * v.cos(), 10.0 * v.sin(), 0.0]),
            x1: curve(|v| [6.0 * v.cos(), 6.0 * v.sin(), 12.0]),
            xu0: curve(|_| [0.0, 0.0, 12.0]),
            xu1: curve(|_| [0.0, 0.0, 12.0]),
        },
        1.0,
        4,
    )
    .unwrap();
    let c = kidney_in_square(128);
    let y = TrimmedSurface {
        surface: surface.clone(),
        map: TrimMap::solve(&c, 6).unwrap(),
    };
    // Its two edges are the surface's points at the trim curve and the border.
    let mut e: f64 = 0.0;
    for j in 0..128 {
        let eta = TAU * j as f64 / 128.0;
        let on = |uv: [f64; 2]| surface.point(uv[0], uv[1]);
        for (xi, uv) in [(0.0, c.trim[j]), (1.0, c.border[j])] {
            let (a, b) = (y.point(xi, eta), on(uv));
            e = e.max((0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt());
        }
    }
    // |X_u| ≈ 12 mm, |X_v| ≈ 10 mm: M's 1e-13 at the curves is 1e-12 mm on X.
    assert!(e < 1e-11, "{e:e}");
    // Inside: every M(ξ, η), 0 < ξ < 1, in the border and out of the trim region
    // (crossing number against 4096-point polygons of the curves).
    let fine = kidney_in_square(4096);
    for i in 1..100 {
        for j in 0..512 {
            let uv = y.map.map(i as f64 / 100.0, TAU * j as f64 / 512.0);
            assert!(
                inside(&fine.border, uv) && !inside(&fine.trim, uv),
                "{uv:?}"
            );
        }
    }
}

#[test]
fn with_no_content_above_n_the_map_is_harmonic() {
    // Curves of degree ≤ 3 and N = 3: no remainder, M = F solves (13).
    let m = TrimMap::solve(&band(32), 3).unwrap();
    let h = 1e-3;
    for p in uniforms(8, 40).chunks(2) {
        let (xi, eta) = (0.1 + 0.8 * p[0], TAU * p[1]);
        let f = |a: f64, b: f64| m.map(a, b);
        for i in 0..2 {
            let lap =
                (f(xi + h, eta)[i] + f(xi - h, eta)[i] + f(xi, eta + h)[i] + f(xi, eta - h)[i]
                    - 4.0 * f(xi, eta)[i])
                    / (h * h);
            assert!(lap.abs() < 1e-5, "ξ = {xi}, η = {eta}: ΔM = {lap:e}");
        }
    }
    // With N = 1 the remainder carries modes 2, 3 at w = 2: not harmonic.
    let r = TrimMap::solve(&band(32), 1).unwrap();
    let lap = |xi: f64, eta: f64| {
        let f = |a: f64, b: f64| r.map(a, b)[1];
        (f(xi + h, eta) + f(xi - h, eta) + f(xi, eta + h) + f(xi, eta - h) - 4.0 * f(xi, eta))
            / (h * h)
    };
    assert!((0..64).any(|j| lap(0.5, TAU * j as f64 / 64.0).abs() > 1e-2));
}

#[test]
fn bad_curves_are_typed_errors_naming_the_curve() {
    let key = |c: &TrimCurves| match TrimMap::solve(c, 3) {
        Err(PdeError::Invalid { key, reason }) => (key, reason),
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("accepted"),
    };
    let mut cw = band(32);
    cw.trim.reverse();
    assert_eq!(key(&cw).0, "trim");
    let mut short = band(32);
    short.border.pop();
    assert_eq!(key(&short).0, "border");
    let mut nan = band(32);
    nan.border[5][1] = f64::NAN;
    assert_eq!(key(&nan).0, "border");
    // A trim curve poking out of the border folds the map.
    let mut out = circle_in_square(64);
    out.trim = ring(64, |e| [0.5 + 0.7 * e.cos(), PI + 0.2 * e.sin()]);
    let (k, reason) = key(&out);
    assert!(
        k == "trim" && matches!(reason, PdeFault::Folds { det, .. } if det <= 0.0),
        "{reason}"
    );
}

#[test]
fn resampling_is_uniform_in_arc_length() {
    let sq = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
    let r = resample_closed(&sq, 8);
    let want = [
        [0.0, 0.0],
        [1.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [2.0, 2.0],
        [1.0, 2.0],
        [0.0, 2.0],
        [0.0, 1.0],
    ];
    assert!(r.iter().zip(want).all(|(a, b)| d2(*a, b) < 1e-15), "{r:?}");
    assert!(resample_closed(&[[1.0, 1.0], [1.0, 1.0]], 8).is_empty());
}
