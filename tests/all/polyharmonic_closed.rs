//! The closed polyharmonic solid's surface (issue 19, docs/method.md §17,
//! "The closed solid"): marching tetrahedra (`sources::polyharmonic::iso`)
//! on analytic fields, and issue 19's sphere of 40 points meshed closed and
//! round. Checked with `surface::Mesh` (closed, oriented, its volume).

use nalgebra::Vector3;
use pfcam::sources::polyharmonic::closed::{closed_mesh, Region};
use pfcam::sources::polyharmonic::iso::{zero_set, Grid3, IsoMesh, T_MIN};
use pfcam::sources::polyharmonic::sphere::sphere_model;
use pfcam::sources::polyharmonic::{solve, Kernel, Model};
use pfcam::surface::Mesh;
use std::f64::consts::PI;

fn mesh(m: IsoMesh) -> Mesh {
    Mesh {
        vertices: m.vertices,
        triangles: m.triangles,
    }
}

/// A sphere of radius 0.7 at spacing 0.1: closed, facing out (positive
/// volume), every vertex on it to the root's precision unless clamped
/// (T_MIN of an edge of at most 0.1·√3), the volume within 3 % of 4πr³/3
/// (the inscribed polyhedron).
#[test]
fn a_sphere_is_closed_and_outward() {
    let r = 0.7;
    let f = |x: Vector3<f64>| x.norm() - r;
    let g = Grid3::covering(Vector3::repeat(-1.0), Vector3::repeat(1.0), 0.1).unwrap();
    let m = mesh(zero_set(&g, &f).unwrap());
    m.check().unwrap();
    let exact = 4.0 / 3.0 * PI * r * r * r;
    let v = m.volume();
    assert!(
        v > 0.0 && (v - exact).abs() < 0.03 * exact,
        "{v} against {exact}"
    );
    let off = m
        .vertices
        .iter()
        .map(|p| (Vector3::from(*p).norm() - r).abs())
        .fold(0.0, f64::max);
    assert!(off < T_MIN * 0.1 * 3f64.sqrt(), "{off}");
}

/// Two blobs meeting at a saddle (the ambiguous case of marching cubes)
/// still give a closed mesh; a torus too, its volume within 10 % of
/// 2π²Rr² at spacing 0.13 (r = 0.2 is under two cells).
#[test]
fn saddles_and_a_torus_stay_closed() {
    let g = Grid3::covering(Vector3::repeat(-1.0), Vector3::repeat(1.0), 0.13).unwrap();
    let two = |x: Vector3<f64>| {
        let a = (x - Vector3::repeat(0.3)).norm();
        let b = (x + Vector3::repeat(0.3)).norm();
        a.min(b) - 0.52
    };
    mesh(zero_set(&g, &two).unwrap()).check().unwrap();
    let torus = |x: Vector3<f64>| (x.x.hypot(x.y) - 0.55).hypot(x.z) - 0.2;
    let m = mesh(zero_set(&g, &torus).unwrap());
    m.check().unwrap();
    let exact = 2.0 * PI * PI * 0.55 * 0.04;
    assert!(
        (m.volume() - exact).abs() < 0.1 * exact,
        "{} against {exact}",
        m.volume()
    );
}

/// Issue 19's sphere: 40 points on the unit sphere (Fibonacci lattice) and
/// its centre inside, T2A with A = 0.3, box [−2, 2]³ with 6 elements a side.
fn sphere() -> Model {
    sphere_model(6, Kernel::T2A { a: 0.3 })
}

/// The sphere's surface at spacing 0.04: closed and facing out, every
/// vertex within 0.01 of radius 1 (measured 0.0030; the zero set is within
/// 0.003 of it along rays, §17), and the volume within 0.1 % of 4π/3
/// (measured −0.033 %: the field's own deviation and the inscribed
/// polyhedron's deficit).
#[test]
fn the_sphere_of_forty_points_is_closed_and_round() {
    let model = sphere();
    let sol = solve(&model).unwrap();
    let region = Region::of(&model.points, model.kernel, &sol, 6).unwrap();
    region.check_closed(&sol).unwrap();
    let m = mesh(closed_mesh(&sol, 6, region, 0.04).unwrap());
    m.check().unwrap();
    let off = m
        .vertices
        .iter()
        .map(|p| (Vector3::from(*p).norm() - 1.0).abs())
        .fold(0.0, f64::max);
    assert!(off < 0.01, "max |r − 1| = {off}");
    let exact = 4.0 / 3.0 * PI;
    let v = m.volume();
    assert!(
        (v - exact).abs() < 1e-3 * exact,
        "volume {v} against {exact}"
    );
}
