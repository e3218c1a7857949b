//! Prints the per-level figures of a boss or cavity job: z, s, N, max boundary
//! error, the gouge check's clearance, for a cavity the uncut share of the
//! reachable area, and where the time went.
//! `cargo run --release --example levels_report -- jobs/mfs-mould.toml [OUT.nc]`
//! (with OUT.nc, the G-code is written there without `pfcam run`'s own
//! simulation, to look at a program that run refuses with `pfcam simulate`).
use std::time::Instant;

fn main() {
    let path = std::env::args()
        .nth(1)
        .expect("usage: levels_report JOB.toml");
    let job = pfcam::job::load_job(std::path::Path::new(&path)).unwrap_or_else(|e| panic!("{e}"));
    let t = Instant::now();
    let out = pfcam::pipeline::run(&job, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    let total = t.elapsed().as_secs_f64();
    println!(
        "{} levels in {total:.2} s, min clearance {:.4} mm",
        out.levels.len(),
        out.min_clearance
    );
    let mut worst: f64 = 0.0;
    let (mut ts, mut tp) = (0.0, 0.0);
    for l in &out.levels {
        println!(
            "z {:8.3}  s {:.4}  N {:4}  max error {:.2e}  clearance {:+.4}  uncut {}  solve {:.3} s  paths {:.3} s",
            l.z,
            l.s,
            l.n,
            l.max_error,
            l.min_clearance,
            l.uncut.map_or("-".into(), |u| format!("{:.4} %", 100.0 * u)),
            l.t_solve,
            l.t_paths
        );
        worst = worst.max(l.uncut.unwrap_or(0.0));
        ts += l.t_solve;
        tp += l.t_paths;
    }
    println!("worst uncut share: {:.4} %", 100.0 * worst);
    println!("grid, contours and schedule {:.2} s; level solves {ts:.2} s; tracing and clearing {tp:.2} s (the last two summed over levels, which run in parallel)", out.t_schedule);
    for w in &out.warnings {
        println!("warning: {w}");
    }
    if let Some(nc) = std::env::args().nth(2) {
        let g = pfcam::gcode::write_gcode_on(&out.toolpath, &job, out.stock)
            .unwrap_or_else(|e| panic!("{e}"));
        std::fs::write(&nc, g).unwrap_or_else(|e| panic!("{nc}: {e}"));
        println!("wrote {nc} (not simulated)");
    }
}
