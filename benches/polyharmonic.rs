//! Speed of Ochiai's polyharmonic solid (`sources::polyharmonic`, issue 19):
//! the l = 2 solve, the top envelope and the closed solid's surface. Run:
//! `cargo bench --bench polyharmonic`. Figures in docs/method.md §17 are the
//! medians criterion prints.

use criterion::{criterion_group, criterion_main, Criterion};
use pfcam::sources::polyharmonic::closed::{closed_mesh, Region};
use pfcam::sources::polyharmonic::sphere::sphere_model;
use pfcam::sources::polyharmonic::{solve, Envelope, Kernel, Model};
use std::hint::black_box;

/// 40 points on the unit sphere (Fibonacci lattice) + its centre inside,
/// T2A with A = 0.3, box [−2, 2]³ with `per_edge` elements per face edge.
fn sphere(per_edge: usize) -> Model {
    sphere_model(per_edge, Kernel::T2A { a: 0.3 })
}

fn polyharmonic(c: &mut Criterion) {
    let mut g = c.benchmark_group("polyharmonic");
    g.sample_size(10);
    for per_edge in [6, 10] {
        let model = sphere(per_edge);
        let n = 6 * per_edge * per_edge;
        g.bench_function(
            format!("sphere of 40 points: solve, N = {n}, M = 41"),
            |b| b.iter(|| solve(black_box(&model)).unwrap()),
        );
    }
    let sol = solve(&sphere(6)).unwrap();
    let env = Envelope {
        step: 0.05,
        tol: 1e-4,
    }
    .validated(&sol)
    .unwrap();
    g.bench_function(
        "sphere of 40 points: envelope, 10 x 10 rays, N = 216",
        |b| {
            b.iter(|| {
                let mut hits = 0;
                for i in 0..10 {
                    for j in 0..10 {
                        let (x, y) = (-1.2 + 0.24 * i as f64, -1.2 + 0.24 * j as f64);
                        hits += usize::from(env.height(black_box(&sol), x, y).is_some());
                    }
                }
                hits
            })
        },
    );
    let model = sphere(6);
    let region = Region::of(&model.points, model.kernel, &sol, 6).unwrap();
    g.bench_function(
        "sphere of 40 points: closed surface, spacing 0.04, N = 216",
        |b| b.iter(|| closed_mesh(black_box(&sol), 6, region, 0.04).unwrap()),
    );
    g.finish();
}

criterion_group!(benches, polyharmonic);
criterion_main!(benches);
