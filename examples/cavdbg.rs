use pfcam::geometry::{build_shape, DistanceIndex};
use pfcam::levels::plan::{plan_levels, LevelJob};
use pfcam::toolpath::zlevel::LevelParams;
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let job = pfcam::job::load_job(std::path::Path::new(&path)).unwrap();
    let shape = build_shape(&job.shape).unwrap();
    let tol = job.operation.tolerance;
    let b = pfcam::pipeline::boundary_for(&shape, tol * 0.05).unwrap();
    let outer = b.radius;
    let prep = pfcam::field::Prepared::new(b).unwrap();
    let n = 110 * shape.regions.len() + 8 + prep.sinks.len() * 6;
    let solved = pfcam::field::solve_auto(&prep, n, None, true).unwrap();
    let glyphs: Vec<_> = shape.contours().map(|c| c.flatten(tol * 0.05)).collect();
    let params = LevelParams {
        radius: job.tool.diameter / 2.0,
        tol,
        stepover: job.tool.stepover,
        ramp_angle: 3.0,
        climb: true,
        feed: 800.0,
        plunge_feed: 200.0,
        safe_z: 5.0,
        top: 0.0,
        stock_lo: Default::default(),
        stock_hi: Default::default(),
    };
    let lj = LevelJob {
        field: &solved.solution.field,
        glyphs: &glyphs,
        profile: job.profile.as_ref().unwrap(),
        cavity: true,
        top: 0.0,
        stepdown: job.tool.stepdown,
        max_scallop: job.operation.max_scallop,
        margin: 5.0,
        outer_radius: outer,
        params,
    };
    let p = plan_levels(&lj).unwrap();
    for (cut, info) in p.cuts.iter().zip(&p.info) {
        let idx = DistanceIndex::new(&cut.part);
        println!(
            "level z {:.3} s {:.4} uncut {:?} paths {}",
            cut.z,
            cut.s,
            info.uncut,
            cut.paths.len()
        );
        for path in &cut.paths {
            let mut m = f64::INFINITY;
            for w in path.points.windows(2) {
                m = m.min(idx.segment_distance(w[0], w[1], 4.0));
            }
            println!(
                "   {} pts {} min clearance {:.4}",
                path.label,
                path.points.len(),
                m - params.radius
            );
        }
    }
}
