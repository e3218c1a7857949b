//! The drop of a ball onto triangles, exactly: the lowest centre height at
//! which a ball of radius r, centred over (x, y), touches a triangle without
//! entering any. It is the largest of the heights at which the ball touches
//! each triangle's face, edges and corners:
//! - the face (plane with upward unit normal n): the ball touches it at
//!   (x, y) − r·n_xy, centre height = the plane's height there + r·n_z, if
//!   that point lies inside the triangle;
//! - an edge (the line A + t·D, 0 ≤ t ≤ 1): the centre C = (x, y, z) lies r
//!   from the line, |C − A|² − ((C − A)·D)²/|D|² = r², a quadratic in z (its
//!   larger root), if the foot of C on the line lies within the edge;
//! - a corner V within r in plan: z = V_z + √(r² − d²).
//!
//! Independent of the tool-path code's drop-cutter: `simulate` checks the
//! programs, so it must not share their geometry.

type V3 = [f64; 3];

/// The centre height of a ball of radius `r` over (`x`, `y`) touching
/// triangle `t` (its face, edges or corners), or −∞ where it cannot.
pub(crate) fn ball_on_triangle(t: &[V3; 3], x: f64, y: f64, r: f64) -> f64 {
    let mut z = f64::NEG_INFINITY;
    for v in t {
        let d2 = (v[0] - x).powi(2) + (v[1] - y).powi(2);
        if d2 <= r * r {
            z = z.max(v[2] + (r * r - d2).sqrt());
        }
    }
    for k in 0..3 {
        z = z.max(on_edge(t[k], t[(k + 1) % 3], x, y, r));
    }
    z.max(on_face(t, x, y, r))
}

/// The ball touching the segment a–b (see the module docs); −∞ if the
/// contact lies off the segment or the edge is vertical (its corners then
/// decide).
fn on_edge(a: V3, b: V3, x: f64, y: f64, r: f64) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let qa = 1.0 - d[2] * d[2] / l2;
    if l2 == 0.0 || qa <= 1e-12 {
        return f64::NEG_INFINITY;
    }
    // C − A = e + z·ẑ.
    let e = [x - a[0], y - a[1], -a[2]];
    let ed = e[0] * d[0] + e[1] * d[1] + e[2] * d[2];
    let ee = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
    let qb = 2.0 * e[2] - 2.0 * ed * d[2] / l2;
    let qc = ee - ed * ed / l2 - r * r;
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 {
        return f64::NEG_INFINITY;
    }
    let z = (-qb + disc.sqrt()) / (2.0 * qa);
    let t = (ed + z * d[2]) / l2;
    if (0.0..=1.0).contains(&t) {
        z
    } else {
        f64::NEG_INFINITY
    }
}

/// The ball touching the triangle's face (see the module docs); −∞ if the
/// contact lies outside it or the face is vertical.
fn on_face(t: &[V3; 3], x: f64, y: f64, r: f64) -> f64 {
    let u = [t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]];
    let w = [t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]];
    let mut n = [
        u[1] * w[2] - u[2] * w[1],
        u[2] * w[0] - u[0] * w[2],
        u[0] * w[1] - u[1] * w[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len == 0.0 || (n[2] / len).abs() < 1e-12 {
        return f64::NEG_INFINITY;
    }
    let s = n[2].signum() / len;
    n = [n[0] * s, n[1] * s, n[2] * s];
    let (px, py) = (x - r * n[0], y - r * n[1]);
    // Barycentric coordinates of (px, py) in the triangle's plan.
    let det = u[0] * w[1] - u[1] * w[0];
    if det == 0.0 {
        return f64::NEG_INFINITY;
    }
    let (qx, qy) = (px - t[0][0], py - t[0][1]);
    let bu = (qx * w[1] - qy * w[0]) / det;
    let bw = (u[0] * qy - u[1] * qx) / det;
    if bu < 0.0 || bw < 0.0 || bu + bw > 1.0 {
        return f64::NEG_INFINITY;
    }
    t[0][2] + bu * u[2] + bw * w[2] + r * n[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest z + √(r² − d²) over a fine sampling of the triangle (a
    /// lower bound of the exact drop, within the sampling's reach of it).
    fn sampled(t: &[V3; 3], x: f64, y: f64, r: f64, n: usize) -> f64 {
        let mut best = f64::NEG_INFINITY;
        for i in 0..=n {
            for j in 0..=(n - i) {
                let (a, b) = (i as f64 / n as f64, j as f64 / n as f64);
                let q: Vec<f64> = (0..3)
                    .map(|k| t[0][k] + a * (t[1][k] - t[0][k]) + b * (t[2][k] - t[0][k]))
                    .collect();
                let d2 = (q[0] - x).powi(2) + (q[1] - y).powi(2);
                if d2 <= r * r {
                    best = best.max(q[2] + (r * r - d2).sqrt());
                }
            }
        }
        best
    }

    #[test]
    fn a_ball_on_a_level_face_rests_r_above_it() {
        let t = [[0.0, 0.0, -2.0], [4.0, 0.0, -2.0], [0.0, 4.0, -2.0]];
        assert!((ball_on_triangle(&t, 1.0, 1.0, 1.5) - (-0.5)).abs() < 1e-12);
    }

    /// On steep, tilted and level triangles, over points inside, beside and
    /// beyond them: the exact drop is never below the sampled one and within
    /// the sampling's error of it.
    #[test]
    fn the_drop_matches_a_fine_sampling_of_the_triangle() {
        let tris: [[V3; 3]; 3] = [
            [[0.0, 0.0, 0.0], [1.0, 0.1, 0.3], [0.2, 1.0, -0.4]],
            [[0.0, 0.0, 0.0], [0.05, 0.0, -2.0], [0.0, 1.0, 0.0]],
            [[-1.0, -0.5, 1.0], [1.5, 0.2, 1.0], [0.1, 1.2, 1.0]],
        ];
        let r = 1.5875;
        let mut compared = 0;
        for t in &tris {
            for i in -6..=6 {
                for j in -6..=6 {
                    let (x, y) = (0.3 * i as f64, 0.3 * j as f64);
                    let exact = ball_on_triangle(t, x, y, r);
                    let s = sampled(t, x, y, r, 400);
                    if s == f64::NEG_INFINITY {
                        assert_eq!(exact, f64::NEG_INFINITY, "{t:?} at {x} {y}");
                        continue;
                    }
                    assert!(exact >= s - 1e-12, "{t:?} at {x} {y}: {exact} < {s}");
                    assert!(exact - s < 2e-3, "{t:?} at {x} {y}: {exact} vs {s}");
                    compared += 1;
                }
            }
        }
        assert!(compared > 300, "{compared}");
    }
}
