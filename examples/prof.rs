use std::time::Instant;
fn main() {
    let t = Instant::now();
    let prep = pfcam::field::Prepared::new(pfcam::field::paper_boundary('I').unwrap()).unwrap();
    println!(
        "prepare {:?} edges {}",
        t.elapsed(),
        prep.polygons().iter().map(|p| p.len()).sum::<usize>()
    );
    let layout = pfcam::field::Layout {
        n_total: 516,
        distance: 4.0,
        corner_clusters: true,
        corner_fraction: 0.4,
    };
    let t = Instant::now();
    let pr = prep.problem(&layout).unwrap();
    println!("problem {:?}", t.elapsed());
    let t = Instant::now();
    let s = pfcam::field::mfs::solve(&pr).unwrap();
    println!("solve {:?} err {:e}", t.elapsed(), s.max_error);
}
