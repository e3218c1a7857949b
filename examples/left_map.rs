//! Where material is left: `cargo run --release --example left_map -- JOB.toml A.nc [B.nc ...]`
//! (cells of 0.1 mm; `LEFT_MAP_RES=0.05` for finer ones)
//! prints the cells farthest above what the last program's tool can reach of
//! the part (simulate::reach) after the programs, with x, y; measured along
//! the part's normal, as `pfcam simulate` measures it, with the part's
//! height and slope there.
use pfcam::simulate::part::part_surface;
use pfcam::simulate::{job_facts, simulate_programs, SimOptions};
fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let job = pfcam::job::load_job(std::path::Path::new(&a[0])).expect("job");
    let res: f64 = std::env::var("LEFT_MAP_RES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0.1);
    let facts = job_facts(&job, res).expect("facts");
    let part = facts.part.clone().expect("part");
    let texts: Vec<(String, String)> = a[1..]
        .iter()
        .map(|f| (f.clone(), std::fs::read_to_string(f).expect("read")))
        .collect();
    let progs: Vec<(&str, &str)> = texts
        .iter()
        .map(|(n, t)| (n.as_str(), t.as_str()))
        .collect();
    let opts = SimOptions {
        resolution: res,
        job: Some(facts),
        ..SimOptions::default()
    };
    let seq = simulate_programs(&progs, &opts).expect("sim");
    let (h, cos) = part_surface(&seq.map, &part);
    // Over what the last program's tool can reach of the part.
    let last = texts
        .last()
        .map(|t| pfcam::simulate::header::read_header(&t.1).tool);
    let env = last
        .flatten()
        .map(|t| pfcam::simulate::reach::envelope(&seq.map.grid, &h, &t));
    let g = seq.map.grid;
    let mut v: Vec<(f64, f64, f64, f64, f64)> = Vec::new();
    for j in 0..g.ny {
        for i in 0..g.nx {
            let p = h[j * g.nx + i];
            let e = env.as_ref().map_or(p, |e| e[j * g.nx + i].max(p));
            if p.is_finite() {
                let k = j * g.nx + i;
                v.push(((seq.map.at(i, j) - e) * cos[k], g.cx(i), g.cy(j), p, cos[k]));
            }
        }
    }
    v.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (d, x, y, z, c) in v.iter().take(12) {
        let deg = c.clamp(-1.0, 1.0).acos().to_degrees();
        println!("{d:.4} at X{x:.2} Y{y:.2} (part z {z:.3}, slope {deg:.0} deg)");
    }
}
