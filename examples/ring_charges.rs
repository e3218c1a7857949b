//! How many charges the outer ring or a sink ring needs: one of the paper's
//! glyphs solved with N singularities (the distance chosen as pfcam chooses it,
//! corner share 0.4), then solved again at that distance with the ring's
//! charges replaced by `count` charges on the same circle (2 × count
//! collocation points on the ring, the layout's check points between them).
//! Prints the max boundary error over all check points and over the ring's.
//! docs/method.md §3 and §3a quote it.
//! `cargo run --release --example ring_charges -- I 516 plain outer 4,8`
//! (GLYPH N plain|pairs outer|sink COUNTS)
use pfcam::field::setup::Groups;
use pfcam::field::{self, mfs, Layout, Prepared, Problem};
use pfcam::geometry::Vec2;
use std::f64::consts::TAU;

/// `count` charges on a circle of radius `charge_radius` about `centre`, with
/// 2 × count collocation points of u = 0 on the circle of radius `radius` and
/// `checks` check points between neighbouring ones: the layout's own circle
/// (`field::setup`), with another count.
fn ring(centre: Vec2, radius: f64, charge_radius: f64, count: usize, checks: usize) -> Problem {
    let at = |a: f64, r: f64| centre + Vec2::new(a.cos(), a.sin()) * r;
    let zero = |p| mfs::Condition { p, value: 0.0 };
    let mut pr = Problem::default();
    for j in 0..count {
        pr.charges
            .push(at(TAU * (j as f64 + 0.25) / count as f64, charge_radius));
    }
    for j in 0..2 * count {
        pr.colloc
            .push(zero(at(TAU * j as f64 / (2 * count) as f64, radius)));
        for q in 1..=checks {
            let a = TAU * (j as f64 + q as f64 / (checks + 1) as f64) / (2 * count) as f64;
            pr.checks.push(zero(at(a, radius)));
        }
    }
    pr
}

/// One solve with a ring of `count` charges.
pub struct RingSolve {
    pub count: usize,
    /// Singularities in all.
    pub n: usize,
    /// Max boundary error over all check points.
    pub max_error: f64,
    /// Max boundary error over the ring's check points.
    pub on_ring: f64,
}

/// The paper's glyph `ch` laid out with `n` singularities (`pairs` or the
/// plain layout) and the distance chosen, then solved at that distance with the
/// outer ring (`outer`) or every sink ring holding `count` charges, for each
/// of `counts`. Also returns the chosen distance and the error as pfcam lays
/// the glyph out.
pub fn measure(
    ch: char,
    n: usize,
    pairs: bool,
    outer: bool,
    counts: &[usize],
) -> (f64, f64, Vec<RingSolve>) {
    let prep = Prepared::new(field::paper_boundary(ch).expect("a paper glyph")).unwrap();
    let base = Layout {
        n_total: n,
        distance: 1.0,
        corner_clusters: true,
        corner_fraction: 0.4,
        pairs,
    };
    let chosen = field::solve_with(&prep, base, None).unwrap_or_else(|e| panic!("{e}"));
    let groups: Groups = prep.groups(&chosen.layout).unwrap();
    let checks_per_interval = |g: &Problem| g.checks.len() / g.colloc.len().max(1);
    let solves = counts
        .iter()
        .map(|&count| {
            let mut g = groups.clone();
            let ring_checks: Vec<mfs::Condition> = if outer {
                let old = g.outer.as_ref().expect("an outer circle");
                let b = &prep.boundary;
                let new = ring(
                    b.centre,
                    b.radius,
                    b.radius * field::setup::OUTER_CHARGE_FACTOR,
                    count,
                    checks_per_interval(old),
                );
                let checks = new.checks.clone();
                g.outer = Some(new);
                checks
            } else {
                assert!(!g.sinks.is_empty(), "{ch} has no counter, so no sink");
                let mut checks = Vec::new();
                for (sink, pr) in &mut g.sinks {
                    let k = checks_per_interval(pr);
                    *pr = ring(
                        sink.centre,
                        sink.radius,
                        sink.radius * field::setup::SINK_CHARGE_FACTOR,
                        count,
                        k,
                    );
                    checks.extend(pr.checks.iter().cloned());
                }
                checks
            };
            let problem = g.concat();
            let sol = mfs::solve(&problem).unwrap_or_else(|e| panic!("{e}"));
            let on_ring = ring_checks
                .iter()
                .map(|c| (sol.field.value(c.p) - c.value).abs())
                .fold(0.0, f64::max);
            RingSolve {
                count,
                n: problem.charges.len(),
                max_error: sol.max_error,
                on_ring,
            }
        })
        .collect();
    (chosen.layout.distance, chosen.solution.max_error, solves)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: ring_charges GLYPH N plain|pairs outer|sink COUNTS";
    assert!(args.len() == 5, "{usage}");
    let ch = args[0].chars().next().expect(usage);
    let n: usize = args[1].parse().expect(usage);
    let pairs = match args[2].as_str() {
        "plain" => false,
        "pairs" => true,
        _ => panic!("{usage}"),
    };
    let outer = match args[3].as_str() {
        "outer" => true,
        "sink" => false,
        _ => panic!("{usage}"),
    };
    let counts: Vec<usize> = args[4]
        .split(',')
        .map(|c| c.parse().expect(usage))
        .collect();
    let (d, err, solves) = measure(ch, n, pairs, outer, &counts);
    println!(
        "{ch}, {} layout, N = {n}, d = {d:.2} font units: max error {err:.2e} as pfcam lays it out",
        args[2]
    );
    for r in solves {
        println!(
            "{} ring of {}: N = {}, max error {:.2e}, on the ring {:.2e}",
            args[3], r.count, r.n, r.max_error, r.on_ring
        );
    }
}
