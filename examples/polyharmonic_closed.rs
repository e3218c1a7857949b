//! Figures of the closed polyharmonic solid's surface (docs/method.md §17,
//! "The closed solid"): issue 19's sphere of 40 points and its centre
//! (T2A, A = 0.3, box [−2, 2]³, 6 elements a side) meshed by marching
//! tetrahedra at several spacings. Run:
//! `cargo run --release --example polyharmonic_closed`.

use nalgebra::Vector3;
use pfcam::sources::polyharmonic::closed::{closed_mesh, Region};
use pfcam::sources::polyharmonic::sphere::sphere_model;
use pfcam::sources::polyharmonic::{solve, Kernel, Model};
use std::time::Instant;

fn sphere() -> Model {
    sphere_model(6, Kernel::T2A { a: 0.3 })
}

fn main() {
    let model = sphere();
    let sol = solve(&model).expect("the sphere solves");
    let region = Region::of(&model.points, model.kernel, &sol, 6).expect("a region");
    region.check_closed(&sol).expect("closed");
    println!(
        "region [{:.3}, {:.3}]^3 (the points' box grown by 0.25 x 2 + A = 0.8, cut to the box less one element side)",
        region.lo.x, region.hi.x
    );
    println!("| spacing | triangles | max \\|r − 1\\| | mean \\|r − 1\\| | volume | (V − 4π/3)/(4π/3) | time |");
    println!("|---|---|---|---|---|---|---|");
    let exact = 4.0 / 3.0 * std::f64::consts::PI;
    for spacing in [0.1, 0.05, 0.04, 0.02] {
        let t0 = Instant::now();
        let iso = closed_mesh(&sol, 6, region, spacing).expect("a mesh");
        let m = pfcam::surface::Mesh {
            vertices: iso.vertices,
            triangles: iso.triangles,
        };
        let dt = t0.elapsed().as_secs_f64();
        m.check().expect("closed and oriented");
        let r: Vec<f64> = m
            .vertices
            .iter()
            .map(|p| (Vector3::from(*p).norm() - 1.0).abs())
            .collect();
        let max = r.iter().cloned().fold(0.0, f64::max);
        let mean = r.iter().sum::<f64>() / r.len() as f64;
        let v = m.volume();
        println!(
            "| {spacing} | {} | {max:.4} | {mean:.4} | {v:.4} | {:+.2e} | {dt:.2} s |",
            m.triangles.len(),
            (v - exact) / exact
        );
    }
}
