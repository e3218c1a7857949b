use super::*;
use crate::sources::polyharmonic::elements::BoxMesh;
use crate::sources::polyharmonic::elements::{self_inv_r, self_r};
use crate::sources::polyharmonic::gauss::GaussRule;

fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
    Vector3::new(x, y, z)
}

fn rule(order: usize, ratio: f64, max_depth: u32) -> QuadRule {
    QuadRule::new(Quadrature {
        order,
        ratio,
        max_depth,
    })
    .unwrap()
}

/// ∫ r^k dA over [−a, a] × [−b, b] from its centre in polar coordinates, by
/// Gauss–Legendre in θ and r over the eight triangles the diagonals and the
/// axes cut it into.
fn polar_brute(a: f64, b: f64, k: i32) -> f64 {
    let g = GaussRule::new(30);
    let tri = |p: f64, q: f64| {
        // Triangle with legs p (along θ = 0) and q: r from 0 to p / cos θ.
        g.integrate(0.0, (q / p).atan(), |t| {
            g.integrate(0.0, p / t.cos(), |r| r.powi(k) * r)
        })
    };
    4.0 * (tri(a, b) + tri(b, a))
}

/// The same by the element quadrature from the centre, split 16 levels deep
/// towards it (the centre is a corner of the pieces, never a node).
fn adaptive_brute(a: f64, b: f64, k: i32) -> f64 {
    let q = rule(8, 2.0, 16);
    let el = Element {
        centre: v(0.3, -0.2, 0.5),
        normal: v(0.0, 0.0, 1.0),
        u: v(1.0, 0.0, 0.0),
        v: v(0.0, 1.0, 0.0),
        a,
        b,
    };
    let mut sum = 0.0;
    q.visit(&el, el.centre, &mut |x, w| {
        sum += w * (x - el.centre).norm().powi(k)
    });
    sum
}

#[test]
fn self_integrals_are_exact() {
    let s2 = 2f64.sqrt();
    let l = (1.0 + s2).ln();
    for h in [0.1, 1.0, 3.0] {
        let a = 0.5 * h;
        assert!((self_inv_r(a, a) - 4.0 * h * l).abs() < 1e-14 * h);
        assert!((self_r(a, a) - h.powi(3) / 6.0 * (s2 + l)).abs() < 1e-14 * h.powi(3));
    }
    for (a, b) in [(0.5, 0.5), (0.5, 0.2), (0.1, 0.7)] {
        for (k, exact) in [(-1, self_inv_r(a, b)), (1, self_r(a, b))] {
            let polar = polar_brute(a, b, k);
            assert!(
                (polar - exact).abs() < 1e-13 * exact,
                "k {k} {a}×{b}: polar {polar} vs {exact}"
            );
            let adaptive = adaptive_brute(a, b, k);
            // The 4 pieces 2⁻¹⁶ wide at the centre carry the only error.
            assert!(
                (adaptive - exact).abs() < 1e-5 * exact,
                "k {k} {a}×{b}: {adaptive} vs {exact}"
            );
        }
    }
}

/// max |Σⱼ h₁(e, j) + ½| over the collocation points e of `mesh`.
fn worst_row_sum(mesh: &BoxMesh, q: &QuadRule) -> f64 {
    let mut worst: f64 = 0.0;
    for e in &mesh.elements {
        let sum: f64 = mesh
            .elements
            .iter()
            .map(|el| influence(el, e.centre, q).h1)
            .sum();
        worst = worst.max((sum + 0.5).abs());
    }
    worst
}

#[test]
fn double_layer_rows_sum_to_minus_a_half() {
    let cube = BoxMesh::new(v(-1.0, -1.0, -1.0), v(1.0, 1.0, 1.0), 4).unwrap();
    let slab = BoxMesh::new(v(-2.0, 0.0, -0.5), v(1.0, 1.5, 0.5), 3).unwrap();
    // Coarse to fine: each rule's worst row is within its bound, and the
    // bounds fall by orders of magnitude.
    for mesh in [&cube, &slab] {
        let coarse = worst_row_sum(mesh, &rule(2, 0.5, 4));
        let default = worst_row_sum(mesh, &QuadRule::new(Quadrature::default()).unwrap());
        let fine = worst_row_sum(mesh, &rule(10, 2.0, 14));
        assert!(coarse < 1e-2, "coarse {coarse:.2e}");
        assert!(default < 1e-9, "default {default:.2e}");
        assert!(fine < 1e-13, "fine {fine:.2e}");
        assert!(
            coarse > 10.0 * default,
            "coarse {coarse:.2e} default {default:.2e}"
        );
    }
    // From inside the box the double layer of 1 is −1 (Gauss), from outside 0.
    let q = QuadRule::new(Quadrature::default()).unwrap();
    for (p, want) in [
        (v(0.3, -0.9, 0.95), -1.0),
        (v(0.0, 0.0, 0.0), -1.0),
        (v(1.3, 0.2, 0.0), 0.0),
    ] {
        let sum: f64 = cube.elements.iter().map(|el| influence(el, p, &q).h1).sum();
        assert!((sum - want).abs() < 1e-9, "at {p:?}: {sum}");
    }
}

#[test]
fn near_singular_integrals_agree_with_a_much_finer_rule() {
    let mesh = BoxMesh::new(v(-1.0, -1.0, -1.0), v(1.0, 1.0, 1.0), 2).unwrap();
    let el = &mesh.elements[0];
    let default = QuadRule::new(Quadrature::default()).unwrap();
    let fine = rule(14, 3.0, 16);
    // Points 0.1 and 0.001 of a side from the element, over its edge and its face.
    for off in [0.1, 0.001] {
        for p in [
            el.centre - el.normal * off + el.u * el.a,
            el.centre - el.normal * off + el.u * (0.3 * el.a),
            el.centre + el.u * (el.a + off) - el.normal * off,
        ] {
            let (x, y) = (influence(el, p, &default), influence(el, p, &fine));
            for (a, b) in [(x.g1, y.g1), (x.g2, y.g2), (x.h1, y.h1), (x.h2, y.h2)] {
                assert!((a - b).abs() < 1e-9, "off {off} at {p:?}: {a} vs {b}");
            }
        }
    }
}

#[test]
fn influence_gradients_match_finite_differences() {
    let mesh = BoxMesh::new(v(-1.0, -1.0, -1.0), v(1.0, 1.0, 1.0), 2).unwrap();
    let q = rule(10, 2.0, 14);
    let eps = 1e-5;
    for el in &mesh.elements[..6] {
        for p in [v(0.2, -0.3, 0.1), v(-0.8, -0.7, 0.9)] {
            let g = influence_gradient(el, p, &q);
            for i in 0..3 {
                let e = Vector3::ith(i, eps);
                let (hi, lo) = (influence(el, p + e, &q), influence(el, p - e, &q));
                let fd = [hi.g1 - lo.g1, hi.g2 - lo.g2, hi.h1 - lo.h1, hi.h2 - lo.h2]
                    .map(|d| d / (2.0 * eps));
                let an = [g.g1[i], g.g2[i], g.h1[i], g.h2[i]];
                for (f, a) in fd.iter().zip(an) {
                    assert!(
                        (f - a).abs() < 1e-7 * (1.0 + a.abs()),
                        "{p:?} axis {i}: fd {f} vs {a}"
                    );
                }
            }
        }
    }
}

#[test]
fn bad_settings_are_typed_errors() {
    for q in [
        Quadrature {
            order: 0,
            ..Quadrature::default()
        },
        Quadrature {
            order: 65,
            ..Quadrature::default()
        },
        Quadrature {
            ratio: 0.0,
            ..Quadrature::default()
        },
        Quadrature {
            ratio: f64::NAN,
            ..Quadrature::default()
        },
        Quadrature {
            max_depth: 17,
            ..Quadrature::default()
        },
    ] {
        let e = QuadRule::new(q).unwrap_err();
        assert!(e.to_string().starts_with("quadrature:"), "{e}");
    }
    let e = BoxMesh::new(v(0.0, 0.0, 0.0), v(1.0, 0.0, 1.0), 3).unwrap_err();
    assert!(e.to_string().starts_with("box:"), "{e}");
    let e = BoxMesh::new(v(0.0, 0.0, f64::NAN), v(1.0, 1.0, 1.0), 3).unwrap_err();
    assert!(e.to_string().starts_with("box:"), "{e}");
    for n in [0, 21] {
        let e = BoxMesh::new(v(0.0, 0.0, 0.0), v(1.0, 1.0, 1.0), n).unwrap_err();
        assert!(e.to_string().starts_with("elements:"), "{e}");
    }
}

#[test]
fn the_mesh_covers_the_box_surface() {
    let (lo, hi) = (v(-2.0, 0.0, -0.5), v(1.0, 1.5, 0.5));
    let mesh = BoxMesh::new(lo, hi, 3).unwrap();
    assert_eq!(mesh.elements.len(), 54);
    let area: f64 = mesh.elements.iter().map(Element::area).sum();
    let s = hi - lo;
    assert!((area - 2.0 * (s.x * s.y + s.y * s.z + s.z * s.x)).abs() < 1e-12);
    // Every centre on the surface, its normal pointing out.
    for e in &mesh.elements {
        assert!(!mesh.contains(e.centre));
        assert!(mesh.contains(e.centre - e.normal * 1e-9));
    }
}
