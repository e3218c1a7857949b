//! How close Γ(s) comes to the glyph outline as s → 1, for a job's shape field:
//! Hausdorff distance (polygon to polygon, densified at 0.05 mm, no field used),
//! the number of outline and hole loops, and the field's max boundary error.
//! `cargo run --release --example top_outline -- jobs/mfs-sign.toml 0.99,0.999,0.9999`
use pfcam::field::isolines::{isolines, Grid};
use pfcam::geometry::polygon_area;
use pfcam::geometry::{DistanceIndex, Vec2};

fn densify(loops: &[Vec<Vec2>], step: f64) -> Vec<Vec2> {
    let mut out = Vec::new();
    for l in loops {
        for k in 0..l.len() {
            let (a, b) = (l[k], l[(k + 1) % l.len()]);
            let n = ((b - a).norm() / step).ceil().max(1.0) as usize;
            out.extend((0..n).map(|i| a.lerp(b, i as f64 / n as f64)));
        }
    }
    out
}

/// The largest distance from a point of `from` to `to`, and that point.
fn one_way(from: &[Vec<Vec2>], to: &[Vec<Vec2>]) -> (f64, Vec2) {
    let idx = DistanceIndex::new(to);
    densify(from, 0.05)
        .iter()
        .map(|&p| (idx.distance(p), p))
        .fold((0.0, Vec2::ZERO), |a, b| if b.0 > a.0 { b } else { a })
}

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("usage: top_outline JOB.toml S1,S2,...");
    let ss: Vec<f64> = args
        .next()
        .unwrap_or("0.97,0.99,0.999,0.9999".into())
        .split(',')
        .map(|s| s.parse().expect("a number"))
        .collect();
    let job = pfcam::job::load_job(std::path::Path::new(&path)).unwrap_or_else(|e| panic!("{e}"));
    let (shape, _) = pfcam::pipeline::job_shape(&job, &mut |_| {}).unwrap();
    let tol = job.operation.tolerance * 0.25;
    let t = std::time::Instant::now();
    let (solved, rep, _) = pfcam::pipeline::solve_shape(&shape, &job, tol, &mut |_| {}).unwrap();
    println!(
        "N {} M {} d {:.3} max error {:.3e} ({:.2} s)",
        rep.n,
        rep.m,
        rep.distance,
        rep.max_error,
        t.elapsed().as_secs_f64()
    );
    let polys: Vec<Vec<Vec2>> = shape.contours().map(|c| c.flatten(tol)).collect();
    let (lo, hi) = shape.bbox().unwrap();
    let pad = Vec2::new(5.0, 5.0);
    let grid = Grid::sample(&solved.solution.field, lo - pad, hi + pad, 0.1, &polys);
    let svg_out = args.next();
    let mut svg = String::new();
    let path_of = |loops: &[Vec<Vec2>], colour: &str| {
        let mut d = String::new();
        for l in loops {
            for (k, p) in l.iter().enumerate() {
                d += &format!("{}{:.3} {:.3} ", if k == 0 { "M" } else { "L" }, p.x, -p.y);
            }
            d += "Z ";
        }
        format!("<path d=\"{d}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"0.15\"/>\n")
    };
    svg += &path_of(&polys, "black");
    let colours = ["red", "orange", "green", "blue", "purple", "grey"];
    for (i, s) in ss.into_iter().enumerate() {
        let loops: Vec<Vec<Vec2>> = isolines(&grid, s, &solved.solution.field, &polys)
            .into_iter()
            .map(|r| r.into_points())
            .collect();
        svg += &path_of(&loops, colours[i % colours.len()]);
        let outlines = loops.iter().filter(|l| polygon_area(l) > 0.0).count();
        let (out, at_out) = one_way(&loops, &polys);
        let (inn, at_in) = one_way(&polys, &loops);
        println!(
            "s {s:<8} loops {} (outlines {outlines}, holes {}), Hausdorff to the glyph {:.3} mm; Γ to glyph {out:.3} at ({:.2}, {:.2}), glyph to Γ {inn:.3} at ({:.2}, {:.2})",
            loops.len(),
            loops.len() - outlines,
            out.max(inn),
            at_out.x, at_out.y, at_in.x, at_in.y
        );
    }
    if let Some(f) = svg_out {
        let (a, b) = (lo - pad, hi + pad);
        let doc = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{} {} {} {}\" width=\"{}mm\" height=\"{}mm\">\n<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"white\"/>\n{svg}</svg>\n",
            a.x, -b.y, b.x - a.x, b.y - a.y, b.x - a.x, b.y - a.y, a.x, -b.y, b.x - a.x, b.y - a.y
        );
        std::fs::write(f, doc).expect("write the SVG");
    }
}
