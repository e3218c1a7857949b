//! Field evaluations, kernel pairs, expansion terms, distance queries and
//! drop-cutter drops per pipeline stage, for each job given (issue 13), on one
//! thread so that the stages follow each other and their seconds add up:
//! `cargo run --release --features count-evals --example count_evals -- jobs/mfs-sign.toml ...`
//! (`pipeline::run`, as `cargo bench --bench pfcam -- shipped` times it;
//! `pfcam run` also simulates the program, draws the preview and writes files).
//! With `--json` one JSON object per job.
use pfcam::count;

fn main() {
    let mut json = false;
    let mut paths = Vec::new();
    for a in std::env::args().skip(1) {
        if a == "--json" {
            json = true;
        } else {
            paths.push(a);
        }
    }
    assert!(
        !paths.is_empty(),
        "usage: count_evals [--json] JOB.toml ..."
    );
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    for path in paths {
        let job =
            pfcam::job::load_job(std::path::Path::new(&path)).unwrap_or_else(|e| panic!("{e}"));
        count::take();
        count::set_stage(count::Stage::Other);
        let t = std::time::Instant::now();
        pool.install(|| pfcam::pipeline::run(&job, &mut |_| {}))
            .unwrap_or_else(|e| panic!("{path}: {e}"));
        let total = t.elapsed().as_secs_f64();
        let rows = count::take();
        if json {
            let stages: Vec<serde_json::Value> = rows
                .iter()
                .map(|(s, c)| {
                    serde_json::json!({
                        "stage": s.name(), "seconds": c.seconds, "evals": c.evals,
                        "pairs": c.pairs, "terms": c.terms, "queries": c.queries, "drops": c.drops
                    })
                })
                .collect();
            println!(
                "{}",
                serde_json::json!({"job": job.name, "seconds": total, "stages": stages})
            );
            continue;
        }
        println!("{} ({path}): {total:.2} s on one thread", job.name);
        println!(
            "  {:<26} {:>8} {:>14} {:>16} {:>14} {:>14} {:>10}",
            "stage",
            "seconds",
            "evaluations",
            "kernel pairs",
            "exp. terms",
            "dist. queries",
            "drops"
        );
        let mut sum = count::Counts::default();
        for (s, c) in &rows {
            println!(
                "  {:<26} {:>8.2} {:>14} {:>16} {:>14} {:>14} {:>10}",
                s.name(),
                c.seconds,
                c.evals,
                c.pairs,
                c.terms,
                c.queries,
                c.drops
            );
            sum.seconds += c.seconds;
            sum.evals += c.evals;
            sum.pairs += c.pairs;
            sum.terms += c.terms;
            sum.queries += c.queries;
            sum.drops += c.drops;
        }
        println!(
            "  {:<26} {:>8.2} {:>14} {:>16} {:>14} {:>14} {:>10}",
            "total", sum.seconds, sum.evals, sum.pairs, sum.terms, sum.queries, sum.drops
        );
    }
}
