//! Measured figures for docs/method.md §17, "Polyharmonic solids from points
//! (Ochiai)": `cargo run --release --example polyharmonic_figures`.

use nalgebra::Vector3;
use pfcam::sources::polyharmonic::quadrature::influence;
use pfcam::sources::polyharmonic::sphere::{fibonacci, sphere_model};
use pfcam::sources::polyharmonic::{
    solve, solve_dirichlet, BoxMesh, Envelope, GivenPoint, Kernel, Model, PointKind, QuadRule,
    Quadrature, Solution,
};
use std::time::Instant;

fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
    Vector3::new(x, y, z)
}

/// Green's identity: T₁ = |x − c|², T₂ = −6 on [−1, 1]³, no points.
fn greens(per_edge: usize) -> (f64, f64, f64, f64, f64, usize) {
    let c = v(0.3, -0.2, 0.1);
    let mesh = BoxMesh::new(v(-1.0, -1.0, -1.0), v(1.0, 1.0, 1.0), per_edge).expect("mesh");
    let t1: Vec<f64> = mesh
        .elements
        .iter()
        .map(|e| (e.centre - c).norm_squared())
        .collect();
    let exact: Vec<f64> = mesh
        .elements
        .iter()
        .map(|e| 2.0 * (e.centre - c).dot(&e.normal))
        .collect();
    let t2 = vec![-6.0; t1.len()];
    let start = Instant::now();
    let sol =
        solve_dirichlet(mesh, &t1, &t2, &[], Kernel::T2, Quadrature::default()).expect("solve");
    let secs = start.elapsed().as_secs_f64();
    let ev1 = sol
        .v1
        .iter()
        .zip(&exact)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let ev2 = sol.v2.iter().map(|a| a.abs()).fold(0.0, f64::max);
    // Area-weighted RMS of the V₁ error, and the worst element's ring: 0 for
    // an element on a box edge, 1 for the next row in, ...
    let els = &sol.mesh().elements;
    let area: f64 = els.iter().map(|e| e.area()).sum();
    let rms = (els
        .iter()
        .zip(sol.v1.iter().zip(&exact))
        .map(|(e, (a, b))| e.area() * (a - b).powi(2))
        .sum::<f64>()
        / area)
        .sqrt();
    let worst = (0..els.len())
        .max_by(|&i, &j| {
            (sol.v1[i] - exact[i])
                .abs()
                .total_cmp(&(sol.v1[j] - exact[j]).abs())
        })
        .unwrap_or(0);
    let e = &els[worst];
    let from_edge = (0..3)
        .filter(|&k| e.normal[k] == 0.0)
        .map(|k| 1.0 - e.centre[k].abs())
        .fold(f64::INFINITY, f64::min);
    let ring = (from_edge / (2.0 * e.a)).floor() as usize;
    let et1 = [
        v(0.0, 0.0, 0.0),
        v(0.5, -0.4, 0.2),
        v(-0.6, 0.6, -0.5),
        v(0.2, 0.1, 0.7),
    ]
    .iter()
    .map(|&x| (sol.value(x).expect("inside") - (x - c).norm_squared()).abs())
    .fold(0.0, f64::max);
    (ev1, ev2, et1, secs, rms, ring)
}

/// First zero of T₁ from the origin along d: steps of 0.05, then bisection.
fn radius_along(sol: &Solution, d: Vector3<f64>) -> Option<f64> {
    let (mut lo, mut hi) = (0.0, None);
    for k in 1..=38 {
        let t = 0.05 * k as f64;
        if sol.value(d * t)? > 0.0 {
            hi = Some(t);
            break;
        }
        lo = t;
    }
    let mut hi = hi?;
    while hi - lo > 1e-9 {
        let mid = 0.5 * (lo + hi);
        if sol.value(d * mid)? > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// Two balls of radius 0.5 about (±0.65, 0, 0): 24 surface points and a centre
/// each, and (with `separator`) an outside point at the origin.
fn two_bumps(separator: bool) -> Model {
    let mut points = Vec::new();
    for cx in [-0.65, 0.65] {
        let c = v(cx, 0.0, 0.0);
        for d in fibonacci(24, 0.2) {
            points.push(GivenPoint {
                p: c + d * 0.5,
                kind: PointKind::Surface,
            });
        }
        points.push(GivenPoint {
            p: c,
            kind: PointKind::Inside,
        });
    }
    if separator {
        points.push(GivenPoint {
            p: Vector3::zeros(),
            kind: PointKind::Outside,
        });
    }
    let mut m = sphere_model(5, Kernel::T2A { a: 0.3 });
    m.points = points;
    m
}

/// max |Σⱼ h₁(e, j) + ½| over the collocation points of [−1, 1]³ with 4 elements per edge.
fn worst_row_sum(q: Quadrature) -> f64 {
    let mesh = BoxMesh::new(v(-1.0, -1.0, -1.0), v(1.0, 1.0, 1.0), 4).expect("mesh");
    let rule = QuadRule::new(q).expect("rule");
    let mut worst = 0.0f64;
    for e in &mesh.elements {
        let sum: f64 = mesh
            .elements
            .iter()
            .map(|el| influence(el, e.centre, &rule).h1)
            .sum();
        worst = worst.max((sum + 0.5).abs());
    }
    worst
}

fn main() {
    println!("Double-layer rows on [-1, 1]^3, 4 elements per edge: max |row sum + 1/2|");
    for (order, ratio, max_depth) in [(2, 0.5, 4), (4, 1.0, 8), (6, 1.5, 12), (10, 2.0, 14)] {
        let e = worst_row_sum(Quadrature {
            order,
            ratio,
            max_depth,
        });
        println!("  order {order:>2}  ratio {ratio}  depth {max_depth:>2}: {e:.2e}");
    }
    println!();
    println!("Green's identity T1 = |x - c|^2 on [-1, 1]^3 (T2 = -6, V2 = 0):");
    println!("  n/edge  N     max|V1 err| (ring)  rms V1 err  max|V2|     max|T1 err| inside  order(T1)  solve s");
    let mut last: Option<f64> = None;
    let mut last_n = 0usize;
    for n in [2, 3, 4, 6, 8, 12] {
        let (ev1, ev2, et1, secs, rms, ring) = greens(n);
        let order = last.map(|l| (l / et1).ln() / (n as f64 / last_n as f64).ln());
        let order = order.map_or("-".to_string(), |o| format!("{o:.2}"));
        println!(
            "  {n:>5}  {:>4}  {ev1:.3e} ({ring})   {rms:.3e}   {ev2:.3e}   {et1:.3e}           {order:>6}   {secs:.2}",
            6 * n * n
        );
        last = Some(et1);
        last_n = n;
    }

    println!("\n40 points on the unit sphere + centre (inside), box [-2, 2]^3:");
    println!("  kernel            n/edge  max|r - 1| (240 rays)  condition   solve s");
    let mut dirs = fibonacci(200, 0.37);
    dirs.extend(fibonacci(40, 0.0));
    for (kernel, n) in [
        (Kernel::T2A { a: 0.3 }, 4),
        (Kernel::T2A { a: 0.3 }, 6),
        (Kernel::T2A { a: 0.3 }, 8),
        (Kernel::T2A { a: 1.0 }, 6),
        (Kernel::T2, 6),
    ] {
        let start = Instant::now();
        let sol = solve(&sphere_model(n, kernel)).expect("solve");
        let secs = start.elapsed().as_secs_f64();
        let worst = dirs
            .iter()
            .map(|&d| radius_along(&sol, d).map_or(f64::INFINITY, |r| (r - 1.0).abs()))
            .fold(0.0, f64::max);
        println!(
            "  {:<16}  {n:>5}   {worst:.4}                  {:.2e}    {secs:.2}",
            format!("{kernel:?}"),
            sol.condition
        );
    }

    let model = sphere_model(6, Kernel::T2A { a: 0.3 });
    let sol = solve(&model).expect("solve");
    let worst = model
        .points
        .iter()
        .filter(|g| g.kind == PointKind::Surface)
        .map(|g| sol.normal(g.p).map_or(f64::INFINITY, |n| n.angle(&g.p)))
        .fold(0.0, f64::max);
    println!("  normal (28) at the 40 surface points (T2A, A = 0.3, 6/edge): max angle to radial {worst:.4} rad");
    println!(
        "\nTop envelope of the sphere (T2A, A = 0.3, 6/edge), 33 x 33 rays over [-1.2, 1.2]^2:"
    );
    let sol = solve(&sphere_model(6, Kernel::T2A { a: 0.3 })).expect("solve");
    let env = Envelope {
        step: 0.05,
        tol: 1e-6,
    }
    .validated(&sol)
    .expect("settings");
    let start = Instant::now();
    let (mut worst, mut hits, mut misses) = (0.0f64, 0, 0);
    for i in 0..33 {
        for j in 0..33 {
            let (x, y) = (-1.2 + 0.075 * i as f64, -1.2 + 0.075 * j as f64);
            match env.height(&sol, x, y) {
                Some(h) => {
                    hits += 1;
                    let rho = x.hypot(y);
                    if rho < 0.95 {
                        worst = worst.max((h - (1.0 - rho * rho).sqrt()).abs());
                    }
                }
                None => misses += 1,
            }
        }
    }
    let secs = start.elapsed().as_secs_f64();
    println!("  hits {hits}, misses {misses}, max |h - sqrt(1 - rho^2)| for rho < 0.95: {worst:.4}, {:.2} ms/ray", 1e3 * secs / 1089.0);
    let start = Instant::now();
    let mut sum = 0.0;
    for i in 0..1000 {
        let t = i as f64 / 1000.0;
        sum += sol.value(v(t - 0.5, 0.3 * t, 0.8 - t)).expect("inside");
    }
    let us = 1e6 * start.elapsed().as_secs_f64() / 1000.0;
    println!("  one T1 evaluation (N = 216, M = 41): {us:.0} us (checksum {sum:.3})");

    println!("\nTwo balls r = 0.5 about (+-0.65, 0, 0), T2A A = 0.3, 5/edge: min T1 on the gap x in [-0.15, 0.15]:");
    for separator in [false, true] {
        let sol = solve(&two_bumps(separator)).expect("solve");
        let min = (0..=30)
            .map(|i| {
                sol.value(v(-0.15 + 0.01 * i as f64, 0.0, 0.0))
                    .expect("inside")
            })
            .fold(f64::INFINITY, f64::min);
        println!("  separator {separator}: min T1 = {min:.4}");
    }
}
