//! Max boundary error of a paper glyph's paired layout against the
//! pseudo-boundary distance d (in units of h = perimeter / N) and the corner
//! share f: `cargo run --release --example dscan -- I 800`.
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let ch = args.get(1).and_then(|s| s.chars().next()).unwrap_or('I');
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(800);
    let prep = pfcam::field::Prepared::new(pfcam::field::paper_boundary(ch).unwrap()).unwrap();
    let h = prep.perimeter() / n as f64;
    for f in [0.3, 0.4, 0.5] {
        let row: Vec<String> = [0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 8.0]
            .iter()
            .map(|&r| {
                let layout = pfcam::field::Layout {
                    n_total: n,
                    distance: r * h,
                    corner_clusters: true,
                    corner_fraction: f,
                    pairs: true,
                };
                match pfcam::field::solve_layout(&prep, &layout) {
                    Ok((s, _)) => format!("{:.1e}", s.max_error),
                    Err(e) => format!("{e}"),
                }
            })
            .collect();
        println!("{ch} N {n} f {f}: {}", row.join(" "));
    }
}
