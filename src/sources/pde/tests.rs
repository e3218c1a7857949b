use super::*;
use crate::num::testing::uniforms;
use std::f64::consts::TAU;

type Curve = fn(f64) -> [f64; 3];

fn sample(f: Curve, k: usize) -> Vec<[f64; 3]> {
    (0..k).map(|j| f(TAU * j as f64 / k as f64)).collect()
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

// A wobbly tube: trigonometric polynomials of degree ≤ 12 (r(v) cos v with
// cos 11v in r), below K/2 for K ≥ 26, so the samples determine the curves exactly.
fn x0(v: f64) -> [f64; 3] {
    let r = 10.0 + (5.0 * v).cos() + 0.5 * (7.0 * v).sin() + 0.2 * (11.0 * v).cos();
    [r * v.cos(), r * v.sin(), 0.3 * (3.0 * v).sin()]
}
fn x1(v: f64) -> [f64; 3] {
    let r = 6.0 + 0.8 * (4.0 * v).cos() + 0.3 * (9.0 * v).sin();
    [2.0 + r * v.cos(), r * v.sin(), 12.0]
}
fn xu0(v: f64) -> [f64; 3] {
    [
        3.0 * v.cos() + (6.0 * v).sin(),
        3.0 * v.sin(),
        8.0 + (8.0 * v).cos(),
    ]
}
fn xu1(v: f64) -> [f64; 3] {
    [
        -2.0 * v.cos(),
        -2.0 * v.sin() + 0.5 * (10.0 * v).cos(),
        10.0,
    ]
}

fn wobbly(k: usize) -> BoundaryCurves {
    BoundaryCurves {
        x0: sample(x0, k),
        x1: sample(x1, k),
        xu0: sample(xu0, k),
        xu1: sample(xu1, k),
    }
}

/// Largest distance between the surface's four conditions and the curves at `vs`.
fn condition_error(s: &PdeSurface, vs: &[f64]) -> f64 {
    let given: [Curve; 4] = [x0, x1, xu0, xu1];
    vs.iter()
        .map(|&v| {
            let got = [s.point(0.0, v), s.point(1.0, v), s.du(0.0, v), s.du(1.0, v)];
            (0..4)
                .map(|i| dist(got[i], given[i](v)))
                .fold(0.0, crate::num::max_or_nan)
        })
        .fold(0.0, crate::num::max_or_nan)
}

fn sample_vs(k: usize) -> Vec<f64> {
    (0..k).map(|j| TAU * j as f64 / k as f64).collect()
}

#[test]
fn conditions_hold_at_the_samples() {
    for (k, n, a) in [
        (24, 4, 1.0),
        (64, 4, 1.0),
        (64, 0, 0.5),
        (25, 12, 0.3),
        (64, 8, 2.0),
    ] {
        let s = PdeSurface::solve(&wobbly(k), a, n).unwrap();
        let e = condition_error(&s, &sample_vs(k));
        assert!(e < 1e-12, "K = {k}, N = {n}, a = {a}: {e:e}");
    }
}

#[test]
fn conditions_hold_at_random_v_for_band_limited_curves() {
    // The curves have degree 11 < K/2, so the interpolant of the samples is the curve.
    let vs: Vec<f64> = uniforms(7, 200).iter().map(|r| TAU * r).collect();
    for (k, n) in [(26, 3), (64, 6)] {
        let s = PdeSurface::solve(&wobbly(k), 1.0, n).unwrap();
        let e = condition_error(&s, &vs);
        assert!(e < 1e-12, "K = {k}, N = {n}: {e:e}");
        // F alone misses the content above N at the ends.
        let f = s.without_remainder();
        assert!(condition_error(&f, &vs) > 0.1);
    }
}

#[test]
fn the_remainder_does_the_work_at_the_ends_and_fades_inside() {
    let s = PdeSurface::solve(&wobbly(64), 1.0, 4).unwrap();
    let f = s.without_remainder();
    let vs = sample_vs(64);
    let gap = |u: f64| {
        vs.iter()
            .map(|&v| dist(s.point(u, v), f.point(u, v)))
            .fold(0.0, f64::max)
    };
    // The x0 content above mode 4 (cos 5v, sin 7v, cos 11v on the radius, sin 3v... )
    // reaches about 1.7 mm; F misses it at u = 0.
    assert!(gap(0.0) > 1.0, "{}", gap(0.0));
    assert!(gap(1.0) > 0.5, "{}", gap(1.0));
    // w = 5: a position residual ρ at u = 0 is met by ρ (1 + wu) e^{−wu} (zero slope),
    // 0.29 ρ at u = ½; measured 0.42 mm there against 1.13 mm at u = 0.
    assert!(gap(0.5) < 0.5 * gap(0.0), "{} vs {}", gap(0.5), gap(0.0));
}

/// Radius at u = ½ of the mode-1 fourth-order solution f(u) with f(0) = f(1) = ρ,
/// f′(0) = s, f′(1) = −s, λ = a, h = ½. The conditions are symmetric about u = ½, and
/// the solution unique, so f(½ + t) = α cosh λt + β t sinh λt; the two conditions at
/// t = h give α = (ρ (S + λhC) + s h S) / (S C + λh), S = sinh λh, C = cosh λh.
fn cylinder_waist(rho: f64, s: f64, a: f64) -> f64 {
    let h = 0.5;
    let (sh, ch) = ((a * h).sinh(), (a * h).cosh());
    (rho * (sh + a * h * ch) + s * h * sh) / (sh * ch + a * h)
}

#[test]
fn a_cylinder_has_the_closed_form_waist() {
    let (rho, height, k) = (7.0, 20.0, 32);
    for s in [0.0, 6.0, -4.0] {
        let ring = |r: f64, z: f64| -> Vec<[f64; 3]> {
            sample_vs(k)
                .iter()
                .map(|&v| [r * v.cos(), r * v.sin(), z])
                .collect()
        };
        let curves = BoundaryCurves {
            x0: ring(rho, 0.0),
            x1: ring(rho, height),
            xu0: ring(s, height),
            xu1: ring(-s, height),
        };
        for a in [0.3, 1.0, 2.5, 6.0] {
            let surf = PdeSurface::solve(&curves, a, 3).unwrap();
            let want = cylinder_waist(rho, s, a);
            for &v in &uniforms(3, 10) {
                let p = surf.point(0.5, TAU * v);
                let r = p[0].hypot(p[1]);
                assert!(
                    (r - want).abs() < 1e-12 * rho,
                    "s = {s}, a = {a}: {r} vs {want}"
                );
                assert!((p[2] - height * 0.5).abs() < 1e-12 * height);
            }
        }
    }
    // Sanity of the closed form: a → 0 is the Hermite cubic (ρ + s/4 at u = ½).
    assert!((cylinder_waist(rho, 2.0, 1e-4) - (rho + 0.5)).abs() < 1e-6);
}

#[test]
fn large_a_times_n_stays_finite_and_meets_the_conditions() {
    // a·N = 100, w = 105: e^{anu} in the paper's basis would be e^{100}.
    let k = 64;
    let s = PdeSurface::solve(&wobbly(k), 5.0, 20).unwrap();
    assert!(condition_error(&s, &sample_vs(k)) < 1e-12);
    for &u in &[0.0, 0.01, 0.5, 0.99, 1.0] {
        for &v in &uniforms(11, 20) {
            let p = s.point(u, TAU * v);
            let d = s.du(u, TAU * v);
            assert!(p.iter().chain(d.iter()).all(|x| x.is_finite()));
        }
    }
}

#[test]
fn the_spine_is_the_mean_over_v_and_the_hermite_cubic_of_the_means() {
    let k = 48;
    let curves = wobbly(k);
    let s = PdeSurface::solve(&curves, 1.5, 5).unwrap();
    let mean = |c: &[[f64; 3]]| -> [f64; 3] {
        std::array::from_fn(|i| c.iter().map(|p| p[i]).sum::<f64>() / c.len() as f64)
    };
    let sp = s.spine();
    assert!(dist(sp.p1, mean(&curves.x0)) < 1e-12);
    assert!(dist(sp.v2, mean(&curves.xu1)) < 1e-12);
    for &u in &[0.0, 0.2, 0.5, 0.9] {
        // Every periodic mode n ≤ K/2 averages to zero over the samples.
        let avg = mean(
            &sample_vs(k)
                .iter()
                .map(|&v| s.point(u, v))
                .collect::<Vec<_>>(),
        );
        assert!(dist(avg, sp.point(u)) < 1e-12, "u = {u}");
    }
}

#[test]
fn an_edited_spine_moves_the_surface_by_exactly_the_spine_change() {
    let s = PdeSurface::solve(&wobbly(48), 1.0, 5).unwrap();
    let old = s.spine();
    let new = Spine {
        p1: [1.0, -2.0, 0.5],
        p2: [4.0, 3.0, 15.0],
        v1: [5.0, 0.0, 10.0],
        v2: [-3.0, 2.0, 14.0],
    };
    let moved = s.with_spine(new);
    assert_eq!(s.with_spine(old), s);
    let r = uniforms(5, 60);
    for pair in r.chunks(2) {
        let (u, v) = (pair[0], TAU * pair[1]);
        let shift: [f64; 3] = std::array::from_fn(|i| new.point(u)[i] - old.point(u)[i]);
        let got: [f64; 3] = std::array::from_fn(|i| moved.point(u, v)[i] - s.point(u, v)[i]);
        assert!(dist(got, shift) < 1e-12);
        assert!(dist(moved.dv(u, v), s.dv(u, v)) < 1e-12);
    }
    // The ends follow the new end points and derivatives.
    let at0: [f64; 3] = std::array::from_fn(|i| s.point(0.0, 1.0)[i] - old.p1[i] + new.p1[i]);
    assert!(dist(moved.point(0.0, 1.0), at0) < 1e-12);
}

#[test]
fn derivatives_match_finite_differences() {
    let s = PdeSurface::solve(&wobbly(48), 1.2, 6).unwrap();
    let h = 1e-6;
    for pair in uniforms(9, 40).chunks(2) {
        let (u, v) = (0.05 + 0.9 * pair[0], TAU * pair[1]);
        let fd_u: [f64; 3] =
            std::array::from_fn(|i| (s.point(u + h, v)[i] - s.point(u - h, v)[i]) / (2.0 * h));
        let fd_v: [f64; 3] =
            std::array::from_fn(|i| (s.point(u, v + h)[i] - s.point(u, v - h)[i]) / (2.0 * h));
        assert!(
            dist(fd_u, s.du(u, v)) < 1e-5,
            "{:?} vs {:?}",
            fd_u,
            s.du(u, v)
        );
        assert!(
            dist(fd_v, s.dv(u, v)) < 1e-5,
            "{:?} vs {:?}",
            fd_v,
            s.dv(u, v)
        );
    }
}

#[test]
fn bad_input_is_a_typed_error_naming_the_field() {
    let c = wobbly(16);
    let key = |r: Result<PdeSurface, PdeError>| match r {
        Err(PdeError::Invalid { key, .. }) => key,
        other => panic!("{other:?}"),
    };
    assert_eq!(key(PdeSurface::solve(&c, 0.0, 2)), "a");
    assert_eq!(key(PdeSurface::solve(&c, f64::NAN, 2)), "a");
    assert_eq!(key(PdeSurface::solve(&c, 1.0, 8)), "x0");
    let mut short = c.clone();
    short.xu1.pop();
    assert_eq!(key(PdeSurface::solve(&short, 1.0, 2)), "xu1");
    let mut nan = c.clone();
    nan.x1[3][2] = f64::INFINITY;
    assert_eq!(key(PdeSurface::solve(&nan, 1.0, 2)), "x1");
    let e = PdeSurface::solve(&c, -1.0, 2).unwrap_err().to_string();
    assert!(e.starts_with("a: "), "{e}");
}

#[test]
fn a_ring_equals_the_points_it_samples() {
    let s = PdeSurface::solve(&wobbly(64), 0.7, 5).expect("solve");
    for u in [0.0, 0.3, 0.75, 1.0] {
        for p in [13, 64, 200] {
            let ring = s.ring(u, p);
            assert_eq!(ring.len(), p);
            for (j, q) in ring.iter().enumerate() {
                let d = dist(*q, s.point(u, TAU * j as f64 / p as f64));
                assert!(d < 1e-12, "u {u}, p {p}, j {j}: {d}");
            }
        }
    }
}
