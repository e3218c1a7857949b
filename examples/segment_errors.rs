//! The errors of `Segment`'s closed forms that docs/shapes.md's table quotes,
//! measured on the cubics of `geometry::segment`'s unit tests (a copy: those
//! are private to the test module) the way those tests measure them, which
//! assert only bounds and print nothing.
//! `cargo run --release --example segment_errors`
use pfcam::geometry::{Segment, Vec2};

fn v(x: f64, y: f64) -> Vec2 {
    Vec2::new(x, y)
}

/// The unit tests' cubics: a glyph serif (paper letter I), an S-bend, a tight
/// loop-like curve, a cusp-free arch, one with a control point on its start,
/// and a true cusp at t = 1/2.
pub fn test_cubics() -> Vec<Segment> {
    let c = |p: [(f64, f64); 4]| Segment::Cubic {
        p0: v(p[0].0, p[0].1),
        p1: v(p[1].0, p[1].1),
        p2: v(p[2].0, p[2].1),
        p3: v(p[3].0, p[3].1),
    };
    vec![
        c([(18.0, 19.0), (103.0, 21.0), (115.0, 38.0), (115.0, 109.0)]),
        c([(0.0, 0.0), (100.0, 200.0), (-50.0, 300.0), (200.0, 100.0)]),
        c([(0.0, 0.0), (300.0, 100.0), (-200.0, 100.0), (100.0, 0.0)]),
        c([(-1.0, 0.0), (-1.0, 0.55), (1.0, 0.55), (1.0, 0.0)]),
        c([(5.0, 5.0), (5.0, 5.0), (40.0, -7.0), (60.0, 30.0)]),
        c([(0.0, 0.0), (10.0, 10.0), (0.0, 10.0), (10.0, 0.0)]),
    ]
}

/// `n` equal parameter steps along the segment.
fn fine(seg: &Segment, n: usize) -> Vec<Vec2> {
    (0..=n).map(|k| seg.eval(k as f64 / n as f64)).collect()
}

/// What the table quotes, in its order.
pub struct Errors {
    /// Largest relative error of `deriv` and of `deriv2` against central
    /// differences (h = 1e-5), the cubics and a line.
    pub deriv: f64,
    pub deriv2: f64,
    /// Largest relative error of `length` against a 2·10⁵-chord flattening.
    pub length: f64,
    /// Largest relative error of `length_to(t_at_length(s))` against s.
    pub t_at_length: f64,
    /// Largest error of `area_term` against a 10⁵-chord shoelace, relative
    /// to the squared length.
    pub area_term: f64,
    /// Smallest and largest curve-to-chord distance of `flatten_into(tol)`,
    /// as a share of tol (tol = 1, 0.1, 0.01, 0.001).
    pub flatten: (f64, f64),
}

pub fn measure() -> Errors {
    let cubics = test_cubics();
    let h = 1e-5;
    let (mut deriv, mut deriv2) = (0.0f64, 0.0f64);
    let line = Segment::Line {
        a: v(1.0, 2.0),
        b: v(-3.0, 7.0),
    };
    for seg in cubics.iter().chain([&line]) {
        let scale = seg.deriv(0.5).norm().max(1.0);
        for k in 1..20 {
            let t = k as f64 / 20.0;
            let fd1 = (seg.eval(t + h) - seg.eval(t - h)) / (2.0 * h);
            let fd2 = (seg.deriv(t + h) - seg.deriv(t - h)) / (2.0 * h);
            deriv = deriv.max((fd1 - seg.deriv(t)).norm() / scale);
            deriv2 = deriv2.max((fd2 - seg.deriv2(t)).norm() / scale);
        }
    }
    let (mut length, mut t_at_length, mut area_term) = (0.0f64, 0.0f64, 0.0f64);
    for seg in &cubics {
        let pts = fine(seg, 200_000);
        let poly: f64 = pts.windows(2).map(|w| w[0].dist(w[1])).sum();
        length = length.max((seg.length() - poly).abs() / poly);
        let total = seg.length();
        for k in 0..=50 {
            let s = total * k as f64 / 50.0;
            let t = seg.t_at_length(s);
            t_at_length = t_at_length.max((seg.length_to(t) - s).abs() / total);
        }
        let pts = fine(seg, 100_000);
        let poly: f64 = pts.windows(2).map(|w| 0.5 * w[0].cross(w[1])).sum();
        area_term = area_term.max((seg.area_term() - poly).abs() / total.powi(2));
    }
    let mut flatten = (f64::INFINITY, 0.0f64);
    for tol in [1.0, 0.1, 0.01, 0.001] {
        for seg in &cubics {
            let mut pts = vec![seg.start()];
            seg.flatten_into(tol, &mut pts);
            let n = pts.len() - 1;
            let mut worst: f64 = 0.0;
            for k in 0..n {
                let (a, b) = (pts[k], pts[k + 1]);
                for j in 1..64 {
                    let p = seg.eval((k as f64 + j as f64 / 64.0) / n as f64);
                    let ab = b - a;
                    let u = ((p - a).dot(ab) / ab.norm2().max(1e-300)).clamp(0.0, 1.0);
                    worst = worst.max(p.dist(a + ab * u));
                }
            }
            flatten = (flatten.0.min(worst / tol), flatten.1.max(worst / tol));
        }
    }
    Errors {
        deriv,
        deriv2,
        length,
        t_at_length,
        area_term,
        flatten,
    }
}

fn main() {
    let e = measure();
    println!("deriv {:.1e}, deriv2 {:.1e}", e.deriv, e.deriv2);
    println!("length {:.1e}", e.length);
    println!("t_at_length round trip {:.1e}", e.t_at_length);
    println!("area_term {:.1e}", e.area_term);
    println!("flatten_into: {:.2}–{:.2} × tol", e.flatten.0, e.flatten.1);
}
