fn main() {
    let args: Vec<String> = std::env::args().collect();
    let ch = args.get(1).and_then(|s| s.chars().next()).unwrap_or('I');
    let frac: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0.4);
    let ns: Vec<usize> = args
        .get(3)
        .map(|s| s.split(',').map(|x| x.parse().unwrap()).collect())
        .unwrap_or(vec![78, 148, 272, 396, 516]);
    let prep = pfcam::field::Prepared::new(pfcam::field::paper_boundary(ch).unwrap()).unwrap();
    for n in ns {
        let base = pfcam::field::Layout {
            n_total: n,
            distance: 1.0,
            corner_clusters: frac > 0.0,
            corner_fraction: frac,
            pairs: false,
        };
        match pfcam::field::solve_with(&prep, base, None) {
            Ok(s) => println!(
                "frac {frac} n {n} m {} d {:.3} err {:.3e} cond {:.1e}",
                s.m, s.layout.distance, s.solution.max_error, s.solution.condition
            ),
            Err(e) => println!("n {n} err {e}"),
        }
    }
}
