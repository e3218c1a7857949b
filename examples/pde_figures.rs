//! Measured figures for docs/method.md, "Bloor–Wilson PDE surfaces (Ugail)":
//! `cargo run --release --example pde_figures`.

use pfcam::sources::pde::{BoundaryCurves, PdeSurface};
use pfcam::sources::pde6::{BoundaryCurves6, PdeSurface6};
use std::f64::consts::TAU;

fn ring(k: usize, f: impl Fn(f64) -> [f64; 3]) -> Vec<[f64; 3]> {
    (0..k).map(|j| f(TAU * j as f64 / k as f64)).collect()
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

/// A squircle (|x|⁴ + |y|⁴ = 10⁴, not band-limited) at z = 0 to a circle of radius
/// 6 at z = 15, Xᵤ = (0, 0, 15) at both ends.
fn vase(k: usize) -> (BoundaryCurves, impl Fn(f64) -> [f64; 3]) {
    let squircle = |v: f64| {
        let (s, c) = v.sin_cos();
        let r = 10.0 / (c.powi(4) + s.powi(4)).powf(0.25);
        [r * c, r * s, 0.0]
    };
    let curves = BoundaryCurves {
        x0: ring(k, squircle),
        x1: ring(k, |v| [6.0 * v.cos(), 6.0 * v.sin(), 15.0]),
        xu0: ring(k, |_| [0.0, 0.0, 15.0]),
        xu1: ring(k, |_| [0.0, 0.0, 15.0]),
    };
    (curves, squircle)
}

fn main() {
    four_curve_conditioning();
    trim_figures();
    tube_figures();
    println!("squircle→circle vase, a = 1:");
    println!("  K   N   max|X(0,vk)-x0| max|X(0,v)-x0(v)| (997 v)  |R| at u=0, ½");
    for (k, n) in [(64, 4), (64, 8), (256, 8), (256, 20)] {
        let (curves, squircle) = vase(k);
        let s = PdeSurface::solve(&curves, 1.0, n).expect("valid curves");
        let f = s.without_remainder();
        let at_samples = curves
            .x0
            .iter()
            .enumerate()
            .map(|(j, p)| dist(s.point(0.0, TAU * j as f64 / k as f64), *p));
        let between = (0..997).map(|i| {
            let v = TAU * (i as f64 + 0.5) / 997.0;
            dist(s.point(0.0, v), squircle(v))
        });
        let gap = |u: f64| {
            (0..k)
                .map(|j| TAU * j as f64 / k as f64)
                .map(|v| dist(s.point(u, v), f.point(u, v)))
                .fold(0.0, f64::max)
        };
        println!(
            "  {k:<3} {n:<3} {:<15.2e} {:<23.2e} {:.3} mm, {:.3} mm",
            at_samples.fold(0.0, f64::max),
            between.fold(0.0, f64::max),
            gap(0.0),
            gap(0.5)
        );
    }
    println!("a = 5, N = 20 (a·N = 100), K = 64: max condition error at the samples");
    let (curves, _) = vase(64);
    let s = PdeSurface::solve(&curves, 5.0, 20).expect("valid curves");
    let e = (0..64)
        .map(|j| TAU * j as f64 / 64.0)
        .map(|v| {
            dist(
                s.point(0.0, v),
                curves.x0[(v / TAU * 64.0).round() as usize],
            )
            .max(dist(s.du(1.0, v), [0.0, 0.0, 15.0]))
        })
        .fold(0.0, f64::max);
    println!("  {e:.2e}");
    println!("sixth order, same vase, Xuu = 0 at both ends, K = 64:");
    println!("  a    N   max error X | Xu / w | Xuu / w²  (w = a (N + 1))");
    let (c4, _) = vase(64);
    let zero = vec![[0.0; 3]; 64];
    let c6 = BoundaryCurves6 {
        curves: [c4.x0, c4.x1, c4.xu0, c4.xu1, zero.clone(), zero],
    };
    for (a, n) in [(1.0, 3), (0.5, 6), (5.0, 20)] {
        let s = PdeSurface6::solve(&c6, a, n).expect("valid curves");
        let w: f64 = a * (n + 1) as f64;
        let mut e = [0.0f64; 3];
        for j in 0..64 {
            let v = TAU * j as f64 / 64.0;
            for (row, curve) in c6.curves.iter().enumerate() {
                let d = dist(s.eval(row / 2, (row % 2) as f64, v), curve[j]);
                e[row / 2] = e[row / 2].max(d / w.powi((row / 2) as i32));
            }
        }
        println!("  {a:<4} {n:<3} {:.2e} | {:.2e} | {:.2e}", e[0], e[1], e[2]);
    }
}

/// 002's four-curve conditions: the gain and condition number of one mode's
/// system against λ, for three choices of (s, t).
fn four_curve_conditioning() {
    use pfcam::sources::pde::four_curve_conditioning;
    println!("four-curve conditions (002): gain | cond of the row-equilibrated 4×4, by λ");
    print!("  (s, t)      ");
    let lambdas = [0.0, 1.0, 5.0, 10.0, 20.0, 30.0, 40.0, 60.0, 80.0];
    lambdas.iter().for_each(|l| print!(" λ={l:<10}"));
    println!();
    for (s, t) in [(0.3, 0.7), (1.0 / 3.0, 2.0 / 3.0), (0.2, 0.45)] {
        print!("  ({s:.3}, {t:.3})");
        for &l in &lambdas {
            let r = four_curve_conditioning(0, l, s, t);
            print!(" {:.1e}|{:<4.0}", r.gain, r.cond);
        }
        println!();
    }
}

/// 002's trimming map: a circle and a kidney (non-convex) trim in a square
/// border, K = 128 samples, N = 8: the curves met, the Jacobian's minimum on a
/// 401 × 4096 sample of (ξ, η), and the time of one solve.
fn trim_figures() {
    use pfcam::sources::pde_trim::{resample_closed, TrimCurves, TrimMap};
    use std::f64::consts::PI;
    let k = 128;
    let square = [
        [1.0, PI],
        [1.0, PI + 0.5],
        [0.0, PI + 0.5],
        [0.0, PI - 0.5],
        [1.0, PI - 0.5],
    ];
    let circle = |e: f64| [0.5 + 0.2 * e.cos(), PI + 0.2 * e.sin()];
    let kidney = |e: f64| {
        let r = 0.2 * (1.0 + 0.35 * (2.0 * e).cos() - 0.1 * (3.0 * e).sin());
        [0.5 + r * e.cos(), PI + r * e.sin()]
    };
    println!("trimming (002 §3.1), square border v = π ± 0.5, K = {k}, N = 8:");
    println!("  trim    max|M(0)-C1|,|M(1)-C2| at ηk  min det J (401×4096)  at (ξ, η)   solve");
    type Curve<'a> = &'a dyn Fn(f64) -> [f64; 2];
    let shapes: [(&str, Curve); 2] = [("circle", &circle), ("kidney", &kidney)];
    for (name, f) in shapes {
        let c = TrimCurves {
            trim: (0..k).map(|j| f(TAU * j as f64 / k as f64)).collect(),
            border: resample_closed(&square, k),
        };
        let t0 = std::time::Instant::now();
        let m = TrimMap::solve(&c, 8).expect("valid curves");
        let dt = t0.elapsed();
        let e = (0..k)
            .map(|j| {
                let eta = TAU * j as f64 / k as f64;
                let (a, b) = (m.map(0.0, eta), m.map(1.0, eta));
                let d = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]);
                d(a, c.trim[j]).max(d(b, c.border[j]))
            })
            .fold(0.0, f64::max);
        let (det, xi, eta) = m.min_jacobian(400, 4096);
        println!(
            "  {name:<7} {e:<32.2e} {det:<20.4} ({xi:.4}, {eta:.4})  {:.1} ms",
            dt.as_secs_f64() * 1e3
        );
    }
}

/// The vase as a part (`sources::pde_tube`): X_z − A₀z, section areas, the time
/// of the checks, how far a trimmed window's sides overhang, and the refusal of
/// a bulging cylinder.
fn tube_figures() {
    use pfcam::levels::sections::{net_area, Sections};
    use pfcam::sources::pde_tube::{PdeTube, TubeError, TubeKind};
    let (curves, _) = vase(128);
    let t0 = std::time::Instant::now();
    let boss = PdeTube::new(&curves, 1.0, 8, TubeKind::Boss, vec![], (512, 0.01)).expect("nests");
    let dt = t0.elapsed().as_secs_f64();
    let s = boss.surface();
    let mut ez: f64 = 0.0;
    for i in 0..=100 {
        for j in 0..256 {
            let (u, v) = (i as f64 / 100.0, TAU * j as f64 / 256.0);
            ez = ez.max((s.point(u, v)[2] - s.spine().point(u)[2]).abs());
        }
    }
    println!(
        "vase as a boss (K = 128, N = 8, P = 512, tol 0.01 mm): new() {:.0} ms",
        dt * 1e3
    );
    println!("  max |X_z − A₀z| on 101 × 256 (u, v): {ez:.2e} mm");
    for z in [-15.0, -11.25, -7.5, -3.75, 0.0] {
        println!(
            "  z = {z:<6} u = {:.4}  area {:.3} mm²",
            boss.level_value(z),
            net_area(&boss.section(z))
        );
    }
    let window = vec![vec![[0.6, 1.0], [1.2, 1.0], [1.2, 2.0], [0.6, 2.0]]];
    match PdeTube::new(&curves, 1.0, 8, TubeKind::Boss, window.clone(), (512, 1e-9)) {
        Err(e @ TubeError::Overhang { .. }) => {
            println!("  window u ≥ 0.6, v ∈ [1, 2], tol 1e-9: {e}")
        }
        other => println!("  window, tol 1e-9: {:?}", other.map(|_| ())),
    }
    let ok = PdeTube::new(&curves, 1.0, 8, TubeKind::Boss, window, (512, 0.01)).is_ok();
    println!("  the same window, tol 0.01 mm: accepted = {ok}");
    let k = 32;
    let bulge = BoundaryCurves {
        x0: ring(k, |v| [5.0 * v.cos(), 5.0 * v.sin(), 0.0]),
        x1: ring(k, |v| [5.0 * v.cos(), 5.0 * v.sin(), 20.0]),
        xu0: ring(k, |v| [6.0 * v.cos(), 6.0 * v.sin(), 20.0]),
        xu1: ring(k, |v| [-6.0 * v.cos(), -6.0 * v.sin(), 20.0]),
    };
    if let Err(e) = PdeTube::new(&bulge, 1.0, 4, TubeKind::Boss, vec![], (256, 0.01)) {
        println!("  bulging cylinder (ρ 5, H 20, s 6): {e}");
    }
}
