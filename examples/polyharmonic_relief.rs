//! The relief's speed and accuracy (docs/method.md §17, "Speed"): the fast
//! field against the exact one, the relief against direct rays, and the time
//! of a 0.2 mm grid of h. `cargo run --release --example polyharmonic_relief`.

use nalgebra::Vector3;
use pfcam::sources::polyharmonic::{
    solve, Envelope, FastField, GivenPoint, Kernel, Model, PointKind, Quadrature, Relief,
    ReliefSpec,
};
use std::time::Instant;

/// The face of jobs/polyharmonic-face.toml, read from its CSV file.
fn face() -> Vec<GivenPoint> {
    let text = std::fs::read_to_string("jobs/polyharmonic-face.csv").expect("the face's points");
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('x') && !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let n = |k: usize| f[k].trim().parse::<f64>().expect("a number");
            let kind = match f[3].trim() {
                "inside" => PointKind::Inside,
                "outside" => PointKind::Outside,
                _ => PointKind::Surface,
            };
            GivenPoint {
                p: Vector3::new(n(0), n(1), n(2)),
                kind,
            }
        })
        .collect()
}

fn main() {
    let a: f64 = std::env::args().nth(1).map_or(4.0, |s| s.parse().unwrap());
    let spacing: f64 = std::env::args().nth(2).map_or(2.0, |s| s.parse().unwrap());
    let order: usize = std::env::args().nth(3).map_or(4, |s| s.parse().unwrap());
    let model = Model {
        lo: Vector3::new(-40.0, -40.0, -50.0),
        hi: Vector3::new(110.0, 130.0, 60.0),
        per_edge: 6,
        kernel: Kernel::T2A { a },
        points: face(),
        quadrature: Quadrature::default(),
    };
    let t = Instant::now();
    let sol = solve(&model).expect("solve");
    println!(
        "solve {:.3} s, condition {:.3e}, M = {}",
        t.elapsed().as_secs_f64(),
        sol.condition,
        model.points.len()
    );
    let zmax = 13.0;
    let start = zmax + 0.25 * (60.0 - zmax);
    let (lo, hi) = (
        Vector3::new(0.0, 0.0, -0.5),
        Vector3::new(70.0, 90.0, start),
    );
    let t = Instant::now();
    let fast = FastField::new(sol.clone(), lo, hi, spacing, order).expect("fast");
    println!(
        "fast field {:.3} s (spacing {spacing}, order {order})",
        t.elapsed().as_secs_f64()
    );
    let mut worst: f64 = 0.0;
    let mut worst_g: f64 = 0.0;
    for k in 0..400 {
        let u = (k as f64 * 0.618_033_988_7).fract();
        let x = Vector3::new(
            70.0 * u,
            90.0 * (3.0 * u).fract(),
            -0.5 + (start + 0.5) * (7.0 * u).fract(),
        );
        worst = worst.max((fast.value(x) - sol.value(x).unwrap()).abs());
        worst_g = worst_g.max((fast.gradient(x) - sol.gradient(x).unwrap()).norm());
    }
    println!("max |T1 fast - exact| = {worst:.3e}, max |grad diff| = {worst_g:.3e} (400 points)");
    let spec = ReliefSpec {
        origin: [0.0, 0.0],
        size: [70.0, 90.0],
        base: 0.0,
        start,
        step: 0.5,
        coarse: 1.0,
    };
    let t = Instant::now();
    let relief = Relief::new(fast, spec).expect("relief");
    println!("coarse rays {:.3} s", t.elapsed().as_secs_f64());
    let env = Envelope {
        step: 0.05,
        tol: 1e-9,
    };
    let (mut dmax, mut hmax, mut slope): (f64, f64, f64) = (0.0, 0.0, 0.0);
    let t = Instant::now();
    for k in 0..150 {
        let u = (k as f64 * 0.618_033_988_7).fract();
        let (x, y) = (70.0 * u, 90.0 * (3.0 * u).fract());
        let direct = env.height(&sol, x, y).map_or(0.0, |z| z.max(0.0));
        let h = relief.height(x, y);
        dmax = dmax.max((direct - h).abs());
    }
    println!(
        "max |relief - direct| = {dmax:.3e} over 150 rays ({:.2} s direct+relief)",
        t.elapsed().as_secs_f64()
    );
    let t = Instant::now();
    use rayon::prelude::*;
    let (nx, ny) = (351, 451);
    let hs: Vec<f64> = (0..nx * ny)
        .into_par_iter()
        .map(|k| relief.height((k % nx) as f64 * 0.2, (k / nx) as f64 * 0.2))
        .collect();
    println!(
        "0.2 mm grid {nx} x {ny}: {:.2} s",
        t.elapsed().as_secs_f64()
    );
    let mut at = (0.0, 0.0);
    let mut steep = 0;
    for (k, h) in hs.iter().enumerate() {
        hmax = hmax.max(*h);
        if k % 7 == 0 {
            let (x, y) = ((k % nx) as f64 * 0.2, (k / nx) as f64 * 0.2);
            let g = relief.gradient_at(x, y, *h);
            let m = g[0].hypot(g[1]);
            steep += usize::from(m > 0.9);
            if m > slope {
                (slope, at) = (m, (x, y));
            }
        }
    }
    println!(
        "max h {hmax:.3}, max slope {slope:.3} at {at:?}, {steep} of {} samples steeper than 0.9",
        hs.len() / 7
    );
    // A picture: ASCII
    for j in (0..ny).step_by(20).rev() {
        let row: String = (0..nx)
            .step_by(8)
            .map(|i| {
                let h = hs[j * nx + i];
                b" .:-=+*#%@"[((h / hmax * 9.0).round() as usize).min(9)] as char
            })
            .collect();
        println!("{row}");
    }
}
