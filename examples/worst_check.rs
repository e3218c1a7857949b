//! Where a job's shape field errs most: its ten worst check points.
//! `cargo run --release --example worst_check -- JOB.toml`
fn main() {
    let path = std::env::args().nth(1).expect("JOB.toml");
    let job = pfcam::job::load_job(std::path::Path::new(&path)).expect("job");
    let (shape, _) = pfcam::pipeline::job_shape(&job, &mut |_| {}).expect("shape");
    let flat = job.operation.tolerance * pfcam::pipeline::FLATTEN_FRACTION;
    let (solved, report, _) =
        pfcam::pipeline::solve_shape(&shape, &job, flat, &mut |_| {}).expect("solve");
    println!("N {} error {:.3e}", report.n, report.max_error);
    let f = &solved.solution.field;
    let mut e: Vec<(f64, f64, f64)> = solved
        .solution
        .checks
        .iter()
        .map(|c| ((f.value(c.p) - c.value).abs(), c.p.x, c.p.y))
        .collect();
    e.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (err, x, y) in e.iter().take(10) {
        println!("{err:.3e} at ({x:.3}, {y:.3})");
    }
    let (_, wx, wy) = e[0];
    for c in shape.contours() {
        let pts = c.flatten(flat);
        for (i, p) in pts.iter().enumerate() {
            if (p.x - wx).hypot(p.y - wy) < 1.0 {
                let a = pts[(i + pts.len() - 1) % pts.len()];
                let b = pts[(i + 1) % pts.len()];
                let turn = (p.x - a.x) * (b.y - p.y) - (p.y - a.y) * (b.x - p.x);
                let la = (p.x - a.x).hypot(p.y - a.y);
                let lb = (b.x - p.x).hypot(b.y - p.y);
                println!(
                    "  v {i} ({:.4}, {:.4}) turn {:.4} rad",
                    p.x,
                    p.y,
                    (turn / la / lb).asin()
                );
            }
        }
    }
}
