use super::*;
use crate::sources::polyharmonic::gauss::GaussRule;

const ALL: [Kernel; 5] = [
    Kernel::T1,
    Kernel::T2,
    Kernel::T3,
    Kernel::T1A { a: 0.3 },
    Kernel::T2A { a: 0.3 },
];

fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
    Vector3::new(x, y, z)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// ∫_{|y| ≤ A} T*(|x − y|) dy for |x| = r, numerically: in spherical shells ρ
/// around the ball's centre and the distance s = |x − y| on each shell
/// (dμ = s ds / (rρ)), Gauss–Legendre in ρ (split at ρ = r, where |r − ρ|
/// kinks) and in s.
fn ball_integral_shells(point: Kernel, a: f64, r: f64) -> f64 {
    let rule = GaussRule::new(24);
    let shell = |rho: f64| {
        let inner = rule.integrate((r - rho).abs(), r + rho, |s| point.radial(s).f * s);
        2.0 * PI * rho / r * inner
    };
    if r < a {
        rule.integrate(0.0, r, shell) + rule.integrate(r, a, shell)
    } else {
        rule.integrate(0.0, a, shell)
    }
}

/// The same integral as a plain tensor rule in (ρ, θ, φ) about the ball's
/// centre, for a point x off every axis outside the ball (smooth integrand).
fn ball_integral_tensor(point: Kernel, a: f64, x: Vector3<f64>) -> f64 {
    // 40 points per axis: 1e-13 for |x| = 2A (20 points give 4e-8).
    let rule = GaussRule::new(40);
    rule.integrate(0.0, a, |rho| {
        rule.integrate(0.0, PI, |theta| {
            let (st, ct) = theta.sin_cos();
            rule.integrate(0.0, 2.0 * PI, |phi| {
                let y = v(rho * st * phi.cos(), rho * st * phi.sin(), rho * ct);
                point.value(x - y) * rho * rho * st
            })
        })
    })
}

#[test]
fn spread_kernels_match_a_numerical_ball_integral() {
    for a in [0.3, 1.0, 2.5] {
        for frac in [0.1, 0.5, 0.9, 0.999, 1.001, 1.5, 4.0] {
            let r = frac * a;
            for (spread, point) in [
                (Kernel::T1A { a }, Kernel::T1),
                (Kernel::T2A { a }, Kernel::T2),
            ] {
                let num = ball_integral_shells(point, a, r);
                let got = spread.radial(r).f;
                assert!(rel(got, num) < 1e-12, "{spread:?} r {r}: {got} vs {num}");
            }
        }
        let x = v(0.7, -1.1, 0.4) * (1.5 * a);
        for (spread, point) in [
            (Kernel::T1A { a }, Kernel::T1),
            (Kernel::T2A { a }, Kernel::T2),
        ] {
            let num = ball_integral_tensor(point, a, x);
            let e = rel(spread.value(x), num);
            assert!(e < 1e-11, "{spread:?}: {num} (relative error {e:.2e})");
        }
    }
}

#[test]
fn spread_kernels_and_gradients_are_continuous_at_the_ball() {
    for a in [0.05, 0.3, 1.7] {
        for k in [Kernel::T1A { a }, Kernel::T2A { a }] {
            let (lo, hi) = (k.radial(a * (1.0 - 1e-12)), k.radial(a * (1.0 + 1e-12)));
            let scale = k.radial(a).f;
            assert!((lo.f - hi.f).abs() < 1e-10 * scale, "{k:?} value");
            // f' = g r, and the gradient is g·d: compare f' (scale f/A).
            let (dlo, dhi) = (lo.g * a, hi.g * a);
            assert!(
                (dlo - dhi).abs() < 1e-10 * scale / a,
                "{k:?} f': {dlo} {dhi}"
            );
            let d = v(0.6, -0.48, 0.64) * a;
            let (gi, go) = (k.gradient(d * (1.0 - 1e-12)), k.gradient(d * (1.0 + 1e-12)));
            assert!((gi - go).norm() < 1e-10 * scale / a);
        }
    }
    // The closed forms at r = A: A²/3, −A/3, A⁴/5, 4A³/30.
    let a: f64 = 0.7;
    let (r1, r2) = (Kernel::T1A { a }.radial(a), Kernel::T2A { a }.radial(a));
    assert!(rel(r1.f, a * a / 3.0) < 1e-15 && rel(r1.g * a, -a / 3.0) < 1e-15);
    assert!(rel(r2.f, a.powi(4) / 5.0) < 1e-15 && rel(r2.g * a, 4.0 * a.powi(3) / 30.0) < 1e-15);
}

#[test]
fn spread_kernels_tend_to_the_point_kernels_times_the_ball_volume() {
    let d = v(0.3, 0.5, -0.4);
    for (spread, point) in [(1usize, Kernel::T1), (2, Kernel::T2)] {
        let mut last = f64::INFINITY;
        for a in [0.2, 0.05, 0.0125, 0.003125] {
            let k = if spread == 1 {
                Kernel::T1A { a }
            } else {
                Kernel::T2A { a }
            };
            let vol = 4.0 * PI * a * a * a / 3.0;
            let e = rel(k.value(d) / vol, point.value(d));
            let eg = (k.gradient(d) / vol - point.gradient(d)).norm() / point.gradient(d).norm();
            // T*₁A is exactly vol·T*₁ outside the ball; T*₂A differs by
            // A⁵/(30r), relative A²/(5r²): each halving of A quarters it.
            assert!(e < 0.3 * last + 1e-15 && e < a * a, "T{spread}A a {a}: {e}");
            assert!(
                eg < 2.0 * a * a / d.norm_squared(),
                "T{spread}A a {a}: grad {eg}"
            );
            last = e;
        }
    }
}

#[test]
fn gradients_and_hessians_match_finite_differences() {
    let pts = [v(0.7, -0.2, 0.4), v(0.1, 0.05, -0.12), v(-1.3, 2.0, 0.5)];
    let eps = 1e-5;
    for k in ALL {
        for d in pts {
            let r = k.radial(d.norm());
            let mut hess_err: f64 = 0.0;
            let mut grad_err: f64 = 0.0;
            for i in 0..3 {
                let mut e = Vector3::zeros();
                e[i] = eps;
                let fd = (k.value(d + e) - k.value(d - e)) / (2.0 * eps);
                grad_err = grad_err.max((fd - k.gradient(d)[i]).abs());
                let fdg = (k.gradient(d + e) - k.gradient(d - e)) / (2.0 * eps);
                for j in 0..3 {
                    let exact = r.h * d[i] * d[j] + if i == j { r.g } else { 0.0 };
                    hess_err = hess_err.max((fdg[j] - exact).abs());
                }
            }
            let scale = k.gradient(d).norm().max(k.value(d).abs());
            assert!(grad_err < 1e-8 * scale, "{k:?} at {d:?}: grad {grad_err}");
            assert!(
                hess_err < 1e-6 * scale / d.norm(),
                "{k:?} at {d:?}: hess {hess_err}"
            );
        }
    }
}

/// The 7-point finite-difference Laplacian of the value, Richardson-extrapolated
/// from steps 0.01|d| and 0.005|d| (error O(step⁴)).
fn fd_laplacian(k: Kernel, d: Vector3<f64>) -> f64 {
    let eps = 0.01 * d.norm();
    (4.0 * fd_laplacian_step(k, d, 0.5 * eps) - fd_laplacian_step(k, d, eps)) / 3.0
}

fn fd_laplacian_step(k: Kernel, d: Vector3<f64>, eps: f64) -> f64 {
    let mut sum = -6.0 * k.value(d);
    for i in 0..3 {
        let mut e = Vector3::zeros();
        e[i] = eps;
        sum += k.value(d + e) + k.value(d - e);
    }
    sum / (eps * eps)
}

#[test]
fn each_kernel_is_the_laplacian_of_the_next() {
    let a = 0.3;
    for d in [v(0.7, -0.2, 0.4), v(1.5, 0.9, -2.0), v(0.1, 0.05, -0.12)] {
        for (up, down) in [
            (Kernel::T2, Kernel::T1),
            (Kernel::T3, Kernel::T2),
            (Kernel::T2A { a }, Kernel::T1A { a }),
        ] {
            let (lap, want) = (fd_laplacian(up, d), down.value(d));
            assert!(rel(lap, want) < 1e-7, "Δ{up:?} at {d:?}: {lap} vs {want}");
        }
        let inside = d.norm() < a;
        let lap1 = fd_laplacian(Kernel::T1A { a }, d);
        let want = if inside { -1.0 } else { 0.0 };
        assert!((lap1 - want).abs() < 1e-7, "ΔT1A at {d:?}: {lap1}");
        let lap0 = fd_laplacian(Kernel::T1, d);
        let scale = Kernel::T1.value(d) / d.norm_squared();
        assert!(lap0.abs() < 1e-7 * scale, "ΔT1 at {d:?}: {lap0}");
    }
}

#[test]
fn a_ball_radius_must_be_positive_and_finite() {
    for a in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        for k in [Kernel::T1A { a }, Kernel::T2A { a }] {
            let e = k.validated().unwrap_err();
            assert!(e.to_string().starts_with("kernel.a:"), "{e}");
        }
    }
    assert_eq!(
        Kernel::T2A { a: 0.3 }.validated(),
        Ok(Kernel::T2A { a: 0.3 })
    );
    assert_eq!(Kernel::T3.validated(), Ok(Kernel::T3));
}
