//! Issue 19's sphere, the model the tests, the examples and the benchmark
//! share: 40 points on the unit sphere (a Fibonacci lattice) given on the
//! surface and its centre given inside, in the box [−2, 2]³.

use super::{GivenPoint, Kernel, Model, PointKind, Quadrature};
use nalgebra::Vector3;

/// `n` nearly uniform unit vectors (the Fibonacci lattice), turned by
/// `phase` about z: zᵢ = 1 − (2i + 1)/n, angle i·π(3 − √5) + phase.
pub fn fibonacci(n: usize, phase: f64) -> Vec<Vector3<f64>> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let t = golden * i as f64 + phase;
            Vector3::new(r * t.cos(), r * t.sin(), z)
        })
        .collect()
}

/// The sphere of 40 surface points and its centre inside, with `kernel`,
/// in the box [−2, 2]³ with `per_edge` elements per face edge.
pub fn sphere_model(per_edge: usize, kernel: Kernel) -> Model {
    let mut points: Vec<GivenPoint> = fibonacci(40, 0.0)
        .into_iter()
        .map(|p| GivenPoint {
            p,
            kind: PointKind::Surface,
        })
        .collect();
    points.push(GivenPoint {
        p: Vector3::zeros(),
        kind: PointKind::Inside,
    });
    Model {
        lo: Vector3::repeat(-2.0),
        hi: Vector3::repeat(2.0),
        per_edge,
        kernel,
        points,
        quadrature: Quadrature::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lattice_is_on_the_unit_sphere_and_balanced() {
        let p = fibonacci(40, 0.3);
        assert_eq!(p.len(), 40);
        for q in &p {
            assert!((q.norm() - 1.0).abs() < 1e-14, "{q:?}");
        }
        // zᵢ are symmetric about 0, so the centroid's z is 0.
        let zc: f64 = p.iter().map(|q| q.z).sum::<f64>() / 40.0;
        assert!(zc.abs() < 1e-14, "{zc}");
        let m = sphere_model(6, Kernel::T2);
        assert_eq!(m.points.len(), 41);
        assert_eq!(m.points[40].kind, PointKind::Inside);
        assert_eq!((m.lo, m.hi), (Vector3::repeat(-2.0), Vector3::repeat(2.0)));
    }
}
