use super::*;
use crate::num::testing::uniforms;
use std::f64::consts::TAU;

fn ring(k: usize, f: impl Fn(f64) -> [f64; 3]) -> Vec<[f64; 3]> {
    (0..k).map(|j| f(TAU * j as f64 / k as f64)).collect()
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

type Curve = fn(f64) -> [f64; 3];

/// Four band-limited curves (degree ≤ 11 < K/2 for K ≥ 24): a tube with a bulge.
const CURVES: [Curve; 4] = [
    |v| {
        let r = 10.0 + (5.0 * v).cos() + 0.2 * (11.0 * v).cos();
        [r * v.cos(), r * v.sin(), 0.3 * (3.0 * v).sin()]
    },
    |v| {
        let r = 12.0 + 0.5 * (7.0 * v).sin();
        [r * v.cos(), 1.0 + r * v.sin(), 5.0]
    },
    |v| {
        let r = 9.0 + 0.8 * (4.0 * v).cos();
        [0.5 + r * v.cos(), r * v.sin(), 9.0 + 0.2 * (2.0 * v).cos()]
    },
    |v| {
        let r = 6.0 + 0.3 * (9.0 * v).sin();
        [2.0 + r * v.cos(), r * v.sin(), 12.0]
    },
];

fn four(k: usize, s: f64, t: f64) -> FourCurves {
    FourCurves {
        p0: ring(k, CURVES[0]),
        p1: ring(k, CURVES[1]),
        p2: ring(k, CURVES[2]),
        p3: ring(k, CURVES[3]),
        s,
        t,
    }
}

/// Largest distance between X(uᵢ, v) and the four curves at `vs`.
fn four_curve_error(x: &PdeSurface, s: f64, t: f64, vs: &[f64]) -> f64 {
    let us = [0.0, s, t, 1.0];
    vs.iter()
        .flat_map(|&v| (0..4).map(move |i| (i, v)))
        .map(|(i, v)| dist(x.point(us[i], v), CURVES[i](v)))
        .fold(0.0, crate::num::max_or_nan)
}

#[test]
fn the_four_curves_are_met_at_random_v() {
    let vs: Vec<f64> = uniforms(21, 300).iter().map(|r| TAU * r).collect();
    for (k, n, a, s, t) in [
        (64, 6, 1.0, 0.3, 0.7),
        (32, 3, 1.0, 0.3, 0.7),
        (64, 4, 0.5, 0.2, 0.45),
        (48, 8, 0.6, 0.5, 0.8),
    ] {
        let (x, _) = PdeSurface::through_four_curves(&four(k, s, t), a, n).unwrap();
        let e = four_curve_error(&x, s, t, &vs);
        // Measured: 2.2e-14 to 3.4e-13 mm on curves of radius ~10 mm (the
        // largest at a = 0.5, s, t = 0.2, 0.45, where λ = 0.5 has cond 339).
        assert!(
            e < 1e-12,
            "K = {k}, N = {n}, a = {a}, s = {s}, t = {t}: {e:e}"
        );
        let f = x.without_remainder();
        assert!(
            four_curve_error(&f, s, t, &vs) > 0.1,
            "the remainder does the work"
        );
    }
}

#[test]
fn a_two_end_surface_is_its_own_four_curve_surface() {
    // Every mode of the two-end surface lies in the span of its λ (a n, or w above
    // N), and those are the four-curve surface's functions too: the curves
    // X(0), X(s), X(t), X(1) of one determine it again.
    let k = 48;
    let ends = super::super::BoundaryCurves {
        x0: ring(k, CURVES[0]),
        x1: ring(k, CURVES[3]),
        xu0: ring(k, |v| [3.0 * v.cos() + (6.0 * v).sin(), 3.0 * v.sin(), 8.0]),
        xu1: ring(k, |v| [-2.0 * v.cos(), -2.0 * v.sin(), 10.0]),
    };
    let (a, n, s, t) = (1.0, 5, 0.35, 0.6);
    let x = PdeSurface::solve(&ends, a, n).unwrap();
    let at = |u: f64| ring(k, |v| x.point(u, v));
    let c = FourCurves {
        p0: at(0.0),
        p1: at(s),
        p2: at(t),
        p3: at(1.0),
        s,
        t,
    };
    let (y, _) = PdeSurface::through_four_curves(&c, a, n).unwrap();
    let r = uniforms(4, 400);
    let e = r
        .chunks(2)
        .map(|p| dist(x.point(p[0], TAU * p[1]), y.point(p[0], TAU * p[1])))
        .fold(0.0, crate::num::max_or_nan);
    // Measured: 1.7e-14 mm.
    assert!(e < 1e-11, "{e:e}");
}

#[test]
fn the_conditioning_report_is_the_surfaces_response_to_a_unit_wiggle() {
    // A unit cos nv on one curve (x only), the others zero: the surface's largest
    // |X_x(u, 0)| over u = j/400 is that datum's gain; the report gives the
    // largest over the four curves.
    let (k, a, modes, s, t) = (16, 1.0, 4, 0.3, 0.7);
    let zero = vec![[0.0; 3]; k];
    let (_, report) = PdeSurface::through_four_curves(&four(k, s, t), a, modes).unwrap();
    assert_eq!(report.len(), modes + 2);
    for (n, r) in report.iter().enumerate() {
        let lambda = if n == 0 {
            0.0
        } else {
            a * n.min(modes + 1) as f64
        };
        assert_eq!((r.n, r.lambda), (n, lambda));
        assert!(r.cond >= 1.0 && r.cond.is_finite(), "{r:?}");
        let mut response: f64 = 0.0;
        for i in 0..4 {
            let mut curves = [zero.clone(), zero.clone(), zero.clone(), zero.clone()];
            curves[i] = ring(k, |v| [(n as f64 * v).cos(), 0.0, 0.0]);
            let [p0, p1, p2, p3] = curves;
            let c = FourCurves {
                p0,
                p1,
                p2,
                p3,
                s,
                t,
            };
            let (x, _) = PdeSurface::through_four_curves(&c, a, modes).unwrap();
            for j in 0..=400 {
                response = response.max(x.point(j as f64 / 400.0, 0.0)[0].abs());
            }
        }
        assert!(
            (response - r.gain).abs() < 1e-9 * r.gain,
            "n = {n}: {response} vs {r:?}"
        );
    }
    // The gain grows with λ (exponentially: interior conditions).
    assert!(report.windows(2).skip(1).all(|w| w[1].gain > w[0].gain));
}

#[test]
fn a_large_a_is_refused_as_ill_conditioned_naming_the_key() {
    let c = four(64, 0.3, 0.7);
    let err = |a: f64, n: usize| match PdeSurface::through_four_curves(&c, a, n) {
        Err(PdeError::IllConditioned { key, gain, .. }) => {
            assert!(gain > GAIN_LIMIT, "{gain}");
            key
        }
        Err(e) => panic!("a = {a}, N = {n}: {e}"),
        Ok(_) => panic!("a = {a}, N = {n}: accepted"),
    };
    assert_eq!(err(20.0, 4), "a");
    // Measured gains (s, t = 0.3, 0.7): 5.0e3 at λ = 40, 1.3e6 at 60. Modes
    // 1..11 (λ ≤ 55) pass at a = 5 but not the remainder at w = a(N + 1) = 60.
    assert_eq!(err(5.0, 11), "modes");
    assert!(PdeSurface::through_four_curves(&c, 5.0, 10).is_ok());
}

#[test]
fn s_and_t_outside_or_out_of_order_are_typed_errors() {
    let key = |s: f64, t: f64| match PdeSurface::through_four_curves(&four(32, s, t), 1.0, 3) {
        Err(PdeError::Invalid { key, .. }) => key,
        Err(e) => panic!("s = {s}, t = {t}: {e}"),
        Ok(_) => panic!("s = {s}, t = {t}: accepted"),
    };
    assert_eq!(key(0.0, 0.5), "s");
    assert_eq!(key(-0.1, 0.5), "s");
    assert_eq!(key(1.0, 0.5), "s");
    assert_eq!(key(f64::NAN, 0.5), "s");
    assert_eq!(key(0.5, 0.5), "t");
    assert_eq!(key(0.6, 0.4), "t");
    assert_eq!(key(0.3, 1.0), "t");
    assert_eq!(key(0.3, f64::INFINITY), "t");
    let e = PdeSurface::through_four_curves(&four(32, 0.6, 0.4), 1.0, 3)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("t: ") && e.contains("(0.6, 1)"), "{e}");
    let mut short = four(32, 0.3, 0.7);
    short.p2.pop();
    match PdeSurface::through_four_curves(&short, 1.0, 3) {
        Err(PdeError::Invalid { key, .. }) => assert_eq!(key, "p2"),
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("a short p2 accepted"),
    }
}

#[test]
fn the_spine_is_the_cubic_through_the_means() {
    let (s, t) = (0.25, 0.6);
    let c = four(40, s, t);
    let (x, _) = PdeSurface::through_four_curves(&c, 1.0, 4).unwrap();
    let mean = |p: &[[f64; 3]]| -> [f64; 3] {
        std::array::from_fn(|i| p.iter().map(|q| q[i]).sum::<f64>() / p.len() as f64)
    };
    let sp = x.spine();
    for (u, p) in [(0.0, &c.p0), (s, &c.p1), (t, &c.p2), (1.0, &c.p3)] {
        assert!(dist(sp.point(u), mean(p)) < 1e-12, "u = {u}");
    }
}
