//! The harmonic polynomials that fit a bidegree, in the power basis, and
//! their exact Bernstein nets: an independent reference for the mould (they
//! do not go through the linear solve).
//!
//! Re (u + iv)ᵏ and Im (u + iv)ᵏ are harmonic; those whose monomials uᵃvᵇ all
//! have a ≤ m and b ≤ n span the harmonic polynomials of bidegree (m, n)
//! (a harmonic polynomial's homogeneous parts are harmonic, and the
//! homogeneous harmonic polynomials of degree k are spanned by these two).

use super::bernstein::binomial;

/// A polynomial as (power of u, power of v, coefficient) terms.
pub(crate) type Polynomial = Vec<(usize, usize, f64)>;

/// Re (u + iv)ᵏ (`imaginary` false) or Im (u + iv)ᵏ: the terms
/// C(k, b) i^b u^(k−b) v^b with b even (real) or odd (imaginary).
pub fn re_im_power(k: usize, imaginary: bool) -> Polynomial {
    (0..=k)
        .filter(|b| (b % 2 == 1) == imaginary)
        .map(|b| {
            let sign = if (b / 2) % 2 == 0 { 1.0 } else { -1.0 };
            (k - b, b, sign * binomial(k, b))
        })
        .collect()
}

/// The basis of the harmonic polynomials of bidegree (m, n): every nonzero
/// Re/Im (u + iv)ᵏ, k ≤ m + n, that fits. Its size is 2(n + 1) for m = n odd
/// and for m = n + 1, and 2n + 1 for m = n even.
pub fn harmonic_basis(m: usize, n: usize) -> Vec<Polynomial> {
    (0..=m + n)
        .flat_map(|k| [re_im_power(k, false), re_im_power(k, true)])
        .filter(|p| !p.is_empty() && p.iter().all(|&(a, b, _)| a <= m && b <= n))
        .collect()
}

/// The exact Bernstein net, row-major (m + 1) × (n + 1), of a polynomial of
/// bidegree ≤ (m, n): uᵃ = Σ_i C(i, a)/C(m, a) B_i^m(u), likewise vᵇ.
pub fn bernstein_net(p: &[(usize, usize, f64)], m: usize, n: usize) -> Vec<f64> {
    (0..=m)
        .flat_map(|i| (0..=n).map(move |j| (i, j)))
        .map(|(i, j)| {
            p.iter()
                .map(|&(a, b, c)| {
                    c * binomial(i, a) / binomial(m, a) * binomial(j, b) / binomial(n, b)
                })
                .sum()
        })
        .collect()
}

/// The polynomial's value at (u, v).
pub fn eval(p: &[(usize, usize, f64)], u: f64, v: f64) -> f64 {
    p.iter()
        .map(|&(a, b, c)| c * u.powi(a as i32) * v.powi(b as i32))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubes_are_written_out() {
        // (u + iv)³ = u³ − 3uv² + i(3u²v − v³).
        assert_eq!(re_im_power(3, false), vec![(3, 0, 1.0), (1, 2, -3.0)]);
        assert_eq!(re_im_power(3, true), vec![(2, 1, 3.0), (0, 3, -1.0)]);
    }

    #[test]
    fn the_net_evaluates_to_the_polynomial() {
        let p = re_im_power(4, true);
        let net = bernstein_net(&p, 5, 4);
        let (u, v) = (0.3_f64, 0.8_f64);
        let mut s = 0.0;
        for i in 0..=5 {
            for j in 0..=4 {
                s += net[i * 5 + j]
                    * binomial(5, i)
                    * u.powi(i as i32)
                    * (1.0 - u).powi(5 - i as i32)
                    * binomial(4, j)
                    * v.powi(j as i32)
                    * (1.0 - v).powi(4 - j as i32);
            }
        }
        assert!((s - eval(&p, u, v)).abs() < 1e-13);
    }

    /// The dimension count of the module doc (the Laplacian system's kernel).
    #[test]
    fn basis_sizes() {
        assert_eq!(harmonic_basis(3, 3).len(), 8);
        assert_eq!(harmonic_basis(4, 4).len(), 9);
        assert_eq!(harmonic_basis(5, 4).len(), 10);
    }
}
