//! Prints the per-level figures of a boss or cavity job (z, s, N, max boundary
//! error, and for a cavity the uncut share of the reachable area).
//! `cargo run --release --example levels_report -- jobs/mfs-mould.toml`
fn main() {
    let path = std::env::args()
        .nth(1)
        .expect("usage: levels_report JOB.toml");
    let job = pfcam::job::load_job(std::path::Path::new(&path)).unwrap_or_else(|e| panic!("{e}"));
    let t = std::time::Instant::now();
    let out = pfcam::pipeline::run(&job, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    println!(
        "{} levels in {:.2?}, min clearance {:.4} mm",
        out.levels.len(),
        t.elapsed(),
        out.min_clearance
    );
    let mut worst: f64 = 0.0;
    for l in &out.levels {
        println!(
            "z {:8.3}  s {:.4}  N {:4}  max error {:.2e}  uncut {}",
            l.z,
            l.s,
            l.n,
            l.max_error,
            l.uncut
                .map_or("-".into(), |u| format!("{:.4} %", 100.0 * u))
        );
        worst = worst.max(l.uncut.unwrap_or(0.0));
    }
    println!("worst uncut share: {:.4} %", 100.0 * worst);
    for w in &out.warnings {
        println!("warning: {w}");
    }
}
