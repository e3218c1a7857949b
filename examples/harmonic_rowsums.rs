//! The harmonic Bézier mould's accuracy per degree, past the cap
//! (docs/method.md §14): `cargo run --release --example harmonic_rowsums [-- MAX_DEGREE]`.
//!
//! Columns: the row-sum error max |Σ_c M_rc − 1|; the solve's relative
//! residual; the largest |coefficient|; the asymmetry (max difference between
//! a coefficient and its mirror under i ↔ m − i and j ↔ n − j, over the
//! largest coefficient); the reproduction error (max |net − exact| over the
//! exact net's size, for every harmonic polynomial of the bidegree, its rows
//! put through the mould).

use pfcam::sources::harmonic_bezier::polynomials::{bernstein_net, harmonic_basis};
use pfcam::sources::harmonic_bezier::{solve_mould, Form, Mould};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let top: usize = std::env::args().nth(1).map_or(Ok(16), |s| s.parse())?;
    println!(
        "{:>3} {:>6} {:>12} {:>10} {:>11} {:>10} {:>10}",
        "n", "form", "row-sum err", "residual", "max |coef|", "asymmetry", "reproduce"
    );
    for n in 1..=top.min(30) {
        let forms: &[Form] = if n % 2 == 0 {
            &[Form::Square, Form::Raised]
        } else {
            &[Form::Square]
        };
        for &form in forms {
            let m = match solve_mould(n, form) {
                Ok(m) => m,
                Err(e) => {
                    println!("{n:>3} {:>6} {e}", form.name());
                    continue;
                }
            };
            let big = (0..m.rows())
                .flat_map(|r| m.row(r).iter().copied())
                .fold(0.0_f64, |a, c| a.max(c.abs()));
            let res = m.residual.map_or("-".to_string(), |r| format!("{r:.1e}"));
            println!(
                "{n:>3} {:>6} {:>12.1e} {res:>10} {big:>11.3e} {:>10.1e} {:>10.1e}",
                form.name(),
                m.row_sum_error,
                asymmetry(&m) / big.max(1.0),
                reproduction_error(&m)
            );
        }
    }
    Ok(())
}

/// max |M(mirror) − mirror(M)| under i ↔ m − i (blocks swap) and j ↔ n − j.
fn asymmetry(m: &Mould) -> f64 {
    let (n, a) = (m.degree, m.across);
    let mut worst = 0.0_f64;
    for i in 1..a {
        for j in 0..=n {
            let (p, q, r) = (
                m.point(i, j).unwrap_or(&[]),
                m.point(a - i, j).unwrap_or(&[]),
                m.point(i, n - j).unwrap_or(&[]),
            );
            for c in 0..=n {
                worst = worst
                    .max((q[c] - p[c + n + 1]).abs())
                    .max((r[c] - p[n - c]).abs())
                    .max((r[c + n + 1] - p[2 * n + 1 - c]).abs());
            }
        }
    }
    worst
}

/// max over the harmonic basis of max |mould net − exact net| / max |exact|.
fn reproduction_error(m: &Mould) -> f64 {
    let (n, a, w) = (m.degree, m.across, m.degree + 1);
    harmonic_basis(a, n)
        .iter()
        .map(|poly| {
            let exact = bernstein_net(poly, a, n);
            let net = m.net(&exact[..w], &exact[a * w..]);
            let size = exact.iter().fold(0.0_f64, |s, c| s.max(c.abs()));
            let err = net
                .iter()
                .zip(&exact)
                .fold(0.0_f64, |s, (x, y)| s.max((x - y).abs()));
            err / size
        })
        .fold(0.0, f64::max)
}
